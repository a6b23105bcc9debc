"""What a goal-action agent chooses during its evaluations: the rows of a run's ``goal_choice.csv``.

A ``goal-action`` agent (``attentive_gym.wrappers.GoalActionWrapper``) sets the model's top-down
goal and its six map weights every step, and each step's ``info`` says what is in force
(``goal_choice``, ``goal_choice_matches``, ``map_weights``). ``GoalChoiceTally`` counts an
evaluation's steps from those entries; its ``row`` is the evaluation's row of
``goal_choice.csv`` (``goal_choice_columns``): whether the learned goal is the task's, and
which weights the agent settles on, as training goes on.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from attentive_gym.attention import Goal
from attentive_gym.attention.config import MAP_NAMES

__all__ = [
    "GOAL_CHOICE_FILE",
    "GoalChoiceTally",
    "goal_choice_columns",
    "goal_share_columns",
    "menu_labels",
    "WEIGHT_COLUMNS",
]

#: The file of a goal-action run (and of a comparison with goal-action runs).
GOAL_CHOICE_FILE = "goal_choice.csv"
#: The columns of the mean weight of F1..F6 over an evaluation's steps.
WEIGHT_COLUMNS = tuple(f"mean_weight_{name}" for name in MAP_NAMES)


def goal_share_columns(menu_size: int) -> tuple[str, ...]:
    """The columns of each menu entry's share of an evaluation's steps: ``goal_share_0`` ...
    ``goal_share_<menu_size - 1>`` (menu order)."""
    return tuple(f"goal_share_{index}" for index in range(menu_size))


def goal_choice_columns(menu_size: int) -> tuple[str, ...]:
    """The columns of ``goal_choice.csv`` for a goal menu of ``menu_size`` entries.

    ``variant``, ``seed``, ``env_steps`` (the training's env steps at the evaluation),
    ``n_steps`` (the evaluation's env steps, all episodes together), ``task_goal_share`` (the
    share of those steps whose chosen goal is the episode's task goal, in [0, 1]), each menu
    entry's share (``goal_share_columns``, in [0, 1], summing to 1) and the mean weight of each
    map (``WEIGHT_COLUMNS``, in [0, the wrapper's ``max_weight``]).
    """
    run = ("variant", "seed", "env_steps")
    return (*run, "n_steps", "task_goal_share", *goal_share_columns(menu_size), *WEIGHT_COLUMNS)


class GoalChoiceTally:
    """Counts of an evaluation's steps: which menu entry was in force, whether it was the
    task's goal, and the sum of the map weights.

    Call it with each step's ``info`` (``evaluation.evaluate_policy``'s ``on_step``), then
    read ``row()``.

    Args:
        menu_size: entries of the agent's goal menu (``GoalActionWrapper.goal_menu``), >= 1.
    """

    def __init__(self, menu_size: int) -> None:
        if isinstance(menu_size, bool) or not isinstance(menu_size, int) or menu_size < 1:
            raise ValueError(f"menu_size must be an integer >= 1, got {menu_size!r}")
        self.menu_size = menu_size
        self.steps = 0
        self.task_goal_steps = 0
        self.choice_steps = np.zeros(menu_size, np.int64)
        self.weight_sums = np.zeros(len(MAP_NAMES))

    def __call__(self, info: Mapping[str, Any]) -> None:
        """Count one step from its ``info``; ``ValueError`` when ``info`` lacks the choice
        (not a goal-action env) or holds no choice (a step before any action) or one outside the menu."""
        missing = [key for key in ("goal_choice", "goal_choice_matches", "map_weights") if key not in info]
        if missing:
            raise ValueError(f"a goal-action step's info holds {missing}; is the env wrapped by GoalActionWrapper?")
        choice = info["goal_choice"]
        if not 0 <= choice < self.menu_size:
            raise ValueError(f"info['goal_choice'] must be a menu index in [0, {self.menu_size}), got {choice!r}")
        self.steps += 1
        self.task_goal_steps += bool(info["goal_choice_matches"])
        self.choice_steps[choice] += 1
        self.weight_sums += info["map_weights"]

    def row(self) -> dict[str, Any]:
        """``n_steps``, ``task_goal_share``, each entry's share and each map's mean weight
        (``goal_choice_columns`` but the run's ``variant``, ``seed`` and ``env_steps``)."""
        if self.steps == 0:
            raise ValueError("no evaluation step was counted; call the tally with each step's info first")
        shares = self.choice_steps / self.steps
        weights = self.weight_sums / self.steps
        return {
            "n_steps": self.steps,
            "task_goal_share": self.task_goal_steps / self.steps,
            **{column: float(share) for column, share in zip(goal_share_columns(self.menu_size), shares)},
            **{column: float(weight) for column, weight in zip(WEIGHT_COLUMNS, weights)},
        }


def menu_labels(menu: Sequence[Goal | None]) -> tuple[str, ...]:
    """Each entry of a goal menu as a legend names it: ``"no goal"`` or the goal's text
    (``"speed in [0.5, 0.9] m/s"``)."""
    return tuple("no goal" if goal is None else str(goal) for goal in menu)
