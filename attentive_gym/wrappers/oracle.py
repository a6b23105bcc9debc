"""``OracleFocus``: the ``"focus"`` observation filled from the privileged state.

The ceiling for any attention: the observation has the ``"focus"`` layout
(``attentive_gym.wrappers.encoders.FocusEncoder``), but the attended body is always the
target, read from the simulator rather than perceived:

- ``"region"``: the region of the target's true bearing (no focus when it is behind the
  robot or beyond the laser's range); ``"event"``: origin top-down when in a region.
- ``"sonar"``, ``"laser"``: the (noisy) readings of that region, as the focus has them.
- ``"distance"``, ``"motion"``: the target's true distance and its true ground velocity
  along the line of sight (the range rate) with its direction label.
- ``"features"``: zeros (the oracle runs no feature maps).
- ``"memory"``: its first slot is the target's true bearing, distance and speed, goal
  match 1 and age 0, wherever the target is; the other slots are empty.

It reads ``info["robot_pose"]``, ``info["mover_positions"]``, ``info["mover_velocities"]``
and ``info["target_index"]`` of ``AttentiveRescueEnv``. Never use it as an agent's
observation in a claim about perception: it is a bound.
"""

from __future__ import annotations

import math
from typing import Any

import gymnasium as gym
import numpy as np

from attentive_gym.attention import AttentionConfig, Direction, FocusView
from attentive_gym.attention.regions import LASER_FOV_DEG
from attentive_gym.attention.working_memory import MEMORY_FIELDS
from attentive_gym.wrappers.attention import DEFAULT_MEMORY_SLOTS
from attentive_gym.wrappers.encoders import NO_EVENT, FocusEncoder

__all__ = ["OracleFocus"]

_TOP_DOWN_EVENT = (False, False, True)


class OracleFocus(gym.Wrapper, gym.utils.RecordConstructorArgs):
    """The focus observation of an attention that always sees the target truly.

    Args:
        env: an ``AttentiveRescueEnv`` (possibly wrapped).
        memory_slots: slots of the ``"memory"`` entry (as ``AttentionWrapper``'s).
        config: the ``AttentionConfig`` whose bounds and grid the layout uses (default:
            the default configuration).
        proximity: add the ``"proximity"`` entry, every region's nearest reading (from the
            readings, as ``"focus"`` has it; default False).
    """

    def __init__(
        self,
        env: gym.Env,
        memory_slots: int = DEFAULT_MEMORY_SLOTS,
        config: AttentionConfig | None = None,
        proximity: bool = False,
    ) -> None:
        gym.utils.RecordConstructorArgs.__init__(self, memory_slots=memory_slots, config=config, proximity=proximity)
        gym.Wrapper.__init__(self, env)
        if not isinstance(memory_slots, int) or isinstance(memory_slots, bool) or memory_slots < 0:
            raise ValueError(f"memory_slots must be an integer >= 0, got {memory_slots!r}")
        self.config = AttentionConfig() if config is None else config
        self._encoder = FocusEncoder(self.config, env.observation_space, memory_slots, proximity=proximity)
        self.observation_space = self._encoder.space
        self._memory_slots = memory_slots
        self._grid = self._encoder.grid

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        raw, info = self.env.reset(seed=seed, options=options)
        return self.observe_step(raw, info), info

    def step(self, action):
        raw, reward, terminated, truncated, info = self.env.step(action)
        return self.observe_step(raw, info), reward, terminated, truncated, info

    def observe_step(self, raw: dict[str, np.ndarray], info: dict[str, Any]) -> dict[str, np.ndarray]:
        """The oracle's observation of a step's ``raw`` one and its ``info``
        (``attentive_gym.vector.protocol.ObservationStage``: a fleet calls it for batched steps)."""
        target = int(info["target_index"])
        if target < 0:
            return self._encoder.encode(raw, None, NO_EVENT)
        x, y, heading = info["robot_pose"]
        c, s = math.cos(heading), math.sin(heading)
        dx, dy = np.asarray(info["mover_positions"][target], float) - (x, y)
        vx, vy = info["mover_velocities"][target]
        position = np.array([c * dx + s * dy, -s * dx + c * dy])  # robot frame
        velocity = np.array([c * vx + s * vy, -s * vx + c * vy])  # robot axes, over the ground
        distance = float(np.hypot(*position))
        speed = float(np.hypot(*velocity))
        bearing = (1.0, 0.0) if distance == 0.0 else (position[0] / distance, position[1] / distance)
        memory = np.zeros((self._memory_slots, len(MEMORY_FIELDS)), np.float32)
        if self._memory_slots:
            memory[0] = (*bearing, min(distance, self.config.max_distance_m), speed, 1.0, 0.0)
        view = self._view(raw, position, velocity, distance, speed)
        return self._encoder.encode(raw, view, NO_EVENT if view is None else _TOP_DOWN_EVENT, memory)

    def _view(self, raw, position: np.ndarray, velocity: np.ndarray, distance: float, speed: float) -> FocusView | None:
        """The target's region as the focus would show it, None when it is in no region."""
        beam = math.floor(math.degrees(math.atan2(position[1], position[0])) + 0.5 * LASER_FOV_DEG)
        if not 0 <= beam < len(self._grid.beam_region) or distance > self.config.laser_max_range_m:
            return None
        region = int(self._grid.beam_region[beam])
        beams = self._grid.beam_indices[region]
        sonar = int(self._grid.region_sonar[region])
        sonar_range = min(float(raw["sonar"][sonar]), self.config.sonar_max_range_m)
        rate = float(position @ velocity) / distance if distance > 0.0 else 0.0
        epsilon = self.config.direction_epsilon_mps
        direction = Direction.TOWARDS if rate < -epsilon else Direction.AWAY if rate > epsilon else Direction.STATIC
        return FocusView(
            region=region,
            bearing_rad=float(self._grid.bearings_rad[region]),
            sonar_range_m=sonar_range,
            sonar_echo=sonar_range < self.config.sonar_max_range_m - self.config.no_echo_epsilon_m,
            laser_beams=beams,
            laser_ranges_m=np.minimum(raw["laser"][beams], self.config.laser_max_range_m),
            range_rate_mps=rate,
            direction=direction,
            distance_m=distance,
            features=np.zeros(6),
            track_id=0,
            track_position_m=position,
            track_velocity_mps=velocity,
            track_speed_mps=speed,
            track_age_s=0.0,
        )
