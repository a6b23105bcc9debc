"""``docs/results/safe_rescue.md``: raw, focus and the oracle under candidate safe-rescue tasks.

From ``docs/results/safe_rescue.csv`` (written by ``tools/safe_rescue_table.py``): per task
setting and controller, the mean over seeds of the final success, safe success, contact
time and episode length, with 95 % bootstrap intervals (``attentive_gym.statistics``).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

from attentive_gym.statistics import bootstrap_ci
from page_text import RESULTS, banner, interval, read_rows, table

NAME = "safe_rescue.md"
SOURCE = RESULTS / "safe_rescue.csv"
WRITTEN_BY = "python tools/safe_rescue_table.py"
#: column → (header, bounds of the metric, decimals, scale from the CSV's unit)
_METRICS = {
    "success_rate": ("success", (0.0, 1.0), 2, 1.0),
    "safe_success_rate": ("safe success", (0.0, 1.0), 2, 1.0),
    "mean_contact_s": ("contact (s / episode)", (0.0, float("inf")), 2, 1.0),
    "mean_episode_length": ("episode (s)", (0.0, float("inf")), 1, 0.05),
}


def _cells(rows: Sequence[Mapping[str, str]]) -> list[str]:
    """One cell per metric: the mean over the rows (seeds) with its 95 % bootstrap interval."""
    cells = []
    for column, (_, bounds, digits, scale) in _METRICS.items():
        point, low, high = bootstrap_ci([float(row[column]) * scale for row in rows], bounds=bounds)
        cells.append(interval(point, low, high, digits))
    return cells


def summary_table(rows: Sequence[Mapping[str, str]]) -> str:
    """The Markdown table: a line per (setting, controller, env steps) in first-seen order
    (the scripted controllers' env steps are 0: they are not trained)."""
    groups: dict[tuple[str, str, int], list[Mapping[str, str]]] = {}
    for row in rows:
        groups.setdefault((row["setting"], row["controller"], int(row["env_steps"])), []).append(row)
    lines = [
        [
            setting,
            controller,
            f"{steps:,}" if steps else "—",
            str(len(group)),
            str(sum(int(row["n_episodes"]) for row in group)),
            *_cells(group),
        ]
        for (setting, controller, steps), group in groups.items()
    ]
    headers = ["task setting", "controller", "env steps", "seeds", "episodes"]
    headers += [header for header, *_ in _METRICS.values()]
    return table(headers, lines)


def page(root: Path, write_figures: bool = True) -> str:
    """The text of ``docs/results/safe_rescue.md`` under ``root`` (it has no figures)."""
    rows = read_rows(root, SOURCE.name, WRITTEN_BY)
    steps = sorted({int(row["env_steps"]) for row in rows if row["controller"].startswith("ppo")})
    budget = ", ".join(f"{s:,}" for s in steps)
    return "\n".join(
        [
            "# Safe rescue: raw, focus and the oracle under candidate tasks",
            "",
            banner([SOURCE]),
            "A success is **safe** when the robot reached the target with at most 1 s in contact in the episode. "
            "Each task setting below changes the defaults (`RewardConfig()`, the focus layout without `proximity`) "
            "by the fields it names; the arena is the main comparison's (8 m, 2 distractors, 3 rubble pieces per "
            f"100 m²). `ppo raw`, `ppo focus`, `ppo random-focus`, `ppo oracle`: PPO on that variant (at {budget} "
            "env steps), its final evaluation (raw has no `proximity` entry: its laser holds it); "
            "in brackets where it differs from the earlier 4 envs × 256-step rollout, its rollout; `warm start "
            "clearance` where PPO first cloned the clearance controller's demonstrations (`--warm-start clearance`, "
            "[Agents](../agents.md); their 64,000 env steps count in the budget), `warm start privileged` where the "
            "teacher was the same controller steering for the target's true bearing, read from the world's truth, "
            "so that every variant, raw included, clones one behaviour from its own observation "
            "(`--warm-start privileged`); and `model v1` where the attended variant ran the model's version 1. "
            "Two scripted controllers on the same episodes: `true-bearing` steers at the target's true bearing at "
            "full speed, so it reaches the target on the straight line and avoids nothing; `clearance` reads the "
            "oracle's observation with `proximity` and nothing else, and heads for the target through the free "
            "heading nearest to it (`perception.controllers.clearance_controller`): what that observation allows "
            "a policy. Cells: mean over seeds [95 % bootstrap interval].",
            "",
            summary_table(rows),
            "## Reproduce",
            "",
            "```bash",
            'ARENA=\'"arena_size_m": 8.0, "num_distractors": 2, "rubble_per_100m2": 3.0\'',
            "for seed in 41 42 43; do  # one setting; about 6 min per run on 2 cores",
            "  attentive-gym train --variant oracle --seed $seed --steps 250000 --eval-every 125000 "
            "--eval-episodes 40 \\",
            "    --out runs/safe/limit1-prox-s$seed --env-kwargs "
            '"{$ARENA, \\"proximity\\": true, \\"reward\\": {\\"contact_limit_s\\": 1.0}}"',
            "done",
            f"{WRITTEN_BY} runs/safe/*-s4[123]   # adds the true-bearing rows; writes {SOURCE.as_posix()}",
            "",
            "# today's rollout, with and without the warm start: 5 seeds × 1M each, about 30 minutes per line",
            'TASK="{$ARENA, \\"proximity\\": true, \\"reward\\": {\\"contact_limit_s\\": 1.0, \\"near_per_s\\": 4.0}}"',
            "COMMON='--variants oracle --seeds 41,42,43,44,45 --steps 1000000 --eval-every 250000 --eval-episodes 40 "
            "--model 1'  # the model's version of the time",
            'attentive-gym compare $COMMON --env-kwargs "$TASK" --out runs/safe-plain',
            'attentive-gym compare $COMMON --env-kwargs "$TASK" --warm-start clearance --out runs/safe-warm',
            "# focus: the same with --variants focus, into runs/safe-focus-plain and runs/safe-focus-warm",
            "# one teacher for all (10 seeds, about 40 minutes per line): the privileged teacher for raw, focus,",
            "# random-focus and the oracle, and raw without it (5 seeds); raw's task has no proximity entry",
            'RAW_TASK="{$ARENA, \\"reward\\": {\\"contact_limit_s\\": 1.0, \\"near_per_s\\": 4.0}}"',
            "COMMON='--seeds 41,42,43,44,45,46,47,48,49,50 --steps 1000000 --eval-every 250000 --eval-episodes 40 "
            "--workers 2 --model 1'",
            'attentive-gym compare --variants raw $COMMON --env-kwargs "$RAW_TASK" --warm-start privileged '
            "--out runs/safe-raw-privileged",
            'attentive-gym compare --variants raw $COMMON --seeds 41,42,43,44,45 --env-kwargs "$RAW_TASK" '
            "--out runs/safe-raw-plain",
            'attentive-gym compare --variants focus $COMMON --env-kwargs "$TASK" --warm-start privileged '
            "--out runs/safe-focus-privileged",
            'attentive-gym compare --variants random-focus $COMMON --env-kwargs "$TASK" --warm-start privileged '
            "--out runs/safe-random-focus-privileged",
            'attentive-gym compare --variants oracle $COMMON --env-kwargs "$TASK" --warm-start privileged '
            "--out runs/safe-oracle-privileged",
            f"{WRITTEN_BY} runs/safe-plain/runs/* runs/safe-warm/runs/* runs/safe-focus-*/runs/* "
            "runs/safe-raw-*/runs/* runs/safe-random-focus-privileged/runs/* runs/safe-oracle-privileged/runs/*",
            "python tools/report.py render",
            "```",
            "",
        ]
    )
