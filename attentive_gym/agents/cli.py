"""``attentive-gym train``, ``evaluate`` and ``compare``: add-functions for ``attentive_gym.cli``.

Each ``add_*`` adds one subcommand to an argparse sub-parser collection; the handlers raise
``ValueError`` for invalid input, which ``attentive_gym.cli.main`` prints as one line on
stderr with exit status 2.
"""

from __future__ import annotations

import argparse
import json
import os
from pathlib import Path
from typing import Any

from attentive_gym.wrappers.variants import VARIANTS

__all__ = ["add_train", "add_evaluate", "add_compare", "parse_env_kwargs"]


def parse_env_kwargs(text: str | None) -> dict[str, Any]:
    """``--env-kwargs``: a JSON object (or the path of a .json file holding one) → dict."""
    if not text:
        return {}
    if not text.lstrip().startswith("{"):
        path = Path(text)
        if not path.is_file():
            raise ValueError(f"--env-kwargs must be a JSON object or a .json file, got {text!r}")
        text = path.read_text()
    try:
        value = json.loads(text)
    except json.JSONDecodeError as err:
        raise ValueError(f"--env-kwargs is not valid JSON: {err}") from None
    if not isinstance(value, dict):
        raise ValueError(f"--env-kwargs must be a JSON object, got {type(value).__name__}")
    return value


def _positive_int(text: str) -> int:
    try:
        value = int(text.replace("_", ""))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {text!r}")
    return value


def _non_negative_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer >= 0, got {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"expected an integer >= 0, got {text!r}")
    return value


def _add_run_options(parser: argparse.ArgumentParser, steps_default: int | None) -> None:
    parser.add_argument("--algo", choices=("ppo", "sac"), default="ppo", help="SB3 algorithm (default: ppo)")
    parser.add_argument("--steps", type=_positive_int, default=steps_default,
                        help=f"training budget in env steps per run (default: {steps_default})")
    parser.add_argument("--n-envs", type=_positive_int, default=4, help="vectorised training envs (default: 4)")
    parser.add_argument("--vec-env", choices=("dummy", "subproc"), default="dummy",
                        help="DummyVecEnv (one process, default) or SubprocVecEnv")
    parser.add_argument("--eval-every", type=_positive_int, help="env steps between evaluations (default: steps/10)")
    parser.add_argument("--eval-episodes", type=_positive_int, default=None, help="episodes per evaluation (default: 20)")
    parser.add_argument("--checkpoint-every", type=_positive_int, help="env steps between checkpoints (default: steps/5)")
    parser.add_argument("--env-kwargs", metavar="JSON",
                        help='make_env keyword arguments, e.g. \'{"arena_size_m": 8, "num_distractors": 2}\'')
    parser.add_argument("--algo-kwargs", metavar="JSON", help='SB3 keyword arguments, e.g. \'{"n_steps": 128}\'')


def _spec_from_args(args: argparse.Namespace, variant: str, seed: int, defaults: dict[str, Any] | None = None):
    from attentive_gym.agents.config import RunSpec

    defaults = defaults or {}
    steps = args.steps if args.steps is not None else defaults.get("total_steps", 100_000)
    algo_kwargs = parse_env_kwargs(args.algo_kwargs) if args.algo_kwargs else {}
    return RunSpec(
        variant=variant, algo=args.algo, total_steps=steps, seed=seed, n_envs=args.n_envs, vec_env=args.vec_env,
        eval_every=args.eval_every or defaults.get("eval_every", max(1, steps // 10)),
        eval_episodes=args.eval_episodes or defaults.get("eval_episodes", 20),
        checkpoint_every=args.checkpoint_every or defaults.get("checkpoint_every", max(1, steps // 5)),
        env_kwargs=parse_env_kwargs(args.env_kwargs) if args.env_kwargs else dict(defaults.get("env_kwargs", {})),
        algo_kwargs=algo_kwargs,
        torch_threads=getattr(args, "torch_threads", 1),
    )


# --- train ------------------------------------------------------------------------------
def add_train(subparsers) -> None:
    parser = subparsers.add_parser(
        "train", help="train an SB3 policy on one observation variant",
        description="Train PPO (or SAC) on one observation variant with periodic evaluation, TensorBoard logs and "
                    "checkpoints. Writes DIR/spec.json, eval.csv, checkpoint/, tb/, final_model.zip, metrics.json, "
                    "done. Rerunning into an unfinished DIR resumes from its checkpoint.",
    )
    parser.add_argument("--variant", default="focus", metavar="NAME", help=f"one of {', '.join(VARIANTS)} (default: focus)")
    parser.add_argument("--seed", type=_non_negative_int, default=0, help="seed (default: 0)")
    parser.add_argument("--out", type=Path, help="run folder (default: runs/train-<variant>-seed<seed>)")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    parser.add_argument("--torch-threads", type=_positive_int, default=1, help="torch threads (default: 1)")
    _add_run_options(parser, steps_default=100_000)
    parser.set_defaults(handler=_run_train)


def _run_train(args: argparse.Namespace) -> int:
    from attentive_gym.agents.training import train

    spec = _spec_from_args(args, args.variant, args.seed)
    out = args.out or Path("runs") / f"train-{spec.run_name}"
    metrics = train(spec, out, progress_bar=not args.no_progress)
    final = metrics.get("final") or {}
    print(f"{spec.run_name}: {metrics['env_steps']} env steps; final success rate {final.get('success_rate', float('nan')):.2f}, "
          f"return {final.get('mean_return', float('nan')):.2f}; wrote {out}")
    return 0


# --- evaluate ---------------------------------------------------------------------------
def add_evaluate(subparsers) -> None:
    parser = subparsers.add_parser(
        "evaluate", help="evaluate a trained model",
        description="Evaluate a model saved by 'train' (its run folder or a .zip in it) on fixed episode seeds: "
                    "success rate, mean return, collision steps and episode length. --video records MP4s "
                    "(gymnasium RecordVideo, needs moviepy).",
    )
    parser.add_argument("model", type=Path, help="run folder or .zip model")
    parser.add_argument("--episodes", type=_positive_int, default=20, help="episodes (default: 20)")
    parser.add_argument("--seed", type=_non_negative_int, default=None, help="first episode seed (default: the run's eval seed)")
    parser.add_argument("--video", type=Path, metavar="DIR", help="also record --video-episodes episodes into DIR")
    parser.add_argument("--video-episodes", type=_positive_int, default=1, help="episodes to record (default: 1)")
    parser.add_argument("--json", action="store_true", help="print the result as JSON")
    parser.set_defaults(handler=_run_evaluate)


def _run_evaluate(args: argparse.Namespace) -> int:
    from attentive_gym.agents.evaluation import evaluate_policy, record_videos
    from attentive_gym.agents.training import env_factory, eval_seed, load_model

    model, spec = load_model(args.model)
    seed = eval_seed(spec) if args.seed is None else args.seed
    result = evaluate_policy(model, env_factory(spec), args.episodes, seed)
    row = {"variant": spec.variant, "model": str(args.model), "seed": seed, **result.row()}
    if args.json:
        print(json.dumps(row))
    else:
        print(f"{spec.variant}: {result.n_episodes} episodes, success rate {result.success_rate:.2f}, "
              f"return {result.mean_return:.2f} ± {result.std_return:.2f}, collision steps {result.mean_collision_steps:.1f}, "
              f"length {result.mean_episode_length:.0f} steps")
    if args.video:
        for path in record_videos(model, lambda **kw: env_factory(spec, **kw)(), args.video, args.video_episodes, seed):
            print(f"wrote {path}")
    return 0


# --- compare ----------------------------------------------------------------------------
def add_compare(subparsers) -> None:
    parser = subparsers.add_parser(
        "compare", help="train every (variant, seed) pair and compare learning curves",
        description="Train every (variant, seed) pair in parallel, then write DIR/results.csv (one row per variant, "
                    "seed and eval point), DIR/learning_curves.png (mean and 95%% CI across seeds) and "
                    "DIR/summary.md + summary.csv (final success rate and return with 95%% CIs, env steps to the "
                    "success threshold). A rerun into DIR trains only the unfinished runs.",
    )
    parser.add_argument("--variants", default=None, metavar="LIST", help="comma list (default: raw,raw-stack,focus)")
    parser.add_argument("--seeds", default=None, metavar="N|LIST", help="a count (5 = seeds 0..4) or a comma list (default: 5)")
    parser.add_argument("--out", type=Path, default=None, help="output folder (default: runs/compare, or runs/compare-quick)")
    parser.add_argument("--backend", choices=("process", "ray"), default="process", help="process pool (default) or ray")
    parser.add_argument("--workers", type=_positive_int, default=os.cpu_count() or 1, help="runs in parallel (default: CPU count)")
    parser.add_argument("--threshold", type=float, default=0.5, help="success rate for 'steps to threshold' (default: 0.5)")
    parser.add_argument("--quick", action="store_true",
                        help="a ~6-minute budget on 2 cores: raw,raw-stack,focus × 3 seeds × 150k steps in an "
                             "8 m arena (explicit options still win)")
    _add_run_options(parser, steps_default=None)
    parser.set_defaults(handler=_run_compare)


def _run_compare(args: argparse.Namespace) -> int:
    from attentive_gym.agents.compare import QUICK, compare
    from attentive_gym.agents.config import parse_seeds, parse_variants

    defaults = dict(QUICK) if args.quick else {}  # _spec_from_args holds the plain defaults
    variants = parse_variants(args.variants) if args.variants else tuple(defaults.get("variants", ("raw", "raw-stack", "focus")))
    seeds = parse_seeds(args.seeds) if args.seeds else tuple(defaults.get("seeds", range(5)))
    if not 0.0 <= args.threshold <= 1.0:
        raise ValueError(f"--threshold must be a success rate in [0, 1], got {args.threshold}")
    base = _spec_from_args(args, variants[0], seeds[0], defaults)
    out = args.out or Path("runs") / ("compare-quick" if args.quick else "compare")
    print(f"compare: {len(variants)} variants × {len(seeds)} seeds × {base.total_steps} env steps "
          f"({args.backend}, {args.workers} workers) → {out}", flush=True)
    result = compare(variants, seeds, base, out, backend=args.backend, workers=args.workers, threshold=args.threshold,
                     log=lambda line: print(line, flush=True))
    if result.summary_md is not None:
        print(result.summary_md.read_text(), end="")
        print(f"wrote {result.results_csv}, {result.figure}, {result.summary_csv}, {result.summary_md}")
    if result.failed:
        print(f"{len(result.failed)} run(s) failed: {', '.join(result.failed)}; rerun the same command to retry them")
        return 1
    return 0
