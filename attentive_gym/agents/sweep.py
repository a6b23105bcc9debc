"""The clutter sweep: the same comparison at several numbers of distractors.

``clutter_sweep(variants, seeds, base, distractors, out)`` runs ``compare.compare`` once per
distractor count, into ``out/distractors-<n>/`` (each resumable as a comparison is), then
writes into ``out``:

- ``sweep.csv``: every evaluation row of every comparison with its ``num_distractors``
  (``SWEEP_COLUMNS``);
- ``sweep_summary.csv``: per (distractors, variant), final success and safe success (mean,
  IQM) and contact time (mean) with 95 % bootstrap CIs and the probability of improvement
  over the baseline (``SWEEP_SUMMARY_COLUMNS``);
- ``success_vs_distractors.png``: final success rate, safe success rate and contact time
  against distractors, per variant.

If attention is worth anything, its advantage over the raw sensors should grow with
clutter: the figure shows whether it does.
"""

from __future__ import annotations

import json
import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from attentive_gym.agents.compare import compare, settings_differences
from attentive_gym.agents.config import RunSpec
from attentive_gym.agents.plots import plot_success_vs_distractors
from attentive_gym.agents.results import EVAL_COLUMNS, SUMMARY_COLUMNS, read_csv, summarise, write_csv_atomic

__all__ = [
    "SWEEP_COLUMNS",
    "SWEEP_SUMMARY_COLUMNS",
    "SweepResult",
    "clutter_sweep",
    "sweep_tables",
    "parse_distractors",
]

SWEEP_COLUMNS = ("num_distractors", *EVAL_COLUMNS)
SWEEP_SUMMARY_COLUMNS = ("num_distractors", *SUMMARY_COLUMNS)


@dataclass
class SweepResult:
    """Where the sweep's outputs are, and the runs that failed (run folder → error)."""

    out: Path
    results_csv: Path | None = None
    summary_csv: Path | None = None
    figure: Path | None = None
    failed: dict[str, str] = field(default_factory=dict)


def parse_distractors(text: str) -> tuple[int, ...]:
    """``"1,3,6"`` → (1, 3, 6): distinct integers ≥ 0, in the given order."""
    items = [item.strip() for item in str(text).split(",")]
    try:
        counts = tuple(int(item) for item in items)
    except ValueError:
        raise ValueError(f"distractor counts must be a comma list of integers >= 0, e.g. 1,3,6; got {text!r}") from None
    if any(n < 0 for n in counts) or len(set(counts)) != len(counts):
        raise ValueError(f"distractor counts must be distinct integers >= 0, e.g. 1,3,6; got {text!r}")
    return counts


def clutter_sweep(
    variants: Sequence[str],
    seeds: Sequence[int],
    base: RunSpec,
    distractors: Sequence[int],
    out: str | os.PathLike,
    *,
    backend: str = "process",
    workers: int = 2,
    threshold: float = 0.5,
    extend: bool = False,
    log: Callable[[str], None] = print,
) -> SweepResult:
    """Compare ``variants`` over ``seeds`` at each count in ``distractors`` (the env keyword
    ``num_distractors`` of ``base.env_kwargs`` replaced), then tabulate and plot every count
    whose comparison ``out`` holds (those of earlier sweeps into ``out`` too).

    ``extend`` trains each count's comparison on to a larger budget, as in ``compare``.
    Raises what ``compare`` raises (invalid specs before anything trains, an interrupt).
    """
    if not distractors:
        raise ValueError("the sweep needs at least one distractor count")
    out = Path(out)
    specs = {n: base.replace(env_kwargs={**base.env_kwargs, "num_distractors": int(n)}) for n in distractors}
    result = SweepResult(out)
    for n, spec in specs.items():
        log(f"sweep: {n} distractor(s)")
        outcome = compare(
            variants,
            seeds,
            spec,
            out / f"distractors-{n}",
            backend=backend,
            workers=workers,
            threshold=threshold,
            extend=extend,
            log=log,
        )
        result.failed.update({f"distractors-{n}/{name}": error for name, error in outcome.failed.items()})
    rows = []
    for n in _counts_in(out):  # every count in ``out``: a rerun at some counts keeps the others in the tables
        differences = _differences(out / f"distractors-{n}" / "compare.json", variants, seeds, base)
        if differences:
            log(
                f"sweep: note: distractors-{n} was trained with other settings than this command's ({differences}); "
                "its rows enter the tables as they are"
            )
        rows.extend({"num_distractors": n, **row} for row in read_csv(out / f"distractors-{n}" / "results.csv"))
    if not rows:
        return result
    summary = sweep_tables(rows, threshold)
    result.results_csv = write_csv_atomic(out / "sweep.csv", rows, SWEEP_COLUMNS)
    result.summary_csv = write_csv_atomic(out / "sweep_summary.csv", summary, SWEEP_SUMMARY_COLUMNS)
    result.figure = plot_success_vs_distractors(summary, out / "success_vs_distractors.png")
    return result


def sweep_tables(rows: Sequence[Mapping[str, Any]], threshold: float = 0.5) -> list[dict[str, Any]]:
    """``summarise`` per distractor count: rows of ``SWEEP_SUMMARY_COLUMNS``, in the counts'
    first-seen order."""
    summary = []
    for n in dict.fromkeys(int(r["num_distractors"]) for r in rows):
        at_n = [r for r in rows if int(r["num_distractors"]) == n]
        summary.extend({"num_distractors": n, **row} for row in summarise(at_n, threshold=threshold))
    return summary


def _differences(settings_path: Path, variants: Sequence[str], seeds: Sequence[int], base: RunSpec) -> str:
    """How the comparison whose ``compare.json`` is ``settings_path`` differs from this sweep's
    ``variants``, ``seeds`` and ``base`` run, its distractor count aside (``compare.settings_differences``);
    "" when it does not, or when the file is missing."""
    if not settings_path.is_file():
        return ""
    old = json.loads(settings_path.read_text())
    without_count = lambda kwargs: {k: v for k, v in kwargs.items() if k != "num_distractors"}  # noqa: E731
    old["run"]["env_kwargs"] = without_count(old["run"]["env_kwargs"])
    return settings_differences(old, variants, seeds, base.replace(env_kwargs=without_count(base.env_kwargs)))


def _counts_in(out: Path) -> list[int]:
    """The distractor counts whose comparison in ``out`` has results (``distractors-N/results.csv``), ascending."""
    counts = []
    for folder in out.glob("distractors-*"):
        suffix = folder.name.removeprefix("distractors-")
        if suffix.isdigit() and (folder / "results.csv").is_file():
            counts.append(int(suffix))
    return sorted(counts)
