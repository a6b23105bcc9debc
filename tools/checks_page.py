"""``docs/results/checks.md``: the paper's experiment checks per kinematics mode.

From ``docs/results/experiment_checks.csv`` (written by ``tools/experiments_table.py``):
rendering reads the measurement back (``attentive_gym.experiments.table.from_rows``) and
never reruns an experiment.
"""

from __future__ import annotations

import json
from pathlib import Path

from attentive_gym.experiments.table import MIN_PASS_RATE, from_rows, markdown
from page_text import RESULTS, banner, read_rows

NAME = "checks.md"
SOURCE = RESULTS / "experiment_checks.csv"
WRITTEN_BY = "python tools/experiments_table.py"


def page(root: Path, write_figures: bool = True) -> str:
    """The text of ``docs/results/checks.md`` under ``root`` (it has no figures).

    Raises:
        FileNotFoundError: the CSV is missing.
        ValueError: its rows are no single measurement (``from_rows``).
    """
    rows = read_rows(root, SOURCE.name, WRITTEN_BY)
    try:
        measured, n_seeds, noise, config = from_rows(rows)
    except ValueError as err:
        raise ValueError(f"{root / SOURCE}: {err}") from None
    setting = (
        "docs/model.md defaults"
        if not config
        else f"`AttentionConfig` fields `{json.dumps(config, sort_keys=True)}` over docs/model.md defaults"
    )
    threshold = f"{MIN_PASS_RATE:.0%}".replace("%", " %")
    return "\n".join(
        [
            "# Experiment checks",
            "",
            banner([SOURCE]),
            "Every criterion of docs/model.md §9 for the paper's five experiments, with the robot immobile at the "
            f"origin ({setting}), in each kinematics mode: `tracker` (the default), `window` and `literal`, and the "
            "tracker under the `usarsim` sensor profile. Each cell: whether the check holds noise-free (**fail** in "
            f"bold), then the share of {n_seeds} seeds with noise that pass it (Gaussian σ = {noise:g} of the reading, "
            f"or the profile's own noise), bold below {threshold}. The last row counts the checks that hold.",
            "",
            markdown(measured, n_seeds, noise),
            "",
            "## Reproduce",
            "",
            "```bash",
            f"{WRITTEN_BY}    # about 15 s on 2 cores once the kernels are compiled; writes {SOURCE.as_posix()}",
            "python tools/report.py render",
            "```",
            "",
        ]
    )
