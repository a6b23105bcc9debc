"""Scan rates (``scan_due``, ``ScanHold``) and sensor profiles (``SensorProfile``, ``resolve_sensor_profile``)."""

from __future__ import annotations

import dataclasses
import doctest
import importlib
import math
import pickle

import numpy as np
import pytest

from attentive_gym.sensors import (
    DEFAULT_SENSOR_PROFILE,
    SCAN_TOLERANCE_S,
    SENSOR_PROFILES,
    ScanHold,
    SensorProfile,
    SensorReading,
    resolve_sensor_profile,
    scan_due,
)

DT_S = 0.05
BAD_INTERVALS = [0.0, -0.2, math.nan, math.inf, -math.inf, "0.2", True, np.bool_(True), [0.2], complex(0.2, 0)]
INTERVAL_MESSAGE = r"must be None \(a scan every step\) or a finite number of seconds > 0"


def _reading(step: int) -> SensorReading:
    """A distinct reading per step: ranges = step, owners = step."""
    return SensorReading(np.full(16, float(step)), np.full(180, float(step)), np.full(16, step), np.full(180, step))


def _run(hold: ScanHold, steps: int, dt_s: float = DT_S):
    """``(returned readings, sonar times, laser times)`` of ``steps`` updates at world times ``k dt``."""
    out, sonar_times, laser_times = [], [], []
    for k in range(steps):
        out.append(hold.update(_reading(k), k * dt_s))
        sonar_times.append(hold.sonar_time_s)
        laser_times.append(hold.laser_time_s)
    return out, sonar_times, laser_times


def test_scan_due_rules():
    assert scan_due(0.0, -math.inf, 0.2)  # never scanned
    assert scan_due(0.0, 0.0, None) and scan_due(0.01, 0.0, None)  # None: every step
    assert not scan_due(3 * DT_S, 0.0, 0.2)
    assert scan_due(4 * DT_S, 0.0, 0.2)
    assert scan_due(0.2 - SCAN_TOLERANCE_S / 2, 0.0, 0.2)  # rounding below the multiple still scans
    assert not scan_due(0.2 - 2 * SCAN_TOLERANCE_S, 0.0, 0.2)


def test_interval_02_at_dt_005_scans_every_fourth_step_and_holds_in_between():
    out, sonar_times, laser_times = _run(ScanHold(0.2, 0.2), 13)
    expected_scan = [0, 0, 0, 0, 4, 4, 4, 4, 8, 8, 8, 8, 12]
    assert laser_times == sonar_times == pytest.approx([k * DT_S for k in expected_scan], abs=1e-12)
    for reading, scan in zip(out, expected_scan):
        for array in (reading.sonar, reading.laser, reading.sonar_owner, reading.laser_owner):
            assert np.all(array == scan)
    assert out[1] is out[0] and out[3] is out[0] and out[4] is not out[0]  # held, not copied


def test_sensors_keep_their_own_intervals():
    out, sonar_times, laser_times = _run(ScanHold(None, 0.1), 6)
    assert sonar_times == pytest.approx([k * DT_S for k in range(6)], abs=1e-12)
    assert laser_times == pytest.approx([0.0, 0.0, 0.1, 0.1, 0.2, 0.2], abs=1e-12)
    assert [r.sonar[0] for r in out] == [0, 1, 2, 3, 4, 5]
    assert [r.laser[0] for r in out] == [0, 0, 2, 2, 4, 4]
    assert [r.laser_owner[0] for r in out] == [0, 0, 2, 2, 4, 4]
    assert out[1].laser is out[0].laser and out[1].sonar is not out[0].sonar  # the held laser arrays themselves


def test_an_interval_off_the_step_grid_counts_from_the_last_scan():
    _, _, laser_times = _run(ScanHold(None, 0.12), 7)  # 0.15 s after a scan is the first step >= 0.12 s
    assert laser_times == pytest.approx([0.0, 0.0, 0.0, 0.15, 0.15, 0.15, 0.3], abs=1e-12)


def test_an_interval_below_the_step_scans_every_step():
    out, sonar_times, laser_times = _run(ScanHold(0.01, DT_S), 5)
    assert sonar_times == laser_times == pytest.approx([k * DT_S for k in range(5)], abs=1e-12)
    assert [r.laser[0] for r in out] == [0, 1, 2, 3, 4]


def test_every_step_returns_the_fresh_reading_itself():
    hold = ScanHold()
    fresh = _reading(3)
    assert hold.update(fresh, 0.15) is fresh and hold.reading is fresh
    assert hold.sonar_time_s == hold.laser_time_s == 0.15


def test_reset_scans_both_sensors_at_the_next_update():
    hold = ScanHold(0.2, 0.2)
    assert hold.reading is None and hold.sonar_time_s == hold.laser_time_s == -math.inf
    _run(hold, 3)
    hold.reset()
    assert hold.reading is None and hold.laser_time_s == -math.inf
    again = hold.update(_reading(9), 0.0)  # a new episode starts its clock again at 0
    assert again.laser[0] == 9 and hold.laser_time_s == hold.sonar_time_s == 0.0


def test_hold_pickles_with_its_held_reading():
    hold = ScanHold(0.2, 0.2)
    _run(hold, 2)
    clone = pickle.loads(pickle.dumps(hold))
    assert clone.laser_time_s == 0.0 and clone.update(_reading(2), 2 * DT_S).laser[0] == 0
    assert clone.update(_reading(4), 4 * DT_S).laser[0] == 4


@pytest.mark.parametrize("value", BAD_INTERVALS)
def test_bad_intervals_are_refused_naming_the_argument(value):
    with pytest.raises(ValueError, match="sonar_scan_interval_s " + INTERVAL_MESSAGE):
        ScanHold(sonar_scan_interval_s=value)
    with pytest.raises(ValueError, match="laser_scan_interval_s " + INTERVAL_MESSAGE):
        ScanHold(laser_scan_interval_s=value)


def test_intervals_are_converted_to_floats():
    hold = ScanHold(np.float32(0.25), 1)
    assert type(hold.sonar_scan_interval_s) is float and type(hold.laser_scan_interval_s) is float
    assert hold.laser_scan_interval_s == 1.0


# --- profiles -------------------------------------------------------------------------------
def test_the_usarsim_profile_is_usarsims_defaults():
    assert set(SENSOR_PROFILES) == {"usarsim"}
    assert SENSOR_PROFILES["usarsim"] == SensorProfile("uniform", 0.05, 0.2, 0.2)
    assert DEFAULT_SENSOR_PROFILE == SensorProfile("gaussian", 0.05, None, None)


def test_profiles_are_read_only():
    with pytest.raises(TypeError):
        SENSOR_PROFILES["usarsim"] = DEFAULT_SENSOR_PROFILE
    with pytest.raises(dataclasses.FrozenInstanceError):
        SENSOR_PROFILES["usarsim"].noise = 0.1


def test_resolve_starts_from_the_profile_and_given_settings_win():
    assert resolve_sensor_profile(None) == DEFAULT_SENSOR_PROFILE
    assert resolve_sensor_profile("usarsim") == SENSOR_PROFILES["usarsim"]
    assert resolve_sensor_profile(
        "usarsim", noise_model="gaussian", noise=0.1, laser_scan_interval_s=0.05
    ) == SensorProfile("gaussian", 0.1, 0.2, 0.05)
    assert resolve_sensor_profile(None, noise_model="uniform", sonar_scan_interval_s=0.5) == SensorProfile(
        "uniform", 0.05, 0.5, None
    )
    assert resolve_sensor_profile("usarsim", noise=0.0).noise == 0.0  # a given 0 is not "not given"


@pytest.mark.parametrize("name", ["gazebo", "USARSim", "", 3, ["usarsim"]])
def test_unknown_profiles_are_refused_listing_the_allowed_ones(name):
    with pytest.raises(ValueError, match=r"unknown sensor_profile .*; allowed: None or one of \['usarsim'\]"):
        resolve_sensor_profile(name)


@pytest.mark.parametrize(
    "fields, message",
    [
        (("laplace", 0.05, None, None), r"noise_model must be one of \['gaussian', 'uniform'\]"),
        (("uniform", 1.0, None, None), r"noise must be a finite number in \[0, 1\)"),
        (("uniform", -0.01, None, None), r"noise must be a finite number in \[0, 1\)"),
        (("uniform", 0.05, 0.0, None), "sonar_scan_interval_s " + INTERVAL_MESSAGE),
        (("uniform", 0.05, None, math.nan), "laser_scan_interval_s " + INTERVAL_MESSAGE),
    ],
)
def test_bad_profile_fields_are_refused_naming_the_field(fields, message):
    with pytest.raises(ValueError, match=message):
        SensorProfile(*fields)
    name, noise, sonar, laser = fields
    with pytest.raises(ValueError, match=message):
        resolve_sensor_profile(
            "usarsim", noise_model=name, noise=noise, sonar_scan_interval_s=sonar, laser_scan_interval_s=laser
        )


def test_profile_fields_are_converted_to_floats():
    profile = SensorProfile("uniform", np.float32(0.25), 1, np.float64(0.5))
    assert type(profile.noise) is float and type(profile.sonar_scan_interval_s) is float
    assert type(profile.laser_scan_interval_s) is float and profile.sonar_scan_interval_s == 1.0


@pytest.mark.parametrize("module", ["scans", "profiles"])
def test_docstring_examples_run(module):
    result = doctest.testmod(importlib.import_module(f"attentive_gym.sensors.{module}"))
    assert result.attempted > 0 and result.failed == 0
