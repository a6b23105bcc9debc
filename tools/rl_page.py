"""``docs/results/rl.md``: the RL comparison's tables and figures, from the merged CSVs.

- ``load(root)``: the rows of ``docs/results/rl_comparison.csv`` and ``rl_clutter.csv``
  (the second may be absent), checked for the columns ``report add`` writes (the
  safe-success columns aside, which rows written before them lack).
- ``safe_note(rows)``: the line saying which runs predate the safe-success measure
  (``PREDATE_SAFE_SUCCESS`` when all of them do).
- ``default_runs(comparison)``: the runs of ``HEADLINE_VARIANTS`` trained with today's
  defaults, at the largest budget all of them reached (the README's headline).
- ``results_markdown(comparison, clutter, figures, sources, page_dir, write_figures)``: the
  learning-curve figures, today's defaults as ``rliable`` reports them (IQM, probability of
  improvement, performance profiles), then at every training budget the summary table and attention
  against its bound and control, then the clutter tables (safe success and contact time
  too where the rows record them); writes the figures into
  ``figures`` unless told not to.
- ``page(root, write_figures)``: the whole page, with its banner and how to reproduce it.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from attentive_gym.agents.config import ALGO_DEFAULTS, RunSpec
from attentive_gym.agents.merged import (
    SCALED,
    UNNOTED_MODEL_VERSION,
    UNNOTED_TASK_VERSION,
    algo_tag,
    budgets,
    clutter_targets,
    default_tag,
    labelled,
    learning_curve_figures,
    ordered,
    summarise_by_setting,
    targets,
)
from attentive_gym.agents.plots import (
    plot_learning_curves,
    plot_performance_profiles,
    plot_success_vs_distractors,
    recorded,
    steps_label,
)
from attentive_gym.agents.results import EVAL_COLUMNS, SAFE_COLUMNS, read_csv, run_finals, summarise, summary_markdown
from attentive_gym.agents.sweep import sweep_tables
from attentive_gym.agents.warm_start import DEMO_STEPS
from attentive_gym.envs.reward import SAFE_CONTACT_S
from page_text import FIGURES, RESULTS, banner, interval, number, summary_interval, table

NAME = "rl.md"
#: The variants of the README's headline and of the performance profiles, in their order:
#: the baseline, the control, attention, the bound.
HEADLINE_VARIANTS = ("raw", "random-focus", "focus", "oracle")
#: The performance profiles' figure.
PROFILES = "rl_profiles.png"
#: The figure of today's PPO rollout beside the earlier one, and its variants.
ROLLOUTS = "rl_rollouts.png"
ROLLOUT_VARIANTS = ("raw", "focus", "oracle")
#: The main comparison's arena (the ``--env-kwargs`` of the commands under "Reproduce").
COMPARISON_ARENA = "an 8 m arena with 2 distractors and 3 rubble pieces per 100 m²"
COMPARISON = RESULTS / "rl_comparison.csv"
CLUTTER = RESULTS / "rl_clutter.csv"
#: What rows without ``SAFE_COLUMNS`` are, in one line.
PREDATE_SAFE_SUCCESS = (
    f"These runs predate the safe-success measure (success with at most {SAFE_CONTACT_S:g} s in contact): they "
    "trained and were evaluated on the v0 task, so they record no safe success or contact time."
)


def _intro(comparison: Sequence[Mapping[str, Any]]) -> str:
    """What the runs were and how to read their names and intervals."""
    episodes = sorted({int(row["n_episodes"]) for row in comparison})
    default = default_tag()
    return f"""\
The comparison trains every variant in {COMPARISON_ARENA} (the clutter sweep: 0–5
distractors) and evaluates it at every checkpoint on {" or ".join(map(str, episodes))} episodes
with the deterministic policy. A variant's name says how it was trained
when that is not PPO with SB3's constant learning rate on normalised observations:
`({default})` is today's default (raw's and the oracle's tag has no model note: they run no
model; attended rows without one are on its version 0), `(recurrent-ppo)` an LSTM policy, `(unscaled)` a policy
that saw the observation in its own units. Intervals are 95 % stratified-bootstrap
intervals across seeds, as `rliable` computes them; P(success > raw of its setting) is the
probability that a seed of the variant beats a seed of raw trained the same way. Safe success
is success with at most {SAFE_CONTACT_S:g} s in contact in the episode, contact time the seconds
in contact per episode.
A run trained further than a table's budget counts there with its curve cut at the budget.
A warm-started run's first evaluation follows the cloning of its teacher's demonstrations
({DEMO_STEPS:,} env steps): its curve starts where the cloned behaviour is, and what PPO adds is the
rise after it.
`oracle` (the target's true state in the focus layout) bounds attention from above;
`random-focus` (a region drawn at random, the same bottleneck) is its control.
"""


_REPRODUCE = """\
## Reproduce

Train a comparison, merge its rows into the CSVs, and render this page. A run records the
task and model versions it trains on, the latest by default, and PPO clones the privileged
teacher first by default. The headline's rows (`warm start privileged, task v1, model v2`)
ran on the model's version 2, hence `--model 2` (the latest is 3). At 1M steps a run takes
about 4 to 6 minutes, two at a time on 2 cores, so the 40 runs about 100 minutes:

```bash
attentive-gym compare --variants raw,random-focus,focus,oracle --seeds 41,42,43,44,45,46,47,48,49,50 \\
    --steps 1000000 --eval-every 250000 --eval-episodes 40 --model 2 \\
    --env-kwargs '{"arena_size_m": 8, "num_distractors": 2, "rubble_per_100m2": 3}' --workers 2 --out runs/main
python tools/report.py add runs/main/results.csv              # into docs/results/rl_comparison.csv
python tools/report.py render                                  # this page, the figures and the README's headline
```

The rows tagged `model v1` are `focus` and `random-focus` on the model's version 1, the same
command with `--variants random-focus,focus --model 1` (about 100 minutes). The rows tagged
`model v3` are `focus` on version 3, the latest: the same command with `--variants focus
--seeds 41,42,43,44,45 --model 3` (about 30 minutes).

The rows of the other settings came from the same command with their flags: `--task 0
--warm-start none` for the rows without a task note (the first task, without a warm start),
`--algo
recurrent-ppo`, `--n-envs 4 --algo-kwargs '{"n_steps": 256, "batch_size": 256}'` for the rollout
before `algo_defaults` 3, `--algo-kwargs '{"learning_rate": 3e-4}'` for the constant rate,
`--obs-scaling none`. An attended variant's rows without a model note are on the model's
version 0; raw's and the oracle's never carry one, as they run no model. The clutter sweep
(the first task, 250k steps):

```bash
attentive-gym compare --variants raw,focus,oracle,random-focus --distractors 0,1,2,3,5 --seeds 5 --steps 250000 \\
    --task 0 --warm-start none --eval-every 50000 --eval-episodes 20 --checkpoint-every 50000 \\
    --env-kwargs '{"arena_size_m": 8, "rubble_per_100m2": 3}' --workers 2 --out runs/clutter
python tools/report.py add runs/clutter/sweep.csv --clutter   # into docs/results/rl_clutter.csv
```

`report add` tags the rows with the comparison's algorithm, learning rate, rollout, warm start,
task and model (from its `compare.json`) and replaces the rows of the same runs; see
[the agents guide](../agents.md).
"""


def default_runs(comparison: Sequence[Mapping[str, Any]]) -> tuple[int, list[dict[str, Any]]] | None:
    """``(budget, rows)``: the rows of ``HEADLINE_VARIANTS`` trained with today's defaults
    (``RunSpec``'s algorithm tag, normalised observations) at the largest budget every one of
    them reached (runs trained further cut there); None when no budget has them all."""
    rows = [
        row
        for row in comparison
        if row["variant"] in HEADLINE_VARIANTS
        and row["algo"] == default_tag(row["variant"])
        and row.get("obs_scaling") == SCALED
    ]
    complete = [(budget, at) for budget, at in budgets(rows) if {r["variant"] for r in at} == set(HEADLINE_VARIANTS)]
    return complete[-1] if complete else None


def _margin(summary: Mapping[str, Mapping[str, Any]], variant: str, key: str) -> str:
    """``"yes, 0.78"``: whether ``variant``'s ``key`` interval (a ``summarise`` key such as
    ``final_safe_success``) lies wholly above raw's, and the share of the raw → oracle gap its
    mean closes; "—" where a mean is not recorded or the oracle is not above raw."""
    row, raw, oracle = summary[variant], summary["raw"], summary["oracle"]
    means = [row[f"{key}_mean"], raw[f"{key}_mean"], oracle[f"{key}_mean"]]
    if any(math.isnan(value) for value in means) or means[2] <= means[1]:
        return "—"
    above = "yes" if row[f"{key}_ci_low"] > raw[f"{key}_ci_high"] else "no"
    return f"{above}, {(means[0] - means[1]) / (means[2] - means[1]):.2f}"


def _profiles_markdown(
    comparison: Sequence[Mapping[str, Any]], figures: Path, link: Path, write_figures: bool
) -> list[str]:
    """The section on today's defaults' headline runs, as ``rliable`` reports them: IQM and
    probability of improvement over raw in success and safe success, and the performance
    profiles' figure (drawn unless told not to); none without those runs."""
    found = default_runs(comparison)
    if found is None:
        return []
    budget, at_budget = found
    summary = {row["variant"]: row for row in summarise(at_budget)}
    finals = run_finals(at_budget)
    seeds = sorted({row["n_seeds"] for row in summary.values()})

    def cell(row, key):
        """A summary value without a ``_mean`` suffix (an IQM, a probability), with its interval."""
        return "—" if math.isnan(row[key]) else interval(row[key], row[f"{key}_ci_low"], row[f"{key}_ci_high"])

    keys = ("final_success_iqm", "final_safe_success_iqm", "prob_improvement", "prob_safe_improvement")
    lines = [[variant, *(cell(summary[variant], key) for key in keys)] for variant in HEADLINE_VARIANTS]
    if write_figures:
        plot_performance_profiles(
            {variant: finals[variant] for variant in HEADLINE_VARIANTS},
            figures / PROFILES,
            title=f"today's defaults, {steps_label(budget)} env steps, {' or '.join(map(str, seeds))} seeds per "
            "variant: shaded: 95 % bootstrap CI",
        )
    margins = [
        [variant, *(_margin(summary, variant, key) for key in ("final_success", "final_safe_success"))]
        for variant in HEADLINE_VARIANTS
        if variant not in ("raw", "oracle")
    ]
    return [
        f"## Today's defaults at {steps_label(budget)} env steps: IQM, improvement and performance profiles",
        "",
        f"The README's headline runs ({' or '.join(map(str, seeds))} seeds per variant), as `rliable` reports "
        "them: the interquartile mean of the seeds' final values, the probability that a seed beats a seed of "
        "raw, and each variant's run-score distribution (the share of its runs scoring above τ; a curve above "
        "another at every τ dominates it).",
        "",
        table(
            [
                "variant",
                "final success, IQM [95 % CI]",
                f"final safe success (≤ {SAFE_CONTACT_S:g} s in contact), IQM [95 % CI]",
                "P(success > raw) [95 % CI]",
                "P(safe success > raw) [95 % CI]",
            ],
            lines,
        ),
        "Against raw and the oracle (means): whether the variant's interval lies above raw's, and the share of "
        "the raw → oracle gap it closes.",
        "",
        table(["variant", "success: above raw, gap closed", "safe success: above raw, gap closed"], margins),
        f"![performance profiles of today's defaults]({(link / PROFILES).as_posix()})",
        "",
    ]


def _rollouts_markdown(
    comparison: Sequence[Mapping[str, Any]], figures: Path, link: Path, write_figures: bool
) -> list[str]:
    """The learning curves of raw, focus and oracle under today's PPO rollout beside the earlier
    one (``algo_defaults`` 2: 4 envs × 256 steps), both on the model's version
    ``UNNOTED_MODEL_VERSION`` and the task's ``UNNOTED_TASK_VERSION`` without a warm start (the
    earlier rollout's only setting), up to today's headline budget
    (drawn unless told not to); none without rows of both."""
    found = default_runs(comparison)
    first = {"env_version": UNNOTED_MODEL_VERSION, "task_version": UNNOTED_TASK_VERSION, "warm_start": None}
    today = algo_tag(RunSpec(**first).to_dict())
    earlier = algo_tag(RunSpec(algo_defaults=ALGO_DEFAULTS[-2], **first).to_dict())
    if found is None:
        return []
    budget = found[0]
    rows = [
        row
        for row in comparison
        if row["algo"] in (today, earlier)
        and row.get("obs_scaling") == SCALED
        and row["variant"] in ROLLOUT_VARIANTS
        and row["env_steps"] <= budget
    ]
    if {(row["algo"], row["variant"]) for row in rows} != {(t, v) for t in (today, earlier) for v in ROLLOUT_VARIANTS}:
        return []
    rollout = {today: "32 envs × 64 steps", earlier: "4 envs × 256 steps"}
    if write_figures:
        plot_learning_curves(
            [
                {**row, "variant": f"{row['variant']} ({rollout[row['algo']]})"}
                for row in sorted(rows, key=lambda r: (r["algo"] != earlier, ROLLOUT_VARIANTS.index(r["variant"])))
            ],
            figures / ROLLOUTS,
            metrics=("success_rate",),
            title="two PPO rollouts: mean over seeds, shaded: 95 % bootstrap CI",
        )
    return [
        "## Today's PPO rollout against the earlier one",
        "",
        f"Success of raw, focus and oracle trained with today's rollout (`{today}`) and with the "
        f"earlier rollout (`{earlier}`: 4 envs × 256 steps, minibatches of 256), up to {steps_label(budget)} env "
        "steps, focus on the model's version 0 in both. Today's takes half the gradient steps per env step and "
        "trains 2.4× faster per CPU second "
        "([the note](../notes/2026-12-06-faster-ppo.md)).",
        "",
        f"![learning curves of the two rollouts]({(link / ROLLOUTS).as_posix()})",
        "",
    ]


def load(root: Path) -> tuple[list[dict[str, Any]], list[dict[str, Any]]]:
    """``(comparison rows, clutter rows)`` under ``root``; no clutter rows when its file is absent.

    Raises:
        ValueError: the comparison holds no rows, or a file lacks the columns ``report add`` writes.
        FileNotFoundError: the comparison is missing.
    """
    if not (root / COMPARISON).is_file():
        raise FileNotFoundError(f"{root / COMPARISON} is missing; 'python tools/report.py add' writes it")
    comparison = read_csv(root / COMPARISON)
    clutter = read_csv(root / CLUTTER) if (root / CLUTTER).is_file() else []
    if not comparison:
        raise ValueError(f"{root / COMPARISON} holds no rows; add a comparison with 'python tools/report.py add'")
    check_columns(root / COMPARISON, comparison, ("algo", *EVAL_COLUMNS), "a file written by 'report add'")
    check_columns(
        root / CLUTTER, clutter, ("algo", "num_distractors", *EVAL_COLUMNS), "a file written by 'report add --clutter'"
    )
    return comparison, clutter


def check_columns(path: Path, rows: Sequence[Mapping[str, Any]], columns: Sequence[str], what: str) -> None:
    """``ValueError`` naming the ``columns`` the first of ``rows`` (read from ``path``) lacks;
    ``SAFE_COLUMNS`` may be missing (rows written before the safe-success measure)."""
    missing = [c for c in columns if rows and c not in rows[0] and c not in SAFE_COLUMNS]
    if missing:
        raise ValueError(f"{path} lacks the columns {missing} ({what} has them)")


def safe_note(rows: Sequence[Mapping[str, Any]]) -> str:
    """One line for ``rows`` some of which do not record the safe-success measure
    (``SAFE_COLUMNS``): they predate it (the v0 task); "" when every row records it."""
    missing = [row for row in rows if not recorded([row], "safe_success_rate")]
    if not missing:
        return ""
    if len(missing) == len(rows):
        return PREDATE_SAFE_SUCCESS + "\n"
    return "Runs whose safe success and contact time read — predate that measure (the v0 task).\n"


def _attention_markdown(rows: Sequence[Mapping[str, Any]]) -> str:
    """A row per attended variant: how soon it reaches raw's final success, whether its
    interval lies above raw's, and the share of the raw → oracle gap it closes."""
    return table(
        [
            "attended variant",
            "env steps to raw's final success, ÷ raw's budget",
            "final success interval above raw's",
            "share of the raw → oracle gap closed",
        ],
        [
            [
                row["variant"],
                number(row["steps_fraction"]),
                "yes" if row["above_raw"] else "no",
                number(row["gap_closed"]),
            ]
            for row in rows
        ],
    )


def _count_headers(first: str, counts: Sequence[int]) -> list[str]:
    """The headers of a table with a ``first`` column and a column per distractor count."""
    return [first, *(f"{n} distractor{'s' * (n != 1)}" for n in counts)]


def _clutter_markdown(summary: Sequence[Mapping[str, Any]], variants: Sequence[str], key: str = "final_success") -> str:
    """A row per variant (in the order of ``variants``), a column per count: the summary's
    ``key`` (``<key>_mean`` [``_ci_low``, ``_ci_high``]; default final success)."""
    counts = sorted({row["num_distractors"] for row in summary})
    cell = {(row["variant"], row["num_distractors"]): row for row in summary}
    rows = []
    for variant in variants:
        values = []
        for n in counts:
            row = cell.get((variant, n))
            values.append("—" if row is None else summary_interval(row, key) + f" (n={row['n_seeds']})")
        rows.append([variant, *values])
    return table(_count_headers("variant", counts), rows)


def _clutter_safe_markdown(summary: Sequence[Mapping[str, Any]], variants: Sequence[str]) -> list[str]:
    """The parts of the final safe success and contact time tables by distractor count (as
    ``_clutter_markdown``); none where ``summary`` does not record them."""
    if not recorded(summary, "final_safe_success_mean"):
        return []
    return [
        f"Final safe success (at most {SAFE_CONTACT_S:g} s in contact; mean [95 % bootstrap CI]) by the number "
        "of distractors:",
        "",
        _clutter_markdown(summary, variants, "final_safe_success"),
        "Final contact time (s in contact per episode; mean [95 % bootstrap CI]) by the number of distractors:",
        "",
        _clutter_markdown(summary, variants, "final_contact_s"),
    ]


def _clutter_margins_markdown(rows: Sequence[Mapping[str, Any]]) -> str:
    """A row per attended variant, a column per count: "margin over raw (gap closed)"."""
    counts = sorted({row["num_distractors"] for row in rows})
    cell = {(row["variant"], row["num_distractors"]): row for row in rows}
    lines = []
    for variant in dict.fromkeys(row["variant"] for row in rows):
        values = []
        for n in counts:
            row = cell.get((variant, n))
            if row is None or math.isnan(row["margin"]):
                values.append("—")
            else:
                gap = "" if math.isnan(row["gap_closed"]) else f" ({row['gap_closed']:.2f})"
                values.append(f"{row['margin']:+.2f}{gap}")
        lines.append([variant, *values])
    return table(_count_headers("attended variant", counts), lines)


def results_markdown(
    comparison: Sequence[Mapping[str, Any]],
    clutter: Sequence[Mapping[str, Any]],
    figures: Path,
    page_dir: Path = Path("."),
    write_figures: bool = True,
) -> str:
    """The results as Markdown, figure paths relative to ``page_dir``; writes the figures
    into ``figures`` unless ``write_figures`` is false.

    Args:
        comparison: the merged comparison's rows (``COMPARISON_COLUMNS``).
        clutter: the merged clutter sweep's rows (``CLUTTER_COLUMNS``), or none.
        figures: the folder of the PNGs.
        page_dir: the folder of the page the text goes into.
        write_figures: draw the figures (else only name them).
    """
    link = Path(os.path.relpath(figures, page_dir))
    rows = labelled(ordered(comparison))
    # the curves of the runs on normalised observations where there are some, one figure per setting
    figures_of_settings = learning_curve_figures([row for row in rows if row.get("obs_scaling") == SCALED] or rows)
    parts = [
        "## Learning curves",
        "",
        "Mean success rate over seeds at each evaluation (with safe success and contact time where the runs "
        "record them), a figure per training setting; shaded: the 95 % bootstrap interval.",
        "",
    ]
    for name, setting, _ in figures_of_settings:
        parts += [f"![learning curves, {setting}]({(link / name).as_posix()})", ""]
    parts += _profiles_markdown(comparison, figures, link, write_figures)
    parts += _rollouts_markdown(comparison, figures, link, write_figures)
    for budget, at_budget in budgets(rows):
        summary = summarise_by_setting(at_budget)
        parts += [
            f"## After {steps_label(budget)} env steps",
            "",
            summary_markdown(summary),
            "Attention against its bound and control:",
            "",
            _attention_markdown(targets(at_budget, summary)),
        ]
    if write_figures:
        for name, setting, setting_rows in figures_of_settings:
            plot_learning_curves(
                setting_rows, figures / name, title=f"{setting}: mean over seeds, shaded: 95 % bootstrap CI"
            )
    if clutter:
        clutter_rows = labelled(ordered(clutter))
        variants = list(dict.fromkeys(row["variant"] for row in clutter_rows))
        clutter_budgets = budgets(clutter_rows, ("variant", "num_distractors", "seed"))
        for k, (budget, at_budget) in enumerate(clutter_budgets):
            clutter_summary = sweep_tables(at_budget)
            shown = [v for v in variants if any(row["variant"] == v for row in clutter_summary)]
            after = f" after {steps_label(budget)} env steps" if len(clutter_budgets) > 1 else ""
            parts += [
                f"## Against clutter{after}",
                "",
                "Final success (mean [95 % bootstrap CI]) by the number of distractors:",
                "",
                _clutter_markdown(clutter_summary, shown),
                *_clutter_safe_markdown(clutter_summary, shown),
                "Final success over raw's at each count, and in brackets the share of the raw → oracle gap "
                "closed (where the oracle was run at that count):",
                "",
                _clutter_margins_markdown(clutter_targets(clutter_summary)),
            ]
            if k == 0:  # the figure: the sweep at the budget every run reached, normalised runs where there are
                parts += [f"![final success against distractors]({(link / 'rl_clutter.png').as_posix()})", ""]
                if write_figures:
                    scaled_variants = {row["variant"] for row in at_budget if row.get("obs_scaling") == SCALED}
                    plot_success_vs_distractors(
                        [row for row in clutter_summary if row["variant"] in scaled_variants] or clutter_summary,
                        figures / "rl_clutter.png",
                        budget if len(clutter_budgets) > 1 else None,
                    )
    return "\n".join(parts).rstrip() + "\n"


def page(root: Path, write_figures: bool = True) -> str:
    """The text of ``docs/results/rl.md`` under ``root``; draws the figures unless told not to."""
    comparison, clutter = load(root)
    sources = [COMPARISON, *([CLUTTER] if clutter else [])]
    body = results_markdown(comparison, clutter, root / FIGURES, root / RESULTS, write_figures)
    note = safe_note([*comparison, *clutter])
    intro = _intro(comparison) + (f"\n{note}" if note else "")
    return "\n".join(["# RL comparison", "", banner(sources), intro, body, _REPRODUCE])
