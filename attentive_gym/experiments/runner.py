"""Run one of the paper's experiments: the immobile robot in its scenario, the model attending.

- ``run_experiment(name, noise, seed, out_dir)``: step ``AttentiveRescueEnv`` with zero
  commands and the ``AttentionModel`` configured by the registry; returns an
  ``ExperimentResult`` and, with ``out_dir``, writes ``DIR/NAME.npz`` (the trace, in the
  ``TraceRecorder`` format) and ``DIR/NAME.png`` (the figure).
- ``ExperimentResult``: the trace plus the ground truth of the run (mover positions) and
  the goal in force at each step.
"""

from __future__ import annotations

import math
import numbers
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from attentive_gym.attention import AttentionConfig, AttentionModel, Trace, TraceRecorder
from attentive_gym.attention.regions import FRONT_SONARS
from attentive_gym.attention.trace import save_trace
from attentive_gym.envs.rescue_env import AttentiveRescueEnv
from attentive_gym.experiments.registry import Experiment, get_experiment

__all__ = ["ExperimentResult", "run_experiment", "DT_S", "MAX_NOISE"]

#: Step of the experiments (s), the paper's 20 Hz.
DT_S = 0.05
#: Largest relative noise σ accepted (the env's bound).
MAX_NOISE = 0.5


@dataclass(frozen=True, eq=False)
class ExperimentResult:
    """One run of an experiment.

    Attributes:
        experiment: the registry entry that was run.
        noise: relative σ of the sensor noise (0 = exact readings).
        seed: the env's seed (drives the noise).
        trace: the model's outputs and readings (T steps, J = 8 regions).
        mover_positions: ``(T, K, 2)`` world positions (m) of the K moving robots.
        mover_names: their names, ``(K,)``.
        sees: ``(T, K, 8)`` bool, front sonar n's echo at step k comes from mover i
            (the noise-free truth of which sonar sees which robot).
        goal_index: ``(T,)`` int, which goal set was in force at each step: 0 the
            experiment's initial goals, i > 0 those of ``goal_changes[i - 1]``.
        paths: files written (trace ``.npz``, figure ``.png``), empty without ``out_dir``.
    """

    experiment: Experiment
    noise: float
    seed: int
    trace: Trace
    mover_positions: np.ndarray
    mover_names: tuple[str, ...]
    sees: np.ndarray
    goal_index: np.ndarray
    paths: tuple[Path, ...] = ()


def run_experiment(name: str, noise: float = 0.0, seed: int = 0,
                   out_dir: str | os.PathLike | None = None, figure: bool = True) -> ExperimentResult:
    """Run experiment ``name`` with the robot immobile at the origin.

    Args:
        name: "exp01" … "exp05".
        noise: relative σ of the multiplicative Gaussian sensor noise, in [0, 0.5].
        seed: seed of the env (an int >= 0); with noise 0 it does not matter.
        out_dir: folder to write ``NAME.npz`` (trace) and ``NAME.png`` (figure) into;
            None writes nothing.
        figure: with ``out_dir``, also write the figure.

    Returns:
        The ``ExperimentResult``; the same arguments give the same trace bit for bit.

    Raises:
        ValueError: for an unknown name, a noise outside [0, 0.5] or a bad seed.
    """
    experiment = get_experiment(name)
    noise = _check_noise(noise)
    seed = _check_seed(seed)
    env = AttentiveRescueEnv(experiment.name, sensor_noise=noise, dt=DT_S, time_limit_s=experiment.duration_s)
    model = AttentionModel(AttentionConfig(ego_motion=None))  # the paper's immobile robot
    model.set_weights(experiment.weights)
    recorder = TraceRecorder(model.config)
    changes = experiment.goal_changes
    n_steps = int(round(experiment.duration_s / DT_S)) + 1
    positions, owners, goal_index = [], [], np.empty(n_steps, dtype=np.int64)
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
        recorder.append(model.step(t, sonar, laser, observation["odometry"]), sonar, laser)
        positions.append(info["mover_positions"])
        owners.append(info["sonar_hits"][:FRONT_SONARS])
    env.close()
    result = ExperimentResult(
        experiment=experiment, noise=noise, seed=seed, trace=recorder.to_trace(),
        mover_positions=np.stack(positions), mover_names=tuple(info["mover_names"]),
        sees=np.stack(owners)[:, None, :] == mover_ids[None, :, None], goal_index=goal_index,
    )
    if out_dir is None:
        return result
    out = Path(out_dir)
    paths = [save_trace(result.trace, out / f"{name}.npz")]
    if figure:
        from attentive_gym.experiments.figures import plot_experiment

        paths.append(plot_experiment(result, out / f"{name}.png"))
    return ExperimentResult(**{**vars(result), "paths": tuple(paths)})


def _check_noise(noise) -> float:
    ok = isinstance(noise, numbers.Real) and not isinstance(noise, bool) and math.isfinite(noise)
    if not ok or not 0.0 <= noise <= MAX_NOISE:
        raise ValueError(f"noise must be a relative σ in [0, {MAX_NOISE}] (e.g. 0.05 for 5 %), got {noise!r}")
    return float(noise)


def _check_seed(seed) -> int:
    if isinstance(seed, bool) or not isinstance(seed, numbers.Integral) or seed < 0:
        raise ValueError(f"seed must be an int >= 0, got {seed!r}")
    return int(seed)
