"""``AttentiveRescueVectorEnv``: N rescue environments in one process, as one Gymnasium ``VectorEnv``.

``gym.make_vec(ID, num_envs=N, vectorization_mode="vector_entry_point")`` builds it for
every registered id (``make_vector_env`` is the entry point). Its members are the same
environments ``make_env`` builds, stepped together by ``attentive_gym.vector.fleet.Fleet``
(all robots' sensors in one compiled, parallel call; the attentional models in another), so
its numbers equal those of ``SyncVectorEnv`` over single environments with the same seeds,
bit for bit.

Gymnasium 1.x semantics: autoreset ``NEXT_STEP`` (default), ``SAME_STEP`` (the final
observation and info under ``info["final_obs"]`` / ``info["final_info"]``) or
``DISABLED``; ``reset(seed=s)`` seeds member i with ``s + i`` (or a list, one per
member); ``options={"reset_mask": mask}`` resets only some members; ``info`` is
batched with ``_key`` masks as ``SyncVectorEnv`` does; ``render()`` renders member 0.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space, concatenate, create_empty_array

from attentive_gym.vector.batching import batch_infos, batch_step_infos, stack_observations
from attentive_gym.vector.fleet import Fleet
from attentive_gym.wrappers.variants import make_env

__all__ = ["AttentiveRescueVectorEnv", "make_vector_env", "AUTORESET_MODES"]

#: Autoreset modes by name, as ``autoreset_mode=`` takes them (or the ``AutoresetMode``).
AUTORESET_MODES = {mode.value: mode for mode in AutoresetMode}


def make_vector_env(
    num_envs: int = 1,
    variant: str = "raw",
    *,
    autoreset_mode: str | AutoresetMode = AutoresetMode.NEXT_STEP,
    render_mode: str | None = None,
    copy: bool = True,
    max_episode_steps: int | None = None,
    threads: int | None = None,
    **kwargs: Any,
) -> AttentiveRescueVectorEnv:
    """``num_envs`` environments of ``variant`` (``wrappers.make_env``'s keywords in ``kwargs``).

    Only member 0 gets ``render_mode``: it is the one ``render()`` draws.
    ``max_episode_steps`` truncates every member's episodes as ``gym.make``'s does;
    ``threads``: numba threads of the compiled stages (``Fleet``'s).
    """
    count = _check_num_envs(num_envs)
    limit = _check_max_episode_steps(max_episode_steps)
    envs = [
        make_env(variant, **kwargs, **({"render_mode": render_mode} if i == 0 and render_mode else {}))
        for i in range(count)
    ]
    return AttentiveRescueVectorEnv(
        envs, autoreset_mode=autoreset_mode, copy=copy, max_episode_steps=limit, threads=threads
    )


def _check_num_envs(num_envs: Any) -> int:
    if isinstance(num_envs, (bool, np.bool_)) or not isinstance(num_envs, (int, np.integer)) or num_envs < 1:
        raise ValueError(f"num_envs must be an integer >= 1, got {num_envs!r}")
    return int(num_envs)


def _check_max_episode_steps(value: Any) -> int | None:
    """``max_episode_steps`` as ``gym.make`` takes it: None or -1 for no limit, else an integer >= 1."""
    if value is None or (isinstance(value, (int, np.integer)) and not isinstance(value, bool) and value == -1):
        return None
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)) or value < 1:
        raise ValueError(f"max_episode_steps must be an integer >= 1 (None or -1: no limit), got {value!r}")
    return int(value)


class AttentiveRescueVectorEnv(VectorEnv):
    """Rescue environments stepped together in one process.

    Args:
        envs: the members (``make_env`` environments of one variant; see ``attentive_gym.vector.fleet``).
        autoreset_mode: ``"NextStep"`` (default), ``"SameStep"``, ``"Disabled"``, or an
            ``AutoresetMode``.
        copy: return copies of the batched observation (as ``SyncVectorEnv`` does by
            default); False hands out the env's own buffer, overwritten by the next step.
        max_episode_steps: truncate a member's episode after this many steps, as gymnasium's
            ``TimeLimit`` (which ``gym.make(..., max_episode_steps=n)`` adds) does; None: no limit.
        threads: numba threads of the compiled stages; None: ``vector.threads.default_threads(N)``.

    Spaces: ``single_observation_space`` / ``single_action_space`` are a member's;
    ``observation_space`` / ``action_space`` are batched with a leading ``num_envs`` axis.
    ``step`` takes an ``(num_envs, *action shape)`` array: a wrong shape, or a NaN or inf
    in any member's action, raises ``ValueError`` before any member moves.
    """

    def __init__(
        self,
        envs: Sequence[gym.Env],
        autoreset_mode: str | AutoresetMode = AutoresetMode.NEXT_STEP,
        copy: bool = True,
        max_episode_steps: int | None = None,
        threads: int | None = None,
    ) -> None:
        self._fleet = Fleet(envs, threads)
        self.envs = self._fleet.envs
        self.num_envs = len(self.envs)
        if isinstance(autoreset_mode, str):
            if autoreset_mode not in AUTORESET_MODES:
                raise ValueError(f"unknown autoreset_mode {autoreset_mode!r}; allowed: {list(AUTORESET_MODES)}")
            autoreset_mode = AUTORESET_MODES[autoreset_mode]
        elif not isinstance(autoreset_mode, AutoresetMode):
            raise ValueError(f"autoreset_mode must be one of {list(AUTORESET_MODES)}, got {autoreset_mode!r}")
        self.autoreset_mode = autoreset_mode
        self.copy = copy
        self.max_episode_steps = _check_max_episode_steps(max_episode_steps)
        self._elapsed_steps = np.zeros(self.num_envs, np.int64)
        first = self.envs[0]
        self.render_mode = first.render_mode
        self.metadata = {**first.metadata, "autoreset_mode": autoreset_mode}
        self.single_observation_space = first.observation_space
        self.single_action_space = first.action_space
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self._observations = create_empty_array(self.single_observation_space, self.num_envs)
        self._env_obs: list[Any] = [None] * self.num_envs
        self._rewards = np.zeros(self.num_envs, np.float64)
        self._terminations = np.zeros(self.num_envs, np.bool_)
        self._truncations = np.zeros(self.num_envs, np.bool_)
        self._autoreset_envs = np.zeros(self.num_envs, np.bool_)
        self._started = False

    # --- episodes -------------------------------------------------------------------------
    def reset(self, *, seed: int | Sequence[int | None] | None = None, options: dict[str, Any] | None = None):
        """Reset every member (or those of ``options["reset_mask"]``); see the module docstring."""
        seeds = _seeds(seed, self.num_envs)
        options = None if options is None else dict(options)
        mask = np.ones(self.num_envs, np.bool_)
        if options is not None and "reset_mask" in options:
            mask = _check_mask(options.pop("reset_mask"), self.num_envs)
        infos = []
        for i in np.flatnonzero(mask).tolist():
            self._env_obs[i], info = self.envs[i].reset(seed=seeds[i], options=options)
            infos.append((i, info))
        self._terminations[mask] = self._truncations[mask] = self._autoreset_envs[mask] = False
        self._elapsed_steps[mask] = 0
        self._started = True
        return self._batched_observations(), batch_infos(infos, self.num_envs)

    def step(self, actions):
        """Step every member (NEXT_STEP: reset those that ended at the previous step instead)."""
        if not self._started:
            raise RuntimeError("call reset() before step()")
        batch = self._fleet.check_actions(actions)
        if self.autoreset_mode == AutoresetMode.DISABLED and self._autoreset_envs.any():
            ended = np.flatnonzero(self._autoreset_envs).tolist()
            raise RuntimeError(
                f"env(s) {ended} ended; with autoreset disabled, reset them "
                "(reset(options={'reset_mask': mask})) before stepping"
            )
        if self.autoreset_mode == AutoresetMode.NEXT_STEP:  # those that ended at the previous step restart
            stepping = np.flatnonzero(~self._autoreset_envs).tolist()
        else:
            stepping = list(range(self.num_envs))
        results, completed = self._fleet.step(stepping, batch)
        if completed is None:
            rewards, terminations, truncations = zip(*[result[1:4] for result in results]) if results else ((),) * 3
        else:
            rewards, terminations, truncations = completed.rewards, completed.terminations, completed.truncations
        terminations, truncations = np.array(terminations, np.bool_), np.array(truncations, np.bool_)
        self._elapsed_steps[stepping] += 1
        if self.max_episode_steps is not None:
            truncations = truncations | (self._elapsed_steps[stepping] >= self.max_episode_steps)
        self._rewards[stepping], self._terminations[stepping], self._truncations[stepping] = (
            rewards,
            terminations,
            truncations,
        )
        for i, result in zip(stepping, results):
            self._env_obs[i] = result[0]
        ended = self.autoreset_mode == AutoresetMode.SAME_STEP and bool(terminations.any() or truncations.any())
        if len(stepping) == self.num_envs and not ended:  # every member stepped, none reset: infos from arrays
            infos = batch_step_infos([result[4] for result in results], completed)
        else:
            infos = batch_infos(self._step_infos(stepping, results), self.num_envs)
        self._autoreset_envs = self._terminations | self._truncations
        return (
            self._batched_observations(),
            self._rewards.copy(),
            self._terminations.copy(),
            self._truncations.copy(),
            infos,
        )

    def _step_infos(self, stepping: list[int], results: list) -> list[tuple[int, dict[str, Any]]]:
        """The ``(index, info)`` pairs of a step in which members reset: NEXT_STEP resets those
        not ``stepping`` (their reset's info), SAME_STEP resets those that ended (their final
        observation and info first); the others' step info."""
        infos = []
        info_of = {i: result[4] for i, result in zip(stepping, results)}
        for i in range(self.num_envs):
            if i not in info_of:  # NEXT_STEP: ended at the previous step, reset now
                self._env_obs[i], info = self.envs[i].reset()
                self._rewards[i], self._terminations[i], self._truncations[i] = 0.0, False, False
                self._elapsed_steps[i] = 0
            else:
                info = info_of[i]
                if self.autoreset_mode == AutoresetMode.SAME_STEP and (self._terminations[i] or self._truncations[i]):
                    infos.append((i, {"final_obs": self._env_obs[i], "final_info": info}))
                    self._env_obs[i], info = self.envs[i].reset()
                    self._elapsed_steps[i] = 0
            infos.append((i, info))
        return infos

    def _batched_observations(self):
        """The members' observations batched: into new arrays (``copy``) or into the env's buffer."""
        space, members = self.single_observation_space, self._env_obs
        if self.copy:  # one stack per entry (gymnasium's generic concatenate costs ~10x more)
            stacked = stack_observations(space, members)
            return (
                stacked
                if stacked is not None
                else concatenate(space, members, create_empty_array(space, self.num_envs))
            )
        stacked = stack_observations(space, members, self._observations)
        self._observations = stacked if stacked is not None else concatenate(space, members, self._observations)
        return self._observations

    @property
    def threads(self) -> int:
        """numba threads the compiled stages of a step run on (the fleet's)."""
        return self._fleet.threads

    # --- members --------------------------------------------------------------------------
    def render(self):
        """Member 0's frame (``render_mode`` ``"rgb_array"``: an ``(H, W, 3)`` uint8 array)."""
        return self.envs[0].render()

    def call(self, name: str, *args: Any, **kwargs: Any) -> tuple[Any, ...]:
        """Each member's attribute ``name``, called with the arguments if it is callable."""
        values = []
        for env in self.envs:
            attribute = env.get_wrapper_attr(name)
            values.append(attribute(*args, **kwargs) if callable(attribute) else attribute)
        return tuple(values)

    def get_attr(self, name: str) -> tuple[Any, ...]:
        """Each member's attribute ``name``."""
        return tuple(env.get_wrapper_attr(name) for env in self.envs)

    def set_attr(self, name: str, values: Any | Sequence[Any]) -> None:
        """Set attribute ``name`` of every member: to ``values[i]`` for a list or tuple, else to ``values``."""
        if not isinstance(values, (list, tuple)):
            values = [values] * self.num_envs
        if len(values) != self.num_envs:
            raise ValueError(f"set_attr needs one value per env ({self.num_envs}), got {len(values)}")
        for env, value in zip(self.envs, values):
            env.set_wrapper_attr(name, value)

    def close_extras(self, **kwargs: Any) -> None:
        self._fleet.close()


def _seeds(seed, num_envs: int) -> list[int | None]:
    if seed is None:
        return [None] * num_envs
    if isinstance(seed, (int, np.integer)) and not isinstance(seed, (bool, np.bool_)):
        return [int(seed) + i for i in range(num_envs)]
    if isinstance(seed, (list, tuple, np.ndarray)) and len(seed) == num_envs:
        return list(seed)
    raise ValueError(f"seed must be None, an int, or a list of {num_envs} seeds (one per env), got {seed!r}")


def _check_mask(mask, num_envs: int) -> np.ndarray:
    if not isinstance(mask, np.ndarray) or mask.dtype != np.bool_ or mask.shape != (num_envs,):
        raise ValueError(f"options['reset_mask'] must be a bool numpy array of shape ({num_envs},), got {mask!r}")
    if not mask.any():
        raise ValueError("options['reset_mask'] must select at least one env")
    return mask
