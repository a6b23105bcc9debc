"""Compare observation variants: train every (variant, seed) pair, then tabulate and plot.

``compare(variants, seeds, base, out)`` writes into ``out``:

- ``compare.json``: the comparison's settings (a rerun into ``out`` must use the same);
- ``runs/<variant>-seed<seed>/``: one ``training.train`` folder per pair;
- ``results.csv``: tidy, one row per (variant, seed, eval point), ``results.EVAL_COLUMNS``;
- ``learning_curves.png``: success rate and return vs env steps, mean ± 95 % CI across seeds;
- ``summary.csv`` / ``summary.md``: final success rate and return with 95 % CIs and env
  steps to reach the success threshold.

A rerun (after a kill or a crash) trains only the runs without a ``done`` marker, resuming
each from its checkpoint; finished runs are read, not retrained. ``QUICK`` is the budget
of ``attentive-gym compare --quick``: about ten minutes on two cores.
"""

from __future__ import annotations

import json
import os
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Sequence

from attentive_gym.agents.backends import run_many
from attentive_gym.agents.config import RunSpec
from attentive_gym.agents.plots import plot_learning_curves
from attentive_gym.agents.results import (
    EVAL_COLUMNS,
    SUMMARY_COLUMNS,
    read_csv,
    summarise,
    summary_markdown,
    write_csv_atomic,
    write_json_atomic,
    write_text_atomic,
)
from attentive_gym.agents.training import is_done

__all__ = ["QUICK", "CompareResult", "compare", "collect", "run_dir_of"]

#: ``--quick``: 3 variants × 3 seeds × 150 000 PPO steps, 10 eval episodes every 15 000
#: steps, in the main comparison's smaller arena (8 m, 2 distractors, 3 rubble per 100 m²).
QUICK: dict[str, Any] = {
    "variants": ("raw", "raw-stack", "focus"),
    "seeds": (0, 1, 2),
    "total_steps": 150_000,
    "eval_every": 15_000,
    "eval_episodes": 10,
    "checkpoint_every": 50_000,
    "env_kwargs": {"arena_size_m": 8.0, "num_distractors": 2, "rubble_per_100m2": 3.0},
}


@dataclass
class CompareResult:
    """Where the outputs are, and which runs finished or failed (run folder → error)."""

    out: Path
    results_csv: Path | None
    figure: Path | None
    summary_csv: Path | None
    summary_md: Path | None
    summary: list[dict[str, Any]] = field(default_factory=list)
    trained: list[str] = field(default_factory=list)
    skipped: list[str] = field(default_factory=list)
    failed: dict[str, str] = field(default_factory=dict)


def run_dir_of(out: str | os.PathLike, spec: RunSpec) -> Path:
    return Path(out) / "runs" / spec.run_name


def _settings(variants, seeds, base: RunSpec, threshold: float) -> dict[str, Any]:
    template = base.to_dict()
    template.pop("variant")
    template.pop("seed")
    return {"variants": list(variants), "seeds": list(seeds), "run": template, "threshold": threshold}


def compare(
    variants: Sequence[str],
    seeds: Sequence[int],
    base: RunSpec,
    out: str | os.PathLike,
    *,
    backend: str = "process",
    workers: int = 2,
    threshold: float = 0.5,
    log: Callable[[str], None] = print,
) -> CompareResult:
    """Train the missing (variant, seed) runs of the comparison in ``out``, then ``collect``.

    Args:
        variants: observation variants (validated through ``RunSpec``).
        seeds: training seeds (distinct, ≥ 0).
        base: the run template; its ``variant`` and ``seed`` are replaced per pair.
        out: output folder (created).
        backend: ``"process"`` (spawn pool) or ``"ray"``.
        workers: runs in parallel.
        threshold: success rate for "env steps to threshold" in the summary.
        log: progress lines.
    """
    if not variants or not seeds:
        raise ValueError("compare needs at least one variant and one seed")
    specs = [base.replace(variant=v, seed=s) for s in seeds for v in variants]
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    settings = _settings(variants, seeds, base, threshold)
    settings_path = out / "compare.json"
    if settings_path.is_file():
        old = json.loads(settings_path.read_text())
        if old != json.loads(json.dumps(settings)):
            raise ValueError(f"{out} holds a comparison with other settings ({settings_path}); use another --out folder")
    else:
        write_json_atomic(settings_path, settings)
    todo = [(spec.to_dict(), str(run_dir_of(out, spec))) for spec in specs if not is_done(run_dir_of(out, spec))]
    result_skipped = [spec.run_name for spec in specs if is_done(run_dir_of(out, spec))]
    if result_skipped:
        log(f"{len(result_skipped)} run(s) already done, {len(todo)} to train")
    trained, failed = [], {}
    t0 = time.perf_counter()
    for i, outcome in enumerate(run_many(todo, backend=backend, workers=workers), 1):
        name = Path(outcome.run_dir).name
        if outcome.ok:
            trained.append(name)
            log(f"[{i}/{len(todo)}] {name}: done, {outcome.env_steps} env steps ({time.perf_counter() - t0:.0f} s)")
        else:
            failed[name] = outcome.error or "failed"
            log(f"[{i}/{len(todo)}] {name}: FAILED: {outcome.error} (see {outcome.run_dir}/error.txt)")
    result = collect(out, specs, threshold=threshold)
    result.trained, result.skipped, result.failed = trained, result_skipped, failed
    return result


def collect(out: str | os.PathLike, specs: Sequence[RunSpec], threshold: float = 0.5) -> CompareResult:
    """Write ``results.csv``, the figure and the summary from the finished runs among ``specs``."""
    out = Path(out)
    rows: list[dict[str, Any]] = []
    for spec in specs:
        run_dir = run_dir_of(out, spec)
        if is_done(run_dir):
            rows.extend(read_csv(run_dir / "eval.csv"))
    if not rows:
        return CompareResult(out, None, None, None, None)
    results_csv = write_csv_atomic(out / "results.csv", rows, EVAL_COLUMNS)
    summary = summarise(rows, threshold=threshold)
    summary_csv = write_csv_atomic(out / "summary.csv", summary, SUMMARY_COLUMNS)
    summary_md = write_text_atomic(out / "summary.md", summary_markdown(summary))
    figure = plot_learning_curves(rows, out / "learning_curves.png")
    return CompareResult(out, results_csv, figure, summary_csv, summary_md, summary)
