"""``attentive-gym experiment NAME|all [--noise S] [--seed N] [--kinematics MODE] [--profile P] [--out DIR]``.

Runs one experiment (or all five, with a progress line on stderr after each: its time, the
elapsed time and an ETA), prints each docs/model.md §9 check as PASS/FAIL with its measured
values, and with ``--out`` writes ``DIR/NAME.npz`` (the trace) and ``DIR/NAME.png`` (the
figure). ``--kinematics`` picks the model's kinematics mode (tracker, window, literal, or
truth: the perfect-perception bound), ``--profile`` the env's sensor profile (usarsim).
Exit status 0 whatever the checks say.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from attentive_gym._atomic import refuse_existing
from attentive_gym._optional import require
from attentive_gym.experiments.checks import check_experiment
from attentive_gym.experiments.registry import EXPERIMENT_NAMES, get_experiment
from attentive_gym.experiments.runner import EXPERIMENT_KINEMATICS, _check_kinematics, _check_profile, run_experiment
from attentive_gym.progress import Progress, format_duration
from attentive_gym.sensors import SENSOR_PROFILES

__all__ = ["add_experiment_parser"]

_ALL = "all"


def add_experiment_parser(subparsers) -> None:
    """Add the ``experiment`` subcommand to an argparse ``subparsers`` object."""
    parser = subparsers.add_parser(
        "experiment",
        help="reproduce one of the paper's experiments (or all)",
        description=(
            "Run one of the paper's experiments with the robot immobile, print the docs/model.md §9 checks "
            f"and optionally write DIR/NAME.npz and DIR/NAME.png. NAME: {', '.join(EXPERIMENT_NAMES)} "
            f"or {_ALL}."
        ),
    )
    parser.add_argument("name", metavar="NAME", help=f"{', '.join(EXPERIMENT_NAMES)} or {_ALL}")
    parser.add_argument(
        "--noise",
        type=float,
        default=None,
        help="relative sensor noise in [0, 0.5]: σ, or the half-width under a uniform-noise "
        "profile (default: the profile's, 0 without one; the paper's is 0.05)",
    )
    parser.add_argument("--seed", type=int, default=0, help="seed of the noise (int >= 0, default 0)")
    parser.add_argument(
        "--kinematics",
        default="tracker",
        metavar="MODE",
        help=f"the model's kinematics: {', '.join(EXPERIMENT_KINEMATICS)} (truth: the model fed the simulator's "
        "true kinematics, the perfect-perception bound; default tracker)",
    )
    parser.add_argument(
        "--profile",
        default=None,
        metavar="PROFILE",
        help=f"the env's sensor profile: {', '.join(sorted(SENSOR_PROFILES))} "
        "(default none: Gaussian noise, a scan every step)",
    )
    parser.add_argument("--out", type=Path, help="folder for NAME.npz and NAME.png (default: write nothing)")
    parser.add_argument(
        "--overwrite",
        action="store_true",
        help="replace NAME.npz and NAME.png where --out already holds them (refused otherwise)",
    )
    parser.set_defaults(handler=_run)


def _run(args: argparse.Namespace) -> int:
    names = EXPERIMENT_NAMES if args.name == _ALL else (get_experiment(args.name).name,)
    _check_kinematics(args.kinematics), _check_profile(args.profile)  # before any run starts
    if args.out is not None and args.out.exists() and not args.out.is_dir():
        raise ValueError(f"--out {args.out} is a file; give a folder (it is created if missing)")
    if args.out is not None:
        require("matplotlib", "writing the experiments' figures (--out)")
    if args.out is not None and not args.overwrite:
        refuse_existing([args.out / f"{name}{suffix}" for name in names for suffix in (".npz", ".png")])
    progress = Progress(len(names)) if args.name == _ALL else None
    lines = []
    for name in names:
        start_s = time.monotonic()
        result = run_experiment(
            name, noise=args.noise, seed=args.seed, out_dir=args.out, kinematics=args.kinematics, profile=args.profile
        )
        checks = check_experiment(result)
        verdict = f"{name}: {sum(c.passed for c in checks)}/{len(checks)} checks pass"
        if progress is not None:
            print(
                progress.line(f"{verdict} in {format_duration(time.monotonic() - start_s)}"),
                file=sys.stderr,
                flush=True,
            )
        lines.append(verdict)
        lines.extend(f"  {'PASS' if c.passed else 'FAIL'} {c.name}: {c.measured}" for c in checks)
        lines.extend(f"  wrote {path}" for path in result.paths)
    print("\n".join(lines))
    return 0
