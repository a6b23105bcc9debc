"""``attentive-gym train``, ``evaluate``, ``compare`` and ``generalise``: add-functions for ``attentive_gym.cli``.

Each ``add_*`` adds one subcommand to an argparse sub-parser collection; the handlers raise
``ValueError`` for invalid input, which ``attentive_gym.cli.main`` prints as one line on
stderr with exit status 2, and ``stopping.Interrupted`` on Ctrl-C or SIGTERM (one line
saying what is kept and how to resume; exit status 130 or 143).
"""

from __future__ import annotations

import argparse
import json
import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

from attentive_gym._optional import require
from attentive_gym.agents.backends import BACKENDS
from attentive_gym.agents.config import (
    ALGO_DEFAULTS,
    ALGOS,
    DEFAULT_WARM_START,
    N_ENVS,
    OBS_SCALINGS,
    PPO_N_ENVS,
    QUICK,
    SCHEDULE_KEYS,
    STEPS_PER_EVAL_EPISODE,
    VEC_ENVS,
    WARM_START_MIN_STEPS,
    RunSpec,
    default_eval_episodes,
)
from attentive_gym.agents.pretrained import PRETRAINED, pretrained_record, pretrained_run
from attentive_gym.agents.stopping import Interrupted, raise_on_stop_signals
from attentive_gym.agents.warm_start import DEMO_STEPS, WARM_STARTS
from attentive_gym.attention.config import MODEL_VERSIONS
from attentive_gym.envs.reward import SAFE_CONTACT_S
from attentive_gym.envs.tasks import TASK_VERSIONS
from attentive_gym.wrappers.variants import VARIANTS

__all__ = ["add_train", "add_evaluate", "add_compare", "add_generalise", "parse_json_object"]


def parse_json_object(text: str | None, flag: str) -> dict[str, Any]:
    """``flag``'s value (``--env-kwargs`` or ``--algo-kwargs``): a JSON object, or the path of a
    .json file holding one → dict. None (the flag not given) → {}; an empty value, invalid
    JSON, NaN or Infinity, or anything but an object raises ``ValueError`` naming ``flag``."""
    if text is None:
        return {}
    if not text.strip():
        raise ValueError(f"{flag} is empty; give a JSON object such as '{{}}' or leave the flag out")
    if not text.lstrip().startswith("{"):
        path = Path(text)
        if not path.is_file():
            raise ValueError(f"{flag} must be a JSON object or a .json file, got {text!r}")
        text = path.read_text()
    try:
        value = json.loads(text, parse_constant=_reject_constant)
    except json.JSONDecodeError as err:
        raise ValueError(f"{flag} is not valid JSON: {err}") from None
    except _NonFiniteJSON as err:
        raise ValueError(f"{flag} holds {err}, which is not a finite number; numbers must be finite") from None
    if not isinstance(value, dict):
        raise ValueError(f"{flag} must be a JSON object, got {type(value).__name__}")
    return value


class _NonFiniteJSON(ValueError):
    """JSON's NaN, Infinity or -Infinity, which Python's ``json`` would otherwise accept."""


def _reject_constant(name: str):
    raise _NonFiniteJSON(name)


def _int_at_least(low: int) -> Callable[[str], int]:
    """An argparse ``type``: the text as an integer >= ``low`` (``100_000`` allowed), else a usage error."""

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            value = None
        if value is None or value < low:
            raise argparse.ArgumentTypeError(f"expected an integer >= {low}, got {text!r}")
        return value

    return parse


_positive_int = _int_at_least(1)
_non_negative_int = _int_at_least(0)

#: ``compare --quick``'s seeds, as the ``--seeds`` count they equal.
_QUICK_SEEDS = len(QUICK["seeds"])
#: ``compare``'s variants and seeds without ``--quick``.
_COMPARE_VARIANTS = ("raw", "focus", "oracle", "random-focus")
_COMPARE_SEEDS = 5


#: ``--extend``'s help; ``what`` names the existing runs.
_EXTEND_HELP = (
    "train {what}, trained with a smaller --steps and otherwise the same options, on to --steps from "
    "its latest checkpoint (its evaluations so far are kept; the final model is replaced; without "
    "--eval-every, --eval-episodes and --checkpoint-every it keeps their values from the existing runs)"
)


def _with_quick(text: str, key: str, quick: bool) -> str:
    """``"(default: <text>)"``, plus ``QUICK[key]`` (as JSON) with ``--quick`` where the command has that option."""
    return f"(default: {text}; {json.dumps(QUICK[key])} with --quick)" if quick else f"(default: {text})"


def _add_run_options(parser: argparse.ArgumentParser, quick: bool) -> None:
    """Options shared by ``train`` and ``compare``; ``quick``: the command has ``--quick`` (help shows its budget)."""
    parser.add_argument(
        "--algo",
        choices=ALGOS,
        default=RunSpec.algo,
        help=f"SB3 algorithm; recurrent-ppo is sb3-contrib's RecurrentPPO with an LSTM policy "
        f"(default: {RunSpec.algo})",
    )
    steps = _with_quick(str(RunSpec.total_steps), "total_steps", quick)
    parser.add_argument(
        "--steps", type=_positive_int, default=None, help=f"training budget in env steps per run {steps}"
    )
    parser.add_argument(
        "--n-envs",
        type=_positive_int,
        default=None,
        help=f"vectorised training envs (default: {PPO_N_ENVS} with ppo, {N_ENVS} with recurrent-ppo and sac)",
    )
    parser.add_argument(
        "--vec-env",
        "--vec",
        choices=VEC_ENVS,
        default=RunSpec.vec_env,
        help="native (one process, all sensors in one call), dummy (SB3 DummyVecEnv) or subproc "
        f"(SB3 SubprocVecEnv, one process per env); same numbers (default: {RunSpec.vec_env})",
    )
    parser.add_argument(
        "--obs-scaling",
        choices=OBS_SCALINGS,
        default=RunSpec.obs_scaling,
        help="running: the policy sees every observation entry normalised by running mean and "
        "standard deviation (SB3 VecNormalize; saved with the model, frozen in evaluation); "
        f"none: in its own units (metres, seconds, flags) (default: {RunSpec.obs_scaling})",
    )
    parser.add_argument(
        "--warm-start",
        choices=[*WARM_STARTS, "none"],
        default=None,
        help=f"ppo only: clone a scripted teacher's demonstrations ({DEMO_STEPS:,} env steps, counted in --steps) "
        "before training; clearance: the reactive avoider on the working memory's first row and the proximity "
        "entry (a focus-layout variant with its proximity entry); privileged: the same avoider steering for the "
        "target's true bearing, read from the world's truth during the demonstrations only; none: no warm start "
        "(default: privileged where it can read the observation, in a budget of at least "
        f"{WARM_START_MIN_STEPS:,} steps: raw, saliency, and the focus layout with its proximity entry, goal-action "
        "with the task's goal; none for the others and for other algorithms; a trained folder keeps its own)",
    )
    parser.add_argument(
        "--task",
        type=int,
        choices=TASK_VERSIONS,
        help="the task's version (envs.tasks): 1, safe rescue, an episode ends after 1 s of contact and the focus "
        "layout senses each region's nearest reading; 0, the first task, contact only costs (default: the latest, "
        f"{TASK_VERSIONS[-1]}; a trained folder keeps its own)",
    )
    parser.add_argument(
        "--model",
        type=int,
        choices=MODEL_VERSIONS,
        help="the version of the attentional model's defaults (attention.MODEL_VERSIONS) that the attended "
        "variants run: 3, with the start test; 2, with the occlusion rule; 1, with free-space evidence and the start "
        "and edge rules; 0, "
        f"the first tracker (default: the latest, {MODEL_VERSIONS[-1]}; a trained folder keeps its own)",
    )
    parser.add_argument(
        "--eval-every",
        type=_positive_int,
        help=f"env steps between evaluations {_with_quick('steps/10', 'eval_every', quick)}",
    )
    episodes = _with_quick(
        f"steps/{STEPS_PER_EVAL_EPISODE}, at least 1, at most {RunSpec.eval_episodes}", "eval_episodes", quick
    )
    parser.add_argument("--eval-episodes", type=_positive_int, help=f"episodes per evaluation {episodes}")
    parser.add_argument(
        "--checkpoint-every",
        type=_positive_int,
        help=f"env steps between checkpoints {_with_quick('steps/5', 'checkpoint_every', quick)}",
    )
    parser.add_argument(
        "--env-kwargs",
        metavar="JSON",
        help='make_env keyword arguments, e.g. \'{"arena_size_m": 8, "num_distractors": 2}\' '
        f"{_with_quick('none', 'env_kwargs', quick)}",
    )
    parser.add_argument(
        "--algo-kwargs",
        metavar="JSON",
        help="SB3 keyword arguments over the run's defaults, e.g. '{\"n_steps\": 128}'; "
        f'{", ".join(SCHEDULE_KEYS)} also take "lin_<number>", a linear decay to 0 over the '
        "budget (defaults: "
        f"ppo {json.dumps(RunSpec().default_algo_kwargs())}, "
        f"recurrent-ppo {json.dumps(RunSpec(algo='recurrent-ppo').default_algo_kwargs())}, "
        f"sac {json.dumps(RunSpec(algo='sac').default_algo_kwargs())})",
    )


def _spec_from_args(
    args: argparse.Namespace,
    variant: str,
    seed: int,
    defaults: dict[str, Any] | None = None,
    stored: dict[str, Any] | None = None,
) -> RunSpec:
    """The ``RunSpec`` of the parsed options; ``defaults`` (``QUICK``) fill what was not given.

    Without ``defaults``, the evaluation and checkpoint settings follow ``--steps``: an
    evaluation every steps/10 env steps of ``default_eval_episodes(steps)`` episodes, a
    checkpoint every steps/5.

    ``stored``: the settings of the trained run (or comparison) in the output folder. When
    ``--steps`` asks for at least what it has, their evaluation and checkpoint settings stand
    in for the defaults that depend on ``--steps``: resuming a run needs none of those flags,
    and extending it only ``--extend`` and the new ``--steps``. Their
    ``algo_defaults`` (1 where they have none) always stand, and ``env_version`` and
    ``task_version`` (0 where they have none) and ``warm_start`` unless ``--model``, ``--task``
    or ``--warm-start`` is given: a folder keeps the default hyper-parameters, model, task and
    start it was trained with (a flag that differs is refused as a change of settings).
    """
    defaults = dict(defaults or {})
    steps = args.steps if args.steps is not None else defaults.get("total_steps", RunSpec.total_steps)
    if stored is not None and steps >= stored.get("total_steps", steps):
        defaults.update(
            {key: stored[key] for key in ("eval_every", "eval_episodes", "checkpoint_every") if key in stored}
        )
    return RunSpec(
        variant=variant,
        algo=args.algo,
        total_steps=steps,
        seed=seed,
        n_envs=args.n_envs,
        vec_env=args.vec_env,
        eval_every=args.eval_every or defaults.get("eval_every", max(1, steps // 10)),
        eval_episodes=args.eval_episodes or defaults.get("eval_episodes", default_eval_episodes(steps)),
        checkpoint_every=args.checkpoint_every or defaults.get("checkpoint_every", max(1, steps // 5)),
        env_kwargs=(
            parse_json_object(args.env_kwargs, "--env-kwargs")
            if args.env_kwargs is not None
            else dict(defaults.get("env_kwargs", {}))
        ),
        algo_kwargs=parse_json_object(args.algo_kwargs, "--algo-kwargs"),
        torch_threads=getattr(args, "torch_threads", RunSpec.torch_threads),
        obs_scaling=args.obs_scaling,
        warm_start=_warm_start(getattr(args, "warm_start", None), stored),
        algo_defaults=ALGO_DEFAULTS[-1] if stored is None else stored.get("algo_defaults", 1),
        env_version=_version(getattr(args, "model", None), stored, "env_version", MODEL_VERSIONS),
        task_version=_version(getattr(args, "task", None), stored, "task_version", TASK_VERSIONS),
    )


def _version(option: int | None, stored: dict[str, Any] | None, key: str, versions: tuple[int, ...]) -> int:
    """A ``RunSpec`` version field ``key`` (``env_version`` from ``--model``, ``task_version``
    from ``--task``): the version given; when not given, the trained folder's own (0 where it
    has none), else the latest of ``versions``."""
    if option is not None:
        return option
    return versions[-1] if stored is None else stored.get(key, 0)


def _warm_start(option: str | None, stored: dict[str, Any] | None) -> str | None:
    """``RunSpec.warm_start`` from ``--warm-start``: the teacher named, None for ``none``; when
    not given, the trained folder's own (None where it has none), else the run's default."""
    if option is not None:
        return None if option == "none" else option
    return DEFAULT_WARM_START if stored is None else stored.get("warm_start")


def _trained_settings(path: Path, trained: bool, *keys: str) -> dict[str, Any] | None:
    """The JSON object at ``path`` (``spec.json`` or ``compare.json``), descended into by
    ``keys``, when ``trained`` (its runs hold a checkpoint or are done); None otherwise or
    when the file is absent or unreadable (the binding step reports those)."""
    if not trained:
        return None
    try:
        value = json.loads(path.read_text())
        for key in keys:
            value = value[key]
    except (OSError, ValueError, KeyError, TypeError):
        return None
    return value if isinstance(value, dict) else None


# --- train ------------------------------------------------------------------------------
def add_train(subparsers) -> None:
    parser = subparsers.add_parser(
        "train",
        help="train an SB3 policy on one observation variant",
        description="Train PPO (or SAC, or RecurrentPPO) on one observation variant with periodic evaluation, "
        "TensorBoard logs and checkpoints. Writes DIR/spec.json, eval.csv (goal-action: and goal_choice.csv), "
        "checkpoint/, tb/, final_model.zip, metrics.json, done. The spec is checked (one env built, the SB3 keywords "
        "checked) before anything is written. Rerunning into an unfinished DIR, after Ctrl-C or a "
        "kill, resumes from its checkpoint; with --extend and a larger --steps, a finished run trains "
        "on from its final checkpoint.",
    )
    parser.add_argument(
        "--variant", default="focus", metavar="NAME", help=f"one of {', '.join(VARIANTS)} (default: focus)"
    )
    parser.add_argument("--seed", type=_non_negative_int, default=0, help="seed (default: 0)")
    parser.add_argument("--out", type=Path, help="run folder (default: runs/train-<variant>-seed<seed>)")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    parser.add_argument("--extend", action="store_true", help=_EXTEND_HELP.format(what="the run in --out"))
    parser.add_argument(
        "--torch-threads",
        type=_positive_int,
        default=RunSpec.torch_threads,
        help=f"threads of torch and of the sensor sweep (default: {RunSpec.torch_threads})",
    )
    _add_run_options(parser, quick=False)
    parser.set_defaults(handler=_run_train)


def _require_agents_extra(command: str) -> None:
    """Raise ``MissingExtraError`` naming the ``agents`` extra, before any work, when torch or
    stable-baselines3 is not installed."""
    for module in ("torch", "stable_baselines3"):
        require(module, f"attentive-gym {command}")


def _run_train(args: argparse.Namespace) -> int:
    _require_agents_extra("train")
    from attentive_gym.agents.training import holds_progress, train

    out = args.out or Path("runs") / f"train-{RunSpec(variant=args.variant, seed=args.seed).run_name}"
    spec = _spec_from_args(
        args, args.variant, args.seed, stored=_trained_settings(out / "spec.json", holds_progress(out))
    )
    print(
        f"{spec.run_name}: {spec.total_steps} env steps, evaluated on {_count(spec.eval_episodes, 'episode')} at 0 "
        f"env steps, every {spec.eval_every} and at the end (--eval-episodes, --eval-every)",
        flush=True,
    )
    try:
        with raise_on_stop_signals():
            metrics = train(spec, out, progress_bar=not args.no_progress, extend=args.extend)
    except Interrupted as stop:
        raise Interrupted(stop.signum, _train_resume_hint(out, spec)) from None
    final = metrics.get("final") or {}
    print(
        f"{spec.run_name}: {metrics['env_steps']} env steps; "
        f"final success rate {final.get('success_rate', float('nan')):.2f}, "
        f"safe success rate {final.get('safe_success_rate', float('nan')):.2f} (≤ {SAFE_CONTACT_S:g} s in contact), "
        f"contact {final.get('mean_contact_s', float('nan')):.1f} s / episode, "
        f"return {final.get('mean_return', float('nan')):.2f}; wrote {out}"
    )
    return 0


def _train_resume_hint(out: Path, spec: RunSpec) -> str:
    """What an interrupted ``train`` keeps, and how to resume it."""
    from attentive_gym.agents.training import checkpoint_steps

    steps = checkpoint_steps(out)
    if steps is None:
        return (
            f"no checkpoint yet in {out} (one every {spec.checkpoint_every} env steps); "
            "rerun the same command to start again"
        )
    return f"the checkpoint at {steps} env steps is kept in {out}; rerun the same command to resume from it"


# --- evaluate ---------------------------------------------------------------------------
def add_evaluate(subparsers) -> None:
    parser = subparsers.add_parser(
        "evaluate",
        help="evaluate a trained model",
        description="Evaluate a model saved by 'train' (its run folder or a .zip in it) on fixed episode seeds: "
        f"success rate, safe success rate (success with at most {SAFE_CONTACT_S:g} s in contact), mean return, "
        "contact time (s), collision steps and episode length. --video records MP4s "
        "(gymnasium RecordVideo, needs moviepy).",
    )
    parser.add_argument("model", type=Path, nargs="?", help="run folder or .zip model (or --pretrained)")
    parser.add_argument(
        "--pretrained",
        choices=PRETRAINED,
        help="evaluate the small policy shipped with the package for this variant instead of a run's",
    )
    parser.add_argument("--episodes", type=_positive_int, default=20, help="episodes (default: 20)")
    parser.add_argument(
        "--seed", type=_non_negative_int, default=None, help="first episode seed (default: the run's eval seed)"
    )
    parser.add_argument("--video", type=Path, metavar="DIR", help="also record --video-episodes episodes into DIR")
    parser.add_argument("--video-episodes", type=_positive_int, default=1, help="episodes to record (default: 1)")
    parser.add_argument("--json", action="store_true", help="print the result as JSON")
    parser.set_defaults(handler=_run_evaluate)


def _run_evaluate(args: argparse.Namespace) -> int:
    if (args.model is None) == (args.pretrained is None):
        raise ValueError("give a run folder or .zip model, or --pretrained VARIANT (one of them)")
    _require_agents_extra("evaluate")
    from attentive_gym.agents.evaluation import check_video_dir, evaluate_policy, record_videos
    from attentive_gym.agents.training import env_factory, eval_seed, load_policy

    if args.video:
        require("moviepy", "--video (gymnasium's RecordVideo writes MP4 with it)")
        check_video_dir(args.video)
    if args.pretrained is not None:
        args.model = pretrained_run(args.pretrained)
        record = pretrained_record(args.pretrained)
        low, high = record["success_ci"]
        steps, episodes = record["trained"]["total_steps"], record["episodes"]
        print(
            f"the pretrained {args.pretrained} policy ({record['env_id']}, {steps:,} steps): "
            f"success {record['success_rate']:.2f} [{low:.2f}, {high:.2f}] on {episodes} episodes when shipped"
        )
    model, spec = load_policy(args.model)
    seed = eval_seed(spec) if args.seed is None else args.seed
    result = evaluate_policy(model, env_factory(spec), args.episodes, seed)
    row = {"variant": spec.variant, "model": str(args.model), "seed": seed, **result.row()}
    if args.json:
        print(json.dumps(row))
    else:
        print(
            f"{spec.variant}: {result.n_episodes} episodes, success rate {result.success_rate:.2f}, "
            f"safe success rate {result.safe_success_rate:.2f} (≤ {SAFE_CONTACT_S:g} s in contact), "
            f"return {result.mean_return:.2f} ± {result.std_return:.2f}, "
            f"contact {result.mean_contact_s:.1f} s / episode, "
            f"collision steps {result.mean_collision_steps:.1f}, "
            f"length {result.mean_episode_length:.0f} steps"
        )
    if args.video:
        for path in record_videos(model, lambda **kw: env_factory(spec, **kw)(), args.video, args.video_episodes, seed):
            print(f"wrote {path}")
    return 0


# --- generalise -------------------------------------------------------------------------
def add_generalise(subparsers) -> None:
    from attentive_gym.agents.generalisation import CSV_NAME, SHIFTS

    parser = subparsers.add_parser(
        "generalise",
        help="evaluate a comparison's policies on settings they were not trained on",
        description="Evaluate the final policy of every finished run of a comparison (its --out folder) on its "
        "own evaluation episodes under each shift of its environment, one at a time: "
        f"{', '.join(repr(name) for name in SHIFTS)}. Writes DIR/{CSV_NAME} (one row per run and shift, "
        "written as each finishes: Ctrl-C keeps the finished rows and a rerun evaluates only the missing ones), "
        "DIR/generalisation_summary.csv (per shift and variant: success, safe success and contact time, mean "
        "over seeds with 95 % bootstrap CIs) and DIR/generalisation.png.",
    )
    parser.add_argument("comparison", type=Path, help="the --out folder of 'attentive-gym compare'")
    parser.add_argument("--shifts", metavar="LIST", help="comma list of shifts (default: all of them)")
    parser.add_argument("--episodes", type=_positive_int, default=20, help="episodes per run and shift (default: 20)")
    parser.add_argument(
        "--workers",
        type=_positive_int,
        default=os.cpu_count() or 1,
        help=f"evaluations in parallel (default: the CPU count, {os.cpu_count() or 1} here)",
    )
    parser.set_defaults(handler=_run_generalise)


def _run_generalise(args: argparse.Namespace) -> int:
    _require_agents_extra("generalise")
    from attentive_gym.agents.generalisation import SUMMARY_COLUMNS, generalise, parse_shifts, summarise_shifts
    from attentive_gym.agents.plots import plot_generalisation
    from attentive_gym.agents.results import write_csv_atomic

    shifts = parse_shifts(args.shifts)
    try:
        rows = generalise(args.comparison, shifts, args.episodes, args.workers)
    except Interrupted as stop:
        kept = args.comparison / "generalisation.csv"
        raise Interrupted(stop.signum, f"the finished rows are in {kept}; rerun to evaluate the rest") from None
    summary = summarise_shifts(rows)
    write_csv_atomic(args.comparison / "generalisation_summary.csv", summary, SUMMARY_COLUMNS)
    figure = plot_generalisation(summary, args.comparison / "generalisation.png")
    for row in summary:
        print(
            f"{row['shift']:>16} {row['variant']:<13} success {row['success_mean']:.2f} "
            f"[{row['success_ci_low']:.2f}, {row['success_ci_high']:.2f}], safe {row['safe_success_mean']:.2f} "
            f"[{row['safe_success_ci_low']:.2f}, {row['safe_success_ci_high']:.2f}] ({row['n_seeds']} seeds)"
        )
    print(f"wrote {args.comparison / 'generalisation_summary.csv'} and {figure}")
    return 0


# --- compare ----------------------------------------------------------------------------
def add_compare(subparsers) -> None:
    parser = subparsers.add_parser(
        "compare",
        help="train every (variant, seed) pair and compare learning curves",
        description="Train every (variant, seed) pair in parallel, then write DIR/results.csv (one row per variant, "
        "seed and eval point), DIR/learning_curves.png (mean and 95 % CI across seeds), "
        "DIR/performance_profiles.png (the share of runs above each final success and safe success) and "
        "DIR/summary.md + summary.csv (final success rate, safe success rate, contact time and return with "
        "95 % CIs, env steps to the success threshold) and, with the goal-action variant, DIR/goal_choice.csv + "
        "goal_choice.png (its chosen goal against the task's, and its map weights). Every run's spec is checked "
        "before anything is trained. Ctrl-C (or SIGTERM) stops the runs in progress and starts no queued one; a "
        "rerun into DIR trains only the unfinished runs, each from its last checkpoint, and one with more --seeds "
        "or --variants (the same settings otherwise) trains only the new runs.",
    )
    parser.add_argument(
        "--variants",
        default=None,
        metavar="LIST",
        help=f"comma list of {', '.join(VARIANTS)} (default: {','.join(_COMPARE_VARIANTS)})",
    )
    parser.add_argument(
        "--seeds",
        default=None,
        metavar="N|LIST",
        help=f"a count (5 = seeds 0..4) or a comma list of distinct seeds "
        f"(default: {_COMPARE_SEEDS}; {_QUICK_SEEDS} with --quick)",
    )
    parser.add_argument(
        "--out", type=Path, default=None, help="output folder (default: runs/compare, or runs/compare-quick)"
    )
    parser.add_argument("--backend", choices=BACKENDS, default="process", help="process pool or ray (default: process)")
    workers = os.cpu_count() or 1
    parser.add_argument(
        "--workers",
        type=_positive_int,
        default=workers,
        help=f"runs in parallel (default: the CPU count, {workers} here)",
    )
    parser.add_argument(
        "--threshold", type=float, default=0.5, help="success rate for 'steps to threshold' (default: 0.5)"
    )
    parser.add_argument(
        "--quick",
        action="store_true",
        help=f"the README's quick comparison: {','.join(QUICK['variants'])} × {_QUICK_SEEDS} seeds × "
        f"{QUICK['total_steps']} steps in an {QUICK['env_kwargs']['arena_size_m']:g} m arena "
        "(explicit options still win)",
    )
    parser.add_argument(
        "--distractors",
        metavar="LIST",
        help="a clutter sweep: the comparison at each distractor count of the comma list (e.g. 1,3,6), "
        "into DIR/distractors-N/, then DIR/sweep.csv, sweep_summary.csv and "
        "success_vs_distractors.png (final success, safe success and contact time against distractors per variant)",
    )
    parser.add_argument("--extend", action="store_true", help=_EXTEND_HELP.format(what="the comparison in --out"))
    _add_run_options(parser, quick=True)
    parser.set_defaults(handler=_run_compare)


def _run_compare(args: argparse.Namespace) -> int:
    _require_agents_extra("compare")
    from attentive_gym.agents.compare import compare, runs_hold_progress
    from attentive_gym.agents.config import parse_seeds, parse_variants

    defaults = dict(QUICK) if args.quick else {}  # _spec_from_args holds the plain defaults
    variants = (
        parse_variants(args.variants)
        if args.variants is not None
        else tuple(defaults.get("variants", _COMPARE_VARIANTS))
    )
    seeds = parse_seeds(args.seeds) if args.seeds is not None else tuple(defaults.get("seeds", range(_COMPARE_SEEDS)))
    if not 0.0 <= args.threshold <= 1.0:
        raise ValueError(f"--threshold must be a success rate in [0, 1], got {args.threshold}")
    out = args.out or Path("runs") / ("compare-quick" if args.quick else "compare")
    stored = _trained_settings(out / "compare.json", runs_hold_progress(out), "run")
    if args.distractors is not None:  # a sweep: the settings of the comparisons at its counts
        from attentive_gym.agents.sweep import parse_distractors

        points = [out / f"distractors-{n}" for n in parse_distractors(args.distractors)]
        stored = next(
            filter(
                None, (_trained_settings(point / "compare.json", runs_hold_progress(point), "run") for point in points)
            ),
            None,
        )
    base = _spec_from_args(args, variants[0], seeds[0], defaults, stored)
    if args.distractors is not None:
        return _run_sweep(args, variants, seeds, base, out)
    print(
        f"compare: {_count(len(variants), 'variant')} × {_count(len(seeds), 'seed')} × {base.total_steps} env steps "
        f"({args.backend}, {_count(args.workers, 'worker')}) → {out}",
        flush=True,
    )
    result = compare(
        variants,
        seeds,
        base,
        out,
        backend=args.backend,
        workers=args.workers,
        threshold=args.threshold,
        extend=args.extend,
        log=lambda line: print(line, flush=True),
    )
    if result.summary_md is not None:
        print(result.summary_md.read_text(), end="")
        print(f"wrote {result.results_csv}, {result.figure}, {result.summary_csv}, {result.summary_md}")
        print(f"wrote {result.profiles_figure}")
    if result.goal_choice_figure is not None:
        print(f"wrote {result.goal_choice_figure.with_suffix('.csv')}, {result.goal_choice_figure}")
    if result.failed:
        print(f"{len(result.failed)} run(s) failed: {', '.join(result.failed)}; rerun the same command to retry them")
        return 1
    return 0


def _count(n: int, noun: str) -> str:
    """``n`` and ``noun``, in the plural unless ``n`` is 1: "1 seed", "3 seeds"."""
    return f"{n} {noun}{'' if n == 1 else 's'}"


def _run_sweep(args: argparse.Namespace, variants, seeds, base, out: Path) -> int:
    """``compare --distractors``: the comparison at each distractor count."""
    from attentive_gym.agents.sweep import clutter_sweep, parse_distractors

    counts = parse_distractors(args.distractors)
    if "num_distractors" in base.env_kwargs and args.env_kwargs is not None:
        raise ValueError("--distractors sets num_distractors; leave it out of --env-kwargs")
    print(
        f"compare: clutter sweep over {_count(len(counts), 'distractor count')} × {_count(len(variants), 'variant')} "
        f"× {_count(len(seeds), 'seed')} × {base.total_steps} env steps ({args.backend}, "
        f"{_count(args.workers, 'worker')}) → {out}",
        flush=True,
    )
    result = clutter_sweep(
        variants,
        seeds,
        base,
        counts,
        out,
        backend=args.backend,
        workers=args.workers,
        threshold=args.threshold,
        extend=args.extend,
        log=lambda line: print(line, flush=True),
    )
    if result.summary_csv is not None:
        print(f"wrote {result.results_csv}, {result.summary_csv}, {result.figure}")
    if result.failed:
        print(f"{len(result.failed)} run(s) failed: {', '.join(result.failed)}; rerun the same command to retry them")
        return 1
    return 0
