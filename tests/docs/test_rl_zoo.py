"""The RL Baselines3 Zoo hyperparameters that the package ships (``attentive_gym/agents/rl_zoo``).

Every registered ``AttentiveRescue`` id has an entry for PPO and RecurrentPPO (read from
Gymnasium's registry at test time, so a new id without an entry fails here), each entry's
policy builds on its environment, and ``rl_zoo3.train`` trains with the shipped file.
"""

import os
import subprocess
import sys
from pathlib import Path

import gymnasium as gym
import pytest

import attentive_gym  # noqa: F401  (registers the ids)
from attentive_gym.agents.config import SCHEDULE_KEYS, RunSpec, parse_schedule
from attentive_gym.agents.normalization import CLIP
from attentive_gym.agents.rl_zoo import ZOO_ALGOS, conf_file, load_hyperparams

ROOT = Path(__file__).resolve().parents[2]
POLICIES = {"ppo": "MultiInputPolicy", "ppo_lstm": "MultiInputLstmPolicy"}
RUNSPEC_ALGOS = {"ppo": "ppo", "ppo_lstm": "recurrent-ppo"}
#: ``train``'s observation normalisation (``normalization.normalize``), in rl-zoo3's terms.
NORMALIZE = {"norm_obs": True, "norm_reward": False, "clip_obs": CLIP}
#: Entries that configure rl-zoo3 rather than the algorithm.
ZOO_KEYS = ("n_envs", "n_timesteps", "normalize", "policy")


def algorithm_kwargs(entry: dict) -> dict:
    """An entry's keyword arguments of the algorithm, as rl-zoo3 passes them: without its
    own keys, and ``policy_kwargs`` (a string of Python in the file) evaluated."""
    kwargs = {k: v for k, v in entry.items() if k not in ZOO_KEYS}
    if isinstance(kwargs.get("policy_kwargs"), str):
        kwargs["policy_kwargs"] = eval(kwargs["policy_kwargs"], {"dict": dict})
    return kwargs


def registered_ids() -> list[str]:
    return sorted(env_id for env_id in gym.registry if env_id.startswith("AttentiveRescue"))


def test_the_registry_holds_the_variants():
    assert {"AttentiveRescue-v0", "AttentiveRescueFocus-v1"} <= set(registered_ids())


@pytest.mark.parametrize("algo", ZOO_ALGOS)
def test_every_registered_id_has_an_entry(algo):
    hyperparams = load_hyperparams(algo)
    missing = [env_id for env_id in registered_ids() if env_id not in hyperparams]
    assert not missing, f"{conf_file(algo)} has no entry for {missing}"
    stale = sorted(set(hyperparams) - set(registered_ids()))
    assert not stale, f"{conf_file(algo)} has entries for ids that are not registered: {stale}"


@pytest.mark.parametrize("algo", ZOO_ALGOS)
def test_the_entries_are_the_projects_settings(algo):
    """The algorithm's settings are ``RunSpec``'s defaults for it and its environment count
    (rl-zoo3 evaluates ``policy_kwargs``, a string of Python, into keyword arguments)."""
    spec = RunSpec(algo=RUNSPEC_ALGOS[algo])
    for env_id, entry in load_hyperparams(algo).items():
        assert entry["policy"] == POLICIES[algo], env_id
        assert entry["n_envs"] == spec.n_envs, env_id
        assert algorithm_kwargs(entry) == spec.default_algo_kwargs(), env_id
        assert spec.obs_scaling == "running" and eval(entry["normalize"]) == NORMALIZE, env_id


def test_the_modules_serve_the_files():
    from attentive_gym.agents.rl_zoo import ppo, ppo_lstm

    assert ppo.hyperparams == load_hyperparams("ppo")
    assert ppo_lstm.hyperparams == load_hyperparams("ppo_lstm")
    assert conf_file("ppo") == ROOT / "attentive_gym" / "agents" / "rl_zoo" / "ppo.yml"
    with pytest.raises(ValueError, match="available"):
        conf_file("dqn")


@pytest.mark.parametrize("algo", ZOO_ALGOS)
def test_every_entry_builds_on_its_environment(algo):
    """The policy each entry names accepts the observation and action spaces of its id."""
    ALGOS = pytest.importorskip("rl_zoo3.utils", reason="needs rl-zoo3 (the 'test' extra)").ALGOS

    for env_id, entry in load_hyperparams(algo).items():
        env = gym.make(env_id)
        try:
            kwargs = {
                key: parse_schedule(key, value) if key in SCHEDULE_KEYS and isinstance(value, str) else value
                for key, value in algorithm_kwargs(entry).items()
            }  # "lin_3e-4", as rl-zoo3 reads it
            model = ALGOS[algo](entry["policy"], env, device="cpu", **kwargs)
            assert model.observation_space == env.observation_space, env_id
        finally:
            env.close()


@pytest.mark.slow
def test_rl_zoo_trains_with_the_shipped_file(tmp_path):
    """``python -m rl_zoo3.train`` with ``--conf-file`` (one PPO update: 32 envs × 64 steps)."""
    pytest.importorskip("rl_zoo3", reason="needs rl-zoo3 (the 'test' extra)")
    command = [
        sys.executable,
        "-m",
        "rl_zoo3.train",
        "--algo",
        "ppo",
        "--env",
        "AttentiveRescueFocus-v1",
        "--gym-packages",
        "attentive_gym",
        "--conf-file",
        str(conf_file("ppo")),
        "-n",
        "256",
        "--eval-freq",
        "-1",
        "--save-freq",
        "-1",
        "--device",
        "cpu",
        "--num-threads",
        "1",
        "--seed",
        "0",
        "--log-interval",
        "-2",
        "-f",
        str(tmp_path / "logs"),
    ]
    env = {**os.environ, "SDL_VIDEODRIVER": "dummy"}
    # the timeout only guards against a hang: ~20 s alone, it took over 120 s on 2 cores shared with 5 training runs
    done = subprocess.run(command, cwd=tmp_path, env=env, capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    assert "MultiInputPolicy" in done.stdout
    models = list((tmp_path / "logs" / "ppo").glob("AttentiveRescueFocus-v1_*/AttentiveRescueFocus-v1.zip"))
    assert len(models) == 1, done.stdout[-3000:]
