"""Fuzzing AttentiveRescue-v0: actions, keyword arguments and reset options.

Every case ends in a correct result (finite observation inside the space) or a clear
ValueError/TypeError raised by attentive_gym's own validation that names the problem.
"""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
from reliability_helpers import assert_clear_error, assert_finite_observation, outcome

from attentive_gym.attention.goals import GOAL_ENCODING_SIZE, Goal
from attentive_gym.envs.rescue_env import AttentiveRescueEnv

_ENV = AttentiveRescueEnv()
_ENV.reset(seed=0)

weird_floats = st.floats(allow_nan=True, allow_infinity=True, width=64)
scalars = st.one_of(
    weird_floats,
    st.integers(-(2**70), 2**70),
    st.booleans(),
    st.none(),
    st.text(max_size=3),
    st.complex_numbers(max_magnitude=10),
)
actions = st.one_of(
    hnp.arrays(st.sampled_from([np.float32, np.float64]), 2, elements=st.floats(width=32)),
    hnp.arrays(np.float16, 2, elements=st.floats(width=16)),
    hnp.arrays(
        st.sampled_from([np.float32, np.float64, np.int64, np.int8, np.bool_]),
        hnp.array_shapes(min_dims=0, max_dims=3, max_side=3),
    ),
    st.lists(scalars, max_size=4),
    st.tuples(weird_floats, weird_floats),
    scalars,
    st.dictionaries(st.text(max_size=2), weird_floats, max_size=2),
)


def _expected_valid(action) -> bool:
    if np.iscomplexobj(action):
        return False
    try:
        array = np.asarray(action, dtype=np.float64)
    except (TypeError, ValueError):
        return False
    return array.shape == (2,) and bool(np.all(np.isfinite(array)))


@settings(max_examples=300)
@given(actions)
def test_any_action_steps_or_raises_a_clear_error(action):
    state = _ENV.world.robot.pose.copy(), _ENV.world.time_s
    result, error = outcome(lambda: _ENV.step(action))
    if _expected_valid(action):
        assert error is None, f"valid action {action!r} raised {error!r}"
        obs, reward, terminated, truncated, info = result
        assert_finite_observation(_ENV, obs)
        assert math.isfinite(reward) and np.all(np.isfinite(info["robot_pose"]))
        if terminated or truncated:
            _ENV.reset(seed=1)
    else:
        assert error is not None, f"invalid action {action!r} was accepted"
        assert_clear_error(error, "action")
        assert np.array_equal(_ENV.world.robot.pose, state[0]) and _ENV.world.time_s == state[1]  # no effect


# --- keyword arguments ------------------------------------------------------------------
KWARG_VALUES = {
    "sensor_noise": st.one_of(
        weird_floats, st.sampled_from([0.0, 0.5, 0.51, -0.1, "0.1", None, True, np.float32(0.2)])
    ),
    "dt": st.one_of(weird_floats, st.sampled_from([0.5, 0.51, 0.0, 1e-3, "0.05", None, np.float64(0.1)])),
    "arena_size_m": st.one_of(
        weird_floats,
        st.sampled_from(
            [4.0, 3.9, (10, 6), (10,), (10, 10, 10), None, "big", [8.0, 8.0], (np.float32(9.0), 9), (3, 100)]
        ),
    ),
    "num_distractors": st.one_of(st.integers(-3, 25), st.sampled_from([2.0, True, None, "3", np.int64(2)])),
    "rubble_per_100m2": st.one_of(weird_floats, st.sampled_from([0, 51, 1e12, "x", None, True])),
    "max_mover_speed_mps": st.one_of(weird_floats, st.sampled_from([0.3, 20.0, 20.1, 1e300, "fast", None])),
    "time_limit_s": st.one_of(weird_floats, st.sampled_from([None, 1e-3, 1e7, "10", True])),
    "goals": st.sampled_from(
        [
            None,
            (),
            5,
            "speed",
            Goal.between("speed", 0.5, 0.9),
            [Goal.smaller("speed", 0.3)],
            (Goal.smaller("distance", 1.0),),
            (Goal.greater("speed", 19.0),),
            ("speed > 1",),
            (Goal.direction_is("away"),),
        ]
    ),
    "scenario": st.sampled_from(["rescue", "exp01", "exp09", "", None, 3, ["exp01"], "nothere.yaml", "x.txt"]),
    "render_mode": st.sampled_from([None, "rgb_array", "ascii", ["human"], 1]),
    "robot": st.sampled_from([{}, None, "p2at"]),
}
#: the name(s) an error about each keyword must mention
KWARG_NAMES = {
    "arena_size_m": ("arena_size_m", "width_m", "height_m", "arena must be", "rubble", "place mover"),
    "rubble_per_100m2": ("rubble_per_100m2", "rubble"),
    "num_distractors": ("num_distractors", "place mover", "distractor"),
    "max_mover_speed_mps": ("max_mover_speed_mps", "task goal", "distractor_speed_range_mps"),
    "goals": ("goals", "goal"),
}


@settings(max_examples=250)
@given(
    st.sets(st.sampled_from(sorted(KWARG_VALUES)), min_size=1, max_size=3).flatmap(
        lambda keys: st.fixed_dictionaries({k: KWARG_VALUES[k] for k in sorted(keys)})
    )
)
def test_any_keyword_arguments_build_a_working_env_or_raise_a_clear_error(kwargs):
    def make_and_run():
        env = AttentiveRescueEnv(**kwargs)
        obs, _ = env.reset(seed=0)
        assert_finite_observation(env, obs)
        for _ in range(3):
            obs, reward, *_ = env.step(env.action_space.sample())
            assert_finite_observation(env, obs)
            assert math.isfinite(reward)
        return env

    _, error = outcome(make_and_run)
    if error is not None:
        names = [n for key in kwargs for n in KWARG_NAMES.get(key, (key,))] + ["goal"]
        assert_clear_error(error, *names)


def test_unknown_keyword_names_it():
    _, error = outcome(lambda: AttentiveRescueEnv(arena_size=10))
    assert_clear_error(error, "arena_size")


@pytest.mark.parametrize(
    "kwargs, names",
    [
        ({"arena_size_m": (10, 10, 10)}, ("arena_size_m",)),
        ({"arena_size_m": None}, ("arena_size_m",)),
        ({"max_mover_speed_mps": "fast"}, ("max_mover_speed_mps",)),
        ({"max_mover_speed_mps": 1e300}, ("max_mover_speed_mps",)),
        ({"goals": 5}, ("goals",)),
        ({"goals": Goal.between("speed", 0.5, 0.9)}, ("goals",)),
        ({"rubble_per_100m2": 1000.0}, ("rubble_per_100m2",)),
        ({"arena_size_m": 1e4}, ("rubble",)),
        ({"num_distractors": True}, ("num_distractors",)),
    ],
)
def test_keyword_bugs_found_by_fuzzing_now_raise_clear_errors(kwargs, names):
    _, error = outcome(lambda: AttentiveRescueEnv(**kwargs).reset(seed=0))
    assert_clear_error(error, *names)


def test_infeasible_arena_raises_value_error_not_runtime_error():
    _, error = outcome(lambda: AttentiveRescueEnv(arena_size_m=4.0, num_distractors=20).reset(seed=0))
    assert_clear_error(error, "place mover")


def test_numpy_scalars_are_accepted_as_numbers():
    env = AttentiveRescueEnv(
        sensor_noise=np.float32(0.1), dt=np.float64(0.1), num_distractors=np.int64(2), arena_size_m=np.float32(9.0)
    )
    obs, _ = env.reset(seed=0)
    assert_finite_observation(env, obs)


# --- reset options ------------------------------------------------------------------------
goal_options = st.one_of(
    st.none(),
    hnp.arrays(np.float64, GOAL_ENCODING_SIZE, elements=weird_floats),
    hnp.arrays(np.float32, st.integers(0, 20), elements=st.floats(0, 30, width=32)),
    st.lists(st.one_of(st.floats(0, 2), st.text(max_size=1)), min_size=GOAL_ENCODING_SIZE, max_size=GOAL_ENCODING_SIZE),
    st.sampled_from(
        [
            Goal.between("speed", 0.5, 0.9),
            Goal.smaller("speed", 0.3),
            Goal.direction_is("towards"),
            Goal.smaller("distance", 2.0),
            Goal.greater("speed", 25.0),
            "speed",
            3,
        ]
    ),
)


@settings(max_examples=150)
@given(goal_options, st.sampled_from(["rescue", "exp04"]), st.booleans())
def test_any_reset_goal_works_or_raises_a_clear_error(goal, scenario, extra_key):
    env = AttentiveRescueEnv(scenario)
    options = {"goal": goal, **({"target": 1} if extra_key else {})}
    result, error = outcome(lambda: env.reset(seed=0, options=options))
    if error is None:
        obs, info = result
        assert_finite_observation(env, obs)
        assert_finite_observation(env, env.step(np.zeros(2, np.float32))[0])
    else:
        assert_clear_error(error, "goal", "option", "encoding", "task goal")
