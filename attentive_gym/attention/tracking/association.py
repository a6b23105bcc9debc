"""Optimal assignment of segments to tracks (docs/model.md §10): a compiled Hungarian method.

- ``min_cost_assignment``: the assignment of rows to columns of a rectangular cost
  matrix with the least total cost (the shortest-augmenting-path Hungarian method,
  O(n² m)), the same optimum as ``scipy.optimize.linear_sum_assignment``.
- ``gated_assignment``: tracks × segments by global nearest neighbour: the most pairs
  inside the gate, then the least total generalised distance (Mahalanobis distance plus
  the log-determinant of the innovation covariance).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["min_cost_assignment", "gated_assignment"]

#: The cost of a pair outside the gate: larger than any sum of costs inside it, so the
#: assignment takes as many pairs inside the gate as it can.
_OUTSIDE_GATE = 1e9


@njit(cache=True)
def _assign_rows(cost, n_rows, n_cols, row_of_col):
    """Hungarian method for ``n_rows <= n_cols``; writes the row assigned to each column
    (−1 for none) into ``row_of_col`` ``(n_cols,)``."""
    inf = np.inf
    u = np.zeros(n_rows + 1)
    v = np.zeros(n_cols + 1)
    p = np.zeros(n_cols + 1, np.int64)  # p[j]: 1-based row matched to column j; p[0] is the row being added
    way = np.zeros(n_cols + 1, np.int64)
    for i in range(1, n_rows + 1):
        p[0] = i
        j0 = 0
        minv = np.full(n_cols + 1, inf)
        used = np.zeros(n_cols + 1, np.bool_)
        while True:
            used[j0] = True
            i0 = p[j0]
            delta = inf
            j1 = 0
            for j in range(1, n_cols + 1):
                if not used[j]:
                    current = cost[i0 - 1, j - 1] - u[i0] - v[j]
                    if current < minv[j]:
                        minv[j] = current
                        way[j] = j0
                    if minv[j] < delta:
                        delta = minv[j]
                        j1 = j
            for j in range(n_cols + 1):
                if used[j]:
                    u[p[j]] += delta
                    v[j] -= delta
                else:
                    minv[j] -= delta
            j0 = j1
            if p[j0] == 0:
                break
        while True:
            j1 = way[j0]
            p[j0] = p[j1]
            j0 = j1
            if j0 == 0:
                break
    for j in range(n_cols):
        row_of_col[j] = p[j + 1] - 1


@njit(cache=True)
def min_cost_assignment(cost, row_to_col):
    """The least-cost assignment of the rows of ``cost`` ``(n, m)`` (finite) to its columns.

    Writes into ``row_to_col`` ``(n,)`` the column of each row, −1 for the rows left
    over when ``n > m``. Every column is used when ``n >= m``, every row when ``n <= m``.
    """
    n_rows, n_cols = cost.shape
    row_to_col[:] = -1
    if n_rows == 0 or n_cols == 0:
        return
    if n_rows <= n_cols:
        row_of_col = np.empty(n_cols, np.int64)
        _assign_rows(cost, n_rows, n_cols, row_of_col)
        for j in range(n_cols):
            if row_of_col[j] >= 0:
                row_to_col[row_of_col[j]] = j
    else:
        col_of_row = np.empty(n_rows, np.int64)
        _assign_rows(cost.T.copy(), n_cols, n_rows, col_of_row)
        for i in range(n_rows):
            row_to_col[i] = col_of_row[i]


@njit(cache=True)
def gated_assignment(distance2, log_det, gate, row_to_col):
    """Global-nearest-neighbour assignment of tracks (rows) to measurements (columns).

    Pairs whose squared Mahalanobis distance ``distance2`` ``(n, m)`` is below ``gate``
    may match. Among the assignments, the one that matches the most such pairs and, of
    those, has the least total ``distance2 + log_det`` (``log_det`` ``(n, m)``: log of the
    innovation covariance's determinant; with it, a track with a vague prediction does
    not take a measurement from one that predicts it well) wins. ``row_to_col`` ``(n,)``
    gets each row's column, −1 for none.
    """
    n_rows, n_cols = distance2.shape
    cost = np.empty((n_rows, n_cols))
    for i in range(n_rows):
        for j in range(n_cols):
            pair = distance2[i, j] + log_det[i, j]
            # a pair outside the gate, or of a covariance beyond float range, cannot match
            # (an infinite cost would also keep the Hungarian method from ending)
            cost[i, j] = pair if distance2[i, j] < gate and math.isfinite(pair) else _OUTSIDE_GATE
    min_cost_assignment(cost, row_to_col)
    for i in range(n_rows):
        j = row_to_col[i]
        if j >= 0 and cost[i, j] >= _OUTSIDE_GATE:
            row_to_col[i] = -1
