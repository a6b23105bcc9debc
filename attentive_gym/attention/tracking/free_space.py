"""Free-space evidence of motion (docs/model.md §10): a laser echo where an earlier scan saw through.

A static world never puts a surface inside space the laser has seen to be free. So an echo
that lies, by more than the range noise, short of where an earlier scan's beams passed
freely must come from a body that moved there, and a point an earlier scan hit that the
current scan now sees through must belong to a body that left. Both tests need no velocity
estimate, so they see a start at once, where a tracker must first estimate a velocity.

The scans are compared in the odometry frame (``Tracker``'s): each stored scan keeps the
laser's pose at its time, so the robot's own motion is compensated by the poses.

- ``ScanHistory``: a short ring buffer of past scans and their laser poses.
- ``remember_scan``: store a scan, at most one per ``spacing_s``.
- ``past_scan``: the stored scan closest to a lag before now.
- ``compared_frames`` / ``violation``: by how many σ one echo of a scan lies inside the space
  other scans saw as free (conservatively the smallest range of each scan's beams within a
  small width of the echo, at least the beam it falls in and its two neighbours, so that
  depth edges and grazing surfaces give none).
- ``evidence_runs``: runs of neighbouring beams whose scores pass a threshold each and, over
  the run, a combined one: the beams with moving evidence.
- ``scan_evidence``: one scan's evidence against the past scans at several lags: the
  echoes that appeared in free space (``violation``), worked out only for the beams a caller
  wants and the runs that reach them.
- ``seen_through``: the vacated test of one point (a track's earlier position): by how much
  the current scan sees past it. It is a test per body, not per beam: a beam that now
  passes a body's old place may end on the body itself (it moved away along the beam) or
  on the background behind it, and one beam cannot tell which.
- ``segment_evidence``: the share of each scan segment's beams with moving evidence.
- ``weigh_motion``: the tracker's probabilities of moving weighed by the evidence: tracks
  born moving, and the log-odds of matched tracks raised with evidence and lowered without.

Units: seconds, metres, radians. Beam ``j`` of an ``n``-beam scan spans the bearings
``first + j·step`` to ``first + (j + 1)·step`` (rad, laser frame, counter-clockwise from
its forward axis); a range at or above ``no_echo_m`` is no echo (free as far as it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

__all__ = [
    "BEAM_SIGMAS",
    "MIN_BEAMS",
    "MARGIN_M",
    "WIDTH_M",
    "MIN_SHARE",
    "UNDETECTABLE_SIGMAS",
    "DETECTABLE_SIGMAS",
    "PARAMETERS",
    "evidence_parameters",
    "ScanHistory",
    "remember_scan",
    "past_scan",
    "compared_frames",
    "violation",
    "evidence_runs",
    "scan_evidence",
    "seen_through",
    "segment_evidence",
    "motion_weights",
    "detectability",
    "weigh_motion",
]

#: The tracker's fixed settings of the tests: a beam's least score (σ), the fewest beams of a
#: run, the margin (m) and width (m) of ``evidence_parameters``, and the least share of a
#: segment's beams that makes it evidence (``weigh_motion``).
BEAM_SIGMAS, MIN_BEAMS, MARGIN_M, WIDTH_M, MIN_SHARE = 1.0, 3, 0.05, 0.05, 0.3
#: A matched track's motion over the longest lag, in σ of the range noise at its distance,
#: below which it leaves no evidence (its silence counts for nothing) and from which it
#: surely does (its silence counts in full): ``detectability``.
UNDETECTABLE_SIGMAS, DETECTABLE_SIGMAS = 1.0, 3.0
#: Slots of ``ScanHistory.counters``: the row the next scan goes to, and how many are stored.
_NEXT, _STORED = 0, 1
#: The tests' parameters, in the order of their vector (``evidence_parameters``).
PARAMETERS = ("first_rad", "step_rad", "no_echo_m", "noise_rel", "noise_floor_m", "margin_m", "width_m")
_FIRST, _STEP, _NO_ECHO, _NOISE_REL, _NOISE_FLOOR, _MARGIN, _WIDTH = range(len(PARAMETERS))


def evidence_parameters(
    first_rad: float,
    step_rad: float,
    no_echo_m: float,
    noise_rel: float,
    noise_floor_m: float,
    margin_m: float,
    width_m: float,
) -> np.ndarray:
    """The parameter vector ``(7,)`` of ``violation``, ``scan_evidence`` and ``seen_through``.

    Args:
        first_rad, step_rad: the beams' geometry (module docstring).
        no_echo_m: ranges at or above it are no echo (m): nothing to test, free that far.
        noise_rel, noise_floor_m: a range's σ is ``max(noise_rel · r, noise_floor_m)`` (m).
        margin_m: how far (m) an echo must lie inside free space beyond the noise.
        width_m: the width (m) across the other scan's beams around an echo that it must have
            seen free (at least the beam the echo falls in and its two neighbours), so that
            thin structure seen edge-on, which rays can pass beside, gives no evidence.
    """
    values = (first_rad, step_rad, no_echo_m, noise_rel, noise_floor_m, margin_m, width_m)
    if not all(math.isfinite(v) for v in values) or step_rad <= 0.0 or min(values[2:]) < 0.0:
        raise ValueError(f"evidence parameters must be finite, step_rad > 0 and the others after it >= 0; got {values}")
    return np.array(values, np.float64)


@dataclass(frozen=True, eq=False)
class ScanHistory:
    """A ring buffer of the last ``capacity`` stored scans.

    Attributes:
        times: ``(K,)`` each stored scan's time (s).
        poses: ``(K, 3)`` the laser's pose at that time in the odometry frame (x m, y m,
            heading rad).
        ranges: ``(K, n)`` the scan's ranges (m).
        counters: ``(2,)`` int64: the row the next scan is written to, and how many rows
            hold a scan.
    """

    times: np.ndarray
    poses: np.ndarray
    ranges: np.ndarray
    counters: np.ndarray

    @classmethod
    def empty(cls, capacity: int, n_beams: int) -> ScanHistory:
        """A history with room for ``capacity`` scans of ``n_beams`` beams, holding none."""
        if capacity < 1 or n_beams < 3:
            raise ValueError(f"a scan history needs capacity >= 1 and >= 3 beams, got {capacity} and {n_beams}")
        return cls(np.zeros(capacity), np.zeros((capacity, 3)), np.zeros((capacity, n_beams)), np.zeros(2, np.int64))

    def clear(self) -> None:
        """Forget every stored scan."""
        self.counters[:] = 0


def motion_weights(
    min_share: float,
    vacated_sigmas: float,
    born_moving: float,
    evidence_log_odds: float,
    none_log_odds: float,
    floor: float,
) -> np.ndarray:
    """The weight vector ``(6,)`` of ``weigh_motion``.

    Args:
        min_share: the share of a segment's beams with evidence that makes it evidence, in (0, 1].
        vacated_sigmas: how far (σ) a scan must see past a track's static place, > 0.
        born_moving: a track born with evidence starts with this probability of moving, in (0, 1).
        evidence_log_odds: the log-odds a matched track gains with evidence, >= 0.
        none_log_odds: the log-odds it gains without, <= 0.
        floor: probabilities stay within ``[floor, 1 - floor]``, in (0, 0.5).
    """
    values = (min_share, vacated_sigmas, born_moving, evidence_log_odds, none_log_odds, floor)
    if not (
        all(math.isfinite(v) for v in values)
        and 0.0 < min_share <= 1.0
        and vacated_sigmas > 0.0
        and 0.0 < born_moving < 1.0
        and evidence_log_odds >= 0.0
        and none_log_odds <= 0.0
        and 0.0 < floor < 0.5
    ):
        raise ValueError(
            "motion weights need min_share in (0, 1], vacated_sigmas > 0, born_moving in (0, 1), "
            f"evidence_log_odds >= 0, none_log_odds <= 0 and floor in (0, 0.5); got {values}"
        )
    return np.array(values, np.float64)


@njit(cache=True)
def remember_scan(t_s, ranges, pose, spacing_s, times, poses, past, counters):
    """Store the scan ``ranges`` ``(n,)`` taken at ``t_s`` (s) from the laser pose ``pose``
    ``(3,)`` in the history's arrays (``ScanHistory``'s fields), unless the newest stored scan
    is less than ``spacing_s`` (s) older; whether it was stored."""
    stored = counters[_STORED]
    capacity = times.shape[0]
    if stored > 0:
        newest = (counters[_NEXT] - 1) % capacity
        if t_s - times[newest] < spacing_s:
            return False
    row = counters[_NEXT]
    times[row] = t_s
    poses[row, 0], poses[row, 1], poses[row, 2] = pose[0], pose[1], pose[2]
    past[row, :] = ranges
    counters[_NEXT] = (row + 1) % capacity
    counters[_STORED] = min(stored + 1, capacity)
    return True


@njit(cache=True)
def past_scan(t_s, lag_s, times, counters):
    """The row of the stored scan whose age at ``t_s`` is closest to ``lag_s`` (s), among those
    whose age lies within ``[lag_s / 2, 3 lag_s / 2]``; −1 for none."""
    best, best_gap = -1, 0.5 * lag_s
    capacity = times.shape[0]
    for k in range(counters[_STORED]):
        row = (counters[_NEXT] - 1 - k) % capacity
        gap = abs((t_s - times[row]) - lag_s)
        if gap <= best_gap:
            best, best_gap = row, gap
    return best


@njit(cache=True)
def _range_sigma(r, noise_rel, noise_floor_m):
    return max(noise_rel * r, noise_floor_m)


@njit(cache=True)
def _free_score(rho, j, free, params):
    """By how many σ a point at ``rho`` (m) in beam ``j`` of the scan ``free`` lies inside its
    free space (``violation``); 0 where the beams within ``width_m / 2`` of it leave the
    field of view."""
    step, no_echo = params[_STEP], params[_NO_ECHO]
    half = max(1, int(math.ceil(0.5 * params[_WIDTH] / (max(rho, 1e-6) * step))))
    if j - half < 0 or j + half > free.shape[0] - 1:
        return 0.0
    f = no_echo
    for i in range(j - half, j + half + 1):
        f = min(f, free[i])
    inside = f - rho - params[_MARGIN]
    if inside <= 0.0:  # most echoes: on or behind what B saw, no need for the noise
        return 0.0
    noise_rel, noise_floor = params[_NOISE_REL], params[_NOISE_FLOOR]
    sigma_rho, sigma_f = _range_sigma(rho, noise_rel, noise_floor), _range_sigma(f, noise_rel, noise_floor)
    return inside / math.sqrt(sigma_rho * sigma_rho + sigma_f * sigma_f)


@njit(cache=True)
def compared_frames(hit_pose, rows, poses, frames):
    """The rigid transform from scan A's laser pose ``hit_pose`` ``(3,)`` into each compared
    scan B's (``poses[row]`` for the history's ``rows`` ``(L,)``): ``frames`` ``(L, 4)`` output,
    per row A's laser position in B's laser frame ``(tx, ty)`` (m) and the cosine and sine of
    A's heading relative to B's."""
    for k in range(rows.shape[0]):
        free_pose = poses[rows[k]]
        turn = hit_pose[2] - free_pose[2]
        c, s = math.cos(free_pose[2]), math.sin(free_pose[2])
        dx, dy = hit_pose[0] - free_pose[0], hit_pose[1] - free_pose[1]
        frames[k, 0], frames[k, 1] = c * dx + s * dy, -s * dx + c * dy
        frames[k, 2], frames[k, 3] = math.cos(turn), math.sin(turn)


@njit(cache=True)
def violation(b, r, rows, frames, past, params):
    """By how many σ the echo at range ``r`` (m) of beam ``b`` of scan A lies inside the space
    the compared scans B saw as free, the most over them: B's ranges ``past[rows[k]]``, A's
    pose in B's frame ``frames[k]`` (``compared_frames``); both scans share the beams'
    geometry (``params``: ``evidence_parameters``).

    Each B's score is ``max(0, (f − ρ − margin) / σ)``, with ρ the echo's distance from B's
    laser, f the smallest of B's ranges on the beams within ``width_m / 2`` of it (at ρ) and
    at least the neighbours of the beam it falls in, and σ the noise of the difference; 0
    where those beams leave B's field of view, and at no echo."""
    if r >= params[_NO_ECHO]:
        return 0.0
    first, step = params[_FIRST], params[_STEP]
    bearing = first + (b + 0.5) * step
    bc, bs = math.cos(bearing), math.sin(bearing)
    score = 0.0
    for k in range(rows.shape[0]):
        tx, ty, ct, st = frames[k, 0], frames[k, 1], frames[k, 2], frames[k, 3]
        x, y = tx + r * (ct * bc - st * bs), ty + r * (st * bc + ct * bs)
        beam = int(math.floor((math.atan2(y, x) - first) / step))
        score = max(score, _free_score(math.sqrt(x * x + y * y), beam, past[rows[k]], params))
    return score


@njit(cache=True)
def evidence_runs(scores, beam_threshold, run_threshold, min_beams, flags):
    """Flag ``flags`` ``(n,)`` the beams of the runs of neighbouring beams whose ``scores``
    ``(n,)`` (σ) each reach ``beam_threshold``, where a run holds at least ``min_beams`` beams
    and its combined score ``Σ scores / √beams`` reaches ``run_threshold`` (σ: the noise of
    one beam's test averages out over a body's beams); returns how many beams are flagged."""
    n = scores.shape[0]
    flags[:] = False
    flagged, start, total = 0, -1, 0.0
    for b in range(n + 1):
        passing = b < n and scores[b] >= beam_threshold
        if passing:
            if start < 0:
                start, total = b, 0.0
            total += scores[b]
        elif start >= 0:
            beams = b - start
            if beams >= min_beams and total / math.sqrt(beams) >= run_threshold:
                flags[start:b] = True
                flagged += beams
            start = -1
    return flagged


@njit(cache=True)
def scan_evidence(t_s, ranges, pose, lags_s, times, poses, past, counters, params, wanted, beam_threshold, appeared):
    """The moving evidence of the scan ``ranges`` ``(n,)`` taken at ``t_s`` (s) from the laser
    pose ``pose`` ``(3,)``: ``appeared`` ``(n,)`` (σ) is, per beam, by how much its echo lies
    inside the free space of the stored scans (``ScanHistory``'s arrays) closest to the lags
    ``lags_s`` ``(L,)`` (s) before it (``violation``: the most over the lags; ``past_scan``,
    each stored scan used once). Returns how many past scans were compared.

    Only what ``evidence_runs`` needs for the ``wanted`` ``(n,)`` beams is worked out: those
    beams, and the beams of any run of scores at or above ``beam_threshold`` (σ) that reaches
    one of them, so that each wanted beam's run is the one the whole scan would give. The
    other beams' entries are 0.
    """
    n = ranges.shape[0]
    appeared[:] = 0.0
    rows = np.full(lags_s.shape[0], -1, np.int64)
    compared = 0
    for k in range(lags_s.shape[0]):
        row = past_scan(t_s, lags_s[k], times, counters)
        if row < 0 or t_s - times[row] <= 0.0 or row in rows[:compared]:
            continue
        rows[compared] = row
        compared += 1
    if compared == 0:
        return 0
    rows = rows[:compared]
    frames = np.empty((compared, 4))
    compared_frames(pose, rows, poses, frames)
    done = wanted.copy()
    for b in range(n):
        if wanted[b]:
            appeared[b] = violation(b, ranges[b], rows, frames, past, params)
    for b in range(n):  # runs that pass a wanted beam: follow them out to where they end
        if not (done[b] and appeared[b] >= beam_threshold):
            continue
        for direction in (-1, 1):
            j = b + direction
            while 0 <= j < n and not done[j]:
                appeared[j] = violation(j, ranges[j], rows, frames, past, params)
                done[j] = True
                if appeared[j] < beam_threshold:
                    break
                j += direction
    return compared


@njit(cache=True)
def seen_through(x, y, ranges, pose, params):
    """By how many σ the scan ``ranges`` ``(n,)`` taken from the laser pose ``pose`` ``(3,)``
    sees past the point ``(x, y)`` (m, odometry frame): ``violation``'s score of an echo at
    that point (0 outside the field of view). A body's earlier point seen through has left
    (the vacated test)."""
    first, step = params[_FIRST], params[_STEP]
    dx, dy = x - pose[0], y - pose[1]
    rho = math.sqrt(dx * dx + dy * dy)
    phi = (math.atan2(dy, dx) - pose[2] + math.pi) % (2.0 * math.pi) - math.pi
    return _free_score(rho, int(math.floor((phi - first) / step)), ranges, params)


@njit(cache=True)
def segment_evidence(flags, bounds, count, shares):
    """The share of each segment's beams with moving evidence: ``shares[m]`` for the ``count``
    segments whose beams are ``bounds[m, 0] <= b < bounds[m, 1]`` (``segmentation``'s
    ``(B, 2)`` bounds), from the flags ``(n,)`` of ``evidence_runs``."""
    for m in range(count):
        start, stop = bounds[m, 0], bounds[m, 1]
        flagged = 0
        for b in range(start, stop):
            flagged += flags[b]
        shares[m] = flagged / max(stop - start, 1)


@njit(cache=True, inline="always")
def detectability(state, pose, params, lag_s):
    """How surely (0 to 1) the motion of a track with the constant-velocity state ``state``
    ``(4,)`` (odometry frame: x, y m; vx, vy m/s) would have left free-space evidence over the
    longest lag ``lag_s`` (s), seen from the laser pose ``pose`` ``(3,)``: 0 while its move over
    the lag is within ``UNDETECTABLE_SIGMAS`` of the range noise at its distance, 1 from
    ``DETECTABLE_SIGMAS``, linear between."""
    rho = math.hypot(state[0] - pose[0], state[1] - pose[1])
    sigma = max(params[_NOISE_REL] * rho, params[_NOISE_FLOOR])
    moved = math.hypot(state[2], state[3]) * lag_s / sigma
    return min(max((moved - UNDETECTABLE_SIGMAS) / (DETECTABLE_SIGMAS - UNDETECTABLE_SIGMAS), 0.0), 1.0)


@njit(cache=True)
def weigh_motion(
    t_s, shares, ranges, pose, params, weights, segment_of, static_x, alive, born_s, p_moving, cv_x, lag_s
):
    """Weigh each track's probability of moving ``p_moving`` ``(K,)`` by the scan's free-space
    evidence, in place, after the tracker's own update of the scan at ``t_s`` (s).

    A track matched to a segment this scan (``segment_of[k] >= 0``) has evidence when at least
    ``weights[0]`` of the segment's beams have it (``shares``, ``segment_evidence``), or when
    the scan ``ranges`` (taken from the laser pose ``pose``) sees through its static
    hypothesis' place ``static_x[k]`` by at least ``weights[1]`` σ (``seen_through``: the body
    left the place where it would stand). A track not matched this scan (coasting, hidden or
    missed) has none. A track born this scan (``born_s[k] == t_s``) with evidence starts at
    probability ``weights[2]`` (born moving); an older one's log-odds gain ``weights[3]`` with
    evidence and ``weights[4]`` (≤ 0) without, so a track coasting out of view does not keep
    the label it had. A matched track without evidence gains ``weights[4]`` times its
    ``detectability``: a body too slow, or too far, for its motion to stand out of the range
    noise over ``lag_s`` (s) leaves no evidence whether it moves or not, and its silence says
    nothing. Probabilities stay within ``[weights[5], 1 − weights[5]]``.

    Args:
        params: ``(7,)`` ``evidence_parameters``.
        weights: ``(6,)`` as above (``motion_weights``).
        segment_of, static_x, alive, born_s: the tracker's ``(K,)``, ``(K, 2)`` (odometry frame,
            m), ``(K,)`` and ``(K,)`` (s) arrays.
        cv_x: the tracks' constant-velocity states ``(K, 4)`` (odometry frame; m, m/s).
        lag_s: the longest lag (s) a scan is compared over.
    """
    floor = weights[5]
    for k in range(alive.shape[0]):
        m = segment_of[k]
        if not alive[k]:
            continue
        evidence = m >= 0 and (
            shares[m] >= weights[0] or seen_through(static_x[k, 0], static_x[k, 1], ranges, pose, params) >= weights[1]
        )
        if born_s[k] == t_s:
            if evidence:
                p_moving[k] = weights[2]
            continue
        p = p_moving[k]
        gain = weights[3] if evidence else weights[4]
        if not evidence and m >= 0:  # matched: its silence counts as far as its motion was detectable
            gain *= detectability(cv_x[k], pose, params, lag_s)
        odds = math.log(p / (1.0 - p)) + gain
        p_moving[k] = min(max(1.0 / (1.0 + math.exp(-odds)), floor), 1.0 - floor)
