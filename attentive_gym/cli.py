"""The ``attentive-gym`` command line.

Subcommands (one small function each, registered in ``_SUBCOMMANDS``):

- ``attend LOG --out DIR``: replay readings logged from a robot (CSV or NPZ, formats in
  ``attentive_gym.attention.io.replay``, or a ROS bag, ``attentive_gym.attention.io.rosbag``)
  through the attentional model and write ``DIR/trace.npz`` and ``DIR/trace.png``. A bag's
  reader prints what it used and assumed (topics and rates, dropped scans, the laser's
  mount and its source, masked beams, missing odometry), one line each.
- ``experiment NAME|all [--noise S] [--seed N] [--out DIR]``: reproduce the paper's
  experiments and print docs/model.md §9's checks (``attentive_gym.experiments.cli``).
- ``train [--variant V] [--algo ppo|sac] [--steps N] [--seed S] [--n-envs K] [--out DIR]``,
  ``evaluate MODEL [--episodes N] [--video DIR]`` and ``compare --variants A,B --seeds N
  --steps N --out DIR [--backend process|ray] [--workers W] [--quick]``: SB3 agents on the
  observation variants (``attentive_gym.agents.cli``; needs the ``agents`` extra).

Every command prints one line on stderr when numba compiles kernels rather than loading
them from its cache (``_kernel_cache.announce_compilation``): the first run after an
install or an update spends about a minute there.

Errors in the user's input (a malformed log, an invalid goal, map list or configuration)
print one line on stderr and exit with status 2. Ctrl-C (and SIGTERM for ``train`` and
``compare``) prints one line, without a traceback, and exits with the shell's 128 + the
signal's number (130 for SIGINT). ``main`` returns the exit status.
"""

from __future__ import annotations

import argparse
import json
import signal
import sys
from collections.abc import Callable, Sequence
from pathlib import Path

from attentive_gym._kernel_cache import announce_compilation
from attentive_gym._optional import MissingExtraError, require
from attentive_gym.agents.cli import add_compare, add_evaluate, add_generalise, add_train
from attentive_gym.agents.config import QUICK, RunSpec
from attentive_gym.agents.stopping import Interrupted, quiet_teardown
from attentive_gym.attention.config import LASER_PROFILES, configured
from attentive_gym.experiments.cli import add_experiment_parser

__all__ = ["main", "build_parser"]

#: Exit status for invalid input (the same as argparse's usage errors).
EXIT_USAGE = 2


def _add_attend(subparsers) -> None:
    parser = subparsers.add_parser(
        "attend",
        help="replay a logged run through the attentional model",
        description=(
            "Replay sonar and laser readings logged from a robot through the attentional model. "
            "LOG is a CSV with header t,sonar_0..sonar_15 (or sonar_0..sonar_7),laser_0..laser_179 "
            "and optional v,w odometry columns (s, m, m/s, rad/s), an NPZ with arrays t (T,), "
            "sonar (T,16|8), laser (T,180) and optional odometry (T,2), or a ROS bag: a ROS 1 .bag, "
            "a ROS 2 bag folder or its .db3 or .mcap file (needs the 'ros' extra). A bag's "
            "sensor_msgs/LaserScan, sensor_msgs/Range (one topic per sonar) and nav_msgs/Odometry "
            "topics are found by message type; the flags below name them otherwise. "
            "Writes DIR/trace.npz and DIR/trace.png."
        ),
    )
    parser.add_argument("log", type=Path, help="the logged run (.csv, .npz, .bag, .db3, .mcap or a ROS 2 bag folder)")
    parser.add_argument("--out", type=Path, required=True, help="output folder")
    parser.add_argument(
        "--goal",
        action="append",
        default=[],
        metavar="SPEC",
        help="a top-down goal, e.g. speed:between:0.5:0.9, speed:greater:0.6, "
        "distance:smaller:2, direction:towards (repeatable, one per feature)",
    )
    parser.add_argument(
        "--maps", metavar="SPEC", help="active maps and weights, e.g. F1,F3 or F1=1,F4=2 (default: the configuration's)"
    )
    parser.add_argument(
        "--state", metavar="STATE", help="Global Attentive State: drowsy, alert, vigilant or a gain > 0"
    )
    parser.add_argument(
        "--config",
        metavar="JSON",
        help="AttentionConfig fields as a JSON object, or the path of a .json file holding one "
        "(over --profile's values)",
    )
    parser.add_argument(
        "--profile",
        choices=sorted(LASER_PROFILES),
        help="tracker values for a kind of laser and target: indoor-people, a Hokuyo/SICK indoor laser "
        "with people walking (default: the simulator's 0.2 m victims, 5 %% range noise)",
    )
    parser.add_argument("--no-figure", action="store_true", help="write trace.npz only")
    parser.add_argument(
        "--overwrite",
        action="store_true",
        help="replace trace.npz and trace.png where --out already holds them (refused otherwise)",
    )
    bag = parser.add_argument_group("ROS bags", "topics of a bag, when they are not one of each message type")
    bag.add_argument(
        "--laser-topic",
        metavar="TOPIC[,TOPIC...]",
        help="the sensor_msgs/LaserScan topic (the time base), or several, comma-separated: merged into the "
        "robot frame on the model's beams (nearest echo per bearing) at the first one's scans",
    )
    bag.add_argument(
        "--all-lasers",
        action="store_true",
        help="merge every sensor_msgs/LaserScan topic (natural name order; the first is the time base)",
    )
    bag.add_argument(
        "--sonar-topics",
        metavar="A,B,...",
        help="the sensor_msgs/Range topics, P2AT sonar 0 first: 8 (front) or 16 (whole ring), "
        "or any number with --sonar-bearings (default: all Range topics in natural name order; "
        "none: the front sonars are read from the laser)",
    )
    bag.add_argument("--odom-topic", metavar="TOPIC", help="the nav_msgs/Odometry topic (ego-motion)")
    bag.add_argument(
        "--sonar-bearings",
        metavar="DEG,DEG,...",
        help="one bearing (deg, counter-clockwise from the heading) per sonar topic, for sonars "
        "that are not the P2AT ring: each stands in for the nearest front sonar, the laser "
        "for the others",
    )
    bag.add_argument(
        "--laser-mount",
        action="append",
        metavar="X,Y,YAW_DEG[,upside-down]",
        help="where the laser sits on the robot (m, robot frame: x forward, y left) and where its "
        "beam at angle 0 points (deg, counter-clockwise from the heading; 180: facing backwards), "
        "',upside-down' for one mounted upside down; with several lasers once per laser, in topic order "
        "(default: from the bag's TF, else, for the first laser, the configuration's 0.16,0,0)",
    )
    bag.add_argument(
        "--laser-upside-down",
        action="store_true",
        help="the (first) laser is mounted upside down: its beam angles run clockwise seen from above "
        "(default: from TF)",
    )
    bag.add_argument(
        "--min-range", metavar="M", help="echoes nearer than M metres read as no echo (the robot's own parts)"
    )
    bag.add_argument(
        "--mask-angles",
        metavar="A:B[,C:D]",
        help="bearings (deg, robot frame, counter-clockwise from the heading, -180..180) whose beams read "
        "as no echo, e.g. 120:180,-180:-120",
    )
    bag.add_argument(
        "--keep-self-returns",
        action="store_true",
        help="keep the beams that hold a constant echo nearer than 0.5 m through the whole bag "
        "(by default they are taken for the robot's own structure and masked)",
    )
    parser.set_defaults(handler=_run_attend)


def _run_attend(args: argparse.Namespace) -> int:
    from attentive_gym._atomic import refuse_existing
    from attentive_gym.attention import AttentionModel, load_log, parse_goal, parse_maps, replay_log
    from attentive_gym.attention.io.rosbag import is_bag_path, parse_bag_topics, parse_scan_options
    from attentive_gym.attention.io.trace import save_trace

    if args.out.exists() and not args.out.is_dir():
        raise ValueError(f"--out {args.out} is a file; give a folder (it is created if missing)")
    if not args.overwrite:
        refuse_existing([args.out / "trace.npz", *([] if args.no_figure else [args.out / "trace.png"])])
    if not args.no_figure:
        require("matplotlib", "the trace's figure (--no-figure skips it)")
    config = configured(args.profile, args.config)
    goals = [parse_goal(spec) for spec in args.goal]
    weights = parse_maps(args.maps) if args.maps else None
    topics = parse_bag_topics(
        args.laser_topic, args.sonar_topics, args.odom_topic, args.sonar_bearings, args.all_lasers
    )
    scan_options = parse_scan_options(
        args.laser_mount, args.laser_upside_down, args.min_range, args.mask_angles, args.keep_self_returns
    )
    if is_bag_path(args.log):
        log, config = _open_bag(args.log, topics, config, scan_options)
    elif scan_options is not None:
        raise ValueError(
            f"{args.log}: --laser-mount, --laser-upside-down, --min-range, --mask-angles and --keep-self-returns "
            "apply to ROS bags only (a CSV or NPZ log's laser is already on the model's beams)"
        )
    else:
        log = load_log(args.log, topics=topics, config=config)
    model = AttentionModel(config)
    model.set_goals(*goals)
    if weights is not None:
        model.set_weights(weights)
    if args.state:
        model.set_state(_parse_state_arg(args.state))
    trace = replay_log(log, model)
    args.out.mkdir(parents=True, exist_ok=True)
    trace_path = save_trace(trace, args.out / "trace.npz")
    print(f"{trace.n_steps} steps, {int(trace.fired.sum())} courses fired; wrote {trace_path}")
    if not args.no_figure:
        from attentive_gym.viz.trace_figure import plot_trace

        figure_path = args.out / "trace.png"
        plot_trace(trace, path=figure_path)
        print(f"wrote {figure_path}")
    return 0


def _open_bag(path: Path, topics, config, scan_options):
    """A bag's log and the model's configuration with the laser mount and range it was read
    with (no echo at the scans' ``range_max`` where that is shorter than the configured
    range); prints the reader's notes (topics, rates, drops, mount, range, masks, odometry),
    one per line."""
    from attentive_gym.attention.io.rosbag import open_bag

    replay = open_bag(path, topics, config, scan_options, sensor_range=True)
    for note in replay.notes:
        print(note)
    return replay.log, replay.config


def _parse_state_arg(text: str) -> str | float:
    try:
        return float(text)
    except ValueError:
        return text


#: Subcommand name → function adding it to the parser; the lead adds ``experiment``, ``train``...
_SUBCOMMANDS: dict[str, Callable] = {
    "attend": _add_attend,
    "experiment": add_experiment_parser,
    "train": add_train,
    "evaluate": add_evaluate,
    "compare": add_compare,
    "generalise": add_generalise,
}


def _quick_run() -> str:
    """What ``compare --quick`` trains, in words, from ``QUICK``: "PPO on raw, focus and oracle
    observations, 3 seeds each"."""
    *others, last = QUICK["variants"]
    variants = f"{', '.join(others)} and {last}" if others else last
    return f"{RunSpec.algo.upper()} on {variants} observations, {len(QUICK['seeds'])} seeds each"


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with every subcommand."""
    parser = argparse.ArgumentParser(
        prog="attentive-gym",
        description="attentive_gym: a bio-inspired attentional model for multi-sensor robots, its Gymnasium "
        "rescue environment, and RL comparisons of attended against raw observations.",
        epilog=f"start with: 'attentive-gym compare --quick' ({_quick_run()}) or 'attentive-gym experiment all' "
        "(the paper's five experiments); 'attentive-gym COMMAND --help' lists a command's options.",
    )
    subparsers = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for add in _SUBCOMMANDS.values():
        add(subparsers)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status (0 ok, 2 invalid input, 128 + signal number when stopped)."""
    parser = build_parser()
    args = parser.parse_args(argv)
    announce_compilation()
    try:
        return args.handler(args)
    except (ValueError, OSError, json.JSONDecodeError, MissingExtraError) as err:
        print(f"attentive-gym {args.command}: error: {err}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt as stop:
        stop = stop if isinstance(stop, Interrupted) else Interrupted(signal.SIGINT)
        print(f"attentive-gym {args.command}: {stop}", file=sys.stderr)
        quiet_teardown()
        return stop.exit_status


if __name__ == "__main__":
    sys.exit(main())
