"""``benchmarks/bench_real_bags.py``'s driving-robot measure: the mean number per step of
confirmed tracks labelled moving (probability of moving over 0.5), on bags written with
rosbags' writers (helpers in ``tests/attention/test_rosbag.py``): about 0 for a static room
seen by a still robot, and above 0 where a body crosses it."""

from __future__ import annotations

import csv

import numpy as np
import pytest

from attentive_gym.attention.io.trace import Trace
from support import load_benchmark, load_test_module

bench = load_benchmark("bench_real_bags")
_bags = load_test_module("attention/test_rosbag.py")
SCAN_NS, T0_NS, scan, write_bag = _bags.SCAN_NS, _bags.T0_NS, _bags.scan, _bags.write_bag
HALF_DEGREE = np.radians(0.5)
BEARINGS = -np.pi / 2 + HALF_DEGREE * (np.arange(360) + 0.5)  # 360 beams over the front 180°
DIRECTIONS = np.stack([np.cos(BEARINGS), np.sin(BEARINGS)], axis=1)
RANGE_MAX_M = 5.6
WALL_M = 4.0
POSTS = ((2.0, 1.2, 0.1), (3.0, -1.0, 0.15))  # still round bodies: x, y, radius (m, laser frame)
N_SCANS = 80


def _ranges(bodies) -> np.ndarray:
    """``(360,)`` ranges (m) from the laser: a wall 4 m around, round ``bodies`` (x, y, radius) in front of it."""
    ranges = np.full(len(BEARINGS), WALL_M)
    for x, y, radius in bodies:
        centre = np.array([x, y])
        along = DIRECTIONS @ centre
        miss = radius**2 - (centre @ centre - along**2)
        hit = (miss >= 0.0) & (along > 0.0)
        ranges = np.where(hit, np.minimum(ranges, along - np.sqrt(np.maximum(miss, 0.0))), ranges)
    return ranges


def _bag(tmp_path, walker: bool):
    """8 s at 10 Hz of a still robot (no odometry) before two posts; with ``walker``, a body
    of 0.2 m radius 2.5 m ahead crossing from left to right at 1 m/s from 1 s to 6 s."""
    messages = []
    for k in range(N_SCANS):
        bodies = list(POSTS)
        if walker:
            bodies.append((2.5, float(np.clip(2.5 - 0.1 * (k - 10), -2.5, 2.5)), 0.2))
        stamp = T0_NS + k * SCAN_NS
        fields = {"angle_min": BEARINGS[0], "increment": HALF_DEGREE, "range_max": RANGE_MAX_M}
        messages.append(("/scan", scan(stamp, _ranges(bodies), **fields), stamp))
    folder = tmp_path / ("walker" if walker else "static")
    folder.mkdir()
    return write_bag(folder, "mcap", messages)


def test_moving_tracks_per_step_counts_confirmed_tracks_over_one_half():
    trace = Trace(
        **{name: np.zeros((4, *shape)) for name, shape in (("t", ()), ("O1", (8,)), ("O2", (180,)))},
        **{name: np.zeros((4, 8)) for name in ("C", "C_BU", "C_TD", "M", "L")},
        F=np.zeros((4, 6, 8)),
        focus=np.full(4, -1),
        fired=np.zeros(4, bool),
        origin=np.full(4, -1, np.int8),
        config={},
        track_step=np.array([0, 0, 1, 2, 2, 2]),
        track_moving_probability=np.array([0.9, 0.4, 0.51, 0.5, 0.99, 0.8]),
        track_confirmed=np.array([True, True, True, True, False, True]),
    )
    # moving: step 0's first, step 1's, step 2's last (0.5 is not over 0.5; unconfirmed don't count)
    assert bench.moving_tracks_per_step(trace) == pytest.approx(3 / 4)


def test_a_static_room_has_no_moving_tracks_and_a_crossing_body_has(tmp_path, capsys):
    static, _ = bench.measure_bag(_bag(tmp_path, walker=False), [])
    assert static.steps == N_SCANS and static.motion_steps == 0
    assert static.moving_tracks <= 0.05
    crossing, _ = bench.measure_bag(_bag(tmp_path, walker=True), [])
    assert crossing.moving_tracks >= 0.3  # the walker's track, moving over some of its 5 s of 8
    path = tmp_path / "figures.csv"
    bench.main([str(tmp_path / "walker" / "run_mcap"), "--csv", str(path)])
    printed = capsys.readouterr().out
    assert "| time-shuffled focus | moving tracks per step |" in printed
    row = next(row for row in csv.DictReader(path.open()) if row["metric"] == "moving_tracks_per_step")
    assert float(row["value"]) == pytest.approx(crossing.moving_tracks, rel=1e-5)
