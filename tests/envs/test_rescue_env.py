"""AttentiveRescue-v0: API conformance, determinism, pickling, bad input, task logic."""

import math
import pickle

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import attentive_gym  # noqa: F401  (registers the environments)
from attentive_gym.attention.goals import Goal
from attentive_gym.envs.rescue_env import AttentiveRescueEnv
from attentive_gym.world.builtin import BUILTIN_SCENARIOS
from attentive_gym.world.world import ROBOT_ID
from support import assert_same

SCENARIOS = ["rescue", *sorted(BUILTIN_SCENARIOS)]


def rollout(env, seed, steps=60, action_seed=0):
    """Observations, rewards and infos of a seeded random rollout."""
    rng = np.random.default_rng(action_seed)
    obs, info = env.reset(seed=seed)
    trace = [obs]
    for _ in range(steps):
        obs, reward, terminated, truncated, info = env.step(rng.uniform(-1, 1, 2).astype(np.float32))
        trace.append((obs, reward, terminated, truncated, info["robot_pose"], info["mover_positions"]))
        if terminated or truncated:
            obs, info = env.reset()
    return trace


@pytest.mark.parametrize("scenario", SCENARIOS)
def test_gymnasium_check_env(scenario):
    env = gym.make("AttentiveRescue-v0", scenario=scenario).unwrapped
    check_env(env, skip_render_check=True)


def test_sb3_check_env():
    from stable_baselines3.common.env_checker import check_env as sb3_check_env

    sb3_check_env(AttentiveRescueEnv(), warn=True)


def test_make_by_module_path_and_registration_is_idempotent():
    from attentive_gym.registration import register_environments

    register_environments()
    register_environments()
    env = gym.make("attentive_gym:AttentiveRescue-v0")
    assert isinstance(env.unwrapped, AttentiveRescueEnv)


@pytest.mark.parametrize("scenario", ["rescue", "exp03"])
def test_same_seed_same_trajectory_bit_for_bit(scenario):
    first = rollout(AttentiveRescueEnv(scenario), seed=11)
    second = rollout(AttentiveRescueEnv(scenario), seed=11)
    assert_same(first, second)


def test_different_seeds_differ():
    a = rollout(AttentiveRescueEnv(), seed=1, steps=5)
    b = rollout(AttentiveRescueEnv(), seed=2, steps=5)
    assert not np.array_equal(a[0]["laser"], b[0]["laser"])


def test_pickle_round_trip_continues_identically():
    env = AttentiveRescueEnv()
    env.reset(seed=5)
    for _ in range(10):
        env.step(np.array([0.5, 0.2], np.float32))
    clone = pickle.loads(pickle.dumps(env))
    for _ in range(20):
        action = np.array([0.8, -0.3], np.float32)
        assert_same(env.step(action)[:4], clone.step(action)[:4])


def test_observations_match_the_space_and_sensor_limits():
    env = AttentiveRescueEnv()
    obs, _ = env.reset(seed=0)
    for _ in range(50):
        assert env.observation_space.contains(obs)
        assert np.all(obs["sonar"] >= 0.15) and np.all(obs["sonar"] <= 5.0)
        assert np.all(obs["laser"] <= 20.0)
        obs, *_ = env.step(env.action_space.sample())


def test_noise_free_readings_match_the_geometry():
    env = AttentiveRescueEnv("exp01", sensor_noise=0.0)
    obs, info = env.reset(seed=0)
    # exp01: a P2AT 3 m away at +10°, its near face 3 - 0.313 m from the origin, seen by s4
    assert obs["sonar"][3] == pytest.approx(3.0 - 0.313 - 0.245 * np.cos(np.radians(0)), abs=0.06)
    assert info["sonar_hits"][3] == 1
    assert np.all(obs["sonar"][[0, 1, 5, 6, 7]] == 5.0)
    assert set(info["laser_hits"]) <= {-1, 1}


def test_reaching_the_target_terminates_with_the_bonus():
    env = AttentiveRescueEnv()
    env.reset(seed=3)
    world = env.world
    target = world.movers[env._target_index]
    # put the robot next to the target: the next step succeeds
    x, y = target.body.position
    world.robot.body.position = (x + 0.9, y)
    world.robot.control.position = (x + 0.9, y)
    _, reward, terminated, truncated, info = env.step(np.zeros(2, np.float32))
    assert terminated and not truncated and info["success"]
    assert reward > env.reward_config.success - 2.0
    assert info["target_distance_m"] <= 1.0


def test_time_limit_truncates():
    env = AttentiveRescueEnv("exp01", time_limit_s=1.0)
    env.reset(seed=0)
    flags = [env.step(np.zeros(2, np.float32))[3] for _ in range(20)]
    assert flags == [False] * 19 + [True]


def test_goal_option_fixes_the_goal_and_its_encoding():
    env = AttentiveRescueEnv()
    goal = Goal.smaller("speed", 0.3)
    obs, info = env.reset(seed=0, options={"goal": goal})
    np.testing.assert_array_equal(obs["goal"], goal.encode())
    assert info["goal"] == str(goal)
    obs, _ = env.reset(seed=0, options={"goal": Goal.between("speed", 0.5, 0.9).encode()})
    assert Goal.decode(obs["goal"]) == Goal.between("speed", 0.5, 0.9)


@pytest.mark.parametrize(
    "action, message",
    [
        (np.array([np.nan, 0.0]), "finite"),
        (np.array([np.inf, 0.0]), "finite"),
        (np.zeros(3), "shape"),
        (np.zeros((2, 1)), "shape"),
        ("fast", "numeric"),
    ],
)
def test_bad_actions_raise_value_error(action, message):
    env = AttentiveRescueEnv()
    env.reset(seed=0)
    with pytest.raises(ValueError, match=message):
        env.step(action)


def test_out_of_range_actions_are_clipped():
    a, b = AttentiveRescueEnv(), AttentiveRescueEnv()
    a.reset(seed=4)
    b.reset(seed=4)
    for _ in range(10):
        assert_same(a.step(np.array([7.0, -3.0]))[:4], b.step(np.array([1.0, -1.0]))[:4])


@pytest.mark.parametrize(
    "kwargs, error, message",
    [
        ({"scenario": "moon"}, ValueError, "unknown scenario 'moon'; allowed"),
        ({"scenario": "missing.yaml"}, ValueError, "does not exist"),
        ({"sensor_noise": -0.1}, ValueError, "sensor_noise must be a number in"),
        ({"dt": 0.0}, ValueError, "dt must be a number in"),
        ({"render_mode": "ascii"}, ValueError, "render_mode must be None or one of"),
        ({"num_distractors": 100}, ValueError, "num_distractors"),
        ({"goals": (Goal.smaller("distance", 1.0),)}, ValueError, "distance goals"),
        ({"speed": 2}, TypeError, "allowed: \\['scenario'"),
    ],
)
@pytest.mark.filterwarnings("ignore:.*render_mode='ascii'.*:UserWarning")  # gymnasium's own warning, before ours
def test_bad_keywords_raise_errors_listing_what_is_allowed(kwargs, error, message):
    with pytest.raises(error, match=message):
        gym.make("AttentiveRescue-v0", **kwargs)


def test_bad_reset_options():
    env = AttentiveRescueEnv()
    with pytest.raises(ValueError, match="unknown reset option"):
        env.reset(options={"target": 1})
    with pytest.raises(ValueError, match="distance goals"):
        env.reset(options={"goal": Goal.smaller("distance", 1.0)})


def test_a_refused_reset_leaves_the_episode_as_it_was():
    env = gym.make("AttentiveRescue-v0", scenario="exp01")
    env.reset(seed=0)
    goal, scenario = env.unwrapped.goal, env.unwrapped.scenario
    with pytest.raises(ValueError, match="bounds above 20"):
        env.reset(options={"goal": Goal.smaller("distance", 30.0)})
    assert env.unwrapped.goal == goal and env.unwrapped.scenario is scenario
    observation = env.step(np.zeros(2, np.float32))[0]
    assert env.observation_space.contains(observation)


@pytest.mark.parametrize("variant", ["raw", "focus", "oracle"])
def test_human_mode_draws_one_frame_per_step_with_that_steps_overlay(variant, monkeypatch):
    from attentive_gym.wrappers import make_env

    env = make_env(variant, render_mode="human")
    base = env.unwrapped
    frames = []
    original = type(base).render
    monkeypatch.setattr(type(base), "render", lambda self: frames.append(self.world.time_s) or original(self))
    env.reset(seed=0)
    for _ in range(3):
        env.step(np.zeros(2, np.float32))
    assert frames == pytest.approx([0.0, 0.05, 0.1, 0.15])
    env.close()


def test_public_space_and_robot_body():
    env = gym.make("AttentiveRescue-v0")
    env.reset(seed=0)
    world = env.unwrapped.world
    assert world.robot.body in world.space.bodies
    assert world.entities[ROBOT_ID].kind == "robot"


def test_render_rgb_array_draws_the_world():
    env = AttentiveRescueEnv(render_mode="rgb_array")
    env.reset(seed=0)
    frame = env.render()
    assert frame.dtype == np.uint8 and frame.ndim == 3 and frame.shape[2] == 3
    assert len(np.unique(frame.reshape(-1, 3), axis=0)) > 5  # walls, rubble, movers, beams
    assert env.metadata["render_fps"] == pytest.approx(20.0)
    env.close()


def test_render_human_is_headless_safe():
    env = AttentiveRescueEnv(render_mode="human", dt=0.1)
    env.reset(seed=0)
    env.step(np.zeros(2, np.float32))
    assert env.render() is None
    assert env.metadata["render_fps"] == pytest.approx(10.0)
    env.close()


def test_info_reports_the_worlds_state_bit_for_bit_with_its_types():
    """The info's robot and mover entries are what the world's public reads give, exactly, with
    the types and dtypes of the documented info (a crowded arena: contacts on the way)."""
    env = AttentiveRescueEnv(arena_size_m=7.0, num_distractors=4, rubble_per_100m2=15.0)
    _, info = env.reset(seed=3)
    rng = np.random.default_rng(3)
    touched = 0
    for _ in range(120):
        world = env.world
        np.testing.assert_array_equal(info["robot_pose"], world.robot.pose)
        np.testing.assert_array_equal(info["robot_velocity"], world.robot.odometry)
        np.testing.assert_array_equal(info["mover_positions"], world.mover_positions())
        np.testing.assert_array_equal(info["mover_velocities"], world.mover_velocities())
        assert info["time_s"] == world.time_s and info["mover_names"] == world.mover_names
        assert {key: type(value) for key, value in info.items()} == {
            **dict.fromkeys(("robot_pose", "robot_velocity", "mover_positions", "mover_velocities"), np.ndarray),
            **dict.fromkeys(("sonar_hits", "laser_hits"), np.ndarray),
            **dict.fromkeys(("time_s", "target_distance_m", "contact_s", "sonar_time_s", "laser_time_s"), float),
            "mover_names": tuple,
            "target_index": int,
            "collision": bool,
            "success": bool,
            "goal": str,
        }
        assert info["robot_pose"].dtype == info["robot_velocity"].dtype == np.float64
        _, _, terminated, truncated, info = env.step(np.array([rng.uniform(0.6, 1.0), rng.uniform(-0.3, 0.3)]))
        touched += info["collision"]
        if terminated or truncated:
            _, info = env.reset()
    assert touched >= 10


def test_contact_s_sums_the_episodes_collision_steps_and_its_limit_ends_the_episode():
    """``contact_s`` is dt times the episode's steps with a collision (0 after a reset); with
    ``contact_limit_s`` the episode terminates, without success, at the first step past it,
    and the same seed without a limit keeps going with the same trajectory up to there."""

    def run(reward):
        env = AttentiveRescueEnv(arena_size_m=7.0, num_distractors=4, rubble_per_100m2=15.0, reward=reward)
        _, info = env.reset(seed=3)
        assert info["contact_s"] == 0.0
        steps, rng = [], np.random.default_rng(3)
        for _ in range(400):
            _, _, terminated, truncated, info = env.step(np.array([1.0, rng.uniform(-0.3, 0.3)]))
            steps.append((info["collision"], info["contact_s"], terminated, info["success"], info["robot_pose"].copy()))
            if terminated or truncated:
                break
        return env.dt, steps

    dt, free = run({})
    assert all(c == pytest.approx(dt * sum(s[0] for s in free[: i + 1])) for i, (_, c, *_) in enumerate(free))
    assert free[-1][1] > 0.5, "the crowded arena must give contacts"
    _, limited = run({"contact_limit_s": 0.5})
    end = next(i for i, s in enumerate(free) if s[1] > 0.5 + 1e-9)
    assert len(limited) == end + 1 and limited[-1][2] and not limited[-1][3]
    assert not any(s[2] for s in limited[:-1])
    for a, b in zip(free[: end + 1], limited):
        np.testing.assert_array_equal(a[4], b[4])


@pytest.mark.parametrize("limit", [-1.0, math.inf, math.nan, "1"])
def test_a_bad_contact_limit_is_refused_naming_what_is_allowed(limit):
    with pytest.raises(ValueError, match=r"contact_limit_s must be None or a finite number >= 0"):
        AttentiveRescueEnv(reward={"contact_limit_s": limit})


def test_the_near_penalty_charges_the_clearance_below_near_m_and_nothing_above():
    """With ``near_per_s`` the reward drops by near_per_s · dt · max(0, 1 − clearance / near_m),
    the clearance being the robot's nearest sonar reading; the trajectory is unchanged."""
    kwargs = {"arena_size_m": 7.0, "num_distractors": 4, "rubble_per_100m2": 15.0}
    plain = AttentiveRescueEnv(**kwargs)
    near = AttentiveRescueEnv(**kwargs, reward={"near_per_s": 10.0, "near_m": 0.4})
    plain.reset(seed=3)
    near.reset(seed=3)
    rng = np.random.default_rng(3)
    charged = 0
    for _ in range(200):
        action = np.array([1.0, rng.uniform(-0.3, 0.3)])
        _, r_plain, *ends, _ = plain.step(action)
        _, r_near, *_ = near.step(action)
        clearance = near._reading.sonar.min()
        np.testing.assert_array_equal(near._reading.sonar, plain._reading.sonar)
        assert r_near == pytest.approx(r_plain - 10.0 * near.dt * max(0.0, 1.0 - clearance / 0.4), abs=1e-12)
        charged += clearance < 0.4
        if any(ends):
            break
    assert charged >= 5, "the crowded arena must bring the robot near something"


@pytest.mark.parametrize(("field", "value"), [("near_m", 0.0), ("near_per_s", -1.0)])
def test_a_bad_near_setting_is_refused(field, value):
    with pytest.raises(ValueError, match=f"RewardConfig.{field} must be"):
        AttentiveRescueEnv(reward={field: value})
