"""Reward of the rescue task.

- ``RewardConfig``: the weights, in units that do not depend on the step size.
- ``rescue_reward``: one step's reward from progress, collision, nearness, success and time.
- ``SAFE_CONTACT_S``: the contact an episode may have and still count as a safe success.

Per step of ``dt`` seconds::

    r = progress_per_m · (p_prev − p_now)        # metres gained towards the target
        − collision_per_s · dt · [robot touched anything during the step]
        − near_per_s · dt · max(0, 1 − clearance / near_m)  # clearance: the nearest sonar reading
        − time_per_s · dt
        + success · [d_now ≤ success_radius_m]   # the episode then terminates

``d`` is the straight-line distance from the robot's centre to the target's; ``p`` is the
distance progress counts: ``d`` itself (``progress="euclidean"``), or the length of the
shortest path round walls and rubble (``progress="geodesic"``, ``envs.geodesic``), so that
a detour round rubble earns what it gains instead of losing what it moves sideways.

With ``contact_limit_s`` set, the episode also terminates, without success, at the first
step after which the robot has been in contact for more than ``contact_limit_s`` seconds
in all (the step's own reward is paid as above).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["PROGRESS_MODES", "SAFE_CONTACT_S", "RewardConfig", "contact_exceeded", "rescue_reward"]

#: s: a success is safe when the robot was in contact for at most this long in the episode.
SAFE_CONTACT_S = 1.0
#: The distances progress may count: the straight line, or the shortest path round walls and rubble.
PROGRESS_MODES = ("euclidean", "geodesic")


@dataclass(frozen=True)
class RewardConfig:
    """Reward weights (all ≥ 0), and the distance progress counts.

    Attributes:
        progress_per_m: reward per metre the robot-to-target distance shrinks.
        progress: the distance that is meant, one of ``PROGRESS_MODES``: ``"euclidean"``, the
            straight line; ``"geodesic"``, the shortest path that keeps the robot 0.3 m clear
            of walls and rubble (``envs.geodesic.GeodesicDistance``; moving bodies are not
            in it). Success is judged on the straight line either way.
        success: bonus on reaching the target (distance ≤ ``success_radius_m``).
        collision_per_s: penalty per second spent touching walls, rubble or movers.
        time_per_s: penalty per second elapsed.
        success_radius_m: centre-to-centre distance that counts as reaching the target.
        near_per_s: penalty per second at zero clearance (the robot's nearest sonar reading,
            m), falling linearly to 0 at a clearance of ``near_m``: a warning before contact.
        near_m: the clearance (m, > 0) below which ``near_per_s`` applies.
        contact_limit_s: seconds of contact (summed over the episode) beyond which the
            episode terminates without success; None: no limit.
    """

    progress_per_m: float = 1.0
    success: float = 10.0
    collision_per_s: float = 2.0
    time_per_s: float = 0.1
    success_radius_m: float = 1.0
    near_per_s: float = 0.0
    near_m: float = 0.3
    contact_limit_s: float | None = None
    progress: str = "euclidean"

    def __post_init__(self) -> None:
        if self.progress not in PROGRESS_MODES:
            raise ValueError(f"RewardConfig.progress must be one of {PROGRESS_MODES}, got {self.progress!r}")
        for name, value in vars(self).items():
            if name == "progress" or (name == "contact_limit_s" and value is None):
                continue
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value >= 0.0):
                allowed = "None or a finite number >= 0" if name == "contact_limit_s" else "a finite number >= 0"
                raise ValueError(f"RewardConfig.{name} must be {allowed}, got {value!r}")
        for name in ("success_radius_m", "near_m"):
            if getattr(self, name) <= 0.0:
                raise ValueError(f"RewardConfig.{name} must be > 0, got {getattr(self, name)}")


def rescue_reward(
    config: RewardConfig,
    dt_s: float,
    progress_m: float,
    distance_m: float,
    collided: bool,
    clearance_m: float,
) -> tuple[float, bool]:
    """The step's reward and whether the target was reached: ``progress_m``, the metres gained
    towards the target over the step (of the distance ``config.progress`` counts);
    ``distance_m``, the straight-line distance to it after the step; ``clearance_m``, the
    robot's nearest sonar reading after the step (m)."""
    success = distance_m <= config.success_radius_m
    reward = (
        config.progress_per_m * progress_m
        - config.collision_per_s * dt_s * float(collided)
        - config.near_per_s * dt_s * max(0.0, 1.0 - clearance_m / config.near_m)
        - config.time_per_s * dt_s
        + config.success * float(success)
    )
    return reward, success


def contact_exceeded(config: RewardConfig, contact_s: float) -> bool:
    """Whether ``contact_s`` seconds of contact in the episode end it (``contact_limit_s``)."""
    return config.contact_limit_s is not None and contact_s > config.contact_limit_s + 1e-9
