"""Configuration of the attentional model (docs/model.md, every section).

- ``AttentionConfig``: frozen dataclass holding every parameter of the model, with its
  default and unit; validated at construction.
- ``ATTENTIVE_STATES``: the named levels of the Global Attentive State (gain ``g``).
- ``MAP_NAMES``: the six feature maps, in order, with their aliases.
- ``parse_state``: a named level or a positive float → the gain ``g``.
- ``LASER_PROFILES`` / ``profile_config``: named sets of tracker values for a kind of laser
  and target (``indoor-people``: a Hokuyo/SICK indoor laser and walking people);
  ``configured``: a profile and a JSON object of fields over the defaults.
- ``MODEL_VERSIONS`` / ``check_model_version`` / ``version_fields``: the versions of the
  defaults, a version checked against them, and the fields that rebuild an earlier one
  (``VERSION_0_FIELDS``, ``VERSION_1_FIELDS``, ``VERSION_2_FIELDS``).

Units: seconds (s), metres (m), metres per second (m/s), radians (rad) unless a field
name says otherwise (``_deg``).
"""

from __future__ import annotations

import dataclasses
import json
import math
import numbers
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType
from typing import Any

__all__ = [
    "AttentionConfig",
    "ATTENTIVE_STATES",
    "MAP_NAMES",
    "MAP_ALIASES",
    "BOTTOM_UP_MAPS",
    "TOP_DOWN_MAPS",
    "GRIDS",
    "EGO_MOTION_MODES",
    "SONAR_EGO_MODELS",
    "KINEMATICS_MODES",
    "MAX_MAP_WEIGHT",
    "MAX_FREE_SPACE_LAGS",
    "is_map_weight",
    "parse_state",
    "LASER_PROFILES",
    "MODEL_VERSIONS",
    "check_model_version",
    "VERSION_0_FIELDS",
    "VERSION_1_FIELDS",
    "VERSION_2_FIELDS",
    "version_fields",
    "profile_config",
    "configured",
]

#: Global Attentive State levels (docs/model.md §7): gain ``g`` multiplying the saliency map.
ATTENTIVE_STATES: Mapping[str, float] = {"drowsy": 0.5, "alert": 1.0, "vigilant": 1.5}

#: The largest weight a feature map may have: any larger and the combined map's sums could
#: leave float range (a weight of 1e308 made C, L and saliency NaN).
MAX_MAP_WEIGHT = 1e6
#: The most past scans a laser scan is compared with for free-space evidence.
MAX_FREE_SPACE_LAGS = 8

#: Versions of the model's defaults, the last one current. The attended environments' ids
#: carry it (``AttentiveRescueFocus-v1``), and a run's ``spec.json`` records it, so that a
#: change of defaults never silently changes what a trained policy sees.
#:
#: - 0 (until 2026-12-06): the tracker without the motion stages, ``VERSION_0_FIELDS``.
#: - 1 (until 2026-12-07): free-space evidence, the tracker's start rules and its
#:   field-of-view edge rule on, and, in the simulator, the dead reckoning of its physics
#:   sub-steps (docs/notes/2026-12-06-motion-by-default.md); ``VERSION_1_FIELDS``.
#: - 2 (until 2026-12-07): the occlusion rule on (``track_occlusion_keeps_motion``;
#:   docs/notes/2026-12-07-phantoms-behind-passing-bodies.md); ``VERSION_2_FIELDS``.
#: - 3: the start test on, at 6 nats (``track_onset_log_ratio``;
#:   docs/notes/2026-12-07-a-start-test.md).
MODEL_VERSIONS = (0, 1, 2, 3)


def check_model_version(version: Any, name: str = "model version") -> int:
    """``version`` if it is one of ``MODEL_VERSIONS`` (an int, not a bool or a float); else
    ``ValueError`` naming ``name`` (how the caller calls it), the value and the allowed ones."""
    if type(version) is not int or version not in MODEL_VERSIONS:
        raise ValueError(f"unknown {name} {version!r}; allowed: {list(MODEL_VERSIONS)}")
    return version


#: The fields whose defaults version 3 changed, with their version 2 values: as an
#: ``AttentionConfig`` override, they rebuild version 2's defaults.
VERSION_2_FIELDS: Mapping[str, Any] = MappingProxyType({"track_onset_log_ratio": 0.0})
#: The fields whose defaults versions 2 and 3 changed, with their version 1 values: as an
#: ``AttentionConfig`` override, they rebuild version 1's defaults.
VERSION_1_FIELDS: Mapping[str, Any] = MappingProxyType({"track_occlusion_keeps_motion": False, **VERSION_2_FIELDS})
#: The fields whose defaults versions 1 to 3 changed, with their version 0 values: as an
#: ``AttentionConfig`` override, they rebuild version 0's defaults.
VERSION_0_FIELDS: Mapping[str, Any] = MappingProxyType(
    {
        "free_space_evidence": False,
        "track_onset_speed_sigma_mps": 0.0,
        "track_standing_speed_sigma_mps": 0.0,
        "track_runaway_speed_mps": 0.0,
        "track_edge_keeps_motion": False,
        **VERSION_1_FIELDS,
    }
)
#: Each earlier version → the overrides that rebuild its defaults from the current ones.
_EARLIER_FIELDS = {0: VERSION_0_FIELDS, 1: VERSION_1_FIELDS, 2: VERSION_2_FIELDS}


def version_fields(version: int) -> dict[str, Any]:
    """The ``AttentionConfig`` fields that rebuild model ``version``'s defaults from the
    current ones (none for the current version).

    Raises:
        ValueError: for an unknown version (listing the known ones).
    """
    return dict(_EARLIER_FIELDS.get(check_model_version(version), {}))


def is_map_weight(value: Any) -> bool:
    """Whether ``value`` is a feature map's weight: a real number (not a bool) in [0, ``MAX_MAP_WEIGHT``]."""
    return (
        isinstance(value, numbers.Real)
        and not isinstance(value, bool)
        and math.isfinite(value)
        and 0.0 <= value <= MAX_MAP_WEIGHT
    )


#: The six feature maps in the order of the rows of ``F``.
MAP_NAMES: tuple[str, ...] = ("F1", "F2", "F3", "F4", "F5", "F6")
#: Descriptive aliases accepted wherever a map name is.
MAP_ALIASES: Mapping[str, str] = {
    "motion": "F1",
    "direction": "F2",
    "distance": "F3",
    "goal_speed": "F4",
    "goal_direction": "F5",
    "goal_distance": "F6",
}
#: Row indices of the bottom-up (F1–F3) and top-down (F4–F6) maps in ``F``.
BOTTOM_UP_MAPS = (0, 1, 2)
TOP_DOWN_MAPS = (3, 4, 5)

#: Attention grids: "sonar" (J = 8, one region per front sonar) or "laser" (J = 180).
GRIDS = ("sonar", "laser")
#: Ego-motion compensation: "odometry" (default) or None (the paper, literally).
EGO_MOTION_MODES = ("odometry", None)
#: How a sonar reading of a static world is predicted after the robot moved (§3).
SONAR_EGO_MODELS = ("laser", "point")
#: How motion is estimated (§3, §10): "tracker" (objects tracked in the laser scan, the
#: default), "window" (K-sample least-squares range rate), "literal" (the paper's
#: two-sample difference).
KINEMATICS_MODES = ("tracker", "window", "literal")


def parse_state(state: str | float) -> float:
    """The gain ``g`` of a Global Attentive State.

    Args:
        state: a level name of ``ATTENTIVE_STATES`` ("drowsy", "alert", "vigilant") or a
            finite gain > 0.

    Returns:
        The gain ``g`` (dimensionless).

    Raises:
        ValueError: for an unknown name or a gain that is not a finite number > 0.
    """
    if isinstance(state, str):
        try:
            return ATTENTIVE_STATES[state.lower()]
        except KeyError:
            allowed = ", ".join(f"{k!r} ({v:g})" for k, v in ATTENTIVE_STATES.items())
            raise ValueError(f"unknown attentive state {state!r}; allowed: {allowed}, or a gain > 0") from None
    if isinstance(state, bool) or not isinstance(state, (int, float)):
        raise ValueError(f"an attentive state is a level name or a gain > 0, got {state!r}")
    gain = float(state)
    if not (math.isfinite(gain) and gain > 0.0):
        raise ValueError(f"an attentive state gain must be a finite number > 0, got {state!r}")
    return gain


@dataclass(frozen=True)
class AttentionConfig:
    """Every parameter of the attentional model (docs/model.md), with defaults and units.

    Every number is checked when the configuration is built (``ValueError`` naming the
    field, its unit and the allowed range); a setting that must be positive is also at most
    1e6 in its unit, so that no filter or map leaves float range.

    Sensorial memory and kinematics (§2, §3, §10).

    Attributes:
        kinematics: "tracker" (default): objects segmented from each laser scan and
            tracked with a constant-velocity Kalman filter in an odometry-fixed frame,
            sonars filtered for what the laser does not see; "window": the K-sample
            least-squares range rate per reading; "literal": the paper's two-sample
            difference (K = 2).
        memory_window: W, readings kept per observation space (samples, >= 2).
        slope_samples: K, samples of the least-squares range-rate slope (2 <= K <= W);
            K = 2 is the paper's literal two-sample difference.
        max_speed_mps: MAX_SPEED, speeds are clipped to it and F1 is normalised by it.
        direction_epsilon_mps: ε_v, ``|v| <= ε_v`` is labelled static.
        ego_motion: "odometry" compensates the robot's own motion, None reproduces the
            paper (immobile robot).
        sonar_ego_model: how a static world's sonar reading is predicted after a move:
            "laser" (default) from the laser scan re-projected into the new pose and read
            through the sonar cone (right for walls seen obliquely, whose range does not
            change when driving past them); "point" is docs/model.md's ``−v dt cos θ``, exact
            for a point-like echo on the sonar axis only.
        sonar_cone_half_width_deg: half-width of a sonar cone (deg), used by the "laser"
            sonar ego-motion model.
        sonar_ego_match_m: the "laser" model is used for a sonar only while the laser's
            nearest echo in its cone agrees with the sonar's previous reading to within
            this (m); otherwise the sonar sees something the laser does not and the
            "point" model applies.

    Tracker (§10; ``kinematics="tracker"`` only).

    Attributes:
        range_noise_rel: relative standard deviation of a range reading that the filters
            assume (dimensionless; 0.05 = 5 % Gaussian; a uniform ±a noise has σ = a/√3).
        range_noise_floor_m: the smallest range σ assumed for one reading (m).
        segment_jump_m: fixed part of the range jump that breaks a scan segment (m).
        segment_jump_sigmas: range-dependent part of that threshold, in σ of the
            difference of two neighbouring readings (``√2 · range_noise_rel · r``).
        segment_min_beams: segments with fewer beams may update a track but not start
            one (beams).
        max_object_extent_m: segments longer than this (end to end, m) are static
            structure (walls): never tracked, their speed is 0.
        foreground_flank_beams: a run of beams inside static structure that lies nearer
            than the surface around it, with a range jump at both ends, is a body of its
            own (one standing in front of a wall); the surface is the line through this
            many beams on each side of the run (beams; 0 turns the search off).
        foreground_sigmas: how significantly nearer than that surface a run must lie, in
            σ of its depth (from the range noise of its and its flanks' beams).
        foreground_margin_m: the depth a run must exceed beyond that (m).
        foreground_edge_sigmas: how significant the range jump at each end of such a run
            must be (σ): a bend or a corner of one surface has none.
        track_accel_psd_m2ps3: spectral density ``q`` of the white-noise acceleration of
            the constant-velocity model (m²/s³); smaller is smoother, larger follows
            turns sooner.
        track_static_drift_m2ps: how fast the measured centre of a static body may wander
            as the view changes (m²/s), the process noise of the static hypothesis.
        track_switch_rate_hz: how often a body is assumed to start or stop moving (1/s),
            the prior that blurs the probability that a track moves, per second.
        track_position_sigma_m: σ of a new track's position beyond its measurement (m).
        track_initial_speed_sigma_mps: σ of a new track's velocity, per axis (m/s).
        track_surface_sigma_m: σ of where on its surface a segment's centroid lies,
            across the line of sight (m): visible extent and shape change with the view.
        track_gate_chi2: Mahalanobis gate of an association (χ² with 2 degrees of
            freedom; 13.8 keeps 99.9 % of true matches).
        track_confirm_hits: a track counts once it has been matched this many times.
        track_delete_misses: a confirmed track is deleted after this many scans in a row
            in which the laser should have seen it but did not match it.
        track_coast_s: a confirmed track hidden from the laser (outside its field of view
            or behind something nearer) coasts on its velocity for at most this long (s).
        max_tracks: the most tracks kept at once.
        sonar_accel_psd_m2ps3: ``q`` of each front sonar's range/rate filter (m²/s³).
        odometry_previous_weight: the weight of the previous reading's velocity when the
            robot's pose is dead-reckoned over a step (the current one's is 1 minus it; in
            [0, 1]). 0.5, the default, is the trapezoid rule (exact for odometry that ramps
            linearly and continuously: a real robot's). The simulator moves its robot in S
            physics sub-steps (``world.physics_substeps``), each at the velocity it starts
            with, which makes ``(S + 1) / (2 S)`` exact: 0.75 at its default step of 0.05 s
            (heading error over 1 s of random driving: p99 0.16° against 2.6° with 0.5). The
            attended environments of model version 1 set it so
            (``wrappers.attention.default_config``).
        free_space_evidence: weigh each track's probability of moving by free-space evidence
            (``tracking.free_space``): an echo inside space an earlier scan saw through, or a
            body's static place now seen through (docs/notes/2026-12-05-free-space-evidence.md).
            On since model version 1 (``MODEL_VERSIONS``).
        free_space_lags_s: the ages (s, at most 8, each > 0) of the past scans a scan is
            compared with.
        free_space_run_sigmas: a run of neighbouring beams (each ≥ 1 σ, at least 3) is
            evidence when its combined score ``Σ σ / √beams`` reaches this (σ); a track's
            static place counts as seen through beyond it.
        free_space_born_moving: the probability of moving of a track born with evidence
            (in (0, 1); one born without starts at 0.5).
        free_space_evidence_log_odds: what a matched track's log-odds of moving gain at a
            scan with evidence (≥ 0).
        free_space_none_log_odds: what they gain at a scan without (≤ 0): motion that leaves
            no trace in free space (a centroid shifting as structure is hidden and shown)
            fades.
        track_onset_speed_sigma_mps: at a start (a track's probability of moving rises past
            0.5 from at most 0.1), the constant-velocity filter's velocity σ restarts at this, per
            axis (m/s; 0 turns it off): the filter, sure that a standing body's velocity is
            0, would otherwise follow the start over 0.3–0.5 s and overshoot once its lag
            is absorbed (``tracker.onset_velocity``).
        track_standing_speed_sigma_mps: a track judged standing keeps at least this
            velocity σ per axis (m/s; 0 turns it off), so that its constant-velocity
            hypothesis stays ready to explain a start.
        track_runaway_speed_mps: a track whose velocity estimate exceeds this (m/s; 0 turns
            it off; above the fastest body of the scene) was matched to another body's
            segment or to structure sliding into view; it restarts standing.
        track_edge_keeps_motion: a track matched to a segment cut by the laser's
            field-of-view edge keeps its probability of moving (the filters still update):
            the visible part of what the edge cuts slides as the robot turns or drives,
            which the filters would take for motion.
        track_occlusion_keeps_motion: a track matched to a segment with an end hidden behind
            a nearer echo (the beam beyond that end reads nearer) keeps its probability of
            moving (the filters still update; free-space evidence still weighs it): the
            visible part of a body partly hidden by another slides as that one moves, which
            the filters would take for motion. On since model version 2.
        track_onset_log_ratio: a track judged standing whose last centroids fit a start
            (standing, then moving at a constant velocity; ``tracking.onset``) better than
            standing by this log-likelihood ratio (nats; 0 turns the test off) has started:
            its velocity, position and their covariance come from the fit, and its odds of
            moving grow by the ratio. 6 since model version 3.
        track_change_log_ratio: a track judged moving whose last centroids fit a change of
            velocity (a line with a kink: a stop, a turn, a reversal; ``tracking.onset``)
            better than the line by this log-likelihood ratio (nats; 0 turns the test off) has
            changed: its position and velocity come from the part after the kink.
        track_outlier_share: the share of a track's matches that the motion probability
            takes for outliers (0–0.5; 0 turns it off): each filter's likelihood of a match
            is a mixture of its Gaussian (weight ``1 − share``) and one
            ``track_outlier_sigmas`` times wider (``kalman.robust_log_likelihood``), so that a
            centroid that jumps (a segment that merges, splits or shows a new face) weighs on
            either hypothesis no more than the wide component allows.
        track_outlier_sigmas: how many times wider than the filter's the outlier
            component is (σ, > 1).
        track_speed_goal_probability: judge a speed goal at a region by the probability
            that the region's track moves at a wanted speed (its probability of moving ×
            P(speed in the goal's range), the speed normal along the velocity estimate with
            its covariance; ``track_regions.speed_goal_probability``): the goal holds where
            it is at least ½, and F4 is ``min(1, 2 p)``. Off: the goal is judged from the
            track's speed weighted by its probability of moving, F4 by the table over it
            (§5). Tracker only; a region whose speed comes from a sonar filter keeps the
            table.

    Sensors (§1).

    Attributes:
        laser_mount_x_m, laser_mount_y_m: where the laser sits on the robot (robot frame,
            m); the tracker places its echoes with it (the env's P2AT-like robot: 0.16 m
            ahead of its centre).
        laser_mount_yaw_deg: the direction the laser's beam at angle 0 points (deg,
            counter-clockwise from the robot's heading, -360..360; 180: facing backwards).
        laser_upside_down: the laser is mounted upside down (its beam angles run
            clockwise seen from above). This and the yaw are applied where a ROS bag's
            scan is placed onto the model's robot-frame bearings
            (``attention.io.rosbag``); the model takes laser readings already on those
            bearings (as a CSV or NPZ log's are), seen from ``laser_mount_x_m, _y_m``.
        sonar_max_range_m, sonar_min_range_m: sonar range (m).
        laser_max_range_m: laser saturation ``mr`` (m).
        no_echo_epsilon_m: a reading within this of its sensor's maximum range means
            "nothing there" (m).

    Feature maps (§4, §5).

    Attributes:
        grid: "sonar" (J = 8, one region per front sonar) or "laser" (J = 180, one per beam).
        laser_only: F3 from the laser alone (default: laser fused with sonar by max).
        max_distance_m: MAXDISTANCE of F6 (m).
        td_require_target: top-down maps are 0 where their region has no echo (F4–F6)
            or no motion (F4: static direction label); False keeps the raw goal table.
        weights: weights of F1..F6 (>= 0; 0 = inactive). A top-down map is active only
            while a goal for its feature is set.
        normalise_combined: divide the combined map by the sum of the active weights.
        balance_groups: while both groups have active maps, scale the active top-down
            weights so that they sum to the active bottom-up weights' sum: a goal that
            holds then weighs as much as all the bottom-up evidence together, however
            many maps each group has (docs/model.md §6). False uses the weights as given.
        silent_goal_maps_out: at each step, leave an active top-down map that is 0 in every
            region out of the combined map's normaliser, so that a goal holding nowhere
            does not dilute the bottom-up maps (needs ``normalise_combined``; docs/model.md §6).

    Winner selection (§8).

    Attributes:
        threshold: θ, the focus fires when ``max L >= θ`` (> 0).
        state: initial Global Attentive State, a name of ``ATTENTIVE_STATES`` or a gain > 0.

    Attentional map, bottom-up course (§7).

    Attributes:
        preactivation_s, excitation_s, ior_s: phase lengths (s).
        A_exc, A_ior: peak amplitudes of excitation and inhibition of return (gain units).
        kernel_rise_fraction, kernel_decay_fraction: time constants of the rise-and-decay
            kernel ``h_T`` as fractions of the phase length T (rise < decay).
        lateral_sigma_regions: σ of the lateral spread ``G`` (regions, >= 0.01).

    Attentional map, top-down course (§7).

    Attributes:
        A_td: plateau of the top-down enhancement (gain units).
        td_onset_s: delay before the enhancement starts (s).
        td_tau_on_s, td_tau_off_s: rise and post-release decay time constants (s).
        vigilance_after_s: hold time after which vigilance adaptation starts (s).
        vigilance_amplitude_rel: adaptation plateau in units of ``A_td``.
        vigilance_tau_s: growth time constant of the adaptation (s).
        vigilance_recovery_s: decay time constant of the adaptation after release (s).
    """

    # --- sensorial memory and kinematics -----------------------------------------
    kinematics: str = "tracker"
    memory_window: int = 10
    slope_samples: int = 5
    max_speed_mps: float = 1.0
    direction_epsilon_mps: float = 0.05
    ego_motion: str | None = "odometry"
    sonar_ego_model: str = "laser"
    sonar_cone_half_width_deg: float = 15.0
    sonar_ego_match_m: float = 0.25
    # --- tracker -------------------------------------------------------------------
    range_noise_rel: float = 0.05
    range_noise_floor_m: float = 0.01
    segment_jump_m: float = 0.3
    segment_jump_sigmas: float = 3.0
    segment_min_beams: int = 2
    max_object_extent_m: float = 1.2
    foreground_flank_beams: int = 4
    foreground_sigmas: float = 4.5
    foreground_margin_m: float = 0.1
    foreground_edge_sigmas: float = 2.0
    track_accel_psd_m2ps3: float = 0.02
    track_static_drift_m2ps: float = 0.0025
    track_switch_rate_hz: float = 0.4
    track_position_sigma_m: float = 0.1
    track_initial_speed_sigma_mps: float = 1.0
    track_surface_sigma_m: float = 0.05
    track_gate_chi2: float = 13.8
    track_confirm_hits: int = 3
    track_delete_misses: int = 3
    track_coast_s: float = 1.5
    max_tracks: int = 64
    sonar_accel_psd_m2ps3: float = 0.5
    odometry_previous_weight: float = 0.5
    free_space_evidence: bool = True
    free_space_lags_s: tuple[float, ...] = (0.1, 0.2, 0.4, 0.7, 1.0)
    free_space_run_sigmas: float = 4.0
    free_space_born_moving: float = 0.9
    free_space_evidence_log_odds: float = 2.0
    free_space_none_log_odds: float = -0.5
    track_onset_speed_sigma_mps: float = 1.0
    track_standing_speed_sigma_mps: float = 0.3
    track_runaway_speed_mps: float = 1.5
    track_edge_keeps_motion: bool = True
    track_occlusion_keeps_motion: bool = True
    track_onset_log_ratio: float = 6.0
    track_change_log_ratio: float = 0.0
    track_outlier_share: float = 0.0
    track_outlier_sigmas: float = 3.0
    track_speed_goal_probability: bool = False
    # --- sensors -------------------------------------------------------------------
    laser_mount_x_m: float = 0.16
    laser_mount_y_m: float = 0.0
    laser_mount_yaw_deg: float = 0.0
    laser_upside_down: bool = False
    sonar_max_range_m: float = 5.0
    sonar_min_range_m: float = 0.15
    laser_max_range_m: float = 20.0
    no_echo_epsilon_m: float = 0.01
    # --- feature maps --------------------------------------------------------------
    grid: str = "sonar"
    laser_only: bool = False
    max_distance_m: float = 20.0
    td_require_target: bool = True
    weights: tuple[float, float, float, float, float, float] = (1.0, 1.0, 1.0, 1.0, 1.0, 1.0)
    normalise_combined: bool = True
    balance_groups: bool = True
    silent_goal_maps_out: bool = False
    # --- winner selection ----------------------------------------------------------
    threshold: float = 0.1
    state: str | float = "alert"
    # --- bottom-up course ----------------------------------------------------------
    preactivation_s: float = 0.15
    excitation_s: float = 0.15
    ior_s: float = 0.3
    A_exc: float = 1.0
    A_ior: float = 0.8
    kernel_rise_fraction: float = 1.0 / 20.0
    kernel_decay_fraction: float = 1.0 / 2.0
    lateral_sigma_regions: float = 0.5
    # --- top-down course -----------------------------------------------------------
    A_td: float = 1.0
    td_onset_s: float = 0.2
    td_tau_on_s: float = 0.05
    td_tau_off_s: float = 0.02
    vigilance_after_s: float = 6.0
    vigilance_amplitude_rel: float = 1.5
    vigilance_tau_s: float = 1.0
    vigilance_recovery_s: float = 2.0

    def __post_init__(self) -> None:
        for name in ("memory_window", "slope_samples"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or value < 2:
                raise ValueError(f"AttentionConfig.{name} must be an int >= 2 (samples), got {value!r}")
        if self.kinematics not in KINEMATICS_MODES:
            raise ValueError(f"AttentionConfig.kinematics must be one of {KINEMATICS_MODES}, got {self.kinematics!r}")
        for name in ("segment_min_beams", "track_confirm_hits", "track_delete_misses", "max_tracks"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or value < 1:
                raise ValueError(f"AttentionConfig.{name} must be an int >= 1, got {value!r}")
        value = self.foreground_flank_beams
        if isinstance(value, bool) or not isinstance(value, int) or value < 0:
            raise ValueError(f"AttentionConfig.foreground_flank_beams must be an int >= 0 (beams), got {value!r}")
        if self.slope_samples > self.memory_window:
            raise ValueError(
                f"AttentionConfig.slope_samples must be <= memory_window={self.memory_window}, got {self.slope_samples}"
            )
        positive = (
            ("max_speed_mps", "m/s"),
            ("sonar_max_range_m", "m"),
            ("laser_max_range_m", "m"),
            ("max_distance_m", "m"),
            ("sonar_ego_match_m", "m"),
            ("range_noise_floor_m", "m"),
            ("max_object_extent_m", "m"),
            ("foreground_sigmas", "σ"),
            ("foreground_edge_sigmas", "σ"),
            ("track_accel_psd_m2ps3", "m²/s³"),
            ("track_static_drift_m2ps", "m²/s"),
            ("track_switch_rate_hz", "1/s"),
            ("track_position_sigma_m", "m"),
            ("track_initial_speed_sigma_mps", "m/s"),
            ("track_surface_sigma_m", "m"),
            ("track_gate_chi2", "χ² units"),
            ("track_coast_s", "s"),
            ("sonar_accel_psd_m2ps3", "m²/s³"),
            ("threshold", "saliency units"),
            ("preactivation_s", "s"),
            ("excitation_s", "s"),
            ("ior_s", "s"),
            ("td_onset_s", "s"),
            ("td_tau_on_s", "s"),
            ("td_tau_off_s", "s"),
            ("vigilance_after_s", "s"),
            ("vigilance_tau_s", "s"),
            ("vigilance_recovery_s", "s"),
        )
        for name, unit in positive:  # bounded above too: a filter's 1e300 would leave float range
            _check_number(name, getattr(self, name), unit, low=0.0, low_inclusive=False, high=_MAX_SETTING)
        # a narrower spread is no spread at all; 2σ² must stay a normal float (G's diagonal is 0/0 otherwise)
        _check_number(
            "lateral_sigma_regions",
            self.lateral_sigma_regions,
            "regions",
            low=0.01,
            low_inclusive=True,
            high=_MAX_SETTING,
        )
        for name in ("laser_mount_x_m", "laser_mount_y_m"):
            _check_number(name, getattr(self, name), "m", low=-_MAX_MOUNT_M, low_inclusive=True, high=_MAX_MOUNT_M)
        yaw = self.laser_mount_yaw_deg
        _check_number("laser_mount_yaw_deg", yaw, "deg", low=-360.0, low_inclusive=True, high=360.0)
        non_negative = (
            ("direction_epsilon_mps", "m/s"),
            ("range_noise_rel", "fraction of the range"),
            ("segment_jump_m", "m"),
            ("segment_jump_sigmas", "σ"),
            ("foreground_margin_m", "m"),
            ("sonar_min_range_m", "m"),
            ("no_echo_epsilon_m", "m"),
            ("A_exc", "gain units"),
            ("A_ior", "gain units"),
            ("A_td", "gain units"),
            ("vigilance_amplitude_rel", "multiples of A_td"),
        )
        for name, unit in non_negative:
            _check_number(name, getattr(self, name), unit, low=0.0, low_inclusive=True)
        # >= 0.5 deg: every cone holds a 1-degree laser beam; <= 30 deg: only the ±90° cones
        # reach the laser's edges (front sonars are 20-40 deg apart)
        _check_number(
            "sonar_cone_half_width_deg", self.sonar_cone_half_width_deg, "deg", low=0.5, low_inclusive=True, high=30.0
        )
        if self.sonar_min_range_m >= self.sonar_max_range_m:
            raise ValueError(
                f"AttentionConfig.sonar_min_range_m must be < sonar_max_range_m={self.sonar_max_range_m} m, "
                f"got {self.sonar_min_range_m}"
            )
        if self.no_echo_epsilon_m >= self.sonar_max_range_m - self.sonar_min_range_m:
            raise ValueError(
                "AttentionConfig.no_echo_epsilon_m must be smaller than the sonar's span "
                f"({self.sonar_max_range_m - self.sonar_min_range_m} m), got {self.no_echo_epsilon_m}"
            )
        for name in ("kernel_rise_fraction", "kernel_decay_fraction"):
            _check_number(name, getattr(self, name), "fraction of the phase length", low=0.0, low_inclusive=False)
        if self.kernel_rise_fraction >= self.kernel_decay_fraction:
            raise ValueError(
                "AttentionConfig.kernel_rise_fraction must be < kernel_decay_fraction "
                f"({self.kernel_decay_fraction}), got {self.kernel_rise_fraction}"
            )
        if self.grid not in GRIDS:
            raise ValueError(f"AttentionConfig.grid must be one of {GRIDS}, got {self.grid!r}")
        if self.ego_motion not in EGO_MOTION_MODES:
            raise ValueError(f"AttentionConfig.ego_motion must be one of {EGO_MOTION_MODES}, got {self.ego_motion!r}")
        if self.sonar_ego_model not in SONAR_EGO_MODELS:
            raise ValueError(
                f"AttentionConfig.sonar_ego_model must be one of {SONAR_EGO_MODELS}, got {self.sonar_ego_model!r}"
            )
        self._check_free_space()
        for name in ("track_onset_log_ratio", "track_change_log_ratio"):
            _check_number(name, getattr(self, name), "nats", low=0.0, low_inclusive=True, high=100.0)
        _check_number("track_outlier_share", self.track_outlier_share, "a share", low=0.0, low_inclusive=True, high=0.5)
        _check_number("track_outlier_sigmas", self.track_outlier_sigmas, "σ", low=1.0, low_inclusive=False, high=100.0)
        for name in (
            "laser_only",
            "td_require_target",
            "normalise_combined",
            "balance_groups",
            "silent_goal_maps_out",
            "laser_upside_down",
            "free_space_evidence",
            "track_edge_keeps_motion",
            "track_occlusion_keeps_motion",
            "track_speed_goal_probability",
        ):
            if not isinstance(getattr(self, name), bool):
                raise ValueError(f"AttentionConfig.{name} must be True or False, got {getattr(self, name)!r}")
        if self.silent_goal_maps_out and not self.normalise_combined:
            raise ValueError(
                "AttentionConfig.silent_goal_maps_out leaves maps out of the combined map's normaliser, "
                "so it needs normalise_combined=True"
            )
        try:
            entries = tuple(self.weights)
        except TypeError:
            entries = ()
        if len(entries) != len(MAP_NAMES) or not all(is_map_weight(w) for w in entries):
            raise ValueError(
                f"AttentionConfig.weights must be 6 numbers in [0, {MAX_MAP_WEIGHT:g}] (F1..F6), got {self.weights!r}"
            )
        weights = tuple(float(w) for w in entries)
        object.__setattr__(self, "weights", weights)
        try:
            parse_state(self.state)
        except ValueError as err:
            raise ValueError(f"AttentionConfig.state: {err}") from None

    def _check_free_space(self) -> None:
        """The dead reckoning's weight and the free-space evidence's settings."""
        _check_number(
            "odometry_previous_weight", self.odometry_previous_weight, "weight", low=0.0, low_inclusive=True, high=1.0
        )
        try:
            lags = tuple(float(lag) for lag in self.free_space_lags_s)
        except (TypeError, ValueError):
            lags = ()
        if not 1 <= len(lags) <= MAX_FREE_SPACE_LAGS or not all(
            math.isfinite(lag) and 0.0 < lag <= 10.0 for lag in lags
        ):
            raise ValueError(
                f"AttentionConfig.free_space_lags_s must be 1 to {MAX_FREE_SPACE_LAGS} ages in (0, 10] s, "
                f"got {self.free_space_lags_s!r}"
            )
        object.__setattr__(self, "free_space_lags_s", lags)
        _check_number(
            "free_space_run_sigmas", self.free_space_run_sigmas, "σ", low=0.0, low_inclusive=False, high=100.0
        )
        _check_number(
            "free_space_born_moving",
            self.free_space_born_moving,
            "probability",
            low=0.0,
            low_inclusive=False,
            high=0.999,
        )
        _check_number(
            "free_space_evidence_log_odds",
            self.free_space_evidence_log_odds,
            "log-odds",
            low=0.0,
            low_inclusive=True,
            high=50.0,
        )
        _check_number(
            "free_space_none_log_odds",
            self.free_space_none_log_odds,
            "log-odds",
            low=-50.0,
            low_inclusive=True,
            high=0.0,
        )
        for name in ("track_onset_speed_sigma_mps", "track_standing_speed_sigma_mps", "track_runaway_speed_mps"):
            _check_number(name, getattr(self, name), "m/s", low=0.0, low_inclusive=True, high=100.0)

    # --- derived quantities ---------------------------------------------------------
    @property
    def course_s(self) -> float:
        """Length of a whole bottom-up course: pre-activation + excitation + IOR (s)."""
        return self.preactivation_s + self.excitation_s + self.ior_s

    @property
    def gain(self) -> float:
        """The initial Global Attentive State gain ``g``."""
        return parse_state(self.state)

    # --- serialisation --------------------------------------------------------------
    def to_dict(self) -> dict[str, Any]:
        """The fields as plain JSON-compatible values (tuples become lists)."""
        return {
            f.name: (list(v) if isinstance(v := getattr(self, f.name), tuple) else v) for f in dataclasses.fields(self)
        }

    def to_json(self) -> str:
        """The configuration as a JSON object string (keys sorted)."""
        return json.dumps(self.to_dict(), sort_keys=True)

    @classmethod
    def from_dict(cls, values: Mapping[str, Any]) -> AttentionConfig:
        """Build a configuration from a mapping of field names; missing fields keep defaults.

        Raises:
            ValueError: for an unknown field name (listing the allowed ones) or an invalid value.
        """
        if not isinstance(values, Mapping):
            raise ValueError(f"an attention configuration must be a JSON object / mapping, got {type(values).__name__}")
        names = [f.name for f in dataclasses.fields(cls)]
        unknown = sorted(set(values) - set(names))
        if unknown:
            raise ValueError(f"unknown AttentionConfig field(s) {unknown}; allowed: {', '.join(names)}")
        kwargs = dict(values)
        if "weights" in kwargs and isinstance(kwargs["weights"], list):
            kwargs["weights"] = tuple(kwargs["weights"])
        return cls(**kwargs)

    @classmethod
    def from_json(cls, text: str) -> AttentionConfig:
        """Inverse of ``to_json``; ``ValueError`` for malformed JSON or invalid fields."""
        try:
            values = json.loads(text)
        except json.JSONDecodeError as err:
            raise ValueError(f"attention configuration is not valid JSON: {err}") from None
        return cls.from_dict(values)


#: The farthest a laser can sit from the robot's centre (m).
_MAX_MOUNT_M = 5.0


#: The largest value of a positive setting (in its own unit: m, s, m/s, σ, ...).
_MAX_SETTING = 1e6


def _check_number(
    name: str, value: Any, unit: str, *, low: float, low_inclusive: bool, high: float | None = None
) -> None:
    ok = isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
    if ok:
        ok = value >= low if low_inclusive else value > low
    if ok and high is not None:
        ok = value <= high
    if not ok:
        bound = f"{'>=' if low_inclusive else '>'} {low:g}" + (f" and <= {high:g}" if high is not None else "")
        raise ValueError(f"AttentionConfig.{name} must be a finite number {bound} ({unit}), got {value!r}")


#: Named sets of ``AttentionConfig`` values for a kind of laser and target, applied over a
#: configuration by ``profile_config`` (``attentive-gym attend --profile NAME``). The defaults
#: are tuned for the simulator's round 0.2 m victims seen by a 20 m laser with 5 % noise.
#:
#: ``indoor-people``: a Hokuyo URG/UTM or SICK TiM/LMS indoor laser (range noise about 1 %,
#: at least 2 cm) with people walking: legs are two arcs of 0.1-0.15 m that swing at several
#: m/s² and stop at each step, so bodies longer than 0.5 m are structure (furniture,
#: walls) and the tracks' velocities follow quick changes (``track_accel_psd_m2ps3`` 2).
#: A walking-speed goal with nobody walking in view leaves the bottom-up maps alone
#: (``silent_goal_maps_out``). Measured on public bags of people walking past a still laser:
#: docs/results/real_bags.md.
LASER_PROFILES: Mapping[str, Mapping[str, Any]] = {
    "indoor-people": {
        "range_noise_rel": 0.01,
        "range_noise_floor_m": 0.02,
        "max_object_extent_m": 0.5,
        "track_accel_psd_m2ps3": 2.0,
        "silent_goal_maps_out": True,
    },
}


def profile_config(name: str, config: AttentionConfig | None = None) -> AttentionConfig:
    """``config`` (default ``AttentionConfig()``) with the values of profile ``name`` of
    ``LASER_PROFILES``.

    Raises:
        ValueError: for an unknown profile name (listing the known ones).
    """
    if name not in LASER_PROFILES:
        raise ValueError(f"unknown laser profile {name!r}; known: {', '.join(LASER_PROFILES)}")
    return dataclasses.replace(AttentionConfig() if config is None else config, **LASER_PROFILES[name])


def configured(profile: str | None = None, config_json: str | None = None) -> AttentionConfig:
    """The model's configuration as ``attend`` and the real-bag benchmark take it: the
    defaults, the values of laser ``profile`` (``LASER_PROFILES``) over them, and the fields of
    ``config_json`` (a JSON object, or the path of a .json file holding one) over those.

    Raises:
        ValueError: for an unknown profile, malformed JSON, or a field that is unknown or
            out of range (``AttentionConfig.from_json``).
        OSError: for a .json path that cannot be read.
    """
    config = AttentionConfig() if profile is None else profile_config(profile)
    if not config_json:
        return config
    text = config_json if config_json.lstrip().startswith("{") else Path(config_json).read_text(encoding="utf-8")
    given = AttentionConfig.from_json(text)
    return dataclasses.replace(config, **{name: getattr(given, name) for name in json.loads(text)})
