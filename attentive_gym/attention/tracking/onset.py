"""Starts told by a change test on a track's recent centroids (docs/model.md §10).

A body standing still that starts to move shifts its centroid along a ramp. The filters
see the start one innovation at a time; a generalised likelihood ratio (GLR) test over
the last scans' centroids sees the whole ramp at once. For each start time ``τ`` among the
buffered scans it fits by weighted least squares the ramp model

    z_i = a + v · max(0, t_i − τ)          (a, v ∈ R²)

against the standing model ``z_i = a``, each centroid ``z_i`` weighed by its measurement
covariance ``R_i``. The log-likelihood ratio of the best start,
``½ (χ²_standing − χ²_ramp)``, above a threshold says the body started; the fit gives its
velocity, its position now and their covariance at once, instead of the 0.3–0.5 s the
constant-velocity filter needs to absorb a start (Willsky & Jones, IEEE TAC 1976).

- ``remember_centroid``: push a matched centroid into a track's ring buffer.
- ``ramp_onset``: the test of every standing track just matched; a start sets its
  constant-velocity state from the fit and its probability of moving from the ratio. While
  the laser drives, a start must also beat a centre that slides with the segment's extent
  (static structure whose faces turn away shrinks and slides). With a second threshold it
  also runs the change test on every moving track (``velocity_change``).
- ``velocity_change``: a moving body that stops, turns or reverses bends its centroids'
  line. The test fits ``z_i = a + v (t_i − t) + w · max(0, τ − t_i)`` (a line through now, with
  a kink at τ) against the line ``z_i = a + v (t_i − t)``; a change sets the track's
  position and velocity from the part after τ.

Units: seconds, metres, m/s. Arrays: ``history`` ``(K, CENTROID_BUFFER, 9)``, a row per
centroid: time (s), position x, y (m, odometry frame), covariance xx, xy, yy (m²), the
segment's extent (m), the laser's position x, y (m);
``counts`` ``(K,)`` int64, centroids pushed since the track's buffer was cleared.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from attentive_gym.attention.tracking.track_regions import MOTION_FLOOR, MOVING_PROBABILITY

__all__ = [
    "ONSET_WINDOW",
    "CENTROID_BUFFER",
    "MIN_CENTROIDS",
    "MIN_CHANGE_CENTROIDS",
    "remember_centroid",
    "ramp_onset",
    "ramp_fit",
    "velocity_change",
    "kink_fit",
]

#: Centroids the start test fits (scans): 0.4 s at 20 Hz, 1.6 s at 5 Hz.
ONSET_WINDOW = 8
#: Centroids kept per track, and the most the change test fits (scans): a change of velocity
#: bends a line less than a start lifts a standing body, and needs a longer run before it.
CENTROID_BUFFER = 16
#: The fewest centroids the test runs on: two standing, two moving.
MIN_CENTROIDS = 4
#: The fewest centroids after a start: one would let a single outlier pass for a ramp.
_MIN_MOVING = 2
#: The fewest centroids the change test runs on: two before the change, two after, and one
#: more than its six parameters need to leave a scatter to judge.
MIN_CHANGE_CENTROIDS = 5
#: A fitted start slower than this (m/s) is not taken: slow wander of a static segment's
#: centre as the view changes, not a body's motion.
MIN_START_SPEED_MPS = 0.1
#: σ of a centroid's scan-to-scan wander beyond the range noise (m). The measurement
#: covariance's surface term (``track_surface_sigma_m``: where on its surface a body's
#: centre is measured) is an offset that stays while the view does, which the fit's ``a``
#: absorbs; what changes from scan to scan is smaller.
WANDER_SIGMA_M = 0.02
#: How much a segment's extent may differ from its window's mean by range noise alone (m).
EXTENT_NOISE_M = 0.1
#: How far a centroid may slide per metre the laser travelled since the previous one (m/m):
#: as the robot drives, segments of rubble and walls merge, split and show new faces, and
#: their centres jump by as much as the robot moved.
VIEW_SLIDE = 1.0
#: The laser's travel over a track's buffered centroids (m) beyond which a start must also beat
#: a centre that slides with the segment's extent (``_reshaping_ratio``): the view of static
#: structure changes only as the laser moves.
VIEW_TRAVEL_M = 0.05


@njit(cache=True, inline="always")
def remember_centroid(k, t_s, z, r, extent_m, surface_sigma_m, laser_pose, history, counts):
    """Push track ``k``'s centroid ``z`` ``(2,)`` (m) of a segment ``extent_m`` (m) across, measured
    at ``t_s`` (s) from the laser at ``laser_pose`` ``(3,)`` (odometry frame), into its ring buffer
    ``history[k]``, overwriting the oldest when full. Its
    covariance is the measurement's ``r`` ``(2, 2)`` (m²) with the surface term
    ``surface_sigma_m²`` (isotropic) replaced by ``WANDER_SIGMA_M²``."""
    row = history[k, counts[k] % history.shape[1]]
    row[0], row[1], row[2] = t_s, z[0], z[1]
    shift = WANDER_SIGMA_M * WANDER_SIGMA_M - surface_sigma_m * surface_sigma_m
    row[3], row[4], row[5] = r[0, 0] + shift, r[0, 1], r[1, 1] + shift
    row[6] = extent_m
    row[7], row[8] = laser_pose[0], laser_pose[1]
    counts[k] += 1


@njit(cache=True)
def ramp_fit(times, z, weights, start_s, theta, covariance):
    """Weighted least-squares fit of ``z_i = a + v · max(0, t_i − start_s)``.

    Args:
        times: ``(n,)`` the centroids' times (s); z: ``(n, 2)`` positions (m);
            weights: ``(n, 2, 2)`` their inverse covariances (1/m²).
        start_s: the start time τ (s).
        theta: ``(4,)`` output ``(a_x, a_y, v_x, v_y)`` (m, m/s).
        covariance: ``(4, 4)`` output, the fit's covariance.

    Returns:
        χ² of the fit (the weighted sum of squared residuals), or ``inf`` when the
        normal equations are singular.
    """
    factors = np.empty((times.shape[0], 2))
    for i in range(times.shape[0]):
        factors[i, 0], factors[i, 1] = 1.0, max(0.0, times[i] - start_s)
    return _regression(factors, z, weights, theta, covariance)


@njit(cache=True)
def ramp_onset(t_s, log_ratio_threshold, change_log_ratio, runaway_mps, history, counts, cv_x, cv_P, p_moving, alive):
    """The start test of every live track judged standing (``p_moving ≤ MOVING_PROBABILITY``)
    whose newest centroid is this scan's (``t_s``, s), in place; 0 for ``log_ratio_threshold``
    (nats) turns it off.

    A track judged moving takes the change test at ``change_log_ratio`` (nats;
    ``velocity_change``), or, with 0, clears its buffer (``counts[k] = 0``): the start test
    looks for a start in a standing phase only. With at least ``MIN_CENTROIDS`` centroids, each buffered time
    with at least ``_MIN_MOVING`` centroids after it, and the midpoint after it (a start falls
    between scans: at 5 Hz, taking the scan before would halve the fitted speed), is tried
    as the start τ (the oldest: the body moved all along). Each ratio is divided by the
    ramp's own scatter, ``max(1, χ²_ramp / (2n − 4))``: a segment whose centroid jumps more
    than its covariance allows (its shape changing as the view does) needs a larger shift
    to count, and the fit's covariance grows by the same factor. Where the laser travelled
    more than ``VIEW_TRAVEL_M`` over the buffer, the best start must also pass the threshold
    once the centre may slide with the segment's extent (``_reshaping_ratio``). Where the
    best start's ratio exceeds ``log_ratio_threshold`` (nats) and its fitted speed lies in
    ``[MIN_START_SPEED_MPS, runaway_mps]`` (m/s), the track has started:

    - ``cv_x[k]`` ``(4,)`` becomes the fit's position now and velocity, ``cv_P[k]``
      ``(4, 4)`` their covariance;
    - ``p_moving[k]``'s odds grow by the ratio (at most ``1 − 10⁻³``), and its buffer clears.
    """
    window = history.shape[1]
    times = np.empty(window)
    z = np.empty((window, 2))
    weights = np.empty((window, 2, 2))
    sums = np.empty(6)
    theta = np.empty(4)
    best_covariance = np.empty((4, 4))
    for k in range(alive.shape[0]):
        if not alive[k]:
            continue
        moving = p_moving[k] > MOVING_PROBABILITY
        if moving and change_log_ratio <= 0.0:
            counts[k] = 0
            continue
        if counts[k] == 0 or history[k, (counts[k] - 1) % window, 0] != t_s:
            continue
        if moving:
            velocity_change(k, t_s, change_log_ratio, runaway_mps, history, counts, cv_x, cv_P, times, z, weights, sums)
            continue
        n = min(counts[k], window, ONSET_WINDOW)
        if n < MIN_CENTROIDS or log_ratio_threshold <= 0.0:
            continue
        standing = _gather(history[k], counts[k], n, times, z, weights, sums)
        if 0.5 * standing <= log_ratio_threshold:
            continue  # no start can explain more than the standing fit leaves
        best, best_start, best_scale = 0.0, 0.0, 1.0
        for j in range(n - _MIN_MOVING):
            for half in range(2):
                start = times[j] + 0.5 * half * (times[j + 1] - times[j])
                # scattered more than the covariances say: the segment's shape moves, not only the body
                ratio, scale = _scaled_ratio(standing, _ramp_chi2(times, z, weights, n, start, sums), 2 * n - 4)
                if ratio > best:
                    best, best_start, best_scale = ratio, start, scale
        if best <= log_ratio_threshold:
            continue
        if _laser_travel(history[k], counts[k], n) > VIEW_TRAVEL_M and (
            _reshaping_ratio(history[k], counts[k], n, times, z, weights, best_start) <= log_ratio_threshold
        ):
            continue  # the centre moved with the segment's extent as the laser drove: a view that changed
        ramp_fit(times[:n], z[:n], weights[:n], best_start, theta, best_covariance)
        speed = math.hypot(theta[2], theta[3])
        if speed < MIN_START_SPEED_MPS or (runaway_mps > 0.0 and speed > runaway_mps):
            continue
        _set_from_fit(k, t_s - best_start, theta, best_scale * best_covariance, cv_x, cv_P)
        odds = p_moving[k] / (1.0 - p_moving[k]) * math.exp(min(best, 50.0))
        p_moving[k] = min(odds / (1.0 + odds), 1.0 - MOTION_FLOOR)
        counts[k] = 0


@njit(cache=True)
def velocity_change(k, t_s, log_ratio_threshold, runaway_mps, history, counts, cv_x, cv_P, times, z, weights, sums):
    """The change test of moving track ``k`` whose newest centroid is this scan's (``t_s``, s),
    in place.

    With at least ``MIN_CHANGE_CENTROIDS`` buffered centroids (weighed as ``_gather`` weighs
    them), each buffered time with at least two centroids before it and two from it on, and
    the midpoint before it, is tried as the change τ of ``kink_fit``'s model against its line
    (``w = 0``). The line's fit is shared by every τ, and each kink's χ² follows from the 2×2
    Schur complement of the line's normal equations. Each ratio ``½ (χ²_line − χ²_kink)`` is
    divided by the kink's own scatter, ``max(1, χ²_kink / (2n − 6))``. Where the best exceeds
    ``log_ratio_threshold`` (nats) and the speed after τ is under ``runaway_mps`` (m/s; 0: no
    bound), the body changed its motion:

    ``cv_x[k]`` becomes the fit's position now and velocity after τ, ``cv_P[k]`` their
    covariance (× the scatter), and the buffer clears. The probability of moving stays: a
    stop's velocity is near zero, and the filters judge it from there. ``times``, ``z``,
    ``weights`` and ``sums`` are scratch arrays of at least the buffer's length (``_gather``'s).
    """
    window = history.shape[1]
    n = min(counts[k], window)
    if n < MIN_CHANGE_CENTROIDS:
        return
    _gather(history[k], counts[k], n, times, z, weights, sums)
    line, line_inverse, line_rhs = _line_fit(times, z, weights, n, t_s)
    if 0.5 * line <= log_ratio_threshold:
        return  # no change can explain more than the line leaves
    best, best_change, best_scale = 0.0, 0.0, 1.0
    for j in range(2, n - 1):
        for half in range(2):
            change = times[j] - 0.5 * half * (times[j] - times[j - 1])
            kink = line - _kink_reduction(times, z, weights, n, t_s, change, line_inverse, line_rhs)
            ratio, scale = _scaled_ratio(line, kink, 2 * n - 6)
            if ratio > best:
                best, best_change, best_scale = ratio, change, scale
    if best <= log_ratio_threshold:
        return
    theta, covariance = np.empty(6), np.empty((6, 6))
    kink_fit(times[:n], z[:n], weights[:n], t_s, best_change, theta, covariance)
    speed = math.hypot(theta[2], theta[3])
    if runaway_mps > 0.0 and speed > runaway_mps:
        return
    cv_x[k] = theta[:4]
    cv_P[k] = best_scale * covariance[:4, :4]
    counts[k] = 0


@njit(cache=True)
def kink_fit(times, z, weights, now_s, change_s, theta, covariance):
    """Weighted least-squares fit of ``z_i = a + v (t_i − now_s) + w · max(0, change_s − t_i)``:
    a body at ``a`` now, moving at ``v`` since ``change_s`` and at ``v − w`` before.

    Args:
        times: ``(n,)`` the centroids' times (s); z: ``(n, 2)`` positions (m);
            weights: ``(n, 2, 2)`` their inverse covariances (1/m²).
        now_s: the time of ``a`` (s); change_s: the change τ (s).
        theta: ``(6,)`` output ``(a_x, a_y, v_x, v_y, w_x, w_y)`` (m, m/s, m/s).
        covariance: ``(6, 6)`` output, the fit's covariance.

    Returns:
        χ² of the fit, or ``inf`` when the normal equations are singular.
    """
    factors = np.empty((times.shape[0], 3))
    for i in range(times.shape[0]):
        factors[i, 0], factors[i, 1], factors[i, 2] = 1.0, times[i] - now_s, max(0.0, change_s - times[i])
    return _regression(factors, z, weights, theta, covariance)


@njit(cache=True)
def _regression(factors, z, weights, theta, covariance):
    """Weighted least-squares fit of ``z_i = Σ_b factors[i, b] · θ_b`` (``θ_b ∈ R²``): the
    regressors ``factors`` ``(n, m)`` act on both axes of the positions ``z`` ``(n, 2)`` (m),
    weighed by ``weights`` ``(n, 2, 2)`` (1/m²). ``theta`` ``(2m,)`` and ``covariance``
    ``(2m, 2m)`` are outputs, ``θ_b`` at ``theta[2b : 2b + 2]``. Returns χ² of the fit, or
    ``inf`` when the normal equations are singular."""
    n, m = factors.shape
    normal, rhs = _normal_equations(factors, z, weights)
    if abs(np.linalg.det(normal)) < 1e-300:
        return math.inf
    covariance[:] = np.linalg.inv(normal)
    theta[:] = covariance @ rhs
    chi2 = 0.0
    for i in range(n):
        e0, e1 = z[i, 0], z[i, 1]
        for b in range(m):
            e0 -= factors[i, b] * theta[2 * b]
            e1 -= factors[i, b] * theta[2 * b + 1]
        chi2 += weights[i, 0, 0] * e0 * e0 + 2.0 * weights[i, 0, 1] * e0 * e1 + weights[i, 1, 1] * e1 * e1
    return chi2


@njit(cache=True, inline="always")
def _normal_equations(factors, z, weights):
    """The normal matrix ``(2m, 2m)`` and right-hand side ``(2m,)`` of ``_regression``'s fit over
    the rows of ``factors`` ``(n, m)``."""
    n, m = factors.shape
    normal = np.zeros((2 * m, 2 * m))
    rhs = np.zeros(2 * m)
    for i in range(n):
        for b in range(m):
            for p in range(2):
                rhs[2 * b + p] += factors[i, b] * (weights[i, p, 0] * z[i, 0] + weights[i, p, 1] * z[i, 1])
                for c in range(m):
                    for q in range(2):
                        normal[2 * b + p, 2 * c + q] += factors[i, b] * factors[i, c] * weights[i, p, q]
    return normal, rhs


@njit(cache=True, inline="always")
def _line_fit(times, z, weights, n, now_s):
    """χ² of the line ``z_i = a + v (t_i − now_s)`` over the first ``n`` centroids, with the
    inverse ``(4, 4)`` of its normal matrix and its right-hand side ``(4,)`` (``_kink_reduction``'s)."""
    factors = np.empty((n, 2))
    quadratic = 0.0
    for i in range(n):
        factors[i, 0], factors[i, 1] = 1.0, times[i] - now_s
        for p in range(2):
            quadratic += z[i, p] * (weights[i, p, 0] * z[i, 0] + weights[i, p, 1] * z[i, 1])
    normal, rhs = _normal_equations(factors, z, weights)
    inverse = np.linalg.inv(normal)
    return quadratic - rhs @ inverse @ rhs, inverse, rhs


@njit(cache=True, inline="always")
def _kink_reduction(times, z, weights, n, now_s, change_s, line_inverse, line_rhs):
    """How much a kink at ``change_s`` lowers the line's χ² (``_line_fit``'s): ``yᵀ S⁻¹ y`` with
    ``B`` ``(4, 2)`` and ``C`` ``(2, 2)`` the kink column's blocks of the normal matrix, ``S = C −
    Bᵀ A⁻¹ B`` and ``y = r_w − Bᵀ A⁻¹ r`` (the partitioned least squares)."""
    b = np.zeros((4, 2))
    c = np.zeros((2, 2))
    r_w = np.zeros(2)
    for i in range(n):
        r = change_s - times[i]
        if r <= 0.0:
            continue
        s = times[i] - now_s
        for p in range(2):
            r_w[p] += r * (weights[i, p, 0] * z[i, 0] + weights[i, p, 1] * z[i, 1])
            for q in range(2):
                b[p, q] += r * weights[i, p, q]
                b[p + 2, q] += r * s * weights[i, p, q]
                c[p, q] += r * r * weights[i, p, q]
    m = line_inverse @ b
    schur = c - b.T @ m
    y = r_w - m.T @ line_rhs
    det = schur[0, 0] * schur[1, 1] - schur[0, 1] * schur[1, 0]
    if det <= 0.0:
        return 0.0
    return (schur[1, 1] * y[0] * y[0] - (schur[0, 1] + schur[1, 0]) * y[0] * y[1] + schur[0, 0] * y[1] * y[1]) / det


@njit(cache=True, inline="always")
def _laser_travel(rows, count, n):
    """How far the laser moved (m) between the oldest and the newest of ``n`` buffered centroids."""
    window = rows.shape[0]
    first, last = rows[(count - n) % window], rows[(count - 1) % window]
    return math.hypot(last[7] - first[7], last[8] - first[8])


@njit(cache=True)
def _reshaping_ratio(rows, count, n, times, z, weights, start_s):
    """The start's log-likelihood ratio once both models may also move the centre in proportion
    to the segment's extent (``z_i = a + g (e_i − ē) [+ v · max(0, t_i − τ)]``, ``g ∈ R²``): a
    segment that shrinks as its faces turn away from a driving laser slides its centre with
    its extent, which a body that starts does not. Weighted least squares over the first ``n``
    centroids (each whitened by its weight), divided by the ramp's excess scatter as in
    ``ramp_onset``."""
    window = rows.shape[0]
    extent = np.empty(n)
    for i in range(n):
        extent[i] = rows[(count - n + i) % window, 6]
    extent -= extent.mean()
    design = np.zeros((2 * n, 6))
    target = np.empty(2 * n)
    for i in range(n):
        l00 = math.sqrt(weights[i, 0, 0])  # Lᵀ with L Lᵀ = W_i, the Cholesky factor of the weight
        l10 = weights[i, 1, 0] / l00
        l11 = math.sqrt(max(weights[i, 1, 1] - l10 * l10, 1e-300))
        s = max(0.0, times[i] - start_s)
        for column, factor in ((0, 1.0), (2, extent[i]), (4, s)):
            design[2 * i, column], design[2 * i, column + 1] = l00 * factor, l10 * factor
            design[2 * i + 1, column + 1] = l11 * factor
        target[2 * i] = l00 * z[i, 0] + l10 * z[i, 1]
        target[2 * i + 1] = l11 * z[i, 1]
    standing = _residual2(np.ascontiguousarray(design[:, :4]), target)
    ramp = _residual2(design, target)
    return _scaled_ratio(standing, ramp, 2 * n - 6)[0]


@njit(cache=True, inline="always")
def _scaled_ratio(simple_chi2, model_chi2, dof):
    """The log-likelihood ratio of a model over a simpler one it contains, ``½ (χ²_simple −
    χ²_model)``, divided by the model's excess scatter ``max(1, χ²_model / dof)`` (``dof`` its
    degrees of freedom), and that scale."""
    scale = max(1.0, model_chi2 / dof)
    return 0.5 * (simple_chi2 - model_chi2) / scale, scale


@njit(cache=True, inline="always")
def _residual2(design, target):
    """The squared norm of the least-squares residual of ``design @ x ≈ target``."""
    x = np.linalg.lstsq(design, target)[0]
    residual = target - design @ x
    return residual @ residual


@njit(cache=True, inline="always")
def _ramp_chi2(times, z, weights, n, start_s, sums):
    """χ² of ``ramp_fit``'s fit over the first ``n`` centroids, in closed form: the normal
    equations ``[[A, B], [B, C]] θ = (r_a, r_v)`` solved by the 2×2 Schur complement of ``A``.
    ``sums`` ``(6,)`` holds what no start changes (``_gather``'s): ``A`` (xx, xy, yy), ``r_a``
    and ``Σ zᵀ W z``."""
    b00 = b01 = b11 = c00 = c01 = c11 = v0 = v1 = 0.0
    for i in range(n):
        s = max(0.0, times[i] - start_s)
        if s == 0.0:
            continue
        w00, w01, w11 = weights[i, 0, 0], weights[i, 0, 1], weights[i, 1, 1]
        b00 += s * w00
        b01 += s * w01
        b11 += s * w11
        c00 += s * s * w00
        c01 += s * s * w01
        c11 += s * s * w11
        v0 += s * (w00 * z[i, 0] + w01 * z[i, 1])
        v1 += s * (w01 * z[i, 0] + w11 * z[i, 1])
    a00, a01, a11, r0, r1, quadratic = sums[0], sums[1], sums[2], sums[3], sums[4], sums[5]
    det_a = a00 * a11 - a01 * a01
    i00, i01, i11 = a11 / det_a, -a01 / det_a, a00 / det_a  # A⁻¹
    m00, m01 = i00 * b00 + i01 * b01, i00 * b01 + i01 * b11  # M = A⁻¹ B
    m10, m11 = i01 * b00 + i11 * b01, i01 * b01 + i11 * b11
    s00, s01, s11 = c00 - (b00 * m00 + b01 * m10), c01 - (b00 * m01 + b01 * m11), c11 - (b01 * m01 + b11 * m11)
    y0, y1 = v0 - (m00 * r0 + m10 * r1), v1 - (m01 * r0 + m11 * r1)  # r_v − Mᵀ r_a
    det_s = s00 * s11 - s01 * s01
    if det_s <= 0.0:
        return math.inf
    tv0, tv1 = (s11 * y0 - s01 * y1) / det_s, (s00 * y1 - s01 * y0) / det_s
    ta0 = i00 * r0 + i01 * r1 - (m00 * tv0 + m01 * tv1)
    ta1 = i01 * r0 + i11 * r1 - (m10 * tv0 + m11 * tv1)
    return quadratic - (r0 * ta0 + r1 * ta1 + v0 * tv0 + v1 * tv1)


@njit(cache=True, inline="always")
def _gather(rows, count, n, times, z, weights, sums):
    """The newest ``n`` of ``count`` buffered centroids ``rows`` into ``times``, ``z`` and
    ``weights`` (inverse covariances), oldest first; returns χ² of the standing model (the
    weighted mean's residuals), with the start-free sums of the normal equations in ``sums``
    (``_ramp_chi2``'s). Each centroid gets more variance on each axis for two causes
    of a centre sliding with the view, not with the body: ``(max(0, |Δ| − EXTENT_NOISE_M) / 2)²``
    for a segment whose extent differs from the window's mean by ``Δ`` (a face coming into
    view, an end hidden), and ``(VIEW_SLIDE · d)²`` for the laser's travel ``d`` (m) since the
    previous centroid."""
    window = rows.shape[0]
    mean_extent = 0.0
    for i in range(n):
        mean_extent += rows[(count - n + i) % window, 6] / n
    sums[:] = 0.0
    for i in range(n):
        row = rows[(count - n + i) % window]
        times[i], z[i, 0], z[i, 1] = row[0], row[1], row[2]
        reshaped = 0.25 * max(0.0, abs(row[6] - mean_extent) - EXTENT_NOISE_M) ** 2  # grew or shrank: its centre slid
        if i > 0:
            before = rows[(count - n + i - 1) % window]
            reshaped += (VIEW_SLIDE * math.hypot(row[7] - before[7], row[8] - before[8])) ** 2
        xx, yy = row[3] + reshaped, row[5] + reshaped
        det = xx * yy - row[4] * row[4]
        weights[i, 0, 0], weights[i, 0, 1] = yy / det, -row[4] / det
        weights[i, 1, 0], weights[i, 1, 1] = -row[4] / det, xx / det
        wz0 = weights[i, 0, 0] * z[i, 0] + weights[i, 0, 1] * z[i, 1]
        wz1 = weights[i, 1, 0] * z[i, 0] + weights[i, 1, 1] * z[i, 1]
        sums[0] += weights[i, 0, 0]
        sums[1] += weights[i, 0, 1]
        sums[2] += weights[i, 1, 1]
        sums[3] += wz0
        sums[4] += wz1
        sums[5] += z[i, 0] * wz0 + z[i, 1] * wz1
    det = sums[0] * sums[2] - sums[1] * sums[1]
    mean0 = (sums[2] * sums[3] - sums[1] * sums[4]) / det
    mean1 = (sums[0] * sums[4] - sums[1] * sums[3]) / det
    return sums[5] - (sums[3] * mean0 + sums[4] * mean1)


@njit(cache=True, inline="always")
def _set_from_fit(k, elapsed_s, theta, covariance, cv_x, cv_P):
    """Track ``k``'s constant-velocity state from a ramp fit ``theta`` ``(4,)`` (covariance
    ``(4, 4)``) whose start lies ``elapsed_s`` (s) back: position ``a + v·elapsed_s``, velocity
    ``v``, covariance ``J Σ Jᵀ`` with ``J = [[I, elapsed_s I], [0, I]]``."""
    jacobian = np.eye(4)
    jacobian[0, 2] = elapsed_s
    jacobian[1, 3] = elapsed_s
    cv_x[k, 0] = theta[0] + elapsed_s * theta[2]
    cv_x[k, 1] = theta[1] + elapsed_s * theta[3]
    cv_x[k, 2], cv_x[k, 3] = theta[2], theta[3]
    cv_P[k] = jacobian @ covariance @ jacobian.T
