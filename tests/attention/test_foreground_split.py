"""Bodies standing in front of structure (docs/model.md §10, "Bodies in front of structure"):
``segmentation.split_foreground`` finds them inside static-structure segments, and the tracker
follows them; walls, slanted walls and box corners stay static."""

import math

import numpy as np
import pytest

from attentive_gym.attention import AttentionConfig, AttentionModel
from attentive_gym.attention.regions import laser_bearings_rad
from attentive_gym.attention.tracking.segmentation import (
    SEGMENT_FIELDS,
    STRUCTURE,
    TRACKABLE,
    UPDATE_ONLY,
    measure_segments,
    segment_scan,
    split_foreground,
)

BEAMS = laser_bearings_rad()
COS, SIN = np.cos(BEAMS), np.sin(BEAMS)
STEP_RAD = math.radians(1.0)
NO_ECHO_M = 19.99
RADIUS_M = 0.25  # a victim
DT_S = 0.05
X, Y, CANDIDATE = (SEGMENT_FIELDS.index(f) for f in ("x_m", "y_m", "candidate"))
DEFAULTS = AttentionConfig()


def _noisy(rng, ranges, sigma=0.05, max_range=20.0):
    out = ranges * (1.0 + sigma * rng.standard_normal(ranges.shape))
    return np.where(ranges >= max_range, max_range, np.clip(out, 0.0, max_range))


def _segments(laser, *, flank_beams=DEFAULTS.foreground_flank_beams, capacity=180):
    """(count before the split, count after, bounds, table) of one scan, with the defaults."""
    c = DEFAULTS
    bounds = np.zeros((capacity, 2), np.int64)
    table = np.zeros((capacity, len(SEGMENT_FIELDS)))
    n = segment_scan(
        laser, NO_ECHO_M, c.range_noise_rel, c.range_noise_floor_m, c.segment_jump_m, c.segment_jump_sigmas, bounds
    )
    measure_segments(
        laser,
        COS,
        SIN,
        STEP_RAD,
        NO_ECHO_M,
        bounds,
        n,
        c.range_noise_rel,
        c.range_noise_floor_m,
        c.track_surface_sigma_m,
        c.max_object_extent_m,
        c.segment_min_beams,
        table,
    )
    total = split_foreground(
        laser,
        COS,
        SIN,
        STEP_RAD,
        NO_ECHO_M,
        bounds,
        n,
        c.range_noise_rel,
        c.range_noise_floor_m,
        c.track_surface_sigma_m,
        c.max_object_extent_m,
        c.segment_min_beams,
        flank_beams,
        c.foreground_sigmas,
        c.foreground_margin_m,
        c.foreground_edge_sigmas,
        table,
    )
    return n, total, bounds, table


def _trackable_at(table, count, xy, within_m=0.2):
    return any(
        table[m, CANDIDATE] == TRACKABLE and math.hypot(table[m, X] - xy[0], table[m, Y] - xy[1]) < within_m
        for m in range(count)
    )


def _box(cx, cy, half, angle):
    """The four sides of a square box (segments for ``scene.cast``)."""
    c, s = math.cos(angle), math.sin(angle)
    corners = [
        (cx + c * dx - s * dy, cy + s * dx + c * dy)
        for dx, dy in ((half, half), (-half, half), (-half, -half), (half, -half))
    ]
    return [(*corners[i], *corners[(i + 1) % 4]) for i in range(4)]


WALL = [(3.75, -10.0, 3.75, 10.0)]  # 0.5 m behind a victim centred 3 m ahead
DISC = (3.0, 0.4)


# --- the split itself ------------------------------------------------------------------------------
def test_a_disc_half_a_metre_before_a_wall_merges_with_it_without_the_split(scene):
    laser = scene.cast((0, 0), 0.0, BEAMS, segments=WALL, circles=[(*DISC, RADIUS_M)])
    n, total, _, table = _segments(laser, flank_beams=0)
    assert total == n and not _trackable_at(table, n, DISC)  # one wall segment, static structure
    assert table[:n, CANDIDATE].tolist() == [STRUCTURE]


def test_a_disc_half_a_metre_before_a_wall_is_split_off_noise_free(scene):
    laser = scene.cast((0, 0), 0.0, BEAMS, segments=WALL, circles=[(*DISC, RADIUS_M)])
    n, total, bounds, table = _segments(laser)
    assert total == n + 1
    assert table[n, CANDIDATE] == TRACKABLE
    # its centre, not its surface (0.2 m nearer), as any segment's (the extent of its beams is 0.4 m)
    assert math.hypot(table[n, X] - DISC[0], table[n, Y] - DISC[1]) < 0.08
    hit = np.flatnonzero(laser < 3.5)  # the disc's beams
    assert bounds[n].tolist() == [hit[0], hit[-1] + 1]
    assert table[0, CANDIDATE] == STRUCTURE  # the wall around it stays structure


@pytest.mark.parametrize("distance_m", [2.0, 3.0, 4.0])
def test_a_disc_half_a_metre_before_a_wall_is_split_off_under_5_percent_noise(scene, distance_m):
    disc = (distance_m, 0.4)
    wall = [(distance_m + RADIUS_M + 0.5, -10.0, distance_m + RADIUS_M + 0.5, 10.0)]
    clean = scene.cast((0, 0), 0.0, BEAMS, segments=wall, circles=[(*disc, RADIUS_M)])
    rng = np.random.default_rng(11)
    found = sum(
        _trackable_at(table, total, disc, 0.3)
        for _, total, _, table in (_segments(_noisy(rng, clean)) for _ in range(50))
    )
    assert found >= 45  # measured: 50, 50 and 48 of 50


def test_a_disc_split_from_the_wall_on_one_side_only_is_found_at_the_segment_end(scene):
    # noise-free, the jump on the disc's right edge breaks the scan and the left one does not
    disc = (3.0, -1.0)
    wall = [(3.85, -10.0, 3.85, 10.0)]
    laser = scene.cast((0, 0), 0.0, BEAMS, segments=wall, circles=[(*disc, RADIUS_M)])
    n0 = _segments(laser, flank_beams=0)[0]
    assert n0 == 2  # wall | disc + wall: the disc sits at one end of a structure segment
    n, total, _, table = _segments(laser)
    assert total == n + 1 and _trackable_at(table, total, disc, 0.1)


@pytest.mark.parametrize(
    "name, walls",
    [
        ("wall at 4 m", [(4.0, -10.0, 4.0, 10.0)]),
        ("wall at 8 m", [(8.0, -20.0, 8.0, 20.0)]),
        ("oblique wall, 30 deg", [(3.0, -6.0, 3.0 + 12.0 * math.tan(math.radians(30)), 6.0)]),
        ("oblique wall, 60 deg", [(1.0, -3.0, 1.0 + 6.0 * math.tan(math.radians(60)), 3.0)]),
        ("corridor", [(-20.0, 1.0, 20.0, 1.0), (-20.0, -1.5, 20.0, -1.5)]),
        ("room", [(5.0, -5.0, 5.0, 5.0), (-5.0, 5.0, 5.0, 5.0), (-5.0, -5.0, 5.0, -5.0)]),
    ],
)
def test_noise_does_not_split_plain_walls(scene, name, walls):
    clean = scene.cast((0, 0), 0.0, BEAMS, segments=walls)
    assert _segments(clean)[1] == _segments(clean)[0]
    rng = np.random.default_rng(5)
    false_runs = sum(total - n for n, total, _, _ in (_segments(_noisy(rng, clean)) for _ in range(500)))
    assert false_runs <= 1, name  # measured: at most 1 scan in 3000 on any of them


def test_a_box_larger_than_a_body_before_a_wall_is_not_cut_into_one(scene):
    # a 1 m box seen across its diagonal (1.4 m) 0.4 m before a wall: it merges with the wall;
    # its parts that would fit max_object_extent_m are not bodies either
    walls = _box(3.5, 0.3, 0.5, math.radians(45)) + [(4.6, -10.0, 4.6, 10.0)]
    clean = scene.cast((0, 0), 0.0, BEAMS, segments=walls)
    rng = np.random.default_rng(0)
    runs = sum(total - n for n, total, _, _ in (_segments(_noisy(rng, clean)) for _ in range(300)))
    assert runs <= 3


def test_the_split_fills_the_table_only_as_far_as_it_holds(scene):
    laser = scene.cast((0, 0), 0.0, BEAMS, segments=WALL, circles=[(*DISC, RADIUS_M)])
    n, total, _, _ = _segments(laser, capacity=1)
    assert n == total == 1


def test_a_short_run_may_update_a_track_but_not_start_one(scene):
    laser = scene.cast((0, 0), 0.0, BEAMS, segments=WALL, circles=[(*DISC, RADIUS_M)])
    c = DEFAULTS
    bounds = np.zeros((180, 2), np.int64)
    table = np.zeros((180, len(SEGMENT_FIELDS)))
    n = segment_scan(
        laser, NO_ECHO_M, c.range_noise_rel, c.range_noise_floor_m, c.segment_jump_m, c.segment_jump_sigmas, bounds
    )
    measure_segments(
        laser,
        COS,
        SIN,
        STEP_RAD,
        NO_ECHO_M,
        bounds,
        n,
        c.range_noise_rel,
        c.range_noise_floor_m,
        c.track_surface_sigma_m,
        c.max_object_extent_m,
        50,
        table,
    )
    total = split_foreground(
        laser,
        COS,
        SIN,
        STEP_RAD,
        NO_ECHO_M,
        bounds,
        n,
        c.range_noise_rel,
        c.range_noise_floor_m,
        c.track_surface_sigma_m,
        c.max_object_extent_m,
        50,
        c.foreground_flank_beams,
        c.foreground_sigmas,
        c.foreground_margin_m,
        c.foreground_edge_sigmas,
        table,
    )
    assert total == n + 1 and table[n, CANDIDATE] == UPDATE_ONLY  # fewer than segment_min_beams=50


# --- the tracker ---------------------------------------------------------------------------------------
def _run(
    scene, walls, discs_at, steps, *, seed, robot_at=lambda t: ((0.0, 0.0), 0.0), odometry=lambda t: None, **config
):
    rng = np.random.default_rng(seed)
    model = AttentionModel(AttentionConfig(laser_mount_x_m=0.0, **config))
    outs = []
    for k in range(steps):
        t = k * DT_S
        origin, heading = robot_at(t)
        sonar, laser = scene.readings(
            origin, heading, segments=walls, circles=[(x, y, RADIUS_M) for x, y in discs_at(t)]
        )
        outs.append(
            model.step(
                t,
                _noisy(rng, sonar, max_range=scene.SONAR_MAX_M),
                _noisy(rng, laser, max_range=scene.LASER_MAX_M),
                odometry(t),
            )
        )
    return outs


@pytest.mark.parametrize("seed", range(3))
def test_a_victim_walking_along_a_wall_keeps_one_track(scene, seed):
    # 0.5 m in front of the wall, crossing the view at 0.5 m/s, under 5 % noise
    def discs(t):
        return [(3.0, -1.5 + 0.5 * t)]

    def followed(**config):
        ids, missed = [], 0
        for k, out in enumerate(_run(scene, WALL, discs, 120, seed=seed, **config)[20:], start=20):
            tracks, xy = out.tracks, np.array(discs(k * DT_S)[0])
            d = np.hypot(*(tracks.position_m - xy).T) if len(tracks) else np.array([np.inf])
            i = int(np.argmin(d))
            if d[i] < 0.5 and tracks.confirmed[i]:
                ids.append(int(tracks.id[i]))
            else:
                missed += 1
        return ids, missed

    ids, missed = followed()
    assert missed == 0 and len(set(ids)) == 1
    ids, missed = followed(foreground_flank_beams=0)
    assert missed == 100  # without the split the victim is part of the wall


@pytest.mark.parametrize(
    "name, walls",
    [
        ("wall", [(4.0, -10.0, 4.0, 10.0)]),
        ("oblique wall", [(2.0, -6.0, 2.0 + 12.0 * math.tan(math.radians(50)), 6.0)]),
        ("box corner", _box(3.0, 0.3, 0.35, math.radians(45)) + [(3.9, -10.0, 3.9, 10.0)]),
        ("big box before a wall", _box(3.5, 0.3, 0.5, math.radians(45)) + [(4.6, -10.0, 4.6, 10.0)]),
    ],
)
@pytest.mark.parametrize("driving", [False, True])
@pytest.mark.parametrize("start_test", [0.0, 6.0])
def test_static_structure_gives_no_moving_track(scene, name, walls, driving, start_test):
    # a box in front of a wall is split off and tracked as a static body, like a box standing
    # alone: its track's speed starts from the constant-velocity filter's first guesses (up to
    # ~0.5 m/s for a box standing alone, in its first second) and then stays near 0; with the
    # start test on too (a box corner's segment that misses a scan and comes back reshaped, or
    # that shrinks as the robot drives past, must not read as a start)
    motion = dict(robot_at=lambda t: ((0.5 * t - 1.0, -1.5), 0.0), odometry=lambda t: (0.5, 0.0)) if driving else {}
    speeds, settled = [], [0.0]
    for seed in range(4):
        for out in _run(scene, walls, lambda t: [], 80, seed=seed, track_onset_log_ratio=start_test, **motion):
            tracks = out.tracks
            speeds += tracks.speed_mps[tracks.confirmed].tolist()
            settled += tracks.speed_mps[tracks.confirmed & (tracks.age_s > 1.0)].tolist()
    assert max(settled) < 0.1, name  # measured: at most 0.08 m/s (driving past the box)
    if speeds:
        assert np.percentile(speeds, 90) < (0.1 if driving else 0.05), name  # measured: 0.02 still, 0.09 driving
    if name in ("wall", "oblique wall"):
        assert not speeds  # no track at all


@pytest.mark.parametrize(
    "field, value",
    [
        ("foreground_flank_beams", -1),
        ("foreground_flank_beams", 2.5),
        ("foreground_flank_beams", True),
        ("foreground_sigmas", 0.0),
        ("foreground_edge_sigmas", -1.0),
        ("foreground_margin_m", -0.1),
        ("foreground_margin_m", float("nan")),
    ],
)
def test_bad_foreground_settings_are_refused(field, value):
    with pytest.raises(ValueError, match=field):
        AttentionConfig(**{field: value})


def test_the_search_can_be_turned_off(scene):
    laser = scene.cast((0, 0), 0.0, BEAMS, segments=WALL, circles=[(*DISC, RADIUS_M)])
    n, total, _, _ = _segments(laser, flank_beams=0)
    assert total == n
