"""Attended environments' speed against gymnasium's BipedalWalker-v3, in one run.

For every observation variant (``attentive_gym.wrappers.VARIANTS``) built with
``make_env`` (random actions, no rendering, no gymnasium checker wrappers), prints the
median steps/s over alternating rounds with BipedalWalker-v3, and the ratio (target for
the attended variants: ≥ 1.0×). Also splits one attended step into its parts: the base
environment, the model's step and the observation encoding.

Usage: ``python benchmarks/bench_wrappers.py [--seconds 1] [--rounds 3] [--csv PATH]``
(BipedalWalker needs ``pip install -e ".[bench]"``). ``--csv`` also writes the figures as tidy
rows into ``PATH`` (``tidy_csv``).
"""

from __future__ import annotations

import argparse
import statistics
import time

import gymnasium as gym
import numpy as np

from attentive_gym.wrappers import VARIANTS, make_env
from bench_env import steps_per_second
from tidy_csv import Figures


def compare_variants(seconds: float, rounds: int, figures: Figures) -> None:
    peer = gym.make("BipedalWalker-v3").unwrapped
    envs = {variant: make_env(variant) for variant in VARIANTS}
    for env in envs.values():
        steps_per_second(env, 0.3)  # warm-up: compiles the numba kernels
    rates: dict[str, list[float]] = {name: [] for name in (*envs, "BipedalWalker-v3")}
    for _ in range(rounds):
        rates["BipedalWalker-v3"].append(steps_per_second(peer, seconds))
        for variant, env in envs.items():
            rates[variant].append(steps_per_second(env, seconds))
    peer_rate = statistics.median(rates["BipedalWalker-v3"])
    print("== observation variants vs BipedalWalker-v3 (medians of alternating rounds) ==")
    print(f"{'variant':<18} {'steps/s':>9} {'µs/step':>9} {'ratio':>7}")
    for name, values in rates.items():
        rate = statistics.median(values)
        print(f"{name:<18} {rate:9.0f} {1e6 / rate:9.1f} {rate / peer_rate:6.2f}x")
        figures.add("variants", name, {"steps_per_s": rate})
    print("target: attended variants (focus, saliency, masked, goal-action) >= 1.0x")


def split_focus_step(figures: Figures, steps: int = 3000) -> None:
    """Time the base env, the model and the encoder separately within focus steps."""
    env = make_env("focus")
    env.reset(seed=0)
    base, model, encoder = env.env, env.model, env._encoder
    actions = np.random.default_rng(0).uniform(-1, 1, (steps, 2)).astype(np.float32)
    totals = np.zeros(3)
    for action in actions:
        t0 = time.perf_counter()
        raw, _, terminated, truncated, info = base.step(action)
        t1 = time.perf_counter()
        output = model.step(info["time_s"], raw["sonar"], raw["laser"], raw["odometry"])
        t2 = time.perf_counter()
        region, event = env._attended(output)
        encoder.encode_region(raw, output, region, event, env._remember(output, region))
        t3 = time.perf_counter()
        totals += (t1 - t0, t2 - t1, t3 - t2)
        if terminated or truncated:
            base.reset()
            model.reset()
    env_us, model_us, encode_us = totals / steps * 1e6
    print("== one focus step, split ==")
    print(f"base env {env_us:6.1f} µs   model {model_us:6.1f} µs   encoding and memory {encode_us:6.1f} µs")
    print(f"model / env: {model_us / env_us:.2f} (target < 0.5)")
    figures.add("split", "focus", {"base_env_us": env_us, "model_us": model_us, "encoding_us": encode_us})


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=1.0, help="wall time per measurement (s)")
    parser.add_argument("--rounds", type=int, default=3, help="alternating measurement rounds")
    parser.add_argument("--csv", default=None, help="also write the figures as tidy rows into this CSV")
    args = parser.parse_args(argv)
    figures = Figures("wrappers")
    compare_variants(args.seconds, args.rounds, figures)
    split_focus_step(figures)
    if args.csv:
        figures.write(args.csv)


if __name__ == "__main__":
    main()
