"""The speed goal judged from a track's velocity, covariance and probability of moving
(``AttentionConfig.track_speed_goal_probability``, ``track_regions.speed_goal_probability``)."""

import math

import numpy as np
import pytest

from attentive_gym.attention import AttentionConfig, AttentionModel, Goal
from attentive_gym.attention.tracking.track_regions import speed_goal_probability
from attentive_gym.wrappers.variants import make_env

BAND = (0.5, 0.9)
N_STEPS = 150


def _phi(z: float) -> float:
    return 0.5 * (1.0 + math.erf(z / math.sqrt(2.0)))


def test_the_probability_is_the_normal_speed_along_the_velocity_times_moving():
    # speed 0.7 along x, σ 0.1 along it (the cross-axis variance does not count): ±2σ
    assert speed_goal_probability(0.7, 0.0, 0.01, 0.0, 4.0, 1.0, *BAND) == pytest.approx(_phi(2) - _phi(-2))
    # the same velocity turned 90° and 45°, the covariance turned with it
    assert speed_goal_probability(0.0, 0.7, 4.0, 0.0, 0.01, 1.0, *BAND) == pytest.approx(_phi(2) - _phi(-2))
    c = math.sqrt(0.5)
    rot = np.array([[c, -c], [c, c]])
    spread = rot @ np.diag([0.01, 4.0]) @ rot.T
    assert speed_goal_probability(0.7 * c, 0.7 * c, spread[0, 0], spread[0, 1], spread[1, 1], 1.0, *BAND) == (
        pytest.approx(_phi(2) - _phi(-2))
    )
    # weighted by the probability of moving: a static body has no speed
    assert speed_goal_probability(0.7, 0.0, 0.01, 0.0, 0.01, 0.4, *BAND) == pytest.approx(0.4 * (_phi(2) - _phi(-2)))
    assert speed_goal_probability(0.7, 0.0, 0.01, 0.0, 0.01, 0.0, *BAND) == 0.0
    # an open range: GREATER(0.5) and SMALLER(0.5)
    assert speed_goal_probability(0.6, 0.0, 0.01, 0.0, 0.01, 1.0, 0.5, math.inf) == pytest.approx(_phi(1))
    assert speed_goal_probability(0.6, 0.0, 0.01, 0.0, 0.01, 1.0, -math.inf, 0.5) == pytest.approx(1 - _phi(1))
    # known exactly: the point rule
    assert speed_goal_probability(0.7, 0.0, 0.0, 0.0, 0.0, 1.0, *BAND) == 1.0
    assert speed_goal_probability(0.95, 0.0, 0.0, 0.0, 0.0, 1.0, *BAND) == 0.0
    # at rest, the mean variance: speed 0 with σ 1 in [0.5, 0.9]
    assert speed_goal_probability(0.0, 0.0, 0.5, 0.0, 1.5, 1.0, *BAND) == pytest.approx(_phi(0.9) - _phi(0.5))


def test_a_mean_outside_the_band_is_never_judged_in_it():
    rng = np.random.default_rng(0)
    for _ in range(2000):
        vx, vy = rng.uniform(-1.5, 1.5, 2)
        a = rng.normal(size=(2, 2))
        spread = a @ a.T * rng.uniform(0.001, 1.0)
        p = speed_goal_probability(vx, vy, spread[0, 0], spread[0, 1], spread[1, 1], rng.uniform(0, 1), *BAND)
        assert 0.0 <= p <= 1.0
        if not BAND[0] <= math.hypot(vx, vy) <= BAND[1]:
            assert p < 0.5


@pytest.fixture(scope="module")
def drive():
    """``N_STEPS`` random-drive steps of the raw env (5 % noise, seed 3): ``(t, sonar, laser,
    odometry)`` each."""
    env = make_env("raw")
    env.reset(seed=3)
    rng = np.random.default_rng(3)
    steps = []
    for _ in range(N_STEPS):
        obs, _, _, _, info = env.step(rng.uniform(-1, 1, 2).astype(np.float32))
        steps.append((info["time_s"], obs["sonar"].copy(), obs["laser"].copy(), obs["odometry"].copy()))
    env.close()
    return steps


@pytest.mark.parametrize("grid", ["sonar", "laser"])
def test_f4_and_the_goal_follow_the_probability_at_the_regions_track(drive, grid):
    config = AttentionConfig(range_noise_rel=0.05, track_speed_goal_probability=True, grid=grid)
    model = AttentionModel(config)
    model.set_goals(Goal.between("speed", *BAND))
    judged = held = 0
    for t, sonar, laser, odometry in drive:
        out = model.step(t, sonar, laser, odometry)
        tracks = out.tracks
        for j in range(len(out.F[3])):
            view = out.view_of(j)
            if view.track_id is None:
                continue
            k = int(np.flatnonzero(tracks.id == view.track_id)[0])
            p_moving = tracks.moving_probability[k]
            vx, vy = tracks.velocity_mps[k] / p_moving if p_moving > 0 else (0.0, 0.0)
            s = tracks.covariance[k]
            p = speed_goal_probability(vx, vy, s[2, 2], s[2, 3], s[3, 3], p_moving, *BAND)
            if abs(p - 0.5) < 1e-6:
                continue
            target = p_moving > 0.5 and min(tracks.speed_mps[k], config.max_speed_mps) > config.direction_epsilon_mps
            assert out.F[3, j] == pytest.approx(min(1.0, 2.0 * p) * target, abs=1e-9)
            assert out.goal_fulfilled[j] == (p >= 0.5 and target)
            judged += 1
            held += bool(out.goal_fulfilled[j])
    assert judged > 100 and held > 5  # the judgement was exercised, both ways


def test_off_the_goal_is_judged_from_the_weighted_speed(drive):
    """The default keeps the table over the region's speed (model version 1's outputs)."""
    assert not AttentionConfig().track_speed_goal_probability
    model = AttentionModel(AttentionConfig(range_noise_rel=0.05))
    goal = Goal.between("speed", *BAND)
    model.set_goals(goal)
    differs = 0
    on = AttentionModel(AttentionConfig(range_noise_rel=0.05, track_speed_goal_probability=True))
    on.set_goals(goal)
    for t, sonar, laser, odometry in drive:
        out, out_on = model.step(t, sonar, laser, odometry), on.step(t, sonar, laser, odometry)
        # in band and a target (F4 = the table's 1 × the target flag)
        held = np.array([goal.is_fulfilled(s) for s in out.speeds_mps])
        np.testing.assert_array_equal(out.goal_fulfilled, held & (out.F[3] == 1.0))
        differs += int(np.any(out.F[3] != out_on.F[3]))
    assert differs > 0
