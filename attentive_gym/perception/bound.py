"""A perfect-perception bound: the attentional model fed the simulator's true kinematics.

The bound keeps everything of the model but the kinematics (docs/model.md §3, §10): the same
readings, sensorial memory, maps F1–F6, goals, courses (IOR and top-down holds), gain and
selection (§4–§8), with each reading channel's range rate, speed and moving flag taken from
the simulator's truth instead of the tracker's estimates. Its focus on target is what the
model's selection achieves once perception is perfect: with chance (1/8) it frames the
perception benchmark's figures (``benchmarks/bench_perception.py``, focus section).

- ``true_kinematics``: the ``(188,)`` channel kinematics (8 front sonars, then 180 laser
  beams) of one step from the truth. A mover counts once it lies on at least
  ``SEEN_BEAMS`` laser beams of the current scan (``info["laser_hits"]``): each of its beams
  gets its true speed (m/s, the norm of its world-frame velocity, clipped to
  ``AttentionConfig.max_speed_mps``, as the tracker reports ground speed), its range rate
  (m/s: its ground velocity along the line of sight from the robot, + away, the tracker's
  convention: the robot's own motion compensated) and moving = speed > the direction ε;
  each front sonar's channel (region j) the counted mover in its region that a speed goal
  wants (moving, speed in the goal's band), else the fastest. Every other channel reads 0,
  not moving. It is exactly the tracker's ``track_channels`` run on the counted movers as
  perfectly known, confirmed, surely moving tracks (one per contiguous run of a mover's
  beams), so the rules (region of a body, ranking, clipping, moving) are the model's own;
  the sonars' own range/rate filters, which the tracker falls back on where the laser sees
  nothing, are left out (the truth has no sonar-only bodies).
- ``PerfectPerceptionModel``: an ``AttentionModel`` (kinematics ``"tracker"``, sonar grid)
  whose ``step`` takes the step's truth (``TrueScene``) and runs the model's own compiled
  stages on it: ``sense`` (readings, memory), ``true_kinematics`` in place of ``track_step``,
  then ``sonar_grid_maps`` (§4–§6) and ``select`` (§7–§8), the kernels ``attend_one`` calls.
- ``PerfectPerceptionWrapper``: a raw ``AttentiveRescue-v0`` environment with the bound model
  stepped as ``AttentionWrapper`` steps its model (at reset and every step), its output in
  ``info["attention"]``: ``records.record_episode`` records it as any attended env.
- ``make_bound_env``: that environment, configured as ``settings.make_attentive_env``.

Units: metres, seconds, m/s, radians (world frame x, y; robot frame x forward, y left).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from types import MappingProxyType
from typing import Any, NamedTuple

import gymnasium as gym
import numpy as np

from attentive_gym.attention import AttentionConfig, AttentionModel, AttentionOutput, Goal
from attentive_gym.attention.compiled.records import KEPT_OUTPUTS
from attentive_gym.attention.compiled.step_kernels import select, sense, sonar_grid_maps
from attentive_gym.attention.model import _N_CHANNELS, _output
from attentive_gym.attention.tracking.track_regions import track_channels
from attentive_gym.attention.tracking.tracker import GOAL_PROBABILITY_PARAM
from attentive_gym.perception.motion import VIEW_BEAMS
from attentive_gym.perception.settings import PERCEPTION_TASK
from attentive_gym.wrappers import make_env

__all__ = [
    "SEEN_BEAMS",
    "TrueScene",
    "true_kinematics",
    "PerfectPerceptionModel",
    "PerfectPerceptionWrapper",
    "make_bound_env",
]

#: A mover counts as seen on at least this many laser beams of the scan (as ``motion``'s view).
SEEN_BEAMS = VIEW_BEAMS
_N_SONAR = 8
_N_BEAMS = _N_CHANNELS - _N_SONAR


class TrueScene(NamedTuple):
    """The simulator's truth at one step (``AttentiveRescue-v0``'s info), M movers.

    Attributes:
        robot_pose: ``(3,)`` the robot's x, y (m) and heading (rad), world frame.
        laser_hits: ``(180,)`` int, the entity id each beam of the current scan hit (−1: none).
        mover_ids: ``(M,)`` int, the movers' entity ids.
        mover_xy: ``(M, 2)`` the movers' centres, world frame (m).
        mover_velocity: ``(M, 2)`` their velocities, world frame (m/s).
    """

    robot_pose: np.ndarray
    laser_hits: np.ndarray
    mover_ids: np.ndarray
    mover_xy: np.ndarray
    mover_velocity: np.ndarray

    @classmethod
    def of_info(cls, info: Mapping[str, Any], mover_ids: np.ndarray) -> TrueScene:
        """The truth of a step's ``info`` (``robot_pose``, ``laser_hits``, ``mover_positions``,
        ``mover_velocities``), the movers being ``mover_ids`` (M,)."""
        return cls(
            np.asarray(info["robot_pose"], np.float64),
            np.asarray(info["laser_hits"], np.int64),
            np.asarray(mover_ids, np.int64),
            np.asarray(info["mover_positions"], np.float64).reshape(-1, 2),
            np.asarray(info["mover_velocities"], np.float64).reshape(-1, 2),
        )


def _beam_runs(beams: np.ndarray) -> list[tuple[int, int]]:
    """The contiguous runs ``(start, stop)`` of the sorted beam indices ``beams``."""
    breaks = np.flatnonzero(np.diff(beams) != 1) + 1
    starts = np.concatenate([[0], breaks])
    stops = np.concatenate([breaks, [beams.size]])
    return [(int(beams[a]), int(beams[b - 1]) + 1) for a, b in zip(starts, stops)]


def true_kinematics(
    t_s: float,
    scene: TrueScene,
    tracker_constants: tuple,
    wanted_speed: np.ndarray,
    readings: np.ndarray,
    valid: np.ndarray,
    rates: np.ndarray,
    speeds: np.ndarray,
    moving: np.ndarray,
    region_track: np.ndarray,
    speed_probability: np.ndarray,
) -> np.ndarray:
    """Write one step's true channel kinematics (see the module docstring).

    Args:
        t_s: the step's time (s).
        scene: the step's truth.
        tracker_constants: ``Tracker.constants`` of the model's configuration (the
            confirmation hits, maximum speed, direction ε, the beams' regions, ...).
        wanted_speed: ``(2,)`` the speeds a speed goal wants ``[lo, hi]`` (m/s), ``[inf, inf]``
            without one.
        readings, valid: ``(188,)`` the step's clipped readings (m) and echo flags.
        rates, speeds: ``(188,)`` outputs (m/s); moving: ``(188,)`` bool output;
        region_track: ``(8,)`` int64 output, the row of ``scene``'s movers behind each front
            sonar's channel, −1 for none.
        speed_probability: ``(8,)`` output, the probability that the speed goal holds at
            that mover when the configuration judges so (``track_speed_goal_probability``;
            with the truth's zero covariance, 1 or 0), else −1.

    Returns:
        ``(M,)`` bool: the movers seen on at least ``SEEN_BEAMS`` beams (those that count).
    """
    (_, _, _, _, beam_step, _, confirm_hits, max_speed, epsilon, beam_region, cone_bounds) = tracker_constants[:11]
    match_m, match_sigmas, noise_rel, noise_floor = tracker_constants[11:15]
    hits_of = scene.laser_hits[None, :] == scene.mover_ids[:, None]  # (M, 180)
    seen = hits_of.sum(axis=1) >= SEEN_BEAMS
    # one perfectly known track per contiguous run of a seen mover's beams
    owners, bounds_list = [], []
    for m in np.flatnonzero(seen):
        for run in _beam_runs(np.flatnonzero(hits_of[m])):
            owners.append(m)
            bounds_list.append(run)
    n = len(owners)
    owner = np.array(owners, np.int64)
    cv_x = np.zeros((n, 4))
    if n:
        cv_x[:, :2], cv_x[:, 2:] = scene.mover_xy[owner], scene.mover_velocity[owner]
    bounds = np.array(bounds_list, np.int64).reshape(n, 2)
    slots = np.empty(_N_SONAR, np.int64)
    params = tracker_constants[5]
    track_channels(
        float(t_s),
        scene.robot_pose,
        confirm_hits,
        max_speed,
        epsilon,
        wanted_speed,
        beam_step,
        beam_region,
        cone_bounds,
        match_m,
        match_sigmas,
        noise_rel,
        noise_floor,
        params[GOAL_PROBABILITY_PARAM] != 0.0,
        readings,
        valid,
        cv_x,
        np.zeros((n, 4, 4)),  # known exactly
        np.ones(n),  # surely moving: the velocity as it is, labelled moving above ε
        np.ones(n, np.bool_),
        np.full(n, max(confirm_hits, 1), np.int64),
        np.full(n, float(t_s)),  # known now: no prediction
        np.arange(n, dtype=np.int64),  # track k's segment is run k
        bounds,
        np.zeros((_N_SONAR, 2)),
        np.zeros(_N_SONAR, np.int64),  # no sonar filter: nothing seen by the sonars alone
        rates,
        speeds,
        moving,
        slots,
        speed_probability,
    )
    region_track[:] = -1
    behind = slots >= 0
    region_track[behind] = owner[slots[behind]]
    return seen


class PerfectPerceptionModel(AttentionModel):
    """The attentional model with the simulator's true kinematics (the bound; module docstring).

    Args:
        config: the model's configuration; its ``kinematics`` is set to ``"tracker"`` (the
            readings are not differenced; the channels' kinematics come from the truth).
            Only the sonar grid (the default) is supported.

    Goals, weights, state and ``reset`` are the ``AttentionModel``'s; ``step`` needs the truth.

    Raises:
        ValueError: for a configuration on the laser grid.
    """

    def __init__(self, config: AttentionConfig | None = None) -> None:
        config = AttentionConfig() if config is None else config
        if config.grid != "sonar":
            raise ValueError(f"PerfectPerceptionModel supports the sonar grid only, got grid={config.grid!r}")
        super().__init__(dataclasses.replace(config, kinematics="tracker"))
        constants = self.tracker.constants
        self._max_speed, self._epsilon = constants[7], constants[8]  # m/s, as the compiled step reads them
        self._beam_region = np.asarray(constants[9], np.int64)
        #: ``(8,)`` the row of the latest step's movers behind each front sonar's channel (−1: none).
        self.region_mover = np.full(_N_SONAR, -1, np.int64)
        #: ``(M,)`` the latest step's movers that counted (seen on ``SEEN_BEAMS`` beams or more).
        self.seen = np.zeros(0, np.bool_)

    def step(
        self,
        t: float,
        sonar,
        laser,
        odometry=None,
        *,
        truth: TrueScene,
        sonar_time_s: float | None = None,
        laser_time_s: float | None = None,
    ) -> AttentionOutput:
        """``AttentionModel.step`` (same arguments, checks and output) with the channels'
        kinematics of ``truth`` (``true_kinematics``) in place of the tracker's. The output
        has no tracks."""
        if not isinstance(truth, TrueScene):
            raise ValueError(f"truth must be a TrueScene, got {type(truth).__name__}")
        if truth.laser_hits.shape != (_N_BEAMS,):
            raise ValueError(f"truth.laser_hits must hold {_N_BEAMS} entity ids, got shape {truth.laser_hits.shape}")
        inputs = self._checked(t, sonar, laser, odometry, sonar_time_s, laser_time_s)
        _ = self.model_state  # room for one more course, the arrays views of the state (as ``step``)
        t, _, _, push, _, _, _, _ = self._advance(*inputs)
        _, arrays = self._records.take()
        (readings, valid, rates, region_slot, F, C_BU, C_TD, C, region_speed, distances, nearest) = arrays[:11]
        (origins, directions, fulfilled, M, L, speeds, moving, speed_probability, results) = arrays[11:]
        cfg = self.config
        F.fill(0.0)
        # §2: the readings into the memory (K = 0: the rates are not differenced)
        sense(
            self._row[:_N_CHANNELS],
            self._limits,
            *self._memory.buffers,
            t,
            0,
            self._ego,
            False,
            push,
            readings,
            valid,
            rates,
        )
        # §3 from the truth, in place of the tracker's §10
        self.seen = true_kinematics(
            t,
            truth,
            self.tracker.constants,
            self._wanted_speed,
            readings,
            valid,
            rates,
            speeds,
            moving,
            self.region_mover,
            speed_probability,
        )
        region_slot[:] = -1  # no track table
        sonar_grid_maps(
            readings,
            valid,
            rates,
            speeds,
            moving,
            speed_probability,
            self._max_ranges,
            self._max_speed,
            self._epsilon,
            cfg.max_distance_m,
            cfg.laser_only,
            cfg.laser_max_range_m,
            self._beam_region,
            self._active,
            self._goal_plan,
            self._goal_options,
            self._combine,
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
        )
        winner, fired = select(
            t,
            fulfilled,
            origins,
            C,
            float(self._gain_cell[0]),
            cfg.threshold,
            self._spread,
            *self._courses.arrays,
            M,
            L,
        )
        focus = winner if L[winner] >= cfg.threshold else -1
        results[:] = (winner, focus, L[winner], fired, origins[winner], 0)  # records.RESULTS
        return _output(self, t, arrays[:KEPT_OUTPUTS], results.tolist())


class PerfectPerceptionWrapper(gym.Wrapper):
    """A raw ``AttentiveRescue-v0`` environment whose steps feed ``PerfectPerceptionModel``.

    Args:
        env: the raw environment (``make_env("raw", ...)``).
        config: the model's configuration (``PerfectPerceptionModel``).

    As ``AttentionWrapper`` does, the model is reset with the environment, takes the
    episode's goal (decoded from ``obs["goal"]``) and steps on every observation, reset
    included, with the scan times; ``info["attention"]`` carries its output. The
    observations are the raw ones.
    """

    def __init__(self, env: gym.Env, config: AttentionConfig | None = None) -> None:
        super().__init__(env)
        self.model = PerfectPerceptionModel(config)
        self._mover_ids = np.zeros(0, np.int64)

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        raw, info = self.env.reset(seed=seed, options=options)
        self.model.reset()
        goal = Goal.decode(raw["goal"])
        self.model.set_goals() if goal is None else self.model.set_goals(goal)
        self._mover_ids = np.array([m.entity.id for m in self.env.unwrapped.world.movers], np.int64)
        self._observe(raw, info)
        return raw, info

    def step(self, action):
        raw, reward, terminated, truncated, info = self.env.step(action)
        self._observe(raw, info)
        return raw, reward, terminated, truncated, info

    def _observe(self, raw: Mapping[str, np.ndarray], info: dict[str, Any]) -> None:
        info["attention"] = self.model.step(
            info["time_s"],
            raw["sonar"],
            raw["laser"],
            raw["odometry"],
            truth=TrueScene.of_info(info, self._mover_ids),
            sonar_time_s=info.get("sonar_time_s"),
            laser_time_s=info.get("laser_time_s"),
        )


def make_bound_env(
    range_noise_rel: float = 0.0,
    attention_fields: Mapping[str, Any] = MappingProxyType({}),
    **env_kwargs: Any,
) -> PerfectPerceptionWrapper:
    """The perfect-perception environment: a raw environment (``env_kwargs``: the sensors'
    noise, the arena) with ``PerfectPerceptionModel`` of ``AttentionConfig(range_noise_rel=...,
    **attention_fields)``, as ``settings.make_attentive_env`` configures the model.

    Raises:
        TypeError: when the installed environment does not accept a keyword of ``env_kwargs``.
        ValueError: for a field of ``attention_fields`` that ``AttentionConfig`` refuses.
    """
    fields = {key: value for key, value in attention_fields.items() if key != "kinematics"}
    config = AttentionConfig(kinematics="tracker", range_noise_rel=range_noise_rel, **fields)
    return PerfectPerceptionWrapper(make_env("raw", task=PERCEPTION_TASK, **env_kwargs), config)
