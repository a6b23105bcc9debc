"""The robot's sensors together: the sonar ring and the laser, with range noise.

- ``SensorReading``: one reading of every sensor, with the owner id each echo came from.
- ``BatchReading``: the readings of N robots as ``(N, ·)`` blocks that a caller can reuse.
- ``SensorSuite``: reads both sensors at a pose, adds Gaussian or uniform noise
  (``noise.NOISE_MODELS``) from the caller's RNG, and gives the geometry of a reading for
  drawing (``laser_segments``, ``sonar_cones``). ``read_batch`` reads N robots in one
  compiled call (a batched env's perceive stage: place every member's moving bodies, sweep,
  add the noise); ``read`` (one robot) and ``read_many`` (a list of requests) are shells
  over the same per-robot kernel.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numba import njit, prange

from attentive_gym.sensors._checks import check_geometry, check_owner, check_pose, check_relative_std
from attentive_gym.sensors.geometry import SceneGeometry, place_moving
from attentive_gym.sensors.laser import LaserConfig, LaserScanner
from attentive_gym.sensors.noise import check_noise_model, unit_noise, unit_noise_rows
from attentive_gym.sensors.raycast import cones_kernel, fan_kernel
from attentive_gym.sensors.sonar import SonarConfig, SonarRing
from attentive_gym.sensors.stack import B0, B1, C0, C1, ENDPOINTS, P0, P1, S0, S1, SceneStack

__all__ = ["BatchReading", "SensorReading", "SensorSuite"]

#: Entries of the parameter vector the kernels take (``SensorSuite``'s, built once): the
#: sonar cone's half-width (rad) and range limits (m), the laser's mount in the robot frame
#: (m), the bearing of its first beam (rad), the angle between beams (rad) and its range
#: (m), and the relative noise level.
HALF_WIDTH, SONAR_MIN, SONAR_MAX, MOUNT_X, MOUNT_Y, FIRST_BEARING, LASER_STEP, LASER_MAX, NOISE_LEVEL = range(9)


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


@dataclass(frozen=True, eq=False)
class BatchReading:
    """The readings of N robots, row i for robot i: what ``SensorSuite.read_batch`` fills.

    Attributes:
        sonar: ``(N, K)`` float64 sonar ranges (m), K sonars.
        laser: ``(N, R)`` float64 laser ranges (m), R beams.
        sonar_owner: ``(N, K)`` int64 owner ids of the sonar echoes (-1: no echo).
        laser_owner: ``(N, R)`` int64 owner ids of the beams' hits (-1: nothing within range).
        unit_noise: ``(N, K + R)`` float64 unit draws (``noise.unit_noise``) each row's noise
            came from, sonar first.

    A block passed back to ``read_batch`` as ``out`` is overwritten in place: copy a row
    (or a ``reading(i)``) that must outlive the next read.

    Raises:
        ValueError: for arrays of inconsistent shapes, other dtypes, or not C-contiguous.
    """

    sonar: np.ndarray
    laser: np.ndarray
    sonar_owner: np.ndarray
    laser_owner: np.ndarray
    unit_noise: np.ndarray

    def __post_init__(self) -> None:
        n, k = self.sonar.shape if self.sonar.ndim == 2 else (-1, -1)
        r = self.laser.shape[1] if self.laser.ndim == 2 else -1
        expected = {
            "sonar": ((n, k), np.float64),
            "laser": ((n, r), np.float64),
            "sonar_owner": ((n, k), np.int64),
            "laser_owner": ((n, r), np.int64),
            "unit_noise": ((n, k + r), np.float64),
        }
        for name, (shape, dtype) in expected.items():
            array = getattr(self, name)
            if not (
                isinstance(array, np.ndarray)
                and array.shape == shape
                and array.dtype == dtype
                and array.flags.c_contiguous
                and array.flags.writeable
                and n >= 0
            ):
                raise ValueError(
                    f"BatchReading.{name} must be a writeable C-contiguous {np.dtype(dtype).name} array of shape "
                    f"(N, {'K' if name.startswith('sonar') else 'R' if name.startswith('laser') else 'K + R'}) "
                    f"with N, K, R from sonar (N, K) and laser (N, R); got {getattr(array, 'shape', array)!r}"
                )

    @classmethod
    def empty(cls, n: int, num_sonars: int, num_beams: int) -> BatchReading:
        """An uninitialised block for ``n`` robots with ``num_sonars`` sonars and ``num_beams`` beams."""
        return cls(
            np.empty((n, num_sonars)),
            np.empty((n, num_beams)),
            np.empty((n, num_sonars), np.int64),
            np.empty((n, num_beams), np.int64),
            np.empty((n, num_sonars + num_beams)),
        )

    def __len__(self) -> int:
        return self.sonar.shape[0]

    def reading(self, i: int) -> SensorReading:
        """Robot ``i``'s ``SensorReading``, as views of the block's rows (not copies)."""
        return _reading(self.sonar[i], self.laser[i], self.sonar_owner[i], self.laser_owner[i])


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

    ``noise_std`` and ``noise_model`` are read-only once built.

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
        self._noise_std = check_relative_std("noise_std", noise_std)
        self._noise_model = check_noise_model("noise_model", noise_model)
        ring, scanner = self.sonar_ring, self.laser_scanner
        s, c = ring.config, scanner.config
        self._num_sonars, self._num_beams = ring.num_sonars, c.num_beams
        self._params = np.array(
            [
                ring._half_width_rad,
                s.min_range_m,
                s.max_range_m,
                c.mount_x_m,
                c.mount_y_m,
                scanner._first_bearing_rad,
                c.step_rad,
                c.max_range_m,
                self._noise_std,
            ]
        )

    @property
    def noise_std(self) -> float:
        """The relative noise level (sigma, or the uniform half-width)."""
        return self._noise_std

    @property
    def noise_model(self) -> str:
        """The noise model, one of ``noise.NOISE_MODELS``."""
        return self._noise_model

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

        Raises:
            ValueError: for a bad pose. TypeError: for a geometry, rng or owner of the wrong type.
        """
        x, y, theta = check_pose(pose)
        geometry = check_geometry(geometry)
        exclude = check_owner(exclude_owner)
        if not isinstance(rng, np.random.Generator):
            raise TypeError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
        draws = unit_noise(self._noise_model, self._num_sonars + self._num_beams, rng)
        sonar, laser = np.empty(self._num_sonars), np.empty(self._num_beams)
        sonar_owner, laser_owner = np.empty(self._num_sonars, np.int64), np.empty(self._num_beams, np.int64)
        ring = self.sonar_ring
        _read_member(
            x,
            y,
            theta,
            ring._positions,
            ring._bearings,
            self._params,
            geometry.segments,
            geometry.segment_owner,
            geometry.circles,
            geometry.circle_owner,
            exclude,
            draws,
            sonar,
            sonar_owner,
            laser,
            laser_owner,
        )
        return _reading(sonar, laser, sonar_owner, laser_owner)

    def empty_batch(self, n: int) -> BatchReading:
        """An uninitialised ``BatchReading`` for ``n`` robots with these sensors (``read_batch``'s ``out``)."""
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 0:
            raise ValueError(f"n must be an int >= 0 (the number of robots), got {n!r}")
        return BatchReading.empty(int(n), self._num_sonars, self._num_beams)

    def read_batch(
        self,
        poses,
        scenes: SceneStack,
        rngs: Sequence[np.random.Generator],
        exclude_owner=-1,
        *,
        body_poses=None,
        out: BatchReading | None = None,
        active=None,
    ) -> BatchReading:
        """Read the sensors of N robots, all with these sensors, in one compiled call.

        The call places every member's moving bodies (``scenes``' ``GeometryCache``
        members) at their poses, sweeps both sensors of every robot (in parallel on numba's
        threads) and adds the noise; the noise is drawn first, member by member.

        Args:
            poses: ``(N, 3)`` robot poses ``x_m, y_m, theta_rad`` (world frame), row i for robot i.
            scenes: the N scenes, robot i sees ``scenes.scenes[i]``.
            rngs: N ``numpy.random.Generator``; robot i's noise comes from ``rngs[i]``, the
                draws ``read`` makes (sonar then laser), member after member.
            exclude_owner: each robot's own owner id (-1: none): one int for all, or ``(N,)`` ints.
            body_poses: ``(B, 3)`` float64 poses ``x_m, y_m, angle_rad`` of the stack's moving
                bodies (``SceneStack.body_start`` says whose rows), or None to read them
                from pymunk.
            out: a ``BatchReading`` of N rows with these sensors' widths to fill in place
                (reused from call to call), or None for a new one.
            active: ``(N,)`` bool, the robots to read (e.g. the members that step while
                others reset), or None for all. An inactive robot's row of ``out`` is left
                as it was, its generator is not drawn from, and its pose, body poses and
                ``rngs`` entry are not used (only their shapes are checked).

        Returns:
            ``out`` (or the new block): row i equals, bit for bit, ``read(poses[i], scene,
            rngs[i], exclude_owner[i])`` with ``scene`` robot i's scene at its body poses
            (``GeometryCache.update(body_poses[body_start[i]:body_start[i + 1]])``).

        Raises:
            ValueError: for poses, body poses, owners, ``active`` or ``out`` of the wrong
                shape, a non-finite pose of an active robot, or not N generators; before
                any generator is advanced.
            TypeError: for ``scenes`` that is not a ``SceneStack`` or an rng that is not a Generator.

        Example:
            >>> suite = SensorSuite(noise_std=0.0)
            >>> scenes = SceneStack([SceneGeometry.empty(), SceneGeometry.empty()])
            >>> out = suite.read_batch(np.zeros((2, 3)), scenes, [np.random.default_rng(0), np.random.default_rng(1)])
            >>> out.laser.shape, float(out.laser.max())
            ((2, 180), 20.0)
        """
        if not isinstance(scenes, SceneStack):
            raise TypeError(f"scenes must be a SceneStack, got {type(scenes).__name__}")
        n = len(scenes)
        flags, rows = _check_active(active, n)
        poses = _check_poses(poses, n, rows)
        excludes = _check_owners(exclude_owner, n)
        if len(rngs) != n:
            raise ValueError(f"rngs must hold one numpy.random.Generator per robot: {n}, got {len(rngs)}")
        _check_rngs(rngs, rows=rows)
        body_poses = scenes.check_body_poses(scenes.body_poses() if body_poses is None else body_poses, active)
        if out is None:
            out = self.empty_batch(n)
        elif not isinstance(out, BatchReading):
            raise TypeError(f"out must be a BatchReading or None, got {type(out).__name__}")
        elif out.sonar.shape != (n, self._num_sonars) or out.laser.shape != (n, self._num_beams):
            raise ValueError(
                f"out must hold {n} rows of {self._num_sonars} sonars and {self._num_beams} beams "
                f"(SensorSuite.empty_batch({n})); got sonar {out.sonar.shape} and laser {out.laser.shape}"
            )
        return self._read_stack(poses, scenes, rngs, excludes, body_poses, out, flags, rows)

    def read_many(self, requests: Sequence[tuple]) -> list[SensorReading]:
        """Read the sensors of many robots, all with these sensors, in one compiled call.

        Args:
            requests: one ``(pose, geometry, rng, exclude_owner)`` per robot, as the
                arguments of ``read``.

        Returns:
            One ``SensorReading`` per request, the same, bit for bit, as ``read`` of each
            request in turn gives (each robot's noise is drawn from its own ``rng``, in the
            same order); the robots are swept in parallel on the machine's cores.

        Raises:
            ValueError, TypeError: as ``read``, for any request, before any rng is advanced.
        """
        n = len(requests)
        if n == 0:
            return []
        poses = np.array([request[0] for request in requests], dtype=np.float64)
        if poses.shape != (n, 3) or not np.isfinite(poses).all():
            raise ValueError(
                f"every request's pose must be finite with shape (3,) = x_m, y_m, theta_rad; got {poses!r}"
            )
        stack = SceneStack([check_geometry(request[1]) for request in requests])
        excludes = np.array([check_owner(request[3]) for request in requests], np.int64)
        rngs = [request[2] for request in requests]
        _check_rngs(rngs, "request")
        batch = self._read_stack(
            poses, stack, rngs, excludes, np.empty((0, 3)), self.empty_batch(n), np.ones(n, np.uint8), None
        )
        return [batch.reading(i) for i in range(n)]

    def _read_stack(self, poses, stack, rngs, excludes, body_poses, out: BatchReading, flags, rows) -> BatchReading:
        """``read_batch`` after its checks: the noise of the active ``rows`` (None: all)
        drawn into ``out``, then the kernel over the rows whose ``flags`` are set."""
        unit_noise_rows(self._noise_model, rngs, out.unit_noise, rows)
        ring = self.sonar_ring
        _read_many_kernel(
            poses,
            flags,
            excludes,
            stack.layout,
            ring._positions,
            ring._bearings,
            self._params,
            stack.segments,
            stack.segment_owner,
            stack.circles,
            stack.circle_owner,
            stack.local_points,
            stack.point_body,
            body_poses,
            out.unit_noise,
            out.sonar,
            out.sonar_owner,
            out.laser,
            out.laser_owner,
        )
        return out

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


def _check_active(active, n: int) -> tuple[np.ndarray, np.ndarray | None]:
    """``(flags (n,) uint8, rows)`` of the robots to read: every one (``rows`` None) for
    ``active=None``, else those ``active`` marks; ``ValueError`` unless it is ``(n,)`` bools."""
    if active is None:
        return np.ones(n, np.uint8), None
    array = np.asarray(active)
    if array.dtype != np.bool_ or array.shape != (n,):
        raise ValueError(
            f"active must be None or an (N,) bool array (N = {n}), got shape {array.shape} of dtype {array.dtype}"
        )
    return array.astype(np.uint8), np.flatnonzero(array)


def _check_poses(poses, n: int, rows=None) -> np.ndarray:
    """``poses`` as a contiguous ``(n, 3)`` float64 array, or ``ValueError`` unless it is a
    real array of that shape with finite entries in ``rows`` (None: all), naming the first
    robot whose pose is not."""
    array = np.asarray(poses)
    if array.dtype.kind not in "iuf" or array.shape != (n, 3):
        raise ValueError(
            f"poses must be a real (N, 3) array, x_m, y_m, theta_rad of each of the N = {n} robots; "
            f"got shape {array.shape} of dtype {array.dtype}"
        )
    array = np.ascontiguousarray(array, dtype=np.float64)
    if not np.isfinite(array if rows is None else array[rows]).all():
        finite = np.isfinite(array).all(axis=1)
        row = int(next(i for i in (range(n) if rows is None else rows) if not finite[i]))
        raise ValueError(f"poses must be finite; robot {row} has x_m, y_m, theta_rad = {array[row].tolist()}")
    return array


def _check_owners(exclude_owner, n: int) -> np.ndarray:
    """``exclude_owner`` (one int, or ``(n,)`` ints) as an ``(n,)`` int64 array, or ``ValueError``."""
    if isinstance(exclude_owner, (int, np.integer)) and not isinstance(exclude_owner, bool):
        return np.full(n, exclude_owner, np.int64)
    array = np.asarray(exclude_owner)
    if array.dtype.kind not in "iu" or array.shape != (n,):
        raise ValueError(
            f"exclude_owner must be one int or an (N,) int array (N = {n}; -1: none); "
            f"got {exclude_owner!r} of shape {array.shape} and dtype {array.dtype}"
        )
    return np.ascontiguousarray(array, dtype=np.int64)


def _check_rngs(rngs, what: str = "rngs", rows=None) -> None:
    """``TypeError`` unless every entry of ``rngs`` (those in ``rows``; None: all) is a
    ``numpy.random.Generator``."""
    for i in range(len(rngs)) if rows is None else rows:
        if not isinstance(rngs[i], np.random.Generator):
            raise TypeError(f"{what} {i}: rng must be a numpy.random.Generator, got {type(rngs[i]).__name__}")


@njit(cache=True)
def _noisy(ranges, sigma, draws, offset, min_range, max_range, out):
    """``noise.apply_range_noise`` of ``ranges`` into ``out``, with the unit draws ``draws[offset:]``."""
    for k in range(ranges.shape[0]):
        r = ranges[k]
        if r >= max_range:
            out[k] = max_range
            continue
        v = r * (1.0 + sigma * draws[offset + k])
        if v < min_range:
            v = min_range
        elif v > max_range:
            v = max_range
        out[k] = v


@njit(cache=True)
def _read_member(
    x,
    y,
    theta,
    sonar_positions,
    sonar_bearings,
    params,
    segments,
    segment_owner,
    circles,
    circle_owner,
    exclude,
    draws,
    sonar_out,
    sonar_owner_out,
    laser_out,
    laser_owner_out,
):
    """One robot's reading: both sweeps of the scene and the noise, into the outputs.

    Args:
        x, y, theta: the robot's pose (m, m, rad).
        sonar_positions: ``(K, 2)`` transducer positions in the robot frame (m).
        sonar_bearings: ``(K,)`` cone axes in the robot frame (rad).
        params: the parameter vector (``HALF_WIDTH`` ... ``NOISE_LEVEL``).
        segments, segment_owner, circles, circle_owner: the scene (``SceneGeometry``'s arrays).
        exclude: the owner id the sensors ignore (-1: none).
        draws: ``(K + R,)`` unit noise draws, sonar first.
        sonar_out, sonar_owner_out: ``(K,)`` float64 and int64, written.
        laser_out, laser_owner_out: ``(R,)`` float64 and int64, written (R beams).
    """
    sonar_min = params[SONAR_MIN]
    sonar_max = params[SONAR_MAX]
    sonar, sonar_owner, _ = cones_kernel(
        x,
        y,
        theta,
        sonar_positions,
        sonar_bearings,
        params[HALF_WIDTH],
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
    c = math.cos(theta)
    s = math.sin(theta)
    mount_x = params[MOUNT_X]
    mount_y = params[MOUNT_Y]
    laser, laser_owner = fan_kernel(
        x + c * mount_x - s * mount_y,
        y + s * mount_x + c * mount_y,
        theta + params[FIRST_BEARING],
        params[LASER_STEP],
        laser_out.shape[0],
        params[LASER_MAX],
        segments,
        segment_owner,
        circles,
        circle_owner,
        exclude,
    )
    sigma = params[NOISE_LEVEL]
    _noisy(sonar, sigma, draws, 0, sonar_min, sonar_max, sonar_out)
    _noisy(laser, sigma, draws, sonar.shape[0], 0.0, params[LASER_MAX], laser_out)
    sonar_owner_out[:] = sonar_owner
    laser_owner_out[:] = laser_owner


@njit(cache=True, parallel=True)
def _read_many_kernel(
    poses,
    active,
    excludes,
    layout,
    sonar_positions,
    sonar_bearings,
    params,
    segments,
    segment_owner,
    circles,
    circle_owner,
    local_points,
    point_body,
    body_poses,
    draws,
    sonar_out,
    sonar_owner_out,
    laser_out,
    laser_owner_out,
):
    """``_read_member`` for robot i of ``poses`` ``(N, 3)`` in its rows of a ``SceneStack``
    (``layout``, ``segments`` ... ``point_body``), after placing its moving points at its
    rows of ``body_poses`` ``(B, 3)`` (checked finite); one robot per parallel iteration,
    with row i of ``draws``, into row i of the outputs; robots whose ``active`` (``(N,)``
    uint8) is 0 are skipped."""
    for i in prange(poses.shape[0]):
        if active[i] == 0:
            continue
        s0 = layout[i, S0]
        s1 = layout[i, S1]
        c0 = layout[i, C0]
        c1 = layout[i, C1]
        p0 = layout[i, P0]
        p1 = layout[i, P1]
        if p1 > p0:
            place_moving(
                body_poses[layout[i, B0] : layout[i, B1]],
                local_points[p0:p1],
                point_body[p0:p1],
                layout[i, ENDPOINTS],
                segments[s0:s1],
                circles[c0:c1],
            )
        _read_member(
            poses[i, 0],
            poses[i, 1],
            poses[i, 2],
            sonar_positions,
            sonar_bearings,
            params,
            segments[s0:s1],
            segment_owner[s0:s1],
            circles[c0:c1],
            circle_owner[c0:c1],
            excludes[i],
            draws[i],
            sonar_out[i],
            sonar_owner_out[i],
            laser_out[i],
            laser_owner_out[i],
        )
