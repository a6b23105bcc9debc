"""Motion laws of scripted movers.

- ``PathMotion``: closed-form, piecewise-linear position along a ``PathBehaviour``.
- ``PursueMotion`` / ``EvadeMotion``: steer towards / away from the attentive robot.
- ``make_motion``: the motion law for a behaviour.

Each law answers one question: which velocity (m/s, world frame) brings the body where it
should be after ``h`` seconds. ``follows_clock`` tells whether the law is a schedule (a
path, which a mover blocked by the robot resumes where it stopped) or a reaction to the
robot (pursue, evade). Path positions are exact functions of time, and the
velocity is computed from the body's *current* position, so rounding never accumulates
and the positions at step boundaries do not depend on the step size.

These classes are the laws' reference: the pure-Python world step runs them once per
environment step, and the compiled world step (``world.compiled``) does the same
arithmetic on the numbers ``world.state`` copies from them, bit for bit. Distances are
``sqrt(dx*dx + dy*dy)`` on both sides (CPython's ``math.hypot`` rounds differently from
C's ``hypot``).
"""

from __future__ import annotations

import bisect
import math

from attentive_gym.world.scenario import Behaviour, EvadeBehaviour, PathBehaviour, PursueBehaviour

__all__ = ["PathMotion", "PursueMotion", "EvadeMotion", "make_motion"]


class PathMotion:
    """Piecewise-linear motion through the legs of a ``PathBehaviour``.

    Args:
        behaviour: the path.
        start_xy: the body's start position (m).
    """

    follows_clock = True

    def __init__(self, behaviour: PathBehaviour, start_xy: tuple[float, float]) -> None:
        points = [(float(start_xy[0]), float(start_xy[1]))]
        times = [behaviour.start_delay_s]
        legs = list(behaviour.legs)
        if behaviour.loop:  # close the loop at the last leg's speed, without a pause
            legs.append(type(legs[-1])(to=tuple(start_xy), speed_mps=legs[-1].speed_mps))
        for leg in legs:
            times.append(times[-1] + math.dist(leg.to, points[-1]) / leg.speed_mps)
            points.append(leg.to)
            if leg.pause_s > 0.0:
                times.append(times[-1] + leg.pause_s)
                points.append(leg.to)
        self.knot_t = times  # (K,) s, non-decreasing
        self.knot_xy = points  # (K,) (x m, y m)
        self.start_delay_s = behaviour.start_delay_s
        self.period_s = times[-1] - behaviour.start_delay_s if behaviour.loop else None  # s
        self.face_motion = behaviour.face_motion

    def position(self, t_s: float) -> tuple[float, float]:
        """Where the body is at time ``t_s`` (s): (x m, y m)."""
        if self.period_s is not None and self.period_s > 0.0 and t_s > self.start_delay_s:
            t_s = self.start_delay_s + math.fmod(t_s - self.start_delay_s, self.period_s)
        knots = self.knot_t
        i = bisect.bisect_right(knots, t_s)
        if i == 0:
            return self.knot_xy[0]
        if i == len(knots):
            return self.knot_xy[-1]
        (x0, y0), (x1, y1) = self.knot_xy[i - 1], self.knot_xy[i]
        u = (t_s - knots[i - 1]) / (knots[i] - knots[i - 1])
        return (x0 + u * (x1 - x0), y0 + u * (y1 - y0))

    def velocity(self, t_s: float, h_s: float, position, robot_xy) -> tuple[float, float]:
        """Velocity (m/s) that reaches ``position(t_s + h_s)`` from ``position`` in ``h_s``."""
        x, y = self.position(t_s + h_s)
        return ((x - position[0]) / h_s, (y - position[1]) / h_s)


class PursueMotion:
    """Drive straight at the robot at ``speed_mps``, stopping ``stop_distance_m`` away."""

    face_motion = True
    follows_clock = False

    def __init__(self, behaviour: PursueBehaviour) -> None:
        self.behaviour = behaviour

    def velocity(self, t_s: float, h_s: float, position, robot_xy) -> tuple[float, float]:
        b = self.behaviour
        dx, dy = robot_xy[0] - position[0], robot_xy[1] - position[1]
        distance = math.sqrt(dx * dx + dy * dy)
        if t_s < b.start_delay_s or distance <= b.stop_distance_m:
            return (0.0, 0.0)
        gain = min(b.speed_mps, (distance - b.stop_distance_m) / h_s) / distance
        return (dx * gain, dy * gain)


class EvadeMotion:
    """Drive straight away from the robot at ``speed_mps``, never leaving ``bounds``.

    Args:
        behaviour: the evasion.
        bounds: ``(x_min, y_min, x_max, y_max)`` (m) of the world.
        extent_m: the body's radius; it keeps that far inside the bounds.
    """

    face_motion = True
    follows_clock = False

    def __init__(self, behaviour: EvadeBehaviour, bounds: tuple[float, float, float, float], extent_m: float) -> None:
        self.behaviour = behaviour
        self.low = (bounds[0] + extent_m, bounds[1] + extent_m)  # lowest x, y (m) of the centre
        self.high = (bounds[2] - extent_m, bounds[3] - extent_m)  # highest x, y (m) of the centre

    def velocity(self, t_s: float, h_s: float, position, robot_xy) -> tuple[float, float]:
        b = self.behaviour
        dx, dy = position[0] - robot_xy[0], position[1] - robot_xy[1]
        distance = math.sqrt(dx * dx + dy * dy)
        if t_s < b.start_delay_s or distance == 0.0:
            return (0.0, 0.0)
        gain = b.speed_mps * h_s / distance
        wanted = (
            min(max(position[0] + dx * gain, self.low[0]), self.high[0]),
            min(max(position[1] + dy * gain, self.low[1]), self.high[1]),
        )
        return ((wanted[0] - position[0]) / h_s, (wanted[1] - position[1]) / h_s)


def make_motion(
    behaviour: Behaviour,
    start_xy: tuple[float, float],
    bounds: tuple[float, float, float, float],
    extent_m: float,
) -> PathMotion | PursueMotion | EvadeMotion:
    """The motion law of ``behaviour`` for a body starting at ``start_xy`` (m)."""
    if isinstance(behaviour, PathBehaviour):
        return PathMotion(behaviour, start_xy)
    if isinstance(behaviour, PursueBehaviour):
        return PursueMotion(behaviour)
    if isinstance(behaviour, EvadeBehaviour):
        return EvadeMotion(behaviour, bounds, extent_m)
    raise TypeError(f"unknown behaviour {type(behaviour).__name__}")
