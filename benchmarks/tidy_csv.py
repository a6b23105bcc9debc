"""The speed benchmarks' figures as tidy CSV rows, all benchmarks in one file.

``Figures(benchmark)`` collects one row per (section, subject, number of envs, metric);
``write(path)`` merges them into ``path``: the sections this run wrote replace this
benchmark's rows of those sections, in their place, and every other row stays, so a run of
some sections keeps the benchmark's others. A ``run`` section, rewritten by every run,
records the machine the run had (``cpus``: the cores this process may use;
``numba_threads``). ``tools/report.py render`` turns the file
(``docs/results/performance.csv``) into ``docs/results/performance.md``.
Metric names carry their unit: ``*_us`` µs, ``*_per_s`` per second, ``*_mib`` MiB, and
``*_fraction`` / ``*_ratio`` no unit.
"""

from __future__ import annotations

import csv
import os
from collections.abc import Mapping
from pathlib import Path

import numba

from attentive_gym.agents.results import write_csv_atomic

#: The file's columns; ``num_envs`` is empty where the figure is not a vector env's.
COLUMNS = ("benchmark", "section", "subject", "num_envs", "metric", "value")


def cpus() -> int:
    """The cores this process may run on (its affinity where the OS tells it)."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1


class Figures:
    """One benchmark's figures, as rows of ``COLUMNS``."""

    def __init__(self, benchmark: str):
        self.benchmark = benchmark
        self.rows: list[dict[str, str]] = []

    def add(self, section: str, subject: str, metrics: Mapping[str, float], num_envs: int | None = None) -> None:
        """One row per entry of ``metrics`` (name → value in the name's unit)."""
        for metric, value in metrics.items():
            self.rows.append(
                {
                    "benchmark": self.benchmark,
                    "section": section,
                    "subject": subject,
                    "num_envs": "" if num_envs is None else str(num_envs),
                    "metric": metric,
                    "value": f"{float(value):.6g}",
                }
            )

    def write(self, path: str | os.PathLike) -> Path:
        """Merge the rows into the CSV at ``path`` (created if missing), with the ``run`` rows.

        Each section this run wrote takes the place of the rows this benchmark had in that
        section; a section new to the file goes after the benchmark's last row (or at the
        end); all other rows stay where they are.
        """
        path = Path(path)
        run = Figures(self.benchmark)
        run.add("run", "machine", {"cpus": cpus(), "numba_threads": numba.get_num_threads()})
        fresh: dict[str, list[dict[str, str]]] = {}
        for row in [*run.rows, *self.rows]:
            fresh.setdefault(row["section"], []).append(row)
        merged: list[dict[str, str]] = []
        for row in _read(path):
            if row["benchmark"] != self.benchmark or row["section"] not in fresh:
                merged.append(row)
            elif fresh[row["section"]]:  # the section's first old row: the new rows go here
                merged.extend(fresh[row["section"]])
                fresh[row["section"]] = []
        ours = [i for i, row in enumerate(merged) if row["benchmark"] == self.benchmark]
        at = ours[-1] + 1 if ours else len(merged)
        merged[at:at] = [row for rows in fresh.values() for row in rows]
        write_csv_atomic(path, merged, COLUMNS)
        print(f"wrote {len(self.rows)} rows of {self.benchmark} to {path}")
        return path


def _read(path: Path) -> list[dict[str, str]]:
    """The rows of the CSV at ``path`` as text, none where it does not exist yet."""
    if not path.is_file():
        return []
    with open(path, newline="", encoding="utf-8") as handle:
        return list(csv.DictReader(handle))
