"""The attentional model (MODEL.md §1–§8): one ``step`` per timestamped sensor reading.

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
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Iterable, Mapping

import numpy as np
from numba import njit

from attentive_gym.attention.attentional_map import CourseBook, attentional_map, lateral_spread
from attentive_gym.attention.config import (
    BOTTOM_UP_MAPS,
    MAP_ALIASES,
    MAP_NAMES,
    TOP_DOWN_MAPS,
    AttentionConfig,
    parse_state,
)
from attentive_gym.attention.features import (
    Spaces,
    direction_goal_map,
    distance_map,
    goal_knots,
    goal_map,
    label_columns,
    majority_labels,
    motion_map,
    rarity_map,
)
from attentive_gym.attention.goals import Direction, Feature, Goal
from attentive_gym.attention.kinematics import (
    planar_displacement,
    point_range_change,
    predict_scan,
    virtual_sonar,
)
from attentive_gym.attention.memory import SensorMemory
from attentive_gym.attention.regions import (
    FRONT_SONARS,
    LASER_BEAMS,
    SONAR_RING,
    Grid,
    front_sonar_bearings_rad,
    laser_bearings_rad,
    sonar_cone_reduction,
)

__all__ = [
    "AttentionModel",
    "AttentionOutput",
    "FocusView",
    "ORIGIN_BOTTOM_UP",
    "ORIGIN_TOP_DOWN",
    "ORIGIN_CODES",
    "GOAL_MAP_OF_FEATURE",
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
        range_rate_mps: the sonar's range rate (m/s, + away), ego-motion compensated; 0
            without a steady echo.
        direction: the region's direction label.
        distance_m: nearest valid sonar or laser reading in the region (m), None if none.
        features: ``(6,)`` F1..F6 at the region.
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
        speeds_mps: ``(J,)`` speed of each region's sonar echo (m/s).
        distances_m: ``(J,)`` nearest valid reading per region (m); ``max_distance_m``
            where nothing is in range.
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
    #  nearest valid reading per region (J,), inf where none)
    _sources: tuple = field(repr=False, default=())

    def __eq__(self, other: object) -> bool:
        """Equal when every public field is equal (arrays element-wise, exactly)."""
        if not isinstance(other, AttentionOutput):
            return NotImplemented
        return all(np.array_equal(getattr(self, f), getattr(other, f)) for f in _OUTPUT_FIELDS)

    __hash__ = None  # holds arrays: mutable in practice, so not hashable

    @functools.cached_property
    def view(self) -> FocusView | None:
        """What the sensors see at the focus, None without focus."""
        if self.focus is None:
            return None
        grid, readings, valid, rates, nearest = self._sources
        j = self.focus
        sonar_index = int(grid.region_sonar[j])
        beams = grid.beam_indices[j]
        sonar_range = float(readings[sonar_index])
        return FocusView(
            region=j,
            bearing_rad=float(grid.bearings_rad[j]),
            sonar_range_m=sonar_range,
            sonar_echo=bool(valid[sonar_index]),
            laser_beams=beams,
            laser_ranges_m=readings[_LASER][beams],
            range_rate_mps=float(rates[sonar_index]),
            direction=Direction(int(self.directions[j])),
            distance_m=float(nearest[j]) if np.isfinite(nearest[j]) else None,
            features=self.F[:, j].copy(),
        )


#: The public fields of ``AttentionOutput``, compared by ``==``.
_OUTPUT_FIELDS = tuple(f.name for f in dataclasses.fields(AttentionOutput) if not f.name.startswith("_"))


class AttentionModel:
    """The bio-inspired multi-sensor attentional model, fed one timestamped reading per step.

    Args:
        config: parameters (``AttentionConfig()`` by default).

    Per step (MODEL.md §8): store readings → F1–F3 → F4–F6 and goal masks → C and
    origins → update top-down holds → M(t) → L → winner-takes-all (a fire appends a
    course at t) → output. Goals, weights and state set between steps apply from the
    next step; ``reset()`` clears the memory and courses but keeps them.

    Top-down maps and goals: a speed goal drives F4, a direction goal F5, a distance goal
    F6. A top-down map is active when its weight is > 0 *and* a goal for its feature is
    set; inactive maps are 0 and left out of the normaliser of C. A top-down course is
    held while every active goal is fulfilled at its region; a top-down winner where the
    goals are only partly met (graded values) takes the focus but starts no course.

    Region quantities (sonar grid; on the laser grid the region's sonar is the one whose
    cone holds the beam): the speed and range rate are the sonar's (as F1); the direction
    label is the sonar's when it is moving, else the majority label of the region's laser
    beams; the distance is the nearest valid sonar or laser reading.
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
        self._spread = lateral_spread(self.grid.n_regions, config.lateral_sigma_regions)
        self._max_ranges = np.concatenate(
            [np.full(FRONT_SONARS, config.sonar_max_range_m), np.full(LASER_BEAMS, config.laser_max_range_m)]
        )
        self._no_echo_from = self._max_ranges - config.no_echo_epsilon_m
        beams = laser_bearings_rad()
        self._beam_bearings, self._beam_cos, self._beam_sin = beams, np.cos(beams), np.sin(beams)
        sonars = front_sonar_bearings_rad()
        self._sonar_cos, self._sonar_sin = np.cos(sonars), np.sin(sonars)
        self._cone_plan = sonar_cone_reduction(config.sonar_cone_half_width_deg)
        self._spaces = Spaces.make((FRONT_SONARS, LASER_BEAMS))
        self._row = np.zeros(_REAR.stop)
        self._goals: dict[Feature, Goal] = {}
        self._td_plan: list[tuple[int, Feature, Goal, tuple | None]] = []
        self._weights = np.asarray(config.weights, dtype=float)
        self._gain = config.gain
        self._active = np.zeros(len(MAP_NAMES))
        self._update_active()
        self._last_t: float | None = None

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
            values = list(weights)
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
            if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value) or value < 0:
                raise ValueError(f"the weight of {MAP_NAMES[index]} must be a finite number >= 0, got {value!r}")
            new[index] = float(value)
        self._weights = new
        self._update_active()

    def set_state(self, state: str | float) -> None:
        """Set the Global Attentive State: "drowsy" (0.5), "alert" (1), "vigilant" (1.5) or a gain > 0."""
        self._gain = parse_state(state)

    def _update_active(self) -> None:
        active = self._weights.copy()
        for feature, row in GOAL_MAP_OF_FEATURE.items():
            if feature not in self._goals:
                active[row] = 0.0
        self._active = active
        maxima = {Feature.SPEED: self.config.max_speed_mps, Feature.DISTANCE: self.config.max_distance_m}
        # (row of F, feature, goal, goal-table knots) of every active top-down map
        self._td_plan = [
            (row, feature, self._goals[feature],
             goal_knots(self._goals[feature], maxima[feature]) if feature in maxima else None)
            for feature, row in GOAL_MAP_OF_FEATURE.items() if active[row] > 0.0
        ]
        self._active_td = active[list(TOP_DOWN_MAPS)]
        total = float(active.sum())
        normaliser = 1.0 / total if (self.config.normalise_combined and total > 0.0) else 1.0
        # weights of C_BU = w_BU @ F[:3] and C_TD = w_TD @ F[3:], normaliser folded in
        self._combine_bu = active[list(BOTTOM_UP_MAPS)] * normaliser
        self._combine_td = self._active_td * normaliser

    # --- dynamics -----------------------------------------------------------------------
    def reset(self) -> None:
        """Forget the sensorial memory and every course; goals, weights and state are kept."""
        self._memory.reset()
        self._courses.reset()
        self._last_t = None

    def step(self, t: float, sonar, laser, odometry=None) -> AttentionOutput:
        """Process one reading and select the focus.

        Args:
            t: time of the reading (s); strictly increasing from step to step.
            sonar: ``(16,)`` ring ranges or ``(8,)`` front ranges (m); only the front 8
                are used (rear sonars are validated and ignored). Readings above the
                maximum range are clipped to it; at (or within ``no_echo_epsilon_m`` of)
                the maximum they mean "no echo".
            laser: ``(180,)`` ranges (m), beam 0 rightmost.
            odometry: ``(linear m/s, angular rad/s)``, the robot's velocity over the
                interval since the previous reading, for ego-motion compensation;
                None means the robot did not move (the paper's immobile robot).

        Returns:
            The step's ``AttentionOutput``.

        Raises:
            ValueError: for a time that is not finite or not after the previous one, a
                reading of the wrong length, NaN, inf or negative, or a malformed odometry.
                The model's state is unchanged then.
        """
        cfg = self.config
        grid = self.grid
        t = self._check_time(t)
        readings = self._check_readings(sonar, laser)
        motion = self._check_odometry(odometry)
        np.minimum(readings, self._max_ranges, out=readings)
        invalid = readings >= self._no_echo_from
        ego = self._ego_change(t, motion) if motion is not None else None
        memory = self._memory
        memory.push(t, readings, invalid, ego)
        self._last_t = t

        # --- kinematics from memory (§3) --------------------------------------------------
        rates = memory.range_rates(cfg.slope_samples)
        valid = ~invalid
        active = self._active
        n_regions = grid.n_regions
        F = np.zeros((len(MAP_NAMES), n_regions))
        if not grid.is_laser:  # the sonar grid: one compiled call, same arithmetic
            region_speed, sonar_labels, directions, nearest, distances = _sonar_grid_kernel(
                rates, readings, invalid, self._max_ranges, cfg.max_speed_mps, cfg.direction_epsilon_mps,
                cfg.max_distance_m, grid.beam_region, self._spaces.rarity_scale, self._spaces.rarity_shift,
                active[0] > 0.0, active[1] > 0.0, active[2] > 0.0, cfg.laser_only, cfg.laser_max_range_m, F,
            )
            echo = nearest < np.inf
        else:
            abs_rates = np.abs(rates)
            speed = np.minimum(abs_rates, cfg.max_speed_mps)
            labels = np.sign(rates) * (abs_rates > cfg.direction_epsilon_mps)
            columns = label_columns(labels)
            o1, o2 = readings[_SONAR], readings[_LASER]
            sonar_speed, sonar_labels8 = speed[_SONAR], labels[_SONAR]

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
                    F[2] = np.maximum(grid.reduce_beams(np.maximum, contrast[_LASER]),
                                      grid.sonar_to_regions(contrast[_SONAR]))

            # --- region quantities --------------------------------------------------------------
            sonar_labels = grid.sonar_to_regions(sonar_labels8)
            laser_labels = (labels[_LASER] if grid.is_laser
                            else majority_labels(columns[_LASER], grid.beam_region, n_regions))
            directions = np.where(sonar_labels != 0.0, sonar_labels, laser_labels)
            nearest_all = np.where(valid, readings, np.inf)
            nearest = np.minimum(grid.reduce_beams(np.minimum, nearest_all[_LASER]),
                                 grid.sonar_to_regions(nearest_all[_SONAR]))
            echo = nearest < np.inf
            distances = np.minimum(nearest, cfg.max_distance_m)
            region_speed = grid.sonar_to_regions(sonar_speed)

        # --- top-down maps and goal masks (§5) --------------------------------------------
        fulfilled = None
        for row, feature, goal, knots in self._td_plan:
            if feature is Feature.SPEED:
                values, ok = goal_map(region_speed, goal, cfg.max_speed_mps, knots)
                target = grid.sonar_to_regions(valid[_SONAR]) & (sonar_labels != 0.0)
            elif feature is Feature.DIRECTION:
                values, ok = direction_goal_map(directions, goal)
                target = echo
            else:
                values, ok = goal_map(distances, goal, cfg.max_distance_m, knots)
                target = echo
            if cfg.td_require_target:
                values *= target
                ok &= target
            F[row] = values
            fulfilled = ok if fulfilled is None else fulfilled & ok
        if fulfilled is None:
            fulfilled = np.zeros(n_regions, dtype=bool)

        # --- combined map and origins (§6) ------------------------------------------------
        C_BU = self._combine_bu @ F[:3]
        C_TD = self._combine_td @ F[3:]
        C = C_BU + C_TD
        top_down = C_TD > C_BU

        # --- attentional map, saliency, winner (§7, §8) -----------------------------------
        courses = self._courses
        courses.update_holds(t, fulfilled)
        gains = courses.centre_gains(t)
        M = np.ones(n_regions) if gains is None else attentional_map(gains, self._spread)
        L = M * C
        if self._gain != 1.0:
            L *= self._gain
        winner = int(L.argmax())
        saliency = float(L[winner])
        focus = origin = None
        fired = False
        if saliency >= cfg.threshold:
            focus = winner
            if top_down[winner]:
                origin = ORIGIN_TOP_DOWN
                # a course is held while the goal holds, so one starts only where it holds
                if fulfilled[winner] and not courses.top_down_held(winner):
                    courses.start_top_down(winner, t)
                    fired = True
            else:
                origin = ORIGIN_BOTTOM_UP
                if not courses.bottom_up_active(winner, t):
                    courses.start_bottom_up(winner, t)
                    fired = True
        return AttentionOutput(
            t=t, focus=focus, fired=fired, origin=origin, saliency=saliency,
            F=F, C=C, C_BU=C_BU, C_TD=C_TD, origins=top_down.view(np.int8), M=M, L=L, gain=self._gain,
            goal_fulfilled=fulfilled, directions=directions.astype(np.int8), speeds_mps=region_speed,
            distances_m=distances, _sources=(grid, readings.copy(), valid, rates, nearest),
        )

    # --- input checks and ego-motion -----------------------------------------------------
    def _check_time(self, t) -> float:
        if type(t) is not float and (isinstance(t, (bool, np.bool_)) or not isinstance(t, numbers.Real)):
            raise ValueError(f"t must be the reading's time in seconds (a real number), got {t!r}")
        t = float(t)
        if not math.isfinite(t):
            raise ValueError(f"t must be a finite time in seconds, got {t}")
        if self._last_t is not None and t <= self._last_t:
            raise ValueError(
                f"t must increase from step to step (seconds); got t={t!r} after t={self._last_t!r}. "
                "Call reset() to start a new run."
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
        row = self._row
        row[_SONAR] = sonar[:FRONT_SONARS]
        row[_LASER] = laser
        row[_REAR] = sonar[FRONT_SONARS:] if sonar.shape[0] == SONAR_RING else 0.0
        # a finite sum of values that are all >= 0 rules out NaN, inf and negatives
        if not (row.min() >= 0.0 and math.isfinite(np.add.reduce(row))):
            for name, values in (("sonar", sonar), ("laser", laser)):
                bad = np.flatnonzero(~np.isfinite(values) | (values < 0.0))
                if bad.size:
                    raise ValueError(
                        f"{name} readings must be finite ranges >= 0 m (report 'no echo' as the maximum range, "
                        f"not inf); bad entries at indices {bad[:10].tolist()}: {values[bad[:10]].tolist()}"
                    )
        return row[:_N_CHANNELS]

    @staticmethod
    def _check_odometry(odometry) -> tuple[float, float] | None:
        if odometry is None:
            return None
        try:
            linear, angular = odometry
            motion = (float(linear), float(angular))
        except (TypeError, ValueError):
            raise ValueError(f"odometry must be (linear m/s, angular rad/s), got {odometry!r}") from None
        if not (math.isfinite(motion[0]) and math.isfinite(motion[1])):
            raise ValueError(f"odometry must be 2 finite numbers (linear m/s, angular rad/s), got {odometry!r}")
        return motion

    def _ego_change(self, t: float, motion: tuple[float, float]) -> np.ndarray | None:
        """Range change a static world shows since the previous reading, per channel (m)."""
        if self.config.ego_motion is None or self._memory.count == 0 or motion == (0.0, 0.0):
            return None
        dx, dy, dtheta = planar_displacement(motion[0], motion[1], t - self._memory.latest_time)
        previous = self._memory.latest()
        laser_prev = previous[_LASER]
        predicted = predict_scan(laser_prev, self._beam_cos, self._beam_sin, self._beam_bearings, dx, dy, dtheta)
        change = np.empty(_N_CHANNELS)
        np.subtract(predicted, laser_prev, out=change[_LASER])
        point = point_range_change(dx, dy, self._sonar_cos, self._sonar_sin)
        if self.config.sonar_ego_model == "point":
            change[_SONAR] = point
        else:
            # the laser's view of each cone, before and after the move; used where it
            # sees what the sonar saw
            before = virtual_sonar(laser_prev, self._beam_bearings, self._cone_plan)
            after = virtual_sonar(predicted, self._beam_bearings, self._cone_plan)
            seen = np.abs(before - previous[_SONAR]) <= self.config.sonar_ego_match_m
            change[_SONAR] = np.where(seen, after - before, point)
        return change


def _map_index(key: str) -> int:
    if isinstance(key, str):
        name = MAP_ALIASES.get(key.lower(), key.upper())
        if name in MAP_NAMES:
            return MAP_NAMES.index(name)
    allowed = ", ".join(MAP_NAMES) + " or " + ", ".join(MAP_ALIASES)
    raise ValueError(f"unknown feature map {key!r}; allowed: {allowed}")


def _as_float_array(values, name: str) -> np.ndarray:
    try:
        return np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be an array of ranges in metres, got {type(values).__name__}") from None


# --- the fused sonar-grid kernel (J = 8) -------------------------------------------------
# One compiled call for §3's labels and speeds, F1–F3 and the region quantities on the sonar
# grid. It repeats numpy's arithmetic operation for operation (sums in numpy's pairwise
# order, see ``_pairwise_sum``), so its results are identical to the array expressions of
# the general path, which still serves the laser grid.


@njit(cache=True)
def _pairwise_block(a, lo, n):
    """numpy's pairwise summation of ``a[lo:lo + n]`` for ``n <= 128`` (one block)."""
    if n < 8:
        res = 0.0
        for i in range(n):
            res += a[lo + i]
        return res
    r0, r1, r2, r3 = a[lo], a[lo + 1], a[lo + 2], a[lo + 3]
    r4, r5, r6, r7 = a[lo + 4], a[lo + 5], a[lo + 6], a[lo + 7]
    i = 8
    m = n - n % 8
    while i < m:
        r0 += a[lo + i]
        r1 += a[lo + i + 1]
        r2 += a[lo + i + 2]
        r3 += a[lo + i + 3]
        r4 += a[lo + i + 4]
        r5 += a[lo + i + 5]
        r6 += a[lo + i + 6]
        r7 += a[lo + i + 7]
        i += 8
    res = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    while i < n:
        res += a[lo + i]
        i += 1
    return res


@njit(cache=True)
def _pairwise_halves(a, lo, n):
    """numpy's pairwise summation for ``n <= 256``: blocks, or two halves of blocks."""
    if n <= 128:
        return _pairwise_block(a, lo, n)
    n2 = n // 2
    n2 -= n2 % 8
    return _pairwise_block(a, lo, n2) + _pairwise_block(a, lo + n2, n - n2)


@njit(cache=True)
def _pairwise_sum(a, lo, n):
    """``sum(a[lo:lo + n])`` in the order of numpy's pairwise summation (``np.add.reduce``
    of a contiguous array), for ``n <= 496`` (two levels of halves; no recursion, which
    numba does not cache reliably)."""
    if n <= 128:
        return _pairwise_block(a, lo, n)
    n2 = n // 2
    n2 -= n2 % 8
    return _pairwise_halves(a, lo, n2) + _pairwise_halves(a, lo + n2, n - n2)


@njit(cache=True)
def _sonar_grid_kernel(rates, readings, invalid, max_ranges, max_speed, epsilon, max_distance, beam_region,
                       rarity_scale, rarity_shift, do_f1, do_f2, do_f3, laser_only, laser_max, F):
    """Fill ``F[0:3]`` (active rows only) and return ``(sonar_speed, sonar_labels,
    directions, nearest, distances)``, all ``(8,)``, for the sonar grid (8 front sonars
    then 180 beams in the channel vectors)."""
    n_sonar = 8
    n = rates.shape[0]
    n_laser = n - n_sonar
    labels = np.empty(n)
    columns = np.empty(n, np.int64)
    counts = np.zeros(6, np.int64)  # label counts per (space, column)
    for k in range(n):
        r = rates[k]
        a = abs(r)
        label = 0.0
        column = 2
        if a > epsilon:
            if r > 0.0:
                label, column = 1.0, 1
            elif r < 0.0:
                label, column = -1.0, 0
        labels[k] = label
        columns[k] = column
        counts[(0 if k < n_sonar else 3) + column] += 1
    sonar_speed = np.empty(n_sonar)
    for j in range(n_sonar):
        sonar_speed[j] = min(abs(rates[j]), max_speed)
    if do_f1:
        mean = _pairwise_sum(sonar_speed, 0, n_sonar) / n_sonar
        for j in range(n_sonar):
            F[0, j] = abs(sonar_speed[j] - mean) / max_speed
    if do_f2:
        for j in range(n_sonar):
            F[1, j] = rarity_scale[j] / counts[columns[j]] - rarity_shift[j]
        for i in range(n_laser):
            k = n_sonar + i
            value = rarity_scale[k] / counts[3 + columns[k]] - rarity_shift[k]
            j = beam_region[i]
            if value > F[1, j]:
                F[1, j] = value
    if do_f3:
        if laser_only:
            mean = _pairwise_sum(readings, n_sonar, n_laser) / n_laser
            first = np.full(n_sonar, -np.inf)
            for i in range(n_laser):
                value = abs(readings[n_sonar + i] - mean) / laser_max
                j = beam_region[i]
                if value > first[j]:
                    first[j] = value
            for j in range(n_sonar):
                F[2, j] = first[j]
        else:
            # add.reduceat: the first element, then the pairwise sum of the rest
            sonar_mean = (readings[0] + _pairwise_sum(readings, 1, n_sonar - 1)) / n_sonar
            laser_mean = (readings[n_sonar] + _pairwise_sum(readings, n_sonar + 1, n_laser - 1)) / n_laser
            laser_part = np.full(n_sonar, -np.inf)
            for i in range(n_laser):
                k = n_sonar + i
                value = abs(readings[k] - laser_mean) / max_ranges[k]
                j = beam_region[i]
                if value > laser_part[j]:
                    laser_part[j] = value
            for j in range(n_sonar):
                F[2, j] = max(laser_part[j], abs(readings[j] - sonar_mean) / max_ranges[j])
    # region quantities
    label_counts = np.zeros((n_sonar, 3), np.int64)
    nearest = np.full(n_sonar, np.inf)
    for i in range(n_laser):
        k = n_sonar + i
        j = beam_region[i]
        label_counts[j, columns[k]] += 1
        if not invalid[k] and readings[k] < nearest[j]:
            nearest[j] = readings[k]
    sonar_labels = labels[:n_sonar].copy()
    directions = np.empty(n_sonar)
    distances = np.empty(n_sonar)
    for j in range(n_sonar):
        if sonar_labels[j] != 0.0:
            directions[j] = sonar_labels[j]
        else:
            best = 0
            for c in range(1, 3):
                if label_counts[j, c] > label_counts[j, best]:
                    best = c
            directions[j] = -1.0 if best == 0 else (1.0 if best == 1 else 0.0)
        if not invalid[j] and readings[j] < nearest[j]:
            nearest[j] = readings[j]
        distances[j] = min(nearest[j], max_distance)
    return sonar_speed, sonar_labels, directions, nearest, distances
