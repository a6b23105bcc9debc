"""AttentiveRescue-v0 under gymnasium's vector envs and SB3's SubprocVecEnv."""

import gymnasium as gym
import numpy as np
import pytest

import attentive_gym  # noqa: F401


@pytest.mark.parametrize("mode", ["sync", "async"])
def test_make_vec_matches_single_envs(mode):
    kwargs = {"vector_kwargs": {"context": "spawn"}} if mode == "async" else {}
    vec = gym.make_vec("attentive_gym:AttentiveRescue-v0", num_envs=2, vectorization_mode=mode, **kwargs)
    singles = [gym.make("AttentiveRescue-v0") for _ in range(2)]
    obs, _ = vec.reset(seed=[3, 4])
    expected = [env.reset(seed=s)[0] for env, s in zip(singles, (3, 4))]
    for i in range(2):
        np.testing.assert_array_equal(obs["laser"][i], expected[i]["laser"])
    actions = np.array([[0.5, 0.1], [-0.2, 0.9]], np.float32)
    for _ in range(5):
        obs, rewards, *_ = vec.step(actions)
        for i, env in enumerate(singles):
            single_obs, single_reward, *_ = env.step(actions[i])
            np.testing.assert_array_equal(obs["sonar"][i], single_obs["sonar"])
            assert rewards[i] == pytest.approx(single_reward)
    vec.close()


@pytest.mark.slow
def test_sb3_subproc_vec_env_with_spawn():
    from stable_baselines3.common.env_util import make_vec_env
    from stable_baselines3.common.vec_env import SubprocVecEnv

    vec = make_vec_env(
        "attentive_gym:AttentiveRescue-v0",
        n_envs=2,
        seed=0,
        vec_env_cls=SubprocVecEnv,
        vec_env_kwargs={"start_method": "spawn"},
    )
    obs = vec.reset()
    assert obs["laser"].shape == (2, 180)
    obs, rewards, dones, infos = vec.step(np.zeros((2, 2), np.float32))
    assert rewards.shape == (2,) and len(infos) == 2
    vec.close()
