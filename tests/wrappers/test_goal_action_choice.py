"""GoalActionWrapper: the agent's goal and weights reach the model at every step, and info says which."""

import numpy as np
import pytest

from attentive_gym.attention.config import MAP_NAMES
from attentive_gym.wrappers import DEFAULT_GOAL_MENU, make_env
from attentive_gym.wrappers.goal_action import DEFAULT_MAX_WEIGHT, NO_CHOICE

K = len(DEFAULT_GOAL_MENU)


def asked_for(action):
    """(menu index, (6,) float64 weights) that ``action`` asks for, by the wrapper's layout."""
    action = np.clip(np.asarray(action, np.float64), -1.0, 1.0)
    return int(np.argmax(action[2 : 2 + K])), (action[2 + K :] + 1.0) * 0.5 * DEFAULT_MAX_WEIGHT


def test_the_chosen_goal_and_weights_reach_the_model_and_info_at_every_step():
    env = make_env("goal-action", time_limit_s=2.0)  # 40-step episodes: the steps span resets
    attention = env.env
    rng = np.random.default_rng(7)
    _, info = env.reset(seed=3)
    assert info["goal_choice"] == NO_CHOICE and info["goal_choice_matches"] is False
    np.testing.assert_array_equal(info["map_weights"], np.ones(len(MAP_NAMES)))  # the configured weights
    matched = resets = 0
    for step in range(120):
        action = rng.uniform(-1.1, 1.1, env.action_space.shape).astype(np.float32)  # a few beyond the bounds
        _, _, terminated, truncated, info = env.step(action)
        choice, weights = asked_for(action)
        goal = DEFAULT_GOAL_MENU[choice]
        assert attention.model.goals == (() if goal is None else (goal,)), f"step {step}"
        np.testing.assert_array_equal(np.fromiter(attention.model.weights.values(), float), weights)
        assert info["goal_choice"] == choice and type(info["goal_choice"]) is int
        assert info["map_weights"].dtype == np.float64 and info["map_weights"].shape == (len(MAP_NAMES),)
        np.testing.assert_array_equal(info["map_weights"], weights)
        assert info["goal_choice_matches"] == (goal == env.unwrapped.goal)
        matched += info["goal_choice_matches"]
        if terminated or truncated:
            _, info = env.reset()
            resets += 1
            assert info["goal_choice"] == NO_CHOICE and not info["goal_choice_matches"]
    assert resets >= 2 and 0 < matched < 120


def _run_with_goal(choice, steps=60):
    """The model outputs of ``steps`` steps (seed 0, the same motion) choosing menu entry ``choice`` throughout."""
    env = make_env("goal-action", scenario="exp01", sensor_noise=0.0)
    env.reset(seed=0)
    motion = np.random.default_rng(1).uniform(-1, 1, (steps, 2))
    outputs = []
    for linear_angular in motion:
        action = np.ones(env.action_space.shape, np.float32)  # every weight 2
        action[:2] = linear_angular
        action[2 : 2 + K] = -1.0
        action[2 + choice] = 1.0
        outputs.append(env.step(action)[4]["attention"])
    return outputs


def test_attention_depends_on_the_chosen_goal():
    without, with_goal = _run_with_goal(DEFAULT_GOAL_MENU.index(None)), _run_with_goal(1)  # speed in [0.5, 0.9]
    assert not any(out.goal_fulfilled.any() or out.F[3].any() for out in without)  # no goal: no top-down map
    assert any(out.F[3].any() for out in with_goal)
    assert any(not np.array_equal(a.C, b.C) for a, b in zip(without, with_goal))


@pytest.mark.parametrize("choice", range(K))
def test_info_says_whether_the_chosen_goal_is_the_tasks(choice):
    env = make_env("goal-action")
    task_goal = DEFAULT_GOAL_MENU[1]
    env.reset(seed=0, options={"goal": task_goal})
    action = np.zeros(env.action_space.shape, np.float32)
    action[2 + choice] = 1.0
    info = env.step(action)[4]
    assert info["goal_choice"] == choice and info["goal_choice_matches"] == (choice == 1)
