"""The attentive robot: a Pioneer P2AT-sized skid-steer base in pymunk.

- ``RobotConfig``: size, mass, velocity and acceleration limits, drive force limits.
- ``Robot``: the pymunk body, driven by a kinematic *control body* through a pivot joint
  (linear) and a gear joint (angular) with bounded force and torque. The robot therefore
  follows velocity commands in free space but is stopped, physically, by walls and other
  bodies; the pivot joint also removes lateral slip, as skid-steer wheels do.

Commands are linear (m/s, along the heading) and angular (rad/s, counter-clockwise)
velocities; each physics sub-step moves the commanded velocity towards the target by at
most the acceleration limits. The command, its ramp and the pose read back after each
step live in the world's record (``world.state``), which the compiled world step reads
and writes; ``Robot.command`` and ``Robot.drive`` are the pure-Python step's versions.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pymunk

from attentive_gym import _pymunk_access
from attentive_gym.world.state import robot_record

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
        state: the ``(1,)`` ``world.state.WORLD_DTYPE`` record that holds the robot's
            command and read-back pose (its world's); a new one when omitted.
    """

    def __init__(
        self,
        space: pymunk.Space,
        config: RobotConfig,
        pose: tuple[float, float, float],
        state: np.ndarray | None = None,
    ) -> None:
        self.config = config
        self.state = robot_record(config) if state is None else state
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
        self.read_back()

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
        self.state["target"][0] = (
            min(max(linear, -c.max_linear_mps), c.max_linear_mps),
            min(max(angular, -c.max_angular_rps), c.max_angular_rps),
        )

    def drive(self, h_s: float) -> None:
        """Ramp the command towards the target for a sub-step of ``h_s`` and apply it."""
        c = self.config
        state = self.state
        (target_linear, target_angular), (linear, angular) = state["target"][0].tolist(), state["command"][0].tolist()
        linear = _approach(linear, target_linear, c.linear_accel_mps2 * h_s)
        angular = _approach(angular, target_angular, c.angular_accel_rps2 * h_s)
        state["command"][0] = (linear, angular)
        # Drive along the chord of the arc turned during this sub-step (the heading at its
        # middle), so the body's velocity stays aligned with its heading while turning.
        heading = self.body.angle + 0.5 * angular * h_s
        control = self.control
        _pymunk_access.set_velocity(control, linear * math.cos(heading), linear * math.sin(heading))
        _pymunk_access.set_angular_velocity(control, angular)

    @property
    def target(self) -> tuple[float, float]:
        """The commanded ``(linear m/s, angular rad/s)``, clipped to the limits."""
        linear, angular = self.state["target"][0].tolist()
        return linear, angular

    @property
    def drive_command(self) -> tuple[float, float]:
        """The ramped ``(linear m/s, angular rad/s)`` the drive was last given."""
        linear, angular = self.state["command"][0].tolist()
        return linear, angular

    def read_back(self) -> None:
        """Copy the body's pose and velocity into ``state`` (``robot_pose``,
        ``robot_velocity``), as the compiled step does after every step."""
        body = self.body
        vx, vy = _pymunk_access.velocity(body)
        self.state["robot_pose"][0] = _pymunk_access.pose(body)
        self.state["robot_velocity"][0] = (vx, vy, body.angular_velocity)

    @property
    def pose(self) -> np.ndarray:
        """``(x_m, y_m, heading_rad)`` of the body's centre after the last step; the heading
        is not wrapped: it is the angle turned since the start (counter-clockwise positive),
        as pymunk keeps it. A body moved by hand through pymunk shows here after the next
        step (or ``read_back``)."""
        return self.state["robot_pose"][0].copy()

    @property
    def odometry(self) -> np.ndarray:
        """Measured ``(linear m/s along the heading, angular rad/s)`` of the body after the
        last step."""
        state = self.state[0]
        heading = float(state["robot_pose"][2])
        vx, vy, angular = state["robot_velocity"].tolist()
        return np.array([vx * math.cos(heading) + vy * math.sin(heading), angular])

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
