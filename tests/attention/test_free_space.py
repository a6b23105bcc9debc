"""Free-space evidence of motion (attention.tracking.free_space) on hand-built laser scans.

Scans are cast with the sensors' analytic ray caster over small scenes (walls, boxes,
round bodies): a body that appears in free space, bodies moving along a wall, a body moving
away, and the robot driving and turning past static structure, which must give no evidence.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from attentive_gym.attention.tracking import free_space
from attentive_gym.sensors.geometry import SceneGeometry
from attentive_gym.sensors.raycast import cast_fan

BEAMS = 180
STEP = math.radians(1.0)
FIRST = -math.pi / 2
MAX_RANGE = 20.0
BODY = 7  # the owner id of the moving body in the scenes
LAGS = np.array([0.1, 0.2, 0.4, 0.7, 1.0])
DT = 0.05
# the evidence's thresholds as the tests use them: each beam ≥ 1 σ, a run ≥ 4 σ over ≥ 3 beams
BEAM_SIGMAS, RUN_SIGMAS, MIN_BEAMS = 1.0, 4.0, 3
EVERY_BEAM = np.ones(BEAMS, np.bool_)


def parameters(noise_rel: float = 0.01) -> np.ndarray:
    return free_space.evidence_parameters(FIRST, STEP, MAX_RANGE - 0.01, noise_rel, 0.01, 0.05, 0.05)


def scene(segments=(), circles=(), owners=None) -> SceneGeometry:
    segments = np.array(segments, float).reshape(-1, 4)
    circles = np.array(circles, float).reshape(-1, 3)
    owners = np.arange(len(circles)) + 100 if owners is None else np.array(owners)
    return SceneGeometry(segments, np.arange(len(segments)), circles, owners)


def box(cx: float, cy: float, angle: float, length: float, width: float) -> list[list[float]]:
    c, s = math.cos(angle), math.sin(angle)
    corners = [(-length / 2, -width / 2), (length / 2, -width / 2), (length / 2, width / 2), (-length / 2, width / 2)]
    points = [(cx + c * dx - s * dy, cy + s * dx + c * dy) for dx, dy in corners]
    return [[*points[i], *points[(i + 1) % 4]] for i in range(4)]


def cast(geometry: SceneGeometry, pose, rng=None, noise_rel: float = 0.0):
    ranges, owners = cast_fan(np.asarray(pose[:2]), pose[2] + FIRST + 0.5 * STEP, STEP, BEAMS, MAX_RANGE, geometry)
    if noise_rel:
        ranges = np.clip(ranges * (1.0 + noise_rel * rng.standard_normal(BEAMS)), 0.0, MAX_RANGE)
    return ranges, owners


class Run:
    """A history fed one scan per step, and the evidence of the latest."""

    def __init__(self, noise_rel: float = 0.0, wanted: np.ndarray = EVERY_BEAM):
        self.history = free_space.ScanHistory.empty(24, BEAMS)
        self.params = parameters(max(noise_rel, 0.01))
        self.appeared = np.zeros(BEAMS)
        self.flags = np.zeros(BEAMS, np.bool_)
        self.wanted = wanted

    def scan(self, t: float, ranges: np.ndarray, pose) -> np.ndarray:
        """The flags of this scan's moving evidence; then the scan is remembered."""
        h = self.history
        pose = np.asarray(pose, float)
        history = (h.times, h.poses, h.ranges, h.counters)
        free_space.scan_evidence(t, ranges, pose, LAGS, *history, self.params, self.wanted, BEAM_SIGMAS, self.appeared)
        free_space.evidence_runs(self.appeared, BEAM_SIGMAS, RUN_SIGMAS, MIN_BEAMS, self.flags)
        free_space.remember_scan(t, ranges, pose, 0.9 * DT, h.times, h.poses, h.ranges, h.counters)
        return self.flags.copy()


def test_a_body_appearing_in_free_space_is_flagged_and_nothing_else():
    wall = [[5.0, -5.0, 5.0, 5.0]]
    run = Run()
    for k in range(10):
        run.scan(k * DT, cast(scene(wall), (0.0, 0.0, 0.0))[0], (0.0, 0.0, 0.0))
    ranges, owners = cast(scene(wall, [[3.0, 0.0, 0.2]], [BODY]), (0.0, 0.0, 0.0))
    flags = run.scan(10 * DT, ranges, (0.0, 0.0, 0.0))
    assert flags[owners == BODY].all()
    assert not flags[owners != BODY].any()


def test_evidence_worked_out_for_some_beams_matches_the_whole_scans_there():
    """A body moving along a wall under 5 % noise: with only one beam of the body wanted, the
    scores worked out are the whole scan's, the run through that beam is flagged as in the
    whole scan, and nothing else is flagged."""
    radius, wall = 0.2, [[3.0, -5.0, 3.0, 5.0]]
    rng_whole, rng_some = np.random.default_rng(3), np.random.default_rng(3)
    whole, some = Run(0.05), Run(0.05)
    flagged = 0
    for k in range(30):
        y = -1.0 + 0.5 * DT * k
        geometry = scene(wall, [[2.5 - radius, y, radius]], [BODY])
        ranges_whole, owners = cast(geometry, (0.0, 0.0, 0.0), rng_whole, 0.05)
        ranges_some, _ = cast(geometry, (0.0, 0.0, 0.0), rng_some, 0.05)
        body = np.flatnonzero(owners == BODY)
        wanted = np.zeros(BEAMS, np.bool_)
        wanted[body[len(body) // 2]] = True
        some.wanted = wanted
        flags_whole = whole.scan(k * DT, ranges_whole, (0.0, 0.0, 0.0))
        flags_some = some.scan(k * DT, ranges_some, (0.0, 0.0, 0.0))
        worked_out = some.appeared > 0.0
        assert np.array_equal(some.appeared[worked_out], whole.appeared[worked_out]), k
        run = np.zeros(BEAMS, np.bool_)  # the whole scan's run of passing beams through the wanted one
        for direction in (-1, 1):
            b = body[len(body) // 2]
            while 0 <= b < BEAMS and whole.appeared[b] >= BEAM_SIGMAS:
                run[b] = True
                b += direction
        assert np.array_equal(flags_some[run], flags_whole[run]), k
        assert not flags_some[~run].any(), k
        flagged += int(flags_some.sum())
    assert flagged > 0  # the body was flagged: the comparison saw evidence, not only its absence


@pytest.mark.parametrize("gap_m", [0.2, 0.5, 0.9])
def test_a_body_moving_along_a_wall_is_flagged_within_0_3_s(gap_m):
    """A body of radius 0.2 m with ``gap_m`` between it and a wall 3 m ahead, moving at 0.5 m/s
    along the wall, noise-free: from 0.3 s on (when its leading edge has moved over 3 beams)
    every scan flags it, and no scan flags anything else."""
    radius, wall = 0.2, [[3.0, -5.0, 3.0, 5.0]]
    run = Run()
    for k in range(30):
        y = -1.0 + 0.5 * DT * k
        ranges, owners = cast(scene(wall, [[3.0 - gap_m - radius, y, radius]], [BODY]), (0.0, 0.0, 0.0))
        flags = run.scan(k * DT, ranges, (0.0, 0.0, 0.0))
        if k >= 6:
            assert flags[owners == BODY].sum() >= MIN_BEAMS, k
        assert not flags[owners != BODY].any(), k


@pytest.mark.parametrize(("wall_m", "gap_m", "least"), [(2.0, 0.2, 0.95), (3.0, 0.2, 0.9), (3.5, 0.5, 0.95)])
def test_under_5_percent_noise_bodies_near_walls_are_mostly_flagged(wall_m, gap_m, least):
    """The share of scans (after 1 s of motion, 40 runs) in which the body is flagged on at
    least 3 beams, at 5 % range noise (measured: 1.0, 0.99 and 1.0)."""
    rng = np.random.default_rng(1)
    radius, found, total = 0.2, 0, 0
    for _ in range(40):
        run, y0 = Run(0.05), rng.uniform(-1.5, -0.5)
        for k in range(41):
            geometry = scene(
                [[wall_m, -5.0, wall_m, 5.0]], [[wall_m - gap_m - radius, y0 + 0.5 * DT * k, radius]], [BODY]
            )
            ranges, owners = cast(geometry, (0.0, 0.0, 0.0), rng, 0.05)
            flags = run.scan(k * DT, ranges, (0.0, 0.0, 0.0))
            if k >= 20:
                found += flags[owners == BODY].sum() >= MIN_BEAMS
                total += 1
    assert found / total >= least


def test_a_body_moving_away_is_seen_through_where_it_was():
    """Straight away from the laser a body gives no echo in free space (its new place was
    hidden behind it), but its old front point is now seen through (the vacated test)."""
    wall = [[6.0, -5.0, 6.0, 5.0]]
    params = parameters()
    run = Run()
    for k in range(12):
        x = 2.0 + 0.5 * DT * k
        ranges, owners = cast(scene(wall, [[x, 0.0, 0.2]], [BODY]), (0.0, 0.0, 0.0))
        flags = run.scan(k * DT, ranges, (0.0, 0.0, 0.0))
    assert not flags.any()
    old_front = 2.0 - 0.2
    assert free_space.seen_through(old_front, 0.0, ranges, np.zeros(3), params) > RUN_SIGMAS
    now_front = x - 0.2
    assert free_space.seen_through(now_front + 0.02, 0.0, ranges, np.zeros(3), params) == 0.0


def test_driving_and_turning_past_static_structure_gives_no_evidence():
    """The robot drives and turns through a room of boxes and round rubble, noise-free: with
    each scan's true pose, no beam is ever flagged, though the view sweeps over depth edges
    and surfaces seen at grazing angles."""
    rng = np.random.default_rng(3)
    for _ in range(20):
        geometry = _static_room(rng)
        run = Run()
        x, y, heading = 0.0, 0.0, rng.uniform(-math.pi, math.pi)
        linear, angular = rng.uniform(0.0, 0.7), rng.uniform(-1.0, 1.0)
        for k in range(40):
            pose = (x, y, heading)
            assert not run.scan(k * DT, cast(geometry, pose)[0], pose).any()
            x, y = x + linear * DT * math.cos(heading), y + linear * DT * math.sin(heading)
            heading += angular * DT


def test_static_scenes_under_noise_and_motion_give_almost_no_evidence():
    """Random static rooms at 5 % range noise, the robot still or driving: a scan with any
    flagged beam in at most 0.5 % of 2,100 scans (measured: none in 10,500 with these
    thresholds, 0.02 % with runs of 2 beams)."""
    rng = np.random.default_rng(4)
    flagged = scans = 0
    for trial in range(100):
        geometry = _static_room(rng)
        run = Run(0.05)
        x, y, heading = 0.0, 0.0, rng.uniform(-math.pi, math.pi)
        linear, angular = (rng.uniform(0.0, 0.7), rng.uniform(-1.0, 1.0)) if trial % 2 else (0.0, 0.0)
        for k in range(41):
            pose = (x, y, heading)
            flags = run.scan(k * DT, cast(geometry, pose, rng, 0.05)[0], pose)
            if k >= 20:
                flagged += flags.any()
                scans += 1
            x, y = x + linear * DT * math.cos(heading), y + linear * DT * math.sin(heading)
            heading += angular * DT
    assert scans == 2100
    assert flagged / scans <= 0.005


def _static_room(rng: np.random.Generator) -> SceneGeometry:
    """A 10 m walled room with up to 8 boxes and round rubble pieces, none within 1.8 m of the
    centre (where the robot drives)."""
    segments = [[-5.0, -5.0, 5.0, -5.0], [5.0, -5.0, 5.0, 5.0], [5.0, 5.0, -5.0, 5.0], [-5.0, 5.0, -5.0, -5.0]]
    circles = []
    for _ in range(8):
        x, y = rng.uniform(-4.5, 4.5, 2)
        if math.hypot(x, y) < 1.8:
            continue
        if rng.random() < 0.5:
            circles.append([x, y, rng.uniform(0.15, 0.4)])
        else:
            segments += box(x, y, rng.uniform(0.0, math.pi), rng.uniform(0.2, 1.5), rng.uniform(0.1, 0.6))
    return scene(segments, circles)


def test_the_history_keeps_one_scan_per_spacing_and_wraps():
    history = free_space.ScanHistory.empty(4, 3)
    pose, ranges = np.zeros(3), np.ones(3)
    stored = [
        free_space.remember_scan(
            t, ranges * t, pose, 0.09, history.times, history.poses, history.ranges, history.counters
        )
        for t in (0.0, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5)
    ]
    assert stored == [True, False, True, True, True, True, True]
    assert history.counters.tolist() == [2, 4]  # 6 stored in 4 rows: the next row is 2
    assert sorted(history.times.tolist()) == pytest.approx([0.2, 0.3, 0.4, 0.5])
    row = free_space.past_scan(0.6, 0.2, history.times, history.counters)
    assert history.times[row] == pytest.approx(0.4)
    assert free_space.past_scan(0.6, 2.0, history.times, history.counters) == -1  # none that old
    history.clear()
    assert free_space.past_scan(0.6, 0.2, history.times, history.counters) == -1


def test_runs_need_enough_beams_and_a_combined_score():
    scores = np.array([0.0, 2.0, 2.0, 0.0, 3.0, 3.0, 3.0, 0.5, 1.5, 1.5, 1.5, 1.5])
    flags = np.zeros(scores.shape, np.bool_)
    count = free_space.evidence_runs(scores, 1.0, 4.0, 3, flags)
    # [1:3] has 2 beams; [4:7] 3 beams, 9/√3 = 5.2 σ; [8:12] 4 beams, 6/√4 = 3 σ
    assert count == 3
    assert np.flatnonzero(flags).tolist() == [4, 5, 6]


def test_segment_evidence_is_the_share_of_each_segments_flagged_beams():
    flags = np.zeros(10, np.bool_)
    flags[2:5] = True
    bounds = np.array([[0, 2], [2, 6], [6, 10], [0, 0]], np.int64)
    shares = np.full(4, -1.0)
    free_space.segment_evidence(flags, bounds, 3, shares)
    assert shares.tolist() == [0.0, 0.75, 0.0, -1.0]  # the fourth row is not a segment


def _tracks(count: int):
    """Tracker arrays of ``count`` live tracks, each matched to segment k this scan, 3 m ahead
    and moving at 1 m/s: over a 1 s lag far more than ``DETECTABLE_SIGMAS`` of the range noise."""
    cv_x = np.zeros((count, 4))
    cv_x[:, 0], cv_x[:, 2] = 3.0, 1.0
    return {
        "segment_of": np.arange(count, dtype=np.int64),
        "static_x": np.zeros((count, 2)),
        "alive": np.ones(count, np.bool_),
        "born_s": np.zeros(count),
        "p_moving": np.full(count, 0.5),
        "cv_x": cv_x,
        "lag_s": 1.0,
    }


def test_weigh_motion_raises_tracks_with_evidence_and_lowers_those_without():
    weights = free_space.motion_weights(0.3, 4.0, 0.9, 2.0, -0.5, 1e-3)
    ranges = np.full(BEAMS, 10.0)  # a wall 10 m ahead everywhere
    tracks = _tracks(4)
    tracks["static_x"][:] = (20.0, 0.0)  # behind the wall: never seen through
    tracks["static_x"][2] = (3.0, 0.0)  # where the scan now passes freely: the body left
    tracks["born_s"][3] = 1.0  # born this scan
    shares = np.array([0.5, 0.0, 0.0, 0.5])
    free_space.weigh_motion(1.0, shares, ranges, np.zeros(3), parameters(), weights, **tracks)
    p = tracks["p_moving"]
    logistic = 1.0 / (1.0 + np.exp(-np.array([2.0, -0.5])))
    assert p[0] == pytest.approx(logistic[0])  # its segment's beams show evidence
    assert p[1] == pytest.approx(logistic[1])  # no evidence
    assert p[2] == pytest.approx(logistic[0])  # its static place is seen through
    assert p[3] == 0.9  # born moving


def test_a_matched_tracks_silence_counts_as_far_as_its_motion_was_detectable():
    """At 3 m with 1 % noise (σ 3 cm) over a 1 s lag: a track at 2 cm/s moves 0.67 σ, too
    little to leave evidence, and keeps its probability; one at 6 cm/s (2 σ) loses half the
    fading; one at 1 m/s the whole of it. Coasting (not matched), a slow track fades in full."""
    weights = free_space.motion_weights(0.3, 4.0, 0.9, 2.0, -0.5, 1e-3)
    tracks = _tracks(4)
    tracks["static_x"][:] = (20.0, 0.0)  # behind the wall: never seen through
    tracks["cv_x"][:, 2] = (0.02, 0.06, 1.0, 0.02)
    tracks["segment_of"][3] = -1
    state = tracks["cv_x"][0]
    assert free_space.detectability(state, np.zeros(3), parameters(), 1.0) == 0.0
    assert free_space.detectability(tracks["cv_x"][1], np.zeros(3), parameters(), 1.0) == pytest.approx(0.5)
    free_space.weigh_motion(1.0, np.zeros(4), np.full(BEAMS, 10.0), np.zeros(3), parameters(), weights, **tracks)
    logistic = 1.0 / (1.0 + np.exp(-np.array([0.0, -0.25, -0.5, -0.5])))
    np.testing.assert_allclose(tracks["p_moving"], logistic)


def test_weigh_motion_lowers_coasting_tracks_leaves_dead_ones_and_keeps_the_floor():
    weights = free_space.motion_weights(0.3, 4.0, 0.9, 2.0, -50.0, 1e-3)
    tracks = _tracks(3)
    tracks["static_x"][:] = (3.0, 0.0)  # seen through: evidence, were the tracks matched
    tracks["segment_of"][1] = -1  # not matched this scan: coasting, no evidence
    tracks["alive"][2] = False
    shares = np.array([0.0, 0.0, 1.0])
    free_space.weigh_motion(1.0, shares, np.full(BEAMS, 10.0), np.zeros(3), parameters(), weights, **tracks)
    assert tracks["p_moving"].tolist() == [pytest.approx(1.0 / (1.0 + math.exp(-2.0))), 1e-3, 0.5]


def test_bad_parameters_are_refused():
    with pytest.raises(ValueError, match="step_rad > 0"):
        free_space.evidence_parameters(FIRST, 0.0, 19.0, 0.05, 0.01, 0.05, 0.1)
    with pytest.raises(ValueError, match="finite"):
        free_space.evidence_parameters(FIRST, STEP, 19.0, math.nan, 0.01, 0.05, 0.1)
    with pytest.raises(ValueError, match="capacity"):
        free_space.ScanHistory.empty(0, BEAMS)
    with pytest.raises(ValueError, match="none_log_odds <= 0"):
        free_space.motion_weights(0.3, 4.0, 0.9, 2.0, 0.5, 1e-3)
