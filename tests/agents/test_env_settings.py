"""The env's settings objects (reward, robot, sonar, laser) as JSON in a run's spec and command line."""

import json

import pytest

from attentive_gym.agents.config import RunSpec
from attentive_gym.agents.training import env_factory, find_spec
from attentive_gym.cli import main
from attentive_gym.envs import RewardConfig
from attentive_gym.envs.config_mappings import config_as_mapping
from attentive_gym.sensors import LaserConfig, SonarConfig

#: Task 1's reward (the default task) with contact costing 10 per second.
REWARD_10 = config_as_mapping(RewardConfig(collision_per_s=10.0, contact_limit_s=1.0, near_per_s=4.0))


def test_a_spec_stores_every_field_however_the_settings_were_given():
    partial = RunSpec(env_kwargs={"reward": {"collision_per_s": 10}, "time_limit_s": 2.0})
    assert partial.env_kwargs == {"reward": REWARD_10, "time_limit_s": 2.0}
    whole = RewardConfig(collision_per_s=10, contact_limit_s=1.0, near_per_s=4.0)
    assert RunSpec(env_kwargs={"reward": whole, "time_limit_s": 2.0}).same_settings(partial)
    assert RunSpec(env_kwargs={"reward": REWARD_10, "time_limit_s": 2.0}) == partial


def test_a_reward_mapping_fills_its_missing_fields_from_the_specs_task():
    fields = {"reward": {"collision_per_s": 10}}
    assert RunSpec(env_kwargs=fields, task_version=0).env_kwargs["reward"] == config_as_mapping(
        RewardConfig(collision_per_s=10.0)
    )
    assert RunSpec(env_kwargs=fields, task_version=1).env_kwargs["reward"] == REWARD_10
    spec = RunSpec(variant="raw", env_kwargs={"reward": {"contact_limit_s": None}})
    assert env_factory(spec)().unwrapped.reward_config == RewardConfig(near_per_s=4.0)


def test_a_spec_round_trips_through_json_and_rebuilds_the_same_env_settings():
    spec = RunSpec(variant="raw", env_kwargs={"sonar": {"max_range_m": 4}, "laser": {"num_beams": 90}})
    read_back = RunSpec.from_dict(json.loads(spec.to_json()))
    assert read_back == spec and read_back.same_settings(spec)
    env = env_factory(read_back)().unwrapped
    assert env.sensors.sonar_ring.config == SonarConfig(max_range_m=4.0)
    assert env.sensors.laser_scanner.config == LaserConfig(num_beams=90)


@pytest.mark.parametrize(
    "env_kwargs, message",
    [
        ({"reward": {"colision_per_s": 10}}, "reward: RewardConfig has no field(s) ['colision_per_s']; allowed: "),
        ({"robot": {"mass_kg": -1}}, "RobotConfig.mass_kg must be a finite number > 0, got -1"),
        ({"laser": 90}, "env_kwargs: laser must be a LaserConfig or a mapping of its fields, got int"),
    ],
)
def test_a_spec_refuses_a_bad_setting(env_kwargs, message):
    with pytest.raises(ValueError) as caught:
        RunSpec(env_kwargs=env_kwargs)
    assert message in str(caught.value)


def test_train_refuses_an_unknown_reward_field_before_writing_anything(tmp_path, capsys):
    out = tmp_path / "run"
    argv = ["train", "--variant", "raw", "--steps", "64", "--out", str(out)]
    assert main([*argv, "--env-kwargs", '{"reward": {"colision_per_s": 10}}']) == 2
    err = capsys.readouterr().err
    assert "reward: RewardConfig has no field(s) ['colision_per_s']; allowed: ['progress_per_m'," in err
    assert not out.exists()


def test_train_takes_a_reward_mapping_records_it_and_the_run_reads_back_with_it(tmp_path, tiny):
    out = tmp_path / "run"
    env_kwargs = {**tiny.env_kwargs, "reward": {"collision_per_s": 10}}
    argv = ["train", "--variant", "raw", "--steps", "128", "--no-progress", "--out", str(out), "--n-envs", "2"]
    argv += ["--eval-episodes", "1", "--algo-kwargs", json.dumps(tiny.ppo_kwargs)]
    assert main([*argv, "--env-kwargs", json.dumps(env_kwargs)]) == 0
    assert json.loads((out / "spec.json").read_text())["env_kwargs"] == {**tiny.env_kwargs, "reward": REWARD_10}
    _, spec = find_spec(out / "final_model.zip")  # what evaluate reads
    assert env_factory(spec)().unwrapped.reward_config == RewardConfig(
        collision_per_s=10.0, contact_limit_s=1.0, near_per_s=4.0
    )
    assert main([*argv, "--env-kwargs", json.dumps({**tiny.env_kwargs, "reward": REWARD_10})]) == 0  # the same run
