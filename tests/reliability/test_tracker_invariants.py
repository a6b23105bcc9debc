"""The tracker invariants (item 5 of ``attentive_gym.envs.invariants``) hold on real runs and
catch planted faults: each fault below must be reported by name, so the check can fail."""

import dataclasses

import numpy as np
import pytest

from attentive_gym.attention import AttentionConfig, AttentionModel
from attentive_gym.envs.invariants import InvariantChecker, check_invariants, check_tracker
from attentive_gym.envs.rescue_env import AttentiveRescueEnv

DT = 0.05


def _tracked_model(steps: int = 12):
    """A tracker model after ``steps`` readings of two bodies: one approaching (beams 80..89,
    0.03 m closer per step), one still (beams 120..127 at 6 m); no echo elsewhere."""
    model = AttentionModel(AttentionConfig(kinematics="tracker"))
    sonar = np.full(16, 5.0)
    for k in range(steps):
        laser = np.full(180, 20.0)
        laser[80:90] = 4.0 - 0.03 * k
        laser[120:128] = 6.0
        output = model.step(k * DT, sonar, laser)
    return model, output


def _live(model) -> np.ndarray:
    return np.flatnonzero(model.tracker.alive)


def test_a_tracked_run_satisfies_the_tracker_invariants():
    model, output = _tracked_model()
    assert len(output.tracks) == 2 and output.tracks.confirmed.all()
    assert check_tracker(model.tracker, output.tracks) == []


@pytest.mark.parametrize(
    ("fault", "expected"),
    [
        ("nan_cv_x", "tracker cv_x is not finite"),
        ("inf_static_P", "tracker static_P is not finite"),
        ("non_pd_cv_P", "tracker covariance cv_P is not positive definite"),
        ("singular_static_P", "tracker covariance static_P is not positive definite"),
        ("asymmetric_cv_P", "tracker covariance cv_P is not symmetric"),
        ("p_moving_above_1", "tracker motion probability outside [0, 1]"),
        ("duplicate_id", "tracker ids"),
        ("tentative_without_segment", "tentative tracks but the last scan had 0 segments"),
        ("table_rows", "tracks table has 1 rows but the tracker has 2 live tracks"),
    ],
)
def test_planted_tracker_faults_are_reported(fault, expected):
    model, output = _tracked_model()
    tracker, tracks = model.tracker, output.tracks
    k, other = _live(model)
    if fault == "nan_cv_x":
        tracker.cv_x[k, 2] = np.nan
    elif fault == "inf_static_P":
        tracker.static_P[other, 1, 1] = np.inf
    elif fault == "non_pd_cv_P":
        tracker.cv_P[k] = np.diag([1.0, 1.0, 1.0, -1e-6])
    elif fault == "singular_static_P":
        tracker.static_P[k] = [[1.0, 1.0], [1.0, 1.0]]  # symmetric, eigenvalues 0 and 2
    elif fault == "asymmetric_cv_P":
        tracker.cv_P[k, 0, 3] += 1e-6 * np.abs(tracker.cv_P[k]).max()
    elif fault == "p_moving_above_1":
        tracker.p_moving[other] = 1.5
    elif fault == "duplicate_id":
        tracker.ids[other] = tracker.ids[k]
    elif fault == "tentative_without_segment":
        tracker.hits[k] = 1
        tracker.counters[1] = 0
    elif fault == "table_rows":
        tracks = dataclasses.replace(
            tracks, **{f.name: getattr(tracks, f.name)[:1] for f in dataclasses.fields(tracks)}
        )
    violations = check_tracker(tracker, tracks)
    assert any(expected in v for v in violations), violations
    assert len(violations) == 1, violations  # named precisely, nothing else flagged


def test_too_many_live_tracks_are_reported():
    model, _ = _tracked_model(steps=1)
    tracker = model.tracker
    tracker.alive[:] = True  # every slot live: 64 tentative tracks after a scan of 2 segments
    tracker.ids[:] = np.arange(tracker.alive.size)
    tracker.counters[0] = tracker.alive.size
    violations = check_tracker(tracker)
    assert any("64 tentative tracks but the last scan had 2 segments" in v for v in violations), violations
    model, _ = _tracked_model()
    tracker = model.tracker
    tracker.config = dataclasses.replace(tracker.config, max_tracks=1)  # 2 live tracks, 1 allowed
    assert check_tracker(tracker) == ["tracker has 2 live tracks, more than max_tracks=1"]


def test_check_invariants_runs_the_tracker_checks_with_the_model():
    env = AttentiveRescueEnv()
    obs, _ = env.reset(seed=3)
    model = AttentionModel()
    checker = InvariantChecker()
    for _ in range(40):
        obs, _, terminated, truncated, info = env.step(np.array([0.6, 0.2], np.float32))
        output = model.step(info["time_s"], obs["sonar"], obs["laser"], obs["odometry"])
        assert checker.check(env, obs, output, info, model=model) == []
    live = _live(model)
    assert live.size > 0  # the arena's walls and rubble give tracks
    model.tracker.cv_P[live[0]] = -np.eye(4)
    assert any("not positive definite" in v for v in check_invariants(env, obs, output, model=model))
    assert check_invariants(env, obs, output) == []  # without the model: the tracker is not checked
    broken = dataclasses.replace(output.tracks, speed_mps=np.full(len(output.tracks), np.nan))
    vars(output)["tracks"] = broken  # the cached property's slot
    assert any("tracks speed_mps is not finite" in v for v in check_invariants(env, obs, output))
    vars(output)["tracks"] = dataclasses.replace(broken, speed_mps=np.full(len(broken), -1.0))
    assert any("tracks speed_mps is negative" in v for v in check_invariants(env, obs, output))


def test_a_model_without_tracker_has_nothing_to_check():
    env = AttentiveRescueEnv()
    obs, _ = env.reset(seed=0)
    model = AttentionModel(AttentionConfig(kinematics="window"))
    output = model.step(0.0, obs["sonar"], obs["laser"], obs["odometry"])
    assert model.tracker is None and len(output.tracks) == 0
    assert check_invariants(env, obs, output, model=model) == []
