"""``attentive_gym.perception.geometry``: robot-frame points, bearings, view and regions."""

from __future__ import annotations

import math

import numpy as np
import pytest

from attentive_gym.attention.regions import SONAR_BEARINGS_DEG
from attentive_gym.perception import geometry


def test_wrap_angle_lands_in_minus_pi_to_pi():
    angles = np.array([0.0, math.pi, -math.pi, 3 * math.pi / 2, -3 * math.pi / 2, 7.0])
    wrapped = geometry.wrap_angle(angles)
    assert np.all((wrapped >= -math.pi) & (wrapped < math.pi))
    np.testing.assert_allclose(np.cos(wrapped), np.cos(angles), atol=1e-12)
    np.testing.assert_allclose(np.sin(wrapped), np.sin(angles), atol=1e-12)
    assert geometry.wrap_angle(math.pi) == pytest.approx(-math.pi)


def test_to_robot_frame_puts_the_heading_on_x_and_the_left_on_y():
    pose = np.array([1.0, 2.0, math.pi / 2])  # at (1, 2), facing +y
    world = np.array([[1.0, 5.0], [0.0, 2.0], [2.0, 2.0]])  # ahead 3 m, left 1 m, right 1 m
    np.testing.assert_allclose(geometry.to_robot_frame(world, pose), [[3.0, 0.0], [0.0, 1.0], [0.0, -1.0]], atol=1e-12)
    assert geometry.to_robot_frame(np.zeros((4, 3, 2)), pose).shape == (4, 3, 2)


def test_bearings_and_view():
    xy = np.array([[2.0, 0.0], [0.0, 2.0], [-1.0, 0.0], [4.9, 0.0], [5.1, 0.0], [3.0, -3.0]])
    np.testing.assert_allclose(geometry.bearing_of(xy), [0.0, math.pi / 2, math.pi, 0.0, 0.0, -math.pi / 4])
    assert geometry.in_view(xy).tolist() == [True, False, False, True, False, True]  # front and within 5 m


def test_in_sight_needs_the_view_two_beams_and_a_bearing_off_the_edge():
    edge = 4.0 * np.array([math.cos(math.radians(85.0)), math.sin(math.radians(85.0))])
    inside = 4.0 * np.array([math.cos(math.radians(75.0)), -math.sin(math.radians(75.0))])
    xy = np.array([[2.0, 0.0], [2.0, 0.0], [5.1, 0.0], edge, inside, [-1.0, 0.0]])
    beams = np.array([2, 1, 5, 5, 3, 5])
    # on 2 beams; on 1; too far; at 85° (the field of view's edge); at -75°; behind
    assert geometry.in_sight(xy, beams).tolist() == [True, False, False, False, True, False]


def test_each_front_sonar_s_bearing_lies_in_its_region():
    bearings = np.radians(SONAR_BEARINGS_DEG[: geometry.GRID.n_regions])
    xy = 2.0 * np.stack([np.cos(bearings), np.sin(bearings)], axis=-1)
    assert geometry.region_of(xy).tolist() == list(range(geometry.GRID.n_regions))


def test_the_true_target_bearing_comes_from_the_world_s_truth():
    info = {
        "mover_positions": np.array([[9.0, 9.0], [3.0, 4.0]]),
        "target_index": 1,
        "robot_pose": np.array([3.0, 0.0, 0.0]),
    }
    assert geometry.true_target_bearing(info) == pytest.approx(math.pi / 2)  # straight to the left
    info["robot_pose"] = np.array([3.0, 0.0, math.pi / 2])
    assert geometry.true_target_bearing(info) == pytest.approx(0.0, abs=1e-12)  # straight ahead
