"""Reward of the rescue task.

- ``RewardConfig``: the weights, in units that do not depend on the step size.
- ``rescue_reward``: one step's reward from progress, collision, success and time.

Per step of ``dt`` seconds::

    r = progress_per_m · (d_prev − d_now)        # metres gained towards the target
        − collision_per_s · dt · [robot touched anything during the step]
        − time_per_s · dt
        + success · [d_now ≤ success_radius_m]   # the episode then terminates
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["RewardConfig", "rescue_reward"]


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


def rescue_reward(
    config: RewardConfig, dt_s: float, previous_distance_m: float, distance_m: float, collided: bool
) -> tuple[float, bool]:
    """The step's reward and whether the target was reached."""
    success = distance_m <= config.success_radius_m
    reward = (
        config.progress_per_m * (previous_distance_m - distance_m)
        - config.collision_per_s * dt_s * float(collided)
        - config.time_per_s * dt_s
        + config.success * float(success)
    )
    return reward, success
