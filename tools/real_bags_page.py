"""``docs/results/real_bags.md``: the model on real robots' bags, and on a synthetic drive.

From ``docs/results/real_bags.csv``, the tidy rows of ``benchmarks/bench_real_bags.py
--csv`` (bag, setting, goal, metric, value): per bag, setting and goal, the share of the steps
with motion in the raw scans whose focus lies on a region holding motion, against chance and
a time-shuffled focus, and the confirmed tracks labelled moving per step.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

from page_text import RESULTS, banner, number, read_rows, table

NAME = "real_bags.md"
SOURCE = RESULTS / "real_bags.csv"
WRITTEN_BY = "benchmarks/bench_real_bags.py --csv (the commands on docs/results/real_bags.md)"
#: What each bag is: where it comes from, its licence, what it shows.
BAGS = {
    "leg_tracker_demo_stationary_simple.bag": (
        "[angusleigh/leg_tracker](https://github.com/angusleigh/leg_tracker) "
        "`rosbags/demos/demo_stationary_simple_environment.bag` (BSD 3-Clause; in `tests/data`)",
        "a still Hokuyo (512 beams over 180°, 5.6 m, 10 Hz), people walking past",
    ),
    "leg_tracker_positive_1.bag": (
        "leg_tracker `rosbags/training_scans_res=0.33/positive_not_extracted/positive_1.bag` (BSD 3-Clause)",
        "a still laser (768 beams over 270°, 11 m, 7.5 Hz), legs walking near it: the recordings leg_tracker "
        "trains its leg classifier on",
    ),
    "leg_tracker_positive_2.bag": ("the same folder's `positive_2.bag`", "as positive_1"),
    "leg_tracker_positive_3.bag": ("the same folder's `positive_3.bag`", "as positive_1"),
    "obstacle_detector_scans_demo.bag": (
        "[tysik/obstacle_detector](https://github.com/tysik/obstacle_detector) `resources/scans_demo.bag` (BSD)",
        "a still robot with a front and a rear Hokuyo (726 beams over 255°, 5.6 m, 10 Hz) among static bodies "
        "1-1.2 m away; little moves; mounts from the package's `demo.launch`",
    ),
    "corridor_0.3.bag": (
        "synthetic: `benchmarks/corridor_bag.py --speed 0.3`",
        "a robot driving straight down a static corridor at 0.3 m/s with exact odometry, 1 % range noise: "
        "nothing moves, so every moving track is false",
    ),
    "corridor_0.6.bag": ("synthetic: `benchmarks/corridor_bag.py --speed 0.6`", "as above, at 0.6 m/s"),
    "corridor_1.0.bag": ("synthetic: `benchmarks/corridor_bag.py --speed 1.0`", "as above, at 1 m/s"),
}
#: The bags of a driving robot.
DRIVING = {"corridor_0.3.bag", "corridor_0.6.bag", "corridor_1.0.bag"}
_METRICS = (
    ("steps", 0),
    ("motion_steps", 0),
    ("focus_on_motion_fraction", 2),
    ("chance_fraction", 2),
    ("shuffled_fraction", 2),
    ("moving_tracks_per_step", 2),
)
_HEADERS = (
    "bag",
    "setting",
    "goal",
    "steps",
    "steps with motion",
    "focus on a region with motion",
    "chance",
    "time-shuffled focus",
    "moving tracks per step",
)


#: The metrics that compare the focus with the raw scans' motion: meaningless on a driving
#: robot's bag (the backgrounds are per beam over the whole bag), shown as — there.
_STILL_ONLY = {"motion_steps", "focus_on_motion_fraction", "chance_fraction", "shuffled_fraction"}


def figures_table(rows: Sequence[Mapping[str, str]]) -> str:
    """The Markdown table: a line per (bag, setting, goal), the bags in the CSV's order and
    each bag's lines in it too; the focus columns are — for the bags of a driving robot."""
    groups: dict[tuple[str, str, str], dict[str, float]] = {}
    for row in rows:
        groups.setdefault((row["bag"], row["setting"], row["goal"]), {})[row["metric"]] = float(row["value"])
    order = {bag: k for k, bag in enumerate(dict.fromkeys(bag for bag, _, _ in groups))}
    lines = []
    for (bag, setting, goal), metrics in sorted(groups.items(), key=lambda item: order[item[0][0]]):
        still = bag not in DRIVING
        cells = [
            number(metrics.get(name, float("nan")) if still or name not in _STILL_ONLY else None, digits)
            for name, digits in _METRICS
        ]
        lines.append([bag, setting, goal, *cells])
    return table(_HEADERS, lines)


def bags_table(rows: Sequence[Mapping[str, str]]) -> str:
    """The bags measured, with their source and what they show."""
    names = list(dict.fromkeys(row["bag"] for row in rows))
    return table(["bag", "source", "what it shows"], [[name, *BAGS.get(name, ("—", "—"))] for name in names])


def page(root: Path, write_figures: bool = True) -> str:
    """The text of ``docs/results/real_bags.md`` under ``root`` (it has no figures)."""
    rows = read_rows(root, SOURCE.name, WRITTEN_BY)
    return "\n".join(
        [
            "# Real robots' bags",
            "",
            banner([SOURCE]),
            "`benchmarks/bench_real_bags.py` replays each bag through the model (with the sensor's own range) "
            "and finds motion in the raw scans alone, at the laser's own resolution: a scan beam moves when its "
            "echo lies more than 3σ in front of its median over the bag and changed by more than 3σ over 0.2 s; "
            "a region holds motion when 3 or more of its beams move. **Focus on a region with motion** is the "
            "share of the steps with motion whose focus lies on such a region; **chance**, a region drawn "
            "uniformly; **time-shuffled**, the same focus sequence rolled by half the bag. The backgrounds are "
            "per beam over the whole bag, so these three mean something for a still robot only. **Moving tracks "
            "per step** counts the confirmed tracks whose probability of moving exceeds 0.5, whatever the robot "
            "does: on a drive through a static corridor every one is false (the target for a driving robot in a "
            "static room is 0.5 or fewer).",
            "",
            "Settings: `defaults` is the model's version 1 (free-space evidence, the tracker's start rules and "
            "the field-of-view edge rule; [The model](../model.md) §10), `AttentionConfig()` when these bags "
            "were last run; version 2's occlusion rule (`track_occlusion_keeps_motion`) and version 3's start test "
            "(`track_onset_log_ratio`) have not been run on them "
            "(`attention.VERSION_1_FIELDS` as `--config` rebuilds version 1); "
            "`indoor-people` the laser profile of that name (`attend --profile indoor-people`); `version 0` the "
            "defaults before those rules (`attention.VERSION_0_FIELDS` as `--config`). `laser A,B` merges those "
            "LaserScan topics.",
            "",
            "## The bags",
            "",
            bags_table(rows),
            "## Figures",
            "",
            figures_table(rows),
            "## Reproduce",
            "",
            "Fetch the public bags into a folder `B` under the names above (`git show HEAD:PATH > B/NAME` in a "
            "clone of each repository; nothing is downloaded by the project), write the corridors with "
            "`python benchmarks/corridor_bag.py B/corridor_0.6.bag --speed 0.6` (and 0.3, 1.0), then run "
            "`benchmarks/bench_real_bags.py` with `--csv` once per setting and goal, and concatenate the CSVs "
            "(one header) into `docs/results/real_bags.csv`:",
            "",
            "```bash",
            "P='B/leg_tracker_demo_stationary_simple.bag B/leg_tracker_positive_1.bag B/leg_tracker_positive_2.bag "
            "B/leg_tracker_positive_3.bag'",
            "FRONT='--laser-topic /front_scan --laser-mount 0.23565,-0.0005,0'",
            "BOTH='--laser-topic /front_scan,/rear_scan --laser-mount 0.23565,-0.0005,0 "
            "--laser-mount=-0.23832,0.00542,180'",
            'V1=\'{"track_occlusion_keeps_motion": false, "track_onset_log_ratio": 0.0}\'  # the model\'s version 1, '
            "the page's `defaults`",
            'V0=\'{"free_space_evidence": false, "track_onset_speed_sigma_mps": 0.0, '
            '"track_standing_speed_sigma_mps": 0.0, "track_runaway_speed_mps": 0.0, '
            '"track_edge_keeps_motion": false, "track_occlusion_keeps_motion": false, "track_onset_log_ratio": 0.0}\'',
            "# each of these with and without --profile indoor-people (with it, label version 0's runs "
            '"indoor-people, version 0"), and with and without --goal speed:between:0.3:2.0;',
            '# the runs without V0 also take --config "$V1" --label defaults (or indoor-people):',
            "python benchmarks/bench_real_bags.py $P --csv part1.csv",
            'python benchmarks/bench_real_bags.py $P --config "$V0" --label "version 0" --csv part1v0.csv',
            "python benchmarks/bench_real_bags.py B/obstacle_detector_scans_demo.bag $FRONT --csv part2.csv",
            "python benchmarks/bench_real_bags.py B/obstacle_detector_scans_demo.bag $BOTH --csv part3.csv",
            "# the corridors, bottom-up, with and without --profile indoor-people:",
            "python benchmarks/bench_real_bags.py B/corridor_*.bag --csv part4.csv",
            'python benchmarks/bench_real_bags.py B/corridor_*.bag --config "$V0" --label "version 0" --csv part5.csv',
            "```",
            "",
            "The whole batch takes about a minute on 2 cores once the kernels are compiled.",
            "",
        ]
    )
