"""Real-data benchmark: does the focus lie on what moves in a robot's own bag?

Run: ``python benchmarks/bench_real_bags.py BAG [BAG ...] [--goal SPEC ...] [--profile NAME]
[--laser-topic TOPIC[,TOPIC...]] [--all-lasers] [--odom-topic TOPIC] [--laser-mount X,Y,YAW_DEG ...]
[--laser-upside-down] [--min-range M] [--mask-angles A:B[,C:D]] [--config JSON] [--label TEXT] [--csv PATH]``
(ROS 1 ``.bag`` files, ROS 2 bag folders or their ``.db3`` / ``.mcap`` files; the ``ros``
extra; a few seconds per bag once the kernels are compiled).

Each bag is replayed as ``attentive-gym attend`` replays it (``rosbag.open_bag``: the laser's
mount from the flags, the bag's TF or the configuration; self-returns masked), with the
sensor's own range as no echo (``sensor_range=True``: a 5.6 m Hokuyo's no echo is 5.6 m), and
with the goals of ``--goal`` (``attend``'s syntax; none: bottom-up) and the tracker values of
``--profile`` (``config.LASER_PROFILES``; none: the defaults) with ``--config``'s fields over
them (``config.configured``). Independently of the
model, moving beams are found from the raw scans alone, at the laser's own resolution
(``BagReplay.raw``):

- a scan beam's background is its median range over the bag, its spread σ its median
  absolute deviation (× 1.4826, at least ``MIN_SIGMA_M``);
- the beam moves at a scan when its echo lies more than 3 σ in front of its background, its
  range changed by more than 3 σ since the scan ``CHANGE_INTERVAL_S`` (0.2 s) earlier, and
  the beam does not return that range (within 3 σ) in ``RECURRENT_SHARE`` (5 %) of the scans
  or more (and in ``RECURRENT_MIN_SCANS``, 3, at least): a beam flickering between a far
  wall and no echo, or between two surfaces at an edge, returns each of them again and again.

A region of the model (s1..s8: the scan beams whose bearings fall in it) holds motion at a
step when at least ``MIN_MOVING_BEAMS`` (3) of its beams move. Over the steps with motion,
it prints the share of steps whose focus lies on a region holding motion (a step without a
focus is a miss), against two baselines:

- chance: the share of the regions holding motion (a focus drawn uniformly over regions);
- shuffled: the model's own focus sequence rolled by half the bag (its statistics kept,
  its timing lost).

The backgrounds are per beam over the whole bag, so the robot is taken to stand still; on
a driving robot's bag the figures mean little (``attend``'s notes, printed per bag, say
when the scans show the robot moving).

For a driving robot in a static room it also prints the mean number per step of confirmed
tracks whose probability of moving exceeds ``MOVING_PROBABILITY`` (0.5), read from the
trace's tracks (``Trace.track_confirmed``, ``Trace.track_moving_probability``): the tracks
the model takes for moving bodies, whatever the robot's own motion. In a static room every
one of them is a false alarm; the target is 0.5 or fewer per step. It needs no still robot
and no raw scans, and it is printed whether or not the scans hold motion.

``--csv`` writes tidy rows (bag, setting, goal, metric, value); the setting names the lasers,
profile and configuration given, or ``--label``'s text. Nothing is asserted: measure, don't
guess.
"""

from __future__ import annotations

import argparse
import csv
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from attentive_gym._atomic import atomic_file
from attentive_gym.attention import AttentionModel, Trace, parse_goal, replay_log
from attentive_gym.attention.config import LASER_PROFILES, configured
from attentive_gym.attention.io.rosbag import RawScans, open_bag, parse_bag_topics, parse_scan_options
from attentive_gym.attention.regions import FRONT_SONARS, LASER_BEAMS, LASER_FOV_DEG, Grid

#: A beam's range must have changed over this interval (s) to move...
CHANGE_INTERVAL_S = 0.2
#: ... by more than this many σ, and lie this many σ in front of its background.
MOTION_SIGMAS = 3.0
#: The smallest spread σ of a beam's range assumed (m): a laser's range noise.
MIN_SIGMA_M = 0.02
#: A range that a beam returns (within 3 σ) in at least this share of the scans is a static
#: surface, not a mover: the beam of a far wall at the edge of detection flickers between it
#: and no echo, the beam of an edge between two surfaces; a walker crosses a beam at one
#: range for a scan or two.
RECURRENT_SHARE = 0.05
#: ... and in at least this many scans.
RECURRENT_MIN_SCANS = 3
#: A region holds motion when at least this many of its scan beams move.
MIN_MOVING_BEAMS = 3
#: A confirmed track counts as moving when its probability of moving exceeds this.
MOVING_PROBABILITY = 0.5
#: The median absolute deviation of a normal distribution, in σ.
_MAD_PER_SIGMA = 1.4826
CSV_COLUMNS = ("bag", "setting", "goal", "metric", "value")


@dataclass(frozen=True)
class Agreement:
    """How often the focus lies on a region holding motion.

    Attributes:
        steps: the bag's steps.
        motion_steps: the steps at which some region holds motion.
        focus_on_motion: the share of the motion steps whose focus lies on a region holding motion.
        chance: the mean share of the regions holding motion, over the motion steps.
        shuffled: ``focus_on_motion`` of the focus sequence rolled by half the bag.
        moving_tracks: the mean number per step of confirmed tracks labelled moving
            (``moving_tracks_per_step``), over all the steps; NaN where not measured.
    """

    steps: int
    motion_steps: int
    focus_on_motion: float
    chance: float
    shuffled: float
    moving_tracks: float = float("nan")

    def metrics(self) -> dict[str, float]:
        """The figures by metric name (``*_fraction``: no unit)."""
        return {
            "steps": self.steps,
            "motion_steps": self.motion_steps,
            "focus_on_motion_fraction": self.focus_on_motion,
            "chance_fraction": self.chance,
            "shuffled_fraction": self.shuffled,
            "moving_tracks_per_step": self.moving_tracks,
        }


def moving_beams(raw: RawScans, t: np.ndarray) -> np.ndarray:
    """``(T, N)`` bool: the scan beams that move at each scan (the module docstring's rule; a
    no-echo reading never lies in front of its background).

    Args:
        raw: the scans at their own resolution, ``ranges_m`` ``(T, N)`` (m).
        t: ``(T,)`` the scans' times (s), increasing.
    """
    ranges = raw.ranges_m
    background = np.median(ranges, axis=0)
    sigma = np.maximum(_MAD_PER_SIGMA * np.median(np.abs(ranges - background), axis=0), MIN_SIGMA_M)
    earlier = np.searchsorted(t, t - CHANGE_INTERVAL_S, side="right") - 1
    compared = earlier >= 0
    change = np.abs(ranges - ranges[np.maximum(earlier, 0)])
    in_front = ranges < background - MOTION_SIGMAS * sigma
    return in_front & (change > MOTION_SIGMAS * sigma) & compared[:, None] & ~recurrent(ranges, MOTION_SIGMAS * sigma)


def recurrent(ranges: np.ndarray, tolerance_m: np.ndarray) -> np.ndarray:
    """``(T, N)`` bool: the readings that the same beam returns, within ``tolerance_m``
    ``(N,)`` (m), in at least ``RECURRENT_SHARE`` of the scans and ``RECURRENT_MIN_SCANS``:
    a static surface, whichever of several the beam flickers between."""
    ordered = np.sort(ranges, axis=0)
    shares = np.empty(ranges.shape)
    for beam in range(ranges.shape[1]):
        low = np.searchsorted(ordered[:, beam], ranges[:, beam] - tolerance_m[beam], side="left")
        high = np.searchsorted(ordered[:, beam], ranges[:, beam] + tolerance_m[beam], side="right")
        shares[:, beam] = (high - low) / ranges.shape[0]
    return (shares >= RECURRENT_SHARE) & (shares * ranges.shape[0] >= RECURRENT_MIN_SCANS)


def regions_with_motion(moving: np.ndarray, bearings_rad: np.ndarray, n_regions: int) -> np.ndarray:
    """``(T, J)`` bool: the model's regions holding at least ``MIN_MOVING_BEAMS`` moving beams.

    Args:
        moving: ``(T, N)`` the moving scan beams (``moving_beams``).
        bearings_rad: ``(N,)`` their robot-frame bearings (rad); beams outside the model's
            front 180° belong to no region.
        n_regions: J, 8 (front-sonar regions) or 180 (laser grid).
    """
    grid = Grid.make("sonar" if n_regions == FRONT_SONARS else "laser")
    beam = np.floor((np.degrees(bearings_rad) + LASER_FOV_DEG / 2.0) * LASER_BEAMS / LASER_FOV_DEG).astype(int)
    front = (beam >= 0) & (beam < LASER_BEAMS)
    region = grid.beam_region[beam[front]]
    counts = np.zeros((moving.shape[0], n_regions), dtype=int)
    for j in range(n_regions):
        counts[:, j] = moving[:, front][:, region == j].sum(axis=1)
    return counts >= MIN_MOVING_BEAMS


def moving_tracks_per_step(trace: Trace) -> float:
    """The mean number per step of ``trace``'s confirmed tracks whose probability of moving
    exceeds ``MOVING_PROBABILITY`` (0 for a trace without tracks)."""
    moving = trace.track_confirmed & (trace.track_moving_probability > MOVING_PROBABILITY)
    return float(np.count_nonzero(moving)) / trace.n_steps


def agreement(focus: np.ndarray, motion: np.ndarray, moving_tracks: float = float("nan")) -> Agreement:
    """The focus ``(T,)`` (region, -1 none) against the regions holding motion ``(T, J)``;
    ``moving_tracks`` (``moving_tracks_per_step``) is passed through."""
    steps = np.flatnonzero(motion.any(axis=1))
    if steps.size == 0:
        return Agreement(len(focus), 0, float("nan"), float("nan"), float("nan"), moving_tracks)
    return Agreement(
        steps=len(focus),
        motion_steps=int(steps.size),
        focus_on_motion=_share_on_motion(focus, motion, steps),
        chance=float(motion[steps].mean()),
        shuffled=_share_on_motion(np.roll(focus, len(focus) // 2), motion, steps),
        moving_tracks=moving_tracks,
    )


def _share_on_motion(focus: np.ndarray, motion: np.ndarray, steps: np.ndarray) -> float:
    """The share of ``steps`` whose focus lies on a region holding motion."""
    focused = focus[steps]
    hits = (focused >= 0) & motion[steps, np.maximum(focused, 0)]
    return float(hits.mean())


def measure_bag(
    path: Path, goal_specs: list[str], topics=None, options=None, config=None
) -> tuple[Agreement, tuple[str, ...]]:
    """Replay ``path`` with the goals of ``goal_specs`` and the configuration ``config``
    (default ``AttentionConfig()``) and compare its focus with the motion in its raw scans;
    returns the agreement and the replay's notes.

    Raises:
        LogFormatError: for a bag that cannot be replayed (``open_bag``).
        ValueError: for a malformed goal, or scans that change geometry along the bag.
    """
    replay = open_bag(path, topics, config, options, sensor_range=True)
    if replay.raw is None:
        raise ValueError(f"{path}: the scans change geometry along the bag; the raw-scan motion needs one")
    model = AttentionModel(replay.config)
    model.set_goals(*(parse_goal(spec) for spec in goal_specs))
    trace = replay_log(replay.log, model)
    moving = moving_beams(replay.raw, replay.log.t)
    motion = regions_with_motion(moving, replay.raw.bearings_rad, trace.n_regions)
    return agreement(trace.focus, motion, moving_tracks_per_step(trace)), replay.notes


def _table(rows: list[tuple[str, str, str, Agreement]]) -> str:
    """A markdown table of the agreements, one row per bag, setting and goal."""
    lines = [
        "| bag | setting | goal | steps | steps with motion | focus on a region with motion | chance (uniform region) "
        "| time-shuffled focus | moving tracks per step |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for bag, setting, goal, figures in rows:
        lines.append(
            f"| {bag} | {setting} | {goal} | {figures.steps} | {figures.motion_steps} | {figures.focus_on_motion:.2f} "
            f"| {figures.chance:.2f} | {figures.shuffled:.2f} | {figures.moving_tracks:.2f} |"
        )
    return "\n".join(lines)


def write_csv(path: Path, rows: list[tuple[str, str, str, Agreement]]) -> int:
    """Tidy rows (``CSV_COLUMNS``), one per bag, setting, goal and metric, written atomically;
    returns how many (the header aside)."""
    tidy = [
        (bag, setting, goal, metric, f"{value:.6g}")
        for bag, setting, goal, figures in rows
        for metric, value in figures.metrics().items()
    ]
    with atomic_file(path) as file:
        writer = csv.writer(file)
        writer.writerow(CSV_COLUMNS)
        writer.writerows(tidy)
    return len(tidy)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("bags", nargs="+", type=Path, metavar="BAG", help="ROS 1 or ROS 2 bags")
    parser.add_argument(
        "--goal", action="append", default=[], metavar="SPEC", help="a top-down goal as attend takes it (repeatable)"
    )
    parser.add_argument("--profile", choices=sorted(LASER_PROFILES), help="tracker values (config.LASER_PROFILES)")
    parser.add_argument(
        "--config", metavar="JSON", help="AttentionConfig fields over the profile's, a JSON object (as attend takes it)"
    )
    parser.add_argument("--laser-topic", metavar="TOPIC[,TOPIC...]", help="the sensor_msgs/LaserScan topic(s)")
    parser.add_argument("--all-lasers", action="store_true", help="merge every LaserScan topic")
    parser.add_argument("--odom-topic", metavar="TOPIC", help="the nav_msgs/Odometry topic")
    parser.add_argument(
        "--laser-mount", action="append", metavar="X,Y,YAW_DEG", help="a laser's mount, as attend takes it"
    )
    parser.add_argument("--laser-upside-down", action="store_true", help="the laser is mounted upside down")
    parser.add_argument("--min-range", metavar="M", help="echoes nearer than M metres read as no echo")
    parser.add_argument("--mask-angles", metavar="A:B[,C:D]", help="robot-frame bearings (deg) read as no echo")
    parser.add_argument(
        "--label", help="the setting's name in the table and CSV (default: the lasers, profile and config given)"
    )
    parser.add_argument("--csv", type=Path, default=None, help="also write the figures as tidy CSV rows")
    args = parser.parse_args(argv)
    topics = parse_bag_topics(args.laser_topic, None, args.odom_topic, None, args.all_lasers)
    options = parse_scan_options(args.laser_mount, args.laser_upside_down, args.min_range, args.mask_angles)
    try:
        config = configured(args.profile, args.config)
    except (ValueError, OSError) as err:
        parser.error(f"--config: {err}")
    goal = " ".join(args.goal) or "bottom-up"
    lasers = "every laser" if args.all_lasers else args.laser_topic and f"laser {args.laser_topic}"
    setting = args.label or ", ".join(filter(None, [lasers, args.profile, args.config and f"config {args.config}"]))
    setting = setting or "defaults"
    start = time.perf_counter()
    rows = []
    for bag in args.bags:
        figures, notes = measure_bag(bag, args.goal, topics, options, config)
        print(f"{bag}:", *(f"  {note}" for note in notes), sep="\n")
        rows.append((bag.name, setting, goal, figures))
    print()
    print(_table(rows))
    if args.csv is not None:
        print(f"\nwrote {write_csv(args.csv, rows)} rows to {args.csv}")
    print(f"\n(run time {time.perf_counter() - start:.0f} s)")


if __name__ == "__main__":
    main()
