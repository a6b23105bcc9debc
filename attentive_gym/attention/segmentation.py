"""Laser scan segmentation (docs/model.md §10): a scan split into objects, each measured.

- ``segment_scan``: break the scan at no-echo beams and at range jumps larger than a
  threshold that grows with the range (``jump_m + jump_sigmas · √2 · σ(r)``, σ(r) the
  range noise of one reading), so that noise alone rarely splits an object.
- ``measure_segments``: each segment's object position (the centroid of its echo
  points pushed back along the line of sight by a fixed fraction of its extent, where
  the centre of a round or boxy body lies), its extent, its measurement covariance, and
  what the tracker may do with it (``STRUCTURE``, ``UPDATE_ONLY``, ``TRACKABLE``).
- ``carve_body``: a body that a track expects, cut out of whatever segment holds it
  (a body touching a wall merges with it into static structure).
- Column layout of the measurement table: ``SEGMENT_FIELDS``.

Robot frame: x forward, y left (m); beam bearings (rad) increase from right to left.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["segment_scan", "measure_segments", "carve_body", "SEGMENT_FIELDS", "SURFACE_OFFSET_FRACTION", "STRUCTURE",
           "UPDATE_ONLY", "TRACKABLE"]

#: Columns of ``measure_segments``' table, one row per segment.
SEGMENT_FIELDS = ("start", "stop", "x_m", "y_m", "extent_m", "r_xx", "r_xy", "r_yy", "candidate")
_START, _STOP, _X, _Y, _EXTENT, _RXX, _RXY, _RYY, _CANDIDATE = range(len(SEGMENT_FIELDS))
#: The centre of a body lies this fraction of its visible extent behind the centroid of
#: its echoes. π/8 is exact for a distant disc of radius R: beams sample its visible
#: half uniformly across the line of sight, whose mean depth is π R / 4 in front of the
#: centre, and its extent is 2R.
SURFACE_OFFSET_FRACTION = math.pi / 8.0
_SQRT2 = math.sqrt(2.0)
#: Values of the ``candidate`` column: static structure, never tracked (longer than any
#: body that moves); a segment with too few beams to start a track, which may still
#: update one; a segment that may start a track.
STRUCTURE, UPDATE_ONLY, TRACKABLE = 0.0, 1.0, 2.0


@njit(cache=True)
def segment_scan(ranges_m, no_echo_from_m, noise_rel, noise_floor_m, jump_m, jump_sigmas, bounds):
    """Split a scan into runs of consecutive echoes.

    Args:
        ranges_m: ``(B,)`` ranges (m), beam 0 rightmost.
        no_echo_from_m: readings at or above this mean no echo (m).
        noise_rel, noise_floor_m: σ(r) = max(noise_rel · r, noise_floor_m) (m).
        jump_m, jump_sigmas: neighbours whose ranges differ by more than
            ``jump_m + jump_sigmas · √2 · σ(mean of the two)`` belong to different objects.
        bounds: ``(B, 2)`` int64 output: ``start, stop`` beam indices of each segment
            (``stop`` exclusive), in scan order.

    Returns:
        The number of segments written.
    """
    n = ranges_m.shape[0]
    count = 0
    start = -1
    for i in range(n):
        echo = ranges_m[i] < no_echo_from_m
        if not echo:
            if start >= 0:
                bounds[count, 0], bounds[count, 1] = start, i
                count += 1
                start = -1
            continue
        if start >= 0:
            previous = ranges_m[i - 1]
            sigma = max(noise_rel * 0.5 * (previous + ranges_m[i]), noise_floor_m)
            if abs(ranges_m[i] - previous) > jump_m + jump_sigmas * _SQRT2 * sigma:
                bounds[count, 0], bounds[count, 1] = start, i
                count += 1
                start = i
        else:
            start = i
    if start >= 0:
        bounds[count, 0], bounds[count, 1] = start, n
        count += 1
    return count


@njit(cache=True)
def measure_segments(ranges_m, cos_b, sin_b, beam_step_rad, no_echo_from_m, bounds, count, noise_rel, noise_floor_m,
                     surface_sigma_m, max_extent_m, min_beams, table):
    """Measure each segment of ``segment_scan`` as an object, in the robot frame.

    Args:
        ranges_m: ``(B,)`` ranges (m); cos_b, sin_b: ``(B,)`` of the beam bearings.
        beam_step_rad: angle between neighbouring beams (rad).
        no_echo_from_m: readings at or above this mean no echo (m).
        bounds, count: the segments of ``segment_scan``.
        noise_rel, noise_floor_m: the range noise model, as in ``segment_scan``.
        surface_sigma_m: σ of where on its surface the object's measured centre lies,
            along and across the line of sight (m).
        max_extent_m: longer segments are static structure, not candidates for tracking.
        min_beams: segments with fewer beams may update a track but not start one.
        table: ``(B, len(SEGMENT_FIELDS))`` output, one row per segment: beam bounds,
            position (m), extent (m), measurement covariance ``r_xx, r_xy, r_yy`` (m²),
            and ``STRUCTURE``, ``UPDATE_ONLY`` or ``TRACKABLE``.

    The covariance: along the line of sight, the range noise averaged over the
    segment's beams plus ``surface_sigma_m²``; across it, ``surface_sigma_m²`` plus the
    beam quantisation ``(r · step)² / 12``, plus ``(max_extent_m / 2)²`` for each end that
    is not the object's own end (occluded by something nearer, or at the edge of the
    field of view), since the centroid then shifts with what is hidden.
    """
    n_beams = ranges_m.shape[0]
    for m in range(count):
        start, stop = bounds[m, 0], bounds[m, 1]
        hidden_ends = 0
        if start == 0 or (ranges_m[start - 1] < no_echo_from_m and ranges_m[start - 1] < ranges_m[start]):
            hidden_ends += 1
        if stop == n_beams or (ranges_m[stop] < no_echo_from_m and ranges_m[stop] < ranges_m[stop - 1]):
            hidden_ends += 1
        extent = _measure_run(ranges_m, cos_b, sin_b, beam_step_rad, start, stop, -1.0,
                              hidden_ends * (0.5 * max_extent_m) ** 2, noise_rel, noise_floor_m, surface_sigma_m,
                              table[m])
        if extent > max_extent_m:
            table[m, _CANDIDATE] = STRUCTURE
        else:
            table[m, _CANDIDATE] = TRACKABLE if stop - start >= min_beams else UPDATE_ONLY


@njit(cache=True)
def _measure_run(ranges_m, cos_b, sin_b, beam_step_rad, start, stop, known_extent_m, hidden_var_m2, noise_rel,
                 noise_floor_m, surface_sigma_m, row):
    """Measure the beams ``start <= i < stop`` as one body into ``row`` (``SEGMENT_FIELDS``,
    all but ``candidate``); the surface offset uses ``known_extent_m`` when it is >= 0, else
    the run's own extent; ``hidden_var_m2`` is added across the line of sight (m²).
    Returns the run's extent (m)."""
    n = stop - start
    sx = 0.0
    sy = 0.0
    sr = 0.0
    for i in range(start, stop):
        sx += ranges_m[i] * cos_b[i]
        sy += ranges_m[i] * sin_b[i]
        sr += ranges_m[i]
    cx, cy, mean_range = sx / n, sy / n, sr / n
    first_x, first_y = ranges_m[start] * cos_b[start], ranges_m[start] * sin_b[start]
    last_x, last_y = ranges_m[stop - 1] * cos_b[stop - 1], ranges_m[stop - 1] * sin_b[stop - 1]
    extent = math.hypot(last_x - first_x, last_y - first_y)
    distance = math.hypot(cx, cy)
    ux, uy = (cx / distance, cy / distance) if distance > 0.0 else (1.0, 0.0)
    offset = SURFACE_OFFSET_FRACTION * (extent if known_extent_m < 0.0 else known_extent_m)
    sigma = max(noise_rel * mean_range, noise_floor_m)
    along = sigma * sigma / n + surface_sigma_m * surface_sigma_m
    across = surface_sigma_m * surface_sigma_m + (distance * beam_step_rad) ** 2 / 12.0 + hidden_var_m2
    row[_START], row[_STOP] = start, stop
    row[_X], row[_Y] = cx + ux * offset, cy + uy * offset
    row[_EXTENT] = extent
    # R = along · u uᵀ + across · u⊥ u⊥ᵀ
    row[_RXX] = along * ux * ux + across * uy * uy
    row[_RXY] = (along - across) * ux * uy
    row[_RYY] = along * uy * uy + across * ux * ux
    return extent


@njit(cache=True)
def carve_body(ranges_m, cos_b, sin_b, beam_step_rad, no_echo_from_m, x_m, y_m, extent_m, noise_rel, noise_floor_m,
               jump_m, jump_sigmas, surface_sigma_m, min_beams, row):
    """Measure a body expected at ``(x_m, y_m)`` (its centre, robot frame) of extent
    ``extent_m`` from the beams around its bearing, whatever segment they belong to.

    A body that touches a wall or rubble at a similar range merges with it into one long
    segment (static structure); a track that expects the body there can still find it:
    the longest run of echoes, within the body's angular width, whose ranges lie within
    ``jump_m + jump_sigmas · √2 · σ + extent/2`` of the range its surface should have.
    Both ends of the run count as uncertain (``(extent/2)²`` across the line of sight).

    Returns True and writes ``row`` (``SEGMENT_FIELDS``, ``candidate`` = ``UPDATE_ONLY``) when
    such a run of at least ``min_beams`` beams exists, else False.
    """
    n_beams = ranges_m.shape[0]
    distance = math.hypot(x_m, y_m)
    if distance <= 0.0:
        return False
    bearing = math.atan2(y_m, x_m)
    half_width = math.atan2(0.5 * extent_m, distance)
    first_bearing = -0.5 * beam_step_rad * n_beams
    lo = max(int(math.ceil((bearing - half_width - first_bearing) / beam_step_rad - 0.5)), 0)
    hi = min(int(math.floor((bearing + half_width - first_bearing) / beam_step_rad - 0.5)), n_beams - 1)
    expected = distance - SURFACE_OFFSET_FRACTION * extent_m
    tolerance = jump_m + jump_sigmas * _SQRT2 * max(noise_rel * expected, noise_floor_m) + 0.5 * extent_m
    best_start, best_stop, start = 0, 0, -1
    for i in range(lo, hi + 2):
        inside = i <= hi and ranges_m[i] < no_echo_from_m and abs(ranges_m[i] - expected) <= tolerance
        if inside and start < 0:
            start = i
        elif not inside and start >= 0:
            if i - start > best_stop - best_start:
                best_start, best_stop = start, i
            start = -1
    if best_stop - best_start < min_beams:
        return False
    _measure_run(ranges_m, cos_b, sin_b, beam_step_rad, best_start, best_stop, extent_m, (0.5 * extent_m) ** 2,
                 noise_rel, noise_floor_m, surface_sigma_m, row)
    row[_CANDIDATE] = UPDATE_ONLY
    return True
