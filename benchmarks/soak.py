"""Soak test: millions of random-policy steps of ``AttentiveRescue-v0``, invariants checked at every one.

Runs ``--steps`` environment steps (default 1,000,000) spread over many seeds and
scenarios (the procedural arena with several sets of knobs, and ``exp01`` … ``exp05``),
feeds every step to an ``AttentionModel`` (goals and weights varied per episode; the
default ``kinematics="tracker"``), and checks ``attentive_gym.envs.invariants`` after
each step, the tracker's state and track table included. Work is split into chunks run
by a ``multiprocessing`` pool (``--workers``, default: every core).

Prints steps, episodes, violations (the run fails, exit status 1, if there are any),
steps/s, the deepest wall/rubble overlap seen, and how many tracks were checked (track
rows over all steps, the most live at once); ``--json PATH`` writes the same.

    python benchmarks/soak.py                     # 1,000,000 steps
    python benchmarks/soak.py --steps 5000        # a quick check (the test suite runs this)
    python benchmarks/soak.py --steps 3000000 --first-seed 1000   # other episodes
"""

from __future__ import annotations

import argparse
import json
import multiprocessing
import os
import sys
import time
from typing import Any

import numpy as np

#: Environment configurations soaked: (label, keyword arguments of the env).
CONFIGS: tuple[tuple[str, dict[str, Any]], ...] = (
    ("rescue-default", {}),
    ("rescue-empty", {"num_distractors": 0, "rubble_per_100m2": 0.0}),
    ("rescue-crowded", {"arena_size_m": 12.0, "num_distractors": 6, "rubble_per_100m2": 10.0}),
    (
        "rescue-small-fast",
        {"arena_size_m": 8.0, "num_distractors": 2, "rubble_per_100m2": 3.0, "max_mover_speed_mps": 2.0, "dt": 0.1},
    ),
    (
        "rescue-wide-direction",
        {"arena_size_m": (20.0, 8.0), "num_distractors": 4, "sensor_noise": 0.2, "dt": 0.02, "goals": "direction"},
    ),
    ("rescue-noiseless-coarse", {"sensor_noise": 0.0, "dt": 0.25, "rubble_per_100m2": 12.0}),
    ("exp01", {"scenario": "exp01"}),
    ("exp02", {"scenario": "exp02"}),
    ("exp03", {"scenario": "exp03"}),
    ("exp04", {"scenario": "exp04", "dt": 0.1}),
    ("exp05", {"scenario": "exp05", "sensor_noise": 0.0}),
)


def _env_kwargs(kwargs: dict[str, Any]) -> dict[str, Any]:
    from attentive_gym.attention.goals import Goal

    kwargs = dict(kwargs)
    if kwargs.get("goals") == "direction":
        kwargs["goals"] = (
            Goal.direction_is("towards"),
            Goal.direction_is("away"),
            Goal.direction_is("static"),
            Goal.between("speed", 0.5, 0.9),
        )
    return kwargs


def _policy(rng: np.random.Generator, state: dict) -> np.ndarray:
    """Random actions, held for random stretches so the robot also drives into things."""
    if state.get("left", 0) <= 0:
        mode = rng.integers(4)
        if mode == 0:
            state["action"] = None  # fresh uniform noise every step
        elif mode == 1:
            state["action"] = np.array([1.0, rng.uniform(-0.3, 0.3)], np.float32)  # charge ahead
        elif mode == 2:
            state["action"] = np.array([rng.uniform(-1, 1), rng.choice([-1.0, 1.0])], np.float32)  # spin
        else:
            state["action"] = rng.uniform(-1.5, 1.5, 2).astype(np.float32)  # beyond the box: clipped
        state["left"] = int(rng.integers(5, 80))
    state["left"] -= 1
    action = state["action"]
    return rng.uniform(-1, 1, 2).astype(np.float32) if action is None else action


def _configure_model(model, rng: np.random.Generator, goal) -> None:
    from attentive_gym.attention.goals import Goal

    goals = [] if goal is None else [goal]
    if rng.random() < 0.3:
        goals.append(Goal.smaller("distance", float(rng.uniform(0.5, 5.0))))
    model.set_goals(*goals)
    model.set_weights(rng.uniform(0.0, 2.0, 6).round(3).tolist())
    model.set_state(str(rng.choice(["drowsy", "alert", "vigilant"])))


def run_chunk(task: tuple[int, int, int]) -> dict[str, Any]:
    """Run ``steps`` steps of configuration ``config_index`` starting from ``seed``."""
    config_index, seed, steps = task
    os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
    from attentive_gym.attention import AttentionConfig, AttentionModel
    from attentive_gym.envs.invariants import InvariantChecker
    from attentive_gym.envs.rescue_env import AttentiveRescueEnv
    from attentive_gym.world import compiled

    label, kwargs = CONFIGS[config_index]
    env = AttentiveRescueEnv(**_env_kwargs(kwargs))
    rng = np.random.default_rng([seed, config_index])
    grid = "laser" if seed % 5 == 0 else "sonar"
    model = AttentionModel(AttentionConfig(grid=grid))
    checker = InvariantChecker()
    violations: list[str] = []
    n_violations = episodes = done = track_rows = most_tracks = 0
    start = time.perf_counter()
    while done < steps:
        obs, _ = env.reset(seed=int(seed * 1000 + episodes))
        checker.reset()
        model.reset()
        _configure_model(model, rng, env.goal)
        output = model.step(0.0, obs["sonar"], obs["laser"], obs["odometry"])
        problems = checker.check(env, obs, output, model=model)
        state: dict = {}
        episodes += 1
        while done < steps:
            obs, reward, terminated, truncated, info = env.step(_policy(rng, state))
            done += 1
            output = model.step(info["time_s"], obs["sonar"], obs["laser"], obs["odometry"])
            problems = checker.check(env, obs, output, info, model=model)
            n_tracks = len(output.tracks)
            track_rows += n_tracks
            most_tracks = max(most_tracks, n_tracks)
            if not np.isfinite(reward):
                problems.append(f"reward {reward} is not finite")
            if problems:
                n_violations += len(problems)
                if len(violations) < 20:
                    violations.extend(
                        f"{label} seed {seed} episode {episodes} t={info['time_s']:.2f}: {p}" for p in problems
                    )
            if terminated or truncated:
                break
    return {
        "label": label,
        "steps": done,
        "episodes": episodes,
        "violations": n_violations,
        "examples": violations,
        "seconds": time.perf_counter() - start,
        "max_penetration_m": checker.max_penetration_m,
        "track_rows": track_rows,
        "max_live_tracks": most_tracks,
        "world_engine": compiled.engine(),
    }


def make_tasks(steps: int, chunk: int, first_seed: int = 0) -> list[tuple[int, int, int]]:
    """Chunks of at most ``chunk`` steps, round-robin over the configurations, one chunk
    seed each from ``first_seed`` on."""
    tasks = []
    remaining, seed = steps, first_seed
    while remaining > 0:
        n = min(chunk, remaining)
        tasks.append((seed % len(CONFIGS), seed, n))
        remaining -= n
        seed += 1
    return tasks


def soak(
    steps: int = 1_000_000,
    workers: int | None = None,
    chunk: int | None = None,
    progress: bool = False,
    first_seed: int = 0,
) -> dict[str, Any]:
    """Run the soak; returns the summary (see the module docstring)."""
    workers = workers or os.cpu_count() or 1
    chunk = chunk or max(200, min(5000, steps // (2 * len(CONFIGS)) or 1))
    tasks = make_tasks(steps, chunk, first_seed)
    start = time.perf_counter()
    results = []
    if workers == 1:
        iterator = map(run_chunk, tasks)
        pool = None
    else:
        pool = multiprocessing.get_context("spawn").Pool(workers)
        iterator = pool.imap_unordered(run_chunk, tasks)
    try:
        for result in iterator:
            results.append(result)
            if progress:
                done = sum(r["steps"] for r in results)
                print(
                    f"  {done:>9} steps, {sum(r['violations'] for r in results)} violations, "
                    f"{done / (time.perf_counter() - start):.0f} steps/s",
                    file=sys.stderr,
                    flush=True,
                )
    finally:
        if pool is not None:
            pool.close()
            pool.join()
    wall = time.perf_counter() - start
    per_config: dict[str, dict[str, float]] = {}
    for r in results:
        c = per_config.setdefault(r["label"], {"steps": 0, "episodes": 0, "violations": 0, "max_penetration_m": 0.0})
        c["steps"] += r["steps"]
        c["episodes"] += r["episodes"]
        c["violations"] += r["violations"]
        c["max_penetration_m"] = max(c["max_penetration_m"], r["max_penetration_m"])
    total = sum(r["steps"] for r in results)
    return {
        "steps": total,
        "episodes": sum(r["episodes"] for r in results),
        "violations": sum(r["violations"] for r in results),
        "examples": [e for r in results for e in r["examples"]][:20],
        "wall_s": wall,
        "steps_per_s": total / wall if wall > 0 else float("nan"),
        "workers": workers,
        "max_penetration_m": max(c["max_penetration_m"] for c in per_config.values()),
        "track_rows": sum(r["track_rows"] for r in results),
        "max_live_tracks": max(r["max_live_tracks"] for r in results),
        "world_engines": sorted({r["world_engine"] for r in results}),
        "per_config": per_config,
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=1_000_000, help="environment steps in all (default 1,000,000)")
    parser.add_argument("--workers", type=int, default=None, help="processes (default: every core)")
    parser.add_argument("--chunk", type=int, default=None, help="steps per task (default: up to 5000)")
    parser.add_argument(
        "--first-seed",
        type=int,
        default=0,
        help="seed of the first chunk (default 0): another value soaks episodes no earlier run saw",
    )
    parser.add_argument("--json", default=None, help="also write the summary to this file")
    parser.add_argument("--quiet", action="store_true", help="no progress lines")
    args = parser.parse_args(argv)
    if args.steps < 1:
        parser.error("--steps must be >= 1")
    if args.first_seed < 0:
        parser.error("--first-seed must be >= 0")
    summary = soak(args.steps, args.workers, args.chunk, progress=not args.quiet, first_seed=args.first_seed)
    print(f"steps       {summary['steps']}")
    print(f"episodes    {summary['episodes']}")
    print(f"violations  {summary['violations']}")
    print(f"wall        {summary['wall_s']:.1f} s on {summary['workers']} workers")
    print(f"steps/s     {summary['steps_per_s']:.0f} (env + model + invariants)")
    print(f"deepest wall/rubble overlap: {summary['max_penetration_m']:.4f} m")
    print(f"world step  {', '.join(summary['world_engines'])} (attentive_gym.world.compiled.engine())")
    print(f"tracks      {summary['track_rows']} track rows checked, at most {summary['max_live_tracks']} live at once")
    for label, c in summary["per_config"].items():
        print(
            f"  {label:<26} {c['steps']:>8} steps {c['episodes']:>6} episodes {c['violations']:>4} violations "
            f"overlap {c['max_penetration_m']:.3f} m"
        )
    for example in summary["examples"]:
        print("  VIOLATION", example)
    if args.json:
        with open(args.json, "w", encoding="utf-8") as handle:
            json.dump(summary, handle, indent=2)
    return 1 if summary["violations"] else 0


if __name__ == "__main__":
    sys.exit(main())
