"""Several lasers merged into the robot frame (``--laser-topic A,B``, ``--all-lasers``, one
``--laser-mount`` per laser) and the ``indoor-people`` laser profile. Bags are written
with rosbags' writers (helpers in ``test_rosbag`` and ``test_bag_mount``)."""

from __future__ import annotations

import numpy as np
import pytest

from attentive_gym.attention import AttentionConfig, load_trace
from attentive_gym.attention.config import LASER_PROFILES, profile_config
from attentive_gym.attention.io.ros_readings import LaserMount
from attentive_gym.attention.io.rosbag import BagTopics, open_bag, parse_bag_topics, parse_scan_options
from attentive_gym.attention.io.sensor_log import LogFormatError
from attentive_gym.cli import main
from support import load_test_module

_bags, _mount = load_test_module("attention/test_rosbag.py"), load_test_module("attention/test_bag_mount.py")
N_SCANS, SCAN_NS, T0_NS = _bags.N_SCANS, _bags.SCAN_NS, _bags.T0_NS
scan, write_bag = _bags.scan, _bags.write_bag
_framed, _quaternion, tf_message = _mount._framed, _mount._quaternion, _mount.tf_message

FRONT_MOUNT = LaserMount(0.2, 0.0, 0.0, False)
REAR_MOUNT = LaserMount(-0.3, 0.1, 180.0, False)
WALL_M = 10.0  # what the front laser sees on every beam
NO_ECHO = np.nan  # a scan beam without echo


def _rear_ranges(echo_m):
    """360 rear-laser beams (0.5 + j deg, laser frame) without echo but beam 179 (179.5°: after
    the laser's 180° yaw it points 0.5° right of the robot's heading, past the robot)."""
    ranges = np.full(360, NO_ECHO)
    ranges[179] = echo_m
    return ranges


def _rear_point(echo_m):
    """Where the rear laser's echo lies, as a bearing (deg) and range (m) from the front laser
    (to float32 rounding: the message stores its angles as float32)."""
    angle = np.radians(REAR_MOUNT.yaw_deg + 179.5)
    x = REAR_MOUNT.x_m + np.float32(echo_m) * np.cos(angle) - FRONT_MOUNT.x_m
    y = REAR_MOUNT.y_m + np.float32(echo_m) * np.sin(angle) - FRONT_MOUNT.y_m
    return np.degrees(np.arctan2(y, x)), np.hypot(x, y)


def _two_laser_messages(rear_offset_ns=0, rear_echo_m=lambda j: 3.0, with_tf=False):
    """Front scans (180 beams, 10 m) at T0 + k * 0.1 s and rear scans (360 beams over a full
    turn, one echo) from ``rear_offset_ns`` later, each in its own frame; TF mounts both."""
    full_turn = {"angle_min": np.radians(0.5), "increment": np.radians(1.0)}
    messages = []
    for k in range(N_SCANS):
        stamp = T0_NS + k * SCAN_NS
        messages.append(("/front/scan", _framed(scan(stamp, np.full(180, WALL_M)), "front_laser"), stamp))
        rear = stamp + rear_offset_ns
        messages.append(
            ("/rear/scan", _framed(scan(rear, _rear_ranges(rear_echo_m(k)), **full_turn), "rear_laser"), rear)
        )
    if with_tf:
        transforms = [
            ("base_link", frame, (m.x_m, m.y_m, 0.2), _quaternion(0.0, np.radians(m.yaw_deg)))
            for frame, m in (("front_laser", FRONT_MOUNT), ("rear_laser", REAR_MOUNT))
        ]
        messages.insert(0, ("/tf_static", tf_message(T0_NS, *transforms), T0_NS))
    return sorted(messages, key=lambda message: message[2])


def _flags():
    return parse_scan_options(["0.2,0,0", "-0.3,0.1,180"])


def test_a_second_laser_is_merged_seen_from_the_first_by_nearest_echo(tmp_path):
    bag = write_bag(tmp_path, "mcap", _two_laser_messages())
    replay = open_bag(bag, BagTopics(laser="/front/scan", more_lasers=("/rear/scan",)), options=_flags())
    bearing_deg, range_m = _rear_point(3.0)
    beam = int(np.floor(bearing_deg + 90.0))
    laser = replay.log.laser
    assert 0 <= beam < 180 and range_m < WALL_M
    np.testing.assert_allclose(laser[:, beam], range_m, rtol=1e-6)
    assert np.all(np.delete(laser, beam, axis=1) == WALL_M)  # the nearest echo elsewhere: the front's wall
    assert replay.mount == FRONT_MOUNT and replay.config.laser_mount_x_m == FRONT_MOUNT.x_m
    assert replay.mounts == (("/front/scan", FRONT_MOUNT), ("/rear/scan", REAR_MOUNT))
    assert "lasers /front/scan (6 scans, 10.0 Hz), the time base, merged with /rear/scan" in replay.notes[0]
    assert "laser mount of /rear/scan: x -0.3 m, y 0.1 m, yaw 180°, upright (--laser-mount)" in replay.notes
    # the raw scans: the front's 180 beams, then the rear's 360
    assert replay.raw.ranges_m.shape == (N_SCANS, 540)
    np.testing.assert_allclose(replay.raw.ranges_m[:, 180 + 179], np.float32(3.0))


def test_one_laser_alone_reads_as_before(tmp_path):
    bag = write_bag(tmp_path, "mcap", _two_laser_messages())
    alone = open_bag(bag, BagTopics(laser="/front/scan"), options=parse_scan_options("0.2,0,0"))
    assert np.all(alone.log.laser == WALL_M)
    assert alone.notes[1].startswith("laser mount: x 0.2 m")
    assert alone.raw.ranges_m.shape == (N_SCANS, 180)


def test_further_lasers_are_read_at_the_first_ones_scans_and_earlier_scans_dropped(tmp_path):
    # rear scans 0.15 s after the front's: front scans 0 and 1 come before the first rear scan
    bag = write_bag(tmp_path, "db3", _two_laser_messages(150_000_000, lambda j: 2.0 + 0.25 * j))
    replay = open_bag(bag, parse_bag_topics("/front/scan,/rear/scan"), options=_flags())
    assert len(replay.log.t) == N_SCANS - 2
    assert "dropped 2 scans before the first message of /rear/scan" in replay.notes[0]
    # front scan k (k >= 2) at 0.1 k s holds rear scan k - 2 (at 0.1 (k - 2) + 0.15 s)
    for step, k in enumerate(range(2, N_SCANS)):
        bearing_deg, range_m = _rear_point(2.0 + 0.25 * (k - 2))
        np.testing.assert_allclose(replay.log.laser[step, int(np.floor(bearing_deg + 90.0))], range_m, rtol=1e-6)


@pytest.mark.parametrize("fmt", ["ros1", "mcap"])
def test_each_lasers_mount_comes_from_tf_and_all_lasers_finds_them(tmp_path, fmt):
    flags = open_bag(
        write_bag(tmp_path, fmt, _two_laser_messages()), parse_bag_topics("/front/scan,/rear/scan"), options=_flags()
    )
    (tmp_path / "tf").mkdir()
    bag = write_bag(tmp_path / "tf", fmt, _two_laser_messages(with_tf=True))
    replay = open_bag(bag, parse_bag_topics(all_lasers=True))
    assert [topic for topic, _ in replay.mounts] == ["/front/scan", "/rear/scan"]
    for (_, found), (_, given) in zip(replay.mounts, flags.mounts):
        assert found.upside_down == given.upside_down
        np.testing.assert_allclose([found.x_m, found.y_m, found.yaw_deg], [given.x_m, given.y_m, given.yaw_deg])
    np.testing.assert_allclose(replay.log.laser, flags.log.laser, rtol=1e-9)
    assert "laser mount of /rear/scan: x -0.3 m, y 0.1 m, yaw 180°, upright (from TF rear_laser -> base_link)" in (
        replay.notes
    )


def test_a_further_laser_without_a_mount_or_with_mounts_miscounted_is_refused(tmp_path):
    bag = write_bag(tmp_path, "mcap", _two_laser_messages())
    topics = parse_bag_topics("/front/scan,/rear/scan")
    with pytest.raises(
        LogFormatError, match="no mount for the laser on /rear/scan: no TF leads from its frame rear_laser"
    ):
        open_bag(bag, topics)
    with pytest.raises(LogFormatError, match="3 --laser-mount values for 2 laser topics"):
        open_bag(bag, topics, options=parse_scan_options(["0.2,0,0", "-0.3,0,180", "0,0,90"]))
    with pytest.raises(LogFormatError, match="2 sensor_msgs/msg/LaserScan topics .*; choose one with --laser-topic, "):
        open_bag(bag)


def test_laser_topic_and_mount_flags_parse():
    topics = parse_bag_topics(" /front/scan, /rear/scan")
    assert topics.laser == "/front/scan" and topics.more_lasers == ("/rear/scan",)
    assert parse_bag_topics(all_lasers=True) == BagTopics(all_lasers=True)
    with pytest.raises(ValueError, match=r"laser topics \['/scan'\] named more than once"):
        parse_bag_topics("/scan,/scan")
    with pytest.raises(ValueError, match="--all-lasers takes every LaserScan topic"):
        parse_bag_topics("/scan", all_lasers=True)
    options = parse_scan_options(["0.2,0,0", "-0.3,0.1,180,upside-down"])
    assert options.mount_xy_yaw == (0.2, 0.0, 0.0) and options.upside_down is None
    assert options.more_mounts == (LaserMount(-0.3, 0.1, 180.0, True),)
    assert parse_scan_options("0,0,180,upside-down").upside_down is True
    with pytest.raises(ValueError, match="--laser-mount must be X,Y,YAW_DEG"):
        parse_scan_options("0,0,180,sideways")
    with pytest.raises(ValueError, match="X and Y must lie within"):
        parse_scan_options(["0,0,0", "9,0,0"])


def test_attend_merges_two_lasers_and_prints_each_mount(tmp_path, capsys):
    bag = write_bag(tmp_path, "mcap", _two_laser_messages())
    out = tmp_path / "out"
    flags = ["--laser-topic", "/front/scan,/rear/scan", "--laser-mount", "0.2,0,0", "--laser-mount=-0.3,0.1,180"]
    assert main(["attend", str(bag), "--out", str(out), "--no-figure", *flags]) == 0
    printed = capsys.readouterr().out
    assert "laser mount of /front/scan: x 0.2 m" in printed and "laser mount of /rear/scan: x -0.3 m" in printed
    trace = load_trace(out / "trace.npz")
    beam = int(np.floor(_rear_point(3.0)[0] + 90.0))
    np.testing.assert_allclose(trace.O2[:, beam], _rear_point(3.0)[1], rtol=1e-6)


def test_the_indoor_people_profile_sets_its_values_over_a_configuration():
    profile = LASER_PROFILES["indoor-people"]
    config = profile_config("indoor-people", AttentionConfig(threshold=0.2))
    assert {name: getattr(config, name) for name in profile} == dict(profile)
    assert config.threshold == 0.2  # the rest is the given configuration's
    assert profile_config("indoor-people").max_object_extent_m < AttentionConfig().max_object_extent_m
    with pytest.raises(ValueError, match="unknown laser profile 'outdoor'; known: indoor-people"):
        profile_config("outdoor")


def test_attend_takes_a_profile_with_config_fields_over_it(tmp_path):
    bag = write_bag(tmp_path, "mcap", _two_laser_messages())
    out = tmp_path / "out"
    flags = ["--laser-topic", "/front/scan", "--profile", "indoor-people", "--config", '{"range_noise_rel": 0.03}']
    assert main(["attend", str(bag), "--out", str(out), "--no-figure", *flags]) == 0
    config = load_trace(out / "trace.npz").config
    assert config["range_noise_rel"] == 0.03
    assert config["max_object_extent_m"] == LASER_PROFILES["indoor-people"]["max_object_extent_m"]
    assert config["track_accel_psd_m2ps3"] == LASER_PROFILES["indoor-people"]["track_accel_psd_m2ps3"]
