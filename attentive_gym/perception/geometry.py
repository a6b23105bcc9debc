"""Where the movers are as the robot sees them: robot-frame geometry and what counts as in view.

- ``wrap_angle``, ``to_robot_frame``, ``bearing_of``: world points in the robot's frame
  (x forward, y left, m) and their bearings (rad, counter-clockwise from the heading).
- ``in_view``: in front of the robot (``|bearing| < 90°``) within ``VIEW_RANGE_M``.
- ``in_sight``: in view as the laser can see it: within ``VIEW_RANGE_M``, ``|bearing| ≤
  SIGHT_BEARING_DEG`` and on at least ``SIGHT_BEAMS`` laser beams.
- ``region_of``: the attention region (0..7 on ``GRID``) a point lies in.
- ``true_target_xy`` / ``true_target_bearing``: the episode's target's position / bearing, from the world's truth
  (``info`` of an ``AttentiveRescue`` step).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from attentive_gym.attention.regions import Grid, nearest_sonar

__all__ = [
    "GRID",
    "VIEW_RANGE_M",
    "wrap_angle",
    "to_robot_frame",
    "bearing_of",
    "in_view",
    "SIGHT_BEARING_DEG",
    "SIGHT_BEAMS",
    "in_sight",
    "region_of",
    "true_target_xy",
    "true_target_bearing",
]

#: The attention regions the metrics are counted on: the sonar grid's 8, one per front sonar.
GRID = Grid.make("sonar")
#: Movers farther than this (m, centre to centre) are out of view.
VIEW_RANGE_M = 5.0
#: In sight: within this bearing (degrees either side of the heading), away from the laser's
#: field-of-view edge, and on at least this many laser beams of the step's scan.
SIGHT_BEARING_DEG, SIGHT_BEAMS = 80.0, 2


def wrap_angle(angle_rad: np.ndarray | float) -> np.ndarray | float:
    """Angles (rad) wrapped into [−π, π)."""
    return (angle_rad + math.pi) % (2.0 * math.pi) - math.pi


def to_robot_frame(points_xy: np.ndarray, pose: np.ndarray) -> np.ndarray:
    """World points ``(..., 2)`` (m) in the frame of a robot at ``pose`` = (x m, y m, heading
    rad): x forward, y left (m), same shape."""
    x, y, heading = pose
    c, s = math.cos(heading), math.sin(heading)
    dx, dy = points_xy[..., 0] - x, points_xy[..., 1] - y
    return np.stack([c * dx + s * dy, -s * dx + c * dy], axis=-1)


def bearing_of(xy: np.ndarray) -> np.ndarray:
    """Bearings (rad, counter-clockwise from the heading) of robot-frame points ``(..., 2)``."""
    return np.arctan2(xy[..., 1], xy[..., 0])


def in_view(xy: np.ndarray) -> np.ndarray:
    """Whether robot-frame points ``(..., 2)`` lie in front (``|bearing| < 90°``) within
    ``VIEW_RANGE_M``."""
    return (xy[..., 0] > 0.0) & (np.hypot(xy[..., 0], xy[..., 1]) < VIEW_RANGE_M)


def in_sight(xy: np.ndarray, beams: np.ndarray) -> np.ndarray:
    """Whether robot-frame points ``(..., 2)`` that ``beams`` ``(...)`` laser beams hit lie
    within ``VIEW_RANGE_M``, within ``SIGHT_BEARING_DEG`` of the heading and on at least
    ``SIGHT_BEAMS`` beams: a body the laser can see, away from its field of view's edge."""
    near = np.hypot(xy[..., 0], xy[..., 1]) < VIEW_RANGE_M
    return near & (np.abs(bearing_of(xy)) <= math.radians(SIGHT_BEARING_DEG)) & (beams >= SIGHT_BEAMS)


def region_of(xy: np.ndarray) -> np.ndarray:
    """The attention region (0..7, the nearest front sonar's bearing) of robot-frame points
    ``(..., 2)`` in front of the robot."""
    return nearest_sonar(bearing_of(xy))


def true_target_xy(info: Mapping[str, Any]) -> np.ndarray:
    """The episode's target ``(2,)`` in the robot's frame (m), from the world's truth."""
    return to_robot_frame(np.asarray(info["mover_positions"][info["target_index"]], float), info["robot_pose"])


def true_target_bearing(info: Mapping[str, Any]) -> float:
    """Bearing (rad, robot frame) of the episode's target, from the world's truth."""
    return float(bearing_of(true_target_xy(info)))
