"""Measure the experiments' checks per kinematics mode into a CSV, and print the table.

Runs every check of the paper's five experiments noise-free in each kinematics mode and
over ``--seeds`` noisy seeds in each column (``attentive_gym.experiments.table.measure``),
writes the measurement as tidy rows to ``--csv`` (default
``docs/results/experiment_checks.csv``), the tracker's noise-free checks under the settings
that each remove one cause of failure (``measure_causes``) to ``--causes-csv`` (default
``docs/results/experiment_causes.csv``), and prints the Markdown table. ``python
tools/report.py render`` then writes ``docs/results/checks.md`` from the CSV without
rerunning anything (the page says how long the defaults take)::

    python tools/experiments_table.py                                  # 20 seeds at 5 %, the committed CSV
    python tools/experiments_table.py --config '{"normalise_combined": false, "threshold": 0.2}' --csv /tmp/sum.csv
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence
from pathlib import Path

from attentive_gym.agents.results import write_csv_atomic
from attentive_gym.experiments.table import CAUSE_COLUMNS, CSV_COLUMNS, markdown, measure, measure_causes, to_rows

#: The repository's root (this file is in ``tools/``).
ROOT = Path(__file__).resolve().parents[1]
#: Where the committed measurement lives.
DEFAULT_CSV = ROOT / "docs" / "results" / "experiment_checks.csv"
#: Where the committed measurement of the tracker's failures' causes lives.
DEFAULT_CAUSES_CSV = ROOT / "docs" / "results" / "experiment_causes.csv"


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python tools/experiments_table.py", description=__doc__.split("\n")[0])
    parser.add_argument("--seeds", type=int, default=20, help="noisy seeds per column (default 20)")
    parser.add_argument("--noise", type=float, default=0.05, help="Gaussian noise σ of the noisy runs (default 0.05)")
    parser.add_argument("--config", default=None, help="extra AttentionConfig fields as a JSON object")
    parser.add_argument("--workers", type=int, default=2, help="processes (default 2)")
    parser.add_argument(
        "--csv", type=Path, default=DEFAULT_CSV, help=f"where to write the rows (default {DEFAULT_CSV})"
    )
    parser.add_argument(
        "--causes-csv",
        type=Path,
        default=DEFAULT_CAUSES_CSV,
        help=f"where to write the tracker's noise-free checks under CAUSE_SETTINGS (default {DEFAULT_CAUSES_CSV})",
    )
    args = parser.parse_args(argv)
    try:
        config = json.loads(args.config) if args.config else None
        if args.seeds < 1:
            raise ValueError(f"--seeds must be >= 1, got {args.seeds}")
        for flag, path in (("--csv", args.csv), ("--causes-csv", args.causes_csv)):
            if path.is_dir():
                raise ValueError(f"{flag} {path} is a folder; give a file path")
        measured = measure(range(args.seeds), args.noise, config, args.workers)
        causes = measure_causes(config, args.workers)
    except (ValueError, json.JSONDecodeError) as err:
        print(f"{parser.prog}: error: {err}", file=sys.stderr)
        return 2
    write_csv_atomic(args.csv, to_rows(measured, args.seeds, args.noise, config), CSV_COLUMNS)
    write_csv_atomic(args.causes_csv, causes, CAUSE_COLUMNS)
    print(markdown(measured, args.seeds, args.noise))
    print(f"\nwrote {args.csv} and {args.causes_csv}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
