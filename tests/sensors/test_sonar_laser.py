"""The P2AT sonar ring and the laser scanner: hand-computed readings of simple scenes."""

from __future__ import annotations

import math

import numpy as np
import pymunk
import pytest

from attentive_gym.sensors import (
    P2AT_SONAR_MOUNTS,
    GeometryCache,
    LaserConfig,
    LaserScanner,
    SceneGeometry,
    SonarConfig,
    SonarRing,
    cast_rays,
)

POSES = [(0.0, 0.0, 0.0), (1.5, -2.0, 0.7), (-4.0, 3.0, -2.9)]
WALL_ID = 7


def _to_world(pose, points):
    """Robot-frame ``(n, 2)`` points in the world frame of a robot at ``pose``."""
    x, y, theta = pose
    c, s = math.cos(theta), math.sin(theta)
    points = np.asarray(points, float)
    return np.column_stack([x + c * points[:, 0] - s * points[:, 1], y + s * points[:, 0] + c * points[:, 1]])


def _scene(pose, segments=(), circles=(), owner=WALL_ID):
    """Robot-frame segments ``(x1, y1, x2, y2)`` and circles ``(cx, cy, r)`` placed around ``pose``."""
    segments = np.asarray(segments, float).reshape(-1, 4)
    circles = np.asarray(circles, float).reshape(-1, 3)
    world_segments = np.hstack([_to_world(pose, segments[:, :2]), _to_world(pose, segments[:, 2:])])
    world_circles = np.column_stack([_to_world(pose, circles[:, :2]), circles[:, 2]])
    return SceneGeometry(world_segments, np.full(len(segments), owner), world_circles, np.full(len(circles), owner))


def test_p2at_mounts():
    bearings = [90, 50, 30, 10, -10, -30, -50, -90, -90, -130, -150, -170, 170, 150, 130, 90]
    positions_mm = [
        (147, 136),
        (193, 119),
        (227, 79),
        (245, 27),
        (245, -27),
        (227, -79),
        (193, -119),
        (147, -136),
        (-144, -136),
        (-189, -119),
        (-223, -79),
        (-241, -27),
        (-241, 27),
        (-223, 79),
        (-189, 119),
        (-144, 136),
    ]
    assert P2AT_SONAR_MOUNTS.shape == (16, 3)
    np.testing.assert_allclose(np.degrees(P2AT_SONAR_MOUNTS[:, 2]), bearings, atol=1e-12)
    np.testing.assert_allclose(P2AT_SONAR_MOUNTS[:, :2] * 1000.0, positions_mm, atol=1e-9)
    assert not P2AT_SONAR_MOUNTS.flags.writeable
    np.testing.assert_array_equal(np.array(SonarConfig().mounts), P2AT_SONAR_MOUNTS)


@pytest.mark.parametrize("pose", POSES)
def test_sonar_sees_a_wall_ahead(pose):
    """Wall x = 3 m (robot frame). A cone containing the heading reads the perpendicular
    distance from its transducer; the others read along their boundary ray nearest the
    heading, (3 - x_mount) / cos(|bearing| - 15 deg), when that is within 5 m."""
    geometry = _scene(pose, segments=[(3.0, -30.0, 3.0, 30.0)])
    ranges, owners = SonarRing().read(pose, geometry)
    cos = lambda deg: math.cos(math.radians(deg))  # noqa: E731
    expected = [
        5.0,
        (3 - 0.193) / cos(35),
        (3 - 0.227) / cos(15),
        3 - 0.245,
        3 - 0.245,
        (3 - 0.227) / cos(15),
        (3 - 0.193) / cos(35),
        5.0,
    ] + [5.0] * 8  # s1/s8 would need (3 - 0.147) / cos(75) = 11 m
    np.testing.assert_allclose(ranges, expected, atol=1e-12)
    np.testing.assert_array_equal(owners, [-1] + [WALL_ID] * 6 + [-1] * 9)


@pytest.mark.parametrize("pose", POSES)
def test_laser_sees_a_wall_ahead(pose):
    """Beam i at bearing -89.5 + i deg from (0.16, 0): (3 - 0.16) / cos(bearing), up to 20 m."""
    geometry = _scene(pose, segments=[(3.0, -100.0, 3.0, 100.0)])
    ranges, owners = LaserScanner().read(pose, geometry)
    bearings = np.radians(-89.5 + np.arange(180))
    expected = (3.0 - 0.16) / np.cos(bearings)
    seen = expected <= 20.0
    assert seen.sum() == 2 * 82  # |bearing| <= 81.5 deg: 2.84 / cos(81.84 deg) = 20 m
    np.testing.assert_allclose(ranges[seen], expected[seen], rtol=0, atol=1e-9)
    np.testing.assert_array_equal(ranges[~seen], 20.0)
    np.testing.assert_array_equal(owners, np.where(seen, WALL_ID, -1))
    np.testing.assert_allclose(ranges[[89, 90]], 2.84 / math.cos(math.radians(0.5)), rtol=0, atol=1e-12)


def test_laser_beam_zero_is_the_rightmost():
    np.testing.assert_allclose(np.degrees(LaserConfig().bearings_rad), -89.5 + np.arange(180), atol=1e-12)
    pose = (2.0, 1.0, 0.4)
    geometry = _scene(pose, segments=[(-1.0, -2.0, 8.0, -2.0)])  # a wall 2 m to the right (y = -2)
    ranges, owners = LaserScanner().read(pose, geometry)
    assert owners[0] == WALL_ID and owners[-1] == -1
    assert ranges[0] == pytest.approx(2.0 / math.sin(math.radians(89.5)), abs=1e-12)
    assert np.all(owners[90:] == -1)


def test_a_body_behind_is_seen_only_by_rear_sonars():
    pose = (0.5, 0.5, 1.0)
    geometry = _scene(pose, circles=[(-2.0, 0.0, 0.3)])  # a pole 2 m behind
    ranges, owners = SonarRing().read(pose, geometry)
    np.testing.assert_array_equal(owners[:8], [-1] * 8)
    np.testing.assert_array_equal(ranges[:8], [5.0] * 8)
    # s12/s13 (-170/+170 deg, at (-0.241, -/+0.027)) point at its centre: 2 - 0.241 - 0.3 along x, offset 0.027 in y
    nearest = math.hypot(2.0 - 0.241, 0.027) - 0.3
    np.testing.assert_allclose(ranges[[11, 12]], nearest, atol=1e-12)
    np.testing.assert_array_equal(owners[[11, 12]], [WALL_ID, WALL_ID])
    assert set(owners[8:].tolist()) == {-1, WALL_ID}


def test_min_and_max_range_clamping():
    pose = (0.0, 0.0, 0.0)
    ring = SonarRing()
    near = _scene(pose, segments=[(0.3, -1.0, 0.3, 1.0)])  # 0.055 m from s4/s5: too near
    ranges, owners = ring.read(pose, near)
    assert ranges[3] == ranges[4] == 0.15 and owners[3] == owners[4] == WALL_ID
    far = _scene(pose, segments=[(0.245 + 4.999, -0.1, 0.245 + 4.999, 0.1)])  # 4.999 m from s4/s5: an echo
    ranges, owners = ring.read(pose, far)
    assert ranges[3] == pytest.approx(4.999, abs=1e-12) and owners[3] == WALL_ID
    beyond = _scene(pose, segments=[(0.245 + 5.001, -0.1, 0.245 + 5.001, 0.1)])
    ranges, owners = ring.read(pose, beyond)
    assert ranges[3] == 5.0 and owners[3] == -1
    ranges, owners = LaserScanner().read(pose, _scene(pose, segments=[(25.0, -1.0, 25.0, 1.0)]))
    assert np.all(ranges == 20.0) and np.all(owners == -1)


def test_the_robot_body_is_excluded():
    """The transducers sit inside the P2AT's box: without exclusion they see its outline."""
    space = pymunk.Space()
    robot = pymunk.Body(14.0, 1.0)
    robot.position, robot.angle = (1.0, 2.0), 0.5
    box = pymunk.Poly.create_box(robot, (0.626, 0.505))
    wall = pymunk.Segment(space.static_body, (-10.0, 4.0), (10.0, 4.0), 0.0)
    space.add(robot, box, wall)
    geometry = GeometryCache([(0, robot, [box]), (WALL_ID, space.static_body, [wall])]).update()
    pose = (1.0, 2.0, 0.5)
    ranges, owners = SonarRing().read(pose, geometry)
    assert np.all(owners == 0) and np.all(ranges == 0.15)  # every transducer is within 0.15 m of the outline
    ranges, owners = SonarRing().read(pose, geometry, exclude_owner=0)
    assert 0 not in owners and WALL_ID in owners
    laser, laser_owners = LaserScanner().read(pose, geometry, exclude_owner=0)
    assert 0 not in laser_owners
    origin = (1.0 + 0.16 * math.cos(0.5), 2.0 + 0.16 * math.sin(0.5))
    angles = 0.5 + LaserConfig().bearings_rad
    expected, _ = cast_rays(np.repeat([origin], 180, 0), angles, 20.0, geometry, exclude_owner=0)
    np.testing.assert_allclose(laser, expected, atol=1e-12)
    _, laser_owners = LaserScanner().read(pose, geometry)
    assert np.all(laser_owners == 0)  # the laser's origin is inside the box


def test_a_cone_never_misses_a_thin_pole():
    """A 1 cm pole 12 deg off s4's axis, between the rays a 5-ray fan (7.5 deg apart) would cast."""
    pose = (0.0, 0.0, 0.0)
    mx, my, bearing = P2AT_SONAR_MOUNTS[4]
    angle = bearing + math.radians(11.0)
    pole = (mx + 2.0 * math.cos(angle), my + 2.0 * math.sin(angle), 0.005)
    ranges, owners = SonarRing().read(pose, _scene(pose, circles=[pole]))
    assert ranges[4] == pytest.approx(2.0 - 0.005, abs=1e-12) and owners[4] == WALL_ID
    fan = bearing + np.radians(np.linspace(-15.0, 15.0, 5))
    fan_ranges, _ = cast_rays(np.repeat([[mx, my]], 5, 0), fan, 5.0, _scene(pose, circles=[pole]))
    assert np.all(fan_ranges == 5.0)


def test_drawing_helpers():
    pose = (1.0, -1.0, 0.3)
    laser = LaserScanner()
    ranges = np.linspace(1.0, 3.0, 180)
    origins, ends = laser.beam_endpoints(pose, ranges)
    assert origins.shape == ends.shape == (180, 2)
    np.testing.assert_allclose(origins[0], (1.0 + 0.16 * math.cos(0.3), -1.0 + 0.16 * math.sin(0.3)))
    np.testing.assert_allclose(np.hypot(*(ends - origins).T), ranges)
    ring = SonarRing()
    cones = ring.cone_polygons(pose, np.full(16, 2.0))
    assert len(cones) == 16 and all(cone.shape == (8, 2) for cone in cones)
    apex = _to_world(pose, P2AT_SONAR_MOUNTS[:1, :2])[0]
    np.testing.assert_allclose(cones[0][0], apex)
    np.testing.assert_allclose(np.hypot(*(cones[0][1:] - apex).T), 2.0)
    with pytest.raises(ValueError, match=r"ranges must have shape \(16,\)"):
        ring.cone_polygons(pose, np.ones(8))


@pytest.mark.parametrize(
    ("factory", "message"),
    [
        (lambda: SonarConfig(min_range_m=5.0), "0 <= min_range_m < max_range_m"),
        (lambda: SonarConfig(max_range_m=math.nan), "max_range_m must be a finite number"),
        (lambda: SonarConfig(cone_half_width_deg=90.0), r"cone_half_width_deg must be in \(0, 90\)"),
        (lambda: SonarConfig(mounts=[(0.0, 0.0)]), r"mounts must be finite with shape \(N, 3\)"),
        (lambda: SonarConfig(mounts="front"), "mounts must be numeric"),
        (lambda: LaserConfig(num_beams=0), "num_beams must be an int >= 1"),
        (lambda: LaserConfig(num_beams=180.0), "num_beams must be an int >= 1"),
        (lambda: LaserConfig(fov_deg=361.0), r"fov_deg must be in \(0, 360\]"),
        (lambda: LaserConfig(max_range_m=0.0), "max_range_m must be > 0"),
        (lambda: LaserConfig(mount_x_m=math.inf), "mount_x_m must be a finite number"),
        (lambda: SonarRing().read((0.0, 0.0), SceneGeometry.empty()), r"pose must be finite with shape \(3,\)"),
        (lambda: LaserScanner().read((0.0, math.nan, 0.0), SceneGeometry.empty()), "pose must be finite"),
        (lambda: LaserScanner().read(("0", "0", "0"), SceneGeometry.empty()), "pose must be numeric"),
        (lambda: LaserScanner().read((True, False, True), SceneGeometry.empty()), "pose must be numeric"),
    ],
)
def test_bad_configs_and_poses_are_refused(factory, message):
    with pytest.raises(ValueError, match=message):
        factory()


def test_configs_compare_and_hash():
    custom = SonarConfig(mounts=np.array([[0.1, 0.0, 0.0]]))
    assert custom == SonarConfig(mounts=((0.1, 0.0, 0.0),)) and hash(custom) == hash(SonarConfig(mounts=[[0.1, 0, 0]]))
    assert SonarRing(custom).num_sonars == 1
    assert LaserConfig(num_beams=90) == LaserConfig(num_beams=90) != LaserConfig()
    numpy_numbers = LaserConfig(num_beams=np.int64(180), max_range_m=np.float32(20.0))
    assert numpy_numbers == LaserConfig() and type(numpy_numbers.num_beams) is int
    assert type(SonarConfig(max_range_m=np.float32(4.0)).max_range_m) is float
