"""Reward of the rescue task.

- ``RewardConfig``: the weights, in units that do not depend on the step size.
- ``rescue_rewards``: k members' rewards from progress, collision, success and time, as arrays.

Per step of ``dt`` seconds::

    r = progress_per_m · (d_prev − d_now)        # metres gained towards the target
        − collision_per_s · dt · [robot touched anything during the step]
        − time_per_s · dt
        + success · [d_now ≤ success_radius_m]   # the episode then terminates
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

__all__ = ["RewardConfig", "rescue_rewards"]


@dataclass(frozen=True)
class RewardConfig:
    """Reward weights (all ≥ 0).

    Attributes:
        progress_per_m: reward per metre the robot-to-target distance shrinks.
        success: bonus on reaching the target (distance ≤ ``success_radius_m``).
        collision_per_s: penalty per second spent touching walls, rubble or movers.
        time_per_s: penalty per second elapsed.
        success_radius_m: centre-to-centre distance that counts as reaching the target.
    """

    progress_per_m: float = 1.0
    success: float = 10.0
    collision_per_s: float = 2.0
    time_per_s: float = 0.1
    success_radius_m: float = 1.0

    def __post_init__(self) -> None:
        for name, value in vars(self).items():
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value >= 0.0):
                raise ValueError(f"RewardConfig.{name} must be a finite number >= 0, got {value!r}")
        if self.success_radius_m <= 0.0:
            raise ValueError(f"RewardConfig.success_radius_m must be > 0, got {self.success_radius_m}")


def rescue_rewards(
    configs: Sequence[RewardConfig],
    dt_s: np.ndarray,
    previous_distance_m: np.ndarray,
    distance_m: np.ndarray,
    collided: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """k members' step rewards, (k,) float64, and whether each reached its target, (k,) bool.

    Args:
        configs: each member's weights (k of them).
        dt_s: (k,) step lengths (s).
        previous_distance_m: (k,) robot-to-target distances (m) before the step.
        distance_m: (k,) the distances after it.
        collided: (k,) bool: the robot touched anything during the step.

    Member j's numbers equal the formula above evaluated in Python floats for it alone, bit
    for bit (the same operations, elementwise, in the same order).
    """
    weights = np.array(
        [(c.progress_per_m, c.collision_per_s, c.time_per_s, c.success, c.success_radius_m) for c in configs]
    ).reshape(-1, 5)
    progress, collision, time, bonus, radius = weights.T
    success = distance_m <= radius
    reward = (
        progress * (previous_distance_m - distance_m)
        - collision * dt_s * collided.astype(np.float64)
        - time * dt_s
        + bonus * success.astype(np.float64)
    )
    return reward, success
