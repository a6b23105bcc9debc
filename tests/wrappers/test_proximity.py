"""The ``"proximity"`` entry of the focus layout: every region's nearest reading, from the
readings alone, the same in every variant that has the layout, alone or in a fleet."""

import gymnasium as gym
import numpy as np
import pytest

from attentive_gym.attention import AttentionConfig
from attentive_gym.attention.regions import Grid
from attentive_gym.wrappers import make_env

FOCUS_LAYOUT = ("focus", "random-focus", "goal-action", "oracle")


def _expected(raw):
    """Each region's nearest reading, computed directly: the minimum of the region's front
    sonar and of its laser beams, clipped to ``max_distance_m``."""
    grid, config = Grid.make("sonar"), AttentionConfig()
    return np.array(
        [
            min(raw["sonar"][grid.region_sonar[j]], raw["laser"][grid.beam_slices[j]].min(), config.max_distance_m)
            for j in range(grid.n_regions)
        ],
        np.float32,
    )


def _rollout(variant, steps=120, seed=4):
    """(raw observation, observation) pairs of ``variant`` with ``proximity`` over ``steps``
    steps of a fixed action sequence; the raw one is read from the base env's last step."""
    env = make_env(variant, proximity=True, arena_size_m=7.0, num_distractors=3)
    base = env.unwrapped
    rng = np.random.default_rng(seed)
    pairs = []
    observation, _ = env.reset(seed=seed)
    for _ in range(steps):
        observation, _, terminated, truncated, _ = env.step(rng.uniform(-1, 1, env.action_space.shape))
        raw = {"sonar": base._reading.sonar.astype(np.float32), "laser": base._reading.laser.astype(np.float32)}
        pairs.append((raw, observation))
        if terminated or truncated:
            observation, _ = env.reset()
    return env, pairs


@pytest.mark.parametrize("variant", FOCUS_LAYOUT)
def test_proximity_is_each_regions_nearest_reading(variant):
    env, pairs = _rollout(variant)
    assert env.observation_space["proximity"].shape == (8,)
    near = 0
    for raw, observation in pairs:
        np.testing.assert_array_equal(observation["proximity"], _expected(raw))
        assert env.observation_space["proximity"].contains(observation["proximity"])
        near += bool((observation["proximity"] < 1.0).any())
    assert near > 0, "the rollout must pass near something"


def test_the_oracle_senses_no_more_than_the_focus():
    """The oracle's proximity is the focus's on the same seed and actions: readings only,
    nothing from the privileged state."""
    _, oracle = _rollout("oracle")
    _, focus = _rollout("focus")
    for (_, a), (_, b) in zip(oracle, focus):
        np.testing.assert_array_equal(a["proximity"], b["proximity"])


def test_the_layout_without_proximity_is_unchanged():
    with_it, without = make_env("focus", proximity=True), make_env("focus", proximity=False)
    assert "proximity" not in without.observation_space.spaces
    assert set(with_it.observation_space.spaces) - set(without.observation_space.spaces) == {"proximity"}
    assert gym.spaces.flatdim(with_it.observation_space) == gym.spaces.flatdim(without.observation_space) + 8


def test_a_fleet_gives_each_member_alone_bit_for_bit():
    vector = gym.make_vec(
        "AttentiveRescueFocus-v1", num_envs=3, vectorization_mode="vector_entry_point", proximity=True
    )
    alone = [make_env("focus", proximity=True) for _ in range(3)]
    observations, _ = vector.reset(seed=7)
    expected = [env.reset(seed=7 + i)[0] for i, env in enumerate(alone)]
    rng = np.random.default_rng(1)
    for _ in range(60):
        for i, env_obs in enumerate(expected):
            np.testing.assert_array_equal(observations["proximity"][i], env_obs["proximity"])
        actions = rng.uniform(-1, 1, (3, 2)).astype(np.float32)
        observations, *_ = vector.step(actions)
        expected = []
        for env, action in zip(alone, actions):
            observation, _, terminated, truncated, _ = env.step(action)
            assert not (terminated or truncated), "the comparison assumes no episode ends in 3 s"
            expected.append(observation)
    vector.close()


@pytest.mark.parametrize("variant", ["raw", "raw-stack", "saliency", "masked"])
def test_proximity_is_refused_where_there_is_no_focus_layout(variant):
    with pytest.raises(ValueError, match="proximity applies to the variants"):
        make_env(variant, proximity=True)


def test_proximity_must_be_a_flag():
    with pytest.raises(ValueError, match="proximity must be True or False"):
        make_env("focus", proximity=1)
