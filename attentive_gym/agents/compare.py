"""Compare observation variants: train every (variant, seed) pair, then tabulate and plot.

``compare(variants, seeds, base, out)`` writes into ``out``:

- ``compare.json``: the comparison's settings (a rerun into ``out`` must use the same);
- ``runs/<variant>-seed<seed>/``: one ``training.train`` folder per pair;
- ``results.csv``: tidy, one row per (variant, seed, eval point), ``results.EVAL_COLUMNS``;
- ``learning_curves.png``: success rate and return vs env steps, mean ± 95 % CI across seeds;
- ``summary.csv`` / ``summary.md``: final success rate and return with 95 % CIs and env
  steps to reach the success threshold;
- ``performance_profiles.png``: each variant's share of runs scoring above τ, in final
  success and safe success (``plots.plot_performance_profiles``);
- ``goal_choice.csv`` / ``goal_choice.png`` (with a ``goal-action`` variant): its runs'
  ``goal_choice.csv`` rows together, and the figure of what the agent chooses
  (``plots.plot_goal_choice``).

Every run's spec is validated (``training.validate_spec``, once per variant) before anything
is written or trained. A rerun (after Ctrl-C, a kill or a crash) trains only the runs without
a ``done`` marker, resuming each from its checkpoint; finished runs are read, not retrained.
With ``extend``, a comparison whose settings differ only by a larger ``total_steps`` trains
every run on to the new budget from its latest checkpoint (``training.train``'s ``extend``).
SIGINT or SIGTERM stop the runs in progress and start no queued one: ``compare`` raises
``Interrupted`` saying what finished. ``QUICK`` (from ``config``) is the budget of
``attentive-gym compare --quick`` (its run time: the README's main job).
"""

from __future__ import annotations

import contextlib
import json
import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from attentive_gym.agents.backends import JobOutcome, run_many
from attentive_gym.agents.config import DEFAULT_WARM_START, QUICK, RunSpec
from attentive_gym.agents.goal_choice import GOAL_CHOICE_FILE
from attentive_gym.agents.plots import plot_goal_choice, plot_learning_curves, plot_performance_profiles
from attentive_gym.agents.results import (
    EVAL_COLUMNS,
    SUMMARY_COLUMNS,
    read_csv,
    run_finals,
    summarise,
    summary_markdown,
    write_csv_atomic,
    write_json_atomic,
    write_text_atomic,
)
from attentive_gym.agents.stopping import Interrupted
from attentive_gym.agents.training import budget_grows, holds_progress, is_done, validate_spec
from attentive_gym.progress import Progress, format_duration

__all__ = ["QUICK", "CompareResult", "compare", "collect", "run_dir_of", "runs_hold_progress", "settings_differences"]


@dataclass
class CompareResult:
    """Where the outputs are, and which runs finished or failed (run folder → error)."""

    out: Path
    results_csv: Path | None
    figure: Path | None
    summary_csv: Path | None
    summary_md: Path | None
    summary: list[dict[str, Any]] = field(default_factory=list)
    goal_choice_figure: Path | None = None  # goal_choice.png, with a goal-action variant
    profiles_figure: Path | None = None  # performance_profiles.png
    trained: list[str] = field(default_factory=list)
    skipped: list[str] = field(default_factory=list)
    failed: dict[str, str] = field(default_factory=dict)


def run_dir_of(out: str | os.PathLike, spec: RunSpec) -> Path:
    return Path(out) / "runs" / spec.run_name


def _settings(variants, seeds, base: RunSpec, threshold: float) -> dict[str, Any]:
    """``compare.json``: the variants, seeds and threshold, and ``run``, the runs' settings but
    their variant and seed; its ``warm_start`` is ``DEFAULT_WARM_START`` where each variant
    takes its own default (``RunSpec.for_variant``), so that a row's tag can name it."""
    template = base.to_dict()
    template.pop("variant")
    template.pop("seed")
    if base.warm_start == base.default_warm_start():
        template["warm_start"] = DEFAULT_WARM_START
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
    extend: bool = False,
    log: Callable[[str], None] = print,
) -> CompareResult:
    """Train the missing (variant, seed) runs of the comparison in ``out``, then ``collect``.

    Args:
        variants: observation variants (validated through ``RunSpec``).
        seeds: training seeds (distinct, ≥ 0).
        base: the run template; its ``variant`` and ``seed`` are replaced per pair.
        out: output folder (created).
        backend: ``"process"`` (one spawned process per run) or ``"ray"``.
        workers: runs in parallel.
        threshold: success rate for "env steps to threshold" in the summary.
        extend: ``out`` may hold the comparison with a smaller ``total_steps``: train its
            runs on to ``base.total_steps``.
        log: progress lines, one per finished run (its own wall time, the elapsed time, an ETA).

    Raises:
        ValueError: a run's spec cannot start, or ``out`` holds another comparison (one of a
            smaller budget too, without ``extend``); nothing is written or trained then.
        Interrupted: SIGINT or SIGTERM stopped the comparison; its text says how many runs
            are done and how to resume.
    """
    if not variants or not seeds:
        raise ValueError("compare needs at least one variant and one seed")
    specs = [base.for_variant(v, seed=s) for s in seeds for v in variants]
    for variant in variants:  # the seed changes nothing that validation checks
        validate_spec(base.for_variant(variant))
    out = Path(out)
    _bind_settings(out, _settings(variants, seeds, base, threshold), base, extend)
    skipped = [spec.run_name for spec in specs if is_done(run_dir_of(out, spec), spec.total_steps)]
    todo = [(spec.to_dict(), str(run_dir_of(out, spec))) for spec in specs if spec.run_name not in skipped]
    if skipped:
        log(f"{len(skipped)} run(s) already done, {len(todo)} to train")
    trained, failed = [], {}
    progress = Progress(len(todo))
    try:
        with contextlib.closing(run_many(todo, backend=backend, workers=workers)) as outcomes:
            for outcome in outcomes:
                name = Path(outcome.run_dir).name
                if outcome.ok:
                    trained.append(name)
                else:
                    failed[name] = outcome.error or "failed"
                log(progress.line(_outcome_text(name, outcome)))
    except Interrupted as stop:
        raise Interrupted(stop.signum, _resume_hint(out, specs)) from None
    result = collect(out, specs, threshold=threshold)
    result.trained, result.skipped, result.failed = trained, skipped, failed
    return result


def _bind_settings(out: Path, settings: dict[str, Any], base: RunSpec, extend: bool) -> None:
    """Write ``out/compare.json``, or check that the comparison already there has ``settings``.

    Over a comparison whose runs hold progress (a checkpoint or a finished run), allowed are:
    the same runs with another vectorisation or threshold (neither changes a trained number:
    the file is rewritten); more seeds or variants with the same run settings (five seeds
    grown to ten, say: the runs trained stand and only the new ones train); and, with
    ``extend``, the same runs with a larger ``total_steps``. Anything else raises
    ``ValueError`` naming what differs. Before any run made progress (a start that failed, on
    a typo in ``algo_kwargs`` say), the folder is taken over.
    """
    path = out / "compare.json"
    if path.is_file() and runs_hold_progress(out):
        old = json.loads(path.read_text())
        differences = settings_differences(old, settings["variants"], settings["seeds"], base)
        old_base = _stored_base(old, base)
        same_runs = (old["variants"], old["seeds"]) == (list(settings["variants"]), list(settings["seeds"]))
        more_runs = set(old["variants"]) <= set(settings["variants"]) and set(old["seeds"]) <= set(settings["seeds"])
        grown = more_runs and not old_base.differences(base)  # new seeds or variants beside the trained runs
        if same_runs and budget_grows(old_base, base):
            if not extend:
                raise ValueError(
                    f"{out} holds this comparison with {old_base.total_steps} env steps per run; "
                    f"extend it to {base.total_steps} (--extend) or use another --out folder"
                )
        elif differences and not grown:  # anything but the vectorisation, the threshold or more runs
            raise ValueError(
                f"{out} holds a comparison with other settings ({path}: {differences}); use another --out folder"
            )
    write_json_atomic(path, settings)


def settings_differences(old: dict[str, Any], variants: Sequence[str], seeds: Sequence[int], base: RunSpec) -> str:
    """How a comparison's stored settings ``old`` (its ``compare.json``) differ from ``variants``,
    ``seeds`` and the run template ``base``, the vectorisation aside (it changes no number):
    e.g. ``"seeds [0] → [0, 1], eval_every 25 → 51"``; "" when they do not."""
    old_base = _stored_base(old, base)
    lists = [
        f"{key} {old[key]} → {list(new)}"
        for key, new in (("variants", variants), ("seeds", seeds))
        if old[key] != list(new)
    ]
    return ", ".join(filter(None, [*lists, old_base.differences(base)]))


def _stored_base(old: dict[str, Any], base: RunSpec) -> RunSpec:
    """The run template of stored settings ``old``, with ``base``'s variant, seed and vectorisation."""
    return RunSpec.from_dict({**old["run"], "variant": base.variant, "seed": base.seed, "vec_env": base.vec_env})


def runs_hold_progress(out: Path) -> bool:
    """Whether any run folder of the comparison in ``out`` holds a checkpoint or a finished run."""
    return any(holds_progress(run_dir) for run_dir in (out / "runs").glob("*") if run_dir.is_dir())


def _outcome_text(name: str, outcome: JobOutcome) -> str:
    """``"focus-seed0: done, 100000 env steps in 2m43s"`` or ``"focus-seed0: FAILED after 3s: <error>"``."""
    took = format_duration(outcome.wall_s) if outcome.wall_s is not None else "an unknown time"
    if outcome.ok:
        return f"{name}: done, {outcome.env_steps} env steps in {took}"
    error_file = Path(outcome.run_dir) / "error.txt"
    see = f" (see {error_file})" if error_file.is_file() else ""
    return f"{name}: FAILED after {took}: {outcome.error}{see}"


def _resume_hint(out: Path, specs: Sequence[RunSpec]) -> str:
    """What an interrupted comparison finished, and how to train the rest."""
    missing = [spec for spec in specs if not is_done(run_dir_of(out, spec), spec.total_steps)]
    return (
        f"{len(specs) - len(missing)}/{len(specs)} runs done in {out}; rerun the same command to train only "
        f"the {len(missing)} missing one(s) (a stopped run resumes from its last checkpoint)"
    )


def collect(out: str | os.PathLike, specs: Sequence[RunSpec], threshold: float = 0.5) -> CompareResult:
    """Write ``results.csv``, the figure and the summary from the finished runs among ``specs``."""
    out = Path(out)
    done = [run_dir_of(out, spec) for spec in specs if is_done(run_dir_of(out, spec), spec.total_steps)]
    rows = [row for run_dir in done for row in read_csv(run_dir / "eval.csv")]
    if not rows:
        return CompareResult(out, None, None, None, None)
    results_csv = write_csv_atomic(out / "results.csv", rows, EVAL_COLUMNS)
    summary = summarise(rows, threshold=threshold)
    summary_csv = write_csv_atomic(out / "summary.csv", summary, SUMMARY_COLUMNS)
    summary_md = write_text_atomic(out / "summary.md", summary_markdown(summary))
    figure = plot_learning_curves(rows, out / "learning_curves.png")
    result = CompareResult(out, results_csv, figure, summary_csv, summary_md, summary)
    result.profiles_figure = plot_performance_profiles(run_finals(rows), out / "performance_profiles.png")
    result.goal_choice_figure = _collect_goal_choice(out, done)
    return result


def _collect_goal_choice(out: Path, run_dirs: Sequence[Path]) -> Path | None:
    """Write ``out/goal_choice.csv`` (the rows of the runs' ``goal_choice.csv``, in their
    columns) and its figure ``out/goal_choice.png`` when some of ``run_dirs`` hold one
    (goal-action runs); the figure's path, or None."""
    files = [run_dir / GOAL_CHOICE_FILE for run_dir in run_dirs if (run_dir / GOAL_CHOICE_FILE).is_file()]
    rows = [row for path in files for row in read_csv(path)]
    if not rows:
        return None
    write_csv_atomic(out / GOAL_CHOICE_FILE, rows, list(rows[0]))
    return plot_goal_choice(rows, out / "goal_choice.png")
