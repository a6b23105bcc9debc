"""``cast_rays``, ``cast_fan`` and ``cone_nearest`` against pymunk's own queries."""

from __future__ import annotations

import math

import numpy as np
import pymunk
import pytest

from attentive_gym.sensors import SceneGeometry, cast_fan, cast_rays, cone_nearest, cone_nearest_points

RANGE_TOLERANCE_M = 1e-6  # the agreement the brief asks of the analytic casters
MAX_RANGE_M = 20.0


def _owner_of_primitives(g: SceneGeometry) -> set[int]:
    return set(g.segment_owner.tolist()) | set(g.circle_owner.tolist())


@pytest.mark.parametrize("seed", range(10))
def test_cast_rays_matches_pymunk_on_random_scenes(pm, seed):
    scene = pm.random_scene(seed)
    geometry = scene.cache().update()
    rng = np.random.default_rng(seed)
    # random outside origins, plus origins inside the (excluded) robot, like its laser
    robot_points = np.array([scene.robot.local_to_world(tuple(p)) for p in rng.uniform(-0.25, 0.25, (20, 2))])
    origins = np.vstack([pm.outside_points(scene, rng, 100), robot_points])
    angles = rng.uniform(-np.pi, np.pi, len(origins))
    ranges, owners = cast_rays(origins, angles, MAX_RANGE_M, geometry, exclude_owner=pm.ROBOT_ID)

    exact_ranges, exact_owners = pm.pymunk_cast(scene, origins, angles, MAX_RANGE_M, exact=True)
    np.testing.assert_allclose(ranges, exact_ranges, rtol=0, atol=RANGE_TOLERANCE_M)
    np.testing.assert_array_equal(owners, exact_owners)
    # pymunk's capsule query itself, wherever it is exact (see conftest.EXACT_FILTER)
    direct_ranges, direct_owners = pm.pymunk_cast(scene, origins, angles, MAX_RANGE_M)
    trusted = np.array([not scene.in_capsule_blind_spot(o) for o in origins])
    assert trusted.mean() > 0.8
    np.testing.assert_allclose(ranges[trusted], direct_ranges[trusted], rtol=0, atol=RANGE_TOLERANCE_M)
    np.testing.assert_array_equal(owners[trusted], direct_owners[trusted])
    # the comparison covers hits on every kind of body and misses
    assert (owners == -1).any() and len(set(owners.tolist()) - {-1}) >= 5
    assert pm.ROBOT_ID not in owners and pm.ROBOT_ID in _owner_of_primitives(geometry)


def test_the_robot_is_seen_unless_excluded(pm):
    space = pymunk.Space()
    robot = pymunk.Body(14.0, 1.0)
    robot.position, robot.angle = (1.0, -2.0), 0.3
    box = pymunk.Poly.create_box(robot, (0.626, 0.505))
    space.add(robot, box)
    geometry = _geometry_of([(pm.ROBOT_ID, robot, [box])])
    origins, angles = np.array([[4.0, -2.0], [1.0, -5.0]]), np.array([np.pi, np.pi / 2])
    ranges, owners = cast_rays(origins, angles, MAX_RANGE_M, geometry)
    for origin, angle, r in zip(origins, angles, ranges):
        end = origin + MAX_RANGE_M * np.array([math.cos(angle), math.sin(angle)])
        info = space.segment_query_first(tuple(origin), tuple(end), 0.0, pymunk.ShapeFilter())
        assert r == pytest.approx(info.alpha * MAX_RANGE_M, abs=RANGE_TOLERANCE_M)
    np.testing.assert_array_equal(owners, [pm.ROBOT_ID, pm.ROBOT_ID])
    ranges, owners = cast_rays(origins, angles, MAX_RANGE_M, geometry, exclude_owner=pm.ROBOT_ID)
    np.testing.assert_array_equal(ranges, [MAX_RANGE_M] * 2)
    np.testing.assert_array_equal(owners, [-1, -1])


def test_scene_of_circles_only(pm):
    scene = pm.random_scene(11, kinds=("circle",))
    geometry = scene.cache().update()
    assert len(geometry.segments) == 4  # only the (excluded) robot's box has edges
    rng = np.random.default_rng(11)
    origins = pm.outside_points(scene, rng, 150)
    angles = rng.uniform(-np.pi, np.pi, len(origins))
    ranges, owners = cast_rays(origins, angles, MAX_RANGE_M, geometry, exclude_owner=pm.ROBOT_ID)
    expected_ranges, expected_owners = pm.pymunk_cast(scene, origins, angles, MAX_RANGE_M)
    np.testing.assert_allclose(ranges, expected_ranges, rtol=0, atol=RANGE_TOLERANCE_M)
    np.testing.assert_array_equal(owners, expected_owners)
    assert (owners == -1).any() and (owners > 0).any()


def test_empty_scene_reads_max_range():
    ranges, owners = cast_rays(np.zeros((3, 2)), [0.0, 1.0, 2.0], 7.5, SceneGeometry.empty())
    np.testing.assert_array_equal(ranges, [7.5] * 3)
    np.testing.assert_array_equal(owners, [-1] * 3)
    ranges, owners = cast_fan([1.0, 2.0], 0.0, 0.1, 5, 7.5, SceneGeometry.empty())
    np.testing.assert_array_equal(ranges, [7.5] * 5)
    ranges, owners = cone_nearest([[0.0, 0.0]], [0.0], 0.2, 7.5, SceneGeometry.empty())
    assert ranges.tolist() == [7.5] and owners.tolist() == [-1]


def _polygon_vertices(scene):
    """``(owner, shape, world vertex)`` of every radius-0 polygon except the robot's."""
    for owner, body, shapes in scene.entries:
        for shape in shapes:
            if owner != 0 and isinstance(shape, pymunk.Poly) and shape.radius == 0.0:
                for v in shape.get_vertices():
                    yield owner, shape, np.array(body.local_to_world(v))


def test_rays_aimed_exactly_at_vertices_never_slip_through(pm):
    """A ray through a polygon vertex sees it, whether it enters the polygon there or
    only touches it. pymunk's answer here depends on rounding (it can even slip through
    a vertex into the polygon and miss it), so the oracle is the vertex itself or the
    nearer hit pymunk reports: range = min(|v - o|, pymunk's first hit)."""
    checked = 0
    for seed in range(3):
        scene = pm.random_scene(seed, kinds=("poly",))
        geometry = scene.cache().update()
        rng = np.random.default_rng(seed)
        for owner, _, vertex in _polygon_vertices(scene):
            origin = pm.outside_points(scene, rng, 1)
            offset = vertex - origin[0]
            angle = [math.atan2(offset[1], offset[0])]
            ranges, owners = cast_rays(origin, angle, MAX_RANGE_M, geometry, pm.ROBOT_ID)
            oracle_range, oracle_owner = pm.pymunk_cast(scene, origin, angle, MAX_RANGE_M)
            distance = float(np.hypot(*offset))
            if distance < oracle_range[0] - RANGE_TOLERANCE_M and distance <= MAX_RANGE_M:
                assert ranges[0] == pytest.approx(distance, abs=1e-9)
                assert owners[0] == owner
            else:
                assert ranges[0] == pytest.approx(oracle_range[0], abs=RANGE_TOLERANCE_M)
                assert owners[0] == oracle_owner[0]
            checked += 1
    assert checked > 100


def test_rays_grazing_vertices_agree_with_pymunk(pm):
    """Rays passing 1e-9 rad to either side of a vertex (grazing it from outside, or
    entering just beside it) agree with pymunk, whose rounding no longer decides."""
    scene = pm.random_scene(5, kinds=("poly",))
    geometry = scene.cache().update()
    rng = np.random.default_rng(5)
    origins, angles = [], []
    for _, _, vertex in _polygon_vertices(scene):
        origin = pm.outside_points(scene, rng, 1)[0]
        offset = vertex - origin
        for side in (-1e-9, 1e-9):
            origins.append(origin)
            angles.append(math.atan2(offset[1], offset[0]) + side)
    ranges, owners = cast_rays(origins, angles, MAX_RANGE_M, geometry, pm.ROBOT_ID)
    expected_ranges, expected_owners = pm.pymunk_cast(scene, origins, angles, MAX_RANGE_M)
    np.testing.assert_allclose(ranges, expected_ranges, rtol=0, atol=RANGE_TOLERANCE_M)
    np.testing.assert_array_equal(owners, expected_owners)
    pairs = owners.reshape(-1, 2)
    assert (pairs[:, 0] != pairs[:, 1]).any(), "some vertex must be grazed (hit on one side only)"


def test_pymunk_capsule_query_has_a_blind_spot():
    """Why the oracle queries capsules through exact stand-ins (conftest.EXACT_FILTER).

    Capsule from (0, 0) to (2, 0), radius 0.5; a ray from (-1, 0.3) (in the capsule's band,
    beyond its end) at 5 deg enters the end cap at t solving |o + t d|^2 = 0.25. pymunk's
    segment query reports the far flat side instead, though its own point query says the
    ray is inside the capsule well before that. Should pymunk fix this, this test fails and
    the stand-ins can go.
    """
    space = pymunk.Space()
    capsule = pymunk.Segment(space.static_body, (0.0, 0.0), (2.0, 0.0), 0.5)
    space.add(capsule)
    origin, angle = np.array([-1.0, 0.3]), math.radians(5.0)
    d = np.array([math.cos(angle), math.sin(angle)])
    b, c = origin @ d, origin @ origin - 0.25
    entry = -b - math.sqrt(b * b - c)
    geometry = _geometry_of([(1, space.static_body, [capsule])])
    ranges, owners = cast_rays(origin[None], [angle], 10.0, geometry)
    assert ranges[0] == pytest.approx(entry, abs=1e-12) and owners[0] == 1
    info = space.segment_query_first(tuple(origin), tuple(origin + 10.0 * d), 0.0, pymunk.ShapeFilter())
    assert info.alpha * 10.0 > entry + 1.0
    assert capsule.point_query(tuple(origin + (entry + 0.05) * d)).distance < 0.0


def _geometry_of(entries) -> SceneGeometry:
    from attentive_gym.sensors import GeometryCache

    return GeometryCache(entries).update()


def test_max_range_and_exclusion_semantics():
    wall = SceneGeometry(
        np.array([[5.0, -1.0, 5.0, 1.0], [2.0, -1.0, 2.0, 1.0]]),
        np.array([3, 4]),
        np.array([[8.0, 0.0, 1.0]]),
        np.array([5]),
    )
    origin, ahead = np.zeros((1, 2)), [0.0]
    ranges, owners = cast_rays(origin, ahead, 10.0, wall)
    assert ranges.tolist() == [2.0] and owners.tolist() == [4]
    ranges, owners = cast_rays(origin, ahead, 10.0, wall, exclude_owner=4)
    assert ranges.tolist() == [5.0] and owners.tolist() == [3]
    ranges, owners = cast_rays(origin, ahead, 5.0, wall, exclude_owner=4)  # a hit at max range counts
    assert ranges.tolist() == [5.0] and owners.tolist() == [3]
    ranges, owners = cast_rays(origin, ahead, 4.999, wall, exclude_owner=4)
    assert ranges.tolist() == [4.999] and owners.tolist() == [-1]
    ranges, owners = cast_rays(np.array([[6.0, 0.0]]), [np.pi], 10.0, wall, exclude_owner=4)  # from behind
    assert ranges.tolist() == [1.0] and owners.tolist() == [3]
    ranges, owners = cast_rays(np.array([[8.0, 0.5]]), [0.0], 10.0, wall)  # inside a solid circle
    assert ranges.tolist() == [0.0] and owners.tolist() == [5]


@pytest.mark.parametrize("seed", range(4))
def test_cast_fan_equals_cast_rays(pm, seed):
    scene = pm.random_scene(20 + seed)
    geometry = scene.cache().update()
    rng = np.random.default_rng(seed)
    fans = [
        (0.0, math.radians(1.0), 180),
        (2.5, math.radians(0.37), 971),
        (-3.0, 2 * np.pi / 360 * 0.999, 360),
        (rng.uniform(-10, 10), rng.uniform(1e-4, 0.05), int(rng.integers(1, 120))),
        (1.0, 0.5, 1),
    ]
    origins = np.vstack([pm.outside_points(scene, rng, 6), [scene.robot.position]])
    for origin in origins:
        for first, step, count in fans:
            ranges, owners = cast_fan(origin, first, step, count, MAX_RANGE_M, geometry, pm.ROBOT_ID)
            angles = first + np.arange(count) * step
            expected_ranges, expected_owners = cast_rays(
                np.repeat(origin[None], count, 0), angles, MAX_RANGE_M, geometry, pm.ROBOT_ID
            )
            np.testing.assert_array_equal(ranges, expected_ranges)
            np.testing.assert_array_equal(owners, expected_owners)


def test_cast_fan_through_primitives_touching_the_origin():
    """A segment through the origin and a circle around it: every ray is tested."""
    geometry = SceneGeometry(
        np.array([[-1.0, 0.0, 1.0, 0.0]]), np.array([1]), np.array([[0.0, 3.0, 0.5], [0.0, 0.0, 0.2]]), np.array([2, 3])
    )
    for exclude in (-1, 3):
        ranges, owners = cast_fan([0.0, 0.0], 0.1, 0.3, 20, 10.0, geometry, exclude)
        angles = 0.1 + np.arange(20) * 0.3
        expected = cast_rays(np.zeros((20, 2)), angles, 10.0, geometry, exclude)
        np.testing.assert_array_equal(ranges, expected[0])
        np.testing.assert_array_equal(owners, expected[1])
    assert set(owners.tolist()) == {1}  # the segment through the origin: every ray at 0


def test_cast_fan_with_a_tiny_step_past_an_endpoint():
    """Rays a hair past a segment's end still hit it within SEGMENT_PARAMETER_SLACK; the
    fan's culling must keep them even when they are far more than one step apart."""
    geometry = SceneGeometry(np.array([[1.0, -10.0, 1.0, 0.0]]), np.array([1]), np.empty((0, 3)), np.empty(0, int))
    step = 1e-13
    first = -50 * step  # rays around the endpoint's direction (0 rad)
    ranges, owners = cast_fan([0.0, 0.0], first, step, 100, 5.0, geometry)
    expected_ranges, expected_owners = cast_rays(np.zeros((100, 2)), first + np.arange(100) * step, 5.0, geometry)
    np.testing.assert_array_equal(owners, expected_owners)
    np.testing.assert_array_equal(ranges, expected_ranges)
    assert (owners[51:] == 1).sum() >= 5  # several rays beyond the endpoint count as hits


# --- cone_nearest -------------------------------------------------------------------

CONE_HALF_WIDTH_RAD = math.radians(15.0)
SONAR_RANGE_M = 5.0
FAN_STEP_RAD = math.radians(0.02)
#: The analytic nearest point lies within half a fan step of a fan ray, or on a boundary
#: ray (which the fan includes and which hits it exactly). Where the surface there meets
#: the rays at >= 15 deg (true of the convex solids below: corners, rounded corners,
#: circles), the neighbouring ray hits within rho * step / sin(15 deg) ~ 3.9 rho * step.
FAN_SLACK_STEPS = 4.0
ON_BOUNDARY_M = 1e-9  # a nearest point is on a shape's outline up to rounding


def _cone_case(pm, seed, kinds, count=25):
    scene = pm.random_scene(seed, kinds=kinds)
    geometry = scene.cache().update()
    rng = np.random.default_rng(100 + seed)
    apexes = pm.outside_points(scene, rng, count)
    headings = rng.uniform(-np.pi, np.pi, count)
    return scene, geometry, apexes, headings


def _fan_minimum(pm, scene, apex, heading):
    """Nearest pymunk hit over a fan spanning the cone, boundary rays included."""
    count = int(round(2 * CONE_HALF_WIDTH_RAD / FAN_STEP_RAD))
    angles = heading - CONE_HALF_WIDTH_RAD + np.arange(count + 1) * (2 * CONE_HALF_WIDTH_RAD / count)
    reach = SONAR_RANGE_M * (1 + 2 * FAN_SLACK_STEPS * FAN_STEP_RAD)
    ranges, _ = pm.pymunk_cast(scene, np.repeat(apex[None], count + 1, 0), angles, reach, exact=True)
    return ranges.min()


def _check_nearest_point(scene, apex, heading, owner, point, distance):
    """The point is at ``distance`` from the apex, inside the cone and on the outline of
    a shape of ``owner``."""
    offset = point - apex
    assert math.hypot(*offset) == pytest.approx(distance, abs=1e-12)
    if distance > 0:
        bearing = math.remainder(math.atan2(offset[1], offset[0]) - heading, 2 * math.pi)
        assert abs(bearing) <= CONE_HALF_WIDTH_RAD + 1e-9
    gaps = [abs(shape.point_query(tuple(point)).distance) for shape, o in scene.owner_of.items() if o == owner]
    assert min(gaps) < ON_BOUNDARY_M


@pytest.mark.parametrize("seed", range(4))
def test_cone_nearest_against_a_dense_pymunk_fan(pm, seed):
    scene, geometry, apexes, headings = _cone_case(pm, seed, ("poly", "rounded poly", "capsule", "circle"))
    ranges, owners, points = cone_nearest_points(
        apexes, headings, CONE_HALF_WIDTH_RAD, SONAR_RANGE_M, geometry, pm.ROBOT_ID
    )
    assert (owners == -1).any() and (owners > 0).sum() >= 8
    for apex, heading, r, owner, point in zip(apexes, headings, ranges, owners, points):
        fan = _fan_minimum(pm, scene, apex, heading)
        if owner == -1:
            assert r == SONAR_RANGE_M and np.isnan(point).all()
            assert fan >= SONAR_RANGE_M - 1e-9
            continue
        assert fan >= r - 1e-9
        assert fan <= r + FAN_SLACK_STEPS * r * FAN_STEP_RAD + 1e-9
        _check_nearest_point(scene, apex, heading, owner, point, r)


def test_cone_nearest_with_lone_segments(pm):
    """Lone zero-thickness segments can point straight at the apex, so a fan of rays may
    see them much farther or not at all: only the fan's lower bound and the point hold."""
    scene, geometry, apexes, headings = _cone_case(pm, 7, ("segment",), count=30)
    ranges, owners, points = cone_nearest_points(
        apexes, headings, CONE_HALF_WIDTH_RAD, SONAR_RANGE_M, geometry, pm.ROBOT_ID
    )
    assert (owners > 0).sum() >= 8
    for apex, heading, r, owner, point in zip(apexes, headings, ranges, owners, points):
        assert _fan_minimum(pm, scene, apex, heading) >= r - 1e-9
        if owner != -1:
            _check_nearest_point(scene, apex, heading, owner, point, r)


def _segments(*rows):
    return SceneGeometry(np.array(rows, float), np.arange(1, len(rows) + 1), np.empty((0, 3)), np.empty(0, int))


def _circles(*rows):
    return SceneGeometry(np.empty((0, 4)), np.empty(0, int), np.array(rows, float), np.arange(1, len(rows) + 1))


@pytest.mark.parametrize(
    ("geometry", "heading_deg", "expected_m", "expected_point"),
    [
        (_segments([3.0, -5.0, 3.0, 5.0]), 0.0, 3.0, (3.0, 0.0)),  # foot of the perpendicular
        (_segments([3.0, -5.0, 3.0, 5.0]), 40.0, 3.0 / math.cos(math.radians(25.0)), None),  # on the right ray
        (_segments([3.0, 0.5, 3.0, 5.0]), 0.0, math.hypot(3.0, 0.5), (3.0, 0.5)),  # endpoint inside the cone
        # x + y = 4: its nearest point (2, 2) is outside the cone, so the left ray (15 deg) clips it
        (
            _segments([1.0, 3.0, 5.0, -1.0]),
            0.0,
            4.0 / (math.cos(math.radians(15.0)) + math.sin(math.radians(15.0))),
            None,
        ),
        (_segments([3.0, -5.0, 3.0, 5.0], [2.0, 4.0, 2.0, 9.0]), 0.0, 3.0, (3.0, 0.0)),  # the other is outside
        (_circles([4.0, 0.5, 1.0]), 0.0, math.hypot(4.0, 0.5) - 1.0, None),  # centre inside the cone
        (_circles([0.0, 4.0, 1.5]), 60.0, None, None),  # centre outside: enters through the left ray
        (_circles([0.0, 4.0, 0.5]), 60.0, 5.0, None),  # beside the cone: no echo
        (_circles([0.3, 0.0, 0.5]), 180.0, 0.0, (0.0, 0.0)),  # apex inside the circle
        (_segments([6.0, -1.0, 6.0, 1.0]), 0.0, 5.0, None),  # beyond max range: no echo
    ],
)
def test_cone_nearest_hand_cases(geometry, heading_deg, expected_m, expected_point):
    half = math.radians(15.0)
    if expected_m is None:  # the left boundary ray at 75 deg entering the circle of radius 1.5 at (0, 4)
        u = np.array([math.cos(math.radians(75.0)), math.sin(math.radians(75.0))])
        b = u @ np.array([0.0, 4.0])
        expected_m = b - math.sqrt(b * b - (16.0 - 1.5**2))
    ranges, owners, points = cone_nearest_points([[0.0, 0.0]], [math.radians(heading_deg)], half, 5.0, geometry)
    assert ranges[0] == pytest.approx(expected_m, abs=1e-12)
    assert (owners[0] == -1) == (expected_m == 5.0)
    if expected_point is not None:
        np.testing.assert_allclose(points[0], expected_point, atol=1e-12)


def test_argument_checks():
    g = SceneGeometry.empty()
    with pytest.raises(ValueError, match=r"origins must have shape \(N, 2\)"):
        cast_rays(np.zeros(3), [0.0], 1.0, g)
    with pytest.raises(ValueError, match="same length"):
        cast_rays(np.zeros((2, 2)), [0.0], 1.0, g)
    with pytest.raises(ValueError, match="angles must be finite"):
        cast_rays(np.zeros((1, 2)), [np.nan], 1.0, g)
    with pytest.raises(ValueError, match="max_range_m must be a finite number > 0"):
        cast_rays(np.zeros((1, 2)), [0.0], -1.0, g)
    with pytest.raises(ValueError, match="max_range_m must be a finite number > 0, got '10'"):
        cast_rays(np.zeros((1, 2)), [0.0], "10", g)
    with pytest.raises(TypeError, match="geometry must be a SceneGeometry"):
        cast_rays(np.zeros((1, 2)), [0.0], 1.0, (np.zeros((0, 4)),))
    with pytest.raises(TypeError, match="exclude_owner must be an int"):
        cast_rays(np.zeros((1, 2)), [0.0], 1.0, g, exclude_owner=True)
    with pytest.raises(ValueError, match=r"half_width_rad must be in \(0, pi/2\)"):
        cone_nearest(np.zeros((1, 2)), [0.0], math.pi / 2, 1.0, g)
    with pytest.raises(ValueError, match="less than a full turn"):
        cast_fan([0.0, 0.0], 0.0, 0.1, 100, 1.0, g)
    with pytest.raises(ValueError, match="num_rays must be an int >= 1"):
        cast_fan([0.0, 0.0], 0.0, 0.1, 0, 1.0, g)
