"""``Fleet``: many rescue environments stepped together, each stage one call over the members.

The core that both batched shells share: ``AttentiveRescueVectorEnv`` (Gymnasium's
``VectorEnv``, ``attentive_gym.vector.vector_env``) and ``NativeVecEnv`` (SB3's ``VecEnv``,
``attentive_gym.vector.sb3``). Each member is a whole single environment (an
``AttentiveRescueEnv`` under the project's observation wrappers, as ``make_env`` builds it),
and the fleet steps it only through the public names of the batching protocol
(``attentive_gym.vector.protocol``), in the order its own ``step`` runs them, so a fleet's
numbers are those of its members stepped one by one, bit for bit:

1. **actions**: every member's action goes down its wrappers' ``action`` hooks and becomes
   its robot's command (``StagedEnv.command``); all are checked before any world moves;
2. **world**: every member's world advances under its command, all in one compiled call
   (``world.step_worlds`` of the members' ``StagedEnv.world``: what each ``move`` does);
3. **perceive**: every member's sensors are read in one compiled, parallel call
   (``SensorSuite.read_batch`` over the members' stacked ``world.geometry_cache``: what each
   ``sensors.read(*sensing_request())`` gives; each member draws its noise from its own
   ``np_random``);
4. **complete**: the members' rewards, terminations, infos and raw observations in one call
   over arrays (``envs.completion.complete_steps``: what each ``StagedEnv.complete_step``
   returns; member by member for a core that is not an ``AttentiveRescueEnv``);
5. **attend**: when every member's innermost observation wrapper is a ``ModelStage``
   (``AttentionWrapper``) and their models can form a ``ModelBatch`` (one configuration, the
   sonar grid: ``attention.compiled.batch.batching_problem``), the models of the stepped
   members run in one compiled, parallel call (``ModelStage.model_reading`` in), and their
   outputs are encoded in one call (``ModelStage.observe_outputs``: each wrapper's
   observation of its model's output, written into one block);
6. **observe**: the observation goes up the remaining wrappers (``ObservationStage.observe_step``,
   or a ``gymnasium.ObservationWrapper``'s ``observation``).

A wrapper is allowed when it is a ``gymnasium.ActionWrapper`` or ``gymnasium.ObservationWrapper``
that keeps their ``step``, an ``ObservationStage`` whose ``step`` is
``observe_step(*env.step(action)[::4])`` on the observation, or an ``ActionWrapper`` that is
also an ``ObservationStage`` (``GoalActionWrapper``), whose ``step`` is ``observe_step`` of
``env.step(action(a))``: its ``action`` is one of stage 1's hooks and its ``observe_step`` one
of stage 6's; any other raises ``ValueError``.
The compiled stages run on ``threads`` numba threads (``attentive_gym.vector.threads``).
"""

from __future__ import annotations

from collections.abc import Sequence

import gymnasium as gym
import numba
import numpy as np

from attentive_gym.attention.compiled.batch import ModelBatch, batching_problem
from attentive_gym.envs.completion import CompletedSteps, complete_steps
from attentive_gym.envs.rescue_env import AttentiveRescueEnv
from attentive_gym.sensors import SceneStack, SensorReading
from attentive_gym.vector.batching import stack_observations  # noqa: F401  (named by the old path envs.fleet)
from attentive_gym.vector.protocol import ModelStage, ObservationStage, StagedEnv, StepResult
from attentive_gym.vector.threads import default_threads, numba_threads
from attentive_gym.world import step_worlds
from attentive_gym.world.world import ROBOT_ID

__all__ = ["Fleet"]


class Fleet:
    """N environments (each possibly wrapped), stepped as one.

    Args:
        envs: the members; every one has a ``StagedEnv`` (an ``AttentiveRescueEnv``) at its
            core, sensors equal to the first's, and the first's action and observation spaces.
        threads: numba threads of the compiled stages (between 1 and
            ``numba.config.NUMBA_NUM_THREADS``); None: ``threads.default_threads(len(envs))``,
            chosen now.

    Raises:
        ValueError: for an empty list, a member whose core lacks the stages, a wrapper the
            fleet cannot step, members with different sensors, actions or observations, or
            a thread count out of range, or members whose steps ``dt`` differ.
    """

    def __init__(self, envs: Sequence[gym.Env], threads: int | None = None) -> None:
        if len(envs) < 1:
            raise ValueError("a fleet needs at least one environment")
        self.envs = list(envs)
        self.bases: list[StagedEnv] = []
        self._action_hooks: list[list] = []
        self._observation_hooks: list[list] = []
        self._stages: list[list] = []
        for i, env in enumerate(self.envs):
            base = env.unwrapped
            if not isinstance(base, StagedEnv):
                raise ValueError(
                    f"env {i} is a {type(base).__name__}, which lacks the stages a fleet steps "
                    "(attentive_gym.vector.protocol.StagedEnv: command, move, sensing_request, complete_step, "
                    "sensors, world, dt, np_random)"
                )
            actions, stages = _hooks(env, i)
            self.bases.append(base)
            self._action_hooks.append(actions)
            self._stages.append(stages)
            self._observation_hooks.append([_observation_hook(stage) for stage in stages])
        first = self.bases[0]
        for i, base in enumerate(self.bases[1:], start=1):
            if _sensor_settings(base.sensors) != _sensor_settings(first.sensors):
                raise ValueError(f"env {i} has other sensors than env 0; a fleet's members share one sensor suite")
            if base.dt != first.dt:
                raise ValueError(f"env {i} steps {base.dt} s, env 0 {first.dt} s; a fleet's members share dt")
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
        self._model_stages = _model_stages(self._stages)
        self._models = None if self._model_stages is None else ModelBatch([w.model for w in self._model_stages])
        self.action_space: gym.spaces.Box = self.envs[0].action_space
        self.observation_space: gym.Space = self.envs[0].observation_space
        self.threads = default_threads(len(self.envs)) if threads is None else _check_threads(threads)
        self._scenes = SceneStack([])  # the members' scenes, restacked when a reset gives one a new world
        self._completes_together = all(isinstance(base, AttentiveRescueEnv) for base in self.bases)

    def __len__(self) -> int:
        return len(self.envs)

    @property
    def batches_models(self) -> bool:
        """Whether the members' attentional models step in one ``ModelBatch`` call."""
        return self._models is not None

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

    def step(self, indices: Sequence[int], actions: np.ndarray) -> tuple[list[StepResult], CompletedSteps | None]:
        """Step the members ``indices`` with their rows of ``actions`` (checked by ``check_actions``).

        Returns:
            One ``(observation, reward, terminated, truncated, info)`` per index, as each
            member's ``step`` would return it, and the completed steps as arrays (row j for
            ``indices[j]``: the rewards, terminations, truncations and the core's info
            entries; None when no member steps or a member's core is not an ``AttentiveRescueEnv``).
        """
        with numba_threads(self.threads):
            commands = self._commands(indices, actions)
            touched = self._move(indices, commands)
            readings = self._perceive(indices)
            steps, completed = self._complete(indices, touched, readings)
            return self._observe(indices, steps), completed

    def _commands(self, indices: Sequence[int], actions: np.ndarray) -> list[tuple[float, float]]:
        """The robots' commands (linear m/s, angular rad/s) of the members ``indices``: each
        action down its wrappers' hooks, then checked and converted by its env."""
        commands = []
        for i in indices:
            action = actions[i]
            for hook in self._action_hooks[i]:
                action = hook(action)
            commands.append(self.bases[i].command(action))
        return commands

    def _move(self, indices: Sequence[int], commands: list[tuple[float, float]]) -> list[bool]:
        """The world stage: every member's world advances under its command; whether each robot
        touched anything."""
        if not indices:
            return []
        worlds = [self.bases[i].world for i in indices]
        return step_worlds(worlds, self.bases[0].dt, np.array(commands, dtype=np.float64)).tolist()

    def _perceive(self, indices: Sequence[int]) -> SensorReading:
        """The perceive stage: the sensors of the members ``indices`` read in one compiled
        call (the others' rows, generators and scenes left alone); their readings as
        ``(len(indices), ·)`` blocks, row j for member ``indices[j]``."""
        bases = self.bases
        self._scenes = scenes = self._scenes.with_scenes([base.world.geometry_cache for base in bases])
        body_poses = np.concatenate([base.world.moving_poses() for base in bases])
        active = np.zeros(len(bases), np.bool_)
        active[list(indices)] = True
        readings = bases[0].sensors.read_batch(
            body_poses[scenes.body_start[:-1]],  # each member's first moving body is its robot
            scenes,
            [base.np_random for base in bases],
            ROBOT_ID,
            body_poses=body_poses,
            active=active,
        )
        rows = slice(None) if len(indices) == len(bases) and list(indices) == list(range(len(bases))) else indices
        return SensorReading(
            readings.sonar[rows], readings.laser[rows], readings.sonar_owner[rows], readings.laser_owner[rows]
        )

    def _complete(
        self, indices: Sequence[int], touched: list[bool], readings: SensorReading
    ) -> tuple[list[StepResult], CompletedSteps | None]:
        """The complete stage: each member's ``(observation, reward, terminated, truncated, info)``
        from its reading (row j of ``readings`` for ``indices[j]``), all in one
        ``envs.completion.complete_steps`` call with the completed steps as arrays when every
        core is an ``AttentiveRescueEnv``; else member by member through ``StagedEnv.complete_step``
        (and no arrays)."""
        bases = [self.bases[i] for i in indices]
        if not bases:
            return [], None
        if not self._completes_together:
            blocks = (readings.sonar, readings.laser, readings.sonar_owner, readings.laser_owner)
            rows = [SensorReading(*(block[j] for block in blocks)) for j in range(len(bases))]
            return [base.complete_step(hit, row) for base, hit, row in zip(bases, touched, rows)], None
        completed = complete_steps(bases, touched, readings)
        for base in bases:
            if base.render_mode == "human" and base.render_overlay is None:
                base.render()
        steps = list(
            zip(
                completed.observations(),
                completed.rewards,
                completed.terminations,
                completed.truncations,
                completed.infos(),
            )
        )
        return steps, completed

    def _observe(self, indices: Sequence[int], steps: list[StepResult]) -> list[StepResult]:
        """The completed ``steps`` of the members ``indices`` with their observations taken up
        the members' wrappers (the models in one batch when they form one)."""
        hooks = [self._observation_hooks[i] for i in indices]
        if self._models is not None:  # every member's innermost stage: its attention wrapper, models batched
            stages = [self._model_stages[i] for i in indices]
            model_readings = [
                stage.model_reading(observation, info) for stage, (observation, _, _, _, info) in zip(stages, steps)
            ]
            outputs = self._models.step(model_readings, list(indices))
            observe = type(stages[0]).observe_outputs if stages else lambda *_: []
            observations = observe(stages, [step[0] for step in steps], [step[4] for step in steps], outputs)
            steps = [(observation, *step[1:]) for observation, step in zip(observations, steps)]
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


def _check_threads(threads) -> int:
    limit = numba.config.NUMBA_NUM_THREADS
    if isinstance(threads, (bool, np.bool_)) or not isinstance(threads, (int, np.integer)) or not 1 <= threads <= limit:
        raise ValueError(f"threads must be an integer in [1, {limit}] (NUMBA_NUM_THREADS), got {threads!r}")
    return int(threads)


def _sensor_settings(sensors) -> tuple:
    """What must be equal for two members' sensors to be read in one ``read_batch`` call."""
    return (sensors.sonar_ring.config, sensors.laser_scanner.config, sensors.noise_model, sensors.noise_std)


def _model_stages(stages: list[list]) -> list[ModelStage] | None:
    """The members' innermost observation stages when every one is a ``ModelStage`` and their
    models can form a ``ModelBatch``; else None."""
    innermost = [member[0] if member else None for member in stages]
    if not all(isinstance(stage, ModelStage) for stage in innermost):
        return None
    return innermost if batching_problem([stage.model for stage in innermost]) is None else None


def _observation_hook(stage):
    """``hook(observation, info) -> observation`` of an observation stage or a Gymnasium
    ``ObservationWrapper``."""
    if isinstance(stage, gym.ObservationWrapper) and type(stage).step is gym.ObservationWrapper.step:
        return lambda observation, info, observe=stage.observation: observe(observation)
    return stage.observe_step


def _hooks(env: gym.Env, index: int) -> tuple[list, list]:
    """The action hooks of ``env``'s wrappers, outermost first, and its observation stages
    (``ObservationStage`` or Gymnasium ``ObservationWrapper`` layers), innermost first. An
    ``ActionWrapper`` that is also an ``ObservationStage`` (``GoalActionWrapper``) gives both."""
    actions, observations = [], []
    layer = env
    while isinstance(layer, gym.Wrapper):
        cls = type(layer)
        if isinstance(layer, gym.ActionWrapper) and cls.step is gym.ActionWrapper.step:
            actions.append(layer.action)
        elif isinstance(layer, gym.ActionWrapper) and isinstance(layer, ObservationStage):  # acts before and after
            actions.append(layer.action)
            observations.append(layer)
        elif isinstance(layer, gym.ObservationWrapper) and cls.step is gym.ObservationWrapper.step:
            observations.append(layer)
        elif isinstance(layer, ObservationStage):
            observations.append(layer)
        else:
            raise ValueError(
                f"env {index}: the wrapper {cls.__name__} cannot be stepped in a fleet; allowed: gymnasium "
                "ActionWrapper/ObservationWrapper subclasses that keep their step(), and observation stages "
                "(attentive_gym.vector.protocol.ObservationStage, ActionWrapper subclasses among them)"
            )
        layer = layer.env
    observations.reverse()
    return actions, observations
