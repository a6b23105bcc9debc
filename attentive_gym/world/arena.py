"""The procedurally generated rescue arena (seeded).

- ``ArenaConfig``: the difficulty knobs (size, rubble density, distractors, speeds, goals).
- ``DEFAULT_TASK_GOALS``: the goals an episode samples from by default.
- ``generate_arena``: one random walled arena with rubble, a target victim that the goal
  describes, and distractors that the goal rules out.

How a goal picks its target: for a **speed** goal the target patrols at a speed that
fulfils the goal with a margin and every distractor at a speed that violates it with the
same margin (speed 0 = standing still); **direction** goals use behaviours instead:
``towards`` → the target pursues the robot, ``away`` → it evades the robot, ``static`` →
it stands still, while distractors patrol at ``distractor_speed_range_mps``. Distance
goals describe where the robot is, not which victim it wants, so they are refused.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

import numpy as np

from attentive_gym.attention.goals import Direction, Feature, Goal
from attentive_gym.world.scenario import (
    BoxRubble,
    CircleRubble,
    EvadeBehaviour,
    Leg,
    MoverSpec,
    PathBehaviour,
    Pose,
    PursueBehaviour,
    Rubble,
    Scenario,
    SegmentRubble,
    TaskSpec,
)

__all__ = ["ArenaConfig", "DEFAULT_TASK_GOALS", "generate_arena"]

#: Goals sampled per episode by default: a medium-speed victim or a slow one that moves.
#: Both describe a target the sensors can tell apart: with the arena's 0.1 m/s speed
#: margin, the medium target patrols at 0.6–0.8 m/s and its distractors at ≤ 0.35 m/s;
#: the slow target at 0.25–0.35 m/s and its distractors stand still or go ≥ 0.55 m/s.
#: (Earlier ``speed <= 0.3`` let the target stand still, and a victim standing still
#: reads as rubble: no sensor tells them apart.)
DEFAULT_TASK_GOALS = (Goal.between("speed", 0.5, 0.9), Goal.between("speed", 0.15, 0.45))

_SPEED_GRID_STEP_MPS = 0.05  # resolution of the speeds a mover can be given
_PLACEMENT_ATTEMPTS = 200  # rejection-sampling tries per body before giving up
_LAYOUT_ATTEMPTS = 20  # whole layouts drawn (from the same generator) before a crowded arena gives up
_WALL_MARGIN_M = 0.6  # keep bodies this far from the enclosure's centre lines
_PATROL_WAYPOINTS = 3
_MAX_MOVER_SPEED_MPS = 20.0  # the largest speed a goal can name (the goal encoding's bound)
_MAX_ARENA_SIDE_M = 10_000.0  # larger sides overflow the rubble count (width × height × density)
_MAX_RUBBLE = 5000  # rubble pieces per arena: placement is quadratic in the count
_MAX_RUBBLE_PER_100M2 = 50.0  # denser than this no longer fits (pieces are up to 1 m long, 0.3 m apart)


@dataclass(frozen=True)
class ArenaConfig:
    """Knobs of the procedural arena (lengths m, speeds m/s, times s).

    Attributes:
        width_m, height_m: the arena inside its enclosure.
        rubble_per_100m2: rubble pieces per 100 m² of floor (rounded).
        num_distractors: moving bodies besides the target (alternately victims and robots).
        max_mover_speed_mps: the fastest any mover goes.
        speed_margin_mps: target and distractor speeds keep at least this far from the
            goal's bounds, so that the goal tells them apart.
        distractor_speed_range_mps: distractor speeds under direction goals.
        min_start_distance_m: movers start at least this far from the robot.
        pursue_stop_distance_m: how close a pursuing target comes to the robot.
        goals: goals an episode samples from (uniformly).
        time_limit_s: the episode's time limit.
    """

    width_m: float = 10.0
    height_m: float = 10.0
    rubble_per_100m2: float = 6.0
    num_distractors: int = 3
    max_mover_speed_mps: float = 1.0
    speed_margin_mps: float = 0.1
    distractor_speed_range_mps: tuple[float, float] = (0.3, 0.9)
    min_start_distance_m: float = 3.0
    pursue_stop_distance_m: float = 1.5
    goals: tuple[Goal, ...] = DEFAULT_TASK_GOALS
    time_limit_s: float = 40.0

    def __post_init__(self) -> None:
        for name in ("width_m", "height_m", "max_mover_speed_mps", "time_limit_s", "min_start_distance_m"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ValueError(f"ArenaConfig.{name} must be a finite number > 0, got {value!r}")
        if max(self.width_m, self.height_m) > _MAX_ARENA_SIDE_M:
            raise ValueError(
                f"the arena must be at most {_MAX_ARENA_SIDE_M} m on each side, got {self.width_m} × {self.height_m}"
            )
        if min(self.width_m, self.height_m) < 4.0:
            raise ValueError(f"the arena must be at least 4 m on each side, got {self.width_m} × {self.height_m}")
        for name in ("rubble_per_100m2", "speed_margin_mps", "pursue_stop_distance_m"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value >= 0):
                raise ValueError(f"ArenaConfig.{name} must be a finite number >= 0, got {value!r}")
        if not (
            isinstance(self.num_distractors, numbers.Integral)
            and not isinstance(self.num_distractors, (bool, np.bool_))
            and 0 <= self.num_distractors <= 20
        ):
            raise ValueError(f"ArenaConfig.num_distractors must be an integer in [0, 20], got {self.num_distractors!r}")
        if self.max_mover_speed_mps > _MAX_MOVER_SPEED_MPS:
            raise ValueError(
                f"ArenaConfig.max_mover_speed_mps must be <= {_MAX_MOVER_SPEED_MPS}, got {self.max_mover_speed_mps!r}"
            )
        if self.rubble_per_100m2 > _MAX_RUBBLE_PER_100M2:
            raise ValueError(
                f"ArenaConfig.rubble_per_100m2 must be <= {_MAX_RUBBLE_PER_100M2}, got {self.rubble_per_100m2!r}"
            )
        if self.rubble_count > _MAX_RUBBLE:
            raise ValueError(
                f"ArenaConfig: rubble_per_100m2={self.rubble_per_100m2!r} over {self.width_m} × {self.height_m} m "
                f"gives {self.rubble_count} rubble pieces; at most {_MAX_RUBBLE} are allowed"
            )
        lo, hi = self.distractor_speed_range_mps
        if not (0 < lo <= hi <= self.max_mover_speed_mps):
            raise ValueError(
                "ArenaConfig.distractor_speed_range_mps must satisfy 0 < lo <= hi <= max_mover_speed_mps, "
                f"got {(lo, hi)}"
            )
        goals = tuple(self.goals)
        if not goals or not all(isinstance(g, Goal) for g in goals):
            raise ValueError("ArenaConfig.goals must be a non-empty sequence of Goal objects")
        for goal in goals:
            check_task_goal(goal, self)
        object.__setattr__(self, "goals", goals)

    @property
    def rubble_count(self) -> int:
        return int(round(self.rubble_per_100m2 * self.width_m * self.height_m / 100.0))


def _speed_grid(config: ArenaConfig) -> np.ndarray:
    steps = int(math.floor(config.max_mover_speed_mps / _SPEED_GRID_STEP_MPS + 1e-9))
    return np.round(np.arange(steps + 1) * _SPEED_GRID_STEP_MPS, 6)


def _speed_choices(goal: Goal, config: ArenaConfig) -> tuple[np.ndarray, np.ndarray]:
    """Speeds (m/s) a target may have (fulfil with margin) and distractors may have (violate with margin)."""
    grid = _speed_grid(config)
    m = config.speed_margin_mps
    status = [goal.is_fulfilled(grid + d) for d in (-m, 0.0, m)]
    return grid[status[0] & status[1] & status[2]], grid[~(status[0] | status[1] | status[2])]


def check_task_goal(goal: Goal, config: ArenaConfig) -> None:
    """Raise ``ValueError`` unless ``goal`` can single out a target in this arena."""
    if goal.feature is Feature.DISTANCE:
        raise ValueError(f"task goal {goal}: distance goals cannot single out a victim; use a speed or direction goal")
    if goal.feature is Feature.SPEED:
        target, distractor = _speed_choices(goal, config)
        if target.size == 0 or (distractor.size == 0 and config.num_distractors > 0):
            raise ValueError(
                f"task goal {goal}: no speeds in [0, {config.max_mover_speed_mps}] m/s tell the target apart "
                f"from distractors with a margin of {config.speed_margin_mps} m/s"
            )


def _rubble_piece(rng: np.random.Generator, x: float, y: float) -> Rubble:
    kind = rng.integers(3)
    if kind == 0:
        return BoxRubble(x, y, rng.uniform(0.3, 1.0), rng.uniform(0.3, 1.0), rng.uniform(0.0, 180.0))
    if kind == 1:
        return CircleRubble(x, y, rng.uniform(0.15, 0.4))
    half = rng.uniform(0.4, 1.0)
    angle = rng.uniform(0.0, math.pi)
    dx, dy = half * math.cos(angle), half * math.sin(angle)
    return SegmentRubble((x - dx, y - dy), (x + dx, y + dy), 0.05)


def _segment_distances(points: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distances (m) from each of ``points`` ``(N, 2)`` to the segment ``a``–``b``, ``(N,)``
    (the same numbers as ``np.linalg.norm`` of the offsets, with less overhead)."""
    ab = b - a
    denom = float(ab @ ab)
    if denom == 0.0:
        offsets = a - points
    else:
        t = np.minimum(np.maximum((points - a) @ ab / denom, 0.0), 1.0)
        offsets = a + t[:, None] * ab - points
    squares = offsets * offsets
    return np.sqrt(squares[:, 0] + squares[:, 1])


class _Layout:
    """Free-space bookkeeping while placing bodies (discs of known extent)."""

    def __init__(self, config: ArenaConfig, rng: np.random.Generator) -> None:
        self.rng = rng
        self.low = np.array([_WALL_MARGIN_M, _WALL_MARGIN_M])
        self.high = np.array([config.width_m, config.height_m]) - _WALL_MARGIN_M
        self.rubble: list[Rubble] = []
        self._rubble_centres = np.empty((0, 2))
        self._rubble_extents = np.empty(0)
        self.discs: list[tuple[np.ndarray, float]] = []  # placed movers and robot: (centre, extent)

    def random_point(self, extent: float) -> np.ndarray:
        return self.rng.uniform(self.low + extent, self.high - extent)

    def add_rubble(self, piece: Rubble) -> None:
        self.rubble.append(piece)
        self._rubble_centres = np.vstack([self._rubble_centres, [piece.x_m, piece.y_m]])
        self._rubble_extents = np.append(self._rubble_extents, piece.extent_m)

    def clear_of_rubble(self, a: np.ndarray, b: np.ndarray, extent: float, gap: float = 0.15) -> bool:
        """Whether a body of ``extent`` (m) swept from ``a`` to ``b`` stays ``gap`` (m) clear of all rubble."""
        distances = _segment_distances(self._rubble_centres, a, b)
        return bool((distances > self._rubble_extents + extent + gap).all())

    def clear_of_discs(self, p: np.ndarray, extent: float, gap: float) -> bool:
        return all(np.linalg.norm(p - c) > e + extent + gap for c, e in self.discs)


def _place_rubble(layout: _Layout, count: int, robot_xy: np.ndarray) -> None:
    for _ in range(count):
        for _ in range(_PLACEMENT_ATTEMPTS):
            x, y = layout.random_point(0.5)
            piece = _rubble_piece(layout.rng, float(x), float(y))
            centre = np.array([piece.x_m, piece.y_m])
            if np.linalg.norm(centre - robot_xy) > piece.extent_m + 1.2 and layout.clear_of_rubble(
                centre, centre, piece.extent_m, gap=0.3
            ):
                layout.add_rubble(piece)
                break


def _patrol(layout: _Layout, start: np.ndarray, extent: float, speed: float) -> PathBehaviour | None:
    """A closed loop of straight legs through free space from ``start``, or None if none was found."""
    for _ in range(_PLACEMENT_ATTEMPTS):
        points = [start] + [layout.random_point(extent) for _ in range(_PATROL_WAYPOINTS - 1)]
        loop = points + [start]
        if all(layout.clear_of_rubble(a, b, extent) for a, b in zip(loop[:-1], loop[1:])):
            legs = tuple(Leg((round(float(p[0]), 6), round(float(p[1]), 6)), speed) for p in points[1:])
            return PathBehaviour(legs=legs, loop=True, face_motion=True)
    return None


def _place_mover(
    layout: _Layout, config: ArenaConfig, robot_xy: np.ndarray, name: str, kind: str, speed: float, behaviour=None
) -> MoverSpec:
    extent = 0.25 if kind == "victim" else 0.5 * math.hypot(0.626, 0.505)
    for _ in range(_PLACEMENT_ATTEMPTS):
        p = layout.random_point(extent)
        if np.linalg.norm(p - robot_xy) < config.min_start_distance_m:
            continue
        if not (layout.clear_of_rubble(p, p, extent, gap=0.3) and layout.clear_of_discs(p, extent, gap=0.5)):
            continue
        if behaviour is None and speed > 0.0:
            path = _patrol(layout, p, extent, speed)
            if path is None:
                continue
        else:
            path = behaviour
        layout.discs.append((p, extent))
        heading = float(layout.rng.uniform(-180.0, 180.0))
        start = Pose(round(float(p[0]), 6), round(float(p[1]), 6), round(heading, 6))
        return MoverSpec(name=name, kind=kind, start=start, behaviour=path)
    raise _NoRoom(
        f"could not place mover {name!r} in a {config.width_m} × {config.height_m} m arena; "
        "lower the rubble density or the number of distractors"
    )


def generate_arena(config: ArenaConfig, rng: np.random.Generator, goal: Goal | None = None) -> Scenario:
    """A random rescue arena whose task is to reach the victim that ``goal`` describes.

    Args:
        config: the arena's knobs.
        rng: every random draw comes from it (pass ``env.np_random``).
        goal: the episode's goal; ``None`` samples one from ``config.goals``.

    Raises:
        ValueError: when no room is left for a mover in ``_LAYOUT_ATTEMPTS`` layouts in a
            row (a crowded arena: fewer distractors or less rubble). A layout without room
            is drawn again, so a crowded arena fails on no single unlucky draw.
    """
    if goal is None:
        goal = config.goals[int(rng.integers(len(config.goals)))]
    check_task_goal(goal, config)
    for _ in range(_LAYOUT_ATTEMPTS):
        try:
            return _draw_arena(config, rng, goal)
        except _NoRoom as crowded:
            error = crowded
    raise ValueError(f"{error} (in {_LAYOUT_ATTEMPTS} layouts in a row)")


class _NoRoom(ValueError):
    """No room is left in a layout for a mover."""


def _draw_arena(config: ArenaConfig, rng: np.random.Generator, goal: Goal) -> Scenario:
    """One draw of ``generate_arena``'s layout for ``goal`` (checked); ``_NoRoom`` when a
    mover finds no room."""
    layout = _Layout(config, rng)
    robot_xy = layout.random_point(0.5)
    layout.discs.append((robot_xy, 0.5))
    _place_rubble(layout, config.rubble_count, robot_xy)

    distractor_kinds = ["victim" if i % 2 == 0 else "robot" for i in range(config.num_distractors)]
    lo, hi = config.distractor_speed_range_mps
    if goal.feature is Feature.SPEED:
        target_speeds, distractor_speeds = _speed_choices(goal, config)
        target_speed = float(rng.choice(target_speeds))
        speeds = [float(rng.choice(distractor_speeds)) for _ in distractor_kinds]
        target_behaviour = None
    else:
        speeds = [float(rng.uniform(lo, hi)) for _ in distractor_kinds]
        target_speed = float(rng.uniform(lo, hi))
        if goal.direction is Direction.TOWARDS:
            target_behaviour = PursueBehaviour(target_speed, stop_distance_m=config.pursue_stop_distance_m)
        elif goal.direction is Direction.AWAY:
            target_behaviour = EvadeBehaviour(target_speed)
        else:
            target_speed, target_behaviour = 0.0, None

    movers = [_place_mover(layout, config, robot_xy, "target", "victim", target_speed, target_behaviour)]
    for i, (kind, speed) in enumerate(zip(distractor_kinds, speeds)):
        movers.append(_place_mover(layout, config, robot_xy, f"{kind} {i + 1}", kind, speed))
    # shuffle so that the target's index in the observation carries no information
    order = rng.permutation(len(movers))
    movers = [movers[i] for i in order]
    return Scenario(
        name="rescue",
        bounds=(0.0, 0.0, config.width_m, config.height_m),
        robot=Pose(round(float(robot_xy[0]), 6), round(float(robot_xy[1]), 6), round(float(rng.uniform(-180, 180)), 6)),
        enclosed=True,
        rubble=tuple(layout.rubble),
        movers=tuple(movers),
        task=TaskSpec(target="target", goal=goal, time_limit_s=config.time_limit_s),
        duration_s=config.time_limit_s,
    )
