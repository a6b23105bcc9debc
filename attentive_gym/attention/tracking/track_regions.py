"""From tracks to the model's per-reading and per-region kinematics (docs/model.md §10).

- ``track_channels``: range rates, speeds and moving flags for every channel of the
  model (8 front sonars, then 180 laser beams), from the ``Tracker``'s state: a beam
  takes the values of the confirmed track its segment was matched to; a front sonar's
  channel those of the region's fastest confirmed track, or, where the region's beams
  see nothing, its own range/rate filter. The F1–F6 stages read these as they read the
  window's range rates. With ``track_speed_goal_probability``, each region's track also
  gets the probability that a speed goal holds at it (``speed_goal_probability``).
- ``track_table``: the live tracks in the robot frame, the rows of a ``TrackTable``.

A track's range rate is its own ground velocity along the line of sight (m/s, + away):
the robot's motion is already compensated, as in docs/model.md §3. Its speed is the norm of
its 2-D ground velocity, so a body crossing in front of the robot has a speed (the
paper's Δs/Δt sees only radial motion).

Small kernels that the model's step calls in its loops are compiled ``inline="always"``:
inlined into their caller, the views of per-track rows (or the arrays) they take need no
reference counting, two atomic operations per array and call otherwise.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["track_channels", "track_table"]

_HALF_PI = 0.5 * math.pi
_SQRT2 = math.sqrt(2.0)
#: A track whose motion probability exceeds this is labelled moving.
MOVING_PROBABILITY = 0.5
#: A track's probability of moving stays within [MOTION_FLOOR, 1 − MOTION_FLOOR], so that
#: either hypothesis can always win back (the filters' update and the start test both bound it).
MOTION_FLOOR = 1e-3


@njit(cache=True, inline="always")
def _region_of(x_m, y_m, beam_step_rad, beam_region):
    """Region of a point in the robot frame (that of the laser beam on its bearing), −1 behind."""
    bearing = math.atan2(y_m, x_m)
    if abs(bearing) > _HALF_PI:
        return -1
    beam = int((bearing + _HALF_PI) / beam_step_rad)
    beam = min(max(beam, 0), beam_region.shape[0] - 1)
    return beam_region[beam]


@njit(cache=True, inline="always")
def _relative(k, t_s, pose, cv_x, filter_t):
    """Track ``k`` predicted to ``t_s`` relative to the robot, in the odometry frame's axes (m)."""
    dt = t_s - filter_t[k]
    return cv_x[k, 0] + dt * cv_x[k, 2] - pose[0], cv_x[k, 1] + dt * cv_x[k, 3] - pose[1]


@njit(cache=True, inline="always")
def speed_goal_probability(vx, vy, var_xx, var_xy, var_yy, p_moving, lo, hi):
    """The probability that a track moves at a speed in ``[lo, hi]`` (m/s; ``hi`` may be
    inf, ``lo`` −inf): its probability of moving ``p_moving`` times P(lo ≤ |v| ≤ hi), the
    speed taken as normal along the velocity ``(vx, vy)`` (m/s): mean ``|v|``, variance the
    velocity covariance ``[[var_xx, var_xy], [var_xy, var_yy]]`` (m²/s²) along its direction
    (its mean variance where ``|v|`` is under 1e-6 m/s). A static body has no speed.

    Measured in the perception arena at 5 % noise (``benchmarks/calibration.py``): of the
    tracks judged in the fast band with probability p, at least about p are (close to p on
    model version 1, more in the middle bins on version 2).
    """
    speed = math.hypot(vx, vy)
    if speed > 1e-6:
        variance = (vx * vx * var_xx + 2.0 * vx * vy * var_xy + vy * vy * var_yy) / (speed * speed)
    else:
        variance = 0.5 * (var_xx + var_yy)
    scale = _SQRT2 * math.sqrt(max(variance, 1e-12))
    below_hi = 1.0 if hi == math.inf else 0.5 * (1.0 + math.erf((hi - speed) / scale))
    below_lo = 0.0 if lo == -math.inf else 0.5 * (1.0 + math.erf((lo - speed) / scale))
    return p_moving * max(below_hi - below_lo, 0.0)


@njit(cache=True)
def track_channels(
    t_s,
    pose,
    confirm_hits,
    max_speed,
    epsilon,
    wanted_speed,
    beam_step_rad,
    beam_region,
    cone_bounds,
    match_m,
    match_sigmas,
    noise_rel,
    noise_floor_m,
    judge_probability,
    readings,
    valid,
    cv_x,
    cv_P,
    p_moving,
    alive,
    hits,
    filter_t,
    segment_of,
    bounds,
    sonar_x,
    sonar_hits,
    rates,
    speeds,
    moving,
    region_track,
    speed_probability,
):
    """Per-channel kinematics from the tracks (see the module docstring).

    Args:
        t_s: the step's time (s); pose: ``(3,)`` the robot in the odometry frame.
        confirm_hits: hits that confirm a track; max_speed: speeds are clipped to it
            (m/s); epsilon: a channel moves when its speed exceeds it (m/s).
        wanted_speed: ``(2,)`` the speeds a speed goal asks for, ``[lo, hi]`` (m/s), or
            ``[inf, inf]`` without one: a region's channel takes the moving track whose
            speed the goal wants, else the region's fastest track.
        beam_step_rad, beam_region: ``(180,)`` the region of each beam.
        cone_bounds: ``(8, 2)`` the beams ``start <= i < stop`` inside each sonar's cone.
        match_m, match_sigmas, noise_rel, noise_floor_m: a laser echo in a sonar's cone
            within ``match_m + match_sigmas · √2 · σ(r)`` of its reading ``r`` (σ(r) =
            max(noise_rel · r, noise_floor_m)) is what the sonar sees (m).
        judge_probability: judge the speed goal by ``speed_goal_probability``
            (``AttentionConfig.track_speed_goal_probability``): a region's channel takes the
            track at which the goal most probably holds, where that is at least ½, and the
            probability is written; else the point rule above, and −1 is written.
        readings, valid: ``(188,)`` the clipped readings (m) and their echo flags.
        cv_x … bounds: the ``Tracker``'s arrays (``cv_P`` ``(capacity, 4, 4)`` the
            constant-velocity filters' covariances); sonar_x, sonar_hits: its sonar filters.
        rates, speeds: ``(188,)`` outputs (m/s); moving: ``(188,)`` bool output;
        region_track: ``(8,)`` int64 output, the track slot behind each front sonar's
            channel, −1 for none; speed_probability: ``(8,)`` output, the probability
            that the speed goal holds at that track, −1 where it is not judged so (no
            track, no speed goal, or ``judge_probability`` off).
    """
    n_sonar = region_track.shape[0]
    rates[:] = 0.0
    speeds[:] = 0.0
    moving[:] = False
    region_track[:] = -1
    speed_probability[:] = -1.0
    judging = judge_probability and wanted_speed[0] != math.inf
    best = np.empty(n_sonar)
    c, s = math.cos(pose[2]), math.sin(pose[2])
    for k in range(alive.shape[0]):
        if not alive[k] or hits[k] < confirm_hits:
            continue
        dx, dy = _relative(k, t_s, pose, cv_x, filter_t)
        vx, vy = p_moving[k] * cv_x[k, 2], p_moving[k] * cv_x[k, 3]
        speed = min(math.hypot(vx, vy), max_speed)
        distance = math.hypot(dx, dy)
        rate = (dx * vx + dy * vy) / distance if distance > 0.0 else 0.0
        is_moving = p_moving[k] > MOVING_PROBABILITY and speed > epsilon
        m = segment_of[k]
        if m >= 0:
            for i in range(bounds[m, 0], bounds[m, 1]):
                rates[n_sonar + i], speeds[n_sonar + i], moving[n_sonar + i] = rate, speed, is_moving
        j = _region_of(c * dx + s * dy, -s * dx + c * dy, beam_step_rad, beam_region)
        if j < 0:
            continue
        # wanted moving tracks first (by the probability that the goal holds there, or by
        # motion probability), then the fastest
        probability = -1.0
        if judging:
            probability = speed_goal_probability(
                cv_x[k, 2],
                cv_x[k, 3],
                cv_P[k, 2, 2],
                cv_P[k, 2, 3],
                cv_P[k, 3, 3],
                p_moving[k],
                wanted_speed[0],
                wanted_speed[1],
            )
            wanted = probability >= 0.5
            strength = probability
        else:
            wanted = is_moving and wanted_speed[0] <= speed <= wanted_speed[1]
            strength = p_moving[k]
        score = 2.0 * max_speed + strength if wanted else speed
        if region_track[j] < 0 or score > best[j]:
            region_track[j] = k
            best[j] = score
            rates[j], speeds[j], moving[j] = rate, speed, is_moving
            speed_probability[j] = probability
    for j in range(n_sonar):
        if region_track[j] >= 0 or not valid[j] or sonar_hits[j] < confirm_hits:
            continue
        laser_sees_it = False
        tolerance = match_m + match_sigmas * _SQRT2 * max(noise_rel * readings[j], noise_floor_m)
        for i in range(cone_bounds[j, 0], cone_bounds[j, 1]):
            k = n_sonar + i
            if valid[k] and abs(readings[k] - readings[j]) <= tolerance:
                laser_sees_it = True
                break
        if not laser_sees_it:
            rate = sonar_x[j, 1]
            rates[j], speeds[j], moving[j] = rate, min(abs(rate), max_speed), abs(rate) > epsilon


@njit(cache=True)
def track_table(
    t_s,
    pose,
    confirm_hits,
    beam_step_rad,
    beam_region,
    cv_x,
    cv_P,
    p_moving,
    alive,
    ids,
    hits,
    born_s,
    filter_t,
    table,
    covariance,
):
    """The live tracks in the robot frame: one row of ``tracker.TRACK_TABLE_FIELDS`` each in
    ``table`` ``(capacity, 11)`` and their covariances in ``covariance`` ``(capacity, 4, 4)``;
    returns the number of rows written (slot order)."""
    c, s = math.cos(pose[2]), math.sin(pose[2])
    n = 0
    for k in range(alive.shape[0]):
        if not alive[k]:
            continue
        dx, dy = _relative(k, t_s, pose, cv_x, filter_t)
        x, y = c * dx + s * dy, -s * dx + c * dy
        vx, vy = p_moving[k] * cv_x[k, 2], p_moving[k] * cv_x[k, 3]
        table[n, 0] = ids[k]
        table[n, 1], table[n, 2] = x, y
        table[n, 3], table[n, 4] = c * vx + s * vy, -s * vx + c * vy
        table[n, 5] = math.hypot(vx, vy)
        table[n, 6] = p_moving[k]
        table[n, 7] = t_s - born_s[k]
        table[n, 8] = 1.0 if hits[k] >= confirm_hits else 0.0
        table[n, 9] = _region_of(x, y, beam_step_rad, beam_region)
        table[n, 10] = k
        # T P Tᵀ with T = diag(Rot(−θ), Rot(−θ))
        for i in range(4):
            for j in range(4):
                total = 0.0
                for a in range(4):
                    ta = _rotation_entry(i, a, c, s)
                    if ta == 0.0:
                        continue
                    for b in range(4):
                        tb = _rotation_entry(j, b, c, s)
                        if tb != 0.0:
                            total += ta * cv_P[k, a, b] * tb
                covariance[n, i, j] = total
        n += 1
    return n


@njit(cache=True)
def _rotation_entry(i, j, c, s):
    """Entry (i, j) of ``diag(Rot(−θ), Rot(−θ))`` for ``c = cos θ``, ``s = sin θ``."""
    if i // 2 != j // 2:
        return 0.0
    a, b = i % 2, j % 2
    if a == b:
        return c
    return s if a == 0 else -s
