"""``SensorSuite.read_batch`` over a ``SceneStack``: the same numbers as ``read`` of each robot
in turn, and ``read`` the same as the sonar ring, the laser and the range noise applied apart."""

from __future__ import annotations

import numpy as np
import pytest

from attentive_gym.sensors import (
    NOISE_MODELS,
    SENSOR_PROFILES,
    BatchReading,
    LaserConfig,
    SceneGeometry,
    SceneStack,
    SensorSuite,
    SonarConfig,
    apply_range_noise,
    resolve_sensor_profile,
    unit_noise,
    unit_noise_rows,
)

FIELDS = ("sonar", "laser", "sonar_owner", "laser_owner")
#: Every sensor profile with each noise model, and a ring and a scanner other than the defaults.
SUITES = [
    (profile, model, custom)
    for profile in (None, *SENSOR_PROFILES)
    for model in NOISE_MODELS
    for custom in (False, True)
]


def _suite(profile, noise_model: str, custom: bool) -> SensorSuite:
    settings = resolve_sensor_profile(profile, noise_model=noise_model)
    if not custom:
        return SensorSuite(noise_std=settings.noise, noise_model=settings.noise_model)
    sonar = SonarConfig(min_range_m=0.3, max_range_m=4.0, cone_half_width_deg=20.0, mounts=((0.1, 0.05, 0.4),) * 3)
    laser = LaserConfig(num_beams=37, fov_deg=270.0, max_range_m=8.0, mount_x_m=-0.05, mount_y_m=0.1)
    return SensorSuite(sonar, laser, noise_std=0.3, noise_model=settings.noise_model)


def _states(rngs) -> list[dict]:
    return [rng.bit_generator.state for rng in rngs]


def _assert_same_reading(a, b) -> None:
    for field in FIELDS:
        np.testing.assert_array_equal(getattr(a, field), getattr(b, field), strict=True)


def _apart(suite: SensorSuite, pose, geometry: SceneGeometry, rng, exclude: int):
    """The reading as the sensors give it apart: each sweep, then ``apply_range_noise`` on
    each, sonar first (the stream ``read`` is documented to draw)."""
    sonar, sonar_owner = suite.sonar_ring.read(pose, geometry, exclude)
    laser, laser_owner = suite.laser_scanner.read(pose, geometry, exclude)
    s, c = suite.sonar_ring.config, suite.laser_scanner.config
    sonar = apply_range_noise(sonar, suite.noise_std, s.min_range_m, s.max_range_m, rng, suite.noise_model)
    laser = apply_range_noise(laser, suite.noise_std, 0.0, c.max_range_m, rng, suite.noise_model)
    return dict(sonar=sonar, laser=laser, sonar_owner=sonar_owner, laser_owner=laser_owner)


def _members(pm, n: int, seed: int):
    """``n`` scenes (random pymunk scenes with moving bodies, every third a fixed
    ``SceneGeometry``), robot poses inside them and random poses of their moving bodies."""
    rng = np.random.default_rng(seed)
    scenes, poses, body_poses = [], [], []
    for i in range(n):
        scene = pm.random_scene(seed + i)
        cache = scene.cache()
        if i % 3 == 2:
            scenes.append(cache.update())
        else:
            scenes.append(cache)
            moving = len(cache.moving_bodies)
            body_poses.append(np.column_stack([rng.uniform(-8.0, 8.0, (moving, 2)), rng.uniform(-40.0, 40.0, moving)]))
        poses.append([*pm.outside_points(scene, rng, 1)[0], rng.uniform(-np.pi, np.pi)])
    return scenes, np.array(poses), np.concatenate(body_poses) if body_poses else np.empty((0, 3))


def _expected(suite, stack: SceneStack, poses, body_poses, seeds, excludes):
    """``read`` of each robot in turn, in its scene placed at its body poses."""
    expected = []
    for i, (scene, rng) in enumerate(zip(stack.scenes, [np.random.default_rng(s) for s in seeds])):
        if not isinstance(scene, SceneGeometry):
            scene = scene.update(body_poses[stack.body_start[i] : stack.body_start[i + 1]])
        expected.append(suite.read(poses[i], scene, rng, int(excludes[i])))
    return expected


@pytest.mark.parametrize(("profile", "noise_model", "custom"), SUITES)
def test_read_equals_the_sensors_read_apart(pm, profile, noise_model, custom):
    suite = _suite(profile, noise_model, custom)
    rng = np.random.default_rng(5)
    for seed in range(3):
        scene = pm.random_scene(seed)
        geometry = scene.cache().update()
        for pose in pm.outside_points(scene, rng, 20):
            pose = (*pose, rng.uniform(-10.0, 10.0))
            exclude = int(rng.integers(-1, 3))
            a, b = np.random.default_rng(seed), np.random.default_rng(seed)
            reading = suite.read(pose, geometry, a, exclude)
            expected = _apart(suite, pose, geometry, b, exclude)
            for field in FIELDS:
                np.testing.assert_array_equal(getattr(reading, field), expected[field], strict=True)
            assert a.bit_generator.state == b.bit_generator.state


@pytest.mark.parametrize(("profile", "noise_model", "custom"), SUITES)
@pytest.mark.parametrize("n", [1, 5])
def test_read_batch_equals_read_of_each_robot_in_turn(pm, profile, noise_model, custom, n):
    suite = _suite(profile, noise_model, custom)
    scenes, poses, body_poses = _members(pm, n, seed=10 * n)
    stack = SceneStack(scenes)
    seeds = list(range(100, 100 + n))
    excludes = np.array([pm.ROBOT_ID, -1, 3, pm.ROBOT_ID, 7][:n])
    expected = _expected(suite, stack, poses, body_poses, seeds, excludes)
    rngs = [np.random.default_rng(s) for s in seeds]
    out = suite.read_batch(poses, stack, rngs, excludes, body_poses=body_poses)
    assert isinstance(out, BatchReading) and len(out) == n
    for i in range(n):
        _assert_same_reading(out.reading(i), expected[i])
    np.testing.assert_array_equal(
        out.unit_noise[0], unit_noise(noise_model, out.unit_noise.shape[1], np.random.default_rng(100))
    )
    again = [np.random.default_rng(s) for s in seeds]
    for _ in range(2):  # into the same block: the same numbers again (the scenes are re-placed, not moved on)
        assert suite.read_batch(poses, stack, again, excludes, body_poses=body_poses, out=out) is out
        again = [np.random.default_rng(s) for s in seeds]
        for i in range(n):
            _assert_same_reading(out.reading(i), expected[i])
    for i in range(n):  # the stack holds each member's scene as the read placed it
        scene = stack.scenes[i]
        placed = (
            scene
            if isinstance(scene, SceneGeometry)
            else scene.update(body_poses[stack.body_start[i] : stack.body_start[i + 1]])
        )
        for field in ("segments", "segment_owner", "circles", "circle_owner"):
            np.testing.assert_array_equal(getattr(stack.geometry(i), field), getattr(placed, field), strict=True)


def test_read_batch_reads_pymunk_poses_without_body_poses(pm):
    suite = SensorSuite(noise_std=0.05)
    scenes, poses, _ = _members(pm, 4, seed=3)
    stack = SceneStack(scenes)
    for scene in scenes:  # move every body in pymunk
        for body in getattr(scene, "moving_bodies", ()):
            body.angle += 0.7
            body.position = (body.position[0] + 0.4, body.position[1] - 0.2)
    expected = [
        suite.read(pose, scene if isinstance(scene, SceneGeometry) else scene.update(), np.random.default_rng(i), 0)
        for i, (pose, scene) in enumerate(zip(poses, scenes))
    ]
    out = suite.read_batch(poses, stack, [np.random.default_rng(i) for i in range(4)], 0)
    for i in range(4):
        _assert_same_reading(out.reading(i), expected[i])
    np.testing.assert_array_equal(
        stack.body_poses(), [(*b.position, b.angle) for s in scenes for b in getattr(s, "moving_bodies", ())]
    )


@pytest.mark.parametrize("noise_model", NOISE_MODELS)
def test_inactive_robots_are_left_alone(pm, noise_model):
    suite = SensorSuite(noise_std=0.05, noise_model=noise_model)
    scenes, poses, body_poses = _members(pm, 5, seed=7)
    stack = SceneStack(scenes)
    active = np.array([True, False, True, False, True])
    expected = _expected(suite, stack, poses, body_poses, range(5), np.zeros(5, int))
    poses[1] = np.nan  # a resetting member's pose and bodies may be anything
    body_poses[stack.body_start[1] : stack.body_start[2]] = np.inf
    out = suite.empty_batch(5)
    for block in (out.sonar, out.laser, out.unit_noise):
        block.fill(-7.0)
    rngs = [np.random.default_rng(s) for s in range(5)]
    untouched = _states(rngs)
    suite.read_batch(poses, stack, rngs, 0, body_poses=body_poses, out=out, active=active)
    for i in range(5):
        if active[i]:
            _assert_same_reading(out.reading(i), expected[i])
            assert rngs[i].bit_generator.state != untouched[i]
        else:
            assert (out.sonar[i] == -7.0).all() and (out.laser[i] == -7.0).all() and (out.unit_noise[i] == -7.0).all()
            assert rngs[i].bit_generator.state == untouched[i]
    for bad in (np.ones(4, bool), np.ones(5, int), [[True] * 5]):
        with pytest.raises(ValueError, match=r"active must be None or an \(N,\) bool array \(N = 5\)"):
            suite.read_batch(poses, stack, rngs, 0, body_poses=body_poses, active=bad)
    with pytest.raises(ValueError, match="poses must be finite; robot 1 has"):
        suite.read_batch(poses, stack, rngs, 0, body_poses=body_poses, active=~active)


def test_one_generator_for_several_robots_draws_their_rows_in_turn(room):
    suite = SensorSuite(noise_std=0.1)
    poses = np.array([[0.0, 0.0, 0.0], [1.0, 1.0, 2.0], [-1.0, 0.5, -1.0]])
    shared = np.random.default_rng(4)
    out = suite.read_batch(poses, SceneStack([room] * 3), [shared] * 3, -1)
    check = np.random.default_rng(4)
    for i, pose in enumerate(poses):
        _assert_same_reading(out.reading(i), suite.read(pose, room, check))
    assert shared.bit_generator.state == check.bit_generator.state


def test_an_empty_batch_draws_nothing(room):
    suite = SensorSuite()
    out = suite.read_batch(np.empty((0, 3)), SceneStack([]), [], -1)
    assert len(out) == 0 and out.laser.shape == (0, 180) and out.unit_noise.shape == (0, 196)


@pytest.mark.parametrize("noise_model", NOISE_MODELS)
def test_unit_noise_rows_are_each_generators_unit_noise(noise_model):
    rngs = [np.random.default_rng(s) for s in (1, 2, 3)]
    out = unit_noise_rows(noise_model, rngs, np.empty((3, 50)))
    for seed, row, rng in zip((1, 2, 3), out, rngs):
        reference = np.random.default_rng(seed)
        np.testing.assert_array_equal(row, unit_noise(noise_model, 50, reference))
        assert rng.bit_generator.state == reference.bit_generator.state
    with pytest.raises(ValueError, match="noise model must be one of"):
        unit_noise_rows("laplace", rngs, out)
    rngs = [np.random.default_rng(s) for s in (1, 2, 3)]
    before = out.copy()
    unit_noise_rows(noise_model, rngs, out, rows=np.array([0, 2]))
    np.testing.assert_array_equal(out[1], before[1])
    np.testing.assert_array_equal(out[2], unit_noise(noise_model, 50, np.random.default_rng(3)))
    assert rngs[1].bit_generator.state == np.random.default_rng(2).bit_generator.state


def test_stack_layout_and_reuse(pm):
    scenes, _, _ = _members(pm, 3, seed=1)
    stack = SceneStack(scenes)
    assert stack.with_scenes(list(scenes)) is stack
    other = stack.with_scenes([scenes[0], pm.random_scene(50).cache(), scenes[2]])
    assert other is not stack and other.scenes[0] is scenes[0]
    moving = [len(getattr(s, "moving_bodies", ())) for s in scenes]
    np.testing.assert_array_equal(stack.body_start, np.cumsum([0, *moving]))
    assert stack.num_bodies == sum(moving) and len(stack) == 3
    with pytest.raises(TypeError, match="scene 1 must be a GeometryCache or a SceneGeometry, got list"):
        SceneStack([scenes[0], []])


def test_bad_input_is_refused_before_any_generator_moves(pm):
    suite = SensorSuite()
    scenes, poses, body_poses = _members(pm, 3, seed=2)
    stack = SceneStack(scenes)
    rngs = [np.random.default_rng(s) for s in range(3)]
    states = _states(rngs)
    nan_pose = poses.copy()
    nan_pose[1, 2] = np.nan
    nan_body = body_poses.copy()
    nan_body[-1, 0] = np.inf
    last_body = len(body_poses) - stack.body_start[1] - 1  # the last member with bodies is member 1 (2 is fixed)
    bad = {
        r"poses must be a real \(N, 3\) array.*N = 3.*got shape \(3, 2\)": dict(poses=poses[:, :2]),
        r"poses must be a real \(N, 3\) array.*got shape \(2, 3\)": dict(poses=poses[:2]),
        r"poses must be a real .* dtype complex128": dict(poses=poses + 0j),
        r"poses must be finite; robot 1 has": dict(poses=nan_pose),
        r"rngs must hold one numpy.random.Generator per robot: 3, got 2": dict(rngs=rngs[:2]),
        r"exclude_owner must be one int or an \(N,\) int array": dict(exclude_owner=np.zeros(2, int)),
        r"exclude_owner must be one int .* dtype float64": dict(exclude_owner=np.zeros(3)),
        rf"body_poses must have shape \({len(body_poses)}, 3\)": dict(body_poses=body_poses[1:]),
        r"body_poses must be a numeric": dict(body_poses=[["x", "y", "z"]] * len(body_poses)),
        rf"body_poses row {len(body_poses) - 1} \(body {last_body} of member 1": dict(body_poses=nan_body),
        r"out must hold 3 rows of 16 sonars and 180 beams": dict(out=suite.empty_batch(2)),
    }
    arguments = dict(poses=poses, scenes=stack, rngs=rngs, exclude_owner=0, body_poses=body_poses)
    for message, change in bad.items():
        with pytest.raises(ValueError, match=message):
            suite.read_batch(**{**arguments, **change})
        assert _states(rngs) == states, message
    for message, change in {
        "scenes must be a SceneStack, got list": dict(scenes=list(scenes)),
        "rngs 2: rng must be a numpy.random.Generator, got int": dict(rngs=[*rngs[:2], 7]),
        "out must be a BatchReading or None, got dict": dict(out={}),
    }.items():
        with pytest.raises(TypeError, match=message):
            suite.read_batch(**{**arguments, **change})
        assert _states(rngs) == states, message


def test_batch_reading_checks_its_arrays():
    good = BatchReading.empty(2, 16, 180)
    with pytest.raises(ValueError, match=r"BatchReading.laser_owner must be a writeable C-contiguous int64"):
        BatchReading(good.sonar, good.laser, good.sonar_owner, good.laser_owner.astype(np.int32), good.unit_noise)
    with pytest.raises(ValueError, match=r"BatchReading.unit_noise must be .* \(N, K \+ R\)"):
        BatchReading(good.sonar, good.laser, good.sonar_owner, good.laser_owner, good.unit_noise[:, :100])
    with pytest.raises(ValueError, match=r"BatchReading.laser must be"):
        BatchReading(good.sonar, np.empty((2, 360))[:, ::2], good.sonar_owner, good.laser_owner, good.unit_noise)
    with pytest.raises(ValueError, match="n must be an int >= 0"):
        SensorSuite().empty_batch(-1)
    reading = good.reading(1)
    reading.laser[0] = 3.0
    assert good.laser[1, 0] == 3.0  # a view of the block's row


def _ram(world, step: int) -> np.ndarray:
    """Full speed at the nearest mover for 40 steps, then a sweeping turn for 40 (into walls)."""
    x, y, heading = world.robot.body.position[0], world.robot.body.position[1], world.robot.body.angle
    if step % 80 >= 40:
        return np.array([1.0, np.sin(0.1 * step)], np.float32)
    dx, dy = (world.mover_positions() - (x, y)).T
    k = int(np.argmin(np.hypot(dx, dy)))
    error = np.angle(np.exp(1j * (np.arctan2(dy[k], dx[k]) - heading)))
    return np.array([1.0, np.clip(2.0 * error, -1.0, 1.0)], np.float32)


@pytest.mark.parametrize("noise_model", NOISE_MODELS)
def test_batch_read_along_rescue_trajectories_equals_the_sensors_read_apart(noise_model):
    """Envs whose robots ram walls and movers, with pursuing and evading targets: at every
    step one batch read of all of them equals each robot's sensors read apart."""
    import copy

    from attentive_gym.attention.goals import Goal
    from attentive_gym.envs.rescue_env import ROBOT_ID, AttentiveRescueEnv
    from attentive_gym.sensors import GeometryCache

    goals = [Goal.direction_is("towards"), Goal.direction_is("away"), Goal.direction_is("towards"), None]
    envs = [AttentiveRescueEnv(noise_model=noise_model) for _ in goals]
    suite = envs[0].sensors
    caches, stack = {}, SceneStack([])
    behaviours, contacts, blocked = set(), 0, 0
    for step in range(240):
        if step % 80 == 0:
            for seed, (env, goal) in enumerate(zip(envs, goals)):
                env.reset(seed=seed + step, options={"goal": goal})
                behaviours.update(type(m.behaviour).__name__ for m in env.world.scenario.movers)
        for env in envs:
            _, _, _, _, info = env.step(_ram(env.world, step))
            contacts += bool(info["collision"])
            blocked += any(m.blocked for m in env.world.movers)
        worlds = [env.world for env in envs]
        for world in worlds:
            if id(world) not in caches:
                caches[id(world)] = GeometryCache(
                    [(ROBOT_ID, world.robot.body, [world.robot.shape])]
                    + [(m.entity.id, m.body, [m.shape]) for m in world.movers]
                    + [(entity.id, world.space.static_body, [shape]) for entity, shape in world.static]
                )
        stack = stack.with_scenes([caches[id(world)] for world in worlds])
        body_poses = stack.body_poses()
        poses = body_poses[stack.body_start[:-1]]  # each cache's first body is its robot
        rngs = [copy.deepcopy(env.np_random) for env in envs]
        out = suite.read_batch(poses, stack, [copy.deepcopy(rng) for rng in rngs], ROBOT_ID, body_poses=body_poses)
        for i, world in enumerate(worlds):
            expected = _apart(suite, poses[i], caches[id(world)].update(), rngs[i], ROBOT_ID)
            for field in FIELDS:
                np.testing.assert_array_equal(getattr(out.reading(i), field), expected[field], strict=True)
    assert {"PursueBehaviour", "EvadeBehaviour", "PathBehaviour"} <= behaviours
    assert contacts >= 50 and blocked >= 3, (contacts, blocked)  # 106 and 7 when written
