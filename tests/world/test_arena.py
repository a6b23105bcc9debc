"""The procedural rescue arena: seeded, valid, and faithful to its goal."""

import numpy as np
import pytest

from attentive_gym.attention.goals import Goal
from attentive_gym.world.arena import ArenaConfig, _segment_distances, generate_arena
from attentive_gym.world.scenario import EvadeBehaviour, PathBehaviour, PursueBehaviour
from attentive_gym.world.world import World


def mover_speed(spec):
    if spec.behaviour is None:
        return 0.0
    if isinstance(spec.behaviour, PathBehaviour):
        speeds = {leg.speed_mps for leg in spec.behaviour.legs}
        assert len(speeds) == 1
        return speeds.pop()
    return spec.behaviour.speed_mps


def test_same_seed_same_arena_and_different_seeds_differ():
    config = ArenaConfig()
    a = generate_arena(config, np.random.default_rng(7))
    b = generate_arena(config, np.random.default_rng(7))
    c = generate_arena(config, np.random.default_rng(8))
    assert a == b
    assert a != c


@pytest.mark.parametrize("seed", range(25))
def test_arenas_build_without_overlap_and_keep_the_knobs(seed):
    config = ArenaConfig(num_distractors=4, rubble_per_100m2=8.0)
    scenario = generate_arena(config, np.random.default_rng(seed))
    World(scenario)  # raises if any body starts overlapping another
    assert len(scenario.movers) == 5
    assert len(scenario.rubble) <= config.rubble_count
    assert scenario.task is not None and scenario.movers[scenario.target_index].kind == "victim"
    robot = np.array([scenario.robot.x_m, scenario.robot.y_m])
    for mover in scenario.movers:
        assert np.linalg.norm([mover.start.x_m - robot[0], mover.start.y_m - robot[1]]) >= config.min_start_distance_m


@pytest.mark.parametrize(
    "goal",
    [Goal.between("speed", 0.5, 0.9), Goal.smaller("speed", 0.3), Goal.greater("speed", 0.6), Goal.equal("speed", 0.4)],
)
def test_speed_goals_single_out_the_target(goal):
    config = ArenaConfig()
    for seed in range(10):
        scenario = generate_arena(config, np.random.default_rng(seed), goal)
        assert scenario.task.goal == goal
        for i, mover in enumerate(scenario.movers):
            speed = mover_speed(mover)
            fulfils = bool(goal.is_fulfilled(speed))
            assert fulfils == (i == scenario.target_index), (seed, mover.name, speed)


@pytest.mark.parametrize(
    "direction, behaviour", [("towards", PursueBehaviour), ("away", EvadeBehaviour), ("static", type(None))]
)
def test_direction_goals_give_the_target_a_matching_behaviour(direction, behaviour):
    scenario = generate_arena(ArenaConfig(), np.random.default_rng(3), Goal.direction_is(direction))
    target = scenario.movers[scenario.target_index]
    assert isinstance(target.behaviour, behaviour)
    others = [m for i, m in enumerate(scenario.movers) if i != scenario.target_index]
    assert all(isinstance(m.behaviour, PathBehaviour) for m in others)


def test_goals_that_cannot_single_out_a_victim_are_refused():
    with pytest.raises(ValueError, match="distance goals cannot single out a victim"):
        ArenaConfig(goals=(Goal.smaller("distance", 2.0),))
    with pytest.raises(ValueError, match="no speeds in"):
        ArenaConfig(goals=(Goal.greater("speed", 5.0),))


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"width_m": 2.0}, "at least 4 m"),
        ({"num_distractors": -1}, "num_distractors"),
        ({"rubble_per_100m2": float("nan")}, "rubble_per_100m2"),
        ({"goals": ()}, "non-empty"),
        ({"distractor_speed_range_mps": (0.5, 0.2)}, "distractor_speed_range_mps"),
    ],
)
def test_bad_knobs_are_refused(kwargs, message):
    with pytest.raises(ValueError, match=message):
        ArenaConfig(**kwargs)


def test_a_crowded_arena_draws_its_layout_again_instead_of_failing():
    # 6 distractors in an 8 m arena: about 1 first layout in 20 has no room for a mover
    config = ArenaConfig(width_m=8.0, height_m=8.0, rubble_per_100m2=3.0, num_distractors=6)
    for seed in range(200):
        scenario = generate_arena(config, np.random.default_rng(seed))
        assert len(scenario.movers) == 7


def test_an_arena_without_room_says_so():
    config = ArenaConfig(width_m=4.0, height_m=4.0, num_distractors=20)
    with pytest.raises(
        ValueError,
        match=r"could not place mover .* 4.0 × 4.0 m arena; lower the rubble density or "
        r"the number of distractors \(in 20 layouts in a row\)",
    ):
        generate_arena(config, np.random.default_rng(0))


def test_segment_distances_are_numpy_s_norms_bit_for_bit():
    # the arena's layout (and so every seed's arena) depends on these exact numbers
    rng = np.random.default_rng(0)
    for _ in range(200):
        points = rng.uniform(-5.0, 5.0, (int(rng.integers(0, 12)), 2))
        a = rng.uniform(-5.0, 5.0, 2)
        b = a if rng.random() < 0.3 else rng.uniform(-5.0, 5.0, 2)
        ab = b - a
        t = np.zeros(len(points)) if ab @ ab == 0.0 else np.clip((points - a) @ ab / float(ab @ ab), 0.0, 1.0)
        expected = np.linalg.norm(a + t[:, None] * ab - points, axis=1)
        assert _segment_distances(points, a, b).tolist() == expected.tolist()
