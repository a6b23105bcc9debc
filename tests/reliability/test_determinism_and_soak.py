"""Determinism across processes, pickling and vector envs; invariants; a short soak.

Complements tests/envs: those compare two in-process rollouts, pickle a fresh-ish env once,
and compare make_vec to single envs on a few observation keys. Here: a spawned process
against this one, pickling at several points of an episode (and of the model), and
async against sync vector envs on every output, across episode boundaries.
"""

import multiprocessing
import pickle
import sys

import gymnasium as gym
import numpy as np
import pytest

import attentive_gym  # noqa: F401  (registers the environments)
from attentive_gym.attention import AttentionConfig, AttentionModel, Goal
from attentive_gym.envs.invariants import check_invariants
from attentive_gym.envs.rescue_env import AttentiveRescueEnv
from support import BENCHMARKS, assert_same


def trajectory(scenario: str, seed: int, steps: int) -> list:
    """Everything a seeded random rollout returns (obs, reward, flags, positions), resets included."""
    env = AttentiveRescueEnv(scenario)
    rng = np.random.default_rng(seed)
    obs, info = env.reset(seed=seed)
    out = [(obs, info["robot_pose"], info["mover_positions"])]
    for _ in range(steps):
        obs, reward, terminated, truncated, info = env.step(rng.uniform(-1, 1, 2).astype(np.float32))
        out.append(
            (obs, reward, terminated, truncated, info["robot_pose"], info["mover_positions"], info["target_distance_m"])
        )
        if terminated or truncated:
            obs, info = env.reset()
            out.append((obs, info["robot_pose"], info["mover_positions"]))
    return out


def _trajectory_bytes(args) -> bytes:
    return pickle.dumps(trajectory(*args))


def test_spawned_process_reproduces_the_in_process_trajectory_bit_for_bit():
    cases = [("rescue", 3, 150), ("exp03", 7, 120)]
    with multiprocessing.get_context("spawn").Pool(1) as pool:
        remote = pool.map(_trajectory_bytes, cases)
    for case, data in zip(cases, remote):
        assert_same(pickle.loads(data), trajectory(*case))


_WARM_START_BUG = pytest.mark.xfail(
    strict=True,
    reason=(
        "open bug found here: a pickled World loses pymunk's warm-start state (accumulated joint and "
        "contact impulses are not pickled), so the copy's odometry differs from the original's by ~1e-17 "
        "a few steps later; see docs/reliability.md"
    ),
)


@pytest.mark.parametrize(
    "scenario, at",
    [
        ("rescue", [0, 37]),
        # the drive's joints carry impulses from the first step on: a copy made then drifts at once
        pytest.param("rescue", [1], marks=_WARM_START_BUG),
        pytest.param("exp05", [5, 90], marks=_WARM_START_BUG),
    ],
)
def test_pickled_env_mid_episode_continues_identically(scenario, at):
    env = AttentiveRescueEnv(scenario)
    env.reset(seed=2)
    rng = np.random.default_rng(0)
    actions = rng.uniform(-1, 1, (150, 2)).astype(np.float32)
    clones = {}
    for i, action in enumerate(actions):
        if i in at:
            clones[i] = pickle.loads(pickle.dumps(env))
        result = env.step(action)
        for clone in clones.values():
            other = clone.step(action)
            assert_same(result[:4], other[:4])
            assert_same(result[4]["robot_pose"], other[4]["robot_pose"])
            assert_same(result[4]["mover_positions"], other[4]["mover_positions"])
        if result[2] or result[3]:
            seed = 100 + i
            env.reset(seed=seed)
            for clone in clones.values():
                clone.reset(seed=seed)


def test_pickled_attention_model_continues_identically():
    env = AttentiveRescueEnv("exp04")
    obs, _ = env.reset(seed=0)
    model = AttentionModel(AttentionConfig())
    model.set_goals(Goal.between("speed", 0.5, 0.9), Goal.smaller("distance", 3.0))
    model.set_weights(F1=1.0, F3=0.5, F4=2.0, F6=1.0)
    model.set_state("vigilant")
    feed = []
    for k in range(120):
        obs, _, _, _, info = env.step(np.array([0.3, 0.1 * np.sin(k / 9)], np.float32))
        feed.append((info["time_s"], obs["sonar"], obs["laser"], obs["odometry"]))
    for t, sonar, laser, odometry in feed[:40]:
        model.step(t, sonar, laser, odometry)
    clone = pickle.loads(pickle.dumps(model))
    fired = 0
    for t, sonar, laser, odometry in feed[40:]:
        a, b = model.step(t, sonar, laser, odometry), clone.step(t, sonar, laser, odometry)
        assert a == b and a.focus == b.focus and a.fired == b.fired
        fired += a.fired
    assert fired > 0  # the continuation exercised the courses, not only quiet steps


def test_async_vector_env_equals_sync_on_every_output_across_resets():
    kwargs = {"num_envs": 2, "time_limit_s": 2.0}
    sync = gym.make_vec("attentive_gym:AttentiveRescue-v0", vectorization_mode="sync", **kwargs)
    async_ = gym.make_vec(
        "attentive_gym:AttentiveRescue-v0", vectorization_mode="async", vector_kwargs={"context": "spawn"}, **kwargs
    )
    try:
        rng = np.random.default_rng(0)
        assert_same(sync.reset(seed=[5, 6])[0], async_.reset(seed=[5, 6])[0])
        resets = 0
        for _ in range(60):  # 2 s episodes at dt 0.05: each env resets (autoreset) at least once
            actions = rng.uniform(-1, 1, (2, 2)).astype(np.float32)
            a, b = sync.step(actions), async_.step(actions)
            assert_same(a[:4], b[:4])
            for key in ("robot_pose", "mover_positions", "time_s"):
                assert_same(a[4][key], b[4][key])
            resets += int(np.sum(a[3]))
        assert resets >= 2
    finally:
        sync.close()
        async_.close()


# --- invariants ----------------------------------------------------------------------------
def test_invariants_hold_on_a_normal_episode_and_catch_planted_faults():
    env = AttentiveRescueEnv()
    obs, _ = env.reset(seed=0)
    model = AttentionModel()
    output = model.step(0.0, obs["sonar"], obs["laser"], obs["odometry"])
    assert check_invariants(env, obs, output) == []
    # a NaN reading, a reading beyond the sensor, a robot teleported into a wall, a runaway spin
    bad = {**obs, "laser": obs["laser"].copy()}
    bad["laser"][3] = np.nan
    assert any("laser" in v and "finite" in v for v in check_invariants(env, bad))
    bad["laser"][3] = 25.0
    assert any("laser" in v for v in check_invariants(env, bad))
    body = env.world.robot.body
    body.position = (0.0, env.scenario.bounds[3] / 2)  # centred on the enclosure's left wall
    env.world.space.reindex_shapes_for_body(body)
    assert any("inside a wall" in v for v in check_invariants(env, obs))
    body.position = (5.0, 5.0)
    env.world.space.reindex_shapes_for_body(body)
    body.angular_velocity = 50.0
    assert any("turn rate" in v for v in check_invariants(env, obs, contact=False))


@pytest.mark.slow
def test_short_soak_has_no_violations():
    benchmarks = str(BENCHMARKS)
    sys.path.insert(0, benchmarks)  # the spawned workers import ``soak`` too: keep it on the path
    try:
        import soak

        summary = soak.soak(steps=3300, workers=2, chunk=300)
    finally:
        sys.path.remove(benchmarks)
    assert summary["steps"] == 3300 and summary["episodes"] >= 11
    assert summary["violations"] == 0, summary["examples"]
    assert set(summary["per_config"]) == {label for label, _ in soak.CONFIGS}
