"""Tidy results: atomic file writes, CSV rows, t-based 95 % confidence intervals, summaries.

- ``write_text_atomic`` / ``write_json_atomic`` / ``write_csv_atomic``: temp file in the same
  folder + ``os.replace``, so a reader (or a killed run) never sees half a file.
- ``t_critical`` / ``mean_ci``: Student-t confidence interval of a mean across seeds.
- ``EVAL_COLUMNS``: the columns of every evaluation row (``eval.csv`` of a run and the
  ``results.csv`` of a comparison, one row per (variant, seed, eval point)).
- ``summarise``: final success rate and return with 95 % CIs and steps to a success threshold.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
import tempfile
from pathlib import Path
from typing import Any, Iterable, Mapping, Sequence

import numpy as np

__all__ = [
    "EVAL_COLUMNS",
    "SUMMARY_COLUMNS",
    "write_text_atomic",
    "write_json_atomic",
    "write_csv_atomic",
    "read_csv",
    "t_critical",
    "mean_ci",
    "summarise",
    "summary_markdown",
]

#: One evaluation of one run. Units: env_steps (environment steps), success_rate [0, 1],
#: returns (reward units), collision_steps (steps in contact per episode), episode_length
#: (steps), wall_s (s since the run started).
EVAL_COLUMNS = (
    "variant", "seed", "env_steps", "n_episodes", "success_rate", "mean_return", "std_return",
    "mean_collision_steps", "mean_episode_length", "wall_s",
)
SUMMARY_COLUMNS = (
    "variant", "n_seeds", "final_env_steps",
    "final_success_mean", "final_success_ci_low", "final_success_ci_high",
    "final_return_mean", "final_return_ci_low", "final_return_ci_high",
    "threshold", "seeds_reaching_threshold", "steps_to_threshold_mean", "steps_to_threshold_ci_low",
    "steps_to_threshold_ci_high",
)


def write_text_atomic(path: str | os.PathLike, text: str) -> Path:
    """Write ``text`` to ``path`` through a temp file in the same folder and ``os.replace``."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="") as handle:
            handle.write(text)
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return path


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


# --- confidence intervals -------------------------------------------------------------
# Two-sided 95 % Student-t critical values t_{0.975, df} for df = 1..30 (standard tables).
_T975 = (
    12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228,
    2.201, 2.179, 2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086,
    2.080, 2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042,
)
_T975_LARGE = ((40, 2.021), (60, 2.000), (120, 1.980), (math.inf, 1.960))


def t_critical(df: int) -> float:
    """Two-sided 95 % Student-t critical value for ``df`` ≥ 1 degrees of freedom.

    Exact table values (3 decimals) up to 30, linear in 1/df between 30, 40, 60, 120 and ∞.
    """
    if isinstance(df, bool) or not isinstance(df, (int, np.integer)) or df < 1:
        raise ValueError(f"degrees of freedom must be an integer >= 1, got {df!r}")
    if df <= 30:
        return _T975[df - 1]
    lo_df, lo_t = 30, _T975[-1]
    for hi_df, hi_t in _T975_LARGE:
        if df <= hi_df:
            x = (1 / lo_df - 1 / df) / (1 / lo_df - (0 if math.isinf(hi_df) else 1 / hi_df))
            return lo_t + x * (hi_t - lo_t)
        lo_df, lo_t = hi_df, hi_t
    return 1.960


def mean_ci(values: Iterable[float]) -> tuple[float, float, float]:
    """(mean, low, high): the t-based 95 % CI of the mean, ``mean ± t(n−1)·s/√n``.

    NaNs are dropped; one value gives (v, v, v) (no spread to estimate); none gives NaNs.
    """
    x = np.asarray([v for v in values if not (isinstance(v, float) and math.isnan(v))], dtype=float)
    if x.size == 0:
        return math.nan, math.nan, math.nan
    mean = float(x.mean())
    if x.size == 1:
        return mean, mean, mean
    half = t_critical(x.size - 1) * float(x.std(ddof=1)) / math.sqrt(x.size)
    return mean, mean - half, mean + half


# --- summaries --------------------------------------------------------------------------
def _by_run(rows: Sequence[Mapping[str, Any]]) -> dict[tuple[str, int], list[Mapping[str, Any]]]:
    runs: dict[tuple[str, int], list[Mapping[str, Any]]] = {}
    for row in rows:
        runs.setdefault((row["variant"], int(row["seed"])), []).append(row)
    for key in runs:
        runs[key].sort(key=lambda r: r["env_steps"])
    return runs


def summarise(rows: Sequence[Mapping[str, Any]], threshold: float = 0.5, final_points: int = 1) -> list[dict[str, Any]]:
    """One summary row per variant (in first-seen order) from tidy evaluation rows.

    Args:
        rows: rows with ``EVAL_COLUMNS`` (several seeds and eval points per variant).
        threshold: success rate a seed must reach; ``steps_to_threshold`` is the first eval
            point at or above it (seeds that never reach it are counted in
            ``seeds_reaching_threshold`` and left out of the mean).
        final_points: the last ``final_points`` eval points of each seed are averaged into
            its "final" value (1 = the last evaluation only).

    Returns:
        Dicts with ``SUMMARY_COLUMNS``; CIs are t-based 95 % across seeds.
    """
    if not 0.0 <= threshold <= 1.0:
        raise ValueError(f"threshold must be a success rate in [0, 1], got {threshold!r}")
    if final_points < 1:
        raise ValueError(f"final_points must be >= 1, got {final_points!r}")
    runs = _by_run(rows)
    summary = []
    for variant in dict.fromkeys(r["variant"] for r in rows):
        seeds = [(key, run) for key, run in runs.items() if key[0] == variant]
        finals_s = [float(np.mean([r["success_rate"] for r in run[-final_points:]])) for _, run in seeds]
        finals_r = [float(np.mean([r["mean_return"] for r in run[-final_points:]])) for _, run in seeds]
        reached = []
        for _, run in seeds:
            hit = next((r["env_steps"] for r in run if r["success_rate"] >= threshold), None)
            if hit is not None:
                reached.append(float(hit))
        s, r, t = mean_ci(finals_s), mean_ci(finals_r), mean_ci(reached)
        summary.append({
            "variant": variant, "n_seeds": len(seeds),
            "final_env_steps": int(min(run[-1]["env_steps"] for _, run in seeds)),
            "final_success_mean": s[0], "final_success_ci_low": s[1], "final_success_ci_high": s[2],
            "final_return_mean": r[0], "final_return_ci_low": r[1], "final_return_ci_high": r[2],
            "threshold": threshold, "seeds_reaching_threshold": len(reached),
            "steps_to_threshold_mean": t[0], "steps_to_threshold_ci_low": t[1], "steps_to_threshold_ci_high": t[2],
        })
    return summary


def summary_markdown(summary: Sequence[Mapping[str, Any]]) -> str:
    """A markdown table of ``summarise``'s rows (means with [95 % CI])."""

    def ci(row, key, fmt):
        mean, low, high = row[f"{key}_mean"], row[f"{key}_ci_low"], row[f"{key}_ci_high"]
        if isinstance(mean, float) and math.isnan(mean):
            return "—"
        return f"{mean:{fmt}} [{low:{fmt}}, {high:{fmt}}]"

    lines = [
        "| variant | seeds | env steps | final success rate [95 % CI] | final return [95 % CI] "
        "| seeds reaching threshold | env steps to threshold [95 % CI] |",
        "|---|---|---|---|---|---|---|",
    ]
    for row in summary:
        lines.append(
            f"| {row['variant']} | {row['n_seeds']} | {row['final_env_steps']} | {ci(row, 'final_success', '.2f')} "
            f"| {ci(row, 'final_return', '.2f')} | {row['seeds_reaching_threshold']}/{row['n_seeds']} "
            f"(≥ {row['threshold']:.2f}) | {ci(row, 'steps_to_threshold', '.0f')} |"
        )
    return "\n".join(lines) + "\n"
