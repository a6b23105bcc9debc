"""``benchmarks/acquisition.py``'s ideal estimator: sightings, the line fit's σ and the judgement,
against hand-computed values."""

from __future__ import annotations

import math

import numpy as np
import pytest

from support import load_benchmark

bench = load_benchmark("acquisition")


def test_a_sighting_goes_on_through_gaps_up_to_the_coast_and_starts_again_after():
    t = np.arange(12) * 0.5
    visible = np.array([0, 1, 1, 0, 0, 1, 0, 0, 0, 0, 1, 1], bool)
    ages = bench.sighting_ages(t, visible, gap_s=1.5)
    assert np.isnan(ages[~visible]).all()
    # a gap of 1.5 s (steps 2 -> 5) keeps the sighting; one of 2.5 s (5 -> 10) ends it
    assert ages[visible] == pytest.approx([0.0, 0.5, 2.0, 0.0, 0.5])


def test_the_line_fit_sigma_of_two_and_of_many_equal_centroids():
    t = np.arange(5) * 0.05
    visible = np.ones(5, bool)
    ages = bench.sighting_ages(t, visible)
    sigma = bench.ideal_speed_sigma(t, visible, ages, np.full(5, 0.01))  # σ = 0.1 m per centroid
    assert sigma[0] == math.inf
    assert sigma[1] == pytest.approx(0.1 / math.sqrt(2 * 0.025**2))  # Σ (t − t̄)² = 2 (dt/2)²
    assert sigma[4] == pytest.approx(0.1 / math.sqrt(np.sum((t - t.mean()) ** 2)))
    window = bench.ideal_speed_sigma(t, visible, ages, np.full(5, 0.01), window_s=0.05)
    assert window[4] == pytest.approx(sigma[1])  # only the last two centroids


def test_the_centroid_variance_follows_the_tracker_s_measurement_model():
    variance = bench.centroid_variance(np.array([2.0]), np.array([4]), noise_rel=0.05)
    along = (0.05 * 2.0) ** 2 / 4 + 0.05**2
    across = 0.05**2 + (2.0 * math.radians(1.0)) ** 2 / 12
    assert variance[0] == pytest.approx(0.5 * (along + across))


def test_the_judgement_needs_the_band_and_a_margin_above_standing():
    band = (0.15, 0.45)
    exact = bench.judged_probability(np.zeros(3), np.array([0.1, 0.3, 0.6]), band)
    assert exact.tolist() == [0.0, 1.0, 0.0]
    assert bench.judged_probability(np.array([math.inf]), np.array([0.3]), band)[0] == 0.0
    centre = bench.judged_probability(np.array([0.15]), np.array([0.3]), band, z=0.0)[0]
    assert centre == pytest.approx(math.erf(1 / math.sqrt(2)))  # ±1 σ
    # a σ of 0.1 m/s puts the standing margin (2σ = 0.2) above the band's 0.15
    margin = bench.judged_probability(np.array([0.1]), np.array([0.3]), band)[0]
    assert margin == pytest.approx(0.5 * (math.erf(1.5 / math.sqrt(2)) - math.erf(-1 / math.sqrt(2))))
