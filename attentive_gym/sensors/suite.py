"""The robot's sensors together: the sonar ring and the laser, with range noise.

- ``SensorReading``: one reading of every sensor, with the owner id each echo came from.
- ``SensorSuite``: reads both sensors at a pose, adds noise from the caller's RNG, and
  gives the geometry of a reading for drawing (``laser_segments``, ``sonar_cones``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from attentive_gym.sensors._checks import check_geometry, check_owner, check_pose, check_relative_std
from attentive_gym.sensors.geometry import SceneGeometry
from attentive_gym.sensors.laser import LaserConfig, LaserScanner
from attentive_gym.sensors.noise import apply_range_noise
from attentive_gym.sensors.sonar import SonarConfig, SonarRing

__all__ = ["SensorReading", "SensorSuite"]


@dataclass(frozen=True, eq=False)
class SensorReading:
    """One reading of the sonar ring and the laser.

    Attributes:
        sonar: ``(N,)`` float64 sonar ranges (m), max range = no echo (N = 16 for a P2AT).
        laser: ``(B,)`` float64 laser ranges (m), max range = nothing within range.
        sonar_owner: ``(N,)`` int64 owner id of the body each sonar's echo came from.
        laser_owner: ``(B,)`` int64 owner id of the body each beam hit.

    Owners are the noise-free truth (-1: no echo); noise changes only the ranges.
    """

    sonar: np.ndarray
    laser: np.ndarray
    sonar_owner: np.ndarray
    laser_owner: np.ndarray


class SensorSuite:
    """The sonar ring and laser scanner of the attentive robot.

    Args:
        sonar: the ring (default: P2AT).
        laser: the scanner (default: 180 beams over 180 deg, 20 m).
        noise_std: relative standard deviation sigma of the multiplicative Gaussian
            range noise (``noise.apply_range_noise``), finite, 0 <= sigma < 1; 0 gives
            exact readings (the RNG is still advanced by the same amount).

    Raises:
        ValueError: for a bad ``noise_std``. TypeError: for configs of the wrong type.

    Example:
        >>> suite = SensorSuite(noise_std=0.0)
        >>> from attentive_gym.sensors import SceneGeometry
        >>> reading = suite.read((0.0, 0.0, 0.0), SceneGeometry.empty(), np.random.default_rng(0))
        >>> float(reading.sonar.max()), float(reading.laser.min())
        (5.0, 20.0)
    """

    def __init__(self, sonar: SonarConfig = SonarConfig(), laser: LaserConfig = LaserConfig(),
                 noise_std: float = 0.05) -> None:
        self.sonar_ring = SonarRing(sonar)
        self.laser_scanner = LaserScanner(laser)
        self.noise_std = check_relative_std("noise_std", noise_std)

    def read(self, pose, geometry: SceneGeometry, rng: np.random.Generator,
             exclude_owner: int = -1) -> SensorReading:
        """Read every sensor from the robot at ``pose``.

        Args:
            pose: ``(3,)`` robot ``x_m, y_m, theta_rad`` (world frame).
            geometry: the scene.
            rng: source of the noise: 16 + 180 standard normals per call (sonar first,
                then laser) for the default sensors, whatever ``noise_std``.
            exclude_owner: the robot's own owner id (ignored by its sensors), -1 for none.

        Returns:
            The noisy ``SensorReading``; the laser's lower clip is 0 m.
        """
        x, y, theta = check_pose(pose)
        geometry = check_geometry(geometry)
        exclude = check_owner(exclude_owner)
        sonar, sonar_owner = self.sonar_ring.sweep(x, y, theta, geometry, exclude)
        laser, laser_owner = self.laser_scanner.sweep(x, y, theta, geometry, exclude)
        s, c = self.sonar_ring.config, self.laser_scanner.config
        return SensorReading(
            sonar=apply_range_noise(sonar, self.noise_std, s.min_range_m, s.max_range_m, rng),
            laser=apply_range_noise(laser, self.noise_std, 0.0, c.max_range_m, rng),
            sonar_owner=sonar_owner,
            laser_owner=laser_owner,
        )

    def laser_segments(self, pose, reading: SensorReading) -> np.ndarray:
        """``(2, B, 2)`` beam origins and ends of ``reading`` (m, world frame) for drawing."""
        return self.laser_scanner.beam_endpoints(pose, reading.laser)

    def sonar_cones(self, pose, reading: SensorReading) -> list[np.ndarray]:
        """One ``(P, 2)`` cone polygon per sonar of ``reading`` (m, world frame) for drawing."""
        return self.sonar_ring.cone_polygons(pose, reading.sonar)
