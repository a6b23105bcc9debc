"""The native vector env (``vector_entry_point``) and SB3's ``NativeVecEnv``: same numbers as the
sync vector env / ``DummyVecEnv`` over single envs, Gymnasium's semantics, clear errors."""

import pickle
import subprocess
import sys
import time

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.vector import AutoresetMode, SyncVectorEnv

import attentive_gym  # noqa: F401  (registers the ids)
from attentive_gym.vector import AttentiveRescueVectorEnv, Fleet, batch_infos, make_vector_env
from attentive_gym.wrappers import VARIANT_IDS, VARIANTS, make_env

SHORT = {"time_limit_s": 1.0, "arena_size_m": 8.0, "num_distractors": 2}  # 20-step episodes: many autoresets


def _native(variant, num_envs=3, **kwargs):
    return gym.make_vec(
        VARIANT_IDS[variant], num_envs=num_envs, vectorization_mode="vector_entry_point", **{**SHORT, **kwargs}
    )


def _sync(variant, num_envs=3, **kwargs):
    return gym.make_vec(VARIANT_IDS[variant], num_envs=num_envs, vectorization_mode="sync", **{**SHORT, **kwargs})


def _assert_same_tree(a, b, where=""):
    """Equal batched observations or infos; object arrays (e.g. the attention output) by type and mask."""
    if isinstance(a, dict):
        assert set(a) == set(b), f"{where}: keys differ: {set(a) ^ set(b)}"
        for key in a:
            _assert_same_tree(a[key], b[key], f"{where}/{key}")
    elif isinstance(a, tuple):
        assert isinstance(b, tuple) and len(a) == len(b), where
        for k, (x, y) in enumerate(zip(a, b)):
            _assert_same_tree(x, y, f"{where}[{k}]")
    elif isinstance(a, np.ndarray) and a.dtype == object:
        assert b.dtype == object and a.shape == b.shape, where
        for x, y in zip(a, b):
            if isinstance(x, (dict, np.ndarray)):
                _assert_same_tree(x, y, where)
            else:
                assert type(x) is type(y), where
    else:
        a, b = np.asarray(a), np.asarray(b)
        assert a.dtype == b.dtype and a.shape == b.shape, f"{where}: {a.dtype}{a.shape} vs {b.dtype}{b.shape}"
        assert np.array_equal(a, b), where


def _run_both(native, sync, steps, seed=11):
    observations, infos = native.reset(seed=seed)
    expected = sync.reset(seed=seed)
    _assert_same_tree(observations, expected[0], "reset obs")
    _assert_same_tree(infos, expected[1], "reset info")
    rng = np.random.default_rng(seed)
    ended = 0
    for t in range(steps):
        actions = rng.uniform(-1, 1, native.action_space.shape).astype(np.float32)
        got, want = native.step(actions), sync.step(actions)
        for k, name in enumerate(("obs", "reward", "terminated", "truncated", "info")):
            _assert_same_tree(got[k], want[k], f"step {t} {name}")
        ended += int(np.sum(got[2] | got[3]))
    return ended


@pytest.mark.parametrize("variant", VARIANTS)
def test_native_equals_sync_bit_for_bit_over_resets_and_autoresets(variant):
    native, sync = _native(variant), _sync(variant)
    assert isinstance(native.unwrapped, AttentiveRescueVectorEnv)
    assert native.single_observation_space == sync.single_observation_space
    assert native.observation_space == sync.observation_space and native.action_space == sync.action_space
    ended = _run_both(native, sync, steps=45)
    assert ended >= 6  # every env ended (and was reset) at least twice
    native.close(), sync.close()


def test_a_safe_task_with_geodesic_progress_matches_sync():
    """The reward's options (geodesic progress, the contact limit, the near penalty) and the
    proximity entry give the same numbers in the fleet as in single envs."""
    task = {"reward": {"progress": "geodesic", "contact_limit_s": 0.2, "near_per_s": 4.0}, "proximity": True}
    assert _run_both(_native("oracle", **task), _sync("oracle", **task), steps=45) >= 6


def test_same_step_autoreset_matches_sync():
    native = make_vector_env(3, "focus", autoreset_mode="SameStep", **SHORT)
    sync = SyncVectorEnv([lambda: make_env("focus", **SHORT) for _ in range(3)], autoreset_mode=AutoresetMode.SAME_STEP)
    assert native.metadata["autoreset_mode"] == AutoresetMode.SAME_STEP
    assert _run_both(native, sync, steps=25) >= 3


def test_disabled_autoreset_needs_a_masked_reset_and_matches_sync():
    native = make_vector_env(2, "raw", autoreset_mode=AutoresetMode.DISABLED, **SHORT)
    sync = SyncVectorEnv([lambda: make_env("raw", **SHORT) for _ in range(2)], autoreset_mode=AutoresetMode.DISABLED)
    native.reset(seed=0), sync.reset(seed=0)
    actions = np.full((2, 2), 0.3, np.float32)
    for _ in range(20):
        _assert_same_tree(native.step(actions), sync.step(actions))
    with pytest.raises(RuntimeError, match=r"env\(s\) \[0, 1\] ended"):
        native.step(actions)
    mask = np.array([True, False])
    _assert_same_tree(native.reset(options={"reset_mask": mask}), sync.reset(options={"reset_mask": mask.copy()}))


def test_max_episode_steps_truncates_as_gym_make_does_and_float64_actions_stay_exact():
    native = _native("focus", num_envs=2, max_episode_steps=7)
    sync = _sync("focus", num_envs=2, max_episode_steps=7)
    native.reset(seed=3), sync.reset(seed=3)
    rng = np.random.default_rng(3)
    truncations = 0
    for t in range(30):
        actions = rng.uniform(-1, 1, (2, 2))  # float64, as sync passes them on
        got, want = native.step(actions), sync.step(actions)
        for key in ("TimeLimit.truncated", "_TimeLimit.truncated"):  # rl_zoo3, once imported, patches TimeLimit
            want[4].pop(key, None)
        for k, name in enumerate(("obs", "reward", "terminated", "truncated", "info")):
            _assert_same_tree(got[k], want[k], f"step {t} {name}")
        truncations += int(got[3].sum())
    assert truncations >= 6  # 7-step episodes, well inside the 20-step time limit
    by_spec = gym.make_vec(
        gym.make(VARIANT_IDS["raw"], max_episode_steps=4, **SHORT).spec, 1, vectorization_mode="vector_entry_point"
    )
    by_spec.reset(seed=0)
    assert [by_spec.step(np.zeros((1, 2)))[3][0] for _ in range(4)] == [False, False, False, True]
    for bad in (0, 2.5, True):
        with pytest.raises(ValueError, match="max_episode_steps must be an integer >= 1"):
            make_vector_env(1, "raw", max_episode_steps=bad)


def test_integer_seed_seeds_env_i_with_seed_plus_i_and_none_differs():
    a = make_vector_env(3, "raw", **SHORT)
    b = make_vector_env(3, "raw", **SHORT)
    obs_int, _ = a.reset(seed=20)
    obs_list, _ = b.reset(seed=[20, 21, 22])
    _assert_same_tree(obs_int, obs_list)
    single = make_env("raw", **SHORT)
    np.testing.assert_array_equal(single.reset(seed=21)[0]["laser"], obs_int["laser"][1])
    assert not np.array_equal(obs_int["laser"][0], obs_int["laser"][1])
    with pytest.raises(ValueError, match="one per env"):
        a.reset(seed=[1, 2])


_TRAJECTORY_DIGEST = """
import hashlib, numpy as np, gymnasium as gym, attentive_gym
env = gym.make_vec("AttentiveRescueFocus-v1", num_envs=3, vectorization_mode="vector_entry_point", time_limit_s=1.0)
digest = hashlib.sha256()
obs, _ = env.reset(seed=5)
rng = np.random.default_rng(0)
for _ in range(30):
    obs, reward, terminated, truncated, _ = env.step(rng.uniform(-1, 1, (3, 2)).astype(np.float32))
    for array in (*obs.values(), reward, terminated, truncated):
        digest.update(np.ascontiguousarray(array).tobytes())
print(digest.hexdigest())
"""


@pytest.mark.slow
def test_same_seed_same_trajectory_in_another_process():
    runs = [
        subprocess.run([sys.executable, "-c", _TRAJECTORY_DIGEST], capture_output=True, text=True, check=True)
        for _ in range(2)
    ]
    namespace = {}
    exec(_TRAJECTORY_DIGEST.replace("print(digest.hexdigest())", "result = digest.hexdigest()"), namespace)
    assert runs[0].stdout.strip() == runs[1].stdout.strip() == namespace["result"]


def test_pickled_vector_env_continues_identically():
    env = make_vector_env(2, "focus", **SHORT)
    env.reset(seed=3)
    actions = np.random.default_rng(0).uniform(-1, 1, (10, 2, 2)).astype(np.float32)
    for a in actions[:4]:
        env.step(a)
    clone = pickle.loads(pickle.dumps(env))
    for a in actions[4:]:
        _assert_same_tree(env.step(a)[:4], clone.step(a)[:4])


def test_bad_input_raises_a_clear_value_error_and_moves_nothing():
    env = make_vector_env(3, "raw", **SHORT)
    with pytest.raises(RuntimeError, match="reset"):
        env.step(np.zeros((3, 2), np.float32))
    env.reset(seed=1)
    twin = make_vector_env(3, "raw", **SHORT)
    twin.reset(seed=1)
    with pytest.raises(ValueError, match=r"shape \(3, 2\).*got shape \(2, 2\)"):
        env.step(np.zeros((2, 2), np.float32))
    bad = np.zeros((3, 2), np.float32)
    bad[2, 1] = np.nan
    with pytest.raises(ValueError, match=r"finite; env\(s\) \[2\]"):
        env.step(bad)
    with pytest.raises(ValueError, match="numeric"):
        env.step([["a", "b"]] * 3)
    good = np.full((3, 2), 0.5, np.float32)
    _assert_same_tree(env.step(good)[:4], twin.step(good)[:4])  # the refused steps moved no env
    for num_envs in (0, -2, 1.5, True, "4"):
        with pytest.raises(ValueError, match="num_envs must be an integer >= 1"):
            make_vector_env(num_envs, "raw")
    with pytest.raises(ValueError, match="unknown autoreset_mode"):
        make_vector_env(1, "raw", autoreset_mode="sometimes")
    with pytest.raises(ValueError, match="reset_mask"):
        env.reset(options={"reset_mask": np.zeros(3, np.bool_)})


def test_fleet_refuses_wrappers_it_cannot_step_and_other_envs():
    with pytest.raises(ValueError, match="TransformReward cannot be stepped in a fleet"):
        Fleet([gym.wrappers.TransformReward(make_env("raw"), lambda r: 2 * r)])

    class OwnStep(gym.ActionWrapper):  # an action wrapper with a step of its own and no observe_step
        def action(self, action):
            return action

        def step(self, action):
            return self.env.step(self.action(action))

    with pytest.raises(ValueError, match="OwnStep cannot be stepped in a fleet"):
        Fleet([OwnStep(make_env("raw"))])
    with pytest.raises(ValueError, match="PendulumEnv, which lacks the stages a fleet steps"):
        Fleet([gym.make("Pendulum-v1").unwrapped])
    with pytest.raises(ValueError, match="other sensors"):
        Fleet([make_env("raw"), make_env("raw", sensor_noise=0.0)])
    with pytest.raises(ValueError, match="observation space differs"):
        Fleet([make_env("raw"), make_env("focus")])
    with pytest.raises(ValueError, match="at least one"):
        Fleet([])


def test_flattened_members_step_in_a_fleet():
    native = AttentiveRescueVectorEnv([make_env("focus", flatten=True, **SHORT) for _ in range(2)])
    sync = SyncVectorEnv([lambda: make_env("focus", flatten=True, **SHORT) for _ in range(2)])
    _run_both(native, sync, steps=25)


@pytest.mark.parametrize("flatten", [False, True])
def test_without_copy_the_batch_is_the_envs_own_buffer_with_syncs_numbers(flatten):
    native = AttentiveRescueVectorEnv([make_env("focus", flatten=flatten, **SHORT) for _ in range(2)], copy=False)
    sync = SyncVectorEnv([lambda: make_env("focus", flatten=flatten, **SHORT) for _ in range(2)])
    first, _ = native.reset(seed=2)
    _assert_same_tree(first, sync.reset(seed=2)[0])
    rng = np.random.default_rng(2)
    for _ in range(25):  # over an autoreset
        actions = rng.uniform(-1, 1, native.action_space.shape).astype(np.float32)
        observation = native.step(actions)[0]
        assert observation is first  # the same buffer, overwritten
        _assert_same_tree(observation, sync.step(actions)[0])


def test_render_draws_env_0_and_info_keeps_every_single_env_key():
    env = make_vector_env(2, "focus", render_mode="rgb_array", **SHORT)
    _, info = env.reset(seed=0)
    frame = env.render()
    assert frame.ndim == 3 and frame.shape[2] == 3 and frame.dtype == np.uint8
    _, _, _, _, info = env.step(np.zeros((2, 2), np.float32))
    single = make_env("focus", **SHORT)
    single.reset(seed=0)
    keys = set(single.step(np.zeros(2, np.float32))[4])
    assert keys <= set(info) and all(info[f"_{k}"].all() for k in keys)
    assert info["attention"][1].t == pytest.approx(0.05) and info["robot_pose"].shape == (2, 3)


def test_batch_infos_equals_gymnasium_add_info():
    rng = np.random.default_rng(0)
    entries = [
        (0, {"a": 1.5, "n": 3, "flag": True, "v": rng.normal(size=2), "obj": "x", "d": {"inner": 2.0}}),
        (2, {"a": 2.5, "n": 4, "flag": False, "v": rng.normal(size=2), "obj": (1, 2), "only2": np.float32(1)}),
        (2, {"final_obs": {"o": np.ones(2)}, "final_info": {"a": 1.0}}),
    ]
    reference = SyncVectorEnv([lambda: make_env("raw") for _ in range(3)])
    expected = {}
    for i, info in entries:
        expected = reference._add_info(expected, info, i)
    _assert_same_tree(batch_infos(entries, 3), expected)
    # every member once, in order, with the same keys (a step without resets): the fast path
    full = [
        (
            i,
            {
                "a": float(i),
                "n": i,
                "flag": i == 1,
                "v": rng.normal(size=(2, 2)).astype(np.float32 if i else np.float64),
                "obj": ("x",) * i,
                "d": {"inner": np.arange(i, i + 3)},
            },
        )
        for i in range(3)
    ]
    expected = {}
    for i, info in full:
        expected = reference._add_info(expected, info, i)
    _assert_same_tree(batch_infos(full, 3), expected)
    assert batch_infos(full, 3)["v"].dtype == np.float64 and batch_infos(full, 3)["d"]["inner"].shape == (3, 3)
    assert batch_infos(full, 3)["obj"].tolist() == [(), ("x",), ("x", "x")]  # each tuple one element
    # the same keys in another order in one member: batched as Gymnasium does too
    shuffled = [(i, dict(reversed(info.items())) if i == 1 else info) for i, info in full]
    expected = {}
    for i, info in shuffled:
        expected = reference._add_info(expected, info, i)
    _assert_same_tree(batch_infos(shuffled, 3), expected)
    assert batch_infos(shuffled, 3)["obj"].tolist() == [(), ("x",), ("x", "x")]


# --- SB3 ----------------------------------------------------------------------------------
def test_native_vec_env_equals_dummy_vec_env_over_monitor():
    from stable_baselines3.common.monitor import Monitor
    from stable_baselines3.common.vec_env import DummyVecEnv

    from attentive_gym.vector.sb3 import NativeVecEnv

    dummy = DummyVecEnv([lambda: Monitor(make_env("focus", **SHORT), info_keywords=("success",)) for _ in range(2)])
    native = NativeVecEnv([make_env("focus", **SHORT) for _ in range(2)], info_keywords=("success",))
    dummy.seed(4), native.seed(4)
    _assert_same_tree(dummy.reset(), native.reset())
    rng = np.random.default_rng(2)
    episodes = 0
    for _ in range(45):
        actions = rng.uniform(-1, 1, (2, 2)).astype(np.float32)
        want, got = dummy.step(actions), native.step(actions)
        for k in range(3):
            _assert_same_tree(got[k], want[k])
        for a, b in zip(got[3], want[3]):
            assert set(a) == set(b) and a["TimeLimit.truncated"] == b["TimeLimit.truncated"]
            if "episode" in b:
                episodes += 1
                assert {k: a["episode"][k] for k in ("r", "l", "success")} == {
                    k: b["episode"][k] for k in ("r", "l", "success")
                }
                _assert_same_tree(a["terminal_observation"], b["terminal_observation"])
    assert episodes >= 4
    last = [info["episode"]["t"] for info in got[3] if "episode" in info]
    elapsed = time.time() - native._t_start
    assert all(0.0 <= t <= elapsed for t in last)  # Monitor's clock: seconds since the env was built
    assert native.env_is_wrapped(Monitor) == [False, False] and native.get_attr("mode") == ["focus", "focus"]
    with pytest.raises(ValueError, match="finite"):
        native.step(np.full((2, 2), np.inf, np.float32))


def test_ppo_learns_the_same_policy_on_native_and_dummy_vec_envs():
    import torch
    from stable_baselines3 import PPO
    from stable_baselines3.common.monitor import Monitor
    from stable_baselines3.common.vec_env import DummyVecEnv

    from attentive_gym.vector.sb3 import NativeVecEnv

    torch.set_num_threads(1)
    kwargs = dict(n_steps=32, batch_size=32, n_epochs=1, seed=0, device="cpu")
    parameters = []
    for vec in (
        DummyVecEnv([lambda: Monitor(make_env("raw", **SHORT)) for _ in range(2)]),
        NativeVecEnv([make_env("raw", **SHORT) for _ in range(2)]),
    ):
        model = PPO("MultiInputPolicy", vec, **kwargs).learn(128)
        parameters.append(torch.nn.utils.parameters_to_vector(model.policy.parameters()).detach().numpy())
    np.testing.assert_array_equal(parameters[0], parameters[1])
