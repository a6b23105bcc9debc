"""``SceneGeometry`` checks and ``GeometryCache``: exact shape conversion and moving bodies."""

from __future__ import annotations

import math
import pickle

import numpy as np
import pymunk
import pytest

from attentive_gym.sensors import GeometryCache, SceneGeometry, cast_rays, shape_primitives

RANGE_TOLERANCE_M = 1e-6


def _sorted_rows(array):
    return np.array(sorted(map(tuple, np.round(array, 12))))


def test_primitives_of_a_box():
    body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
    segments, circles = shape_primitives(pymunk.Poly.create_box(body, (2.0, 1.0)))
    corners = [(1.0, -0.5), (1.0, 0.5), (-1.0, 0.5), (-1.0, -0.5)]
    expected = [(*corners[i], *corners[(i + 1) % 4]) for i in range(4)]
    np.testing.assert_allclose(_sorted_rows(segments), _sorted_rows(np.array(expected)), atol=1e-12)
    assert circles.shape == (0, 3)


@pytest.mark.parametrize("clockwise", [False, True])
def test_primitives_of_a_rounded_polygon(clockwise):
    body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
    corners = [(0.0, 0.0), (2.0, 0.0), (0.0, 1.0)]
    poly = pymunk.Poly(body, corners[::-1] if clockwise else corners, None, 0.25)
    segments, circles = shape_primitives(poly)
    # edges pushed outward by r: the bottom edge to y = -0.25, the left one to x = -0.25
    expected_edges = {
        ((0.0, -0.25), (2.0, -0.25)),
        ((-0.25, 1.0), (-0.25, 0.0)),
    }
    n = np.array([1.0, 2.0]) / math.sqrt(5.0) * 0.25  # outward normal of the hypotenuse, times r
    expected_edges.add((tuple(np.round((2.0, 0.0) + n, 12)), tuple(np.round((0.0, 1.0) + n, 12))))
    got = {(tuple(np.round(s[:2], 12)), tuple(np.round(s[2:], 12))) for s in segments}
    assert {frozenset(e) for e in got} == {frozenset(e) for e in expected_edges}
    np.testing.assert_allclose(_sorted_rows(circles), _sorted_rows(np.array([(*c, 0.25) for c in corners])))


def test_primitives_of_degenerate_rounded_polygons():
    body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
    segments, circles = shape_primitives(pymunk.Poly(body, [(1.0, 1.0)], None, 0.5))  # a dot
    assert segments.shape == (0, 4) and circles.tolist() == [[1.0, 1.0, 0.5]]
    segments, circles = shape_primitives(pymunk.Poly(body, [(0.0, 0.0), (2.0, 0.0)], None, 0.5))  # a capsule
    np.testing.assert_allclose(_sorted_rows(segments), [[0.0, -0.5, 2.0, -0.5], [2.0, 0.5, 0.0, 0.5]])
    np.testing.assert_array_equal(circles, [[0.0, 0.0, 0.5], [2.0, 0.0, 0.5]])


def test_primitives_of_segments_and_circles():
    body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
    segments, circles = shape_primitives(pymunk.Segment(body, (0.0, 0.0), (3.0, 0.0), 0.0))
    np.testing.assert_array_equal(segments, [[0.0, 0.0, 3.0, 0.0]])
    assert circles.shape == (0, 3)
    segments, circles = shape_primitives(pymunk.Segment(body, (0.0, 0.0), (3.0, 0.0), 0.5))
    np.testing.assert_allclose(_sorted_rows(segments), [[0.0, -0.5, 3.0, -0.5], [0.0, 0.5, 3.0, 0.5]])
    np.testing.assert_array_equal(circles, [[0.0, 0.0, 0.5], [3.0, 0.0, 0.5]])
    segments, circles = shape_primitives(pymunk.Segment(body, (1.0, 1.0), (1.0, 1.0), 0.5))  # a dot
    assert segments.shape == (0, 4) and circles.tolist() == [[1.0, 1.0, 0.5]]
    segments, circles = shape_primitives(pymunk.Segment(body, (1.0, 1.0), (1.0, 1.0), 0.0))  # nothing to hit
    assert segments.shape == (0, 4) and circles.shape == (0, 3)
    segments, circles = shape_primitives(pymunk.Circle(body, 0.7, (0.5, -0.25)))
    assert segments.shape == (0, 4) and circles.tolist() == [[0.5, -0.25, 0.7]]


def test_unsupported_shapes_and_mismatched_bodies_are_refused():
    body, other = pymunk.Body(body_type=pymunk.Body.KINEMATIC), pymunk.Body(body_type=pymunk.Body.KINEMATIC)
    with pytest.raises(TypeError, match="unsupported shape type str; allowed: pymunk.Poly"):
        GeometryCache([(1, body, ["box"])])
    with pytest.raises(ValueError, match="is attached to"):
        GeometryCache([(1, body, [pymunk.Circle(other, 1.0)])])
    with pytest.raises(TypeError, match="owner id must be an int"):
        GeometryCache([(1.5, body, [])])


def test_empty_scene_and_bodies_without_shapes():
    empty = GeometryCache([]).update()
    assert empty.segments.shape == (0, 4) and empty.circles.shape == (0, 3)
    assert empty.segment_owner.shape == (0,) and empty.circle_owner.shape == (0,)
    moving = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
    cache = GeometryCache([(3, moving, []), (4, pymunk.Body(body_type=pymunk.Body.STATIC), [])])
    geometry = cache.update()
    assert geometry.segments.shape == (0, 4) and geometry.circles.shape == (0, 3)
    assert cache.moving_bodies == (moving,)
    ranges, owners = cast_rays(np.zeros((2, 2)), [0.0, 1.0], 4.0, geometry)
    assert ranges.tolist() == [4.0, 4.0] and owners.tolist() == [-1, -1]


def test_static_scene_is_placed_once():
    space = pymunk.Space()
    placed = pymunk.Body(body_type=pymunk.Body.STATIC)
    placed.position, placed.angle = (2.0, 1.0), math.pi / 2
    box = pymunk.Poly.create_box(placed, (1.0, 0.5))
    wall = pymunk.Segment(space.static_body, (0.0, 5.0), (4.0, 5.0), 0.0)
    cache = GeometryCache([(1, placed, [box]), (2, space.static_body, [wall])])
    geometry = cache.update()
    assert cache.update() is geometry and cache.moving_bodies == ()
    expected = [placed.local_to_world(v) for v in box.get_vertices()]
    np.testing.assert_allclose(
        _sorted_rows(geometry.segments[geometry.segment_owner == 1][:, :2]),
        _sorted_rows(np.array(expected)),
        atol=1e-12,
    )
    np.testing.assert_array_equal(geometry.segments[geometry.segment_owner == 2], [[0.0, 5.0, 4.0, 5.0]])


def test_moving_body_with_an_offset_centre_of_gravity_is_placed_like_pymunk():
    body = pymunk.Body(3.0, 1.0)
    body.center_of_gravity = (0.4, -0.2)
    body.position, body.angle = (1.5, -2.0), 0.8
    poly = pymunk.Poly(body, [(0.0, 0.0), (1.0, 0.2), (0.3, 0.9)])
    circle = pymunk.Circle(body, 0.3, (-0.5, 0.25))
    cache = GeometryCache([(5, body, [poly, circle])])
    for position, angle in [((1.5, -2.0), 0.8), ((-3.0, 4.0), -2.5)]:
        body.position, body.angle = position, angle
        geometry = cache.update()
        expected = [body.local_to_world(v) for v in poly.get_vertices()]
        np.testing.assert_allclose(_sorted_rows(geometry.segments[:, :2]), _sorted_rows(np.array(expected)), atol=1e-12)
        np.testing.assert_allclose(geometry.circles, [[*body.local_to_world(circle.offset), 0.3]], atol=1e-12)
        np.testing.assert_array_equal(geometry.segment_owner, [5, 5, 5])
        np.testing.assert_array_equal(geometry.circle_owner, [5])


def test_update_follows_moved_bodies(pm):
    scene = pm.random_scene(3)
    cache = scene.cache()
    rng = np.random.default_rng(3)
    moving = cache.moving_bodies
    assert len(moving) == 7  # the robot and six movers
    before = cache.update()
    for body in moving:
        body.position = tuple(np.array(body.position) + rng.uniform(-2.0, 2.0, 2))
        body.angle = body.angle + rng.uniform(-np.pi, np.pi)
    pm.refresh(scene)
    after = cache.update()
    origins = pm.outside_points(scene, rng, 200)
    angles = rng.uniform(-np.pi, np.pi, len(origins))
    expected_ranges, expected_owners = pm.pymunk_cast(scene, origins, angles, 20.0, exact=True)
    ranges, owners = cast_rays(origins, angles, 20.0, after, pm.ROBOT_ID)
    np.testing.assert_allclose(ranges, expected_ranges, rtol=0, atol=RANGE_TOLERANCE_M)
    np.testing.assert_array_equal(owners, expected_owners)
    stale, _ = cast_rays(origins, angles, 20.0, before, pm.ROBOT_ID)
    assert np.abs(stale - expected_ranges).max() > 0.1, "the move must change what the rays see"


def test_a_pickled_cache_follows_its_pickled_bodies():
    space = pymunk.Space()
    body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
    box = pymunk.Poly.create_box(body, (1.0, 1.0))
    space.add(body, box)
    cache = GeometryCache([(1, body, [box])])
    space_copy, cache_copy = pickle.loads(pickle.dumps((space, cache)))
    moved = cache_copy.moving_bodies[0]
    assert moved in space_copy.bodies and moved is not body
    moved.position = (5.0, 0.0)
    assert cache_copy.update().segments[:, 0].min() == 4.5
    assert cache.update().segments[:, 0].min() == -0.5


def test_a_non_finite_pose_is_reported():
    body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
    cache = GeometryCache([(1, body, [pymunk.Circle(body, 0.5)])])
    body.angle = math.nan
    with pytest.raises(ValueError, match="has a non-finite pose"):
        cache.update()


def _assert_same_geometry(a: SceneGeometry, b: SceneGeometry) -> None:
    for field in ("segments", "segment_owner", "circles", "circle_owner"):
        np.testing.assert_array_equal(getattr(a, field), getattr(b, field), strict=True)


@pytest.mark.parametrize("angle_scale_rad", [math.pi, 1e3, 1e7])
def test_update_at_given_poses_equals_update_after_moving_the_bodies(pm, angle_scale_rad):
    rng = np.random.default_rng(int(angle_scale_rad))
    for seed in range(4):
        scene = pm.random_scene(seed)
        cache = scene.cache()
        bodies = cache.moving_bodies
        for _ in range(5):
            for body in bodies:  # the angle first: turning a body moves its origin about its centre of gravity
                body.angle = rng.uniform(-angle_scale_rad, angle_scale_rad)
                body.position = tuple(rng.uniform(-50.0, 50.0, 2))
            poses = np.array([(*body.position, body.angle) for body in bodies])  # as pymunk holds them now
            geometry = cache.update()
            _assert_same_geometry(cache.update(poses), geometry)
            _assert_same_geometry(cache.update(poses.tolist()), geometry)  # any real (B, 3) array-like
            moved = cache.update(poses + [0.5, 0.0, 0.0])  # every moving body 0.5 m along x, nothing else
            moving = np.isin(geometry.segment_owner, [owner for owner, body, _ in scene.entries if body in bodies])
            np.testing.assert_allclose(
                moved.segments[:, ::2] - geometry.segments[:, ::2],
                np.where(moving, 0.5, 0.0)[:, None].repeat(2, 1),
                atol=1e-9,
            )


def test_moving_bodies_are_listed_in_order_of_first_appearance():
    space = pymunk.Space()
    a, b = pymunk.Body(1.0, 1.0), pymunk.Body(body_type=pymunk.Body.KINEMATIC)
    cache = GeometryCache(
        [
            (1, b, [pymunk.Circle(b, 0.2)]),
            (2, space.static_body, [pymunk.Segment(space.static_body, (0.0, 0.0), (1.0, 0.0), 0.0)]),
            (3, a, [pymunk.Poly.create_box(a, (0.4, 0.2))]),
            (4, b, [pymunk.Circle(b, 0.1, (0.5, 0.0))]),
        ]
    )
    assert cache.moving_bodies == (b, a)
    geometry = cache.update(np.array([[1.0, 2.0, math.pi / 2], [-3.0, 0.0, 0.0]]))  # b at (1, 2) turned, a at (-3, 0)
    np.testing.assert_allclose(geometry.circles[:, :2], [[1.0, 2.0], [1.0, 2.5]], atol=1e-15)
    assert geometry.segments[geometry.segment_owner == 3][:, 0].max() == -2.8


def test_bad_given_poses_are_refused():
    body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
    cache = GeometryCache([(1, body, [pymunk.Circle(body, 0.5)]), (2, pymunk.Body(1.0, 1.0), [])])
    for poses in (np.zeros(3), np.zeros((1, 3)), np.zeros((2, 2)), np.zeros((3, 3))):
        with pytest.raises(ValueError, match=r"poses must have shape \(2, 3\): x_m, y_m, angle_rad"):
            cache.update(poses)
    with pytest.raises(ValueError, match="poses must be a numeric"):
        cache.update([["a", "b", "c"], [0.0, 0.0, 0.0]])
    with pytest.raises(
        ValueError, match=r"body 1 of the cache .* has a non-finite pose: x, y, angle = \[0.0, 0.0, inf\]"
    ):
        cache.update(np.array([[0.0, 0.0, 0.0], [0.0, 0.0, np.inf]]))
    static = GeometryCache([(1, pymunk.Space().static_body, [])])
    assert static.update(np.empty((0, 3))) is static.update()
    with pytest.raises(ValueError, match=r"poses must have shape \(0, 3\)"):
        static.update(np.zeros((1, 3)))


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        (dict(segments=np.zeros((2, 3))), r"segments must have shape \(S, 4\)"),
        (dict(circles=np.zeros(3)), r"circles must have shape \(C, 3\)"),
        (dict(segment_owner=np.zeros(2, int)), r"segment_owner must have shape \(1,\)"),
        (dict(circle_owner=np.zeros((1, 1), int)), r"circle_owner must have shape \(1,\)"),
        (dict(segments=np.array([[0.0, np.inf, 1.0, 1.0]])), "must be finite"),
        (dict(circles=np.array([[0.0, 0.0, -1.0]])), "radii must be >= 0"),
    ],
)
def test_scene_geometry_is_checked(kwargs, message):
    arrays = dict(
        segments=np.zeros((1, 4)),
        segment_owner=np.zeros(1, int),
        circles=np.zeros((1, 3)),
        circle_owner=np.zeros(1, int),
    )
    with pytest.raises(ValueError, match=message):
        SceneGeometry(**{**arrays, **kwargs})


def test_scene_geometry_converts_dtypes():
    g = SceneGeometry([[0, 0, 1, 1]], [7], np.zeros((0, 3), np.float32), [])
    assert g.segments.dtype == np.float64 and g.segment_owner.dtype == np.int64
    assert g.circles.dtype == np.float64 and g.circle_owner.dtype == np.int64 and g.circle_owner.shape == (0,)
