"""ROS sensor readings as the model's readings (numpy only; the bag side is ``rosbag``).

- ``ranges_or_no_echo``: ranges outside a sensor's valid interval become "no echo".
- ``ScanResampler``: a ``sensor_msgs/LaserScan`` of any angle_min, angle_increment and
  beam count onto the model's 180 beams over the front 180°.
- ``front_sonars_from_laser``: the 8 front sonars read from the laser scan.
- ``front_sonar_slot``: the front sonar that a range sensor at some bearing stands in for.
- ``latest_at_or_before``: each sample held until the next one, read on another time base.
- ``LaserMount``: where and how the laser sits on the robot; turns a scan's beam angles
  into robot-frame bearings.
- ``bearings_in_intervals``, ``constant_near_beams``: the scan beams that angle masks and
  the robot's own structure hide.
- ``share_of_scans_changing_together``: how often most of the scan changes at once (the
  robot moving, seen without odometry).

"No echo" is the model's convention (``AttentionConfig``, and the env's sensors): the
sensor's maximum range, ``laser_max_range_m`` or ``sonar_max_range_m``.

Bearings are in radians in the robot frame (x forward, y left, counter-clockwise), as in
``regions``; a LaserScan's beam ``k`` points at ``angle_min + k * angle_increment``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from attentive_gym.attention.regions import (
    LASER_BEAMS,
    front_sonar_bearings_rad,
    laser_bearings_rad,
    nearest_sonar,
    sonar_cone_reduction,
)

__all__ = [
    "ranges_or_no_echo",
    "ScanResampler",
    "front_sonars_from_laser",
    "front_sonar_slot",
    "latest_at_or_before",
    "LaserMount",
    "bearings_in_intervals",
    "constant_near_beams",
    "share_of_scans_changing_together",
    "SELF_RETURN_NEAR_M",
    "SELF_RETURN_SPREAD_M",
    "SELF_RETURN_MIN_SCANS",
]

#: Two beams overlap when they share more than this fraction of the narrower one: beams
#: that only touch (a scan on the model's own 1° grid, up to float32 rounding) do not.
_OVERLAP_TOLERANCE = 1e-3


def ranges_or_no_echo(ranges, low_m: float, high_m: float, no_echo_m: float) -> np.ndarray:
    """Valid ranges, clipped to ``no_echo_m``; every other reading reads ``no_echo_m``.

    Args:
        ranges: ranges (m), any shape.
        low_m, high_m: the sensor's valid interval ``low_m <= r < high_m`` (m): a reading
            at its maximum range is no echo too (drivers report "nothing seen" so).
        no_echo_m: the model's no-echo reading (its maximum range, m).

    Returns:
        float64 array of the shape of ``ranges``: NaN, ±inf, ``r < low_m`` and
        ``r >= high_m`` read ``no_echo_m``, and so does anything beyond it.
    """
    ranges = np.asarray(ranges, dtype=np.float64)
    with np.errstate(invalid="ignore"):
        valid = (ranges >= low_m) & (ranges < high_m)
    return np.where(valid, np.minimum(ranges, no_echo_m), no_echo_m)


@dataclass(frozen=True, eq=False)
class ScanResampler:
    """A scan's beams onto the model's 180 laser beams, by nearest echo.

    Model beam ``i`` covers bearings ``[b_i - 0.5°, b_i + 0.5°]`` (``b_i`` of
    ``regions.laser_bearings_rad``), a scan beam ``k`` covers half its angle increment
    either side of its bearing. A model beam reads the nearest echo (the minimum range)
    of the scan beams that overlap it, so a fine scan loses no thin obstacle and a
    coarse one is held over the model beams it spans; a model beam that no scan beam
    overlaps (outside the scan's field of view) reads no echo. Scan bearings are
    wrapped to [-180°, 180°), so scans over 0..360° or clockwise scans (negative
    increment) work as they are.

    Build with ``for_scan``; one resampler serves every scan of the same geometry.

    Attributes:
        order: ``(N,)`` scan beams by increasing wrapped bearing.
        bounds: ``(2 * 180,)`` interleaved ``start, stop`` of each model beam's scan beams
            in ``order`` (a reduction plan for ``np.minimum.reduceat``).
        uncovered: ``(180,)`` True where no scan beam overlaps the model beam.
    """

    order: np.ndarray
    bounds: np.ndarray
    uncovered: np.ndarray

    @classmethod
    def for_scan(cls, angle_min_rad: float, angle_increment_rad: float, n_ranges: int) -> ScanResampler:
        """The resampler of scans of ``n_ranges`` beams from ``angle_min_rad`` by ``angle_increment_rad``.

        Raises:
            ValueError: for no beams, a non-finite angle, or a zero increment with more
                than one beam.
        """
        if n_ranges < 1:
            raise ValueError(f"a laser scan needs at least one range, got {n_ranges}")
        if not (np.isfinite(angle_min_rad) and np.isfinite(angle_increment_rad)):
            raise ValueError(
                f"a laser scan's angle_min and angle_increment must be finite (rad), "
                f"got {angle_min_rad!r} and {angle_increment_rad!r}"
            )
        if angle_increment_rad == 0.0 and n_ranges > 1:
            raise ValueError(f"a laser scan of {n_ranges} ranges needs a non-zero angle_increment (rad), got 0")
        bearings = angle_min_rad + np.arange(n_ranges) * angle_increment_rad
        wrapped = np.mod(bearings + np.pi, 2.0 * np.pi) - np.pi
        order = np.argsort(wrapped, kind="stable")
        wrapped = wrapped[order]
        model_step = np.radians(180.0 / LASER_BEAMS)
        scan_half = abs(angle_increment_rad) / 2.0
        tolerance = _OVERLAP_TOLERANCE * (min(abs(angle_increment_rad), model_step) or model_step)
        centres = laser_bearings_rad()
        start = np.searchsorted(wrapped, centres - model_step / 2.0 - scan_half + tolerance, side="right")
        stop = np.searchsorted(wrapped, centres + model_step / 2.0 + scan_half - tolerance, side="left")
        uncovered = stop <= start
        bounds = np.stack([np.where(uncovered, 0, start), np.where(uncovered, 0, stop)], axis=1).ravel()
        for array in (order, bounds, uncovered):
            array.flags.writeable = False
        return cls(order, bounds.astype(np.intp), uncovered)

    def resample(self, ranges: np.ndarray, no_echo_m: float) -> np.ndarray:
        """Scan ranges ``(..., N)`` (m, no echo already ``no_echo_m``) → model beams ``(..., 180)``."""
        ordered = np.asarray(ranges, dtype=np.float64)[..., self.order]
        # a no-echo sentinel after the last beam, so that a stop of N is a valid index
        padded = np.concatenate([ordered, np.full(ordered.shape[:-1] + (1,), no_echo_m)], axis=-1)
        beams = np.minimum.reduceat(padded, self.bounds, axis=-1)[..., ::2]
        beams[..., self.uncovered] = no_echo_m
        return beams


def front_sonars_from_laser(
    laser: np.ndarray, cone_half_width_deg: float, min_range_m: float, max_range_m: float
) -> np.ndarray:
    """The 8 front sonars as the laser sees them: the nearest echo in each sonar's cone.

    Args:
        laser: ``(..., 180)`` model laser ranges (m).
        cone_half_width_deg: half-width of a sonar cone (deg), ``AttentionConfig.sonar_cone_half_width_deg``.
        min_range_m, max_range_m: the sonar's range (m): nearer echoes read the minimum,
            no echo within the maximum reads the maximum, as the env's sonar does.

    Returns:
        ``(..., 8)`` sonar ranges (m), sonar 0 leftmost. The laser's origin stands in for
        every transducer's (the few centimetres between them are ignored).
    """
    indices, take, _ = sonar_cone_reduction(cone_half_width_deg)
    nearest = np.minimum.reduceat(np.asarray(laser, dtype=np.float64), indices, axis=-1)[..., take]
    return np.clip(nearest, min_range_m, max_range_m)


def front_sonar_slot(bearing_deg: float, cone_half_width_deg: float) -> int:
    """The front sonar (0..7) nearest in bearing to a range sensor at ``bearing_deg``, or
    -1 when it faces backwards (more than a cone half-width behind ±90°: the model reads
    only the front sonars).

    Args:
        bearing_deg: the sensor's bearing (deg, counter-clockwise from the heading, any turn).
        cone_half_width_deg: half-width of a sonar cone (deg).
    """
    bearing = (bearing_deg + 180.0) % 360.0 - 180.0
    if abs(bearing) > np.degrees(front_sonar_bearings_rad()[0]) + cone_half_width_deg:
        return -1
    return int(nearest_sonar(np.radians(bearing)))


def latest_at_or_before(times: np.ndarray, sample_times: np.ndarray, samples: np.ndarray) -> np.ndarray:
    """The latest sample at or before each time (zero-order hold).

    Args:
        times: ``(T,)`` times to read at, each at or after ``sample_times[0]``.
        sample_times: ``(M,)`` non-decreasing times of the samples (same unit as ``times``).
        samples: ``(M, ...)`` samples.

    Returns:
        ``(T, ...)`` samples; of samples with equal times, the last.
    """
    index = np.searchsorted(sample_times, times, side="right") - 1
    if index.size and index.min() < 0:
        raise ValueError("latest_at_or_before: a time precedes the first sample")
    return samples[index]


@dataclass(frozen=True)
class LaserMount:
    """Where and how a laser sits on the robot (robot frame: x forward, y left).

    Attributes:
        x_m, y_m: the laser's origin (m).
        yaw_deg: the direction its beam at angle 0 points (deg, counter-clockwise from
            the robot's heading; 180: a laser facing backwards).
        upside_down: mounted upside down (rolled 180° about its forward axis): its beam
            angles run clockwise seen from above.
    """

    x_m: float = 0.16
    y_m: float = 0.0
    yaw_deg: float = 0.0
    upside_down: bool = False

    def robot_frame_angles(self, angle_min_rad: float, angle_increment_rad: float) -> tuple[float, float]:
        """A scan's ``(angle_min, angle_increment)`` (rad) as robot-frame bearings from the
        laser's origin: a beam at laser angle ``a`` points at ``yaw ± a`` (``-`` upside down)."""
        sign = -1.0 if self.upside_down else 1.0
        return float(np.radians(self.yaw_deg) + sign * angle_min_rad), sign * angle_increment_rad

    def describe(self) -> str:
        """``x 0.16 m, y 0 m, yaw 0°, upright``."""
        side = "upside down" if self.upside_down else "upright"
        return f"x {self.x_m:g} m, y {self.y_m:g} m, yaw {self.yaw_deg:g}°, {side}"


def bearings_in_intervals(bearings_rad: np.ndarray, intervals_deg) -> np.ndarray:
    """Whether each bearing lies in one of the closed intervals ``[(a, b), ...]`` (deg,
    -180 <= a < b <= 180); bearings (rad, any turn) are wrapped to [-180°, 180°)."""
    wrapped = np.mod(np.degrees(np.asarray(bearings_rad, dtype=np.float64)) + 180.0, 360.0) - 180.0
    inside = np.zeros(wrapped.shape, dtype=bool)
    for low, high in intervals_deg:
        inside |= (wrapped >= low) & (wrapped <= high)
    return inside


#: A beam whose echo stays nearer than this (m) through a whole bag is the robot's own structure...
SELF_RETURN_NEAR_M = 0.5
#: ... when its echoes spread over less than this (m) ...
SELF_RETURN_SPREAD_M = 0.05
#: ... and the bag has at least this many scans (a shorter one cannot tell structure from
#: something standing still beside the robot).
SELF_RETURN_MIN_SCANS = 20
#: The share of scans in which such a beam must hold its echo (the rest may drop out).
_SELF_RETURN_HELD = 0.95


def constant_near_beams(ranges: np.ndarray) -> np.ndarray:
    """The scan beams that hold a constant near echo through every scan: the robot's own
    posts, bumpers or cables (``SELF_RETURN_*``).

    Args:
        ranges: ``(M, N)`` ranges (m) of M scans of N beams, "no echo" already a range
            beyond ``SELF_RETURN_NEAR_M`` (``ranges_or_no_echo``).

    Returns:
        ``(N,)`` bool, all False for fewer than ``SELF_RETURN_MIN_SCANS`` scans.
    """
    ranges = np.asarray(ranges, dtype=np.float64)
    if ranges.shape[0] < SELF_RETURN_MIN_SCANS:
        return np.zeros(ranges.shape[1], dtype=bool)
    near = ranges < SELF_RETURN_NEAR_M
    held = near.mean(axis=0) >= _SELF_RETURN_HELD
    nearest = np.where(near, ranges, np.inf).min(axis=0)
    farthest = np.where(near, ranges, -np.inf).max(axis=0)
    return held & (farthest - nearest < SELF_RETURN_SPREAD_M)


#: A beam "changes" when its range moves by more than this (m) over ``_CHANGE_INTERVAL_S``...
_CHANGE_M = 0.1
_CHANGE_INTERVAL_S = 1.0
#: ... and a scan changes "together" when more than this share of its echoing beams do.
_TOGETHER_SHARE = 0.5


def share_of_scans_changing_together(laser: np.ndarray, t: np.ndarray, no_echo_m: float) -> float:
    """The share of scans in which most beams changed since the scan about 1 s before: a
    moving robot changes nearly every range at once, people walking past a still one only
    a few beams.

    Args:
        laser: ``(T, B)`` ranges (m), no echo as ``no_echo_m``.
        t: ``(T,)`` times (s), increasing.
        no_echo_m: the no-echo reading (m); beams without an echo in either scan are
            left out.

    Returns:
        The share in [0, 1]; 0 for a log shorter than the interval.
    """
    laser, t = np.asarray(laser, dtype=np.float64), np.asarray(t, dtype=np.float64)
    earlier = np.searchsorted(t, t - _CHANGE_INTERVAL_S, side="right") - 1
    compared = np.flatnonzero(earlier >= 0)
    if compared.size == 0:
        return 0.0
    now, before = laser[compared], laser[earlier[compared]]
    echo = (now < no_echo_m) & (before < no_echo_m)
    changed = echo & (np.abs(now - before) > _CHANGE_M)
    counted = echo.sum(axis=1)
    together = changed.sum(axis=1) > _TOGETHER_SHARE * np.maximum(counted, 1)
    return float(together.mean())
