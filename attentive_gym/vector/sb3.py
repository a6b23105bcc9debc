"""``NativeVecEnv``: SB3's ``VecEnv`` over a fleet of rescue environments (``attentive_gym.vector.fleet``).

What ``train`` and ``compare`` use by default (``--vec-env native``). It steps its
members as one ``Fleet`` (all sensors in one compiled call) and gives what
``DummyVecEnv`` over ``Monitor``-wrapped members gives, bit for bit in observations,
rewards and dones: automatic reset on the step an episode ends, with
``info["terminal_observation"]`` and ``info["TimeLimit.truncated"]``, and the
``Monitor`` episode record ``info["episode"]`` = ``{"r", "l", "t"}`` (``t``: seconds since
the env was built, as ``Monitor``'s) plus the ``info_keywords`` when an episode ends.

Importing this module needs stable-baselines3 (the ``agents`` extra): without it,
``MissingExtraError`` names the extra. ``import attentive_gym.vector`` does not import it.
"""

from __future__ import annotations

import copy
import time
from collections.abc import Iterable, Sequence
from typing import Any

import gymnasium as gym
import numpy as np

from attentive_gym._optional import require
from attentive_gym.vector.batching import stack_observations
from attentive_gym.vector.fleet import Fleet

_PURPOSE = "NativeVecEnv (SB3's VecEnv over a fleet)"
VecEnv = require("stable_baselines3.common.vec_env.base_vec_env", _PURPOSE).VecEnv
is_wrapped = require("stable_baselines3.common.env_util", _PURPOSE).is_wrapped

__all__ = ["NativeVecEnv"]


class NativeVecEnv(VecEnv):
    """The members ``envs`` (single rescue environments, see ``attentive_gym.vector.fleet``) as one SB3 ``VecEnv``.

    Args:
        envs: the members, e.g. ``[make_env("focus") for _ in range(4)]``.
        info_keywords: ``info`` keys copied into each episode record (as ``Monitor``'s).
        threads: numba threads of the compiled stages; None: ``vector.threads.default_threads(N)``.

    ``seed(s)`` and ``set_options(options)`` apply to the next ``reset`` only, as SB3's
    ``VecEnv`` documents.
    """

    def __init__(self, envs: Sequence[gym.Env], info_keywords: Sequence[str] = (), threads: int | None = None) -> None:
        self._fleet = Fleet(envs, threads)
        self.envs = self._fleet.envs
        self.info_keywords = tuple(info_keywords)
        super().__init__(len(self.envs), self._fleet.observation_space, self._fleet.action_space)
        self._all = list(range(self.num_envs))
        self._next_seeds: list[int | None] = [None] * self.num_envs
        self._next_options: list[dict[str, Any]] = [{} for _ in self._all]
        self._actions: np.ndarray | None = None
        self._observations: list[Any] = [None] * self.num_envs
        self._episode_rewards: list[list[float]] = [[] for _ in self._all]
        self._t_start = time.time()  # Monitor's clock: an episode record's "t" counts from here

    def seed(self, seed: int | None = None) -> Sequence[int | None]:
        """Seed member i's next reset with ``seed + i`` (None: a random ``seed``, as SB3 draws it)."""
        seeds = super().seed(seed)
        self._next_seeds = list(seeds)
        return seeds

    def set_options(self, options: list[dict] | dict | None = None) -> None:
        """Options of the members' next reset: one dict for all, or a list of one per member."""
        if options is None:
            options = {}
        if isinstance(options, dict):
            options = [options] * self.num_envs
        if len(options) != self.num_envs:
            raise ValueError(f"set_options needs one dict or a list of {self.num_envs} dicts, got {len(options)}")
        self._next_options = copy.deepcopy(list(options))

    def reset(self):
        for i, env in enumerate(self.envs):
            options = {"options": self._next_options[i]} if self._next_options[i] else {}
            self._observations[i], self.reset_infos[i] = env.reset(seed=self._next_seeds[i], **options)
            self._episode_rewards[i] = []
        self._next_seeds = [None] * self.num_envs
        self._next_options = [{} for _ in self._all]
        return self._stacked()

    def step_async(self, actions: np.ndarray) -> None:
        self._actions = actions

    def step_wait(self):
        batch = self._fleet.check_actions(self._actions)
        results, completed = self._fleet.step(self._all, batch)
        if completed is None:
            rewards, terminations, truncations = zip(*[result[1:4] for result in results])
        else:
            rewards, terminations, truncations = completed.rewards, completed.terminations, completed.truncations
        dones = np.logical_or(terminations, truncations)
        infos = []
        for i, (observation, reward, terminated, truncated, info) in enumerate(results):
            self._episode_rewards[i].append(float(reward))
            info["TimeLimit.truncated"] = truncated and not terminated
            if terminated or truncated:
                info["episode"] = self._episode_record(i, info)
                info["terminal_observation"] = observation
                observation, self.reset_infos[i] = self.envs[i].reset()
                self._episode_rewards[i] = []
            self._observations[i] = observation
            infos.append(info)
        return self._stacked(), np.array(rewards, np.float32), dones, infos

    def _episode_record(self, i: int, info: dict[str, Any]) -> dict[str, Any]:
        """``Monitor``'s record of member ``i``'s episode that has just ended."""
        rewards = self._episode_rewards[i]
        record = {"r": round(sum(rewards), 6), "l": len(rewards), "t": round(time.time() - self._t_start, 6)}
        for key in self.info_keywords:
            record[key] = info[key]
        return record

    @property
    def threads(self) -> int:
        """numba threads the compiled stages of a step run on (the fleet's)."""
        return self._fleet.threads

    def _stacked(self):
        return stack_observations(self.observation_space, self._observations)

    # --- members --------------------------------------------------------------------------
    def close(self) -> None:
        self._fleet.close()

    def get_images(self) -> Sequence[np.ndarray | None]:
        return [env.render() for env in self.envs]

    def get_attr(self, attr_name: str, indices: int | Iterable[int] | None = None) -> list[Any]:
        return [self.envs[i].get_wrapper_attr(attr_name) for i in _indices(indices, self.num_envs)]

    def set_attr(self, attr_name: str, value: Any, indices: int | Iterable[int] | None = None) -> None:
        for i in _indices(indices, self.num_envs):
            setattr(self.envs[i], attr_name, value)

    def env_method(
        self, method_name: str, *method_args, indices: int | Iterable[int] | None = None, **method_kwargs
    ) -> list[Any]:
        return [
            self.envs[i].get_wrapper_attr(method_name)(*method_args, **method_kwargs)
            for i in _indices(indices, self.num_envs)
        ]

    def env_is_wrapped(
        self, wrapper_class: type[gym.Wrapper], indices: int | Iterable[int] | None = None
    ) -> list[bool]:
        return [is_wrapped(self.envs[i], wrapper_class) for i in _indices(indices, self.num_envs)]


def _indices(indices: int | Iterable[int] | None, num_envs: int) -> list[int]:
    """SB3's ``VecEnvIndices``: None → every member, an int → that member, else the given ones."""
    if indices is None:
        return list(range(num_envs))
    if isinstance(indices, (int, np.integer)):
        return [int(indices)]
    return list(indices)
