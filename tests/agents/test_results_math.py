"""Confidence intervals (checked against hand computation), summaries and atomic writes."""

import math
import os

import pytest

from attentive_gym.agents.results import (
    EVAL_COLUMNS,
    mean_ci,
    read_csv,
    summarise,
    summary_markdown,
    t_critical,
    write_csv_atomic,
    write_text_atomic,
)


def test_t_critical_matches_tables():
    assert t_critical(1) == pytest.approx(12.706)
    assert t_critical(4) == pytest.approx(2.776)
    assert t_critical(30) == pytest.approx(2.042)
    assert t_critical(40) == pytest.approx(2.021)
    assert t_critical(10**9) == pytest.approx(1.960, abs=1e-3)
    assert 2.042 > t_critical(35) > 2.021  # interpolated between the table rows
    for bad in (0, -1, 2.5, True):
        with pytest.raises(ValueError):
            t_critical(bad)


def test_mean_ci_by_hand():
    # x = 0.2, 0.4, 0.6: mean 0.4, s = 0.2, n = 3, t(2) = 4.303 → half width 4.303·0.2/√3 = 0.49687
    mean, low, high = mean_ci([0.2, 0.4, 0.6])
    assert mean == pytest.approx(0.4)
    assert high - mean == pytest.approx(0.496868, abs=1e-5)
    assert mean - low == pytest.approx(0.496868, abs=1e-5)
    # x = 1..5: mean 3, s = √2.5 = 1.58114, t(4) = 2.776 → half width 2.776·1.58114/√5 = 1.96296
    mean, low, high = mean_ci([1, 2, 3, 4, 5])
    assert (mean, low, high) == pytest.approx((3.0, 1.03704, 4.96296), abs=1e-4)
    assert mean_ci([7.0]) == (7.0, 7.0, 7.0)
    assert all(math.isnan(v) for v in mean_ci([]))
    assert mean_ci([1.0, float("nan"), 1.0]) == (1.0, 1.0, 1.0)


def _rows():
    rows = []
    for seed, curve in enumerate(([0.0, 0.4, 0.6], [0.1, 0.6, 0.8], [0.0, 0.2, 0.4])):
        for steps, success in zip((0, 100, 200), curve):
            rows.append({"variant": "a", "seed": seed, "env_steps": steps, "success_rate": success,
                         "mean_return": 10 * success})
    rows.append({"variant": "b", "seed": 0, "env_steps": 0, "success_rate": 0.0, "mean_return": -1.0})
    rows.append({"variant": "b", "seed": 0, "env_steps": 200, "success_rate": 0.2, "mean_return": 1.0})
    return rows


def test_summarise_final_values_and_steps_to_threshold():
    a, b = summarise(_rows(), threshold=0.5)
    assert a["variant"] == "a" and a["n_seeds"] == 3 and a["final_env_steps"] == 200
    mean, low, high = mean_ci([0.6, 0.8, 0.4])
    assert (a["final_success_mean"], a["final_success_ci_low"], a["final_success_ci_high"]) == pytest.approx((mean, low, high))
    assert a["final_return_mean"] == pytest.approx(6.0)
    # seed 0 reaches 0.5 at 200, seed 1 at 100, seed 2 never
    assert a["seeds_reaching_threshold"] == 2
    assert a["steps_to_threshold_mean"] == pytest.approx(150.0)
    assert b["seeds_reaching_threshold"] == 0 and math.isnan(b["steps_to_threshold_mean"])
    text = summary_markdown([a, b])
    assert text.count("\n") == 4 and "| a | 3 | 200 | 0.60 [" in text and "| b |" in text and "0/1" in text
    with pytest.raises(ValueError):
        summarise(_rows(), threshold=1.5)


def test_csv_roundtrip_and_atomic_write(tmp_path):
    rows = [{"variant": "raw", "seed": 1, "env_steps": 1024, "n_episodes": 2, "success_rate": 0.5,
             "mean_return": float("nan")}]
    path = write_csv_atomic(tmp_path / "r.csv", rows, EVAL_COLUMNS)
    back = read_csv(path)
    assert list(back[0]) == list(EVAL_COLUMNS)
    assert back[0]["seed"] == 1 and back[0]["success_rate"] == 0.5 and math.isnan(back[0]["mean_return"])
    # a failed write leaves the old file whole and no temp file behind
    target = write_text_atomic(tmp_path / "x.txt", "old")
    with pytest.raises(TypeError):
        write_text_atomic(target, 123)  # not text: fails after the temp file was opened
    assert target.read_text() == "old"
    assert set(os.listdir(tmp_path)) == {"r.csv", "x.txt"}
