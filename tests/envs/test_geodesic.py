"""The geodesic distance a progress reward may count (``envs.geodesic``,
``RewardConfig(progress="geodesic")``): the grid, the search, and the reward that uses them."""

import math

import numpy as np
import pytest

from attentive_gym.attention import Goal
from attentive_gym.envs import AttentiveRescueEnv, RewardConfig
from attentive_gym.envs.geodesic import CELL_M, CLEARANCE_M, GeodesicDistance, occupancy, path_lengths
from attentive_gym.world.scenario import BoxRubble, CircleRubble, MoverSpec, Pose, Scenario, TaskSpec, WallSpec

#: A 6 m room, the robot at its left, a victim at its right, a 3 m box between them.
ROOM = Scenario(
    "geodesic-room",
    (-3.0, -3.0, 3.0, 3.0),
    robot=Pose(-2.0, 0.0),
    enclosed=True,
    rubble=(BoxRubble(0.0, 0.0, 0.4, 3.0),),
    movers=(MoverSpec("survivor", "victim", Pose(2.0, 0.0)),),
    task=TaskSpec("survivor", Goal.between("speed", 0.0, 0.2)),
)


def _walls(scenario):
    x0, y0, x1, y1 = scenario.bounds
    corners = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
    return [WallSpec(corners[i], corners[(i + 1) % 4]) for i in range(4)]


def test_cells_within_the_clearance_of_rubble_and_walls_are_blocked():
    disc = Scenario("disc", (0.0, 0.0, 4.0, 4.0), rubble=(CircleRubble(2.0, 2.0, 0.5),))
    blocked = occupancy(disc, [])
    centres = (np.arange(blocked.shape[0]) + 0.5) * CELL_M
    x, y = np.meshgrid(centres, centres)
    assert np.array_equal(blocked, np.hypot(x - 2.0, y - 2.0) - 0.5 < CLEARANCE_M)
    walled = occupancy(disc, _walls(disc))
    assert walled[0].all() and walled[-1].all() and walled[:, 0].all() and walled[:, -1].all()
    assert not walled[5, 5]  # 1.1 m from the walls and the disc


def test_path_lengths_are_octile_distances_on_a_free_grid_and_go_round_a_wall():
    free = np.zeros((5, 7), np.bool_)
    lengths = np.empty(free.shape)
    path_lengths(free, np.array([0]), np.array([0.0]), 1.0, lengths)
    i, j = np.mgrid[0:5, 0:7]
    octile = np.maximum(i, j) - np.minimum(i, j) + math.sqrt(2.0) * np.minimum(i, j)
    assert np.allclose(lengths, octile)
    walled = free.copy()
    walled[:4, 3] = True  # a wall down column 3, open at the bottom row
    path_lengths(walled, np.array([0]), np.array([0.0]), 1.0, lengths)
    assert np.isinf(lengths[walled]).all()
    # down to (4, 2), through the gap to (4, 4) without cutting the wall's corner, up to (0, 6)
    assert lengths[0, 6] == pytest.approx(2 * (2 + 2 * math.sqrt(2.0)) + 2)
    closed = free.copy()
    closed[:, 3] = True
    path_lengths(closed, np.array([0]), np.array([0.0]), 1.0, lengths)
    assert np.isinf(lengths[:, 4:]).all()


def test_the_path_round_a_box_is_longer_than_the_straight_line_and_equal_to_it_in_the_open():
    geodesic = GeodesicDistance(ROOM, _walls(ROOM))
    around = geodesic(-2.0, 0.0, 2.0, 0.0)
    # round the box's end (1.5 m off the line, plus the clearance): at least the two straight legs
    corner = 1.5 + CLEARANCE_M
    assert around >= 2 * math.hypot(2.0, corner) - 2 * CELL_M
    assert around > 4.0 + 1.0
    open_side = geodesic(-2.0, 2.4, -0.5, 2.4)  # above the box: nothing between
    assert open_side == pytest.approx(1.5, abs=CELL_M * math.sqrt(2.0))


def test_a_walled_in_target_falls_back_to_the_straight_line():
    boxed = Scenario(
        "boxed",
        (-3.0, -3.0, 3.0, 3.0),
        walls=(
            WallSpec((1.0, -1.0), (1.0, 1.0)),
            WallSpec((1.0, 1.0), (2.6, 1.0)),
            WallSpec((1.0, -1.0), (2.6, -1.0)),
            WallSpec((2.6, -1.0), (2.6, 1.0)),
        ),
    )
    geodesic = GeodesicDistance(boxed, list(boxed.walls))
    assert geodesic(-2.0, 0.0, 1.8, 0.0) == pytest.approx(3.8)


def test_progress_must_be_a_known_mode():
    with pytest.raises(ValueError, match=r"RewardConfig.progress must be one of \('euclidean', 'geodesic'\)"):
        RewardConfig(progress="straight")
    assert RewardConfig().progress == "euclidean"


def test_geodesic_progress_pays_the_path_gained_and_success_stays_on_the_straight_line():
    """Each step's reward is progress_per_m times the path length gained (the collision, near
    and time terms set to 0); the straight-line distance stays in info; the same actions move
    the robot alike under either reward, and the two pay differently behind the box."""
    reward = {"progress": "geodesic", "time_per_s": 0.0, "collision_per_s": 0.0}
    env = AttentiveRescueEnv(scenario=ROOM, reward=reward)
    plain = AttentiveRescueEnv(scenario=ROOM, reward={"time_per_s": 0.0, "collision_per_s": 0.0})
    _, info = env.reset(seed=0)
    plain.reset(seed=0)
    target = info["mover_positions"][info["target_index"]]
    paths = [env._geodesic(*info["robot_pose"][:2], *target)]
    straight_gain, path_gain = 0.0, 0.0
    for _ in range(20):
        _, r, _, _, info = env.step(np.array([1.0, 0.3]))
        _, r_plain, _, _, info_plain = plain.step(np.array([1.0, 0.3]))
        paths.append(env._geodesic(*info["robot_pose"][:2], *target))
        assert r == pytest.approx(paths[-2] - paths[-1])
        assert info["target_distance_m"] == pytest.approx(math.dist(info["robot_pose"][:2], target))
        assert info["robot_pose"].tolist() == info_plain["robot_pose"].tolist()  # the reward moves nothing
        straight_gain += r_plain
        path_gain += r
    assert path_gain != pytest.approx(straight_gain)
