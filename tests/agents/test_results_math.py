"""Bootstrap intervals, IQM and probability of improvement (checked against hand computation),
summaries and atomic writes."""

import math
import os

import numpy as np
import pytest

from attentive_gym.agents.results import (
    EVAL_COLUMNS,
    read_csv,
    summarise,
    summary_markdown,
    write_csv_atomic,
    write_text_atomic,
)
from attentive_gym.agents.statistics import bootstrap_ci, iqm, probability_of_improvement


def test_iqm_by_hand():
    assert iqm(np.array([1.0, 2.0, 3.0, 4.0, 100.0])) == 3.0  # drops 1 and 100
    assert iqm(np.arange(8.0)) == 3.5  # the mean of 2, 3, 4, 5
    assert iqm(np.array([0.7])) == 0.7


def test_bootstrap_ci_hand_computed_cases():
    assert math.isnan(bootstrap_ci([0.4], bounds=(0, 1))[1])  # one seed: no interval
    assert bootstrap_ci([0.4], bounds=(0, 1))[0] == 0.4
    assert bootstrap_ci([0.3, 0.3, 0.3], bounds=(0, 1)) == (0.3, 0.3, 0.3)  # all equal: zero width
    assert bootstrap_ci([1.0, 1.0, 1.0, 1.0], bounds=(0, 1)) == (1.0, 1.0, 1.0)  # at the bound
    # two seeds 0 and 1: resampled means 0, 0.5, 1 with chances 1/4, 1/2, 1/4, so the
    # central 95 % runs from 0 to 1
    assert bootstrap_ci([0.0, 1.0], bounds=(0, 1)) == (0.5, 0.0, 1.0)
    point, low, high = bootstrap_ci([0.0, 0.0, 0.1, 1.0, 1.0], bounds=(0, 1))
    assert 0.0 <= low < point < high <= 1.0  # a t-interval here would reach below 0 and above 1
    assert all(math.isnan(v) for v in bootstrap_ci([]))
    assert bootstrap_ci([1.0, float("nan"), 1.0]) == (1.0, 1.0, 1.0)
    with pytest.raises(ValueError, match="finite"):
        bootstrap_ci([0.1, float("inf")])
    with pytest.raises(ValueError, match="confidence"):
        bootstrap_ci([0.1, 0.2], confidence=1.0)
    with pytest.raises(ValueError, match=r"range \(0, 1\).*1\.3"):
        bootstrap_ci([1.3, 1.0], bounds=(0, 1))  # a success rate above 1 would push the interval past 1
    with pytest.raises(ValueError, match="low <= high"):
        bootstrap_ci([0.4, 0.0], bounds=(1, 0))
    with pytest.raises(ValueError, match="reps"):
        bootstrap_ci([0.4, 0.0], reps=0)
    with pytest.raises(ValueError, match="reps"):
        probability_of_improvement([0.4, 0.0], [0.1, 0.2], reps=0)


def test_bootstrap_ci_agrees_with_the_normal_interval_for_many_seeds_and_is_reproducible():
    values = np.random.default_rng(0).normal(2.0, 1.0, 400)
    point, low, high = bootstrap_ci(values)
    half = 1.96 * values.std(ddof=1) / math.sqrt(values.size)
    assert point == pytest.approx(values.mean())
    assert (high - low) / 2 == pytest.approx(half, rel=0.1)
    assert bootstrap_ci(values) == (point, low, high)
    assert bootstrap_ci(values, iqm)[0] == pytest.approx(iqm(values))


def test_probability_of_improvement_by_hand():
    # pairs: 0.5 beats 2, 0.6 beats 2 and ties 1, 0.7 beats 3 → (2 + 2.5 + 3) / 9
    point, low, high = probability_of_improvement([0.5, 0.6, 0.7], [0.1, 0.2, 0.6])
    assert point == pytest.approx(7.5 / 9)
    assert 0.0 <= low <= point <= high <= 1.0
    assert probability_of_improvement([1.0, 1.0], [1.0, 1.0]) == (0.5, 0.5, 0.5)
    assert probability_of_improvement([1.0, 1.0], [0.0, 0.0]) == (1.0, 1.0, 1.0)
    single = probability_of_improvement([0.9], [0.1, 0.2])
    assert single[0] == 1.0 and math.isnan(single[1])


def _rows():
    rows = []
    for seed, curve in enumerate(([0.0, 0.4, 0.6], [0.1, 0.6, 0.8], [0.0, 0.2, 0.4])):
        for steps, success in zip((0, 100, 200), curve):
            rows.append(
                {"variant": "a", "seed": seed, "env_steps": steps, "success_rate": success, "mean_return": 10 * success}
            )
    rows.append({"variant": "b", "seed": 0, "env_steps": 0, "success_rate": 0.0, "mean_return": -1.0})
    rows.append({"variant": "b", "seed": 0, "env_steps": 200, "success_rate": 0.2, "mean_return": 1.0})
    return rows


def test_summarise_final_values_and_steps_to_threshold():
    a, b = summarise(_rows(), threshold=0.5)
    assert a["variant"] == "a" and a["n_seeds"] == 3 and a["final_env_steps"] == 200
    point, low, high = bootstrap_ci([0.6, 0.8, 0.4], bounds=(0, 1))
    assert (a["final_success_mean"], a["final_success_ci_low"], a["final_success_ci_high"]) == (point, low, high)
    assert point == pytest.approx(0.6) and 0.4 <= low < point < high <= 0.8 + 1e-12
    assert a["final_success_iqm"] == pytest.approx(0.6)  # three seeds: nothing is trimmed
    # no "raw" here: the baseline is the first variant; b's 0.2 is below two of a's three seeds
    assert a["improvement_over"] == b["improvement_over"] == "a"
    assert a["prob_improvement"] == 0.5 and b["prob_improvement"] == pytest.approx(0.0)
    assert math.isnan(b["final_success_ci_low"])  # one seed: no interval
    assert a["final_return_mean"] == pytest.approx(6.0)
    # seed 0 reaches 0.5 at 200, seed 1 at 100, seed 2 never
    assert a["seeds_reaching_threshold"] == 2
    assert a["steps_to_threshold_mean"] == pytest.approx(150.0)
    assert b["seeds_reaching_threshold"] == 0 and math.isnan(b["steps_to_threshold_mean"])
    text = summary_markdown([a, b])
    assert text.count("\n") == 4 and "| a | 3 | 200 | 0.60 [" in text and "| b |" in text and "0/1" in text
    assert "0.20 (1 seed: no CI)" in text and "P(success > a)" in text
    with pytest.raises(ValueError):
        summarise(_rows(), threshold=1.5)


def test_steps_to_threshold_interval_covers_seeds_trained_past_the_shortest_budget():
    rows = [
        {"variant": "a", "seed": seed, "env_steps": steps, "success_rate": float(steps >= hit), "mean_return": 0.0}
        for seed, (hit, budget) in enumerate(((100, 100), (200, 200), (200, 200)))
        for steps in range(0, budget + 1, 100)
    ]
    (a,) = summarise(rows, threshold=0.5)
    assert a["final_env_steps"] == 100 and a["seeds_reaching_threshold"] == 3
    assert a["steps_to_threshold_mean"] == pytest.approx(500 / 3)
    assert (a["steps_to_threshold_ci_low"], a["steps_to_threshold_ci_high"]) == (100.0, 200.0)


def test_summarise_refuses_a_missing_or_impossible_success_rate():
    rows = _rows()
    rows[4] = {**rows[4], "success_rate": float("nan")}  # seed 1 at 100 env steps
    with pytest.raises(ValueError, match="a seed 1 at 100 env steps has nan"):
        summarise(rows)
    rows[4] = {**rows[4], "success_rate": 1.5}
    with pytest.raises(ValueError, match=r"in \[0, 1\]"):
        summarise(rows)


def test_summary_says_why_an_interval_is_missing():
    rows = [{"variant": "raw", "seed": 0, "env_steps": 100, "success_rate": 0.5, "mean_return": 0.0}]
    rows += [
        {"variant": "focus", "seed": seed, "env_steps": 100, "success_rate": value, "mean_return": 0.0}
        for seed, value in enumerate((0.6, 0.7, 0.8))
    ]
    text = summary_markdown(summarise(rows, threshold=0.65))
    focus = next(line for line in text.splitlines() if line.startswith("| focus"))
    assert "1.00 (raw has 1 seed: no CI)" in focus  # P(improvement): the baseline has one seed
    assert "100 [100, 100]" in focus  # two seeds reached the threshold: an interval
    raw = next(line for line in text.splitlines() if line.startswith("| raw"))
    assert "0.50 (1 seed: no CI)" in raw


def test_csv_roundtrip_and_atomic_write(tmp_path):
    rows = [
        {
            "variant": "raw",
            "seed": 1,
            "env_steps": 1024,
            "n_episodes": 2,
            "success_rate": 0.5,
            "mean_return": float("nan"),
        }
    ]
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


def test_learning_curve_ticks_read_in_thousands_and_millions():
    from attentive_gym.agents.plots import steps_label

    assert [steps_label(v) for v in (0, 500, 50_000, 150_000, 1_000_000, 1_500_000)] == [
        "0",
        "500",
        "50k",
        "150k",
        "1M",
        "1.5M",
    ]


def test_learning_curve_bands_stay_inside_the_success_range():
    from attentive_gym.agents.plots import curve_stats

    rows = [
        {"variant": "a", "seed": seed, "env_steps": 100, "success_rate": value}
        for seed, value in enumerate((0.0, 0.0, 0.1, 1.0, 1.0))
    ]
    steps, mean, low, high = curve_stats(rows, "a", "success_rate")
    assert steps.tolist() == [100] and 0.0 <= low[0] < mean[0] < high[0] <= 1.0


def _sweep_rows():
    rows = []
    for n, (raw, focus) in {1: (0.6, 0.5), 3: (0.4, 0.45), 6: (0.2, 0.4)}.items():
        for variant, level in (("raw", raw), ("focus", focus)):
            for seed, noise in enumerate((-0.02, 0.0, 0.02)):
                for steps, success in ((0, 0.2), (100, level + noise)):
                    rows.append(
                        {
                            "num_distractors": n,
                            "variant": variant,
                            "seed": seed,
                            "env_steps": steps,
                            "success_rate": success,
                            "mean_return": success,
                        }
                    )
    return rows


def test_sweep_tables_summarise_each_distractor_count(tmp_path):
    from attentive_gym.agents.plots import plot_success_vs_distractors
    from attentive_gym.agents.sweep import sweep_tables

    summary = sweep_tables(_sweep_rows())
    assert [(r["num_distractors"], r["variant"]) for r in summary] == [
        (n, v) for n in (1, 3, 6) for v in ("raw", "focus")
    ]
    focus = {r["num_distractors"]: r for r in summary if r["variant"] == "focus"}
    assert focus[6]["final_success_mean"] == pytest.approx(0.4) and focus[6]["improvement_over"] == "raw"
    assert focus[1]["prob_improvement"] == 0.0 and focus[6]["prob_improvement"] == 1.0
    path = plot_success_vs_distractors(summary, tmp_path / "sweep.png")
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize(
    "text, ok", [("1,3,6", (1, 3, 6)), ("0", (0,)), ("1,1", None), ("1,", None), ("-1", None), ("a", None)]
)
def test_distractor_counts_are_parsed_strictly(text, ok):
    from attentive_gym.agents.sweep import parse_distractors

    if ok is None:
        with pytest.raises(ValueError, match="distractor counts"):
            parse_distractors(text)
    else:
        assert parse_distractors(text) == ok


def test_a_crowded_learning_curve_legend_sits_below_the_panels(tmp_path, monkeypatch):
    from attentive_gym.agents import plots

    figures = []
    monkeypatch.setattr(plots, "_save", lambda fig, path, layout=True: figures.append(fig) or path)
    rows = [
        {"variant": f"v{k}", "seed": seed, "env_steps": step, "success_rate": 0.5, "mean_return": 1.0}
        for k in range(6)
        for seed in (0, 1)
        for step in (0, 100)
    ]
    plots.plot_learning_curves(rows[: 2 * 2 * 2], tmp_path / "few.png")
    plots.plot_learning_curves(rows, tmp_path / "many.png")
    few, many = figures
    assert few.axes[0].get_legend() is not None and not few.legends
    (legend,) = many.legends
    many.canvas.draw()
    renderer = many.canvas.get_renderer()  # below the panels' tick labels and axis titles too
    assert len(legend.get_texts()) == 6
    assert legend.get_window_extent().y1 < min(ax.get_tightbbox(renderer).y0 for ax in many.axes)


def test_a_variant_keeps_its_colour_across_settings_which_differ_in_line_style(tmp_path, monkeypatch):
    from attentive_gym.agents import plots

    figures = []
    monkeypatch.setattr(plots, "_save", lambda fig, path, layout=True: figures.append(fig) or path)
    labels = ["raw", "focus", "raw (recurrent-ppo)", "focus (recurrent-ppo)", "focus (ppo, lr lin_3e-4)"]
    rows = [
        {"variant": label, "seed": seed, "env_steps": step, "success_rate": 0.5, "mean_return": 1.0}
        for label in labels
        for seed in (0, 1)
        for step in (0, 100)
    ]
    plots.plot_learning_curves(rows, tmp_path / "curves.png")
    lines = {line.get_label().rsplit(" (n=", 1)[0]: line for line in figures[0].axes[0].get_lines()}
    colour = {label: lines[label].get_color() for label in labels}
    style = {label: lines[label].get_linestyle() for label in labels}
    assert colour["raw"] == colour["raw (recurrent-ppo)"] != colour["focus"] == colour["focus (recurrent-ppo)"]
    assert style["raw"] == style["focus"] == "-" and style["raw (recurrent-ppo)"] == style["focus (recurrent-ppo)"]
    assert len({style["focus"], style["focus (recurrent-ppo)"], style["focus (ppo, lr lin_3e-4)"]}) == 3
    assert plots.split_label("focus (ppo, lr lin_3e-4)") == ("focus", " (ppo, lr lin_3e-4)")
