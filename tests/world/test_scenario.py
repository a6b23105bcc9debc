"""Scenario schema: validation, file round trips, and errors that name the problem."""

import json

import pytest
import yaml

from attentive_gym.attention.goals import Goal
from attentive_gym.world.builtin import BUILTIN_SCENARIOS, builtin_scenario
from attentive_gym.world.scenario import BoxRubble, Leg, MoverSpec, PathBehaviour, Pose, Scenario, TaskSpec
from attentive_gym.world.scenario_io import load_scenario, save_scenario, scenario_from_dict, scenario_to_dict

MINIMAL = {
    "name": "corridor",
    "bounds": [-5, -3, 5, 3],
    "enclosed": True,
    "robot": {"x_m": -4, "y_m": 0, "heading_deg": 0},
    "rubble": [{"kind": "box", "x_m": 1, "y_m": 1, "width_m": 0.5, "height_m": 0.4}],
    "movers": [
        {
            "name": "survivor",
            "kind": "victim",
            "start": {"x_m": 3, "y_m": 0},
            "behaviour": {"kind": "path", "loop": True, "legs": [{"to": [3, 2], "speed_mps": 0.7}]},
        }
    ],
    "task": {"target": "survivor", "goal": {"feature": "speed", "relation": "between", "lo": 0.5, "hi": 0.9}},
}


def test_minimal_dict_builds_the_expected_scenario():
    scenario = scenario_from_dict(MINIMAL)
    assert scenario.bounds == (-5.0, -3.0, 5.0, 3.0)
    assert scenario.rubble == (BoxRubble(1.0, 1.0, 0.5, 0.4),)
    mover = scenario.movers[0]
    assert mover.behaviour == PathBehaviour(legs=(Leg((3.0, 2.0), 0.7),), loop=True)
    assert scenario.task == TaskSpec("survivor", Goal.between("speed", 0.5, 0.9))
    assert scenario.target_index == 0


@pytest.mark.parametrize("name", sorted(BUILTIN_SCENARIOS))
@pytest.mark.parametrize("suffix", [".yaml", ".json"])
def test_file_round_trip_is_exact(tmp_path, name, suffix):
    scenario = builtin_scenario(name)
    path = save_scenario(scenario, tmp_path / f"{name}{suffix}")
    assert load_scenario(path) == scenario


def test_round_trip_keeps_tasks_and_goals(tmp_path):
    scenario = scenario_from_dict(MINIMAL)
    assert scenario_from_dict(scenario_to_dict(scenario)) == scenario
    path = tmp_path / "s.json"
    path.write_text(json.dumps(scenario_to_dict(scenario)))
    assert load_scenario(path) == scenario


def _mutated(path, value):
    data = json.loads(json.dumps(MINIMAL))
    *parents, last = path
    node = data
    for key in parents:
        node = node[key]
    if value is KeyError:
        del node[last]
    else:
        node[last] = value
    return data


@pytest.mark.parametrize(
    "path, value, message",
    [
        (("bounds",), KeyError, "missing key 'bounds'"),
        (("colour",), "red", "unknown key 'colour'"),
        (("bounds",), [0, 0, 1], "bounds"),
        (("bounds",), [5, 0, 1, 1], "x_min < x_max"),
        (("rubble", 0, "width_m"), -1, "box.width_m must be > 0"),
        (("rubble", 0, "width_m"), 0, "box.width_m must be > 0"),
        (("rubble", 0, "width_m"), "wide", "expected a number"),
        (("rubble", 0, "kind"), "triangle", "unknown 'triangle'; allowed: ['box', 'circle', 'segment']"),
        (("rubble", 0, "x_m"), 40, "outside bounds"),
        (("movers", 0, "kind"), "dog", "must be one of"),
        (("movers", 0, "behaviour", "legs", 0, "sped"), 1, "legs[0]: unknown key 'sped'"),
        (("movers", 0, "behaviour", "legs", 0, "to"), [30, 0], "outside bounds"),
        (("movers", 0, "behaviour", "legs", 0, "speed_mps"), 0, "leg.speed_mps must be > 0"),
        (("movers", 0, "behaviour", "legs"), [], "at least one leg"),
        (("task", "target"), "nobody", "task.target 'nobody' is not a mover"),
        (("task", "goal", "relation"), "about", "unknown goal relation 'about'"),
        (("task", "goal", "lo"), 2.0, "lo <= hi"),
        (("robot", "x_m"), float("nan"), "must be finite"),
        (("enclosed",), "yes", "expected true or false"),
    ],
)
def test_bad_data_names_the_problem(path, value, message):
    with pytest.raises(ValueError) as error:
        scenario_from_dict(_mutated(path, value))
    assert message in str(error.value)


def test_bad_file_errors_name_the_file(tmp_path):
    path = tmp_path / "broken.yaml"
    path.write_text("name: [unclosed")
    with pytest.raises(ValueError, match="broken.yaml is not valid YAML"):
        load_scenario(path)
    path.write_text(yaml.safe_dump({**MINIMAL, "movers": [{"name": "x"}]}))
    with pytest.raises(ValueError, match=r"broken.yaml: scenario.movers\[0\]: missing key 'kind'"):
        load_scenario(path)
    with pytest.raises(ValueError, match="must end in one of"):
        load_scenario(tmp_path / "scenario.txt")


def test_duplicate_mover_names_are_refused():
    mover = MoverSpec("a", "victim", Pose(0, 0))
    with pytest.raises(ValueError, match="names must be unique"):
        Scenario("dup", (-1, -1, 1, 1), movers=(mover, mover))


@pytest.mark.parametrize(
    ("build", "message"),
    [
        (lambda: Scenario("s", (0, 0, 5, 5), enclosed="false"), "scenario.enclosed must be true or false"),
        (lambda: Scenario("s", (0, 0, 5, 5), robot=(1, 1, 0)), "scenario.robot must be a Pose"),
        (lambda: Scenario("s", (0, 0, 5, 5), walls=[((0, 0), (5, 0))]), r"scenario.walls\[0\] must be a WallSpec"),
        (lambda: Scenario("s", (0, 0, 5, 5), rubble=[{"kind": "circle"}]), r"scenario.rubble\[0\] must be a BoxRubble"),
        (lambda: Scenario("s", (0, 0, 5, 5), movers="victim"), "scenario.movers must be a sequence"),
        (lambda: Scenario("s", (0, 0, 5, 5), task="reach v"), "scenario.task must be a TaskSpec or None"),
        (lambda: MoverSpec("v", "victim", Pose(1, 1), behaviour="pursue"), "behaviour must be a PathBehaviour"),
        (lambda: PathBehaviour(legs=[(1, 1)]), r"path.legs\[0\] must be a Leg"),
    ],
)
def test_scenarios_built_in_python_check_their_types(build, message):
    with pytest.raises(ValueError, match=message):
        build()


def test_numpy_numbers_become_floats_and_save_as_yaml(tmp_path):
    import numpy as np

    box = BoxRubble(np.float64(1.0), np.float32(2.0), np.int64(1), 0.5)
    leg = Leg((np.float64(2.0), 1.0), np.float64(0.5))
    assert type(box.x_m) is float and type(box.y_m) is float and type(box.width_m) is float
    assert type(leg.speed_mps) is float
    scenario = Scenario(
        "np",
        (0, 0, 5, 5),
        rubble=(box,),
        movers=(MoverSpec("v", "victim", Pose(1.0, 4.0), PathBehaviour(legs=(leg,))),),
    )
    path = save_scenario(scenario, tmp_path / "np.yaml")
    assert load_scenario(path) == scenario
