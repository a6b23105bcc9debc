"""``benchmarks/bench_real_bags.py``: moving beams from the raw scans alone, the regions that
hold motion, the focus's agreement against chance and a time-shuffled focus, on a bag with a
synthetic walker written with rosbags' writers (helpers in ``test_rosbag``) and on the real
bag in ``tests/data``."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest

from attentive_gym.attention.io.rosbag import RawScans
from support import load_benchmark, load_test_module

bench = load_benchmark("bench_real_bags")
REAL_BAG = Path(__file__).resolve().parents[1] / "data" / "leg_tracker_demo_stationary_simple.bag"


_bags = load_test_module("attention/test_rosbag.py")
SCAN_NS, T0_NS, scan, write_bag = _bags.SCAN_NS, _bags.T0_NS, _bags.scan, _bags.write_bag
HALF_DEGREE = np.radians(0.5)
BEARINGS = -np.pi / 2 + HALF_DEGREE * (np.arange(360) + 0.5)  # 360 beams over the front 180°
RANGE_MAX_M = 5.6
WALL_M = 4.0
WALKER_RADIUS_M = 0.2


def _walker_ranges(centre_xy) -> np.ndarray:
    """``(360,)`` ranges (m) from the laser: a wall 4 m around, a round walker at ``centre_xy``
    (m, laser frame) in front of it."""
    directions = np.stack([np.cos(BEARINGS), np.sin(BEARINGS)], axis=1)
    along = directions @ np.asarray(centre_xy)
    miss = WALKER_RADIUS_M**2 - (np.dot(centre_xy, centre_xy) - along**2)
    hit = (miss >= 0.0) & (along > 0.0)
    return np.where(hit, along - np.sqrt(np.maximum(miss, 0.0)), WALL_M)


def _walker_bag(tmp_path):
    """8 s at 10 Hz: a walker 2.5 m ahead standing 1 s on the left, crossing to the right
    at 1 m/s over 5 s, standing 2 s (a 5.6 m laser, no odometry)."""
    messages = []
    for k in range(80):
        y = float(np.clip(2.5 - 0.1 * (k - 10), -2.5, 2.5))
        stamp = T0_NS + k * SCAN_NS
        ranges = _walker_ranges((2.5, y))
        fields = {"angle_min": BEARINGS[0], "increment": HALF_DEGREE, "range_max": RANGE_MAX_M}
        messages.append(("/scan", scan(stamp, ranges, **fields), stamp))
    return write_bag(tmp_path, "mcap", messages)


def test_a_beam_moves_when_it_changes_in_front_of_its_background():
    t = 0.1 * np.arange(100)
    ranges = np.full((100, 6), 4.0)
    ranges[50:53, 0] = (
        2.0  # something comes in front for 0.3 s: moves at 50 and 51 (changed within 0.2 s), stands at 52
    )
    ranges[50, 1] = 5.0  # behind its background: never moving
    ranges[:, 2] = 5.6  # open space (no echo) ...
    ranges[50, 2] = 3.0  # ... that something crosses
    ranges[:, 3] += 0.01 * (np.arange(100) % 2)  # noise within 3 cm: no motion
    ranges[:, 4] = np.where(np.arange(100) % 3 == 0, 4.64, 5.6)  # a far wall flickering in and out of detection
    ranges[:, 5] = np.where(np.arange(100) % 4 == 0, 3.4, 4.4)  # an edge between two surfaces
    ranges[[20, 60], 5] = (1.5, 2.5)  # crossed at two ranges
    moving = bench.moving_beams(RawScans(np.zeros(6), ranges), t)
    np.testing.assert_array_equal(np.flatnonzero(moving[:, 0]), [50, 51])
    np.testing.assert_array_equal(np.flatnonzero(moving[:, 2]), [50])
    np.testing.assert_array_equal(np.flatnonzero(moving[:, 5]), [20, 60])
    assert not moving[:, [1, 3, 4]].any()


def test_a_region_holds_motion_with_three_moving_beams():
    bearings = np.radians([80.0, 81.0, 82.0, 85.0, -80.0, -81.0, 100.0, 101.0, 102.0])
    moving = np.array([[True, True, True, False, True, True, True, True, True], [True, True, False] + [False] * 6])
    motion = bench.regions_with_motion(moving, bearings, 8)
    np.testing.assert_array_equal(motion[0], [True] + [False] * 7)  # s1; s8 has 2, beams behind count for none
    assert not motion[1].any()


def test_agreement_against_chance_and_a_shuffled_focus():
    motion = np.zeros((4, 8), dtype=bool)
    motion[0, 0] = motion[1, [0, 1]] = motion[2, 7] = True  # step 3 without motion
    figures = bench.agreement(np.array([0, 5, 7, 0]), motion)
    assert (figures.steps, figures.motion_steps) == (4, 3)
    assert figures.focus_on_motion == pytest.approx(2 / 3)  # steps 0 and 2
    assert figures.chance == pytest.approx((1 + 2 + 1) / 24)
    assert figures.shuffled == pytest.approx(1 / 3)  # rolled by 2: [7, 0, 0, 5]: step 1 only


def test_the_focus_follows_a_synthetic_walker_beyond_chance(tmp_path, capsys):
    bag = _walker_bag(tmp_path)
    figures, notes = bench.measure_bag(bag, [])
    assert "laser range: 5.6 m (the scans' range_max): no echo reads 5.6 m, not the configuration's 20 m" in notes
    assert 40 <= figures.motion_steps <= 55  # the crossing, 5 s at 10 Hz
    assert figures.focus_on_motion >= 0.8
    assert figures.focus_on_motion > figures.chance + 0.5 and figures.focus_on_motion > figures.shuffled + 0.3
    path = tmp_path / "figures.csv"
    bench.main([str(bag), "--goal", "speed:between:0.5:1.5", "--csv", str(path)])
    printed = capsys.readouterr().out
    assert "| bag | setting | goal | steps | steps with motion | focus on a region with motion |" in printed
    assert "| run_mcap | defaults | speed:between:0.5:1.5 | 80 |" in printed
    rows = list(csv.DictReader(path.open()))
    assert [row["metric"] for row in rows] == list(figures.metrics())
    assert {(row["bag"], row["setting"], row["goal"]) for row in rows} == {
        ("run_mcap", "defaults", "speed:between:0.5:1.5")
    }
    bench.main([str(bag), "--profile", "indoor-people", "--config", '{"threshold": 0.05}', "--csv", str(path)])
    assert '| run_mcap | indoor-people, config {"threshold": 0.05} | bottom-up | 80 |' in capsys.readouterr().out
    bench.main([str(bag), "--config", '{"threshold": 0.05}', "--label", "low threshold", "--csv", str(path)])
    assert {row["setting"] for row in csv.DictReader(path.open())} == {"low threshold"}
    with pytest.raises(SystemExit):
        bench.main([str(bag), "--config", '{"thresh": 0.05}'])
    assert "--config: unknown AttentionConfig field(s) ['thresh']" in capsys.readouterr().err


def test_on_the_real_bag_the_focus_beats_chance_and_a_shuffled_focus():
    figures, notes = bench.measure_bag(REAL_BAG, [])
    assert figures.steps == 1265 and figures.motion_steps > 1000
    assert "laser: 512 beams over 180° (1265 scans)" in notes[2]
    assert figures.focus_on_motion > 0.7 > 0.5 > figures.shuffled > figures.chance
