"""``examples/scenario.yaml``: the complete scenario file of docs/scenarios.md loads and runs."""

from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

import attentive_gym  # noqa: F401  (registers the ids)
from attentive_gym.attention.goals import Goal
from attentive_gym.world import load_scenario
from attentive_gym.world.scenario import EvadeBehaviour, PathBehaviour, PursueBehaviour
from attentive_gym.world.scenario_io import scenario_from_dict, scenario_to_dict
from attentive_gym.wrappers import make_env

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "scenario.yaml"


def test_the_example_uses_every_kind_of_body_and_behaviour():
    scenario = load_scenario(EXAMPLE)
    assert scenario.enclosed and scenario.walls
    assert {piece.kind for piece in scenario.rubble} == {"box", "circle", "segment"}
    assert {mover.kind for mover in scenario.movers} == {"victim", "robot"}
    behaviours = [type(mover.behaviour) for mover in scenario.movers]
    assert {PathBehaviour, PursueBehaviour, EvadeBehaviour, type(None)} <= set(behaviours)
    assert scenario.task.target == "survivor"
    assert scenario.task.goal == Goal.between("speed", 0.5, 0.9)
    assert scenario_from_dict(scenario_to_dict(scenario)) == scenario


def test_the_example_runs_in_the_environment():
    env = gym.make("AttentiveRescue-v0", scenario=str(EXAMPLE))
    obs, info = env.reset(seed=0)
    assert info["mover_names"][info["target_index"]] == "survivor"
    assert info["goal"] == "speed in [0.5, 0.9] m/s"
    rng = np.random.default_rng(0)
    for _ in range(200):  # 10 s of random driving
        obs, reward, terminated, truncated, info = env.step(rng.uniform(-1, 1, 2))
        assert np.isfinite(reward) and all(np.all(np.isfinite(v)) for v in obs.values())
        assert not truncated
        if terminated:
            break
    assert env.observation_space.contains(obs)
    env.close()


def test_the_example_truncates_at_its_time_limit():
    env = gym.make("AttentiveRescue-v0", scenario=str(EXAMPLE), time_limit_s=1.0)
    env.reset(seed=0)
    flags = [env.step(np.zeros(2))[3] for _ in range(20)]
    assert flags == [False] * 19 + [True]


@pytest.mark.parametrize("variant", ["focus", "raw-stack"])
def test_the_example_runs_in_the_variants(variant):
    env = make_env(variant, scenario=str(EXAMPLE))
    env.reset(seed=1)
    for _ in range(10):
        env.step(env.action_space.sample())
    env.close()
