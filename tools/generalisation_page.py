"""``docs/results/generalisation.md``: the main comparison's policies on settings they were not trained on.

From ``docs/results/generalisation.csv``, the rows ``attentive-gym generalise`` writes
(``agents.generalisation``): one per trained run and shift, each on the run's own 20
evaluation episodes. The page gives the figure (``agents.plots.plot_generalisation``), success
and safe success per shift and variant (mean over seeds with 95 % bootstrap intervals), and
per shift and metric whether the issue's target holds: focus above raw with the intervals
apart, asked where the oracle is above raw with the intervals apart.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from attentive_gym.agents.generalisation import SHIFTS, summarise_shifts
from attentive_gym.agents.merged import HEADLINE_MODEL_VERSION
from attentive_gym.agents.plots import plot_generalisation
from attentive_gym.envs.reward import SAFE_CONTACT_S
from page_text import FIGURES, RESULTS, banner, read_rows, summary_interval, table

NAME = "generalisation.md"
SOURCE = RESULTS / "generalisation.csv"
FIGURE = "generalisation.png"
WRITTEN_BY = "attentive-gym generalise RUNS, then cp RUNS/generalisation.csv docs/results/"
#: The variants of the tables, in their order (the comparison's).
VARIANTS = ("raw", "random-focus", "focus", "oracle")


def above(
    summary: Mapping[tuple[str, str], Mapping[str, Any]], shift: str, high: str, low: str, metric: str
) -> bool | None:
    """Whether ``high``'s ``metric`` interval (``success`` or ``safe_success``) lies above ``low``'s
    under ``shift`` (None when one is missing)."""
    a, b = summary.get((shift, high)), summary.get((shift, low))
    if a is None or b is None:
        return None
    return a[f"{metric}_ci_low"] > b[f"{metric}_ci_high"]


def verdict(summary: Mapping[tuple[str, str], Mapping[str, Any]], shift: str, metric: str) -> str:
    """The target in ``metric`` under ``shift``, in words."""
    oracle, focus = above(summary, shift, "oracle", "raw", metric), above(summary, shift, "focus", "raw", metric)
    if oracle is None or focus is None:
        return "—"
    if not oracle:
        return "not asked: the oracle's interval is not above raw's"
    return "met" if focus else "**not met**"


def metric_table(summary: Mapping[tuple[str, str], Mapping[str, Any]], shifts: Sequence[str], metric: str) -> str:
    """``metric`` (``success`` or ``safe_success``) per shift and variant, and the target."""
    rows = []
    for shift in shifts:
        cells = [shift]
        for variant in VARIANTS:
            row = summary.get((shift, variant))
            cells.append("—" if row is None else summary_interval(row, metric))
        rows.append([*cells, verdict(summary, shift, metric)])
    return table(["setting", *VARIANTS, "focus above raw (intervals apart)"], rows)


def target_sentence(summary: Mapping[tuple[str, str], Mapping[str, Any]], shifts: Sequence[str], metric: str) -> str:
    """``"met under 5 of the 8 settings where it is asked"`` for ``metric``."""
    asked = [shift for shift in shifts if above(summary, shift, "oracle", "raw", metric)]
    met = [shift for shift in asked if above(summary, shift, "focus", "raw", metric)]
    return f"met under {len(met)} of the {len(asked)} settings where it is asked"


def page(root: Path, write_figures: bool = True) -> str:
    """The text of ``docs/results/generalisation.md`` under ``root``; draws the figure unless told not to."""
    rows = read_rows(root, SOURCE.name, WRITTEN_BY)
    summary_rows = summarise_shifts(rows)
    if write_figures:
        plot_generalisation(
            summary_rows, root / FIGURES / FIGURE, title="zero-shot: mean over seeds, bars: 95 % bootstrap CI"
        )
    summary = {(row["shift"], row["variant"]): row for row in summary_rows}
    shifts = list(dict.fromkeys(row["shift"] for row in summary_rows))
    seeds = sorted({row["n_seeds"] for row in summary_rows})
    steps = sorted({int(row["env_steps"]) for row in rows})
    episodes = sorted({int(row["n_episodes"]) for row in rows})
    settings = "; ".join(f"{name}: `{SHIFTS[name]}`" for name in shifts if SHIFTS[name])
    parts = [
        "# Generalisation: the policies on settings they were not trained on",
        "",
        banner([SOURCE]),
        "The policies of the main comparison ([RL results](rl.md): PPO with today's defaults, "
        f"{' or '.join(f'{s:,}' for s in steps)} env steps, {' or '.join(map(str, seeds))} seeds per variant, "
        "trained on the safe task (task version 1: an episode ends once the robot has been in contact for more "
        f"than {SAFE_CONTACT_S:g} s, so that every success is a safe one) with the attentional model's version "
        f"{HEADLINE_MODEL_VERSION} (raw and the oracle run none) in an 8 m arena with 2 distractors, "
        "3 rubble pieces per 100 m² and 5 % Gaussian noise) are "
        f"evaluated, without further training, on {' or '.join(map(str, episodes))} episodes of each run's own "
        "evaluation seeds under one change of the environment at a time. `as trained` is the training setting "
        f"on the same episodes. The changes, as `make_env` keywords: {settings}.",
        "",
        "The target, focus above raw with the intervals apart wherever the oracle is: in success, "
        f"{target_sentence(summary, shifts, 'success')}; in safe success, "
        f"{target_sentence(summary, shifts, 'safe_success')}.",
        "",
        f"![success and safe success per setting](../figures/{FIGURE})",
        "",
        "## Success rate",
        "",
        metric_table(summary, shifts, "success"),
        f"## Safe success rate (the target reached with at most {SAFE_CONTACT_S:g} s in contact)",
        "",
        metric_table(summary, shifts, "safe_success"),
        "Intervals are 95 % bootstrap intervals across seeds, clipped to [0, 1].",
        "",
        "## Reproduce",
        "",
        "```bash",
        "# runs/main: the headline comparison of rl.md; about 4 minutes per 20 runs with 2 workers on 2 cores",
        "attentive-gym generalise runs/main --episodes 20 --workers 2",
        "cp runs/main/generalisation.csv docs/results/ && python tools/report.py render",
        "```",
        "",
    ]
    return "\n".join(parts)
