"""Analytic ray casting and exact cone queries against a ``SceneGeometry`` (numba kernels).

- ``cast_rays``: first hit of arbitrary rays (range and owner id), brute force over all
  primitives.
- ``cast_fan``: the same for evenly spaced rays from one origin (a scanner), culling
  each primitive to the rays inside the angle it subtends; same results as ``cast_rays``.
- ``cone_nearest``: the exact nearest point of the scene inside each of several cones
  (a sonar's echo), not a fan of rays; ``cone_nearest_points`` also returns the points.

Conventions: world frame, metres and radians, angles counter-clockwise from +x. The
geometry is a set of zero-thickness line segments and circles; circles are solid (a ray
starting inside one hits it at range 0, as pymunk's queries do), segments are curves. A
sensor is meant to sit outside every shape it can see (the physics keeps it there; its
own body is left out with ``exclude_owner``). Primitives whose owner equals
``exclude_owner`` are ignored. Ties between primitives at the same distance go to the
first in scan order (segments before circles, then by index).

The kernels (``rays_kernel``, ``fan_kernel``, ``cones_kernel``) are compiled by numba
on first use (cached on disk, ``cache=True``) and check nothing; the functions above
check shapes and types, convert to float64/int64 once and call them. The sensor classes
call the kernels directly after checking their own inputs.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from attentive_gym.sensors._checks import check_geometry, check_half_width, check_owner, check_positive
from attentive_gym.sensors.geometry import SceneGeometry

__all__ = ["cast_rays", "cast_fan", "cone_nearest", "cone_nearest_points"]

#: Slack on the along-segment parameter (fraction of the segment's length) when a ray
#: crosses it: a ray through a vertex shared by two polygon edges must hit one of them
#: even when rounding puts the crossing a hair outside both (about 1e-16 relative).
SEGMENT_PARAMETER_SLACK = 1e-12
#: Angle (rad) by which ``cast_fan`` widens the angular interval of every primitive
#: before picking the rays to test: covers atan2/asin rounding (~1e-16 rad) and the
#: parameter slack above seen from 1e-6 of a segment's length; culling may only keep
#: too many rays, never too few.
FAN_CULL_SLACK_RAD = 1e-6
_TWO_PI = 2.0 * math.pi


@njit(cache=True)
def _ray_segment(ox, oy, dx, dy, x1, y1, x2, y2):
    """Distance along the unit direction ``(dx, dy)`` from ``(ox, oy)`` to the segment.

    Solves ``o + t d = a + s (b - a)`` with cross products; ``inf`` when parallel, behind
    (t < 0) or beside the segment (s outside [0, 1] beyond the slack).
    """
    ex = x2 - x1
    ey = y2 - y1
    denom = dx * ey - dy * ex
    if denom == 0.0:
        return np.inf
    wx = x1 - ox
    wy = y1 - oy
    t = (wx * ey - wy * ex) / denom
    s = (wx * dy - wy * dx) / denom
    if t < 0.0 or s < -SEGMENT_PARAMETER_SLACK or s > 1.0 + SEGMENT_PARAMETER_SLACK:
        return np.inf
    return t


@njit(cache=True)
def _ray_circle(ox, oy, dx, dy, cx, cy, r):
    """Distance along the unit direction ``(dx, dy)`` from ``(ox, oy)`` to a solid circle.

    0 from inside or on the circle; otherwise the nearer root of
    ``|o + t d - c|^2 = r^2``, written as ``c0 / (-b + sqrt(b^2 - c0))`` (no cancellation
    for grazing rays); ``inf`` when missed or behind.
    """
    mx = ox - cx
    my = oy - cy
    c0 = mx * mx + my * my - r * r
    if c0 <= 0.0:
        return 0.0
    b = mx * dx + my * dy
    if b >= 0.0:
        return np.inf
    disc = b * b - c0
    if disc < 0.0:
        return np.inf
    return c0 / (-b + math.sqrt(disc))


@njit(cache=True)
def rays_kernel(origins, angles, max_range, segments, segment_owner, circles, circle_owner, exclude):
    """``cast_rays`` without argument checks: every ray against every primitive."""
    n = angles.shape[0]
    ranges = np.empty(n)
    owners = np.empty(n, np.int64)
    for k in range(n):
        ox = origins[k, 0]
        oy = origins[k, 1]
        dx = math.cos(angles[k])
        dy = math.sin(angles[k])
        best = np.inf
        who = -1
        for i in range(segments.shape[0]):
            if segment_owner[i] == exclude:
                continue
            t = _ray_segment(ox, oy, dx, dy, segments[i, 0], segments[i, 1], segments[i, 2], segments[i, 3])
            if t < best:
                best = t
                who = segment_owner[i]
        for i in range(circles.shape[0]):
            if circle_owner[i] == exclude:
                continue
            t = _ray_circle(ox, oy, dx, dy, circles[i, 0], circles[i, 1], circles[i, 2])
            if t < best:
                best = t
                who = circle_owner[i]
        if best > max_range:
            best = max_range
            who = -1
        ranges[k] = best
        owners[k] = who
    return ranges, owners


@njit(cache=True)
def _fan_span(start, width, first, step, n):
    """Rays ``first + k step`` (k < n) that may point into the arc ``[start, start + width]``
    (rad, width <= pi) widened by ``FAN_CULL_SLACK_RAD`` on both sides.

    Returns ``(k0, k1, k2)``: rays ``k0..k1``, and rays ``0..k2`` where the arc wraps past
    ``first + 2 pi``; a range whose end is below its start is empty. Floor and ceil make
    each range include the ray just outside either end of the arc as well.
    """
    lo = (start - FAN_CULL_SLACK_RAD - first) % _TWO_PI
    hi = lo + width + 2.0 * FAN_CULL_SLACK_RAD
    k0 = int(math.floor(lo / step))
    k1 = min(int(math.ceil(hi / step)), n - 1)
    k2 = min(int(math.ceil((hi - _TWO_PI) / step)), n - 1)
    return k0, k1, k2


@njit(cache=True)
def fan_kernel(ox, oy, first, step, n, max_range, segments, segment_owner, circles, circle_owner, exclude):
    """``cast_fan`` without argument checks: each primitive against the rays of its arc."""
    dxs = np.empty(n)
    dys = np.empty(n)
    for k in range(n):
        angle = first + k * step
        dxs[k] = math.cos(angle)
        dys[k] = math.sin(angle)
    best = np.full(n, np.inf)
    owners = np.full(n, -1, np.int64)
    for i in range(segments.shape[0]):
        if segment_owner[i] == exclude:
            continue
        x1 = segments[i, 0]
        y1 = segments[i, 1]
        x2 = segments[i, 2]
        y2 = segments[i, 3]
        ax = x1 - ox
        ay = y1 - oy
        bx = x2 - ox
        by = y2 - oy
        if ax * by - ay * bx == 0.0 and ax * bx + ay * by <= 0.0:
            k0, k1, k2 = 0, n - 1, -1  # the segment passes through the origin
        else:
            start = math.atan2(ay, ax)
            width = math.atan2(by, bx) - start
            if width > math.pi:
                width -= _TWO_PI
            elif width < -math.pi:
                width += _TWO_PI
            if width < 0.0:
                start += width
                width = -width
            k0, k1, k2 = _fan_span(start, width, first, step, n)
        for lo, hi in ((k0, k1), (0, k2)):
            for k in range(lo, hi + 1):
                t = _ray_segment(ox, oy, dxs[k], dys[k], x1, y1, x2, y2)
                if t < best[k]:
                    best[k] = t
                    owners[k] = segment_owner[i]
    for i in range(circles.shape[0]):
        if circle_owner[i] == exclude:
            continue
        cx = circles[i, 0]
        cy = circles[i, 1]
        r = circles[i, 2]
        mx = cx - ox
        my = cy - oy
        m2 = mx * mx + my * my
        if m2 - r * r <= 0.0:  # the test of _ray_circle: the origin is inside, every ray hits at 0
            k0, k1, k2 = 0, n - 1, -1
        else:
            half = math.asin(min(r / math.sqrt(m2), 1.0))
            k0, k1, k2 = _fan_span(math.atan2(my, mx) - half, 2.0 * half, first, step, n)
        for lo, hi in ((k0, k1), (0, k2)):
            for k in range(lo, hi + 1):
                t = _ray_circle(ox, oy, dxs[k], dys[k], cx, cy, r)
                if t < best[k]:
                    best[k] = t
                    owners[k] = circle_owner[i]
    for k in range(n):
        if best[k] > max_range:
            best[k] = max_range
            owners[k] = -1
    return best, owners


@njit(cache=True)
def cones_kernel(
    frame_x,
    frame_y,
    frame_theta,
    apexes,
    headings,
    half_width,
    max_range,
    segments,
    segment_owner,
    circles,
    circle_owner,
    exclude,
):
    """``cone_nearest_points`` without argument checks, for apexes and headings given in
    a frame ``(frame_x, frame_y, frame_theta)`` (a robot pose; zeros for the world frame)."""
    n = headings.shape[0]
    ranges = np.empty(n)
    owners = np.empty(n, np.int64)
    points = np.empty((n, 2))
    cf = math.cos(frame_theta)
    sf = math.sin(frame_theta)
    for k in range(n):
        px = frame_x + cf * apexes[k, 0] - sf * apexes[k, 1]
        py = frame_y + sf * apexes[k, 0] + cf * apexes[k, 1]
        heading = frame_theta + headings[k]
        rx = math.cos(heading - half_width)  # right boundary ray
        ry = math.sin(heading - half_width)
        lx = math.cos(heading + half_width)  # left boundary ray
        ly = math.sin(heading + half_width)
        best = np.inf
        who = -1
        qx = np.nan
        qy = np.nan
        for i in range(segments.shape[0]):
            if segment_owner[i] == exclude:
                continue
            ax = segments[i, 0] - px
            ay = segments[i, 1] - py
            bx = segments[i, 2] - px
            by = segments[i, 3] - py
            # inside the wedge: left of the right ray (f1 >= 0) and right of the left ray (f2 >= 0)
            fa1 = rx * ay - ry * ax
            fb1 = rx * by - ry * bx
            fa2 = ax * ly - ay * lx
            fb2 = bx * ly - by * lx
            if (fa1 < 0.0 and fb1 < 0.0) or (fa2 < 0.0 and fb2 < 0.0):
                continue
            t0 = 0.0
            t1 = 1.0
            if fa1 < 0.0:
                t0 = max(t0, fa1 / (fa1 - fb1))
            elif fb1 < 0.0:
                t1 = min(t1, fa1 / (fa1 - fb1))
            if fa2 < 0.0:
                t0 = max(t0, fa2 / (fa2 - fb2))
            elif fb2 < 0.0:
                t1 = min(t1, fa2 / (fa2 - fb2))
            if t0 > t1:
                continue
            ex = bx - ax
            ey = by - ay
            length2 = ex * ex + ey * ey
            t = -(ax * ex + ay * ey) / length2 if length2 > 0.0 else t0
            t = min(max(t, t0), t1)
            nx = ax + t * ex
            ny = ay + t * ey
            distance = math.sqrt(nx * nx + ny * ny)
            if distance < best:
                best = distance
                who = segment_owner[i]
                qx = px + nx
                qy = py + ny
        for i in range(circles.shape[0]):
            if circle_owner[i] == exclude:
                continue
            r = circles[i, 2]
            mx = circles[i, 0] - px
            my = circles[i, 1] - py
            m2 = mx * mx + my * my
            c0 = m2 - r * r
            if c0 <= 0.0:  # the apex is inside the (solid) circle
                if 0.0 < best:
                    best = 0.0
                    who = circle_owner[i]
                    qx = px
                    qy = py
                continue
            m = math.sqrt(m2)
            if m - r >= best:
                continue
            nx = 0.0
            ny = 0.0
            if rx * my - ry * mx >= 0.0 and mx * ly - my * lx >= 0.0:
                # the centre's direction is inside the cone: nearest point towards it
                distance = m - r
                nx = mx * (distance / m)
                ny = my * (distance / m)
            else:
                # otherwise the nearest point is where a boundary ray enters the circle
                distance = np.inf
                for ux, uy in ((rx, ry), (lx, ly)):
                    b = mx * ux + my * uy
                    disc = b * b - c0
                    if b > 0.0 and disc >= 0.0:
                        t = c0 / (b + math.sqrt(disc))
                        if t < distance:
                            distance = t
                            nx = t * ux
                            ny = t * uy
            if distance < best:
                best = distance
                who = circle_owner[i]
                qx = px + nx
                qy = py + ny
        if best > max_range:
            best = max_range
            who = -1
            qx = np.nan
            qy = np.nan
        ranges[k] = best
        owners[k] = who
        points[k, 0] = qx
        points[k, 1] = qy
    return ranges, owners, points


# --- the Python boundary ----------------------------------------------------------


def _finite_array(name: str, value, shape_text: str, ndim: int, last: int | None = None) -> np.ndarray:
    try:
        array = np.ascontiguousarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a numeric array of shape {shape_text}, got {value!r}") from None
    if array.ndim != ndim or (last is not None and array.shape[-1] != last):
        raise ValueError(f"{name} must have shape {shape_text}, got {array.shape}")
    if not np.isfinite(array).all():
        raise ValueError(f"{name} must be finite")
    return array


def _rays_input(points_name, points, angles_name, angles):
    points = _finite_array(points_name, points, "(N, 2)", 2, 2)
    angles = _finite_array(angles_name, angles, "(N,)", 1)
    if len(points) != len(angles):
        raise ValueError(f"{points_name} {points.shape} and {angles_name} {angles.shape} must have the same length N")
    return points, angles


def cast_rays(
    origins, angles, max_range_m: float, geometry: SceneGeometry, exclude_owner: int = -1
) -> tuple[np.ndarray, np.ndarray]:
    """First hit along each ray: range and the owner id of the hit primitive.

    Args:
        origins: ``(R, 2)`` ray starts (m, world frame).
        angles: ``(R,)`` ray directions (rad, world frame, counter-clockwise from +x).
        max_range_m: farthest hit reported (m); hits at exactly this range count.
        geometry: the scene.
        exclude_owner: primitives of this owner are ignored (-1: none).

    Returns:
        ``ranges (R,)`` float64 (m) and ``owners (R,)`` int64; ``max_range_m`` and -1 where
        nothing is hit within range. Cost: R x (S + C) intersection tests.

    Raises:
        ValueError: on wrong shapes, non-finite inputs or a non-positive range.
        TypeError: for a geometry that is not a ``SceneGeometry`` or a non-int owner.

    Example:
        >>> wall = SceneGeometry(np.array([[2.0, -1.0, 2.0, 1.0]]), np.array([9]), np.empty((0, 3)), np.empty(0, int))
        >>> ranges, owners = cast_rays(np.zeros((2, 2)), [0.0, np.pi], 10.0, wall)
        >>> ranges.tolist(), owners.tolist()
        ([2.0, 10.0], [9, -1])
    """
    origins, angles = _rays_input("origins", origins, "angles", angles)
    g = check_geometry(geometry)
    return rays_kernel(
        origins,
        angles,
        check_positive("max_range_m", max_range_m),
        g.segments,
        g.segment_owner,
        g.circles,
        g.circle_owner,
        check_owner(exclude_owner),
    )


def cast_fan(
    origin,
    first_angle_rad: float,
    step_rad: float,
    num_rays: int,
    max_range_m: float,
    geometry: SceneGeometry,
    exclude_owner: int = -1,
) -> tuple[np.ndarray, np.ndarray]:
    """``cast_rays`` for rays from one origin at angles ``first_angle_rad + k step_rad``.

    Each primitive is tested only against the rays inside the angle it subtends from the
    origin (widened by ``FAN_CULL_SLACK_RAD``), so the cost is about S + C plus the
    number of (ray, primitive) pairs that can actually meet, instead of R x (S + C).

    Args:
        origin: ``(2,)`` common start of the rays (m).
        first_angle_rad: direction of ray 0 (rad, world frame).
        step_rad: angle between consecutive rays (rad), > 0 with
            ``(num_rays - 1) * step_rad < 2 pi``.
        num_rays: number of rays R >= 1.
        max_range_m, geometry, exclude_owner: as in ``cast_rays``.

    Returns:
        ``ranges (R,)``, ``owners (R,)`` as ``cast_rays`` returns for the same rays.

    Raises:
        ValueError, TypeError: as ``cast_rays``, or for a bad step or ray count.
    """
    origin = _finite_array("origin", origin, "(2,)", 1, 2)
    try:
        first = float(first_angle_rad)
    except (TypeError, ValueError):
        first = math.nan
    if not math.isfinite(first):
        raise ValueError(f"first_angle_rad must be a finite number, got {first_angle_rad!r}")
    if isinstance(num_rays, bool) or not isinstance(num_rays, (int, np.integer)) or num_rays < 1:
        raise ValueError(f"num_rays must be an int >= 1, got {num_rays!r}")
    step = check_positive("step_rad", step_rad)
    if (num_rays - 1) * step >= _TWO_PI:
        raise ValueError(
            f"the fan must span less than a full turn: (num_rays - 1) * step_rad = {(num_rays - 1) * step} rad"
        )
    g = check_geometry(geometry)
    return fan_kernel(
        origin[0],
        origin[1],
        first,
        step,
        int(num_rays),
        check_positive("max_range_m", max_range_m),
        g.segments,
        g.segment_owner,
        g.circles,
        g.circle_owner,
        check_owner(exclude_owner),
    )


def cone_nearest_points(
    apexes, headings, half_width_rad: float, max_range_m: float, geometry: SceneGeometry, exclude_owner: int = -1
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Exact nearest scene point inside each cone, with its distance and owner.

    The cone of apex p, heading h and half-width w is the wedge of points q with
    ``|bearing(q - p) - h| <= w``. Algorithm, per cone and primitive:

    - segment: clip it to the wedge (the intersection of the two half-planes bounded by
      the boundary rays, exact for w < 90 deg; Liang-Barsky on the segment parameter),
      then take the point of the clipped piece nearest to p (projection, clamped);
    - circle: if the direction p -> centre is inside the wedge, the distance is
      ``|c - p| - r`` along it; otherwise the distance from p along the circle is
      unimodal, so the nearest point inside the wedge is where a boundary ray enters
      the circle (the nearer of the two); an apex inside a circle gives 0.

    Args:
        apexes: ``(K, 2)`` cone apexes (m, world frame).
        headings: ``(K,)`` cone axes (rad, world frame).
        half_width_rad: half the opening angle, in (0, pi/2).
        max_range_m: points farther than this are not echoes (m).
        geometry, exclude_owner: as in ``cast_rays``.

    Returns:
        ``ranges (K,)`` float64 (m), ``owners (K,)`` int64 and ``points (K, 2)`` (m, world
        frame); ``max_range_m``, -1 and NaN where the cone holds nothing within range.

    Raises:
        ValueError, TypeError: as ``cast_rays``, or for a half-width outside (0, pi/2).
    """
    apexes, headings = _rays_input("apexes", apexes, "headings", headings)
    half = check_half_width(half_width_rad)
    g = check_geometry(geometry)
    return cones_kernel(
        0.0,
        0.0,
        0.0,
        apexes,
        headings,
        half,
        check_positive("max_range_m", max_range_m),
        g.segments,
        g.segment_owner,
        g.circles,
        g.circle_owner,
        check_owner(exclude_owner),
    )


def cone_nearest(
    apexes, headings, half_width_rad: float, max_range_m: float, geometry: SceneGeometry, exclude_owner: int = -1
) -> tuple[np.ndarray, np.ndarray]:
    """``ranges (K,)`` and ``owners (K,)`` of ``cone_nearest_points`` (the nearest echo per cone)."""
    ranges, owners, _ = cone_nearest_points(apexes, headings, half_width_rad, max_range_m, geometry, exclude_owner)
    return ranges, owners
