"""Evaluate a policy on fixed episode seeds: success rate, safe success rate, return, contact,
episode length.

``evaluate_policy(model, make_env_fn, episodes, seed)`` steps ``n_parallel`` plain Gymnasium
environments side by side and batches the policy's forward passes (one ``model.predict``
per step for all of them); episode ``i`` is always reset with seed ``seed + i``, so every
evaluation of a run (and every run with the same ``seed``) sees the same arenas.

Recurrent policies (RecurrentPPO's LSTM) get SB3's ``state`` and ``episode_start``: each
environment's state is carried from one step of an episode to the next and reset at the
first step of each episode (``episode_start`` True). Feed-forward policies return no state.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import asdict, dataclass
from typing import Any, NamedTuple

import gymnasium as gym
import numpy as np

from attentive_gym._checks import check_int
from attentive_gym._optional import require
from attentive_gym.envs.reward import SAFE_CONTACT_S

__all__ = [
    "EvalResult",
    "evaluate_policy",
    "record_videos",
    "check_video_dir",
    "PolicyMemory",
    "predict_batch",
    "EVAL_SEED_OFFSET",
]

#: Evaluation episodes use seeds ``run seed + EVAL_SEED_OFFSET + i`` (disjoint from training's).
EVAL_SEED_OFFSET = 10_000


@dataclass(frozen=True)
class EvalResult:
    """Aggregates over ``n_episodes`` episodes (rewards in reward units, lengths in env steps)."""

    n_episodes: int
    success_rate: float  # fraction of episodes ending with info["success"]
    safe_success_rate: float  # fraction ending with success and info["contact_s"] <= SAFE_CONTACT_S (NaN without it)
    mean_return: float
    std_return: float
    mean_collision_steps: float  # steps with info["collision"] per episode
    mean_contact_s: float  # s in contact per episode (the last info["contact_s"]; NaN for an env without it)
    mean_episode_length: float  # env steps per episode
    returns: tuple[float, ...]
    successes: tuple[bool, ...]

    def row(self) -> dict[str, Any]:
        """The aggregate fields (no per-episode tuples), for an evaluation CSV row."""
        data = asdict(self)
        data.pop("returns")
        data.pop("successes")
        return data


class _Running(NamedTuple):
    """An episode in progress: its env slot, episode index, last observation, and whether it has just begun."""

    slot: int
    index: int
    obs: Any
    episode_start: bool


def _stack(observations: list[Any]) -> Any:
    if isinstance(observations[0], dict):
        return {key: np.stack([o[key] for o in observations]) for key in observations[0]}
    return np.stack(observations)


class PolicyMemory:
    """A recurrent policy's state for ``n_envs`` environments, so that any subset can be predicted at once.

    SB3's ``state`` is a tuple of arrays with the environment on axis 1 (RecurrentPPO: the
    LSTM's hidden and cell states, each ``(n_layers, n_envs, hidden_size)``); feed-forward
    policies return ``None`` and nothing is kept.
    """

    def __init__(self, n_envs: int):
        self.n_envs = n_envs
        self.state: tuple[np.ndarray, ...] | None = None

    def take(self, envs: list[int]) -> tuple[np.ndarray, ...] | None:
        """The state of environments ``envs`` (in that order), or ``None`` before any was stored."""
        if self.state is None:
            return None
        return tuple(part[:, envs] for part in self.state)

    def store(self, envs: list[int], state: tuple[np.ndarray, ...] | None) -> None:
        """Keep ``state`` (as returned by ``predict`` for ``envs``) for those environments."""
        if state is None:
            return
        if self.state is None:
            self.state = tuple(np.zeros((part.shape[0], self.n_envs, *part.shape[2:]), part.dtype) for part in state)
        for kept, part in zip(self.state, state):
            kept[:, envs] = part


def predict_batch(
    model: Any,
    observations: list[Any],
    memory: PolicyMemory,
    envs: list[int],
    episode_start: np.ndarray,
    deterministic: bool,
) -> np.ndarray:
    """Actions for the environments ``envs`` (one observation each), carrying ``memory``.

    ``episode_start[k]`` is True at the first step of environment ``envs[k]``'s episode: a
    recurrent policy resets that environment's state to zeros before this step.
    """
    actions, state = model.predict(
        _stack(observations), state=memory.take(envs), episode_start=episode_start, deterministic=deterministic
    )
    memory.store(envs, state)
    return actions


def evaluate_policy(
    model: Any,
    make_env_fn: Callable[[], gym.Env],
    episodes: int,
    seed: int,
    *,
    n_parallel: int = 4,
    deterministic: bool = True,
    envs: list[gym.Env] | None = None,
    on_step: Callable[[dict[str, Any]], None] | None = None,
) -> EvalResult:
    """Run ``episodes`` episodes of ``model`` (anything with SB3's ``predict``).

    Args:
        model: the policy; ``model.predict(batched_obs, state=..., episode_start=..., deterministic=...)``
            → (actions, state), as SB3's (``state`` is ``None`` for feed-forward policies).
        make_env_fn: builds one environment (called ``min(n_parallel, episodes)`` times
            unless ``envs`` is given).
        episodes: number of episodes (≥ 1).
        seed: episode ``i`` is reset with ``seed + i``.
        n_parallel: environments stepped side by side (batched forward passes).
        deterministic: greedy actions (True) or sampled ones.
        envs: environments to reuse (not closed here); they must match ``make_env_fn``.
        on_step: called with each step's ``info``, every environment's, in the order they
            step (e.g. ``goal_choice.GoalChoiceTally``); None: nothing is called.
    """
    check_int("episodes", episodes, 1)
    check_int("n_parallel", n_parallel, 1)
    if envs is not None and not envs:
        raise ValueError("envs must hold at least one environment (or be None to build them)")
    own = envs is None
    if own:
        envs = [make_env_fn() for _ in range(min(n_parallel, episodes))]
    try:
        returns = np.zeros(episodes)
        collisions = np.zeros(episodes)
        lengths = np.zeros(episodes, dtype=int)
        successes = np.zeros(episodes, dtype=bool)
        contacts = np.zeros(episodes)
        memory = PolicyMemory(len(envs))
        next_episode = 0
        active: list[_Running] = []
        for slot, env in enumerate(envs):
            if next_episode < episodes:
                obs, _ = env.reset(seed=seed + next_episode)
                active.append(_Running(slot, next_episode, obs, True))
                next_episode += 1
        while active:
            actions = predict_batch(
                model,
                [a.obs for a in active],
                memory,
                [a.slot for a in active],
                np.array([a.episode_start for a in active]),
                deterministic,
            )
            still = []
            for (slot, index, _, _), action in zip(active, actions):
                obs, reward, terminated, truncated, info = envs[slot].step(action)
                if on_step is not None:
                    on_step(info)
                returns[index] += float(reward)
                collisions[index] += bool(info.get("collision", False))
                lengths[index] += 1
                if terminated or truncated:
                    successes[index] = bool(info.get("success", False))
                    contacts[index] = float(info.get("contact_s", math.nan))
                    if next_episode < episodes:
                        obs, _ = envs[slot].reset(seed=seed + next_episode)
                        still.append(_Running(slot, next_episode, obs, True))
                        next_episode += 1
                else:
                    still.append(_Running(slot, index, obs, False))
            active = still
    finally:
        if own:
            for env in envs:
                env.close()
    return EvalResult(
        n_episodes=episodes,
        success_rate=float(successes.mean()),
        safe_success_rate=math.nan
        if np.isnan(contacts).any()
        else float((successes & (contacts <= SAFE_CONTACT_S)).mean()),
        mean_return=float(returns.mean()),
        std_return=float(returns.std()),
        mean_collision_steps=float(collisions.mean()),
        mean_contact_s=float(contacts.mean()),
        mean_episode_length=float(lengths.mean()),
        returns=tuple(float(r) for r in returns),
        successes=tuple(bool(s) for s in successes),
    )


#: ``RecordVideo``'s file name prefix for the evaluation videos.
VIDEO_PREFIX = "eval"


def check_video_dir(video_dir) -> None:
    """``ValueError`` when ``video_dir`` already holds evaluation videos (``record_videos``
    would overwrite them) or is a file; call it before any work."""
    from pathlib import Path

    video_dir = Path(video_dir)
    if video_dir.exists() and not video_dir.is_dir():
        raise ValueError(f"--video {video_dir} is a file; give a folder")
    existing = sorted(video_dir.glob(f"{VIDEO_PREFIX}-episode-*.mp4")) if video_dir.is_dir() else []
    if existing:
        raise ValueError(
            f"--video {video_dir} already holds {len(existing)} video(s) ({existing[0].name}, ...) that "
            "would be overwritten; give another folder"
        )


def record_videos(model: Any, make_env_fn: Callable[..., gym.Env], video_dir, episodes: int, seed: int) -> list[str]:
    """Record ``episodes`` episodes as MP4 files in ``video_dir`` with gymnasium's ``RecordVideo``;
    returns the files written.

    ``make_env_fn(render_mode="rgb_array")`` must build the environment. Needs ``moviepy``
    (the ``video`` extra): raises ``MissingExtraError`` naming the extra when it is missing,
    and ``ValueError`` when ``video_dir`` already holds videos (``check_video_dir``).
    """
    require("moviepy", "--video (gymnasium's RecordVideo writes MP4 with it)")
    from pathlib import Path

    check_video_dir(video_dir)
    env = gym.wrappers.RecordVideo(
        make_env_fn(render_mode="rgb_array"),
        str(video_dir),
        episode_trigger=lambda _: True,
        name_prefix=VIDEO_PREFIX,
        disable_logger=True,
    )
    memory = PolicyMemory(1)
    try:
        for i in range(episodes):
            obs, _ = env.reset(seed=seed + i)
            done, start = False, True
            while not done:
                action = predict_batch(model, [obs], memory, [0], np.array([start]), deterministic=True)
                obs, _, terminated, truncated, _ = env.step(action[0])
                done, start = terminated or truncated, False
    finally:
        env.close()
    return sorted(str(p) for p in Path(video_dir).glob(f"{VIDEO_PREFIX}-episode-*.mp4"))
