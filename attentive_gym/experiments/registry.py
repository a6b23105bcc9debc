"""The paper's five experiments as data (docs/model.md §9, Colombini et al. §IV).

- ``Experiment``: one experiment — its scenario, the active maps and their weights, the
  goals, goal changes during the run, and the duration.
- ``GoalChange``: new goals from a given time on (Exp05's mid-run goal change).
- ``EXPERIMENTS``: the five experiments by name; ``get_experiment(name)`` looks one up.

The scenarios (``attentive_gym.world.builtin``) fix the geometry and the targets' motion;
this module fixes what the attentive robot attends to. Times are in seconds.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType

from attentive_gym.attention import Goal

__all__ = ["Experiment", "GoalChange", "EXPERIMENTS", "EXPERIMENT_NAMES", "get_experiment"]


@dataclass(frozen=True)
class GoalChange:
    """From ``t_s`` (s) on, the model's goals are ``goals`` (they replace the previous ones)."""

    t_s: float
    goals: tuple[Goal, ...]


@dataclass(frozen=True)
class Experiment:
    """One of the paper's experiments.

    Attributes:
        name: "exp01" … "exp05", also the name of its built-in scenario.
        title: a one-line description.
        weights: active maps and their weights, e.g. ``{"F1": 1.0, "F4": 1.0}``; the
            others are inactive.
        goals: goals set before the first step.
        goal_changes: later goal changes, in increasing time.
        duration_s: simulated time of a run (s); the run has ``duration_s / dt + 1`` steps.
        panels: the figure's panels (names of ``attentive_gym.viz.trace_figure.PANELS``),
            those of the paper's figure plus the WTA raster.
    """

    name: str
    title: str
    weights: Mapping[str, float]
    goals: tuple[Goal, ...]
    goal_changes: tuple[GoalChange, ...]
    duration_s: float
    panels: tuple[str, ...]

    def goals_at(self, t_s: float) -> tuple[Goal, ...]:
        """The goals in force at time ``t_s`` (s)."""
        goals = self.goals
        for change in self.goal_changes:
            if t_s >= change.t_s - 1e-9:
                goals = change.goals
        return goals


def _experiments() -> dict[str, Experiment]:
    speed_goal = Goal.greater("speed", 0.6)
    return {
        "exp01": Experiment(
            name="exp01",
            title="Exp01: motion (F1) — a robot approaches 0.4 m, then backs away",
            weights={"F1": 1.0},
            goals=(),
            goal_changes=(),
            duration_s=10.0,
            panels=("O1", "F1", "M", "L", "WTA"),
        ),
        "exp02": Experiment(
            name="exp02",
            title="Exp02: distance (F3, sonar + laser) — a robot drives past",
            weights={"F3": 1.0},
            goals=(),
            goal_changes=(),
            duration_s=12.0,
            panels=("O1", "O2", "F3", "L", "M", "WTA"),
        ),
        "exp03": Experiment(
            name="exp03",
            title="Exp03: motion + distance (F1 + F3) — two robots come and go",
            weights={"F1": 1.0, "F3": 1.0},
            goals=(),
            goal_changes=(),
            duration_s=24.0,
            panels=("O1", "O2", "F1", "F3", "L", "M", "WTA"),
        ),
        "exp04": Experiment(
            name="exp04",
            title="Exp04: motion + goal speed (F1 + F4, BETWEEN(0.5, 0.9) m/s)",
            weights={"F1": 1.0, "F4": 1.0},
            goals=(Goal.between("speed", 0.5, 0.9),),
            goal_changes=(),
            duration_s=17.0,
            panels=("O1", "F1", "F4", "C", "M", "L", "WTA"),
        ),
        "exp05": Experiment(
            name="exp05",
            title="Exp05: motion + goal speed (F1 + F4, GREATER(0.6) m/s), goal changed mid-run",
            weights={"F1": 1.0, "F4": 1.0},
            goals=(speed_goal,),
            goal_changes=(GoalChange(8.0, (Goal.smaller("speed", 0.6),)), GoalChange(9.0, (speed_goal,))),
            duration_s=19.0,
            panels=("O1", "F1", "F4", "C", "L", "M", "WTA"),
        ),
    }


#: The five experiments by name (read-only).
EXPERIMENTS: Mapping[str, Experiment] = MappingProxyType(_experiments())
EXPERIMENT_NAMES: tuple[str, ...] = tuple(EXPERIMENTS)


def get_experiment(name: str) -> Experiment:
    """The experiment called ``name``; ``ValueError`` listing the allowed names otherwise."""
    try:
        return EXPERIMENTS[name]
    except (KeyError, TypeError):
        raise ValueError(f"unknown experiment {name!r}; allowed: {', '.join(EXPERIMENT_NAMES)}") from None
