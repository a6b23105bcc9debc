"""``GoalActionWrapper``: the agent chooses its own top-down goal and map weights.

The action becomes one ``Box(-1, 1, (2 + K + 6,))`` (a space every SB3 algorithm
supports, PPO and SAC alike), laid out as

- ``[0:2]``: the motion command, passed on to the environment (linear, angular);
- ``[2:2+K]``: one score per entry of the goal menu; the highest score's goal drives
  attention (ties to the first entry);
- ``[2+K:8+K]``: the weights of F1..F6, each mapped from [−1, 1] to [0, ``max_weight``].

The choice applies to the attention computed in the same step, after the motion. At
reset the task's goal and the configured weights are in force until the first action.

Each step's ``info`` (and reset's) says what is in force (``observe_step``):

- ``"goal_choice"``: the menu index of the chosen goal (int; −1 before the first action,
  while the task's goal drives attention);
- ``"goal_choice_matches"``: whether the chosen goal is the episode's task goal (the base
  environment's ``goal``, whose text is ``info["goal"]``; bool, False before the first action);
- ``"map_weights"``: the weights of F1..F6 (``(6,)`` float64, in [0, ``max_weight``] once
  an action set them; the model's ``weights``).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import gymnasium as gym
import numpy as np

from attentive_gym.attention import Goal
from attentive_gym.attention.config import MAP_NAMES
from attentive_gym.envs.rescue_env import checked_action
from attentive_gym.world.arena import DEFAULT_TASK_GOALS
from attentive_gym.wrappers.attention import AttentionWrapper

__all__ = ["GoalActionWrapper", "DEFAULT_GOAL_MENU", "DEFAULT_MAX_WEIGHT", "NO_CHOICE"]

#: Goals the agent can choose from by default: none, the default task goals, and the
#: three direction goals.
DEFAULT_GOAL_MENU: tuple[Goal | None, ...] = (
    None,
    *DEFAULT_TASK_GOALS,
    Goal.direction_is("towards"),
    Goal.direction_is("static"),
    Goal.direction_is("away"),
)
#: The weight an action entry of +1 stands for by default.
DEFAULT_MAX_WEIGHT = 2.0
#: ``info["goal_choice"]`` before the episode's first action.
NO_CHOICE = -1


def _find_attention(env: gym.Env) -> AttentionWrapper:
    current = env
    while isinstance(current, gym.Wrapper):
        if isinstance(current, AttentionWrapper):
            return current
        current = current.env
    raise ValueError("GoalActionWrapper must wrap an AttentionWrapper (e.g. GoalActionWrapper(AttentionWrapper(env)))")


class GoalActionWrapper(gym.ActionWrapper, gym.utils.RecordConstructorArgs):
    """Extend the motion action with a goal choice and six map weights.

    Args:
        env: an environment wrapped (at any depth) by ``AttentionWrapper``, with a
            ``Box`` action of shape (2,), whose base environment holds the episode's task
            goal as ``goal`` (``AttentiveRescueEnv.goal``: a ``Goal`` or None).
        goal_menu: the goals to choose from (``None`` = no top-down goal), at least one.
        max_weight: the weight an action entry of +1 stands for (> 0).

    ``step`` is ``ActionWrapper.step`` followed by ``observe_step``, which adds the choice in
    force to ``info`` (see the module docstring); a fleet (``attentive_gym.vector.fleet``)
    runs ``action`` before its step and ``observe_step`` after it.
    """

    def __init__(
        self,
        env: gym.Env,
        goal_menu: Sequence[Goal | None] = DEFAULT_GOAL_MENU,
        max_weight: float = DEFAULT_MAX_WEIGHT,
    ) -> None:
        gym.utils.RecordConstructorArgs.__init__(self, goal_menu=goal_menu, max_weight=max_weight)
        gym.ActionWrapper.__init__(self, env)
        self._attention = _find_attention(env)
        if not (isinstance(env.action_space, gym.spaces.Box) and env.action_space.shape == (2,)):
            raise ValueError(f"GoalActionWrapper needs a Box action of shape (2,), got {env.action_space}")
        if not hasattr(env.unwrapped, "goal"):
            raise ValueError(
                "GoalActionWrapper needs a base environment holding the task's goal as 'goal' (AttentiveRescueEnv), "
                f"got {type(env.unwrapped).__name__}"
            )
        self.goal_menu = tuple(goal_menu)
        if not self.goal_menu or any(g is not None and not isinstance(g, Goal) for g in self.goal_menu):
            raise ValueError(f"goal_menu must be a non-empty sequence of Goal or None, got {goal_menu!r}")
        if not (isinstance(max_weight, (int, float)) and np.isfinite(max_weight) and max_weight > 0):
            raise ValueError(f"max_weight must be a finite number > 0, got {max_weight!r}")
        self.max_weight = float(max_weight)
        size = 2 + len(self.goal_menu) + len(MAP_NAMES)
        self.action_space = gym.spaces.Box(-1.0, 1.0, shape=(size,), dtype=np.float32)
        self._layout = f"(linear, angular, {len(self.goal_menu)} goal scores, {len(MAP_NAMES)} map weights)"
        self._choice: int | None = None  # the menu entry and weights in force
        self._weights: np.ndarray | None = None
        # the weights an episode starts with until the first action sets them (make_env's weights=)
        self._initial_weights = dict(self._attention.model.weights)

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        self._attention.clear_goal()
        self._attention.model.set_weights(self._initial_weights)
        self._choice, self._weights = None, None
        observation, info = self.env.reset(seed=seed, options=options)
        return self.observe_step(observation, info), info

    def step(self, action):
        observation, reward, terminated, truncated, info = self.env.step(self.action(action))
        return self.observe_step(observation, info), reward, terminated, truncated, info

    def observe_step(self, observation: Any, info: dict[str, Any]) -> Any:
        """The observation below, unchanged; ``info`` gains ``"goal_choice"``,
        ``"goal_choice_matches"`` and ``"map_weights"``, the choice in force (module docstring)."""
        chosen = self._choice is not None
        info["goal_choice"] = self._choice if chosen else NO_CHOICE
        info["goal_choice_matches"] = chosen and self.goal_menu[self._choice] == self.unwrapped.goal
        info["map_weights"] = np.fromiter(self._attention.model.weights.values(), np.float64, len(MAP_NAMES))
        return observation

    def action(self, action):
        action = np.clip(checked_action(action, self.action_space.shape, self._layout), -1.0, 1.0)
        k = len(self.goal_menu)
        choice = int(np.argmax(action[2 : 2 + k]))
        if choice != self._choice:  # re-planning the model's maps only on a change
            self._attention.set_goal(self.goal_menu[choice])
            self._choice = choice
        weights = (action[2 + k :] + 1.0) * 0.5 * self.max_weight
        if not np.array_equal(weights, self._weights):
            self._attention.model.set_weights(weights)
            self._weights = weights
        return action[:2].astype(np.float32)
