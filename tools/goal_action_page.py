"""``docs/results/goal_action.md``: what a goal-action agent learns to ask the model for.

From ``docs/results/goal_choice.csv``, the rows of the goal-action runs' ``goal_choice.csv``
(written by ``attentive-gym compare`` beside its ``results.csv``; ``agents.goal_choice``): per
evaluation, the share of the steps whose chosen goal is the episode's task goal, each menu
entry's share and each map's mean weight. The page gives the figure of their course over
training (``agents.plots.plot_goal_choice``) and their values at the last evaluation, mean
over seeds with a 95 % bootstrap interval; success is on the RL page.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from attentive_gym.agents.goal_choice import WEIGHT_COLUMNS, goal_share_columns, menu_labels
from attentive_gym.agents.plots import plot_goal_choice
from attentive_gym.attention.config import MAP_NAMES
from attentive_gym.statistics import bootstrap_ci
from attentive_gym.wrappers.goal_action import DEFAULT_GOAL_MENU, DEFAULT_MAX_WEIGHT
from page_text import FIGURES, RESULTS, banner, interval, read_rows, table

NAME = "goal_action.md"
SOURCE = RESULTS / "goal_choice.csv"
FIGURE = "goal_choice.png"
WRITTEN_BY = "cp RUNS/goal_choice.csv docs/results/ (attentive-gym compare --variants goal-action writes it)"


def final_rows(rows: Sequence[Mapping[str, str]]) -> list[Mapping[str, str]]:
    """Each seed's row at its last evaluation (the largest ``env_steps``)."""
    last: dict[str, Mapping[str, str]] = {}
    for row in rows:
        seed = row["seed"]
        if seed not in last or int(row["env_steps"]) > int(last[seed]["env_steps"]):
            last[seed] = row
    return list(last.values())


def final_table(rows: Sequence[Mapping[str, str]]) -> str:
    """The last evaluation's task-goal share, menu shares and mean weights: mean over seeds
    [95 % bootstrap interval inside the metric's range]."""
    final = final_rows(rows)
    labels = menu_labels(DEFAULT_GOAL_MENU)
    metrics = [("chosen goal = the task's", "task_goal_share", (0.0, 1.0))]
    metrics += [
        (f"menu: {label}", column, (0.0, 1.0))
        for label, column in zip(labels, goal_share_columns(len(DEFAULT_GOAL_MENU)))
    ]
    metrics += [
        (f"weight of {name}", column, (0.0, DEFAULT_MAX_WEIGHT)) for name, column in zip(MAP_NAMES, WEIGHT_COLUMNS)
    ]
    lines = []
    for label, column, bounds in metrics:
        point, low, high = bootstrap_ci([float(row[column]) for row in final], bounds=bounds)
        lines.append([label, interval(point, low, high)])
    steps = sorted({int(row["env_steps"]) for row in final})
    header = f"at {', '.join(f'{s:,}' for s in steps)} env steps ({len(final)} seeds)"
    return table(["share of the evaluation's steps, or mean weight", header], lines)


def page(root: Path, write_figures: bool = True) -> str:
    """The text of ``docs/results/goal_action.md`` under ``root``; draws the figure unless told not to."""
    rows = read_rows(root, SOURCE.name, WRITTEN_BY)
    if write_figures:
        plot_goal_choice(rows, root / FIGURES / FIGURE, title="goal-action: mean over seeds, shaded: 95 % bootstrap CI")
    menu = ", ".join(f"`{label}`" for label in menu_labels(DEFAULT_GOAL_MENU))
    parts: list[Any] = [
        "# Learned attention control: what goal-action asks for",
        "",
        banner([SOURCE]),
        "The `goal-action` variant's agent sets, every step, the model's top-down goal (one of the menu: "
        f"{menu}) and the weights of its six maps (0 to {DEFAULT_MAX_WEIGHT:g}), beside driving. Each "
        "evaluation counts which goal was in force and the weights' mean (`agents.goal_choice`); whether "
        "the agent's own choice reaches the model at every step is tested "
        "(`tests/wrappers/test_goal_action_choice.py`). The runs below train on today's task with today's "
        "defaults: PPO first clones the privileged teacher, whose demonstrations ask for the episode's task goal "
        "with every weight at 1 (`agents.warm_start.goal_action_label`), what `focus` attends; the figure shows "
        "whether PPO moves away from that. Its success beside `focus` is on the [RL results](rl.md).",
        "",
        f"![goal-action's choices over training](../figures/{FIGURE})",
        "",
        "## At the last evaluation",
        "",
        final_table(rows),
        "## Reproduce",
        "",
        "```bash",
        "# 5 runs, about 25 minutes with 2 workers on 2 cores",
        "attentive-gym compare --variants goal-action --seeds 41,42,43,44,45 --steps 1000000 --eval-every 250000 "
        "--eval-episodes 40 --model 1 "
        '--env-kwargs \'{"arena_size_m": 8, "num_distractors": 2, "rubble_per_100m2": 3}\' '
        "--workers 2 --out runs/goal-action-1m",
        "python tools/report.py add runs/goal-action-1m/results.csv",
        "cp runs/goal-action-1m/goal_choice.csv docs/results/ && python tools/report.py render",
        "```",
        "",
    ]
    return "\n".join(parts)
