"""The scene as the sensors see it: world-frame line segments and circles with owner ids.

- ``SceneGeometry``: immutable world-frame arrays of segments and circles, each tagged
  with the integer id of the body that owns it (the id the sensors report on a hit).
- ``GeometryCache``: converts pymunk shapes into that form once, in each body's local
  frame, and re-places only the moving bodies on every ``update()``, at their pymunk
  poses or at poses the caller gives.
- ``place_moving``: the compiled placement of a cache's moving primitives (the kernel
  ``update`` and the sensors' batched read share).

Every pymunk shape becomes an *exact* set of boundary primitives, so that the analytic
casters of ``raycast`` agree with pymunk's own queries:

==================  ==========================================================
pymunk shape        primitives (local frame)
==================  ==========================================================
``Poly``, r = 0     its edges
``Poly``, r > 0     its edges pushed outward by r, plus a circle of radius r at
                    every vertex (the exact rounded polygon)
``Segment``, r = 0  the segment
``Segment``, r > 0  the capsule: the segment pushed by +r and by -r along its
                    normal, plus a circle of radius r at each end
``Circle``          a circle at ``offset`` of radius r
==================  ==========================================================

Each primitive lies inside its (solid) shape and together they cover the shape's
outline, so the first crossing of a ray, or the nearest point in a cone, seen from
outside the shape is the same for the primitives as for the shape itself.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pymunk
from numba import njit

from attentive_gym import _pymunk_access

__all__ = ["SceneGeometry", "GeometryCache", "shape_primitives"]


@dataclass(frozen=True, eq=False)
class SceneGeometry:
    """World-frame scene geometry (metres) with the owner id of every primitive.

    Attributes:
        segments: ``(S, 4)`` float64 ``x1, y1, x2, y2`` of zero-thickness line segments (m).
        segment_owner: ``(S,)`` int64 owner id of each segment.
        circles: ``(C, 3)`` float64 ``cx, cy, r`` of circles (m), ``r >= 0``.
        circle_owner: ``(C,)`` int64 owner id of each circle.

    Arrays are converted to contiguous float64/int64 on construction (no copy when they
    already are) and checked: shapes, finite coordinates, non-negative radii. Treat
    them as read-only: ``GeometryCache`` may hand the same object out more than once.

    Raises:
        ValueError: on a wrong shape, a non-finite coordinate or a negative radius.
    """

    segments: np.ndarray
    segment_owner: np.ndarray
    circles: np.ndarray
    circle_owner: np.ndarray

    def __post_init__(self) -> None:
        for name, dtype in (
            ("segments", np.float64),
            ("segment_owner", np.int64),
            ("circles", np.float64),
            ("circle_owner", np.int64),
        ):
            object.__setattr__(self, name, np.ascontiguousarray(getattr(self, name), dtype=dtype))
        s, c = self.segments, self.circles
        if s.ndim != 2 or s.shape[1] != 4:
            raise ValueError(f"SceneGeometry.segments must have shape (S, 4) = x1, y1, x2, y2; got {s.shape}")
        if c.ndim != 2 or c.shape[1] != 3:
            raise ValueError(f"SceneGeometry.circles must have shape (C, 3) = cx, cy, r; got {c.shape}")
        if self.segment_owner.shape != (len(s),):
            raise ValueError(
                f"SceneGeometry.segment_owner must have shape ({len(s)},), one id per segment; "
                f"got {self.segment_owner.shape}"
            )
        if self.circle_owner.shape != (len(c),):
            raise ValueError(
                f"SceneGeometry.circle_owner must have shape ({len(c)},), one id per circle; "
                f"got {self.circle_owner.shape}"
            )
        if not (np.isfinite(s).all() and np.isfinite(c).all()):
            raise ValueError("SceneGeometry coordinates and radii must be finite")
        if (c[:, 2] < 0.0).any():
            raise ValueError(f"SceneGeometry circle radii must be >= 0, got min {c[:, 2].min()}")

    @classmethod
    def _unchecked(
        cls, segments: np.ndarray, segment_owner: np.ndarray, circles: np.ndarray, circle_owner: np.ndarray
    ) -> SceneGeometry:
        """A ``SceneGeometry`` of arrays already known to be valid (``GeometryCache``'s
        own, whose only new input, the poses, it checks itself), without the checks."""
        geometry = object.__new__(cls)
        geometry.__dict__.update(
            segments=segments, segment_owner=segment_owner, circles=circles, circle_owner=circle_owner
        )
        return geometry

    @classmethod
    def empty(cls) -> SceneGeometry:
        """A scene with nothing in it."""
        return cls(np.empty((0, 4)), np.empty(0, np.int64), np.empty((0, 3)), np.empty(0, np.int64))


def shape_primitives(shape: pymunk.Shape) -> tuple[np.ndarray, np.ndarray]:
    """The exact boundary primitives of one pymunk shape, in its body's local frame.

    Args:
        shape: a ``pymunk.Poly``, ``pymunk.Segment`` or ``pymunk.Circle``.

    Returns:
        ``(segments (n, 4), circles (m, 3))`` float64 in metres (see the module table).
        A zero-length ``Segment`` of radius 0 yields nothing: it has no extent to hit.

    Raises:
        TypeError: for any other shape type.
    """
    if isinstance(shape, pymunk.Poly):
        vertices = np.array([tuple(v) for v in shape.get_vertices()], dtype=np.float64).reshape(-1, 2)
        radius = float(shape.radius)
        following = np.roll(vertices, -1, axis=0)
        edges = following - vertices
        lengths = np.hypot(edges[:, 0], edges[:, 1])
        keep = lengths > 0.0  # a one-vertex polygon's only "edge" has no length (rounded, it is a circle)
        starts, ends, edges, lengths = vertices[keep], following[keep], edges[keep], lengths[keep]
        if radius > 0.0:
            # pymunk keeps the convex hull counter-clockwise, so the outward normal of an
            # edge is the edge turned clockwise
            normals = np.stack([edges[:, 1], -edges[:, 0]], axis=1) / lengths[:, None]
            starts, ends = starts + radius * normals, ends + radius * normals
            circles = np.column_stack([vertices, np.full(len(vertices), radius)])
        else:
            circles = np.empty((0, 3))
        return np.hstack([starts, ends]), circles
    if isinstance(shape, pymunk.Segment):
        a, b, radius = np.array(tuple(shape.a), float), np.array(tuple(shape.b), float), float(shape.radius)
        length = float(np.hypot(*(b - a)))
        if radius == 0.0:
            return (np.hstack([a, b])[None, :] if length > 0.0 else np.empty((0, 4))), np.empty((0, 3))
        circles = np.array([[a[0], a[1], radius], [b[0], b[1], radius]])
        if length == 0.0:
            return np.empty((0, 4)), circles[:1]
        normal = np.array([b[1] - a[1], a[0] - b[0]]) / length * radius
        sides = np.array([np.hstack([a + normal, b + normal]), np.hstack([a - normal, b - normal])])
        return sides, circles
    if isinstance(shape, pymunk.Circle):
        ox, oy = shape.offset
        return np.empty((0, 4)), np.array([[ox, oy, float(shape.radius)]])
    raise TypeError(
        f"unsupported shape type {type(shape).__name__}; allowed: pymunk.Poly, pymunk.Segment, pymunk.Circle"
    )


class GeometryCache:
    """World-frame ``SceneGeometry`` of a fixed set of pymunk bodies, refreshed cheaply.

    Built once; ``update()`` then re-reads only the poses of the non-static bodies (or
    takes them from the caller) and re-places their local primitives in one compiled call
    (``place_moving``). Static bodies (``body.body_type == pymunk.Body.STATIC``)
    are placed once, at construction: moving a static body later is not followed.
    Shapes added to a body after construction are not seen either.

    Args:
        bodies: ``(owner_id, body, shapes)`` triples; several triples may share a body
            (e.g. ``space.static_body`` with one owner per wall), and ``shapes`` may be
            empty. Every shape must be attached to its ``body``.

    Raises:
        TypeError: for an owner id that is not an int, or an unsupported shape type.
        ValueError: for a shape attached to another body than the one it is listed with.

    Example:
        >>> import pymunk
        >>> body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        >>> box = pymunk.Poly.create_box(body, (1.0, 1.0))
        >>> cache = GeometryCache([(7, body, [box])])
        >>> body.position = (3.0, 0.0)
        >>> float(cache.update().segments[:, 0].min())
        2.5
    """

    def __init__(self, bodies: Sequence[tuple[int, pymunk.Body, Sequence[pymunk.Shape]]]) -> None:
        static_segments, static_segment_owner, static_circles, static_circle_owner = [], [], [], []
        moving_segments, moving_segment_owner, moving_segment_body = [], [], []
        moving_circles, moving_circle_owner, moving_circle_body = [], [], []
        self._bodies: list[pymunk.Body] = []  # the distinct moving bodies
        index_of: dict[int, int] = {}
        for owner, body, shapes in bodies:
            if isinstance(owner, bool) or not isinstance(owner, (int, np.integer)):
                raise TypeError(f"owner id must be an int, got {owner!r} ({type(owner).__name__})")
            segments, circles = _body_primitives(body, shapes)
            if body.body_type == pymunk.Body.STATIC:
                static_segments.append(np.hstack([_place(segments[:, :2], body), _place(segments[:, 2:], body)]))
                static_circles.append(np.column_stack([_place(circles[:, :2], body), circles[:, 2]]))
                static_segment_owner.append(np.full(len(segments), owner, np.int64))
                static_circle_owner.append(np.full(len(circles), owner, np.int64))
                continue
            index = index_of.setdefault(id(body), len(self._bodies))
            if index == len(self._bodies):
                self._bodies.append(body)
            moving_segments.append(segments)
            moving_segment_owner.append(np.full(len(segments), owner, np.int64))
            moving_segment_body.append(np.full(len(segments), index, np.int64))
            moving_circles.append(circles)
            moving_circle_owner.append(np.full(len(circles), owner, np.int64))
            moving_circle_body.append(np.full(len(circles), index, np.int64))
        self._static = SceneGeometry(
            _stack(static_segments, (0, 4)),
            _stack(static_segment_owner, (0,), np.int64),
            _stack(static_circles, (0, 3)),
            _stack(static_circle_owner, (0,), np.int64),
        )
        # moving primitives as local points (segment endpoints, then circle centres),
        # each with the index of its body; the outputs start as copies of templates that
        # hold the static primitives and the moving circles' radii
        local_segments = _stack(moving_segments, (0, 4))
        local_circles = _stack(moving_circles, (0, 3))
        self._local_points = np.ascontiguousarray(np.concatenate([local_segments.reshape(-1, 2), local_circles[:, :2]]))
        self._point_body = np.concatenate(
            [
                np.repeat(_stack(moving_segment_body, (0,), np.int64), 2),
                _stack(moving_circle_body, (0,), np.int64),
            ]
        )
        self._num_moving_endpoints = 2 * len(local_segments)
        self._segment_template = np.vstack([self._static.segments, local_segments])
        self._circle_template = np.vstack([self._static.circles, local_circles])
        self._segment_owner = np.concatenate([self._static.segment_owner, _stack(moving_segment_owner, (0,), np.int64)])
        self._circle_owner = np.concatenate([self._static.circle_owner, _stack(moving_circle_owner, (0,), np.int64)])

    @property
    def moving_bodies(self) -> tuple[pymunk.Body, ...]:
        """The distinct non-static bodies whose poses ``update()`` reads, in the order of
        their first appearance among the construction's triples: row ``b`` of the
        ``poses`` that ``update`` takes is the pose of ``moving_bodies[b]``."""
        return tuple(self._bodies)

    def update(self, poses=None) -> SceneGeometry:
        """The scene now: static primitives as built, moving ones at their bodies' poses.

        Args:
            poses: ``(B, 3)`` float64 ``x_m, y_m, angle_rad`` of ``moving_bodies`` (row ``b``
                for body ``b``; B = ``len(moving_bodies)``), for a caller that already
                holds them; None reads them from pymunk. Either way the same numbers come
                out, bit for bit.

        Returns:
            A new ``SceneGeometry`` (static primitives first, then the moving ones, in the
            order given at construction); with no moving body, the same static object.

        Raises:
            ValueError: for ``poses`` of another shape than ``(B, 3)``, or a moving body's
                position or angle that is not finite.
        """
        if poses is not None:
            poses = self.check_poses(poses)
        if not self._bodies:
            return self._static
        if poses is None:
            poses = np.array(_pymunk_access.poses(self._bodies)).reshape(-1, 3)
        segments = self._segment_template.copy()
        circles = self._circle_template.copy()
        bad = place_moving(poses, self._local_points, self._point_body, self._num_moving_endpoints, segments, circles)
        if bad >= 0:
            body = self._bodies[bad]
            raise ValueError(
                f"body {bad} of the cache ({body!r}) has a non-finite pose: x, y, angle = {poses[bad].tolist()}"
            )
        return SceneGeometry._unchecked(segments, self._segment_owner, circles, self._circle_owner)

    def check_poses(self, poses) -> np.ndarray:
        """``poses`` as a contiguous ``(B, 3)`` float64 array, or ``ValueError`` unless it is
        numeric with one row ``x_m, y_m, angle_rad`` per moving body (finiteness is
        checked where the poses are used)."""
        try:
            array = np.ascontiguousarray(poses, dtype=np.float64)
        except (TypeError, ValueError):
            raise ValueError("poses must be a numeric (B, 3) array, one x_m, y_m, angle_rad per body") from None
        if array.shape != (len(self._bodies), 3):
            raise ValueError(
                f"poses must have shape ({len(self._bodies)}, 3): x_m, y_m, angle_rad of each of the cache's "
                f"{len(self._bodies)} moving bodies; got shape {array.shape}"
            )
        return array


@njit(cache=True)
def place_moving(poses, local_points, point_body, num_endpoints, segments, circles):
    """Place a cache's moving primitives at their bodies' poses, in place (one scene).

    The moving primitives are the last rows of ``segments`` (``num_endpoints // 2`` of
    them) and of ``circles`` (the points after the endpoints); the rows before them, the
    static primitives, and the circles' radii are left as they are.

    Args:
        poses: ``(B, 3)`` float64 ``x, y, angle`` of each body (m, m, rad).
        local_points: ``(P, 2)`` float64 moving points in their body's frame (m): the
            segment endpoints (two per segment, start then end), then the circle centres.
        point_body: ``(P,)`` int64 index into ``poses`` of each point's body.
        num_endpoints: the number of segment endpoints among the points.
        segments: ``(S, 4)`` float64, written: the last ``num_endpoints // 2`` rows.
        circles: ``(C, 3)`` float64, written: columns 0-1 of the last ``P - num_endpoints`` rows.

    Returns:
        -1, or the index of the first body whose pose is not finite (then nothing is written).

    The rotation is the complex product ``(lx + i ly)(cos a + i sin a)`` written out, then
    the translation is added.
    """
    n_bodies = poses.shape[0]
    cos_a = np.empty(n_bodies)
    sin_a = np.empty(n_bodies)
    for b in range(n_bodies):
        if not (math.isfinite(poses[b, 0]) and math.isfinite(poses[b, 1]) and math.isfinite(poses[b, 2])):
            return b
        cos_a[b] = math.cos(poses[b, 2])
        sin_a[b] = math.sin(poses[b, 2])
    first_segment = segments.shape[0] - num_endpoints // 2
    first_circle = circles.shape[0] - (local_points.shape[0] - num_endpoints)
    for k in range(local_points.shape[0]):
        b = point_body[k]
        lx = local_points[k, 0]
        ly = local_points[k, 1]
        c = cos_a[b]
        s = sin_a[b]
        px = (lx * c - ly * s) + poses[b, 0]
        py = (lx * s + ly * c) + poses[b, 1]
        if k < num_endpoints:
            row = first_segment + k // 2
            col = 2 * (k % 2)
            segments[row, col] = px
            segments[row, col + 1] = py
        else:
            row = first_circle + k - num_endpoints
            circles[row, 0] = px
            circles[row, 1] = py
    return -1


def _body_primitives(body: pymunk.Body, shapes: Sequence[pymunk.Shape]) -> tuple[np.ndarray, np.ndarray]:
    """Local-frame ``(segments (n, 4), circles (m, 3))`` of all ``shapes`` of ``body``."""
    segments, circles = [np.empty((0, 4))], [np.empty((0, 3))]
    for shape in shapes:
        s, c = shape_primitives(shape)
        if shape.body is not body:
            raise ValueError(f"a {type(shape).__name__} listed with body {body!r} is attached to {shape.body!r}")
        segments.append(s)
        circles.append(c)
    return np.concatenate(segments), np.concatenate(circles)


def _place(points: np.ndarray, body: pymunk.Body) -> np.ndarray:
    """``(n, 2)`` local points of ``body`` in the world frame (m)."""
    x, y = body.position
    c, s = np.cos(body.angle), np.sin(body.angle)
    return np.column_stack([x + c * points[:, 0] - s * points[:, 1], y + s * points[:, 0] + c * points[:, 1]])


def _stack(parts: list[np.ndarray], empty_shape: tuple[int, ...], dtype=np.float64) -> np.ndarray:
    """``parts`` concatenated along the first axis (an empty array of ``empty_shape`` if none)."""
    return np.ascontiguousarray(np.concatenate(parts), dtype=dtype) if parts else np.empty(empty_shape, dtype)
