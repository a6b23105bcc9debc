"""F1–F6 against hand-computed values, including the resolved typos of docs/model.md §5."""

import numpy as np
import pytest

from attentive_gym.attention import Goal
from attentive_gym.attention.features import (
    Spaces,
    direction_goal_map,
    distance_map,
    goal_knots,
    goal_map,
    goal_table,
    label_columns,
    majority_labels,
    motion_map,
    rarity_map,
)


def test_motion_map_is_contrast_to_the_mean_over_all_elements():
    s = np.array([0.0, 0.0, 0.0, 0.8, 0.0, 0.0, 0.0, 0.0])
    # mean 0.1: |0.8 - 0.1| = 0.7, |0 - 0.1| = 0.1, divided by MAX_SPEED = 2
    np.testing.assert_allclose(motion_map(s, 2.0), [0.05, 0.05, 0.05, 0.35, 0.05, 0.05, 0.05, 0.05])
    np.testing.assert_allclose(motion_map(np.stack([s, s]), 2.0)[1, 3], 0.35)  # batch


def test_rarity_map_n_over_count_normalised():
    labels = np.array([0, 0, 0, 0, 0, 0, -1, 1.0])
    # N = 8: static count 6 -> rho = 8/6, towards/away count 1 -> rho = 8 -> (rho - 1)/7
    expected = [(8 / 6 - 1) / 7] * 6 + [1.0, 1.0]
    np.testing.assert_allclose(rarity_map(labels), expected)
    np.testing.assert_allclose(rarity_map(np.zeros(8)), 0.0)
    two = np.array([-1.0, -1.0, 1.0, 1.0])
    np.testing.assert_allclose(rarity_map(two), (4 / 2 - 1) / 3)


def test_rarity_over_side_by_side_spaces_uses_each_space_alone():
    spaces = Spaces.make((8, 180))
    labels = np.zeros(188)
    labels[3] = -1.0  # one approaching sonar among 8
    labels[8 + 100] = 1.0  # one receding beam among 180
    r = rarity_map(labels, spaces=spaces)
    np.testing.assert_allclose(r[:8], rarity_map(labels[:8]))
    np.testing.assert_allclose(r[8:], rarity_map(labels[8:]))
    assert r[3] == pytest.approx(1.0) and r[108] == pytest.approx(1.0)


def test_majority_labels_break_ties_towards_then_away():
    labels = np.array([0, 0, -1, 1, 1, -1, 0, 0.0])
    regions = np.array([0, 0, 1, 1, 2, 2, 3, 3])
    # region 0: static; 1: tie -1/+1 -> towards; 2: tie +1/-1 -> towards; 3: static
    assert majority_labels(label_columns(labels), regions, 4).tolist() == [0.0, -1.0, -1.0, 0.0]
    labels = np.array([1, 1, 0, 0, 0, 0.0])
    assert majority_labels(label_columns(labels), np.array([0, 0, 0, 1, 1, 1]), 2).tolist() == [1.0, 0.0]


def test_distance_map_single_and_fused():
    laser = np.full(180, 20.0)
    laser[:10] = 2.0  # mean = (170*20 + 10*2)/180 = 19
    f = distance_map(laser, 20.0)
    assert f[0] == pytest.approx(17 / 20) and f[50] == pytest.approx(1 / 20)
    sonar = np.array([5, 5, 5, 1, 5, 5, 5, 5.0])  # mean 4.5
    both = distance_map(
        np.concatenate([sonar, laser]), np.r_[np.full(8, 5.0), np.full(180, 20.0)], Spaces.make((8, 180))
    )
    np.testing.assert_allclose(both[:8], [0.1, 0.1, 0.1, 0.7, 0.1, 0.1, 0.1, 0.1])
    np.testing.assert_allclose(both[8:], f)


@pytest.mark.parametrize(
    ("goal", "x", "expected"),
    [
        # BETWEEN(0.5, 0.9) with MAX 1: inside (bounds inclusive: the ">= d and <= d" typo) -> 1
        (Goal.between("speed", 0.5, 0.9), 0.5, 1.0),
        (Goal.between("speed", 0.5, 0.9), 0.9, 1.0),
        (Goal.between("speed", 0.5, 0.9), 0.7, 1.0),
        (Goal.between("speed", 0.5, 0.9), 0.2, 0.4),  # below: s / lo
        (Goal.between("speed", 0.5, 0.9), 0.95, 0.5),  # above: 1 - (s - hi)/(MAX - hi), fixed parentheses
        (Goal.greater("speed", 0.6), 0.3, 0.5),  # below: s / d (tests the input, not f4)
        (Goal.greater("speed", 0.6), 0.6, 1.0),
        (Goal.smaller("speed", 0.2), 0.6, 0.5),  # above: 1 - (s - d)/(MAX - d)
        (Goal.smaller("speed", 0.2), 0.1, 1.0),
        (Goal.equal("speed", 0.7, tolerance=0.05), 0.74, 1.0),
        (Goal.equal("speed", 0.7, tolerance=0.05), 0.4, 1 - 0.3 / 0.7),  # 1 - |s-d|/max(d, MAX-d)
        (Goal.equal("speed", 0.2, tolerance=0.05), 0.6, 1 - 0.4 / 0.8),
    ],
)
def test_goal_table_speed(goal, x, expected):
    assert goal_table(x, goal, 1.0) == pytest.approx(expected)
    values, ok = goal_map(np.array([x]), goal, 1.0)
    assert values[0] == pytest.approx(expected)
    assert bool(ok[0]) == (expected == 1.0)


def test_goal_table_distance_uses_maxdistance_not_maxspeed():
    # F6 SMALLER above the bound: 1 - (x - d)/(MAXDISTANCE - d) = 1 - (12 - 2)/(20 - 2)
    assert goal_table(12.0, Goal.smaller("distance", 2.0), 20.0) == pytest.approx(1 - 10 / 18)
    # F6 GREATER below: x / d
    assert goal_table(1.0, Goal.greater("distance", 4.0), 20.0) == pytest.approx(0.25)
    assert goal_table(4.0, Goal.greater("distance", 4.0), 20.0) == 1.0


@pytest.mark.parametrize(
    "goal",
    [
        Goal.between("speed", 0.5, 0.9),
        Goal.greater("speed", 0.6),
        Goal.smaller("speed", 0.3),
        Goal.equal("speed", 0.7),
        Goal.between("speed", 0.0, 1.0),
        Goal.greater("speed", 0.0),
        Goal.smaller("speed", 2.0),
        Goal.between("speed", 0.4, 3.0),
    ],
)
def test_goal_map_matches_the_scalar_table_everywhere(goal):
    x = np.linspace(0.0, 1.0, 401)
    values, ok = goal_map(x, goal, 1.0, goal_knots(goal, 1.0))
    np.testing.assert_allclose(values, [goal_table(v, goal, 1.0) for v in x], atol=1e-12)
    np.testing.assert_array_equal(ok, goal.is_fulfilled(x))
    assert values.min() >= 0.0 and values.max() <= 1.0


def test_direction_goal_map_and_wrong_kinds():
    labels = np.array([-1, 0, 1, -1.0])
    values, ok = direction_goal_map(labels, Goal.direction_is("towards"))
    assert values.tolist() == [1.0, 0.0, 0.0, 1.0] and ok.tolist() == [True, False, False, True]
    with pytest.raises(ValueError, match="direction goal"):
        direction_goal_map(labels, Goal.greater("speed", 0.1))
    with pytest.raises(ValueError, match="speed and distance goals"):
        goal_map(labels, Goal.direction_is("away"), 1.0)
