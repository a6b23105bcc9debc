"""The scenes of N robots packed into flat arrays, for one compiled read of all their sensors.

- ``SceneStack``: one scene per member, each a ``GeometryCache`` (its moving bodies placed
  anew at every read) or a fixed ``SceneGeometry``, stacked into flat arrays with each
  member's row ranges (``SensorSuite.read_batch`` sweeps them all in one call);
  ``with_scenes`` keeps a stack for as long as its members keep their scenes.

The stacked moving bodies are the members' ``GeometryCache.moving_bodies``, member by
member: member i's bodies are rows ``body_start[i]:body_start[i + 1]`` of the ``(B, 3)``
body poses a read takes (``x_m, y_m, angle_rad``).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from attentive_gym import _pymunk_access
from attentive_gym.sensors.geometry import GeometryCache, SceneGeometry

__all__ = ["SceneStack"]

#: Columns of ``SceneStack.layout``, one row per member: its segment rows ``[s0, s1)``,
#: circle rows ``[c0, c1)``, moving points ``[p0, p1)`` of which the first ``ENDPOINTS``
#: are segment endpoints, and moving bodies ``[b0, b1)``.
S0, S1, C0, C1, P0, P1, ENDPOINTS, B0, B1 = range(9)


class SceneStack:
    """The scenes of N members as flat arrays with per-member row ranges.

    Each member's rows hold its static primitives and then its moving ones, in the order
    ``GeometryCache.update`` gives them (a ``SceneGeometry`` member: its own rows); a read
    overwrites the moving rows in place, so the arrays hold the scenes of the
    last read.

    Args:
        scenes: one ``GeometryCache`` or ``SceneGeometry`` per member (N >= 0).

    Attributes:
        scenes: the members' scenes, as given (a tuple).
        num_bodies: B, the number of moving bodies of all members together.
        body_start: ``(N + 1,)`` int64 offsets: member i's moving bodies are rows
            ``body_start[i]:body_start[i + 1]`` of the stacked ``(B, 3)`` body poses.
        layout: ``(N, 9)`` int64 row ranges of each member (columns ``S0`` ... ``B1``).
        segments, segment_owner, circles, circle_owner: the stacked ``(S, 4)``, ``(S,)``,
            ``(C, 3)``, ``(C,)`` primitives and owner ids (as in ``SceneGeometry``).
        local_points: ``(P, 2)`` float64 moving points in their body's frame (m).
        point_body: ``(P,)`` int64 index of each point's body among its member's bodies.

    Treat the arrays as read-only; ``geometry(i)`` gives a member's scene as a copy.

    Raises:
        TypeError: for a scene that is neither a ``GeometryCache`` nor a ``SceneGeometry``.

    Example:
        >>> import pymunk
        >>> body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        >>> stack = SceneStack([GeometryCache([(7, body, [pymunk.Circle(body, 0.5)])]), SceneGeometry.empty()])
        >>> stack.num_bodies, stack.body_start.tolist()
        (1, [0, 1, 1])
    """

    def __init__(self, scenes: Sequence[GeometryCache | SceneGeometry]) -> None:
        self.scenes = tuple(scenes)
        segments, segment_owner, circles, circle_owner = [], [], [], []
        local_points, point_body, bodies = [], [], []
        self.layout = np.zeros((len(self.scenes), 9), np.int64)
        s = c = p = b = 0
        for i, scene in enumerate(self.scenes):
            if isinstance(scene, GeometryCache):
                segments.append(scene._segment_template)
                segment_owner.append(scene._segment_owner)
                circles.append(scene._circle_template)
                circle_owner.append(scene._circle_owner)
                local_points.append(scene._local_points)
                point_body.append(scene._point_body)
                bodies += scene._bodies
                endpoints = scene._num_moving_endpoints
                num_points, num_bodies = len(scene._local_points), len(scene._bodies)
            elif isinstance(scene, SceneGeometry):
                segments.append(scene.segments)
                segment_owner.append(scene.segment_owner)
                circles.append(scene.circles)
                circle_owner.append(scene.circle_owner)
                endpoints = num_points = num_bodies = 0
            else:
                raise TypeError(f"scene {i} must be a GeometryCache or a SceneGeometry, got {type(scene).__name__}")
            row = (s, s + len(segments[-1]), c, c + len(circles[-1]), p, p + num_points, endpoints, b, b + num_bodies)
            self.layout[i] = row
            s, c, p, b = row[S1], row[C1], row[P1], row[B1]
        self.segments = _stack(segments, (0, 4), np.float64)
        self.segment_owner = _stack(segment_owner, (0,), np.int64)
        self.circles = _stack(circles, (0, 3), np.float64)
        self.circle_owner = _stack(circle_owner, (0,), np.int64)
        self.local_points = _stack(local_points, (0, 2), np.float64)
        self.point_body = _stack(point_body, (0,), np.int64)
        self._bodies = bodies
        self.num_bodies = len(bodies)
        self.body_start = np.append(self.layout[:, B0], self.num_bodies).astype(np.int64)

    def __len__(self) -> int:
        return len(self.scenes)

    def with_scenes(self, scenes: Sequence[GeometryCache | SceneGeometry]) -> SceneStack:
        """This stack if it holds exactly ``scenes`` (the same objects, in order), else a new
        stack of them (after a member's reset has given it a new scene)."""
        own = self.scenes
        if len(scenes) == len(own) and all(a is b for a, b in zip(scenes, own)):
            return self
        return SceneStack(scenes)

    def body_poses(self) -> np.ndarray:
        """``(B, 3)`` float64 poses ``x_m, y_m, angle_rad`` of the stacked moving bodies, read
        from pymunk now (not checked: ``check_body_poses`` does that)."""
        return np.array(_pymunk_access.poses(self._bodies), np.float64).reshape(-1, 3)

    def check_body_poses(self, body_poses, active=None) -> np.ndarray:
        """``body_poses`` as a contiguous ``(B, 3)`` float64 array, or ``ValueError`` unless it
        is numeric, of that shape and finite in the rows of the members ``active`` marks
        (``(N,)`` bool; None: every member), naming the first body whose pose is not."""
        try:
            array = np.ascontiguousarray(body_poses, dtype=np.float64)
        except (TypeError, ValueError):
            raise ValueError(
                f"body_poses must be a numeric ({self.num_bodies}, 3) array: x_m, y_m, angle_rad per moving body"
            ) from None
        if array.shape != (self.num_bodies, 3):
            raise ValueError(
                f"body_poses must have shape ({self.num_bodies}, 3): x_m, y_m, angle_rad of each of the "
                f"{self.num_bodies} moving bodies of the stack's scenes, member by member; got shape {array.shape}"
            )
        finite = np.isfinite(array)
        if finite.all():
            return array
        finite = finite.all(axis=1)
        if active is not None:
            finite |= ~np.repeat(active, np.diff(self.body_start))
        if not finite.all():
            row = int(np.argmin(finite))
            member = int(np.searchsorted(self.body_start, row, side="right")) - 1
            raise ValueError(
                f"body_poses row {row} (body {row - self.body_start[member]} of member {member}, "
                f"{self._bodies[row]!r}) is not finite: {array[row].tolist()}"
            )
        return array

    def geometry(self, i: int) -> SceneGeometry:
        """Member ``i``'s scene as the stack holds it now (after the last read): a copy."""
        s0, s1, c0, c1 = self.layout[i, :4]
        return SceneGeometry(
            self.segments[s0:s1].copy(),
            self.segment_owner[s0:s1].copy(),
            self.circles[c0:c1].copy(),
            self.circle_owner[c0:c1].copy(),
        )


def _stack(parts: list[np.ndarray], empty_shape: tuple[int, ...], dtype) -> np.ndarray:
    """``parts`` concatenated along the first axis into a new contiguous array (an empty
    array of ``empty_shape`` if none)."""
    return np.concatenate(parts).astype(dtype, copy=False) if parts else np.empty(empty_shape, dtype)
