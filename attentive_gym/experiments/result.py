"""What one run of an experiment produced: the model's trace plus the run's ground truth.

- ``ExperimentResult``: the trace, the noise-free truth (where the robots are, how fast
  they move, which sonar sees which robot), the goal in force at each step, the scan
  times, and how the run was set up (kinematics mode, sensor profile, noise).

This module holds the data only, so that the runner (which makes results), the checks
and the figures (which read them) all import it without importing one another.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from attentive_gym.attention import Trace
from attentive_gym.experiments.registry import Experiment
from attentive_gym.perception.bound import TrueScene

__all__ = ["ExperimentResult"]


@dataclass(frozen=True, eq=False)
class ExperimentResult:
    """One run of an experiment.

    Attributes:
        experiment: the registry entry that was run.
        noise: the relative noise level of the readings (0 = exact): σ for Gaussian noise,
            the half-width ``a`` of ±a for uniform noise.
        seed: the env's seed (drives the noise).
        trace: the model's outputs and readings (T steps, J = 8 regions); its ``config``
            holds the model's ``AttentionConfig``, the kinematics mode included.
        mover_positions: ``(T, K, 2)`` world positions (m) of the K moving robots.
        mover_velocities: ``(T, K, 2)`` their world velocities (m/s).
        mover_names: their names, ``(K,)``.
        sees: ``(T, K, 8)`` bool, front sonar n's echo at step k comes from mover i
            (the noise-free truth of which sonar sees which robot; it holds between scans
            with the readings).
        laser_sees: ``(T, K)`` bool, some laser beam's echo at step k comes from mover i
            (held between scans likewise).
        laser_movers: ``(T, 180)`` int, the mover (row of ``mover_names``) whose body each
            laser beam's echo at step k comes from, −1 for none (held likewise).
        robot_poses: ``(T, 3)`` the robot's x, y (m) and heading (rad) in the world frame.
        goal_index: ``(T,)`` int, which goal set was in force at each step: 0 the
            experiment's initial goals, i > 0 those of ``goal_changes[i - 1]``.
        region_speeds: ``(T, J)`` the model's speed estimate per region (m/s), the
            ``speeds_mps`` of each step's output.
        sonar_time_s, laser_time_s: ``(T,)`` time (s) of the scan each step's sonar and
            laser readings come from (equal to ``trace.t`` when a sensor scans every step).
        kinematics: the model's kinematics mode ("tracker", "window" or "literal"), or
            "truth" for the perfect-perception bound (``runner.TRUTH``; its trace's
            configuration says "tracker").
        profile: the env's ``sensor_profile`` (None or e.g. "usarsim").
        noise_model: "gaussian" or "uniform".
        scan_times_given: the scan times were passed to the model (the sensors scan less
            often than the model steps, so readings hold between scans).
        paths: files written (trace ``.npz``, figure ``.png``), empty without ``out_dir``.
    """

    experiment: Experiment
    noise: float
    seed: int
    trace: Trace
    mover_positions: np.ndarray
    mover_velocities: np.ndarray
    mover_names: tuple[str, ...]
    sees: np.ndarray
    laser_sees: np.ndarray
    laser_movers: np.ndarray
    robot_poses: np.ndarray
    goal_index: np.ndarray
    region_speeds: np.ndarray
    sonar_time_s: np.ndarray
    laser_time_s: np.ndarray
    kinematics: str = "tracker"
    profile: str | None = None
    noise_model: str = "gaussian"
    scan_times_given: bool = False
    paths: tuple[Path, ...] = ()

    @property
    def range_noise_rel(self) -> float:
        """The relative σ of the range noise (dimensionless): ``noise`` for Gaussian noise,
        ``noise / √3`` for uniform ±noise."""
        return self.noise / np.sqrt(3.0) if self.noise_model == "uniform" else self.noise

    def true_scene(self, k: int) -> TrueScene:
        """The simulator's truth at step ``k`` as the perfect-perception model takes it (the
        movers' ids are their rows)."""
        movers = np.arange(len(self.mover_names))
        return TrueScene(
            self.robot_poses[k], self.laser_movers[k], movers, self.mover_positions[k], self.mover_velocities[k]
        )

    def describe_noise(self) -> str:
        """The run's sensors in words, e.g. "no noise", "noise 5 %, seed 0" or
        "usarsim: ±5 % uniform noise, seed 0"."""
        if not self.noise:
            level = "no noise"
        elif self.noise_model == "uniform":
            level = f"±{100 * self.noise:.3g} % uniform noise, seed {self.seed}"
        else:
            level = f"noise {100 * self.noise:.3g} %, seed {self.seed}"
        return f"{self.profile}: {level}" if self.profile else level
