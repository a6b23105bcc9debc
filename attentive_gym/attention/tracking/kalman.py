"""Small Kalman filters of the tracker (docs/model.md §10): compiled, allocation-free kernels.

- ``cv_predict`` / ``cv_update``: the 2-D constant-velocity filter of one track, state
  ``(px, py, vx, vy)`` in metres and m/s, covariance ``(4, 4)``.
- ``static_predict`` / ``static_update``: the filter of the same track under the static
  hypothesis, state ``(px, py)`` (m), covariance ``(2, 2)``; the two filters' likelihoods
  decide how probably the track moves (``motion_probability``).
- ``rate_predict`` / ``rate_update``: the 1-D range/range-rate filter of one sonar, state
  ``(r, ṙ)`` (m, m/s), covariance ``(2, 2)``.
- ``gaussian_log_likelihood_2d``: ``log N(y; 0, S)`` of a 2-D innovation;
  ``robust_log_likelihood``: the likelihood under a Gaussian with a share of outliers.

Process noise is the continuous white-noise acceleration model: spectral density ``q``
(m²/s³) per axis gives ``Q = q [[dt³/3, dt²/2], [dt²/2, dt]]`` over ``dt`` seconds.
Updates use the Joseph form, so covariances stay symmetric and positive definite.
Every kernel works in place on the arrays it is given.

Small kernels that the model's step calls in its loops are compiled ``inline="always"``:
inlined into their caller, the views of per-track rows (or the arrays) they take need no
reference counting, two atomic operations per array and call otherwise.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from attentive_gym.attention._numerics import fma

__all__ = [
    "cv_predict",
    "cv_update",
    "static_predict",
    "static_update",
    "rate_predict",
    "rate_update",
    "gaussian_log_likelihood_2d",
    "robust_log_likelihood",
    "motion_probability",
]

_LOG_2PI = math.log(2.0 * math.pi)


@njit(cache=True, inline="always")
def cv_predict(x, P, dt_s, q):
    """Predict a constant-velocity state ``x`` ``(4,)`` and covariance ``P`` ``(4, 4)``
    over ``dt_s`` seconds with acceleration spectral density ``q`` (m²/s³), in place."""
    dt = dt_s
    x[0] += dt * x[2]
    x[1] += dt * x[3]
    # P <- F P F^T with F = [[I, dt I], [0, I]]: rows then columns
    for j in range(4):
        P[0, j] += dt * P[2, j]
        P[1, j] += dt * P[3, j]
    for i in range(4):
        P[i, 0] += dt * P[i, 2]
        P[i, 1] += dt * P[i, 3]
    q11, q12, q22 = q * dt * dt * dt / 3.0, q * dt * dt / 2.0, q * dt
    for a in range(2):
        P[a, a] += q11
        P[a, a + 2] += q12
        P[a + 2, a] += q12
        P[a + 2, a + 2] += q22


@njit(cache=True)
def _inverse_2x2(s00, s01, s11):
    """Inverse of the symmetric 2 × 2 matrix ``[[s00, s01], [s01, s11]]`` and its determinant."""
    det = s00 * s11 - s01 * s01
    return s11 / det, -s01 / det, s00 / det, det


@njit(cache=True)
def gaussian_log_likelihood_2d(y0, y1, s00, s01, s11):
    """``log N(y; 0, S)`` for the innovation ``y = (y0, y1)`` and its covariance ``S`` (symmetric)."""
    i00, i01, i11, det = _inverse_2x2(s00, s01, s11)
    d2 = y0 * (i00 * y0 + i01 * y1) + y1 * (i01 * y0 + i11 * y1)
    return -0.5 * (d2 + math.log(det)) - _LOG_2PI


@njit(cache=True, inline="always")
def _joseph_update(x, P, z0, z1, R):
    """Update a state whose first two entries are the measured position, in place.

    ``x`` ``(n,)``, ``P`` ``(n, n)``, measurement ``z`` (m) with covariance ``R`` ``(2, 2)``.
    Returns ``log N(innovation; 0, S)``.

    The Joseph form's two matrix products ``(A P) Aᵀ`` (``A = I − K H``, never stored) are
    summed as numba's ``@`` has OpenBLAS's dgemm sum them: each entry a chain of fused
    multiply-adds over k from 0 (``_numerics.fma``), so the floats are those of the
    BLAS form; one scratch allocation (K and A P), no BLAS call.
    """
    n = x.shape[0]
    s00, s01, s11 = P[0, 0] + R[0, 0], 0.5 * (P[0, 1] + P[1, 0]) + R[0, 1], P[1, 1] + R[1, 1]
    y0, y1 = z0 - x[0], z1 - x[1]
    log_likelihood = gaussian_log_likelihood_2d(y0, y1, s00, s01, s11)
    i00, i01, i11, _ = _inverse_2x2(s00, s01, s11)
    scratch = np.empty((n, n + 2))  # columns 0, 1: the gain K; then A P
    for i in range(n):
        scratch[i, 0] = P[i, 0] * i00 + P[i, 1] * i01
        scratch[i, 1] = P[i, 0] * i01 + P[i, 1] * i11
    for i in range(n):
        x[i] += scratch[i, 0] * y0 + scratch[i, 1] * y1
    # Joseph form: P <- (I - K H) P (I - K H)^T + K R K^T, H = [I 0]
    for i in range(n):
        for j in range(n):
            total = 0.0
            for k in range(n):
                total = fma(_gain_complement(scratch, i, k), P[k, j], total)
            scratch[i, 2 + j] = total
    for i in range(n):
        for j in range(i, n):
            upper = _joseph_entry(scratch, R, i, j)
            value = 0.5 * (upper + (upper if i == j else _joseph_entry(scratch, R, j, i)))
            P[i, j] = value
            P[j, i] = value
    return log_likelihood


@njit(cache=True, inline="always")
def _gain_complement(scratch, i, k):
    """Entry ``(i, k)`` of ``A = I − K H`` (``H = [I 0]``), K in ``scratch[:, :2]``."""
    return (1.0 if i == k else 0.0) - (scratch[i, 0] if k == 0 else (scratch[i, 1] if k == 1 else 0.0))


@njit(cache=True, inline="always")
def _joseph_entry(scratch, R, i, j):
    """Entry ``(i, j)`` of ``(A P) Aᵀ + K R Kᵀ``, ``A P`` in ``scratch[:, 2:]`` and K in ``scratch[:, :2]``."""
    total = 0.0
    for k in range(scratch.shape[0]):
        total = fma(scratch[i, 2 + k], _gain_complement(scratch, j, k), total)
    k_i0, k_i1, k_j0, k_j1 = scratch[i, 0], scratch[i, 1], scratch[j, 0], scratch[j, 1]
    return total + (k_i0 * (R[0, 0] * k_j0 + R[0, 1] * k_j1) + k_i1 * (R[1, 0] * k_j0 + R[1, 1] * k_j1))


@njit(cache=True, inline="always")
def cv_update(x, P, z0, z1, R):
    """Update a constant-velocity track with a position measurement ``z`` (m), covariance
    ``R`` ``(2, 2)`` (m²), in place; returns the innovation's log-likelihood."""
    return _joseph_update(x, P, z0, z1, R)


@njit(cache=True, inline="always")
def static_predict(x, P, dt_s, drift_m2ps):
    """Predict a static track: the position stays, its variance grows by ``drift · dt``
    (``drift_m2ps`` in m²/s: how fast the visible surface may wander), in place."""
    P[0, 0] += drift_m2ps * dt_s
    P[1, 1] += drift_m2ps * dt_s


@njit(cache=True, inline="always")
def static_update(x, P, z0, z1, R):
    """Update a static track's position ``x`` ``(2,)`` with ``z`` (m), covariance ``R``,
    in place; returns the innovation's log-likelihood."""
    return _joseph_update(x, P, z0, z1, R)


@njit(cache=True, inline="always")
def robust_log_likelihood(log_likelihood, d2, outlier_share, outlier_sigmas):
    """The log-likelihood of a 2-D innovation under a mixture: ``1 − outlier_share`` of the
    filter's Gaussian (``log_likelihood``, its squared Mahalanobis distance ``d2``) and
    ``outlier_share`` of one with ``outlier_sigmas`` times its σ (covariance × k², so its
    log-density is ``log_likelihood + ½ d2 (1 − 1/k²) − 2 log k`` in 2-D). A small
    innovation keeps about ``log(1 − share)`` of the Gaussian's; a large one is capped by the
    wide component's slower fall."""
    k = outlier_sigmas
    wide = log_likelihood + 0.5 * d2 * (1.0 - 1.0 / (k * k)) - 2.0 * math.log(k)
    narrow_part, wide_part = math.log(1.0 - outlier_share) + log_likelihood, math.log(outlier_share) + wide
    top = max(narrow_part, wide_part)
    return top + math.log(math.exp(narrow_part - top) + math.exp(wide_part - top))


@njit(cache=True)
def motion_probability(p_moving, log_l_moving, log_l_static, switch_probability, floor):
    """Posterior probability that a track moves, after one scan.

    A two-model Bayes filter (an interacting-multiple-model filter without mixing): the
    prior ``p_moving`` is first blurred by ``switch_probability`` per scan (a body may start
    or stop), then weighed by the likelihoods of the scan's measurement under the
    constant-velocity and the static filters. The result is kept within
    ``[floor, 1 − floor]`` so that either hypothesis can win back.
    """
    prior = p_moving * (1.0 - switch_probability) + (1.0 - p_moving) * switch_probability
    top = max(log_l_moving, log_l_static)
    moving = prior * math.exp(log_l_moving - top)
    static = (1.0 - prior) * math.exp(log_l_static - top)
    posterior = moving / (moving + static)
    return min(max(posterior, floor), 1.0 - floor)


@njit(cache=True, inline="always")
def rate_predict(x, P, dt_s, q):
    """Predict a sonar's ``(r, ṙ)`` state and covariance over ``dt_s`` (s), in place."""
    dt = dt_s
    x[0] += dt * x[1]
    P[0, 0] += dt * (P[1, 0] + P[0, 1]) + dt * dt * P[1, 1] + q * dt * dt * dt / 3.0
    P[0, 1] += dt * P[1, 1] + q * dt * dt / 2.0
    P[1, 0] = P[0, 1]
    P[1, 1] += q * dt


@njit(cache=True, inline="always")
def rate_update(x, P, z, r_var):
    """Update a sonar's ``(r, ṙ)`` state with a range ``z`` (m) of variance ``r_var`` (m²), in place."""
    s = P[0, 0] + r_var
    k0, k1 = P[0, 0] / s, P[1, 0] / s
    y = z - x[0]
    x[0] += k0 * y
    x[1] += k1 * y
    p00, p01, p11 = P[0, 0], P[0, 1], P[1, 1]
    # Joseph form with H = [1 0]
    P[0, 0] = (1.0 - k0) ** 2 * p00 + k0 * k0 * r_var
    P[0, 1] = (1.0 - k0) * (p01 - k1 * p00) + k0 * k1 * r_var
    P[1, 0] = P[0, 1]
    P[1, 1] = p11 - 2.0 * k1 * p01 + k1 * k1 * p00 + k1 * k1 * r_var
