"""Shared fixtures of the perception tests: attended environments, and recorded episodes.

Fixtures rather than helpers, because the suite runs with ``--import-mode=importlib``
where test modules cannot import each other.
"""

from __future__ import annotations

import pytest

from attentive_gym.attention import Goal
from attentive_gym.perception import PERCEPTION_ARENA, VARIANT, Wander, make_attentive_env, record_episode, stand_still

SEED = 0  # a seed whose first 2 s show a mover in front within 5 m for over 1 s
SECONDS = 2.0
GOAL = Goal.between("speed", 0.5, 0.9)  # a speed goal: goal agreement is defined


def _attended_env(mode: str, noise: float = 0.0, variant: str = VARIANT, arena=PERCEPTION_ARENA, **env_kwargs):
    """The benchmark's attended ``variant`` with the model in kinematics ``mode`` at Gaussian
    noise ``noise`` (relative σ, the sensors' and the model's), in ``arena``."""
    return make_attentive_env(mode, noise, variant, sensor_noise=noise, **arena, **env_kwargs)


@pytest.fixture
def attended_env():
    """``attended_env(mode, noise=0.0, variant=VARIANT, arena=PERCEPTION_ARENA, **env_kwargs)``: an
    attended environment, closed after the test."""
    made = []

    def make(*args, **kwargs):
        made.append(_attended_env(*args, **kwargs))
        return made[-1]

    yield make
    for env in made:
        env.close()


@pytest.fixture(scope="session")
def records():
    """One 2 s window-mode episode, driving and still, noise-free, with a speed goal."""
    env = _attended_env("window")
    driving = record_episode(env, SEED, GOAL, Wander(SEED), SECONDS)
    still = record_episode(env, SEED, GOAL, stand_still, SECONDS)
    env.close()
    return driving, still


@pytest.fixture(scope="session")
def tracked_record():
    """One 2 s tracker-mode episode, robot still, 5 % noise."""
    env = _attended_env("tracker", noise=0.05)
    record = record_episode(env, SEED, GOAL, stand_still, SECONDS)
    env.close()
    return record
