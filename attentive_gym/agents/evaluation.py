"""Evaluate a policy on fixed episode seeds: success rate, return, collisions, episode length.

``evaluate_policy(model, make_env_fn, episodes, seed)`` steps ``n_parallel`` plain Gymnasium
environments side by side and batches the policy's forward passes (one ``model.predict``
per step for all of them); episode ``i`` is always reset with seed ``seed + i``, so every
evaluation of a run (and every run with the same ``seed``) sees the same arenas.
"""

from __future__ import annotations

import time
from dataclasses import asdict, dataclass
from typing import Any, Callable

import gymnasium as gym
import numpy as np

__all__ = ["EvalResult", "evaluate_policy", "EVAL_SEED_OFFSET"]

#: Evaluation episodes use seeds ``run seed + EVAL_SEED_OFFSET + i`` (disjoint from training's).
EVAL_SEED_OFFSET = 10_000


@dataclass(frozen=True)
class EvalResult:
    """Aggregates over ``n_episodes`` episodes (rewards in reward units, lengths in env steps)."""

    n_episodes: int
    success_rate: float  # fraction of episodes ending with info["success"]
    mean_return: float
    std_return: float
    mean_collision_steps: float  # steps with info["collision"] per episode
    mean_episode_length: float  # env steps per episode
    returns: tuple[float, ...]
    successes: tuple[bool, ...]

    def row(self) -> dict[str, Any]:
        """The aggregate fields (no per-episode tuples), for an evaluation CSV row."""
        data = asdict(self)
        data.pop("returns")
        data.pop("successes")
        return data


def _stack(observations: list[Any]) -> Any:
    if isinstance(observations[0], dict):
        return {key: np.stack([o[key] for o in observations]) for key in observations[0]}
    return np.stack(observations)


def evaluate_policy(
    model: Any,
    make_env_fn: Callable[[], gym.Env],
    episodes: int,
    seed: int,
    *,
    n_parallel: int = 4,
    deterministic: bool = True,
    envs: list[gym.Env] | None = None,
) -> EvalResult:
    """Run ``episodes`` episodes of ``model`` (anything with SB3's ``predict``).

    Args:
        model: the policy; ``model.predict(batched_obs, deterministic=...)`` → (actions, _).
        make_env_fn: builds one environment (called ``min(n_parallel, episodes)`` times
            unless ``envs`` is given).
        episodes: number of episodes (≥ 1).
        seed: episode ``i`` is reset with ``seed + i``.
        n_parallel: environments stepped side by side (batched forward passes).
        deterministic: greedy actions (True) or sampled ones.
        envs: environments to reuse (not closed here); they must match ``make_env_fn``.
    """
    if isinstance(episodes, bool) or not isinstance(episodes, int) or episodes < 1:
        raise ValueError(f"episodes must be an integer >= 1, got {episodes!r}")
    own = envs is None
    if own:
        envs = [make_env_fn() for _ in range(min(n_parallel, episodes))]
    try:
        returns = np.zeros(episodes)
        collisions = np.zeros(episodes)
        lengths = np.zeros(episodes, dtype=int)
        successes = np.zeros(episodes, dtype=bool)
        next_episode = 0
        active: list[tuple[gym.Env, int, Any]] = []  # (env, episode index, last observation)
        for env in envs:
            if next_episode < episodes:
                obs, _ = env.reset(seed=seed + next_episode)
                active.append((env, next_episode, obs))
                next_episode += 1
        while active:
            actions, _ = model.predict(_stack([a[2] for a in active]), deterministic=deterministic)
            still = []
            for (env, index, _), action in zip(active, actions):
                obs, reward, terminated, truncated, info = env.step(action)
                returns[index] += float(reward)
                collisions[index] += bool(info.get("collision", False))
                lengths[index] += 1
                if terminated or truncated:
                    successes[index] = bool(info.get("success", False))
                    if next_episode < episodes:
                        obs, _ = env.reset(seed=seed + next_episode)
                        still.append((env, next_episode, obs))
                        next_episode += 1
                else:
                    still.append((env, index, obs))
            active = still
    finally:
        if own:
            for env in envs:
                env.close()
    return EvalResult(
        n_episodes=episodes,
        success_rate=float(successes.mean()),
        mean_return=float(returns.mean()),
        std_return=float(returns.std()),
        mean_collision_steps=float(collisions.mean()),
        mean_episode_length=float(lengths.mean()),
        returns=tuple(float(r) for r in returns),
        successes=tuple(bool(s) for s in successes),
    )


def record_videos(model: Any, make_env_fn: Callable[..., gym.Env], video_dir, episodes: int, seed: int) -> list[str]:
    """Record ``episodes`` episodes as MP4 files in ``video_dir`` with gymnasium's ``RecordVideo``.

    ``make_env_fn(render_mode="rgb_array")`` must build the environment. Needs ``moviepy``
    (``pip install moviepy``); raises ``ValueError`` saying so when it is missing.
    """
    try:
        import moviepy  # noqa: F401
    except ImportError:
        raise ValueError("--video needs moviepy (gymnasium's RecordVideo writes MP4 with it): pip install moviepy") from None
    from pathlib import Path

    env = gym.wrappers.RecordVideo(make_env_fn(render_mode="rgb_array"), str(video_dir),
                                   episode_trigger=lambda _: True, name_prefix="eval", disable_logger=True)
    try:
        for i in range(episodes):
            obs, _ = env.reset(seed=seed + i)
            done = False
            while not done:
                action, _ = model.predict(_stack([obs]), deterministic=True)
                obs, _, terminated, truncated, _ = env.step(action[0])
                done = terminated or truncated
    finally:
        env.close()
    return sorted(str(p) for p in Path(video_dir).glob("*.mp4"))
