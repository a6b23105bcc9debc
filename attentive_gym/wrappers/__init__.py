"""Wrappers that put the attentional model into the agent's loop.

- ``AttentionWrapper``: observations of what the robot attends to (``"focus"``,
  ``"saliency"`` or ``"masked"``); ``info["attention"]`` holds the model's output.
- ``GoalActionWrapper``: the agent's action also chooses the top-down goal and weights.
- ``StackedReadings``: the raw-sensor baseline with a frame stack.
- ``OracleFocus``: the focus observation filled from the privileged state (a bound).
- ``make_env`` / ``VARIANTS`` / ``VARIANT_IDS``: one line per observation variant.
"""

from attentive_gym.wrappers.attention import OBSERVATION_MODES, AttentionWrapper
from attentive_gym.wrappers.goal_action import DEFAULT_GOAL_MENU, GoalActionWrapper
from attentive_gym.wrappers.oracle import OracleFocus
from attentive_gym.wrappers.stack import StackedReadings
from attentive_gym.wrappers.variants import VARIANT_IDS, VARIANTS, make_env

__all__ = [
    "AttentionWrapper",
    "DEFAULT_GOAL_MENU",
    "GoalActionWrapper",
    "OBSERVATION_MODES",
    "OracleFocus",
    "StackedReadings",
    "VARIANTS",
    "VARIANT_IDS",
    "make_env",
]
