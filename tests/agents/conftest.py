"""Shared tiny budgets for the agents tests (seconds, not minutes)."""

import pytest

pytest.importorskip("stable_baselines3", reason="the agents tests need the 'agents' extra (torch, stable-baselines3)")

from attentive_gym.agents.config import RunSpec  # noqa: E402

#: 40-step episodes, 64-step PPO rollouts on 2 envs: a 256-step run takes about a second.
TINY_ENV = {"time_limit_s": 2.0}
TINY_PPO = {"n_steps": 64, "batch_size": 64, "n_epochs": 1}


def tiny_spec(**changes) -> RunSpec:
    base = dict(
        variant="raw",
        total_steps=384,
        seed=0,
        n_envs=2,
        eval_every=128,
        eval_episodes=2,
        checkpoint_every=128,
        env_kwargs=TINY_ENV,
        algo_kwargs=TINY_PPO,
    )
    base.update(changes)
    return RunSpec(**base)


tiny_spec.env_kwargs = TINY_ENV
tiny_spec.ppo_kwargs = TINY_PPO


@pytest.fixture(scope="session")
def tiny():
    """``tiny(**changes)`` → a tiny ``RunSpec``; ``tiny.env_kwargs`` / ``tiny.ppo_kwargs`` are its settings."""
    return tiny_spec
