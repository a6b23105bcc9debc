"""``benchmarks/calibration.py``'s own parts: the band it is told and where the judged steps lie
(the judgement itself is tested in ``tests/perception/test_calibration.py``)."""

from __future__ import annotations

import argparse
import math

import numpy as np
import pytest

from support import load_benchmark

bench = load_benchmark("calibration")


def test_a_band_is_two_ordered_speeds():
    assert bench.parse_band("0.15,0.45") == (0.15, 0.45)
    for text in ("0.45,0.15", "-0.1,0.5", "0.5", "fast", "0.1,0.2,0.3"):
        with pytest.raises(argparse.ArgumentTypeError, match="--band"):
            bench.parse_band(text)


def test_the_judged_steps_are_split_by_their_body_s_true_speed():
    speed = np.array([0.0, 0.12, 0.3, 0.5, 0.64, 0.9, 0.3])
    judged = np.array([True, True, True, True, True, True, False])
    shares = bench.judged_breakdown(judged, speed, (0.15, 0.45))
    assert shares == pytest.approx(
        {"standing": 1 / 6, "below the band": 1 / 6, "in the band": 1 / 6, "just above": 2 / 6, "faster": 1 / 6}
    )
    assert all(math.isnan(v) for v in bench.judged_breakdown(np.zeros(3, bool), speed[:3], (0.15, 0.45)).values())
