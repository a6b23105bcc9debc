"""Bootstrap intervals, IQM and probability of improvement (checked against hand computation),
summaries and atomic writes."""

import math
import os

import numpy as np
import pytest

from attentive_gym.agents.results import (
    EVAL_COLUMNS,
    SAFE_COLUMNS,
    read_csv,
    summarise,
    summary_markdown,
    write_csv_atomic,
    write_text_atomic,
)
from attentive_gym.statistics import (
    bootstrap_ci,
    iqm,
    performance_profile,
    pooled_median_ci,
    probability_of_improvement,
    ratio_ci,
)


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


def test_ratio_ci_by_hand():
    # clusters scoring 1 of 2 and 3 of 4: pooled 4/6; two clusters resampled give 2/4, 4/6 or
    # 6/8 with chances 1/4, 1/2, 1/4, so the central 95 % runs from 0.5 to 0.75
    assert ratio_ci([1, 3], [2, 4]) == pytest.approx((4 / 6, 0.5, 0.75))
    point, low, high = ratio_ci([3, 0], [4, 0])  # a cluster without events says nothing
    assert point == 0.75 and math.isnan(low) and math.isnan(high)
    assert all(math.isnan(v) for v in ratio_ci([0, 0], [0, 0]))
    assert ratio_ci([2, 2, 2], [4, 4, 4]) == (0.5, 0.5, 0.5)
    for hits, totals, message in (
        ([1], [1, 2], "one count per cluster"),
        ([3], [2], "hits <= totals"),
        ([-1], [2], "0 <= hits"),
    ):
        with pytest.raises(ValueError, match=message):
            ratio_ci(hits, totals)


def test_ratio_ci_resamples_clusters_not_events():
    # the same 200 of 400 events, spread evenly over 10 clusters or all-or-nothing per cluster:
    # the steps of one episode are not independent, and the interval must widen with that
    even_point, even_low, even_high = ratio_ci([20] * 10, [40] * 10)
    point, low, high = ratio_ci([40] * 5 + [0] * 5, [40] * 10)
    assert even_point == point == 0.5 and (even_low, even_high) == (0.5, 0.5)
    assert low < 0.3 and high > 0.7  # about 0.5 ± 1.96·0.5/√10
    assert ratio_ci([40] * 5 + [0] * 5, [40] * 10) == (point, low, high)  # reproducible


def test_pooled_median_ci_by_hand():
    # one cluster of values 1 and 2, one of 3: pooled median 2; resampled, the pair gives
    # medians 1.5, 2 or 3 with chances 1/4, 1/2, 1/4
    assert pooled_median_ci([[1.0, 2.0], [3.0]]) == (2.0, 1.5, 3.0)
    # a start never judged is +inf: the median and a bound may be inf, never NaN
    point, low, high = pooled_median_ci([[1.0], [math.inf], [math.inf]])
    assert (point, low, high) == (math.inf, 1.0, math.inf)
    point, low, high = pooled_median_ci([[4.0, 5.0], []])  # an empty cluster says nothing
    assert point == 4.5 and math.isnan(low) and math.isnan(high)
    assert all(math.isnan(v) for v in pooled_median_ci([[], []]))
    with pytest.raises(ValueError, match=r"\+inf"):
        pooled_median_ci([[1.0, float("nan")]])


def test_probability_of_improvement_by_hand():
    # pairs: 0.5 beats 2, 0.6 beats 2 and ties 1, 0.7 beats 3 → (2 + 2.5 + 3) / 9
    point, low, high = probability_of_improvement([0.5, 0.6, 0.7], [0.1, 0.2, 0.6])
    assert point == pytest.approx(7.5 / 9)
    assert 0.0 <= low <= point <= high <= 1.0
    assert probability_of_improvement([1.0, 1.0], [1.0, 1.0]) == (0.5, 0.5, 0.5)
    assert probability_of_improvement([1.0, 1.0], [0.0, 0.0]) == (1.0, 1.0, 1.0)
    single = probability_of_improvement([0.9], [0.1, 0.2])
    assert single[0] == 1.0 and math.isnan(single[1])


def test_performance_profile_by_hand():
    share, low, high = performance_profile([0.2, 0.5, 0.5, 0.9], [0.0, 0.2, 0.5, 0.8, 1.0])
    assert share.tolist() == [1.0, 0.75, 0.25, 0.25, 0.0]  # strictly above each threshold
    assert (low <= share).all() and (share <= high).all() and low.min() >= 0.0 and high.max() <= 1.0
    assert low[0] == high[0] == 1.0 and low[-1] == high[-1] == 0.0  # every resample agrees there
    assert low[2] < 0.25 < high[2]  # a share of 1 run in 4 is uncertain
    single = performance_profile([0.6], [0.5, 0.7])
    assert single[0].tolist() == [1.0, 0.0] and np.isnan(single[1]).all()
    assert np.isnan(performance_profile([], [0.5])[0]).all()
    with pytest.raises(ValueError, match="thresholds"):
        performance_profile([0.5, 0.6], [float("nan")])


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


def _safe_rows():
    """raw: 2 seeds, final safe success 0.2 and 0.4, contact 2 and 4 s; focus: 3 seeds, safe
    success 0.5 and contact 0.5 s each; at 0 env steps every seed has safe success 0, 9 s."""
    rows = []
    for variant, finals in (("raw", ((0.2, 2.0), (0.4, 4.0))), ("focus", ((0.5, 0.5),) * 3)):
        for seed, (safe, contact) in enumerate(finals):
            for steps, values in ((0, (0.0, 9.0)), (100, (safe, contact))):
                rows.append(
                    {
                        "variant": variant,
                        "seed": seed,
                        "env_steps": steps,
                        "success_rate": 0.6,
                        "safe_success_rate": values[0],
                        "mean_contact_s": values[1],
                        "mean_return": 1.0,
                    }
                )
    return rows


def test_summarise_gives_safe_success_and_contact_time_beside_success():
    raw, focus = summarise(_safe_rows())
    assert (raw["final_safe_success_mean"], raw["final_safe_success_ci_low"], raw["final_safe_success_ci_high"]) == (
        bootstrap_ci([0.2, 0.4], bounds=(0, 1))
    )
    assert raw["final_safe_success_mean"] == pytest.approx(0.3) and raw["final_contact_s_mean"] == pytest.approx(3.0)
    assert (raw["final_contact_s_ci_low"], raw["final_contact_s_ci_high"]) == (2.0, 4.0)  # as bootstrap_ci([0, 1])
    assert focus["final_safe_success_mean"] == focus["final_safe_success_iqm"] == pytest.approx(0.5)
    assert (focus["final_contact_s_ci_low"], focus["final_contact_s_ci_high"]) == (0.5, 0.5)
    assert focus["improvement_over"] == "raw" and focus["prob_improvement"] == 0.5  # equal success
    assert (focus["prob_safe_improvement"], focus["prob_safe_improvement_ci_low"]) == (1.0, 1.0)  # 0.5 beats 0.2, 0.4
    assert raw["prob_safe_improvement"] == 0.5
    # the last two evaluations of each seed averaged: raw's seeds (0 + 0.2) / 2 and (0 + 0.4) / 2
    (early_raw, _) = summarise(_safe_rows(), final_points=2)
    assert early_raw["final_safe_success_mean"] == pytest.approx(0.15)
    assert early_raw["final_contact_s_mean"] == pytest.approx((5.5 + 6.5) / 2)
    text = summary_markdown([raw, focus])
    assert "final safe success (≤ 1 s in contact)" in text and "P(safe success > raw)" in text
    assert "final contact time (s / episode)" in text
    assert "| focus | 3 | 100 | 0.60 [0.60, 0.60] | 0.50 [0.50, 0.50] |" in text
    assert "| 1.00 [1.00, 1.00] | 0.50 [0.50, 0.50] |" in text  # P(safe success > raw), then the contact time


def test_rows_written_before_the_safe_success_measure_summarise_as_not_recorded(tmp_path):
    old_columns = [c for c in EVAL_COLUMNS if c not in SAFE_COLUMNS]
    path = write_csv_atomic(tmp_path / "v0.csv", _rows(), old_columns)  # an eval.csv written before the measure
    for rows in (_rows(), read_csv(path)):
        for row in summarise(rows):
            for key in (
                "final_safe_success_mean",
                "final_safe_success_ci_low",
                "final_safe_success_iqm",
                "final_contact_s_mean",
                "final_contact_s_ci_high",
                "prob_safe_improvement",
            ):
                assert math.isnan(row[key]), key  # never 0
            assert not math.isnan(row["final_success_mean"])
    a = summary_markdown(summarise(_rows()))
    assert "| a | 3 | 200 | 0.60 [0.40, 0.80] | — |" in a
    # one seed without the measure: the variant's safe summary is not recorded, not that of a subset of its seeds
    rows = _safe_rows()
    rows[3] = {k: v for k, v in rows[3].items() if k not in SAFE_COLUMNS}  # raw seed 1 at 100 env steps
    raw, focus = summarise(rows)
    assert math.isnan(raw["final_safe_success_mean"]) and math.isnan(raw["final_contact_s_mean"])
    assert math.isnan(focus["prob_safe_improvement"]) and focus["final_safe_success_mean"] == pytest.approx(0.5)


@pytest.mark.parametrize(
    "change, message",
    [
        (
            {"safe_success_rate": 0.7},
            r"safe_success_rate must be empty \(not recorded\) or a number in \[0, success_rate\]",
        ),
        ({"safe_success_rate": -0.1}, "raw seed 1 at 100 env steps has -0.1 with success_rate 0.6"),
        ({"mean_contact_s": -1.0}, r"mean_contact_s must be empty \(not recorded\) or a number of s >= 0"),
        ({"mean_contact_s": "1 s"}, "raw seed 1 at 100 env steps has '1 s'"),
    ],
)
def test_summarise_refuses_an_impossible_safe_success_or_contact_time(change, message):
    rows = _safe_rows()
    rows[3] = {**rows[3], **change}
    with pytest.raises(ValueError, match=message):
        summarise(rows)


def test_the_learning_curves_show_safe_success_and_contact_time_where_the_rows_record_them(tmp_path, monkeypatch):
    from attentive_gym.agents import plots

    figures = []
    monkeypatch.setattr(plots, "_save", lambda fig, path, layout=True: figures.append(fig) or path)
    plots.plot_learning_curves(_safe_rows(), tmp_path / "safe.png")
    plots.plot_learning_curves(_rows(), tmp_path / "v0.png")
    safe, v0 = figures
    labels = [ax.get_ylabel() for ax in safe.axes]
    assert labels == [
        "success rate",
        "safe success rate (≤ 1 s in contact)",
        "contact time / episode (s)",
        "mean return",
    ]
    for ax in safe.axes[:2]:  # the rates on [0, 1] (with a margin for markers at the ends)
        low, high = ax.get_ylim()
        assert -0.05 < low <= 0.0 and 1.0 <= high < 1.05
    contact_means = [line.get_ydata().tolist() for line in safe.axes[2].get_lines()]
    assert contact_means == [[9.0, 3.0], [9.0, 0.5]]
    assert [ax.get_ylabel() for ax in v0.axes] == ["success rate", "mean return"]  # no empty safe panels
    with pytest.raises(ValueError, match="record none of the metrics"):
        plots.plot_learning_curves(_rows(), tmp_path / "none.png", metrics=("safe_success_rate",))


def test_the_sweep_figure_shows_safe_success_and_contact_time_where_the_summary_records_them(tmp_path, monkeypatch):
    from attentive_gym.agents import plots
    from attentive_gym.agents.sweep import sweep_tables

    figures = []
    monkeypatch.setattr(plots, "_save", lambda fig, path, layout=True: figures.append(fig) or path)
    safe_rows = [{"num_distractors": n, **row} for n in (1, 3) for row in _safe_rows()]
    plots.plot_success_vs_distractors(sweep_tables(safe_rows), tmp_path / "safe.png")
    plots.plot_success_vs_distractors(sweep_tables(_sweep_rows()), tmp_path / "v0.png")
    safe, v0 = figures
    assert [ax.get_ylabel() for ax in safe.axes] == [
        "final success rate",
        "final safe success rate (≤ 1 s in contact)",
        "final contact time / episode (s)",
    ]
    assert safe.axes[1].get_ylim()[0] <= 0.0 and safe.axes[1].get_ylim()[1] >= 1.0
    assert [ax.get_ylabel() for ax in v0.axes] == ["final success rate"]
