"""Observation encoders: an ``AttentionOutput`` and the raw readings → an agent's observation.

One encoder per observation mode of ``AttentionWrapper``; each has an exact
``space`` (a ``gymnasium.spaces.Dict`` of float32 ``Box`` es), ``encode(raw, output)``
and ``encode_many(raws, outputs, ...)``, the observations of k steps at once (k members of
a fleet, or k = 1), written into ``(k, ...)`` blocks whose rows each observation's entries
are views of. ``raw`` is the base environment's observation (``"sonar"`` (16,),
``"laser"`` (180,), ``"odometry"`` (2,), ``"goal"`` (13,)) and ``output`` the model's step
(the focus encoder is also told the attended region, so that the region can be chosen
otherwise: at random, or from the privileged state with a ``FocusView``). Encoders with
equal ``settings`` (a tuple of what decides their numbers) encode alike, so one of them
can encode the others' steps.

- ``FocusEncoder`` (``"focus"``): only the attended region's sub-representation and a
  working memory of the last attended bodies, 64 numbers (layout in its docstring).
- ``SaliencyEncoder`` (``"saliency"``): the raw readings plus the maps L and M.
- ``MaskedEncoder`` (``"masked"``): the raw readings with everything outside the focus
  replaced by the sensor's maximum range, plus 0/1 masks of what was kept.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from gymnasium import spaces
from numba import njit

from attentive_gym.attention import AttentionConfig, AttentionOutput, FocusView, Grid
from attentive_gym.attention.regions import FRONT_SONARS, SONAR_RING
from attentive_gym.attention.working_memory import MEMORY_FIELDS

__all__ = ["ENCODERS", "NO_EVENT", "FocusEncoder", "MaskedEncoder", "SaliencyEncoder", "LASER_BINS", "map_ceilings"]

#: Sub-sectors a focused region's laser beams are summarised into (min range in each).
LASER_BINS = 6
_F32 = np.float32
#: The (fired, bottom-up, top-down) event of an attention step without a course of the model.
NO_EVENT = (False, False, False)


def _box(low, high, shape) -> spaces.Box:
    return spaces.Box(np.full(shape, low, _F32), np.full(shape, high, _F32), dtype=_F32)


def map_ceilings(config: AttentionConfig, gain: float) -> tuple[float, float]:
    """Upper bounds of M and of L for ``config`` and a Global Attentive State gain up to ``gain``.

    A region's centre gain is at most one bottom-up course (``A_exc``) plus a held and a
    decaying top-down course (``2 A_td``); the lateral spread sums it over at most the
    largest row sum of ``G``; C is at most 1 when normalised, else the sum of the weights
    (with ``balance_groups``, the top-down group's weights scaled to the bottom-up group's
    sum: at most twice that sum, or the top-down sum alone when no bottom-up map weighs).
    """
    from attentive_gym.attention.attentional_map import lateral_spread

    n_regions = Grid.make(config.grid).n_regions
    spread = float(lateral_spread(n_regions, config.lateral_sigma_regions).sum(axis=1).max())
    m_high = 1.0 + (config.A_exc + 2.0 * config.A_td) * spread
    bottom_up, top_down = float(sum(config.weights[:3])), float(sum(config.weights[3:]))
    if config.normalise_combined:
        c_high = 1.0
    elif config.balance_groups and bottom_up > 0.0 and top_down > 0.0:
        c_high = max(2.0 * bottom_up, top_down)
    else:
        c_high = bottom_up + top_down
    return m_high, gain * m_high * c_high


def _passthrough_spaces(base: spaces.Dict) -> dict[str, spaces.Box]:
    """The base observation's odometry and goal spaces, kept as they are."""
    return {"odometry": base["odometry"], "goal": base["goal"]}


class FocusEncoder:
    """The attended region's sub-representation (docs/model.md §8) and a working memory of
    the last attended bodies; nothing from outside what was attended.

    Keys (all float32; every region-specific entry is 0 when there is no focus):

    - ``"region"`` (J + 1,): one-hot of the attended region, last slot = no focus.
    - ``"event"`` (3,): fired (a new course started), origin bottom-up, origin top-down.
    - ``"sonar"`` (2,): the region's sonar range (m, [0, sonar max]) and echo flag.
    - ``"laser"`` (6,): minimum laser range (m) in each of 6 equal sub-sectors of the
      region's beams, right to left.
    - ``"distance"`` (1,): nearest valid reading in the region (m), clipped to
      ``max_distance_m``; ``max_distance_m`` when none.
    - ``"motion"`` (4,): range rate (m/s, + away, clipped to ±max speed) and the
      direction label one-hot (towards, static, away).
    - ``"features"`` (6,): F1..F6 at the region.
    - ``"proximity"`` (J,), when ``proximity`` is True: each region's nearest reading (m),
      the minimum of its sonar and its laser beams, clipped to ``max_distance_m``. It
      covers every region, attended or not: a sense of what is near, not of what is there.
    - ``"memory"`` (K · 6,), when ``memory_slots`` = K > 0: the rows of
      ``WorkingMemory.read``, the bodies that matched the goal first, each group most
      recently attended first (cos and sin of the bearing, distance in m up to
      ``max_distance_m``, speed in m/s up to ``max_speed_mps``, goal match, age in s up
      to the memory's horizon); empty slots are all zeros, last.
    - ``"odometry"`` (2,), ``"goal"`` (13,): as in the base observation.

    64 numbers with the sonar grid (J = 8) and K = 3 (72 with ``proximity``). Needs ``grid="sonar"``: with one
    region per laser beam the one-hot alone would be 181 numbers.
    """

    def __init__(
        self,
        config: AttentionConfig,
        base: spaces.Dict,
        memory_slots: int = 0,
        memory_horizon_s: float = 10.0,
        proximity: bool = False,
    ) -> None:
        if not isinstance(proximity, bool):
            raise ValueError(f"proximity must be True or False, got {proximity!r}")
        if config.grid != "sonar":
            raise ValueError(f"the 'focus' observation needs AttentionConfig(grid='sonar'), got grid={config.grid!r}")
        self.grid = Grid.make(config.grid)
        self._max_speed = config.max_speed_mps
        self._max_distance = config.max_distance_m
        j = self.grid.n_regions
        memory_high = np.tile(
            np.array([1.0, 1.0, config.max_distance_m, config.max_speed_mps, 1.0, memory_horizon_s], _F32), memory_slots
        )
        memory_low = np.tile(np.array([-1.0, -1.0, 0.0, 0.0, 0.0, 0.0], _F32), memory_slots)
        self.space = spaces.Dict(
            {
                "region": _box(0.0, 1.0, (j + 1,)),
                "event": _box(0.0, 1.0, (3,)),
                "sonar": spaces.Box(np.zeros(2, _F32), np.array([config.sonar_max_range_m, 1.0], _F32), dtype=_F32),
                "laser": _box(0.0, config.laser_max_range_m, (LASER_BINS,)),
                "distance": _box(0.0, config.max_distance_m, (1,)),
                "motion": spaces.Box(
                    np.array([-self._max_speed, 0, 0, 0], _F32), np.array([self._max_speed, 1, 1, 1], _F32), dtype=_F32
                ),
                "features": _box(0.0, 1.0, (6,)),
                **({"proximity": _box(0.0, config.max_distance_m, (j,))} if proximity else {}),
                **({"memory": spaces.Box(memory_low, memory_high, dtype=_F32)} if memory_slots else {}),
                **_passthrough_spaces(base),
            }
        )
        self._memory_high = memory_high
        # per region: where each laser sub-sector starts within the region's beams (J, LASER_BINS),
        # and the region's beams (start, stop) in the laser scan
        self._bin_starts = np.array(
            [
                np.cumsum([0] + [len(b) for b in np.array_split(beams, LASER_BINS)[:-1]])
                for beams in self.grid.beam_indices
            ],
            np.int64,
        )
        self._beam_bounds = np.array([(s.start, s.stop) for s in self.grid.beam_slices], np.int64)
        offsets = np.cumsum([0] + [space.shape[0] for space in self.space.values()])
        self._parts = {key: slice(a, b) for key, a, b in zip(self.space, offsets[:-1], offsets[1:])}
        self._keys, self._slices = tuple(self._parts), tuple(self._parts.values())
        self._empty_memory = np.zeros((memory_slots, len(MEMORY_FIELDS)), _F32)  # an empty memory reads as zeros
        self._starts = {key: int(a) for key, a in zip(self.space, offsets[:-1])}
        self._at = np.array([self._starts[key] for key in _REGION_KEYS], np.int64)
        # where the odometry, goal and memory start (the memory's start is unused without memory)
        self._tail = np.array([self._starts[key] for key in ("odometry", "goal")] + [self._starts.get("memory", 0)])
        self._size = int(offsets[-1])
        self.settings = (
            "focus",
            self.grid.name,
            self._max_speed,
            self._max_distance,
            tuple(self._memory_high.tolist()),
            tuple((key, part.start, part.stop) for key, part in self._parts.items()),
        )

    def encode(
        self,
        raw: dict[str, np.ndarray],
        view: FocusView | None,
        event: tuple[bool, bool, bool],
        memory: np.ndarray | None = None,
    ) -> dict[str, np.ndarray]:
        """The observation of attending ``view`` (None: no focus).

        Args:
            raw: the base observation.
            view: what the sensors see in the attended region.
            event: (fired, origin bottom-up, origin top-down) of the attention step.
            memory: ``(K, 6)`` rows of ``WorkingMemory.read``; None: every slot empty.
        """
        flat = np.zeros(self._size, _F32)
        _write_common(flat, self._tail, raw["odometry"], raw["goal"], self._memory_rows([memory])[0], self._memory_high)
        if view is None:
            flat[self._at[0] + self.grid.n_regions] = 1.0
        else:
            _write_focus(
                flat,
                self._at,
                view.region,
                *event,
                view.sonar_range_m,
                view.sonar_echo,
                view.laser_ranges_m,
                self._bin_starts[view.region],
                math.inf if view.distance_m is None else view.distance_m,
                self._max_distance,
                view.range_rate_mps,
                self._max_speed,
                int(view.direction),
                view.features,
            )
        self._write_proximity(flat[np.newaxis], [raw])
        return self._observation(flat)

    def encode_many(
        self,
        raws: Sequence[dict[str, np.ndarray]],
        outputs: Sequence[AttentionOutput],
        regions: Sequence[int | None],
        events: Sequence[tuple[bool, bool, bool]],
        memories: Sequence[np.ndarray | None],
    ) -> list[dict[str, np.ndarray]]:
        """The observations of k steps at once, each ``encode_region`` of its own arguments
        (the same numbers), written into one ``(k, size)`` float32 block by one compiled call
        (``encode_region`` itself for k = 1).

        Args:
            raws: k base observations.
            outputs: their models' steps (on the sonar grid).
            regions: the attended region of each step (an index in ``[0, J)``), None: no focus.
            events: each step's (fired, origin bottom-up, origin top-down).
            memories: each step's ``(K, 6)`` working-memory rows, None: every slot empty.

        Returns:
            k observations; each one's entries are views of its row of the block.

        Raises:
            ValueError: for lists of different lengths, an output on another grid, a region
                out of range, an event that is not three flags, or memory rows of another shape.
        """
        count = len(raws)
        if not len(outputs) == len(regions) == len(events) == len(memories) == count:
            raise ValueError(
                f"encode_many takes one output, region, event and memory per raw observation ({count}), got "
                f"{len(outputs)}, {len(regions)}, {len(events)} and {len(memories)}"
            )
        if count == 0:
            return []
        if count == 1:
            return [self.encode_region(raws[0], outputs[0], regions[0], events[0], memories[0])]
        # per step: the grid, the clipped readings, their echo flags, the range rates, the
        # nearest reading per region (AttentionOutput's sources), F, the direction labels
        grids, readings, valid, rates, nearest, F, directions = zip(
            *[(*output._sources[:5], output.F, output.directions) for output in outputs]
        )
        n_regions = self.grid.n_regions
        if any(grid.name != self.grid.name for grid in grids):
            raise ValueError(_WRONG_GRID)
        if any(region is not None and not 0 <= region < n_regions for region in regions):
            raise ValueError(_wrong_regions(n_regions, regions))
        if any(len(event) != 3 for event in events):
            raise ValueError(_wrong_events(events))
        block = np.zeros((count, self._size), _F32)
        _write_focus_rows(
            block,
            self._at,
            self._tail,
            np.array([(-1 if r is None else r, *e) for r, e in zip(regions, events)], np.int64),
            _rows([raw["odometry"] for raw in raws]),
            _rows([raw["goal"] for raw in raws]),
            self._memory_rows(memories),
            self._memory_high,
            _rows(readings),
            _rows(valid),
            _rows(rates),
            _rows(nearest),
            _rows(F),
            _rows(directions),
            self.grid.region_sonar,
            self._beam_bounds,
            self._bin_starts,
            self._max_distance,
            self._max_speed,
        )
        self._write_proximity(block, raws)
        return self._views(block)

    def encode_region(
        self,
        raw: dict[str, np.ndarray],
        output: AttentionOutput,
        region: int | None,
        event: tuple[bool, bool, bool],
        memory: np.ndarray | None = None,
    ) -> dict[str, np.ndarray]:
        """``encode(raw, output.view_of(region), event, memory)`` (None: no focus), the same
        numbers, without building the ``FocusView``: one compiled call reads the region from
        the output's arrays (``encode_many`` of one step; ``ValueError`` as it raises)."""
        grid, readings, valid, rates, nearest = output._sources[:5]
        if grid.name != self.grid.name:
            raise ValueError(_WRONG_GRID)
        if region is not None and not 0 <= region < self.grid.n_regions:
            raise ValueError(_wrong_regions(self.grid.n_regions, [region]))
        if len(event) != 3:
            raise ValueError(_wrong_events([event]))
        empty = self._empty_memory
        if memory is None or not empty.shape[0]:
            memory = empty
        elif memory.shape != empty.shape:
            raise ValueError(_wrong_memory(empty.shape, memory.shape))
        flat = np.zeros(self._size, _F32)
        _write_focus_row(
            flat,
            self._at,
            self._tail,
            -1 if region is None else region,
            *event,
            raw["odometry"],
            raw["goal"],
            memory,
            self._memory_high,
            readings,
            valid,
            rates,
            nearest,
            output.F,
            output.directions,
            self.grid.region_sonar,
            self._beam_bounds,
            self._bin_starts,
            self._max_distance,
            self._max_speed,
        )
        self._write_proximity(flat[np.newaxis], [raw])
        return self._observation(flat)

    def _write_proximity(self, block: np.ndarray, raws: Sequence[dict[str, np.ndarray]]) -> None:
        """Write the ``"proximity"`` entry of k observations into ``block`` ``(k, size)``, from
        their base observations' ``"sonar"`` ``(16,)`` and ``"laser"`` ``(R,)`` ranges (m);
        nothing without the entry."""
        part = self._parts.get("proximity")
        if part is None:
            return
        nearest = self.grid.nearest_reading(
            _rows([raw["sonar"] for raw in raws]), _rows([raw["laser"] for raw in raws])
        )
        block[:, part] = np.minimum(nearest, self._max_distance)

    def _memory_rows(self, memories: Sequence[np.ndarray | None]) -> np.ndarray:
        """The steps' memory rows ``(k, K, 6)`` (zeros for None: an empty memory reads as
        zeros); ``(k, 0, 6)`` when the observation has no memory."""
        empty = self._empty_memory
        if not empty.shape[0] or all(memory is None for memory in memories):
            return np.zeros((len(memories), *empty.shape), _F32)
        rows = _rows([empty if memory is None else memory for memory in memories])
        if rows.shape[1:] != empty.shape:
            raise ValueError(_wrong_memory(empty.shape, rows.shape[1:]))
        return rows

    def _observation(self, flat: np.ndarray) -> dict[str, np.ndarray]:
        """The observation whose entries are views of ``flat`` ``(size,)``."""
        return dict(zip(self._keys, map(flat.__getitem__, self._slices)))

    def _views(self, block: np.ndarray) -> list[dict[str, np.ndarray]]:
        """The observations of ``block``'s rows: per row, each key's entries as a view."""
        columns = [block[:, part] for part in self._slices]
        return [dict(zip(self._keys, entries)) for entries in zip(*columns)]


_WRONG_GRID = "every output must be on the 'sonar' grid, as the 'focus' observation needs"


def _wrong_regions(n_regions: int, regions: Sequence) -> str:
    return f"regions must be indices in [0, {n_regions}) or None (no focus), got {list(regions)}"


def _wrong_events(events: Sequence) -> str:
    return f"events must be (fired, bottom-up, top-down) triples of bools, got {list(events)}"


def _wrong_memory(expected: tuple[int, ...], got: tuple[int, ...]) -> str:
    return f"memory rows must have shape {expected} (slots, MEMORY_FIELDS), got {got}"


def _rows(arrays: Sequence[np.ndarray]) -> np.ndarray:
    """``arrays`` (equal shapes) stacked: ``(k, *shape)`` (a view for one array: the single-step case)."""
    return arrays[0][None] if len(arrays) == 1 else np.array(arrays)


#: The keys of ``FocusEncoder``'s region entries, in the order of ``_write_focus``'s offsets ``at``.
_REGION_KEYS = ("region", "event", "sonar", "laser", "distance", "motion", "features")


@njit(cache=True)
def _write_focus(
    flat,
    at,
    region,
    fired,
    bottom_up,
    top_down,
    sonar_range_m,
    sonar_echo,
    laser_ranges_m,
    bin_starts,
    distance_m,
    max_distance_m,
    range_rate_mps,
    max_speed_mps,
    direction,
    features,
):
    """Write the entries of the attended ``region`` into ``flat`` (float32, zeros there):
    ``at`` ``(7,)`` the offsets of ``_REGION_KEYS``; the region's sonar range (m) and echo,
    its beams' ranges ``(n,)`` (m) summarised as the minimum of each sub-sector starting at
    ``bin_starts`` ``(LASER_BINS,)`` (as ``np.minimum.reduceat``), its nearest reading
    ``distance_m`` (m, not finite for none; clipped to ``max_distance_m``), range rate (m/s,
    clipped to ±``max_speed_mps``), direction label (−1, 0, +1) and ``features`` ``(6,)``."""
    flat[at[0] + region] = 1.0
    flat[at[1]], flat[at[1] + 1], flat[at[1] + 2] = fired, bottom_up, top_down
    flat[at[2]], flat[at[2] + 1] = sonar_range_m, sonar_echo
    n_bins, n_beams = bin_starts.shape[0], laser_ranges_m.shape[0]
    for b in range(n_bins):
        first = bin_starts[b]
        stop = bin_starts[b + 1] if b + 1 < n_bins else n_beams
        low = laser_ranges_m[first]
        for i in range(first + 1, stop):
            value = laser_ranges_m[i]
            low = low if (low < value or low != low) else value  # np.minimum's choice
        flat[at[3] + b] = low
    flat[at[4]] = max_distance_m if not math.isfinite(distance_m) else min(distance_m, max_distance_m)
    flat[at[5]] = min(max(range_rate_mps, -max_speed_mps), max_speed_mps)
    flat[at[5] + 2 + direction] = 1.0
    for f in range(features.shape[0]):
        flat[at[6] + f] = features[f]


@njit(cache=True)
def _write_output_focus(
    flat,
    at,
    region,
    fired,
    bottom_up,
    top_down,
    readings,
    valid,
    rates,
    nearest,
    F,
    directions,
    region_sonar,
    beam_bounds,
    bin_starts,
    max_distance_m,
    max_speed_mps,
):
    """``_write_focus`` of ``region`` read from a model step's arrays (``AttentionOutput``:
    clipped readings, echo flags and range rates ``(188,)``, nearest reading per region
    ``(J,)``, F ``(6, J)``, direction labels ``(J,)``), as ``AttentionOutput.view_of`` reads
    them: the region's sonar ``region_sonar[region]``, its beams ``beam_bounds[region]``."""
    sonar = region_sonar[region]
    first, stop = beam_bounds[region, 0], beam_bounds[region, 1]
    _write_focus(
        flat,
        at,
        region,
        fired,
        bottom_up,
        top_down,
        readings[sonar],
        valid[sonar],
        readings[FRONT_SONARS + first : FRONT_SONARS + stop],
        bin_starts[region],
        nearest[region],
        max_distance_m,
        rates[sonar],
        max_speed_mps,
        directions[region],
        F[:, region],
    )


@njit(cache=True)
def _write_common(flat, tail, odometry, goal, memory, memory_high):
    """Write an observation's entries outside its region into ``flat`` (float32): the
    odometry ``(2,)`` and goal ``(13,)`` at ``tail[0]`` and ``tail[1]``, and the memory rows
    ``(K, 6)`` at ``tail[2]``, each clipped to ``memory_high`` ``(K · 6,)`` (as ``np.minimum``)."""
    for c in range(odometry.shape[0]):
        flat[tail[0] + c] = odometry[c]
    for c in range(goal.shape[0]):
        flat[tail[1] + c] = goal[c]
    m = 0
    for slot in range(memory.shape[0]):
        for f in range(memory.shape[1]):
            value, high = memory[slot, f], memory_high[m]
            flat[tail[2] + m] = value if (value < high or value != value) else high
            m += 1


@njit(cache=True)
def _write_focus_row(
    flat,
    at,
    tail,
    region,
    fired,
    bottom_up,
    top_down,
    odometry,
    goal,
    memory,
    memory_high,
    readings,
    valid,
    rates,
    nearest,
    F,
    directions,
    region_sonar,
    beam_bounds,
    bin_starts,
    max_distance_m,
    max_speed_mps,
):
    """One observation into ``flat`` ``(size,)`` (float32, zeros): ``_write_common`` of the
    ``odometry``, ``goal`` and ``memory`` rows ``(K, 6)``, and ``_write_output_focus`` of
    ``region`` (−1: no focus, the one-hot's last slot set) with the event flags, from its
    model's arrays (``readings``, ``valid``, ``rates`` ``(188,)``, ``nearest`` ``(J,)``, ``F``
    ``(6, J)``, ``directions`` ``(J,)``)."""
    _write_common(flat, tail, odometry, goal, memory, memory_high)
    if region < 0:
        flat[at[0] + region_sonar.shape[0]] = 1.0
        return
    _write_output_focus(
        flat,
        at,
        region,
        fired,
        bottom_up,
        top_down,
        readings,
        valid,
        rates,
        nearest,
        F,
        directions,
        region_sonar,
        beam_bounds,
        bin_starts,
        max_distance_m,
        max_speed_mps,
    )


@njit(cache=True)
def _write_focus_rows(
    block,
    at,
    tail,
    choices,
    odometry,
    goal,
    memory,
    memory_high,
    readings,
    valid,
    rates,
    nearest,
    F,
    directions,
    region_sonar,
    beam_bounds,
    bin_starts,
    max_distance_m,
    max_speed_mps,
):
    """``_write_focus_row`` of k observations into the rows of ``block`` ``(k, size)``: row i
    attends the region ``choices[i, 0]`` with the event flags ``choices[i, 1:4]`` (nonzero:
    set), from row i of every other array (``odometry`` ``(k, 2)``, ``goal`` ``(k, 13)``,
    ``memory`` ``(k, K, 6)``, ``readings``, ``valid``, ``rates`` ``(k, 188)``, ``nearest`` and
    ``directions`` ``(k, J)``, ``F`` ``(k, 6, J)``)."""
    for i in range(block.shape[0]):
        _write_focus_row(
            block[i],
            at,
            tail,
            choices[i, 0],
            choices[i, 1] != 0,
            choices[i, 2] != 0,
            choices[i, 3] != 0,
            odometry[i],
            goal[i],
            memory[i],
            memory_high,
            readings[i],
            valid[i],
            rates[i],
            nearest[i],
            F[i],
            directions[i],
            region_sonar,
            beam_bounds,
            bin_starts,
            max_distance_m,
            max_speed_mps,
        )


class SaliencyEncoder:
    """The raw readings plus the saliency ``"L"`` (J,) and attentional map ``"M"`` (J,).

    L and M lie in [0, their ceilings of ``map_ceilings``] (M's baseline is 1); the other
    keys are the base observation's.
    """

    def __init__(self, config: AttentionConfig, base: spaces.Dict, gain: float) -> None:
        j = Grid.make(config.grid).n_regions
        self._m_high, self._l_high = map_ceilings(config, gain)
        self.settings = ("saliency", j, self._m_high, self._l_high)
        self.space = spaces.Dict(
            {**base.spaces, "L": _box(0.0, self._l_high, (j,)), "M": _box(0.0, self._m_high, (j,))}
        )

    def encode(self, raw: dict[str, np.ndarray], output: AttentionOutput) -> dict[str, np.ndarray]:
        """The raw observation with the output's L and M clipped to their ceilings."""
        return {
            **raw,
            "L": np.minimum(output.L, self._l_high).astype(_F32),
            "M": np.minimum(output.M, self._m_high).astype(_F32),
        }

    def encode_many(
        self, raws: Sequence[dict[str, np.ndarray]], outputs: Sequence[AttentionOutput]
    ) -> list[dict[str, np.ndarray]]:
        """The observations of k steps, each ``encode`` of its own (the same numbers), from
        two ``(k, J)`` float32 blocks (each row a view; ``encode`` itself for k = 1)."""
        if len(raws) != len(outputs):
            raise ValueError(f"encode_many takes one output per raw observation ({len(raws)}), got {len(outputs)}")
        if len(raws) <= 1:
            return [self.encode(raw, output) for raw, output in zip(raws, outputs)]
        saliency = np.minimum(_rows([output.L for output in outputs]), self._l_high).astype(_F32)
        attention = np.minimum(_rows([output.M for output in outputs]), self._m_high).astype(_F32)
        return [{**raw, "L": L, "M": M} for raw, L, M in zip(raws, saliency, attention)]


class MaskedEncoder:
    """The raw readings with everything outside the focus at the sensor's maximum range.

    Keys: the base observation's (``"sonar"``, ``"laser"`` masked), plus
    ``"sonar_mask"`` (16,) and ``"laser_mask"`` (180,), 1 where the reading was kept
    (the focused region's front sonar and laser beams), 0 elsewhere; all 0 without a
    focus. Rear sonars are never in a region, so always masked.
    """

    def __init__(self, config: AttentionConfig, base: spaces.Dict, gain: float) -> None:
        self.grid = Grid.make(config.grid)
        self._sonar_max = _F32(base["sonar"].high.max())
        self._laser_max = _F32(base["laser"].high.max())
        n_beams = base["laser"].shape[0]
        if base["sonar"].shape != (SONAR_RING,) or n_beams != len(self.grid.beam_region):
            raise ValueError(
                f"the 'masked' observation needs {SONAR_RING} sonars and {len(self.grid.beam_region)} laser beams, "
                f"got {base['sonar'].shape[0]} and {n_beams}"
            )
        self.space = spaces.Dict(
            {**base.spaces, "sonar_mask": _box(0.0, 1.0, (SONAR_RING,)), "laser_mask": _box(0.0, 1.0, (n_beams,))}
        )
        # the masks of each region (rows 0..J−1) and of no focus (row J): (J + 1, 16) and (J + 1, 180)
        j = self.grid.n_regions
        self._sonar_masks = np.zeros((j + 1, SONAR_RING), _F32)
        self._laser_masks = np.zeros((j + 1, n_beams), _F32)
        for region in range(j):
            self._sonar_masks[region, int(self.grid.region_sonar[region])] = 1.0
            self._laser_masks[region, self.grid.beam_slices[region]] = 1.0
        self.settings = ("masked", self.grid.name, float(self._sonar_max), float(self._laser_max), n_beams)

    def encode(self, raw: dict[str, np.ndarray], output: AttentionOutput) -> dict[str, np.ndarray]:
        """The raw observation masked by the output's focus."""
        focus = self.grid.n_regions if output.focus is None else output.focus
        sonar_mask, laser_mask = self._sonar_masks[focus], self._laser_masks[focus]
        return {
            **raw,
            "sonar": np.where(sonar_mask > 0, raw["sonar"], self._sonar_max),
            "laser": np.where(laser_mask > 0, raw["laser"], self._laser_max),
            "sonar_mask": sonar_mask.copy(),
            "laser_mask": laser_mask.copy(),
        }

    def encode_many(
        self, raws: Sequence[dict[str, np.ndarray]], outputs: Sequence[AttentionOutput]
    ) -> list[dict[str, np.ndarray]]:
        """The observations of k steps, each ``encode`` of its own (the same numbers), from
        ``(k, 16)`` and ``(k, 180)`` float32 blocks of readings and masks (each row a view;
        ``encode`` itself for k = 1)."""
        if len(raws) != len(outputs):
            raise ValueError(f"encode_many takes one output per raw observation ({len(raws)}), got {len(outputs)}")
        if len(raws) <= 1:
            return [self.encode(raw, output) for raw, output in zip(raws, outputs)]
        no_focus = self.grid.n_regions
        focus = np.array([no_focus if output.focus is None else output.focus for output in outputs], np.intp)
        sonar_masks, laser_masks = self._sonar_masks[focus], self._laser_masks[focus]
        sonar = np.where(sonar_masks > 0, _rows([raw["sonar"] for raw in raws]), self._sonar_max)
        laser = np.where(laser_masks > 0, _rows([raw["laser"] for raw in raws]), self._laser_max)
        return [
            {**raw, "sonar": s, "laser": b, "sonar_mask": sm, "laser_mask": bm}
            for raw, s, b, sm, bm in zip(raws, sonar, laser, sonar_masks, laser_masks)
        ]


#: Observation mode → encoder class.
ENCODERS = {"focus": FocusEncoder, "saliency": SaliencyEncoder, "masked": MaskedEncoder}
