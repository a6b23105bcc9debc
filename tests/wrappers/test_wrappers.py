"""AttentionWrapper, GoalActionWrapper, StackedReadings and the variant helpers."""

import pickle

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env
from stable_baselines3.common.env_checker import check_env as sb3_check_env

import attentive_gym  # noqa: F401  (registers the ids)
from attentive_gym.agents.config import RunSpec
from attentive_gym.attention import Goal
from attentive_gym.wrappers import (
    DEFAULT_GOAL_MENU,
    VARIANT_IDS,
    VARIANTS,
    AttentionWrapper,
    GoalActionWrapper,
    OracleFocus,
    StackedReadings,
    make_env,
)


def rollout(env, seed, steps, action_seed=0):
    """Observations of ``steps`` random steps after ``reset(seed)``, flattened per step."""
    rng = np.random.default_rng(action_seed)
    obs, _ = env.reset(seed=seed)
    out = [gym.spaces.flatten(env.observation_space, obs)]
    for _ in range(steps):
        action = rng.uniform(-1, 1, env.action_space.shape).astype(np.float32)
        obs, *_ = env.step(action)
        out.append(gym.spaces.flatten(env.observation_space, obs))
    return np.array(out)


@pytest.mark.filterwarnings("ignore:.*is different from the unwrapped version")
@pytest.mark.parametrize("variant", VARIANTS)
def test_every_variant_passes_the_gymnasium_and_sb3_checkers(variant):
    env = gym.make(VARIANT_IDS[variant])
    check_env(env.unwrapped if variant == "raw" else env.env.env, skip_render_check=True)  # below the checker wrappers
    sb3_check_env(make_env(variant), warn=False)


@pytest.mark.parametrize("variant", VARIANTS)
def test_observations_stay_in_their_space_and_flatten_exactly(variant):
    env = make_env(variant, flatten=True)
    assert isinstance(env.observation_space, gym.spaces.Box)
    observations = rollout(env, seed=3, steps=150)
    assert observations.shape[1] == env.observation_space.shape[0]
    assert all(env.observation_space.contains(o.astype(np.float32)) for o in observations)
    assert np.isfinite(observations).all()


@pytest.mark.parametrize(
    "variant", ["focus", "saliency", "masked", "goal-action", "raw-stack", "oracle", "random-focus"]
)
def test_same_seed_gives_the_same_attended_observations(variant):
    first = rollout(make_env(variant), seed=11, steps=120)
    env = make_env(variant)
    rollout(env, seed=5, steps=40)  # a different episode first: the reset must clear all state
    second = rollout(env, seed=11, steps=120)
    np.testing.assert_array_equal(first, second)


def test_the_attention_config_may_be_a_mapping_of_some_of_its_fields():
    """``attention={"free_space_evidence": True}`` (as JSON's ``--env-kwargs`` gives it) builds the
    model's configuration with the other fields at their defaults; an unknown field is refused
    by name before anything is built."""
    env = make_env("focus", attention={"free_space_evidence": True, "track_onset_speed_sigma_mps": 1.0})
    config = env.model.config
    assert config.free_space_evidence and config.track_onset_speed_sigma_mps == 1.0
    assert config.range_noise_rel == 0.05
    with pytest.raises(ValueError, match=r"unknown AttentionConfig field\(s\) \['free_space'\]"):
        make_env("focus", attention={"free_space": True})


def test_the_episode_goal_becomes_the_models_goal_at_every_reset():
    env = make_env("focus")
    goal = Goal.smaller("speed", 0.3)
    obs, _ = env.reset(seed=0, options={"goal": goal})
    assert env.model.goals == (goal,)
    np.testing.assert_array_equal(obs["goal"], goal.encode())
    env.reset(seed=1, options={"goal": Goal.between("speed", 0.5, 0.9)})
    assert env.model.goals == (Goal.between("speed", 0.5, 0.9),)


def test_info_carries_the_attention_output_of_the_step():
    env = make_env("saliency")
    env.reset(seed=0)
    _, _, _, _, info = env.step(np.zeros(2, np.float32))
    assert info["attention"] is env.last_output
    assert info["attention"].t == pytest.approx(info["time_s"])


def test_pickled_wrapper_continues_identically():
    env = make_env("focus")
    rollout(env, seed=2, steps=30)
    clone = pickle.loads(pickle.dumps(env))
    actions = np.random.default_rng(1).uniform(-1, 1, (40, 2)).astype(np.float32)
    for action in actions:
        a, b = env.step(action)[0], clone.step(action)[0]
        for key in a:
            np.testing.assert_array_equal(a[key], b[key])


def test_goal_action_chooses_goal_and_weights_each_step():
    env = make_env("goal-action")
    k = len(DEFAULT_GOAL_MENU)
    assert env.action_space.shape == (2 + k + 6,)
    env.reset(seed=0)
    action = np.zeros(env.action_space.shape, np.float32)
    action[2 + 3] = 1.0  # the fourth goal of the menu
    action[2 + k :] = [1.0, -1.0, 0.0, 1.0, -1.0, -1.0]
    env.step(action)
    attention = env.env
    assert attention.model.goals == (DEFAULT_GOAL_MENU[3],)
    assert dict(attention.model.weights) == pytest.approx(
        {"F1": 2.0, "F2": 0.0, "F3": 1.0, "F4": 2.0, "F5": 0.0, "F6": 0.0}
    )
    action[2 : 2 + k] = 0.0
    action[2] = 1.0  # "no goal"
    env.step(action)
    assert attention.model.goals == ()
    env.reset(seed=1, options={"goal": Goal.smaller("speed", 0.3)})
    assert attention.model.goals == (Goal.smaller("speed", 0.3),)  # back to the task's goal
    assert dict(attention.model.weights) == {f"F{i}": 1.0 for i in range(1, 7)}


def test_goal_action_episodes_start_with_the_weights_it_was_made_with():
    env = make_env("goal-action", weights={"F1": 2.0, "F4": 1.0})
    made_with = {"F1": 2.0, "F2": 0.0, "F3": 0.0, "F4": 1.0, "F5": 0.0, "F6": 0.0}
    for seed in (0, 1):
        env.reset(seed=seed)
        assert dict(env.env.model.weights) == made_with  # not the configuration's defaults
        env.step(np.ones(env.action_space.shape, np.float32))
        assert dict(env.env.model.weights) == {f"F{i}": 2.0 for i in range(1, 7)}  # the action sets them


@pytest.mark.parametrize(
    "bad",
    [
        np.zeros(2),
        np.full(14, np.nan),
        np.zeros((2, 14)),
        np.zeros(14, complex),
        np.array([object()] * 14),
        {"a": 1},
        ["a"] * 14,
    ],
)
def test_goal_action_rejects_malformed_actions(bad):
    env = make_env("goal-action")
    env.reset(seed=0)
    with pytest.raises(ValueError, match="action must"):
        env.step(bad)


def test_stacked_readings_shift_oldest_first():
    env = make_env("raw-stack", n_frames=3)
    obs, _ = env.reset(seed=0)
    first = obs["laser"][:180].copy()
    np.testing.assert_array_equal(obs["laser"], np.tile(first, 3))  # filled with the first reading
    obs, *_ = env.step(np.array([1.0, 0.0], np.float32))
    np.testing.assert_array_equal(obs["laser"][:360], np.tile(first, 2))
    np.testing.assert_array_equal(obs["laser"][360:], env.unwrapped._reading.laser.astype(np.float32))
    assert obs["goal"].shape == (13,)


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: make_env("attended"), "unknown variant"),
        (lambda: make_env("raw", weights={"F1": 1.0}), "has no attention"),
        (lambda: AttentionWrapper(make_env("raw"), "focused"), "unknown observation mode"),
        (lambda: AttentionWrapper(gym.make("CartPole-v1")), "needs a Dict observation"),
        (lambda: make_env("raw-stack", n_frames=1), "n_frames must be"),
        (lambda: make_env("goal-action", goal_menu=()), "goal_menu"),
        (lambda: make_env("focus", weights={"F9": 1.0}), "F9"),
        (lambda: make_env("focus", version=4), r"unknown model version 4; allowed: \[0, 1, 2, 3\]"),
        (lambda: make_env("focus", version=True), r"unknown model version True; allowed: \[0, 1, 2, 3\]"),
        (lambda: AttentionWrapper(make_env("raw"), version=1.0), r"unknown model version 1.0; allowed"),
        (lambda: RunSpec(variant="focus", env_version=-1), r"unknown env_version -1; allowed: \[0, 1, 2, 3\]"),
    ],
)
def test_bad_configuration_is_refused_with_a_clear_error(call, message):
    with pytest.raises(ValueError, match=message):
        call()


def test_render_overlays_the_focus_on_the_world():
    env = make_env("focus", scenario="exp01", sensor_noise=0.0, render_mode="rgb_array")
    env.reset(seed=0)
    for _ in range(12):
        _, _, _, _, info = env.step(np.zeros(2, np.float32))
    assert info["attention"].focus is not None
    attended = env.render()
    env.unwrapped.render_overlay = None
    plain = env.unwrapped.render()

    def outlined(frame):
        return (np.all(frame == (255, 120, 0), axis=-1) | np.all(frame == (200, 0, 200), axis=-1)).sum()

    assert attended.shape == plain.shape
    assert outlined(attended) > 50 and outlined(plain) == 0


@pytest.mark.parametrize(
    "wrap",
    [
        lambda env: StackedReadings(env, n_frames=3),
        lambda env: AttentionWrapper(env, "focus", memory_slots=2, selection="random"),
        lambda env: GoalActionWrapper(AttentionWrapper(env, "focus", weights={"F4": 1.0})),
        lambda env: OracleFocus(env, memory_slots=1),
    ],
)
def test_a_wrapped_environments_spec_rebuilds_it(wrap):
    """The wrappers record their constructor arguments: gym.make(env.spec) gives the same env."""
    env = wrap(gym.make("AttentiveRescue-v0", scenario="exp04", sensor_noise=0.02))
    assert all(wrapper.kwargs is not None for wrapper in env.spec.additional_wrappers)
    rebuilt = gym.make(env.spec)
    assert rebuilt.observation_space == env.observation_space
    first, again = env.reset(seed=4)[0], rebuilt.reset(seed=4)[0]
    for _ in range(30):
        action = env.action_space.sample()
        first, *_ = env.step(action)
        again, *_ = rebuilt.step(action)
    for key in first:
        np.testing.assert_array_equal(first[key], again[key])
