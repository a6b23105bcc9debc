"""One line per observation variant: ``make_env(variant, **env_kwargs)`` and registered ids.

| variant | id | observation |
|---|---|---|
| ``"raw"`` | ``AttentiveRescue-v0`` | sonar, laser, odometry, goal |
| ``"raw-stack"`` | ``AttentiveRescueStack-v0`` | the same, sensors stacked over 4 steps |
| ``"focus"`` | ``AttentiveRescueFocus-v0`` | the attended region only (49 numbers) |
| ``"saliency"`` | ``AttentiveRescueSaliency-v0`` | raw readings + maps L and M |
| ``"masked"`` | ``AttentiveRescueMasked-v0`` | raw readings outside the focus masked + masks |
| ``"goal-action"`` | ``AttentiveRescueGoalAction-v0`` | ``"focus"``, the action also picks goal and weights |

``flatten=True`` turns the ``Dict`` observation into one ``Box`` (for ``MlpPolicy``);
keep it False for ``MultiInputPolicy``.
"""

from __future__ import annotations

import functools
from typing import Any, Mapping

import gymnasium as gym

from attentive_gym.attention import AttentionConfig
from attentive_gym.envs.rescue_env import AttentiveRescueEnv
from attentive_gym.wrappers.attention import AttentionWrapper
from attentive_gym.wrappers.goal_action import DEFAULT_GOAL_MENU, GoalActionWrapper
from attentive_gym.wrappers.stack import StackedReadings

__all__ = ["VARIANTS", "VARIANT_IDS", "make_env"]

#: Variant name → registered environment id.
VARIANT_IDS: dict[str, str] = {
    "raw": "AttentiveRescue-v0",
    "raw-stack": "AttentiveRescueStack-v0",
    "focus": "AttentiveRescueFocus-v0",
    "saliency": "AttentiveRescueSaliency-v0",
    "masked": "AttentiveRescueMasked-v0",
    "goal-action": "AttentiveRescueGoalAction-v0",
}
VARIANTS = tuple(VARIANT_IDS)
_ATTENTION_MODES = {"focus": "focus", "saliency": "saliency", "masked": "masked", "goal-action": "focus"}


def make_env(
    variant: str = "focus",
    *,
    flatten: bool = False,
    attention: AttentionConfig | None = None,
    weights: Mapping[str, float] | None = None,
    n_frames: int = 4,
    goal_menu=DEFAULT_GOAL_MENU,
    **env_kwargs: Any,
) -> gym.Env:
    """Build the rescue environment with the observation of ``variant``.

    Args:
        variant: one of ``VARIANTS``.
        flatten: flatten the ``Dict`` observation into one float32 ``Box``.
        attention: the model's configuration (attended variants only).
        weights: the model's map weights (attended variants only).
        n_frames: frames stacked by ``"raw-stack"``.
        goal_menu: goals the ``"goal-action"`` agent chooses from.
        env_kwargs: keyword arguments of ``AttentiveRescueEnv`` (``scenario``,
            ``sensor_noise``, ``dt``, ``render_mode``, the arena's knobs, ...).

    Returns:
        The wrapped environment (no ``TimeLimit``: the environment truncates itself).
    """
    if variant not in VARIANT_IDS:
        raise ValueError(f"unknown variant {variant!r}; allowed: {list(VARIANTS)}")
    if variant in ("raw", "raw-stack") and (attention is not None or weights is not None):
        raise ValueError(f"variant {variant!r} has no attention; 'attention' and 'weights' apply to {list(_ATTENTION_MODES)}")
    env: gym.Env = AttentiveRescueEnv(**env_kwargs)
    if variant == "raw-stack":
        env = StackedReadings(env, n_frames)
    elif variant in _ATTENTION_MODES:
        env = AttentionWrapper(env, _ATTENTION_MODES[variant], config=attention, weights=weights)
        if variant == "goal-action":
            env = GoalActionWrapper(env, goal_menu)
    if flatten:
        env = gym.wrappers.FlattenObservation(env)
    return env


def registered_entry_points() -> dict[str, Any]:
    """Environment id → entry point, for the variants other than the base environment."""
    return {env_id: functools.partial(make_env, variant) for variant, env_id in VARIANT_IDS.items() if variant != "raw"}
