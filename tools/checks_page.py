"""``docs/results/checks.md``: the paper's experiment checks per kinematics mode.

From ``docs/results/experiment_checks.csv`` (written by ``tools/experiments_table.py``):
rendering reads the measurement back (``attentive_gym.experiments.table.from_rows``) and
never reruns an experiment.
"""

from __future__ import annotations

import json
from pathlib import Path

from attentive_gym.experiments.runner import TRUTH
from attentive_gym.experiments.table import CAUSE_KINEMATICS as KINDS
from attentive_gym.experiments.table import COLUMNS, MIN_PASS_RATE, Measured, from_rows, markdown
from page_text import RESULTS, banner, read_rows, table

NAME = "checks.md"
SOURCE = RESULTS / "experiment_checks.csv"
CAUSES = RESULTS / "experiment_causes.csv"
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
    causes = _causes_markdown(measured, read_rows(root, CAUSES.name, WRITTEN_BY))
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
            banner([SOURCE, CAUSES]),
            "Every criterion of docs/model.md §9 for the paper's five experiments, with the robot immobile at the "
            f"origin ({setting}), in each kinematics mode: `tracker` (the default), `window` and `literal`; `truth`, "
            "the perfect-perception bound (the same model fed the simulator's true kinematics of the robots the laser "
            "sees, `attentive_gym.perception.bound`; the readings, and so F2 and F3, keep their noise); and the "
            "tracker under the `usarsim` sensor profile. Each cell: whether the check holds noise-free (**fail** in "
            f"bold), then the share of {n_seeds} seeds with noise that pass it (Gaussian σ = {noise:g} of the reading, "
            f"or the profile's own noise), bold below {threshold}. The last row counts the checks that hold. A check "
            "that `truth` fails is not failed by perception: the model's own dynamics, or the scenario, fail it.",
            "",
            markdown(measured, n_seeds, noise),
            "",
            *causes,
            *_measured_markdown(measured),
            "## Reproduce",
            "",
            "```bash",
            f"{WRITTEN_BY}    # about 25 s on 2 cores once the kernels are compiled; writes {SOURCE.as_posix()}",
            f"                                     # and {CAUSES.as_posix()}",
            "python tools/report.py render",
            "```",
            "",
        ]
    )


def _causes_markdown(measured: Measured, causes: list[dict[str, str]]) -> list[str]:
    """The section on the checks that the window mode holds and the tracker fails noise-free:
    whether each holds with the perfect-perception bound, and with the tracker and the bound
    under every ``CAUSE_SETTINGS`` setting (``causes``: ``measure_causes``' rows); none when
    there is no such check."""
    tracker, window, truth = ("tracker", None), ("window", None), (TRUTH, None)
    failing = [key for key, cell in measured.items() if cell["exact"].get(window) and not cell["exact"].get(tracker)]
    if not failing:
        return []
    settings = list(dict.fromkeys(row["setting"] for row in causes))
    outcome = {
        (row["experiment"], row["check"], row["kinematics"], row["setting"]): row["noise_free"] for row in causes
    }
    bound = {key: measured[key]["exact"].get(truth) for key in failing}
    lines = [
        [
            name,
            f"`{check}`",
            "**fail**",
            _cell({True: "pass", False: "fail"}.get(bound[(name, check)])),
            *(_cell(outcome.get((name, check, kinematics, setting))) for setting in settings for kinematics in KINDS),
        ]
        for name, check in failing
    ]
    return [
        "## What the tracker fails that the window mode holds",
        "",
        f"The {len(failing)} checks that hold noise-free in the window mode and fail with the tracker, rerun "
        "with the tracker noise-free under settings that each take away one cause: the laser clipped to the "
        "sonars' range (the paper's robot saw a target only within it; the laser sees it from 7–8 m) and "
        "vigilance put off (a top-down course longer than its onset adapts, and M falls below 1). A check that "
        "holds under a setting fails by default only through what that setting takes away; one that fails "
        "under both has another cause. Beside the tracker, the perfect-perception bound (`truth`) under the same "
        "settings: a check that it fails too is not one that better perception can hold.",
        "",
        table(
            [
                "experiment",
                "check",
                "tracker",
                "truth",
                *(f"{kinematics}, {setting}" for setting in settings for kinematics in KINDS),
            ],
            lines,
        ),
    ]


def _measured_markdown(measured: Measured) -> list[str]:
    """The section with what each noise-free run measured, a table per experiment: a row per
    check, a column per noise-free set-up of ``COLUMNS`` ("—" where a cell was not measured)."""
    columns = [column for column in COLUMNS if column[1] is None]
    lines = [
        "## What the noise-free runs measured",
        "",
        "Each check's measurement in the noise-free run of each set-up (seed 0), as `attentive-gym experiment NAME "
        "--kinematics MODE` prints it; **fail** marks the checks that do not hold.",
        "",
    ]
    for name in dict.fromkeys(key[0] for key in measured):
        rows = []
        for (experiment, check), cell in measured.items():
            if experiment != name:
                continue
            texts = [
                _measured_cell(cell["exact"].get(column), cell.get("measured", {}).get(column)) for column in columns
            ]
            rows.append([f"`{check}`", *texts])
        lines += [f"### {name}", "", table(["check", *(column[0] for column in columns)], rows), ""]
    return lines


def _measured_cell(passed: bool | None, text: str | None) -> str:
    """A noise-free measurement, prefixed with **fail** when its check does not hold; "—" where
    it was not measured."""
    if passed is None or not text:
        return "—"
    text = text.replace("|", "\\|")
    return text if passed else f"**fail**: {text}"


def _cell(outcome: str | None) -> str:
    """A check's outcome under a setting: "pass", "**fail**", or "—" where it was not measured."""
    return {"pass": "pass", "fail": "**fail**"}.get(outcome or "", "—")
