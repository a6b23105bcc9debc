"""Sensorial memory and kinematics (docs/model.md §2, §3)."""

import math

import numpy as np
import pytest

from attentive_gym.attention.kinematics import (
    direction_labels,
    planar_displacement,
    point_range_change,
    predict_scan,
    slope_weights,
    speeds,
)
from attentive_gym.attention.memory import SensorMemory
from attentive_gym.attention.regions import laser_bearings_rad


def test_slope_weights_two_samples_is_finite_difference_and_lsq_is_exact_on_lines():
    np.testing.assert_allclose(slope_weights([1.0, 1.25]), [-4.0, 4.0])
    t = np.array([0.0, 0.05, 0.11, 0.14, 0.2])  # uneven sampling
    x = 3.0 - 0.7 * t
    assert slope_weights(t) @ x == pytest.approx(-0.7)
    rng = np.random.default_rng(0)
    y = rng.normal(size=5)
    assert slope_weights(t) @ y == pytest.approx(np.polyfit(t, y, 1)[0])


def _memory_with(values, times, invalid=None, window=10):
    mem = SensorMemory(window, len(values[0]))
    for k, (t, v) in enumerate(zip(times, values)):
        inv = np.zeros(len(v), bool) if invalid is None else invalid[k]
        mem.push(t, np.asarray(v, float), inv, None)
    return mem


def test_range_rates_use_the_last_k_samples_and_zero_on_echo_switches():
    times = 0.05 * np.arange(12)
    ramp = 4.0 - 0.5 * times  # approaching at 0.5 m/s
    values = np.stack([ramp, np.full(12, 2.0), ramp], axis=1)
    invalid = np.zeros((12, 3), bool)
    invalid[8, 2] = True  # channel 2 saw no echo 3 samples ago
    mem = _memory_with(values, times, invalid)
    np.testing.assert_allclose(mem.range_rates(5), [-0.5, 0.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(mem.range_rates(3), [-0.5, 0.0, -0.5], atol=1e-12)  # window after the gap
    assert mem.count == 10
    t, rows = mem.chronological()
    np.testing.assert_allclose(t, times[2:]) and np.testing.assert_allclose(rows[:, 1], 2.0)


def test_range_rates_need_two_samples():
    mem = _memory_with([[1.0, 2.0]], [0.0])
    np.testing.assert_array_equal(mem.range_rates(5), [0.0, 0.0])


def test_speeds_and_labels():
    v = np.array([-2.0, -0.3, -0.05, 0.0, 0.04, 0.2, 1.5])
    np.testing.assert_allclose(speeds(v, 1.0), [1.0, 0.3, 0.05, 0.0, 0.04, 0.2, 1.0])
    assert direction_labels(v, 0.05).tolist() == [-1, -1, 0, 0, 0, 1, 1]


def test_planar_displacement_straight_and_arc():
    assert planar_displacement(0.5, 0.0, 0.1) == (0.05, 0.0, 0.0)
    dx, dy, dth = planar_displacement(1.0, math.pi / 2, 1.0)  # quarter circle of radius 2/pi
    r = 2 / math.pi
    assert (dx, dy, dth) == pytest.approx((r, r, math.pi / 2))


def test_predict_scan_of_a_wall_ahead_after_moving_forward():
    b = laser_bearings_rad()
    wall = 4.0 / np.cos(b)  # wall x = 4 m across the front
    front = np.abs(b) < np.radians(60)
    predicted = predict_scan(wall, np.cos(b), np.sin(b), b, 0.1, 0.0, 0.0)
    np.testing.assert_allclose(predicted[front], (3.9 / np.cos(b))[front], rtol=1e-3)
    assert point_range_change(0.1, 0.0, np.cos([0.0, np.pi / 2]), np.sin([0.0, np.pi / 2])) == pytest.approx(
        [-0.1, 0.0]
    )


def test_predict_scan_rotation_shifts_bearings():
    b = laser_bearings_rad()
    scan = 5.0 + np.sin(3 * b)
    turn = np.radians(4.0)
    predicted = predict_scan(scan, np.cos(b), np.sin(b), b, 0.0, 0.0, turn)
    inner = np.abs(b) < np.radians(80)
    np.testing.assert_allclose(predicted[inner], (5.0 + np.sin(3 * (b + turn)))[inner], atol=2e-3)
