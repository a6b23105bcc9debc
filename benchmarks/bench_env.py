"""Raw ``AttentiveRescue-v0`` speed against gymnasium's BipedalWalker-v3, in one run.

Prints:
1. steps/s of the raw env (random actions, no rendering) and of BipedalWalker-v3 (which
   casts 10 lidar rays a step), measured alternately in rounds; medians and their ratio
   (target: ≥ 1.5×);
2. the per-step cost with 10 / 50 / 200 rubble pieces in a 60 × 60 m arena (large enough
   to place 200 pieces and the movers), in µs per step and per shape: the cost should grow
   no worse than linearly with the number of shapes.

Usage: ``python benchmarks/bench_env.py [--seconds 2] [--rounds 5] [--csv PATH]``
(BipedalWalker needs ``pip install -e ".[bench]"``). ``--csv`` also writes the figures, and the
sensor benchmark's, as tidy rows into ``PATH`` (``tidy_csv``; e.g. ``docs/results/performance.csv``).
"""

from __future__ import annotations

import argparse
import statistics
import time

import gymnasium as gym

import attentive_gym  # noqa: F401  (registers the environments)
from tidy_csv import Figures


def steps_per_second(env: gym.Env, seconds: float, seed: int = 0) -> float:
    """Random-action steps per second of ``env`` over about ``seconds`` of wall time."""
    env.action_space.seed(seed)
    env.reset(seed=seed)
    actions = [env.action_space.sample() for _ in range(256)]
    steps, start = 0, time.perf_counter()
    while True:
        for action in actions:
            _, _, terminated, truncated, _ = env.step(action)
            steps += 1
            if terminated or truncated:
                env.reset()
        elapsed = time.perf_counter() - start
        if elapsed >= seconds:
            return steps / elapsed


def step_cost_us(env: gym.Env, seconds: float, seed: int = 0) -> float:
    """µs per random-action ``env.step``, resets excluded (they generate a new arena, whose
    cost grows with the rubble count and is not a step's)."""
    env.action_space.seed(seed)
    env.reset(seed=seed)
    actions = [env.action_space.sample() for _ in range(256)]
    steps, stepping, start = 0, 0.0, time.perf_counter()
    while time.perf_counter() - start < seconds:
        tic = time.perf_counter()
        for action in actions:
            _, _, terminated, truncated, _ = env.step(action)
            steps += 1
            if terminated or truncated:
                stepping += time.perf_counter() - tic
                env.reset()
                tic = time.perf_counter()
        stepping += time.perf_counter() - tic
    return stepping / steps * 1e6


def compare_with_bipedal_walker(seconds: float, rounds: int, figures: Figures) -> None:
    ours = gym.make("AttentiveRescue-v0").unwrapped
    try:
        peer = gym.make("BipedalWalker-v3").unwrapped
    except gym.error.DependencyNotInstalled as error:
        print(f"BipedalWalker-v3 unavailable ({error}); install the [bench] extra")
        return
    steps_per_second(ours, 0.3)  # warm-up: compiles the sensor kernels
    ours_rates, peer_rates = [], []
    for _ in range(rounds):
        ours_rates.append(steps_per_second(ours, seconds))
        peer_rates.append(steps_per_second(peer, seconds))
    a, b = statistics.median(ours_rates), statistics.median(peer_rates)
    print("== raw env vs BipedalWalker-v3 (medians of alternating rounds) ==")
    print(f"AttentiveRescue-v0 : {a:9.0f} steps/s  ({1e6 / a:6.1f} µs/step)")
    print(f"BipedalWalker-v3   : {b:9.0f} steps/s  ({1e6 / b:6.1f} µs/step)")
    print(f"ratio              : {a / b:9.2f}x  (target >= 1.5x)")
    figures.add("peers", "AttentiveRescue-v0", {"steps_per_s": a})
    figures.add("peers", "BipedalWalker-v3", {"steps_per_s": b})


RUBBLE_ARENA_M = 60.0  # a 30 m arena cannot place 200 pieces and the movers


def cost_by_rubble(seconds: float, figures: Figures) -> None:
    side = RUBBLE_ARENA_M
    print(f"== step cost by number of rubble pieces ({side:g} x {side:g} m arena, 3 distractors) ==")
    print(f"{'rubble':>7} {'shapes':>7} {'segments':>9} {'circles':>8} {'µs/step':>9} {'µs/shape':>9} {'vs 10':>7}")
    area_m2 = side * side
    first = None
    for count in (10, 50, 200):
        env = gym.make("AttentiveRescue-v0", arena_size_m=side, rubble_per_100m2=count * 100.0 / area_m2).unwrapped
        env.reset(seed=0)
        assert len(env.scenario.rubble) == count, (len(env.scenario.rubble), count)
        geometry = env.world.geometry()
        shapes = len(env.world.static) + len(env.world.movers) + 1
        cost = step_cost_us(env, seconds)
        first = first or (cost, shapes)
        figures.add("rubble", f"{count} rubble pieces", {"shapes": shapes, "step_us": cost})
        print(
            f"{len(env.scenario.rubble):7d} {shapes:7d} {len(geometry.segments):9d} {len(geometry.circles):8d} "
            f"{cost:9.1f} {cost / shapes:9.2f} {cost / first[0]:6.2f}x"
        )
    print(f"(shapes grew {shapes / first[1]:.1f}x; the step cost should grow no more than that)")


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seconds", type=float, default=2.0, help="wall time per measurement")
    parser.add_argument("--rounds", type=int, default=5, help="alternating rounds for the peer comparison")
    parser.add_argument("--csv", default=None, help="also write the figures as tidy rows into this CSV")
    args = parser.parse_args(argv)
    figures = Figures("env")
    compare_with_bipedal_walker(args.seconds, args.rounds, figures)
    cost_by_rubble(args.seconds, figures)
    if args.csv:
        figures.write(args.csv)
    try:
        from bench_sensors import main as sensor_benchmark
    except ImportError:
        from benchmarks.bench_sensors import main as sensor_benchmark
    print("== sensor sweep vs pymunk per-ray queries ==")
    sensor_benchmark([] if args.csv is None else ["--csv", args.csv])


if __name__ == "__main__":
    main()
