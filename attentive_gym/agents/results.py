"""Tidy results: atomic file writes, CSV rows, summaries with bootstrap confidence intervals.

- ``write_text_atomic`` / ``write_json_atomic`` / ``write_csv_atomic``: temp file in the same
  folder + ``os.replace``, so a reader (or a killed run) never sees half a file.
- ``EVAL_COLUMNS``: the columns of every evaluation row (``eval.csv`` of a run and the
  ``results.csv`` of a comparison, one row per (variant, seed, eval point)).
- ``SAFE_COLUMNS``: the evaluation columns of the safe rescue task, which rows written before
  it lack (their summaries read them as not recorded: NaN).
- ``summarise``: final success rate, safe success rate and return (mean and IQM with 95 %
  bootstrap CIs), final contact time (mean with its CI), the probability of improvement over
  a baseline (in success and in safe success), and steps to a success threshold.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from attentive_gym._atomic import atomic_file
from attentive_gym.envs.reward import SAFE_CONTACT_S
from attentive_gym.statistics import bootstrap_ci, iqm, mean, probability_of_improvement

__all__ = [
    "EVAL_COLUMNS",
    "SAFE_COLUMNS",
    "SUMMARY_COLUMNS",
    "run_finals",
    "write_text_atomic",
    "write_json_atomic",
    "write_csv_atomic",
    "read_csv",
    "summarise",
    "summary_markdown",
]

#: One evaluation of one run. Units: env_steps (environment steps), success_rate and
#: safe_success_rate [0, 1] (safe: the target reached with at most ``SAFE_CONTACT_S`` = 1 s
#: of contact in the episode), returns (reward units), collision_steps (steps in contact per
#: episode), contact_s (s in contact per episode), episode_length (steps), wall_s (s since
#: the run started).
EVAL_COLUMNS = (
    "variant",
    "seed",
    "env_steps",
    "n_episodes",
    "success_rate",
    "safe_success_rate",
    "mean_return",
    "std_return",
    "mean_collision_steps",
    "mean_contact_s",
    "mean_episode_length",
    "wall_s",
)
#: The columns of ``EVAL_COLUMNS`` that evaluations record since the safe rescue task; rows
#: written before it lack them (or hold NaN there), and summaries read them as not recorded.
SAFE_COLUMNS = ("safe_success_rate", "mean_contact_s")
#: One variant's summary. Units: as in ``EVAL_COLUMNS`` (``final_contact_s_*``: s in contact
#: per episode); the ``final_safe_success_*``, ``final_contact_s_*`` and ``prob_safe_improvement*``
#: columns are NaN where the variant's rows do not record ``SAFE_COLUMNS``.
SUMMARY_COLUMNS = (
    "variant",
    "n_seeds",
    "final_env_steps",
    "final_success_mean",
    "final_success_ci_low",
    "final_success_ci_high",
    "final_success_iqm",
    "final_success_iqm_ci_low",
    "final_success_iqm_ci_high",
    "final_safe_success_mean",
    "final_safe_success_ci_low",
    "final_safe_success_ci_high",
    "final_safe_success_iqm",
    "final_safe_success_iqm_ci_low",
    "final_safe_success_iqm_ci_high",
    "final_contact_s_mean",
    "final_contact_s_ci_low",
    "final_contact_s_ci_high",
    "final_return_mean",
    "final_return_ci_low",
    "final_return_ci_high",
    "final_return_iqm",
    "final_return_iqm_ci_low",
    "final_return_iqm_ci_high",
    "improvement_over",
    "prob_improvement",
    "prob_improvement_ci_low",
    "prob_improvement_ci_high",
    "prob_safe_improvement",
    "prob_safe_improvement_ci_low",
    "prob_safe_improvement_ci_high",
    "threshold",
    "seeds_reaching_threshold",
    "steps_to_threshold_mean",
    "steps_to_threshold_ci_low",
    "steps_to_threshold_ci_high",
)


def write_text_atomic(path: str | os.PathLike, text: str) -> Path:
    """Write ``text`` to ``path`` through a temp file in the same folder and ``os.replace``."""
    with atomic_file(path) as handle:
        handle.write(text)
    return Path(path)


def write_json_atomic(path: str | os.PathLike, data: Any) -> Path:
    """``write_text_atomic`` of ``json.dumps(data, indent=2)``."""
    return write_text_atomic(path, json.dumps(data, indent=2, sort_keys=True) + "\n")


def write_csv_atomic(path: str | os.PathLike, rows: Iterable[Mapping[str, Any]], columns: Sequence[str]) -> Path:
    """Write ``rows`` (dicts) with header ``columns``; missing keys are left empty."""
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=list(columns), extrasaction="ignore", lineterminator="\n")
    writer.writeheader()
    for row in rows:
        writer.writerow({k: _format(v) for k, v in row.items()})
    return write_text_atomic(path, buffer.getvalue())


def _format(value: Any) -> Any:
    if isinstance(value, (float, np.floating)):
        return "" if not math.isfinite(value) else f"{float(value):.6g}"
    if isinstance(value, np.integer):
        return int(value)
    return value


def read_csv(path: str | os.PathLike) -> list[dict[str, Any]]:
    """Rows of a CSV as dicts, numbers converted (int where integral text, else float; '' → NaN)."""
    with open(path, newline="", encoding="utf-8") as handle:
        return [{k: _parse(v) for k, v in row.items()} for row in csv.DictReader(handle)]


def _parse(text: str) -> Any:
    if text == "":
        return math.nan
    for cast in (int, float):
        try:
            return cast(text)
        except ValueError:
            pass
    return text


# --- summaries --------------------------------------------------------------------------
def _by_run(rows: Sequence[Mapping[str, Any]]) -> dict[tuple[str, int], list[Mapping[str, Any]]]:
    runs: dict[tuple[str, int], list[Mapping[str, Any]]] = {}
    for row in rows:
        runs.setdefault((row["variant"], int(row["seed"])), []).append(row)
    for key in runs:
        runs[key].sort(key=lambda r: r["env_steps"])
    return runs


def _finals(runs: Sequence[list[Mapping[str, Any]]], metric: str, final_points: int) -> list[float]:
    """Each run's ``metric`` averaged over its last ``final_points`` evaluations."""
    return [float(np.mean([r[metric] for r in run[-final_points:]])) for run in runs]


def _recorded_finals(runs: Sequence[list[Mapping[str, Any]]], metric: str, final_points: int) -> list[float]:
    """``_finals`` of a metric of ``SAFE_COLUMNS``, all NaN (not recorded) unless every run
    records it at each of its last ``final_points`` evaluations: a variant's summary never
    rests on a subset of its seeds."""
    finals = [float(np.mean([r.get(metric, math.nan) for r in run[-final_points:]])) for run in runs]
    return [math.nan] * len(finals) if any(math.isnan(value) for value in finals) else finals


def run_finals(rows: Sequence[Mapping[str, Any]], final_points: int = 1) -> dict[str, dict[str, list[float]]]:
    """Each variant's per-seed final ``success``, ``safe_success`` and ``contact_s`` (the
    values ``summarise`` rests on, in seed order): variant → metric → one value per seed;
    the safe-success and contact lists are NaN unless every seed records them."""
    by_run = _by_run(rows)
    out: dict[str, dict[str, list[float]]] = {}
    for variant in dict.fromkeys(r["variant"] for r in rows):
        runs = [run for key, run in sorted(by_run.items()) if key[0] == variant]
        out[variant] = {
            "success": _finals(runs, "success_rate", final_points),
            "safe_success": _recorded_finals(runs, "safe_success_rate", final_points),
            "contact_s": _recorded_finals(runs, "mean_contact_s", final_points),
        }
    return out


def _check_rates(row: Mapping[str, Any]) -> None:
    """``ValueError`` naming the run and eval point of ``row`` unless its success rate is a
    number in [0, 1], its safe success rate NaN/absent or in [0, success rate], and its
    contact time NaN/absent or >= 0 s."""
    where = f"{row['variant']} seed {row['seed']} at {row['env_steps']} env steps"
    success = row["success_rate"]
    if not (isinstance(success, (int, float, np.number)) and 0.0 <= success <= 1.0):
        raise ValueError(f"success_rate must be a number in [0, 1] at every evaluation; {where} has {success!r}")
    safe, contact = row.get("safe_success_rate", math.nan), row.get("mean_contact_s", math.nan)
    if not (isinstance(safe, (int, float, np.number)) and (math.isnan(safe) or 0.0 <= safe <= success)):
        raise ValueError(
            f"safe_success_rate must be empty (not recorded) or a number in [0, success_rate]; {where} has "
            f"{safe!r} with success_rate {success!r}"
        )
    if not (isinstance(contact, (int, float, np.number)) and (math.isnan(contact) or contact >= 0.0)):
        raise ValueError(f"mean_contact_s must be empty (not recorded) or a number of s >= 0; {where} has {contact!r}")


def summarise(
    rows: Sequence[Mapping[str, Any]], threshold: float = 0.5, final_points: int = 1, baseline: str | None = "raw"
) -> list[dict[str, Any]]:
    """One summary row per variant (in first-seen order) from tidy evaluation rows.

    Args:
        rows: rows with ``EVAL_COLUMNS`` (several seeds and eval points per variant);
            ``SAFE_COLUMNS`` may be absent or NaN (rows written before them).
        threshold: success rate a seed must reach; its steps to threshold are its first
            eval point at or above it (seeds that never reach it are counted in
            ``seeds_reaching_threshold`` and left out of the mean).
        final_points: the last ``final_points`` eval points of each seed are averaged into
            its "final" value (1 = the last evaluation only).
        baseline: the variant that ``prob_improvement`` and ``prob_safe_improvement``
            compare with (default ``"raw"``; the first variant when it is absent or None).

    Returns:
        Dicts with ``SUMMARY_COLUMNS``: means and interquartile means across seeds with
        95 % stratified bootstrap intervals (``attentive_gym.statistics``) clipped to
        the metric's range; NaN bounds for a single seed; NaN safe-success and contact
        columns for a variant not every seed of which records ``SAFE_COLUMNS`` (and NaN
        ``prob_safe_improvement`` when the baseline does not).
    """
    if not 0.0 <= threshold <= 1.0:
        raise ValueError(f"threshold must be a success rate in [0, 1], got {threshold!r}")
    if final_points < 1:
        raise ValueError(f"final_points must be >= 1, got {final_points!r}")
    for row in rows:
        _check_rates(row)
    by_run = _by_run(rows)
    variants = list(dict.fromkeys(r["variant"] for r in rows))
    runs = {variant: [run for key, run in by_run.items() if key[0] == variant] for variant in variants}
    if variants and baseline not in runs:
        baseline = variants[0]
    baseline_success = _finals(runs[baseline], "success_rate", final_points) if variants else []
    baseline_safe = _recorded_finals(runs[baseline], "safe_success_rate", final_points) if variants else []
    summary = []
    for variant in variants:
        success = _finals(runs[variant], "success_rate", final_points)
        safe = _recorded_finals(runs[variant], "safe_success_rate", final_points)
        contact = _recorded_finals(runs[variant], "mean_contact_s", final_points)
        returns = _finals(runs[variant], "mean_return", final_points)
        reached = [
            float(hit)
            for hit in (
                next((r["env_steps"] for r in run if r["success_rate"] >= threshold), None) for run in runs[variant]
            )
            if hit is not None
        ]
        final_steps = int(min(run[-1]["env_steps"] for run in runs[variant]))
        longest = float(max(run[-1]["env_steps"] for run in runs[variant]))  # a seed may reach it past final_steps
        row = {"variant": variant, "n_seeds": len(runs[variant]), "final_env_steps": final_steps}
        for key, values, statistic, bounds in (
            ("final_success", success, mean, (0.0, 1.0)),
            ("final_success_iqm", success, iqm, (0.0, 1.0)),
            ("final_safe_success", safe, mean, (0.0, 1.0)),
            ("final_safe_success_iqm", safe, iqm, (0.0, 1.0)),
            ("final_contact_s", contact, mean, (0.0, math.inf)),
            ("final_return", returns, mean, (-math.inf, math.inf)),
            ("final_return_iqm", returns, iqm, (-math.inf, math.inf)),
        ):
            point, low, high = bootstrap_ci(values, statistic, bounds)
            row.update(
                {f"{key}{'' if key.endswith('iqm') else '_mean'}": point, f"{key}_ci_low": low, f"{key}_ci_high": high}
            )
        row["improvement_over"] = baseline
        for key, values, baseline_values in (
            ("prob_improvement", success, baseline_success),
            ("prob_safe_improvement", safe, baseline_safe),
        ):
            point, low, high = probability_of_improvement(values, baseline_values)
            row.update({key: point, f"{key}_ci_low": low, f"{key}_ci_high": high})
        steps = bootstrap_ci(reached, mean, (0.0, longest))
        row.update(
            {
                "threshold": threshold,
                "seeds_reaching_threshold": len(reached),
                "steps_to_threshold_mean": steps[0],
                "steps_to_threshold_ci_low": steps[1],
                "steps_to_threshold_ci_high": steps[2],
            }
        )
        summary.append(row)
    return summary


def summary_markdown(summary: Sequence[Mapping[str, Any]]) -> str:
    """A markdown table of ``summarise``'s rows (values with [95 % CI]); "—" where a value is
    not recorded (the safe-success and contact columns of rows written before them)."""

    def ci(row, point_key, key, fmt, why_none="1 seed: no CI"):
        """The value with its interval, or with ``why_none`` where it has none."""
        point, low, high = row[point_key], row[f"{key}_ci_low"], row[f"{key}_ci_high"]
        if isinstance(point, float) and math.isnan(point):
            return "—"
        if math.isnan(low):
            return f"{point:{fmt}} ({why_none})"
        return f"{point:{fmt}} [{low:{fmt}}, {high:{fmt}}]"

    def single(row, otherwise):
        return "1 seed: no CI" if row["n_seeds"] == 1 else otherwise

    baselines = list(dict.fromkeys(row["improvement_over"] for row in summary)) or ["raw"]
    baseline = baselines[0] if len(baselines) == 1 else f"{baselines[0].partition(' (')[0]} of its setting"
    baseline_single = f"{baseline} has 1 seed: no CI"
    lines = [
        "| variant | seeds | env steps | final success, mean [95 % CI] "
        f"| final safe success (≤ {SAFE_CONTACT_S:g} s in contact), mean [95 % CI] | final success, IQM [95 % CI] "
        f"| P(success > {baseline}) [95 % CI] | P(safe success > {baseline}) [95 % CI] "
        "| final contact time (s / episode), mean [95 % CI] | final return, mean [95 % CI] | seeds reaching threshold "
        "| env steps to threshold, mean [95 % CI] |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for row in summary:
        lines.append(
            f"| {row['variant']} | {row['n_seeds']} | {row['final_env_steps']} "
            f"| {ci(row, 'final_success_mean', 'final_success', '.2f')} "
            f"| {ci(row, 'final_safe_success_mean', 'final_safe_success', '.2f')} "
            f"| {ci(row, 'final_success_iqm', 'final_success_iqm', '.2f')} "
            f"| {ci(row, 'prob_improvement', 'prob_improvement', '.2f', single(row, baseline_single))} "
            f"| {ci(row, 'prob_safe_improvement', 'prob_safe_improvement', '.2f', single(row, baseline_single))} "
            f"| {ci(row, 'final_contact_s_mean', 'final_contact_s', '.2f')} "
            f"| {ci(row, 'final_return_mean', 'final_return', '.2f')} "
            f"| {row['seeds_reaching_threshold']}/{row['n_seeds']} "
            f"(≥ {row['threshold']:.2f}) "
            f"| {ci(row, 'steps_to_threshold_mean', 'steps_to_threshold', '.0f', single(row, '1 seed reached it'))} |"
        )
    return "\n".join(lines) + "\n"
