"""Path length to the target around the static world: the distance a geodesic progress reward
counts (``RewardConfig(progress="geodesic")``).

A straight-line distance rewards driving at the target through rubble; the length of the
shortest path that keeps the robot clear of walls and rubble rewards going round them, as
navigation benchmarks measure progress (the change in geodesic distance to the goal).

- ``occupancy``: the cells of a grid over a scenario's bounds that lie within a clearance of
  a wall or a piece of rubble (moving bodies are not in it).
- ``path_lengths``: the compiled Dijkstra search of such a grid (8-connected), from seed cells;
  ``path_from``: a point's path length from the searched grid.
- ``GeodesicDistance``: one episode's grid and the distance from a point to the target, the
  search redone whenever the target enters another cell.

Units: metres. Grids are ``(rows, columns)`` with row ``i`` at ``y0 + (i + ½) · cell_m`` and
column ``j`` at ``x0 + (j + ½) · cell_m``, ``(x0, y0)`` the scenario's lower bounds.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numba import njit

from attentive_gym.world.scenario import BoxRubble, CircleRubble, Rubble, Scenario, SegmentRubble, WallSpec

__all__ = ["CELL_M", "CLEARANCE_M", "GeodesicDistance", "occupancy", "path_from", "path_lengths"]

#: Side of a grid cell (m).
CELL_M = 0.2
#: A cell is blocked when its centre lies this close to a wall or rubble (m): the robot's half
#: width (0.25 m) and a margin.
CLEARANCE_M = 0.3
#: Cells around a point searched for a free one to start or end a path from (a 5 × 5 block).
_REACH_CELLS = 2
_DIAGONAL = math.sqrt(2.0)


def occupancy(
    scenario: Scenario, walls: Sequence[WallSpec], cell_m: float = CELL_M, clearance_m: float = CLEARANCE_M
) -> np.ndarray:
    """``(rows, columns)`` bool: the cells of ``scenario``'s bounds whose centre lies within
    ``clearance_m`` of one of ``walls`` (each a box ``thickness_m`` thick) or of the scenario's
    rubble."""
    x0, y0, x1, y1 = scenario.bounds
    columns, rows = max(1, math.ceil((x1 - x0) / cell_m)), max(1, math.ceil((y1 - y0) / cell_m))
    x, y = np.meshgrid(x0 + (np.arange(columns) + 0.5) * cell_m, y0 + (np.arange(rows) + 0.5) * cell_m)
    gap = np.full(x.shape, np.inf)
    for wall in walls:
        gap = np.minimum(gap, _segment_gap(x, y, wall.start, wall.end) - 0.5 * wall.thickness_m)
    for piece in scenario.rubble:
        gap = np.minimum(gap, _rubble_gap(x, y, piece))
    return gap < clearance_m


def _segment_gap(x: np.ndarray, y: np.ndarray, start, end) -> np.ndarray:
    """Distance (m) from the points ``(x, y)`` to the segment ``start``–``end``."""
    (ax, ay), (bx, by) = start, end
    dx, dy = bx - ax, by - ay
    along = np.clip(((x - ax) * dx + (y - ay) * dy) / (dx * dx + dy * dy), 0.0, 1.0)
    return np.hypot(x - ax - along * dx, y - ay - along * dy)


def _rubble_gap(x: np.ndarray, y: np.ndarray, piece: Rubble) -> np.ndarray:
    """Distance (m) from the points ``(x, y)`` to ``piece``'s surface, 0 inside it."""
    if isinstance(piece, CircleRubble):
        return np.maximum(np.hypot(x - piece.x_m, y - piece.y_m) - piece.radius_m, 0.0)
    if isinstance(piece, SegmentRubble):
        return np.maximum(_segment_gap(x, y, piece.start, piece.end) - piece.radius_m, 0.0)
    if isinstance(piece, BoxRubble):
        c, s = math.cos(math.radians(piece.angle_deg)), math.sin(math.radians(piece.angle_deg))
        u, v = c * (x - piece.x_m) + s * (y - piece.y_m), -s * (x - piece.x_m) + c * (y - piece.y_m)
        outside_u = np.maximum(np.abs(u) - 0.5 * piece.width_m, 0.0)
        outside_v = np.maximum(np.abs(v) - 0.5 * piece.height_m, 0.0)
        return np.hypot(outside_u, outside_v)
    raise TypeError(f"unknown rubble {type(piece).__name__}")


@njit(cache=True)
def path_lengths(blocked, seed_cells, seed_lengths, cell_m, lengths):
    """Shortest 8-connected path lengths (m) through the free cells of ``blocked`` ``(rows,
    columns)``, from the seeds (``seed_cells`` ``(n,)`` flat indices, starting at
    ``seed_lengths`` ``(n,)`` m), into ``lengths`` (same shape; ``inf`` where no path reaches).
    A diagonal step may not cut a blocked cell's corner."""
    rows, columns = blocked.shape
    lengths[:] = np.inf
    flat = lengths.reshape(-1)
    capacity = 8 * rows * columns + seed_cells.shape[0]
    heap_length, heap_cell = np.empty(capacity), np.empty(capacity, np.int64)
    size = 0
    for k in range(seed_cells.shape[0]):
        if seed_lengths[k] < flat[seed_cells[k]]:
            flat[seed_cells[k]] = seed_lengths[k]
            size = _push(heap_length, heap_cell, size, seed_lengths[k], seed_cells[k])
    while size > 0:
        length, cell = heap_length[0], heap_cell[0]
        size = _pop(heap_length, heap_cell, size)
        if length > flat[cell]:
            continue  # a longer entry for a cell reached since
        i, j = cell // columns, cell % columns
        for di in range(-1, 2):
            for dj in range(-1, 2):
                ni, nj = i + di, j + dj
                if (di == 0 and dj == 0) or ni < 0 or nj < 0 or ni >= rows or nj >= columns or blocked[ni, nj]:
                    continue
                if di != 0 and dj != 0 and (blocked[i, nj] or blocked[ni, j]):
                    continue
                step = cell_m * (_DIAGONAL if di != 0 and dj != 0 else 1.0)
                if length + step < lengths[ni, nj]:
                    lengths[ni, nj] = length + step
                    size = _push(heap_length, heap_cell, size, length + step, ni * columns + nj)


@njit(cache=True)
def path_from(lengths, x, y, x0, y0, cell_m):
    """The shortest path length (m) from the point ``(x, y)`` given ``lengths`` ``(rows, columns)``
    (``path_lengths``'s, on cells of ``cell_m`` from ``(x0, y0)``): the least, over the cells
    within ``_REACH_CELLS`` of the point's cell, of the cell's length plus the straight line to
    its centre; ``inf`` when none is reached."""
    rows, columns = lengths.shape
    i, j = math.floor((y - y0) / cell_m), math.floor((x - x0) / cell_m)
    best = np.inf
    for ni in range(max(i - _REACH_CELLS, 0), min(i + _REACH_CELLS + 1, rows)):
        for nj in range(max(j - _REACH_CELLS, 0), min(j + _REACH_CELLS + 1, columns)):
            if lengths[ni, nj] < best:
                centre_x, centre_y = x0 + (nj + 0.5) * cell_m, y0 + (ni + 0.5) * cell_m
                best = min(best, lengths[ni, nj] + math.hypot(centre_x - x, centre_y - y))
    return best


@njit(cache=True, inline="always")
def _push(keys, values, size, key, value):
    """Add ``(key, value)`` to the binary min-heap of its first ``size`` entries; the new size."""
    k = size
    keys[k], values[k] = key, value
    while k > 0:
        parent = (k - 1) // 2
        if keys[parent] <= keys[k]:
            break
        keys[parent], keys[k] = keys[k], keys[parent]
        values[parent], values[k] = values[k], values[parent]
        k = parent
    return size + 1


@njit(cache=True, inline="always")
def _pop(keys, values, size):
    """Remove the heap's least entry (read it first); the new size."""
    size -= 1
    keys[0], values[0] = keys[size], values[size]
    k = 0
    while True:
        left, smallest = 2 * k + 1, k
        if left < size and keys[left] < keys[smallest]:
            smallest = left
        if left + 1 < size and keys[left + 1] < keys[smallest]:
            smallest = left + 1
        if smallest == k:
            return size
        keys[smallest], keys[k] = keys[k], keys[smallest]
        values[smallest], values[k] = values[k], values[smallest]
        k = smallest


class GeodesicDistance:
    """The length of the shortest path (m) from a point to the target that keeps
    ``clearance_m`` from walls and rubble, on a grid of ``cell_m`` cells.

    A path starts and ends at free cells within two cells of its ends, plus the straight lines
    from the ends to those cells' centres. The search from the target is redone whenever the
    target enters another cell, so a moving target's distance is exact to within a cell. Where
    no path exists (a point or the target walled in), the distance is the straight line's.

    Args:
        scenario: the episode's world (its bounds and rubble).
        walls: its walls, the enclosure's included (``World.wall_specs``).
    """

    def __init__(
        self, scenario: Scenario, walls: Sequence[WallSpec], cell_m: float = CELL_M, clearance_m: float = CLEARANCE_M
    ) -> None:
        self.cell_m = cell_m
        self.origin = scenario.bounds[:2]
        self.blocked = occupancy(scenario, walls, cell_m, clearance_m)
        self.lengths = np.full(self.blocked.shape, np.inf)
        self._target_cell: tuple[int, int] | None = None

    def __call__(self, x: float, y: float, target_x: float, target_y: float) -> float:
        """The path length (m) from ``(x, y)`` to the target at ``(target_x, target_y)``."""
        target_cell = self._cell(target_x, target_y)
        if target_cell != self._target_cell:
            cells, lengths = self._reach(target_x, target_y)
            path_lengths(self.blocked, cells, lengths, self.cell_m, self.lengths)
            self._target_cell = target_cell
        best = path_from(self.lengths, x, y, self.origin[0], self.origin[1], self.cell_m)
        return best if math.isfinite(best) else math.hypot(target_x - x, target_y - y)

    def _cell(self, x: float, y: float) -> tuple[int, int]:
        return math.floor((y - self.origin[1]) / self.cell_m), math.floor((x - self.origin[0]) / self.cell_m)

    def _reach(self, x: float, y: float) -> tuple[np.ndarray, np.ndarray]:
        """The free cells within ``_REACH_CELLS`` of the point's cell (flat indices) and the
        straight-line distances (m) from the point to their centres."""
        rows, columns = self.blocked.shape
        i, j = self._cell(x, y)
        i0, i1 = max(i - _REACH_CELLS, 0), min(i + _REACH_CELLS + 1, rows)
        j0, j1 = max(j - _REACH_CELLS, 0), min(j + _REACH_CELLS + 1, columns)
        if i0 >= i1 or j0 >= j1:
            return np.zeros(0, np.int64), np.zeros(0)
        ii, jj = np.mgrid[i0:i1, j0:j1]
        free = ~self.blocked[i0:i1, j0:j1]
        ii, jj = ii[free], jj[free]
        centres_x = self.origin[0] + (jj + 0.5) * self.cell_m
        centres_y = self.origin[1] + (ii + 0.5) * self.cell_m
        return ii * columns + jj, np.hypot(centres_x - x, centres_y - y)
