"""The focus observation's working memory, the privileged oracle and the random-focus control."""

import math

import gymnasium as gym
import numpy as np
import pytest

from attentive_gym.attention import Goal
from attentive_gym.attention.regions import laser_bearings_rad
from attentive_gym.attention.working_memory import MEMORY_FIELDS, WorkingMemory
from attentive_gym.envs import AttentiveRescueEnv
from attentive_gym.wrappers import AttentionWrapper, OracleFocus, make_env

# --- WorkingMemory ---------------------------------------------------------------------


def test_memory_dead_reckons_an_entry_with_its_velocity_and_the_robots_pose():
    memory = WorkingMemory(slots=2)
    # attended at t = 1 s: 3 m ahead and 1 m left of a robot at (1, 2) heading +90°
    # (so at (0, 5) in the odometry frame), moving at 0.5 m/s along the robot's x axis
    # (+y in the odometry frame)
    memory.attend(1.0, np.array([1.0, 2.0, math.pi / 2]), 7, np.array([3.0, 1.0]), np.array([0.5, 0.0]), 0.5, True)
    # at t = 3 s the body is at (0, 6); the robot has moved to (0, 2) and turned to 180°
    rows = memory.read(3.0, np.array([0.0, 2.0, math.pi]), max_distance_m=20.0)
    # seen from there it is 4 m away, 90° to the right
    np.testing.assert_allclose(rows[0], [0.0, -1.0, 4.0, 0.5, 1.0, 2.0], atol=1e-6)
    assert not rows[1].any()  # an empty slot is all zeros
    assert rows.shape == (2, len(MEMORY_FIELDS)) and rows.dtype == np.float32


def test_memory_keeps_the_most_recent_bodies_first_and_refreshes_a_known_one():
    memory = WorkingMemory(slots=3)
    pose = np.zeros(3)
    for t, track in enumerate((10, 11, 12, 13)):  # 10 falls out
        memory.attend(float(t), pose, track, np.array([1.0 + track, 0.0]), np.zeros(2), 0.1 * track, False)
    assert memory.read(3.0, pose, 20.0)[:, 2].tolist() == [14.0, 13.0, 12.0]
    memory.attend(4.0, pose, 11, np.array([2.0, 0.0]), np.zeros(2), 0.0, True)  # 11 again: to the front
    rows = memory.read(4.0, pose, 20.0)
    assert rows[:, 2].tolist() == [2.0, 14.0, 13.0] and rows[:, 4].tolist() == [1.0, 0.0, 0.0]
    assert rows[:, 5].tolist() == [0.0, 1.0, 2.0]


def test_memory_reads_the_goal_matches_first_then_the_others_each_by_recency():
    memory = WorkingMemory(slots=4, horizon_s=10.0)
    pose = np.zeros(3)
    # attended in turn: 20 (match), 21, 22 (match), 23; 24 fills no slot (20 falls out)
    for t, (track, match) in enumerate(((20, True), (21, False), (22, True), (23, False), (24, False))):
        memory.attend(float(t), pose, track, np.array([float(track), 0.0]), np.zeros(2), 0.0, match)
    rows = memory.read(4.0, pose, 30.0)
    assert rows[:, 2].tolist() == [22.0, 24.0, 23.0, 21.0]
    assert rows[:, 4].tolist() == [1.0, 0.0, 0.0, 0.0]
    memory.attend(5.0, pose, 21, np.array([21.0, 0.0]), np.zeros(2), 0.0, True)  # 21 now matches
    rows = memory.read(5.0, pose, 30.0)
    assert rows[:, 2].tolist() == [21.0, 22.0, 24.0, 23.0] and rows[:, 4].tolist() == [1.0, 1.0, 0.0, 0.0]
    # an entry past the horizon leaves no gap: the empty rows come last
    memory = WorkingMemory(slots=3, horizon_s=2.0)
    memory.attend(0.0, pose, 1, np.array([5.0, 0.0]), np.zeros(2), 0.0, True)
    memory.attend(1.5, pose, 2, np.array([6.0, 0.0]), np.zeros(2), 0.0, False)
    rows = memory.read(2.5, pose, 30.0)
    assert rows[:, 2].tolist() == [6.0, 0.0, 0.0] and rows[:, 4].tolist() == [0.0, 0.0, 0.0]


def test_memory_forgets_after_its_horizon_and_clips_the_distance():
    memory = WorkingMemory(slots=1, horizon_s=2.0)
    memory.attend(0.0, np.zeros(3), 1, np.array([30.0, 0.0]), np.zeros(2), 0.0, False)
    assert memory.read(2.0, np.zeros(3), max_distance_m=20.0)[0, 2] == 20.0
    assert not memory.read(2.5, np.zeros(3), max_distance_m=20.0).any()
    memory.attend(3.0, np.zeros(3), 1, np.array([1.0, 0.0]), np.zeros(2), 0.0, False)
    memory.reset()
    assert not memory.read(3.0, np.zeros(3), 20.0).any()


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"slots": 0}, "slots must be an integer >= 1"),
        ({"slots": 2.5}, "slots must be an integer >= 1"),
        ({"horizon_s": 0.0}, "horizon_s must be a finite number > 0"),
        ({"horizon_s": float("nan")}, "horizon_s must be a finite number > 0"),
    ],
)
def test_memory_refuses_bad_settings(kwargs, message):
    with pytest.raises(ValueError, match=message):
        WorkingMemory(**kwargs)


# --- a scripted world: the attended observation ignores what it does not attend -------------

_BEARINGS = laser_bearings_rad()


def _laser(bodies, radius=0.25, wall_m=8.0):
    """(180,) ranges of a laser at the origin seeing discs at ``bodies`` (k, 2) before a far wall."""
    ranges = np.full(_BEARINGS.shape, wall_m)
    directions = np.stack([np.cos(_BEARINGS), np.sin(_BEARINGS)], axis=1)
    for centre in bodies:
        along = directions @ centre
        miss2 = centre @ centre - along**2
        hit = (miss2 < radius**2) & (along > 0)
        ranges[hit] = np.minimum(ranges[hit], along[hit] - np.sqrt(radius**2 - miss2[hit]))
    return ranges


class _ScriptedRescue(gym.Env):
    """A still robot between a target driving at it and a second body, as raw readings."""

    def __init__(self, second_velocity):
        self.observation_space = AttentiveRescueEnv().observation_space
        self.action_space = gym.spaces.Box(-1.0, 1.0, (2,), np.float32)
        self._second_velocity = np.asarray(second_velocity, float)
        self._goal = Goal.between("speed", 0.5, 0.9).encode()

    def _observe(self):
        target = np.array([5.0, 0.4]) + self.t * np.array([-0.6, 0.0])
        second = np.array([1.5, -3.0]) + self.t * self._second_velocity
        obs = {
            "sonar": np.full(16, 5.0, np.float32),
            "laser": _laser([target, second]).astype(np.float32),
            "odometry": np.zeros(2, np.float32),
            "goal": self._goal,
        }
        return obs, {"time_s": self.t}

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.t = 0.0
        return self._observe()

    def step(self, action):
        self.t += 0.05
        obs, info = self._observe()
        return obs, 0.0, False, False, info


def _focus_run(second_velocity, steps=80):
    env = AttentionWrapper(_ScriptedRescue(second_velocity), "focus", weights={"F4": 1.0})  # top-down only
    observations, regions = [env.reset(seed=0)[0]], []
    for _ in range(steps):
        obs, *_, info = env.step(np.zeros(2, np.float32))
        observations.append(obs)
        regions.append(info["attention"].focus)
    return observations, regions


def test_focus_observation_is_unchanged_when_an_unattended_body_moves():
    still, still_regions = _focus_run([0.0, 0.0])
    moving, moving_regions = _focus_run([0.0, 0.3])
    target_region = 3  # s4 (+10°): the target comes closer 0.4 m left of the axis
    assert still_regions == moving_regions and target_region in still_regions
    assert all(region in (None, target_region) for region in still_regions)  # the second body is never attended
    assert still[-1]["memory"][0] != 0.0 and still[-1]["memory"][3] == pytest.approx(0.6, abs=0.1)
    for step, (a, b) in enumerate(zip(still, moving)):
        for key in a:
            np.testing.assert_array_equal(a[key], b[key], err_msg=f"{key} at step {step}")


def test_focus_memory_holds_only_attended_bodies():
    env = make_env("focus", sensor_noise=0.05, arena_size_m=10, num_distractors=3)
    env.reset(seed=3)
    attended = set()
    for _ in range(300):
        obs, _, terminated, truncated, info = env.step(env.action_space.sample())
        view = info["attention"].view
        if view is not None and view.track_id is not None:
            attended.add(view.track_id)
        remembered = {int(track) for track in env.memory._ids if track >= 0}
        assert remembered <= attended
        if terminated or truncated:
            break
    assert len(attended) >= 2  # the run attended several bodies, so the check had something to check


# --- the oracle -----------------------------------------------------------------------


def test_oracle_sees_the_target_truly_wherever_it_is():
    env = make_env("oracle", sensor_noise=0.05, arena_size_m=10, num_distractors=3)
    obs, info = env.reset(seed=1)
    behind = 0
    for _ in range(200):
        x, y, heading = info["robot_pose"]
        dx, dy = info["mover_positions"][info["target_index"]] - np.array([x, y])
        forward = math.cos(heading) * dx + math.sin(heading) * dy
        left = -math.sin(heading) * dx + math.cos(heading) * dy
        distance = math.hypot(forward, left)
        np.testing.assert_allclose(
            obs["memory"][:3], [forward / distance, left / distance, distance], rtol=1e-5, atol=1e-5
        )
        assert obs["memory"][4] == 1.0 and not obs["memory"][6:].any()
        if forward < 0:
            behind += 1
            assert obs["region"][-1] == 1.0  # behind the robot: in no region, yet remembered
        else:
            bearing = math.degrees(math.atan2(left, forward))
            assert obs["region"].argmax() == env._grid.beam_region[int(bearing + 90.0)]
            assert obs["distance"][0] == pytest.approx(distance, rel=1e-5)
        assert env.observation_space.contains(obs)
        obs, _, terminated, truncated, info = env.step(np.array([0.3, 1.0], np.float32))  # circle
        if terminated or truncated:
            break
    assert behind > 0


def test_oracle_observation_follows_the_target_not_the_sensors():
    """Moving the target in the simulator's state moves the oracle's view of it, with the
    same readings: it is privileged."""
    base = AttentiveRescueEnv(sensor_noise=0.0)
    oracle = OracleFocus(base)
    raw, info = base.reset(seed=2)
    obs = oracle.observe_step(raw, info)
    moved = dict(info, mover_positions=info["mover_positions"].copy())
    moved["mover_positions"][info["target_index"]] += (1.0, 0.0)
    again = oracle.observe_step(raw, moved)
    assert not np.array_equal(again["memory"][:3], obs["memory"][:3])
    np.testing.assert_array_equal(again["odometry"], obs["odometry"])


# --- the random-focus control -------------------------------------------------------------


def test_random_focus_draws_regions_uniformly_and_reproducibly():
    def regions(seed):
        env = make_env("random-focus", sensor_noise=0.05)
        obs, _ = env.reset(seed=seed)
        drawn = [int(obs["region"].argmax())]
        for _ in range(399):
            obs, *_ = env.step(np.zeros(2, np.float32))
            drawn.append(int(obs["region"].argmax()))
            assert not obs["event"].any()
        return np.array(drawn)

    first, again, other = regions(0), regions(0), regions(1)
    np.testing.assert_array_equal(first, again)
    assert not np.array_equal(first, other)
    counts = np.bincount(first, minlength=9)
    assert counts[8] == 0 and counts[:8].min() > 25  # every region, about 50 times each of 400


def test_random_focus_leaves_the_environment_trajectory_unchanged():
    focus, control = make_env("focus", sensor_noise=0.05), make_env("random-focus", sensor_noise=0.05)
    _, info_focus = focus.reset(seed=5)
    _, info_control = control.reset(seed=5)
    for _ in range(50):
        action = np.array([0.5, 0.2], np.float32)
        *_, info_focus = focus.step(action)
        *_, info_control = control.step(action)
    np.testing.assert_array_equal(info_focus["robot_pose"], info_control["robot_pose"])
    np.testing.assert_array_equal(info_focus["mover_positions"], info_control["mover_positions"])


@pytest.mark.parametrize("variant", ["oracle", "random-focus", "focus"])
def test_focus_layout_variants_share_one_space(variant):
    assert make_env(variant).observation_space == make_env("focus").observation_space
    assert make_env(variant, memory_slots=0).observation_space == make_env("focus", memory_slots=0).observation_space


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: make_env("raw", memory_slots=2), "memory_slots applies to the variants"),
        (lambda: make_env("focus", memory_slots=-1), "memory_slots must be an integer >= 0"),
        (lambda: make_env("oracle", memory_slots=1.5), "memory_slots must be an integer >= 0"),
        (
            lambda: AttentionWrapper(AttentiveRescueEnv(), "saliency", selection="random"),
            "apply to the 'focus' observation",
        ),
        (lambda: AttentionWrapper(AttentiveRescueEnv(), "focus", selection="sometimes"), "unknown selection"),
    ],
)
def test_bad_memory_and_selection_settings_are_refused(call, message):
    with pytest.raises(ValueError, match=message):
        call()
