"""A bag's laser mount: ``--laser-mount``, ``--laser-upside-down`` and the bag's TF, and
odometry from TF. Bags are written with rosbags' writers (helpers in ``test_rosbag``)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from attentive_gym.attention import AttentionConfig, load_trace
from attentive_gym.attention.io.ros_readings import LaserMount
from attentive_gym.attention.io.rosbag import ScanOptions, open_bag, parse_scan_options
from attentive_gym.cli import main
from support import load_test_module

_bags = load_test_module("attention/test_rosbag.py")
N_SCANS, NO_LASER, ROS2, SCAN_NS, T0_NS = _bags.N_SCANS, _bags.NO_LASER, _bags.ROS2, _bags.SCAN_NS, _bags.T0_NS
odom, scan, write_bag = _bags.odom, _bags.scan, _bags.write_bag
RANGES_180 = 1.0 + np.arange(180) / 64.0  # laser beam k at -89.5 + k deg
RANGES_360 = 1.0 + np.arange(360) / 64.0  # laser beam j at 0.5 + j deg


def _framed(message, frame_id):
    """``message`` with its header's frame_id set."""
    return dataclasses.replace(message, header=dataclasses.replace(message.header, frame_id=frame_id))


def _quaternion(roll, yaw):
    """x, y, z, w of a rotation by ``roll`` about x, then ``yaw`` about z (rad)."""
    cr, sr, cy, sy = np.cos(roll / 2), np.sin(roll / 2), np.cos(yaw / 2), np.sin(yaw / 2)
    return sr * cy, sr * sy, cr * sy, cr * cy


def tf_message(stamp_ns, *transforms):
    """A TFMessage of ``(parent, child, (x, y, z), (qx, qy, qz, qw))`` transforms."""
    t = ROS2.types
    stamp = t["builtin_interfaces/msg/Time"](sec=stamp_ns // 10**9, nanosec=stamp_ns % 10**9)
    entries = [
        t["geometry_msgs/msg/TransformStamped"](
            header=t["std_msgs/msg/Header"](stamp=stamp, frame_id=parent),
            child_frame_id=child,
            transform=t["geometry_msgs/msg/Transform"](
                translation=t["geometry_msgs/msg/Vector3"](x=xyz[0], y=xyz[1], z=xyz[2]),
                rotation=t["geometry_msgs/msg/Quaternion"](x=q[0], y=q[1], z=q[2], w=q[3]),
            ),
        )
        for parent, child, xyz, q in transforms
    ]
    return t["tf2_msgs/msg/TFMessage"](transforms=entries)


def _scans(ranges, frame="laser", **fields):
    return [
        ("/scan", _framed(scan(T0_NS + k * SCAN_NS, ranges, **fields), frame), T0_NS + k * SCAN_NS)
        for k in range(N_SCANS)
    ]


def _reversed_upside_down_tf():
    """``/tf_static``: base_link -> plate (a 0.3 m riser) -> laser (reversed, upside down)."""
    return (
        "/tf_static",
        tf_message(
            T0_NS,
            ("base_link", "plate", (-0.25, 0.05, 0.3), (0.0, 0.0, 0.0, 1.0)),
            ("/plate", "/laser", (0.05, 0.0, 0.1), _quaternion(np.pi, np.pi)),  # ROS 1 style names
        ),
        T0_NS,
    )


def _full_circle_scan():
    return {"angle_min": np.radians(0.5), "increment": np.radians(1.0)}


def test_a_yawed_laser_turns_its_beams_by_the_yaw(tmp_path):
    bag = write_bag(tmp_path, "mcap", _scans(RANGES_180))
    laser = open_bag(bag, options=parse_scan_options("0.1,0,90")).log.laser[0]
    # laser beam k (-89.5 + k deg) points at 0.5 + k deg: model beam 90 + k
    np.testing.assert_array_equal(laser[90:], RANGES_180[:90])
    assert np.all(laser[:90] == NO_LASER)


def test_an_upside_down_laser_runs_its_beams_the_other_way(tmp_path):
    bag = write_bag(tmp_path, "db3", _scans(RANGES_180))
    replay = open_bag(bag, options=parse_scan_options(upside_down=True))
    np.testing.assert_array_equal(replay.log.laser[0], RANGES_180[::-1])  # -89.5 + k deg reads at 89.5 - k
    assert replay.mount == LaserMount(0.16, 0.0, 0.0, True)  # the rest is the configuration's


def test_a_reversed_upside_down_laser_from_flags(tmp_path):
    bag = write_bag(tmp_path, "ros1", _scans(RANGES_360, **_full_circle_scan()))
    replay = open_bag(bag, options=parse_scan_options("-0.2,0.05,180", upside_down=True))
    # laser angle a points at 180 - a: model beam i (-89.5 + i deg) reads laser beam 269 - i (269.5 - i deg)
    np.testing.assert_array_equal(replay.log.laser[0], RANGES_360[269 - np.arange(180)])
    assert replay.mount == LaserMount(-0.2, 0.05, 180.0, True)


def _bag_in(tmp_path, name, fmt, messages):
    """A bag written in its own folder ``tmp_path / name``."""
    (tmp_path / name).mkdir()
    return write_bag(tmp_path / name, fmt, messages)


@pytest.mark.parametrize("fmt", ["ros1", "mcap"])
def test_the_mount_is_read_from_tf_through_a_chain_of_frames(tmp_path, fmt):
    scans = _scans(RANGES_360, **_full_circle_scan())
    flags = open_bag(_bag_in(tmp_path, "flags", fmt, scans), options=parse_scan_options("-0.2,0.05,180", True))
    bag = _bag_in(tmp_path, "tf", fmt, [_reversed_upside_down_tf(), *scans])
    replay = open_bag(bag)
    assert replay.mount == flags.mount
    np.testing.assert_array_equal(replay.log.laser, flags.log.laser)
    line = "laser mount: x -0.2 m, y 0.05 m, yaw 180°, upside down (from TF laser -> plate -> base_link)"
    assert line in replay.notes
    # a flag wins over TF for what it gives
    given = open_bag(bag, options=ScanOptions(mount_xy_yaw=(0.1, 0.0, 0.0)))
    assert given.mount == LaserMount(0.1, 0.0, 0.0, True)
    assert given.notes[1].endswith("(--laser-mount; upside down or not: from TF laser -> plate -> base_link)")


def test_without_tf_the_configurations_mount_applies(tmp_path):
    config = AttentionConfig(laser_mount_x_m=-0.3, laser_mount_yaw_deg=180.0)
    replay = open_bag(write_bag(tmp_path, "mcap", _scans(RANGES_360, **_full_circle_scan())), config=config)
    assert replay.mount == LaserMount(-0.3, 0.0, 180.0, False)
    # laser angle a points at 180 + a: model beam i (-89.5 + i deg) reads laser beam 90 + i (90.5 + i deg)
    np.testing.assert_array_equal(replay.log.laser[0], RANGES_360[90 + np.arange(180)])
    assert "(the configuration's, as no TF in the bag leads from the laser's frame to a base frame)" in replay.notes[1]


def test_odometry_is_read_from_tf_when_no_odometry_topic_is_logged(tmp_path):
    v, w = 0.5, 0.2  # m/s, rad/s: a unicycle on an arc, poses at 50 Hz from 20 ms before the first scan
    messages = _scans(np.full(180, 4.0))
    for j in range(40):
        t_ns = T0_NS - 20_000_000 + j * 20_000_000
        s = (t_ns - T0_NS) * 1e-9
        pose = ((v / w) * np.sin(w * s), (v / w) * (1 - np.cos(w * s)), 0.0)
        messages.append(("/tf", tf_message(t_ns, ("odom", "base_link", pose, _quaternion(0.0, w * s))), t_ns))
    messages.append(("/tf_static", tf_message(T0_NS, ("base_link", "laser", (0.1, 0.0, 0.2), (0, 0, 0, 1))), T0_NS))
    replay = open_bag(write_bag(tmp_path, "db3", sorted(messages, key=lambda m: m[2])))
    # 40 poses end at 760 ms: the scans at 0..500 ms all lie within them
    np.testing.assert_allclose(replay.log.odometry, np.tile([v, w], (N_SCANS, 1)), rtol=1e-4)
    assert replay.mount == LaserMount(0.1, 0.0, 0.0, False)
    assert "odometry from TF odom -> base_link (50.0 Hz)" in replay.notes[0]


def test_an_odometry_topic_names_the_base_frame_and_wins_over_tf(tmp_path):
    messages = _scans(np.full(180, 4.0))
    messages += [
        (
            "/odom",
            dataclasses.replace(odom(T0_NS + k * SCAN_NS, 0.3, 0.0), child_frame_id="chassis"),
            T0_NS + k * SCAN_NS,
        )
        for k in range(N_SCANS)
    ]
    messages.append(("/tf_static", tf_message(T0_NS, ("chassis", "laser", (0.4, -0.1, 0.0), (0, 0, 0, 1))), T0_NS))
    replay = open_bag(write_bag(tmp_path, "mcap", sorted(messages, key=lambda m: m[2])))
    assert replay.mount == LaserMount(0.4, -0.1, 0.0, False)
    np.testing.assert_array_equal(replay.log.odometry, np.tile([0.3, 0.0], (N_SCANS, 1)))


def test_attend_runs_the_model_with_the_mount_and_prints_it(tmp_path, capsys):
    messages = [_reversed_upside_down_tf(), *_scans(RANGES_360, **_full_circle_scan())]
    bag, out = write_bag(tmp_path, "mcap", messages), tmp_path / "out"
    assert main(["attend", str(bag), "--out", str(out), "--no-figure"]) == 0
    printed = capsys.readouterr().out
    assert "laser mount: x -0.2 m, y 0.05 m, yaw 180°, upside down (from TF laser -> plate -> base_link)" in printed
    trace = load_trace(out / "trace.npz")
    np.testing.assert_array_equal(trace.O2[0], RANGES_360[269 - np.arange(180)])
    assert (trace.config["laser_mount_x_m"], trace.config["laser_mount_yaw_deg"]) == (-0.2, 180.0)
    assert trace.config["laser_upside_down"] is True


def test_the_config_checks_the_mounts_yaw_and_upside_down_flag():
    with pytest.raises(ValueError, match=r"laser_mount_yaw_deg must be a finite number >= -360 and <= 360 \(deg\)"):
        AttentionConfig(laser_mount_yaw_deg=400.0)
    with pytest.raises(ValueError, match="laser_upside_down must be True or False"):
        AttentionConfig(laser_upside_down="yes")
