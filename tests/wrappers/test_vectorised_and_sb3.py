"""Attended variants under gymnasium's vector envs and stable-baselines3."""

import gymnasium as gym
import numpy as np
import pytest
from stable_baselines3 import PPO
from stable_baselines3.common.vec_env import DummyVecEnv, SubprocVecEnv

import attentive_gym  # noqa: F401
from attentive_gym.wrappers import VARIANT_IDS, make_env


def vector_rollout(envs, steps):
    rng = np.random.default_rng(0)
    obs, _ = envs.reset(seed=[4, 5])
    frames = [obs]
    for _ in range(steps):
        obs, *_ = envs.step(rng.uniform(-1, 1, envs.action_space.shape).astype(np.float32))
        frames.append(obs)
    envs.close()
    return frames


@pytest.mark.parametrize("variant", ["focus", "goal-action"])
def test_async_vector_env_matches_sync(variant):
    env_id = VARIANT_IDS[variant]
    sync = vector_rollout(gym.make_vec(env_id, num_envs=2, vectorization_mode="sync"), 30)
    asynchronous = vector_rollout(
        gym.make_vec(env_id, num_envs=2, vectorization_mode="async", vector_kwargs={"context": "spawn"}), 30
    )
    for a, b in zip(sync, asynchronous):
        for key in a:
            np.testing.assert_array_equal(a[key], b[key])


@pytest.mark.slow
def test_ppo_multi_input_policy_trains_on_focus_observations_in_subprocesses():
    envs = SubprocVecEnv([lambda: make_env("focus") for _ in range(2)], start_method="spawn")
    try:
        model = PPO("MultiInputPolicy", envs, n_steps=32, batch_size=32, n_epochs=1, seed=0, device="cpu")
        model.learn(64)
        action, _ = model.predict(envs.reset(), deterministic=True)
        assert action.shape == (2, 2)
    finally:
        envs.close()


@pytest.mark.parametrize("variant", ["masked", "goal-action", "oracle", "random-focus"])
def test_ppo_mlp_policy_trains_on_flattened_observations(variant):
    envs = DummyVecEnv([lambda: make_env(variant, flatten=True)])
    model = PPO("MlpPolicy", envs, n_steps=32, batch_size=32, n_epochs=1, seed=0, device="cpu")
    before = [p.detach().clone() for p in model.policy.parameters()]
    model.learn(32)
    assert any(not np.array_equal(a.numpy(), b.detach().numpy()) for a, b in zip(before, model.policy.parameters()))
