"""``Fleet``: many rescue environments stepped together, their sensors read in one call.

The core that both batched shells share: ``AttentiveRescueVectorEnv`` (Gymnasium's
``VectorEnv``) and ``attentive_gym.agents.native_vec.NativeVecEnv`` (SB3's ``VecEnv``).
Each member is a whole single environment (an ``AttentiveRescueEnv`` under the
project's observation wrappers, as ``make_env`` builds it), and a step runs the same
stages as its own ``step`` does, in the same order, so a fleet's numbers are those of
its members stepped one by one, bit for bit:

1. each member's action goes down its wrappers' ``action`` hooks, and its world moves
   (``AttentiveRescueEnv._act``);
2. every member's sensors are read in one compiled, parallel call
   (``SensorSuite.read_many``; each member draws its noise from its own generator);
3. each member completes its step (``AttentiveRescueEnv._complete_step``: reward,
   termination, info) and its observation goes up its wrappers' hooks
   (``ObservationWrapper.observation``, or ``_observe_step`` for the attention, oracle
   wrappers: the attentional model runs there). When every member's innermost hook is
   an ``AttentionWrapper``'s and their models can form a ``ModelBatch``
   (``attention.compiled.batch``: one configuration, the sonar grid), the models of the stepped members run in one
   compiled, parallel call first, and each wrapper encodes its model's output.

A wrapper is allowed when it is a ``gymnasium.ActionWrapper`` or
``gymnasium.ObservationWrapper`` that keeps their ``step``, or defines
``_observe_step(observation, info) -> observation`` and steps as
``obs = _observe_step(*env.step(action)[::4])``; any other raises ``ValueError``.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import gymnasium as gym
import numpy as np

from attentive_gym.attention.compiled.batch import ModelBatch, batching_problem
from attentive_gym.envs.rescue_env import AttentiveRescueEnv

__all__ = ["Fleet", "stack_observations"]

StepResult = tuple[Any, float, bool, bool, dict]


class Fleet:
    """N rescue environments (each possibly wrapped), stepped as one.

    Args:
        envs: the members; every one has ``AttentiveRescueEnv`` at its core, the same
            sensors, and the same action space as the first.

    Raises:
        ValueError: for an empty list, a member that is not a rescue environment, a
            wrapper the fleet cannot step, or members with different sensors, actions or
            observations.
    """

    def __init__(self, envs: Sequence[gym.Env]) -> None:
        if len(envs) < 1:
            raise ValueError("a fleet needs at least one environment")
        self.envs = list(envs)
        self.bases: list[AttentiveRescueEnv] = []
        self._action_hooks: list[list] = []
        self._observation_hooks: list[list] = []
        for i, env in enumerate(self.envs):
            base = env.unwrapped
            if not isinstance(base, AttentiveRescueEnv):
                raise ValueError(f"env {i} is a {type(base).__name__}, not an AttentiveRescueEnv")
            actions, observations = _hooks(env, i)
            self.bases.append(base)
            self._action_hooks.append(actions)
            self._observation_hooks.append(observations)
        first = self.bases[0]
        for i, base in enumerate(self.bases[1:], start=1):
            if (
                base.sensors.sonar_ring.config,
                base.sensors.laser_scanner.config,
                base.sensors.noise_model,
                base.sensors.noise_std,
            ) != (
                first.sensors.sonar_ring.config,
                first.sensors.laser_scanner.config,
                first.sensors.noise_model,
                first.sensors.noise_std,
            ):
                raise ValueError(f"env {i} has other sensors than env 0; a fleet's members share one sensor suite")
            if self.envs[i].action_space != self.envs[0].action_space:
                raise ValueError(
                    f"env {i}'s action space {self.envs[i].action_space} differs from env 0's "
                    f"{self.envs[0].action_space}"
                )
            if self.envs[i].observation_space != self.envs[0].observation_space:
                raise ValueError(
                    f"env {i}'s observation space differs from env 0's; a fleet's members are one "
                    "variant with the same settings"
                )
        self._attention = _attention_wrappers(self._observation_hooks)
        self._models = None if self._attention is None else ModelBatch([w.model for w in self._attention])
        self.action_space: gym.spaces.Box = self.envs[0].action_space
        self.observation_space: gym.Space = self.envs[0].observation_space

    def __len__(self) -> int:
        return len(self.envs)

    def check_actions(self, actions) -> np.ndarray:
        """``actions`` as an ``(N, *action shape)`` array, or ``ValueError`` naming what is wrong.

        The whole batch is checked before any member moves: a NaN in one member's action
        leaves every member as it was.
        """
        shape = (len(self.envs), *self.action_space.shape)
        if np.iscomplexobj(actions):
            raise ValueError(f"actions must be real numbers with shape {shape}, got complex values")
        try:  # float64, as each member's own check takes an action: float32 rows convert exactly
            batch = np.asarray(actions, dtype=np.float64)
        except (TypeError, ValueError):
            raise ValueError(f"actions must be numeric with shape {shape} (num_envs, *action shape)") from None
        if batch.shape != shape:
            raise ValueError(f"actions must have shape {shape} (num_envs, *action shape), got shape {batch.shape}")
        finite = np.isfinite(batch).reshape(len(self.envs), -1).all(axis=1)
        if not finite.all():
            bad = np.flatnonzero(~finite)
            raise ValueError(f"actions must be finite; env(s) {bad[:10].tolist()} got {batch[bad[0]].tolist()}")
        return batch

    def step(self, indices: Sequence[int], actions: np.ndarray) -> list[StepResult]:
        """Step the members ``indices`` with their rows of ``actions`` (checked by ``check_actions``).

        Returns:
            One ``(observation, reward, terminated, truncated, info)`` per index, as each
            member's ``step`` would return it.
        """
        collided = []
        for i in indices:
            action = actions[i]
            for hook in self._action_hooks[i]:
                action = hook(action)
            collided.append(self.bases[i]._act(action))
        readings = self.bases[0].sensors.read_many([self.bases[i]._sensing_request() for i in indices])
        steps = [self.bases[i]._complete_step(hit, reading) for i, hit, reading in zip(indices, collided, readings)]
        hooks = [self._observation_hooks[i] for i in indices]
        if self._models is not None:  # every member's innermost hook: its attention wrapper, models batched
            model_readings = [
                self._attention[i]._model_reading(observation, info)
                for i, (observation, _, _, _, info) in zip(indices, steps)
            ]
            outputs = self._models.step(model_readings, list(indices))
            steps = [
                (self._attention[i]._observe_output(raw, info, output), reward, terminated, truncated, info)
                for i, output, (raw, reward, terminated, truncated, info) in zip(indices, outputs, steps)
            ]
            hooks = [member_hooks[1:] for member_hooks in hooks]
        results = []
        for member_hooks, (observation, reward, terminated, truncated, info) in zip(hooks, steps):
            for hook in member_hooks:
                observation = hook(observation, info)
            results.append((observation, reward, terminated, truncated, info))
        return results

    def close(self) -> None:
        for env in self.envs:
            env.close()


def stack_observations(space: gym.Space, observations: Sequence[Any]) -> Any | None:
    """The members' observations of ``space`` (a ``Box`` or a ``Dict`` of ``Box``) as new arrays
    with a leading member axis, one stack per entry; None for any other space. (``np.array``
    of the list stacks as ``np.stack`` does, at 3x its speed, and refuses unequal shapes.)"""
    if isinstance(space, gym.spaces.Box):
        return np.array(observations).astype(space.dtype, copy=False)
    if isinstance(space, gym.spaces.Dict) and all(isinstance(s, gym.spaces.Box) for s in space.spaces.values()):
        return {
            key: np.array([o[key] for o in observations]).astype(s.dtype, copy=False) for key, s in space.spaces.items()
        }
    return None


def _attention_wrappers(observation_hooks: list[list]) -> list | None:
    """The members' attention wrappers when every member's innermost observation hook is
    one's (``_observe_step`` of a wrapper with ``_observe_output`` and a ``model``) and
    their models can form a ``ModelBatch``; else None."""
    wrappers = [getattr(hooks[0], "__self__", None) if hooks else None for hooks in observation_hooks]
    if not all(hasattr(w, "_observe_output") and hasattr(w, "model") for w in wrappers):
        return None
    return wrappers if batching_problem([w.model for w in wrappers]) is None else None


def _hooks(env: gym.Env, index: int) -> tuple[list, list]:
    """The action hooks of ``env``'s wrappers, outermost first, and its observation hooks,
    innermost first (each ``hook(observation, info)``)."""
    actions, observations = [], []
    layer = env
    while isinstance(layer, gym.Wrapper):
        cls = type(layer)
        if isinstance(layer, gym.ActionWrapper) and cls.step is gym.ActionWrapper.step:
            actions.append(layer.action)
        elif isinstance(layer, gym.ObservationWrapper) and cls.step is gym.ObservationWrapper.step:
            observations.append(lambda observation, info, hook=layer.observation: hook(observation))
        elif hasattr(layer, "_observe_step"):
            observations.append(layer._observe_step)
        else:
            raise ValueError(
                f"env {index}: the wrapper {cls.__name__} cannot be stepped in a fleet; allowed: gymnasium "
                "ActionWrapper/ObservationWrapper subclasses that keep their step(), and the project's wrappers"
            )
        layer = layer.env
    observations.reverse()
    return actions, observations
