"""A planar laser scanner (default: 180 beams over the front 180 deg, 20 m).

- ``LaserConfig``: beam count, field of view, range and mounting point.
- ``LaserScanner``: noise-free ranges and hit owners at a robot pose (``read``) and the
  beam segments of a reading for drawing (``beam_endpoints``).

Beam ``i`` points at bearing ``-fov/2 + (i + 0.5) fov / num_beams`` in the robot frame
(x forward, y left, counter-clockwise): beam 0 is the rightmost. All beams start at the
mounting point, so the scan is one ``raycast.cast_fan``.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

import numpy as np

from attentive_gym.sensors._checks import check_geometry, check_owner, check_pose
from attentive_gym.sensors.geometry import SceneGeometry
from attentive_gym.sensors.raycast import fan_kernel

__all__ = ["LaserConfig", "LaserScanner"]


@dataclass(frozen=True)
class LaserConfig:
    """A laser scanner mounted on the robot (defaults: the paper's 180-beam laser).

    Attributes:
        num_beams: number of beams (int >= 1).
        fov_deg: field of view (deg), in (0, 360], centred on the robot's heading.
        max_range_m: saturation range (m), > 0: no hit within it reads it.
        mount_x_m, mount_y_m: the beams' common origin in the robot frame (m).

    Raises:
        ValueError: for a non-finite or out-of-range value.
    """

    num_beams: int = 180
    fov_deg: float = 180.0
    max_range_m: float = 20.0
    mount_x_m: float = 0.16
    mount_y_m: float = 0.0

    def __post_init__(self) -> None:
        if isinstance(self.num_beams, bool) or not isinstance(self.num_beams, numbers.Integral) or self.num_beams < 1:
            raise ValueError(f"LaserConfig.num_beams must be an int >= 1, got {self.num_beams!r}")
        object.__setattr__(self, "num_beams", int(self.num_beams))
        for name in ("fov_deg", "max_range_m", "mount_x_m", "mount_y_m"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value):
                raise ValueError(f"LaserConfig.{name} must be a finite number, got {value!r}")
            object.__setattr__(self, name, float(value))
        if not 0.0 < self.fov_deg <= 360.0:
            raise ValueError(f"LaserConfig.fov_deg must be in (0, 360], got {self.fov_deg!r}")
        if not self.max_range_m > 0.0:
            raise ValueError(f"LaserConfig.max_range_m must be > 0, got {self.max_range_m!r}")

    @property
    def step_rad(self) -> float:
        """Angle between neighbouring beams (rad)."""
        return math.radians(self.fov_deg) / self.num_beams

    @property
    def bearings_rad(self) -> np.ndarray:
        """``(num_beams,)`` beam bearings in the robot frame (rad), rightmost first."""
        return -math.radians(self.fov_deg) / 2.0 + (np.arange(self.num_beams) + 0.5) * self.step_rad


class LaserScanner:
    """Noise-free scans of a laser scanner.

    Args:
        config: the scanner.

    Example:
        >>> from attentive_gym.sensors import SceneGeometry
        >>> wall = SceneGeometry(np.array([[3.16, -50.0, 3.16, 50.0]]), np.array([4]),
        ...                      np.empty((0, 3)), np.empty(0, int))
        >>> ranges, owners = LaserScanner(LaserConfig()).read((0.0, 0.0, 0.0), wall)
        >>> round(float(ranges[90]), 4), int(owners[90])  # 3 m / cos(0.5 deg)
        (3.0001, 4)
    """

    def __init__(self, config: LaserConfig = LaserConfig()) -> None:
        if not isinstance(config, LaserConfig):
            raise TypeError(f"config must be a LaserConfig, got {type(config).__name__}")
        self.config = config
        self._first_bearing_rad = float(config.bearings_rad[0])

    def read(self, pose, geometry: SceneGeometry, exclude_owner: int = -1) -> tuple[np.ndarray, np.ndarray]:
        """One scan from the robot at ``pose``.

        Args:
            pose: ``(3,)`` robot ``x_m, y_m, theta_rad`` (world frame).
            geometry: the scene.
            exclude_owner: owner id the scanner ignores (the robot's own body), -1 for none.

        Returns:
            ``ranges (num_beams,)`` float64 in ``[0, max_range_m]`` (m) and
            ``owners (num_beams,)`` int64 (-1: nothing within range).
        """
        return self.sweep(*check_pose(pose), check_geometry(geometry), check_owner(exclude_owner))

    def sweep(
        self, x_m: float, y_m: float, theta_rad: float, geometry: SceneGeometry, exclude_owner: int
    ) -> tuple[np.ndarray, np.ndarray]:
        """``read`` without argument checks (the hot path of ``SensorSuite``)."""
        c = self.config
        ox, oy = self._origin(x_m, y_m, theta_rad)
        return fan_kernel(
            ox,
            oy,
            theta_rad + self._first_bearing_rad,
            c.step_rad,
            c.num_beams,
            c.max_range_m,
            geometry.segments,
            geometry.segment_owner,
            geometry.circles,
            geometry.circle_owner,
            exclude_owner,
        )

    def beam_endpoints(self, pose, ranges) -> np.ndarray:
        """``(2, num_beams, 2)``: the beams' origin repeated, and each beam's end at its
        read range (m, world frame; for drawing)."""
        x, y, theta = check_pose(pose)
        ranges = np.asarray(ranges, dtype=np.float64)
        if ranges.shape != (self.config.num_beams,):
            raise ValueError(f"ranges must have shape ({self.config.num_beams},), got {ranges.shape}")
        origin = np.array(self._origin(x, y, theta))
        angles = theta + self.config.bearings_rad
        ends = origin + ranges[:, None] * np.column_stack([np.cos(angles), np.sin(angles)])
        return np.stack([np.broadcast_to(origin, ends.shape), ends])

    def _origin(self, x_m: float, y_m: float, theta_rad: float) -> tuple[float, float]:
        """The beams' origin in the world frame (m)."""
        c, s = math.cos(theta_rad), math.sin(theta_rad)
        mx, my = self.config.mount_x_m, self.config.mount_y_m
        return x_m + c * mx - s * my, y_m + s * mx + c * my
