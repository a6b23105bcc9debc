"""Kinematics from sensorial memory (MODEL.md §3): pure functions over arrays.

- ``slope_weights``: least-squares slope weights for samples at given times.
- ``speeds``, ``direction_labels``: ``s = min(|v|, MAX_SPEED)`` and ``d ∈ {−1, 0, +1}``.
- ``planar_displacement``: the robot's motion over an interval from its odometry.
- ``predict_scan``: a static world's laser scan after the robot moved.
- ``point_range_change``: MODEL.md's sonar prediction ``−v dt cos θ`` (point-like echo).
- ``virtual_sonar``: the nearest laser echo inside each sonar cone.

Units: seconds, metres, m/s, radians. Range rates are positive when the range grows
(moving away), as in MODEL.md (d = +1 away, −1 towards).
"""

from __future__ import annotations

import math

import numpy as np

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


def planar_displacement(linear_mps: float, angular_rps: float, dt_s: float) -> tuple[float, float, float]:
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


def predict_scan(ranges_m: np.ndarray, cos_b: np.ndarray, sin_b: np.ndarray, bearings_rad: np.ndarray,
                 dx_m: float, dy_m: float, dtheta_rad: float) -> np.ndarray:
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

    First order in the displacement: ``Δs = −(dx cos θ + dy sin θ)``; MODEL.md's
    ``−v dt cos θ`` for a straight move. Rotation does not change a point's range.
    """
    return -(dx_m * cos_b + dy_m * sin_b)


def virtual_sonar(scan_m: np.ndarray, bearings_rad: np.ndarray,
                  cone_plan: tuple[np.ndarray, np.ndarray, np.ndarray]) -> np.ndarray:
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
