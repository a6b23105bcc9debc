"""Kinematics from sensorial memory (docs/model.md §3): pure functions over arrays.

- ``slope_weights``: least-squares slope weights for samples at given times.
- ``speeds``, ``direction_labels``: ``s = min(|v|, MAX_SPEED)`` and ``d ∈ {−1, 0, +1}``.
- ``planar_displacement``: the robot's motion over an interval from its odometry.
- ``predict_scan``: a static world's laser scan after the robot moved.
- ``point_range_change``: docs/model.md's sonar prediction ``−v dt cos θ`` (point-like echo).
- ``virtual_sonar``: the nearest laser echo inside each sonar cone.
- ``scan_points``, ``ego_range_change``: compiled kernels of the model's step, the same
  arithmetic as ``predict_scan``, ``point_range_change`` and ``virtual_sonar``.

Units: seconds, metres, m/s, radians. Range rates are positive when the range grows
(moving away), as in docs/model.md (d = +1 away, −1 towards).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from attentive_gym.attention._numerics import interp_sorted

__all__ = [
    "slope_weights",
    "speeds",
    "direction_labels",
    "planar_displacement",
    "predict_scan",
    "point_range_change",
    "virtual_sonar",
    "STRAIGHT_LINE_TURN_RAD",
]

#: Below this heading change (rad) over one interval the arc is treated as a straight
#: line: the arc's lateral offset ``v dt · dθ/2`` is then below a nanometre per m/s.
STRAIGHT_LINE_TURN_RAD = 1e-9


def slope_weights(times_s: np.ndarray) -> np.ndarray:
    """Weights ``w`` such that ``w @ x`` is the least-squares slope of ``x`` over ``times_s``.

    The ordinary least-squares slope of samples ``x_k`` at times ``t_k`` is
    ``Σ (t_k − t̄)(x_k − x̄) / Σ (t_k − t̄)²``; because ``Σ (t_k − t̄) = 0`` the ``x̄`` term
    vanishes and the slope is linear in ``x`` with weights ``(t_k − t̄) / Σ (t − t̄)²``.
    With two samples this is the finite difference ``(x_1 − x_0)/(t_1 − t_0)``.

    Args:
        times_s: ``(..., n)`` sample times (s), n >= 2, not all equal.

    Returns:
        ``(..., n)`` weights (1/s).
    """
    t = np.asarray(times_s, dtype=float)
    centred = t - t.mean(axis=-1, keepdims=True)
    return centred / np.sum(centred * centred, axis=-1, keepdims=True)


def speeds(range_rates_mps: np.ndarray, max_speed_mps: float) -> np.ndarray:
    """Speeds ``s = min(|v|, MAX_SPEED)`` (m/s), same shape as ``range_rates_mps``."""
    return np.minimum(np.abs(range_rates_mps), max_speed_mps)


def direction_labels(range_rates_mps: np.ndarray, epsilon_mps: float) -> np.ndarray:
    """Direction labels: +1 away (``v > ε``), −1 towards (``v < −ε``), else 0 (float array)."""
    v = np.asarray(range_rates_mps, dtype=float)
    return np.sign(v) * (np.abs(v) > epsilon_mps)


@njit(cache=True)
def planar_displacement(linear_mps, angular_rps, dt_s):
    """The robot's displacement over ``dt_s`` at constant velocity, in its starting frame.

    Exact for a constant (v, ω) over the interval (a circular arc; a straight line when
    the heading change is below ``STRAIGHT_LINE_TURN_RAD``).

    Args:
        linear_mps: forward velocity v (m/s).
        angular_rps: counter-clockwise turn rate ω (rad/s).
        dt_s: interval (s).

    Returns:
        ``(dx_m, dy_m, dtheta_rad)``: the new position (x forward, y left) and heading
        change, expressed in the frame of the start of the interval.
    """
    dtheta = angular_rps * dt_s
    if abs(dtheta) < STRAIGHT_LINE_TURN_RAD:
        return linear_mps * dt_s, 0.0, dtheta
    radius = linear_mps / angular_rps
    return radius * math.sin(dtheta), radius * (1.0 - math.cos(dtheta)), dtheta


def predict_scan(
    ranges_m: np.ndarray,
    cos_b: np.ndarray,
    sin_b: np.ndarray,
    bearings_rad: np.ndarray,
    dx_m: float,
    dy_m: float,
    dtheta_rad: float,
) -> np.ndarray:
    """The scan a static world would give after the robot moved by ``(dx, dy, dθ)``.

    Each echo of the previous scan is a point ``r (cos b, sin b)``; it is moved into the
    new frame (translate by ``−(dx, dy)``, rotate by ``−dθ``) and the new ranges are read
    at the beam bearings by linear interpolation over the points' new bearings (made
    non-decreasing first, so occlusion folds become flat steps). Beams beyond the
    re-projected field of view take the nearest edge point's range.

    Args:
        ranges_m: ``(n,)`` previous scan (m), one range per beam.
        cos_b, sin_b: ``(n,)`` cosine and sine of the beam bearings.
        bearings_rad: ``(n,)`` beam bearings (rad), increasing.
        dx_m, dy_m, dtheta_rad: the robot's motion since the previous scan (see
            ``planar_displacement``).

    Returns:
        ``(n,)`` predicted ranges (m) at the same bearings.
    """
    x = ranges_m * cos_b - dx_m
    y = ranges_m * sin_b - dy_m
    new_bearings = np.arctan2(y, x) - dtheta_rad
    np.maximum.accumulate(new_bearings, out=new_bearings)
    return np.interp(bearings_rad, new_bearings, np.hypot(x, y))


def point_range_change(dx_m: float, dy_m: float, cos_b: np.ndarray, sin_b: np.ndarray) -> np.ndarray:
    """Range change of point-like echoes on the given bearings after a translation (m).

    First order in the displacement: ``Δs = −(dx cos θ + dy sin θ)``; docs/model.md's
    ``−v dt cos θ`` for a straight move. Rotation does not change a point's range.
    """
    return -(dx_m * cos_b + dy_m * sin_b)


def virtual_sonar(
    scan_m: np.ndarray, bearings_rad: np.ndarray, cone_plan: tuple[np.ndarray, np.ndarray, np.ndarray]
) -> np.ndarray:
    """Nearest laser echo inside each sonar cone: what a sonar would read from the laser.

    The minimum over the beams inside the cone and the scan linearly interpolated at the
    cone's two edges (exact for a wall, whose nearest point in a cone is either its foot
    inside the cone or a cone edge). Edges outside the laser's field of view read the
    outermost beam.

    Args:
        scan_m: ``(180,)`` laser ranges (m).
        bearings_rad: ``(180,)`` beam bearings (rad), increasing.
        cone_plan: ``regions.sonar_cone_reduction(half_width_deg)``.

    Returns:
        ``(8,)`` nearest range in each cone (m).
    """
    indices, take, edges = cone_plan
    inside = np.minimum.reduceat(scan_m, indices)[take]
    at_edges = np.interp(edges, bearings_rad, scan_m)
    return np.minimum(inside, at_edges.min(axis=1))


@njit(cache=True)
def scan_points(ranges_m, cos_b, sin_b, dx_m, dy_m, x_out, y_out):
    """A scan's echo points after a move of ``(dx, dy)``, as in ``predict_scan``:
    ``x = r cos b − dx``, ``y = r sin b − dy`` (m), written into ``x_out``, ``y_out`` ``(n,)``."""
    for i in range(ranges_m.shape[0]):
        x_out[i] = ranges_m[i] * cos_b[i] - dx_m
        y_out[i] = ranges_m[i] * sin_b[i] - dy_m


@njit(cache=True)
def ego_range_change(
    previous,
    angles,
    x,
    y,
    dtheta_rad,
    dx_m,
    dy_m,
    bearings_rad,
    sonar_cos,
    sonar_sin,
    cone_plan,
    cone_edges_rad,
    match_m,
    point_model,
    change,
):
    """The range change a static world shows after the robot's move, per channel (m).

    The arithmetic of ``predict_scan`` for the laser and of ``virtual_sonar`` /
    ``point_range_change`` for the sonars, operation for operation.

    Args:
        previous: ``(S + B,)`` the previous readings (m): S front sonars, then B beams.
        angles: ``(B,)`` ``np.arctan2(y, x)`` of the echo points (rad; numpy's arctan2,
            whose SIMD results differ from libm's in the last bit, so it is taken outside).
        x, y: ``(B,)`` the echo points in the new frame (``scan_points``, m).
        dtheta_rad, dx_m, dy_m: the move (``planar_displacement``).
        bearings_rad: ``(B,)`` beam bearings, increasing.
        sonar_cos, sonar_sin: ``(S,)`` of the front sonar bearings.
        cone_plan: ``(S, 4)`` int per sonar cone: its beams ``start <= i < stop``
            (``regions.sonar_cone_bounds``) and the places of its two edges in
            ``cone_edges_rad``.
        cone_edges_rad: ``(2S,)`` the bearings of all cone edges, increasing.
        match_m: ``sonar_ego_match_m``; point_model: True for ``sonar_ego_model="point"``.
        change: ``(S + B,)`` output (m).
    """
    n_sonar = sonar_cos.shape[0]
    n_beams = bearings_rad.shape[0]
    new_bearings = np.empty(n_beams)
    distances = np.empty(n_beams)
    for i in range(n_beams):
        bearing = angles[i] - dtheta_rad
        # np.maximum.accumulate: occlusion folds become flat steps
        new_bearings[i] = bearing if i == 0 or bearing > new_bearings[i - 1] else new_bearings[i - 1]
        distances[i] = math.hypot(x[i], y[i])
    predicted = np.empty(n_beams)
    interp_sorted(bearings_rad, new_bearings, distances, predicted)
    for i in range(n_beams):
        change[n_sonar + i] = predicted[i] - previous[n_sonar + i]
    laser_prev = previous[n_sonar:]
    if not point_model:
        # the scans at the cone edges, before and after the move
        edges_before = np.empty(2 * n_sonar)
        edges_after = np.empty(2 * n_sonar)
        interp_sorted(cone_edges_rad, bearings_rad, laser_prev, edges_before)
        interp_sorted(cone_edges_rad, bearings_rad, predicted, edges_after)
    for j in range(n_sonar):
        point = -(dx_m * sonar_cos[j] + dy_m * sonar_sin[j])
        if point_model:
            change[j] = point
            continue
        start, stop, edge0, edge1 = cone_plan[j, 0], cone_plan[j, 1], cone_plan[j, 2], cone_plan[j, 3]
        before = min(_min_of(laser_prev, start, stop), min(edges_before[edge0], edges_before[edge1]))
        after = min(_min_of(predicted, start, stop), min(edges_after[edge0], edges_after[edge1]))
        change[j] = after - before if abs(before - previous[j]) <= match_m else point


@njit(cache=True)
def _min_of(values, start, stop):
    """``values[start:stop].min()`` (stop > start)."""
    smallest = values[start]
    for i in range(start + 1, stop):
        smallest = min(smallest, values[i])
    return smallest
