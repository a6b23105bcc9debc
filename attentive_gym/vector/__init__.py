"""Many rescue environments in one process, stepped as one: Gymnasium's and SB3's vector envs.

- ``fleet``: ``Fleet``, the core: N environments stepped stage by stage, each stage one call
  over the members (the worlds, the sensors and the attentional models each in one compiled call).
- ``protocol``: the public names a fleet steps its members through (``StagedEnv``,
  ``ObservationStage``, ``ModelStage``).
- ``vector_env``: ``AttentiveRescueVectorEnv`` (Gymnasium's ``VectorEnv``) and
  ``make_vector_env``, every registered id's ``vector_entry_point``.
- ``sb3``: ``NativeVecEnv``, the fleet as SB3's ``VecEnv`` (needs the ``agents`` extra; imported
  on first use of the name).
- ``batching``: ``stack_observations``, ``batch_infos``, ``batch_step_infos``: the members'
  results with a leading axis (a step's infos straight from the completed steps' arrays).
- ``threads``: how many numba threads the compiled stages run on (``default_threads``).

This layer stands above ``envs`` and ``wrappers``: it builds its members with
``wrappers.make_env`` and steps them through their public stage methods.

Example:
    >>> import numpy as np
    >>> from attentive_gym.vector import make_vector_env
    >>> envs = make_vector_env(4, "focus")
    >>> observations, infos = envs.reset(seed=0)
    >>> observations["memory"].shape
    (4, 18)
    >>> _ = envs.step(np.zeros((4, 2), np.float32))
    >>> envs.close()
"""

from __future__ import annotations

import importlib as _importlib

from attentive_gym.vector.batching import batch_infos, stack_observations
from attentive_gym.vector.fleet import Fleet
from attentive_gym.vector.protocol import ModelStage, ObservationStage, StagedEnv
from attentive_gym.vector.threads import default_threads
from attentive_gym.vector.vector_env import AUTORESET_MODES, AttentiveRescueVectorEnv, make_vector_env

__all__ = [
    "AUTORESET_MODES",
    "AttentiveRescueVectorEnv",
    "Fleet",
    "ModelStage",
    "NativeVecEnv",
    "ObservationStage",
    "StagedEnv",
    "batch_infos",
    "default_threads",
    "make_vector_env",
    "stack_observations",
]


def __getattr__(name: str):
    """``NativeVecEnv``, imported from ``sb3`` on first use (it needs stable-baselines3)."""
    if name == "NativeVecEnv":
        return _importlib.import_module(f"{__name__}.sb3").NativeVecEnv
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
