"""The clutter sweep runs the comparison at each distractor count and tabulates it."""

import json

import pytest

from attentive_gym.agents.results import read_csv
from attentive_gym.agents.sweep import SWEEP_COLUMNS, SWEEP_SUMMARY_COLUMNS
from attentive_gym.cli import main


@pytest.mark.slow
def test_compare_distractors_sweeps_the_clutter(tmp_path, tiny, capsys):
    out = tmp_path / "sweep"
    argv = [
        "compare",
        "--variants",
        "raw,focus",
        "--seeds",
        "1",
        "--steps",
        "128",
        "--n-envs",
        "2",
        "--eval-every",
        "128",
        "--checkpoint-every",
        "64",
        "--eval-episodes",
        "1",
        "--env-kwargs",
        json.dumps(tiny.env_kwargs),
        "--algo-kwargs",
        json.dumps(tiny.ppo_kwargs),
        "--workers",
        "2",
        "--out",
        str(out),
        "--distractors",
        "1,3",
    ]
    assert main(argv) == 0
    header = capsys.readouterr().out.splitlines()[0]
    assert header.startswith(
        "compare: clutter sweep over 2 distractor counts × 2 variants × 1 seed × 128 env steps (process, 2 workers)"
    ), header
    for n in (1, 3):
        spec = json.loads((out / f"distractors-{n}" / "runs" / "raw-seed0" / "spec.json").read_text())
        assert spec["env_kwargs"]["num_distractors"] == n
    rows = read_csv(out / "sweep.csv")
    assert list(rows[0]) == list(SWEEP_COLUMNS)
    assert {(r["num_distractors"], r["variant"]) for r in rows} == {(n, v) for n in (1, 3) for v in ("raw", "focus")}
    summary = read_csv(out / "sweep_summary.csv")
    assert list(summary[0]) == list(SWEEP_SUMMARY_COLUMNS) and len(summary) == 4
    assert (out / "success_vs_distractors.png").read_bytes()[:4] == b"\x89PNG"

    # a rerun at one count (here: trained on) keeps the other count in the sweep's tables
    argv[argv.index("--steps") + 1] = "256"
    assert main([*argv[:-1], "3", "--extend"]) == 0
    rows = read_csv(out / "sweep.csv")
    assert {r["num_distractors"] for r in rows} == {1, 3}
    finals = {n: max(r["env_steps"] for r in rows if r["num_distractors"] == n) for n in (1, 3)}
    assert finals[3] > finals[1]


def test_a_bad_distractor_list_is_refused_before_anything_is_written(tmp_path, capsys):
    out = tmp_path / "sweep"
    assert main(["compare", "--variants", "raw", "--seeds", "1", "--out", str(out), "--distractors", "1,1"]) == 2
    assert "distractor counts must be distinct" in capsys.readouterr().err
    assert not out.exists()
