"""Sensor geometry and the attention grid (docs/model.md §1).

- Constants: the Pioneer sonar ring's bearings, the laser's beam count and bearings.
- ``laser_bearings_rad``: bearing of every laser beam.
- ``nearest_sonar``: the front sonar whose bearing is nearest to each given bearing.
- ``region_name``: the paper's name of a front-sonar region, "s1" … "s8".
- ``sonar_cone_bounds``, ``sonar_cone_reduction``: the laser beams inside each front
  sonar's cone, and a one-call plan to reduce over them.
- ``Grid``: the J attention regions, the map from laser beams and sonars to regions, and
  the reductions of per-beam arrays to regions.

Conventions: robot frame x forward, y left; bearings in radians, counter-clockwise from
the heading. Laser beam ``i`` points at ``−90° + (i + 0.5)°`` (beam 0 is rightmost).
Front sonars 0..7 point at +90, +50, +30, +10, −10, −30, −50, −90° (sonar 0 is leftmost);
the paper names them s1..s8, so region (and sonar) index ``j`` is ``s{j + 1}``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = [
    "SONAR_BEARINGS_DEG",
    "FRONT_SONARS",
    "SONAR_RING",
    "LASER_BEAMS",
    "LASER_FOV_DEG",
    "front_sonar_bearings_rad",
    "laser_bearings_rad",
    "nearest_sonar",
    "region_name",
    "sonar_cone_bounds",
    "sonar_cone_reduction",
    "Grid",
]

#: Bearings of the 16 sonars of a Pioneer P2AT/P3AT ring (deg): front 0..7, rear 8..15.
SONAR_BEARINGS_DEG: tuple[float, ...] = (90, 50, 30, 10, -10, -30, -50, -90, -90, -130, -150, -170, 170, 150, 130, 90)
#: Sonars of the ring (16) and of its front half (8), the observation space O1.
SONAR_RING = 16
FRONT_SONARS = 8
#: Laser beams (observation space O2) and the field of view they cover (deg).
LASER_BEAMS = 180
LASER_FOV_DEG = 180.0


def front_sonar_bearings_rad() -> np.ndarray:
    """Bearings of the 8 front sonars (rad), shape ``(8,)``, sonar 0 at +π/2."""
    return np.radians(np.asarray(SONAR_BEARINGS_DEG[:FRONT_SONARS], dtype=float))


def laser_bearings_rad(n_beams: int = LASER_BEAMS) -> np.ndarray:
    """Bearings of the laser beams (rad), shape ``(n_beams,)``: ``−90° + (i + 0.5)·180°/n``."""
    step = LASER_FOV_DEG / n_beams
    return np.radians(-LASER_FOV_DEG / 2.0 + (np.arange(n_beams) + 0.5) * step)


def nearest_sonar(bearings_rad: np.ndarray) -> np.ndarray:
    """Index of the front sonar whose bearing is nearest to each bearing.

    Args:
        bearings_rad: bearings (rad), any shape, within the front half-plane.

    Returns:
        int array of the same shape with values in 0..7. For the laser this puts the
        region boundaries at ±70°, ±40°, ±20° and 0°.
    """
    sonar = front_sonar_bearings_rad()
    return np.argmin(np.abs(np.asarray(bearings_rad)[..., None] - sonar), axis=-1)


def region_name(index: int, *, with_index: bool = False) -> str:
    """The paper's name of front-sonar region ``index`` (0-based): ``region_name(3)`` is
    "s4", ``region_name(3, with_index=True)`` is "s4 (region 3)".

    Raises:
        ValueError: for an index outside 0..7.
    """
    if not 0 <= index < FRONT_SONARS:
        raise ValueError(f"a front-sonar region index is in 0..{FRONT_SONARS - 1}, got {index!r}")
    name = f"s{int(index) + 1}"
    return f"{name} (region {int(index)})" if with_index else name


def sonar_cone_bounds(half_width_deg: float, n_beams: int = LASER_BEAMS) -> np.ndarray:
    """The laser beams inside each front sonar's cone, as index bounds.

    Args:
        half_width_deg: half-width of a sonar cone (deg), >= 0.5 so that every cone
            holds at least one beam.
        n_beams: laser beams.

    Returns:
        int array ``(8, 2)``: beams ``start <= i < stop`` point within ``half_width_deg``
        of sonar n's bearing. Cones at ±90° are cut by the laser's field of view.
    """
    offset = np.abs(laser_bearings_rad(n_beams)[None, :] - front_sonar_bearings_rad()[:, None])
    inside = offset <= np.radians(half_width_deg)
    if not inside.any(axis=1).all():
        raise ValueError(f"a sonar cone of half-width {half_width_deg} deg holds no laser beam; use >= 0.5 deg")
    start = np.argmax(inside, axis=1)
    stop = n_beams - np.argmax(inside[:, ::-1], axis=1)
    return np.stack([start, stop], axis=1).astype(np.intp)


def sonar_cone_reduction(
    half_width_deg: float, n_beams: int = LASER_BEAMS
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A plan to reduce laser beams over every sonar cone with a single ``ufunc.reduceat``.

    ``ufunc.reduceat(scan, indices, axis=-1)[..., take]`` is the reduction of ``scan``
    (``(..., n_beams)``) over each front sonar's cone, in sonar order. ``reduceat`` over
    ``[s_0, e_0, s_1, e_1, ...]`` reduces ``[s_k, e_k)`` at the even positions; the one cone
    that may end at the last beam goes last, without its stop, because ``reduceat`` runs
    its last segment to the end.

    Returns:
        ``(indices, take, edges_rad)``; ``edges_rad`` ``(8, 2)`` are the bearings of each
        cone's two edges (rad), for reading a scan exactly at the cone's limits.

    Raises:
        ValueError: when more than one cone reaches the last beam (cones wider than the
            sonar spacing allows) or a cone holds no beam.
    """
    bounds = sonar_cone_bounds(half_width_deg, n_beams)
    at_edge = [k for k in range(FRONT_SONARS) if bounds[k, 1] == n_beams]
    if len(at_edge) > 1:
        raise ValueError(f"sonar cones of half-width {half_width_deg} deg are too wide: several reach the laser's edge")
    inner = [k for k in range(FRONT_SONARS) if k not in at_edge]
    indices = [int(i) for k in inner for i in bounds[k]] + [int(bounds[k, 0]) for k in at_edge]
    position = {k: 2 * n for n, k in enumerate(inner)} | {k: len(indices) - 1 for k in at_edge}
    take = np.asarray([position[k] for k in range(FRONT_SONARS)], dtype=np.intp)
    edges = front_sonar_bearings_rad()[:, None] + np.radians(half_width_deg) * np.array([-1.0, 1.0])
    return np.asarray(indices, dtype=np.intp), take, edges


@dataclass(frozen=True, eq=False)
class Grid:
    """The J attention regions and how sensor elements map onto them.

    Build with ``Grid.make("sonar")`` (J = 8, one region per front sonar, region ``j``
    is sonar ``j``) or ``Grid.make("laser")`` (J = 180, region ``j`` is laser beam ``j``).

    Attributes:
        name: "sonar" or "laser".
        n_regions: J.
        bearings_rad: ``(J,)`` bearing of each region's centre (rad).
        beam_region: ``(180,)`` region of each laser beam.
        region_sonar: ``(J,)`` the front sonar that covers each region.
        beam_slices: for each region, the ``slice`` of laser beams it holds.
        beam_indices: for each region, the ``(n,)`` indices of its laser beams.

    A grid is an immutable value (its arrays are read-only), so copies share it: every
    ``AttentionOutput`` refers to its model's grid, and deep-copying an output (as SB3's
    ``DummyVecEnv`` does with each step's ``info``) does not rebuild the grid.
    """

    name: str
    n_regions: int
    bearings_rad: np.ndarray
    beam_region: np.ndarray
    region_sonar: np.ndarray
    beam_slices: tuple[slice, ...]
    beam_indices: tuple[np.ndarray, ...]
    _beam_order: slice
    _starts: np.ndarray

    def __post_init__(self) -> None:
        for array in (self.bearings_rad, self.beam_region, self.region_sonar, self._starts, *self.beam_indices):
            array.flags.writeable = False

    def __copy__(self) -> Grid:
        return self

    def __deepcopy__(self, memo: dict) -> Grid:
        return self

    @classmethod
    def make(cls, name: str) -> Grid:
        """The grid called ``name`` ("sonar" or "laser")."""
        beams = laser_bearings_rad()
        sonar_of_beam = nearest_sonar(beams)
        if name == "sonar":
            # Sonar bearings decrease with the index while beam bearings increase, so the
            # beams of regions 0, 1, ..., 7 are contiguous in reversed beam order.
            reversed_regions = sonar_of_beam[::-1]
            if np.any(np.diff(reversed_regions) < 0):
                raise AssertionError("laser regions are not contiguous in reversed beam order")
            starts = np.searchsorted(reversed_regions, np.arange(FRONT_SONARS))
            slices = tuple(
                slice(int(np.flatnonzero(sonar_of_beam == j).min()), int(np.flatnonzero(sonar_of_beam == j).max()) + 1)
                for j in range(FRONT_SONARS)
            )
            return cls(
                name,
                FRONT_SONARS,
                front_sonar_bearings_rad(),
                sonar_of_beam,
                np.arange(FRONT_SONARS),
                slices,
                _indices(slices),
                slice(None, None, -1),
                starts,
            )
        if name == "laser":
            slices = tuple(slice(i, i + 1) for i in range(LASER_BEAMS))
            return cls(
                name,
                LASER_BEAMS,
                beams,
                np.arange(LASER_BEAMS),
                sonar_of_beam,
                slices,
                _indices(slices),
                slice(None),
                np.arange(LASER_BEAMS),
            )
        raise ValueError(f"unknown grid {name!r}; allowed: 'sonar' (J = 8) or 'laser' (J = 180)")

    @property
    def is_laser(self) -> bool:
        """True when every region is one laser beam."""
        return self.name == "laser"

    def sonar_to_regions(self, values: np.ndarray) -> np.ndarray:
        """Per-front-sonar values ``(..., 8)`` → per-region values ``(..., J)``."""
        return values if not self.is_laser else values[..., self.region_sonar]

    def nearest_reading(self, sonar_m: np.ndarray, laser_m: np.ndarray) -> np.ndarray:
        """Each region's nearest reading (m) ``(..., J)``: the least of its front sonar's range
        (``sonar_m`` ``(..., 16)``) and its laser beams' ranges (``laser_m`` ``(..., 180)``)."""
        return np.minimum(
            np.asarray(sonar_m)[..., self.region_sonar], self.reduce_beams(np.minimum, np.asarray(laser_m))
        )

    def reduce_beams(self, ufunc: np.ufunc, values: np.ndarray) -> np.ndarray:
        """Reduce per-beam values ``(..., 180)`` to regions ``(..., J)`` with ``ufunc``.

        ``ufunc`` is a binary ufunc such as ``np.maximum``, ``np.minimum`` or ``np.add``;
        on the laser grid every region is one beam and ``values`` comes back unchanged.
        """
        if self.is_laser:
            return values
        return ufunc.reduceat(values[..., self._beam_order], self._starts, axis=-1)


def _indices(slices: tuple[slice, ...]) -> tuple[np.ndarray, ...]:
    return tuple(np.arange(s.start, s.stop) for s in slices)
