"""Warm starts: a policy cloned from a scripted teacher before reinforcement learning begins.

PPO on the safe rescue task (an episode ends after 1 s of contact) learns to reach the target
and stalls before it learns to avoid what moves: on the same observation, the scripted
``clearance_controller`` reaches the target safely in about 0.93 of the episodes and PPO's
oracle in 0.82 after 1M steps (``docs/notes/2026-12-05-safe-rescue.md``). A warm start hands
PPO what the teacher knows, as demonstrations (behaviour cloning, then PPO fine-tuning):

1. ``collect_demonstrations``: the run's own training environments are driven for
   ``DEMO_STEPS`` env steps by the teacher's action plus Gaussian noise of ``DEMO_NOISE``
   (so that the demonstrations also show how the teacher recovers from where noise leads;
   the label is always the teacher's clean action), recording each observation, the label
   and the discounted return that followed.
2. ``clone``: the observation statistics are fitted to the demonstrations; the policy's mean
   action is fitted to the labels and its value to the returns (``BC_EPOCHS`` passes of
   Adam); the exploration's standard deviation is then set to ``WARM_ACTION_STD``.

``warm_start(model, vec_env, vec_normalize, spec)`` does both; ``train`` calls it on a new
run whose ``RunSpec.warm_start`` is set, and the demonstrations' env steps count in the run's
budget. Teachers (``WARM_STARTS``), each needing a (linear, angular) action:

- ``"clearance"``, ``perception.controllers.clearance_controller``: reads the first
  working-memory row (the target in the oracle's observation; the latest attended body in
  ``focus``'s) and the ``"proximity"`` entry; so it needs a focus-layout variant built with
  ``proximity=True``.
- ``"privileged"``, ``perception.controllers.privileged_clearance_controller``: the same
  avoider steering for the target's true bearing and distance, read from each step's
  ``info`` (the world's truth), and the ``"proximity"`` entry or the raw ``"sonar"`` and
  ``"laser"`` ranges; so it teaches every variant, ``raw`` included, one behaviour, which each
  student clones from its own observation (a privileged teacher, as in learning by
  cheating).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import gymnasium as gym
import numpy as np

from attentive_gym.attention.config import MAP_NAMES
from attentive_gym.perception.controllers import clearance_controller, privileged_clearance_controller

__all__ = [
    "WARM_STARTS",
    "DEMO_STEPS",
    "DEMO_NOISE",
    "BC_EPOCHS",
    "WARM_ACTION_STD",
    "Demonstrations",
    "check_warm_start",
    "collect_demonstrations",
    "clone",
    "warm_start",
]

#: Teacher name → the policy (observation, info) → action it demonstrates.
WARM_STARTS: dict[str, Callable[[Mapping[str, np.ndarray], Mapping[str, Any]], np.ndarray]] = {
    "clearance": clearance_controller,
    "privileged": privileged_clearance_controller,
}
#: The observation entries each teacher reads (entry → its shape, None: any): it needs one of
#: these sets, and no masked readings.
_NEEDS = {
    "clearance": ({"memory": None, "proximity": None},),
    "privileged": ({"proximity": None}, {"sonar": (16,), "laser": (180,)}),
}
_MASKS = ("sonar_mask", "laser_mask")
#: Which variants can have each teacher, in its refusal.
_FOR = {
    "clearance": "the focus, random-focus or oracle variant with its proximity entry",
    "privileged": "raw or saliency, or the focus, goal-action, random-focus or oracle variant with its proximity entry",
}
#: Env steps of demonstrations (over all training envs), counted in the run's budget.
DEMO_STEPS = 64_000
#: Standard deviation of the noise added to the executed action (the label stays clean).
DEMO_NOISE = 0.3
#: Passes over the demonstrations, minibatch size and Adam's learning rate of the cloning.
BC_EPOCHS, BC_BATCH, BC_LEARNING_RATE = 30, 512, 1e-3
#: The policy's action standard deviation after cloning (PPO's exploration from there on).
WARM_ACTION_STD = 0.3
#: The value target's discount (PPO's default ``gamma``).
_GAMMA = 0.99


@dataclass(frozen=True)
class Demonstrations:
    """``observations``: entry → ``(N, ...)`` raw observations; ``actions`` ``(N, 2)``: the
    teacher's labels in [-1, 1]; ``returns`` ``(N,)``: the discounted reward that followed
    (reward units; cut at the end of the collection)."""

    observations: dict[str, np.ndarray]
    actions: np.ndarray
    returns: np.ndarray


def check_warm_start(
    name: str, observation_space: gym.Space, action_space: gym.Space, goal_menu_size: int | None = None
) -> None:
    """``ValueError`` unless teacher ``name`` is known and can act in these spaces: a (linear,
    angular) action, or ``goal-action``'s (``GoalActionWrapper``) with a menu of
    ``goal_menu_size`` goals, whose goal and weights the teacher sets as ``goal_action_label``."""
    if name not in WARM_STARTS:
        raise ValueError(f"unknown warm_start {name!r}; allowed: None, {', '.join(map(repr, WARM_STARTS))}")
    spaces = dict(observation_space.spaces) if isinstance(observation_space, gym.spaces.Dict) else {}
    entries = list(spaces)
    readable = not any(mask in spaces for mask in _MASKS) and any(
        all(entry in spaces and shape in (None, spaces[entry].shape) for entry, shape in needed.items())
        for needed in _NEEDS[name]
    )
    shapes = [(2,)] + ([] if goal_menu_size is None else [(2 + goal_menu_size + len(MAP_NAMES),)])
    if not readable or getattr(action_space, "shape", None) not in shapes:
        needs = " or ".join(
            str([entry if shape is None else f"{entry} {shape}" for entry, shape in needed.items()])
            for needed in _NEEDS[name]
        )
        raise ValueError(
            f"warm_start {name!r} needs the observation entries {needs} and a (linear, angular) action: "
            f"{_FOR[name]}; this run's observation has {entries or 'no entries'}"
        )


def goal_action_label(motion: np.ndarray, goal_text: str, goal_menu: Sequence[Any], max_weight: float) -> np.ndarray:
    """The teacher's ``motion`` (linear, angular) in ``GoalActionWrapper``'s action layout
    ``(2 + K + 6,)``: a score of +1 for the menu entry of the episode's task goal (``goal_text``,
    ``info["goal"]``; the entry without a goal when the menu lacks it) and −1 for the other
    ``K − 1``, and every map weight at 1, the model's default (each as its action value
    ``2 / max_weight − 1``, clipped to [−1, 1]). So the attention demonstrated is the task's,
    what ``focus`` attends, and PPO may move away from it."""
    texts = [None if goal is None else str(goal) for goal in goal_menu]
    index = texts.index(goal_text) if goal_text in texts else (texts.index(None) if None in texts else 0)
    scores = np.full(len(texts), -1.0)
    scores[index] = 1.0
    weights = np.full(len(MAP_NAMES), np.clip(2.0 / max_weight - 1.0, -1.0, 1.0))
    return np.concatenate([np.asarray(motion, float), scores, weights]).astype(np.float32)


def collect_demonstrations(vec_env, name: str, steps: int, seed: int) -> Demonstrations:
    """Drive the SB3 ``VecEnv`` ``vec_env`` (raw ``Dict`` observations) by teacher ``name``
    plus noise for ``steps`` env steps (rounded up to whole steps of all its envs); the
    noise is drawn from ``seed``. In ``goal-action``'s envs the teacher also sets the goal
    and the weights (``goal_action_label``)."""
    teacher = WARM_STARTS[name]
    layout = _goal_action_layout(vec_env)
    if layout is not None:
        motion_teacher = teacher
        teacher = lambda obs, info: goal_action_label(motion_teacher(obs, info), info["goal"], *layout)  # noqa: E731
    rng = np.random.default_rng(seed)
    n = vec_env.num_envs
    obs = vec_env.reset()
    infos = list(vec_env.reset_infos)
    seen: dict[str, list[np.ndarray]] = {key: [] for key in obs}
    labels, rewards, dones = [], [], []
    for _ in range(math.ceil(steps / n)):
        action = np.stack([teacher({key: value[i] for key, value in obs.items()}, infos[i]) for i in range(n)])
        executed = np.clip(action + DEMO_NOISE * rng.standard_normal(action.shape), -1.0, 1.0).astype(np.float32)
        for key, value in obs.items():
            seen[key].append(np.array(value, copy=True))
        labels.append(action)
        obs, reward, done, step_infos = vec_env.step(executed)
        # a finished episode's info is its last step's; its member's next observation is the new episode's
        infos = [vec_env.reset_infos[i] if done[i] else step_infos[i] for i in range(n)]
        rewards.append(reward)
        dones.append(done)
    returns = np.zeros((len(rewards), n))
    following = np.zeros(n)
    for t in range(len(rewards) - 1, -1, -1):
        following = rewards[t] + _GAMMA * following * (1.0 - dones[t])
        returns[t] = following
    return Demonstrations(
        {key: np.concatenate(values) for key, values in seen.items()},
        np.concatenate(labels).astype(np.float32),
        returns.reshape(-1).astype(np.float32),
    )


def _goal_action_layout(vec_env) -> tuple[tuple[Any, ...], float] | None:
    """``(goal menu, max weight)`` of ``goal-action``'s envs in ``vec_env``; None for others."""
    try:
        return tuple(vec_env.get_attr("goal_menu", [0])[0]), float(vec_env.get_attr("max_weight", [0])[0])
    except AttributeError:
        return None


def clone(model, demonstrations: Demonstrations, vec_normalize, seed: int) -> dict[str, float]:
    """Fit ``model``'s policy (SB3 PPO, a ``Dict`` observation) to ``demonstrations``: the
    observation statistics of ``vec_normalize`` (when not None) to their observations, the
    policy's mean action to the labels and its value to the returns; then set its action
    standard deviation to ``WARM_ACTION_STD``. Returns the last pass's mean squared errors,
    ``{"action_mse", "value_mse"}``."""
    import torch

    observations = demonstrations.observations
    if vec_normalize is not None:
        for key, values in observations.items():
            vec_normalize.obs_rms[key].update(values)
        observations = vec_normalize.normalize_obs(observations)
    policy = model.policy
    inputs = {key: torch.as_tensor(np.asarray(values), dtype=torch.float32) for key, values in observations.items()}
    labels = torch.as_tensor(demonstrations.actions)
    returns = torch.as_tensor(demonstrations.returns)
    optimiser = torch.optim.Adam(policy.parameters(), lr=BC_LEARNING_RATE)
    generator = torch.Generator().manual_seed(seed)
    size = len(labels)
    for _ in range(BC_EPOCHS):
        totals = np.zeros(2)
        order = torch.randperm(size, generator=generator)
        for start in range(0, size, BC_BATCH):
            index = order[start : start + BC_BATCH]
            batch = {key: value[index] for key, value in inputs.items()}
            action_error = ((policy.get_distribution(batch).distribution.mean - labels[index]) ** 2).mean()
            value_error = ((policy.predict_values(batch).flatten() - returns[index]) ** 2).mean()
            optimiser.zero_grad()
            (action_error + 0.5 * value_error).backward()
            optimiser.step()
            totals += len(index) * np.array([action_error.item(), value_error.item()])
    with torch.no_grad():
        policy.log_std.fill_(math.log(WARM_ACTION_STD))
    return {"action_mse": float(totals[0] / size), "value_mse": float(totals[1] / size)}


def warm_start(model, vec_env, vec_normalize, name: str, seed: int) -> int:
    """Collect ``DEMO_STEPS`` env steps of teacher ``name``'s demonstrations in ``vec_env``
    (the raw training envs; ``vec_normalize``: their normalising wrapper or None) and
    ``clone`` them into ``model``; returns the env steps used, which the run's budget counts."""
    demonstrations = collect_demonstrations(vec_env, name, DEMO_STEPS, seed)
    clone(model, demonstrations, vec_normalize, seed)
    return len(demonstrations.actions)
