"""The attentive robot: a Pioneer P2AT-sized skid-steer base in pymunk.

- ``RobotConfig``: size, mass, velocity and acceleration limits, drive force limits.
- ``Robot``: the pymunk body, driven by a kinematic *control body* through a pivot joint
  (linear) and a gear joint (angular) with bounded force and torque. The robot therefore
  follows velocity commands in free space but is stopped, physically, by walls and other
  bodies; the pivot joint also removes lateral slip, as skid-steer wheels do.

Commands are linear (m/s, along the heading) and angular (rad/s, counter-clockwise)
velocities; each physics sub-step moves the commanded velocity towards the target by at
most the acceleration limits.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pymunk

from attentive_gym import _pymunk_access

__all__ = ["RobotConfig", "Robot", "ROBOT_COLLISION_TYPE"]

#: pymunk collision type of the attentive robot's shape.
ROBOT_COLLISION_TYPE = 1


@dataclass(frozen=True)
class RobotConfig:
    """Physical parameters of the attentive robot (defaults: Pioneer P2AT).

    Attributes:
        length_m, width_m: footprint of the body (x forward, y left).
        mass_kg: body mass.
        max_linear_mps: top forward/backward speed.
        max_angular_rps: top turn rate (rad/s).
        linear_accel_mps2, angular_accel_rps2: how fast commands ramp.
        drive_force_n, drive_torque_nm: the most the drive can push against an obstacle.
        friction: Coulomb friction of the body against other shapes.
    """

    length_m: float = 0.626
    width_m: float = 0.505
    mass_kg: float = 14.0
    max_linear_mps: float = 0.7
    max_angular_rps: float = math.radians(140.0)
    linear_accel_mps2: float = 1.0
    angular_accel_rps2: float = math.radians(300.0)
    drive_force_n: float = 400.0
    drive_torque_nm: float = 60.0
    friction: float = 0.6

    def __post_init__(self) -> None:
        for name, value in vars(self).items():
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0.0):
                raise ValueError(f"RobotConfig.{name} must be a finite number > 0, got {value!r}")


class Robot:
    """The attentive robot in a pymunk space.

    Args:
        space: the world's space; the body, its control body and joints are added to it.
        config: physical parameters.
        pose: start ``(x_m, y_m, heading_rad)``.
    """

    def __init__(self, space: pymunk.Space, config: RobotConfig, pose: tuple[float, float, float]) -> None:
        self.config = config
        size = (config.length_m, config.width_m)
        self.body = pymunk.Body(config.mass_kg, pymunk.moment_for_box(config.mass_kg, size))
        self.body.position = pose[:2]
        self.body.angle = pose[2]
        self.shape = pymunk.Poly.create_box(self.body, size)
        self.shape.friction = config.friction
        self.shape.collision_type = ROBOT_COLLISION_TYPE
        self.control = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        self.control.position = pose[:2]
        pivot = pymunk.PivotJoint(self.control, self.body, (0.0, 0.0), (0.0, 0.0))
        pivot.max_bias = 0.0  # correct velocity only, never drag the body to the control's position
        pivot.max_force = config.drive_force_n
        gear = pymunk.GearJoint(self.control, self.body, 0.0, 1.0)
        gear.error_bias = 0.0
        gear.max_bias = 0.0
        gear.max_force = config.drive_torque_nm
        space.add(self.body, self.shape, self.control, pivot, gear)
        self._target = (0.0, 0.0)  # commanded (linear m/s, angular rad/s)
        self._current = (0.0, 0.0)  # ramped command actually sent to the drive

    def command(self, linear_mps: float, angular_rps: float) -> None:
        """Set the target velocities; values beyond the limits are clipped to them.

        Raises:
            ValueError: a velocity is not a finite number.
        """
        c = self.config
        linear, angular = float(linear_mps), float(angular_rps)
        if not (math.isfinite(linear) and math.isfinite(angular)):
            raise ValueError(
                f"robot commands must be finite numbers, got linear {linear_mps!r} m/s, angular {angular_rps!r} rad/s"
            )
        self._target = (
            min(max(linear, -c.max_linear_mps), c.max_linear_mps),
            min(max(angular, -c.max_angular_rps), c.max_angular_rps),
        )

    def drive(self, h_s: float) -> None:
        """Ramp the command towards the target for a sub-step of ``h_s`` and apply it."""
        c = self.config
        linear = _approach(self._current[0], self._target[0], c.linear_accel_mps2 * h_s)
        angular = _approach(self._current[1], self._target[1], c.angular_accel_rps2 * h_s)
        self._current = (linear, angular)
        # Drive along the chord of the arc turned during this sub-step (the heading at its
        # middle), so the body's velocity stays aligned with its heading while turning.
        heading = self.body.angle + 0.5 * angular * h_s
        control = self.control
        _pymunk_access.set_velocity(control, linear * math.cos(heading), linear * math.sin(heading))
        _pymunk_access.set_angular_velocity(control, angular)

    @property
    def pose(self) -> np.ndarray:
        """``(x_m, y_m, heading_rad)`` of the body's centre; the heading is not wrapped: it
        is the angle turned since the start (counter-clockwise positive), as pymunk keeps it."""
        return np.array(_pymunk_access.pose(self.body))

    @property
    def odometry(self) -> np.ndarray:
        """Measured ``(linear m/s along the heading, angular rad/s)`` of the body."""
        body = self.body
        vx, vy = _pymunk_access.velocity(body)
        heading = body.angle
        return np.array([vx * math.cos(heading) + vy * math.sin(heading), body.angular_velocity])

    def in_contact(self) -> bool:
        """Whether the body touches any other shape after the last physics step."""
        counts: list[int] = []
        self.body.each_arbiter(_append_contact_count, counts)
        return any(counts)


def _append_contact_count(arbiter: pymunk.Arbiter, counts: list[int]) -> None:
    counts.append(_pymunk_access.contact_count(arbiter))


def _approach(value: float, target: float, max_change: float) -> float:
    """``value`` moved towards ``target`` by at most ``max_change``."""
    return value + min(max(target - value, -max_change), max_change)
