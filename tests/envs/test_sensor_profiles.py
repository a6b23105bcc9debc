"""AttentiveRescue-v0's sensor settings: noise models, scan intervals, the "usarsim" profile."""

from __future__ import annotations

import copy
import math
import pickle

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import attentive_gym  # noqa: F401  (registers the environments)
from attentive_gym.envs.rescue_env import AttentiveRescueEnv
from attentive_gym.sensors import DEFAULT_SENSOR_PROFILE, SENSOR_PROFILES, SensorProfile
from support import assert_same

DT_S = 0.05
STEPS = 24
SONAR_MIN_M, SONAR_MAX_M, LASER_MAX_M = 0.15, 5.0, 20.0


def _actions(steps: int = STEPS, seed: int = 0) -> list[np.ndarray]:
    rng = np.random.default_rng(seed)
    return [rng.uniform(-1, 1, 2).astype(np.float32) for _ in range(steps)]


def _trace(env: AttentiveRescueEnv, seed: int = 7, steps: int = STEPS) -> list[tuple]:
    """Per step (reset first): observation, info and the float64 reading, with no episode end."""
    obs, info = env.reset(seed=seed)
    trace = [(obs, info, env._reading)]
    for action in _actions(steps):
        obs, _, terminated, truncated, info = env.step(action)
        assert not (terminated or truncated)
        trace.append((obs, info, env._reading))
    return trace


def _scan_steps(interval_s: float, steps: int = STEPS) -> list[int]:
    """Steps (0 = reset) at which a sensor with ``interval_s`` scans, at dt 0.05, on the step grid."""
    every = round(interval_s / DT_S)
    return [k for k in range(steps + 1) if k % every == 0]


# --- settings -------------------------------------------------------------------------------
def test_defaults_are_5_percent_gaussian_scanned_every_step():
    env = AttentiveRescueEnv()
    assert env.sensor_settings == DEFAULT_SENSOR_PROFILE and env.sensor_profile is None
    assert (env.noise_model, env.sensor_noise) == ("gaussian", 0.05)
    assert env.sonar_scan_interval_s is None and env.laser_scan_interval_s is None
    assert (env.sensors.noise_model, env.sensors.noise_std) == ("gaussian", 0.05)


def test_the_usarsim_profile_resolves_to_uniform_5_percent_at_5_hz():
    env = gym.make("AttentiveRescue-v0", sensor_profile="usarsim").unwrapped
    assert env.sensor_profile == "usarsim" and env.sensor_settings == SENSOR_PROFILES["usarsim"]
    assert (env.noise_model, env.sensor_noise) == ("uniform", 0.05)
    assert env.sonar_scan_interval_s == env.laser_scan_interval_s == 0.2
    assert (env.sensors.noise_model, env.sensors.noise_std) == ("uniform", 0.05)


@pytest.mark.parametrize(
    "kwargs, expected",
    [
        ({"noise_model": "gaussian"}, SensorProfile("gaussian", 0.05, 0.2, 0.2)),
        ({"sensor_noise": 0.1}, SensorProfile("uniform", 0.1, 0.2, 0.2)),
        ({"sensor_noise": 0.05}, SensorProfile("uniform", 0.05, 0.2, 0.2)),
        ({"sensor_noise": 0.0}, SensorProfile("uniform", 0.0, 0.2, 0.2)),
        ({"laser_scan_interval_s": DT_S}, SensorProfile("uniform", 0.05, 0.2, DT_S)),
        (
            {"sonar_scan_interval_s": 1.0, "noise_model": "gaussian", "sensor_noise": 0.2},
            SensorProfile("gaussian", 0.2, 1.0, 0.2),
        ),
    ],
)
def test_explicit_settings_beat_the_profile(kwargs, expected):
    env = AttentiveRescueEnv(sensor_profile="usarsim", **kwargs)
    assert env.sensor_settings == expected
    assert (env.sensors.noise_model, env.sensors.noise_std) == (expected.noise_model, expected.noise)


def test_settings_without_a_profile():
    env = AttentiveRescueEnv(noise_model="uniform", laser_scan_interval_s=0.2)
    assert env.sensor_settings == SensorProfile("uniform", 0.05, None, 0.2)


def test_usarsim_env_passes_gymnasiums_checker():
    check_env(AttentiveRescueEnv(sensor_profile="usarsim"), skip_render_check=True)


# --- the default stays what it was --------------------------------------------------------
def test_default_noise_is_the_old_gaussian_formula_on_the_envs_rng():
    noisy, clean = AttentiveRescueEnv(), AttentiveRescueEnv(sensor_noise=0.0)
    noisy.reset(seed=3)
    clean.reset(seed=3)  # the noise level does not change the stream: the same arena, the same state
    for action in _actions(5):
        rng = copy.deepcopy(clean.np_random)
        noisy.step(action)
        clean.step(action)
        normals = rng.standard_normal(16 + 180)
        truth = clean._reading
        expected_sonar = np.clip(truth.sonar * (1 + 0.05 * normals[:16]), SONAR_MIN_M, SONAR_MAX_M)
        expected_sonar[truth.sonar >= SONAR_MAX_M] = SONAR_MAX_M
        expected_laser = np.clip(truth.laser * (1 + 0.05 * normals[16:]), 0.0, LASER_MAX_M)
        expected_laser[truth.laser >= LASER_MAX_M] = LASER_MAX_M
        np.testing.assert_array_equal(noisy._reading.sonar, expected_sonar)
        np.testing.assert_array_equal(noisy._reading.laser, expected_laser)


def test_explicit_default_settings_give_the_default_trajectory():
    default = _trace(AttentiveRescueEnv())
    explicit = _trace(AttentiveRescueEnv(noise_model="gaussian", sensor_noise=0.05))
    not_given = _trace(
        AttentiveRescueEnv(
            sensor_profile=None,
            noise_model=None,
            sensor_noise=None,
            sonar_scan_interval_s=None,
            laser_scan_interval_s=None,
        )
    )
    assert_same([(o, i) for o, i, _ in default], [(o, i) for o, i, _ in explicit])
    assert_same([(o, i) for o, i, _ in default], [(o, i) for o, i, _ in not_given])


def test_every_step_times_equal_the_world_time():
    for _obs, info, _ in _trace(AttentiveRescueEnv(), steps=6):
        assert info["sonar_time_s"] == info["laser_time_s"] == info["time_s"]


# --- scan intervals -------------------------------------------------------------------------
def test_scan_times_with_interval_02_at_dt_005():
    trace = _trace(AttentiveRescueEnv(sensor_profile="usarsim"), steps=12)
    expected = [0.0, 0.0, 0.0, 0.0, 0.2, 0.2, 0.2, 0.2, 0.4, 0.4, 0.4, 0.4, 0.6]
    assert [info["laser_time_s"] for _, info, _ in trace] == pytest.approx(expected, abs=1e-12)
    assert [info["sonar_time_s"] for _, info, _ in trace] == pytest.approx(expected, abs=1e-12)
    assert [info["time_s"] for _, info, _ in trace] == pytest.approx([k * DT_S for k in range(13)], abs=1e-12)


def test_readings_hold_bit_for_bit_between_scans_and_change_at_scans():
    trace = _trace(AttentiveRescueEnv(sensor_profile="usarsim"))
    scans = set(_scan_steps(0.2))
    for k in range(1, len(trace)):
        (before, info_before, _), (now, info_now, _) = trace[k - 1], trace[k]
        for key, hits in (("sonar", "sonar_hits"), ("laser", "laser_hits")):
            if k in scans:
                assert not np.array_equal(now[key], before[key]), (k, key)  # a new scan, new noise
            else:
                np.testing.assert_array_equal(now[key], before[key])
                np.testing.assert_array_equal(info_now[hits], info_before[hits])
        # odometry and the world keep moving every step
        assert not np.array_equal(info_now["robot_pose"], info_before["robot_pose"])


def test_each_sensor_keeps_its_own_interval():
    trace = _trace(AttentiveRescueEnv(sonar_scan_interval_s=0.1), steps=8)
    assert [info["sonar_time_s"] for _, info, _ in trace] == pytest.approx(
        [0.0, 0.0, 0.1, 0.1, 0.2, 0.2, 0.3, 0.3, 0.4], abs=1e-12
    )
    assert [info["laser_time_s"] for _, info, _ in trace] == [info["time_s"] for _, info, _ in trace]
    for k in range(1, len(trace)):
        assert not np.array_equal(trace[k][0]["laser"], trace[k - 1][0]["laser"])
        assert np.array_equal(trace[k][0]["sonar"], trace[k - 1][0]["sonar"]) == (k % 2 == 1)


def test_the_rng_stream_does_not_depend_on_the_interval():
    """At the scan steps, a 5 Hz env reads exactly what an every-step env with the same seed reads."""
    held = _trace(AttentiveRescueEnv(sensor_profile="usarsim"))
    every = _trace(AttentiveRescueEnv(noise_model="uniform"))
    last_scan = 0
    for k, ((obs, info, _), (_obs_every, info_every, _)) in enumerate(zip(held, every)):
        if k in _scan_steps(0.2):
            last_scan = k
        assert_same(info["robot_pose"], info_every["robot_pose"])
        for key, hits in (("sonar", "sonar_hits"), ("laser", "laser_hits")):
            np.testing.assert_array_equal(obs[key], every[last_scan][0][key])
            np.testing.assert_array_equal(info[hits], every[last_scan][1][hits])
        assert info["laser_time_s"] == every[last_scan][1]["time_s"]


def test_usarsim_noise_is_within_5_percent_of_the_truth():
    noisy = _trace(AttentiveRescueEnv(sensor_profile="usarsim"))
    clean = _trace(AttentiveRescueEnv(sensor_profile="usarsim", sensor_noise=0.0))
    worst = 0.0
    for (_, _, reading), (_, _, truth) in zip(noisy, clean):
        for ranges, exact, high in (
            (reading.sonar, truth.sonar, SONAR_MAX_M),
            (reading.laser, truth.laser, LASER_MAX_M),
        ):
            echo = exact < high
            np.testing.assert_array_equal(ranges[~echo], high)
            relative = np.abs(ranges[echo] - exact[echo]) / exact[echo]
            assert np.all(relative <= 0.05 * (1 + 1e-12))
            worst = max(worst, relative.max(initial=0.0))
    assert worst > 0.045  # the noise reaches its bounds, it is not switched off


def test_same_seed_same_readings_with_the_profile():
    first = _trace(AttentiveRescueEnv(sensor_profile="usarsim"), seed=11)
    second = _trace(AttentiveRescueEnv(sensor_profile="usarsim"), seed=11)
    assert_same([(o, i) for o, i, _ in first], [(o, i) for o, i, _ in second])
    other = _trace(AttentiveRescueEnv(sensor_profile="usarsim"), seed=12, steps=1)
    assert not np.array_equal(first[0][0]["laser"], other[0][0]["laser"])


def test_reset_starts_a_new_scan_clock():
    env = AttentiveRescueEnv(sensor_profile="usarsim")
    _trace(env, steps=6)  # last scan at 0.2 s, world time 0.3 s
    obs, info = env.reset(seed=8)
    assert info["laser_time_s"] == info["sonar_time_s"] == info["time_s"] == 0.0
    first = obs["laser"]
    obs, _, _, _, info = env.step(np.zeros(2, np.float32))
    np.testing.assert_array_equal(obs["laser"], first)
    assert info["laser_time_s"] == 0.0


def test_pickle_mid_interval_continues_identically():
    env = AttentiveRescueEnv(sensor_profile="usarsim")
    env.reset(seed=5)
    for action in _actions(6):  # between the scans at 0.2 s and 0.4 s
        env.step(action)
    clone = pickle.loads(pickle.dumps(env))
    assert clone.sensor_settings == env.sensor_settings
    assert clone._reading.laser is clone._scans.reading.laser  # one held reading, not two copies
    # a steady command: random ones can expose pymunk's inexact pickling of angular velocity
    # (±9e-18 rad/s after a round trip, with or without scan intervals)
    action = np.array([0.8, -0.3], np.float32)
    for _ in range(10):
        assert_same(env.step(action), clone.step(action))


# --- bad input ------------------------------------------------------------------------------
INTERVAL_MESSAGE = r"must be None \(a scan every step\) or a finite number of seconds > 0"


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"sensor_profile": "gazebo"}, r"unknown sensor_profile 'gazebo'; allowed: None or one of \['usarsim'\]"),
        ({"sensor_profile": ["usarsim"]}, r"unknown sensor_profile \['usarsim'\]; allowed"),
        ({"noise_model": "laplace"}, r"noise_model must be one of \['gaussian', 'uniform'\], got 'laplace'"),
        ({"noise_model": 1, "sensor_profile": "usarsim"}, r"noise_model must be one of \['gaussian', 'uniform'\]"),
        ({"sensor_noise": 0.6, "sensor_profile": "usarsim"}, r"sensor_noise must be a number in \[0.0, 0.5\]"),
        ({"sensor_noise": "5%", "noise_model": "uniform"}, r"sensor_noise must be a number in \[0.0, 0.5\]"),
        *[
            ({"sonar_scan_interval_s": v}, "sonar_scan_interval_s " + INTERVAL_MESSAGE)
            for v in (0.0, -0.2, math.nan, math.inf, "0.2", True)
        ],
        *[
            ({"laser_scan_interval_s": v, "sensor_profile": "usarsim"}, "laser_scan_interval_s " + INTERVAL_MESSAGE)
            for v in (0, -1e-3, math.nan, -math.inf, b"0.2", False)
        ],
    ],
)
def test_bad_sensor_settings_raise_value_errors_naming_what_is_allowed(kwargs, message):
    with pytest.raises(ValueError, match=message):
        gym.make("AttentiveRescue-v0", **kwargs)
