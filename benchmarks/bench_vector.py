"""The native vector env against its peers, measured in the same run.

Prints:
1. ``focus`` and ``raw`` at N = 16: env-steps/s of the native vector env
   (``vectorization_mode="vector_entry_point"``), of gymnasium's sync vector env over
   single envs, and of BipedalWalker-v3 (one env), measured alternately in rounds;
   medians and the ratios (targets for ``focus``: ≥ 4× the sync vector env, ≥ 3×
   BipedalWalker-v3);
2. against VMAS (its ``flocking`` scenario with 1 agent and a 196-ray lidar, CPU, one
   torch thread) at N = 16, 64, 256: µs per env-step of each (target: below VMAS's);
3. a scaling table of the native ``focus`` env for N = 1 … 256: µs per env-step,
   env-steps/s, and memory per env (the resident memory that building and resetting the N
   envs adds to a fresh process, divided by N; Linux only);
4. the floor of the native ``focus`` env at N = 16: the µs per env-step of the work no
   design of the step around today's kernels can skip (the compiled sensor sweep and
   attentional models, timed inside the running env, and the fewest pymunk calls a step of
   each world needs, the per-body API being Python), beside the budgets the speed targets
   leave (BipedalWalker-v3's µs per step / 3, the sync vector env's / 4, measured in the
   same run).

Random actions, no rendering; resets are part of the stepping (autoreset).

Usage: ``python benchmarks/bench_vector.py [--seconds 2] [--rounds 3] [--max-envs 256]
[--sections peers,vmas,scaling,floor] [--csv PATH]``; ``--csv`` also writes the figures as tidy rows
into ``PATH`` (``tidy_csv``)
(the native env's compiled kernels run on ``attentive_gym.vector.threads.default_threads(N)`` threads:
one below 32 envs, else the idle cores up to ``NUMBA_NUM_THREADS``)
(BipedalWalker needs ``pip install -e ".[bench]"``; VMAS ``pip install vmas``, skipped if absent).
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time

import gymnasium as gym
import numpy as np

import attentive_gym  # noqa: F401  (registers the environments)
from attentive_gym import _pymunk_access
from attentive_gym.attention.compiled import batch as model_batch
from attentive_gym.registration import VARIANT_IDS
from attentive_gym.sensors import suite as sensor_suite
from bench_env import steps_per_second
from call_timer import CallTimer
from tidy_csv import Figures


def vector_rate(env, seconds: float, seed: int = 0) -> float:
    """Env-steps per second (steps × num_envs) of a vector env over about ``seconds``."""
    env.reset(seed=seed)
    rng = np.random.default_rng(seed)
    actions = rng.uniform(-1, 1, (32, *env.action_space.shape)).astype(env.action_space.dtype)
    for action in actions[:3]:  # warm-up
        env.step(action)
    steps, start = 0, time.perf_counter()
    while time.perf_counter() - start < seconds:
        env.step(actions[steps % len(actions)])
        steps += 1
    return steps * env.num_envs / (time.perf_counter() - start)


def make_vector(variant: str, num_envs: int, mode: str):
    return gym.make_vec(VARIANT_IDS[variant], num_envs=num_envs, vectorization_mode=mode)


def peers_at_16(seconds: float, rounds: int, figures: Figures) -> None:
    walker = gym.make("BipedalWalker-v3")
    for variant in ("focus", "raw"):
        envs = {"native": make_vector(variant, 16, "vector_entry_point"), "sync": make_vector(variant, 16, "sync")}
        rates = {"native": [], "sync": [], "BipedalWalker-v3": []}
        for _ in range(rounds):
            for name, env in envs.items():
                rates[name].append(vector_rate(env, seconds))
            rates["BipedalWalker-v3"].append(steps_per_second(walker, seconds))
        med = {name: statistics.median(values) for name, values in rates.items()}
        print(f"== {variant}, N = 16 (medians of {rounds} alternating rounds) ==")
        print(f"{'env':<18} {'env-steps/s':>12} {'µs/env-step':>12}")
        for name, rate in med.items():
            print(f"{name:<18} {rate:12.0f} {1e6 / rate:12.1f}")
        print(
            f"native / sync: {med['native'] / med['sync']:.2f}x   native / BipedalWalker-v3: "
            f"{med['native'] / med['BipedalWalker-v3']:.2f}x" + ("   (targets: 4x, 3x)" if variant == "focus" else "")
        )
        figures.add(
            "peers",
            variant,
            {
                "native_us": 1e6 / med["native"],
                "sync_us": 1e6 / med["sync"],
                "bipedal_walker_us": 1e6 / med["BipedalWalker-v3"],
            },
            num_envs=16,
        )
        for env in envs.values():
            env.close()


class Vmas:
    """VMAS ``flocking`` with one agent and a 196-ray lidar: random actions, µs per env-step."""

    def __init__(self, num_envs: int):
        import torch
        import vmas

        torch.set_num_threads(1)
        self.env = vmas.make_env(
            "flocking", num_envs=num_envs, device="cpu", continuous_actions=True, seed=0, n_agents=1, n_lidar_rays=196
        )
        self.num_envs = num_envs
        self.env.reset()

    def rate(self, seconds: float) -> float:
        import torch

        generator = torch.Generator().manual_seed(0)
        actions = [[torch.rand(self.num_envs, 2, generator=generator) * 2 - 1] for _ in range(16)]
        for action in actions[:3]:
            self.env.step(action)
        steps, start = 0, time.perf_counter()
        while time.perf_counter() - start < seconds:
            self.env.step(actions[steps % len(actions)])
            steps += 1
        return steps * self.num_envs / (time.perf_counter() - start)


def against_vmas(seconds: float, rounds: int, sizes, figures: Figures) -> None:
    try:
        import vmas  # noqa: F401
    except ImportError:
        print("== VMAS: not installed (pip install vmas); skipped ==")
        return
    print("== against VMAS (flocking, 1 agent, 196 lidar rays, CPU, 1 torch thread), µs per env-step ==")
    print(f"{'N':>5} {'VMAS':>8} {'focus':>8} {'raw':>8} {'focus/VMAS speed':>17}")
    for n in sizes:
        peers = {
            "VMAS": Vmas(n),
            "focus": make_vector("focus", n, "vector_entry_point"),
            "raw": make_vector("raw", n, "vector_entry_point"),
        }
        rates = {name: [] for name in peers}
        for _ in range(rounds):
            for name, env in peers.items():
                rates[name].append(env.rate(seconds) if name == "VMAS" else vector_rate(env, seconds))
        us = {name: 1e6 / statistics.median(values) for name, values in rates.items()}
        print(f"{n:5d} {us['VMAS']:8.1f} {us['focus']:8.1f} {us['raw']:8.1f} {us['VMAS'] / us['focus']:16.2f}x")
        figures.add(
            "vmas", "env-step", {"vmas_us": us["VMAS"], "focus_us": us["focus"], "raw_us": us["raw"]}, num_envs=n
        )


_MEMORY_PROBE = """
import gymnasium as gym, attentive_gym
from bench_vector import resident_bytes
probe = gym.make_vec("AttentiveRescueFocus-v1", num_envs=1, vectorization_mode="vector_entry_point")
probe.reset(seed=0)  # imports, compiled kernels and caches: not the envs' memory
before = resident_bytes()
env = gym.make_vec("AttentiveRescueFocus-v1", num_envs={n}, vectorization_mode="vector_entry_point")
env.reset(seed=0)
print((resident_bytes() - before) / {n})
"""


def resident_bytes() -> float:
    """The process's resident memory (bytes), NaN where ``/proc`` is missing."""
    try:
        with open("/proc/self/statm") as statm:
            return int(statm.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
    except OSError:
        return float("nan")


def memory_per_env(n: int) -> float:
    """Resident memory (MiB) that building and resetting ``n`` native ``focus`` envs adds, per env,
    measured in a fresh process."""
    here = os.path.dirname(os.path.abspath(__file__))
    result = subprocess.run(
        [sys.executable, "-c", _MEMORY_PROBE.format(n=n)], capture_output=True, text=True, cwd=here, check=True
    )
    return float(result.stdout.strip()) / 2**20


def scaling(seconds: float, sizes, figures: Figures) -> None:
    print("== native focus env, scaling ==")
    print(f"{'N':>5} {'µs/env-step':>12} {'env-steps/s':>12} {'MiB per env':>12}")
    for n in sizes:
        env = make_vector("focus", n, "vector_entry_point")
        rate = vector_rate(env, seconds)
        env.close()
        memory_mib = memory_per_env(n)
        print(f"{n:5d} {1e6 / rate:12.1f} {rate:12.0f} {memory_mib:12.2f}")
        figures.add("scaling", "focus", {"env_step_us": 1e6 / rate, "memory_per_env_mib": memory_mib}, num_envs=n)


def pymunk_floor_us(envs, steps: int = 300) -> float:
    """µs per env-step of the fewest pymunk calls one step of each member's world makes:
    the robot's velocities and the space's step in each physics sub-step, each mover's
    velocity, and the robot's and movers' poses read back for the sensors."""
    worlds = [env.unwrapped.world for env in envs]
    dt_s = envs[0].unwrapped.dt
    substeps = worlds[0].substeps(dt_s)
    h = dt_s / substeps
    start = time.perf_counter()
    for _ in range(steps):
        for world in worlds:
            robot = world.robot.body
            for _ in range(substeps):
                _pymunk_access.set_velocity(robot, 0.1, 0.0)
                robot.angular_velocity = 0.05
                world.space.step(h)
            for mover in world.movers:
                _pymunk_access.set_velocity(mover.body, 0.1, 0.0)
            _pymunk_access.position(robot), robot.angle
            for mover in world.movers:
                _pymunk_access.position(mover.body), mover.body.angle
    return (time.perf_counter() - start) / (steps * len(worlds)) * 1e6


def floor_at_16(seconds: float, figures: Figures, steps: int = 400) -> None:
    """Section 4: the native ``focus`` env's floor at N = 16 against the targets' budgets."""
    env = make_vector("focus", 16, "vector_entry_point")
    whole_us = 1e6 / vector_rate(env, seconds)
    actions = np.random.default_rng(0).uniform(-1, 1, (32, *env.action_space.shape)).astype(env.action_space.dtype)
    with CallTimer(sensor_suite, "_read_many_kernel") as sensing, CallTimer(model_batch, "attend_many") as models:
        for k in range(steps):
            env.step(actions[k % len(actions)])
    env_steps = steps * env.num_envs
    sensing_us, models_us = sensing.seconds / env_steps * 1e6, models.seconds / env_steps * 1e6
    pymunk_us = pymunk_floor_us(env.envs)
    env.close()
    walker_us = 1e6 / steps_per_second(gym.make("BipedalWalker-v3"), seconds)
    sync = make_vector("focus", 16, "sync")
    sync_us = 1e6 / vector_rate(sync, seconds)
    sync.close()
    floor = sensing_us + models_us + pymunk_us
    print(f"== floor of the native focus env, N = 16, {env.unwrapped.threads} numba thread(s), µs per env-step ==")
    for name, value in (
        ("compiled sensor sweep", sensing_us),
        ("compiled attentional models", models_us),
        ("pymunk's fewest calls", pymunk_us),
        ("floor (their sum)", floor),
        ("the whole step", whole_us),
        ("budget of >= 3x BipedalWalker-v3", walker_us / 3),
        ("budget of >= 4x the sync vector env", sync_us / 4),
    ):
        print(f"{name:<38} {value:8.1f}")
    figures.add(
        "floor",
        "focus",
        {
            "sensor_sweep_us": sensing_us,
            "models_us": models_us,
            "pymunk_us": pymunk_us,
            "floor_us": floor,
            "whole_step_us": whole_us,
            "bipedal_walker_us": walker_us,
            "sync_us": sync_us,
        },
        num_envs=16,
    )
    print(
        f"left above the floor for everything else: {walker_us / 3 - floor:.1f} µs (3x BipedalWalker-v3), "
        f"{sync_us / 4 - floor:.1f} µs (4x sync); the step spends {whole_us - floor:.1f} µs there today"
    )


#: The benchmark's sections, in the order they run.
SECTIONS = ("peers", "vmas", "scaling", "floor")


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seconds", type=float, default=2.0, help="wall time per measurement (s)")
    parser.add_argument("--rounds", type=int, default=3, help="alternating rounds for the peer comparisons")
    parser.add_argument(
        "--max-envs", type=int, default=256, help="largest N of the VMAS comparison and the scaling table"
    )
    parser.add_argument(
        "--sections",
        default=",".join(SECTIONS),
        help=f"comma-separated sections to run, of {', '.join(SECTIONS)} (default: all)",
    )
    parser.add_argument("--csv", default=None, help="also write the figures as tidy rows into this CSV")
    args = parser.parse_args(argv)
    sections = args.sections.split(",")
    unknown = sorted(set(sections) - set(SECTIONS))
    if unknown:
        parser.error(f"unknown section(s) {', '.join(unknown)}; allowed: {', '.join(SECTIONS)}")
    sizes = [n for n in (1, 2, 4, 8, 16, 32, 64, 128, 256) if n <= args.max_envs]
    figures = Figures("vector")
    if "peers" in sections:
        peers_at_16(args.seconds, args.rounds, figures)
    if "vmas" in sections:
        against_vmas(args.seconds, args.rounds, [n for n in (16, 64, 256) if n <= args.max_envs], figures)
    if "scaling" in sections:
        scaling(args.seconds, sizes, figures)
    if "floor" in sections:
        floor_at_16(args.seconds, figures)
    if args.csv:
        figures.write(args.csv)


if __name__ == "__main__":
    main()
