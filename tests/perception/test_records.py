"""``attentive_gym.perception.records``: an episode's truth and the model's outputs, step by step."""

from __future__ import annotations

import doctest
import math
from types import SimpleNamespace

import numpy as np
import pytest

import attentive_gym.perception as perception
from attentive_gym.perception import records
from attentive_gym.perception.geometry import GRID, region_of
from attentive_gym.perception.records import TARGET_CASES, TRACK_MATCH_M, target_case


def test_a_recorded_episode_has_one_row_per_step_in_the_robot_frame(records, attended_env):
    driving, still = records
    for record in (driving, still):
        steps, movers = record.mover_xy.shape[:2]
        assert record.t_s.shape == (steps,) and np.all(np.diff(record.t_s) > 0)
        assert record.t_s[-1] == pytest.approx(2.0) and movers == 4  # the target and 3 distractors
        assert record.mover_velocity.shape == (steps, movers, 2)
        assert record.region_speed.shape == record.static_region.shape == (steps, GRID.n_regions)
        assert record.focus.shape == (steps,) and set(record.focus) <= set(range(-1, GRID.n_regions))
        assert record.track_speed is record.target_case is record.target_track_age is None  # window: no tracks
    assert not np.array_equal(driving.mover_xy, still.mover_xy)  # the driving robot sees the movers move about
    env = attended_env("window")
    obs, info = env.reset(seed=0, options={"goal": driving.goal})
    assert driving.target == info["target_index"]


def test_a_tracker_episode_records_tracks_cases_and_ages(tracked_record):
    record = tracked_record
    steps = len(record.t_s)
    assert record.track_speed.shape == record.mover_xy.shape[:2]
    assert record.target_case.shape == record.target_track_age.shape == (steps,)
    assert set(record.target_case) <= set(range(len(TARGET_CASES)))
    matched = ~np.isnan(record.track_speed)
    assert matched.any() and np.all(record.track_speed[matched] >= 0.0)
    aged = ~np.isnan(record.target_track_age)
    assert aged.any() and np.all(np.diff(record.target_track_age[aged]) >= -1e-9)  # one track, growing older


def test_record_episode_needs_a_positive_length(attended_env):
    with pytest.raises(ValueError, match="seconds .* must be > 0, got 0.0"):
        records.record_episode(attended_env("window"), 0, None, perception.stand_still, 0.0)


def test_static_regions_see_echoes_from_structure_only():
    laser = np.full(180, -1)
    sonar = np.full(16, -1)
    beams = GRID.beam_indices
    laser[beams[0]] = 7  # region 0: a wall
    laser[beams[1][:3]] = 7
    laser[beams[1][3]] = 42  # region 1: a wall and a mover
    sonar[GRID.region_sonar[2]] = 7  # region 2: the wall on its sonar only
    sonar[GRID.region_sonar[3]] = 43  # region 3: a mover on its sonar
    static = records.static_regions(laser, sonar, np.array([42, 43]))
    assert static.tolist() == [True, False, True, False, False, False, False, False]


def _tracks(xy, confirmed=None, speed=None, age=None, moving=None):
    xy = np.array(xy, float).reshape(-1, 2)
    n = len(xy)
    return SimpleNamespace(
        position_m=xy,
        confirmed=np.ones(n, bool) if confirmed is None else np.array(confirmed),
        speed_mps=np.arange(n, dtype=float) if speed is None else np.array(speed),
        age_s=np.full(n, 2.0) if age is None else np.array(age),
        moving_probability=np.full(n, 0.9) if moving is None else np.array(moving, float),
    )


def test_phantom_motion_is_a_confirmed_moving_track_on_no_mover():
    far = 1.0 + records.FALSE_LABEL_M + 0.01
    tracks = _tracks(
        [[1.0, 0.0], [1.0, far], [1.0, -far], [6.0, 0.0], [1.0, 1.2]],
        confirmed=[True, True, False, True, True],
        moving=[0.9, 0.9, 0.9, 0.4, 0.9],
    )
    movers = np.array([[1.0, 0.0], [1.0, 6.0]])
    # on a mover; moving, far from both; unconfirmed; standing; within FALSE_LABEL_M of the first mover
    assert records.false_moving_tracks(tracks, movers).tolist() == [False, True, False, False, False]
    assert records.false_moving_tracks(tracks, np.zeros((0, 2))).tolist() == [True, True, False, False, True]


def test_a_tracker_episode_records_its_phantoms_and_a_window_episode_none(tracked_record, records):
    assert tracked_record.false_label.shape == (len(tracked_record.t_s), 3)
    anywhere, near, in_band = tracked_record.false_label.T
    assert not np.any(near & ~anywhere) and not np.any(in_band & ~anywhere)
    for record in records:  # window mode: no tracks, no phantoms
        assert record.false_label.shape == (len(record.t_s), 3) and not record.false_label.any()


def test_movers_match_the_nearest_confirmed_track_within_reach():
    tracks = _tracks([[2.0, 0.0], [2.2, 0.0], [5.0, 5.0]], confirmed=[False, True, True], speed=[9.0, 0.4, 0.8])
    movers = np.array([[2.0, 0.0], [5.0, 5.0 + TRACK_MATCH_M + 0.01], [5.0, 5.5]])
    assert records.nearest_tracks(tracks, movers).tolist() == [1, -1, 2]  # not the unconfirmed one
    speeds = records.matched_track_speeds(tracks, movers)
    assert speeds[0] == 0.4 and math.isnan(speeds[1]) and speeds[2] == 0.8
    assert records.nearest_track(tracks, movers[1]) is None and records.nearest_track(tracks, movers[0]) == 1
    assert records.nearest_tracks(_tracks(np.zeros((0, 2))), movers).tolist() == [-1, -1, -1]


def _output(focus, fulfilled_region=None, inhibited=False, track_xy=None, track_age_s=2.0):
    """A stand-in for an ``AttentionOutput`` with one confirmed track at ``track_xy`` (none if None)."""
    tracks = _tracks(
        np.zeros((0, 2)) if track_xy is None else [track_xy], age=None if track_xy is None else [track_age_s]
    )
    fulfilled = np.zeros(8, bool)
    if fulfilled_region is not None:
        fulfilled[fulfilled_region] = True
    M = np.ones(8)
    if inhibited:
        M[fulfilled_region] = 0.5
    return SimpleNamespace(focus=focus, tracks=tracks, goal_fulfilled=fulfilled, M=M)


def test_target_cases_tell_perception_from_selection():
    target = np.array([3.0, 0.1])  # region 3 (s4), 3 m ahead
    assert int(region_of(target)) == 3
    case = TARGET_CASES.index
    assert target_case(_output(3), target, 5) == case("on target")
    assert target_case(_output(1), target, 0) == case("hidden from the laser")
    assert target_case(_output(1), target, 5) == case("seen, no track")
    assert target_case(_output(1, track_xy=(3.0, 1.0)), target, 5) == case("seen, no track")  # 0.9 m off
    assert target_case(_output(1, track_xy=(3.1, 0.1), track_age_s=0.5), target, 5) == case(
        "young track, goal not judged"
    )
    assert target_case(_output(1, track_xy=(3.1, 0.1)), target, 5) == case("track, goal not judged")
    assert target_case(_output(None, 3, track_xy=(3.1, 0.1)), target, 5) == case("no focus")
    assert target_case(_output(1, 3, inhibited=True, track_xy=(3.1, 0.1)), target, 5) == case("inhibited")
    assert target_case(_output(1, 3, track_xy=(3.1, 0.1)), target, 5) == case("another region won")


def test_the_package_exports_what_it_lists_and_its_example_runs():
    for name in perception.__all__:
        assert getattr(perception, name) is not None, name
    result = doctest.testmod(perception)
    assert result.attempted >= 5 and result.failed == 0
