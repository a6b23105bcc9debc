"""Observation normalisation of the agents' policies (``RunSpec.obs_scaling="running"``).

The variants' observations keep their units (metres up to 20, seconds up to 10, flags of
0 and 1), and Stable-Baselines3 passes a ``Box`` on to the policy as it is. With
``"running"``, training wraps its vectorised environments in SB3's ``VecNormalize``
(observations only: each entry minus its running mean, over its running standard
deviation, clipped to ±``CLIP``), as the RL Baselines3 Zoo does for continuous control.

- ``normalize(vec_env, stats)``: that wrapper, its statistics taken from a saved file
  when resuming.
- ``save_stats`` / ``load_stats``: the statistics as a plain ``.npz`` (mean, variance
  and count of every entry; no pickle), written atomically beside each checkpoint and
  the final model (``STATS_FILE``).
- ``NormalizedPolicy``: a model whose ``predict`` normalises the observation with frozen
  statistics first, for evaluation and videos (the statistics do not move there).
"""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

__all__ = ["CLIP", "STATS_FILE", "normalize", "save_stats", "load_stats", "NormalizedPolicy"]

#: Normalised observations are clipped to ±CLIP standard deviations (SB3's default).
CLIP = 10.0
#: The statistics' file name, beside ``final_model.zip`` and in ``checkpoint/``.
STATS_FILE = "obs_normalization.npz"


def normalize(vec_env, stats: Path | None = None):
    """``vec_env`` under SB3's ``VecNormalize`` of its observations (rewards untouched), its
    statistics read from ``stats`` (a ``save_stats`` file) when given."""
    from stable_baselines3.common.vec_env import VecNormalize

    wrapped = VecNormalize(vec_env, norm_obs=True, norm_reward=False, clip_obs=CLIP)
    if stats is not None:
        _set_stats(wrapped, stats)
    return wrapped


def save_stats(vec_normalize, path: Path) -> None:
    """Write ``vec_normalize``'s observation statistics to ``path`` (``.npz``), atomically."""
    keys = _keys(vec_normalize)
    arrays = {
        "keys": np.array([str(key) for key in keys]),
        "count": np.array([_rms(vec_normalize, key).count for key in keys]),
    }
    for i, key in enumerate(keys):
        arrays[f"mean_{i}"], arrays[f"var_{i}"] = _rms(vec_normalize, key).mean, _rms(vec_normalize, key).var
    tmp = path.with_name(f".{path.stem}.tmp.npz")
    try:
        np.savez(tmp, **arrays)
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


def load_stats(path: Path, make_env: Callable[[], gym.Env]):
    """A frozen ``VecNormalize`` (over one environment of ``make_env``) with the statistics of
    ``path``, for ``NormalizedPolicy``."""
    from stable_baselines3.common.vec_env import DummyVecEnv

    frozen = normalize(DummyVecEnv([make_env]), path)
    frozen.training = False
    return frozen


class NormalizedPolicy:
    """``model`` behind observation normalisation: ``predict`` normalises with the statistics
    of ``vec_normalize`` (read, never updated) and asks ``model``. Other attributes are the
    model's."""

    def __init__(self, model: Any, vec_normalize) -> None:
        self.model = model
        self.vec_normalize = vec_normalize

    def predict(self, observation, state=None, episode_start=None, deterministic: bool = False):
        return self.model.predict(
            self.vec_normalize.normalize_obs(observation),
            state=state,
            episode_start=episode_start,
            deterministic=deterministic,
        )

    def __getattr__(self, name: str) -> Any:
        return getattr(self.model, name)


def _keys(vec_normalize) -> list:
    """The observation keys ``vec_normalize`` normalises (``[None]`` for a ``Box`` observation)."""
    return list(vec_normalize.norm_obs_keys) if isinstance(vec_normalize.obs_rms, dict) else [None]


def _rms(vec_normalize, key):
    return vec_normalize.obs_rms if key is None else vec_normalize.obs_rms[key]


def _set_stats(vec_normalize, path: Path) -> None:
    with np.load(path) as data:
        saved = [None if key == "None" else str(key) for key in data["keys"]]
        if saved != _keys(vec_normalize):
            raise ValueError(
                f"{path} holds the statistics of the observation entries {saved}, "
                f"not of this environment's {_keys(vec_normalize)}"
            )
        for i, key in enumerate(saved):
            rms = _rms(vec_normalize, key)
            if data[f"mean_{i}"].shape != rms.mean.shape:
                raise ValueError(
                    f"{path}: entry {key!r} has shape {data[f'mean_{i}'].shape}, this environment's {rms.mean.shape}"
                )
            rms.mean, rms.var, rms.count = data[f"mean_{i}"].copy(), data[f"var_{i}"].copy(), float(data["count"][i])
