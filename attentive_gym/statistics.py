"""Statistics across training seeds and episodes, as the RL field reports them (Agarwal et al., 2021).

Used by the agents' summaries and by the perception metrics, so it stands outside the
package's layers (it imports numpy only).

Few seeds make normal-approximation intervals misleading (a success rate's t-interval can
reach below 0 and above 1). Here, following ``rliable``:

- ``iqm``: the interquartile mean (the mean of the middle 50 % of the values), robust to
  an outlying seed and less noisy than the median.
- ``bootstrap_ci``: a percentile bootstrap confidence interval of a statistic, the seeds
  resampled with replacement (stratified by variant: each variant is resampled on its
  own), clipped to the metric's range.
- ``ratio_ci``: a rate pooled over clusters (the steps of episodes: on-target steps over
  steps in view) with a bootstrap interval that resamples whole clusters, since steps of
  one episode are not independent; ``pooled_median_ci``: the same for the median of values
  pooled over clusters (the latencies of every start of every episode).
- ``probability_of_improvement``: P(X > Y) + ½ P(X = Y) for a run X of one variant and a
  run Y of another, with its bootstrap interval (both samples resampled).
- ``performance_profile``: the share of runs scoring above each threshold τ (the run-score
  distribution), with pointwise bootstrap intervals.

Every function is deterministic: the resampling uses a fixed seed. One value gives no
interval (NaN bounds): one seed says nothing about the spread across seeds.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Sequence
from typing import Any

import numpy as np

from attentive_gym._checks import check_int

__all__ = [
    "BOOTSTRAP_REPS",
    "iqm",
    "mean",
    "bootstrap_ci",
    "ratio_ci",
    "pooled_median_ci",
    "probability_of_improvement",
    "performance_profile",
]

#: Bootstrap resamples per interval.
BOOTSTRAP_REPS = 2000
_SEED = 20210829  # fixed, so that summaries are reproducible


def _values(values: Iterable[float]) -> np.ndarray:
    """The finite-or-NaN values as a float array, NaNs dropped; ±inf refused."""
    x = np.asarray(list(values), dtype=float).reshape(-1)
    if np.isinf(x).any():
        raise ValueError(f"values must be finite numbers (NaN = missing), got {x.tolist()}")
    return x[~np.isnan(x)]


def mean(x: np.ndarray, axis: int = -1) -> np.ndarray:
    """The arithmetic mean along ``axis``."""
    return np.mean(x, axis=axis)


def iqm(x: np.ndarray, axis: int = -1) -> np.ndarray:
    """The interquartile mean along ``axis``: sort, drop ⌊n/4⌋ values at each end, average
    the rest (``scipy.stats.trim_mean(x, 0.25)``)."""
    x = np.sort(np.asarray(x, dtype=float), axis=axis)
    n = x.shape[axis]
    cut = int(0.25 * n)
    return np.mean(np.take(x, np.arange(cut, n - cut), axis=axis), axis=axis)


def bootstrap_ci(
    values: Iterable[float],
    statistic: Callable[[np.ndarray, int], np.ndarray] = mean,
    bounds: tuple[float, float] = (-math.inf, math.inf),
    confidence: float = 0.95,
    reps: int = BOOTSTRAP_REPS,
) -> tuple[float, float, float]:
    """(point estimate, low, high) of ``statistic`` over ``values`` (one per seed).

    Args:
        values: one value per seed; NaNs are dropped.
        statistic: ``f(x, axis)`` reducing along ``axis`` (``mean``, ``iqm``).
        bounds: the metric's range (e.g. (0, 1) for a success rate); the interval is
            clipped to it.
        confidence: the interval's coverage, in (0, 1).
        reps: bootstrap resamples.

    Returns:
        NaNs without values; NaN bounds with one value.

    Raises:
        ValueError: ``confidence`` outside (0, 1), ``reps`` < 1, ``bounds`` not ordered
            (low <= high), a value outside ``bounds``, or an infinite value.
    """
    _check_bootstrap(confidence, reps)
    low_bound, high_bound = bounds
    if not low_bound <= high_bound:
        raise ValueError(f"bounds must be (low, high) with low <= high, got {bounds!r}")
    x = _values(values)
    outside = x[(x < low_bound) | (x > high_bound)]
    if outside.size:
        raise ValueError(f"values must lie within the metric's range {bounds}, got {outside.tolist()}")
    if x.size == 0:
        return math.nan, math.nan, math.nan
    point = float(statistic(x, -1))
    if x.size == 1:
        return point, math.nan, math.nan
    rng = np.random.default_rng(_SEED)
    resampled = statistic(x[rng.integers(0, x.size, size=(reps, x.size))], -1)
    return (point, *_percentile_interval(resampled, point, confidence, bounds))


def ratio_ci(
    hits: Sequence[float], totals: Sequence[float], confidence: float = 0.95, reps: int = BOOTSTRAP_REPS
) -> tuple[float, float, float]:
    """(Σ hits / Σ totals, low, high): a rate pooled over clusters, with a percentile bootstrap
    interval that resamples the clusters (cluster ``i`` scores ``hits[i]`` of ``totals[i]``
    events; an episode's on-target steps of its steps in view), clipped to [0, 1].

    Clusters with no events carry no information about the rate and are left out. NaNs
    without events; NaN bounds with one cluster.

    Raises:
        ValueError: ``hits`` and ``totals`` of different lengths, a negative or non-finite
            count, hits above their total, or ``confidence``/``reps`` as ``bootstrap_ci``.
    """
    _check_bootstrap(confidence, reps)
    on, n = np.asarray(hits, dtype=float).reshape(-1), np.asarray(totals, dtype=float).reshape(-1)
    if on.shape != n.shape:
        raise ValueError(f"hits and totals must be one count per cluster each, got {on.size} and {n.size}")
    if not (np.isfinite(on).all() and np.isfinite(n).all()) or (on < 0).any() or (on > n).any():
        raise ValueError(
            f"hits and totals must be finite counts with 0 <= hits <= totals, got {on.tolist()} of {n.tolist()}"
        )
    on, n = on[n > 0], n[n > 0]
    if n.size == 0:
        return math.nan, math.nan, math.nan
    point = float(on.sum() / n.sum())
    if n.size == 1:
        return point, math.nan, math.nan
    rng = np.random.default_rng(_SEED)
    picks = rng.integers(0, n.size, size=(reps, n.size))
    resampled = on[picks].sum(axis=1) / n[picks].sum(axis=1)
    return (point, *_percentile_interval(resampled, point, confidence, (0.0, 1.0)))


def pooled_median_ci(
    clusters: Sequence[Sequence[float]], confidence: float = 0.95, reps: int = BOOTSTRAP_REPS
) -> tuple[float, float, float]:
    """(median, low, high): the median (``np.median``) of the values of every cluster pooled,
    with a percentile bootstrap interval that resamples the clusters (each cluster's values go
    in or out together). Values may be +inf (an event that never happened: a start never
    judged), and so may the median and the bounds; the bounds are resampled medians
    themselves (``inverted_cdf``), never a mean of one and inf.

    Clusters without values are left out. NaNs without values; NaN bounds with one cluster.

    Raises:
        ValueError: a NaN or −inf value, or ``confidence``/``reps`` as ``bootstrap_ci``.
    """
    _check_bootstrap(confidence, reps)
    groups = [np.asarray(cluster, dtype=float).reshape(-1) for cluster in clusters]
    bad = [value for group in groups for value in group if math.isnan(value) or value == -math.inf]
    if bad:
        raise ValueError(f"values must be numbers or +inf (never happened), got {bad}")
    groups = [group for group in groups if group.size]
    if not groups:
        return math.nan, math.nan, math.nan
    point = float(np.median(np.concatenate(groups)))
    if len(groups) == 1:
        return point, math.nan, math.nan
    rng = np.random.default_rng(_SEED)
    picks = rng.integers(0, len(groups), size=(reps, len(groups)))
    medians = np.array([np.median(np.concatenate([groups[i] for i in pick])) for pick in picks])
    tail = 50.0 * (1.0 - confidence)
    low, high = np.percentile(medians, [tail, 100.0 - tail], method="inverted_cdf")
    return point, float(min(low, point)), float(max(high, point))


def _check_bootstrap(confidence: float, reps: int) -> None:
    """``ValueError`` unless ``confidence`` is in (0, 1) and ``reps`` an int ≥ 1."""
    if not 0.0 < confidence < 1.0:
        raise ValueError(f"confidence must be in (0, 1), got {confidence!r}")
    check_int("reps", reps, 1)


def _percentile_interval(
    resampled: np.ndarray, point: float | np.ndarray, confidence: float, bounds: tuple[float, float]
) -> tuple[Any, Any]:
    """The central ``confidence`` interval of the bootstrap distribution ``resampled`` (the
    resamples along its first axis), clipped to ``bounds`` and widened to hold ``point``; one
    interval per entry of the other axes (floats for a 1-D ``resampled``)."""
    tail = 50.0 * (1.0 - confidence)
    low, high = np.clip(np.percentile(resampled, [tail, 100.0 - tail], axis=0), *bounds)
    low, high = np.minimum(low, point), np.maximum(high, point)
    return (float(low), float(high)) if np.ndim(low) == 0 else (low, high)


def _improvement(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """P(X > Y) + ½ P(X = Y) over all pairs, along the last axis of ``x`` (…, n) and ``y`` (…, m)."""
    greater = (x[..., :, None] > y[..., None, :]).mean(axis=(-2, -1))
    equal = (x[..., :, None] == y[..., None, :]).mean(axis=(-2, -1))
    return greater + 0.5 * equal


def probability_of_improvement(
    x_values: Sequence[float],
    y_values: Sequence[float],
    confidence: float = 0.95,
    reps: int = BOOTSTRAP_REPS,
) -> tuple[float, float, float]:
    """(P(X > Y), low, high): the probability that a seed of X scores above a seed of Y
    (ties count half), with a bootstrap interval resampling both; in [0, 1].

    NaN bounds when either side has one value; NaNs when either has none.
    """
    _check_bootstrap(confidence, reps)
    x, y = _values(x_values), _values(y_values)
    if x.size == 0 or y.size == 0:
        return math.nan, math.nan, math.nan
    point = float(_improvement(x, y))
    if x.size == 1 or y.size == 1:
        return point, math.nan, math.nan
    rng = np.random.default_rng(_SEED)
    resampled = _improvement(
        x[rng.integers(0, x.size, size=(reps, x.size))], y[rng.integers(0, y.size, size=(reps, y.size))]
    )
    return (point, *_percentile_interval(resampled, point, confidence, (0.0, 1.0)))


def performance_profile(
    values: Iterable[float], thresholds: Sequence[float], confidence: float = 0.95, reps: int = BOOTSTRAP_REPS
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The share of runs whose score exceeds each threshold τ, with pointwise bootstrap
    intervals (the runs resampled): ``rliable``'s run-score distribution. A curve lying above
    another at every τ dominates it stochastically.

    Args:
        values: one score per run (seed); NaNs are dropped.
        thresholds: the τ values, shape (T,).
        confidence: the intervals' coverage, in (0, 1).
        reps: bootstrap resamples.

    Returns:
        ``(share, low, high)``, each of shape (T,) and in [0, 1]; NaN bounds with one value,
        NaN everywhere with none.
    """
    _check_bootstrap(confidence, reps)
    x, taus = _values(values), np.asarray(thresholds, dtype=float).reshape(-1)
    if np.isnan(taus).any():
        raise ValueError(f"thresholds must be numbers, got {taus.tolist()}")
    nan = np.full(taus.shape, math.nan)
    if x.size == 0:
        return nan, nan.copy(), nan.copy()
    share = (x[:, None] > taus[None, :]).mean(axis=0)
    if x.size == 1:
        return share, nan, nan.copy()
    rng = np.random.default_rng(_SEED)
    resampled = x[rng.integers(0, x.size, size=(reps, x.size))]  # (reps, n)
    shares = (resampled[:, :, None] > taus[None, None, :]).mean(axis=1)  # (reps, T)
    return (share, *_percentile_interval(shares, share, confidence, (0.0, 1.0)))
