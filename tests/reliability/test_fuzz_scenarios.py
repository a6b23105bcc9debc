"""Fuzzing scenario data and files: mutated dicts, bad YAML/JSON, impossible geometry.

Every case ends in a Scenario that builds a working env (finite observations) or a clear
ValueError/TypeError raised by attentive_gym's validation that names the problem.
"""

import copy
import json

import numpy as np
import pytest
import yaml
from hypothesis import given, settings
from hypothesis import strategies as st
from reliability_helpers import assert_clear_error, assert_finite_observation, outcome

from attentive_gym.envs.rescue_env import AttentiveRescueEnv
from attentive_gym.world.scenario_io import load_scenario, scenario_from_dict, scenario_to_dict
from attentive_gym.world.world import World

BASE = {
    "name": "fuzz",
    "bounds": [-5, -3, 5, 3],
    "enclosed": True,
    "robot": {"x_m": -4, "y_m": 0, "heading_deg": 0},
    "walls": [{"start": [0, -2], "end": [0, -1], "thickness_m": 0.2}],
    "rubble": [
        {"kind": "box", "x_m": 1, "y_m": 1, "width_m": 0.5, "height_m": 0.4},
        {"kind": "circle", "x_m": -2, "y_m": 2, "radius_m": 0.3},
        {"kind": "segment", "start": [2, -2], "end": [3, -2], "radius_m": 0.05},
    ],
    "movers": [
        {
            "name": "survivor",
            "kind": "victim",
            "start": {"x_m": 3, "y_m": 0},
            "behaviour": {"kind": "path", "loop": True, "legs": [{"to": [3, 2], "speed_mps": 0.7}]},
        },
        {
            "name": "bot",
            "kind": "robot",
            "start": {"x_m": -1, "y_m": 0},
            "behaviour": {"kind": "pursue", "speed_mps": 0.5},
        },
    ],
    "task": {"target": "survivor", "goal": {"feature": "speed", "relation": "between", "lo": 0.5, "hi": 0.9}},
}

junk = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(-10, 10),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=4),
    st.lists(st.integers(-3, 3), max_size=3),
    st.just({}),
    st.just({"kind": ["box"]}),
    st.just([[1, 2], [3]]),
    st.just({1: 2, "a": 3}),
    st.sampled_from([0.0, -1.0, 1e300, -0.0, 100.0]),
)


def _paths(data, prefix=()):
    """Every (path to a value) in nested dicts and lists."""
    yield prefix
    if isinstance(data, dict):
        for key, value in data.items():
            yield from _paths(value, prefix + (key,))
    elif isinstance(data, list):
        for i, value in enumerate(data):
            yield from _paths(value, prefix + (i,))


PATHS = [p for p in _paths(BASE) if p]


def _mutate(data, path, action, value):
    data = copy.deepcopy(data)
    parent = data
    for key in path[:-1]:
        parent = parent[key]
    last = path[-1]
    if action == "delete":
        del parent[last]
    elif action == "replace":
        parent[last] = value
    elif action == "unknown_key" and isinstance(parent, dict):
        parent[f"extra_{last}"] = value
    else:
        parent[last] = value
    return data


def _check_builds_or_refuses(data):
    def build_and_run():
        scenario = scenario_from_dict(data)
        env = AttentiveRescueEnv(scenario)
        obs, _ = env.reset(seed=0)
        assert_finite_observation(env, obs)
        for _ in range(5):
            obs, reward, *_ = env.step(np.array([1.0, 0.3], np.float32))
            assert_finite_observation(env, obs)
        return scenario

    scenario, error = outcome(build_and_run)
    if error is not None:
        assert_clear_error(
            error,
            "scenario",
            "mover",
            "wall",
            "rubble",
            "task",
            "goal",
            "box",
            "circle",
            "segment",
            "leg",
            "path",
            "pursue",
            "evade",
            "pose",
            "bound",
            "overlap",
        )
    return scenario, error


@settings(max_examples=300)
@given(st.sampled_from(PATHS), st.sampled_from(["delete", "replace", "unknown_key"]), junk)
def test_mutated_scenario_dicts_build_or_name_the_problem(path, action, value):
    data = _mutate(BASE, path, action, value)
    _check_builds_or_refuses(data)


@settings(max_examples=100)
@given(
    st.lists(st.tuples(st.sampled_from(PATHS), st.sampled_from(["delete", "replace"]), junk), min_size=2, max_size=4)
)
def test_several_mutations_at_once(mutations):
    data = BASE
    for path, action, value in mutations:
        try:
            data = _mutate(data, path, action, value)
        except (KeyError, IndexError, TypeError):
            continue  # an earlier mutation removed this place
    _check_builds_or_refuses(data)


geometry = st.fixed_dictionaries(
    {
        "x": st.floats(-6, 6),
        "y": st.floats(-4, 4),
        "size": st.one_of(st.floats(-0.5, 3.0), st.sampled_from([0.0, 1e-9, 1e6])),
        "kind": st.sampled_from(["box", "circle", "segment", "wall", "victim", "robot"]),
    }
)


@settings(max_examples=200)
@given(st.lists(geometry, min_size=1, max_size=4))
def test_overlapping_out_of_arena_and_degenerate_bodies(bodies):
    data = copy.deepcopy(BASE)
    for i, b in enumerate(bodies):
        x, y, size = b["x"], b["y"], b["size"]
        if b["kind"] == "box":
            data["rubble"].append({"kind": "box", "x_m": x, "y_m": y, "width_m": size, "height_m": size})
        elif b["kind"] == "circle":
            data["rubble"].append({"kind": "circle", "x_m": x, "y_m": y, "radius_m": size})
        elif b["kind"] == "segment":
            data["rubble"].append({"kind": "segment", "start": [x, y], "end": [x + size, y], "radius_m": 0.05})
        elif b["kind"] == "wall":
            data["walls"].append({"start": [x, y], "end": [x, y + size], "thickness_m": 0.2})
        else:
            data["movers"].append(
                {
                    "name": f"m{i}",
                    "kind": b["kind"],
                    "start": {"x_m": x, "y_m": y},
                    "radius_m": size,
                    "length_m": size,
                    "width_m": size,
                }
            )
    scenario, error = _check_builds_or_refuses(data)
    if scenario is not None:  # whatever was accepted really is a valid world
        world = World(scenario)
        assert np.all(np.isfinite(world.mover_positions()))


@pytest.mark.parametrize(
    "text, names",
    [
        ("name: [unclosed", ("not valid yaml",)),
        ("- just\n- a list\n", ("expected a mapping",)),
        ("", ("expected a mapping",)),
        ("name: x\nbounds: [0, 0, 1]\n", ("bounds",)),
        ("name: x\nbounds: [0, 0, 10, 10]\n1: 2\nfoo: 3\n", ("unknown key",)),
        ("name: x\nbounds: [0, 0, 10, 10]\nrubble: [{kind: [box]}]\n", ("kind",)),
        ("name: x\nbounds: [0, 0, 10, 10]\nrubble: [{kind: {a: 1}}]\n", ("kind",)),
        (
            "name: x\nbounds: [0, 0, 10, 10]\nmovers: [{name: a, kind: victim, start: {x_m: 1, y_m: 1}, "
            "behaviour: {kind: [path]}}]\n",
            ("kind",),
        ),
        ("name: x\nbounds: [0, 0, .nan, 10]\n", ("bounds",)),
        ("name: 2020-01-01\nbounds: [0, 0, 10, 10]\n", ("name",)),
        ("name: x\nbounds: [0, 0, 10, 10]\ntask: {target: a, goal: {feature: speed, 7: 1}}\n", ("unknown key",)),
        (
            "name: x\nbounds: [0, 0, 10, 10]\nrobot: {x_m: 5, y_m: 5}\nrubble: [{kind: circle, x_m: 5, y_m: 5, "
            "radius_m: 1}]\n",
            ("overlapping",),
        ),
        ("name: x\nbounds: [0, 0, 10, 10]\nenclosed: true\nrobot: {x_m: 0.1, y_m: 5}\n", ("overlapping",)),
        (
            "name: x\nbounds: [0, 0, 10, 10]\nrubble: [{kind: box, x_m: 11, y_m: 5, width_m: 1, height_m: 1}]\n",
            ("outside bounds",),
        ),
        (
            "name: x\nbounds: [0, 0, 10, 10]\nrubble: [{kind: box, x_m: 1, y_m: 5, width_m: 0, height_m: 1}]\n",
            ("width_m",),
        ),
    ],
)
def test_bad_yaml_files_name_the_problem(tmp_path, text, names):
    path = tmp_path / "s.yaml"
    path.write_text(text, encoding="utf-8")
    _, error = outcome(lambda: AttentiveRescueEnv(path).reset(seed=0))
    assert_clear_error(error, *names)


@pytest.mark.parametrize(
    "content, suffix",
    [
        (b"\xff\xfe\x00name", ".yaml"),
        (b'{"name": NaN}', ".json"),
        (b'{"name": "x", "bounds": [0, 0, 1e999, 5]}', ".json"),
    ],
)
def test_undecodable_and_non_finite_files(tmp_path, content, suffix):
    path = tmp_path / f"s{suffix}"
    path.write_bytes(content)
    _, error = outcome(lambda: load_scenario(path))
    assert_clear_error(error, str(path), "bounds", "name")


@settings(max_examples=60)
@given(st.sampled_from(PATHS), junk)
def test_round_trip_of_accepted_scenarios(path, value):
    data = _mutate(BASE, path, "replace", value)
    scenario, error = outcome(lambda: scenario_from_dict(data))
    if error is None:
        again = scenario_from_dict(json.loads(json.dumps(scenario_to_dict(scenario))))
        assert again == scenario
        assert scenario_from_dict(yaml.safe_load(yaml.safe_dump(scenario_to_dict(scenario)))) == scenario
