"""RecurrentPPO (sb3-contrib's LSTM policy): training, resume, and evaluation that carries the LSTM state."""

import json

import gymnasium as gym
import numpy as np
import pytest

pytest.importorskip("sb3_contrib", reason="--algo recurrent-ppo needs sb3-contrib (the 'agents' extra)")

from attentive_gym.agents.evaluation import PolicyMemory, evaluate_policy  # noqa: E402
from attentive_gym.agents.training import _policy_name, env_factory, is_done, load_model, train  # noqa: E402
from attentive_gym.cli import main  # noqa: E402

from .test_training import Interrupt  # noqa: E402

#: A small LSTM keeps a few hundred steps at about a second.
TINY_LSTM = {"n_steps": 64, "batch_size": 64, "n_epochs": 1, "policy_kwargs": {"lstm_hidden_size": 16}}


def _recurrent(tiny, **changes):
    return tiny(algo="recurrent-ppo", algo_kwargs=TINY_LSTM, **changes)


@pytest.mark.parametrize("variant", ["raw", "focus"])
def test_train_and_evaluate_a_recurrent_policy(variant, tmp_path, tiny, capsys):
    spec = _recurrent(tiny, variant=variant, total_steps=256)
    metrics = train(spec, tmp_path / "run")
    assert metrics["env_steps"] == 256 and is_done(tmp_path / "run")
    model, loaded = load_model(tmp_path / "run")
    assert type(model).__name__ == "RecurrentPPO" and loaded == spec
    assert type(model.policy).__name__ == "RecurrentMultiInputActorCriticPolicy"  # MultiInputLstmPolicy
    capsys.readouterr()
    assert main(["evaluate", str(tmp_path / "run"), "--episodes", "3", "--json"]) == 0
    row = json.loads(capsys.readouterr().out)
    assert row["variant"] == variant and row["n_episodes"] == 3


def test_recurrent_resume_continues_from_the_checkpoint(tmp_path, tiny):
    spec = _recurrent(tiny, total_steps=384, checkpoint_every=128)
    with pytest.raises(KeyboardInterrupt):
        train(spec, tmp_path / "run", callbacks=[Interrupt(at=200)])
    assert not is_done(tmp_path / "run")
    metrics = train(spec, tmp_path / "run")
    assert metrics["resumed_from"] == 128 and metrics["env_steps"] == 384
    model, _ = load_model(tmp_path / "run")
    assert model.num_timesteps == 384


def test_batched_evaluation_keeps_each_envs_lstm_state(tmp_path, tiny):
    """One env at a time or three side by side (episodes ending at different steps) give the same episodes."""
    spec = _recurrent(tiny, total_steps=128)
    train(spec, tmp_path / "run", tensorboard=False)
    model, _ = load_model(tmp_path / "run")
    alone = evaluate_policy(model, env_factory(spec), 5, seed=3, n_parallel=1)
    batched = evaluate_policy(model, env_factory(spec), 5, seed=3, n_parallel=3)
    assert batched.returns == pytest.approx(alone.returns, rel=1e-6, abs=1e-6)


class StepIndexEnv(gym.Env):
    """Episodes of ``2 + seed % 4`` steps whose observation is the step index within the episode."""

    observation_space = gym.spaces.Dict({"t": gym.spaces.Box(0.0, 10.0, (1,))})
    action_space = gym.spaces.Box(-1.0, 1.0, (2,))

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.length, self.t = 2 + seed % 4, 0
        return {"t": np.zeros(1)}, {}

    def step(self, action):
        self.t += 1
        return {"t": np.array([float(self.t)])}, 1.0, self.t >= self.length, False, {}


class StepCounter:
    """A fake recurrent policy whose state counts the steps of its env's episode.

    As RecurrentPPO does, it zeroes a row's state where ``episode_start`` is True; it counts
    every row whose state disagrees with the env's step index (state lost, mixed up between
    envs, or not reset at an episode start).
    """

    def __init__(self):
        self.wrong_states = 0

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        n = len(obs["t"])
        count = np.zeros((1, n, 1)) if state is None else state[0].copy()
        count[:, np.asarray(episode_start, bool)] = 0.0
        self.wrong_states += int(np.sum(count[0, :, 0] != obs["t"][:, 0]))
        count += 1.0
        return np.zeros((n, 2), np.float32), (count, -count)


@pytest.mark.parametrize("n_parallel", [1, 3])
def test_evaluation_carries_each_envs_state_and_resets_it_at_episode_starts(n_parallel):
    policy = StepCounter()
    result = evaluate_policy(policy, StepIndexEnv, 7, seed=1, n_parallel=n_parallel)
    assert policy.wrong_states == 0
    assert result.returns == tuple(float(2 + (1 + i) % 4) for i in range(7))  # episodes of 4, 5, 2, 3, 4, 5, 2 steps


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"n_parallel": 0}, "n_parallel must be an integer >= 1, got 0"),
        ({"n_parallel": -2}, "n_parallel"),
        ({"n_parallel": 2.0}, "n_parallel"),
        ({"envs": []}, "envs must hold at least one"),
    ],
)
def test_evaluation_refuses_no_environments_instead_of_reporting_zeros(kwargs, message):
    with pytest.raises(ValueError, match=message):
        evaluate_policy(StepCounter(), StepIndexEnv, 5, seed=1, **kwargs)


def test_policy_memory_keeps_each_envs_rows():
    memory = PolicyMemory(3)
    assert memory.take([0, 2]) is None
    hidden = np.arange(2 * 2 * 4, dtype=np.float32).reshape(2, 2, 4)  # (layers, envs, units)
    memory.store([2, 0], (hidden, -hidden))
    taken = memory.take([0, 2])
    assert np.array_equal(taken[0], hidden[:, [1, 0]]) and np.array_equal(taken[1], -hidden[:, [1, 0]])
    assert np.array_equal(memory.take([1])[0], np.zeros((2, 1, 4)))
    memory.store([1], None)  # a feed-forward policy's "state" changes nothing
    assert np.array_equal(memory.take([0])[0], hidden[:, [1]])


@pytest.mark.parametrize(
    "algo, space, policy",
    [
        ("recurrent-ppo", gym.spaces.Dict({"x": gym.spaces.Box(0, 1, (2,))}), "MultiInputLstmPolicy"),
        ("recurrent-ppo", gym.spaces.Box(0, 1, (2,)), "MlpLstmPolicy"),
        ("ppo", gym.spaces.Dict({"x": gym.spaces.Box(0, 1, (2,))}), "MultiInputPolicy"),
        ("sac", gym.spaces.Box(0, 1, (2,)), "MlpPolicy"),
    ],
)
def test_the_policy_follows_the_observation_space(algo, space, policy):
    assert _policy_name(algo, space) == policy


def test_recurrent_ppo_keywords_are_checked(tmp_path, capsys):
    argv = [
        "train",
        "--algo",
        "recurrent-ppo",
        "--steps",
        "64",
        "--algo-kwargs",
        '{"n_lstm": 2}',
        "--out",
        str(tmp_path / "r"),
    ]
    assert main(argv) == 2
    assert "RecurrentPPO takes no 'n_lstm'; allowed: " in capsys.readouterr().err
    assert not (tmp_path / "r").exists()
