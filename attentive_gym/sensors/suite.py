"""The robot's sensors together: the sonar ring and the laser, with range noise.

- ``SensorReading``: one reading of every sensor, with the owner id each echo came from.
- ``SensorSuite``: reads both sensors at a pose, adds Gaussian or uniform noise
  (``noise.NOISE_MODELS``) from the caller's RNG, and
  gives the geometry of a reading for drawing (``laser_segments``, ``sonar_cones``);
  ``read_many`` reads many robots' sensors in one compiled call (a batched env's fleet).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numba import njit, prange

from attentive_gym.sensors._checks import check_geometry, check_owner, check_pose, check_relative_std
from attentive_gym.sensors.geometry import SceneGeometry
from attentive_gym.sensors.laser import LaserConfig, LaserScanner
from attentive_gym.sensors.noise import check_noise_model, unit_noise
from attentive_gym.sensors.raycast import cones_kernel, fan_kernel
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
        noise_std: the relative level of the multiplicative range noise
            (``noise.apply_range_noise``): sigma for ``"gaussian"``, the half-width ``a``
            of ``U[-a, a)`` for ``"uniform"``; finite, 0 <= level < 1; 0 gives exact
            readings (the RNG is still advanced by the same amount).
        noise_model: one of ``noise.NOISE_MODELS``.

    Raises:
        ValueError: for a bad ``noise_std`` or ``noise_model``. TypeError: for configs of the wrong type.

    Example:
        >>> suite = SensorSuite(noise_std=0.0)
        >>> from attentive_gym.sensors import SceneGeometry
        >>> reading = suite.read((0.0, 0.0, 0.0), SceneGeometry.empty(), np.random.default_rng(0))
        >>> float(reading.sonar.max()), float(reading.laser.min())
        (5.0, 20.0)
    """

    def __init__(
        self,
        sonar: SonarConfig = SonarConfig(),
        laser: LaserConfig = LaserConfig(),
        noise_std: float = 0.05,
        noise_model: str = "gaussian",
    ) -> None:
        self.sonar_ring = SonarRing(sonar)
        self.laser_scanner = LaserScanner(laser)
        self.noise_std = check_relative_std("noise_std", noise_std)
        self.noise_model = check_noise_model("noise_model", noise_model)
        self._num_readings = self.sonar_ring.num_sonars + self.laser_scanner.config.num_beams
        self._laser_step_rad = self.laser_scanner.config.step_rad

    def read(self, pose, geometry: SceneGeometry, rng: np.random.Generator, exclude_owner: int = -1) -> SensorReading:
        """Read every sensor from the robot at ``pose``.

        Args:
            pose: ``(3,)`` robot ``x_m, y_m, theta_rad`` (world frame).
            geometry: the scene.
            rng: source of the noise: one draw per reading, 16 + 180 per call (sonar
                first, then laser) for the default sensors, whatever ``noise_std`` and
                whatever the sensors see: standard normals for ``"gaussian"``,
                ``rng.random`` uniforms for ``"uniform"`` (``noise.unit_noise``).
            exclude_owner: the robot's own owner id (ignored by its sensors), -1 for none.

        Returns:
            The noisy ``SensorReading``; the laser's lower clip is 0 m.
        """
        x, y, theta = check_pose(pose)
        geometry = check_geometry(geometry)
        exclude = check_owner(exclude_owner)
        if not isinstance(rng, np.random.Generator):
            raise TypeError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
        # one draw for both sensors: the same stream as sonar's draws, then the laser's
        draws = unit_noise(self.noise_model, self._num_readings, rng)
        ring, scanner = self.sonar_ring, self.laser_scanner
        s, c = ring.config, scanner.config
        ox, oy = scanner._origin(x, y, theta)
        sonar, sonar_owner, laser, laser_owner = _read_kernel(
            x,
            y,
            theta,
            ring._positions,
            ring._bearings,
            ring._half_width_rad,
            s.min_range_m,
            s.max_range_m,
            ox,
            oy,
            theta + scanner._first_bearing_rad,
            self._laser_step_rad,
            c.num_beams,
            c.max_range_m,
            geometry.segments,
            geometry.segment_owner,
            geometry.circles,
            geometry.circle_owner,
            exclude,
            self.noise_std,
            draws,
        )
        return _reading(sonar, laser, sonar_owner, laser_owner)

    def read_many(self, requests: Sequence[tuple]) -> list[SensorReading]:
        """Read the sensors of many robots, all with these sensors, in one compiled call.

        Args:
            requests: one ``(pose, geometry, rng, exclude_owner)`` per robot, as the
                arguments of ``read``.

        Returns:
            One ``SensorReading`` per request, the same, bit for bit, as ``read`` of each
            request in turn gives (each robot's noise is drawn from its own ``rng``, in the
            same order); the robots are swept in parallel on the machine's cores.
        """
        n = len(requests)
        if n == 0:
            return []
        poses = np.array([request[0] for request in requests], dtype=np.float64)
        if poses.shape != (n, 3) or not np.isfinite(poses).all():
            raise ValueError(
                f"every request's pose must be finite with shape (3,) = x_m, y_m, theta_rad; got {poses!r}"
            )
        geometries = [check_geometry(request[1]) for request in requests]
        excludes = np.array([check_owner(request[3]) for request in requests], np.int64)
        draws = np.empty((n, self._num_readings))
        for i, request in enumerate(requests):
            if not isinstance(request[2], np.random.Generator):
                raise TypeError(f"request {i}: rng must be a numpy.random.Generator, got {type(request[2]).__name__}")
            unit_noise(self.noise_model, self._num_readings, request[2], out=draws[i])
        scanner = self.laser_scanner
        laser = np.array(
            [(*scanner._origin(x, y, theta), theta + scanner._first_bearing_rad) for x, y, theta in poses.tolist()]
        )  # origin x, y (m), first beam's bearing (rad)
        segment_end = np.cumsum([g.segments.shape[0] for g in geometries])
        circle_end = np.cumsum([g.circles.shape[0] for g in geometries])
        ring = self.sonar_ring
        s, c = ring.config, scanner.config
        sonar, sonar_owner = np.empty((n, ring.num_sonars)), np.empty((n, ring.num_sonars), np.int64)
        beams, beam_owner = np.empty((n, c.num_beams)), np.empty((n, c.num_beams), np.int64)
        _read_many_kernel(
            poses,
            ring._positions,
            ring._bearings,
            ring._half_width_rad,
            s.min_range_m,
            s.max_range_m,
            laser,
            self._laser_step_rad,
            c.num_beams,
            c.max_range_m,
            np.concatenate([g.segments for g in geometries]),
            np.concatenate([g.segment_owner for g in geometries]),
            segment_end,
            np.concatenate([g.circles for g in geometries]),
            np.concatenate([g.circle_owner for g in geometries]),
            circle_end,
            excludes,
            self.noise_std,
            draws,
            sonar,
            sonar_owner,
            beams,
            beam_owner,
        )
        return [_reading(sonar[i], beams[i], sonar_owner[i], beam_owner[i]) for i in range(n)]

    def laser_segments(self, pose, reading: SensorReading) -> np.ndarray:
        """``(2, B, 2)`` beam origins and ends of ``reading`` (m, world frame) for drawing."""
        return self.laser_scanner.beam_endpoints(pose, reading.laser)

    def sonar_cones(self, pose, reading: SensorReading) -> list[np.ndarray]:
        """One ``(P, 2)`` cone polygon per sonar of ``reading`` (m, world frame) for drawing."""
        return self.sonar_ring.cone_polygons(pose, reading.sonar)


def _reading(sonar, laser, sonar_owner, laser_owner) -> SensorReading:
    reading = object.__new__(SensorReading)  # the dataclass's fields, without its frozen __init__
    reading.__dict__.update(sonar=sonar, laser=laser, sonar_owner=sonar_owner, laser_owner=laser_owner)
    return reading


@njit(cache=True)
def _noisy(ranges, sigma, draws, offset, min_range, max_range):
    """``noise.apply_range_noise`` in place, with the unit draws ``draws[offset:]``."""
    for k in range(ranges.shape[0]):
        r = ranges[k]
        if r >= max_range:
            ranges[k] = max_range
            continue
        v = r * (1.0 + sigma * draws[offset + k])
        if v < min_range:
            v = min_range
        elif v > max_range:
            v = max_range
        ranges[k] = v


@njit(cache=True)
def _read_kernel(
    x,
    y,
    theta,
    sonar_positions,
    sonar_bearings,
    half_width,
    sonar_min,
    sonar_max,
    laser_x,
    laser_y,
    laser_first,
    laser_step,
    num_beams,
    laser_max,
    segments,
    segment_owner,
    circles,
    circle_owner,
    exclude,
    sigma,
    draws,
):
    """``SensorSuite.read`` after its checks: both sweeps and the noise in one call."""
    sonar, sonar_owner, _ = cones_kernel(
        x,
        y,
        theta,
        sonar_positions,
        sonar_bearings,
        half_width,
        sonar_max,
        segments,
        segment_owner,
        circles,
        circle_owner,
        exclude,
    )
    for k in range(sonar.shape[0]):
        if sonar[k] < sonar_min:
            sonar[k] = sonar_min
    laser, laser_owner = fan_kernel(
        laser_x,
        laser_y,
        laser_first,
        laser_step,
        num_beams,
        laser_max,
        segments,
        segment_owner,
        circles,
        circle_owner,
        exclude,
    )
    _noisy(sonar, sigma, draws, 0, sonar_min, sonar_max)
    _noisy(laser, sigma, draws, sonar.shape[0], 0.0, laser_max)
    return sonar, sonar_owner, laser, laser_owner


@njit(cache=True, parallel=True)
def _read_many_kernel(
    poses,
    sonar_positions,
    sonar_bearings,
    half_width,
    sonar_min,
    sonar_max,
    laser,
    laser_step,
    num_beams,
    laser_max,
    segments,
    segment_owner,
    segment_end,
    circles,
    circle_owner,
    circle_end,
    excludes,
    sigma,
    draws,
    sonar_out,
    sonar_owner_out,
    laser_out,
    laser_owner_out,
):
    """``_read_kernel`` for robot i of ``poses`` ``(n, 3)`` in the scene ``segments[segment_end[i-1]:segment_end[i]]``
    (and likewise the circles), one robot per parallel iteration, into row i of the outputs."""
    for i in prange(poses.shape[0]):
        s0 = 0 if i == 0 else segment_end[i - 1]
        c0 = 0 if i == 0 else circle_end[i - 1]
        sonar, sonar_owner, beams, beam_owner = _read_kernel(
            poses[i, 0],
            poses[i, 1],
            poses[i, 2],
            sonar_positions,
            sonar_bearings,
            half_width,
            sonar_min,
            sonar_max,
            laser[i, 0],
            laser[i, 1],
            laser[i, 2],
            laser_step,
            num_beams,
            laser_max,
            segments[s0 : segment_end[i]],
            segment_owner[s0 : segment_end[i]],
            circles[c0 : circle_end[i]],
            circle_owner[c0 : circle_end[i]],
            excludes[i],
            sigma,
            draws[i],
        )
        sonar_out[i] = sonar
        sonar_owner_out[i] = sonar_owner
        laser_out[i] = beams
        laser_owner_out[i] = beam_owner
