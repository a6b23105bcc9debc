"""The pymunk world: robot dynamics, collisions, scripted movers, overlap checks."""

import math
import pickle

import numpy as np
import pytest

from attentive_gym.world.behaviours import PathMotion
from attentive_gym.world.robot import RobotConfig
from attentive_gym.world.scenario import (
    BoxRubble,
    EvadeBehaviour,
    Leg,
    MoverSpec,
    PathBehaviour,
    Pose,
    PursueBehaviour,
    Scenario,
    WallSpec,
)
from attentive_gym.world.world import ROBOT_ID, World


def run(world, seconds, linear, angular, dt=0.05):
    collided = False
    for _ in range(int(round(seconds / dt))):
        collided |= world.step(dt, linear, angular)
    return collided


def open_world(**kwargs):
    return World(Scenario("open", (-20, -20, 20, 20), **kwargs))


def test_robot_reaches_commanded_speed_within_its_acceleration_limit():
    config = RobotConfig()
    world = open_world()
    run(world, 0.2, config.max_linear_mps, 0.0)
    speed_after_ramp = world.robot.odometry[0]
    assert speed_after_ramp == pytest.approx(0.2 * config.linear_accel_mps2, rel=0.05)
    run(world, 2.0, config.max_linear_mps, 0.0)
    assert world.robot.odometry[0] == pytest.approx(config.max_linear_mps, rel=1e-3)
    x, y, heading = world.robot.pose
    assert abs(y) < 1e-6 and abs(heading) < 1e-6 and x > 1.0


def test_commands_beyond_the_limits_are_clipped():
    config = RobotConfig()
    world = open_world()
    run(world, 3.0, 10.0, -50.0)
    linear, angular = world.robot.odometry
    assert abs(linear) == pytest.approx(config.max_linear_mps, rel=1e-3)
    assert angular == pytest.approx(-config.max_angular_rps, rel=1e-3)


def test_turning_in_place_rotates_without_translating():
    world = open_world()
    run(world, 1.0, 0.0, 1.0)
    x, y, heading = world.robot.pose
    assert math.hypot(x, y) < 1e-6
    assert heading > 0.5


def test_wall_stops_the_robot_at_full_speed_and_contact_is_reported():
    wall = WallSpec((1.5, -3.0), (1.5, 3.0), thickness_m=0.1)
    world = open_world(walls=(wall,))
    collided = run(world, 6.0, RobotConfig().max_linear_mps, 0.0)
    x = world.robot.pose[0]
    wall_face = 1.5 - 0.05
    assert collided
    assert x + RobotConfig().length_m / 2 <= wall_face + 0.02  # never through the wall
    assert x > wall_face - RobotConfig().length_m / 2 - 0.05  # it did reach the wall


def test_no_contact_in_free_space():
    world = open_world()
    assert not run(world, 2.0, 0.7, 0.5)


def test_path_mover_follows_its_legs_exactly_and_independently_of_the_step():
    behaviour = PathBehaviour(legs=(Leg((2.0, 0.0), 0.5, pause_s=0.4), Leg((2.0, 1.0), 0.25)), start_delay_s=0.3)
    mover = MoverSpec("m", "robot", Pose(0.0, 0.0), behaviour)
    positions = {}
    for dt in (0.01, 0.025, 0.05):
        world = open_world(movers=(mover,), robot=Pose(-10, -10))
        samples = []
        for k in range(int(round(10.0 / dt))):
            world.step(dt, 0.0, 0.0)
            if abs((k + 1) * dt * 20 - round((k + 1) * dt * 20)) < 1e-9:  # every 50 ms
                samples.append(world.mover_positions()[0].copy())
        positions[dt] = np.array(samples)
    expected = PathMotion(behaviour, (0.0, 0.0))
    times = 0.05 * np.arange(1, len(positions[0.05]) + 1)
    reference = np.array([expected.position(t) for t in times])
    for dt, got in positions.items():
        np.testing.assert_allclose(got, reference, atol=1e-9, err_msg=f"dt={dt}")
    # the closed form itself: start delay, first leg at 0.5 m/s, pause, second leg
    assert expected.position(0.3) == pytest.approx([0.0, 0.0])
    assert expected.position(0.3 + 2.0) == pytest.approx([1.0, 0.0])
    assert expected.position(0.3 + 4.0 + 0.4) == pytest.approx([2.0, 0.0])
    assert expected.position(0.3 + 4.4 + 2.0) == pytest.approx([2.0, 0.5])
    assert expected.position(100.0) == pytest.approx([2.0, 1.0])


def test_looping_path_repeats():
    behaviour = PathBehaviour(legs=(Leg((1.0, 0.0), 1.0),), loop=True)
    motion = PathMotion(behaviour, (0.0, 0.0))
    assert motion.position(0.5) == pytest.approx([0.5, 0.0])
    assert motion.position(1.5) == pytest.approx([0.5, 0.0])
    assert motion.position(2.25) == pytest.approx([0.25, 0.0])


def test_pursuer_approaches_and_stops_at_its_distance():
    mover = MoverSpec("p", "victim", Pose(4.0, 0.0), PursueBehaviour(0.5, stop_distance_m=1.5))
    world = open_world(movers=(mover,))
    run(world, 2.0, 0.0, 0.0)
    assert world.mover_positions()[0][0] == pytest.approx(3.0, abs=1e-6)
    run(world, 10.0, 0.0, 0.0)
    assert world.mover_positions()[0][0] == pytest.approx(1.5, abs=1e-6)


def test_evader_moves_away_and_stays_inside_bounds():
    mover = MoverSpec("e", "victim", Pose(2.0, 0.0), EvadeBehaviour(1.0))
    world = World(Scenario("box", (-5, -5, 5, 5), movers=(mover,)))
    run(world, 2.0, 0.0, 0.0)
    assert world.mover_positions()[0][0] == pytest.approx(4.0, abs=1e-6)
    run(world, 5.0, 0.0, 0.0)
    assert world.mover_positions()[0][0] == pytest.approx(5.0 - 0.25, abs=1e-6)


def test_an_enclosed_evader_stops_at_the_wall_s_inner_face():
    mover = MoverSpec("e", "victim", Pose(2.0, 0.0), EvadeBehaviour(1.0))
    world = World(Scenario("box", (-5, -5, 5, 5), enclosed=True, movers=(mover,)))
    run(world, 7.0, 0.0, 0.0)
    # the wall, 0.2 m thick, is centred on x = 5: its inner face is at 4.9
    assert world.mover_positions()[0][0] == pytest.approx(5.0 - 0.1 - 0.25, abs=1e-6)
    depths = [
        point.distance
        for hit in world.space.shape_query(world.movers[0].shape)
        for point in hit.contact_point_set.points
    ]
    assert all(depth > -1e-6 for depth in depths)


def test_the_clock_follows_a_changing_step_and_bad_steps_are_refused():
    world = open_world()
    world.step(0.05, 0.0, 0.0)
    world.step(0.1, 0.0, 0.0)
    assert world.time_s == pytest.approx(0.15)
    run(world, 1.0, 0.0, 0.0, dt=0.05)
    assert world.time_s == pytest.approx(1.15)
    for dt in (0.0, -0.05, math.nan, math.inf, "0.05"):
        with pytest.raises(ValueError, match="dt_s must be a finite number of seconds > 0"):
            world.step(dt, 0.0, 0.0)
    with pytest.raises(ValueError, match="robot commands must be finite"):
        world.step(0.05, math.nan, 0.0)
    assert np.isfinite(world.robot.pose).all() and world.time_s == pytest.approx(1.15)


def test_a_mover_stops_at_the_robot_instead_of_crushing_it_against_rubble():
    # a 2 m/s robot drives straight through the parked robot, which has rubble right behind it
    path = PathBehaviour(legs=(Leg((4.0, 0.0), 2.0),))
    mover = MoverSpec("m", "robot", Pose(-3.0, 0.0), path)
    world = open_world(movers=(mover,), rubble=(BoxRubble(0.6, 0.0, 0.3, 2.0),))
    start = world.robot.pose.copy()
    dt, max_robot_speed, mover_speeds = 0.1, 0.0, []
    for _ in range(30):
        world.step(dt, 0.0, 0.0)
        max_robot_speed = max(max_robot_speed, float(np.hypot(*world.robot.body.velocity)))
        mover_speeds.append(float(np.hypot(*world.mover_velocities()[0])))
    assert max_robot_speed < 0.05, "the mover pushed the robot"
    assert np.hypot(*(world.robot.pose[:2] - start[:2])) < 0.02
    stop_x = world.mover_positions()[0][0]
    assert -1.0 < stop_x < -0.2  # waiting in front of the robot, 3 s after it would have passed
    assert mover_speeds[-1] == 0.0
    # the robot leaves: the mover resumes where it stopped and never outruns its leg's speed
    world.robot.body.position = (-10.0, -10.0)
    arrival_s = None
    for _ in range(40):
        world.step(dt, 0.0, 0.0)
        mover_speeds.append(float(np.hypot(*world.mover_velocities()[0])))
        if arrival_s is None and world.mover_positions()[0][0] >= 4.0 - 1e-9:
            arrival_s = world.time_s
    assert max(mover_speeds) <= 2.0 + 1e-9
    assert world.mover_positions()[0] == pytest.approx([4.0, 0.0], abs=1e-9)
    # contact at ~1.2 s, release at 3.0 s: it waited ~1.8 s and arrives that much after 3.5 s
    waited_s = world.movers[0].script_delay_s
    assert 1.6 < waited_s < 2.1
    assert arrival_s == pytest.approx(3.5 + waited_s, abs=dt + 1e-9)


def test_a_pickled_world_keeps_stopping_movers_at_the_robot():
    path = PathBehaviour(legs=(Leg((4.0, 0.0), 2.0),))
    world = open_world(movers=(MoverSpec("m", "robot", Pose(-3.0, 0.0), path),))
    run(world, 1.0, 0.0, 0.0, dt=0.1)  # not yet touching
    copy = pickle.loads(pickle.dumps(world))
    for _ in range(20):
        world.step(0.1, 0.0, 0.0)
        copy.step(0.1, 0.0, 0.0)
        assert copy.mover_positions().tolist() == world.mover_positions().tolist()
        assert copy.robot.pose.tolist() == world.robot.pose.tolist()
    assert copy.movers[0].script_delay_s > 1.0 and np.hypot(*copy.robot.pose[:2]) < 0.02


def test_a_pickled_world_reports_contact_and_the_step_agrees_with_in_contact():
    wall = WallSpec((1.5, -3.0), (1.5, 3.0), thickness_m=0.1)
    world = open_world(walls=(wall,))
    run(world, 0.5, 0.7, 0.0)  # not yet touching
    copy = pickle.loads(pickle.dumps(world))
    reports = []
    for _ in range(160):  # one physics sub-step per env step: in_contact sees what the step saw
        collided = copy.step(copy.physics_dt_s, 0.7, 0.0)
        assert collided == copy.robot.in_contact()
        reports.append(collided)
        assert world.step(world.physics_dt_s, 0.7, 0.0) == collided
    assert not reports[0] and all(reports[-10:])


def test_overlapping_start_is_refused_with_names():
    with pytest.raises(ValueError, match="attentive robot starts overlapping rubble 0"):
        open_world(rubble=(BoxRubble(0.2, 0.0, 0.5, 0.5),))
    with pytest.raises(ValueError, match="'v'|v starts overlapping wall 0"):
        open_world(walls=(WallSpec((3, -1), (3, 1)),), movers=(MoverSpec("v", "victim", Pose(3.0, 0.0)),))


def test_entity_ids_and_public_space():
    scenario = Scenario(
        "ids",
        (-5, -5, 5, 5),
        enclosed=True,
        rubble=(BoxRubble(2, 2, 0.5, 0.5),),
        movers=(MoverSpec("a", "victim", Pose(-2, -2)), MoverSpec("b", "robot", Pose(-2, 2))),
    )
    world = World(scenario)
    kinds = [(e.id, e.kind) for e in world.entities]
    assert kinds[:3] == [(ROBOT_ID, "robot"), (1, "victim"), (2, "robot")]
    assert [k for _, k in kinds[3:]] == ["wall"] * 4 + ["rubble"]
    assert world.robot.body in world.space.bodies
    geometry = world.geometry()
    assert set(np.unique(geometry.segment_owner)) | set(np.unique(geometry.circle_owner)) == set(
        range(len(world.entities))
    )
