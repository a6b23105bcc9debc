"""The public names a fleet (``attentive_gym.vector.fleet``) steps its members through, one protocol per role.

- ``StagedEnv``: the environment at a member's core (``AttentiveRescueEnv``), stepped in stages:
  ``command`` (check an action, convert it to the robot's command), ``move`` (the world advances),
  ``sensing_request`` (what a reading of its sensors needs: a fleet reads the same from its
  ``world`` and ``np_random`` for all members at once), ``complete_step`` (reward,
  termination, info and the observation of a fresh reading). Its ``step(action)`` is
  ``complete_step(move(*command(action)), sensors.read(*sensing_request()))``.
- ``ObservationStage``: a wrapper whose observation of a step is ``observe_step(observation,
  info)`` of the observation and info below it (``OracleFocus``; ``AttentionWrapper``;
  ``GoalActionWrapper``, an ``ActionWrapper`` whose ``observe_step`` adds its choice to ``info``).
- ``ModelStage``: an ``ObservationStage`` that runs an ``AttentionModel`` (``AttentionWrapper``):
  ``observe_step`` is ``observe_output(observation, info, model.step(*model_reading(observation,
  info)))``, so a fleet can step the members' models together (``ModelBatch``) between the two,
  then encode the members' observations together (``observe_outputs``).

Gymnasium's own ``ActionWrapper`` and ``ObservationWrapper`` (those that keep their ``step``) are
stepped through their public ``action`` and ``observation``; they need no protocol of their own.
All classes are ``typing.Protocol`` classes checked at run time (``isinstance`` tests that the
names exist, not their signatures).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, Protocol, runtime_checkable

import gymnasium as gym
import numpy as np

from attentive_gym.attention import AttentionModel, AttentionOutput
from attentive_gym.sensors import SensorReading, SensorSuite
from attentive_gym.world import World

__all__ = ["StagedEnv", "ObservationStage", "ModelStage", "StepResult"]

#: ``(observation, reward, terminated, truncated, info)``, as ``gym.Env.step`` returns it.
StepResult = tuple[Any, float, bool, bool, dict[str, Any]]


@runtime_checkable
class StagedEnv(Protocol):
    """An environment stepped in stages; ``AttentiveRescueEnv`` is one.

    Attributes:
        sensors: the robot's sensors; a fleet reads every member's at once with the first
            member's ``sensors.read_batch`` (so the members' sensors must be equal).
        world: the ``World`` that ``move`` advances (None before the first ``reset``); a
            fleet steps the members' worlds in one ``world.step_worlds`` call, and stacks
            their ``world.geometry_cache`` for the batched sensor read.
        dt: the step (s) ``move`` advances the world by; a fleet's members share it.
        np_random: the generator the sensors' noise is drawn from (as ``sensing_request``
            names it).
        action_space: the action space ``command`` checks against.
        observation_space: the space of ``complete_step``'s observation.
    """

    sensors: SensorSuite
    world: World | None
    dt: float
    np_random: np.random.Generator
    action_space: gym.Space
    observation_space: gym.Space

    def command(self, action: Any) -> tuple[float, float]:
        """``action`` checked (``ValueError`` when bad, ``RuntimeError`` before ``reset``) and
        converted to the robot's command: (linear m/s, angular rad/s). Nothing moves."""

    def move(self, linear_mps: float, angular_rps: float) -> bool:
        """Advance the world by one step under the command; whether the robot touched anything."""

    def sensing_request(self) -> tuple:
        """The arguments of ``sensors.read`` now: ``(pose (3,), scene geometry, rng, own owner id)``."""

    def complete_step(self, touched: bool, reading: SensorReading) -> StepResult:
        """The step's ``(observation, reward, terminated, truncated, info)`` once the world has
        moved (``touched``: ``move``'s result), from the fresh reading ``reading``."""


@runtime_checkable
class ObservationStage(Protocol):
    """A wrapper whose step's observation is ``observe_step`` of the one below it."""

    def observe_step(self, observation: Any, info: dict[str, Any]) -> Any:
        """This wrapper's observation of a step, from the observation and ``info`` below it
        (``info`` may gain entries)."""


@runtime_checkable
class ModelStage(ObservationStage, Protocol):
    """An ``ObservationStage`` that runs an attentional model between reading and encoding.

    Attributes:
        model: the wrapper's ``AttentionModel``; a fleet steps the members' models in one
            ``ModelBatch`` when they can form one (``attention.compiled.batch.batching_problem``).
    """

    model: AttentionModel

    def model_reading(self, observation: Any, info: dict[str, Any]) -> tuple:
        """``model.step``'s arguments for a step's observation and info:
        ``(t, sonar, laser, odometry, sonar_time_s, laser_time_s)``."""

    def observe_output(self, observation: Any, info: dict[str, Any], output: AttentionOutput) -> Any:
        """This wrapper's observation of a step, given its model's ``output`` on it."""

    @classmethod
    def observe_outputs(
        cls,
        stages: Sequence[Any],
        observations: Sequence[Any],
        infos: Sequence[dict[str, Any]],
        outputs: Sequence[AttentionOutput],
    ) -> list[Any]:
        """``observe_output`` of each of k stages (distinct, one observation's settings) on its
        step's observation, info and output, all in one call; the same observations."""
