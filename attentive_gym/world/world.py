"""The pymunk rescue world built from a ``Scenario``.

- ``Entity``: one thing in the world with an integer id (the owner id the sensors report).
- ``Mover``: a scripted kinematic body and its motion law.
- ``World``: the space, the attentive robot, walls, rubble and movers; advances time in
  fixed physics sub-steps and hands the sensors the scene's geometry.

The space is public (``world.space``), as is the robot's body (``world.robot.body``), so
users can add bodies and tests can check sensors against pymunk's own queries. Ids: the
robot is 0, movers 1..M in scenario order, then walls (enclosure first) and rubble.
Scripted movers are kinematic: they follow their scripts exactly and are not pushed back;
walls and rubble are static. A mover never pushes the attentive robot: one that touches it
stops unless it is moving away (a path mover's schedule pauses, so it resumes where it
stopped), as a real robot or person would, instead of crushing it against rubble.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pymunk

from attentive_gym import _pymunk_access
from attentive_gym.sensors.geometry import GeometryCache, SceneGeometry
from attentive_gym.world.behaviours import make_motion
from attentive_gym.world.robot import ROBOT_COLLISION_TYPE, Robot, RobotConfig
from attentive_gym.world.scenario import BoxRubble, CircleRubble, MoverSpec, Scenario, SegmentRubble, WallSpec

__all__ = ["Entity", "Mover", "World", "ROBOT_ID", "MOVER_COLLISION_TYPE", "STATIC_COLLISION_TYPE"]

ROBOT_ID = 0
MOVER_COLLISION_TYPE = 2
STATIC_COLLISION_TYPE = 3
_STATIC_FRICTION = 0.8


@dataclass(frozen=True)
class Entity:
    """One body of the world: its id, kind (robot, victim, wall, rubble) and name."""

    id: int
    kind: str
    name: str


class Mover:
    """A scripted moving body (victim or robot) with its motion law."""

    def __init__(self, entity: Entity, spec: MoverSpec, bounds: tuple[float, float, float, float]) -> None:
        self.entity = entity
        self.spec = spec
        self.body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        self.body.position = (spec.start.x_m, spec.start.y_m)
        self.body.angle = math.radians(spec.start.heading_deg)
        if spec.kind == "victim":
            self.shape: pymunk.Shape = pymunk.Circle(self.body, spec.radius_m)
        else:
            self.shape = pymunk.Poly.create_box(self.body, (spec.length_m, spec.width_m))
        self.shape.collision_type = MOVER_COLLISION_TYPE
        self.shape.friction = _STATIC_FRICTION
        start = (spec.start.x_m, spec.start.y_m)
        self.motion = None if spec.behaviour is None else make_motion(spec.behaviour, start, bounds, spec.extent_m)
        self.script_delay_s = 0.0  # how long a path's schedule has been paused by the robot (s)
        self.touching_robot: tuple[float, float] | None = None  # unit vector towards the robot, while touching
        self.blocked = False  # stopped by the robot during the last step

    def drive(self, t_s: float, h_s: float, robot_xy) -> None:
        """Set the velocity that follows the script over ``[t_s, t_s + h_s]``.

        Called once per environment step: an unblocked body is exactly on its path at every
        step boundary and moves in a straight line in between. A body that touches the robot
        and would not move away from it waits instead, and a path's schedule is delayed by
        the step.
        """
        motion = self.motion
        if motion is None:
            return
        body = self.body
        if self.blocked and motion.follows_clock:
            self.script_delay_s += h_s  # stopped part-way through the last step: redo it
        self.blocked = False
        vx, vy = motion.velocity(t_s - self.script_delay_s, h_s, _pymunk_access.position(body), robot_xy)
        towards_robot = self.touching_robot
        if towards_robot is not None:
            self.touching_robot = None
            if _not_leaving(vx, vy, towards_robot):
                vx = vy = 0.0
                if motion.follows_clock:
                    self.script_delay_s += h_s
        _pymunk_access.set_velocity(body, vx, vy)
        if motion.face_motion and (vx or vy):
            _pymunk_access.set_angle(body, math.atan2(vy, vx))


def _not_leaving(vx: float, vy: float, towards_robot: tuple[float, float]) -> bool:
    """Whether a mover moving at ``(vx, vy)`` m/s heads into, or slides along, the robot it
    touches (sliding would drag the robot by friction): anything but moving away."""
    return (vx != 0.0 or vy != 0.0) and vx * towards_robot[0] + vy * towards_robot[1] >= 0.0


def _note_robot_contact(arbiter: pymunk.Arbiter, space: pymunk.Space, touched: list[bool]) -> None:
    """pre_solve of every contact of the robot: Chipmunk calls it in each physics sub-step in
    which the robot touches a shape (an arbiter with contact points), the same contacts
    ``Robot.in_contact`` counts after the sub-step; an untouched robot pays nothing."""
    touched[0] = True


def _stop_mover_at_robot(arbiter: pymunk.Arbiter, space: pymunk.Space, movers: dict) -> None:
    """pre_solve of robot-mover contacts: a mover not moving away from the robot stops at once.

    A stopped mover is then an obstacle like a wall; the contact with one moving away is
    frictionless, so it cannot drag the robot along. Runs in every physics sub-step in
    which the two touch (pymunk calls it only then), so an untouched world pays nothing.
    ``movers`` maps a mover's shape to its ``Mover``.
    """
    robot_shape, mover_shape = arbiter.shapes
    mover = movers[mover_shape]
    normal = arbiter.normal  # from the robot (shape a) to the mover (shape b)
    towards_robot = (-normal.x, -normal.y)
    mover.touching_robot = towards_robot
    vx, vy = _pymunk_access.velocity(mover.body)
    if _not_leaving(vx, vy, towards_robot):
        _pymunk_access.set_velocity(mover.body, 0.0, 0.0)
        mover.blocked = True
    elif vx or vy:
        arbiter.friction = 0.0


class World:
    """A rescue world: pymunk space, attentive robot, static geometry and scripted movers.

    Args:
        scenario: what to build.
        robot_config: the attentive robot's physical parameters.
        physics_dt_s: the largest physics sub-step (s); each ``step`` is split into equal
            sub-steps no longer than this. At the default 25 ms a robot at full speed
            (0.7 m/s) moves under 2 cm per sub-step, far less than a wall's thickness,
            so it cannot tunnel through one.

    Raises:
        ValueError: if the robot or a mover starts overlapping another body.
    """

    def __init__(self, scenario: Scenario, robot_config: RobotConfig = RobotConfig(), physics_dt_s: float = 0.025):
        if not (math.isfinite(physics_dt_s) and physics_dt_s > 0.0):
            raise ValueError(f"physics_dt_s must be a finite number > 0, got {physics_dt_s!r}")
        self.scenario = scenario
        self.physics_dt_s = physics_dt_s
        self.space = pymunk.Space()
        self.space.gravity = (0.0, 0.0)
        self.robot = Robot(
            self.space, robot_config, (scenario.robot.x_m, scenario.robot.y_m, math.radians(scenario.robot.heading_deg))
        )
        self.entities: list[Entity] = [Entity(ROBOT_ID, "robot", "attentive robot")]
        self.movers: list[Mover] = []
        for spec in scenario.movers:
            mover = Mover(self._new_entity(spec.kind, spec.name), spec, self._free_bounds())
            self.space.add(mover.body, mover.shape)
            self.movers.append(mover)
        if self.movers:
            self.space.on_collision(
                ROBOT_COLLISION_TYPE,
                MOVER_COLLISION_TYPE,
                pre_solve=_stop_mover_at_robot,
                data={m.shape: m for m in self.movers},
            )
        self._robot_touched = [False]  # set by _note_robot_contact while the robot touches anything
        self.space.on_collision(ROBOT_COLLISION_TYPE, None, pre_solve=_note_robot_contact, data=self._robot_touched)
        self.static: list[tuple[Entity, pymunk.Shape]] = []  # walls and rubble
        for i, wall in enumerate(self._enclosure() + list(scenario.walls)):
            self._add_static(self._new_entity("wall", f"wall {i}"), _wall_shape(self.space.static_body, wall))
        for i, piece in enumerate(scenario.rubble):
            self._add_static(self._new_entity("rubble", f"rubble {i}"), _rubble_shape(self.space.static_body, piece))
        self._check_no_overlap()
        self._geometry = GeometryCache(
            [(ROBOT_ID, self.robot.body, [self.robot.shape])]
            + [(m.entity.id, m.body, [m.shape]) for m in self.movers]
            + [(entity.id, self.space.static_body, [shape]) for entity, shape in self.static]
        )
        self.time_s = 0.0
        # the clock: time_s = _clock_start_s + _steps_taken · _clock_dt_s, restarted when the
        # step length changes (a product, not a running sum, so that it does not drift)
        self._clock_start_s = 0.0
        self._clock_dt_s = math.nan
        self._steps_taken = 0

    def _new_entity(self, kind: str, name: str) -> Entity:
        entity = Entity(len(self.entities), kind, name)
        self.entities.append(entity)
        return entity

    def _add_static(self, entity: Entity, shape: pymunk.Shape) -> None:
        shape.collision_type = STATIC_COLLISION_TYPE
        shape.friction = _STATIC_FRICTION
        self.space.add(shape)
        self.static.append((entity, shape))

    def _free_bounds(self) -> tuple[float, float, float, float]:
        """The bounds (m) inside the enclosure walls' inner faces (the bounds themselves
        when the scenario is not enclosed): where an evading mover may go."""
        inset = 0.5 * WallSpec.thickness_m if self.scenario.enclosed else 0.0
        x0, y0, x1, y1 = self.scenario.bounds
        return (x0 + inset, y0 + inset, x1 - inset, y1 - inset)

    def _enclosure(self) -> list[WallSpec]:
        """Walls centred on the bounds (half their thickness lies outside)."""
        if not self.scenario.enclosed:
            return []
        x0, y0, x1, y1 = self.scenario.bounds
        corners = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
        return [WallSpec(corners[i], corners[(i + 1) % 4]) for i in range(4)]

    def _check_no_overlap(self) -> None:
        owner = {id(m.shape): m.entity for m in self.movers}
        owner.update({id(shape): entity for entity, shape in self.static})
        owner[id(self.robot.shape)] = self.entities[ROBOT_ID]
        for subject in [self.robot.shape] + [m.shape for m in self.movers]:
            for hit in self.space.shape_query(subject):
                other = owner.get(id(hit.shape))
                if other is not None and hit.contact_point_set.points:
                    raise ValueError(
                        f"scenario {self.scenario.name!r}: {owner[id(subject)].name} starts overlapping {other.name}"
                    )

    def step(self, dt_s: float, linear_mps: float, angular_rps: float) -> bool:
        """Advance the world by ``dt_s`` seconds with the robot commanded to the given velocities.

        Returns:
            Whether the robot touched another body during the step.

        Raises:
            ValueError: ``dt_s`` is not a finite number > 0, or a command is not finite.
        """
        if not (isinstance(dt_s, (int, float)) and math.isfinite(dt_s) and dt_s > 0.0):
            raise ValueError(f"dt_s must be a finite number of seconds > 0, got {dt_s!r}")
        if dt_s != self._clock_dt_s:
            self._clock_start_s, self._clock_dt_s, self._steps_taken = self.time_s, dt_s, 0
        substeps = self.substeps(dt_s)
        h = dt_s / substeps
        robot = self.robot
        robot.command(linear_mps, angular_rps)
        if self.movers:
            robot_xy = _pymunk_access.position(robot.body)
            t_s = self.time_s
            for mover in self.movers:
                mover.drive(t_s, dt_s, robot_xy)
        touched = self._robot_touched
        touched[0] = False
        space = self.space
        for _ in range(substeps):
            robot.drive(h)
            space.step(h)
        self._steps_taken += 1
        self.time_s = self._clock_start_s + self._steps_taken * dt_s
        return touched[0]

    def substeps(self, dt_s: float) -> int:
        """How many equal physics sub-steps, none longer than ``physics_dt_s``, a ``step`` of
        ``dt_s`` seconds takes."""
        return max(1, math.ceil(dt_s / self.physics_dt_s - 1e-9))

    def geometry(self) -> SceneGeometry:
        """The scene's world-frame geometry now, with owners = entity ids."""
        return self._geometry.update()

    @property
    def mover_names(self) -> tuple[str, ...]:
        """The movers' names, in scenario order."""
        names = self.__dict__.get("_mover_names")
        if names is None or len(names) != len(self.movers):
            names = self._mover_names = tuple(m.entity.name for m in self.movers)
        return names

    def mover_positions(self) -> np.ndarray:
        """``(M, 2)`` mover centres (m)."""
        xy: list[float] = []
        for m in self.movers:
            xy += _pymunk_access.position(m.body)
        return np.array(xy, dtype=float).reshape(-1, 2)

    def mover_velocities(self) -> np.ndarray:
        """``(M, 2)`` mover velocities (m/s)."""
        v: list[float] = []
        for m in self.movers:
            v += _pymunk_access.velocity(m.body)
        return np.array(v, dtype=float).reshape(-1, 2)


def _wall_shape(body: pymunk.Body, wall: WallSpec) -> pymunk.Poly:
    """A box polygon of the wall's thickness around the segment ``start``–``end``."""
    (ax, ay), (bx, by) = wall.start, wall.end
    length = math.hypot(bx - ax, by - ay)
    nx, ny = -(by - ay) / length * wall.thickness_m / 2, (bx - ax) / length * wall.thickness_m / 2
    return pymunk.Poly(body, [(ax - nx, ay - ny), (bx - nx, by - ny), (bx + nx, by + ny), (ax + nx, ay + ny)])


def _rubble_shape(body: pymunk.Body, piece) -> pymunk.Shape:
    if isinstance(piece, BoxRubble):
        transform = pymunk.Transform.translation(piece.x_m, piece.y_m).rotated(math.radians(piece.angle_deg))
        half_w, half_h = piece.width_m / 2, piece.height_m / 2
        corners = [(-half_w, -half_h), (half_w, -half_h), (half_w, half_h), (-half_w, half_h)]
        return pymunk.Poly(body, corners, transform)
    if isinstance(piece, CircleRubble):
        return pymunk.Circle(body, piece.radius_m, (piece.x_m, piece.y_m))
    if isinstance(piece, SegmentRubble):
        return pymunk.Segment(body, piece.start, piece.end, piece.radius_m)
    raise TypeError(f"unknown rubble {type(piece).__name__}")
