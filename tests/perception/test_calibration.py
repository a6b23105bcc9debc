"""The tracker's judgement of a speed goal is calibrated: of the tracks judged in the band
with probability p, about p are, and never fewer (``perception.calibration``). With the
occlusion rule (model version 2) its middle bins are under-confident: the probability of
moving it multiplies is no longer over-confident (docs/notes/2026-12-07-a-calibrated-goal-judgement.md)."""

import numpy as np
import pytest

from attentive_gym.perception import PERCEPTION_ARENA, make_attentive_env, stand_still
from attentive_gym.perception.calibration import JUDGED_FIELDS, brier, judged_track_steps, reliability

BAND = (0.5, 0.9)
#: The calibration benchmark's seeds and length, robot still (``benchmarks/calibration.py``).
SEEDS, SECONDS = (8, 9, 10, 11), 20.0


@pytest.fixture(scope="module")
def steps():
    env = make_attentive_env("tracker", 0.05, "saliency", sensor_noise=0.05, **PERCEPTION_ARENA)
    try:
        return judged_track_steps(env, BAND, SEEDS, SECONDS, lambda seed: stand_still)
    finally:
        env.close()


def test_every_confirmed_track_step_is_judged(steps):
    sizes = {len(steps[name]) for name in JUDGED_FIELDS}
    assert len(sizes) == 1 and sizes.pop() > 500
    assert steps["in_band"].sum() > 50  # movers in the band were tracked: the check is not vacuous
    assert np.all((steps["probability"] >= 0) & (steps["probability"] <= 1))
    speed = steps["true_speed"]  # the truth's flags are the true speed's
    np.testing.assert_array_equal(steps["in_band"], (BAND[0] <= speed) & (speed <= BAND[1]))
    np.testing.assert_array_equal(steps["truly_moving"], speed > 0.1)


def test_the_judgement_is_calibrated_and_beats_the_point_rule(steps):
    truth = steps["in_band"]
    rows = reliability(steps["probability"], truth)
    assert sum(row[2] for row in rows) == truth.size
    judged_high = steps["probability"] >= 0.5
    assert judged_high.sum() > 30
    for low, high, count, mean, share in rows:
        if count >= 40:  # never over-confident beyond sampling noise; under-confident by at most 0.25
            assert mean - 0.1 <= share <= mean + 0.25, (low, high, count, mean, share)
    assert truth[judged_high].mean() >= 0.8  # of the tracks judged in band, most are
    assert brier(steps["probability"], truth) < brier(steps["point"], truth)
