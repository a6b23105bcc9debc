"""``attentive_gym.perception.bound``: the model fed the simulator's true kinematics."""

from __future__ import annotations

import math

import numpy as np
import pytest

from attentive_gym.attention import AttentionConfig, AttentionModel, Goal
from attentive_gym.attention.regions import laser_bearings_rad
from attentive_gym.perception import PERCEPTION_ARENA, focus_on_target, record_episode, stand_still
from attentive_gym.perception.bound import (
    SEEN_BEAMS,
    PerfectPerceptionModel,
    TrueScene,
    make_bound_env,
    true_kinematics,
)
from attentive_gym.perception.geometry import in_view, region_of, to_robot_frame

BEARINGS = laser_bearings_rad()
FAST, SLOW = Goal.between("speed", 0.5, 0.9), Goal.between("speed", 0.15, 0.45)


def _beams_at(bearing_deg: float, count: int) -> np.ndarray:
    """``count`` neighbouring beams around ``bearing_deg`` (robot frame)."""
    centre = int(np.argmin(np.abs(BEARINGS - math.radians(bearing_deg))))
    return np.arange(centre - count // 2, centre - count // 2 + count)


def _scene(movers, pose=(0.0, 0.0, 0.0)) -> TrueScene:
    """A scene of ``movers``: (id, robot-frame bearing deg, range m, world velocity, beams hit)."""
    hits = np.full(180, -1, np.int64)
    x, y, heading = pose
    xy, velocity = [], []
    for mover_id, bearing_deg, range_m, v, beams in movers:
        angle = heading + math.radians(bearing_deg)
        xy.append((x + range_m * math.cos(angle), y + range_m * math.sin(angle)))
        velocity.append(v)
        if beams:
            hits[_beams_at(bearing_deg, beams)] = mover_id
    ids = np.array([m[0] for m in movers], np.int64)
    return TrueScene(np.array(pose, float), hits, ids, np.array(xy, float), np.array(velocity, float))


def _kinematics(scene: TrueScene, goal: Goal | None = None, probability: np.ndarray | None = None, **fields):
    """``true_kinematics`` of ``scene`` with the constants of a model of ``AttentionConfig(**fields)``
    and ``goal``'s wanted speeds (the speed goal's judgements into ``probability`` ``(8,)``)."""
    model = PerfectPerceptionModel(AttentionConfig(**fields))
    model.set_goals() if goal is None else model.set_goals(goal)
    rates, speeds = np.zeros(188), np.zeros(188)
    moving, region_mover = np.zeros(188, np.bool_), np.zeros(8, np.int64)
    seen = true_kinematics(
        0.5,
        scene,
        model.tracker.constants,
        model._wanted_speed,
        np.zeros(188),
        np.zeros(188, np.bool_),
        rates,
        speeds,
        moving,
        region_mover,
        np.empty(8) if probability is None else probability,
    )
    return seen, rates, speeds, moving, region_mover


def _region(bearing_deg: float, range_m: float = 3.0) -> int:
    angle = math.radians(bearing_deg)
    return int(region_of(np.array([range_m * math.cos(angle), range_m * math.sin(angle)])))


def test_a_mover_on_two_beams_gets_its_true_kinematics_on_its_beams_and_its_region():
    # the robot at (1, 2) facing +y: a mover 10° to its left walking away at 0.4 m/s and
    # across at 0.3 m/s, one on a single beam, one hidden from the laser
    pose = (1.0, 2.0, math.pi / 2)
    sight = np.array([math.cos(math.radians(100.0)), math.sin(math.radians(100.0))])  # its line of sight, world
    across = np.array([-sight[1], sight[0]])
    scene = _scene(
        [
            (11, 10.0, 3.0, tuple(0.4 * sight + 0.3 * across), 4),
            (12, -50.0, 2.0, (0.0, 0.7), 1),
            (13, 50.0, 2.0, (0.0, 0.8), 0),
        ],
        pose,
    )
    seen, rates, speeds, moving, region_mover = _kinematics(scene)
    assert seen.tolist() == [True, False, False] and SEEN_BEAMS == 2
    beams = 8 + _beams_at(10.0, 4)
    assert speeds[beams] == pytest.approx(0.5) and moving[beams].all()
    assert rates[beams] == pytest.approx(0.4)  # its ground velocity along the line of sight, + away
    ahead = _region(10.0)
    assert speeds[ahead] == pytest.approx(0.5) and rates[ahead] == pytest.approx(0.4) and moving[ahead]
    assert region_mover[ahead] == 0
    # the mover on one beam and the hidden one get nothing, nor does anything else
    others = np.ones(188, bool)
    others[beams] = others[ahead] = False
    assert not speeds[others].any() and not rates[others].any() and not moving[others].any()
    assert region_mover[_region(-50.0)] == region_mover[_region(50.0)] == -1


def test_a_region_takes_the_mover_the_goal_wants_else_the_fastest():
    # two seen movers in the region 10° left: 0.9 m/s and 0.3 m/s
    scene = _scene([(21, 6.0, 3.0, (0.0, 0.9), 3), (22, 14.0, 3.5, (0.0, 0.3), 3)])
    ahead = _region(10.0)
    assert _region(6.0) == _region(14.0) == ahead
    for goal, speed, row in ((SLOW, 0.3, 1), (FAST, 0.9, 0), (None, 0.9, 0)):
        _, _, speeds, _, region_mover = _kinematics(scene, goal)
        assert speeds[ahead] == pytest.approx(speed) and region_mover[ahead] == row
    # a standing body is not moving; speeds are clipped to the model's maximum
    _, _, speeds, moving, _ = _kinematics(_scene([(31, 10.0, 3.0, (0.0, 0.0), 3), (32, 50.0, 3.0, (5.0, 0.0), 3)]))
    assert speeds[ahead] == 0.0 and not moving[ahead]
    assert speeds[_region(50.0)] == AttentionConfig().max_speed_mps and moving[_region(50.0)]


def test_the_truth_judges_a_speed_goal_surely_where_the_model_judges_by_probability():
    scene = _scene([(21, 6.0, 3.0, (0.0, 0.8), 3), (22, 14.0, 3.5, (0.0, 0.3), 3)])
    ahead = _region(10.0)
    for goal, row in ((SLOW, 1), (FAST, 0), (Goal.between("speed", 0.4, 0.6), 0)):
        probability = np.zeros(8)
        _, _, _, _, region_mover = _kinematics(scene, goal, probability, track_speed_goal_probability=True)
        wanted = goal.is_fulfilled(0.3) or goal.is_fulfilled(0.8)
        assert probability[ahead] == (1.0 if wanted else 0.0) and region_mover[ahead] == row
        assert np.all(probability[np.arange(8) != ahead] == -1.0)  # no mover, not judged
        _kinematics(scene, goal, probability)  # the point rule: nothing judged by probability
        assert np.all(probability == -1.0)


def test_the_model_attends_the_true_mover_its_goal_wants():
    model = PerfectPerceptionModel(AttentionConfig())
    model.set_goals(FAST)
    laser = np.full(180, 20.0)
    laser[_beams_at(30.0, 6)] = 3.0
    sonar = np.full(16, 5.0)
    region = _region(30.0)
    for k, (velocity, beams) in enumerate((((0.7, 0.0), 6), ((0.7, 0.0), 6), ((0.7, 0.0), 1), ((0.0, 0.0), 6))):
        truth = _scene([(41, 30.0, 3.0, velocity, beams)])
        output = model.step(0.1 * (k + 1), sonar, laser, truth=truth)
        wanted = beams >= SEEN_BEAMS and velocity[0] > 0.0
        assert output.goal_fulfilled[region] == wanted and (output.origin == "top-down") == wanted
        assert output.focus == region  # top-down where the goal holds, else bottom-up (the nearest echo)
        assert output.speeds_mps[region] == pytest.approx(0.7 if wanted else 0.0)
        assert len(output.tracks.id) == 0  # the truth, not tracks
    with pytest.raises(ValueError, match="truth must be a TrueScene"):
        model.step(1.0, sonar, laser, truth=None)
    with pytest.raises(ValueError, match="sonar grid only"):
        PerfectPerceptionModel(AttentionConfig(grid="laser"))


#: Seeds whose target is in view within 4 s of a still robot.
SEEDS = (0, 4, 5)


def test_the_bound_records_the_attended_episodes_and_attends_a_seen_target(attended_env):
    # 4 s, robot still, 5 % noise, both goals: the same episodes as the tracker's, a focus on
    # target no lower, and the focus on the target wherever the laser sees it on 2 beams or more
    noise = 0.05
    bound_env = make_bound_env(noise, sensor_noise=noise, **PERCEPTION_ARENA)
    tracker_env = attended_env("tracker", noise)
    episodes = [(seed, goal) for seed in SEEDS for goal in (FAST, SLOW)]
    bound, tracker = [], []
    for seed, goal in episodes:
        tracker.append(record_episode(tracker_env, seed, goal, stand_still, 4.0))
        bound.append(record_episode(bound_env, seed, goal, stand_still, 4.0))
        np.testing.assert_array_equal(bound[-1].mover_xy, tracker[-1].mover_xy)
        assert bound[-1].track_speed is None and bound[-1].target_case is None
    by_bound, by_tracker = focus_on_target(bound), focus_on_target(tracker)
    for goal in (str(FAST), str(SLOW)):
        assert by_bound[goal].steps == by_tracker[goal].steps > 200  # the same in-view steps
        assert by_bound[goal].rate >= by_tracker[goal].rate + 0.1  # 0.99 / 0.69, 0.98 / 0.55 (bound / tracker)
    on, seen_steps = 0, 0
    for seed, goal in episodes:
        obs, info = bound_env.reset(seed=seed, options={"goal": goal})
        target = info["target_index"]
        while info["time_s"] < 4.0 - 1e-9:
            obs, _, _, _, info = bound_env.step(stand_still(obs, info))
            xy = to_robot_frame(info["mover_positions"][target], info["robot_pose"])
            if in_view(xy) and bound_env.model.seen[target]:
                seen_steps += 1
                on += info["attention"].focus == region_of(xy)
    bound_env.close()
    assert seen_steps > 400 and on / seen_steps >= 0.95


def test_without_motion_the_bound_steps_as_the_compiled_model():
    # a static scene: the window's range rates are 0 (to rounding, ~1e-14 m/s), as are the
    # truth's without movers, so the bound's stages (sense, maps, goals, courses, selection)
    # give the compiled step's outputs
    rng = np.random.default_rng(3)
    sonar, laser = rng.uniform(0.5, 5.0, 16), rng.uniform(0.5, 20.0, 180)
    bound, compiled = PerfectPerceptionModel(AttentionConfig()), AttentionModel(AttentionConfig(kinematics="window"))
    foci, fired = set(), 0
    for k in range(40):
        if k == 20:  # bottom-up courses first, then a top-down goal
            for model in (bound, compiled):
                model.set_goals(Goal.between("distance", 0.0, 1.5))
        expected = compiled.step(0.1 * (k + 1), sonar, laser)
        output = bound.step(0.1 * (k + 1), sonar, laser, truth=_scene([]))
        assert (output.focus, output.fired, output.origin) == (expected.focus, expected.fired, expected.origin)
        for name in ("F", "C", "M", "L", "goal_fulfilled", "directions", "speeds_mps", "distances_m"):
            np.testing.assert_allclose(getattr(output, name), getattr(expected, name), rtol=0, atol=1e-12, err_msg=name)
        foci.add(output.focus)
        fired += output.fired
    assert len(foci) > 1 and fired > 1  # courses started and moved the focus
