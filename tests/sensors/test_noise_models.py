"""Noise models: the uniform (USARSim) model, the unchanged Gaussian default, and bad model names."""

from __future__ import annotations

import math

import numpy as np
import pytest

from attentive_gym.sensors import NOISE_MODELS, SensorSuite, apply_range_noise, unit_noise

SONAR_MIN_M, SONAR_MAX_M, LASER_MAX_M = 0.15, 5.0, 20.0


def _gaussian_oracle(ranges, sigma, normals, min_range_m, max_range_m):
    """The Gaussian model as it was first written: ``r (1 + sigma n)``, clipped, no echo kept."""
    ranges = np.asarray(ranges, dtype=np.float64)
    noisy = np.clip(ranges * (1.0 + sigma * normals), min_range_m, max_range_m)
    noisy[ranges >= max_range_m] = max_range_m
    return noisy


def test_the_models_are_gaussian_and_uniform():
    assert NOISE_MODELS == ("gaussian", "uniform")


def test_uniform_noise_is_the_usarsim_formula_on_rng_random():
    ranges = np.linspace(0.3, 4.5, 1000)
    noisy = apply_range_noise(ranges, 0.05, SONAR_MIN_M, SONAR_MAX_M, np.random.default_rng(8), model="uniform")
    u = np.random.default_rng(8).random(ranges.shape)
    np.testing.assert_array_equal(noisy, ranges * (1.0 + 0.05 * (2.0 * u - 1.0)))


def test_uniform_noise_stays_within_a_of_every_reading():
    a = 0.05
    ranges = np.random.default_rng(0).uniform(0.2, 4.7, 200_000)  # (1 ± a) r stays inside [0.15, 5]
    noisy = apply_range_noise(ranges, a, SONAR_MIN_M, SONAR_MAX_M, np.random.default_rng(1), model="uniform")
    relative = noisy / ranges - 1.0
    assert np.all(np.abs(noisy - ranges) <= a * ranges * (1.0 + 1e-12))
    # the bounds are reached: 200k draws leave gaps of about 2a / 200k at either end
    assert relative.min() < -a * 0.999 and relative.max() > a * 0.999


def test_uniform_noise_has_the_spread_of_a_uniform():
    a = 0.05
    ranges = np.full(200_000, 2.0)
    relative = (
        apply_range_noise(ranges, a, SONAR_MIN_M, SONAR_MAX_M, np.random.default_rng(2), model="uniform") / 2.0 - 1.0
    )
    # standard errors: (a / sqrt 3) / sqrt(n) = 6.5e-5 for the mean; for the std of a uniform
    # (kurtosis 1.8): (a / sqrt 3) sqrt(0.8 / (4 n)) = 2.9e-5
    assert abs(relative.mean()) < 3e-4
    assert relative.std() == pytest.approx(a / math.sqrt(3.0), abs=1.5e-4)
    gaussian = apply_range_noise(ranges, a, SONAR_MIN_M, SONAR_MAX_M, np.random.default_rng(2)) / 2.0 - 1.0
    assert gaussian.std() == pytest.approx(a, abs=4e-4)  # the same level is a wider Gaussian


@pytest.mark.parametrize("model", NOISE_MODELS)
def test_no_echo_readings_stay_exactly_at_max_range(model):
    ranges = np.array([SONAR_MAX_M, 7.0, SONAR_MAX_M, 1.0, math.inf])
    noisy = apply_range_noise(ranges, 0.4, SONAR_MIN_M, SONAR_MAX_M, np.random.default_rng(3), model=model)
    np.testing.assert_array_equal(noisy[[0, 1, 2, 4]], SONAR_MAX_M)
    assert noisy[3] != 1.0


def test_uniform_noise_is_clipped_to_the_limits():
    near_min, near_max = np.full(5_000, 0.16), np.full(5_000, 4.99)
    low = apply_range_noise(near_min, 0.5, SONAR_MIN_M, SONAR_MAX_M, np.random.default_rng(4), model="uniform")
    high = apply_range_noise(near_max, 0.5, SONAR_MIN_M, SONAR_MAX_M, np.random.default_rng(4), model="uniform")
    assert low.min() == SONAR_MIN_M and (low == SONAR_MIN_M).mean() > 0.4
    assert high.max() == SONAR_MAX_M and (high == SONAR_MAX_M).mean() > 0.4


@pytest.mark.parametrize("model", NOISE_MODELS)
def test_one_draw_per_reading_whatever_the_level_and_readings(model):
    quiet, loud, reference = (np.random.default_rng(6) for _ in range(3))
    ranges = np.array([0.2, 3.0, SONAR_MAX_M, 9.0])
    exact = apply_range_noise(ranges[:2], 0.0, SONAR_MIN_M, SONAR_MAX_M, quiet, model=model)
    np.testing.assert_array_equal(exact, ranges[:2])
    apply_range_noise(ranges[2:], 0.3, SONAR_MIN_M, SONAR_MAX_M, loud, model=model)  # all "no echo"
    (reference.standard_normal if model == "gaussian" else reference.random)(2)
    assert quiet.bit_generator.state == loud.bit_generator.state == reference.bit_generator.state


def test_gaussian_is_the_default_and_unchanged():
    ranges = np.array([0.15, 0.5, 1.0, 2.5, 4.9, 5.0, 5.0, 0.16])
    default = apply_range_noise(ranges, 0.05, SONAR_MIN_M, SONAR_MAX_M, np.random.default_rng(12))
    explicit = apply_range_noise(ranges, 0.05, SONAR_MIN_M, SONAR_MAX_M, np.random.default_rng(12), model="gaussian")
    normals = np.random.default_rng(12).standard_normal(ranges.shape)
    np.testing.assert_array_equal(default, explicit)
    np.testing.assert_array_equal(default, _gaussian_oracle(ranges, 0.05, normals, SONAR_MIN_M, SONAR_MAX_M))


def test_suite_default_is_the_gaussian_oracle_sonar_first_then_laser(room):
    pose = (0.3, 0.2, 0.4)
    clean = SensorSuite(noise_std=0.0).read(pose, room, np.random.default_rng(0))
    default = SensorSuite().read(pose, room, np.random.default_rng(21))
    explicit = SensorSuite(noise_std=0.05, noise_model="gaussian").read(pose, room, np.random.default_rng(21))
    normals = np.random.default_rng(21).standard_normal(16 + 180)
    np.testing.assert_array_equal(
        default.sonar, _gaussian_oracle(clean.sonar, 0.05, normals[:16], SONAR_MIN_M, SONAR_MAX_M)
    )
    np.testing.assert_array_equal(default.laser, _gaussian_oracle(clean.laser, 0.05, normals[16:], 0.0, LASER_MAX_M))
    np.testing.assert_array_equal(explicit.sonar, default.sonar)
    np.testing.assert_array_equal(explicit.laser, default.laser)


def test_uniform_suite_matches_apply_range_noise_and_keeps_owners(room):
    pose = (0.3, 0.2, 0.4)
    suite = SensorSuite(noise_std=0.05, noise_model="uniform")
    assert suite.noise_model == "uniform"
    reading = suite.read(pose, room, np.random.default_rng(5))
    clean = SensorSuite(noise_std=0.0, noise_model="uniform").read(pose, room, np.random.default_rng(0))
    rng = np.random.default_rng(5)
    np.testing.assert_array_equal(
        reading.sonar, apply_range_noise(clean.sonar, 0.05, SONAR_MIN_M, SONAR_MAX_M, rng, model="uniform")
    )
    np.testing.assert_array_equal(
        reading.laser, apply_range_noise(clean.laser, 0.05, 0.0, LASER_MAX_M, rng, model="uniform")
    )
    assert rng.bit_generator.state == _after_uniform_draws(5, 16 + 180)
    np.testing.assert_array_equal(reading.laser_owner, clean.laser_owner)
    np.testing.assert_array_equal(reading.sonar_owner, clean.sonar_owner)
    valid = clean.laser < LASER_MAX_M
    assert np.all(np.abs(reading.laser - clean.laser)[valid] <= 0.05 * clean.laser[valid] * (1.0 + 1e-12))


def _after_uniform_draws(seed: int, count: int) -> dict:
    rng = np.random.default_rng(seed)
    rng.random(count)
    return rng.bit_generator.state


def test_unit_noise_draws_per_model():
    np.testing.assert_array_equal(
        unit_noise("gaussian", 7, np.random.default_rng(1)), np.random.default_rng(1).standard_normal(7)
    )
    draws = unit_noise("uniform", (3, 4), np.random.default_rng(1))
    assert draws.shape == (3, 4) and draws.dtype == np.float64
    np.testing.assert_array_equal(draws, 2.0 * np.random.default_rng(1).random((3, 4)) - 1.0)


@pytest.mark.parametrize("model", ["laplace", "Gaussian", "", None, 0, ["uniform"]])
def test_unknown_models_are_refused_naming_the_allowed_ones(model):
    allowed = r"must be one of \['gaussian', 'uniform'\]"
    with pytest.raises(ValueError, match="model " + allowed):
        apply_range_noise([1.0], 0.05, SONAR_MIN_M, SONAR_MAX_M, np.random.default_rng(0), model=model)
    with pytest.raises(ValueError, match="noise_model " + allowed):
        SensorSuite(noise_model=model)
    with pytest.raises(ValueError, match="noise model " + allowed):
        unit_noise(model, 3, np.random.default_rng(0))
