"""The Pioneer P2AT/P3AT sonar ring: 16 cones, each reading its nearest echo exactly.

- ``P2AT_SONAR_MOUNTS``: the ring's ``(16, 3)`` mounts ``x_m, y_m, bearing_rad`` (robot frame).
- ``SonarConfig``: range limits, cone half-width and mounts.
- ``SonarRing``: noise-free readings of a ring at a robot pose (``read``) and the cone
  polygons of a reading for drawing (``cone_polygons``).

Robot frame: x forward, y left, bearings counter-clockwise from the heading. A reading
is the distance from the transducer to the nearest point of the scene inside its cone
(``raycast.cone_nearest``), not a fan of rays: a thin pole inside the cone is never
missed. Nearer than the minimum range reads the minimum range; nothing within the
maximum range reads the maximum range ("no echo", owner -1).
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

import numpy as np

from attentive_gym.sensors._checks import check_geometry, check_half_width, check_owner, check_pose
from attentive_gym.sensors.geometry import SceneGeometry
from attentive_gym.sensors.raycast import cones_kernel

__all__ = ["P2AT_SONAR_MOUNTS", "SonarConfig", "SonarRing"]

# ARIA's p3at.p parameter file: SonarUnit x (mm), y (mm), heading (deg); front 0..7, rear 8..15
_P2AT_MOUNTS_MM_DEG = (
    (147, 136, 90),
    (193, 119, 50),
    (227, 79, 30),
    (245, 27, 10),
    (245, -27, -10),
    (227, -79, -30),
    (193, -119, -50),
    (147, -136, -90),
    (-144, -136, -90),
    (-189, -119, -130),
    (-223, -79, -150),
    (-241, -27, -170),
    (-241, 27, 170),
    (-223, 79, 150),
    (-189, 119, 130),
    (-144, 136, 90),
)
_P2AT_MOUNTS = tuple((x / 1000.0, y / 1000.0, math.radians(deg)) for x, y, deg in _P2AT_MOUNTS_MM_DEG)

#: ``(16, 3)`` P2AT/P3AT sonar mounts: ``x_m, y_m, bearing_rad`` in the robot frame
#: (x forward, y left); indices 0..7 front (+90 ... -90 deg), 8..15 rear (-90 ... +90 deg).
P2AT_SONAR_MOUNTS = np.array(_P2AT_MOUNTS)
P2AT_SONAR_MOUNTS.flags.writeable = False

#: Number of arc points per cone polygon in ``SonarRing.cone_polygons`` (drawing only).
_CONE_ARC_POINTS = 7


@dataclass(frozen=True)
class SonarConfig:
    """A sonar ring (defaults: Pioneer P2AT).

    Attributes:
        min_range_m: echoes nearer than this read this (m), >= 0.
        max_range_m: no echo within this reads this (m), > ``min_range_m``.
        cone_half_width_deg: half the opening angle of every cone (deg), in (0, 90).
        mounts: ``(N, 3)`` ``x_m, y_m, bearing_rad`` per transducer in the robot frame;
            stored as a tuple of float triples (so configs compare and hash).

    Raises:
        ValueError: for a non-finite or out-of-range value or badly shaped mounts.
    """

    min_range_m: float = 0.15
    max_range_m: float = 5.0
    cone_half_width_deg: float = 15.0
    mounts: tuple[tuple[float, float, float], ...] = _P2AT_MOUNTS

    def __post_init__(self) -> None:
        for name in ("min_range_m", "max_range_m", "cone_half_width_deg"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value):
                raise ValueError(f"SonarConfig.{name} must be a finite number, got {value!r}")
            object.__setattr__(self, name, float(value))
        if not 0.0 <= self.min_range_m < self.max_range_m:
            raise ValueError(
                f"SonarConfig needs 0 <= min_range_m < max_range_m, got {self.min_range_m!r} and {self.max_range_m!r}"
            )
        if not 0.0 < self.cone_half_width_deg < 90.0:
            raise ValueError(f"SonarConfig.cone_half_width_deg must be in (0, 90), got {self.cone_half_width_deg!r}")
        try:
            mounts = np.array(self.mounts, dtype=np.float64)
        except (TypeError, ValueError):
            raise ValueError(
                f"SonarConfig.mounts must be numeric (N, 3) = x_m, y_m, bearing_rad; got {self.mounts!r}"
            ) from None
        if mounts.ndim != 2 or mounts.shape[1] != 3 or len(mounts) == 0 or not np.isfinite(mounts).all():
            raise ValueError(f"SonarConfig.mounts must be finite with shape (N, 3), N >= 1; got shape {mounts.shape}")
        object.__setattr__(self, "mounts", tuple(tuple(float(v) for v in row) for row in mounts))


class SonarRing:
    """Noise-free readings of a sonar ring.

    Args:
        config: the ring.

    Example:
        >>> from attentive_gym.sensors import SceneGeometry
        >>> wall = SceneGeometry(np.array([[3.0, -5.0, 3.0, 5.0]]), np.array([1]), np.empty((0, 3)), np.empty(0, int))
        >>> ranges, owners = SonarRing(SonarConfig()).read((0.0, 0.0, 0.0), wall)
        >>> round(float(ranges[3]), 3), int(owners[3])  # s4 at (0.245 m, 0.027 m), +10 deg
        (2.755, 1)
    """

    def __init__(self, config: SonarConfig = SonarConfig()) -> None:
        if not isinstance(config, SonarConfig):
            raise TypeError(f"config must be a SonarConfig, got {type(config).__name__}")
        self.config = config
        mounts = np.array(config.mounts)
        self._positions = np.ascontiguousarray(mounts[:, :2])
        self._bearings = np.ascontiguousarray(mounts[:, 2])
        self._half_width_rad = check_half_width(math.radians(config.cone_half_width_deg))

    @property
    def num_sonars(self) -> int:
        """Number of transducers N."""
        return len(self._bearings)

    def read(self, pose, geometry: SceneGeometry, exclude_owner: int = -1) -> tuple[np.ndarray, np.ndarray]:
        """Each cone's nearest echo from the robot at ``pose``.

        Args:
            pose: ``(3,)`` robot ``x_m, y_m, theta_rad`` (world frame).
            geometry: the scene.
            exclude_owner: owner id the ring ignores (the robot's own body), -1 for none.

        Returns:
            ``ranges (N,)`` float64 in ``[min_range_m, max_range_m]`` (m) and
            ``owners (N,)`` int64 (-1: no echo).
        """
        return self.sweep(*check_pose(pose), check_geometry(geometry), check_owner(exclude_owner))

    def sweep(
        self, x_m: float, y_m: float, theta_rad: float, geometry: SceneGeometry, exclude_owner: int
    ) -> tuple[np.ndarray, np.ndarray]:
        """``read`` without argument checks (the hot path of ``SensorSuite``)."""
        c = self.config
        ranges, owners, _ = cones_kernel(
            x_m,
            y_m,
            theta_rad,
            self._positions,
            self._bearings,
            self._half_width_rad,
            c.max_range_m,
            geometry.segments,
            geometry.segment_owner,
            geometry.circles,
            geometry.circle_owner,
            exclude_owner,
        )
        np.maximum(ranges, c.min_range_m, out=ranges)
        return ranges, owners

    def cone_polygons(self, pose, ranges) -> list[np.ndarray]:
        """One ``(P, 2)`` world-frame polygon (m) per transducer: its apex and an arc of
        ``_CONE_ARC_POINTS`` points at the read range across the cone (for drawing)."""
        x, y, theta = check_pose(pose)
        ranges = np.asarray(ranges, dtype=np.float64)
        if ranges.shape != (self.num_sonars,):
            raise ValueError(f"ranges must have shape ({self.num_sonars},), got {ranges.shape}")
        c, s = math.cos(theta), math.sin(theta)
        apexes = np.column_stack(
            [
                x + c * self._positions[:, 0] - s * self._positions[:, 1],
                y + s * self._positions[:, 0] + c * self._positions[:, 1],
            ]
        )
        spread = np.linspace(-self._half_width_rad, self._half_width_rad, _CONE_ARC_POINTS)
        angles = theta + self._bearings[:, None] + spread[None, :]  # (N, P - 1)
        arcs = apexes[:, None, :] + ranges[:, None, None] * np.stack([np.cos(angles), np.sin(angles)], axis=-1)
        return [np.vstack([apex[None, :], arc]) for apex, arc in zip(apexes, arcs)]
