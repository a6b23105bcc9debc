"""The sensor as it is: a bag's laser range as the model's no echo (``open_bag(...,
sensor_range=True)``), the scans at their own resolution (``BagReplay.raw``), and the robot's
pose recorded in a replay's trace. Bags are written with rosbags' writers (helpers in
``test_rosbag``)."""

from __future__ import annotations

import numpy as np
import pytest

from attentive_gym.attention import AttentionConfig, AttentionModel, TraceRecorder, load_trace, replay_log
from attentive_gym.attention.io.rosbag import open_bag
from attentive_gym.attention.io.trace import save_trace
from support import load_test_module

_bags = load_test_module("attention/test_rosbag.py")
SCAN_NS, T0_NS, scan, write_bag = _bags.SCAN_NS, _bags.T0_NS, _bags.scan, _bags.write_bag
HOKUYO_M = 5.6
HALF_DEGREE = np.radians(0.5)
N_SCANS = 8


def _hokuyo_bag(tmp_path, fmt="mcap"):
    """8 scans of 360 half-degree beams over the front 180° (range_max 5.6 m, stored as
    float32): a wall at 4 m on the left half, nothing (range_max) on the right half, and
    beam 0 (rightmost) at 5.59 m, an echo just inside the range."""
    ranges = np.where(np.arange(360) >= 180, 4.0, HOKUYO_M)
    ranges[0] = 5.59
    fields = {"angle_min": -np.pi / 2 + HALF_DEGREE / 2, "increment": HALF_DEGREE, "range_max": np.float32(HOKUYO_M)}
    messages = [("/scan", scan(T0_NS + k * SCAN_NS, ranges, **fields), T0_NS + k * SCAN_NS) for k in range(N_SCANS)]
    return write_bag(tmp_path, fmt, messages)


@pytest.mark.parametrize("fmt", ["ros1", "mcap"])
def test_the_sensors_range_is_the_models_no_echo(tmp_path, fmt):
    replay = open_bag(_hokuyo_bag(tmp_path, fmt), sensor_range=True)
    assert replay.config.laser_max_range_m == HOKUYO_M
    laser = replay.log.laser
    np.testing.assert_array_equal(laser[:, 90:], 4.0)  # the wall, on the model's left beams
    np.testing.assert_array_equal(laser[:, 1:90], HOKUYO_M)  # nothing seen: no echo is 5.6 m, not 20 m
    np.testing.assert_allclose(laser[:, 0], 5.59, atol=1e-6)  # an echo just inside the range stays one
    assert "laser range: 5.6 m (the scans' range_max): no echo reads 5.6 m, not the configuration's 20 m" in (
        replay.notes
    )


def test_without_sensor_range_the_configurations_no_echo_stays_and_is_named(tmp_path):
    replay = open_bag(_hokuyo_bag(tmp_path))
    assert replay.config.laser_max_range_m == AttentionConfig().laser_max_range_m == 20.0
    np.testing.assert_array_equal(replay.log.laser[:, 1:90], 20.0)
    assert (
        "laser range: the scans' range_max is 5.6 m; no echo reads the configuration's 20 m (laser_max_range_m)"
        in replay.notes
    )


def test_a_sensor_reaching_beyond_the_configuration_keeps_its_range(tmp_path):
    config = AttentionConfig(laser_max_range_m=5.0)
    replay = open_bag(_hokuyo_bag(tmp_path), config=config, sensor_range=True)
    assert replay.config.laser_max_range_m == 5.0
    assert np.all(replay.log.laser <= 5.0)
    assert not any(note.startswith("laser range") for note in replay.notes)


def test_the_replays_configuration_carries_the_mount(tmp_path):
    replay = open_bag(_hokuyo_bag(tmp_path), config=AttentionConfig(laser_mount_x_m=-0.1, laser_mount_yaw_deg=10.0))
    assert (replay.config.laser_mount_x_m, replay.config.laser_mount_yaw_deg) == (-0.1, 10.0)
    assert (replay.mount.x_m, replay.mount.yaw_deg) == (-0.1, 10.0)


def test_raw_scans_keep_the_lasers_resolution_and_bearings(tmp_path):
    replay = open_bag(_hokuyo_bag(tmp_path), sensor_range=True)
    raw = replay.raw
    assert raw.ranges_m.shape == (N_SCANS, 360)
    np.testing.assert_allclose(np.degrees(raw.bearings_rad[[0, 359]]), [-89.75, 89.75], atol=1e-4)
    np.testing.assert_array_equal(raw.ranges_m[:, 180:], 4.0)
    np.testing.assert_array_equal(raw.ranges_m[:, 1:180], HOKUYO_M)


def test_a_replay_records_the_robots_pose_and_the_trace_keeps_it(tmp_path):
    messages, _ = _bags.ring_bag_messages()  # odometry: v = 0.1 j m/s, w = -0.01 j rad/s
    replay = open_bag(write_bag(tmp_path, "db3", messages), sensor_range=True)
    model = AttentionModel(replay.config)
    trace = replay_log(replay.log, model)
    assert trace.pose.shape == (trace.n_steps, 3)
    np.testing.assert_array_equal(trace.pose[-1], model.odometry_pose)
    assert trace.pose[-1, 0] > 0.0  # it drove forward
    loaded = load_trace(save_trace(trace, tmp_path / "trace.npz"))
    np.testing.assert_array_equal(loaded.pose, trace.pose)


def test_a_trace_without_poses_loads_with_none_and_poses_come_at_every_step_or_none(tmp_path):
    config = AttentionConfig(kinematics="window")
    model, recorder = AttentionModel(config), TraceRecorder(config)
    sonar, laser = np.full(16, 5.0), np.full(180, 20.0)
    recorder.append(model.step(0.05, sonar, laser), sonar, laser)
    assert model.odometry_pose is None
    assert load_trace(save_trace(recorder.to_trace(), tmp_path / "trace.npz")).pose is None
    with pytest.raises(ValueError, match="the robot's pose at every step of a trace or at none"):
        recorder.append(model.step(0.1, sonar, laser), sonar, laser, np.zeros(3))
