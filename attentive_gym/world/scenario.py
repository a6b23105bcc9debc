"""Scenarios as data: the documented schema of a rescue world.

- ``Scenario``: everything needed to build a world (bounds, robot start, walls, rubble,
  moving bodies, optional task).
- ``WallSpec``, ``BoxRubble``, ``CircleRubble``, ``SegmentRubble``: static geometry.
- ``MoverSpec`` with a behaviour: ``PathBehaviour`` (waypoint legs with speeds, pauses,
  start delay, optional loop), ``PursueBehaviour`` (approach the robot) or
  ``EvadeBehaviour`` (move away from the robot).
- ``TaskSpec``: which mover is the target, the goal that describes it, the time limit.

All lengths are metres, speeds m/s, angles degrees, times seconds; the world frame has
x to the right and y up, angles counter-clockwise from +x. Every class validates itself
at construction and raises ``ValueError`` naming the offending field. Scenarios load from
YAML or JSON files with ``attentive_gym.world.scenario_io``; the keys there are exactly
the field names here.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, field
from typing import Literal

from attentive_gym.attention.goals import Goal

__all__ = [
    "Point",
    "Pose",
    "WallSpec",
    "BoxRubble",
    "CircleRubble",
    "SegmentRubble",
    "Rubble",
    "Leg",
    "PathBehaviour",
    "PursueBehaviour",
    "EvadeBehaviour",
    "Behaviour",
    "MoverSpec",
    "TaskSpec",
    "Scenario",
    "MOVER_KINDS",
]

#: The kinds of moving body; victims are circles, robots P2AT-sized boxes.
MOVER_KINDS = ("victim", "robot")


def _finite(owner: str, name: str, value) -> float:
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ValueError(f"{owner}.{name} must be a number, got {value!r}")
    if not math.isfinite(value):
        raise ValueError(f"{owner}.{name} must be finite, got {value}")
    return float(value)


def _positive(owner: str, name: str, value) -> float:
    value = _finite(owner, name, value)
    if value <= 0.0:
        raise ValueError(f"{owner}.{name} must be > 0, got {value}")
    return value


def _non_negative(owner: str, name: str, value) -> float:
    value = _finite(owner, name, value)
    if value < 0.0:
        raise ValueError(f"{owner}.{name} must be >= 0, got {value}")
    return value


def _keep(spec, check, owner: str, name: str) -> None:
    """Store ``check(owner, name, value)`` (the value as a plain float) in ``spec.name``."""
    object.__setattr__(spec, name, check(owner, name, getattr(spec, name)))


def _all_of(owner: str, name: str, items, kinds) -> tuple:
    """``items`` as a tuple, each an instance of ``kinds``; ``ValueError`` naming the first that is not."""
    if isinstance(items, (str, bytes)) or not hasattr(items, "__iter__"):
        raise ValueError(f"{owner}.{name} must be a sequence, got {items!r}")
    items = tuple(items)
    allowed = " or ".join(kind.__name__ for kind in kinds)
    for i, item in enumerate(items):
        if not isinstance(item, kinds):
            raise ValueError(f"{owner}.{name}[{i}] must be a {allowed}, got {item!r}")
    return items


def _point(owner: str, name: str, value) -> tuple[float, float]:
    if not isinstance(value, (tuple, list)) or len(value) != 2:
        raise ValueError(f"{owner}.{name} must be a pair [x_m, y_m], got {value!r}")
    return (_finite(owner, f"{name}[0]", value[0]), _finite(owner, f"{name}[1]", value[1]))


Point = tuple[float, float]


@dataclass(frozen=True)
class Pose:
    """A position (m) and heading (degrees, counter-clockwise from +x)."""

    x_m: float
    y_m: float
    heading_deg: float = 0.0

    def __post_init__(self) -> None:
        for name in ("x_m", "y_m", "heading_deg"):
            _keep(self, _finite, "pose", name)


@dataclass(frozen=True)
class WallSpec:
    """A straight wall from ``start`` to ``end`` (m), built as a box ``thickness_m`` thick."""

    start: Point
    end: Point
    thickness_m: float = 0.2

    def __post_init__(self) -> None:
        object.__setattr__(self, "start", _point("wall", "start", self.start))
        object.__setattr__(self, "end", _point("wall", "end", self.end))
        _keep(self, _positive, "wall", "thickness_m")
        if self.start == self.end:
            raise ValueError(f"wall.start and wall.end must differ, both are {self.start}")


@dataclass(frozen=True)
class BoxRubble:
    """A static box centred at (x_m, y_m), ``width_m`` along its own x, rotated ``angle_deg``."""

    x_m: float
    y_m: float
    width_m: float
    height_m: float
    angle_deg: float = 0.0
    kind: Literal["box"] = "box"

    def __post_init__(self) -> None:
        for name in ("x_m", "y_m", "angle_deg"):
            _keep(self, _finite, "box", name)
        _keep(self, _positive, "box", "width_m")
        _keep(self, _positive, "box", "height_m")

    @property
    def extent_m(self) -> float:
        """Radius of the circle around the centre that contains the box."""
        return 0.5 * math.hypot(self.width_m, self.height_m)


@dataclass(frozen=True)
class CircleRubble:
    """A static disc centred at (x_m, y_m)."""

    x_m: float
    y_m: float
    radius_m: float
    kind: Literal["circle"] = "circle"

    def __post_init__(self) -> None:
        _keep(self, _finite, "circle", "x_m")
        _keep(self, _finite, "circle", "y_m")
        _keep(self, _positive, "circle", "radius_m")

    @property
    def extent_m(self) -> float:
        return self.radius_m


@dataclass(frozen=True)
class SegmentRubble:
    """A static beam from ``start`` to ``end`` with rounded ends of ``radius_m``."""

    start: Point
    end: Point
    radius_m: float = 0.05
    kind: Literal["segment"] = "segment"

    def __post_init__(self) -> None:
        object.__setattr__(self, "start", _point("segment", "start", self.start))
        object.__setattr__(self, "end", _point("segment", "end", self.end))
        _keep(self, _positive, "segment", "radius_m")

    @property
    def x_m(self) -> float:
        return 0.5 * (self.start[0] + self.end[0])

    @property
    def y_m(self) -> float:
        return 0.5 * (self.start[1] + self.end[1])

    @property
    def extent_m(self) -> float:
        return 0.5 * math.dist(self.start, self.end) + self.radius_m


Rubble = BoxRubble | CircleRubble | SegmentRubble


@dataclass(frozen=True)
class Leg:
    """Move in a straight line to ``to`` at ``speed_mps``, then wait ``pause_s``."""

    to: Point
    speed_mps: float
    pause_s: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "to", _point("leg", "to", self.to))
        _keep(self, _positive, "leg", "speed_mps")
        _keep(self, _non_negative, "leg", "pause_s")


@dataclass(frozen=True)
class PathBehaviour:
    """Follow ``legs`` from the start position after ``start_delay_s``.

    With ``loop`` the path repeats, returning to the start position at the last leg's
    speed. The body keeps its start heading unless ``face_motion`` (a robot backing away
    keeps facing the way it came, as in the paper's experiments). Stop-and-go is a
    ``pause_s`` on a leg. Positions are a closed-form function of time, so the motion
    is exact and independent of the step size.
    """

    legs: tuple[Leg, ...]
    start_delay_s: float = 0.0
    loop: bool = False
    face_motion: bool = False
    kind: Literal["path"] = "path"

    def __post_init__(self) -> None:
        legs = _all_of("path", "legs", self.legs, (Leg,))
        if not legs:
            raise ValueError("path.legs must hold at least one leg")
        object.__setattr__(self, "legs", legs)
        _keep(self, _non_negative, "path", "start_delay_s")
        if not isinstance(self.loop, bool) or not isinstance(self.face_motion, bool):
            raise ValueError("path.loop and path.face_motion must be true or false")


@dataclass(frozen=True)
class PursueBehaviour:
    """Drive towards the attentive robot at ``speed_mps``, stopping ``stop_distance_m`` from it."""

    speed_mps: float
    stop_distance_m: float = 0.8
    start_delay_s: float = 0.0
    kind: Literal["pursue"] = "pursue"

    def __post_init__(self) -> None:
        _keep(self, _positive, "pursue", "speed_mps")
        _keep(self, _non_negative, "pursue", "stop_distance_m")
        _keep(self, _non_negative, "pursue", "start_delay_s")


@dataclass(frozen=True)
class EvadeBehaviour:
    """Drive away from the attentive robot at ``speed_mps`` (stopping at the world's bounds)."""

    speed_mps: float
    start_delay_s: float = 0.0
    kind: Literal["evade"] = "evade"

    def __post_init__(self) -> None:
        _keep(self, _positive, "evade", "speed_mps")
        _keep(self, _non_negative, "evade", "start_delay_s")


Behaviour = PathBehaviour | PursueBehaviour | EvadeBehaviour


@dataclass(frozen=True)
class MoverSpec:
    """A scripted moving body: a survivor (``victim``) or another robot.

    Victims are discs of ``radius_m``; robots are boxes ``length_m`` × ``width_m``
    (P2AT-sized by default). ``behaviour=None`` keeps the body still.
    """

    name: str
    kind: Literal["victim", "robot"]
    start: Pose
    behaviour: Behaviour | None = None
    radius_m: float = 0.25
    length_m: float = 0.626
    width_m: float = 0.505

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name:
            raise ValueError(f"mover.name must be a non-empty string, got {self.name!r}")
        if self.kind not in MOVER_KINDS:
            raise ValueError(f"mover {self.name!r}: kind must be one of {MOVER_KINDS}, got {self.kind!r}")
        if not isinstance(self.start, Pose):
            raise ValueError(f"mover {self.name!r}: start must be a Pose")
        if self.behaviour is not None and not isinstance(
            self.behaviour, (PathBehaviour, PursueBehaviour, EvadeBehaviour)
        ):
            raise ValueError(
                f"mover {self.name!r}: behaviour must be a PathBehaviour, PursueBehaviour, EvadeBehaviour "
                f"or None, got {self.behaviour!r}"
            )
        for name in ("radius_m", "length_m", "width_m"):
            _keep(self, _positive, f"mover {self.name!r}", name)

    @property
    def extent_m(self) -> float:
        """Radius of the circle around the body's centre that contains it."""
        return self.radius_m if self.kind == "victim" else 0.5 * math.hypot(self.length_m, self.width_m)


@dataclass(frozen=True)
class TaskSpec:
    """The rescue task: reach the mover named ``target``, which ``goal`` describes."""

    target: str
    goal: Goal
    time_limit_s: float = 40.0

    def __post_init__(self) -> None:
        if not isinstance(self.goal, Goal):
            raise ValueError(f"task.goal must be a Goal, got {type(self.goal).__name__}")
        if not isinstance(self.target, str):
            raise ValueError(f"task.target must be a mover's name, got {self.target!r}")
        _keep(self, _positive, "task", "time_limit_s")


@dataclass(frozen=True)
class Scenario:
    """A complete rescue world.

    Attributes:
        name: identifier, used in file names and figures.
        bounds: ``(x_min, y_min, x_max, y_max)`` in metres; every body must lie inside.
        robot: the attentive robot's start pose.
        enclosed: build walls along the bounds.
        walls, rubble, movers: the world's bodies.
        task: the rescue task, or ``None`` (reward 0, episodes end only by time).
        duration_s: the episode length when there is no task (experiments).
    """

    name: str
    bounds: tuple[float, float, float, float]
    robot: Pose = field(default_factory=lambda: Pose(0.0, 0.0, 0.0))
    enclosed: bool = False
    walls: tuple[WallSpec, ...] = ()
    rubble: tuple[Rubble, ...] = ()
    movers: tuple[MoverSpec, ...] = ()
    task: TaskSpec | None = None
    duration_s: float = 40.0

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name:
            raise ValueError(f"scenario.name must be a non-empty string, got {self.name!r}")
        if not isinstance(self.bounds, (tuple, list)) or len(self.bounds) != 4:
            raise ValueError(f"scenario.bounds must be [x_min, y_min, x_max, y_max], got {self.bounds!r}")
        bounds = tuple(_finite("scenario", f"bounds[{i}]", v) for i, v in enumerate(self.bounds))
        if bounds[0] >= bounds[2] or bounds[1] >= bounds[3]:
            raise ValueError(f"scenario.bounds must have x_min < x_max and y_min < y_max, got {bounds}")
        object.__setattr__(self, "bounds", bounds)
        if not isinstance(self.robot, Pose):
            raise ValueError(f"scenario.robot must be a Pose, got {self.robot!r}")
        if not isinstance(self.enclosed, bool):
            raise ValueError(f"scenario.enclosed must be true or false, got {self.enclosed!r}")
        for name, kinds in (
            ("walls", (WallSpec,)),
            ("rubble", (BoxRubble, CircleRubble, SegmentRubble)),
            ("movers", (MoverSpec,)),
        ):
            object.__setattr__(self, name, _all_of("scenario", name, getattr(self, name), kinds))
        if self.task is not None and not isinstance(self.task, TaskSpec):
            raise ValueError(f"scenario.task must be a TaskSpec or None, got {self.task!r}")
        _keep(self, _positive, "scenario", "duration_s")
        names = [m.name for m in self.movers]
        duplicates = sorted({n for n in names if names.count(n) > 1})
        if duplicates:
            raise ValueError(f"scenario.movers: names must be unique, repeated: {duplicates}")
        if self.task is not None and self.task.target not in names:
            raise ValueError(f"task.target {self.task.target!r} is not a mover; movers are {names}")
        self._check_inside_bounds()

    def _check_inside_bounds(self) -> None:
        x0, y0, x1, y1 = self.bounds

        def inside(x: float, y: float, margin: float) -> bool:
            return x0 + margin <= x <= x1 - margin and y0 + margin <= y <= y1 - margin

        if not inside(self.robot.x_m, self.robot.y_m, 0.0):
            raise ValueError(f"scenario.robot at ({self.robot.x_m}, {self.robot.y_m}) is outside bounds {self.bounds}")
        for i, wall in enumerate(self.walls):
            for end in (wall.start, wall.end):
                if not inside(*end, 0.0):
                    raise ValueError(f"scenario.walls[{i}] end {end} is outside bounds {self.bounds}")
        for i, piece in enumerate(self.rubble):
            if not inside(piece.x_m, piece.y_m, 0.0):
                raise ValueError(f"scenario.rubble[{i}] at ({piece.x_m}, {piece.y_m}) is outside bounds {self.bounds}")
        for mover in self.movers:
            if not inside(mover.start.x_m, mover.start.y_m, 0.0):
                raise ValueError(f"mover {mover.name!r} starts outside bounds {self.bounds}")
            if isinstance(mover.behaviour, PathBehaviour):
                for j, leg in enumerate(mover.behaviour.legs):
                    if not inside(*leg.to, 0.0):
                        raise ValueError(f"mover {mover.name!r} leg {j} goes to {leg.to}, outside bounds {self.bounds}")

    @property
    def target_index(self) -> int | None:
        """Index of the task's target in ``movers``, or ``None`` without a task."""
        if self.task is None:
            return None
        return [m.name for m in self.movers].index(self.task.target)
