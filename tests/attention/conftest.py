"""Shared helpers for the attention tests: analytic sensor readings of simple 2-D scenes.

Exposed as the ``scene`` fixture (a namespace), because the suite runs with
``--import-mode=importlib`` where test modules cannot import each other.
"""

from __future__ import annotations

import types

import numpy as np
import pytest

from attentive_gym.attention.regions import SONAR_BEARINGS_DEG, laser_bearings_rad

SONAR_MAX_M = 5.0
LASER_MAX_M = 20.0
CONE_HALF_WIDTH_DEG = 15.0
CONE_SAMPLES = 121  # rays per sonar cone: 0.25 deg apart over 30 deg


def cast(origin, heading, bearings, segments=(), circles=(), max_range=LASER_MAX_M):
    """Exact ranges along rays from ``origin`` at ``heading + bearings`` to segments and circles."""
    angles = heading + np.asarray(bearings, dtype=float)
    d = np.stack([np.cos(angles), np.sin(angles)], axis=-1)  # (n, 2)
    best = np.full(angles.shape, np.inf)
    o = np.asarray(origin, dtype=float)
    for x1, y1, x2, y2 in segments:
        a = np.array([x1, y1]) - o
        e = np.array([x2 - x1, y2 - y1])
        denom = d[:, 0] * (-e[1]) - d[:, 1] * (-e[0])
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (a[0] * (-e[1]) - a[1] * (-e[0])) / denom
            u = (d[:, 0] * a[1] - d[:, 1] * a[0]) / denom
        hit = (np.abs(denom) > 1e-12) & (t > 0) & (u >= 0) & (u <= 1)
        best = np.where(hit & (t < best), t, best)
    for cx, cy, r in circles:
        c = np.array([cx, cy]) - o
        b = d @ c
        disc = b**2 - (c @ c - r**2)
        t = b - np.sqrt(np.maximum(disc, 0.0))
        hit = (disc >= 0) & (t > 0)
        best = np.where(hit & (t < best), t, best)
    return np.minimum(best, max_range)


def readings(origin, heading, segments=(), circles=()):
    """(sonar (16,), laser (180,)) of a robot at ``origin`` facing ``heading``; sonars are cones."""
    laser = cast(origin, heading, laser_bearings_rad(), segments, circles, LASER_MAX_M)
    offsets = np.radians(np.linspace(-CONE_HALF_WIDTH_DEG, CONE_HALF_WIDTH_DEG, CONE_SAMPLES))
    sonar = np.array(
        [
            cast(origin, heading, np.radians(b) + offsets, segments, circles, SONAR_MAX_M).min()
            for b in SONAR_BEARINGS_DEG
        ]
    )
    return sonar, laser


def flat_scene(sonar_m=3.0, laser_m=8.0):
    """Uniform readings: every sonar at ``sonar_m``, every beam at ``laser_m``."""
    return np.full(16, sonar_m), np.full(180, laser_m)


@pytest.fixture
def scene():
    return types.SimpleNamespace(
        cast=cast, readings=readings, flat=flat_scene, SONAR_MAX_M=SONAR_MAX_M, LASER_MAX_M=LASER_MAX_M
    )
