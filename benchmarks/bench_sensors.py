"""Cost of one sensor sweep (180 laser beams + 16 exact sonar cones), analytic vs pymunk.

Prints, in one run:
1. µs per sweep with the analytic numba kernels against the same sweep done with pymunk
   per-ray queries (180 laser rays + 16 sonars x 5 rays), on one scene of about 60
   segments and 10 circles, and their ratio (target: >= 10x); also the cost of
   ``GeometryCache.update()`` and of a whole noisy ``SensorSuite.read``;
2. the sweep cost with 10 / 50 / 200 random shapes (boxes, circles, segments) in a
   20 x 20 m walled arena, which should grow no worse than linearly with the shapes.

Timings: ``time.perf_counter``, median over repeats of a batch of calls, after a warm-up
(which also compiles the kernels). Usage: ``python benchmarks/bench_sensors.py [--repeats 15] [--csv PATH]``;
``--csv`` also writes the figures as tidy rows into ``PATH`` (``tidy_csv``).
"""

from __future__ import annotations

import argparse
import math
import statistics
import time

import numpy as np
import pymunk

from attentive_gym.sensors import GeometryCache, LaserConfig, LaserScanner, SensorSuite, SonarConfig, SonarRing
from tidy_csv import Figures

ROBOT_ID = 0
ROBOT_CATEGORY = 0b10
RAYS_PER_SONAR = 5  # what a ray-fan sonar would need at least: one ray every 7.5 deg
ARENA_M = 20.0
ROBOT_CLEARANCE_M = 1.5  # no shape this close to the robot's centre
WALL_M = 0.2  # thickness of the arena's walls


def arena(num_shapes: int, seed: int = 0):
    """A walled 20 x 20 m arena with ``num_shapes`` random boxes, circles and segments
    (static and kinematic), and the P2AT-sized robot in the middle.

    Returns:
        ``(space, entries for GeometryCache, robot pose (3,))``.
    """
    rng = np.random.default_rng(seed)
    space = pymunk.Space()
    robot = pymunk.Body(14.0, 1.0)
    robot.angle = 0.3
    robot_shape = pymunk.Poly.create_box(robot, (0.626, 0.505))
    robot_shape.filter = pymunk.ShapeFilter(categories=ROBOT_CATEGORY)
    space.add(robot, robot_shape)
    entries = [(ROBOT_ID, robot, [robot_shape])]
    half = ARENA_M / 2
    owner = 1
    for x0, y0, x1, y1 in [
        (-half, -half, half, -half + WALL_M),
        (half - WALL_M, -half, half, half),
        (-half, half - WALL_M, half, half),
        (-half, -half, -half + WALL_M, half),
    ]:
        wall = pymunk.Poly(space.static_body, [(x0, y0), (x1, y0), (x1, y1), (x0, y1)])
        space.add(wall)
        entries.append((owner, space.static_body, [wall]))
        owner += 1
    for i in range(num_shapes):
        while True:
            centre = rng.uniform(-half + 1.0, half - 1.0, 2)
            if np.hypot(*centre) > ROBOT_CLEARANCE_M:
                break
        moving = i % 5 == 0
        body = pymunk.Body(body_type=pymunk.Body.KINEMATIC) if moving else space.static_body
        offset = (0.0, 0.0) if moving else tuple(centre)
        kind = ("box", "circle", "segment")[i % 3]
        if kind == "box":
            transform = pymunk.Transform.translation(*offset).rotated(rng.uniform(0, np.pi))
            shape = pymunk.Poly(body, [(-0.4, -0.25), (0.4, -0.25), (0.4, 0.25), (-0.4, 0.25)], transform)
        elif kind == "circle":
            shape = pymunk.Circle(body, rng.uniform(0.1, 0.4), offset)
        else:
            direction = rng.uniform(0, np.pi)
            d = 0.5 * np.array([math.cos(direction), math.sin(direction)])
            shape = pymunk.Segment(body, tuple(offset - d), tuple(offset + d), 0.0)
        if moving:
            body.position = tuple(centre)
            body.angle = rng.uniform(0, np.pi)
            space.add(body)
        space.add(shape)
        entries.append((owner, body, [shape]))
        owner += 1
    return space, entries, np.array([0.0, 0.0, robot.angle])


def _median_us(call, repeats: int, batch: int) -> float:
    """Median over ``repeats`` batches of the µs one ``call()`` takes."""
    for _ in range(batch):
        call()
    samples = []
    for _ in range(repeats):
        start = time.perf_counter()
        for _ in range(batch):
            call()
        samples.append((time.perf_counter() - start) / batch * 1e6)
    return statistics.median(samples)


def _sweepers(space, entries, pose):
    """Callables ``(analytic sweep, pymunk per-ray sweep, geometry update, noisy suite
    read)`` for a robot at ``pose``, and the scene's ``SceneGeometry``."""
    cache = GeometryCache(entries)
    geometry = cache.update()
    ring, scanner = SonarRing(SonarConfig()), LaserScanner(LaserConfig())
    suite = SensorSuite(noise_std=0.05)
    rng = np.random.default_rng(0)
    x, y, theta = (float(v) for v in pose)

    def analytic():
        ring.read(pose, geometry, ROBOT_ID)
        scanner.read(pose, geometry, ROBOT_ID)

    c, s = math.cos(theta), math.sin(theta)
    laser = LaserConfig()
    laser_origin = (x + c * laser.mount_x_m, y + s * laser.mount_x_m)
    laser_ends = [
        (
            laser_origin[0] + laser.max_range_m * math.cos(theta + b),
            laser_origin[1] + laser.max_range_m * math.sin(theta + b),
        )
        for b in laser.bearings_rad
    ]
    sonar = SonarConfig()
    spread = np.radians(np.linspace(-sonar.cone_half_width_deg, sonar.cone_half_width_deg, RAYS_PER_SONAR))
    sonar_rays = []
    for mx, my, bearing in sonar.mounts:
        apex = (x + c * mx - s * my, y + s * mx + c * my)
        for offset in spread:
            angle = theta + bearing + offset
            sonar_rays.append(
                (apex, (apex[0] + sonar.max_range_m * math.cos(angle), apex[1] + sonar.max_range_m * math.sin(angle)))
            )
    query_filter = pymunk.ShapeFilter(mask=pymunk.ShapeFilter.ALL_MASKS() ^ ROBOT_CATEGORY)
    query = space.segment_query_first

    def per_ray():
        laser_hits = [query(laser_origin, end, 0.0, query_filter) for end in laser_ends]
        for apex, end in sonar_rays:
            query(apex, end, 0.0, query_filter)
        return laser_hits

    return analytic, per_ray, cache.update, lambda: suite.read(pose, cache.update(), rng, ROBOT_ID), geometry


def _laser_disagreement_m(per_ray, pose, geometry) -> float:
    """Largest difference (m) between the analytic laser and pymunk's rays, same scene."""
    max_range = LaserConfig().max_range_m
    pymunk_ranges = np.array([max_range if hit is None else hit.alpha * max_range for hit in per_ray()])
    analytic, _ = LaserScanner(LaserConfig()).read(pose, geometry, ROBOT_ID)
    return float(np.abs(analytic - pymunk_ranges).max())


def compare_with_pymunk(repeats: int, figures: Figures) -> None:
    space, entries, pose = arena(21, seed=1)
    analytic, per_ray, update, suite_read, geometry = _sweepers(space, entries, pose)
    a = _median_us(analytic, repeats, 200)
    p = _median_us(per_ray, repeats, 5)
    print(
        f"== one sweep: laser 180 beams + 16 sonar cones, {len(geometry.segments)} segments + "
        f"{len(geometry.circles)} circles (medians of {repeats}) =="
    )
    print(f"analytic kernels (exact cones)        : {a:8.1f} µs/sweep  (target <= 60 µs)")
    print(f"pymunk per-ray ({180 + 16 * RAYS_PER_SONAR} segment queries)  : {p:8.1f} µs/sweep")
    print(f"ratio                                 : {p / a:8.1f}x  (target >= 10x)")
    disagreement_m = _laser_disagreement_m(per_ray, pose, geometry)
    update_us, read_us = _median_us(update, repeats, 200), _median_us(suite_read, repeats, 200)
    print(f"laser: analytic vs pymunk, max |diff| : {disagreement_m:8.1e} m")
    print(f"GeometryCache.update()                : {update_us:8.1f} µs")
    print(f"SensorSuite.read incl. update + noise : {read_us:8.1f} µs")
    figures.add("sweep", "analytic kernels", {"sweep_us": a, "max_laser_difference_m": disagreement_m})
    figures.add("sweep", "pymunk per-ray queries", {"sweep_us": p, "rays": 180 + 16 * RAYS_PER_SONAR})
    figures.add("sweep", "GeometryCache.update", {"call_us": update_us})
    figures.add("sweep", "SensorSuite.read", {"call_us": read_us})


def cost_by_shapes(repeats: int, figures: Figures) -> None:
    print("== sweep cost by number of random shapes (20 x 20 m walled arena) ==")
    print(f"{'shapes':>7} {'segments':>9} {'circles':>8} {'analytic µs':>12} {'µs/shape':>9} {'pymunk µs':>10}")
    for count in (10, 50, 200):
        space, entries, pose = arena(count, seed=count)
        analytic, per_ray, _, _, geometry = _sweepers(space, entries, pose)
        a = _median_us(analytic, repeats, 100)
        p = _median_us(per_ray, repeats, 3)
        print(f"{count:7d} {len(geometry.segments):9d} {len(geometry.circles):8d} {a:12.1f} {a / count:9.2f} {p:10.1f}")
        figures.add("shapes", f"{count} shapes", {"analytic_sweep_us": a, "pymunk_sweep_us": p})


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=15, help="timed batches per figure (median taken)")
    parser.add_argument("--csv", default=None, help="also write the figures as tidy rows into this CSV")
    args = parser.parse_args(argv)
    figures = Figures("sensors")
    compare_with_pymunk(args.repeats, figures)
    cost_by_shapes(args.repeats, figures)
    if args.csv:
        figures.write(args.csv)


if __name__ == "__main__":
    main()
