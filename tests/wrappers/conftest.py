import numpy as np
import pytest

from attentive_gym.wrappers import make_env


def _run_until_focus(env, max_steps=200):
    """Step ``env`` with zero actions until the attention has a focus; return (obs, info)."""
    for _ in range(max_steps):
        obs, _, terminated, truncated, info = env.step(np.zeros(env.action_space.shape, np.float32))
        if info["attention"].focus is not None:
            return obs, info
        assert not (terminated or truncated)
    raise AssertionError("no focus within max_steps")


@pytest.fixture
def exp01_focus_env():
    env = make_env("focus", scenario="exp01", sensor_noise=0.0, proximity=False)
    env.reset(seed=0)
    yield env
    env.close()


@pytest.fixture
def run_until_focus():
    return _run_until_focus
