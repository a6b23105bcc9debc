"""Feature maps F1–F6 (docs/model.md §4, §5) as pure functions over arrays.

Bottom-up (values in [0, 1]):

- ``motion_map`` (F1): speed contrast ``|s_n − mean(s)| / MAX_SPEED``.
- ``rarity_map`` (F2): rarity of each element's direction label, ``(N/count − 1)/(N − 1)``.
- ``distance_map`` (F3): range contrast ``|o_n − mean(o)| / max_range``.
- ``label_columns``, ``majority_labels``: counting direction labels, per region.
- ``Spaces``: several observation spaces side by side in one channel vector (the 8
  front sonars then the 180 laser beams), so that F2 and F3 of both spaces cost one
  pass; each space keeps its own mean, count and N.

Top-down (values in [0, 1], plus a boolean "fulfilled" mask):

- ``goal_table``: the graded goal table of F4/F6 for one value (the definition).
- ``goal_knots``, ``goal_map`` (F4 over speed in m/s, F6 over distance in m): the same
  table over arrays (it is piecewise linear, so it is interpolated between its knots).
- ``direction_goal_map`` (F5): 1 where the direction label equals the wanted one.

Functions work on the last axis. ``motion_map``, ``distance_map`` (without ``spaces``),
``goal_map`` and ``direction_goal_map`` accept leading batch dimensions; the counting
ones take one reading ``(N,)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from attentive_gym.attention.goals import Feature, Goal, Relation

__all__ = [
    "LABEL_PREFERENCE",
    "Spaces",
    "motion_map",
    "label_columns",
    "rarity_map",
    "majority_labels",
    "distance_map",
    "goal_table",
    "goal_knots",
    "goal_map",
    "direction_goal_map",
]

#: Direction labels in the order that breaks ties of ``majority_labels``: a moving label
#: beats "static", and "towards" (approaching, the more urgent for a robot) beats "away".
LABEL_PREFERENCE = np.array([-1.0, 1.0, 0.0])
#: ``_LABEL_COLUMN[d]`` is the column of label d in ``LABEL_PREFERENCE`` (d = −1 indexes the
#: last entry): 0 → 2, +1 → 1, −1 → 0.
_LABEL_COLUMN = np.array([2, 1, 0])
_N_LABELS = len(LABEL_PREFERENCE)


@dataclass(frozen=True, eq=False)
class Spaces:
    """Observation spaces laid side by side in one channel vector (precomputed constants).

    Build with ``Spaces.make((8, 180))``: channels 0..7 are space 0, 8..187 space 1.

    Attributes:
        sizes: N of each space.
        starts: ``(S,)`` first channel of each space.
        ids: ``(N_total,)`` space of each channel.
        label_bins: ``(N_total,)`` first label-count bin of each channel's space (3 per space).
        rarity_scale, rarity_shift: ``(N_total,)`` ``N/(N − 1)`` and ``1/(N − 1)`` of each
            channel's space, so that the normalised rarity is ``scale/count − shift``.
    """

    sizes: tuple[int, ...]
    starts: np.ndarray
    ids: np.ndarray
    label_bins: np.ndarray
    rarity_scale: np.ndarray
    rarity_shift: np.ndarray

    @classmethod
    def make(cls, sizes: tuple[int, ...]) -> Spaces:
        """Spaces of the given sizes (each >= 2), in order."""
        if any(n < 2 for n in sizes):
            raise ValueError(f"every observation space needs >= 2 elements, got sizes {sizes}")
        starts = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.intp)
        ids = np.repeat(np.arange(len(sizes)), sizes)
        n = np.asarray(sizes, dtype=float)[ids]
        return cls(tuple(sizes), starts, ids, _N_LABELS * ids, n / (n - 1.0), 1.0 / (n - 1.0))

    def means(self, values: np.ndarray) -> np.ndarray:
        """``(N_total,)`` the mean of each channel's space."""
        return (np.add.reduceat(values, self.starts) / np.asarray(self.sizes))[self.ids]


def motion_map(speeds_mps: np.ndarray, max_speed_mps: float) -> np.ndarray:
    """F1: ``|s_n − mean(s)| / MAX_SPEED`` with the mean over all N elements (§4).

    Args:
        speeds_mps: ``(..., N)`` speeds in [0, MAX_SPEED] (m/s).
        max_speed_mps: MAX_SPEED (m/s).

    Returns:
        ``(..., N)`` values in [0, 1].
    """
    mean = np.add.reduce(speeds_mps, axis=-1, keepdims=True) / speeds_mps.shape[-1]
    return np.abs(speeds_mps - mean) / max_speed_mps


def label_columns(labels: np.ndarray) -> np.ndarray:
    """Direction labels in {−1, 0, +1} → their column (0, 1, 2) in ``LABEL_PREFERENCE`` (int array)."""
    return _LABEL_COLUMN[np.asarray(labels).astype(np.intp)]


def rarity_map(labels: np.ndarray, columns: np.ndarray | None = None, spaces: Spaces | None = None) -> np.ndarray:
    """F2 on one observation space (or several side by side): normalised label rarity (§4).

    ``ρ_n = N / count(d == d_n)`` lies in [1, N]; the result is ``(ρ_n − 1)/(N − 1)``:
    0 when every element shares the label, 1 for a label that occurs once. With
    ``spaces``, N and the counts are those of each element's own space.

    Args:
        labels: ``(N,)`` direction labels in {−1, 0, +1}.
        columns: ``label_columns(labels)`` if already computed.
        spaces: the layout of several spaces in ``labels``; None for one space.

    Returns:
        ``(N,)`` values in [0, 1].
    """
    if columns is None:
        columns = label_columns(labels)
    if spaces is None:
        n = float(labels.shape[-1])
        counts = np.bincount(columns, minlength=_N_LABELS)
        return (n / (n - 1.0)) / counts[columns] - 1.0 / (n - 1.0)
    bins = columns + spaces.label_bins
    counts = np.bincount(bins, minlength=_N_LABELS * len(spaces.sizes))
    return spaces.rarity_scale / counts[bins] - spaces.rarity_shift


def majority_labels(columns: np.ndarray, regions: np.ndarray, n_regions: int) -> np.ndarray:
    """The most frequent direction label of each region.

    Args:
        columns: ``(N,)`` ``label_columns`` of the elements' labels.
        regions: ``(N,)`` region of each element, in 0..J−1; every region holds at
            least one element (as on both grids).
        n_regions: J.

    Returns:
        ``(J,)`` labels in {−1, 0, +1}; ties go to the earlier label of ``LABEL_PREFERENCE``.
    """
    counts = np.bincount(regions * _N_LABELS + columns, minlength=_N_LABELS * n_regions)
    return LABEL_PREFERENCE[counts.reshape(n_regions, _N_LABELS).argmax(axis=1)]


def distance_map(ranges_m: np.ndarray, max_range_m: float | np.ndarray, spaces: Spaces | None = None) -> np.ndarray:
    """F3 on one observation space (or several side by side): ``|o_n − mean(o)| / max_range`` (§4).

    Args:
        ranges_m: ``(..., N)`` ranges in [0, max_range] (m); no-echo readings at the maximum.
        max_range_m: the sensor's maximum range (m): 20 m laser, 5 m sonar; with
            ``spaces``, an ``(N,)`` array of each element's maximum.
        spaces: the layout of several spaces in ``ranges_m`` (then ``(N,)`` only), each
            with its own mean; None for one space.

    Returns:
        ``(..., N)`` values in [0, 1].
    """
    if spaces is None:
        mean = np.add.reduce(ranges_m, axis=-1, keepdims=True) / ranges_m.shape[-1]
    else:
        mean = spaces.means(ranges_m)
    return np.abs(ranges_m - mean) / max_range_m


def goal_table(x: float, goal: Goal, max_value: float) -> float:
    """The graded goal table of F4 (speed, m/s) and F6 (distance, m) for one value (§5).

    Fulfilled values (``goal.is_fulfilled``) give 1; the others a graded closeness:

    ============  ============================  =================================
    relation      where not fulfilled            value
    ============  ============================  =================================
    BETWEEN       ``x < lo``                     ``x / lo``
    BETWEEN       ``x > hi``                     ``1 − (x − hi)/(MAX − hi)``
    GREATER(d)    ``x < d``                      ``x / d``
    SMALLER(d)    ``x > d``                      ``1 − (x − d)/(MAX − d)``
    EQUAL(d)      ``|x − d| > tol``              ``1 − |x − d| / max(d, MAX − d)``
    ============  ============================  =================================

    clipped to [0, 1]. MAX is MAX_SPEED for F4 and MAXDISTANCE for F6. This reading
    fixes the paper's typos: BETWEEN holds for ``lo <= x <= hi`` (not ``>= d and <= d``),
    its upper row and SMALLER's row are ``1 − (x − bound)/(MAX − bound)``, the GREATER and
    SMALLER rows test the input ``x`` (not the output), and F6 uses MAXDISTANCE.

    Args:
        x: speed (m/s) or distance (m) in [0, max_value].
        goal: a speed or distance goal.
        max_value: MAX_SPEED (m/s) or MAXDISTANCE (m), > 0.
    """
    if goal.feature is Feature.DIRECTION:
        raise ValueError("the goal table handles speed and distance goals; use direction_goal_map for direction")
    if goal.is_fulfilled(x):
        return 1.0
    relation = goal.relation
    if relation is Relation.EQUAL:
        value = 1.0 - abs(x - goal.lo) / max(goal.lo, max_value - goal.lo)
    elif relation in (Relation.BETWEEN, Relation.GREATER) and x < goal.lo:
        value = x / goal.lo
    elif goal.hi < max_value:  # BETWEEN above hi, SMALLER above its bound (hi == lo)
        value = 1.0 - (x - goal.hi) / (max_value - goal.hi)
    else:  # above a bound at or beyond MAX: x itself is out of range
        value = 0.0
    return min(max(value, 0.0), 1.0)


def goal_knots(goal: Goal, max_value: float) -> tuple[np.ndarray, np.ndarray]:
    """Knots of the goal table as a piecewise-linear function of x on [0, max_value].

    Every row of ``goal_table`` is linear in x between the bounds, so the table (without
    EQUAL's tolerance band, which ``goal_map`` adds) is the linear interpolation of its
    values at ``0``, the bounds inside ``[0, max_value]`` and ``max_value``.

    Returns:
        ``(xp, fp)``: increasing knots and the table's values there.
    """
    bounds = {0.0, float(max_value)} | {b for b in (goal.lo, goal.hi) if 0.0 < b < max_value}
    xp = np.array(sorted(bounds))
    if goal.relation is Relation.EQUAL:  # the graded row, also inside the tolerance band
        span = max(goal.lo, max_value - goal.lo)
        fp = [min(max(1.0 - abs(x - goal.lo) / span, 0.0), 1.0) for x in xp]
    else:
        fp = [goal_table(float(x), goal, max_value) for x in xp]
    return xp, np.asarray(fp)


def goal_map(
    values: np.ndarray, goal: Goal, max_value: float, knots: tuple[np.ndarray, np.ndarray] | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """F4 (speed, m/s) or F6 (distance, m): ``goal_table`` over an array (§5).

    Args:
        values: ``(..., J)`` raw speeds (m/s) or distances (m) in [0, max_value].
        goal: a speed or distance goal.
        max_value: MAX_SPEED (m/s) or MAXDISTANCE (m), > 0.
        knots: ``goal_knots(goal, max_value)`` if already computed.

    Returns:
        ``(map, fulfilled)``: ``(..., J)`` float in [0, 1] and ``(..., J)`` bool.
    """
    if goal.feature is Feature.DIRECTION:
        raise ValueError("goal_map handles speed and distance goals; use direction_goal_map for direction")
    xp, fp = goal_knots(goal, max_value) if knots is None else knots
    fulfilled = goal.is_fulfilled(values)
    # fulfilled is 0/1 and the table lies in [0, 1]: the maximum is 1 where fulfilled
    return np.maximum(np.interp(values, xp, fp), fulfilled), fulfilled


def direction_goal_map(labels: np.ndarray, goal: Goal) -> tuple[np.ndarray, np.ndarray]:
    """F5: 1 where the region's direction label equals the goal's direction, else 0 (§5).

    Args:
        labels: ``(..., J)`` direction labels in {−1, 0, +1}.
        goal: a direction goal (``Goal.direction_is(...)``).

    Returns:
        ``(map, fulfilled)``: ``(..., J)`` float in {0, 1} and the same as bool.
    """
    if goal.feature is not Feature.DIRECTION:
        raise ValueError(f"direction_goal_map needs a direction goal, got a {goal.feature.value} goal")
    fulfilled = goal.is_fulfilled(labels)
    return fulfilled.astype(float), fulfilled
