"""Zero-shot generalisation (``agents.generalisation``, ``attentive-gym generalise``) on a tiny comparison."""

import math

import pytest

from attentive_gym.agents.generalisation import (
    COLUMNS,
    SHIFTS,
    SUMMARY_COLUMNS,
    evaluate_shift,
    finished_runs,
    generalise,
    parse_shifts,
    summarise_shifts,
)
from attentive_gym.agents.results import read_csv
from attentive_gym.agents.training import train
from attentive_gym.cli import main


@pytest.fixture(scope="module")
def comparison(tmp_path_factory, tiny):
    """A comparison folder with two finished tiny runs (raw seed 0, focus seed 1) and an unfinished one."""
    root = tmp_path_factory.mktemp("comparison")
    for variant, seed in (("raw", 0), ("focus", 1)):
        train(tiny(variant=variant, seed=seed), root / "runs" / f"{variant}-seed{seed}", tensorboard=False)
    (root / "runs" / "oracle-seed0").mkdir()  # started, never finished: not evaluated
    return root


def test_as_trained_reproduces_the_runs_own_final_evaluation(comparison):
    """The shift-free row is the run's final evaluation (same policy, same episode seeds), bit for bit."""
    run = comparison / "runs" / "raw-seed0"
    final = read_csv(run / "eval.csv")[-1]
    row = evaluate_shift(str(run), "as trained", int(final["n_episodes"]))
    assert set(row) == set(COLUMNS) and row["env_steps"] == final["env_steps"]
    for key in ("success_rate", "safe_success_rate", "mean_return", "mean_episode_length", "mean_contact_s"):
        assert row[key] == pytest.approx(final[key], abs=1e-4), key


def test_a_shift_reaches_the_environment(comparison, monkeypatch):
    """Each shift's keywords replace the run's own: the env is built with them, and a noisier sensor
    changes the episodes."""
    import attentive_gym.agents.training as training

    built = []
    original = training.env_factory
    monkeypatch.setattr(
        training, "env_factory", lambda spec, **kw: built.append(kw) or original(spec, **kw), raising=True
    )
    run = str(comparison / "runs" / "raw-seed0")
    calm, noisy = (evaluate_shift(run, shift, 2) for shift in ("as trained", "10 % noise"))
    assert built[0] == {} and built[-1] == {"sensor_noise": 0.10}
    assert calm["mean_return"] != noisy["mean_return"]


def test_generalise_writes_a_row_per_run_and_shift_and_a_rerun_evaluates_only_the_missing_ones(comparison):
    lines = []
    rows = generalise(comparison, ["as trained", "0 distractors"], episodes=2, report=lines.append)
    assert [(r["variant"], r["seed"], r["shift"]) for r in rows] == [
        ("raw", 0, "as trained"),
        ("raw", 0, "0 distractors"),
        ("focus", 1, "as trained"),
        ("focus", 1, "0 distractors"),
    ]
    assert lines[0] == "generalise: 2 runs × 2 shifts, 4 to evaluate (2 episodes each)"
    on_disk = read_csv(comparison / "generalisation.csv")
    assert [(r["variant"], r["shift"], r["success_rate"]) for r in on_disk] == [
        (r["variant"], r["shift"], r["success_rate"]) for r in rows
    ]
    lines.clear()
    again = generalise(comparison, ["as trained", "0 distractors", "12 m arena"], episodes=2, report=lines.append)
    assert lines[0] == "generalise: 2 runs × 3 shifts, 2 to evaluate (2 episodes each)"
    assert [r for r in again if r["shift"] != "12 m arena"] == on_disk
    with pytest.raises(ValueError, match=r"holds rows of \[2\] episodes .* --episodes 2"):
        generalise(comparison, ["as trained"], episodes=3)
    assert read_csv(comparison / "generalisation.csv") == again  # the refusal wrote nothing


def test_a_pool_of_processes_gives_the_same_rows(comparison, tmp_path):
    """Two worker processes evaluate the same episodes as one process does."""
    import shutil

    copy = tmp_path / "copy"
    shutil.copytree(comparison / "runs", copy / "runs")
    pooled = generalise(copy, ["as trained", "6 distractors"], episodes=2, workers=2, report=lambda _: None)
    alone = [r for r in read_csv(comparison / "generalisation.csv") if r["shift"] == "as trained"]
    assert [r for r in pooled if r["shift"] == "as trained"] == alone
    assert {r["shift"] for r in pooled} == {"as trained", "6 distractors"} and len(pooled) == 4


def test_the_summary_gives_each_shift_and_variant_its_mean_and_interval_inside_the_range():
    rows = [
        {
            "variant": variant,
            "seed": seed,
            "shift": shift,
            "success_rate": s,
            "safe_success_rate": s / 2,
            "mean_contact_s": c,
        }
        for variant, rates in (("raw", (0.2, 0.4, 0.6)), ("focus", (0.9, 1.0, 0.8)))
        for seed, (s, c) in enumerate(zip(rates, (1.0, 2.0, 3.0)))
        for shift in ("10 % noise", "as trained")
    ]
    summary = summarise_shifts(rows)
    assert [(r["shift"], r["variant"]) for r in summary] == [
        ("as trained", "raw"),
        ("as trained", "focus"),
        ("10 % noise", "raw"),
        ("10 % noise", "focus"),
    ]
    raw = summary[0]
    assert set(raw) == set(SUMMARY_COLUMNS) and raw["n_seeds"] == 3
    assert raw["success_mean"] == pytest.approx(0.4) and raw["contact_s_mean"] == pytest.approx(2.0)
    for row in summary:
        for metric in ("success", "safe_success"):
            assert 0.0 <= row[f"{metric}_ci_low"] <= row[f"{metric}_mean"] <= row[f"{metric}_ci_high"] <= 1.0
    assert summary[1]["success_ci_high"] == 1.0  # clipped to the rate's range
    with pytest.raises(ValueError, match="unknown shift"):
        summarise_shifts([{**rows[0], "shift": "moon"}])


def test_bad_input_is_refused_with_the_allowed_values(tmp_path, capsys):
    assert parse_shifts(None) == list(SHIFTS)
    assert parse_shifts("2 % noise, 12 m arena") == ["2 % noise", "12 m arena"]
    with pytest.raises(ValueError, match=r"unknown shift\(s\) \['moon'\]; allowed: \['as trained'"):
        parse_shifts("moon")
    with pytest.raises(ValueError, match="twice"):
        parse_shifts("2 % noise,2 % noise")
    with pytest.raises(ValueError, match="no runs/ folder"):
        finished_runs(tmp_path)
    (tmp_path / "runs" / "raw-seed0").mkdir(parents=True)
    with pytest.raises(ValueError, match="no finished run"):
        finished_runs(tmp_path)
    assert main(["generalise", str(tmp_path), "--shifts", "moon"]) == 2
    assert "unknown shift(s) ['moon']" in capsys.readouterr().err
    assert not (tmp_path / "generalisation.csv").exists()


def test_the_command_writes_the_rows_the_summary_and_the_figure(comparison, capsys):
    assert (
        main(
            ["generalise", str(comparison), "--shifts", "as trained,0 distractors", "--episodes", "2", "--workers", "1"]
        )
        == 0
    )
    printed = capsys.readouterr().out
    assert "2 runs × 2 shifts, 0 to evaluate" in printed  # the rows of the test above
    assert "as trained raw" in " ".join(printed.split())
    summary = read_csv(comparison / "generalisation_summary.csv")
    assert {(r["shift"], r["variant"]) for r in summary} == {
        (shift, variant) for shift in ("as trained", "0 distractors", "12 m arena") for variant in ("raw", "focus")
    }
    assert all(math.isnan(r["success_ci_low"]) for r in summary)  # one seed each: no interval
    assert (comparison / "generalisation.png").stat().st_size > 10_000
