"""AttentionConfig validation and serialisation; sensor geometry and the attention grid."""

import math

import numpy as np
import pytest

from attentive_gym.attention import AttentionConfig, Grid, parse_state
from attentive_gym.attention.kinematics import virtual_sonar
from attentive_gym.attention.regions import (
    laser_bearings_rad,
    nearest_sonar,
    sonar_cone_bounds,
    sonar_cone_reduction,
)


def test_defaults_follow_model_md():
    cfg = AttentionConfig()
    assert (cfg.memory_window, cfg.slope_samples) == (10, 5)
    assert (cfg.sonar_max_range_m, cfg.sonar_min_range_m, cfg.laser_max_range_m) == (5.0, 0.15, 20.0)
    assert (cfg.max_speed_mps, cfg.direction_epsilon_mps, cfg.threshold) == (1.0, 0.05, 0.1)
    assert (cfg.preactivation_s, cfg.excitation_s, cfg.ior_s, cfg.course_s) == (0.15, 0.15, 0.3, 0.6)
    assert (cfg.td_onset_s, cfg.vigilance_after_s, cfg.vigilance_amplitude_rel) == (0.2, 6.0, 1.5)
    assert (cfg.vigilance_tau_s, cfg.vigilance_recovery_s, cfg.lateral_sigma_regions) == (1.0, 2.0, 0.5)
    assert cfg.grid == "sonar" and cfg.ego_motion == "odometry" and cfg.normalise_combined
    assert cfg.weights == (1.0,) * 6 and cfg.gain == 1.0


@pytest.mark.parametrize(
    ("field", "value", "message"),
    [
        ("memory_window", 1, "memory_window must be an int >= 2"),
        ("slope_samples", 11, "slope_samples must be <= memory_window=10"),
        ("max_speed_mps", 0.0, "max_speed_mps must be a finite number > 0"),
        ("threshold", float("nan"), "threshold must be a finite number > 0"),
        ("A_ior", -0.1, "A_ior must be a finite number >= 0"),
        ("sonar_min_range_m", 6.0, "sonar_min_range_m must be < sonar_max_range_m"),
        ("kernel_rise_fraction", 0.6, "kernel_rise_fraction must be < kernel_decay_fraction"),
        ("grid", "hex", "grid must be one of"),
        ("ego_motion", "gps", "ego_motion must be one of"),
        ("weights", (1, 1, 1), r"weights must be 6 numbers in \[0, 1e\+06\]"),
        ("weights", (1, 1, 1, 1, 1, -1), r"weights must be 6 numbers in \[0, 1e\+06\]"),
        ("state", "sleepy", "unknown attentive state 'sleepy'"),
        ("sonar_cone_half_width_deg", 45.0, "sonar_cone_half_width_deg must be a finite number >= 0.5 and <= 30"),
        ("laser_only", 1, "laser_only must be True or False"),
        ("lateral_sigma_regions", 1e-170, r"lateral_sigma_regions must be a finite number >= 0.01 and <= 1e\+06"),
        ("track_accel_psd_m2ps3", 1e300, r"track_accel_psd_m2ps3 must be a finite number > 0 and <= 1e\+06 \(m²/s³\)"),
        ("weights", (True,) * 6, r"weights must be 6 numbers in \[0, 1e\+06\]"),
    ],
)
def test_invalid_config_names_field_and_range(field, value, message):
    with pytest.raises(ValueError, match=message):
        AttentionConfig(**{field: value})


def test_config_json_round_trip_and_unknown_field():
    cfg = AttentionConfig(grid="laser", weights=(1, 0, 2, 0, 0, 1), state=1.25, ego_motion=None)
    back = AttentionConfig.from_json(cfg.to_json())
    assert back == cfg
    with pytest.raises(ValueError, match="unknown AttentionConfig field"):
        AttentionConfig.from_dict({"treshold": 0.2})
    with pytest.raises(ValueError, match="not valid JSON"):
        AttentionConfig.from_json("{threshold: 0.2")


def test_parse_state_levels_and_gains():
    assert (parse_state("drowsy"), parse_state("ALERT"), parse_state("vigilant"), parse_state(2)) == (
        0.5,
        1.0,
        1.5,
        2.0,
    )
    for bad in (0, -1.0, math.inf, "", True):
        with pytest.raises(ValueError):
            parse_state(bad)


def test_laser_bearings_and_region_boundaries():
    b = np.degrees(laser_bearings_rad())
    assert b[0] == pytest.approx(-89.5) and b[179] == pytest.approx(89.5)
    grid = Grid.make("sonar")
    # boundaries at ±70, ±40, ±20, 0 deg: region sizes 20, 30, 20, 20 | 20, 20, 30, 20 beams
    assert np.bincount(grid.beam_region).tolist() == [20, 30, 20, 20, 20, 20, 30, 20]
    assert grid.beam_region[0] == 7 and grid.beam_region[179] == 0  # beam 0 rightmost, sonar 0 leftmost
    assert nearest_sonar(np.radians([69.9, 70.1, -0.1, 0.1])).tolist() == [1, 0, 4, 3]
    assert [(s.start, s.stop) for s in grid.beam_slices][:2] == [(160, 180), (130, 160)]
    x = np.arange(180.0)
    assert grid.reduce_beams(np.maximum, x).tolist() == [179, 159, 129, 109, 89, 69, 49, 19]
    laser = Grid.make("laser")
    assert laser.n_regions == 180 and laser.region_sonar[0] == 7 and laser.reduce_beams(np.maximum, x) is x
    with pytest.raises(ValueError, match="unknown grid"):
        Grid.make("hex")


def test_virtual_sonar_is_min_over_cone_and_exact_at_edges():
    bounds = sonar_cone_bounds(15.0)
    assert bounds[3].tolist() == [85, 115]  # +10 deg: beams at -4.5 .. +24.5 deg
    plan = sonar_cone_reduction(15.0)
    rng = np.random.default_rng(1)
    scan = rng.uniform(1.0, 10.0, 180)
    beams = laser_bearings_rad()
    expected = [min(scan[s:e].min(), np.interp(plan[2][k], beams, scan).min()) for k, (s, e) in enumerate(bounds)]
    np.testing.assert_allclose(virtual_sonar(scan, beams, plan), expected)


def test_each_regions_nearest_reading_is_the_least_of_its_sonar_and_its_beams():
    rng = np.random.default_rng(0)
    sonar, laser = rng.uniform(0.2, 5.0, (3, 16)), rng.uniform(0.2, 20.0, (3, 180))
    grid = Grid.make("sonar")
    nearest = grid.nearest_reading(sonar, laser)
    expected = [
        [min(sonar[n, grid.region_sonar[j]], laser[n, beams].min()) for j, beams in enumerate(grid.beam_slices)]
        for n in range(3)
    ]
    assert nearest.shape == (3, grid.n_regions) and np.array_equal(nearest, expected)
    laser[1, grid.beam_slices[2].start] = 0.05  # a near echo on the region's first beam wins over its sonar
    assert grid.nearest_reading(sonar, laser)[1, 2] == 0.05
    assert np.array_equal(grid.nearest_reading(sonar[0], laser[0]), expected[0])  # one reading, no batch axis
