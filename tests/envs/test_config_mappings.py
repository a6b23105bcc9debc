"""The env's settings objects (reward, robot, sonar, laser) given as plain mappings."""

import json

import gymnasium as gym
import numpy as np
import pytest

import attentive_gym  # noqa: F401  (registers the ids)
from attentive_gym.envs import AttentiveRescueEnv, RewardConfig
from attentive_gym.envs.config_mappings import CONFIG_KEYWORDS, config_as_mapping, config_from, env_kwargs_as_mappings
from attentive_gym.sensors import LaserConfig, SonarConfig
from attentive_gym.world.robot import RobotConfig
from attentive_gym.wrappers.variants import make_env

#: One changed field per keyword, as JSON would give it, and the dataclass it stands for.
CHANGES = {
    "reward": ({"collision_per_s": 10}, RewardConfig(collision_per_s=10.0)),
    "robot": ({"mass_kg": 20.0, "max_linear_mps": 0.5}, RobotConfig(mass_kg=20.0, max_linear_mps=0.5)),
    "sonar": ({"max_range_m": 4}, SonarConfig(max_range_m=4.0)),
    "laser": ({"num_beams": 90, "fov_deg": 270}, LaserConfig(num_beams=90, fov_deg=270.0)),
}


def _configs(env) -> dict:
    """The settings objects an env was built with, by keyword."""
    base = env.unwrapped
    sensors = base.sensors
    return {
        "reward": base.reward_config,
        "robot": base.robot_config,
        "sonar": sensors.sonar_ring.config,
        "laser": sensors.laser_scanner.config,
    }


@pytest.mark.parametrize("keyword", CONFIG_KEYWORDS)
def test_a_mapping_builds_the_same_config_as_the_dataclass(keyword):
    mapping, config = CHANGES[keyword]
    assert config_from(keyword, mapping) == config
    assert config_from(keyword, {}) == CONFIG_KEYWORDS[keyword]()  # fields left out keep their defaults
    assert config_from(keyword, config) is config
    assert _configs(AttentiveRescueEnv(**{keyword: mapping}))[keyword] == config


def test_an_env_from_mappings_steps_bit_for_bit_as_one_from_dataclasses():
    from_mappings = AttentiveRescueEnv(**{k: mapping for k, (mapping, _) in CHANGES.items()})
    from_configs = AttentiveRescueEnv(**{k: config for k, (_, config) in CHANGES.items()})
    assert from_mappings.observation_space == from_configs.observation_space
    observations = [env.reset(seed=5)[0] for env in (from_mappings, from_configs)]
    for _ in range(5):
        steps = [env.step(np.array([1.0, 0.3], np.float32)) for env in (from_mappings, from_configs)]
        assert steps[0][1] == steps[1][1]
        observations += [step[0] for step in steps]
    for first, second in zip(observations[::2], observations[1::2]):
        for key in first:
            np.testing.assert_array_equal(first[key], second[key])


def test_gym_make_and_make_env_take_mappings():
    env = gym.make("AttentiveRescue-v0", reward={"collision_per_s": 10}, laser={"num_beams": 90})
    assert env.unwrapped.reward_config == RewardConfig(collision_per_s=10.0)
    assert env.observation_space["laser"].shape == (90,)
    focus = make_env("focus", robot={"mass_kg": 20.0}, sonar={"max_range_m": 4})
    assert _configs(focus)["robot"] == RobotConfig(mass_kg=20.0)
    assert _configs(focus)["sonar"] == SonarConfig(max_range_m=4.0)


@pytest.mark.parametrize("keyword", CONFIG_KEYWORDS)
def test_an_unknown_field_is_named_with_the_allowed_ones_before_anything_is_built(keyword, monkeypatch):
    import attentive_gym.envs.rescue_env as rescue_env

    monkeypatch.setattr(rescue_env, "SensorSuite", None)  # building anything would fail otherwise
    allowed = [name for name in config_as_mapping(CONFIG_KEYWORDS[keyword]())]
    with pytest.raises(ValueError) as caught:
        AttentiveRescueEnv(**{keyword: {"bogus_m": 1.0}})
    assert str(caught.value) == (
        f"{keyword}: {CONFIG_KEYWORDS[keyword].__name__} has no field(s) ['bogus_m']; allowed: {allowed}"
    )


@pytest.mark.parametrize(
    "keyword, mapping, message",
    [
        ("reward", {"collision_per_s": -1}, "RewardConfig.collision_per_s must be a finite number >= 0, got -1"),
        ("robot", {"mass_kg": 0}, "RobotConfig.mass_kg must be a finite number > 0, got 0"),
        ("sonar", {"max_range_m": "far"}, "SonarConfig.max_range_m must be a finite number, got 'far'"),
        ("laser", {"num_beams": 0}, "LaserConfig.num_beams must be an int >= 1, got 0"),
    ],
)
def test_a_bad_value_raises_the_dataclass_own_error(keyword, mapping, message):
    with pytest.raises(ValueError) as caught:
        AttentiveRescueEnv(**{keyword: mapping})
    assert str(caught.value) == message


def test_anything_but_the_dataclass_or_a_mapping_is_refused():
    with pytest.raises(TypeError, match="reward must be a RewardConfig or a mapping of its fields, got str"):
        AttentiveRescueEnv(reward="collision_per_s=10")
    with pytest.raises(TypeError, match="laser must be a LaserConfig or a mapping of its fields, got SonarConfig"):
        AttentiveRescueEnv(laser=SonarConfig())


@pytest.mark.parametrize("keyword", CONFIG_KEYWORDS)
def test_the_mapping_form_is_plain_json_and_builds_the_config_again(keyword):
    config = CHANGES[keyword][1]
    mapping = config_as_mapping(config)
    assert json.loads(json.dumps(mapping)) == mapping  # no tuples: equal to what is read back
    assert list(mapping) == [name for name in config_as_mapping(CONFIG_KEYWORDS[keyword]())]  # every field
    assert config_from(keyword, json.loads(json.dumps(mapping))) == config


def test_env_kwargs_resolve_each_setting_and_keep_the_others():
    resolved = env_kwargs_as_mappings({"reward": {"collision_per_s": 10}, "sonar": SonarConfig(), "dt": 0.1})
    assert resolved == {
        "reward": config_as_mapping(RewardConfig(collision_per_s=10.0)),
        "sonar": config_as_mapping(SonarConfig()),
        "dt": 0.1,
    }
