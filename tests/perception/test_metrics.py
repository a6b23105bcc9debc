"""``attentive_gym.perception.metrics``: the metrics tell a corrupted estimate, a perfect focus
and a still robot apart, and select the (mover, step) pairs they claim to."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from attentive_gym.attention import Goal
from attentive_gym.perception import metrics
from attentive_gym.perception.geometry import in_sight, in_view, region_of
from attentive_gym.perception.records import TARGET_CASES, EpisodeRecord

GOAL = Goal.between("speed", 0.5, 0.9)


def test_metrics_are_finite_and_in_range(records):
    driving, _ = records
    figures = metrics.speed_metrics([driving])
    assert figures["region_pairs"] > 0 and figures["static_regions"] > 0
    for name in ("region_median_mps", "region_p90_mps", "region_rmse_mps", "static_median_mps", "static_p90_mps"):
        assert math.isfinite(figures[name]) and figures[name] >= 0.0, name
    assert figures["region_median_mps"] <= figures["region_p90_mps"]
    assert 0.0 <= figures["goal_agreement_region"] <= 1.0
    assert "track_pairs" not in figures and "false_label_steps" not in figures  # the window mode has no tracks
    for focus in metrics.focus_on_target([driving]).values():
        assert focus.steps > 0 and 0.0 <= focus.rate <= 1.0 and focus.episodes == 1


def test_a_corrupted_estimate_has_a_larger_error(records):
    driving, _ = records
    real = metrics.speed_metrics([driving])
    corrupted = metrics.speed_metrics([dataclasses.replace(driving, region_speed=driving.region_speed + 1.0)])
    assert corrupted["region_pairs"] == real["region_pairs"]
    assert corrupted["region_median_mps"] > real["region_median_mps"]
    assert corrupted["region_rmse_mps"] > real["region_rmse_mps"]
    assert corrupted["static_median_mps"] == pytest.approx(real["static_median_mps"] + 1.0)


def test_the_true_speed_as_estimate_has_no_error(records):
    driving, _ = records
    visible = in_view(driving.mover_xy)
    regions = region_of(driving.mover_xy)
    true_speed = np.linalg.norm(driving.mover_velocity, axis=-1)
    perfect = driving.region_speed.copy()
    steps, movers = np.nonzero(visible)
    perfect[steps, regions[steps, movers]] = true_speed[steps, movers]
    # two movers in one region cannot both be right: keep the pairs alone in their region
    crowded = np.array(
        [
            [np.sum(regions[k][visible[k]] == regions[k, m]) > 1 for m in range(visible.shape[1])]
            for k in range(visible.shape[0])
        ]
    )
    alone_xy = np.where(crowded[..., None], -1.0, driving.mover_xy)
    record = dataclasses.replace(driving, region_speed=perfect, mover_xy=alone_xy)
    figures = metrics.speed_metrics([record])
    assert figures["region_pairs"] > 0
    assert figures["region_rmse_mps"] == pytest.approx(0.0, abs=1e-12)
    assert figures["goal_agreement_region"] == 1.0


def test_a_focus_on_the_target_scores_one(records):
    driving, _ = records
    target_regions = region_of(driving.mover_xy[:, driving.target])
    rates = metrics.focus_on_target([dataclasses.replace(driving, focus=target_regions)])
    assert [focus.rate for focus in rates.values()] == [1.0]
    nowhere = metrics.focus_on_target([dataclasses.replace(driving, focus=np.full_like(driving.focus, -1))])
    assert [focus.rate for focus in nowhere.values()] == [0.0]


def test_focus_on_target_gives_an_interval_over_the_episodes(records):
    driving, still = records
    on = [
        dataclasses.replace(record, focus=region_of(record.mover_xy[:, record.target]))
        for record in (driving, dataclasses.replace(still, goal=driving.goal))
    ]
    off = dataclasses.replace(on[1], focus=np.full_like(on[1].focus, -1))
    [focus] = metrics.focus_on_target([on[0], off]).values()
    steps = [int(in_view(record.mover_xy[:, record.target]).sum()) for record in (on[0], off)]
    assert min(steps) > 0 and focus.episodes == 2 and focus.steps == sum(steps)
    assert focus.rate == pytest.approx(steps[0] / sum(steps))
    # one episode all on target, the other all off: resampled, the pair gives 0, the rate or 1
    assert (focus.low, focus.high) == (0.0, 1.0)
    [both_on] = metrics.focus_on_target(on).values()
    assert (both_on.rate, both_on.low, both_on.high) == (1.0, 1.0, 1.0)


def test_focus_on_target_in_sight_counts_only_the_steps_the_laser_sees_the_target_on(records):
    driving, _ = records
    target_xy = driving.mover_xy[:, driving.target]
    assert driving.target_beams is not None and driving.target_beams.shape == driving.t_s.shape
    visible = np.flatnonzero(in_view(target_xy))
    assert visible.size >= 2
    beams = np.zeros_like(driving.target_beams)
    beams[visible[::2]] = 3  # the laser sees the target at every other step in view
    on_target = np.where(np.arange(len(driving.t_s)) % 2 == visible[0] % 2, region_of(target_xy), -1)
    record = dataclasses.replace(driving, target_beams=beams, focus=on_target)
    [focus] = metrics.focus_on_target([record], in_sight_only=True).values()
    rate, steps = focus.rate, focus.steps
    sighted = np.flatnonzero(in_sight(target_xy, beams))
    assert steps == sighted.size > 0
    assert rate == pytest.approx(np.mean(on_target[sighted] == region_of(target_xy[sighted])))
    with pytest.raises(ValueError, match="target_beams"):
        metrics.focus_on_target([dataclasses.replace(driving, target_beams=None)], in_sight_only=True)


def test_still_robot_sees_static_structure_still(records):
    _, still = records
    figures = metrics.speed_metrics([still])
    assert figures["static_median_mps"] == pytest.approx(0.0, abs=1e-9)  # noise-free, walls do not move


def test_turns_and_view_time_select_pairs():
    steps = 80
    t_s = np.arange(1, steps + 1) * 0.05
    velocity = np.zeros((steps, 1, 2))
    velocity[:, 0] = (0.5, 0.0)
    velocity[40:, 0] = (0.0, 0.5)  # a 90° turn at step 40 (t = 2.05 s)
    xy = np.tile([[2.0, 0.0]], (steps, 1, 1))
    xy[:10] = (-2.0, 0.0)  # behind the robot until step 10 (in view from t = 0.55 s)
    record = EpisodeRecord(
        GOAL, 0, t_s, xy, velocity, np.zeros((steps, 8)), None, np.full(steps, -1), np.zeros((steps, 8), bool)
    )
    steady, transient = metrics.pair_masks(record)
    # settled from t = 1.55 s (step 30); transient until 1 s after the turn (step 60)
    assert np.flatnonzero(steady[:, 0]).tolist() == list(range(30, 40)) + list(range(61, steps))
    assert np.flatnonzero(transient[:, 0]).tolist() == list(range(40, 61))


def test_turns_are_direction_changes_above_the_threshold_and_starts_and_stops():
    speed = 0.5
    small, large = metrics.TURN_ANGLE_RAD - 0.05, metrics.TURN_ANGLE_RAD + 0.05
    headings = [0.0, 0.0, small, small + large]
    velocity = np.array(
        [[[speed * math.cos(h), speed * math.sin(h)]] for h in headings] + [[[0.0, 0.0]], [[0.0, 0.01]], [[0.3, 0.0]]]
    )  # stops, creeps (still), starts
    assert metrics.turns(velocity)[:, 0].tolist() == [False, False, False, True, True, False, True]


def test_time_since_counts_from_the_latest_event():
    t_s = np.array([0.0, 0.5, 1.0, 1.5])
    event = np.array([[False, True], [True, False], [False, False], [True, False]])
    since = metrics.time_since(t_s, event)
    assert since[:, 0].tolist() == [math.inf, 0.0, 0.5, 0.0]
    assert since[:, 1].tolist() == [0.0, 0.5, 1.0, 1.5]


def test_error_stats_of_known_errors_and_of_none():
    stats = metrics.error_stats(np.array([1.0, 2.0, 3.0, 4.0]), np.array([1.0, 1.0, 1.0, 1.0]))
    assert stats["pairs"] == 4 and stats["median_mps"] == 1.5
    assert stats["p90_mps"] == pytest.approx(2.7) and stats["rmse_mps"] == pytest.approx(math.sqrt(14 / 4))
    empty = metrics.error_stats(np.zeros(0), np.zeros(0))
    assert empty["pairs"] == 0 and all(math.isnan(empty[k]) for k in ("median_mps", "p90_mps", "rmse_mps"))


def test_region_estimates_read_the_region_each_mover_lies_in():
    xy = np.array([[[3.0, 0.1], [1.0, -3.0]]])  # region 3 (sonar at +10°), region 7 (sonar at −90°)
    region_speed = np.arange(8, dtype=float)[None, :] / 10
    assert region_of(xy).tolist() == [[3, 7]]
    record = EpisodeRecord(
        GOAL, 0, np.array([0.05]), xy, np.zeros((1, 2, 2)), region_speed, None, np.array([-1]), np.zeros((1, 8), bool)
    )
    np.testing.assert_array_equal(metrics.region_estimates(record), [[0.3, 0.7]])


def test_target_cases_of_a_tracker_episode_add_up_to_one(tracked_record):
    record = tracked_record
    cases = metrics.target_cases([record])
    assert list(cases) == [metrics.case_key(case) for case in TARGET_CASES]
    assert sum(cases.values()) == pytest.approx(1.0)
    visible = in_view(record.mover_xy[:, record.target])
    on_target = record.focus[visible] == region_of(record.mover_xy[visible, record.target])
    assert cases["case_on_target"] == pytest.approx(on_target.mean())
    assert math.isnan(metrics.target_cases([dataclasses.replace(record, target_case=None)])["case_on_target"])


def test_case_keys_are_identifiers():
    assert metrics.case_key("seen, no track") == "case_seen_no_track"
    assert all(metrics.case_key(case).isidentifier() for case in TARGET_CASES)


def test_focus_after_turns_splits_the_steps_at_the_target_s_turns():
    steps = 60
    t_s = np.arange(1, steps + 1) * 0.0625  # steps of 1/16 s: 1 s after a step is exactly a step
    velocity = np.zeros((steps, 1, 2))
    velocity[:, 0] = (0.5, 0.0)
    velocity[30:, 0] = (-0.5, 0.0)  # the target reverses at step 30
    xy = np.tile([[2.0, 0.0]], (steps, 1, 1))  # in view, region 3 or 4 (on the axis)
    region = int(region_of(xy[0, 0]))
    focus = np.full(steps, region)
    focus[30:47] = -1  # lost for the 17 steps within 1 s after the turn (its end included)
    record = EpisodeRecord(GOAL, 0, t_s, xy, velocity, np.zeros((steps, 8)), None, focus, np.zeros((steps, 8), bool))
    rates = metrics.focus_after_turns([record])
    assert rates == {"focus_on_target_after_turn": 0.0, "focus_on_target_otherwise": 1.0}


def test_focus_by_track_age_groups_the_steps_by_the_target_track_s_age():
    steps = 10
    xy = np.tile([[2.0, 0.0]], (steps, 1, 1))  # in view
    xy[9] = (-2.0, 0.0)  # behind the robot: not counted
    region = int(region_of(xy[0, 0]))
    age = np.array([np.nan, np.nan, 0.2, 0.9, 1.0, 1.5, 3.0, 4.0, 9.0, 9.0])
    focus = np.array([region, -1, -1, region, region, region, -1, region, region, -1])
    record = EpisodeRecord(
        GOAL,
        0,
        np.arange(1, steps + 1) * 0.05,
        xy,
        np.zeros((steps, 1, 2)),
        np.zeros((steps, 8)),
        None,
        focus,
        np.zeros((steps, 8), bool),
        target_track_age=age,
    )
    by_age = metrics.focus_by_track_age([record])
    assert by_age["focus_on_target_no_track"] == 0.5
    assert by_age["focus_on_target_track_0_to_1_s"] == 0.5
    assert by_age["focus_on_target_track_1_to_2_s"] == 1.0  # an age of exactly 1 s falls in the upper bin
    assert by_age["focus_on_target_track_2_to_4_s"] == 0.0
    assert by_age["focus_on_target_track_over_4_s"] == 1.0
    assert by_age["steps_no_track"] == pytest.approx(2 / 9)
    assert sum(v for k, v in by_age.items() if k.startswith("steps_")) == pytest.approx(1.0)
    assert metrics.focus_by_track_age([dataclasses.replace(record, target_track_age=None)]) == {}


def test_phantom_shares_count_the_steps_of_every_tracker_episode(tracked_record):
    figures = metrics.speed_metrics([tracked_record, tracked_record])
    anywhere, near, in_band = tracked_record.false_label.mean(axis=0)
    assert figures["false_label_steps"] == pytest.approx(anywhere)
    assert figures["false_label_near_steps"] == pytest.approx(near)
    assert figures["false_in_band_steps"] == pytest.approx(in_band)
    assert 0.0 <= figures["false_label_near_steps"] <= figures["false_label_steps"] <= 1.0
    # two copies of one episode agree: the interval over the episodes has no width
    assert figures["false_label_steps_low"] == figures["false_label_steps_high"] == pytest.approx(anywhere)
    # an episode free of phantoms beside one full of them: the interval spans both
    clean = dataclasses.replace(tracked_record, false_label=np.zeros_like(tracked_record.false_label))
    full = dataclasses.replace(tracked_record, false_label=np.ones_like(tracked_record.false_label))
    mixed = metrics.speed_metrics([clean, full])
    assert (mixed["false_label_steps"], mixed["false_label_steps_low"], mixed["false_label_steps_high"]) == (
        0.5,
        0.0,
        1.0,
    )
