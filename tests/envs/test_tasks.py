"""The task's versions: their rewards, the proximity entry, and the registered ids that build them."""

import gymnasium as gym
import numpy as np
import pytest

import attentive_gym  # noqa: F401  (registers the ids)
from attentive_gym.attention import MODEL_VERSIONS
from attentive_gym.envs.reward import RewardConfig
from attentive_gym.envs.tasks import TASK_VERSIONS, check_task_version, task_proximity, task_reward
from attentive_gym.registration import EARLIER_IDS, ID_VERSIONS, MODEL_VARIANTS, VARIANT_IDS
from attentive_gym.wrappers.variants import FOCUS_LAYOUT, make_env

SAFE = RewardConfig(contact_limit_s=1.0, near_per_s=4.0)
SMALL = {"arena_size_m": 8.0, "num_distractors": 2, "rubble_per_100m2": 3.0}


def test_each_version_has_its_reward_and_proximity():
    assert TASK_VERSIONS[-1] == 1
    assert task_reward(0) == RewardConfig() and task_reward(1) == SAFE
    assert not task_proximity(0) and task_proximity(1)


def test_a_reward_mapping_sets_its_fields_over_the_versions_defaults_and_a_config_is_taken_whole():
    assert task_reward(1, {"collision_per_s": 10}) == RewardConfig(
        collision_per_s=10, contact_limit_s=1.0, near_per_s=4.0
    )
    assert task_reward(1, {"contact_limit_s": None}) == RewardConfig(near_per_s=4.0)
    assert task_reward(0, {"near_per_s": 1.0}) == RewardConfig(near_per_s=1.0)
    assert task_reward(1, RewardConfig()) == RewardConfig()


@pytest.mark.parametrize("version", [2, -1, 1.0, True, "1", None])
def test_an_unknown_version_is_refused_with_the_known_ones(version):
    with pytest.raises(ValueError, match=r"task must be one of the task versions \[0, 1\], got"):
        check_task_version(version)
    with pytest.raises(ValueError, match="task must be one of the task versions"):
        make_env("raw", task=version)


def test_a_bad_reward_field_is_named_under_every_version():
    with pytest.raises(ValueError, match=r"RewardConfig has no field\(s\) \['colision_per_s'\]"):
        make_env("raw", task=1, reward={"colision_per_s": 1})


@pytest.mark.parametrize("variant", ["focus", "raw"])
def test_version_1_is_version_0_with_the_safe_reward_and_proximity_step_for_step(variant):
    """The safe task is exactly the first task with its fields given: the same observations,
    rewards and endings for the same actions, bit for bit."""
    proximity = {"proximity": True} if variant in FOCUS_LAYOUT else {}
    safe = make_env(variant, task=1, **SMALL)
    spelled_out = make_env(variant, task=0, reward={"contact_limit_s": 1.0, "near_per_s": 4.0}, **proximity, **SMALL)
    rng = np.random.default_rng(3)
    obs_a, _ = safe.reset(seed=11)
    obs_b, _ = spelled_out.reset(seed=11)
    ended = 0
    for _ in range(300):
        action = rng.uniform(-1.0, 1.0, 2).astype(np.float32)
        obs_a, r_a, term_a, trunc_a, info_a = safe.step(action)
        obs_b, r_b, term_b, trunc_b, info_b = spelled_out.step(action)
        assert obs_a.keys() == obs_b.keys()
        for key in obs_a:
            np.testing.assert_array_equal(obs_a[key], obs_b[key])
        assert (r_a, term_a, trunc_a, info_a["contact_s"]) == (r_b, term_b, trunc_b, info_b["contact_s"])
        if term_a or trunc_a:
            ended += 1
            obs_a, _ = safe.reset(seed=11 + ended)
            obs_b, _ = spelled_out.reset(seed=11 + ended)
    assert ("proximity" in obs_a) == (variant in FOCUS_LAYOUT)


def test_an_episode_of_version_1_ends_after_a_second_of_contact_and_one_of_version_0_does_not():
    """In a crowded arena, driving ahead: version 1 terminates without success at the first step
    past 1 s of contact; version 0 goes on past it."""
    crowded = {"arena_size_m": 7.0, "num_distractors": 4, "rubble_per_100m2": 15.0}
    for task in (1, 0):
        env = make_env("raw", task=task, **crowded)
        env.reset(seed=3)
        rng = np.random.default_rng(3)
        for _ in range(400):
            _, _, terminated, truncated, info = env.step(np.array([1.0, rng.uniform(-0.3, 0.3)], np.float32))
            if terminated or truncated or info["contact_s"] > 1.5:
                break
        if task == 1:
            assert terminated and not info["success"] and 1.0 < info["contact_s"] <= 1.0 + env.unwrapped.dt + 1e-9
        else:
            assert not terminated and info["contact_s"] > 1.5


def test_the_current_ids_build_the_latest_versions_and_the_earlier_ids_their_own():
    assert set(ID_VERSIONS) == set(VARIANT_IDS.values()) | set(EARLIER_IDS)
    for env_id, (variant, task, model) in ID_VERSIONS.items():
        assert gym.spec(env_id).kwargs == {"variant": variant, "task": task, "version": model}
        current = task == TASK_VERSIONS[-1] and (model == MODEL_VERSIONS[-1] or variant not in MODEL_VARIANTS)
        assert (env_id in VARIANT_IDS.values()) == current, env_id
    assert ID_VERSIONS["AttentiveRescue-v0"][1] == 0 and ID_VERSIONS["AttentiveRescueFocus-v1"][1:] == (0, 1)
    assert ID_VERSIONS["AttentiveRescueFocus-v2"][1:] == (1, 1) and ID_VERSIONS["AttentiveRescueFocus-v3"][1:] == (1, 2)
    assert ID_VERSIONS["AttentiveRescueFocus-v4"][1:] == (1, 3)
    assert VARIANT_IDS["raw"] == "AttentiveRescue-v1" and VARIANT_IDS["focus"] == "AttentiveRescueFocus-v4"
    current = gym.make(VARIANT_IDS["focus"])
    assert current.unwrapped.reward_config == SAFE and "proximity" in current.observation_space.spaces
    earlier = gym.make("AttentiveRescueFocus-v1")
    assert earlier.unwrapped.reward_config == RewardConfig() and "proximity" not in earlier.observation_space.spaces


def test_every_model_variant_has_an_id_per_model_version_on_the_first_task():
    for variant in MODEL_VARIANTS:
        versions = {model for v, task, model in ID_VERSIONS.values() if v == variant and task == 0}
        assert versions == {0, 1}, variant


def test_the_attended_ids_of_the_current_task_build_their_own_model_version():
    configs = {}
    for env_id in ("AttentiveRescueFocus-v2", "AttentiveRescueFocus-v3", "AttentiveRescueFocus-v4"):
        env = gym.make(env_id)
        configs[env_id[-2:]] = env.get_wrapper_attr("model").config
        env.close()
    assert configs["v2"].track_occlusion_keeps_motion is False
    assert configs["v3"].track_occlusion_keeps_motion is True and configs["v3"].track_onset_log_ratio == 0.0
    assert configs["v4"].track_onset_log_ratio == 6.0

    def differ(a, b):
        return {f for f in vars(configs[a]) if getattr(configs[a], f) != getattr(configs[b], f)}

    assert differ("v2", "v3") == {"track_occlusion_keeps_motion"}
    assert differ("v3", "v4") == {"track_onset_log_ratio"}
