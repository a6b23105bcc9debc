"""``StackedReadings``: the raw-sensor baseline with history (speeds need several frames).

The ``"sonar"``, ``"laser"`` and ``"odometry"`` entries become 1-D stacks of
``n_frames`` readings, oldest first (``(n_frames · n,)``: frame k is ``[k·n:(k+1)·n]``);
``"goal"`` stays a single copy (it does not change within an episode).
At reset the stack is filled with the first reading.
"""

from __future__ import annotations

from collections import deque
from typing import Any

import gymnasium as gym
import numpy as np

__all__ = ["StackedReadings", "STACKED_KEYS"]

#: Observation entries that are stacked.
STACKED_KEYS = ("sonar", "laser", "odometry")


class StackedReadings(gym.ObservationWrapper, gym.utils.RecordConstructorArgs):
    """Stack the last ``n_frames`` sensor readings of a Dict observation.

    Args:
        env: an environment with a ``Dict`` observation holding ``STACKED_KEYS``.
        n_frames: frames kept (>= 2).
    """

    def __init__(self, env: gym.Env, n_frames: int = 4) -> None:
        gym.utils.RecordConstructorArgs.__init__(self, n_frames=n_frames)
        gym.ObservationWrapper.__init__(self, env)
        if isinstance(n_frames, bool) or not isinstance(n_frames, int) or n_frames < 2:
            raise ValueError(f"n_frames must be an int >= 2, got {n_frames!r}")
        base = env.observation_space
        if not isinstance(base, gym.spaces.Dict) or any(k not in base.spaces for k in STACKED_KEYS):
            raise ValueError(f"StackedReadings needs a Dict observation with keys {list(STACKED_KEYS)}, got {base}")
        self.n_frames = n_frames
        stacked = {
            key: gym.spaces.Box(
                np.tile(base[key].low, n_frames), np.tile(base[key].high, n_frames), dtype=base[key].dtype
            )
            for key in STACKED_KEYS
        }
        self.observation_space = gym.spaces.Dict({**base.spaces, **stacked})
        self._frames = {key: deque(maxlen=n_frames) for key in STACKED_KEYS}

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        observation, info = self.env.reset(seed=seed, options=options)
        for key in STACKED_KEYS:
            self._frames[key].clear()
            self._frames[key].extend([observation[key]] * (self.n_frames - 1))
        return self.observation(observation), info

    def observation(self, observation):
        stacked = {}
        for key in STACKED_KEYS:
            self._frames[key].append(observation[key])
            stacked[key] = np.concatenate(self._frames[key])
        return {**observation, **stacked}
