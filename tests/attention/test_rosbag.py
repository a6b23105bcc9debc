"""ROS bags as logs: ``attentive_gym.attention.io.rosbag`` and ``attentive-gym attend BAG``.

Every bag is written here with rosbags' own writers: ROS 1 ``.bag``, ROS 2 sqlite3
``.db3`` and ROS 2 ``.mcap``, a few dozen messages each.
"""

from __future__ import annotations

import re
import shutil
import struct
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from rosbags.rosbag1 import Writer as Ros1Writer
from rosbags.rosbag2 import CompressionFormat, CompressionMode, StoragePlugin
from rosbags.rosbag2 import Writer as Ros2Writer
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

from attentive_gym.attention import AttentionConfig, load_log, load_trace
from attentive_gym.attention.io.replay import LogFormatError
from attentive_gym.attention.io.ros_readings import ScanResampler, front_sonar_slot, ranges_or_no_echo
from attentive_gym.attention.io.rosbag import BagTopics, parse_bag_topics, read_bag
from attentive_gym.attention.regions import sonar_cone_bounds
from attentive_gym.cli import main

REPO = Path(__file__).resolve().parents[2]
ROS2 = get_typestore(Stores.ROS2_HUMBLE)
ROS1 = get_typestore(Stores.ROS1_NOETIC)
ROS1.register(get_types_from_msg("geometry_msgs/TransformStamped[] transforms", "tf2_msgs/msg/TFMessage"))
LASER, RANGE, ODOM = "sensor_msgs/msg/LaserScan", "sensor_msgs/msg/Range", "nav_msgs/msg/Odometry"
STRING = "std_msgs/msg/String"
T0_NS = 1_700_000_000_000_000_000  # stamps near a real epoch time
SCAN_NS = 100_000_000  # 10 Hz scans
N_SCANS = 6
STORAGE_PLUGINS = {"db3": StoragePlugin.SQLITE3, "mcap": StoragePlugin.MCAP}
CFG = AttentionConfig()
NO_LASER, NO_SONAR = CFG.laser_max_range_m, CFG.sonar_max_range_m


# --- messages -------------------------------------------------------------------------


def _header(stamp_ns: int):
    stamp = ROS2.types["builtin_interfaces/msg/Time"](sec=stamp_ns // 10**9, nanosec=stamp_ns % 10**9)
    return ROS2.types["std_msgs/msg/Header"](stamp=stamp, frame_id="base_link")


ONE_DEGREE_RAD = np.pi / 180.0


def scan(
    stamp_ns,
    ranges,
    angle_min=-np.pi / 2 + 0.5 * ONE_DEGREE_RAD,
    increment=ONE_DEGREE_RAD,
    range_min=0.05,
    range_max=30.0,
):
    ranges = np.asarray(ranges, dtype=np.float32)
    return ROS2.types[LASER](
        header=_header(stamp_ns),
        angle_min=angle_min,
        angle_max=angle_min + (len(ranges) - 1) * increment,
        angle_increment=increment,
        time_increment=0.0,
        scan_time=0.1,
        range_min=range_min,
        range_max=range_max,
        ranges=ranges,
        intensities=np.zeros(0, np.float32),
    )


def sonar(stamp_ns, value, min_range=0.1, max_range=6.0):
    return ROS2.types[RANGE](
        header=_header(stamp_ns),
        radiation_type=0,
        field_of_view=0.5,
        min_range=min_range,
        max_range=max_range,
        range=value,
    )


def odom(stamp_ns, v, w):
    t = ROS2.types
    pose = t["geometry_msgs/msg/PoseWithCovariance"](
        pose=t["geometry_msgs/msg/Pose"](
            position=t["geometry_msgs/msg/Point"](x=0.0, y=0.0, z=0.0),
            orientation=t["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0),
        ),
        covariance=np.zeros(36),
    )
    twist = t["geometry_msgs/msg/TwistWithCovariance"](
        twist=t["geometry_msgs/msg/Twist"](
            linear=t["geometry_msgs/msg/Vector3"](x=v, y=0.0, z=0.0),
            angular=t["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=w),
        ),
        covariance=np.zeros(36),
    )
    return t[ODOM](header=_header(stamp_ns), child_frame_id="base_link", pose=pose, twist=twist)


def chatter():
    return ROS2.types[STRING](data="hello")


# --- bags -----------------------------------------------------------------------------


def write_bag(tmp_path, fmt, messages, topics=None, compressed=False):
    """A bag of ``messages`` ``(topic, message, receive_ns)``; returns the path to open.

    ``fmt``: "ros1" (``run.bag``), "db3" / "mcap" (a ROS 2 bag folder), "db3-file" /
    "mcap-file" (the storage file alone, moved out of its folder). ``topics`` declares
    ``{name: msgtype}`` connections beyond those of the messages (empty topics);
    ``compressed``: ROS 2 messages compressed one by one with zstd.
    """
    declared = dict(topics or {})
    for topic, message, _ in messages:
        declared.setdefault(topic, message.__msgtype__)
    if fmt == "ros1":
        path = tmp_path / "run.bag"
        with Ros1Writer(path) as writer:
            connections = {name: writer.add_connection(name, kind, typestore=ROS1) for name, kind in declared.items()}
            for topic, message, receive_ns in messages:
                kind = message.__msgtype__
                writer.write(connections[topic], receive_ns, ROS2.cdr_to_ros1(ROS2.serialize_cdr(message, kind), kind))
        return path
    storage, _, alone = fmt.partition("-")
    folder = tmp_path / f"run_{storage}"
    writer = Ros2Writer(folder, version=9, storage_plugin=STORAGE_PLUGINS[storage])
    if compressed:
        writer.set_compression(CompressionMode.MESSAGE, CompressionFormat.ZSTD)
    with writer:
        connections = {name: writer.add_connection(name, kind, typestore=ROS2) for name, kind in declared.items()}
        for topic, message, receive_ns in messages:
            writer.write(connections[topic], receive_ns, ROS2.serialize_cdr(message, message.__msgtype__))
    if not alone:
        return folder
    return shutil.move(folder / f"{folder.name}.{storage}", tmp_path / f"alone.{storage}")


def ring_bag_messages():
    """6 scans at 10 Hz, 16 sonars (``/sonar_0`` .. ``/sonar_15``) stamped as the scans,
    odometry at 20 Hz from 10 ms after the first scan (so the first scan is dropped).

    Returns ``(messages, expected)``: ``expected`` holds the readings of the 5 kept steps.
    """
    messages, laser_rows = [], []
    for k in range(N_SCANS):
        stamp = T0_NS + k * SCAN_NS
        ranges = 2.0 + 0.25 * k + np.arange(180) / 64.0  # exact in float32
        laser_rows.append(ranges)
        messages.append(("/scan", scan(stamp, ranges), stamp + 1000))
        for n in range(16):
            messages.append((f"/sonar_{n}", sonar(stamp, 1.0 + 0.125 * n + 0.0625 * k), stamp))
    for j in range(2 * N_SCANS):
        stamp = T0_NS + 10_000_000 + j * SCAN_NS // 2
        messages.append(("/odom", odom(stamp, 0.1 * j, -0.01 * j), stamp))
    kept = np.arange(1, N_SCANS)
    expected = {
        "t": (kept - 1) * 0.1,
        "laser": np.asarray(laser_rows)[kept],
        # a sample at a scan's stamp is read at that scan
        "sonar": 1.0 + 0.125 * np.arange(16)[None, :] + 0.0625 * kept[:, None],
        # odometry j at 10 + 50 j ms: scan k (at 100 k ms) reads j = 2 k - 1
        "odometry": np.stack([0.1 * (2 * kept - 1), -0.01 * (2 * kept - 1)], axis=1),
    }
    return sorted(messages, key=lambda m: m[2]), expected


def scan_only_messages(ranges_of_step, **scan_fields):
    return [
        ("/scan", scan(T0_NS + k * SCAN_NS, ranges_of_step(k), **scan_fields), T0_NS + k * SCAN_NS)
        for k in range(N_SCANS)
    ]


# --- readings come back as written ------------------------------------------------------


@pytest.mark.parametrize("fmt", ["ros1", "db3", "mcap", "db3-file", "mcap-file"])
def test_readings_come_back_as_written_and_aligned_on_the_scans(tmp_path, fmt):
    messages, expected = ring_bag_messages()
    log = load_log(write_bag(tmp_path, fmt, messages))
    np.testing.assert_allclose(log.t, expected["t"], atol=1e-9)
    np.testing.assert_array_equal(log.laser, expected["laser"])
    assert log.sonar.shape == (N_SCANS - 1, 16)
    np.testing.assert_allclose(log.sonar, expected["sonar"], rtol=1e-6)  # float32 in the message
    np.testing.assert_allclose(log.odometry, expected["odometry"], rtol=1e-12)


@pytest.mark.parametrize("storage", ["db3", "mcap"])
def test_a_storage_file_in_its_bag_folder_reads_the_folder(tmp_path, storage):
    # with per-message compression only metadata.yaml says that the messages are compressed
    messages, expected = ring_bag_messages()
    folder = write_bag(tmp_path, storage, messages, compressed=True)
    log = load_log(folder / f"{folder.name}.{storage}")
    np.testing.assert_array_equal(log.laser, expected["laser"])


def test_a_scan_of_another_angle_range_and_increment_is_resampled_onto_the_model_beams(tmp_path):
    # 241 beams every 0.5 deg over [-60, 60] deg: beam k at -60 + 0.5 k deg
    ranges = 1.0 + np.arange(241) / 64.0
    ranges[100:111] = np.nan  # -10 .. -5 deg
    ranges[130:141] = np.inf  # 5 .. 10 deg
    ranges[160:171] = 0.01  # 20 .. 25 deg, below range_min
    ranges[180:191] = 30.0  # 30 .. 35 deg, at range_max
    ranges[200:211] = 25.0  # 40 .. 45 deg, within range_max but beyond the model's 20 m
    messages = scan_only_messages(
        lambda k: ranges, angle_min=np.radians(-60.0), increment=np.radians(0.5), range_min=0.02, range_max=30.0
    )
    laser = load_log(write_bag(tmp_path, "mcap", messages)).laser[0]
    # model beam i covers [-90 + i, -89 + i] deg: the nearest echo of the scan beams overlapping it
    assert np.all(laser[:29] == NO_LASER)  # outside the scan
    assert laser[29] == ranges[0]  # [-61, -60]: the scan's first beam, at -60 deg, reaches -59.75
    assert laser[30] == ranges[0]  # [-60, -59]: beams at -60, -59.5, -59 deg
    assert laser[90] == ranges[180 - 60]  # [0, 1]: beams at 0, 0.5, 1 deg
    assert laser[150] == ranges[240]  # [60, 61]: the last beam only
    assert np.all(laser[151:] == NO_LASER)
    for first_deg, last_deg in ((-10, -5), (5, 10), (20, 25), (30, 35), (40, 45)):
        inside = np.arange(90 + first_deg + 1, 90 + last_deg - 1)  # model beams wholly inside the run
        assert np.all(laser[inside] == NO_LASER), (first_deg, laser[inside])
    assert laser[90 - 11] == ranges[98]  # [-11, -10]: beams at -11, -10.5 valid, -10 is NaN


@pytest.mark.parametrize(
    "angle_min_deg, increment_deg, n, expected",
    [
        (-89.5, 1.0, 180, lambda r: r),  # the model's own grid
        (89.5, -1.0, 180, lambda r: r[::-1]),  # the same, clockwise
        # 0..359 deg: model beam i, over [-90 + i, -89 + i] deg, reads the beams at both ends
        (0.0, 1.0, 360, lambda r: np.minimum(np.roll(r, 90)[:180], np.roll(r, 89)[:180])),
        # 2 deg beams at -90 + 2 m, each over [-91 + 2 m, -89 + 2 m]: model beam i lies in beam (i + 1) // 2
        (-90.0, 2.0, 91, lambda r: r[(np.arange(180) + 1) // 2]),
    ],
)
def test_scan_resampler_geometries(angle_min_deg, increment_deg, n, expected):
    ranges = 1.0 + np.arange(n) / 64.0
    beams = ScanResampler.for_scan(np.radians(angle_min_deg), np.radians(increment_deg), n).resample(ranges, NO_LASER)
    np.testing.assert_array_equal(beams, expected(ranges))


def test_readings_outside_the_sensors_interval_are_no_echo():
    readings = [8.0, 7.9, 25.0, np.nan, -np.inf, np.inf, 0.01, 0.02]
    np.testing.assert_array_equal(
        ranges_or_no_echo(readings, 0.02, 8.0, NO_LASER),
        [NO_LASER, 7.9, NO_LASER, NO_LASER, NO_LASER, NO_LASER, NO_LASER, 0.02],
    )
    np.testing.assert_array_equal(ranges_or_no_echo([25.0, 19.0], 0.02, 30.0, NO_LASER), [NO_LASER, 19.0])


def test_scan_resampler_rejects_a_scan_it_cannot_place():
    with pytest.raises(ValueError, match="non-zero angle_increment"):
        ScanResampler.for_scan(0.0, 0.0, 10)
    with pytest.raises(ValueError, match="at least one range"):
        ScanResampler.for_scan(0.0, 0.01, 0)
    with pytest.raises(ValueError, match="finite"):
        ScanResampler.for_scan(float("nan"), 0.01, 10)


# --- topics ---------------------------------------------------------------------------


def test_topics_are_found_by_message_type_whatever_their_names(tmp_path):
    messages = []
    for k in range(N_SCANS):
        stamp = T0_NS + k * SCAN_NS
        messages.append(("/robot/front_laser", scan(stamp, np.full(180, 3.0 + k)), stamp))
        messages.append(("/base/odometry", odom(stamp, 0.5, 0.25), stamp))
        messages.append(("/chatter", chatter(), stamp))
        for n in range(8):
            messages.append((f"/p2at/sonar{n}", sonar(stamp, 0.5 + 0.5 * n), stamp))
    log = load_log(write_bag(tmp_path, "db3", messages))
    np.testing.assert_array_equal(log.laser[:, 0], 3.0 + np.arange(N_SCANS))
    np.testing.assert_array_equal(log.sonar, np.tile(0.5 + 0.5 * np.arange(8), (N_SCANS, 1)))
    np.testing.assert_array_equal(log.odometry, np.tile([0.5, 0.25], (N_SCANS, 1)))


def test_range_topics_map_onto_the_ring_in_natural_name_order(tmp_path):
    stamp = T0_NS
    messages = [("/scan", scan(stamp + k * SCAN_NS, np.full(180, 9.0)), stamp + k * SCAN_NS) for k in range(2)]
    messages += [(f"/sonar{n}", sonar(stamp, 0.25 * (n + 1)), stamp) for n in range(16)]
    log = load_log(write_bag(tmp_path, "ros1", sorted(messages, key=lambda m: m[2])))
    np.testing.assert_array_equal(log.sonar[0], 0.25 * (np.arange(16) + 1))  # /sonar10 is sonar 10, not 2


def _two_of_each_bag(tmp_path):
    messages = []
    for k in range(N_SCANS):
        stamp = T0_NS + k * SCAN_NS
        messages += [
            ("/front/scan", scan(stamp, np.full(180, 3.0)), stamp),
            ("/rear/scan", scan(stamp, np.full(180, 4.0)), stamp),
            ("/odom", odom(stamp, 0.3, 0.0), stamp),
            ("/odom_filtered", odom(stamp, 0.2, 0.1), stamp),
        ]
        messages += [(f"/sonar/{n}", sonar(stamp, 0.5 + 0.25 * n), stamp) for n in range(16)]
    return write_bag(tmp_path, "mcap", messages)


def test_flags_choose_among_topics_of_the_same_type(tmp_path):
    bag = _two_of_each_bag(tmp_path)
    with pytest.raises(
        LogFormatError,
        match=r"2 sensor_msgs/msg/LaserScan topics \(/front/scan, /rear/scan\); "
        "choose one with --laser-topic",
    ):
        load_log(bag)
    with pytest.raises(LogFormatError, match="choose one with --odom-topic"):
        load_log(bag, topics=BagTopics(laser="/rear/scan"))
    chosen = [f"/sonar/{n}" for n in (7, 6, 5, 4, 3, 2, 1, 0)]
    log = load_log(bag, topics=parse_bag_topics("/rear/scan", ",".join(chosen), "/odom_filtered"))
    assert np.all(log.laser == 4.0)
    np.testing.assert_array_equal(log.odometry[0], [0.2, 0.1])
    np.testing.assert_array_equal(log.sonar[0], 0.5 + 0.25 * np.arange(7, -1, -1))  # in the order named


def test_sonar_bearings_place_other_sonars_on_the_front_ring_and_the_laser_fills_the_rest(tmp_path):
    laser = np.full(180, 12.0)
    laser[110] = 2.0  # 20.5 deg: inside the cones of sonars 2 (30 deg) and 3 (10 deg)
    messages = []
    for k in range(N_SCANS):
        stamp = T0_NS + k * SCAN_NS
        messages.append(("/scan", scan(stamp, laser), stamp))
        messages += [
            ("/us/left", sonar(stamp, 1.5), stamp),
            ("/us/left2", sonar(stamp, 1.25), stamp),
            ("/us/right", sonar(stamp, 0.75), stamp),
            ("/us/back", sonar(stamp, 0.5), stamp),
            ("/us/far", sonar(stamp, 3.0, max_range=3.0), stamp),
        ]  # at its maximum: no echo
    bag = write_bag(tmp_path, "ros1", messages)
    topics = parse_bag_topics(sonars="/us/left,/us/left2,/us/right,/us/back,/us/far", sonar_bearings="12,8,-45,180,-10")
    reading = load_log(bag, topics=topics).sonar[0]
    assert reading.shape == (8,)
    assert reading[3] == 1.25  # 12 and 8 deg both stand in for sonar 3 (10 deg): the nearest echo, not the laser
    assert reading[6] == 0.75  # -45 deg: sonar 6 (-50 deg)
    assert reading[2] == 2.0  # from the laser's cone
    assert reading[4] == NO_SONAR  # /us/far, at its 3 m maximum
    assert np.all(reading[[0, 1, 5, 7]] == NO_SONAR)  # the laser sees nothing within 5 m there
    assert front_sonar_slot(180.0, 15.0) == -1 and front_sonar_slot(-100.0, 15.0) == 7
    # the same bearings apply to the Range topics found by type, in natural name order
    found = load_log(bag, topics=parse_bag_topics(sonar_bearings="180,-10,12,8,-45")).sonar[0]
    np.testing.assert_array_equal(found, reading)


def test_a_laser_only_bag_reads_the_front_sonars_from_the_laser(tmp_path):
    laser = np.full(180, 25.0)  # beyond the laser's range_max: no echo
    laser[100] = 1.0  # 10.5 deg
    laser[30] = 0.1  # -59.5 deg, nearer than the sonar's minimum
    laser[175] = 4.0  # 85.5 deg
    log = load_log(write_bag(tmp_path, "db3", scan_only_messages(lambda k: laser, range_max=22.0)))
    assert log.sonar.shape == (N_SCANS, 8) and log.odometry is None
    bounds = sonar_cone_bounds(CFG.sonar_cone_half_width_deg)
    expected = np.array(
        [min(CFG.sonar_max_range_m, max(CFG.sonar_min_range_m, log.laser[0, a:b].min())) for a, b in bounds]
    )
    np.testing.assert_array_equal(log.sonar[0], expected)
    np.testing.assert_array_equal(
        log.sonar[0], [4.0, NO_SONAR, NO_SONAR, 1.0, NO_SONAR, NO_SONAR, CFG.sonar_min_range_m, NO_SONAR]
    )


def test_zero_stamps_fall_back_to_the_receive_time(tmp_path):
    messages = [("/scan", scan(0, np.full(180, 3.0)), T0_NS + k * 250_000_000) for k in range(4)]
    log = load_log(write_bag(tmp_path, "mcap", messages))
    np.testing.assert_allclose(log.t, [0.0, 0.25, 0.5, 0.75], atol=1e-9)


def test_unset_range_limits_are_checked_against_the_models(tmp_path):
    messages = []
    for k in range(2):
        stamp = T0_NS + k * SCAN_NS
        messages.append(("/scan", scan(stamp, np.full(180, 3.0), range_min=0.0, range_max=0.0), stamp))
        messages += [(f"/s{n}", sonar(stamp, 2.0 if n else 7.0, min_range=0.0, max_range=0.0), stamp) for n in range(8)]
    log = load_log(write_bag(tmp_path, "db3", messages))
    assert np.all(log.laser == 3.0)
    np.testing.assert_array_equal(log.sonar[0], [NO_SONAR] + [2.0] * 7)  # 7 m is past the model's 5 m


# --- errors ---------------------------------------------------------------------------


def _error_bags(tmp_path):
    """name → (path, topics, message fragment); one bag per failure."""
    base = scan_only_messages(lambda k: np.full(180, 3.0))
    odometry = [("/odom", odom(T0_NS + k * SCAN_NS, 0.1, 0.0), T0_NS + k * SCAN_NS) for k in range(N_SCANS)]
    back = list(base)
    back[3] = ("/scan", scan(T0_NS + SCAN_NS, np.full(180, 3.0)), back[3][2])
    late = [(f"/sonar_late{n}", sonar(T0_NS + 10 * SCAN_NS, 1.0), T0_NS) for n in range(8)]  # after every scan
    cases = {}

    def bag(name, fmt, messages, topics=None, declared=None, match=""):
        folder = tmp_path / name
        folder.mkdir()
        cases[name] = (write_bag(folder, fmt, messages, declared), topics, match)

    listing = "topics: /odom (nav_msgs/msg/Odometry), /scan (sensor_msgs/msg/LaserScan)"
    bag(
        "missing topic",
        "ros1",
        base + odometry,
        BagTopics(laser="/front_scan"),
        match=f"no topic /front_scan (named by --laser-topic); {listing}",
    )
    bag(
        "wrong type",
        "db3",
        base + odometry,
        BagTopics(laser="/odom"),
        match="topic /odom (named by --laser-topic) is nav_msgs/msg/Odometry, not sensor_msgs/msg/LaserScan; "
        f"{listing}",
    )
    bag(
        "wrong sonar type",
        "mcap",
        base + odometry,
        BagTopics(sonars=("/scan",)),
        match="topic /scan (named by --sonar-topics) is sensor_msgs/msg/LaserScan, not sensor_msgs/msg/Range",
    )
    bag(
        "no laser topic",
        "mcap",
        odometry,
        match="no sensor_msgs/msg/LaserScan topic; topics: /odom (nav_msgs/msg/Odometry)",
    )
    bag(
        "no laser message",
        "db3",
        odometry,
        declared={"/scan": LASER},
        match="topic /scan holds no sensor_msgs/msg/LaserScan message; topics: /odom (nav_msgs/msg/Odometry, "
        f"{N_SCANS} messages), /scan (sensor_msgs/msg/LaserScan, 0 messages)",
    )
    bag(
        "time backwards",
        "ros1",
        back,
        match="time goes backwards on /scan: message 3 is stamped 1700000000.100000000 s after 1700000000.200000000 s",
    )
    odometry_back = [
        ("/odom", odom(T0_NS + (N_SCANS - k) * SCAN_NS, 0.1, 0.0), T0_NS + k * SCAN_NS) for k in range(N_SCANS)
    ]
    repeat = list(base)
    repeat[2] = ("/scan", scan(T0_NS + SCAN_NS, np.full(180, 3.0)), repeat[2][2])
    bag(
        "scan stamps repeat",
        "db3",
        repeat,
        match="message 2 is stamped 1700000000.100000000 s after "
        "1700000000.100000000 s; stamps must increase from scan to scan",
    )
    bag("odometry backwards", "mcap", base + odometry_back, match="time goes backwards on /odom: message 1")
    bag(
        "five sonars",
        "db3",
        base + [(f"/sonar_{n}", sonar(T0_NS, 1.0), T0_NS) for n in range(5)],
        match="5 sensor_msgs/msg/Range topics (/sonar_0, /sonar_1, /sonar_2, /sonar_3, /sonar_4) do not map onto "
        "the P2AT ring",
    )
    bag(
        "bearings count",
        "ros1",
        base,
        BagTopics(sonar_bearings_deg=(10.0, -10.0)),
        match="2 sonar bearings for 0 sensor_msgs/msg/Range topics (none)",
    )
    bag(
        "sonar after the last scan",
        "mcap",
        base + late,
        match="no scan on /scan at or after the first message of /sonar_late0",
    )
    bag(
        "empty topic",
        "db3",
        base,
        BagTopics(odometry="/odom"),
        declared={"/odom": ODOM},
        match="topic /odom holds no message; topics: /odom (nav_msgs/msg/Odometry, 0 messages)",
    )
    for fmt in ("ros1", "db3", "mcap"):
        bag(f"empty {fmt}", fmt, [], match="the bag is empty (no topic)")
    cases["not a bag"] = (tmp_path / "garbage.bag", None, "not a readable ROS bag (File magic is invalid.)")
    (tmp_path / "garbage.bag").write_text("garbage")
    (tmp_path / "whole").mkdir()
    whole = write_bag(tmp_path / "whole", "ros1", base).read_bytes()  # a recording cut short: no index
    (tmp_path / "cut.bag").write_bytes(whole[: len(whole) // 2])
    cases["cut short"] = (
        tmp_path / "cut.bag",
        None,
        "not a readable ROS bag (Bag index looks damaged: Header could not be read from file.); "
        "a ROS 1 bag cut short while recording, or with a damaged index, can be repaired with: "
        f"rosbag reindex {tmp_path / 'cut.bag'}",
    )
    # an index-data record whose entry count disagrees with its size (as in some old demo bags)
    damaged = bytearray(whole)
    count_at = damaged.index(b"count=", damaged.index(b"op=\x04")) + len("count=")
    damaged[count_at : count_at + 4] = struct.pack("<I", struct.unpack_from("<I", damaged, count_at)[0] - 1)
    (tmp_path / "damaged.bag").write_bytes(bytes(damaged))
    cases["damaged index"] = (
        tmp_path / "damaged.bag",
        None,
        "not a readable ROS bag (its records do not match their declared sizes); a ROS 1 bag cut short "
        f"while recording, or with a damaged index, can be repaired with: rosbag reindex {tmp_path / 'damaged.bag'}",
    )
    (tmp_path / "old.bag").write_bytes(b"#ROSRECORD V1.2\n" + bytes(64))
    cases["format 1.2"] = (
        tmp_path / "old.bag",
        None,
        "it is a ROS bag of format 1.2, which only ROS 1's own tools read: "
        f"rosbag filter {tmp_path / 'old.bag'} {tmp_path / 'old'}_v2.bag True writes it anew as format 2.0",
    )
    cases["folder"] = (tmp_path / "plain_folder", None, "holds no metadata.yaml")
    (tmp_path / "plain_folder").mkdir()
    cases["flags on a csv"] = (tmp_path / "log.csv", BagTopics(laser="/scan"), "topic options apply to ROS bags only")
    (tmp_path / "log.csv").write_text("t\n")
    return cases


def test_bad_bags_raise_clear_log_format_errors(tmp_path):
    for name, (path, topics, match) in _error_bags(tmp_path).items():
        with pytest.raises(LogFormatError) as caught:
            load_log(path, topics=topics)
        assert match in str(caught.value), (name, str(caught.value))
        assert str(path) in str(caught.value), name
        assert not re.search(r"\('|\['|',\)", str(caught.value)), (name, str(caught.value))  # no Python reprs


def test_the_cli_prints_a_bag_error_on_one_line_and_exits_2(tmp_path, capsys):
    bags = _error_bags(tmp_path)
    path, _, match = bags["no laser topic"]
    assert main(["attend", str(path), "--out", str(tmp_path / "out"), "--no-figure"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("attentive-gym attend: error:") and match in err and err.count("\n") == 1
    path, _, _ = bags["missing topic"]
    assert main(["attend", str(path), "--out", str(tmp_path / "out"), "--laser-topic", "/front_scan"]) == 2
    assert "no topic /front_scan (named by --laser-topic)" in capsys.readouterr().err
    assert main(["attend", str(path), "--out", str(tmp_path / "out"), "--sonar-bearings", "10,left"]) == 2
    assert "sonar bearings must be comma-separated numbers (deg)" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


def test_bag_topics_reject_bad_flags():
    with pytest.raises(ValueError, match="named more than once"):
        parse_bag_topics(sonars="/a,/b,/a")
    with pytest.raises(ValueError, match="2 sonar bearings for 3 sonar topics"):
        parse_bag_topics(sonars="/a,/b,/c", sonar_bearings="1,2")
    with pytest.raises(ValueError, match="finite"):
        parse_bag_topics(sonar_bearings="10,nan")
    with pytest.raises(ValueError, match="non-empty names"):
        parse_bag_topics(sonars="/a,,/b")
    assert parse_bag_topics() is None


def test_without_rosbags_a_bag_asks_for_the_ros_extra(tmp_path, monkeypatch):
    messages, _ = ring_bag_messages()
    bag = write_bag(tmp_path, "mcap", messages)
    monkeypatch.setitem(sys.modules, "rosbags.highlevel", None)  # importing it now raises ImportError
    with pytest.raises(
        LogFormatError,
        match=r"needs the rosbags package; install it with pip install "
        r"'attentive_gym\[ros\]'",
    ):
        read_bag(bag)


def test_reading_bags_imports_rosbags_only_when_a_bag_is_read():
    code = (
        "import sys; import attentive_gym.attention.io.rosbag, attentive_gym.attention as att; "
        "assert 'rosbags' not in sys.modules; print('ok')"
    )
    result = subprocess.run([sys.executable, "-c", code], cwd=REPO, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "ok"


# --- end to end -----------------------------------------------------------------------


def test_attend_replays_a_bag_end_to_end(tmp_path, capsys):
    messages, expected = ring_bag_messages()
    bag = write_bag(tmp_path, "ros1", messages)
    out = tmp_path / "out"
    assert main(["attend", str(bag), "--out", str(out), "--no-figure"]) == 0
    trace = load_trace(out / "trace.npz")
    assert trace.n_steps == N_SCANS - 1
    np.testing.assert_array_equal(trace.O2, expected["laser"])
    assert f"{N_SCANS - 1} steps" in capsys.readouterr().out
    assert main(["attend", str(bag), "--out", str(out), "--no-figure"]) == 2  # trace.npz is there
    assert "trace.npz already exist(s); pass --overwrite" in capsys.readouterr().err
    assert main(["attend", str(bag), "--out", str(out), "--no-figure", "--overwrite"]) == 0


def test_attend_flags_name_the_topics(tmp_path):
    bag = _two_of_each_bag(tmp_path)
    out = tmp_path / "out"
    assert (
        main(
            [
                "attend",
                str(bag),
                "--out",
                str(out),
                "--no-figure",
                "--laser-topic",
                "/rear/scan",
                "--odom-topic",
                "/odom_filtered",
                "--sonar-topics",
                "/sonar/3,/sonar/12",
                "--sonar-bearings",
                "10,-30",
            ]
        )
        == 0
    )
    trace = load_trace(out / "trace.npz")
    assert np.all(trace.O2 == 4.0)
    # /sonar/3 stands in for sonar 3 (10 deg), /sonar/12 for sonar 5 (-30 deg), the rear laser's 4 m for the rest
    np.testing.assert_array_equal(trace.O1[0], [4.0, 4.0, 4.0, 0.5 + 0.25 * 3, 4.0, 0.5 + 0.25 * 12, 4.0, 4.0])
