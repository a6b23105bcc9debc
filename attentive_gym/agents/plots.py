"""Figures of a comparison: learning curves (mean across seeds with a 95 % bootstrap band, per
variant), what a goal-action agent chooses as it trains (``plot_goal_choice``) and, for a
clutter sweep, final success, safe success and contact time against the number of distractors;
zero-shot success per shift (``plot_generalisation``); and the run-score distributions of
final success and safe success (``plot_performance_profiles``). Panels of the safe-success
measure (``results.SAFE_COLUMNS``) are left out where the rows do not record it (rows written
before it)."""

from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from attentive_gym._atomic import save_figure
from attentive_gym._optional import require
from attentive_gym.agents.goal_choice import WEIGHT_COLUMNS, goal_share_columns, menu_labels
from attentive_gym.attention import Goal
from attentive_gym.attention.config import MAP_ALIASES, MAP_NAMES
from attentive_gym.envs.reward import SAFE_CONTACT_S
from attentive_gym.statistics import bootstrap_ci, performance_profile
from attentive_gym.wrappers.goal_action import DEFAULT_GOAL_MENU, DEFAULT_MAX_WEIGHT
from attentive_gym.wrappers.variants import VARIANTS

__all__ = [
    "curve_stats",
    "recorded",
    "plot_learning_curves",
    "plot_success_vs_distractors",
    "plot_goal_choice",
    "plot_generalisation",
    "plot_performance_profiles",
    "split_label",
    "steps_label",
    "METRIC_BOUNDS",
    "METRIC_LABELS",
]

#: The range of each bounded metric; confidence bands are clipped to it.
METRIC_BOUNDS = {
    "success_rate": (0.0, 1.0),
    "safe_success_rate": (0.0, 1.0),
    "mean_collision_steps": (0.0, float("inf")),
    "mean_contact_s": (0.0, float("inf")),
    "mean_episode_length": (0.0, float("inf")),
}
#: The axis label of each metric of an evaluation row, with its unit.
METRIC_LABELS = {
    "success_rate": "success rate",
    "safe_success_rate": f"safe success rate (≤ {SAFE_CONTACT_S:g} s in contact)",
    "mean_return": "mean return",
    "mean_collision_steps": "collision steps / episode",
    "mean_contact_s": "contact time / episode (s)",
    "mean_episode_length": "episode length (steps)",
}
#: The y range of a rate's panel: [0, 1] with a margin, so that markers at 0 and 1 show whole.
_RATE_LIMITS = (-0.03, 1.03)


def steps_label(steps: float, _position=None) -> str:
    """An env-step count as a tick label: 0, 500, 50k, 1.5M."""
    for scale, suffix in ((1e6, "M"), (1e3, "k")):
        if abs(steps) >= scale:
            return f"{steps / scale:.3g}{suffix}"
    return f"{steps:.0f}"


def recorded(rows: Sequence[Mapping[str, Any]], key: str) -> bool:
    """Whether some row of ``rows`` holds a number (not NaN) under ``key``: rows written
    before a column existed lack it, or hold NaN there."""
    return any(isinstance(row.get(key), (int, float, np.number)) and not math.isnan(row[key]) for row in rows)


def _rate_axis(ax, metric: str) -> None:
    """Fix the y range of a panel of a rate (bounded to [0, 1] in ``METRIC_BOUNDS``) to [0, 1]."""
    if METRIC_BOUNDS.get(metric) == (0.0, 1.0):
        ax.set_ylim(*_RATE_LIMITS)


def curve_stats(
    rows: Sequence[Mapping[str, Any]], variant: str, metric: str, bounds: tuple[float, float] | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(env_steps, mean, ci_low, ci_high) of ``metric`` across seeds at each eval point of ``variant``.

    The band is the 95 % bootstrap interval of the mean, clipped to ``bounds`` (default: the
    metric's ``METRIC_BOUNDS``, else none); NaN (no band) with one seed, NaN where no seed
    records ``metric``. Only eval points every seed of the variant reached are kept (so a
    band always spans the same seeds).
    """
    by_steps: dict[int, list[float]] = {}
    seeds = {r["seed"] for r in rows if r["variant"] == variant}
    for row in rows:
        if row["variant"] == variant:
            by_steps.setdefault(int(row["env_steps"]), []).append(float(row.get(metric, math.nan)))
    steps = sorted(s for s, v in by_steps.items() if len(v) == len(seeds))
    if bounds is None:
        bounds = METRIC_BOUNDS.get(metric, (-float("inf"), float("inf")))
    stats = np.array([bootstrap_ci(by_steps[s], bounds=bounds) for s in steps]).reshape(-1, 3)
    return np.array(steps), stats[:, 0], stats[:, 1], stats[:, 2]


#: Up to this many variants, the legend sits inside the first panel; more go below the
#: panels, in rows of ``_LEGEND_COLUMNS`` entries.
_LEGEND_INSIDE = 4
_LEGEND_COLUMNS = 4
#: Line styles of a label's settings (``split_label``), in order of appearance; a
#: variant keeps one colour across settings.
_SETTING_STYLES = ("-", "--", ":", "-.")


def split_label(label: str) -> tuple[str, str]:
    """A variant label as ``(variant, setting)``: ``"focus (recurrent-ppo)"`` →
    ``("focus", " (recurrent-ppo)")``; ``"raw"`` → ``("raw", "")``."""
    variant, bracket, notes = label.partition(" (")
    return variant, bracket + notes


def _line_styles(labels: Sequence[str]) -> dict[str, dict[str, str]]:
    """matplotlib ``color`` and ``linestyle`` of each label: one colour per variant, the same
    in every figure for the project's variants (their order in ``VARIANTS``; others after
    them), one line style per setting (both cycling when there are more than they have)."""
    parts = {label: split_label(label) for label in labels}
    variants = list(dict.fromkeys([*VARIANTS, *(variant for variant, _ in parts.values())]))
    settings = list(dict.fromkeys(setting for _, setting in parts.values()))
    return {
        label: {
            "color": f"C{variants.index(variant) % 10}",
            "linestyle": _SETTING_STYLES[settings.index(setting) % len(_SETTING_STYLES)],
        }
        for label, (variant, setting) in parts.items()
    }


def plot_learning_curves(
    rows: Sequence[Mapping[str, Any]],
    path: str | os.PathLike,
    metrics: Sequence[str] = ("success_rate", "safe_success_rate", "mean_contact_s", "mean_return"),
    title: str | None = None,
) -> Path:
    """Write a PNG with one panel per metric that ``rows`` record (``recorded``; two panels a
    row): per-variant mean curve and 95 % CI band vs env steps, rates on [0, 1]; a variant
    has one colour, its settings (``split_label``) different line styles.

    Raises:
        ValueError: no rows, or none of ``metrics`` recorded in them.
    """
    plt = _pyplot()
    from matplotlib.ticker import FuncFormatter

    variants = list(dict.fromkeys(r["variant"] for r in rows))
    if not variants:
        raise ValueError("no evaluation rows to plot")
    shown = [metric for metric in metrics if recorded(rows, metric)]
    if not shown:
        raise ValueError(f"the evaluation rows record none of the metrics {list(metrics)} to plot")
    columns = min(len(shown), 2)
    panel_rows = math.ceil(len(shown) / columns)
    fig, axes = plt.subplots(panel_rows, columns, figsize=(5.2 * columns, 3.8 * panel_rows), squeeze=False)
    for ax in axes.flat[len(shown) :]:
        ax.remove()
    styles = _line_styles(variants)
    for ax, metric in zip(axes.flat, shown):
        for variant in variants:
            steps, mean, low, high = curve_stats(rows, variant, metric)
            n = len({r["seed"] for r in rows if r["variant"] == variant})
            (line,) = ax.plot(steps, mean, marker=".", label=f"{variant} (n={n})", **styles[variant])
            ax.fill_between(steps, low, high, color=line.get_color(), alpha=0.2, linewidth=0)
        ax.set_xlabel("environment steps")
        ax.xaxis.set_major_formatter(FuncFormatter(steps_label))
        ax.set_ylabel(METRIC_LABELS.get(metric, metric))
        _rate_axis(ax, metric)
        ax.grid(alpha=0.3)
    fig.suptitle(title or "mean over seeds, shaded: 95 % bootstrap CI", fontsize=10)
    if len(variants) <= _LEGEND_INSIDE:
        axes[0][0].legend(loc="best", fontsize=8)
        return _save(fig, path)
    legend_columns = min(len(variants), _LEGEND_COLUMNS if columns > 1 else 2)  # what the figure's width holds
    fig.legend(
        *axes[0][0].get_legend_handles_labels(), loc="lower center", ncol=legend_columns, fontsize=8, frameon=False
    )
    legend_rows = math.ceil(len(variants) / legend_columns)
    fig.tight_layout(rect=(0, 0.06 * legend_rows / panel_rows, 1, 1))  # room for the legend's rows below the panels
    return _save(fig, path, layout=False)


#: The panels of ``plot_success_vs_distractors``: summary key (``results.SUMMARY_COLUMNS``'s
#: ``<key>_mean``, ``_ci_low``, ``_ci_high``) and the metric whose label and range it takes.
_SWEEP_PANELS = (
    ("final_success", "success_rate"),
    ("final_safe_success", "safe_success_rate"),
    ("final_contact_s", "mean_contact_s"),
)


def plot_success_vs_distractors(
    summary: Sequence[Mapping[str, Any]], path: str | os.PathLike, budget: int | None = None
) -> Path:
    """Write a PNG of final success rate, and beside it final safe success rate and contact
    time (s / episode) where ``summary`` records them (``recorded``), against the number of
    distractors: means, 95 % bootstrap CIs as error bars, one line per variant, from rows of
    ``sweep.sweep_tables``; a variant has one colour, its settings (``split_label``)
    different line styles, as in ``plot_learning_curves``; the legend sits beside the last
    panel. ``budget`` (env steps), when given, is named in the title: runs trained further
    are shown cut there."""
    plt = _pyplot()
    variants = list(dict.fromkeys(r["variant"] for r in summary))
    if not variants:
        raise ValueError("no summary rows to plot")
    panels = [(key, metric) for key, metric in _SWEEP_PANELS if recorded(summary, f"{key}_mean")]
    fig, axes = plt.subplots(1, len(panels), figsize=(4.6 * len(panels) + 3.0, 3.9), squeeze=False)
    styles = _line_styles(variants)
    for ax, (key, metric) in zip(axes[0], panels):
        for variant in variants:
            rows = sorted((r for r in summary if r["variant"] == variant), key=lambda r: r["num_distractors"])
            x = np.array([r["num_distractors"] for r in rows], float)
            y = np.array([r[f"{key}_mean"] for r in rows], float)
            low = np.nan_to_num(y - np.array([r[f"{key}_ci_low"] for r in rows], float))
            high = np.nan_to_num(np.array([r[f"{key}_ci_high"] for r in rows], float) - y)
            seeds = min(r["n_seeds"] for r in rows)
            ax.errorbar(
                x, y, yerr=[low, high], marker="o", capsize=3, label=f"{variant} (n={seeds})", **styles[variant]
            )
        ax.set_xlabel("distractors in the arena")
        ax.set_ylabel(f"final {METRIC_LABELS[metric]}")
        _rate_axis(ax, metric)
        ax.set_xticks(sorted({r["num_distractors"] for r in summary}))
        ax.grid(alpha=0.3)
    axes[0][-1].legend(loc="center left", bbox_to_anchor=(1.02, 0.5), fontsize=8)
    after = "" if budget is None else f"after {steps_label(budget)} env steps (longer runs cut there)\n"
    fig.suptitle(f"{after}mean over seeds, bars: 95 % bootstrap CI", fontsize=10)
    return _save(fig, path)


def plot_goal_choice(
    rows: Sequence[Mapping[str, Any]],
    path: str | os.PathLike,
    menu: Sequence[Goal | None] = DEFAULT_GOAL_MENU,
    max_weight: float = DEFAULT_MAX_WEIGHT,
    title: str | None = None,
) -> Path:
    """Write a PNG of what a goal-action agent chooses as it trains, from the rows of its runs'
    ``goal_choice.csv`` (one variant, any number of seeds; ``goal_choice.goal_choice_columns``).

    Left: the share of the evaluation steps whose chosen goal is the task's (black), and each
    entry of ``menu``'s share, on [0, 1]. Right: each map's mean weight (F1..F6), on [0,
    ``max_weight``] (``GoalActionWrapper``'s). Each curve is the mean across seeds vs env
    steps with its 95 % bootstrap CI band (``curve_stats``), as in ``plot_learning_curves``.

    Raises:
        ValueError: no rows, rows of more than one variant, or rows whose menu shares are not
            those of ``menu`` (one ``goal_share_<i>`` column per entry).
    """
    plt = _pyplot()
    variants = list(dict.fromkeys(r["variant"] for r in rows))
    if not variants:
        raise ValueError("no goal-choice rows to plot")
    if len(variants) > 1:
        raise ValueError(f"plot_goal_choice draws one variant's rows; got the variants {variants}")
    shares = goal_share_columns(len(menu))
    found = tuple(key for key in rows[0] if key.startswith("goal_share_"))
    if found != shares:
        raise ValueError(
            f"the rows hold the menu shares {list(found)}, the menu of {len(menu)} entries needs {list(shares)}"
        )
    fig, (goals_ax, weights_ax) = plt.subplots(1, 2, figsize=(11.0, 4.6))
    names = {name: alias.replace("_", " ") for alias, name in MAP_ALIASES.items()}
    goal_curves = [
        ("task_goal_share", "the task's goal", {"color": "black", "linewidth": 2.2}),
        *((column, label, {"color": f"C{i}"}) for i, (column, label) in enumerate(zip(shares, menu_labels(menu)))),
    ]
    weight_curves = [
        (column, f"{name} ({names[name]})", {"color": f"C{i}"})
        for i, (column, name) in enumerate(zip(WEIGHT_COLUMNS, MAP_NAMES))
    ]
    _draw_curves(goals_ax, rows, goal_curves, (0.0, 1.0), "chosen goal's share of evaluation steps")
    _draw_curves(weights_ax, rows, weight_curves, (0.0, max_weight), f"mean map weight (0 to {max_weight:g})")
    goals_ax.set_ylim(*_RATE_LIMITS)
    weights_ax.set_ylim(-0.03 * max_weight, 1.03 * max_weight)
    seeds = len({r["seed"] for r in rows})
    fig.suptitle(title or f"{variants[0]}, n={seeds} seeds: mean over seeds, shaded: 95 % bootstrap CI", fontsize=10)
    return _save(fig, path)


def plot_generalisation(
    summary: Sequence[Mapping[str, Any]], path: str | os.PathLike, title: str | None = None
) -> Path:
    """Two panels, success and safe success: per shift (x), one bar per variant with its 95 %
    interval."""
    plt = _pyplot()
    shifts = list(dict.fromkeys(row["shift"] for row in summary))
    variants = list(dict.fromkeys(row["variant"] for row in summary))
    styles = _line_styles(variants)
    by_key = {(row["shift"], row["variant"]): row for row in summary}
    fig, axes = plt.subplots(2, 1, figsize=(max(7.0, 1.1 * len(shifts) + 2), 6.5), sharex=True)
    width = 0.8 / len(variants)
    for ax, metric, label in zip(axes, ("success", "safe_success"), ("success rate", "safe success rate")):
        for k, variant in enumerate(variants):
            xs, heights, errors = [], [], [[], []]
            for i, shift in enumerate(shifts):
                row = by_key.get((shift, variant))
                if row is None:
                    continue
                mean, low, high = (row[f"{metric}_{part}"] for part in ("mean", "ci_low", "ci_high"))
                xs.append(i - 0.4 + width * (k + 0.5))
                heights.append(mean)
                errors[0].append(0.0 if math.isnan(low) else mean - low)
                errors[1].append(0.0 if math.isnan(high) else high - mean)
            ax.bar(xs, heights, width, yerr=errors, capsize=2, color=styles[variant]["color"], label=variant)
        ax.set_ylim(0.0, 1.0)
        ax.set_ylabel(f"{label}\n(mean over seeds, 95 % CI)")
        ax.grid(axis="y", alpha=0.3)
    axes[0].legend(ncol=len(variants), fontsize="small", loc="lower center", bbox_to_anchor=(0.5, 1.0), frameon=False)
    axes[-1].set_xticks(range(len(shifts)), shifts, rotation=20, ha="right")
    axes[-1].set_xlabel("evaluation setting (the policies trained on 'as trained')")
    if title:
        fig.suptitle(title)
    return _save(fig, path)


def plot_performance_profiles(
    finals: Mapping[str, Mapping[str, Sequence[float]]], path: str | os.PathLike, title: str | None = None
) -> Path:
    """Two panels, final success and final safe success: for each variant, the share of its
    runs scoring above τ against τ in [0, 1] (``statistics.performance_profile``), with a
    shaded 95 % bootstrap band.

    Args:
        finals: variant → ``{"success": [...], "safe_success": [...]}``, one value per seed.
        path: the PNG to write.
        title: the figure's title.
    """
    plt = _pyplot()
    taus = np.linspace(0.0, 1.0, 101)
    styles = _line_styles(list(finals))
    fig, axes = plt.subplots(1, 2, figsize=(10.0, 4.2), sharey=True)
    for ax, metric, label in zip(
        axes, ("success", "safe_success"), ("final success", f"final safe success (≤ {SAFE_CONTACT_S:g} s in contact)")
    ):
        for variant, values in finals.items():
            share, low, high = performance_profile(values[metric], taus)
            style = styles[variant]
            ax.step(taus, share, where="post", color=style["color"], linestyle=style["linestyle"], label=variant)
            ax.fill_between(taus, low, high, step="post", color=style["color"], alpha=0.15, linewidth=0)
        ax.set_xlim(0.0, 1.0)
        ax.set_ylim(-0.02, 1.02)
        ax.set_xlabel(f"τ ({label} of a run)")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("fraction of runs scoring > τ")
    seeds = sorted({len(values["success"]) for values in finals.values()})
    axes[0].legend(fontsize="small", loc="lower left")
    fig.suptitle(
        title or f"performance profiles, {' or '.join(map(str, seeds))} seeds: shaded: 95 % bootstrap CI", fontsize=10
    )
    return _save(fig, path)


def _draw_curves(
    ax, rows: Sequence[Mapping[str, Any]], curves: Sequence[tuple[str, str, dict]], bounds: tuple, ylabel: str
) -> None:
    """Draw each ``(column, label, line style)`` of ``curves`` on ``ax``: the mean across the
    rows' seeds vs env steps with its 95 % CI band clipped to ``bounds``; the legend below."""
    from matplotlib.ticker import FuncFormatter

    variant = rows[0]["variant"]
    for column, label, style in curves:
        steps, mean, low, high = curve_stats(rows, variant, column, bounds)
        (line,) = ax.plot(steps, mean, marker=".", label=label, **style)
        ax.fill_between(steps, low, high, color=line.get_color(), alpha=0.15, linewidth=0)
    ax.set_xlabel("environment steps")
    ax.xaxis.set_major_formatter(FuncFormatter(steps_label))
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2, fontsize=8, frameon=False)


def _pyplot():
    """matplotlib's pyplot on the Agg backend (no display needed); ``MissingExtraError``
    without matplotlib (the ``plot`` extra, which the ``agents`` extra pulls in)."""
    require("matplotlib", "drawing a comparison's figures").use("Agg", force=False)
    import matplotlib.pyplot as plt

    return plt


def _save(fig, path: str | os.PathLike, layout: bool = True) -> Path:
    """Save ``fig`` as a PNG atomically (temp file + rename) and close it; ``layout``: tighten
    its layout first (False where the caller has laid it out)."""
    import matplotlib.pyplot as plt

    if layout:
        fig.tight_layout()
    try:
        return save_figure(fig, path, dpi=120)
    finally:
        plt.close(fig)
