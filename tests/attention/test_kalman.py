"""The Joseph update's compiled loops (``kalman._joseph_update``) against the BLAS form they replace."""

from fractions import Fraction

import numpy as np
import pytest
from numba import njit

from attentive_gym.attention.tracking.kalman import (
    cv_update,
    gaussian_log_likelihood_2d,
    robust_log_likelihood,
    static_update,
)


@njit(cache=False)
def _blas_joseph_update(x, P, z0, z1, R):
    """The previous implementation: the Joseph form with numba's ``@`` (BLAS dgemm)."""
    n = x.shape[0]
    s00, s01, s11 = P[0, 0] + R[0, 0], 0.5 * (P[0, 1] + P[1, 0]) + R[0, 1], P[1, 1] + R[1, 1]
    det = s00 * s11 - s01 * s01
    i00, i01, i11 = s11 / det, -s01 / det, s00 / det
    y0, y1 = z0 - x[0], z1 - x[1]
    K = np.empty((n, 2))
    for i in range(n):
        K[i, 0] = P[i, 0] * i00 + P[i, 1] * i01
        K[i, 1] = P[i, 0] * i01 + P[i, 1] * i11
    for i in range(n):
        x[i] += K[i, 0] * y0 + K[i, 1] * y1
    A = np.empty((n, n))
    for i in range(n):
        for j in range(n):
            A[i, j] = (1.0 if i == j else 0.0) - (K[i, 0] if j == 0 else (K[i, 1] if j == 1 else 0.0))
    new = (A @ P) @ A.T
    for i in range(n):
        for j in range(n):
            new[i, j] += K[i, 0] * (R[0, 0] * K[j, 0] + R[0, 1] * K[j, 1]) + K[i, 1] * (
                R[1, 0] * K[j, 0] + R[1, 1] * K[j, 1]
            )
    for i in range(n):
        for j in range(i, n):
            value = 0.5 * (new[i, j] + new[j, i])
            P[i, j] = value
            P[j, i] = value


def _fma(a, b, c):
    """``a * b + c`` rounded once (exact rational arithmetic, then one rounding to float64)."""
    return float(Fraction(a) * Fraction(b) + Fraction(c))


def _cases(rng, n, count):
    for _ in range(count):
        L = rng.normal(size=(n, n)) * 10 ** rng.uniform(-3, 0.5)
        P = L @ L.T + np.eye(n) * 1e-5
        Lr = rng.normal(size=(2, 2)) * 10 ** rng.uniform(-3, -0.5)
        R = Lr @ Lr.T + np.eye(2) * 1e-6
        yield rng.normal(size=n), P, float(rng.normal()), float(rng.normal()), R


def _blas_sums_by_fma_chains() -> bool:
    """Whether numba's ``@`` (this machine's BLAS) sums each entry as a chain of fused multiply-adds."""
    rng = np.random.default_rng(7)
    A, B = rng.normal(size=(4, 4)), rng.normal(size=(4, 4))
    product = njit(lambda a, b: a @ b)(A, B)
    chains = [[0.0] * 4 for _ in range(4)]
    for i in range(4):
        for j in range(4):
            for k in range(4):
                chains[i][j] = _fma(A[i, k], B[k, j], chains[i][j])
    return np.array_equal(product, np.array(chains))


@pytest.mark.parametrize("update, n", [(cv_update, 4), (static_update, 2)])
def test_joseph_update_equals_fused_multiply_add_chains_exactly(update, n):
    rng = np.random.default_rng(n)
    for x, P, z0, z1, R in _cases(rng, n, 40):
        x_new, P_new = x.copy(), P.copy()
        update(x_new, P_new, z0, z1, R)
        s00, s01, s11 = P[0, 0] + R[0, 0], 0.5 * (P[0, 1] + P[1, 0]) + R[0, 1], P[1, 1] + R[1, 1]
        det = s00 * s11 - s01 * s01
        i00, i01, i11 = s11 / det, -s01 / det, s00 / det
        K = [(P[i, 0] * i00 + P[i, 1] * i01, P[i, 0] * i01 + P[i, 1] * i11) for i in range(n)]
        A = [[(1.0 if i == k else 0.0) - (K[i][k] if k < 2 else 0.0) for k in range(n)] for i in range(n)]
        AP = [[0.0] * n for _ in range(n)]
        for i in range(n):
            for j in range(n):
                for k in range(n):
                    AP[i][j] = _fma(A[i][k], P[k, j], AP[i][j])
        new = [[0.0] * n for _ in range(n)]
        for i in range(n):
            for j in range(n):
                for k in range(n):
                    new[i][j] = _fma(AP[i][k], A[j][k], new[i][j])
                new[i][j] += K[i][0] * (R[0, 0] * K[j][0] + R[0, 1] * K[j][1]) + K[i][1] * (
                    R[1, 0] * K[j][0] + R[1, 1] * K[j][1]
                )
        expected = np.array([[0.5 * (new[i][j] + new[j][i]) for j in range(n)] for i in range(n)])
        assert np.array_equal(P_new, expected)
        assert np.array_equal(x_new, x + np.array([K[i][0] * (z0 - x[0]) + K[i][1] * (z1 - x[1]) for i in range(n)]))


@pytest.mark.parametrize("update, n", [(cv_update, 4), (static_update, 2)])
def test_joseph_update_equals_the_blas_form(update, n):
    exact = _blas_sums_by_fma_chains()
    rng = np.random.default_rng(10 + n)
    for x, P, z0, z1, R in _cases(rng, n, 500):
        x_new, P_new, x_old, P_old = x.copy(), P.copy(), x.copy(), P.copy()
        update(x_new, P_new, z0, z1, R)
        _blas_joseph_update(x_old, P_old, z0, z1, R)
        assert np.array_equal(x_new, x_old)
        if exact:  # this machine's BLAS sums as the loops do: the same floats
            assert np.array_equal(P_new, P_old)
        else:
            np.testing.assert_allclose(P_new, P_old, rtol=1e-12, atol=1e-15 * np.abs(P_old).max())


def _mixture(y, S, share, sigmas):
    """log((1 − share) N(y; 0, S) + share N(y; 0, sigmas² S)), summed directly."""

    def density(cov):
        return np.exp(-0.5 * y @ np.linalg.solve(cov, y)) / (2 * np.pi * np.sqrt(np.linalg.det(cov)))

    return np.log((1 - share) * density(S) + share * density(sigmas**2 * S))


@pytest.mark.parametrize("y", [(0.01, -0.02), (0.3, 0.1), (2.0, -1.5)])
def test_the_robust_likelihood_is_the_mixture_of_the_filter_s_gaussian_and_a_wider_one(y):
    y, S = np.array(y), np.array([[0.05, 0.01], [0.01, 0.03]])
    gaussian = gaussian_log_likelihood_2d(y[0], y[1], S[0, 0], S[0, 1], S[1, 1])
    d2 = y @ np.linalg.solve(S, y)
    assert robust_log_likelihood(gaussian, d2, 0.2, 3.0) == pytest.approx(_mixture(y, S, 0.2, 3.0), rel=1e-9)


def test_a_jump_weighs_less_on_the_motion_test_with_outliers():
    # a static track's prediction is tight, a constant-velocity track's wider: a centroid jump
    # of 0.5 m (a segment that merged) favours "moving" by many nats with Gaussians alone
    static_S, moving_S = np.diag([0.01, 0.01]), np.diag([0.06, 0.06])

    def ratio(y, share):
        """log L(moving) − log L(static) of the innovation ``y``, with ``share`` outliers (0: none)."""
        logs = []
        for S in (moving_S, static_S):
            gaussian = gaussian_log_likelihood_2d(y[0], y[1], S[0, 0], S[0, 1], S[1, 1])
            logs.append(
                gaussian if share == 0 else robust_log_likelihood(gaussian, y @ np.linalg.solve(S, y), share, 3.0)
            )
        return logs[0] - logs[1]

    jump, small = np.array([0.5, 0.0]), np.array([0.02, 0.01])
    assert ratio(jump, 0.0) > 8.0
    assert 0.0 < ratio(jump, 0.2) < 0.5 * ratio(jump, 0.0)
    # a small innovation: both filters lose about the same log(1 − share), their ratio stays
    assert ratio(small, 0.2) == pytest.approx(ratio(small, 0.0), abs=0.05)
