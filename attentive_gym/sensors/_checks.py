"""Argument checks shared by the sensor modules (the Python boundary of the kernels).

Each returns the value converted to what the kernels take, or raises an error that says
what was wrong and what is allowed.
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from attentive_gym.sensors.geometry import SceneGeometry

__all__ = [
    "check_geometry",
    "check_half_width",
    "check_owner",
    "check_pose",
    "check_positive",
    "check_relative_std",
    "check_scan_interval",
]


def _is_real(value) -> bool:
    """Whether ``value`` is a real number (Python's or numpy's), not a bool or a string."""
    return isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_))


def check_positive(name: str, value) -> float:
    """``value`` as a float, or ``ValueError`` unless it is a finite real number > 0."""
    if not (_is_real(value) and math.isfinite(value) and value > 0.0):
        raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
    return float(value)


def check_half_width(half_width_rad) -> float:
    """``half_width_rad`` as a float, or ``ValueError`` unless it lies in (0, pi/2)."""
    half = check_positive("half_width_rad", half_width_rad)
    if half >= math.pi / 2.0:
        raise ValueError(f"half_width_rad must be in (0, pi/2) so the cone is convex, got {half_width_rad!r}")
    return half


def check_relative_std(name: str, value) -> float:
    """``value`` as a float, or ``ValueError`` unless it is finite with 0 <= value < 1.

    Below 1 so that one standard deviation of noise cannot flip a range's sign.
    """
    if not (_is_real(value) and math.isfinite(value) and 0.0 <= value < 1.0):
        raise ValueError(f"{name} must be a finite number in [0, 1), got {value!r}")
    return float(value)


def check_scan_interval(name: str, value) -> float | None:
    """``value`` as a float (s), ``None`` for "every step", or ``ValueError`` unless it is
    ``None`` or a finite real number > 0 (strings and bools are refused)."""
    if value is None:
        return None
    if not (_is_real(value) and math.isfinite(value) and value > 0.0):
        raise ValueError(f"{name} must be None (a scan every step) or a finite number of seconds > 0, got {value!r}")
    return float(value)


def check_geometry(geometry) -> SceneGeometry:
    """``geometry`` itself, or ``TypeError`` unless it is a ``SceneGeometry``."""
    if not isinstance(geometry, SceneGeometry):
        raise TypeError(f"geometry must be a SceneGeometry, got {type(geometry).__name__}")
    return geometry


def check_owner(exclude_owner) -> int:
    """``exclude_owner`` as an int, or ``TypeError`` unless it is an integer (-1: none)."""
    if isinstance(exclude_owner, bool) or not isinstance(exclude_owner, (int, np.integer)):
        raise TypeError(f"exclude_owner must be an int (-1 for none), got {exclude_owner!r}")
    return int(exclude_owner)


def check_pose(pose) -> tuple[float, float, float]:
    """``pose`` as ``(x_m, y_m, theta_rad)`` floats, or ``ValueError`` unless finite with shape (3,)."""
    array = np.asarray(pose)
    if array.dtype.kind not in "iuf":  # not strings, bools, objects or complex numbers
        raise ValueError(f"pose must be numeric (3,) = x_m, y_m, theta_rad; got {pose!r}")
    array = array.astype(np.float64, copy=False)
    if array.shape != (3,) or not np.isfinite(array).all():
        raise ValueError(f"pose must be finite with shape (3,) = x_m, y_m, theta_rad; got {array.tolist()!r}")
    return float(array[0]), float(array[1]), float(array[2])
