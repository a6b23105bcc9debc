"""The batched info of a step built from the completed steps' arrays (``batch_step_infos``) equals
``batch_infos`` of the members' info dicts, and SyncVectorEnv's, in keys, order, dtypes and values."""

import gymnasium as gym
import numpy as np
import pytest

import attentive_gym  # noqa: F401  (registers the ids)
from attentive_gym.attention.goals import Goal
from attentive_gym.vector import batch_infos
from attentive_gym.vector.batching import batch_step_infos
from attentive_gym.wrappers import VARIANT_IDS

#: A crowded arena whose targets pursue or evade the robot (contacts, blocked movers), short
#: episodes (autoresets), and the usarsim profile (readings held between scans).
CROWDED = {
    "time_limit_s": 4.0,
    "arena_size_m": 7.0,
    "num_distractors": 4,
    "rubble_per_100m2": 15.0,
    "goals": (Goal.direction_is("towards"), Goal.direction_is("away")),
    "sensor_profile": "usarsim",
}


def _assert_identical(a, b, where=""):
    """Equal in keys and their order, types, dtypes, shapes and bytes; object entries by value
    (the attention output by type)."""
    if isinstance(a, dict):
        assert list(a) == list(b), f"{where}: keys {list(a)} vs {list(b)}"
        for key in a:
            _assert_identical(a[key], b[key], f"{where}/{key}")
    elif isinstance(a, np.ndarray):
        assert isinstance(b, np.ndarray) and a.dtype == b.dtype and a.shape == b.shape, where
        if a.dtype != object:
            assert a.tobytes() == b.tobytes(), where
        else:
            for x, y in zip(a, b):
                if isinstance(x, (tuple, str, np.ndarray)) or x is None:
                    _assert_identical(x, y, where)
                else:
                    assert type(x) is type(y), where
    elif isinstance(a, tuple):
        assert type(b) is tuple and len(a) == len(b), where
        for x, y in zip(a, b):
            _assert_identical(x, y, where)
    else:
        assert type(a) is type(b) and a == b, f"{where}: {a!r} vs {b!r}"


@pytest.mark.parametrize("variant", ["raw", "focus", "goal-action"])
def test_step_infos_from_arrays_equal_syncs_in_order_and_dtype(variant):
    native = gym.make_vec(VARIANT_IDS[variant], num_envs=3, vectorization_mode="vector_entry_point", **CROWDED)
    sync = gym.make_vec(VARIANT_IDS[variant], num_envs=3, vectorization_mode="sync", **CROWDED)
    for got, want in zip(native.reset(seed=4), sync.reset(seed=4)):
        _assert_identical(got, want, "reset")
    rng = np.random.default_rng(4)
    choices = np.random.default_rng(5)  # goal-action's goal scores and weights, beside the same motions
    extra = native.single_action_space.shape[0] - 2
    touched = ended = matched = 0
    for t in range(200):
        motions = rng.uniform((0.2, -1.0), (1.0, 1.0), (3, 2))
        actions = np.hstack([motions, choices.uniform(-1, 1, (3, extra))]).astype(np.float32)
        got, want = native.step(actions), sync.step(actions)
        for k, name in enumerate(("obs", "reward", "terminated", "truncated", "info")):
            _assert_identical(got[k], want[k], f"step {t} {name}")
        touched += int(got[4]["collision"][got[4]["_collision"]].sum())
        ended += int(np.sum(got[2] | got[3]))
        matched += int(got[4].get("goal_choice_matches", np.zeros(3, bool)).sum())
    assert touched > 0 and ended >= 3
    if variant == "goal-action":  # the agent's choice in every member's info, the task's goal among them
        assert {"goal_choice", "goal_choice_matches", "map_weights"} <= set(got[4]) and matched > 0
        assert got[4]["goal_choice"].dtype == np.int64 and got[4]["map_weights"].shape == (3, 6)
    native.close(), sync.close()


def test_step_infos_take_the_envs_keys_from_the_arrays_and_the_wrappers_keys_from_the_dicts():
    env = gym.make_vec(VARIANT_IDS["focus"], num_envs=2, vectorization_mode="vector_entry_point", **CROWDED)
    env.reset(seed=4)
    fleet = env.unwrapped._fleet
    results, completed = fleet.step([0, 1], np.zeros((2, 2)))
    infos = [result[4] for result in results]
    batched = batch_step_infos(infos, completed)
    _assert_identical(batched, batch_infos(list(enumerate(infos)), 2))
    assert batched["sonar_hits"] is completed.info["sonar_hits"]  # an array of the completion, not a restack
    assert list(batched)[-2:] == ["attention", "_attention"]
    _assert_identical(batch_step_infos(infos, None), batch_infos(list(enumerate(infos)), 2))
    env.close()
