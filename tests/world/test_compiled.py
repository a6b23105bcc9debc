"""The compiled world step against the pure-Python one, bit for bit, and its batched entry point."""

import copy
import math
import os
import pickle
import subprocess
import sys
import warnings

import numpy as np
import pymunk
import pytest

from attentive_gym import _pymunk_access
from attentive_gym.attention.goals import Goal
from attentive_gym.world import ArenaConfig, World, builtin_scenario, compiled, generate_arena
from attentive_gym.world.builtin import BUILTIN_SCENARIOS
from attentive_gym.world.scenario import (
    BoxRubble,
    EvadeBehaviour,
    Leg,
    MoverSpec,
    PathBehaviour,
    Pose,
    PursueBehaviour,
    Scenario,
)

STEPS = 1500  # world-steps per scene and engine
DT_S = 0.05


@pytest.fixture
def engine():
    """``use(name)`` selects an engine for the test; the compiled one is restored after."""

    def use(name):
        assert compiled.select_engine(pure_python=name == "python") == name

    yield use
    assert compiled.select_engine() == "compiled"


def mixed_scene() -> Scenario:
    """An enclosed room with a pursuer, a late evader, a looping path with a pause that
    turns to face its motion, and a still robot."""
    movers = (
        MoverSpec("pursuer", "robot", Pose(3.0, 0.0), PursueBehaviour(0.6, stop_distance_m=0.3)),
        MoverSpec("evader", "victim", Pose(-2.0, 1.0), EvadeBehaviour(0.5, start_delay_s=0.5)),
        MoverSpec(
            "looper",
            "victim",
            Pose(0.0, -2.0),
            PathBehaviour((Leg((2.0, -2.0), 0.8, pause_s=0.3), Leg((0.0, 0.5), 0.9)), loop=True, face_motion=True),
        ),
        MoverSpec("still", "robot", Pose(-3.0, -3.0)),
    )
    return Scenario("mixed", (-5, -5, 5, 5), enclosed=True, movers=movers, rubble=(BoxRubble(3.5, 3.5, 0.5, 0.5),))


def scenes() -> dict[str, Scenario]:
    """Procedural arenas (patrolling, pursuing and evading targets), the built-in scenarios
    and the mixed room."""
    found = {}
    for seed in range(2):
        for goal in (None, Goal.direction_is("towards"), Goal.direction_is("away")):
            found[f"arena {seed} {goal}"] = generate_arena(ArenaConfig(), np.random.default_rng(seed), goal)
    found.update({name: builtin_scenario(name) for name in BUILTIN_SCENARIOS})
    found["mixed"] = mixed_scene()
    return found


def rough_drive(world: World, steps: int, seed: int) -> np.ndarray:
    """Drive the robot at random, then at the nearest mover, then straight ahead (60 steps
    each, repeating), with a longer step now and then; one row per step: touched, clock,
    robot pose, odometry and pymunk velocities, movers' positions, velocities, angles,
    blocked flags and schedule delays."""
    rng = np.random.default_rng(seed)
    rows = []
    for k in range(steps):
        phase = (k // 60) % 3
        linear, angular = rng.uniform(-1.0, 1.0), rng.uniform(-3.0, 3.0)
        if phase > 0:
            x, y, heading = world.robot.pose
            positions = world.mover_positions()
            linear, angular = 0.9, 0.0
            if len(positions) and phase == 1:
                offset = positions - (x, y)
                j = int(np.argmin((offset**2).sum(axis=1)))
                bearing = math.atan2(offset[j, 1], offset[j, 0]) - heading
                angular = 3.0 * math.atan2(math.sin(bearing), math.cos(bearing))
        touched = world.step(DT_S if k % 97 else 2 * DT_S, linear, angular)
        movers = world.movers
        rows.append(
            np.concatenate(
                [
                    [float(touched), world.time_s],
                    world.robot.pose,
                    world.robot.odometry,
                    world.robot.body.velocity,
                    [world.robot.body.angular_velocity],
                    world.mover_positions().ravel(),
                    world.mover_velocities().ravel(),
                    [m.body.angle for m in movers],
                    [float(m.blocked) for m in movers],
                    [m.script_delay_s for m in movers],
                ]
            )
        )
    return np.array(rows)


@pytest.mark.parametrize("name", list(scenes()))
def test_compiled_and_python_steps_agree_bit_for_bit(name, engine):
    scenario = scenes()[name]
    runs = {}
    for which in ("compiled", "python"):
        engine(which)
        runs[which] = rough_drive(World(scenario), STEPS, seed=len(name))
    np.testing.assert_array_equal(runs["compiled"], runs["python"])
    assert runs["compiled"][:, 0].mean() > 0.2, "the robot should be in contact often"


def test_contacts_blocked_movers_pursuit_and_evasion_happen_in_the_mixed_room(engine):
    for which in ("compiled", "python"):
        engine(which)
        world = World(mixed_scene())
        rows = rough_drive(world, STEPS, seed=3)
        blocked = rows[:, -8:-4]  # the four movers' blocked flags
        delays = rows[:, -4:]
        assert rows[:, 0].any() and blocked[:, 0].any(), "the pursuer never stopped at the robot"
        assert delays[-1, 2] > 0.0, "the looping path was never paused by the robot"
        speeds = np.hypot(rows[:, 18:26:2], rows[:, 19:26:2])  # the movers' speeds (m/s)
        assert speeds[:, 0].max() > 0.5 and speeds[:, 1].max() > 0.4 and speeds[:, 3].max() == 0.0


def test_step_worlds_equals_each_world_stepped_alone():
    names = ["mixed", "exp01", "arena 0 direction == away", "arena 1 None"]
    all_scenes = scenes()
    scenarios = [all_scenes[n] for n in names] + [Scenario("empty", (-5, -5, 5, 5))]
    physics_dt_s = [0.025, 0.01, 0.025, 0.04, 0.025]  # sub-steps differ between the worlds
    together = [World(s, physics_dt_s=h) for s, h in zip(scenarios, physics_dt_s)]
    alone = [World(s, physics_dt_s=h) for s, h in zip(scenarios, physics_dt_s)]
    rng = np.random.default_rng(7)
    touched_any = np.zeros(len(together), bool)
    for k in range(400):
        commands = rng.uniform([-1.0, -3.0], [1.0, 3.0], size=(len(together), 2))
        if k >= 50:  # then straight ahead, into whatever is there
            commands = np.array([[0.9, 0.0]] * len(together))
        dt = DT_S if k % 50 else 0.03
        touched = compiled.step_worlds(together, dt, commands)
        assert touched.dtype == np.bool_ and touched.shape == (len(together),)
        expected = [w.step(dt, *c) for w, c in zip(alone, commands.tolist())]
        assert touched.tolist() == expected
        touched_any |= touched
        for a, b in zip(together, alone):
            assert a.state.world.tobytes() == b.state.world.tobytes()
            assert a.state.movers.tobytes() == b.state.movers.tobytes()
    assert touched_any.sum() >= 3, "contacts should happen in the batch"


def world_snapshot(world: World) -> tuple:
    bodies = [world.robot.body, world.robot.control] + [m.body for m in world.movers]
    return (
        world.state.world.tobytes(),
        world.state.movers.tobytes(),
        [(tuple(b.position), b.angle, tuple(b.velocity), b.angular_velocity) for b in bodies],
    )


@pytest.mark.parametrize("which", compiled.ENGINES)
def test_a_bad_command_in_one_world_moves_no_world(which, engine):
    engine(which)
    worlds = [World(mixed_scene()) for _ in range(3)]
    compiled.step_worlds(worlds, DT_S, np.full((3, 2), 0.5))
    before = [world_snapshot(w) for w in worlds]
    commands = np.full((3, 2), 0.5)
    commands[2, 1] = math.nan
    with pytest.raises(ValueError, match=r"robot commands must be finite numbers.*angular nan rad/s for world 2"):
        compiled.step_worlds(worlds, DT_S, commands)
    with pytest.raises(ValueError, match=r"commands must have shape \(N, 2\).*N = 3.*got shape \(2, 2\)"):
        compiled.step_worlds(worlds, DT_S, commands[:2])
    with pytest.raises(ValueError, match="dt_s must be a finite number of seconds > 0"):
        compiled.step_worlds(worlds, math.inf, np.zeros((3, 2)))
    with pytest.raises(ValueError, match="worlds must be distinct"):
        compiled.step_worlds([worlds[0], worlds[1], worlds[0]], DT_S, np.zeros((3, 2)))
    assert [world_snapshot(w) for w in worlds] == before


def test_a_failing_probe_warns_once_and_the_python_step_gives_the_same_numbers(monkeypatch):
    reference = rough_drive(World(mixed_scene()), 300, seed=1)
    monkeypatch.setattr(pymunk, "version", "7.9.0")
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            assert compiled.select_engine() == "python"
        assert len(caught) == 1 and caught[0].category is RuntimeWarning
        assert "pymunk 7.9.0 is outside the tested range >=7.3,<7.4" in str(caught[0].message)
        assert compiled.engine() == "python"
        np.testing.assert_array_equal(rough_drive(World(mixed_scene()), 300, seed=1), reference)
    finally:
        monkeypatch.undo()
        assert compiled.select_engine() == "compiled"


def test_the_probe_passes_on_the_installed_pymunk():
    assert _pymunk_access.probe_batch_layout() is None


def test_the_environment_variable_forces_the_python_step():
    code = "from attentive_gym.world import compiled; print(compiled.engine())"
    env = {**os.environ, compiled.PURE_PYTHON_VARIABLE: "1"}
    result = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    assert result.stdout.strip() == "python" and "Warning" not in result.stderr


@pytest.mark.parametrize("duplicate", [lambda world: pickle.loads(pickle.dumps(world)), copy.deepcopy])
def test_a_copied_world_steps_its_own_bodies(duplicate, engine):
    world = World(mixed_scene())
    rough_drive(world, 100, seed=2)
    before = world_snapshot(world)
    runs = {}
    for which in ("compiled", "python"):
        engine(which)
        twin = duplicate(world)
        assert twin.kernel_row().tolist() != world.kernel_row().tolist()
        runs[which] = rough_drive(twin, 300, seed=5)
    np.testing.assert_array_equal(runs["compiled"], runs["python"])
    assert world_snapshot(world) == before


def test_moving_poses_are_the_geometry_cache_s_bodies_after_the_step():
    world = World(mixed_scene())
    rough_drive(world, 50, seed=4)
    bodies = world.geometry_cache.moving_bodies
    expected = [[*b.position, b.angle] for b in bodies]
    assert world.moving_poses().tolist() == expected
    from_pymunk = world.geometry_cache.update()
    geometry = world.geometry()
    for name in ("segments", "segment_owner", "circles", "circle_owner"):
        np.testing.assert_array_equal(getattr(geometry, name), getattr(from_pymunk, name))
