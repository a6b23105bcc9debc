"""Range noise, the ``SensorSuite`` and the runnable examples of the sensors package."""

from __future__ import annotations

import doctest
import importlib
import math
import pickle

import numpy as np
import pytest

from attentive_gym.sensors import (
    LaserConfig,
    LaserScanner,
    SceneGeometry,
    SensorReading,
    SensorSuite,
    SonarConfig,
    SonarRing,
    apply_range_noise,
)


def _readings():
    return np.array([0.15, 0.5, 1.0, 2.5, 4.9, 5.0, 5.0])


def test_noise_is_deterministic_for_a_seeded_rng():
    a = apply_range_noise(_readings(), 0.05, 0.15, 5.0, np.random.default_rng(3))
    b = apply_range_noise(_readings(), 0.05, 0.15, 5.0, np.random.default_rng(3))
    np.testing.assert_array_equal(a, b)
    c = apply_range_noise(_readings(), 0.05, 0.15, 5.0, np.random.default_rng(4))
    assert not np.array_equal(a, c)


def test_noise_formula_and_no_echo_readings():
    ranges = _readings()
    noisy = apply_range_noise(ranges, 0.05, 0.15, 5.0, np.random.default_rng(9))
    draws = np.random.default_rng(9).standard_normal(ranges.shape)
    expected = np.clip(ranges * (1 + 0.05 * draws), 0.15, 5.0)
    np.testing.assert_array_equal(noisy[:5], expected[:5])
    np.testing.assert_array_equal(noisy[5:], [5.0, 5.0])  # no echo stays no echo, exactly
    assert noisy is not ranges and np.array_equal(ranges, _readings())  # the input is untouched


def test_zero_noise_is_exact_and_draws_the_same_stream():
    ranges = _readings()
    quiet, loud = np.random.default_rng(1), np.random.default_rng(1)
    np.testing.assert_array_equal(apply_range_noise(ranges, 0.0, 0.15, 5.0, quiet), ranges)
    apply_range_noise(ranges, 0.2, 0.15, 5.0, loud)
    assert quiet.standard_normal() == loud.standard_normal()  # both consumed len(ranges) normals


def test_noise_is_clipped_to_the_limits():
    ranges = np.full(10_000, 0.2)
    noisy = apply_range_noise(ranges, 0.9, 0.15, 5.0, np.random.default_rng(0))
    assert noisy.min() == 0.15 and noisy.max() < 5.0 and (noisy == 0.15).mean() > 0.3


def test_relative_error_has_the_requested_spread():
    ranges = np.full(200_000, 2.0)
    sigma = 0.05
    relative = apply_range_noise(ranges, sigma, 0.15, 5.0, np.random.default_rng(0)) / ranges - 1.0
    # standard errors: sigma / sqrt(n) = 1.1e-4 for the mean, sigma / sqrt(2 n) = 7.9e-5 for the std
    assert abs(relative.mean()) < 5e-4
    assert relative.std() == pytest.approx(sigma, abs=4e-4)


@pytest.mark.parametrize("sigma", [-0.01, 1.0, math.nan, math.inf, "5%", "0.05", None, True])
def test_bad_sigma_is_refused(sigma):
    with pytest.raises(ValueError, match=r"relative_std must be a finite number in \[0, 1\)"):
        apply_range_noise(_readings(), sigma, 0.15, 5.0, np.random.default_rng(0))
    with pytest.raises(ValueError, match=r"noise_std must be a finite number in \[0, 1\)"):
        SensorSuite(noise_std=sigma)


def test_bad_limits_and_rng_are_refused():
    with pytest.raises(ValueError, match="0 <= min_range_m < max_range_m"):
        apply_range_noise(_readings(), 0.05, 5.0, 5.0, np.random.default_rng(0))
    with pytest.raises(TypeError, match="rng must be a numpy.random.Generator"):
        apply_range_noise(_readings(), 0.05, 0.15, 5.0, np.random.RandomState(0))


def test_noise_free_suite_reads_the_ring_and_the_scanner(room):
    pose = (0.3, 0.2, 0.4)
    reading = SensorSuite(noise_std=0.0).read(pose, room, np.random.default_rng(0))
    sonar, sonar_owner = SonarRing().read(pose, room)
    laser, laser_owner = LaserScanner().read(pose, room)
    np.testing.assert_array_equal(reading.sonar, sonar)
    np.testing.assert_array_equal(reading.laser, laser)
    np.testing.assert_array_equal(reading.sonar_owner, sonar_owner)
    np.testing.assert_array_equal(reading.laser_owner, laser_owner)
    assert reading.sonar.shape == (16,) and reading.laser.shape == (180,)
    assert reading.sonar.dtype == reading.laser.dtype == np.float64
    assert reading.sonar_owner.dtype == reading.laser_owner.dtype == np.int64
    assert {1, 2} <= set(laser_owner.tolist()) and 3 in sonar_owner


def test_noisy_suite_keeps_owners_and_limits_and_is_seeded(room):
    suite = SensorSuite(noise_std=0.05)
    pose = (0.3, 0.2, 0.4)
    a = suite.read(pose, room, np.random.default_rng(5))
    b = suite.read(pose, room, np.random.default_rng(5))
    clean = SensorSuite(noise_std=0.0).read(pose, room, np.random.default_rng(5))
    np.testing.assert_array_equal(a.sonar, b.sonar)
    np.testing.assert_array_equal(a.laser, b.laser)
    np.testing.assert_array_equal(a.sonar_owner, clean.sonar_owner)
    np.testing.assert_array_equal(a.laser_owner, clean.laser_owner)
    assert not np.array_equal(a.laser, clean.laser)
    assert np.all((a.sonar >= 0.15) & (a.sonar <= 5.0)) and np.all((a.laser >= 0.0) & (a.laser <= 20.0))
    np.testing.assert_array_equal(a.sonar[clean.sonar == 5.0], 5.0)
    # sonar first, then laser: the stream is the one apply_range_noise would draw
    rng = np.random.default_rng(5)
    expected_sonar = apply_range_noise(clean.sonar, 0.05, 0.15, 5.0, rng)
    expected_laser = apply_range_noise(clean.laser, 0.05, 0.0, 20.0, rng)
    np.testing.assert_array_equal(a.sonar, expected_sonar)
    np.testing.assert_array_equal(a.laser, expected_laser)


def test_rng_use_does_not_depend_on_the_noise_level(room):
    quiet, loud = np.random.default_rng(2), np.random.default_rng(2)
    SensorSuite(noise_std=0.0).read((0.0, 0.0, 0.0), room, quiet)
    SensorSuite(noise_std=0.3).read((0.0, 0.0, 0.0), room, loud)
    assert quiet.bit_generator.state == loud.bit_generator.state


def test_suite_configs_drawing_and_pickling(room):
    suite = SensorSuite(SonarConfig(max_range_m=3.0), LaserConfig(num_beams=90, fov_deg=270.0), noise_std=0.0)
    pose = (0.0, 0.0, 0.0)
    reading = suite.read(pose, room, np.random.default_rng(0))
    assert reading.sonar.max() <= 3.0 and reading.laser.shape == (90,)
    assert suite.laser_segments(pose, reading).shape == (2, 90, 2)
    assert len(suite.sonar_cones(pose, reading)) == 16
    clone = pickle.loads(pickle.dumps(suite))
    again = clone.read(pose, room, np.random.default_rng(0))
    np.testing.assert_array_equal(again.laser, reading.laser)
    assert isinstance(reading, SensorReading)
    with pytest.raises(TypeError, match="config must be a SonarConfig"):
        SensorSuite(LaserConfig())
    with pytest.raises(TypeError, match="exclude_owner must be an int"):
        suite.read(pose, room, np.random.default_rng(0), exclude_owner="robot")


@pytest.mark.parametrize("module", ["geometry", "raycast", "sonar", "laser", "noise", "stack", "suite"])
def test_docstring_examples_run(module):
    result = doctest.testmod(importlib.import_module(f"attentive_gym.sensors.{module}"))
    assert result.attempted > 0 and result.failed == 0


@pytest.mark.parametrize("noise_model", ["gaussian", "uniform"])
def test_read_many_equals_read_of_each_robot_in_turn(noise_model):
    from attentive_gym.envs.rescue_env import ROBOT_ID, AttentiveRescueEnv

    envs = [AttentiveRescueEnv(noise_model=noise_model) for _ in range(5)]
    for seed, env in enumerate(envs):
        env.reset(seed=seed)
    robots = [env.world.robot.body for env in envs]
    requests = [
        ((*robot.position, robot.angle), env.world.geometry(), env.np_random, ROBOT_ID)
        for robot, env in zip(robots, envs)
    ]
    requests[4] = (requests[4][0], SceneGeometry.empty(), requests[4][2], -1)  # an empty scene, no owner left out
    states = [env.np_random.bit_generator.state for env in envs]
    many = envs[0].sensors.read_many(requests)
    for env, state in zip(envs, states):
        env.np_random.bit_generator.state = state
    for request, batched in zip(requests, many):
        single = envs[0].sensors.read(*request)
        for field in ("sonar", "laser", "sonar_owner", "laser_owner"):
            np.testing.assert_array_equal(getattr(batched, field), getattr(single, field))
    assert envs[0].sensors.read_many([]) == []
    with pytest.raises(ValueError, match="pose must be finite"):
        envs[0].sensors.read_many([((0.0, np.nan, 0.0), *requests[0][1:])])
    with pytest.raises(TypeError, match="request 0: rng"):
        envs[0].sensors.read_many([(requests[0][0], requests[0][1], 7, -1)])
