"""Laser scan segmentation (docs/model.md §10): a scan split into objects, each measured.

- ``segment_scan``: break the scan at no-echo beams and at range jumps larger than a
  threshold that grows with the range (``jump_m + jump_sigmas · √2 · σ(r)``, σ(r) the
  range noise of one reading), so that noise alone rarely splits an object.
- ``measure_segments``: each segment's object position (the centroid of its echo
  points pushed back along the line of sight by a fixed fraction of its extent, where
  the centre of a round or boxy body lies), its extent, its measurement covariance, and
  what the tracker may do with it (``STRUCTURE``, ``UPDATE_ONLY``, ``TRACKABLE``).
- ``split_foreground``: bodies standing in front of structure, found inside its segments
  as runs of beams significantly nearer than the surface around them (a body less than
  a jump threshold in front of a wall merges with it into one long segment).
- ``carve_body``: a body that a track expects, cut out of whatever segment holds it
  (a body touching a wall merges with it into static structure).
- Column layout of the measurement table: ``SEGMENT_FIELDS``.

Robot frame: x forward, y left (m); beam bearings (rad) increase from right to left.

Small kernels that the model's step calls in its loops are compiled ``inline="always"``:
inlined into their caller, the views of per-track rows (or the arrays) they take need no
reference counting, two atomic operations per array and call otherwise.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = [
    "segment_scan",
    "measure_segments",
    "split_foreground",
    "carve_body",
    "SEGMENT_FIELDS",
    "SURFACE_OFFSET_FRACTION",
    "STRUCTURE",
    "UPDATE_ONLY",
    "TRACKABLE",
]

#: Columns of ``measure_segments``' table, one row per segment.
SEGMENT_FIELDS = ("start", "stop", "x_m", "y_m", "extent_m", "r_xx", "r_xy", "r_yy", "candidate")
_START, _STOP, _X, _Y, _EXTENT, _RXX, _RXY, _RYY, _CANDIDATE = range(len(SEGMENT_FIELDS))
#: The centre of a body lies this fraction of its visible extent behind the centroid of
#: its echoes. π/8 is exact for a distant disc of radius R: beams sample its visible
#: half uniformly across the line of sight, whose mean depth is π R / 4 in front of the
#: centre, and its extent is 2R.
SURFACE_OFFSET_FRACTION = math.pi / 8.0
_SQRT2 = math.sqrt(2.0)
#: ``split_foreground``: the fewest beams of a run; the part of a run's depth that the
#: range jump at each of its ends inside a segment must show (a body's edges are as deep
#: as it stands in front of its background, a bend's are not); the σ of the loose screen
#: (2 beams either side of a beam boundary) for where a run may start or end.
_FOREGROUND_MIN_BEAMS = 3
_EDGE_DEPTH_FRACTION = 0.25
_EDGE_SCREEN_SIGMAS = 1.0
#: Runs are searched up to this many times ``max_extent_m``: the best run, when longer than
#: that, is structure in front of structure (a big box before a wall), and none of its parts
#: is a body.
_SEARCH_EXTENT_FACTOR = 2.0
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
def measure_segments(
    ranges_m,
    cos_b,
    sin_b,
    beam_step_rad,
    no_echo_from_m,
    bounds,
    count,
    noise_rel,
    noise_floor_m,
    surface_sigma_m,
    max_extent_m,
    min_beams,
    table,
):
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
        extent = _measure_run(
            ranges_m,
            cos_b,
            sin_b,
            beam_step_rad,
            start,
            stop,
            -1.0,
            hidden_ends * (0.5 * max_extent_m) ** 2,
            noise_rel,
            noise_floor_m,
            surface_sigma_m,
            table[m],
        )
        if extent > max_extent_m:
            table[m, _CANDIDATE] = STRUCTURE
        else:
            table[m, _CANDIDATE] = TRACKABLE if stop - start >= min_beams else UPDATE_ONLY


@njit(cache=True)
def split_foreground(
    ranges_m,
    cos_b,
    sin_b,
    beam_step_rad,
    no_echo_from_m,
    bounds,
    count,
    noise_rel,
    noise_floor_m,
    surface_sigma_m,
    max_extent_m,
    min_beams,
    flank_beams,
    sigmas,
    margin_m,
    edge_sigmas,
    table,
):
    """Find bodies standing in front of structure: runs of beams inside a ``STRUCTURE``
    segment that lie significantly nearer than the surface around them, with a range
    jump at both ends; each becomes a segment of its own, appended after the ``count``
    rows of ``segment_scan`` and ``measure_segments``.

    A body less than a jump threshold in front of a wall or rubble merges with it into one
    segment longer than ``max_extent_m``, which yields no measurement (or, split from it
    on one side only, sits at one end of such a segment). A candidate run ``i <= k < j``
    (at least 3 beams, at most ``2 · max_extent_m`` end to end) qualifies when:

    - its **depth**, how much nearer its echo centroid lies, along its line of sight, than
      the line through the centroids of its two flanks (``flank_beams`` beams on either
      side, which may reach into the neighbouring segments but not past a beam without
      echo: a wall behind it seen at any angle), exceeds ``margin_m + sigmas · σ``, σ the
      depth's standard deviation from the range noise of the run's and the flanks'
      beams propagated through that geometry (exact to first order, so that walls seen
      at a grazing angle are not split by noise);
    - both of its **ends are edges** (``_edge_z`` >= ``edge_sigmas``): an end at the
      segment's end next to a farther beam (that jump passed the segment's test), or an
      end inside the segment where the surface beyond lies farther than the run's beams
      next to the end, both as a mean (by more than ``_EDGE_DEPTH_FRACTION`` of the
      depth) and extrapolated as a line from up to ``2 · flank_beams`` beams beyond: a
      convex corner, a bend, or the end of a wall cut off by the ``max_extent_m`` limit
      continues smoothly there, a body's edge does not.

    Among the candidates, the one with the largest ``(depth − margin_m) / σ`` wins and its
    beams are taken; it becomes a segment when it is at most ``max_extent_m`` long (a
    longer one is structure in front of structure, such as a big box before a wall, and
    searching up to twice the limit keeps its parts from passing for bodies). The search
    repeats among the beams not yet taken until none qualifies. To keep it cheap,
    runs only start and end where a loose screen sees a step (the 2 beams outside at
    least ``_EDGE_SCREEN_SIGMAS`` σ farther than the 2 inside) or at a segment's end; the
    flanks' centroids are computed once per start and per end; and a run's depth comes
    first, alone: its variance, a bound from the flanks' mean ranges (``_flank_bound``) and
    its edges are only worked out for a run deeper than ``margin_m`` that may beat the best.

    Args:
        ranges_m, cos_b, sin_b, beam_step_rad, no_echo_from_m: the scan, as in ``measure_segments``.
        bounds, table: ``segment_scan``'s and ``measure_segments``' outputs, ``count`` rows of
            each; the runs found are appended to both (as many as their rows hold).
        noise_rel, noise_floor_m, surface_sigma_m: the noise model, as in ``measure_segments``.
        max_extent_m: the longest run (end to end, m).
        min_beams: a run with fewer beams is ``UPDATE_ONLY``, else ``TRACKABLE``.
        flank_beams: beams on each side of a run that define the surface behind it (0: no
            search).
        sigmas, margin_m: the significance a run's depth needs (σ) and the depth it must
            exceed beyond that (m).
        edge_sigmas: the significance each end's range jump needs (σ).

    Returns:
        The number of rows in ``bounds`` and ``table``: ``count`` plus the runs found. Each
        run is measured by ``_measure_run`` with both ends its own (its edges, which
        nothing nearer hides); the segment around it stays ``STRUCTURE``.
    """
    n_beams = ranges_m.shape[0]
    capacity = min(bounds.shape[0], table.shape[0])
    w = flank_beams
    total = count
    if w < 1:
        return total
    structure = False
    for m in range(count):
        structure = structure or table[m, _CANDIDATE] == STRUCTURE
    if not structure:
        return total
    # prefix sums of the echo points, the ranges and the echoes
    px, py, pr = np.zeros(n_beams + 1), np.zeros(n_beams + 1), np.zeros(n_beams + 1)
    echoes = np.zeros(n_beams + 1, np.int64)
    for i in range(n_beams):
        r = ranges_m[i]
        px[i + 1], py[i + 1], pr[i + 1] = px[i] + r * cos_b[i], py[i] + r * sin_b[i], pr[i] + r
        echoes[i + 1] = echoes[i] + (1 if r < no_echo_from_m else 0)
    # where a run may start (opens) or end (closes), between beams k - 1 and k: a step or a
    # structure segment's end; next_close[k], the first such end at or after k
    opens, closes = np.zeros(n_beams + 1, np.bool_), np.zeros(n_beams + 1, np.bool_)
    for k in range(2, n_beams - 1):
        inside, outside = ranges_m[k] + ranges_m[k + 1], ranges_m[k - 2] + ranges_m[k - 1]
        sigma = max(noise_rel * 0.25 * (inside + outside), noise_floor_m)
        opens[k] = 0.5 * (outside - inside) >= _EDGE_SCREEN_SIGMAS * sigma
        closes[k] = 0.5 * (inside - outside) >= _EDGE_SCREEN_SIGMAS * sigma
    for m in range(count):
        if table[m, _CANDIDATE] == STRUCTURE:
            opens[bounds[m, 0]] = True
            closes[bounds[m, 1]] = True
    next_close = np.empty(n_beams + 2, np.int64)
    next_close[n_beams + 1] = n_beams + 1
    for k in range(n_beams, -1, -1):
        next_close[k] = k if closes[k] else next_close[k + 1]
    # the right flank of a run ending at k: the w beams from k as one point (``_group``)
    flanks = np.empty((n_beams + 1, 4))
    for k in range(n_beams - w + 1):
        if closes[k]:
            flanks[k, 0], flanks[k, 1], flanks[k, 2], flanks[k, 3] = _group(
                px, py, pr, k, k + w, noise_rel, noise_floor_m
            )
    used = np.zeros(n_beams, np.bool_)
    widest = _SEARCH_EXTENT_FACTOR * max_extent_m
    for m in range(count):
        if table[m, _CANDIDATE] != STRUCTURE:
            continue
        a, b = bounds[m, 0], bounds[m, 1]
        while total < capacity:
            best_z, best_i, best_j = sigmas, -1, -1
            stop = a  # a run from i ends at the latest before the first beam taken after it
            for i in range(a, b - _FOREGROUND_MIN_BEAMS + 1):
                if not opens[i] or used[i] or i < w or echoes[i] - echoes[i - w] < w:
                    continue
                if stop <= i:
                    stop = i + 1
                    while stop < b and not used[stop]:
                        stop += 1
                xi, yi = ranges_m[i] * cos_b[i], ranges_m[i] * sin_b[i]
                left = _group(px, py, pr, i - w, i, noise_rel, noise_floor_m)
                j = next_close[i + _FOREGROUND_MIN_BEAMS]
                while j <= stop:
                    n = j - i
                    mean_range = (pr[j] - pr[i]) / n
                    span = (n - 1) * beam_step_rad
                    if span * mean_range > widest:
                        break
                    if j + w <= n_beams and echoes[j + w] - echoes[j] == w:
                        right = (flanks[j, 0], flanks[j, 1], flanks[j, 2], flanks[j, 3])
                        run = _group(px, py, pr, i, j, noise_rel, noise_floor_m)
                        behind, ux, uy, cross = _sight_line(left, right, run)
                        depth = behind - run[2]
                        if behind > 0.0 and depth > margin_m:  # the rest only here: most runs lie on the surface
                            variance = _depth_variance(left, right, run, w, w, n, behind, ux, uy, cross)
                            if variance > 0.0:
                                z = (depth - margin_m) / math.sqrt(variance)
                                last_x, last_y = ranges_m[j - 1] * cos_b[j - 1], ranges_m[j - 1] * sin_b[j - 1]
                                if (
                                    z > best_z
                                    and _flank_bound(
                                        px,
                                        py,
                                        pr,
                                        i,
                                        j,
                                        w,
                                        mean_range,
                                        span,
                                        noise_rel,
                                        noise_floor_m,
                                        margin_m,
                                        best_z,
                                    )
                                    and math.hypot(last_x - xi, last_y - yi) <= widest
                                    and _edge_z(ranges_m, px, py, pr, a, b, i, j, w, depth, noise_rel, noise_floor_m)
                                    >= edge_sigmas
                                ):
                                    best_z, best_i, best_j = z, i, j
                    j = next_close[j + 1]
            if best_i < 0:
                break
            for i in range(best_i, best_j):
                used[i] = True
            first_x, first_y = ranges_m[best_i] * cos_b[best_i], ranges_m[best_i] * sin_b[best_i]
            last_x, last_y = ranges_m[best_j - 1] * cos_b[best_j - 1], ranges_m[best_j - 1] * sin_b[best_j - 1]
            if math.hypot(last_x - first_x, last_y - first_y) > max_extent_m:
                continue  # the body in front is larger than any that moves: structure, and so is any part of it
            bounds[total, 0], bounds[total, 1] = best_i, best_j
            _measure_run(
                ranges_m,
                cos_b,
                sin_b,
                beam_step_rad,
                best_i,
                best_j,
                -1.0,
                0.0,
                noise_rel,
                noise_floor_m,
                surface_sigma_m,
                table[total],
            )
            table[total, _CANDIDATE] = TRACKABLE if best_j - best_i >= min_beams else UPDATE_ONLY
            total += 1
    return total


@njit(cache=True, inline="always")
def _edge_z(ranges_m, px, py, pr, a, b, i, j, w, depth_m, noise_rel, noise_floor_m):
    """How clearly both ends of the run ``i <= k < j`` (inside the segment ``a <= k < b``, in
    front of its background by ``depth_m``) are the edges of a body: the smaller of the two
    ends' significance (σ; see ``split_foreground``).

    An end at the segment's end counts when the beam beyond it is farther (+inf), not when
    it is nearer (occluded: −inf). An end inside the segment takes the smaller of two
    tests of the range jump between the run's (up to) ``w`` beams next to it and the
    segment's beams beyond it: their means (up to ``w`` beams beyond) differ by more than
    ``_EDGE_DEPTH_FRACTION · depth_m``; and, with at least 4 beams beyond, the run's beams
    lie in front of the line through the two halves of (up to) ``2 w`` beams beyond.
    """
    inner = max(1, min(w, (j - i) // 2))
    worst = 1e300
    for side in range(2):
        if side == 0:
            edge, beyond, outer, longer = i, i - 1, min(w, i - a), min(2 * w, i - a)
            q0, q1, o0, o1 = i, i + inner, i - outer, i
        else:
            edge, beyond, outer, longer = j - 1, j, min(w, b - j), min(2 * w, b - j)
            q0, q1, o0, o1 = j - inner, j, j, j + outer
        if outer == 0:  # the segment's end
            if ranges_m[beyond] < ranges_m[edge]:
                return -1e300
            continue
        near, far = (pr[q1] - pr[q0]) / inner, (pr[o1] - pr[o0]) / outer
        sigma_near, sigma_far = max(noise_rel * near, noise_floor_m), max(noise_rel * far, noise_floor_m)
        z = (far - near - _EDGE_DEPTH_FRACTION * depth_m) / math.sqrt(
            sigma_near * sigma_near / inner + sigma_far * sigma_far / outer
        )
        if longer >= 4:
            h = longer // 2
            if side == 0:
                step, variance = _line_depth(px, py, pr, i - 2 * h, i - h, i - h, i, q0, q1, noise_rel, noise_floor_m)
            else:
                step, variance = _line_depth(px, py, pr, j, j + h, j + h, j + 2 * h, q0, q1, noise_rel, noise_floor_m)
            if variance <= 0.0:
                return -1e300
            z = min(z, step / math.sqrt(variance))
        worst = min(worst, z)
    return worst


@njit(cache=True, inline="always")
def _flank_bound(px, py, pr, i, j, w, mean_range, span, noise_rel, noise_floor_m, margin_m, best_z):
    """Whether the run ``i <= k < j`` (``w`` beams in each flank; ``mean_range`` its mean range,
    m; ``span`` its angular width, rad) passes the bound that ``split_foreground`` sets before
    it may beat ``best_z`` (σ): its depth can exceed ``margin_m + best_z · σ/√n`` (σ the range
    noise at its mean range, n its beams) only if the line between its flanks lies nowhere
    farther than the farther flank's mean range and its centroid is nearer than its mean
    range by less than the span allows. Exact arithmetic implies it from the depth; rounding
    may not, so it stays, and the search finds the runs it always found, to the bit."""
    farther = max(pr[i] - pr[i - w], pr[j + w] - pr[j]) / w
    sigma = max(noise_rel * mean_range, noise_floor_m)
    n = j - i
    needed = best_z * sigma / math.sqrt(n) + margin_m
    return (
        farther - mean_range * math.cos(0.5 * span) >= needed
        and farther - math.hypot(px[j] - px[i], py[j] - py[i]) / n >= needed
    )


@njit(cache=True, inline="always")
def _line_depth(px, py, pr, a0, a1, b0, b1, q0, q1, noise_rel, noise_floor_m):
    """How much nearer than the line through the centroids of the beams ``[a0, a1)`` and
    ``[b0, b1)`` the centroid of the beams ``[q0, q1)`` lies, along its line of sight (m;
    prefix sums ``px, py, pr`` of the echo points and ranges), and the variance of that
    depth (m²) from the range noise of the three groups (``_depth_variance``). Variance 0
    where the geometry gives no depth (``_sight_line``)."""
    a = _group(px, py, pr, a0, a1, noise_rel, noise_floor_m)
    b = _group(px, py, pr, b0, b1, noise_rel, noise_floor_m)
    q = _group(px, py, pr, q0, q1, noise_rel, noise_floor_m)
    behind, ux, uy, cross = _sight_line(a, b, q)
    if behind <= 0.0:
        return 0.0, 0.0
    return behind - q[2], _depth_variance(a, b, q, a1 - a0, b1 - b0, q1 - q0, behind, ux, uy, cross)


@njit(cache=True, inline="always")
def _group(px, py, pr, k0, k1, noise_rel, noise_floor_m):
    """The beams ``[k0, k1)`` as one point (prefix sums ``px, py, pr`` of the echo points and
    ranges): the centroid ``x, y`` of their echo points (m), its range (m), and the range
    noise σ at their mean range (m)."""
    n = k1 - k0
    x, y = (px[k1] - px[k0]) / n, (py[k1] - py[k0]) / n
    return x, y, math.hypot(x, y), max(noise_rel * (pr[k1] - pr[k0]) / n, noise_floor_m)


@njit(cache=True)
def _sight_line(a, b, q):
    """Where the line of sight to the point ``q`` meets the line through the points ``a`` and
    ``b`` (each ``_group``'s ``x, y, range, σ``): its range there ``behind`` (m), the unit
    line of sight ``ux, uy``, and its cross product with ``b − a``. ``behind`` is 0 where the
    geometry gives none (a point at the sensor, the line of sight parallel to the line);
    the line lies behind the sensor where it is negative."""
    if q[2] <= 0.0 or a[2] <= 0.0 or b[2] <= 0.0:
        return 0.0, 0.0, 0.0, 0.0
    ux, uy = q[0] / q[2], q[1] / q[2]
    dx, dy = b[0] - a[0], b[1] - a[1]
    cross = ux * dy - uy * dx  # the line of sight against the line
    if abs(cross) < 1e-6 * (abs(dx) + abs(dy)):
        return 0.0, 0.0, 0.0, 0.0
    return (a[0] * dy - a[1] * dx) / cross, ux, uy, cross


@njit(cache=True)
def _depth_variance(a, b, q, na, nb, nq, behind, ux, uy, cross):
    """The variance (m²) of ``_line_depth``'s depth of the group ``q`` (``nq`` beams) before
    the line through the groups ``a`` and ``b`` (``na``, ``nb`` beams), given ``_sight_line``'s
    outputs (``behind`` > 0): the range noise of the three groups, propagated through the
    geometry to first order (each centroid moves along its own line of sight)."""
    ax, ay, range_a, sigma_a = a
    bx, by, range_b, sigma_b = b
    sigma_q = q[3]
    dx, dy = bx - ax, by - ay
    # first-order sensitivity of ``behind`` to each anchor moving along its own line of sight
    eax, eay, ebx, eby = ax / range_a, ay / range_a, bx / range_b, by / range_b
    gain_a = ((eax * dy - eay * dx) + behind * (ux * eay - uy * eax)) / cross
    gain_b = ((ax * eby - ay * ebx) - behind * (ux * eby - uy * ebx)) / cross
    return sigma_q * sigma_q / nq + (gain_a * sigma_a) ** 2 / na + (gain_b * sigma_b) ** 2 / nb


@njit(cache=True, inline="always")
def _measure_run(
    ranges_m,
    cos_b,
    sin_b,
    beam_step_rad,
    start,
    stop,
    known_extent_m,
    hidden_var_m2,
    noise_rel,
    noise_floor_m,
    surface_sigma_m,
    row,
):
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
def carve_body(
    ranges_m,
    cos_b,
    sin_b,
    beam_step_rad,
    no_echo_from_m,
    x_m,
    y_m,
    extent_m,
    noise_rel,
    noise_floor_m,
    jump_m,
    jump_sigmas,
    surface_sigma_m,
    min_beams,
    row,
):
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
    _measure_run(
        ranges_m,
        cos_b,
        sin_b,
        beam_step_rad,
        best_start,
        best_stop,
        extent_m,
        (0.5 * extent_m) ** 2,
        noise_rel,
        noise_floor_m,
        surface_sigma_m,
        row,
    )
    row[_CANDIDATE] = UPDATE_ONLY
    return True
