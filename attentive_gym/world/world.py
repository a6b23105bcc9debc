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

The world's control state (the robot's command and ramp, the clock, the movers' laws and
stops, the poses read back after each step) lives in numpy records, ``world.state``
(``world.state`` module); ``Robot`` and ``Mover`` read their attributes from them. A body
moved by hand through ``world.space`` shows in them (poses, velocities, ``geometry()``) after
the next step, or at once after ``world.read_back()``.
``World.step`` runs ``world.compiled.step_worlds`` for this one world: a compiled step, or
the pure-Python one (``World._step_python``) where pymunk's internals are not the tested
ones.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pymunk

from attentive_gym import _pymunk_access
from attentive_gym.sensors.geometry import GeometryCache, SceneGeometry
from attentive_gym.world import compiled
from attentive_gym.world.behaviours import EvadeMotion, PathMotion, PursueMotion, make_motion
from attentive_gym.world.robot import ROBOT_COLLISION_TYPE, Robot, RobotConfig
from attentive_gym.world.scenario import BoxRubble, CircleRubble, MoverSpec, Scenario, SegmentRubble, WallSpec
from attentive_gym.world.state import mover_records, robot_record

__all__ = [
    "Entity",
    "Mover",
    "World",
    "WorldState",
    "ROBOT_ID",
    "PHYSICS_DT_S",
    "physics_substeps",
    "MOVER_COLLISION_TYPE",
    "STATIC_COLLISION_TYPE",
]

ROBOT_ID = 0
#: The world's default largest physics sub-step (s).
PHYSICS_DT_S = 0.025


def physics_substeps(dt_s: float, physics_dt_s: float = PHYSICS_DT_S) -> int:
    """How many equal physics sub-steps, none longer than ``physics_dt_s`` (s), a world's step
    of ``dt_s`` seconds takes."""
    return max(1, math.ceil(dt_s / physics_dt_s - 1e-9))


MOVER_COLLISION_TYPE = 2
STATIC_COLLISION_TYPE = 3
_STATIC_FRICTION = 0.8


@dataclass(frozen=True)
class Entity:
    """One body of the world: its id, kind (robot, victim, wall, rubble) and name."""

    id: int
    kind: str
    name: str


@dataclass(frozen=True, eq=False)
class WorldState:
    """A world's control state as numpy records (``world.state`` module), the arrays the
    compiled step reads and writes; kept for the world's life (never replaced).

    Attributes:
        world: ``(1,)`` ``WORLD_DTYPE``: the robot's command, ramp and limits, the clock,
            the touch flag, the robot's pose and velocity after the last step.
        movers: ``(M,)`` ``MOVER_DTYPE``, in scenario order: laws, stops, poses and
            velocities after the last step.
        knots: ``(K, 3)`` float64 path knots (t s, x m, y m).
    """

    world: np.ndarray
    movers: np.ndarray
    knots: np.ndarray


class Mover:
    """A scripted moving body (victim or robot) with its motion law.

    Args:
        entity: its id, kind and name.
        spec: what to build.
        motion: its law (``behaviours.make_motion``), ``None`` for a body that stays still.
        records: the world's ``(M,)`` ``MOVER_DTYPE`` records; ``index``: this mover's row.
    """

    def __init__(
        self,
        entity: Entity,
        spec: MoverSpec,
        motion: PathMotion | PursueMotion | EvadeMotion | None,
        records: np.ndarray,
        index: int,
    ) -> None:
        self.entity = entity
        self.spec = spec
        self.motion = motion
        self._records = records
        self._index = index
        self.body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        self.body.position = (spec.start.x_m, spec.start.y_m)
        self.body.angle = math.radians(spec.start.heading_deg)
        if spec.kind == "victim":
            self.shape: pymunk.Shape = pymunk.Circle(self.body, spec.radius_m)
        else:
            self.shape = pymunk.Poly.create_box(self.body, (spec.length_m, spec.width_m))
        self.shape.collision_type = MOVER_COLLISION_TYPE
        self.shape.friction = _STATIC_FRICTION

    @property
    def script_delay_s(self) -> float:
        """How long the robot has paused a path's schedule (s)."""
        return float(self._records["script_delay_s"][self._index])

    @property
    def touching_robot(self) -> tuple[float, float] | None:
        """The unit vector towards the robot while touching it (until the next step drives
        the mover), else ``None``."""
        row = self._records[self._index]
        if not row["touching"]:
            return None
        x, y = row["towards_robot"].tolist()
        return x, y

    @property
    def blocked(self) -> bool:
        """Whether the robot stopped the mover during the last step."""
        return bool(self._records["blocked"][self._index])

    def drive(self, t_s: float, h_s: float, robot_xy) -> None:
        """Set the velocity that follows the script over ``[t_s, t_s + h_s]`` (the
        pure-Python step's version of the compiled ``_drive_mover``).

        Called once per environment step: an unblocked body is exactly on its path at every
        step boundary and moves in a straight line in between. A body that touches the robot
        and would not move away from it waits instead, and a path's schedule is delayed by
        the step.
        """
        motion = self.motion
        if motion is None:
            return
        body = self.body
        records, i = self._records, self._index  # field first, then row: the cheap way round
        script_delay_s = records["script_delay_s"].item(i)
        if records["blocked"][i] and motion.follows_clock:
            script_delay_s += h_s  # stopped part-way through the last step: redo it
        records["blocked"][i] = 0
        vx, vy = motion.velocity(t_s - script_delay_s, h_s, _pymunk_access.position(body), robot_xy)
        if records["touching"][i]:
            records["touching"][i] = 0
            if _not_leaving(vx, vy, records["towards_robot"][i].tolist()):
                vx = vy = 0.0
                if motion.follows_clock:
                    script_delay_s += h_s
        records["script_delay_s"][i] = script_delay_s
        _pymunk_access.set_velocity(body, vx, vy)
        if motion.face_motion and (vx or vy):
            _pymunk_access.set_angle(body, math.atan2(vy, vx))


def _not_leaving(vx: float, vy: float, towards_robot: tuple[float, float]) -> bool:
    """Whether a mover moving at ``(vx, vy)`` m/s heads into, or slides along, the robot it
    touches (sliding would drag the robot by friction): anything but moving away."""
    return (vx != 0.0 or vy != 0.0) and vx * towards_robot[0] + vy * towards_robot[1] >= 0.0


def _note_robot_contact(arbiter: pymunk.Arbiter, space: pymunk.Space, world: np.ndarray) -> None:
    """pre_solve of every contact of the robot: Chipmunk calls it in each physics sub-step in
    which the robot touches a shape (an arbiter with contact points), the same contacts
    ``Robot.in_contact`` counts after the sub-step; an untouched robot pays nothing.
    ``world`` is the world's ``(1,)`` record; it sets ``touched``."""
    world["touched"] = 1


def _stop_mover_at_robot(arbiter: pymunk.Arbiter, space: pymunk.Space, movers: tuple[np.ndarray, dict]) -> None:
    """pre_solve of robot-mover contacts: a mover not moving away from the robot stops at once.

    A stopped mover is then an obstacle like a wall; the contact with one moving away is
    frictionless, so it cannot drag the robot along. Runs in every physics sub-step in
    which the two touch (pymunk calls it only then), so an untouched world pays nothing.
    ``movers`` is the world's ``(M,)`` mover records and a map from a mover's shape to its
    row; it sets the row's ``touching``, ``towards_robot`` and ``blocked``.
    """
    records, index = movers
    robot_shape, mover_shape = arbiter.shapes
    row = records[index[mover_shape]]  # a view of the mover's record
    normal = arbiter.normal  # from the robot (shape a) to the mover (shape b)
    towards_robot = (-normal.x, -normal.y)
    row["touching"] = 1
    row["towards_robot"] = towards_robot
    body = mover_shape.body
    vx, vy = _pymunk_access.velocity(body)
    if _not_leaving(vx, vy, towards_robot):
        _pymunk_access.set_velocity(body, 0.0, 0.0)
        row["blocked"] = 1
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

    Attributes:
        geometry_cache: the ``GeometryCache`` of the robot, the movers, walls and rubble
            (owners = entity ids), from which ``geometry()`` places the scene; a batched
            sensor read stacks the members' caches (``sensors.SceneStack``).

    Raises:
        ValueError: if the robot or a mover starts overlapping another body.
    """

    def __init__(
        self, scenario: Scenario, robot_config: RobotConfig = RobotConfig(), physics_dt_s: float = PHYSICS_DT_S
    ):
        if not (math.isfinite(physics_dt_s) and physics_dt_s > 0.0):
            raise ValueError(f"physics_dt_s must be a finite number > 0, got {physics_dt_s!r}")
        self.scenario = scenario
        self.physics_dt_s = physics_dt_s
        self.space = pymunk.Space()
        self.space.gravity = (0.0, 0.0)
        bounds = self._free_bounds()
        motions = [
            None
            if spec.behaviour is None
            else make_motion(spec.behaviour, (spec.start.x_m, spec.start.y_m), bounds, spec.extent_m)
            for spec in scenario.movers
        ]
        self.state = WorldState(robot_record(robot_config, physics_dt_s), *mover_records(motions))
        self.robot = Robot(
            self.space,
            robot_config,
            (scenario.robot.x_m, scenario.robot.y_m, math.radians(scenario.robot.heading_deg)),
            self.state.world,
        )
        self.entities: list[Entity] = [Entity(ROBOT_ID, "robot", "attentive robot")]
        self.movers: list[Mover] = []
        for i, (spec, motion) in enumerate(zip(scenario.movers, motions)):
            mover = Mover(self._new_entity(spec.kind, spec.name), spec, motion, self.state.movers, i)
            self.space.add(mover.body, mover.shape)
            self.movers.append(mover)
        self.read_back()
        if self.movers:
            self.space.on_collision(
                ROBOT_COLLISION_TYPE,
                MOVER_COLLISION_TYPE,
                pre_solve=_stop_mover_at_robot,
                data=(self.state.movers, {m.shape: i for i, m in enumerate(self.movers)}),
            )
        self.space.on_collision(ROBOT_COLLISION_TYPE, None, pre_solve=_note_robot_contact, data=self.state.world)
        self.static: list[tuple[Entity, pymunk.Shape]] = []  # walls and rubble
        for i, wall in enumerate(self.wall_specs):
            self._add_static(self._new_entity("wall", f"wall {i}"), _wall_shape(self.space.static_body, wall))
        for i, piece in enumerate(scenario.rubble):
            self._add_static(self._new_entity("rubble", f"rubble {i}"), _rubble_shape(self.space.static_body, piece))
        self._check_no_overlap()
        self.geometry_cache = GeometryCache(
            [(ROBOT_ID, self.robot.body, [self.robot.shape])]
            + [(m.entity.id, m.body, [m.shape]) for m in self.movers]
            + [(entity.id, self.space.static_body, [shape]) for entity, shape in self.static]
        )
        self._kernel_row: np.ndarray | None = None

    def __getstate__(self) -> dict:
        state = self.__dict__.copy()
        state["_kernel_row"] = None  # addresses: a copy has its own
        state.pop("_mover_names", None)
        state.pop("_mover_handles", None)
        return state

    @property
    def time_s(self) -> float:
        """The world's clock (s): ``clock_start_s + steps_taken · clock_dt_s`` of
        ``state.world``, restarted when the step length changes (a product, not a running
        sum, so that it does not drift)."""
        return float(self.state.world["time_s"][0])

    def kernel_row(self) -> np.ndarray:
        """``(1, compiled.ROW_SIZE)`` int64: the addresses of this world's records and of its
        Chipmunk space and bodies, and the record counts, as the compiled step reads them.
        Valid while the world lives; a copy or an unpickled world computes its own."""
        row = self._kernel_row
        if row is None:
            handles = np.array([_pymunk_access.handle(m.body) for m in self.movers], dtype=np.int64)
            self._mover_handles = handles  # kept alive with the row that points at it
            state = self.state
            row = np.zeros((1, compiled.ROW_SIZE), dtype=np.int64)
            row[0, compiled.ROW_WORLD] = state.world.ctypes.data
            row[0, compiled.ROW_MOVERS] = state.movers.ctypes.data
            row[0, compiled.ROW_NUM_MOVERS] = len(state.movers)
            row[0, compiled.ROW_KNOTS] = state.knots.ctypes.data
            row[0, compiled.ROW_NUM_KNOTS] = len(state.knots)
            row[0, compiled.ROW_SPACE] = _pymunk_access.handle(self.space)
            row[0, compiled.ROW_ROBOT] = _pymunk_access.handle(self.robot.body)
            row[0, compiled.ROW_CONTROL] = _pymunk_access.handle(self.robot.control)
            row[0, compiled.ROW_MOVER_BODIES] = handles.ctypes.data
            self._kernel_row = row
        return row

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

    @property
    def wall_specs(self) -> list[WallSpec]:
        """Every wall of the world: the enclosure's (when the scenario is enclosed), then the scenario's."""
        return self._enclosure() + list(self.scenario.walls)

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

        The same call as ``compiled.step_worlds`` with this one world.

        Returns:
            Whether the robot touched another body during the step.

        Raises:
            ValueError: ``dt_s`` is not a finite number > 0, or a command is not finite.
        """
        return bool(compiled.step_worlds((self,), dt_s, ((linear_mps, angular_rps),))[0])

    def _step_python(self, dt_s: float, linear_mps: float, angular_rps: float) -> bool:
        """The pure-Python step (checked arguments): what the compiled step does, in Python."""
        world = self.state.world
        time_s = world["time_s"].item(0)
        if dt_s != world["clock_dt_s"][0]:
            world["clock_start_s"], world["clock_dt_s"], world["steps_taken"] = time_s, dt_s, 0
        substeps = self.substeps(dt_s)
        h = dt_s / substeps
        robot = self.robot
        robot.command(linear_mps, angular_rps)
        if self.movers:
            robot_xy = _pymunk_access.position(robot.body)
            for mover in self.movers:
                mover.drive(time_s, dt_s, robot_xy)
        world["touched"] = 0
        space = self.space
        for _ in range(substeps):
            robot.drive(h)
            space.step(h)
        steps_taken = world["steps_taken"].item(0) + 1
        world["steps_taken"] = steps_taken
        world["time_s"] = world["clock_start_s"].item(0) + steps_taken * dt_s
        self.read_back()
        return bool(world["touched"][0])

    def read_back(self) -> None:
        """Copy the robot's and the movers' poses and velocities from pymunk into
        ``state`` (the compiled step does it after every step)."""
        self.robot.read_back()
        if self.movers:
            bodies = [mover.body for mover in self.movers]
            records = self.state.movers
            records["pose"] = np.array(_pymunk_access.poses(bodies)).reshape(-1, 3)
            records["velocity"] = [_pymunk_access.velocity(body) for body in bodies]

    def substeps(self, dt_s: float) -> int:
        """How many equal physics sub-steps, none longer than ``physics_dt_s``, a ``step`` of
        ``dt_s`` seconds takes (``physics_substeps``)."""
        return physics_substeps(dt_s, self.physics_dt_s)

    def geometry(self) -> SceneGeometry:
        """The scene's world-frame geometry after the last step, with owners = entity ids
        (its moving bodies at ``moving_poses()``)."""
        return self.geometry_cache.update(self.moving_poses())

    def moving_poses(self) -> np.ndarray:
        """``(1 + M, 3)`` float64 (x m, y m, angle rad) of the robot and the movers after the
        last step, in the order of ``GeometryCache.moving_bodies`` of ``geometry()``'s cache
        (robot, then movers in scenario order); a new array."""
        poses = np.empty((1 + len(self.movers), 3))
        poses[0] = self.state.world["robot_pose"][0]
        poses[1:] = self.state.movers["pose"]
        return poses

    @property
    def mover_names(self) -> tuple[str, ...]:
        """The movers' names, in scenario order."""
        names = self.__dict__.get("_mover_names")
        if names is None or len(names) != len(self.movers):
            names = self._mover_names = tuple(m.entity.name for m in self.movers)
        return names

    def mover_positions(self) -> np.ndarray:
        """``(M, 2)`` mover centres (m) after the last step (a new array)."""
        return self.state.movers["pose"][:, :2].copy()

    def mover_velocities(self) -> np.ndarray:
        """``(M, 2)`` mover velocities (m/s) after the last step (a new array)."""
        return self.state.movers["velocity"].copy()


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
