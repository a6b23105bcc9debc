"""One line per observation variant: ``make_env(variant, **env_kwargs)`` and registered ids.

| variant | id | observation |
|---|---|---|
| ``"raw"`` | ``AttentiveRescue-v1`` | sonar, laser, odometry, goal |
| ``"raw-stack"`` | ``AttentiveRescueStack-v1`` | the same, sensors stacked over 4 steps |
| ``"focus"`` | ``AttentiveRescueFocus-v4`` | the attended region, 3 remembered bodies, each region's nearest reading |
| ``"saliency"`` | ``AttentiveRescueSaliency-v4`` | raw readings + maps L and M |
| ``"masked"`` | ``AttentiveRescueMasked-v4`` | raw readings outside the focus masked + masks |
| ``"goal-action"`` | ``AttentiveRescueGoalAction-v4`` | ``"focus"``, the action also picks goal and weights |
| ``"oracle"`` | ``AttentiveRescueOracle-v1`` | ``"focus"``'s layout filled from the privileged state |
| ``"random-focus"`` | ``AttentiveRescueRandomFocus-v4`` | ``"focus"`` of a random region each step (a control) |

These ids build the current task (``envs.tasks.TASK_VERSIONS``: safe rescue) and the model's
current defaults (``attention.MODEL_VERSIONS``); the earlier ids
(``registration.EARLIER_IDS``) keep the earlier versions, so that their results and policies
reproduce.

``flatten=True`` turns the ``Dict`` observation into one ``Box`` (for ``MlpPolicy``);
keep it False for ``MultiInputPolicy``.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

import gymnasium as gym

from attentive_gym.attention import MODEL_VERSIONS, AttentionConfig, check_model_version
from attentive_gym.envs.rescue_env import AttentiveRescueEnv
from attentive_gym.envs.tasks import TASK_VERSIONS, check_task_version, task_proximity, task_reward
from attentive_gym.registration import VARIANT_IDS
from attentive_gym.wrappers.attention import AttentionWrapper, default_config
from attentive_gym.wrappers.goal_action import DEFAULT_GOAL_MENU, GoalActionWrapper
from attentive_gym.wrappers.oracle import OracleFocus
from attentive_gym.wrappers.stack import StackedReadings

__all__ = ["FOCUS_LAYOUT", "VARIANTS", "VARIANT_IDS", "has_proximity", "make_env"]

VARIANTS = tuple(VARIANT_IDS)
_ATTENTION_MODES = {
    "focus": "focus",
    "saliency": "saliency",
    "masked": "masked",
    "goal-action": "focus",
    "random-focus": "focus",
}
#: The variants whose observation has the focus layout (attended region, memory, optional proximity).
FOCUS_LAYOUT = ("focus", "goal-action", "random-focus", "oracle")


def has_proximity(variant: str, task: int, proximity: bool | None = None) -> bool:
    """Whether ``variant``'s observation carries the ``"proximity"`` entry: for a variant with
    the focus layout, ``proximity`` as given (the wrapper checks that it is a bool) or, where it
    is None, task ``task``'s default (``envs.tasks.task_proximity``); False for the others."""
    if variant not in FOCUS_LAYOUT:
        return False
    return task_proximity(task) if proximity is None else proximity


def make_env(
    variant: str = "focus",
    *,
    flatten: bool = False,
    attention: AttentionConfig | Mapping[str, Any] | None = None,
    weights: Mapping[str, float] | None = None,
    n_frames: int = 4,
    goal_menu=DEFAULT_GOAL_MENU,
    memory_slots: int | None = None,
    proximity: bool | None = None,
    version: int = MODEL_VERSIONS[-1],
    task: int = TASK_VERSIONS[-1],
    **env_kwargs: Any,
) -> gym.Env:
    """Build the rescue environment with the observation of ``variant``.

    Args:
        variant: one of ``VARIANTS``.
        flatten: flatten the ``Dict`` observation into one float32 ``Box``.
        attention: the model's configuration (attended variants only): an
            ``AttentionConfig`` (taken as it is), or a mapping of some of its fields over
            the defaults of ``version`` for this robot (``wrappers.attention.default_config``;
            ``--env-kwargs '{"attention": {"free_space_evidence": false}}'``).
        weights: the model's map weights (attended variants only).
        n_frames: frames stacked by ``"raw-stack"``.
        goal_menu: goals the ``"goal-action"`` agent chooses from.
        memory_slots: bodies in the working memory of the variants with the focus layout
            (``"focus"``, ``"goal-action"``, ``"random-focus"``, ``"oracle"``; default 3,
            0 = no ``"memory"`` entry).
        proximity: add the ``"proximity"`` entry (every region's nearest reading, 8
            numbers) to the variants with the focus layout: a sense of what is near, for
            avoiding what the focus does not attend (None: the task's default,
            ``envs.tasks.task_proximity``; True from task version 1).
        version: the version of the model's defaults (``attention.MODEL_VERSIONS``; the
            latest by default).
        task: the version of the task (``envs.tasks.TASK_VERSIONS``; the latest by
            default): the defaults of ``reward`` and ``proximity``.
        env_kwargs: keyword arguments of ``AttentiveRescueEnv`` (``scenario``,
            ``sensor_noise``, ``dt``, ``render_mode``, the arena's knobs, ...); a ``reward``
            mapping sets its fields over the task's reward (``envs.tasks.task_reward``).

    Returns:
        The wrapped environment (no ``TimeLimit``: the environment truncates itself).
    """
    if variant not in VARIANT_IDS:
        raise ValueError(f"unknown variant {variant!r}; allowed: {list(VARIANTS)}")
    if variant in ("raw", "raw-stack", "oracle") and (attention is not None or weights is not None):
        raise ValueError(
            f"variant {variant!r} has no attention; 'attention' and 'weights' apply to {list(_ATTENTION_MODES)}"
        )
    check_model_version(version)
    check_task_version(task)
    if isinstance(attention, Mapping):
        AttentionConfig.from_dict(attention)  # names and values checked before anything is built
    elif attention is not None and not isinstance(attention, AttentionConfig):
        raise ValueError(f"attention must be an AttentionConfig or a mapping of its fields, got {attention!r}")
    if memory_slots is not None and variant not in FOCUS_LAYOUT:
        raise ValueError(f"memory_slots applies to the variants {list(FOCUS_LAYOUT)}, not {variant!r}")
    if proximity and variant not in FOCUS_LAYOUT:
        raise ValueError(f"proximity applies to the variants {list(FOCUS_LAYOUT)}, not {variant!r}")
    proximity = has_proximity(variant, task, proximity)
    env: gym.Env = AttentiveRescueEnv(**{**env_kwargs, "reward": task_reward(task, env_kwargs.get("reward"))})
    if isinstance(attention, Mapping):
        attention = dataclasses.replace(default_config(env, version), **attention)
    if variant == "raw-stack":
        env = StackedReadings(env, n_frames)
    elif variant == "oracle":
        env = OracleFocus(env, proximity=proximity, **({} if memory_slots is None else {"memory_slots": memory_slots}))
    elif variant in _ATTENTION_MODES:
        focus = {
            "memory_slots": memory_slots,
            "selection": "random" if variant == "random-focus" else "winner",
            "proximity": proximity,
        }
        env = AttentionWrapper(
            env,
            _ATTENTION_MODES[variant],
            config=attention,
            weights=weights,
            version=version,
            **(focus if variant in FOCUS_LAYOUT else {}),
        )
        if variant == "goal-action":
            env = GoalActionWrapper(env, goal_menu)
    if flatten:
        env = gym.wrappers.FlattenObservation(env)
    return env
