"""A bag's masks and what ``attend`` says: ``--min-range``, ``--mask-angles``, self-returns,
the summary line, a bag without odometry, bad flags and the compile notice. Bags are
written with rosbags' writers (helpers in ``test_rosbag``)."""

from __future__ import annotations

import numba
import numpy as np
import pytest

from attentive_gym import _kernel_cache
from attentive_gym.attention.io.rosbag import ScanOptions, open_bag, parse_scan_options
from attentive_gym.cli import main
from support import load_test_module

_bags = load_test_module("attention/test_rosbag.py")
NO_LASER, SCAN_NS, T0_NS = _bags.NO_LASER, _bags.SCAN_NS, _bags.T0_NS
scan, write_bag = _bags.scan, _bags.write_bag
N_LONG = 25  # scans: enough to tell the robot's own structure (SELF_RETURN_MIN_SCANS) from a still object


def _scans(ranges_of_step, n=N_LONG, **fields):
    return [("/scan", scan(T0_NS + k * SCAN_NS, ranges_of_step(k), **fields), T0_NS + k * SCAN_NS) for k in range(n)]


def _with_posts(k):
    """Walls at 4 m; posts at 0.15 m (±1 cm, beams 20-22 and 150-151: -69.5..-67.5° and 60.5..61.5°);
    beam 100 near but moving (0.2-0.4 m): not a post."""
    ranges = np.full(180, 4.0)
    ranges[20:23] = 0.15 + 0.01 * (k % 3 - 1)
    ranges[150:152] = 0.16
    ranges[100] = 0.2 + 0.2 * (k % 2)
    return ranges


def test_min_range_and_angle_masks_hide_beams(tmp_path):
    ranges = np.full(180, 4.0)
    ranges[10] = 0.3  # -79.5 deg
    bag = write_bag(tmp_path, "mcap", _scans(lambda k: ranges, n=3))
    laser = open_bag(bag, options=parse_scan_options(min_range="0.35", mask_angles="-10:-5.2,30:40")).log.laser[0]
    expected = ranges.copy()
    expected[10] = NO_LASER  # nearer than --min-range
    expected[80:85] = NO_LASER  # beams at -9.5 .. -5.5 deg (-5.5 lies inside; -4.5 does not)
    expected[120:130] = NO_LASER  # 30.5 .. 39.5 deg
    np.testing.assert_array_equal(laser, expected)


def test_angle_masks_are_in_the_robot_frame(tmp_path):
    bag = write_bag(tmp_path, "db3", _scans(lambda k: 1.0 + np.arange(180) / 64.0, n=3))
    # a laser yawed 90 deg: laser beam k (-89.5 + k deg) points at 0.5 + k deg, model beam 90 + k;
    # the mask's 0..45 deg are laser beams 0..44 (laser -89.5..-45.5 deg)
    options = parse_scan_options("0,0,90", mask_angles="0:45")
    laser = open_bag(bag, options=options).log.laser[0]
    assert np.all(laser[90:135] == NO_LASER)
    np.testing.assert_array_equal(laser[135:], 1.0 + np.arange(45, 90) / 64.0)


def test_constant_near_returns_are_found_reported_and_masked(tmp_path):
    bag = write_bag(tmp_path, "ros1", _scans(_with_posts))
    replay = open_bag(bag)
    posts = [20, 21, 22, 150, 151]
    assert np.all(replay.log.laser[:, posts] == NO_LASER)
    expected = np.float32([0.2 + 0.2 * (k % 2) for k in range(N_LONG)])  # as the message holds them
    np.testing.assert_array_equal(replay.log.laser[:, 100], expected)
    line = (
        "self-returns: 5 scan beams at -69.5..-67.5°, 60.5..61.5° (robot frame) hold a constant 0.14-0.16 m echo "
        f"through all {N_LONG} scans, the robot's own structure: masked as no echo (--keep-self-returns keeps them)"
    )
    assert line in replay.notes
    kept = open_bag(bag, options=ScanOptions(keep_self_returns=True))
    assert np.all(kept.log.laser[:, posts] < 0.2)
    assert not any(note.startswith("self-returns") for note in kept.notes)


def test_a_short_bag_masks_no_self_returns(tmp_path):
    replay = open_bag(write_bag(tmp_path, "mcap", _scans(_with_posts, n=19)))
    assert np.all(replay.log.laser[:, 20:23] < 0.2)


def test_the_summary_names_topics_rates_and_dropped_scans(tmp_path):
    messages, _ = _bags.ring_bag_messages()
    replay = open_bag(write_bag(tmp_path, "db3", messages))
    assert replay.notes[0] == (
        "used: laser /scan (6 scans, 10.0 Hz), odometry /odom (20.0 Hz), 16 sonar topics (10.0 Hz); "
        "5 steps over 0.4 s; dropped 1 scan before the first message of /odom"
    )
    assert replay.notes[1] == (
        "laser mount: x 0.16 m, y 0 m, yaw 0°, upright (the configuration's, "
        "as no TF in the bag leads from the laser's frame to a base frame)"
    )
    assert replay.notes[2] == (
        "laser: 180 beams over 180° (6 scans), covering 180 of the model's 180 front beams (-90..90°, robot frame)"
    )
    assert len(replay.notes) == 3  # odometry: nothing to say


def test_without_odometry_a_standing_robot_is_assumed_and_a_moving_one_is_noticed(tmp_path):
    (tmp_path / "still").mkdir()
    people = write_bag(tmp_path / "still", "mcap", _scans(lambda k: np.where(np.arange(180) == k, 1.0, 4.0)))
    notes = open_bag(people).notes
    assert "front sonars read from the laser" in notes[0] and "no odometry" in notes[0]
    assert notes[-1].startswith("no odometry (no nav_msgs/Odometry topic, no TF odom -> base): a standing robot")
    (tmp_path / "moving").mkdir()
    driving = write_bag(tmp_path / "moving", "mcap", _scans(lambda k: np.full(180, 4.0 - 0.05 * k)))
    assert open_bag(driving).notes[-1] == (
        "the robot seems to move: most beams change together in 100% of the scans (over 1 s); "
        "its motion will read as the world's (give the bag's odometry with --odom-topic)"
    )


@pytest.mark.parametrize(
    "flags, message",
    [
        (["--laser-mount", "0.2,0"], "--laser-mount must be X,Y,YAW_DEG: the laser's position (m, robot frame)"),
        (["--laser-mount", "0.2,0,left"], "--laser-mount must be X,Y,YAW_DEG"),
        (["--laser-mount", "9,0,0"], "--laser-mount X and Y must lie within ±5 m of the robot's centre"),
        (["--mask-angles", "10:5"], "--mask-angles must be A:B[,C:D...] in degrees, robot frame"),
        (["--mask-angles", "10"], "-180 <= A < B <= 180, e.g. 120:180,-180:-120; got 10"),
        (["--min-range", "-0.1"], "--min-range must be a finite distance >= 0 (m), got -0.1"),
        (["--min-range", "near"], "--min-range must be a distance (m); got near"),
    ],
)
def test_bad_flags_exit_2_with_one_line_before_writing(tmp_path, capsys, flags, message):
    bag = write_bag(tmp_path, "mcap", _scans(lambda k: np.full(180, 4.0), n=3))
    out = tmp_path / "out"
    assert main(["attend", str(bag), "--out", str(out), *flags]) == 2
    err = capsys.readouterr().err
    assert err.startswith("attentive-gym attend: error: ") and message in err and err.count("\n") == 1
    assert not out.exists()


def test_mount_and_mask_flags_refuse_a_csv_log(tmp_path, capsys):
    log = tmp_path / "log.csv"
    log.write_text("t\n")
    assert main(["attend", str(log), "--out", str(tmp_path / "out"), "--min-range", "0.2"]) == 2
    assert "apply to ROS bags only" in capsys.readouterr().err


def test_attend_prints_the_bags_notes(tmp_path, capsys):
    bag = write_bag(tmp_path, "ros1", _scans(_with_posts))
    assert main(["attend", str(bag), "--out", str(tmp_path / "out"), "--no-figure"]) == 0
    printed = capsys.readouterr().out.splitlines()
    assert printed[0].startswith(f"used: laser /scan ({N_LONG} scans, 10.0 Hz), no odometry")
    assert printed[1].startswith("laser mount: x 0.16 m")
    assert any(line.startswith("self-returns: 5 scan beams") for line in printed)
    assert any(line.startswith("no odometry") for line in printed)


def test_a_kernel_compiled_on_a_cold_cache_prints_one_notice(capsys, monkeypatch):
    monkeypatch.setattr(_kernel_cache, "_announced", False)  # as in a fresh process
    _kernel_cache.announce_compilation()
    _kernel_cache.announce_compilation()  # installed once

    @numba.njit  # not cached: compiled here
    def twice(x):
        return 2 * x

    assert twice(2) == 4 and twice(2.5) == 5.0  # two compilations
    assert capsys.readouterr().err == _kernel_cache.COMPILE_NOTICE + "\n"


def test_every_command_installs_the_compile_notice(tmp_path, monkeypatch):
    installed = []
    monkeypatch.setattr("attentive_gym.cli.announce_compilation", lambda: installed.append(True))
    main(["attend", str(tmp_path / "missing.bag"), "--out", str(tmp_path / "out")])
    assert installed == [True]
