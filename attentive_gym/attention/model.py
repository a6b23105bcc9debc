"""The attentional model (docs/model.md §1–§8): one ``step`` per timestamped sensor reading.

- ``AttentionModel``: sensorial memory → feature maps F1–F6 → combined map C with
  origins → attentional map M → saliency L → winner-takes-all; holds the goals, the
  map weights and the Global Attentive State.
- ``AttentionOutput``: everything one step produced (frozen).
- ``FocusView``: the sub-representation of the focused region for a decision maker.

Time is in seconds everywhere; ranges in metres; range rates and speeds in m/s;
bearings in radians (robot frame: x forward, y left, counter-clockwise).

Example:
    >>> import numpy as np
    >>> from attentive_gym.attention import AttentionModel, AttentionConfig, Goal
    >>> model = AttentionModel(AttentionConfig(ego_motion=None))
    >>> model.set_goals(Goal.between("speed", 0.5, 0.9))
    >>> out = model.step(0.0, np.full(8, 3.0), np.full(180, 3.0))
    >>> out.focus is None            # a uniform scene holds nothing salient
    True
"""

from __future__ import annotations

import dataclasses
import functools
import math
import numbers
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np
from numba import njit

from attentive_gym.attention.attentional_map import CourseBook, course_parameters, lateral_spread
from attentive_gym.attention.compiled.records import (
    COURSE_FIELDS,
    KEPT_OUTPUTS,
    MEMORY_FIELDS,
    OUTPUT_ARRAYS,
    ModelState,
    StateLayout,
    goal_options,
    output_dtype,
)
from attentive_gym.attention.compiled.step_kernels import (
    PLAN_COLUMNS,
    attend_many,
    fulfilling_range,
    goal_maps,
    goal_plan_row,
    load_row,
    select,
    sense,
    window_kinematics,
)
from attentive_gym.attention.config import (
    BOTTOM_UP_MAPS,
    MAP_ALIASES,
    MAP_NAMES,
    MAX_MAP_WEIGHT,
    TOP_DOWN_MAPS,
    AttentionConfig,
    is_map_weight,
    parse_state,
)
from attentive_gym.attention.features import (
    Spaces,
    distance_map,
    label_columns,
    motion_map,
    rarity_map,
)
from attentive_gym.attention.goals import Direction, Feature, Goal
from attentive_gym.attention.kinematics import ego_range_change, planar_displacement, scan_points
from attentive_gym.attention.memory import SensorMemory
from attentive_gym.attention.regions import (
    FRONT_SONARS,
    LASER_BEAMS,
    SONAR_RING,
    Grid,
    front_sonar_bearings_rad,
    laser_bearings_rad,
    sonar_cone_bounds,
)
from attentive_gym.attention.tracking.tracker import STATE_FIELDS as TRACKER_FIELDS
from attentive_gym.attention.tracking.tracker import (
    TRACK_TABLE_FIELDS,
    Tracker,
    TrackTable,
    table_from_rows,
    track_step,
)

__all__ = [
    "AttentionModel",
    "AttentionOutput",
    "FocusView",
    "ORIGIN_BOTTOM_UP",
    "ORIGIN_TOP_DOWN",
    "ORIGIN_CODES",
    "GOAL_MAP_OF_FEATURE",
    "MIN_TIME_STEP_S",
]

ORIGIN_BOTTOM_UP = "bottom-up"
ORIGIN_TOP_DOWN = "top-down"
#: Integer codes of origins in traces: 0 bottom-up, 1 top-down, −1 no focus.
ORIGIN_CODES: Mapping[str | None, int] = MappingProxyType({ORIGIN_BOTTOM_UP: 0, ORIGIN_TOP_DOWN: 1, None: -1})
#: Which top-down map (row of F) a goal over each feature drives.
GOAL_MAP_OF_FEATURE: Mapping[Feature, int] = MappingProxyType(
    {Feature.SPEED: 3, Feature.DIRECTION: 4, Feature.DISTANCE: 5}
)
_N_CHANNELS = FRONT_SONARS + LASER_BEAMS
_SONAR = slice(0, FRONT_SONARS)
_LASER = slice(FRONT_SONARS, _N_CHANNELS)
#: Input row layout: front sonars, laser beams (the memory's channels), then rear sonars.
_REAR = slice(_N_CHANNELS, _N_CHANNELS + SONAR_RING - FRONT_SONARS)


@dataclass(frozen=True, eq=False)
class FocusView:
    """What the sensors see in the focused region (the sub-representation of §8).

    Attributes:
        region: the region index j*.
        bearing_rad: bearing of the region's centre (rad, counter-clockwise from the heading).
        sonar_range_m: the reading of the front sonar covering the region (m), clipped to
            the sonar's maximum (which means no echo).
        sonar_echo: whether that sonar has an echo.
        laser_beams: ``(n,)`` indices of the region's laser beams.
        laser_ranges_m: ``(n,)`` their ranges (m), clipped to the laser's maximum.
        range_rate_mps: the region's range rate (m/s, + away), ego-motion compensated:
            its track's ground velocity along the line of sight (``kinematics="tracker"``)
            or the sonar's range rate (the other modes); 0 without a steady echo.
        direction: the region's direction label.
        distance_m: nearest valid sonar or laser reading in the region (m), None if none.
        features: ``(6,)`` F1..F6 at the region.
        track_id: the tracked body the region's motion comes from (``kinematics=
            "tracker"``: of the region's confirmed tracks, a moving one whose speed the
            speed goal wants, by motion probability, else the fastest; docs/model.md §10),
            None for none.
        track_position_m: ``(2,)`` its centre in the robot frame (m), None for none.
        track_velocity_mps: ``(2,)`` its ground velocity in the robot's axes (m/s).
        track_speed_mps: its speed (m/s); track_age_s: time since it was first seen (s).
    """

    region: int
    bearing_rad: float
    sonar_range_m: float
    sonar_echo: bool
    laser_beams: np.ndarray
    laser_ranges_m: np.ndarray
    range_rate_mps: float
    direction: Direction
    distance_m: float | None
    features: np.ndarray
    track_id: int | None = None
    track_position_m: np.ndarray | None = None
    track_velocity_mps: np.ndarray | None = None
    track_speed_mps: float | None = None
    track_age_s: float | None = None


@dataclass(frozen=True, eq=False)
class AttentionOutput:
    """Everything one ``AttentionModel.step`` produced.

    Attributes:
        t: time of the reading (s).
        focus: the winning region j* (``argmax L``, ties to the lowest index) when
            ``L[j*] >= threshold``, else None.
        fired: a new course started at the focus this step.
        origin: "bottom-up" or "top-down" for the focus, None without focus.
        saliency: ``L[j*]`` (the maximum of L, also when below the threshold).
        F: ``(6, J)`` feature maps F1..F6; inactive maps are 0.
        C: ``(J,)`` combined map, ``C_BU + C_TD``.
        C_BU, C_TD: ``(J,)`` weighted bottom-up and top-down parts of C (same normaliser).
        origins: ``(J,)`` int8, 1 where the region is top-down (``C_TD > C_BU``), else 0.
        M: ``(J,)`` attentional map (gain, baseline 1, >= 0).
        L: ``(J,)`` saliency ``g · M · C``.
        gain: the Global Attentive State gain g used.
        goal_fulfilled: ``(J,)`` bool, every active top-down goal holds at the region.
        directions: ``(J,)`` int8 region direction labels (−1 towards, 0, +1 away).
        speeds_mps: ``(J,)`` speed of each region (m/s): the full 2-D ground speed of its
            track with the tracker, the sonar echo's ``|range rate|`` otherwise (clipped to
            ``max_speed_mps``).
        distances_m: ``(J,)`` nearest valid reading per region (m); ``max_distance_m``
            where nothing is in range.
        tracks: (property) the tracked bodies (``TrackTable``, robot frame); empty
            unless ``kinematics="tracker"``; built on first access.
        view: (property) what the sensors see at the focus (``FocusView``), None
            without focus; built on first access.
    """

    t: float
    focus: int | None
    fired: bool
    origin: str | None
    saliency: float
    F: np.ndarray
    C: np.ndarray
    C_BU: np.ndarray
    C_TD: np.ndarray
    origins: np.ndarray
    M: np.ndarray
    L: np.ndarray
    gain: float
    goal_fulfilled: np.ndarray
    directions: np.ndarray
    speeds_mps: np.ndarray
    distances_m: np.ndarray
    # (grid, clipped readings (188,), their validity (188,), range rates (188,),
    #  nearest valid reading per region (J,), inf where none, the tracker's slot behind
    #  each front sonar's channel (8,), −1 for none, the tracks' rows (n, 11) and
    #  covariances (n, 4, 4) of ``Tracker.step``)
    _sources: tuple = field(repr=False, default=())

    def __eq__(self, other: object) -> bool:
        """Equal when every public field is equal (arrays element-wise, exactly)."""
        if not isinstance(other, AttentionOutput):
            return NotImplemented
        return self.tracks == other.tracks and all(
            np.array_equal(getattr(self, f), getattr(other, f)) for f in _OUTPUT_FIELDS
        )

    __hash__ = None  # holds arrays: mutable in practice, so not hashable

    def __deepcopy__(self, memo: dict) -> AttentionOutput:
        """A copy with copied arrays, sharing the immutable grid; ``view`` and ``tracks`` are
        rebuilt on demand.

        Four times cheaper than the generic deep copy (SB3's ``DummyVecEnv`` deep-copies
        every step's ``info``, which holds the output).
        """
        clone = object.__new__(AttentionOutput)
        state = {}
        for name, value in vars(self).items():
            if name == "_sources":
                state[name] = (value[0], *(array.copy() for array in value[1:])) if value else value
            elif isinstance(value, np.ndarray):
                state[name] = value.copy()
            elif name not in ("view", "tracks"):  # numbers, strings, None: immutable
                state[name] = value
        vars(clone).update(state)
        memo[id(self)] = clone
        return clone

    @functools.cached_property
    def tracks(self) -> TrackTable:
        """The tracked bodies of the step (``TrackTable``), empty without a tracker."""
        return table_from_rows(*self._sources[6:8])

    @functools.cached_property
    def view(self) -> FocusView | None:
        """What the sensors see at the focus, None without focus."""
        return None if self.focus is None else self.view_of(self.focus)

    def view_of(self, region: int) -> FocusView:
        """What the sensors see in ``region`` (an index in ``[0, J)``), focused or not."""
        grid, readings, valid, rates, nearest, region_slot, track_rows, _ = self._sources
        if (
            isinstance(region, (bool, np.bool_))
            or not isinstance(region, numbers.Integral)
            or not 0 <= region < grid.n_regions
        ):
            raise ValueError(f"region must be an integer index in [0, {grid.n_regions}), got {region!r}")
        j = int(region)
        sonar_index = int(grid.region_sonar[j])
        beams = grid.beam_slices[j]
        track = self._track_row(j)
        nearest_m = float(nearest[j])
        # the frozen dataclass's generated __init__ costs ~4 µs: fill its fields (all of them) directly
        view = object.__new__(FocusView)
        vars(view).update(
            region=j,
            bearing_rad=float(grid.bearings_rad[j]),
            sonar_range_m=float(readings[sonar_index]),
            sonar_echo=bool(valid[sonar_index]),
            laser_beams=grid.beam_indices[j],
            laser_ranges_m=readings[FRONT_SONARS + beams.start : FRONT_SONARS + beams.stop].copy(),
            range_rate_mps=float(rates[sonar_index]),
            direction=_DIRECTIONS[self.directions[j] + 1],
            distance_m=nearest_m if math.isfinite(nearest_m) else None,
            features=self.F[:, j].copy(),
            track_id=None if track is None else int(track[_ID]),
            track_position_m=None if track is None else track[_X : _X + 2].copy(),
            track_velocity_mps=None if track is None else track[_VX : _VX + 2].copy(),
            track_speed_mps=None if track is None else float(track[_SPEED]),
            track_age_s=None if track is None else float(track[_AGE]),
        )
        return view

    def _track_row(self, region: int) -> np.ndarray | None:
        """The row ``(11,)`` (columns ``TRACK_TABLE_FIELDS``) of the track behind ``region``'s
        motion (its sonar channel's), None for none; ``region`` in ``[0, J)``."""
        grid, region_slot, track_rows = self._sources[0], self._sources[5], self._sources[6]
        row = _row_of_slot(track_rows, region_slot[grid.region_sonar[region]])
        return None if row < 0 else track_rows[row]


#: The direction labels by ``label + 1``.
_DIRECTIONS = (Direction.TOWARDS, Direction.STATIC, Direction.AWAY)
#: The public fields of ``AttentionOutput``, compared by ``==``.
_OUTPUT_FIELDS = tuple(f.name for f in dataclasses.fields(AttentionOutput) if not f.name.startswith("_"))


class AttentionModel:
    """The bio-inspired multi-sensor attentional model, fed one timestamped reading per step.

    Args:
        config: parameters (``AttentionConfig()`` by default).

    Per step (docs/model.md §8): store readings → F1–F3 → F4–F6 and goal masks → C and
    origins → update top-down holds → M(t) → L → winner-takes-all (a fire appends a
    course at t) → output. Goals, weights and state set between steps apply from the
    next step; ``reset()`` clears the memory and courses but keeps them.

    Top-down maps and goals: a speed goal drives F4, a direction goal F5, a distance goal
    F6. A top-down map is active when its weight is > 0 *and* a goal for its feature is
    set; inactive maps are 0 and left out of the normaliser of C. A top-down course is
    held while every active goal is fulfilled at its region; a top-down winner where the
    goals are only partly met (graded values) takes the focus but starts no course.

    Region quantities (sonar grid; on the laser grid a beam's sonar is the front sonar
    nearest its bearing, docs/model.md §1): the speed and range rate are the sonar channel's (as F1): with
    ``kinematics="tracker"`` those of the region's tracked body (docs/model.md §10; F1 and F4
    then see the full 2-D speed, where the paper's Δs/Δt sees only radial motion), else
    the sonar's range rate; the direction label is the sonar channel's when it is moving,
    else the majority label of the region's laser beams; the distance is the nearest
    valid sonar or laser reading.

    State: everything a step reads and writes besides its inputs lives in one
    ``ModelState`` (``model_state``: three flat buffers, ``compiled.records``), which the
    model's memory, course book and tracker are views of. On the sonar grid a step is one
    compiled call over it (``step_kernels.attend_many``). A ``ModelBatch`` batches models by
    handing each its rows of shared buffers (``bind_state``).
    """

    def __init__(self, config: AttentionConfig | None = None) -> None:
        if config is None:
            config = AttentionConfig()
        if not isinstance(config, AttentionConfig):
            raise ValueError(f"config must be an AttentionConfig, got {type(config).__name__}")
        self.config = config
        self.grid = Grid.make(config.grid)
        self._memory = SensorMemory(config.memory_window, _N_CHANNELS)
        self._courses = CourseBook(config, self.grid.n_regions)
        constants = _constants(config)
        self._spread, self._max_ranges, self._limits = constants["spread"], constants["max_ranges"], constants["limits"]
        beams = laser_bearings_rad()
        self._beam_bearings, self._beam_cos, self._beam_sin = beams, np.cos(beams), np.sin(beams)
        sonars = front_sonar_bearings_rad()
        self._sonar_cos, self._sonar_sin = np.cos(sonars), np.sin(sonars)
        # each sonar cone's beams (start, stop) and the places of its two edges in the
        # increasing list of all cone edges (rad), as ego_range_change takes them
        edges = sonars[:, None] + np.radians(config.sonar_cone_half_width_deg) * np.array([-1.0, 1.0])
        order = np.argsort(edges, axis=None, kind="stable")
        places = np.empty(order.size, dtype=np.intp)
        places[order] = np.arange(order.size)
        bounds = sonar_cone_bounds(config.sonar_cone_half_width_deg)
        self._cone_plan = np.concatenate([bounds, places.reshape(edges.shape)], axis=1)
        self._cone_edges = edges.ravel()[order]
        self._spaces = Spaces.make((FRONT_SONARS, LASER_BEAMS))
        self._row = np.zeros(_REAR.stop)
        # ego-motion scratch: echo points x, y (m), their bearings (rad), the range change (m)
        self._scan_x, self._scan_y, self._scan_angles = (np.empty(LASER_BEAMS) for _ in range(3))
        self._ego = np.empty(_N_CHANNELS)
        # K of the range-rate slope: the configured window, the paper's two samples, or none
        # (the tracker estimates motion)
        self._slope_samples = _slope_samples(config)
        self._tracker = Tracker(config) if config.kinematics == "tracker" else None
        self._sonar_time: float | None = None  # times (s) of the latest sonar and laser scans
        self._laser_time: float | None = None
        self._goals: dict[Feature, Goal] = {}
        self._weights = np.asarray(config.weights, dtype=float)
        self._gain = config.gain
        # the goals' settings (``_update_active`` writes them in place)
        self._active = np.zeros(len(MAP_NAMES))
        self._goal_plan = np.zeros((len(TOP_DOWN_MAPS), PLAN_COLUMNS))
        self._combine = np.zeros((2, len(BOTTOM_UP_MAPS)))
        self._goal_options = goal_options(config)
        self._wanted_speed = np.zeros(2)
        self._adopt()
        self._update_active()
        self._last_t: float | None = None
        self._records = _Records(output_dtype(self.grid.n_regions, _N_CHANNELS, FRONT_SONARS))

    # --- settings ---------------------------------------------------------------------
    @property
    def goals(self) -> tuple[Goal, ...]:
        """The current goals (at most one per feature: speed, direction, distance)."""
        return tuple(self._goals[f] for f in GOAL_MAP_OF_FEATURE if f in self._goals)

    @property
    def weights(self) -> Mapping[str, float]:
        """Read-only ``{"F1": w1, ..., "F6": w6}``; 0 means inactive."""
        return MappingProxyType({name: float(w) for name, w in zip(MAP_NAMES, self._weights)})

    @property
    def active_maps(self) -> tuple[str, ...]:
        """Names of the maps that feed C now (weight > 0, and a goal set for top-down maps)."""
        return tuple(name for name, w in zip(MAP_NAMES, self._active) if w > 0.0)

    @property
    def state(self) -> float:
        """The Global Attentive State gain g."""
        return self._gain

    @property
    def tracker(self) -> Tracker | None:
        """The model's ``Tracker`` (``kinematics="tracker"``), None in the other modes; its
        arrays are views of ``model_state`` (read it afresh after a copy or a batch step)."""
        return self._tracker

    @property
    def odometry_pose(self) -> np.ndarray | None:
        """``(3,)`` copy of the robot's dead-reckoned pose (x m, y m, heading rad) in the
        frame that odometry keeps fixed to the world since ``reset``, in which the tracks
        live; None unless ``kinematics="tracker"``."""
        return None if self._tracker is None else self._tracker.pose.copy()

    def set_goals(self, *goals: Goal) -> None:
        """Replace the goals; ``set_goals()`` clears them.

        Args:
            goals: ``Goal`` objects, at most one per feature (speed → F4, direction → F5,
                distance → F6).

        Raises:
            ValueError: for something that is not a ``Goal`` or two goals over one feature.
        """
        new: dict[Feature, Goal] = {}
        for goal in goals:
            if not isinstance(goal, Goal):
                raise ValueError(f"set_goals takes Goal objects (e.g. Goal.between('speed', 0.5, 0.9)), got {goal!r}")
            if goal.feature in new:
                raise ValueError(
                    f"at most one goal per feature; got two {goal.feature.value} goals: {new[goal.feature]} and {goal}"
                )
            new[goal.feature] = goal
        self._goals = new
        self._update_active()

    def set_weights(self, weights: Mapping[str, float] | Iterable[float] | None = None, /, **named: float) -> None:
        """Choose the active maps and their weights.

        Args:
            weights: a mapping from map names ("F1".."F6" or "motion", "direction",
                "distance", "goal_speed", "goal_direction", "goal_distance") to weights,
                or a sequence of 6 weights for F1..F6.
            named: the same as keyword arguments, e.g. ``set_weights(F1=1, F4=2)``.

        Maps not named get weight 0 (inactive). With no argument at all, the weights of
        the configuration are restored.

        Raises:
            ValueError: for an unknown map name, a map named twice, or a weight that is
                not a finite number >= 0.
        """
        if weights is None and not named:
            self._weights = np.asarray(self.config.weights, dtype=float)
            self._update_active()
            return
        new = np.zeros(len(MAP_NAMES))
        pairs: list[tuple[str, object]] = []
        if isinstance(weights, Mapping):
            pairs.extend(weights.items())
        elif weights is not None:
            if isinstance(weights, str):
                raise ValueError(f"weights must be a mapping or 6 numbers, got the string {weights!r}")
            try:
                values = list(weights)
            except TypeError:
                raise ValueError(f"weights must be a mapping or 6 numbers (F1..F6), got {weights!r}") from None
            if len(values) != len(MAP_NAMES):
                raise ValueError(f"a weight sequence needs 6 entries (F1..F6), got {len(values)}")
            pairs.extend(zip(MAP_NAMES, values))
        pairs.extend(named.items())
        seen: set[int] = set()
        for key, value in pairs:
            index = _map_index(key)
            if index in seen:
                raise ValueError(f"map {MAP_NAMES[index]} is given more than one weight")
            seen.add(index)
            if not is_map_weight(value):
                raise ValueError(
                    f"the weight of {MAP_NAMES[index]} must be a number in [0, {MAX_MAP_WEIGHT:g}], got {value!r}"
                )
            new[index] = float(value)
        self._weights = new
        self._update_active()

    def set_state(self, state: str | float) -> None:
        """Set the Global Attentive State: "drowsy" (0.5), "alert" (1), "vigilant" (1.5) or a gain > 0."""
        self._gain = parse_state(state)
        self._gain_cell[0] = self._gain

    def _update_active(self) -> None:
        """Write the goals' settings (``_active``, ``_goal_plan``, ``_wanted_speed``, ``_combine``)
        from the goals and weights, in place (they are state fields)."""
        active = self._weights.copy()
        for feature, row in GOAL_MAP_OF_FEATURE.items():
            if feature not in self._goals:
                active[row] = 0.0
        self._active[:] = active
        maxima = {Feature.SPEED: self.config.max_speed_mps, Feature.DISTANCE: self.config.max_distance_m}
        # one row per top-down map (F4..F6) for the compiled goal maps, see PLAN_COLUMNS
        plan = np.zeros((len(TOP_DOWN_MAPS), PLAN_COLUMNS))
        for feature, row in GOAL_MAP_OF_FEATURE.items():
            if active[row] > 0.0:
                plan[row - TOP_DOWN_MAPS[0]] = goal_plan_row(self._goals[feature], maxima.get(feature))
        self._goal_plan[:] = plan
        # the speeds [lo, hi] (m/s) an active speed goal asks for: the tracker's top-down
        # choice of a region's track
        speed_goal = self._goals.get(Feature.SPEED) if active[GOAL_MAP_OF_FEATURE[Feature.SPEED]] > 0.0 else None
        self._wanted_speed[:] = (np.inf, np.inf) if speed_goal is None else fulfilling_range(speed_goal)
        combined = active.copy()  # the weights C uses
        bottom_up, top_down = list(BOTTOM_UP_MAPS), list(TOP_DOWN_MAPS)
        bottom_up_total, top_down_total = float(active[bottom_up].sum()), float(active[top_down].sum())
        if self.config.balance_groups and bottom_up_total > 0.0 and top_down_total > 0.0:
            # the top-down weights' shares of their group, times the bottom-up group's total
            # (dividing first keeps subnormal weights finite)
            combined[top_down] = active[top_down] / top_down_total * bottom_up_total
        total = float(combined.sum())
        divisor = total if (self.config.normalise_combined and total > 0.0) else 1.0
        # weights of C_BU = w_BU @ F[:3] (row 0) and C_TD = w_TD @ F[3:] (row 1), normaliser folded in;
        # divided, not multiplied by 1/total, which overflows for subnormal weights
        self._combine[:] = np.stack([combined[bottom_up], combined[top_down]]) / divisor

    # --- dynamics -----------------------------------------------------------------------
    def reset(self) -> None:
        """Forget the sensorial memory and every course; goals, weights and state are kept."""
        self._memory.reset()
        self._courses.reset()
        if self._tracker is not None:
            self._tracker.reset()
        self._last_t = self._sonar_time = self._laser_time = None

    def step(
        self,
        t: float,
        sonar,
        laser,
        odometry=None,
        *,
        sonar_time_s: float | None = None,
        laser_time_s: float | None = None,
    ) -> AttentionOutput:
        """Process one reading and select the focus.

        Args:
            t: time of the reading (s); strictly increasing from step to step.
            sonar: ``(16,)`` ring ranges or ``(8,)`` front ranges (m); only the front 8
                are used (rear sonars are validated and ignored). Readings above the
                maximum range are clipped to it; at (or within ``no_echo_epsilon_m`` of)
                the maximum they mean "no echo".
            laser: ``(180,)`` ranges (m), beam 0 rightmost.
            odometry: ``(linear m/s, angular rad/s)``, the robot's velocity at this
                reading, for ego-motion compensation; None means the robot did not move
                (the paper's immobile robot).
            sonar_time_s, laser_time_s: the time (s) of the scan each reading comes from,
                for sensors that scan less often than the model steps (default ``t``: a
                fresh scan). A reading whose scan time has not advanced is a held one: it
                is not stored again, and the tracker does not see it again. Scan times
                must not exceed ``t`` nor go back.

        Returns:
            The step's ``AttentionOutput``.

        Raises:
            ValueError: for a time that is not finite or not after the previous one, a
                reading of the wrong length, NaN, inf or negative, a malformed odometry, or
                a scan time after ``t`` or before the previous scan's. The model's state
                is unchanged then.
        """
        inputs = self._checked(t, sonar, laser, odometry, sonar_time_s, laser_time_s)
        state = self.model_state
        step = self._advance(*inputs)
        records, arrays = self._records.take()
        if self.grid.is_laser:
            return self._step_laser_grid(step, arrays)
        layout = state.layout
        attend_many(
            _ONE_MEMBER,
            layout.table,
            layout.constant_floats,
            layout.constant_ints,
            state.floats,
            state.ints,
            state.flags,
            np.array([step], np.float64),
            records,
        )
        return _output(self, step[0], arrays[:KEPT_OUTPUTS], arrays[-1].tolist())

    def _checked(self, t, sonar, laser, odometry, sonar_time_s, laser_time_s) -> tuple:
        """``step``'s arguments checked (``ValueError`` as ``step`` says), before anything
        changes: ``(t, motion or None, sonar_new, laser_new, sonar_time_s, laser_time_s)``;
        the readings are in the input row."""
        t = self._check_time(t)
        self._check_readings(sonar, laser)
        motion = self._check_odometry(odometry)
        if motion is not None and self._last_t is not None:
            dt = t - self._last_t
            if not (math.isfinite(motion[0] * dt) and math.isfinite(motion[1] * dt)):
                raise ValueError(
                    f"odometry {odometry!r} over the {dt:g} s since the last reading is not a finite "
                    "displacement; call reset() after a gap this long"
                )
        sonar_new, laser_new = self._check_scan_times(t, sonar_time_s, laser_time_s)
        return t, motion, sonar_new, laser_new, sonar_time_s, laser_time_s

    def _advance(self, t, motion, sonar_new, laser_new, sonar_time_s, laser_time_s) -> tuple:
        """Take a checked reading's times (and, in the window modes, its ego-motion change);
        returns the step's ``(t, dt, moved, push, linear, angular, laser_new, sonar_new)``
        as ``attend_one`` takes them."""
        push = sonar_new or laser_new
        # the window's ego-motion compensation (the tracker compensates in its own frame)
        moved = push and motion is not None and self._tracker is None and self._ego_change(t, motion)
        dt = 0.0 if self._last_t is None else t - self._last_t
        self._last_t = t
        if sonar_new:  # a scan without a time is a fresh one, taken at t
            self._sonar_time = t if sonar_time_s is None else sonar_time_s
        if laser_new:
            self._laser_time = t if laser_time_s is None else laser_time_s
        linear, angular = (0.0, 0.0) if motion is None or self.config.ego_motion is None else motion
        return t, dt, moved, push, linear, angular, laser_new, sonar_new

    # --- state ----------------------------------------------------------------------------
    @property
    def model_state(self) -> ModelState:
        """Everything a step reads and writes besides its inputs (``records.STATE_FIELDS``:
        the input row, the goals' settings, the sensorial memory, the courses, the tracker),
        as one ``ModelState`` whose fields the model's own arrays are views of.

        The state has room for one more course of each kind: a full course book grows
        first, and the model moves to a new, larger state (so do a copied or unpickled
        model, whose arrays are no longer views of their state). Read it afresh before a
        step; a batch rebinds a model whose state changed (``bind_state``).
        """
        self._courses.reserve()
        if not self._attached():
            self._adopt()
        return self._state

    def bind_state(self, state: ModelState) -> None:
        """Move the model's state into ``state`` (e.g. rows of a batch's buffers): its values
        are copied there and the model's arrays become views of it.

        Raises:
            ValueError: when ``state``'s layout does not fit the model's (another
                configuration, or room for fewer courses than the model holds).
        """
        current = self.model_state
        if not state.layout.fits(current.layout):
            raise ValueError(
                "bind_state takes a state of the model's layout (same configuration, room for at least "
                f"{current.layout.course_capacity} courses of each kind)"
            )
        state.load(self._state_arrays())
        self._bind(state)

    def _state_arrays(self) -> dict[str, np.ndarray]:
        """Every state field's current array, by name (``records.STATE_FIELDS``)."""
        arrays = {
            "row": self._row,
            "ego": self._ego,
            "active": self._active,
            "goal_plan": self._goal_plan,
            "combine": self._combine,
            "gain": np.array([self._gain]),
            "wanted_speed": self._wanted_speed,
        }
        arrays.update(zip(MEMORY_FIELDS, self._memory.buffers))
        arrays.update(zip(COURSE_FIELDS, self._courses.arrays[1:]))
        if self._tracker is None:
            shapes = _layout(self.config, self._courses.arrays[1].shape[0]).shapes
            arrays.update((f"tracker.{n}", np.zeros(shapes[f"tracker.{n}"][1])) for n in TRACKER_FIELDS)
        else:
            arrays.update((f"tracker.{n}", array) for n, array in zip(TRACKER_FIELDS, self._tracker.state))
        return arrays

    def _adopt(self) -> None:
        """Move the model's arrays into a fresh ``ModelState`` sized for its course book."""
        state = ModelState(_layout(self.config, self._courses.arrays[1].shape[0]))
        state.load(self._state_arrays())
        self._bind(state)

    def _bind(self, state: ModelState) -> None:
        """Make the model's arrays (and its memory's, course book's and tracker's) views of
        ``state``'s fields."""
        field = state.field
        self._row, self._ego = field("row"), field("ego")
        self._active, self._goal_plan, self._combine = field("active"), field("goal_plan"), field("combine")
        self._gain_cell, self._wanted_speed = field("gain"), field("wanted_speed")
        memory, courses = self._memory, self._courses
        memory._state, memory._times, memory._samples, memory._ego_offset = (field(n) for n in MEMORY_FIELDS)
        (courses._bu_regions, courses._bu_starts, courses._td_regions, courses._td_times, courses._counts) = (
            field(n) for n in COURSE_FIELDS
        )
        if self._tracker is not None:
            for name in TRACKER_FIELDS:
                setattr(self._tracker, name, field(f"tracker.{name}"))
        self._state = state

    def _attached(self) -> bool:
        """Whether the model's arrays are still views of its state. A copy or a pickle
        replaces all of them (the input row tells), a course book that grew its course
        arrays (the first tells)."""
        return self._state.holds(self._row) and self._state.holds(self._courses._bu_regions)

    def _step_laser_grid(self, step: tuple, arrays: list[np.ndarray]) -> AttentionOutput:
        """``step`` on the laser grid: the kernels one by one, F1–F3 and the region
        quantities in numpy, into a step record's ``arrays`` (``record_arrays``)."""
        cfg = self.config
        grid = self.grid
        t, dt, moved, push, linear, angular, laser_new, sonar_new = step
        (
            readings,
            valid,
            rates,
            region_slot,
            F,
            C_BU,
            C_TD,
            C,
            region_speed,
            distances,
            nearest,
            origins,
            directions,
            fulfilled,
            M,
            L,
            speeds,
            moving,
            speed_probability,
            results,
        ) = arrays
        F.fill(0.0)  # inactive maps stay 0
        # --- sensorial memory and kinematics (§2, §3, §10) ------------------------------------
        sense(
            self._row[:_N_CHANNELS],
            self._limits,
            *self._memory.buffers,
            t,
            self._slope_samples,
            self._ego,
            moved,
            push,
            readings,
            valid,
            rates,
        )
        n_tracks = 0
        if self._tracker is None:
            window_kinematics(rates, valid, cfg.max_speed_mps, cfg.direction_epsilon_mps, speeds, moving)
            region_slot[:] = -1
            speed_probability[:] = -1.0
        else:
            # §10: the tracker takes the new scans and fills the channels' kinematics
            n_tracks = track_step(
                t,
                dt,
                linear,
                angular,
                laser_new,
                sonar_new,
                readings,
                valid,
                self._wanted_speed,
                *self._tracker.constants,
                *self._tracker.state,
                rates,
                speeds,
                moving,
                region_slot,
                speed_probability,
            )
        active = self._active
        labels = np.sign(rates) * (np.abs(rates) > cfg.direction_epsilon_mps)
        columns = label_columns(labels)
        o2 = readings[_LASER]
        sonar_speed, sonar_labels8 = speeds[_SONAR], labels[_SONAR]

        # --- bottom-up maps (§4) ----------------------------------------------------------
        if active[0] > 0.0:
            F[0] = grid.sonar_to_regions(motion_map(sonar_speed, cfg.max_speed_mps))
        if active[1] > 0.0:
            rarity = rarity_map(labels, columns, self._spaces)
            F[1] = np.maximum(grid.sonar_to_regions(rarity[_SONAR]), grid.reduce_beams(np.maximum, rarity[_LASER]))
        if active[2] > 0.0:
            if cfg.laser_only:
                F[2] = grid.reduce_beams(np.maximum, distance_map(o2, cfg.laser_max_range_m))
            else:
                contrast = distance_map(readings, self._max_ranges, self._spaces)
                F[2] = np.maximum(
                    grid.reduce_beams(np.maximum, contrast[_LASER]), grid.sonar_to_regions(contrast[_SONAR])
                )

        # --- region quantities --------------------------------------------------------------
        sonar_labels = grid.sonar_to_regions(sonar_labels8)
        region_labels = np.where(sonar_labels != 0.0, sonar_labels, labels[_LASER])
        directions[:] = region_labels
        nearest_all = np.where(valid, readings, np.inf)
        nearest[:] = np.minimum(
            grid.reduce_beams(np.minimum, nearest_all[_LASER]), grid.sonar_to_regions(nearest_all[_SONAR])
        )
        echo = nearest < np.inf
        np.minimum(nearest, cfg.max_distance_m, out=distances)
        region_speed[:] = grid.sonar_to_regions(sonar_speed)
        speed_target = grid.sonar_to_regions(moving[_SONAR])

        # --- top-down maps, goal masks (§5), combined map and origins (§6) -----------------
        goal_maps(
            F,
            region_speed,
            speed_target,
            grid.sonar_to_regions(speed_probability),
            region_labels,
            distances,
            echo,
            self._goal_plan,
            self._goal_options,
            self._combine,
            C_BU,
            C_TD,
            C,
            origins,
            fulfilled,
        )

        # --- attentional map, saliency, winner (§7, §8) -----------------------------------
        winner, fired = select(
            t, fulfilled, origins, C, self._gain, cfg.threshold, self._spread, *self._courses.arrays, M, L
        )
        focus = winner if L[winner] >= cfg.threshold else -1
        results[:] = (winner, focus, L[winner], fired, origins[winner], n_tracks)  # records.RESULTS
        return _output(self, t, arrays[:KEPT_OUTPUTS], results.tolist())

    # --- input checks and ego-motion -----------------------------------------------------
    def _check_time(self, t) -> float:
        if type(t) is not float and (isinstance(t, (bool, np.bool_)) or not isinstance(t, numbers.Real)):
            raise ValueError(f"t must be the reading's time in seconds (a real number), got {t!r}")
        t = float(t)
        if not math.isfinite(t):
            raise ValueError(f"t must be a finite time in seconds, got {t}")
        if self._last_t is not None and not t - self._last_t >= MIN_TIME_STEP_S:
            raise ValueError(
                f"t must increase from step to step (seconds, by at least {MIN_TIME_STEP_S:g} s); got t={t!r} "
                f"after t={self._last_t!r}. Call reset() to start a new run."
            )
        return t

    def _check_readings(self, sonar, laser) -> np.ndarray:
        """Copy the readings into the input row; returns its ``(188,)`` channel part (a view)."""
        sonar = _as_float_array(sonar, "sonar")
        laser = _as_float_array(laser, "laser")
        if sonar.shape not in ((SONAR_RING,), (FRONT_SONARS,)):
            raise ValueError(
                f"sonar must hold {SONAR_RING} ring or {FRONT_SONARS} front ranges (m), got shape {sonar.shape}"
            )
        if laser.shape != (LASER_BEAMS,):
            raise ValueError(f"laser must hold {LASER_BEAMS} ranges (m), got shape {laser.shape}")
        if not load_row(sonar, laser, self._row):
            for name, values in (("sonar", sonar), ("laser", laser)):
                bad = np.flatnonzero(~np.isfinite(values) | (values < 0.0))
                if bad.size:
                    raise ValueError(
                        f"{name} readings must be finite ranges >= 0 m (report 'no echo' as the maximum range, "
                        f"not inf); bad entries at indices {bad[:10].tolist()}: {values[bad[:10]].tolist()}"
                    )
        return self._row[:_N_CHANNELS]

    def _check_scan_times(self, t: float, sonar_time_s, laser_time_s) -> tuple[bool, bool]:
        """Whether the sonar and the laser readings are new scans (see ``step``)."""
        return (
            _is_new_scan("sonar_time_s", sonar_time_s, self._sonar_time, t),
            _is_new_scan("laser_time_s", laser_time_s, self._laser_time, t),
        )

    @staticmethod
    def _check_odometry(odometry) -> tuple[float, float] | None:
        if odometry is None:
            return None
        if type(odometry) is np.ndarray and odometry.shape == (2,) and odometry.dtype in _KERNEL_DTYPES:
            motion = tuple(odometry.tolist())  # the floats that float() of each entry gives
        else:
            try:
                linear, angular = odometry
                motion = (float(linear), float(angular))
            except (TypeError, ValueError):
                raise ValueError(f"odometry must be (linear m/s, angular rad/s), got {odometry!r}") from None
        if not (math.isfinite(motion[0]) and math.isfinite(motion[1])):
            raise ValueError(f"odometry must be 2 finite numbers (linear m/s, angular rad/s), got {odometry!r}")
        return motion

    def _ego_change(self, t: float, motion: tuple[float, float]) -> bool:
        """Write into ``self._ego`` the range change a static world shows since the previous
        reading, per channel (m); False (nothing written) when there is none to compensate.

        The laser scan is predicted as by ``kinematics.predict_scan``; a sonar's change is
        the laser's view of its cone before and after the move where that view matches
        the sonar's reading (``sonar_ego_match_m``), else ``point_range_change``.
        """
        memory = self._memory
        if self.config.ego_motion is None or memory.count == 0 or motion == (0.0, 0.0):
            return False
        dx, dy, dtheta = planar_displacement(motion[0], motion[1], t - memory.latest_time)
        previous = memory.latest()
        x, y, angles = self._scan_x, self._scan_y, self._scan_angles
        scan_points(previous[_LASER], self._beam_cos, self._beam_sin, dx, dy, x, y)
        np.arctan2(y, x, out=angles)
        ego_range_change(
            previous,
            angles,
            x,
            y,
            dtheta,
            dx,
            dy,
            self._beam_bearings,
            self._sonar_cos,
            self._sonar_sin,
            self._cone_plan,
            self._cone_edges,
            self.config.sonar_ego_match_m,
            self.config.sonar_ego_model == "point",
            self._ego,
        )
        return True


#: The tracks in the modes without a tracker.
_NO_TRACK_ROWS = (np.zeros((0, len(TRACK_TABLE_FIELDS))), np.zeros((0, 4, 4)))
#: The member list of a model stepped alone (its state is a batch of one).
_ONE_MEMBER = np.zeros(1, np.int64)
#: The flags among a step record's arrays (stored as uint8, handed out as bool).
_RECORD_FLAGS = frozenset(name for name, dtype, _ in OUTPUT_ARRAYS if dtype is np.bool_)
#: The fields of a step record in ``record_arrays``' order.
_RECORD_FIELDS = (*(name for name, _, _ in OUTPUT_ARRAYS), "results")
#: Step records a model allocates at a time.
_RECORD_BLOCK = 16


def record_arrays(records: np.ndarray) -> list[np.ndarray]:
    """The fields of the step records ``records`` ``(n,)`` (``records.output_dtype``) as arrays
    ``(n, ...)``: ``OUTPUT_ARRAYS`` (flags viewed as bool), then ``results``; views."""
    return [records[name].view(np.bool_) if name in _RECORD_FLAGS else records[name] for name in _RECORD_FIELDS]


class _Records:
    """Fresh step records for one model, allocated ``_RECORD_BLOCK`` at a time (one
    allocation and one set of field views per block, not per step).

    Args:
        dtype: the records' dtype (``records.output_dtype``).
    """

    def __init__(self, dtype: np.dtype) -> None:
        self.dtype = dtype
        self._taken = _RECORD_BLOCK

    def take(self) -> tuple[np.ndarray, list[np.ndarray]]:
        """A record no step has used, ``(1,)``, and its arrays (``record_arrays`` without the
        record axis)."""
        k = self._taken
        if k == _RECORD_BLOCK:
            self._block = np.empty(_RECORD_BLOCK, self.dtype)
            self._fields = record_arrays(self._block)
            k = 0
        self._taken = k + 1
        return self._block[k : k + 1], [field[k] for field in self._fields]

    def __getstate__(self) -> dict:
        """Pickled without the block: a copy starts a block of its own."""
        return {"dtype": self.dtype, "_taken": _RECORD_BLOCK}


def outputs_of_records(records: np.ndarray, models, times) -> list[AttentionOutput]:
    """The ``AttentionOutput`` of each model's step from its record (``records.output_dtype``).

    Args:
        records: ``(n,)`` the step's records, one per model, in the order of ``models``.
        models: the ``AttentionModel`` of each record, as it is after the step.
        times: the time (s) of each model's reading.

    The outputs' arrays are views of ``records``.
    """
    kept = record_arrays(records)[:KEPT_OUTPUTS]
    # zip over the (n, ...) fields hands out each model's row views (faster than indexing each)
    return [
        _output(model, t, arrays, results)
        for model, t, arrays, results in zip(models, times, zip(*kept), records["results"].tolist())
    ]


def _output(model: AttentionModel, t: float, arrays, results: list[float]) -> AttentionOutput:
    """The ``AttentionOutput`` of ``model``'s step at ``t`` (s) from its record's first
    ``KEPT_OUTPUTS`` arrays (``record_arrays`` without the record axis) and results (the
    floats of ``records.RESULTS``); the tracks are copied from the model's tracker."""
    readings, valid, rates, region_slot, F, C_BU, C_TD, C = arrays[:8]
    region_speed, distances, nearest, origins, directions, fulfilled, M, L = arrays[8:]
    _, focus, saliency, fired, top_down, n_tracks = results
    tracker = model._tracker
    if tracker is None:
        track_rows = _NO_TRACK_ROWS
    else:
        count = int(n_tracks)
        track_rows = (tracker._rows[:count].copy(), tracker._covariance[:count].copy())
    focus = None if focus < 0.0 else int(focus)
    # the frozen dataclass's generated __init__ costs ~3 µs a step: fill its fields (all of
    # them, in order) directly
    output = object.__new__(AttentionOutput)
    vars(output).update(
        t=t,
        focus=focus,
        fired=fired != 0.0,
        origin=None if focus is None else (ORIGIN_TOP_DOWN if top_down else ORIGIN_BOTTOM_UP),
        saliency=saliency,
        F=F,
        C=C,
        C_BU=C_BU,
        C_TD=C_TD,
        origins=origins,
        M=M,
        L=L,
        gain=model._gain,
        goal_fulfilled=fulfilled,
        directions=directions,
        speeds_mps=region_speed,
        distances_m=distances,
        _sources=(model.grid, readings, valid, rates, nearest, region_slot, *track_rows),
    )
    return output


def _slope_samples(config: AttentionConfig) -> int:
    """K of the range-rate slope: the configured window, the paper's two samples, or 0 (the
    tracker estimates motion)."""
    return {"window": config.slope_samples, "literal": 2, "tracker": 0}[config.kinematics]


@functools.lru_cache(maxsize=16)
def _constants(config: AttentionConfig) -> dict[str, np.ndarray]:
    """The configuration's constant fields (``records.CONSTANT_FIELDS``), read-only arrays."""
    max_ranges = np.concatenate(
        [np.full(FRONT_SONARS, config.sonar_max_range_m), np.full(LASER_BEAMS, config.laser_max_range_m)]
    )
    tracker = _idle_tracker(config)
    (beam_cos, beam_sin, sonar_cos, sonar_sin, beam_step, params, confirm_hits) = tracker.constants[:7]
    (max_speed, epsilon, beam_region, cone_bounds, match_m, match_sigmas, noise_rel, noise_floor) = tracker.constants[
        7:
    ]
    constants = {
        # per channel: the maximum range, and the reading from which on it means no echo (m)
        "limits": np.stack([max_ranges, max_ranges - config.no_echo_epsilon_m]),
        "max_ranges": max_ranges,
        "spread": lateral_spread(Grid.make(config.grid).n_regions, config.lateral_sigma_regions),
        "course_params": course_parameters(config),
        "beam_cos": beam_cos,
        "beam_sin": beam_sin,
        "sonar_cos": sonar_cos,
        "sonar_sin": sonar_sin,
        "tracker_params": params,
        "float_scalars": np.array(
            [
                beam_step,
                max_speed,
                epsilon,
                match_m,
                match_sigmas,
                noise_rel,
                noise_floor,
                config.max_distance_m,
                config.laser_max_range_m,
                config.threshold,
            ],
            np.float64,
        ),
        "beam_region": np.asarray(beam_region, np.int64),
        "cone_bounds": np.asarray(cone_bounds, np.int64),
        "int_scalars": np.array(
            [
                _slope_samples(config),
                config.kinematics == "tracker",
                confirm_hits,
                config.laser_only,
                goal_options(config),
            ],
            np.int64,
        ),
    }
    for array in constants.values():
        array.flags.writeable = False
    return constants


@functools.lru_cache(maxsize=64)
def _layout(config: AttentionConfig, course_capacity: int) -> StateLayout:
    """The state layout of a model of ``config`` with room for ``course_capacity`` courses of
    each kind (the tracker's fields are empty without a tracker)."""
    window, channels = config.memory_window, _N_CHANNELS
    tracked = config.kinematics == "tracker"
    shapes = {
        "row": (np.float64, (_REAR.stop,)),
        "ego": (np.float64, (channels,)),
        "active": (np.float64, (len(MAP_NAMES),)),
        "goal_plan": (np.float64, (len(TOP_DOWN_MAPS), PLAN_COLUMNS)),
        "combine": (np.float64, (2, len(BOTTOM_UP_MAPS))),
        "gain": (np.float64, (1,)),
        "wanted_speed": (np.float64, (2,)),
        "memory_state": (np.int64, (2,)),
        "times": (np.float64, (window,)),
        "samples": (np.float64, (3, window, channels)),
        "ego_offset": (np.float64, (channels,)),
        "bu_regions": (np.int64, (course_capacity,)),
        "bu_starts": (np.float64, (course_capacity,)),
        "td_regions": (np.int64, (course_capacity,)),
        "td_times": (np.float64, (course_capacity, 3)),
        "counts": (np.int64, (2,)),
    }
    for name, array in zip(TRACKER_FIELDS, _idle_tracker(config).state):
        shapes[f"tracker.{name}"] = (array.dtype, array.shape if tracked else (0, *array.shape[1:]))
    return StateLayout(shapes, _constants(config))


@functools.lru_cache(maxsize=8)
def _idle_tracker(config: AttentionConfig) -> Tracker:
    """A tracker that never steps: its constants and the shapes of its state (one per
    configuration, shared)."""
    return Tracker(config)


#: The column of the track rows (``Tracker.step``) that holds a track's slot.
_SLOT = TRACK_TABLE_FIELDS.index("slot")
_ID, _X, _VX, _SPEED, _AGE = (TRACK_TABLE_FIELDS.index(name) for name in ("id", "x", "vx", "speed", "age"))


@njit(cache=True)
def _row_of_slot(track_rows, slot):
    """The row of ``track_rows`` ``(n, 11)`` (``Tracker.step``'s, in slot order) that holds track
    slot ``slot``, −1 for none (also for ``slot`` < 0)."""
    for row in range(track_rows.shape[0]):
        if track_rows[row, _SLOT] == slot:
            return row
    return -1


#: The smallest time between two readings (s): closer readings would make the range-rate
#: slope's denominator underflow to 0 (a ZeroDivisionError inside the compiled kernel).
MIN_TIME_STEP_S = 1e-9


def _map_index(key: str) -> int:
    if isinstance(key, str):
        name = MAP_ALIASES.get(key.lower(), key.upper())
        if name in MAP_NAMES:
            return MAP_NAMES.index(name)
    allowed = ", ".join(MAP_NAMES) + " or " + ", ".join(MAP_ALIASES)
    raise ValueError(f"unknown feature map {key!r}; allowed: {allowed}")


#: Array types the compiled kernels read as they are (others are converted to float64 first).
_KERNEL_DTYPES = (np.dtype(np.float64), np.dtype(np.float32))


def _is_new_scan(name: str, value, previous: float | None, t: float) -> bool:
    """Whether a scan at time ``value`` (s; None: a fresh scan at ``t``) is new after the
    previous scan's time ``previous`` (None: none yet); ``ValueError`` for a time that is not
    a finite number, after ``t`` or before ``previous``."""
    if value is None:
        return True
    if type(value) is not float and (isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real)):
        raise ValueError(f"{name} must be the scan's time in seconds (a finite number), got {value!r}")
    if not math.isfinite(value):
        raise ValueError(f"{name} must be the scan's time in seconds (a finite number), got {value!r}")
    if value > t:
        raise ValueError(f"{name}={value!r} is after the reading's time t={t!r}; a scan cannot come from the future")
    if previous is not None and value < previous:
        raise ValueError(
            f"{name}={value!r} is before the previous scan's time {previous!r}; scan times must not go back"
        )
    return previous is None or value > previous


def _as_float_array(values, name: str) -> np.ndarray:
    if type(values) is np.ndarray and values.dtype in _KERNEL_DTYPES:
        return values  # float32 widens exactly in the kernel, as np.asarray(values, float) does
    try:
        array = np.asarray(values)
    except (TypeError, ValueError):  # e.g. a ragged list
        array = np.asarray(None)
    if array.dtype.kind not in "iuf":  # bool, complex, strings, objects: not ranges
        raise ValueError(
            f"{name} must be an array of ranges in metres (real numbers), got {type(values).__name__} "
            f"of dtype {array.dtype}"
        )
    return array.astype(float, copy=False)
