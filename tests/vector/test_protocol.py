"""The batching protocol (``attentive_gym.vector.protocol``): the project's envs and wrappers
speak it, a fleet steps members that expose nothing but its public names, and a fleet's steps
equal single steps in crowded arenas (contacts, blocked movers, pursuing and evading targets)."""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.vector import SyncVectorEnv

import attentive_gym  # noqa: F401  (registers the ids)
from attentive_gym.attention import Goal
from attentive_gym.envs import AttentiveRescueEnv
from attentive_gym.vector import AttentiveRescueVectorEnv, Fleet, ModelStage, ObservationStage, StagedEnv
from attentive_gym.wrappers import AttentionWrapper, OracleFocus, StackedReadings, make_env

SHORT = {"time_limit_s": 1.0, "arena_size_m": 8.0, "num_distractors": 2}
#: A small arena crowded with rubble and movers, the targets pursuing or evading the robot:
#: the robot touches something in many steps, and movers run into it and the rubble.
CROWDED = {
    "time_limit_s": 4.0,
    "arena_size_m": 7.0,
    "num_distractors": 4,
    "rubble_per_100m2": 15.0,
    "goals": (Goal.direction_is("towards"), Goal.direction_is("away")),
}


class PublicOnly(gym.Env):
    """An ``AttentiveRescueEnv`` seen through the protocol's public names only (and Gymnasium's
    ``reset``/``step``): a fleet that reached for any other name of the env would fail."""

    def __init__(self, env: AttentiveRescueEnv) -> None:
        self._env = env
        self.action_space, self.observation_space, self.sensors = env.action_space, env.observation_space, env.sensors

    @property
    def world(self):
        return self._env.world

    @property
    def dt(self) -> float:
        return self._env.dt

    @property
    def np_random(self):
        return self._env.np_random

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        return self._env.reset(seed=seed, options=options)

    def step(self, action):
        return self._env.step(action)

    def command(self, action):
        return self._env.command(action)

    def move(self, linear_mps: float, angular_rps: float) -> bool:
        return self._env.move(linear_mps, angular_rps)

    def sensing_request(self) -> tuple:
        return self._env.sensing_request()

    def complete_step(self, touched, reading):
        return self._env.complete_step(touched, reading)


class HalvedLaser(gym.Wrapper):
    """A wrapper of one's own that speaks the protocol: its observation is ``observe_step``'s."""

    def step(self, action):
        observation, reward, terminated, truncated, info = self.env.step(action)
        return self.observe_step(observation, info), reward, terminated, truncated, info

    def reset(self, **kwargs):
        observation, info = self.env.reset(**kwargs)
        return self.observe_step(observation, info), info

    def observe_step(self, observation, info):
        info["halved"] = True
        return {**observation, "laser": (observation["laser"] * 0.5).astype(np.float32)}


def _rollout(env, steps: int, seed: int = 3) -> list:
    """Batched observations, rewards, terminations, truncations and the info keys of ``env``
    over ``steps`` random steps after ``reset(seed=seed)``."""
    observation, _ = env.reset(seed=seed)
    frames = [observation]
    rng = np.random.default_rng(seed)
    for _ in range(steps):
        observation, reward, terminated, truncated, info = env.step(
            rng.uniform(-1, 1, env.action_space.shape).astype(np.float32)
        )
        frames.append((observation, reward, terminated, truncated, sorted(info)))
    env.close()
    return frames


def _assert_same(a, b) -> None:
    if isinstance(a, dict):
        assert a.keys() == b.keys()
        for key in a:
            _assert_same(a[key], b[key])
    elif isinstance(a, (tuple, list)):
        assert len(a) == len(b)
        for x, y in zip(a, b):
            _assert_same(x, y)
    else:
        a, b = np.asarray(a), np.asarray(b)
        assert a.dtype == b.dtype and a.shape == b.shape and np.array_equal(a, b)


def test_the_project_speaks_the_protocol():
    env = make_env("focus")
    assert isinstance(env.unwrapped, StagedEnv)
    assert isinstance(env, ModelStage) and isinstance(env, ObservationStage)
    oracle = OracleFocus(AttentiveRescueEnv())
    assert isinstance(oracle, ObservationStage) and not isinstance(oracle, ModelStage)
    assert not isinstance(StackedReadings(AttentiveRescueEnv()), ObservationStage)  # a Gymnasium ObservationWrapper
    assert not isinstance(gym.make("Pendulum-v1").unwrapped, StagedEnv)


def test_a_step_is_its_stages():
    env, twin = AttentiveRescueEnv(**SHORT), AttentiveRescueEnv(**SHORT)
    env.reset(seed=5), twin.reset(seed=5)
    for action in np.random.default_rng(5).uniform(-1.5, 1.5, (30, 2)):
        linear, angular = twin.command(action)
        assert (linear, angular) == (
            np.clip(action[0], -1, 1) * twin.robot_config.max_linear_mps,
            np.clip(action[1], -1, 1) * twin.robot_config.max_angular_rps,
        )
        touched = twin.move(linear, angular)
        staged = twin.complete_step(touched, twin.sensors.read(*twin.sensing_request()))
        _assert_same(env.step(action)[:4], staged[:4])
        if staged[2] or staged[3]:
            env.reset(), twin.reset()


def test_command_checks_before_anything_moves():
    env = AttentiveRescueEnv(**SHORT)
    with pytest.raises(RuntimeError, match="call reset"):
        env.command(np.zeros(2))
    env.reset(seed=0)
    pose = env.world.robot.pose
    for bad in (np.array([np.nan, 0.0]), np.zeros(3), "fast"):
        with pytest.raises(ValueError, match="action must"):
            env.command(bad)
    assert np.array_equal(env.world.robot.pose, pose) and env.world.time_s == 0.0


def test_a_fleet_of_members_that_expose_only_the_public_names_equals_their_single_steps():
    config = AttentionWrapper(AttentiveRescueEnv(**SHORT)).model.config  # the config make_env's wrapper assumes
    members = [AttentionWrapper(PublicOnly(AttentiveRescueEnv(**SHORT)), config=config) for _ in range(3)]
    fleet = Fleet(members)
    assert fleet.batches_models  # the attention wrappers are model stages: one ModelBatch
    native = AttentiveRescueVectorEnv(members)
    sync = SyncVectorEnv([lambda: AttentionWrapper(AttentiveRescueEnv(**SHORT), config=config) for _ in range(3)])
    _assert_same(_rollout(native, 45), _rollout(sync, 45))


def test_a_wrapper_of_ones_own_that_speaks_the_protocol_steps_in_a_fleet():
    native = AttentiveRescueVectorEnv([HalvedLaser(make_env("raw", **SHORT)) for _ in range(2)])
    sync = SyncVectorEnv([lambda: HalvedLaser(make_env("raw", **SHORT)) for _ in range(2)])
    frames = _rollout(native, 30)
    _assert_same(frames, _rollout(sync, 30))
    assert "halved" in frames[-1][4]


@pytest.mark.parametrize("variant", ["raw", "focus", "oracle"])
def test_crowded_arenas_with_pursuers_and_evaders_step_as_single_envs(variant):
    native = gym.make_vec(
        attentive_gym.registration.VARIANT_IDS[variant], num_envs=4, vectorization_mode="vector_entry_point", **CROWDED
    )
    sync = gym.make_vec(
        attentive_gym.registration.VARIANT_IDS[variant], num_envs=4, vectorization_mode="sync", **CROWDED
    )
    observation, info = native.reset(seed=7)
    expected = sync.reset(seed=7)
    _assert_same(observation, expected[0])
    rng = np.random.default_rng(7)
    contacts, ended = 0, 0
    for _ in range(200):  # ahead at 60-100 % of the top speed, turning a little: into rubble and movers
        actions = np.column_stack([rng.uniform(0.6, 1.0, 4), rng.uniform(-0.3, 0.3, 4)]).astype(np.float32)
        got, want = native.step(actions), sync.step(actions)
        _assert_same(got[:4], want[:4])
        for key in ("collision", "robot_pose", "mover_positions", "mover_velocities", "target_distance_m"):
            _assert_same(got[4][key], want[4][key])
        contacts += int(np.sum(got[4]["collision"] & got[4]["_collision"]))
        ended += int(np.sum(got[2] | got[3]))
    assert contacts >= 50 and ended >= 8  # contacts in many steps, and autoresets
    native.close(), sync.close()
