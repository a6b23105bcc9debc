"""Zero-shot generalisation: a comparison's trained policies on settings they were not trained on.

Every finished run of a comparison (``DIR/runs/<variant>-seed<seed>/``) is evaluated, as it
was trained, on the run's own evaluation episodes with one shift of its environment at a
time (``SHIFTS``: fewer or more distractors, a larger arena, USARSim's sensors, less or more
noise). A shift replaces the run's ``make_env`` keywords of the same name and keeps the rest.

- ``generalise(comparison_dir, ...)``: the rows, one per (run, shift), written to
  ``DIR/generalisation.csv`` (``COLUMNS``) as each finishes, so a stopped evaluation keeps
  its rows and a rerun evaluates only the missing ones;
- ``summarise_shifts(rows)``: per (shift, variant), the mean over seeds of success, safe
  success and contact time with 95 % bootstrap intervals inside each metric's range;
(``agents.plots.plot_generalisation`` draws the summary.)
"""

from __future__ import annotations

import math
import multiprocessing
import os
from collections.abc import Callable, Iterator, Mapping, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from pathlib import Path
from typing import Any

from attentive_gym._checks import check_int
from attentive_gym.agents.results import read_csv, write_csv_atomic
from attentive_gym.agents.stopping import raise_on_stop_signals, stop_on_sigterm_only
from attentive_gym.statistics import bootstrap_ci
from attentive_gym.wrappers.variants import VARIANTS

__all__ = [
    "SHIFTS",
    "COLUMNS",
    "SUMMARY_COLUMNS",
    "CSV_NAME",
    "parse_shifts",
    "finished_runs",
    "evaluate_shift",
    "generalise",
    "summarise_shifts",
]

#: Shift name → the ``make_env`` keywords it sets over the run's own. ``"as trained"`` is the
#: run's own setting on the same episodes, the reference of every other.
SHIFTS: dict[str, dict[str, Any]] = {
    "as trained": {},
    "0 distractors": {"num_distractors": 0},
    "4 distractors": {"num_distractors": 4},
    "6 distractors": {"num_distractors": 6},
    "12 m arena": {"arena_size_m": 12.0},
    "usarsim sensors": {"sensor_profile": "usarsim"},
    "2 % noise": {"sensor_noise": 0.02},
    "10 % noise": {"sensor_noise": 0.10},
}
#: Each shift's place in ``SHIFTS``, the order of rows and summaries.
_SHIFT_RANK = {name: k for k, name in enumerate(SHIFTS)}
#: The columns of ``generalisation.csv``: one row per (run, shift); rates in [0, 1], contact
#: in s per episode, length in steps.
COLUMNS = (
    "variant",
    "seed",
    "shift",
    "env_steps",
    "n_episodes",
    "success_rate",
    "safe_success_rate",
    "mean_contact_s",
    "mean_return",
    "mean_episode_length",
)
#: The columns of ``summarise_shifts``' rows (``<metric>_mean``, ``_ci_low``, ``_ci_high``).
SUMMARY_COLUMNS = (
    "shift",
    "variant",
    "n_seeds",
    *(
        f"{metric}_{part}"
        for metric in ("success", "safe_success", "contact_s")
        for part in ("mean", "ci_low", "ci_high")
    ),
)
CSV_NAME = "generalisation.csv"
#: Summary metric → (the CSV's column, the metric's range for the bootstrap interval).
_METRICS = {
    "success": ("success_rate", (0.0, 1.0)),
    "safe_success": ("safe_success_rate", (0.0, 1.0)),
    "contact_s": ("mean_contact_s", (0.0, math.inf)),
}


def parse_shifts(text: str | None) -> list[str]:
    """A comma list of ``SHIFTS`` names (None: all of them, in their order).

    Raises:
        ValueError: an unknown or repeated name (the message lists the allowed ones).
    """
    if text is None:
        return list(SHIFTS)
    names = [name.strip() for name in text.split(",")]
    unknown = [name for name in names if name not in SHIFTS]
    if unknown:
        raise ValueError(f"unknown shift(s) {unknown}; allowed: {list(SHIFTS)}")
    if len(set(names)) != len(names):
        raise ValueError(f"--shifts names a shift twice: {names}")
    return names


def finished_runs(comparison_dir: str | os.PathLike) -> list[Path]:
    """The finished runs under ``comparison_dir/runs`` (each with its ``done`` marker), by name.

    Raises:
        ValueError: there is no such folder, or it holds no finished run.
    """
    from attentive_gym.agents.training import is_done

    runs = Path(comparison_dir) / "runs"
    if not runs.is_dir():
        raise ValueError(f"{comparison_dir} holds no runs/ folder; give the --out folder of 'attentive-gym compare'")
    done = sorted(path for path in runs.iterdir() if path.is_dir() and is_done(path))
    if not done:
        raise ValueError(f"{runs} holds no finished run; finish the comparison first")
    return done


def evaluate_shift(run_dir: str, shift: str, episodes: int) -> dict[str, Any]:
    """The row (``COLUMNS``) of the final policy of ``run_dir`` on ``episodes`` episodes of its
    own evaluation seeds, with the environment shifted by ``SHIFTS[shift]``."""
    import numba
    import torch

    from attentive_gym.agents.evaluation import evaluate_policy
    from attentive_gym.agents.training import DONE_MARKER, env_factory, eval_seed, load_policy

    torch.set_num_threads(1)
    numba.set_num_threads(1)
    model, spec = load_policy(run_dir)
    result = evaluate_policy(model, env_factory(spec, **SHIFTS[shift]), episodes, eval_seed(spec))
    return {
        "variant": spec.variant,
        "seed": spec.seed,
        "shift": shift,
        "env_steps": int(Path(run_dir, DONE_MARKER).read_text()),
        "n_episodes": result.n_episodes,
        "success_rate": result.success_rate,
        "safe_success_rate": result.safe_success_rate,
        "mean_contact_s": result.mean_contact_s,
        "mean_return": result.mean_return,
        "mean_episode_length": result.mean_episode_length,
    }


def _evaluations(jobs: Sequence[tuple[str, str]], episodes: int, workers: int) -> Iterator[dict[str, Any]]:
    """The rows of ``jobs`` (``(run folder, shift)``), in the order they finish: in this process
    with one worker, else in a pool of ``workers`` processes (Ctrl-C stops the pool; SIGTERM
    stops each of its processes)."""
    if workers == 1:
        for run, shift in jobs:
            yield evaluate_shift(run, shift, episodes)
        return
    context = multiprocessing.get_context("spawn")
    with raise_on_stop_signals(), ProcessPoolExecutor(workers, context, initializer=_worker_setup) as pool:
        pending: set[Future] = {pool.submit(evaluate_shift, run, shift, episodes) for run, shift in jobs}
        try:
            while pending:
                done, pending = wait(pending, return_when=FIRST_COMPLETED)
                yield from (future.result() for future in done)
        except BaseException:
            for future in pending:
                future.cancel()
            raise


def _worker_setup() -> None:
    """A pool process: Ctrl-C is the parent's to handle; SIGTERM stops it."""
    stop_on_sigterm_only()


def generalise(
    comparison_dir: str | os.PathLike,
    shifts: Sequence[str] = tuple(SHIFTS),
    episodes: int = 20,
    workers: int = 1,
    report: Callable[[str], None] = print,
) -> list[dict[str, Any]]:
    """Evaluate every finished run of ``comparison_dir`` under each of ``shifts``; returns the rows
    of ``comparison_dir/generalisation.csv`` (``COLUMNS``, by variant, shift and seed), earlier
    ones included.

    Rows already in that file for ``episodes`` episodes are kept and not evaluated again; each new
    row is written as soon as it is done (an atomic rewrite), so Ctrl-C loses only the rows in
    progress. ``workers`` > 1 evaluates in that many processes. ``report`` gets one line per
    finished row.

    Raises:
        ValueError: an unknown shift, ``episodes`` or ``workers`` < 1, no finished run, or a
            ``generalisation.csv`` of another episode count (nothing is written then).
    """
    for shift in shifts:
        if shift not in SHIFTS:
            raise ValueError(f"unknown shift {shift!r}; allowed: {list(SHIFTS)}")
    check_int("episodes", episodes, 1)
    check_int("workers", workers, 1)
    runs = finished_runs(comparison_dir)
    out = Path(comparison_dir) / CSV_NAME
    kept = read_csv(out) if out.is_file() else []
    other = sorted({int(row["n_episodes"]) for row in kept} - {episodes})
    if other:
        raise ValueError(
            f"{out} holds rows of {other} episodes per run and shift; give --episodes {other[0]} to add to "
            "them, or move the file away to start again"
        )
    have = {(row["variant"], int(row["seed"]), row["shift"]) for row in kept}
    rows = list(kept)
    jobs = []
    for run in runs:
        variant, seed = run.name.rsplit("-seed", 1)
        jobs += [(str(run), shift) for shift in shifts if (variant, int(seed), shift) not in have]
    report(f"generalise: {len(runs)} runs × {len(shifts)} shifts, {len(jobs)} to evaluate ({episodes} episodes each)")
    for row in _evaluations(jobs, episodes, workers):
        rows.append(row)
        write_csv_atomic(out, _sorted(rows), COLUMNS)
        report(
            f"{row['variant']}-seed{row['seed']}, {row['shift']}: success {row['success_rate']:.2f}, "
            f"safe {row['safe_success_rate']:.2f}"
        )
    return read_csv(out) if out.is_file() else []  # as written: the rows rounded as the file holds them


def _rank(row: Mapping[str, Any]) -> tuple[int, int]:
    """A row's variant (in ``VARIANTS``' order, unknown ones last) and shift (``SHIFTS``' order) ranks."""
    return VARIANTS.index(row["variant"]) if row["variant"] in VARIANTS else len(VARIANTS), _SHIFT_RANK[row["shift"]]


def _sorted(rows: Sequence[Mapping[str, Any]]) -> list[Mapping[str, Any]]:
    """``rows`` by variant (``VARIANTS``' order), shift (``SHIFTS``' order) and seed.

    Raises:
        ValueError: a row's shift is not in ``SHIFTS``.
    """
    unknown = sorted({row["shift"] for row in rows} - set(SHIFTS))
    if unknown:
        raise ValueError(f"rows of unknown shift(s) {unknown}; allowed: {list(SHIFTS)}")
    return sorted(rows, key=lambda r: (*_rank(r), int(r["seed"])))


def summarise_shifts(rows: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """Per (shift, variant), in ``SHIFTS``' and ``VARIANTS``' order: ``n_seeds`` and the mean over
    seeds of success, safe success and contact time (s per episode), each with its 95 %
    bootstrap interval inside the metric's range (``SUMMARY_COLUMNS``).

    Raises:
        ValueError: a shift that is not in ``SHIFTS``, or a rate outside [0, 1].
    """
    groups: dict[tuple[str, str], list[Mapping[str, Any]]] = {}
    for row in sorted(_sorted(rows), key=lambda r: _rank(r)[::-1]):  # shift first, then variant
        groups.setdefault((row["shift"], row["variant"]), []).append(row)
    out = []
    for (shift, variant), group in groups.items():
        summary: dict[str, Any] = {"shift": shift, "variant": variant, "n_seeds": len(group)}
        for metric, (column, bounds) in _METRICS.items():
            point, low, high = bootstrap_ci([float(row[column]) for row in group], bounds=bounds)
            summary.update({f"{metric}_mean": point, f"{metric}_ci_low": low, f"{metric}_ci_high": high})
        out.append(summary)
    return out
