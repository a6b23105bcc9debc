"""The world's control state as numpy records, the form the compiled world step reads.

- ``WORLD_DTYPE``: one record per world: the robot's command, ramp and limits, the clock,
  the touch flag, and the robot's pose and velocity read back after each step.
- ``MOVER_DTYPE``: one record per scripted mover: its motion law and parameters, the
  state of its stops at the robot, and its pose and velocity read back after each step.
- ``robot_record`` / ``mover_records``: build them for a robot and a scenario's movers,
  with the ``(K, 3)`` path knots (t s, x m, y m) the path movers index into.

Flags are ``uint8`` (numba records cannot hold bools). Records are aligned structured
arrays; a world keeps one ``(1,)`` world array, one ``(M,)`` mover array and one knot
array for its whole life, so the compiled step may hold their addresses.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from attentive_gym.world.behaviours import EvadeMotion, PathMotion, PursueMotion

if TYPE_CHECKING:
    from attentive_gym.world.robot import RobotConfig

__all__ = [
    "WORLD_DTYPE",
    "MOVER_DTYPE",
    "LAW_STILL",
    "LAW_PATH",
    "LAW_PURSUE",
    "LAW_EVADE",
    "robot_record",
    "mover_records",
]

#: ``MOVER_DTYPE.law``: a body without a behaviour (it never moves by itself).
LAW_STILL = 0
#: ``MOVER_DTYPE.law``: a piecewise-linear path through knots (``PathMotion``).
LAW_PATH = 1
#: ``MOVER_DTYPE.law``: drive at the robot (``PursueMotion``).
LAW_PURSUE = 2
#: ``MOVER_DTYPE.law``: drive away from the robot inside bounds (``EvadeMotion``).
LAW_EVADE = 3

WORLD_DTYPE = np.dtype(
    [
        ("target", "f8", (2,)),  # commanded (linear m/s, angular rad/s), clipped to the limits
        ("command", "f8", (2,)),  # the ramped command sent to the drive (m/s, rad/s)
        ("max_linear_mps", "f8"),
        ("max_angular_rps", "f8"),
        ("linear_accel_mps2", "f8"),
        ("angular_accel_rps2", "f8"),
        ("physics_dt_s", "f8"),  # the largest physics sub-step (s)
        ("time_s", "f8"),  # the clock: clock_start_s + steps_taken · clock_dt_s
        ("clock_start_s", "f8"),
        ("clock_dt_s", "f8"),  # the step length the clock counts (s); NaN before the first step
        ("steps_taken", "i8"),  # steps of clock_dt_s since clock_start_s
        ("robot_pose", "f8", (3,)),  # x m, y m, heading rad (unwrapped), after the last step
        ("robot_velocity", "f8", (3,)),  # vx m/s, vy m/s, angular rad/s, after the last step
        ("touched", "u1"),  # the robot touched a shape during the last step
    ],
    align=True,
)

MOVER_DTYPE = np.dtype(
    [
        ("law", "i8"),  # LAW_STILL, LAW_PATH, LAW_PURSUE or LAW_EVADE
        ("face_motion", "u1"),  # turn the body to face its velocity
        ("follows_clock", "u1"),  # a schedule (path) that a stop delays, not a reaction
        ("touching", "u1"),  # touched the robot in the last step (set by the contact callback)
        ("blocked", "u1"),  # stopped by the robot during the last step
        ("speed_mps", "f8"),  # pursue / evade speed
        ("stop_distance_m", "f8"),  # pursue: how close it comes
        ("start_delay_s", "f8"),  # it stays still before this time
        ("period_s", "f8"),  # path: loop period (s); NaN when the path does not loop
        ("low", "f8", (2,)),  # evade: lowest x, y (m) of its centre
        ("high", "f8", (2,)),  # evade: highest x, y (m) of its centre
        ("first_knot", "i8"),  # path: its first row in the knot array
        ("num_knots", "i8"),  # path: its number of knots
        ("script_delay_s", "f8"),  # how long the robot has paused the path's schedule (s)
        ("towards_robot", "f8", (2,)),  # unit vector from the mover to the robot, while touching
        ("pose", "f8", (3,)),  # x m, y m, angle rad, after the last step
        ("velocity", "f8", (2,)),  # vx, vy m/s, after the last step
    ],
    align=True,
)


def robot_record(config: RobotConfig, physics_dt_s: float = math.nan) -> np.ndarray:
    """A ``(1,)`` ``WORLD_DTYPE`` array for a robot at rest with ``config``'s limits, physics
    sub-steps of at most ``physics_dt_s`` and a clock at 0 s that has not counted a step yet."""
    record = np.zeros(1, WORLD_DTYPE)
    record["max_linear_mps"] = config.max_linear_mps
    record["max_angular_rps"] = config.max_angular_rps
    record["linear_accel_mps2"] = config.linear_accel_mps2
    record["angular_accel_rps2"] = config.angular_accel_rps2
    record["physics_dt_s"] = physics_dt_s
    record["clock_dt_s"] = math.nan
    return record


def mover_records(motions: Sequence[PathMotion | PursueMotion | EvadeMotion | None]) -> tuple[np.ndarray, np.ndarray]:
    """``(movers (M,) MOVER_DTYPE, knots (K, 3) float64)`` of the movers' motion laws.

    The records hold the numbers the laws hold: a path's knots (start time s, x m, y m per
    row; a mover's rows in order), start delay and loop period; pursuit's and evasion's
    speed, stop distance, start delay and bounds.
    """
    movers = np.zeros(len(motions), MOVER_DTYPE)
    movers["period_s"] = math.nan
    knots: list[tuple[float, float, float]] = []
    for i, motion in enumerate(motions):
        row = movers[i]  # a view of the record
        if motion is None:
            row["law"] = LAW_STILL
            continue
        row["face_motion"] = motion.face_motion
        row["follows_clock"] = motion.follows_clock
        if isinstance(motion, PathMotion):
            row["law"] = LAW_PATH
            row["start_delay_s"] = motion.start_delay_s
            row["period_s"] = math.nan if motion.period_s is None else motion.period_s
            row["first_knot"], row["num_knots"] = len(knots), len(motion.knot_t)
            knots += [(t, x, y) for t, (x, y) in zip(motion.knot_t, motion.knot_xy)]
        elif isinstance(motion, PursueMotion):
            row["law"] = LAW_PURSUE
            row["speed_mps"] = motion.behaviour.speed_mps
            row["stop_distance_m"] = motion.behaviour.stop_distance_m
            row["start_delay_s"] = motion.behaviour.start_delay_s
        else:
            row["law"] = LAW_EVADE
            row["speed_mps"] = motion.behaviour.speed_mps
            row["start_delay_s"] = motion.behaviour.start_delay_s
            row["low"], row["high"] = motion.low, motion.high
    return movers, np.array(knots, dtype=np.float64).reshape(-1, 3)
