"""Run one of the paper's experiments: the immobile robot in its scenario, the model attending.

- ``run_experiment(name, noise, seed, out_dir, figure, *, kinematics, profile, config)``:
  step ``AttentiveRescueEnv`` with zero commands and the ``AttentionModel`` configured by
  the registry; returns an ``ExperimentResult`` and, with ``out_dir``, writes
  ``DIR/NAME.npz`` (the trace, in the ``TraceRecorder`` format) and ``DIR/NAME.png`` (the
  figure). ``kinematics="truth"`` runs the perfect-perception bound instead: the same model
  with the simulator's true kinematics (``attentive_gym.perception.bound``).
- ``experiment_model(config, kinematics)``: the model a run of that kinematics steps.
- ``experiment_config(kinematics, noise_model, noise, config)``: the model's
  ``AttentionConfig`` for a run.
- ``ExperimentResult`` (from ``attentive_gym.experiments.result``): the trace plus the
  ground truth of the run.
"""

from __future__ import annotations

import dataclasses
import math
import numbers
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from attentive_gym.attention import AttentionConfig, AttentionModel, TraceRecorder
from attentive_gym.attention.config import KINEMATICS_MODES
from attentive_gym.attention.io.trace import save_trace
from attentive_gym.attention.regions import FRONT_SONARS
from attentive_gym.envs.rescue_env import AttentiveRescueEnv
from attentive_gym.experiments.figures import plot_experiment
from attentive_gym.experiments.registry import get_experiment
from attentive_gym.experiments.result import ExperimentResult
from attentive_gym.perception.bound import PerfectPerceptionModel, TrueScene
from attentive_gym.sensors import SENSOR_PROFILES, LaserConfig, resolve_sensor_profile

__all__ = [
    "ExperimentResult",
    "run_experiment",
    "experiment_config",
    "experiment_model",
    "DT_S",
    "MAX_NOISE",
    "FIXED_FIELDS",
    "TRUTH",
    "EXPERIMENT_KINEMATICS",
]

#: Step of the experiments (s), the paper's 20 Hz.
DT_S = 0.05
#: Largest relative noise level accepted (the env's bound).
MAX_NOISE = 0.5
#: ``AttentionConfig`` fields the runner sets itself (``config`` may not override them):
#: the paper's immobile robot (``ego_motion=None``) and the ``kinematics`` keyword.
FIXED_FIELDS = ("ego_motion", "kinematics")
_CONFIG_FIELDS = frozenset(f.name for f in dataclasses.fields(AttentionConfig))
#: The runner's kinematics beyond the model's modes: the simulator's true kinematics fed to the
#: same model (``PerfectPerceptionModel``), which frames each check as the perfect-perception
#: bound frames the perception benchmark's figures.
TRUTH = "truth"
#: Every ``kinematics`` a run accepts: the model's modes, then ``TRUTH``.
EXPERIMENT_KINEMATICS = (*KINEMATICS_MODES, TRUTH)


def run_experiment(
    name: str,
    noise: float | None = None,
    seed: int = 0,
    out_dir: str | os.PathLike | None = None,
    figure: bool = True,
    *,
    kinematics: str = "tracker",
    profile: str | None = None,
    config: Mapping[str, Any] | None = None,
) -> ExperimentResult:
    """Run experiment ``name`` with the robot immobile at the origin.

    The model is ``AttentionConfig(ego_motion=None, kinematics=kinematics,
    range_noise_rel=σ)`` with σ the relative standard deviation of the run's range noise
    (``noise`` for Gaussian noise, ``noise / √3`` for the uniform ±noise of the "usarsim"
    profile) and the laser's mounting point of the env's ``LaserConfig``, plus the fields in
    ``config``. When the profile's sensors scan less often than
    the 20 Hz step (readings hold between scans), each step's scan times go to
    ``AttentionModel.step`` (``sonar_time_s``, ``laser_time_s``), so held readings are not
    taken for new ones.

    Args:
        name: "exp01" … "exp05".
        noise: the relative noise level in [0, 0.5]: σ of the multiplicative Gaussian noise,
            or the half-width ``a`` under a uniform-noise profile. None (default): the
            profile's level (±5 % for "usarsim"), or 0 without a profile.
        seed: seed of the env (an int >= 0); with noise 0 it does not matter.
        out_dir: folder to write ``NAME.npz`` (trace) and ``NAME.png`` (figure) into;
            None writes nothing.
        figure: with ``out_dir``, also write the figure.
        kinematics: the model's kinematics mode, one of "tracker" (default), "window",
            "literal" (``AttentionConfig.kinematics``), or "truth": the perfect-perception
            bound, the model (as "tracker") fed each step's true kinematics of the movers the
            laser sees (``PerfectPerceptionModel``).
        profile: the env's ``sensor_profile``: None (Gaussian noise, both sensors scanned
            every step) or a name of ``attentive_gym.sensors.SENSOR_PROFILES`` ("usarsim":
            uniform noise, 5 Hz scans).
        config: further ``AttentionConfig`` fields (e.g. ``{"normalise_combined": False,
            "threshold": 0.2}``, or a tracker constant); ``range_noise_rel`` given here
            replaces the one derived from the noise. ``ego_motion`` and ``kinematics`` are
            set by the runner.

    Returns:
        The ``ExperimentResult``; the same arguments give the same trace bit for bit.

    Raises:
        ValueError: for an unknown name, kinematics mode or profile, a noise outside
            [0, 0.5], a bad seed, or a ``config`` that is not a mapping of valid
            ``AttentionConfig`` fields.
    """
    experiment = get_experiment(name)
    kinematics = _check_kinematics(kinematics)
    profile = _check_profile(profile)
    settings = resolve_sensor_profile(profile)
    noise = settings.noise if noise is None and profile is not None else _check_noise(0.0 if noise is None else noise)
    seed = _check_seed(seed)
    laser = LaserConfig()  # the env's laser, and where it sits for the tracker
    model = experiment_model(
        experiment_config(
            kinematics, settings.noise_model, noise, config, laser_mount_m=(laser.mount_x_m, laser.mount_y_m)
        ),
        kinematics,
    )
    holds = settings.sonar_scan_interval_s is not None or settings.laser_scan_interval_s is not None
    env = AttentiveRescueEnv(
        experiment.name,
        sensor_profile=profile,
        sensor_noise=noise,
        dt=DT_S,
        time_limit_s=experiment.duration_s,
        laser=laser,
    )
    model.set_weights(experiment.weights)
    recorder = TraceRecorder(model.config)
    changes = experiment.goal_changes
    n_steps = int(round(experiment.duration_s / DT_S)) + 1
    positions, velocities, owners, laser_owners, poses = [], [], [], [], []
    speeds, sonar_times, laser_times = [], [], []
    goal_index = np.empty(n_steps, dtype=np.int64)
    observation, info = env.reset(seed=seed)
    mover_ids = np.array([mover.entity.id for mover in env.world.movers])
    goals_set = 0
    model.set_goals(*experiment.goals)
    still = np.zeros(2, dtype=np.float32)
    for k in range(n_steps):
        if k:
            observation, _, _, _, info = env.step(still)
        t = info["time_s"]
        while goals_set < len(changes) and t >= changes[goals_set].t_s - 1e-9:
            model.set_goals(*changes[goals_set].goals)
            goals_set += 1
        goal_index[k] = goals_set
        sonar, laser = observation["sonar"], observation["laser"]
        scans = {"sonar_time_s": info["sonar_time_s"], "laser_time_s": info["laser_time_s"]} if holds else {}
        if kinematics == TRUTH:
            scans["truth"] = TrueScene.of_info(info, mover_ids)
        output = model.step(t, sonar, laser, observation["odometry"], **scans)
        recorder.append(output, sonar, laser)
        positions.append(info["mover_positions"])
        velocities.append(info["mover_velocities"])
        owners.append(info["sonar_hits"][:FRONT_SONARS])
        laser_owners.append(info["laser_hits"])
        poses.append(info["robot_pose"])
        speeds.append(output.speeds_mps)
        sonar_times.append(info["sonar_time_s"])
        laser_times.append(info["laser_time_s"])
    env.close()
    # (T, 180): the row of the mover each beam's echo comes from, −1 for none
    hits = np.stack(laser_owners)
    laser_movers = np.where(hits[..., None] == mover_ids, np.arange(len(mover_ids)), -1).max(axis=-1)
    result = ExperimentResult(
        experiment=experiment,
        noise=noise,
        seed=seed,
        trace=recorder.to_trace(),
        mover_positions=np.stack(positions),
        mover_velocities=np.stack(velocities),
        mover_names=tuple(info["mover_names"]),
        sees=np.stack(owners)[:, None, :] == mover_ids[None, :, None],
        laser_sees=(laser_movers[:, None, :] == np.arange(len(mover_ids))[None, :, None]).any(axis=2),
        laser_movers=laser_movers,
        robot_poses=np.asarray(poses, dtype=float),
        goal_index=goal_index,
        region_speeds=np.stack(speeds),
        sonar_time_s=np.asarray(sonar_times, dtype=float),
        laser_time_s=np.asarray(laser_times, dtype=float),
        kinematics=kinematics,
        profile=profile,
        noise_model=settings.noise_model,
        scan_times_given=holds,
    )
    if out_dir is None:
        return result
    out = Path(out_dir)
    paths = [save_trace(result.trace, out / f"{name}.npz")]
    if figure:
        paths.append(plot_experiment(result, out / f"{name}.png"))
    return dataclasses.replace(result, paths=tuple(paths))


def experiment_config(
    kinematics: str = "tracker",
    noise_model: str = "gaussian",
    noise: float = 0.0,
    config: Mapping[str, Any] | None = None,
    laser_mount_m: tuple[float, float] | None = None,
) -> AttentionConfig:
    """The model's configuration for a run: ``AttentionConfig(ego_motion=None,
    kinematics=kinematics, range_noise_rel=σ, laser_mount_x_m=x, laser_mount_y_m=y,
    **config)``, σ = ``noise`` (Gaussian) or ``noise / √3`` (uniform ±noise), ``(x, y)`` =
    ``laser_mount_m``, where the env's laser sits on the robot (m; None keeps the config's
    default); the kinematics is "tracker" for ``TRUTH``, whose model runs as the tracker. See
    ``run_experiment``."""
    sigma = noise / math.sqrt(3.0) if noise_model == "uniform" else noise
    fields: dict[str, Any] = {"range_noise_rel": sigma}
    if laser_mount_m is not None:
        fields["laser_mount_x_m"], fields["laser_mount_y_m"] = (float(v) for v in laser_mount_m)
    fields.update(_check_config(config))
    mode = _check_kinematics(kinematics)
    return AttentionConfig(**fields, ego_motion=None, kinematics="tracker" if mode == TRUTH else mode)


def experiment_model(config: AttentionConfig, kinematics: str) -> AttentionModel:
    """The model a run of ``kinematics`` steps: ``PerfectPerceptionModel(config)`` for
    ``TRUTH`` (its ``step`` then takes ``truth=``), else ``AttentionModel(config)``."""
    return PerfectPerceptionModel(config) if _check_kinematics(kinematics) == TRUTH else AttentionModel(config)


def _check_kinematics(kinematics) -> str:
    if not isinstance(kinematics, str) or kinematics not in EXPERIMENT_KINEMATICS:
        raise ValueError(f"kinematics must be one of {', '.join(EXPERIMENT_KINEMATICS)}, got {kinematics!r}")
    return kinematics


def _check_profile(profile) -> str | None:
    if profile is not None and (not isinstance(profile, str) or profile not in SENSOR_PROFILES):
        raise ValueError(f"profile must be None or one of {', '.join(sorted(SENSOR_PROFILES))}, got {profile!r}")
    return profile


def _check_config(config) -> dict[str, Any]:
    if config is None:
        return {}
    if not isinstance(config, Mapping):
        raise ValueError(f"config must be a mapping of AttentionConfig fields, got {type(config).__name__}")
    unknown = sorted(str(key) for key in config if key not in _CONFIG_FIELDS)
    if unknown:
        raise ValueError(f"config has unknown AttentionConfig field(s) {unknown}")
    fixed = sorted(key for key in config if key in FIXED_FIELDS)
    if fixed:
        raise ValueError(
            f"config may not set {fixed}: the runner sets ego_motion=None (the immobile robot) "
            "and kinematics comes from the kinematics argument"
        )
    return dict(config)


def _check_noise(noise) -> float:
    ok = isinstance(noise, numbers.Real) and not isinstance(noise, bool) and math.isfinite(noise)
    if not ok or not 0.0 <= noise <= MAX_NOISE:
        raise ValueError(f"noise must be a relative level in [0, {MAX_NOISE}] (e.g. 0.05 for 5 %), got {noise!r}")
    return float(noise)


def _check_seed(seed) -> int:
    if isinstance(seed, bool) or not isinstance(seed, numbers.Integral) or seed < 0:
        raise ValueError(f"seed must be an int >= 0, got {seed!r}")
    return int(seed)
