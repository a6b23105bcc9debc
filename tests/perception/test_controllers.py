"""``attentive_gym.perception.controllers``: what each scripted policy does, and their success rates."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
from gymnasium import spaces

from attentive_gym.attention import ORIGIN_BOTTOM_UP, ORIGIN_TOP_DOWN
from attentive_gym.envs import AttentiveRescueEnv
from attentive_gym.perception import CONTROL_ARENA, controllers
from attentive_gym.perception.controllers import (
    SEARCH_SPIN,
    WANDER_ANGULAR,
    WANDER_CLEARANCE_M,
    WANDER_LINEAR,
    WANDER_PERIOD_S,
    FocusController,
    RandomController,
    Wander,
    clearance_controller,
    free_heading,
    steer,
    true_bearing_controller,
)
from attentive_gym.wrappers import make_env


def test_steer_turns_towards_the_bearing_and_drives_only_when_facing_it():
    assert steer(0.0).tolist() == [1.0, 0.0]
    assert steer(None).tolist() == [0.0, SEARCH_SPIN]  # nothing to steer to: spin in place
    action = steer(0.25)
    assert action.dtype == np.float32
    np.testing.assert_allclose(action, [math.cos(0.25), 0.5], rtol=1e-6)
    np.testing.assert_allclose(steer(-2.0), [0.0, -1.0])  # behind: turn at the limit, no forward drive


def _output(origin, bearing_rad=0.0, track_xy=None):
    """A stand-in for an ``AttentionOutput`` with a focus view."""
    return SimpleNamespace(origin=origin, view=SimpleNamespace(bearing_rad=bearing_rad, track_position_m=track_xy))


def test_focus_bearing_prefers_the_focused_track():
    assert controllers.focus_bearing(_output(ORIGIN_TOP_DOWN, 0.3)) == 0.3
    assert controllers.focus_bearing(_output(ORIGIN_TOP_DOWN, 0.3, (1.0, 1.0))) == pytest.approx(math.pi / 4)


def test_the_focus_controller_follows_the_top_down_focus_as_the_robot_turns():
    policy = FocusController(dt_s=0.1)
    turning = {"odometry": np.array([0.0, 1.0])}  # 1 rad/s to the left
    assert policy(turning, {"attention": _output(ORIGIN_BOTTOM_UP, 0.5)}).tolist() == steer(None).tolist()
    np.testing.assert_array_equal(policy(turning, {"attention": _output(ORIGIN_TOP_DOWN, 0.3)}), steer(0.3))
    # a bottom-up focus does not replace it; the robot's turn carries it 0.1 rad to the right per step
    np.testing.assert_allclose(policy(turning, {"attention": _output(ORIGIN_BOTTOM_UP, -1.0)}), steer(0.2))
    np.testing.assert_allclose(policy(turning, {"attention": SimpleNamespace(origin=None)}), steer(0.1))  # no focus


def test_the_memory_controller_steers_at_the_first_memory_row_only_when_it_matched_the_goal():
    memory = np.zeros((3, 6), np.float32)
    memory[0, :5] = [math.cos(0.5), math.sin(0.5), 2.0, 0.6, 1.0]  # 0.5 rad to the left, matched
    memory[1, :5] = [1.0, 0.0, 1.0, 0.3, 0.0]
    np.testing.assert_allclose(controllers.memory_controller({"memory": memory.ravel()}, None), steer(0.5), rtol=1e-6)
    memory[0, 4] = 0.0  # no goal match anywhere: search
    assert controllers.memory_controller({"memory": memory.ravel()}, None).tolist() == steer(None).tolist()


def test_the_true_bearing_controller_steers_at_the_target():
    info = {"mover_positions": np.array([[2.0, 1.0]]), "target_index": 0, "robot_pose": np.array([1.0, 1.0, 0.0])}
    np.testing.assert_array_equal(controllers.true_bearing_controller({}, info), steer(0.0))


def test_wander_drives_a_seeded_sinusoid_and_turns_away_from_close_obstacles():
    clear = {"laser": np.full(180, 10.0)}
    wander, again = Wander(seed=3), Wander(seed=3)
    assert (wander.phase_rad, wander.turn_sign) == (again.phase_rad, again.turn_sign)
    assert 0.0 <= wander.phase_rad < 2 * math.pi and wander.turn_sign in (-1.0, 1.0)
    action = wander(clear, {"time_s": 2.0})
    expected = WANDER_ANGULAR * math.sin(2 * math.pi * 2.0 / WANDER_PERIOD_S + wander.phase_rad)
    np.testing.assert_allclose(action, [WANDER_LINEAR, expected], rtol=1e-6)
    blocked = {"laser": np.where(np.arange(180) == 95, WANDER_CLEARANCE_M - 0.1, 10.0)}  # 5° left of ahead
    assert wander(blocked, {"time_s": 2.0}).tolist() == [0.0, wander.turn_sign]
    side = {"laser": np.where(np.arange(180) == 10, 0.1, 10.0)}  # close, but 80° to the right
    assert wander(side, {"time_s": 2.0})[0] == pytest.approx(WANDER_LINEAR)
    assert {Wander(seed).turn_sign for seed in range(20)} == {-1.0, 1.0}


def test_the_random_controller_is_seeded_and_stand_still_is_zero():
    def draws(seed):
        policy = RandomController(spaces.Box(-1.0, 1.0, (2,), np.float32), seed)
        return np.array([policy(None, None) for _ in range(5)])

    np.testing.assert_array_equal(draws(7), draws(7))
    assert not np.array_equal(draws(7), draws(8))
    assert draws(7).shape == (5, 2) and np.all(np.abs(draws(7)) <= 1.0)
    assert controllers.stand_still({}, {}).tolist() == [0.0, 0.0]


def test_every_steering_controller_reaches_more_targets_than_random_actions(attended_env):
    """On seeds 0..3 of 10 s episodes, noise-free: the oracle reaches 2/4 targets, the focus
    controller 1/4 and the memory controller 2/4, random actions none."""
    seeds = range(4)
    env = attended_env("window", arena=CONTROL_ARENA, time_limit_s=10.0)
    random = controllers.control_success(env, lambda env, seed: RandomController(env.action_space, seed), seeds)
    focus = controllers.control_success(env, lambda env, seed: FocusController(env.unwrapped.dt), seeds)
    oracle = controllers.control_success(env, lambda env, seed: controllers.true_bearing_controller, seeds)
    focus_env = attended_env("tracker", variant="focus", arena=CONTROL_ARENA, time_limit_s=10.0)
    memory = controllers.control_success(focus_env, lambda env, seed: controllers.memory_controller, seeds)
    assert oracle > random and focus > random and memory > random, (oracle, focus, memory, random)


def test_the_oracle_reaches_targets_that_standing_still_does_not(attended_env):
    env = attended_env("window", arena=CONTROL_ARENA)
    oracle = controllers.control_success(env, lambda env, seed: controllers.true_bearing_controller, [0, 1])
    still = controllers.control_success(env, lambda env, seed: controllers.stand_still, [0, 1])
    assert oracle > still


def test_control_success_needs_a_seed():
    with pytest.raises(ValueError, match="at least one seed"):
        controllers.control_success(None, lambda env, seed: controllers.stand_still, [])


def test_free_heading_keeps_the_target_bearing_when_nothing_is_near_and_goes_around_what_is():
    far = np.full(8, 5.0)
    assert abs(free_heading(far, 0.0, 3.0)) == pytest.approx(np.radians(0.5))  # a beam nearest 0
    blocked_ahead = far.copy()
    blocked_ahead[[3, 4]] = 0.6  # the two front regions (≈ ±10°) read 0.6 m
    heading = free_heading(blocked_ahead, 0.0, 3.0)
    assert heading is not None and abs(heading) > np.radians(15)  # the corridor passes beside them
    assert free_heading(np.full(8, 0.5), 0.0, 3.0) is None  # everything within the look-ahead


def test_the_clearance_controller_reaches_more_targets_safely_than_steering_straight():
    """On the main comparison's arena with a 1 s contact limit, the reactive avoider on the
    oracle's observation with proximity succeeds where the straight line strikes something."""
    task = {"arena_size_m": 8.0, "num_distractors": 2, "rubble_per_100m2": 3.0, "reward": {"contact_limit_s": 1.0}}

    def successes(env, policy):
        reached = 0
        for seed in range(51_000, 51_020):  # the evaluation episodes of seed 41
            observation, info = env.reset(seed=seed)
            ended = False
            while not ended:
                observation, _, terminated, truncated, info = env.step(policy(observation, info))
                ended = terminated or truncated
            reached += info["success"]
        return reached

    avoided = successes(make_env("oracle", proximity=True, **task), clearance_controller)
    straight = successes(AttentiveRescueEnv(**task), true_bearing_controller)
    assert avoided >= 18 and avoided >= straight + 4, (avoided, straight)  # measured: 19 and 13
