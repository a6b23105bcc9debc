"""Tracked kinematics (docs/model.md §10): objects of the laser scan tracked over time.

- ``Tracker``: the state of every track and of the sonar filters, as plain arrays
  (struct of arrays, one row per track slot), and the robot's pose in a frame that
  odometry keeps fixed to the world. ``step`` takes one reading (odometry, laser scan,
  sonar reading) in one compiled call (``track_step``) and reports the tracks.
- ``TrackTable``: the tracks of one step, as the model outputs them (robot frame).
- ``track_scan``: the compiled kernel of one scan: segment, split bodies off the structure
  they stand in front of (``segmentation``), predict, gate and assign (``association``),
  update (``kalman``), confirm, delete, give birth; then free-space evidence
  (``free_space``) and the start rules (``onset_velocity``, ``onset``) weigh the tracks.

Each track runs two filters on the same measurements: a constant-velocity Kalman filter
and a static one (the body does not move; its measured centre may wander slowly as the
view changes). Their likelihoods give the probability that the body moves
(``kalman.motion_probability``); the reported velocity is the constant-velocity
estimate weighted by it, so walls' and rubble's tracks report speeds near 0 while a
moving body's is unbiased once it is clearly moving. Because the filters live in the
odometry-fixed frame, the robot's own motion is compensated by construction.

Units: seconds, metres, m/s, radians.

Small kernels that the model's step calls in its loops are compiled ``inline="always"``:
inlined into their caller, the views of per-track rows (or the arrays) they take need no
reference counting, two atomic operations per array and call otherwise.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from attentive_gym.attention.config import MAX_FREE_SPACE_LAGS, AttentionConfig
from attentive_gym.attention.kinematics import planar_displacement
from attentive_gym.attention.regions import (
    FRONT_SONARS,
    LASER_BEAMS,
    LASER_FOV_DEG,
    Grid,
    front_sonar_bearings_rad,
    laser_bearings_rad,
    sonar_cone_bounds,
)
from attentive_gym.attention.tracking import free_space
from attentive_gym.attention.tracking.association import gated_assignment
from attentive_gym.attention.tracking.kalman import (
    cv_predict,
    cv_update,
    motion_probability,
    rate_predict,
    rate_update,
    robust_log_likelihood,
    static_predict,
    static_update,
)
from attentive_gym.attention.tracking.onset import CENTROID_BUFFER, ramp_onset, remember_centroid
from attentive_gym.attention.tracking.segmentation import (
    SEGMENT_FIELDS,
    STRUCTURE,
    TRACKABLE,
    carve_body,
    measure_segments,
    segment_scan,
    split_foreground,
)
from attentive_gym.attention.tracking.track_regions import MOTION_FLOOR, MOVING_PROBABILITY, track_channels, track_table

__all__ = [
    "Tracker",
    "GOAL_PROBABILITY_PARAM",
    "TrackTable",
    "EMPTY_TRACKS",
    "track_scan",
    "track_step",
    "advance_pose",
    "free_space_step",
    "table_from_rows",
    "TRACK_TABLE_FIELDS",
    "STATE_FIELDS",
]

#: The probability that a new track moves, before any evidence.
_MOTION_PRIOR = 0.5
#: A track starts when its probability of moving rises past 0.5 from at most this: a body
#: known to stand. One hovering about 0.5 (a slow body, or one the filters cannot yet tell)
#: keeps its velocity, which a restart at every crossing would throw away.
ONSET_STANDING_PROBABILITY = 0.1
#: What a started track's position variance grows by (m²): a tenth of a metre's σ.
ONSET_POSITION_VAR_M2 = 0.01
#: Weight of a new match in a track's extent average (a tenth: ≈ the last ten scans).
_EXTENT_SMOOTHING = 0.1
#: Only a track this probably moving looks for its body inside longer segments: static
#: bodies that touch a wall are part of the structure.
_CARVE_PROBABILITY = 0.5
# parameter vector of the kernels, built once from the configuration
(
    _NO_ECHO,
    _NOISE_REL,
    _NOISE_FLOOR,
    _JUMP,
    _JUMP_SIGMAS,
    _MIN_BEAMS,
    _MAX_EXTENT,
    _SURFACE,
    _Q,
    _DRIFT,
    _SWITCH_RATE,
    _POSITION_SIGMA,
    _SPEED_SIGMA,
    _GATE,
    _CONFIRM,
    _DELETE,
    _SONAR_Q,
    _COAST,
    _MOUNT_X,
    _MOUNT_Y,
    _FG_FLANK,
    _FG_SIGMAS,
    _FG_MARGIN,
    _FG_EDGE,
    _ODOMETRY_WEIGHT,
    _FS_ON,
    _FS_RUN_SIGMAS,
    _FS_BORN_MOVING,
    _FS_EVIDENCE,
    _FS_NONE,
    _ONSET_SIGMA,
    _READY_SIGMA,
    _RUNAWAY,
    _EDGE_KEEPS,
    _GOAL_PROBABILITY,
    _OCCLUSION_KEEPS,
    _ONSET_LOG_RATIO,
    _CHANGE_LOG_RATIO,
    _OUTLIER_SHARE,
    _OUTLIER_SIGMAS,
    _FS_SPACING,
    _FS_N_LAGS,
    _FS_LAGS,
) = range(43)
_N_PARAMS = _FS_LAGS + MAX_FREE_SPACE_LAGS
#: The parameter vector's entry of ``AttentionConfig.track_speed_goal_probability`` (1.0 on).
GOAL_PROBABILITY_PARAM = _GOAL_PROBABILITY
_START, _STOP, _X, _Y, _EXTENT, _RXX, _RXY, _RYY, _CANDIDATE = (
    SEGMENT_FIELDS.index(f) for f in ("start", "stop", "x_m", "y_m", "extent_m", "r_xx", "r_xy", "r_yy", "candidate")
)


@dataclass(frozen=True, eq=False)
class TrackTable:
    """The tracks of one step (n rows), in the robot frame at the step's time.

    Attributes:
        id: ``(n,)`` int64 track ids, unique within a run (from 0, never reused).
        position_m: ``(n, 2)`` centre of each body (x forward, y left, m), predicted to
            the step's time.
        velocity_mps: ``(n, 2)`` its velocity over the ground, in the robot's axes (m/s):
            the constant-velocity estimate weighted by ``moving_probability``.
        speed_mps: ``(n,)`` the norm of ``velocity_mps`` (m/s).
        moving_probability: ``(n,)`` the probability that the body moves, in [0, 1].
        covariance: ``(n, 4, 4)`` covariance of (x, y, vx, vy) of the constant-velocity
            filter, in the robot's axes (m², m²/s, m²/s²).
        age_s: ``(n,)`` time since each track was born (s).
        confirmed: ``(n,)`` bool, matched at least ``track_confirm_hits`` times.
        region: ``(n,)`` int64 attention region of the body's bearing (sonar grid), −1
            behind the robot.
    """

    id: np.ndarray
    position_m: np.ndarray
    velocity_mps: np.ndarray
    speed_mps: np.ndarray
    moving_probability: np.ndarray
    covariance: np.ndarray
    age_s: np.ndarray
    confirmed: np.ndarray
    region: np.ndarray

    def __len__(self) -> int:
        return int(self.id.shape[0])

    def __eq__(self, other: object) -> bool:
        """Equal when every array is equal, element-wise and exactly."""
        if not isinstance(other, TrackTable):
            return NotImplemented
        return all(np.array_equal(getattr(self, f), getattr(other, f)) for f in _TABLE_ATTRIBUTES)

    __hash__ = None

    def row(self, track_id: int) -> int | None:
        """The row of the track with ``track_id``, None if it is not in the table."""
        rows = np.flatnonzero(self.id == track_id)
        return int(rows[0]) if rows.size else None


#: Columns of the compiled table behind ``TrackTable`` (one row per track).
TRACK_TABLE_FIELDS = ("id", "x", "y", "vx", "vy", "speed", "p_moving", "age", "confirmed", "region", "slot")
_N_TABLE = len(TRACK_TABLE_FIELDS)
_TABLE_ATTRIBUTES = (
    "id",
    "position_m",
    "velocity_mps",
    "speed_mps",
    "moving_probability",
    "covariance",
    "age_s",
    "confirmed",
    "region",
)


def table_from_rows(rows: np.ndarray, covariance: np.ndarray) -> TrackTable:
    """A read-only ``TrackTable`` from the track rows of ``Tracker.step`` ``(n, 11)`` (columns
    ``TRACK_TABLE_FIELDS``) and their covariances ``(n, 4, 4)``."""
    arrays = (
        rows[:, 0].astype(np.int64),
        rows[:, 1:3],
        rows[:, 3:5],
        rows[:, 5],
        rows[:, 6],
        covariance,
        rows[:, 7],
        rows[:, 8] > 0.0,
        rows[:, 9].astype(np.int64),
    )
    for array in arrays:
        array.flags.writeable = False
    table = object.__new__(TrackTable)  # the frozen dataclass's fields, without its __init__
    vars(table).update(zip(_TABLE_ATTRIBUTES, arrays))
    return table


#: The ``Tracker`` arrays ``track_step`` updates in place, in its argument order.
STATE_FIELDS = (
    "pose",
    "odometry",
    "sonar_pose",
    "bounds",
    "segments",
    "cv_x",
    "cv_P",
    "static_x",
    "static_P",
    "p_moving",
    "alive",
    "ids",
    "hits",
    "misses",
    "born_s",
    "filter_t",
    "seen_s",
    "extent_m",
    "segment_of",
    "counters",
    "scan_history",
    "centroid_history",
    "centroid_count",
    "sonar_x",
    "sonar_P",
    "sonar_hits",
    "sonar_t",
    "_rows",
    "_covariance",
)

#: The table of a step without tracks (every mode but "tracker").
EMPTY_TRACKS = table_from_rows(np.zeros((0, _N_TABLE)), np.zeros((0, 4, 4)))


class Tracker:
    """Tracks of the laser's objects and range/rate filters of the front sonars.

    Args:
        config: the model's configuration (the tracker's fields, §10).

    The robot's pose is dead-reckoned from odometry (``step``) in a frame fixed to
    the world at the first reading; tracks live in that frame. ``reset`` forgets all.
    """

    def __init__(self, config: AttentionConfig) -> None:
        self.config = config
        capacity = config.max_tracks
        self.cv_x = np.zeros((capacity, 4))
        self.cv_P = np.zeros((capacity, 4, 4))
        self.static_x = np.zeros((capacity, 2))
        self.static_P = np.zeros((capacity, 2, 2))
        self.p_moving = np.zeros(capacity)
        self.alive = np.zeros(capacity, np.bool_)
        self.ids = np.zeros(capacity, np.int64)
        self.hits = np.zeros(capacity, np.int64)
        self.misses = np.zeros(capacity, np.int64)
        self.born_s = np.zeros(capacity)
        self.filter_t = np.zeros(capacity)
        self.seen_s = np.zeros(capacity)  # time of the track's last match (s)
        self.extent_m = np.zeros(capacity)  # the body's extent, averaged over its matches (m)
        self.segment_of = np.full(capacity, -1, np.int64)  # segment matched at the last scan
        self.counters = np.zeros(4, np.int64)  # next id, segments of the last scan, the scan history's 2
        # past laser scans for free-space evidence, a row each: time (s), the laser's pose (x m, y m,
        # heading rad; odometry frame), its ranges (m) (free_space.ScanHistory's arrays side by side)
        spacing = 0.45 * min(config.free_space_lags_s)  # every scan at 20 Hz while the shortest lag is 0.1 s
        rows = math.ceil(max(config.free_space_lags_s) / spacing) + 2 if config.free_space_evidence else 0
        self.scan_history = np.zeros((rows, 4 + LASER_BEAMS))
        # each track's last matched centroids for the start and change tests (onset.ramp_onset)
        self.centroid_history = np.zeros((capacity, CENTROID_BUFFER, 9))
        self.centroid_count = np.zeros(capacity, np.int64)
        self.bounds = np.zeros((LASER_BEAMS, 2), np.int64)
        self.segments = np.zeros((LASER_BEAMS, len(SEGMENT_FIELDS)))
        self.sonar_x = np.zeros((FRONT_SONARS, 2))
        self.sonar_P = np.zeros((FRONT_SONARS, 2, 2))
        self.sonar_hits = np.zeros(FRONT_SONARS, np.int64)
        self.sonar_t = np.zeros(FRONT_SONARS)
        self.sonar_pose = np.zeros(3)  # the pose of the sonars' previous reading
        self.pose = np.zeros(3)  # x, y (m), heading (rad) in the odometry frame
        self.odometry = np.zeros(3)  # the previous reading's (v m/s, ω rad/s), 1.0 once there is one
        sonars = front_sonar_bearings_rad()
        self._sonar_cos, self._sonar_sin = np.cos(sonars), np.sin(sonars)
        bearings = laser_bearings_rad()
        self.beam_cos, self.beam_sin = np.cos(bearings), np.sin(bearings)
        self.beam_step_rad = math.radians(LASER_FOV_DEG / LASER_BEAMS)
        params = np.zeros(_N_PARAMS)
        params[_NO_ECHO] = config.laser_max_range_m - config.no_echo_epsilon_m
        params[_NOISE_REL], params[_NOISE_FLOOR] = config.range_noise_rel, config.range_noise_floor_m
        params[_JUMP], params[_JUMP_SIGMAS] = config.segment_jump_m, config.segment_jump_sigmas
        params[_MIN_BEAMS], params[_MAX_EXTENT] = config.segment_min_beams, config.max_object_extent_m
        params[_SURFACE], params[_Q] = config.track_surface_sigma_m, config.track_accel_psd_m2ps3
        params[_DRIFT], params[_SWITCH_RATE] = config.track_static_drift_m2ps, config.track_switch_rate_hz
        params[_POSITION_SIGMA] = config.track_position_sigma_m
        params[_SPEED_SIGMA] = config.track_initial_speed_sigma_mps
        params[_GATE] = config.track_gate_chi2
        params[_CONFIRM], params[_DELETE] = config.track_confirm_hits, config.track_delete_misses
        params[_SONAR_Q] = config.sonar_accel_psd_m2ps3
        params[_COAST] = config.track_coast_s
        params[_MOUNT_X], params[_MOUNT_Y] = config.laser_mount_x_m, config.laser_mount_y_m
        params[_FG_FLANK], params[_FG_SIGMAS] = config.foreground_flank_beams, config.foreground_sigmas
        params[_FG_MARGIN], params[_FG_EDGE] = config.foreground_margin_m, config.foreground_edge_sigmas
        params[_ODOMETRY_WEIGHT] = config.odometry_previous_weight
        params[_FS_ON], params[_FS_RUN_SIGMAS] = config.free_space_evidence, config.free_space_run_sigmas
        params[_FS_BORN_MOVING] = config.free_space_born_moving
        params[_FS_EVIDENCE], params[_FS_NONE] = config.free_space_evidence_log_odds, config.free_space_none_log_odds
        params[_ONSET_SIGMA] = config.track_onset_speed_sigma_mps
        params[_READY_SIGMA] = config.track_standing_speed_sigma_mps
        params[_RUNAWAY] = config.track_runaway_speed_mps
        params[_EDGE_KEEPS] = config.track_edge_keeps_motion
        params[_GOAL_PROBABILITY] = config.track_speed_goal_probability
        params[_OCCLUSION_KEEPS] = config.track_occlusion_keeps_motion
        params[_ONSET_LOG_RATIO] = config.track_onset_log_ratio
        params[_CHANGE_LOG_RATIO] = config.track_change_log_ratio
        params[_OUTLIER_SHARE], params[_OUTLIER_SIGMAS] = config.track_outlier_share, config.track_outlier_sigmas
        params[_FS_SPACING], params[_FS_N_LAGS] = spacing, len(config.free_space_lags_s)
        params[_FS_LAGS : _FS_LAGS + len(config.free_space_lags_s)] = config.free_space_lags_s
        self.params = params
        self._beam_region = Grid.make("sonar").beam_region
        self._cone_bounds = sonar_cone_bounds(config.sonar_cone_half_width_deg).astype(np.int64)
        self._rows = np.zeros((capacity, _N_TABLE))
        self._covariance = np.zeros((capacity, 4, 4))

    def reset(self) -> None:
        """Forget every track, the sonar filters, the past laser scans and the pose."""
        self.alive[:] = False
        self.segment_of[:] = -1
        self.counters[:] = 0
        self.sonar_hits[:] = 0
        self.pose[:] = 0.0
        self.sonar_pose[:] = 0.0
        self.odometry[:] = 0.0

    @property
    def constants(self) -> tuple:
        """The kernels' fixed inputs, in ``track_step``'s order: beam and front-sonar
        cosines and sines, the beam step (rad), the parameter vector, the confirmation
        hits, the maximum speed and direction ε (m/s), the sonar grid's region of each
        beam, the sonar cones' beam bounds, and the sonar-to-laser match distance (m),
        jump σs and range noise (relative, floor m)."""
        cfg = self.config
        return (
            self.beam_cos,
            self.beam_sin,
            self._sonar_cos,
            self._sonar_sin,
            self.beam_step_rad,
            self.params,
            cfg.track_confirm_hits,
            cfg.max_speed_mps,
            cfg.direction_epsilon_mps,
            self._beam_region,
            self._cone_bounds,
            cfg.sonar_ego_match_m,
            cfg.segment_jump_sigmas,
            cfg.range_noise_rel,
            cfg.range_noise_floor_m,
        )

    @property
    def state(self) -> tuple[np.ndarray, ...]:
        """The arrays ``track_step`` updates in place, in its order (``STATE_FIELDS``):
        poses, the last scan's segments, the tracks, the sonar filters, and the table's
        scratch rows."""
        return tuple(getattr(self, name) for name in STATE_FIELDS)

    def step(
        self,
        t_s: float,
        dt_s: float,
        odometry: tuple[float, float] | None,
        laser_new: bool,
        sonar_new: bool,
        readings: np.ndarray,
        valid: np.ndarray,
        rates: np.ndarray,
        speeds: np.ndarray,
        moving: np.ndarray,
        wanted_speed: np.ndarray,
    ) -> tuple[np.ndarray, np.ndarray, tuple[np.ndarray, np.ndarray]]:
        """One reading, in one compiled call (``track_step``): dead-reckon the pose over
        ``dt_s``, take the laser scan and the sonar reading where they are new, and write
        every reading channel's kinematics.

        Args:
            t_s: the reading's time (s); dt_s: the time since the previous reading (s).
            odometry: the robot's ``(linear m/s, angular rad/s)`` at this reading (None:
                standing still); the motion over the interval uses the mean of this and the
                previous reading's velocities (``advance_pose``).
            laser_new, sonar_new: whether the laser scan and the sonar reading are new scans
                (a held reading is not tracked twice).
            readings, valid: ``(188,)`` clipped readings (m) and echo flags (8 front sonars,
                then 180 beams; the laser's are clipped to its maximum range).
            rates, speeds: ``(188,)`` outputs (m/s); moving: ``(188,)`` bool output
                (``track_regions.track_channels``).
            wanted_speed: ``(2,)`` the speeds ``[lo, hi]`` a speed goal asks for (m/s),
                ``[inf, inf]`` without one.

        Returns:
            ``(8,)`` int64 the track slot behind each front sonar's channel (−1 for none),
            ``(8,)`` the probability that the speed goal holds at that track (−1 where not
            judged so: ``track_regions.track_channels``), and the live tracks in the robot
            frame: rows ``(n, 11)`` (columns ``TRACK_TABLE_FIELDS``, slot order) and
            covariances ``(n, 4, 4)``, new arrays (``table_from_rows`` makes them a
            ``TrackTable``).
        """
        linear, angular = (0.0, 0.0) if odometry is None else odometry
        region_slot = np.empty(FRONT_SONARS, np.int64)
        speed_probability = np.empty(FRONT_SONARS)
        n = track_step(
            t_s,
            dt_s,
            linear,
            angular,
            laser_new,
            sonar_new,
            readings,
            valid,
            wanted_speed,
            *self.constants,
            *self.state,
            rates,
            speeds,
            moving,
            region_slot,
            speed_probability,
        )
        return region_slot, speed_probability, (self._rows[:n].copy(), self._covariance[:n].copy())


@njit(cache=True)
def advance_pose(dt_s, linear, angular, pose, odometry, previous_weight):
    """Dead-reckon ``pose`` ``(3,)`` (x, y in m, heading in rad; odometry frame) over ``dt_s``
    seconds, in place, given the robot's velocity at this reading (``linear`` m/s,
    ``angular`` rad/s); ``odometry`` ``(3,)`` holds the previous reading's velocity (and 1.0
    once there is one) and becomes this one's.

    The motion over the interval uses ``previous_weight`` times the previous reading's
    velocity plus the rest of this one's (``AttentionConfig.odometry_previous_weight``: 0.5,
    the trapezoid rule, is exact while the velocity ramps linearly and continuously; a
    simulator that moves the robot in sub-steps at their starting velocities needs more
    weight on the previous); the first reading's interval uses its own.
    """
    before_linear, before_angular = linear, angular
    if odometry[2] != 0.0:
        before_linear, before_angular = odometry[0], odometry[1]
    odometry[0], odometry[1], odometry[2] = linear, angular, 1.0
    now_weight = 1.0 - previous_weight
    mean_linear = previous_weight * before_linear + now_weight * linear
    mean_angular = previous_weight * before_angular + now_weight * angular
    if dt_s <= 0.0 or (mean_linear == 0.0 and mean_angular == 0.0):
        return
    dx, dy, dtheta = planar_displacement(mean_linear, mean_angular, dt_s)
    x, y, heading = pose[0], pose[1], pose[2]
    c, s = math.cos(heading), math.sin(heading)
    pose[0], pose[1], pose[2] = x + c * dx - s * dy, y + s * dx + c * dy, heading + dtheta


@njit(cache=True)
def track_step(
    t_s,
    dt_s,
    linear,
    angular,
    laser_new,
    sonar_new,
    readings,
    valid,
    wanted_speed,
    beam_cos,
    beam_sin,
    sonar_cos,
    sonar_sin,
    beam_step_rad,
    params,
    confirm_hits,
    max_speed,
    epsilon,
    beam_region,
    cone_bounds,
    match_m,
    match_sigmas,
    noise_rel,
    noise_floor_m,
    pose,
    odometry,
    sonar_pose,
    bounds,
    segments,
    cv_x,
    cv_P,
    static_x,
    static_P,
    p_moving,
    alive,
    ids,
    hits,
    misses,
    born_s,
    filter_t,
    seen_s,
    extent_m,
    segment_of,
    counters,
    scan_history,
    centroid_history,
    centroid_count,
    sonar_x,
    sonar_P,
    sonar_hits,
    sonar_t,
    rows,
    covariance,
    rates,
    speeds,
    moving,
    region_slot,
    speed_probability,
):
    """``Tracker.step``: ``advance_pose``, ``track_scan`` of ``readings[8:]`` when ``laser_new``
    (then ``free_space_step``, ``onset_velocity`` and ``onset.ramp_onset`` (with the change test), each unless the
    configuration turns it off), ``sonar_filters`` of
    ``readings[:8]`` when ``sonar_new``, ``track_channels`` and
    ``track_table`` (into ``rows``, ``covariance``); returns the number of table rows.

    The arguments are the step's inputs (``Tracker.step``'s), ``Tracker.constants``,
    ``Tracker.state`` and the outputs ``rates``, ``speeds``, ``moving``, ``region_slot``,
    ``speed_probability``."""
    advance_pose(dt_s, linear, angular, pose, odometry, params[_ODOMETRY_WEIGHT])
    n_sonar = region_slot.shape[0]
    if laser_new:
        onsets = params[_ONSET_SIGMA] > 0.0 or params[_READY_SIGMA] > 0.0 or params[_RUNAWAY] > 0.0
        before = p_moving.copy() if onsets else p_moving
        track_scan(
            t_s,
            pose,
            readings[n_sonar:],
            beam_cos,
            beam_sin,
            beam_step_rad,
            params,
            bounds,
            segments,
            cv_x,
            cv_P,
            static_x,
            static_P,
            p_moving,
            alive,
            ids,
            hits,
            misses,
            born_s,
            filter_t,
            seen_s,
            extent_m,
            segment_of,
            counters,
            centroid_history,
            centroid_count,
        )
        if params[_FS_ON] != 0.0:
            free_space_step(
                t_s,
                pose,
                readings[n_sonar:],
                beam_step_rad,
                params,
                bounds,
                counters,
                scan_history,
                segment_of,
                static_x,
                alive,
                born_s,
                p_moving,
                cv_x,
            )
        if onsets:
            onset_velocity(
                t_s,
                params[_ONSET_SIGMA],
                params[_READY_SIGMA],
                params[_RUNAWAY],
                before,
                cv_x,
                cv_P,
                p_moving,
                alive,
                born_s,
            )
        if params[_ONSET_LOG_RATIO] > 0.0 or params[_CHANGE_LOG_RATIO] > 0.0:
            ramp_onset(
                t_s,
                params[_ONSET_LOG_RATIO],
                params[_CHANGE_LOG_RATIO],
                params[_RUNAWAY],
                centroid_history,
                centroid_count,
                cv_x,
                cv_P,
                p_moving,
                alive,
            )
    if sonar_new:
        sonar_filters(
            t_s,
            pose,
            sonar_pose,
            readings[:n_sonar],
            valid[:n_sonar],
            sonar_cos,
            sonar_sin,
            params,
            sonar_x,
            sonar_P,
            sonar_hits,
            sonar_t,
        )
    track_channels(
        t_s,
        pose,
        confirm_hits,
        max_speed,
        epsilon,
        wanted_speed,
        beam_step_rad,
        beam_region,
        cone_bounds,
        match_m,
        match_sigmas,
        noise_rel,
        noise_floor_m,
        params[_GOAL_PROBABILITY] != 0.0,
        readings,
        valid,
        cv_x,
        cv_P,
        p_moving,
        alive,
        hits,
        filter_t,
        segment_of,
        bounds,
        sonar_x,
        sonar_hits,
        rates,
        speeds,
        moving,
        region_slot,
        speed_probability,
    )
    return track_table(
        t_s,
        pose,
        confirm_hits,
        beam_step_rad,
        beam_region,
        cv_x,
        cv_P,
        p_moving,
        alive,
        ids,
        hits,
        born_s,
        filter_t,
        rows,
        covariance,
    )


@njit(cache=True)
def onset_velocity(t_s, onset_sigma_mps, standing_sigma_mps, runaway_mps, before, cv_x, cv_P, p_moving, alive, born_s):
    """Keep each track's constant-velocity filter ready for a start, in place (``cv_P``
    ``(K, 4, 4)``), after the scan at ``t_s`` (s) has set the probabilities of moving
    (``before`` ``(K,)`` → ``p_moving`` ``(K,)``, by the filters and by free-space evidence).

    - A track judged standing (``p_moving ≤ MOVING_PROBABILITY``) keeps a velocity variance
      of at least ``standing_sigma_mps²`` per axis: its moving hypothesis stays open to a
      start. Learnt on a standing body, the variance would shrink until the filter, sure the
      velocity is 0, explained a start no better than the static filter does.
    - A track whose velocity estimate ``cv_x[k, 2:4]`` exceeds ``runaway_mps`` (faster than
      any body the scene holds: the track was matched to another body's segment, or to
      structure whose visible part slid along it as the robot drove) restarts standing: its
      velocity 0 with the started track's variances below, its probability of moving
      ``_MOTION_PRIOR`` (not moving until the next scans say so).
    - A track older than this scan whose probability rose past ``MOVING_PROBABILITY`` from at
      most ``ONSET_STANDING_PROBABILITY`` has started: its velocity variance restarts at
      ``onset_sigma_mps²`` per axis and its position variance grows by
      ``ONSET_POSITION_VAR_M2`` (m²), both uncorrelated, so the
      next scans set its position and velocity afresh, as a new track's, instead of
      following the start slowly and overshooting once its lag is absorbed.

    A σ of 0 turns that rule off.
    """
    onset_variance, standing_variance = onset_sigma_mps * onset_sigma_mps, standing_sigma_mps * standing_sigma_mps
    for k in range(alive.shape[0]):
        if not alive[k]:
            continue
        if runaway_mps > 0.0 and math.hypot(cv_x[k, 2], cv_x[k, 3]) > runaway_mps:
            cv_x[k, 2], cv_x[k, 3] = 0.0, 0.0
            p_moving[k] = _MOTION_PRIOR
            _restart_velocity(k, onset_variance, cv_P)
            continue
        if p_moving[k] <= MOVING_PROBABILITY:
            for i in range(2, 4):
                cv_P[k, i, i] = max(cv_P[k, i, i], standing_variance)
            continue
        if onset_variance > 0.0 and born_s[k] != t_s and before[k] <= ONSET_STANDING_PROBABILITY:
            _restart_velocity(k, onset_variance, cv_P)


@njit(cache=True, inline="always")
def _restart_velocity(k, variance, cv_P):
    """Track ``k``'s velocity variance becomes ``variance`` per axis (m²/s²), uncorrelated with its
    position, whose variance grows by ``ONSET_POSITION_VAR_M2`` (m²); nothing without a variance."""
    if variance == 0.0:
        return
    for i in range(2):
        for j in range(2):
            cv_P[k, i, j + 2] = 0.0
            cv_P[k, j + 2, i] = 0.0
            cv_P[k, i + 2, j + 2] = variance if i == j else 0.0
        cv_P[k, i, i] += ONSET_POSITION_VAR_M2


@njit(cache=True)
def free_space_step(
    t_s,
    robot_pose,
    ranges_m,
    beam_step_rad,
    params,
    bounds,
    counters,
    history,
    segment_of,
    static_x,
    alive,
    born_s,
    p_moving,
    cv_x,
):
    """Weigh the tracks' probabilities of moving by the free-space evidence of the laser scan
    ``ranges_m`` ``(n,)`` just tracked (``track_scan``'s segments ``bounds``, ``counters[1]`` of
    them), then remember the scan (``tracking.free_space``; the history's rows are
    ``Tracker.scan_history``'s, its counters ``counters[2:4]``). The laser's pose is the
    robot's ``robot_pose`` ``(3,)`` with the mounting point; ``cv_x`` ``(K, 4)`` are the tracks'
    constant-velocity states, by which a silent track's motion is judged detectable or not."""
    n = ranges_m.shape[0]
    c, s = math.cos(robot_pose[2]), math.sin(robot_pose[2])
    laser = np.empty(3)
    laser[0] = robot_pose[0] + c * params[_MOUNT_X] - s * params[_MOUNT_Y]
    laser[1] = robot_pose[1] + s * params[_MOUNT_X] + c * params[_MOUNT_Y]
    laser[2] = robot_pose[2]
    evidence_params = np.array(
        [
            -0.5 * beam_step_rad * n,
            beam_step_rad,
            params[_NO_ECHO],
            params[_NOISE_REL],
            params[_NOISE_FLOOR],
            free_space.MARGIN_M,
            free_space.WIDTH_M,
        ]
    )
    times, poses, past, history_counters = history[:, 0], history[:, 1:4], history[:, 4:], counters[2:4]
    lags = params[_FS_LAGS : _FS_LAGS + int(params[_FS_N_LAGS])]
    appeared = np.empty(n)
    flags = np.empty(n, np.bool_)
    wanted = np.zeros(n, np.bool_)  # the beams of the segments the tracks matched: the only ones weighed
    for k in range(alive.shape[0]):
        m = segment_of[k]
        if alive[k] and m >= 0:
            wanted[bounds[m, 0] : bounds[m, 1]] = True
    free_space.scan_evidence(
        t_s,
        ranges_m,
        laser,
        lags,
        times,
        poses,
        past,
        history_counters,
        evidence_params,
        wanted,
        free_space.BEAM_SIGMAS,
        appeared,
    )
    free_space.evidence_runs(appeared, free_space.BEAM_SIGMAS, params[_FS_RUN_SIGMAS], free_space.MIN_BEAMS, flags)
    shares = np.zeros(bounds.shape[0])
    free_space.segment_evidence(flags, bounds, counters[1], shares)
    weights = np.array(
        [
            free_space.MIN_SHARE,
            params[_FS_RUN_SIGMAS],
            params[_FS_BORN_MOVING],
            params[_FS_EVIDENCE],
            params[_FS_NONE],
            MOTION_FLOOR,
        ]
    )
    free_space.weigh_motion(
        t_s,
        shares,
        ranges_m,
        laser,
        evidence_params,
        weights,
        segment_of,
        static_x,
        alive,
        born_s,
        p_moving,
        cv_x,
        lags.max(),
    )
    free_space.remember_scan(t_s, ranges_m, laser, params[_FS_SPACING], times, poses, past, history_counters)


@njit(cache=True)
def sonar_filters(t_s, pose, sonar_pose, readings_m, valid, sonar_cos, sonar_sin, params, x, P, hits, filter_t):
    """One reading of each front sonar into its ``(r, ṙ)`` range/rate filter, in place.

    ``readings_m`` ``(8,)`` (m) and ``valid`` ``(8,)`` bool (a sonar without an echo
    restarts) taken at ``t_s`` (s). The robot's own motion since the previous reading is
    taken out first, as for an echo on the sonar's axis (docs/model.md §3's point model
    ``−(dx cos θ + dy sin θ)``); ``sonar_pose`` ``(3,)``, the pose of the previous reading,
    becomes ``pose``."""
    dx_world, dy_world = pose[0] - sonar_pose[0], pose[1] - sonar_pose[1]
    c, s = math.cos(sonar_pose[2]), math.sin(sonar_pose[2])
    dx, dy = c * dx_world + s * dy_world, -s * dx_world + c * dy_world  # in the previous robot frame
    for j in range(x.shape[0]):
        if not valid[j]:
            hits[j] = 0
            continue
        sigma = max(params[_NOISE_REL] * readings_m[j], params[_NOISE_FLOOR])
        if t_s - filter_t[j] > params[_COAST]:
            hits[j] = 0  # too long ago to predict from
        if hits[j] == 0:
            x[j, 0], x[j, 1] = readings_m[j], 0.0
            P[j, 0, 0], P[j, 0, 1], P[j, 1, 0] = sigma * sigma, 0.0, 0.0
            P[j, 1, 1] = params[_SPEED_SIGMA] ** 2
        else:
            x[j, 0] -= dx * sonar_cos[j] + dy * sonar_sin[j]
            rate_predict(x[j], P[j], t_s - filter_t[j], params[_SONAR_Q])
            rate_update(x[j], P[j], readings_m[j], sigma * sigma)
        hits[j] += 1
        filter_t[j] = t_s
    sonar_pose[:] = pose


@njit(cache=True)
def track_scan(
    t_s,
    robot_pose,
    ranges_m,
    cos_b,
    sin_b,
    beam_step_rad,
    params,
    bounds,
    segments,
    cv_x,
    cv_P,
    static_x,
    static_P,
    p_moving,
    alive,
    ids,
    hits,
    misses,
    born_s,
    filter_t,
    seen_s,
    extent_m,
    segment_of,
    counters,
    centroid_history,
    centroid_count,
):
    """One laser scan into the tracks, in place (the arrays of ``Tracker``).

    1. Segment the scan and measure each segment (laser frame); look for bodies standing
       in front of static structure, which become segments of their own
       (``segmentation.split_foreground``); then move the candidates' measurements into
       the odometry frame with the laser's pose there (``robot_pose`` ``(3,)`` and the
       laser's mounting point).
    2. Delete the tracks unseen for more than ``params[_COAST]`` seconds; predict the
       others to ``t_s``.
    3. Cost of each (track, candidate) pair: the squared Mahalanobis distance of the
       candidate from the track's predicted position; assign by least total cost with
       the gate ``params[_GATE]`` (``association.gated_assignment``).
    4. Update matched tracks (both filters, then the motion probability; with
       ``track_edge_keeps_motion``, a segment cut by the field of view's edge leaves the
       probability as it was: the visible part of a body or wall slides as the edge sweeps
       it, which the filters would take for motion; with ``track_occlusion_keeps_motion``, so
       does a segment with an end hidden behind a nearer echo, whose visible part slides
       as the body in front moves). Delete an
       unmatched tentative track at once. An unmatched confirmed track where the laser
       should have seen it (in the field of view, not behind a nearer echo) looks for
       its body where it expects it if it moves (``segmentation.carve_body``: it may
       have merged with a wall) and updates from it inside the gate; else it counts a
       miss. It is deleted after ``params[_DELETE]`` misses in a row, or once it has had
       no segment of its own for ``params[_COAST]`` seconds (hidden bodies coast, merged
       ones follow their carved measurements, meanwhile). A matched track's centroid goes
       into its buffer for the start and change tests, when either is on (``onset.remember_centroid``; a
       segment cut by the edge or hidden at an end clears it instead, and so does a miss).
    5. Give each unmatched candidate with enough beams a new track in a free slot (none
       when full); its buffer starts with its centroid.
    """
    no_echo = params[_NO_ECHO]
    buffered = params[_ONSET_LOG_RATIO] != 0.0 or params[_CHANGE_LOG_RATIO] != 0.0  # the centroid tests' buffers
    n_segments = segment_scan(
        ranges_m, no_echo, params[_NOISE_REL], params[_NOISE_FLOOR], params[_JUMP], params[_JUMP_SIGMAS], bounds
    )
    measure_segments(
        ranges_m,
        cos_b,
        sin_b,
        beam_step_rad,
        no_echo,
        bounds,
        n_segments,
        params[_NOISE_REL],
        params[_NOISE_FLOOR],
        params[_SURFACE],
        params[_MAX_EXTENT],
        int(params[_MIN_BEAMS]),
        segments,
    )
    n_segments = split_foreground(
        ranges_m,
        cos_b,
        sin_b,
        beam_step_rad,
        no_echo,
        bounds,
        n_segments,
        params[_NOISE_REL],
        params[_NOISE_FLOOR],
        params[_SURFACE],
        params[_MAX_EXTENT],
        int(params[_MIN_BEAMS]),
        int(params[_FG_FLANK]),
        params[_FG_SIGMAS],
        params[_FG_MARGIN],
        params[_FG_EDGE],
        segments,
    )
    counters[1] = n_segments
    c, s = math.cos(robot_pose[2]), math.sin(robot_pose[2])
    pose = np.empty(3)  # the laser's
    pose[0] = robot_pose[0] + c * params[_MOUNT_X] - s * params[_MOUNT_Y]
    pose[1] = robot_pose[1] + s * params[_MOUNT_X] + c * params[_MOUNT_Y]
    pose[2] = robot_pose[2]
    candidate = np.empty(n_segments, np.int64)
    z = np.empty((n_segments, 2))
    r = np.empty((n_segments, 2, 2))
    n_candidates = 0
    for m in range(n_segments):
        if segments[m, _CANDIDATE] == STRUCTURE:
            continue
        candidate[n_candidates] = m
        _to_odometry(pose, c, s, segments[m], z[n_candidates], r[n_candidates])
        n_candidates += 1
    capacity = alive.shape[0]
    rows = np.empty(capacity, np.int64)
    dts = np.zeros(capacity)
    n_rows = 0
    for k in range(capacity):
        segment_of[k] = -1
        if alive[k] and t_s - seen_s[k] > params[_COAST]:
            alive[k] = False  # unseen for too long to predict
        if alive[k]:
            dt = t_s - filter_t[k]
            if dt > 0.0:
                cv_predict(cv_x[k], cv_P[k], dt, params[_Q])
                static_predict(static_x[k], static_P[k], dt, params[_DRIFT])
                filter_t[k] = t_s
            dts[k] = dt
            rows[n_rows] = k
            n_rows += 1
    distance2 = np.empty((n_rows, n_candidates))
    log_det = np.empty((n_rows, n_candidates))
    for a in range(n_rows):
        k = rows[a]
        for b in range(n_candidates):
            distance2[a, b], log_det[a, b] = _mahalanobis2(cv_x[k], cv_P[k], z[b], r[b])
    assignment = np.empty(n_rows, np.int64)
    gated_assignment(distance2, log_det, params[_GATE], assignment)
    taken = np.zeros(n_candidates, np.bool_)
    carved = np.empty(len(SEGMENT_FIELDS))
    carved_z, carved_r = np.empty(2), np.empty((2, 2))
    for a in range(n_rows):
        k = rows[a]
        b = assignment[a]
        if b >= 0:
            p_before = p_moving[k]
            _update(
                k,
                dts[k],
                z[b],
                r[b],
                segments[candidate[b], _EXTENT],
                params,
                cv_x,
                cv_P,
                static_x,
                static_P,
                p_moving,
                hits,
                misses,
                extent_m,
            )
            m = candidate[b]
            cut = segments[m, _START] == 0 or segments[m, _STOP] == ranges_m.shape[0]
            occluded = _occluded(ranges_m, segments[m, _START], segments[m, _STOP])
            if params[_EDGE_KEEPS] != 0.0 and cut:
                p_moving[k] = p_before  # cut by the field of view's edge: where the body is, only in part
            elif params[_OCCLUSION_KEEPS] != 0.0 and occluded:
                p_moving[k] = p_before  # partly hidden behind a nearer body: its visible part slides as that moves
            if buffered and (cut or occluded):
                centroid_count[k] = 0  # a part of the body: its centroid slides with the view, not with the body
            elif buffered:
                remember_centroid(
                    k, t_s, z[b], r[b], segments[m, _EXTENT], params[_SURFACE], pose, centroid_history, centroid_count
                )
            seen_s[k] = t_s
            segment_of[k] = m
            taken[b] = True
            continue
        if hits[k] < params[_CONFIRM]:
            alive[k] = False
            continue
        hidden = _hidden(cv_x[k], pose, ranges_m, beam_step_rad, 0.5 * params[_MAX_EXTENT])
        found = False
        if not hidden and p_moving[k] > _CARVE_PROBABILITY:
            # a moving body merged into a longer segment? look for it where the track expects it
            dx, dy = cv_x[k, 0] - pose[0], cv_x[k, 1] - pose[1]
            found = carve_body(
                ranges_m,
                cos_b,
                sin_b,
                beam_step_rad,
                no_echo,
                c * dx + s * dy,
                -s * dx + c * dy,
                extent_m[k],
                params[_NOISE_REL],
                params[_NOISE_FLOOR],
                params[_JUMP],
                params[_JUMP_SIGMAS],
                params[_SURFACE],
                int(params[_MIN_BEAMS]),
                carved,
            )
            if found:
                _to_odometry(pose, c, s, carved, carved_z, carved_r)
                found = _mahalanobis2(cv_x[k], cv_P[k], carved_z, carved_r)[0] < params[_GATE]
            if found:  # not a segment of its own: the track still dies after track_coast_s
                _update(
                    k,
                    dts[k],
                    carved_z,
                    carved_r,
                    extent_m[k],
                    params,
                    cv_x,
                    cv_P,
                    static_x,
                    static_P,
                    p_moving,
                    hits,
                    misses,
                    extent_m,
                )
        if not (hidden or found):
            misses[k] += 1
            centroid_count[k] = 0  # in view but not matched: its segment is unstable, its centroids with it
        if misses[k] >= params[_DELETE] or t_s - seen_s[k] > params[_COAST]:
            alive[k] = False
    slot = 0
    for b in range(n_candidates):
        if taken[b] or segments[candidate[b], _CANDIDATE] != TRACKABLE:
            continue
        while slot < capacity and alive[slot]:
            slot += 1
        if slot == capacity:
            break
        _birth(
            slot,
            t_s,
            z[b],
            r[b],
            params,
            cv_x,
            cv_P,
            static_x,
            static_P,
            p_moving,
            alive,
            ids,
            hits,
            misses,
            born_s,
            filter_t,
            counters,
        )
        seen_s[slot] = t_s
        extent_m[slot] = segments[candidate[b], _EXTENT]
        segment_of[slot] = candidate[b]
        centroid_count[slot] = 0
        if buffered:
            remember_centroid(
                slot,
                t_s,
                z[b],
                r[b],
                segments[candidate[b], _EXTENT],
                params[_SURFACE],
                pose,
                centroid_history,
                centroid_count,
            )


@njit(cache=True, inline="always")
def _to_odometry(pose, c, s, row, z, r):
    """A measurement row (``SEGMENT_FIELDS``, in the frame of ``pose``) into the odometry frame: position
    ``z`` ``(2,)`` (m) and covariance ``r`` ``(2, 2)`` = Rot R Rotᵀ; ``c, s`` = cos, sin of the heading."""
    x, y = row[_X], row[_Y]
    z[0], z[1] = pose[0] + c * x - s * y, pose[1] + s * x + c * y
    rxx, rxy, ryy = row[_RXX], row[_RXY], row[_RYY]
    r[0, 0] = c * c * rxx - 2.0 * c * s * rxy + s * s * ryy
    r[0, 1] = c * s * (rxx - ryy) + (c * c - s * s) * rxy
    r[1, 0] = r[0, 1]
    r[1, 1] = s * s * rxx + 2.0 * c * s * rxy + c * c * ryy


@njit(cache=True, inline="always")
def _mahalanobis2(x, P, z, r):
    """Squared Mahalanobis distance of the measurement ``z`` (covariance ``r``) from the
    predicted position of the state ``x`` (covariance ``P``), and the log-determinant of
    the innovation covariance (log m⁴)."""
    s00, s01, s11 = P[0, 0] + r[0, 0], P[0, 1] + r[0, 1], P[1, 1] + r[1, 1]
    y0, y1 = z[0] - x[0], z[1] - x[1]
    det = s00 * s11 - s01 * s01
    return (s11 * y0 * y0 - 2.0 * s01 * y0 * y1 + s00 * y1 * y1) / det, math.log(det)


@njit(cache=True, inline="always")
def _update(k, dt_s, z, r, extent, params, cv_x, cv_P, static_x, static_P, p_moving, hits, misses, extent_m):
    """Update track ``k`` with the measurement ``z`` (odometry frame, covariance ``r``) of a
    body ``extent`` metres across: both filters, the motion probability (each filter's
    likelihood with a share of outliers, ``params[_OUTLIER_SHARE]`` > 0:
    ``kalman.robust_log_likelihood``), the counters, and the track's extent (an exponential
    average over matches)."""
    outliers = params[_OUTLIER_SHARE]
    if outliers > 0.0:
        d2_moving = _mahalanobis2(cv_x[k], cv_P[k], z, r)[0]
        d2_static = _mahalanobis2(static_x[k], static_P[k], z, r)[0]
    moving = cv_update(cv_x[k], cv_P[k], z[0], z[1], r)
    static = static_update(static_x[k], static_P[k], z[0], z[1], r)
    if outliers > 0.0:
        moving = robust_log_likelihood(moving, d2_moving, outliers, params[_OUTLIER_SIGMAS])
        static = robust_log_likelihood(static, d2_static, outliers, params[_OUTLIER_SIGMAS])
    switch = 1.0 - math.exp(-params[_SWITCH_RATE] * dt_s)
    p_moving[k] = motion_probability(p_moving[k], moving, static, switch, MOTION_FLOOR)
    hits[k] += 1
    misses[k] = 0
    extent_m[k] += _EXTENT_SMOOTHING * (extent - extent_m[k])


@njit(cache=True, inline="always")
def _occluded(ranges_m, start, stop):
    """Whether the segment of the beams ``start <= i < stop`` has an end hidden behind a nearer
    echo: the beam beyond that end reads nearer than the end's own beam."""
    first, last = int(start), int(stop) - 1
    return (first > 0 and ranges_m[first - 1] < ranges_m[first]) or (
        last < ranges_m.shape[0] - 1 and ranges_m[last + 1] < ranges_m[last]
    )


@njit(cache=True, inline="always")
def _hidden(state, pose, ranges_m, beam_step_rad, margin_m):
    """Whether the laser at ``pose`` could not have seen a track at ``state[:2]`` (odometry
    frame, m): outside its field of view, or behind an echo more than ``margin_m`` nearer."""
    dx, dy = state[0] - pose[0], state[1] - pose[1]
    c, s = math.cos(pose[2]), math.sin(pose[2])
    x, y = c * dx + s * dy, -s * dx + c * dy
    bearing = math.atan2(y, x)
    half_fov = 0.5 * beam_step_rad * ranges_m.shape[0]
    if abs(bearing) >= half_fov:
        return True
    beam = min(int((bearing + half_fov) / beam_step_rad), ranges_m.shape[0] - 1)
    return ranges_m[beam] < math.hypot(x, y) - margin_m


@njit(cache=True, inline="always")
def _birth(
    k, t_s, z, r, params, cv_x, cv_P, static_x, static_P, p_moving, alive, ids, hits, misses, born_s, filter_t, counters
):
    """Start track slot ``k`` at the measurement ``z`` ``(2,)`` with covariance ``r`` ``(2, 2)``."""
    position_var = params[_POSITION_SIGMA] ** 2
    cv_x[k, 0], cv_x[k, 1], cv_x[k, 2], cv_x[k, 3] = z[0], z[1], 0.0, 0.0
    static_x[k, 0], static_x[k, 1] = z[0], z[1]
    cv_P[k] = 0.0
    for i in range(2):
        for j in range(2):
            cv_P[k, i, j] = r[i, j]
            static_P[k, i, j] = r[i, j]
        cv_P[k, i, i] += position_var
        static_P[k, i, i] += position_var
        cv_P[k, i + 2, i + 2] = params[_SPEED_SIGMA] ** 2
    p_moving[k] = _MOTION_PRIOR
    alive[k] = True
    ids[k] = counters[0]
    counters[0] += 1
    hits[k] = 1
    misses[k] = 0
    born_s[k] = t_s
    filter_t[k] = t_s
