"""``ScaledObservation``: every entry of the observation mapped from its bounds to [−1, 1].

The variants' observations keep their units (metres up to 20, seconds up to 10, one-hots
in {0, 1}), as the spaces declare them. A policy network sees them better on a common
scale: Stable-Baselines3 scales image spaces but passes a ``Box`` on as it is, and
inputs of a few metres next to flags of 0 and 1 slow learning down. This wrapper maps
each ``Box`` linearly from its declared ``[low, high]`` to ``[−1, 1]`` per element:
stateless (nothing to save beside a model, unlike a running normaliser), the same in
training and evaluation, and exact to invert. An element whose bounds are equal is 0.
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np

__all__ = ["ScaledObservation"]


class ScaledObservation(gym.ObservationWrapper, gym.utils.RecordConstructorArgs):
    """Each ``Box`` of the observation (a ``Box`` or a ``Dict`` of them), element by element,
    from ``[low, high]`` to ``[−1, 1]`` (float32).

    Args:
        env: the environment; every bound of its observation space must be finite.

    Raises:
        ValueError: for a space that is not a ``Box`` or a ``Dict`` of them, or an
            entry with an infinite bound (naming it).
    """

    def __init__(self, env: gym.Env) -> None:
        gym.utils.RecordConstructorArgs.__init__(self)
        gym.ObservationWrapper.__init__(self, env)
        space = env.observation_space
        if isinstance(space, gym.spaces.Dict):
            boxes = dict(space.spaces)
        elif isinstance(space, gym.spaces.Box):
            boxes = {None: space}
        else:
            raise ValueError(f"ScaledObservation needs a Box or a Dict of Boxes, got {type(space).__name__}")
        self._centre: dict[Any, np.ndarray] = {}
        self._inverse_half_span: dict[Any, np.ndarray] = {}
        scaled = {}
        for key, box in boxes.items():
            name = "the observation" if key is None else f"observation entry {key!r}"
            if not isinstance(box, gym.spaces.Box):
                raise ValueError(f"ScaledObservation needs Box entries; {name} is a {type(box).__name__}")
            low, high = box.low.astype(np.float64), box.high.astype(np.float64)
            if not (np.isfinite(low).all() and np.isfinite(high).all()):
                raise ValueError(f"ScaledObservation needs finite bounds; {name} has bounds "
                                 f"[{low.min()}, {high.max()}]")
            half_span = 0.5 * (high - low)
            self._centre[key] = 0.5 * (low + high)
            self._inverse_half_span[key] = np.divide(1.0, half_span, out=np.zeros_like(half_span),
                                                     where=half_span > 0.0)
            scaled[key] = gym.spaces.Box(-1.0, 1.0, box.shape, np.float32)
        self.observation_space = scaled[None] if None in scaled else gym.spaces.Dict(scaled)

    def observation(self, observation):
        """``observation`` with every element at ``(x − centre) / half span`` (float32; a
        bound lands on ±1 up to rounding, which the clip to [−1, 1] takes off)."""
        if None in self._centre:
            return self._scale(None, observation)
        return {key: self._scale(key, value) for key, value in observation.items()}

    def _scale(self, key, value) -> np.ndarray:
        scaled = (np.asarray(value, np.float64) - self._centre[key]) * self._inverse_half_span[key]
        return np.clip(scaled, -1.0, 1.0).astype(np.float32)
