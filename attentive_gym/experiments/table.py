"""The table of the experiments' checks, one column per kinematics mode.

- ``COLUMNS``: the measured set-ups, (kinematics mode, sensor profile): the three modes
  and the perfect-perception bound ("truth") with Gaussian noise, and the tracker under the
  "usarsim" profile.
- ``measure(seeds, noise, config, workers)``: for every check, whether it holds noise-free
  in each mode, and its pass rate over ``seeds`` with noise in each column.
- ``to_rows(measured, n_seeds, noise, config)`` / ``from_rows(rows)``: the measurement as
  tidy rows (``CSV_COLUMNS``, one per check and column) and back, so that a table can be
  rendered again without rerunning the experiments.
- ``markdown(measured)``: the table as Markdown, with a row of totals.
- ``measure_causes(config, workers)``: every check with the tracker and with the
  perfect-perception bound, noise-free, under each of ``CAUSE_SETTINGS`` (the laser clipped to
  the sonars' range; no vigilance), as tidy rows: which checks fail only through what a
  setting removes.

The repository's ``tools/experiments_table.py`` measures the table into
``docs/results/experiment_checks.csv`` (its run time: ``docs/results/checks.md``) and
``tools/report.py render`` writes the docs page from it. ``python -m
attentive_gym.experiments.table`` runs that tool, in a checkout of the repository, with a
``DeprecationWarning``.
"""

from __future__ import annotations

import json
import math
import sys
import warnings
from collections.abc import Mapping, Sequence
from concurrent.futures import ProcessPoolExecutor
from types import ModuleType
from typing import Any

from attentive_gym._checks import check_int
from attentive_gym._scripts import CHECKOUT_TOOLS, load_checkout_tool
from attentive_gym.experiments.checks import CHECKS, check_experiment
from attentive_gym.experiments.registry import EXPERIMENT_NAMES
from attentive_gym.experiments.runner import TRUTH, _check_config, _check_noise, run_experiment
from attentive_gym.sensors.sonar import SonarConfig

__all__ = [
    "COLUMNS",
    "CSV_COLUMNS",
    "MIN_PASS_RATE",
    "CAUSE_SETTINGS",
    "CAUSE_KINEMATICS",
    "CAUSE_COLUMNS",
    "measure",
    "measure_causes",
    "to_rows",
    "from_rows",
    "markdown",
    "main",
]

#: The measured set-ups: (kinematics mode, sensor profile); None = Gaussian noise, a scan a step.
COLUMNS: tuple[tuple[str, str | None], ...] = (
    ("tracker", None),
    ("window", None),
    ("literal", None),
    (TRUTH, None),
    ("tracker", "usarsim"),
)
#: docs/model.md §9: a criterion must hold in at least this fraction of the noisy seeds.
MIN_PASS_RATE = 0.8

# (experiment, check) → {"exact": {column: bool}, "rate": {column: float}}
Measured = dict[tuple[str, str], dict[str, dict[tuple[str, str | None], Any]]]


def _outcomes(job: tuple) -> tuple[tuple, dict[str, tuple[bool, str]]]:
    _, name, noise, seed, kinematics, profile, config = job
    result = run_experiment(name, noise=noise, seed=seed, kinematics=kinematics, profile=profile, config=config)
    return job, {c.name: (c.passed, c.measured) for c in check_experiment(result)}


def _run_jobs(jobs: list[tuple], workers: int) -> list[tuple[tuple, dict[str, tuple[bool, str]]]]:
    """Each job's ``_outcomes``, in order, in ``workers`` processes (1: in this one)."""
    if workers == 1:
        return [_outcomes(job) for job in jobs]
    with ProcessPoolExecutor(workers) as pool:
        return list(pool.map(_outcomes, jobs, chunksize=4))


def measure(
    seeds: Sequence[int] = range(20),
    noise: float = 0.05,
    config: Mapping[str, Any] | None = None,
    workers: int = 1,
    names: Sequence[str] = EXPERIMENT_NAMES,
) -> Measured:
    """Every check of ``names``: noise-free in each Gaussian column, and over ``seeds``
    with noise in every column (``noise`` σ for the Gaussian ones, the profile's own
    noise for a profile's).

    Args:
        seeds: the env seeds of the noisy runs.
        noise: relative σ of the Gaussian columns' noise.
        config: extra ``AttentionConfig`` fields for every run (see ``run_experiment``).
        workers: processes to run in (1: in this one).
        names: the experiments.

    Returns:
        ``{(experiment, check): {"exact": {column: passed}, "measured": {column: what the
        noise-free run measured, in words}, "rate": {column: pass rate}}}``; a profile's
        column has no "exact" nor "measured" entry (its noise is part of the profile).
    """
    seeds = list(seeds)
    config = _check_config(config)
    _check_noise(noise)
    check_int("workers", workers, 1)
    jobs = [
        ("exact", name, 0.0, 0, kinematics, None, config)
        for name in names
        for kinematics, profile in COLUMNS
        if profile is None
    ]
    jobs += [
        ("rate", name, None if profile else noise, seed, kinematics, profile, config)
        for name in names
        for kinematics, profile in COLUMNS
        for seed in seeds
    ]
    done = _run_jobs(jobs, workers)
    table: Measured = {
        (name, check): {"exact": {}, "measured": {}, "rate": {}} for name in names for check in CHECKS[name]
    }
    for (kind, name, _, _, kinematics, profile, _), outcomes in done:
        column = (kinematics, profile)
        for check, (ok, measured) in outcomes.items():
            cell = table[(name, check)]
            if kind == "exact":
                cell["exact"][column] = ok
                cell["measured"][column] = measured
            else:
                cell["rate"][column] = cell["rate"].get(column, 0.0) + ok / len(seeds)
    return table


#: The tidy CSV of a measurement: one row per (check, column). ``noise_free``: "pass",
#: "fail", or empty for a profile's column (its noise is part of the profile); ``noise``: the
#: relative σ of the noisy runs, empty for a profile's column; ``seeds_passed`` of ``seeds``
#: noisy runs passed; ``config``: the extra ``AttentionConfig`` fields, as JSON; ``measured``: what
#: the noise-free run measured, in words (empty for a profile's column).
CSV_COLUMNS = (
    "experiment",
    "check",
    "kinematics",
    "profile",
    "noise_free",
    "noise",
    "seeds",
    "seeds_passed",
    "config",
    "measured",
)


def to_rows(
    measured: Measured, n_seeds: int, noise: float, config: Mapping[str, Any] | None = None
) -> list[dict[str, str]]:
    """``measured`` (from ``measure`` over ``n_seeds`` seeds at ``noise``, with ``config``)
    as tidy rows of text (``CSV_COLUMNS``), in ``measured``'s order and ``COLUMNS``' order."""
    check_int("n_seeds", n_seeds, 1)
    config_text = json.dumps(dict(config or {}), sort_keys=True)
    rows = []
    for (name, check), cell in measured.items():
        for column in COLUMNS:
            if column not in cell["rate"]:
                continue
            kinematics, profile = column
            exact = cell["exact"].get(column)
            rows.append(
                {
                    "experiment": name,
                    "check": check,
                    "kinematics": kinematics,
                    "profile": profile or "",
                    "noise_free": "" if exact is None else ("pass" if exact else "fail"),
                    "noise": "" if profile else repr(float(noise)),
                    "seeds": str(n_seeds),
                    "seeds_passed": str(round(cell["rate"][column] * n_seeds)),
                    "config": config_text,
                    "measured": cell["measured"].get(column, ""),
                }
            )
    return rows


def from_rows(rows: Sequence[Mapping[str, str]]) -> tuple[Measured, int, float, dict[str, Any]]:
    """The measurement that ``to_rows`` wrote (rows as ``csv.DictReader`` reads them):
    ``(measured, n_seeds, noise, config)``.

    Raises:
        ValueError: no rows, a missing column, a column not in ``COLUMNS``, or rows that
            disagree on the seeds, the noise or the config (one measurement per file).
    """
    if not rows:
        raise ValueError("no rows: a table has at least one check")
    missing = [c for c in CSV_COLUMNS if c not in rows[0]]
    if missing:
        raise ValueError(f"the rows lack the columns {missing}; a table's rows have {list(CSV_COLUMNS)}")
    shared = {key: {row[key] for row in rows} for key in ("seeds", "config")}
    shared["noise"] = {row["noise"] for row in rows if row["profile"] == ""}
    for key, values in shared.items():
        if len(values) > 1:
            raise ValueError(f"the rows hold more than one measurement: {key} is {sorted(values)}")
    n_seeds = int(next(iter(shared["seeds"])))
    noise = float(next(iter(shared["noise"]))) if shared["noise"] else math.nan
    measured: Measured = {}
    for row in rows:
        column = (row["kinematics"], row["profile"] or None)
        if column not in COLUMNS:
            raise ValueError(f"{row['experiment']} {row['check']}: the column {column} is none of {list(COLUMNS)}")
        cell = measured.setdefault((row["experiment"], row["check"]), {"exact": {}, "measured": {}, "rate": {}})
        if row["noise_free"] not in ("pass", "fail", ""):
            raise ValueError(
                f"{row['experiment']} {row['check']}: noise_free is {row['noise_free']!r}; "
                "allowed: 'pass', 'fail' or empty"
            )
        if row["noise_free"]:
            cell["exact"][column] = row["noise_free"] == "pass"
            cell["measured"][column] = row["measured"]
        cell["rate"][column] = int(row["seeds_passed"]) / n_seeds
    return measured, n_seeds, noise, json.loads(next(iter(shared["config"])))


#: Settings of the tracker that each remove one cause of failing a check noise-free: (label,
#: ``AttentionConfig`` fields over the measurement's). The laser's range is clipped to the
#: sonars' (the paper's robot saw a target only within them), or vigilance is put off beyond
#: every experiment's length (so a top-down course never adapts).
CAUSE_SETTINGS: tuple[tuple[str, dict[str, float]], ...] = (
    (f"laser clipped to {SonarConfig().max_range_m:g} m", {"laser_max_range_m": SonarConfig().max_range_m}),
    ("no vigilance", {"vigilance_after_s": 1000.0}),
)
#: The kinematics ``measure_causes`` reruns: the tracker, and the perfect-perception bound.
CAUSE_KINEMATICS = ("tracker", TRUTH)
#: The tidy CSV of ``measure_causes``: one row per (check, kinematics, setting); ``noise_free``:
#: "pass" or "fail".
CAUSE_COLUMNS = ("experiment", "check", "kinematics", "setting", "config", "noise_free")


def measure_causes(
    config: Mapping[str, Any] | None = None, workers: int = 1, names: Sequence[str] = EXPERIMENT_NAMES
) -> list[dict[str, str]]:
    """Every check of ``names`` with each of ``CAUSE_KINEMATICS``, noise-free, under each of
    ``CAUSE_SETTINGS`` (its fields over ``config``), as tidy rows of text (``CAUSE_COLUMNS``):
    a check that fails by default and holds under a setting fails through what that setting
    removes."""
    config = _check_config(config)
    check_int("workers", workers, 1)
    cases = [(kinematics, label, fields) for kinematics in CAUSE_KINEMATICS for label, fields in CAUSE_SETTINGS]
    jobs = [
        ("exact", name, 0.0, 0, kinematics, None, {**config, **fields})
        for kinematics, _, fields in cases
        for name in names
    ]
    done = _run_jobs(jobs, workers)
    labels = [label for _, label, _ in cases for _ in names]
    return [
        {
            "experiment": job[1],
            "check": check,
            "kinematics": job[4],
            "setting": label,
            "config": json.dumps(job[6], sort_keys=True),
            "noise_free": "pass" if ok else "fail",
        }
        for label, (job, outcomes) in zip(labels, done)
        for check, (ok, _) in outcomes.items()
    ]


def _header(column: tuple[str, str | None], n_seeds: int, noise: float) -> str:
    kinematics, profile = column
    if profile:
        return f"{kinematics}, {profile}: {n_seeds} seeds"
    return f"{kinematics}: noise off; {n_seeds} seeds @ {noise:.0%}".replace("%", " %")


def markdown(measured: Measured, n_seeds: int = 20, noise: float = 0.05) -> str:
    """``measured`` (from ``measure``) as a Markdown table: per check and column "pass"
    or "**fail**" noise-free, then the noisy pass rate (bold below ``MIN_PASS_RATE``);
    the last row counts the checks that hold."""
    lines = [
        "| experiment | check | " + " | ".join(_header(c, n_seeds, noise) for c in COLUMNS) + " |",
        "|---|---|" + "---|" * len(COLUMNS),
    ]
    exact_total = {c: 0 for c in COLUMNS}
    rate_total = {c: 0 for c in COLUMNS}
    for (name, check), cell in measured.items():
        cells = []
        for column in COLUMNS:
            rate = cell["rate"].get(column)
            rate_text = "" if rate is None else (f"{rate:.0%}" if rate >= MIN_PASS_RATE else f"**{rate:.0%}**")
            rate_text = rate_text.replace("%", " %")
            rate_total[column] += rate is not None and rate >= MIN_PASS_RATE
            if column in cell["exact"]:
                ok = cell["exact"][column]
                exact_total[column] += ok
                cells.append(f"{'pass' if ok else '**fail**'}; {rate_text}")
            else:
                cells.append(rate_text)
        lines.append(f"| {name} | `{check}` | " + " | ".join(cells) + " |")
    n = len(measured)
    totals = [f"{exact_total[c]}/{n}; {rate_total[c]}/{n}" if c[1] is None else f"{rate_total[c]}/{n}" for c in COLUMNS]
    lines.append(
        f"| **all** | holding (noise off; ≥ {MIN_PASS_RATE:.0%} of seeds) | ".replace("%", " %")
        + " | ".join(totals)
        + " |"
    )
    return "\n".join(lines)


#: What replaces ``python -m attentive_gym.experiments.table``.
_REPLACEMENT = "python tools/experiments_table.py (in a checkout of the repository; it also writes the CSV)"
#: The repository's tools folder, where a checkout has it.
_TOOLS = CHECKOUT_TOOLS
#: The tool ``main`` forwards to.
_TOOL = "experiments_table"


def _tool() -> ModuleType:
    """The module ``tools/experiments_table.py`` of the checkout this package was installed from.

    Raises:
        RuntimeError: the package is not installed from a checkout (no ``tools/`` beside it).
    """
    return load_checkout_tool(_TOOL, "python -m attentive_gym.experiments.table", _REPLACEMENT, _TOOLS)


def main(argv: Sequence[str] | None = None) -> int:
    """Deprecated: ``python tools/experiments_table.py`` with the same arguments (``--seeds``,
    ``--noise``, ``--config``, ``--workers`` as before, and ``--csv``: the tool also writes the
    measurement, by default to the checkout's ``docs/results/experiment_checks.csv``).

    Raises:
        RuntimeError: the package is not installed from a checkout, so there is no tool to run.
    """
    warnings.warn(
        f"python -m attentive_gym.experiments.table is deprecated; use {_REPLACEMENT}", DeprecationWarning, stacklevel=2
    )
    return _tool().main(argv)


if __name__ == "__main__":
    sys.exit(main())
