"""Fuzzing goals, map weights, attentive states and AttentionModel inputs.

Every case ends in a correct result (finite, non-negative M and L) or a clear
ValueError/TypeError raised by attentive_gym's validation that names the problem; an
input refused by ``step`` leaves the model unchanged.
"""

import math
import pickle

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
from reliability_helpers import assert_clear_error, outcome

from attentive_gym.attention import MAP_ALIASES, MAP_NAMES, AttentionConfig, AttentionModel, Goal
from attentive_gym.attention.config import MAX_MAP_WEIGHT
from attentive_gym.attention.goals import Feature, Relation

weird_floats = st.floats(allow_nan=True, allow_infinity=True)
bounds = st.one_of(weird_floats, st.none(), st.integers(-5, 5), st.sampled_from(["0.5", "x", True, [1.0]]))
features = st.sampled_from(["speed", "distance", "direction", "SPEED", Feature.SPEED, "velocity", "", None, 3])
relations = st.sampled_from(["equal", "between", "greater", "smaller", Relation.BETWEEN, "less", None, 1])
directions = st.sampled_from([None, "towards", "away", "static", "AWAY", 1, -1, 0, 5, "left", 0.5])


# --- goals --------------------------------------------------------------------------------
@settings(max_examples=400)
@given(features, relations, bounds, bounds, st.one_of(weird_floats, st.sampled_from([0.0, 0.1, "t", None])), directions)
def test_any_goal_is_valid_or_refused_naming_the_problem(feature, relation, lo, hi, tolerance, direction):
    goal, error = outcome(lambda: Goal(feature, relation, lo=lo, hi=hi, tolerance=tolerance, direction=direction))
    if error is not None:
        assert_clear_error(error, "feature", "relation", "bound", "lo", "hi", "tolerance", "direction")
        return
    assert isinstance(goal.feature, Feature) and isinstance(goal.relation, Relation)
    if goal.feature is Feature.DIRECTION:
        assert goal.relation is Relation.EQUAL and goal.lo is None and goal.direction is not None
    else:
        assert math.isfinite(goal.lo) and math.isfinite(goal.hi) and 0.0 <= goal.lo <= goal.hi
        assert math.isfinite(goal.tolerance) and goal.tolerance >= 0.0
    vector = goal.encode()
    if np.all(np.isfinite(vector)):  # bounds beyond float32 cannot round-trip
        decoded = Goal.decode(vector)
        assert decoded.feature is goal.feature and decoded.relation is goal.relation


@pytest.mark.parametrize(
    "make, names",
    [
        (lambda: Goal.between("velocity", 0.1, 0.2), ("goal feature", "velocity")),
        (lambda: Goal("speed", "less", lo=0.1), ("goal relation", "less")),
        (lambda: Goal.between("speed", 0.9, 0.5), ("lo <= hi",)),
        (lambda: Goal.between("speed", float("nan"), 0.5), ("bound lo", "finite")),
        (lambda: Goal.between("speed", 0.1, float("inf")), ("bound hi", "finite")),
        (lambda: Goal.greater("distance", -1.0), ("bound lo", ">= 0")),
        (lambda: Goal.equal("speed", 0.5, tolerance=-0.1), ("tolerance",)),
        (lambda: Goal.equal("speed", 0.5, tolerance=float("nan")), ("tolerance",)),
        (lambda: Goal("direction", "between", direction="towards"), ("direction goals only support relation",)),
        (lambda: Goal("direction", "equal"), ("direction goal needs direction",)),
        (lambda: Goal("direction", "equal", lo=1.0, direction="away"), ("no numeric bounds",)),
        (lambda: Goal("speed", "greater", lo=0.5, direction="away"), ("takes no direction",)),
        (lambda: Goal("speed", "greater", lo=0.5, hi=0.7), ("one bound",)),
        (lambda: Goal("speed", "greater", lo=0.5, tolerance=0.1), ("tolerance applies to equal goals only",)),
        (lambda: Goal("speed", "between", lo=0.5), ("needs both lo and hi",)),
        (lambda: Goal.direction_is("sideways"), ("unknown direction", "sideways")),
        (lambda: Goal.between("speed", "fast", 1.0), ("bound lo must be a number",)),
        (lambda: Goal.decode(["a"] * 13), ("goal encoding",)),
        (lambda: Goal.decode(np.zeros(12)), ("goal encoding",)),
        (lambda: Goal.decode(np.full(13, np.nan)), ("goal encoding",)),
    ],
)
def test_every_invalid_goal_combination_names_its_problem(make, names):
    _, error = outcome(make)
    assert error is not None
    assert_clear_error(error, *names)


@settings(max_examples=200)
@given(hnp.arrays(np.float64, st.sampled_from([13, 12, 14, 0]), elements=weird_floats))
def test_goal_decode_of_any_vector(vector):
    goal, error = outcome(lambda: Goal.decode(vector))
    if error is not None:
        assert_clear_error(error, "goal encoding")
    elif goal is not None:
        assert goal.feature is Feature.DIRECTION or (math.isfinite(goal.lo) and 0.0 <= goal.lo <= goal.hi)


# --- weights, goals and states on the model -------------------------------------------------
map_keys = st.sampled_from([*MAP_NAMES, *MAP_ALIASES, "f1", "MOTION", "F7", "F0", "speed", "", 1, None])
weight_values = st.one_of(weird_floats, st.integers(-2, 3), st.sampled_from([True, "1", None, [1.0], np.float32(0.5)]))


def _weight_ok(value) -> bool:
    import numbers

    return (
        not isinstance(value, bool)
        and isinstance(value, numbers.Real)
        and math.isfinite(value)
        and 0 <= value <= MAX_MAP_WEIGHT
    )


def _index(key):
    if not isinstance(key, str):
        return None
    name = MAP_ALIASES.get(key.lower(), key.upper())
    return MAP_NAMES.index(name) if name in MAP_NAMES else None


@settings(max_examples=400)
@given(
    st.one_of(
        st.dictionaries(map_keys, weight_values, max_size=7),
        st.lists(weight_values, max_size=8),
        st.sampled_from(["F1", 3, None, 2.0]),
    )
)
def test_any_weights_are_set_exactly_or_refused_naming_the_map(weights):
    model = AttentionModel()
    before = dict(model.weights)
    _, error = outcome(lambda: model.set_weights(weights))
    if isinstance(weights, dict):
        indices = [_index(k) for k in weights]
        valid = None not in indices and len(set(indices)) == len(indices) and all(map(_weight_ok, weights.values()))
    elif isinstance(weights, list):
        valid = len(weights) == 6 and all(map(_weight_ok, weights))
    else:
        valid = weights is None
    if valid:
        assert error is None, error
        if isinstance(weights, dict):
            expected = [0.0] * 6
            for key, value in weights.items():
                expected[_index(key)] = float(value)
            assert list(model.weights.values()) == expected
    else:
        assert error is not None, f"{weights!r} was accepted"
        assert_clear_error(error, "map", "weight", "F1", "F2", "F3", "F4", "F5", "F6")
        assert dict(model.weights) == before  # unchanged


@pytest.mark.parametrize("state", ["asleep", -1.0, 0.0, float("nan"), float("inf"), None, True, [1.0]])
def test_bad_attentive_states_are_refused(state):
    _, error = outcome(lambda: AttentionModel().set_state(state))
    assert_clear_error(error, "attentive state", "state")


@pytest.mark.parametrize("goals", [("speed > 1",), (None,), (Goal.smaller("speed", 1), Goal.greater("speed", 2))])
def test_bad_goal_sets_are_refused(goals):
    _, error = outcome(lambda: AttentionModel().set_goals(*goals))
    assert_clear_error(error, "goal")


# --- model inputs ---------------------------------------------------------------------------
reading = st.one_of(st.floats(0.0, 25.0), st.sampled_from([np.nan, np.inf, -np.inf, -0.5, 1e308, 0.0, 5.0, 20.0]))
time_moves = st.one_of(st.floats(1e-3, 0.5), st.sampled_from([0.0, -0.05, np.nan, np.inf, 1e-12, 1e-9, 1e6, "0.1"]))
odometries = st.one_of(
    st.none(),
    st.tuples(st.floats(-2, 2), st.floats(-3, 3)),
    st.tuples(weird_floats, weird_floats),
    st.sampled_from([(0.5,), (0.1, 0.2, 0.3), "ab", 3.0, [1e300, -1e300], np.array([0.3, 0.1]), {"v": 1, "w": 2}]),
)


@st.composite
def input_sequences(draw):
    steps = []
    for _ in range(draw(st.integers(3, 12))):
        sonar_len = draw(st.sampled_from([16, 16, 16, 8, 7, 17]))
        laser_len = draw(st.sampled_from([180, 180, 180, 179, 0]))
        base = draw(st.floats(0.2, 19.0))
        sonar = np.full(sonar_len, min(base, 5.0))
        laser = np.full(laser_len, base)
        for array in (sonar, laser):
            if array.size and draw(st.booleans()):
                array[draw(st.integers(0, array.size - 1))] = draw(reading)
        steps.append((draw(time_moves), sonar, laser, draw(odometries)))
    return steps


def _problems(t, last_t, sonar, laser, odometry) -> list[str]:
    """The names an error may mention (every problem of the step); empty for a valid step."""
    problems = []
    if isinstance(t, str) or not math.isfinite(t) or (last_t is not None and not t - last_t >= 1e-9):
        problems.append("t")
    if sonar.shape not in ((16,), (8,)) or not np.all(np.isfinite(sonar) & (sonar >= 0)):
        problems.append("sonar")
    if laser.shape != (180,) or not np.all(np.isfinite(laser) & (laser >= 0)):
        problems.append("laser")
    if odometry is not None:
        try:
            linear, angular = odometry
            if not (math.isfinite(float(linear)) and math.isfinite(float(angular))):
                problems.append("odometry")
            elif (
                not problems
                and last_t is not None
                and not (math.isfinite(float(linear) * (t - last_t)) and math.isfinite(float(angular) * (t - last_t)))
            ):
                problems.append("odometry")  # a finite rate over the gap overflows
        except (TypeError, ValueError):
            problems.append("odometry")
    return problems


_PROBE = (np.full(16, 2.5), np.full(180, 7.5), (0.2, 0.1))


@settings(max_examples=150)
@given(input_sequences(), st.sampled_from(["sonar", "laser"]), st.booleans())
def test_any_input_sequence_steps_or_raises_and_outputs_stay_finite(steps, grid, goals):
    model = AttentionModel(AttentionConfig(grid=grid))
    if goals:
        model.set_goals(Goal.between("speed", 0.2, 0.9), Goal.smaller("distance", 3.0), Goal.direction_is("towards"))
    t = 0.0
    last_t = None
    for move, sonar, laser, odometry in steps:
        t_now = move if isinstance(move, str) else t + move
        problems = _problems(t_now, last_t, sonar, laser, odometry)
        snapshot = pickle.dumps(model) if problems else None
        output, error = outcome(lambda: model.step(t_now, sonar, laser, odometry))  # noqa: B023 (called at once)
        if not problems:
            assert error is None, f"valid step refused: {error!r}"
            for name in ("F", "C", "M", "L", "speeds_mps", "distances_m"):
                values = getattr(output, name)
                assert np.all(np.isfinite(values)), f"{name} not finite"
            assert np.all(output.M >= 0) and np.all(output.L >= 0)
            t, last_t = t_now, t_now
        else:
            assert error is not None, f"invalid step accepted (expected an error about {problems})"
            assert_clear_error(error, *problems)
            # the refused step left no trace: the model continues exactly as a copy taken before it
            probe_t = (last_t or 0.0) + 0.05
            assert pickle.loads(pickle.dumps(model)).step(probe_t, *_PROBE) == pickle.loads(snapshot).step(
                probe_t, *_PROBE
            )


def test_time_steps_below_a_nanosecond_are_refused_instead_of_dividing_by_zero():
    model = AttentionModel()
    model.step(5e-324, np.full(16, 3.0), np.full(180, 8.0))
    _, error = outcome(lambda: model.step(1e-323, np.full(16, 3.0), np.full(180, 8.0)))
    assert_clear_error(error, "t must increase")


def test_far_future_times_and_huge_odometry_stay_finite():
    model = AttentionModel()
    model.set_goals(Goal.between("speed", 0.5, 0.9))
    rng = np.random.default_rng(0)
    for k in range(30):
        out = model.step(1e300 * (k + 1), rng.uniform(0.2, 5, 16), rng.uniform(0.1, 20, 180), (1e3, -1e3))
        assert np.all(np.isfinite(out.M)) and np.all(np.isfinite(out.L)) and np.all(out.L >= 0)


def test_odometry_that_overflows_over_the_gap_is_refused_naming_odometry():
    model = AttentionModel()
    model.step(1.0, np.full(16, 3.0), np.full(180, 8.0))
    _, error = outcome(lambda: model.step(1e300, np.full(16, 3.0), np.full(180, 8.0), (1e300, -1e300)))
    assert_clear_error(error, "odometry")
    assert np.all(np.isfinite(model.step(2.0, np.full(16, 3.0), np.full(180, 8.0), (0.5, 0.1)).L))
