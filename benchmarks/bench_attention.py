"""Cost of one ``AttentionModel.step`` (all six maps) against one raw env step.

Run: ``python benchmarks/bench_attention.py [--steps N] [--csv PATH]``. Prints µs per model step for a
stationary and a moving robot (ego-motion compensation on), µs per raw
``AttentiveRescue-v0`` step with random actions when that environment can be made, and
their ratio (wall-clock times, measured in the same run). The model's CPU time per step is
printed too: it is what the step costs when the machine is shared with other jobs. The
readings are realistic: a room with walls, two targets moving at 0.5-0.8 m/s, 5 %
multiplicative noise. ``--csv`` also writes the figures as tidy rows into ``PATH``
(``tidy_csv``). Nothing is asserted: measure, don't guess.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from attentive_gym.attention import AttentionConfig, AttentionModel, Goal
from attentive_gym.attention.regions import SONAR_BEARINGS_DEG, laser_bearings_rad
from tidy_csv import Figures

NOISE = 0.05  # 5 % multiplicative Gaussian noise, as in the paper
DT_S = 0.05
ROOM_HALF_WIDTH_M = 4.0
ROOM_DEPTH_M = 9.0
SONAR_MAX_M, LASER_MAX_M = 5.0, 20.0
WARM_UP = 200


def _scene_ranges(bearings: np.ndarray, t: float) -> np.ndarray:
    """Ranges (m) along ``bearings`` in a box room with two targets moving back and forth."""
    c, s = np.cos(bearings), np.sin(bearings)
    with np.errstate(divide="ignore"):
        wall_x = np.where(c > 1e-9, ROOM_DEPTH_M / c, np.inf)
        wall_y = np.where(np.abs(s) > 1e-9, ROOM_HALF_WIDTH_M / np.abs(s), np.inf)
    ranges = np.minimum(wall_x, wall_y)
    for phase, speed, (bearing, radius) in ((0.0, 0.7, (0.17, 0.3)), (1.3, 0.5, (-0.55, 0.3))):
        r = 1.5 + abs(((speed * t + phase) % 6.0) - 3.0)
        hit = np.abs(np.sin(bearings - bearing)) * r < radius
        ranges = np.where(hit & (np.cos(bearings - bearing) > 0), np.minimum(ranges, r - radius), ranges)
    return ranges


def make_readings(n: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    beams = laser_bearings_rad()
    sonar_bearings = np.radians(SONAR_BEARINGS_DEG)
    sonar = np.empty((n, 16))
    laser = np.empty((n, 180))
    for k in range(n):
        t = k * DT_S
        sonar[k] = np.minimum(_scene_ranges(sonar_bearings, t), SONAR_MAX_M)
        laser[k] = np.minimum(_scene_ranges(beams, t), LASER_MAX_M)
    sonar *= 1.0 + NOISE * rng.standard_normal(sonar.shape)
    laser *= 1.0 + NOISE * rng.standard_normal(laser.shape)
    return np.clip(sonar, 0.0, SONAR_MAX_M), np.clip(laser, 0.0, LASER_MAX_M)


def time_model(steps: int, odometry: tuple[float, float] | None) -> tuple[float, float, int]:
    """Wall-clock and CPU µs per step with all six maps active, and the courses fired."""
    sonar, laser = make_readings(steps + WARM_UP)
    model = AttentionModel(AttentionConfig())
    model.set_goals(Goal.between("speed", 0.5, 0.9), Goal.direction_is("towards"), Goal.smaller("distance", 3.0))
    assert model.active_maps == ("F1", "F2", "F3", "F4", "F5", "F6")
    fired = 0
    for k in range(WARM_UP):
        model.step(k * DT_S, sonar[k], laser[k], odometry)
    start, start_cpu = time.perf_counter(), time.process_time()
    for k in range(WARM_UP, WARM_UP + steps):
        fired += model.step(k * DT_S, sonar[k], laser[k], odometry).fired
    cpu = time.process_time() - start_cpu
    return (time.perf_counter() - start) / steps * 1e6, cpu / steps * 1e6, fired


def time_env(steps: int) -> float | None:
    """µs per raw ``AttentiveRescue-v0`` step with random actions, or None if it cannot be made."""
    try:
        import gymnasium as gym

        import attentive_gym  # noqa: F401  (registers the environments)

        env = gym.make("AttentiveRescue-v0").unwrapped
        env.reset(seed=0)
        env.action_space.seed(0)
        actions = [env.action_space.sample() for _ in range(steps)]
    except Exception as err:  # the env is written concurrently: report, don't fail
        print(f"AttentiveRescue-v0 is not available ({type(err).__name__}: {err}); model figures only")
        return None
    start = time.perf_counter()
    for action in actions:
        _, _, terminated, truncated, _ = env.step(action)
        if terminated or truncated:
            env.reset()
    elapsed = time.perf_counter() - start
    env.close()
    return elapsed / steps * 1e6


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=5000)
    parser.add_argument("--csv", default=None, help="also write the figures as tidy rows into this CSV")
    args = parser.parse_args(argv)
    still, still_cpu, fired_still = time_model(args.steps, None)
    moving, moving_cpu, fired_moving = time_model(args.steps, (0.4, 0.2))
    env = time_env(min(args.steps, 2000))
    rows = [
        ("model step, robot still (6 maps, J=8)", still, still_cpu),
        ("model step, robot moving (ego-motion)", moving, moving_cpu),
    ]
    if env is not None:
        rows.append(("raw AttentiveRescue-v0 step", env, None))
    print(f"{'what':45s} {'us/step':>9s} {'cpu us':>8s}")
    for name, value, cpu in rows:
        print(f"{name:45s} {value:9.1f} {'' if cpu is None else f'{cpu:8.1f}'}")
    print(f"(courses fired: {fired_still} still, {fired_moving} moving, over {args.steps} steps)")
    if env is not None:
        print(f"ratio model/env: {still / env:.2f} still, {moving / env:.2f} moving (target < 0.5)")
    if args.csv:
        figures = Figures("attention")
        figures.add("model", "robot still", {"step_us": still, "cpu_step_us": still_cpu})
        figures.add("model", "robot moving", {"step_us": moving, "cpu_step_us": moving_cpu})
        if env is not None:
            figures.add("model", "raw AttentiveRescue-v0", {"step_us": env})
        figures.write(args.csv)


if __name__ == "__main__":
    main()
