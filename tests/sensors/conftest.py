"""Shared helpers for the sensor tests: random pymunk scenes and pymunk's own queries as oracle.

Exposed as the ``pm`` fixture (a namespace), because the suite runs with
``--import-mode=importlib`` where test modules cannot import each other.
"""

from __future__ import annotations

import math
import types
from dataclasses import dataclass

import numpy as np
import pymunk
import pytest

from attentive_gym.sensors import GeometryCache, SceneGeometry

ROBOT_ID = 0
#: pymunk categories: the robot (left out of every oracle query, as the casters leave
#: out ``exclude_owner``), the capsules (``Segment`` with radius > 0), and the exact
#: stand-in of every capsule (a rectangle ``Poly`` plus two ``Circle``s, same body).
ROBOT_CATEGORY = 0b10
CAPSULE_CATEGORY = 0b100
STAND_IN_CATEGORY = 0b1000
_ALL = pymunk.ShapeFilter.ALL_MASKS()
#: pymunk's own shapes, capsules included.
QUERY_FILTER = pymunk.ShapeFilter(mask=_ALL ^ ROBOT_CATEGORY ^ STAND_IN_CATEGORY)
#: Capsules replaced by their stand-ins. Chipmunk's capsule ray query has a blind spot:
#: from a start inside the band |distance to the axis| < r beyond an end, a ray whose
#: line crosses the near flat side returns only that side (often the exit point) and
#: never tests the end caps (``cpSegmentShapeSegmentQuery``; see
#: ``test_pymunk_capsule_query_has_a_blind_spot``). Its ``Poly`` and ``Circle``
#: queries are exact, so the stand-ins give the exact answer everywhere.
EXACT_FILTER = pymunk.ShapeFilter(mask=_ALL ^ ROBOT_CATEGORY ^ CAPSULE_CATEGORY)
#: An origin must be at least this far outside every (non-robot) shape (m).
ORIGIN_CLEARANCE_M = 1e-3


@dataclass
class Scene:
    """A pymunk space, the ``(owner, body, shapes)`` entries and the owner of every shape."""

    space: pymunk.Space
    entries: list
    owner_of: dict
    robot: pymunk.Body

    def cache(self) -> GeometryCache:
        return GeometryCache(self.entries)

    def add(self, owner: int, body: pymunk.Body, shapes: list) -> None:
        if body is not self.space.static_body and body not in self.space.bodies:
            self.space.add(body)
        self.space.add(*shapes)
        self.entries.append((owner, body, shapes))
        for shape in shapes:
            self.owner_of[shape] = owner
            if isinstance(shape, pymunk.Segment) and shape.radius > 0.0:
                shape.filter = pymunk.ShapeFilter(categories=CAPSULE_CATEGORY)
                for stand_in in capsule_stand_ins(shape):
                    stand_in.filter = pymunk.ShapeFilter(categories=STAND_IN_CATEGORY)
                    self.space.add(stand_in)
                    self.owner_of[stand_in] = owner

    def capsules(self, exclude_owner: int = ROBOT_ID) -> list[tuple[np.ndarray, np.ndarray, float]]:
        """World ``(a, b, r)`` of every capsule not owned by ``exclude_owner``."""
        return [
            (np.array(shape.body.local_to_world(shape.a)), np.array(shape.body.local_to_world(shape.b)), shape.radius)
            for owner, _, shapes in self.entries
            if owner != exclude_owner
            for shape in shapes
            if isinstance(shape, pymunk.Segment) and shape.radius > 0.0
        ]

    def in_capsule_blind_spot(self, origin) -> bool:
        """Whether ``origin`` lies in the band of a capsule beyond its ends (where
        pymunk's capsule ray query is not exact; see ``EXACT_FILTER``)."""
        o = np.asarray(origin, float)
        for a, b, r in self.capsules():
            axis = b - a
            along = np.dot(o - a, axis) / np.dot(axis, axis)
            across = abs(axis[0] * (o - a)[1] - axis[1] * (o - a)[0]) / np.linalg.norm(axis)
            if across < r and not 0.0 <= along <= 1.0:
                return True
        return False


def capsule_stand_ins(capsule: pymunk.Segment) -> list[pymunk.Shape]:
    """The capsule as a rectangle ``Poly`` and two end ``Circle``s on the same body."""
    a, b, r = np.array(capsule.a), np.array(capsule.b), capsule.radius
    normal = np.array([a[1] - b[1], b[0] - a[0]]) / np.linalg.norm(b - a) * r
    corners = [tuple(a + normal), tuple(a - normal), tuple(b - normal), tuple(b + normal)]
    body = capsule.body
    return [pymunk.Poly(body, corners), pymunk.Circle(body, r, tuple(a)), pymunk.Circle(body, r, tuple(b))]


def _random_shape(rng: np.random.Generator, body: pymunk.Body, centre, kind: str) -> pymunk.Shape:
    """A shape of ``kind`` near ``centre`` (local coordinates of ``body``)."""
    cx, cy = centre
    size = rng.uniform(0.2, 1.2)
    if kind in ("poly", "rounded poly"):
        angles = np.sort(rng.uniform(0, 2 * np.pi, rng.integers(3, 8)))
        radii = size * rng.uniform(0.5, 1.0, len(angles))
        points = [(cx + r * math.cos(a), cy + r * math.sin(a)) for r, a in zip(radii, angles)]
        radius = rng.uniform(0.05, 0.3) if kind == "rounded poly" else 0.0
        return pymunk.Poly(body, points, None, radius)
    if kind in ("segment", "capsule"):
        a = rng.uniform(0, 2 * np.pi)
        half = (size * math.cos(a), size * math.sin(a))
        radius = rng.uniform(0.05, 0.3) if kind == "capsule" else 0.0
        return pymunk.Segment(body, (cx - half[0], cy - half[1]), (cx + half[0], cy + half[1]), radius)
    if kind == "circle":
        return pymunk.Circle(body, size * 0.7, (cx, cy))
    raise ValueError(kind)


SHAPE_KINDS = ("poly", "rounded poly", "segment", "capsule", "circle")


def random_scene(
    seed: int, num_static: int = 10, num_moving: int = 6, kinds=SHAPE_KINDS, arena_m: float = 8.0
) -> Scene:
    """A seeded scene: static shapes on ``space.static_body`` (one owner each), a placed
    static body, dynamic and kinematic bodies (some with a centre of gravity off their
    origin) carrying 1-3 shapes each at random poses, and the robot (owner 0, masked
    out of the oracle's queries). Shapes may overlap; nothing is stepped."""
    rng = np.random.default_rng(seed)
    space = pymunk.Space()
    robot = pymunk.Body(14.0, 1.0)
    robot.position = tuple(rng.uniform(-arena_m, arena_m, 2))
    robot.angle = rng.uniform(-np.pi, np.pi)
    robot_shape = pymunk.Poly.create_box(robot, (0.626, 0.505))
    robot_shape.filter = pymunk.ShapeFilter(categories=ROBOT_CATEGORY)
    scene = Scene(space, [], {}, robot)
    scene.add(ROBOT_ID, robot, [robot_shape])
    owner = 1
    for _ in range(num_static):
        kind = kinds[rng.integers(len(kinds))]
        centre = rng.uniform(-arena_m, arena_m, 2)
        scene.add(owner, space.static_body, [_random_shape(rng, space.static_body, centre, kind)])
        owner += 1
    placed = pymunk.Body(body_type=pymunk.Body.STATIC)
    placed.position = tuple(rng.uniform(-arena_m, arena_m, 2))
    placed.angle = rng.uniform(-np.pi, np.pi)
    scene.add(
        owner,
        placed,
        [_random_shape(rng, placed, rng.uniform(-1, 1, 2), kinds[rng.integers(len(kinds))]) for _ in range(2)],
    )
    owner += 1
    for i in range(num_moving):
        body = pymunk.Body(body_type=pymunk.Body.KINEMATIC) if i % 3 == 2 else pymunk.Body(2.0, 1.0)
        if i % 2:
            body.center_of_gravity = tuple(rng.uniform(-0.3, 0.3, 2))
        body.position = tuple(rng.uniform(-arena_m, arena_m, 2))
        body.angle = rng.uniform(-np.pi, np.pi)
        shapes = [
            _random_shape(rng, body, rng.uniform(-0.8, 0.8, 2), kinds[rng.integers(len(kinds))])
            for _ in range(rng.integers(1, 4))
        ]
        scene.add(owner, body, shapes)
        owner += 1
    return scene


def outside_points(scene: Scene, rng: np.random.Generator, count: int, arena_m: float = 9.0) -> np.ndarray:
    """``(count, 2)`` random points at least ``ORIGIN_CLEARANCE_M`` outside every
    non-robot shape (they may lie inside the robot, as its sensors do)."""
    points = []
    while len(points) < count:
        p = tuple(rng.uniform(-arena_m, arena_m, 2))
        if not scene.space.point_query(p, ORIGIN_CLEARANCE_M, QUERY_FILTER):
            points.append(p)
    return np.array(points)


def pymunk_cast(
    scene: Scene, origins, angles, max_range_m: float, exact: bool = False
) -> tuple[np.ndarray, np.ndarray]:
    """Ranges and owners from ``space.segment_query_first`` along each ray (the oracle);
    ``exact``: with capsules replaced by their stand-ins (``EXACT_FILTER``)."""
    ranges, owners = [], []
    query_filter = EXACT_FILTER if exact else QUERY_FILTER
    for (ox, oy), angle in zip(np.asarray(origins, float), np.asarray(angles, float)):
        end = (ox + max_range_m * math.cos(angle), oy + max_range_m * math.sin(angle))
        info = scene.space.segment_query_first((ox, oy), end, 0.0, query_filter)
        if info is None:
            ranges.append(max_range_m)
            owners.append(-1)
        else:
            ranges.append(info.alpha * math.dist((ox, oy), end))
            owners.append(scene.owner_of[info.shape])
    return np.array(ranges), np.array(owners)


def refresh(scene: Scene) -> None:
    """Make pymunk's cached shape positions follow bodies moved by hand."""
    for body in scene.space.bodies:
        scene.space.reindex_shapes_for_body(body)


@pytest.fixture
def pm():
    """Scene builders and pymunk oracles for the sensor tests."""
    return types.SimpleNamespace(
        ROBOT_ID=ROBOT_ID,
        QUERY_FILTER=QUERY_FILTER,
        EXACT_FILTER=EXACT_FILTER,
        SHAPE_KINDS=SHAPE_KINDS,
        Scene=Scene,
        random_scene=random_scene,
        outside_points=outside_points,
        pymunk_cast=pymunk_cast,
        refresh=refresh,
    )


@pytest.fixture
def room() -> SceneGeometry:
    """A room 8 x 6 m around the origin with a box and a pole inside (owners 1, 2, 3)."""
    x0, y0, x1, y1 = -3.0, -2.0, 5.0, 4.0
    walls = [(x0, y0, x1, y0), (x1, y0, x1, y1), (x1, y1, x0, y1), (x0, y1, x0, y0)]
    box = [(2.0, -0.5, 2.5, -0.5), (2.5, -0.5, 2.5, 0.5), (2.5, 0.5, 2.0, 0.5), (2.0, 0.5, 2.0, -0.5)]
    return SceneGeometry(
        np.array(walls + box), np.array([1] * 4 + [2] * 4), np.array([[-1.0, 1.5, 0.2]]), np.array([3])
    )
