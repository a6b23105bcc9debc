"""Perception benchmark: does the attentional model see motion and attend to the goal's target?

Run: ``python benchmarks/bench_perception.py [--modes tracker,window,literal] [--episodes 24]
[--seconds 20] [--control-episodes 40] [--sections speed,focus,control,cost,clutter] [--csv PATH]``
(about 2 minutes on 2 quiet cores for the first four sections, which are the default;
``clutter`` adds about 5 minutes).

For each kinematics mode (``AttentionConfig(kinematics=...)``, docs/model.md §3 and §10), the
robot still or driving (a scripted wander, ``Wander``), and each sensor noise setting
(``NOISE_SETTINGS``: Gaussian σ = 0, 2 % and 5 %, and the env's ``sensor_profile="usarsim"``:
uniform ±5 %, 5 Hz scans), in the procedural 10 m arena with 3 distractors, it prints
markdown tables of:

1. ``speed``: the error of the speed estimate of the region a mover lies in against the
   mover's true speed, over (mover, step) pairs where the mover has been in front of the
   robot and within 5 m for at least 1 s; separately the pairs within 1 s after the mover
   turned; with tracks (``out.tracks``, tracker mode) the error of the nearest confirmed
   track too; the speed of regions whose echoes all come from static structure (should be
   ≈ 0); and how often "the goal holds" judged from the estimate agrees with the truth.
2. ``focus``: per default task goal, the fraction of the steps with the target in front and
   within 5 m at which the focus is the target's region (chance: 1/8), and each noisy
   setting's figure relative to the same mode's noise-free one (what the noise takes away).
3. ``control``: success rates in the 8 m arena with 2 distractors (seeds 0..N−1) of a
   controller steered by the latest top-down focus, of the same controller steered by the
   first row of the ``focus`` observation's working memory when it matched the goal
   (``memory_controller``: it reads nothing but the observation a policy gets), of the
   same controller steered by the true target bearing (a privileged oracle) and of random
   actions.
4. ``cost``: µs per ``AttentionModel.step`` (and of it, the tracker's step) on readings
   recorded from a driving episode at 5 % noise, beside a raw ``AttentiveRescue-v0`` step
   with random actions, measured in alternating rounds of the same run (medians).
5. ``clutter`` (only when asked for): in the RL comparison's arena (8 m, 3 rubble pieces
   per 100 m², 5 % noise) with 1, 2, 3 and 5 distractors, the focus on target of the
   driving robot and the success of the memory, true-bearing and random controllers: how
   perception and the attended observation hold up as bodies are added.

Every random draw is seeded: the same command prints the same numbers (the timings aside).
A configuration the installed package does not accept yet (an unknown env keyword) is
reported as unavailable. ``--csv`` also writes the figures as a tidy table (one row per
configuration and metric). Nothing is asserted: measure, don't guess.
"""

from __future__ import annotations

import argparse
import csv
import math
import statistics
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Iterable, Mapping

import numpy as np

from attentive_gym._atomic import atomic_file
from attentive_gym.attention import ORIGIN_TOP_DOWN, AttentionConfig, AttentionModel, Goal, Grid
from attentive_gym.attention import model as model_module
from attentive_gym.attention.goals import Feature
from attentive_gym.attention.regions import nearest_sonar
from attentive_gym.attention.tracker import Tracker
from attentive_gym.attention.working_memory import MEMORY_FIELDS
from attentive_gym.world import arena
from attentive_gym.wrappers import make_env
from call_timer import CallTimer

MODES = ("tracker", "window", "literal")
SECTIONS = ("speed", "focus", "control", "cost", "clutter")
DEFAULT_SECTIONS = ("speed", "focus", "control", "cost")
ROBOT_MODES = ("still", "driving")

# The attended variant the benchmark runs. The model and ``info["attention"]`` are the same
# in every attended variant; "saliency" also passes the raw laser on, which the wander needs.
VARIANT = "saliency"
GRID = Grid.make("sonar")
USARSIM_NOISE_HALF_WIDTH = 0.05  # the usarsim profile's uniform noise: ±5 % of the reading


@dataclass(frozen=True)
class NoiseSetting:
    """A sensor noise configuration.

    Attributes:
        name: the label printed in the tables.
        env_kwargs: keyword arguments of the environment that select it.
        sigma_rel: the relative σ of one reading (dimensionless), given to the model as
            ``AttentionConfig.range_noise_rel``.
    """

    name: str
    env_kwargs: Mapping[str, Any]
    sigma_rel: float


NOISE_SETTINGS = (
    NoiseSetting("gauss 0", {"sensor_noise": 0.0}, 0.0),
    NoiseSetting("gauss 0.02", {"sensor_noise": 0.02}, 0.02),
    NoiseSetting("gauss 0.05", {"sensor_noise": 0.05}, 0.05),
    NoiseSetting("usarsim", {"sensor_profile": "usarsim"}, USARSIM_NOISE_HALF_WIDTH / math.sqrt(3.0)),
)
CONTROL_NOISE = ("gauss 0.05", "usarsim")
COST_NOISE = "gauss 0.05"

PERCEPTION_ARENA = {"arena_size_m": 10.0, "num_distractors": 3}
CONTROL_ARENA = {"arena_size_m": 8.0, "num_distractors": 2}
CLUTTER_ARENA = {"arena_size_m": 8.0, "rubble_per_100m2": 3.0}  # the RL comparison's (docs/results/rl.md)
CLUTTER_DISTRACTORS = (1, 2, 3, 5)
CLUTTER_NOISE = "gauss 0.05"

# --- what counts as a (mover, step) pair -------------------------------------------------
VIEW_RANGE_M = 5.0  # movers farther than this (centre to centre) are out of view
SETTLE_S = 1.0  # a mover counts once it has been in view continuously this long
TURN_ANGLE_RAD = math.radians(30.0)  # a velocity direction change above this is a turn
TRANSIENT_S = 1.0  # pairs within this after a turn are reported apart
MOVING_MPS = 0.02  # below this a mover is still, its direction undefined (movers go in 0.05 m/s steps)
_COS, _SIN, _MATCH = (MEMORY_FIELDS.index(f) for f in ("cos_bearing", "sin_bearing", "goal_match"))
TRACK_MATCH_M = 0.75  # the nearest confirmed track within this of a mover is its track
#: Bins (s) of the age of the target's track in the focus-by-track-age table: how long a
#: track must have lasted before its goal can be judged.
TRACK_AGE_BINS_S = (0.0, 1.0, 2.0, 4.0, math.inf)

# --- controllers (actions are fractions of 0.7 m/s and 140°/s) ---------------------------
WANDER_LINEAR = 0.6
WANDER_ANGULAR = 0.3  # amplitude of the sinusoidal turn
WANDER_PERIOD_S = 8.0
WANDER_FRONT_BEAMS = slice(60, 120)  # laser beams at bearings −30° .. +30°
WANDER_CLEARANCE_M = 0.8  # turn in place when the front laser sees closer than this
STEER_LINEAR = 1.0  # forward command when facing the goal bearing
STEER_GAIN_PER_RAD = 2.0  # angular command per radian of bearing error
SEARCH_SPIN = 0.5  # angular command while there is no bearing to steer to
COST_RECORD_S = 30.0  # length of the driving episode whose readings the cost section replays


# ===================================================================== geometry
def wrap_angle(angle_rad: np.ndarray | float) -> np.ndarray | float:
    """Angles (rad) wrapped into [−π, π)."""
    return (angle_rad + math.pi) % (2.0 * math.pi) - math.pi


def to_robot_frame(points_xy: np.ndarray, pose: np.ndarray) -> np.ndarray:
    """World points ``(..., 2)`` (m) in the frame of a robot at ``pose`` = (x m, y m, heading
    rad): x forward, y left (m), same shape."""
    x, y, heading = pose
    c, s = math.cos(heading), math.sin(heading)
    dx, dy = points_xy[..., 0] - x, points_xy[..., 1] - y
    return np.stack([c * dx + s * dy, -s * dx + c * dy], axis=-1)


def bearing_of(xy: np.ndarray) -> np.ndarray:
    """Bearings (rad, counter-clockwise from the heading) of robot-frame points ``(..., 2)``."""
    return np.arctan2(xy[..., 1], xy[..., 0])


def in_view(xy: np.ndarray) -> np.ndarray:
    """Whether robot-frame points ``(..., 2)`` lie in front (|bearing| < 90°) within
    ``VIEW_RANGE_M``."""
    return (xy[..., 0] > 0.0) & (np.hypot(xy[..., 0], xy[..., 1]) < VIEW_RANGE_M)


def region_of(xy: np.ndarray) -> np.ndarray:
    """The attention region (0..7, the nearest front sonar's bearing) of robot-frame points
    ``(..., 2)`` in front of the robot."""
    return nearest_sonar(bearing_of(xy))


def true_target_bearing(info: Mapping[str, Any]) -> float:
    """Bearing (rad, robot frame) of the episode's target, from the world's truth."""
    target = info["mover_positions"][info["target_index"]]
    return float(bearing_of(to_robot_frame(target, info["robot_pose"])))


# ===================================================================== controllers
def steer(bearing_rad: float | None) -> np.ndarray:
    """The action (linear, angular; fractions in [−1, 1]) that turns towards ``bearing_rad``
    (robot frame) and drives forward in proportion to max(0, cos(bearing)); spinning in
    place when there is no bearing."""
    if bearing_rad is None:
        return np.array([0.0, SEARCH_SPIN], np.float32)
    linear = STEER_LINEAR * max(0.0, math.cos(bearing_rad))
    angular = float(np.clip(STEER_GAIN_PER_RAD * bearing_rad, -1.0, 1.0))
    return np.array([linear, angular], np.float32)


def focus_bearing(output) -> float:
    """Bearing (rad) of an ``AttentionOutput``'s focus: the focused track's bearing when the
    view carries one, else the centre bearing of the focused region."""
    view = output.view
    track_xy = getattr(view, "track_position_m", None)
    if track_xy is not None:
        return float(bearing_of(np.asarray(track_xy, float)))
    return view.bearing_rad


class FocusController:
    """Steers towards the latest top-down focus (``steer``).

    The focus's bearing is kept in the robot frame as the robot turns: each step it drops
    by the odometry's angular velocity × ``dt_s`` until the next top-down focus replaces it.
    Before the first top-down focus the robot spins in place.
    """

    def __init__(self, dt_s: float) -> None:
        self.dt_s = dt_s
        self.bearing_rad: float | None = None

    def __call__(self, obs: Mapping[str, np.ndarray], info: Mapping[str, Any]) -> np.ndarray:
        if self.bearing_rad is not None:
            self.bearing_rad = float(wrap_angle(self.bearing_rad - float(obs["odometry"][1]) * self.dt_s))
        output = info["attention"]
        if output.origin == ORIGIN_TOP_DOWN:
            self.bearing_rad = focus_bearing(output)
        return steer(self.bearing_rad)


def memory_controller(obs: Mapping[str, np.ndarray], info: Mapping[str, Any]) -> np.ndarray:
    """``steer`` towards the first row of a ``focus`` observation's working memory when that
    body matched the goal (the rows hold the goal matches first), else spin: a reactive
    policy that reads nothing but the observation (``info`` is not used)."""
    rows = np.asarray(obs["memory"]).reshape(-1, len(MEMORY_FIELDS))
    cos_bearing, sin_bearing, goal_match = rows[0, _COS], rows[0, _SIN], rows[0, _MATCH]
    return steer(math.atan2(sin_bearing, cos_bearing) if goal_match > 0.5 else None)


def true_bearing_controller(obs: Mapping[str, np.ndarray], info: Mapping[str, Any]) -> np.ndarray:
    """``steer`` towards the target's true bearing (a privileged oracle)."""
    return steer(true_target_bearing(info))


class RandomController:
    """Random actions from ``action_space``, seeded with ``seed``."""

    def __init__(self, action_space, seed: int) -> None:
        self.action_space = action_space
        self.action_space.seed(seed)

    def __call__(self, obs: Mapping[str, np.ndarray], info: Mapping[str, Any]) -> np.ndarray:
        return self.action_space.sample()


class Wander:
    """Scripted exploration, deterministic given ``seed``: forward at ``WANDER_LINEAR`` with
    a slow sinusoidal turn (phase drawn from the seed), turning in place (direction drawn
    from the seed) while the front laser beams see something closer than
    ``WANDER_CLEARANCE_M``."""

    def __init__(self, seed: int) -> None:
        rng = np.random.default_rng(seed)
        self.phase_rad = float(rng.uniform(0.0, 2.0 * math.pi))
        self.turn_sign = float(rng.choice((-1.0, 1.0)))

    def __call__(self, obs: Mapping[str, np.ndarray], info: Mapping[str, Any]) -> np.ndarray:
        if float(np.min(obs["laser"][WANDER_FRONT_BEAMS])) < WANDER_CLEARANCE_M:
            return np.array([0.0, self.turn_sign], np.float32)
        angular = WANDER_ANGULAR * math.sin(2.0 * math.pi * info["time_s"] / WANDER_PERIOD_S + self.phase_rad)
        return np.array([WANDER_LINEAR, angular], np.float32)


def stand_still(obs: Mapping[str, np.ndarray], info: Mapping[str, Any]) -> np.ndarray:
    """The zero action."""
    return np.zeros(2, np.float32)


# ===================================================================== environments
def make_attentive_env(mode: str, noise: NoiseSetting, variant: str = VARIANT, **env_kwargs: Any):
    """The attended environment ``variant`` (default ``VARIANT``; ``"focus"`` for an
    observation with the working memory) with the model in kinematics ``mode``.

    Raises:
        TypeError: when the installed environment does not accept a keyword of ``noise``.
    """
    config = AttentionConfig(kinematics=mode, range_noise_rel=noise.sigma_rel)
    return make_env(variant, attention=config, **noise.env_kwargs, **env_kwargs)


def make_raw_env(noise: NoiseSetting, **env_kwargs: Any):
    """The raw ``AttentiveRescue-v0`` environment (no model, no checker wrappers)."""
    return make_env("raw", **noise.env_kwargs, **env_kwargs)


# ===================================================================== recording
@dataclass(frozen=True)
class EpisodeRecord:
    """Per-step truth and model output of one episode (T steps, M movers, J = 8 regions).

    Attributes:
        goal: the episode's goal.
        target: index of the target among the movers.
        t_s: ``(T,)`` time of each step (s).
        mover_xy: ``(T, M, 2)`` mover centres in the robot frame (m).
        mover_velocity: ``(T, M, 2)`` mover velocities in the world frame (m/s).
        region_speed: ``(T, J)`` the model's speed estimate per region (m/s).
        track_speed: ``(T, M)`` speed of each mover's matched confirmed track (m/s), NaN
            where none is within ``TRACK_MATCH_M``; None when the model produced no track
            in the whole episode (the modes without a tracker).
        focus: ``(T,)`` the focused region, −1 for none.
        static_region: ``(T, J)`` regions with an echo and no echo from a mover.
        target_case: ``(T,)`` why the focus is or is not on the target at each step, an
            index into ``TARGET_CASES`` (``target_case``); None when not recorded.
        target_track_age: ``(T,)`` age (s) of the target's track (``nearest_track``), NaN
            where it has none; None when not recorded.
    """

    goal: Goal
    target: int
    t_s: np.ndarray
    mover_xy: np.ndarray
    mover_velocity: np.ndarray
    region_speed: np.ndarray
    track_speed: np.ndarray | None
    focus: np.ndarray
    static_region: np.ndarray
    target_case: np.ndarray | None = None
    target_track_age: np.ndarray | None = None


#: ``(J, 180)`` which laser beams each region holds.
_REGION_BEAMS = GRID.beam_region[None, :] == np.arange(GRID.n_regions)[:, None]


def static_regions(laser_hits: np.ndarray, sonar_hits: np.ndarray, mover_ids: np.ndarray) -> np.ndarray:
    """``(J,)`` bool: the region's laser beams or front sonar have an echo, and none of them
    comes from a mover. ``laser_hits`` (180,) and ``sonar_hits`` (16,) are entity ids per
    reading (−1: no echo); ``mover_ids`` the movers' entity ids."""
    sonar = sonar_hits[GRID.region_sonar]
    mover_echo = (_REGION_BEAMS & np.isin(laser_hits, mover_ids)).any(axis=1) | np.isin(sonar, mover_ids)
    echo = (_REGION_BEAMS & (laser_hits >= 0)).any(axis=1) | (sonar >= 0)
    return echo & ~mover_echo


def nearest_tracks(tracks, xy: np.ndarray) -> np.ndarray:
    """``(M,)`` row in ``tracks`` of the confirmed track nearest to each robot-frame position
    ``xy`` (M, 2) (m), −1 where none lies within ``TRACK_MATCH_M``."""
    confirmed = np.flatnonzero(np.asarray(tracks.confirmed, bool))
    rows = np.full(len(xy), -1)
    if confirmed.size:
        positions = np.asarray(tracks.position_m, float).reshape(-1, 2)[confirmed]
        distance = np.linalg.norm(xy[:, None, :] - positions[None, :, :], axis=-1)
        nearest = distance.argmin(axis=1)
        close = distance[np.arange(len(xy)), nearest] <= TRACK_MATCH_M
        rows[close] = confirmed[nearest[close]]
    return rows


def matched_track_speeds(tracks, mover_xy: np.ndarray) -> np.ndarray:
    """``(M,)`` speed (m/s) of each mover's track (``nearest_tracks`` of its robot-frame
    position ``mover_xy`` (M, 2)), NaN where it has none."""
    rows = nearest_tracks(tracks, mover_xy)
    matched = np.full(len(mover_xy), np.nan)
    matched[rows >= 0] = np.asarray(tracks.speed_mps, float)[rows[rows >= 0]]
    return matched


Policy = Callable[[Mapping[str, np.ndarray], Mapping[str, Any]], np.ndarray]

#: Why the focus is or is not on the target's region at a step, checked in this order: the
#: focus is there; the perception misses the target (the laser does not see it; it sees it
#: but no confirmed track lies within ``TRACK_MATCH_M``; a track does, but the goal is not
#: judged to hold in the target's region, the track younger or older than ``SETTLE_S``);
#: or the goal is judged to hold there and the selection goes elsewhere (no focus at all;
#: the region is inhibited, M < 1; another region wins).
TARGET_CASES = ("on target", "hidden from the laser", "seen, no track", "young track, goal not judged",
                "track, goal not judged", "no focus", "inhibited", "another region won")


def nearest_track(tracks, xy: np.ndarray) -> int | None:
    """``nearest_tracks`` of one position ``xy`` (2,) (m): a row, or None."""
    row = int(nearest_tracks(tracks, np.reshape(xy, (1, 2)))[0])
    return None if row < 0 else row


def target_case(output, target_xy: np.ndarray, target_laser_beams: int) -> int:
    """The index in ``TARGET_CASES`` of a step: the model's ``output``, the target's
    robot-frame position ``target_xy`` (2,) (m) and how many laser beams hit it."""
    region = int(region_of(target_xy))
    if output.focus == region:
        return 0
    nearest = nearest_track(output.tracks, target_xy)
    if nearest is None:
        return 1 if target_laser_beams == 0 else 2
    if not output.goal_fulfilled[region]:
        return 3 if output.tracks.age_s[nearest] < SETTLE_S else 4
    if output.focus is None:
        return 5
    return 6 if output.M[region] < 1.0 else 7


def record_episode(env, seed: int, goal: Goal, policy: Policy, seconds: float) -> EpisodeRecord:
    """Run one episode of the attended ``env`` (reset with ``seed`` and ``goal``) under
    ``policy`` for ``seconds`` (s) or until it ends, and record every step after the reset."""
    obs, info = env.reset(seed=seed, options={"goal": goal})
    mover_ids = np.array([m.entity.id for m in env.unwrapped.world.movers])
    target_id = mover_ids[info["target_index"]]
    steps: list[tuple] = []
    tracked = False  # whether the model produced any track in the episode
    while info["time_s"] < seconds - 1e-9:
        obs, _, terminated, truncated, info = env.step(policy(obs, info))
        output = info["attention"]
        xy = to_robot_frame(info["mover_positions"], info["robot_pose"])
        tracks = getattr(output, "tracks", None)
        tracked = tracked or (tracks is not None and len(tracks.id) > 0)
        target_track = None if tracks is None else nearest_track(tracks, xy[info["target_index"]])
        steps.append((
            info["time_s"], xy, info["mover_velocities"], output.speeds_mps,
            np.full(len(xy), np.nan) if tracks is None else matched_track_speeds(tracks, xy),
            -1 if output.focus is None else output.focus,
            static_regions(info["laser_hits"], info["sonar_hits"], mover_ids),
            target_case(output, xy[info["target_index"]], int(np.sum(info["laser_hits"] == target_id))),
            math.nan if target_track is None else tracks.age_s[target_track],
        ))
        if terminated or truncated:
            break
    t_s, xy, velocity, region_speed, track_speed, focus, static, case, age = zip(*steps)
    return EpisodeRecord(
        goal=goal, target=int(info["target_index"]), t_s=np.array(t_s), mover_xy=np.array(xy),
        mover_velocity=np.array(velocity), region_speed=np.array(region_speed),
        track_speed=np.array(track_speed) if tracked else None,
        focus=np.array(focus), static_region=np.array(static), target_case=np.array(case) if tracked else None,
        target_track_age=np.array(age) if tracked else None,
    )


# ===================================================================== metrics
def time_since(t_s: np.ndarray, event: np.ndarray) -> np.ndarray:
    """``(T, M)`` seconds since the latest ``event`` (T, M) at or before each step, inf
    before the first."""
    last = np.full(event.shape[1], -np.inf)
    since = np.empty(event.shape)
    for k, t in enumerate(t_s):
        last = np.where(event[k], t, last)
        since[k] = t - last
    return since


def turns(velocity: np.ndarray) -> np.ndarray:
    """``(T, M)`` bool: the mover's velocity ``(T, M, 2)`` (m/s) changed direction by more
    than ``TURN_ANGLE_RAD`` since the previous step, or it started or stopped (a direction
    appeared or vanished); False at the first step."""
    before, after = velocity[:-1], velocity[1:]
    speed_before, speed_after = np.linalg.norm(before, axis=-1), np.linalg.norm(after, axis=-1)
    moving_before, moving_after = speed_before > MOVING_MPS, speed_after > MOVING_MPS
    both = moving_before & moving_after
    cosine = np.sum(before * after, axis=-1) / np.where(both, speed_before * speed_after, 1.0)
    turned = (both & (cosine < math.cos(TURN_ANGLE_RAD))) | (moving_before != moving_after)
    return np.vstack([np.zeros((1, velocity.shape[1]), bool), turned])


def pair_masks(record: EpisodeRecord) -> tuple[np.ndarray, np.ndarray]:
    """``(T, M)`` bool masks of the steady and the transient (mover, step) pairs.

    Both hold movers in view (``in_view``) continuously for at least ``SETTLE_S``; the
    transient ones are within ``TRANSIENT_S`` after a turn (``turns``), the steady ones not.
    """
    visible = in_view(record.mover_xy)
    entered = visible & ~np.vstack([np.zeros((1, visible.shape[1]), bool), visible[:-1]])
    settled = visible & (time_since(record.t_s, entered) >= SETTLE_S - 1e-9)
    transient = settled & (time_since(record.t_s, turns(record.mover_velocity)) <= TRANSIENT_S + 1e-9)
    return settled & ~transient, transient


def region_estimates(record: EpisodeRecord) -> np.ndarray:
    """``(T, M)`` each mover's speed estimate (m/s): the speed of the region it lies in."""
    regions = region_of(record.mover_xy)
    return np.take_along_axis(record.region_speed, regions, axis=1)


def error_stats(estimate: np.ndarray, truth: np.ndarray) -> dict[str, float]:
    """Median, 90th percentile and root mean square of ``|estimate − truth|`` (m/s), and
    the number of pairs; NaN statistics for no pairs."""
    error = np.abs(np.asarray(estimate, float) - np.asarray(truth, float))
    if error.size == 0:
        return {"pairs": 0, "median_mps": math.nan, "p90_mps": math.nan, "rmse_mps": math.nan}
    return {"pairs": int(error.size), "median_mps": float(np.median(error)),
            "p90_mps": float(np.percentile(error, 90)), "rmse_mps": float(np.sqrt(np.mean(error**2)))}


@dataclass
class Pairs:
    """(mover, step) pairs pooled over episodes, one entry per pair (speeds in m/s)."""

    true: list[np.ndarray] = field(default_factory=list)
    region: list[np.ndarray] = field(default_factory=list)
    track: list[np.ndarray] = field(default_factory=list)
    goal_true: list[np.ndarray] = field(default_factory=list)
    goal_region: list[np.ndarray] = field(default_factory=list)
    goal_track: list[np.ndarray] = field(default_factory=list)

    def add(self, record: EpisodeRecord, mask: np.ndarray) -> None:
        """Add the pairs of ``record`` selected by ``mask`` (T, M); goal judgements only for
        a speed goal."""
        true = np.linalg.norm(record.mover_velocity, axis=-1)[mask]
        region = region_estimates(record)[mask]
        track = np.full(true.shape, np.nan) if record.track_speed is None else record.track_speed[mask]
        self.true.append(true)
        self.region.append(region)
        self.track.append(track)
        if record.goal.feature is Feature.SPEED:
            matched = ~np.isnan(track)
            self.goal_true.append(record.goal.is_fulfilled(true))
            self.goal_region.append(record.goal.is_fulfilled(region))
            self.goal_track.append(np.where(matched, record.goal.is_fulfilled(np.nan_to_num(track)), np.nan))

    def array(self, name: str) -> np.ndarray:
        """The pooled entries of ``name`` (float)."""
        parts = getattr(self, name)
        return np.concatenate(parts).astype(float) if parts else np.zeros(0)


def _prefixed(prefix: str, stats: Mapping[str, float]) -> dict[str, float]:
    return {f"{prefix}_{name}": value for name, value in stats.items()}


def _agreement(judged: np.ndarray, truth: np.ndarray) -> float:
    """Fraction of the pairs where ``judged`` (1/0, NaN = no judgement) equals ``truth``."""
    keep = ~np.isnan(judged)
    return float(np.mean(judged[keep] == truth[keep])) if keep.any() else math.nan


def speed_metrics(records: Iterable[EpisodeRecord]) -> dict[str, float]:
    """Speed-error, static-structure and goal-classification figures of a configuration.

    Keys: ``region_*`` / ``transient_region_*`` (``error_stats`` of the region estimate on
    steady / transient pairs), ``track_*`` / ``transient_track_*`` and
    ``track_unmatched_frac`` (steady pairs without a matched track) when tracks exist,
    ``static_regions``, ``static_median_mps``, ``static_p90_mps`` (speed of the regions
    that see static structure only), ``goal_agreement_region`` / ``goal_agreement_track``
    (fraction of steady pairs, speed goals only; NaN otherwise).
    """
    records = list(records)
    steady, transient = Pairs(), Pairs()
    for record in records:
        steady_mask, transient_mask = pair_masks(record)
        steady.add(record, steady_mask)
        transient.add(record, transient_mask)
    metrics: dict[str, float] = {}
    for prefix, pairs in (("region", steady), ("transient_region", transient)):
        metrics |= _prefixed(prefix, error_stats(pairs.array("region"), pairs.array("true")))
    if any(record.track_speed is not None for record in records):
        for prefix, pairs in (("track", steady), ("transient_track", transient)):
            track, true = pairs.array("track"), pairs.array("true")
            matched = ~np.isnan(track)
            metrics |= _prefixed(prefix, error_stats(track[matched], true[matched]))
        unmatched = np.isnan(steady.array("track"))
        metrics["track_unmatched_frac"] = float(unmatched.mean()) if unmatched.size else math.nan
    static = np.concatenate([r.region_speed[r.static_region] for r in records])
    metrics["static_regions"] = int(static.size)
    metrics["static_median_mps"] = float(np.median(static)) if static.size else math.nan
    metrics["static_p90_mps"] = float(np.percentile(static, 90)) if static.size else math.nan
    goal_true = steady.array("goal_true")
    metrics["goal_agreement_region"] = _agreement(steady.array("goal_region"), goal_true)
    metrics["goal_agreement_track"] = _agreement(steady.array("goal_track"), goal_true)
    return metrics


def focus_on_target(records: Iterable[EpisodeRecord]) -> dict[str, tuple[float, int]]:
    """Per goal (``str(goal)``): the fraction of the steps with the target in view
    (``in_view``) at which the focus is the target's region, and the number of such steps
    (NaN rate for none)."""
    hits: dict[str, list[int]] = {}
    for record in records:
        target_xy = record.mover_xy[:, record.target]
        visible = in_view(target_xy)
        on_target = record.focus[visible] == region_of(target_xy[visible])
        counts = hits.setdefault(str(record.goal), [0, 0])
        counts[0] += int(on_target.sum())
        counts[1] += int(visible.sum())
    return {goal: (on / n if n else math.nan, n) for goal, (on, n) in hits.items()}


def target_cases(records: Iterable[EpisodeRecord]) -> dict[str, float]:
    """The fraction of the steps with the target in view (``in_view``) that falls in each of
    ``TARGET_CASES`` (keys ``case_...``), over the records that have cases."""
    counts = np.zeros(len(TARGET_CASES))
    for record in records:
        if record.target_case is not None:
            visible = in_view(record.mover_xy[:, record.target])
            counts += np.bincount(record.target_case[visible], minlength=len(TARGET_CASES))
    total = counts.sum()
    return {_case_key(case): (n / total if total else math.nan) for case, n in zip(TARGET_CASES, counts)}


def _age_bin_key(low: float, high: float) -> str:
    return f"focus_on_target_track_{low:g}_to_{high:g}_s" if math.isfinite(high) else f"focus_on_target_track_over_{low:g}_s"


def focus_by_track_age(records: Iterable[EpisodeRecord]) -> dict[str, float]:
    """Focus on target (as ``focus_on_target``, both goals) over the in-view steps at which
    the target has no track (``focus_on_target_no_track``) or a track whose age falls in
    each bin of ``TRACK_AGE_BINS_S``, with each group's share of the steps (``steps_...``);
    NaN rates for empty groups, {} without recorded ages."""
    keys = ["focus_on_target_no_track"] + [_age_bin_key(lo, hi) for lo, hi in zip(TRACK_AGE_BINS_S, TRACK_AGE_BINS_S[1:])]
    hits = np.zeros((len(keys), 2))  # [group] × [on target, steps]
    for record in records:
        if record.target_track_age is None:
            continue
        target_xy = record.mover_xy[:, record.target]
        visible = in_view(target_xy)
        age = record.target_track_age
        group = np.where(np.isnan(age), 0, np.searchsorted(TRACK_AGE_BINS_S, np.nan_to_num(age), side="right"))
        on_target = record.focus == region_of(target_xy)
        for index in range(len(keys)):
            mask = visible & (group == index)
            hits[index] += on_target[mask].sum(), mask.sum()
    total = hits[:, 1].sum()
    if not total:
        return {}
    rates = {key: (on / n if n else math.nan) for key, (on, n) in zip(keys, hits)}
    shares = {"steps_" + key[len("focus_on_target_"):]: n / total for key, (_, n) in zip(keys, hits)}
    return {**rates, **shares}


def focus_after_turns(records: Iterable[EpisodeRecord]) -> dict[str, float]:
    """Focus on target (as ``focus_on_target``, both goals) over the in-view steps within
    ``TRANSIENT_S`` after the target turned (``turns``), and over the others."""
    hits = np.zeros((2, 2))  # [after a turn, otherwise] × [on target, steps]
    for record in records:
        target_xy = record.mover_xy[:, record.target]
        visible = in_view(target_xy)
        after = time_since(record.t_s, turns(record.mover_velocity))[:, record.target] <= TRANSIENT_S
        on_target = record.focus == region_of(target_xy)
        for row, mask in enumerate((visible & after, visible & ~after)):
            hits[row] += on_target[mask].sum(), mask.sum()
    rates = [on / n if n else math.nan for on, n in hits]
    return {"focus_on_target_after_turn": rates[0], "focus_on_target_otherwise": rates[1]}


def _case_key(case: str) -> str:
    return "case_" + case.replace(",", "").replace(" ", "_")


# ===================================================================== sections
@dataclass
class Results:
    """Every figure of the run as tidy rows: section, mode, robot, noise, goal, metric, value
    (and distractors, in the clutter section)."""

    rows: list[dict[str, Any]] = field(default_factory=list)

    def add(self, section: str, config: Mapping[str, str], metrics: Mapping[str, float], goal: str = "") -> None:
        """Add one row per metric of ``metrics`` for configuration ``config``."""
        for metric, value in metrics.items():
            self.rows.append({"section": section, **config, "goal": goal, "metric": metric, "value": value})


def _noise(name: str) -> NoiseSetting:
    return next(setting for setting in NOISE_SETTINGS if setting.name == name)


def _fmt(value: float, digits: int = 3) -> str:
    """A number for a table cell; an em dash for NaN."""
    if isinstance(value, (int, np.integer)):
        return str(value)
    return "—" if value is None or not math.isfinite(value) else f"{value:.{digits}f}"


def markdown_table(headers: list[str], rows: list[list[str]]) -> str:
    """A markdown table with ``headers`` and string cells ``rows``."""
    lines = ["| " + " | ".join(headers) + " |", "|" + "---|" * len(headers)]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines)


def perception_records(modes: Iterable[str], episodes: int, seconds: float, goals: tuple[Goal, ...]):
    """Record ``episodes`` episodes (seeds 0.., goals in turn) per mode, noise setting and
    robot mode. Yields ``(mode, noise name, robot, records or the error that made the
    configuration unavailable)``."""
    for mode in modes:
        for noise in NOISE_SETTINGS:
            try:
                env = make_attentive_env(mode, noise, **PERCEPTION_ARENA)
            except TypeError as error:
                for robot in ROBOT_MODES:
                    yield mode, noise.name, robot, error
                continue
            for robot in ROBOT_MODES:
                records = [
                    record_episode(env, seed, goals[seed % len(goals)],
                                   stand_still if robot == "still" else Wander(seed), seconds)
                    for seed in range(episodes)
                ]
                yield mode, noise.name, robot, records
            env.close()


#: (column header, metric key) of the speed table and of the track table.
SPEED_COLUMNS = (
    ("steady pairs", "region_pairs"), ("median", "region_median_mps"), ("p90", "region_p90_mps"),
    ("RMSE", "region_rmse_mps"), ("transient pairs", "transient_region_pairs"),
    ("transient median", "transient_region_median_mps"), ("transient RMSE", "transient_region_rmse_mps"),
    ("static median m/s", "static_median_mps"), ("static p90 m/s", "static_p90_mps"),
    ("goal agreement", "goal_agreement_region"),
)
TRACK_COLUMNS = (
    ("matched pairs", "track_pairs"), ("unmatched", "track_unmatched_frac"), ("median", "track_median_mps"),
    ("p90", "track_p90_mps"), ("RMSE", "track_rmse_mps"), ("transient median", "transient_track_median_mps"),
    ("transient RMSE", "transient_track_rmse_mps"), ("goal agreement", "goal_agreement_track"),
)


def _cells(metrics: Mapping[str, float], columns) -> list[str]:
    """The table cells of ``metrics`` for ``columns``: m/s to 2 decimals, fractions to 3."""
    return [_fmt(metrics[key], 2 if key.endswith("_mps") else 3) for _, key in columns]


def print_perception(results: Results, modes, episodes: int, seconds: float, sections) -> None:
    """Sections 1–3: speed error, static structure, goal classification, focus on target."""
    goals = tuple(arena.DEFAULT_TASK_GOALS)
    goal_names = [str(goal) for goal in goals]
    speed_rows, track_rows, focus_rows, case_rows, age_rows = [], [], [], [], []
    focus_by_setting: dict[tuple[str, str, str], dict[str, float]] = {}  # (mode, robot, noise) → goal → rate
    for mode, noise, robot, records in perception_records(modes, episodes, seconds, goals):
        config = {"mode": mode, "robot": robot, "noise": noise}
        label = [mode, robot, noise]
        if isinstance(records, Exception):
            note = f"unavailable ({type(records).__name__}: {records})"
            speed_rows.append(label + [note] + [""] * (len(SPEED_COLUMNS) - 1))
            focus_rows.append(label + [note] + [""] * (len(goal_names) - 1))
            continue
        metrics = speed_metrics(records)
        if "speed" in sections:
            results.add("speed", config, metrics)
        speed_rows.append(label + _cells(metrics, SPEED_COLUMNS))
        if "track_pairs" in metrics:
            track_rows.append(label + _cells(metrics, TRACK_COLUMNS))
        focus = focus_on_target(records)
        focus_by_setting[(mode, robot, noise)] = {goal: rate for goal, (rate, _) in focus.items()}
        for goal, (rate, steps) in focus.items():
            if "focus" in sections:
                results.add("focus", config, {"focus_on_target": rate, "target_in_view_steps": steps}, goal=goal)
        focus_rows.append(label + [f"{_fmt(focus.get(g, (math.nan, 0))[0])} ({focus.get(g, (math.nan, 0))[1]})"
                                   for g in goal_names])
        cases = target_cases(records)
        if not math.isnan(cases[_case_key(TARGET_CASES[0])]):
            after_turns = focus_after_turns(records)
            if "focus" in sections:
                results.add("focus", config, {**cases, **after_turns})
            case_rows.append(label + [_fmt(cases[_case_key(case)], 3) for case in TARGET_CASES]
                             + [_fmt(after_turns[key], 3) for key in after_turns])
        by_age = focus_by_track_age(records)
        if by_age:
            if "focus" in sections:
                results.add("focus", config, by_age)
            rates = [key for key in by_age if key.startswith("focus_on_target_")]
            age_rows.append(label + [f"{_fmt(by_age[key])} ({_fmt(by_age['steps_' + key[len('focus_on_target_'):]], 2)})"
                                     for key in rates])
    header = ["mode", "robot", "noise"]
    print(f"\n### Perception ({episodes} episodes × {seconds:g} s per row, seeds 0..{episodes - 1}, "
          f"10 m arena, 3 distractors; goals in turn: {', '.join(goal_names)})")
    if "speed" in sections:
        print("\nSpeed of the region a mover lies in vs its true speed, |error| in m/s, over (mover, step) pairs "
              f"in front within {VIEW_RANGE_M:g} m for ≥ {SETTLE_S:g} s; transient = within {TRANSIENT_S:g} s after "
              "a turn; static = regions whose echoes all come from static structure; goal agreement = "
              "`goal.is_fulfilled` of the estimate equals that of the truth (steady pairs, speed goals).\n")
        print(markdown_table(header + [name for name, _ in SPEED_COLUMNS], speed_rows))
        if track_rows:
            print(f"\nTrack speed (nearest confirmed track within {TRACK_MATCH_M:g} m of the mover) vs true speed, "
                  "|error| in m/s, same pairs; unmatched = fraction of steady pairs without a track.\n")
            print(markdown_table(header + [name for name, _ in TRACK_COLUMNS], track_rows))
    if "focus" in sections:
        print("\nFocus on target: fraction of the steps with the target in front within "
              f"{VIEW_RANGE_M:g} m at which the focus is the target's region (steps in brackets); "
              f"chance = 1/{GRID.n_regions} = {1 / GRID.n_regions:.3f}.\n")
        print(markdown_table(header + [f"`{g}`" for g in goal_names], focus_rows))
        relative_rows = _focus_relative_to_noise_free(results, focus_by_setting, goal_names)
        if relative_rows:
            print(f"\nFocus on target relative to the same mode and robot noise-free (`{NOISE_SETTINGS[0].name}`): "
                  "how much of the model's own noise-free focus each noise setting leaves.\n")
            print(markdown_table(header + [f"`{g}`" for g in goal_names], relative_rows))
        if case_rows:
            print("\nWhy the focus is or is not on the target, as fractions of the same steps (both goals; "
                  f"`TARGET_CASES`): perception misses it (hidden from the laser; seen but no confirmed track within "
                  f"{TRACK_MATCH_M:g} m; a track younger or older than {SETTLE_S:g} s, but the goal is not judged to "
                  "hold in the target's region), or the goal holds there and the selection goes elsewhere. "
                  f"Then the focus on target within {TRANSIENT_S:g} s after the target turned, and at the other "
                  "steps.\n")
            print(markdown_table(header + list(TARGET_CASES) + ["on target after a turn", "on target otherwise"],
                                 case_rows))
        if age_rows:
            bins = [f"{lo:g}–{hi:g} s" if math.isfinite(hi) else f"≥ {lo:g} s"
                    for lo, hi in zip(TRACK_AGE_BINS_S, TRACK_AGE_BINS_S[1:])]
            print("\nFocus on target by the age of the target's track (the confirmed track nearest to it within "
                  f"{TRACK_MATCH_M:g} m), both goals; each group's share of the steps in brackets. A young track's "
                  "speed is not yet known well enough to judge the goal.\n")
            print(markdown_table(header + ["no track"] + bins, age_rows))


def _focus_relative_to_noise_free(results: Results, focus_by_setting: Mapping[tuple[str, str, str], Mapping[str, float]],
                                  goal_names: list[str]) -> list[list[str]]:
    """Rows of the focus on target of every noisy setting divided by that of the same mode and
    robot noise-free (NaN where either is undefined), each ratio also added to ``results``
    as ``focus_over_noise_free``."""
    rows = []
    for (mode, robot, noise), rates in focus_by_setting.items():
        noise_free = focus_by_setting.get((mode, robot, NOISE_SETTINGS[0].name))
        if noise == NOISE_SETTINGS[0].name or noise_free is None:
            continue
        cells = []
        for goal in goal_names:
            reference = noise_free.get(goal, math.nan)
            ratio = rates.get(goal, math.nan) / reference if reference > 0.0 else math.nan
            results.add("focus", {"mode": mode, "robot": robot, "noise": noise}, {"focus_over_noise_free": ratio},
                        goal=goal)
            cells.append(_fmt(ratio))
        rows.append([mode, robot, noise] + cells)
    return rows


def control_success(env, make_policy: Callable[[Any, int], Policy], seeds: Iterable[int]) -> float:
    """Fraction of the episodes (one per seed) that end in ``info["success"]`` before
    truncation; ``make_policy(env, seed)`` gives each episode's policy."""
    seeds = list(seeds)
    successes = 0
    for seed in seeds:
        obs, info = env.reset(seed=seed)
        policy = make_policy(env, seed)
        terminated = truncated = False
        while not (terminated or truncated):
            obs, _, terminated, truncated, info = env.step(policy(obs, info))
        successes += bool(info["success"])
    return successes / len(seeds)


def print_clutter(results: Results, modes, episodes: int, seconds: float, control_episodes: int) -> None:
    """Section 5: focus on target (robot driving) and controller success per distractor count."""
    goals = tuple(arena.DEFAULT_TASK_GOALS)
    noise = _noise(CLUTTER_NOISE)
    seeds = range(control_episodes)
    rows, case_rows = [], []
    for distractors in CLUTTER_DISTRACTORS:
        world = {**CLUTTER_ARENA, "num_distractors": distractors}
        raw = make_raw_env(noise, **world)
        oracle = control_success(raw, lambda env, seed: true_bearing_controller, seeds)
        random = control_success(raw, lambda env, seed: RandomController(env.action_space, seed), seeds)
        raw.close()
        for mode in modes:
            env = make_attentive_env(mode, noise, **world)
            records = [record_episode(env, seed, goals[seed % len(goals)], Wander(seed), seconds)
                       for seed in range(episodes)]
            per_goal = [(rate * n, n) for rate, n in focus_on_target(records).values() if n]  # both goals together
            on, steps = sum(on for on, _ in per_goal), sum(n for _, n in per_goal)
            focus = on / steps if steps else math.nan
            env.close()
            focus_env = make_attentive_env(mode, noise, "focus", **world)
            memory = control_success(focus_env, lambda env, seed: memory_controller, seeds)
            focus_env.close()
            memory_ratio = memory / oracle if oracle else math.nan
            cases = target_cases(records)
            results.add("clutter", {"mode": mode, "robot": "driving", "noise": noise.name, "distractors": distractors},
                        {"focus_on_target": focus, "target_in_view_steps": int(steps), **cases})
            if not math.isnan(cases[_case_key(TARGET_CASES[0])]):
                case_rows.append([str(distractors), mode] + [_fmt(cases[_case_key(case)]) for case in TARGET_CASES])
            results.add("clutter", {"mode": mode, "robot": "controller", "noise": noise.name,
                                    "distractors": distractors},
                        {"success_memory": memory, "success_true_bearing": oracle, "success_random": random,
                         "memory_over_true_bearing": memory_ratio})
            rows.append([str(distractors), mode, f"{_fmt(focus)} ({int(steps)})", _fmt(memory, 2), _fmt(oracle, 2),
                         _fmt(random, 2), _fmt(memory_ratio, 2)])
    print(f"\n### Clutter (8 m arena, 3 rubble pieces per 100 m², {noise.name} noise; focus on target: "
          f"{episodes} episodes × {seconds:g} s, robot driving, both goals; controllers: {control_episodes} episodes)\n")
    print(markdown_table(["distractors", "mode", "focus on target (steps)", "memory controller", "true bearing",
                          "random", "memory / true bearing"], rows))
    if case_rows:
        print("\nWhy the focus is or is not on the target (`TARGET_CASES`, as in the focus section), robot driving:\n")
        print(markdown_table(["distractors", "mode", *TARGET_CASES], case_rows))


def print_control(results: Results, modes, episodes: int) -> None:
    """Section 4: success of the focus and memory controllers, the true-bearing oracle and
    random actions."""
    seeds = range(episodes)
    rows = []
    for noise_name in CONTROL_NOISE:
        noise = _noise(noise_name)
        try:
            raw = make_raw_env(noise, **CONTROL_ARENA)
        except TypeError as error:
            rows += [[mode, noise_name, f"unavailable ({type(error).__name__})", "", "", ""] for mode in modes]
            continue
        oracle = control_success(raw, lambda env, seed: true_bearing_controller, seeds)
        random = control_success(raw, lambda env, seed: RandomController(env.action_space, seed), seeds)
        for mode in modes:
            env = make_attentive_env(mode, noise, **CONTROL_ARENA)
            focus = control_success(env, lambda env, seed: FocusController(env.unwrapped.dt), seeds)
            memory = control_success(make_attentive_env(mode, noise, "focus", **CONTROL_ARENA),
                                     lambda env, seed: memory_controller, seeds)
            ratio = focus / oracle if oracle else math.nan
            memory_ratio = memory / oracle if oracle else math.nan
            results.add("control", {"mode": mode, "robot": "controller", "noise": noise_name},
                        {"success_focus": focus, "success_memory": memory, "success_true_bearing": oracle,
                         "success_random": random, "focus_over_true_bearing": ratio,
                         "memory_over_true_bearing": memory_ratio})
            rows.append([mode, noise_name, _fmt(focus, 2), _fmt(memory, 2), _fmt(oracle, 2), _fmt(random, 2),
                         _fmt(ratio, 2), _fmt(memory_ratio, 2)])
    print(f"\n### Steering controllers (8 m arena, 2 distractors, {episodes} episodes, seeds 0..{episodes - 1}; "
          "success = target reached before the time limit)\n")
    print("The true-bearing and random controllers do not use the model: their rates are the same in every mode.\n")
    print("The memory controller reads only the `focus` observation: the first row of its working memory when "
          "that body matched the goal.\n")
    print(markdown_table(["mode", "noise", "focus controller", "memory controller", "true bearing (oracle)", "random",
                          "focus / true bearing", "memory / true bearing"], rows))


def record_readings(seconds: float, seed: int = 0) -> tuple[list[tuple], Goal]:
    """``(t s, sonar (16,), laser (180,), odometry (2,))`` of every step of a wander in the raw
    env at ``COST_NOISE`` (10 m arena, 3 distractors), for ``seconds`` (s) or until the
    episode ends, and the episode's goal."""
    env = make_raw_env(_noise(COST_NOISE), **PERCEPTION_ARENA)
    obs, info = env.reset(seed=seed)
    policy = Wander(seed)
    readings = []
    while info["time_s"] < seconds - 1e-9:
        obs, _, terminated, truncated, info = env.step(policy(obs, info))
        readings.append((info["time_s"], obs["sonar"].copy(), obs["laser"].copy(), obs["odometry"].copy()))
        if terminated or truncated:
            break
    return readings, env.goal


def time_model_us(model: AttentionModel, readings: list[tuple]) -> tuple[float, float, float]:
    """Wall-clock µs per ``model.step`` over ``readings`` (the model is reset first); of it,
    per call of the compiled step ``attend_one`` (timed in a second pass, so that timing it
    does not slow the first); and per step of a separate ``Tracker`` of the same
    configuration fed the same readings (the model's tracker runs inside its one compiled
    step; 0 without a tracker)."""
    model.reset()
    start = time.perf_counter()
    outputs = [model.step(t, sonar, laser, odometry) for t, sonar, laser, odometry in readings]
    elapsed = time.perf_counter() - start
    compiled = _compiled_step_us(model, readings)
    if model.config.kinematics != "tracker":
        return elapsed / len(readings) * 1e6, compiled, 0.0
    tracker = Tracker(model.config)
    wanted_speed = model._wanted_speed
    channels = outputs[0]._sources[1].shape[0]
    rates, speeds, moving = np.empty(channels), np.empty(channels), np.empty(channels, np.bool_)
    inside, previous_t = 0.0, None
    for (t, _, _, odometry), output in zip(readings, outputs):
        clipped, valid = output._sources[1], output._sources[2]  # the readings the model's tracker took
        dt = 0.0 if previous_t is None else t - previous_t
        previous_t = t
        begin = time.perf_counter()
        tracker.step(t, dt, (float(odometry[0]), float(odometry[1])), True, True, clipped, valid, rates, speeds,
                     moving, wanted_speed)
        inside += time.perf_counter() - begin
    return elapsed / len(readings) * 1e6, compiled, inside / len(readings) * 1e6


def _compiled_step_us(model: AttentionModel, readings: list[tuple]) -> float:
    """µs per call of the model's compiled step (``attend_one``, with numba's dispatch of its
    arguments) over ``readings``, the model reset first: the part of ``model.step`` that no
    Python around it can save."""
    model.reset()
    with CallTimer(model_module, "attend_one") as compiled:
        for t, sonar, laser, odometry in readings:
            model.step(t, sonar, laser, odometry)
    return compiled.seconds / len(readings) * 1e6


def time_env_us(env, actions: list[np.ndarray]) -> float:
    """Wall-clock µs per ``env.step`` over ``actions``, resets excluded."""
    env.reset(seed=0)
    elapsed = 0.0
    for action in actions:
        start = time.perf_counter()
        _, _, terminated, truncated, _ = env.step(action)
        elapsed += time.perf_counter() - start
        if terminated or truncated:
            env.reset()
    return elapsed / len(actions) * 1e6


def print_cost(results: Results, modes, rounds: int) -> None:
    """Section 4: µs per model step per mode beside a raw env step, medians of alternating rounds."""
    readings, goal = record_readings(COST_RECORD_S)
    models = {}
    for mode in modes:
        models[mode] = AttentionModel(AttentionConfig(kinematics=mode, range_noise_rel=_noise(COST_NOISE).sigma_rel))
        models[mode].set_goals(goal)
    env = make_raw_env(_noise(COST_NOISE), **PERCEPTION_ARENA)
    env.action_space.seed(0)
    actions = [env.action_space.sample() for _ in readings]
    parts = ("", " compiled", " tracker")
    times: dict[str, list[float]] = {f"{mode}{part}": [] for mode in modes for part in parts}
    times["env"] = []
    for round_index in range(rounds + 1):  # round 0 warms up (numba compiles) and is dropped
        figures = {}
        for mode, model in models.items():
            for part, value in zip(parts, time_model_us(model, readings)):
                figures[f"{mode}{part}"] = value
        figures["env"] = time_env_us(env, actions)
        if round_index:
            for name, value in figures.items():
                times[name].append(value)
    env_us = statistics.median(times["env"])
    rows = []
    for mode in modes:
        model_us, compiled_us = statistics.median(times[mode]), statistics.median(times[f"{mode} compiled"])
        metrics = {"model_step_us": model_us, "env_step_us": env_us, "model_over_env": model_us / env_us,
                   "compiled_step_us": compiled_us, "compiled_over_env": compiled_us / env_us}
        tracker_cells = ["—", "—"]
        if models[mode]._tracker is not None:
            tracker_us = statistics.median(times[f"{mode} tracker"])
            metrics.update(tracker_step_us=tracker_us, tracker_over_env=tracker_us / env_us)
            tracker_cells = [f"{tracker_us:.1f}", f"{tracker_us / env_us:.2f}"]
        results.add("cost", {"mode": mode, "robot": "driving", "noise": COST_NOISE}, metrics)
        rows.append([mode, f"{model_us:.1f}", f"{compiled_us:.1f}", tracker_cells[0], f"{env_us:.1f}",
                     f"{model_us / env_us:.2f}", f"{compiled_us / env_us:.2f}", tracker_cells[1]])
    print(f"\n### Model step cost (readings of a {len(readings)}-step driving episode at 5 % noise; "
          f"medians of {rounds} alternating rounds)\n")
    print(markdown_table(["mode", "model step µs", "of which the compiled step µs", "the tracker alone µs",
                          "raw env step µs", "model / env step", "compiled step / env step", "tracker / env step"],
                         rows))


def write_csv(path: Path, rows: list[dict[str, Any]]) -> None:
    """Write the tidy ``rows`` to ``path`` atomically (a temporary file, then ``os.replace``)."""
    fields = ["section", "mode", "robot", "noise", "goal", "metric", "value", "distractors"]
    with atomic_file(path) as file:
        writer = csv.DictWriter(file, fieldnames=fields, restval="")
        writer.writeheader()
        writer.writerows(rows)


def _choices(text: str, allowed: tuple[str, ...]) -> list[str]:
    """A comma-separated list of names, each one of ``allowed``."""
    names = [name.strip() for name in text.split(",") if name.strip()]
    unknown = [name for name in names if name not in allowed]
    if unknown or not names:
        raise argparse.ArgumentTypeError(f"unknown or no names {unknown}; allowed: {', '.join(allowed)}")
    return names


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--modes", type=lambda s: _choices(s, MODES), default=list(MODES))
    parser.add_argument("--episodes", type=int, default=24, help="episodes per row of sections speed and focus")
    parser.add_argument("--seconds", type=float, default=20.0, help="length of those episodes (s)")
    parser.add_argument("--control-episodes", type=int, default=40, help="episodes per controller (seeds 0..N-1)")
    parser.add_argument("--rounds", type=int, default=5, help="timing rounds of the cost section")
    parser.add_argument("--sections", type=lambda s: _choices(s, SECTIONS), default=list(DEFAULT_SECTIONS),
                        help=f"comma-separated, of {', '.join(SECTIONS)} (default: {','.join(DEFAULT_SECTIONS)})")
    parser.add_argument("--csv", type=Path, default=None, help="also write the figures as a tidy CSV")
    args = parser.parse_args(argv)
    start = time.perf_counter()
    results = Results()
    if {"speed", "focus"} & set(args.sections):
        print_perception(results, args.modes, args.episodes, args.seconds, args.sections)
    if "control" in args.sections:
        print_control(results, args.modes, args.control_episodes)
    if "cost" in args.sections:
        print_cost(results, args.modes, args.rounds)
    if "clutter" in args.sections:
        print_clutter(results, args.modes, args.episodes, args.seconds, args.control_episodes)
    if args.csv is not None:
        write_csv(args.csv, results.rows)
        print(f"\nwrote {len(results.rows)} rows to {args.csv}")
    print(f"\n(run time {time.perf_counter() - start:.0f} s)")


if __name__ == "__main__":
    main()
