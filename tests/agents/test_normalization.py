"""Observation normalisation (``RunSpec.obs_scaling="running"``): statistics saved with the
model, restored on resume, frozen in evaluation; bad statistics refused."""

import numpy as np
import pytest
from stable_baselines3.common.vec_env import DummyVecEnv

from attentive_gym.agents.evaluation import evaluate_policy
from attentive_gym.agents.normalization import STATS_FILE, NormalizedPolicy, load_stats, normalize, save_stats
from attentive_gym.agents.results import read_csv
from attentive_gym.agents.training import env_factory, eval_seed, load_policy, train

from .test_training import Interrupt


def _count(path):
    with np.load(path) as data:
        return data["count"]


def test_a_normalised_run_saves_its_statistics_and_evaluation_uses_them(tmp_path, tiny):
    spec = tiny()
    assert spec.obs_scaling == "running"  # the default
    train(spec, tmp_path / "a", tensorboard=False)
    for name in (STATS_FILE, f"checkpoint/{STATS_FILE}"):
        assert (tmp_path / "a" / name).is_file(), name
    # every training observation went into the statistics: 2 envs × 192 steps and the first reset
    np.testing.assert_allclose(_count(tmp_path / "a" / STATS_FILE), 386.0001)  # every entry (epsilon: 1e-4)
    policy, loaded = load_policy(tmp_path / "a")
    assert isinstance(policy, NormalizedPolicy) and loaded == spec and policy.num_timesteps == 384
    # the loaded policy plays the final evaluation's episodes exactly as training's last evaluation did
    last = read_csv(tmp_path / "a" / "eval.csv")[-1]
    result = evaluate_policy(policy, env_factory(spec), spec.eval_episodes, eval_seed(spec))
    assert result.row()["mean_return"] == pytest.approx(last["mean_return"], abs=1e-5)
    assert result.row()["mean_episode_length"] == last["mean_episode_length"]


def test_a_run_in_the_observations_own_units_saves_no_statistics(tmp_path, tiny):
    spec = tiny(obs_scaling="none", total_steps=128)
    train(spec, tmp_path / "a", tensorboard=False)
    assert not (tmp_path / "a" / STATS_FILE).exists()
    assert not (tmp_path / "a" / "checkpoint" / STATS_FILE).exists()
    policy, _ = load_policy(tmp_path / "a")
    assert type(policy).__name__ == "PPO"


def test_resume_restores_the_statistics(tmp_path, tiny):
    spec = tiny(total_steps=640, checkpoint_every=256, eval_every=256)
    with pytest.raises(KeyboardInterrupt):
        train(spec, tmp_path / "run", tensorboard=False, callbacks=[Interrupt(at=400)])
    # the checkpoint at 256 steps: 2 envs × 128 steps and the first reset
    np.testing.assert_allclose(_count(tmp_path / "run" / "checkpoint" / STATS_FILE), 258.0001)
    train(spec, tmp_path / "run", tensorboard=False)
    train(spec, tmp_path / "straight", tensorboard=False)
    # resumed: the checkpoint's statistics, the resumed run's reset and its 2 × 192 steps
    resumed, straight = _count(tmp_path / "run" / STATS_FILE), _count(tmp_path / "straight" / STATS_FILE)
    np.testing.assert_allclose(resumed, straight + 2)


def test_missing_or_foreign_statistics_are_refused(tmp_path, tiny):
    spec = tiny(total_steps=128)
    train(spec, tmp_path / "a", tensorboard=False)
    focus_stats = tmp_path / "focus.npz"
    save_stats(normalize(DummyVecEnv([env_factory(tiny(variant="focus"))])), focus_stats)
    with pytest.raises(ValueError, match="holds the statistics of the observation entries"):
        load_stats(focus_stats, env_factory(spec))
    (tmp_path / "a" / STATS_FILE).unlink()
    with pytest.raises(ValueError, match=f"was trained on normalised observations, but .*{STATS_FILE} is missing"):
        load_policy(tmp_path / "a")
