"""PPO training speed on the attended environment against PPO on a trivial environment.

Both runs use the same PPO set-up as ``attentive-gym train`` (``RunSpec`` defaults:
``MultiInputPolicy``, 32 environments, 64-step rollouts, minibatch 512, 5 epochs, one
torch thread) and the same observation/action spaces; they differ only in the environment:

- ``focus``: ``make_env("focus")``, the attended observation (64 numbers in a ``Dict``),
  in the native ``NativeVecEnv`` (``--vec-env dummy``: SB3's ``DummyVecEnv``);
- ``trivial``: a ``gym.Env`` with the same spaces that returns pre-drawn random
  observations (800-step episodes, reward 0): what PPO alone costs.

A third run trains ``focus`` with the earlier defaults (``RunSpec(algo_defaults=2)``: 4
environments, 256-step rollouts, minibatch 256), so the speed-up of today's defaults is
measured in the same rounds.

Prints env-steps per second of each (median over alternating rounds), the fraction of
``focus`` training time spent inside the environment (measured with a timing wrapper
around the vector env's ``step_wait``/``reset``, and estimated as ``1 − t_trivial / t_focus``; target
≤ 25 %), today's defaults over the earlier ones (target ≥ 2), and a JSON line with all
figures. Times are this process's **CPU time**
(``time.process_time``; torch runs one thread), so other jobs on a busy machine do not
distort the comparison; ``--clock wall`` uses wall time instead.

Usage: ``python benchmarks/bench_training.py [--steps 20480] [--rounds 2] [--variant focus] [--vec-env native]
[--csv PATH]``; ``--csv`` also writes the figures as tidy rows into ``PATH`` (``tidy_csv``).
"""

from __future__ import annotations

import argparse
import json
import statistics
import time

import gymnasium as gym

from tidy_csv import Figures


class TrivialEnv(gym.Env):
    """Same spaces as ``like``; observations drawn up front from its space; 800-step episodes."""

    def __init__(self, like: gym.Env, episode_steps: int = 800, pool: int = 256, seed: int = 0):
        self.observation_space = like.observation_space
        self.action_space = like.action_space
        self.observation_space.seed(seed)
        self._pool = [self.observation_space.sample() for _ in range(pool)]
        self._episode_steps = episode_steps
        self._t = 0

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self._t = 0
        return self._pool[0], {}

    def step(self, action):
        self._t += 1
        return self._pool[self._t % len(self._pool)], 0.0, False, self._t >= self._episode_steps, {}


CLOCKS = {"cpu": time.process_time, "wall": time.perf_counter}
#: The ``RunSpec.algo_defaults`` version that today's PPO defaults are timed against.
EARLIER_DEFAULTS = 2


def rollout(spec) -> str:
    """``spec``'s PPO rollout in words: ``"32 envs × 64 steps, minibatch 512"``."""
    hyper = spec.hyper_parameters()
    return f"{spec.n_envs} envs × {hyper['n_steps']} steps, minibatch {hyper['batch_size']}"


def timed(vec, total: list[float], clock=time.process_time):
    """``vec`` (an SB3 ``VecEnv``) adding the time of every ``reset`` and ``step_wait`` (s, by
    ``clock``) to the one-element list ``total``."""
    from stable_baselines3.common.vec_env import VecEnvWrapper

    class VecTimer(VecEnvWrapper):
        def reset(self):
            t0 = clock()
            out = self.venv.reset()
            total[0] += clock() - t0
            return out

        def step_wait(self):
            t0 = clock()
            out = self.venv.step_wait()
            total[0] += clock() - t0
            return out

    return VecTimer(vec)


def train_rate(
    make_one, steps: int, vec_env: str, seed: int = 0, clock=time.process_time, algo_defaults: int | None = None
) -> tuple[float, float]:
    """(env-steps/s of PPO.learn, fraction of that time inside the environments), with the
    ``RunSpec`` defaults (those of version ``algo_defaults``; None: today's) and ``vec_env`` =
    ``"native"`` or ``"dummy"``."""
    import numba
    import torch
    from stable_baselines3 import PPO
    from stable_baselines3.common.vec_env import DummyVecEnv

    from attentive_gym.agents.config import RunSpec
    from attentive_gym.vector.sb3 import NativeVecEnv

    spec = RunSpec() if algo_defaults is None else RunSpec(algo_defaults=algo_defaults)
    torch.set_num_threads(spec.torch_threads)
    numba.set_num_threads(spec.torch_threads)  # as train does
    env_time = [0.0]
    members = [make_one() for _ in range(spec.n_envs)]
    vec = timed(
        NativeVecEnv(members) if vec_env == "native" else DummyVecEnv([lambda env=env: env for env in members]),
        env_time,
        clock,
    )
    model = PPO("MultiInputPolicy", vec, seed=seed, device="cpu", **spec.merged_algo_kwargs())
    model.learn(spec.n_envs * spec.merged_algo_kwargs()["n_steps"])  # warm-up: numba, torch
    env_time[0] = 0.0
    t0 = clock()
    model.learn(steps, reset_num_timesteps=False)
    elapsed = clock() - t0
    vec.close()
    return steps / elapsed, env_time[0] / elapsed


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=20480, help="env steps per timed PPO.learn (default: 20480)")
    parser.add_argument("--rounds", type=int, default=2, help="alternating rounds (default: 2)")
    parser.add_argument("--variant", default="focus", help="observation variant (default: focus)")
    parser.add_argument("--clock", choices=sorted(CLOCKS), default="cpu", help="cpu (process time, default) or wall")
    parser.add_argument(
        "--vec-env",
        choices=("native", "dummy"),
        default="native",
        help="the attended env's vectorisation (default: native, as train uses)",
    )
    parser.add_argument("--csv", default=None, help="also write the figures as tidy rows into this CSV")
    args = parser.parse_args(argv)

    from attentive_gym.agents.config import RunSpec
    from attentive_gym.wrappers import make_env

    probe = make_env(args.variant)
    earlier = f"{args.variant}, earlier defaults"
    # name: (env maker, vectorisation, algo_defaults); the trivial env is no rescue env: SB3's DummyVecEnv
    runs = {
        args.variant: (lambda: make_env(args.variant), args.vec_env, None),
        "trivial": (lambda: TrivialEnv(probe), "dummy", None),
        earlier: (lambda: make_env(args.variant), args.vec_env, EARLIER_DEFAULTS),
    }
    rates: dict[str, list[float]] = {name: [] for name in runs}
    fractions: dict[str, list[float]] = {name: [] for name in runs}
    for _ in range(args.rounds):
        for name, (make_one, vec_env, algo_defaults) in runs.items():
            clock = CLOCKS[args.clock]
            rate, fraction = train_rate(make_one, args.steps, vec_env, clock=clock, algo_defaults=algo_defaults)
            rates[name].append(rate)
            fractions[name].append(fraction)
    med = {name: statistics.median(values) for name, values in rates.items()}
    frac = {name: statistics.median(values) for name, values in fractions.items()}
    estimate = 1.0 - med["trivial"] ** -1 / med[args.variant] ** -1
    today, before = RunSpec(), RunSpec(algo_defaults=EARLIER_DEFAULTS)
    print(f"== PPO env-steps per {args.clock} second, {args.steps} steps × {args.rounds} rounds (medians) ==")
    print(f"{'run':<28} {'steps/s':>9} {'µs/step':>9} {'time in env':>12}")
    for name in runs:
        print(f"{name:<28} {med[name]:9.0f} {1e6 / med[name]:9.1f} {100 * frac[name]:11.1f}%")
    print(
        f"{args.variant} trains at {med[args.variant] / med['trivial']:.2f}x the trivial env's speed; "
        f"time in env: {100 * frac[args.variant]:.1f}% measured, {100 * estimate:.1f}% from the speed ratio "
        f"(target <= 25%)"
    )
    print(
        f"today's defaults ({rollout(today)}) train {args.variant} at {med[args.variant] / med[earlier]:.2f}x "
        f"the earlier defaults' speed ({rollout(before)}; target >= 2)"
    )
    print(
        json.dumps(
            {
                "variant": args.variant,
                "vec_env": args.vec_env,
                "clock": args.clock,
                "steps": args.steps,
                "rounds": args.rounds,
                "steps_per_s": med,
                "env_fraction": frac,
                "env_fraction_from_ratio": estimate,
                "over_earlier_defaults": med[args.variant] / med[earlier],
                "rates": rates,
            }
        )
    )
    if args.csv:
        figures = Figures("training")
        for name in (args.variant, "trivial"):
            subject = f"{name} ({args.vec_env})" if name == args.variant else name
            figures.add(
                "ppo",
                subject,
                {f"{args.clock}_steps_per_s": med[name], "env_fraction": frac[name], "n_envs": today.n_envs},
            )
        figures.add(
            "earlier defaults",
            f"{args.variant} ({args.vec_env})",
            {f"{args.clock}_steps_per_s": med[earlier], "n_envs": before.n_envs},
        )
        figures.write(args.csv)


if __name__ == "__main__":
    main()
