"""``docs/results/perception.md``: how well the model sees motion and attends the target.

From the tidy CSVs of ``benchmarks/bench_perception.py --csv`` (``perception.csv``: the
``speed``, ``focus``, ``control`` and ``cost`` sections; ``perception_clutter.csv``: the
``clutter`` section; ``perception_motion.csv``: the ``motion`` section):

- ``summary_table(rows)``: the three kinematics modes side by side at 5 % Gaussian noise;
- ``cases_table(rows)`` / ``track_age_table(rows)``: the tracker's steps with the target
  in view, sorted by why the focus was or was not on it, and by the age of its track;
- ``noise_table(rows)``: the tracker under every noise setting;
- ``clutter_table(rows)``: focus and controllers against the number of distractors;
- ``motion_table(rows)``: starts, phantoms and recall on the motion scenes;
- ``page(root)``: the whole page.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

from attentive_gym.perception.geometry import SIGHT_BEAMS, SIGHT_BEARING_DEG, VIEW_RANGE_M
from attentive_gym.perception.records import FALSE_LABEL_M
from page_text import RESULTS, banner, interval, number, read_rows, table, values

NAME = "perception.md"
SOURCES = (RESULTS / "perception.csv", RESULTS / "perception_clutter.csv", RESULTS / "perception_motion.csv")
MODES = ("tracker", "window", "literal")
#: The benchmark's perfect-perception bound, in the place of a mode in its CSV.
BOUND = "perfect perception"
#: The cost section's row of the tracker with version 0's defaults (the benchmark's ``VERSION_0_TRACKER``).
VERSION_0_TRACKER = "tracker (version 0)"
NOISY = "gauss 0.05"
NOISE_FREE = "gauss 0"
#: The noise settings of the benchmark, as its CSV names them, and how the page names them.
NOISE_NAMES = {
    "gauss 0": "none",
    "gauss 0.02": "2 % Gaussian",
    "gauss 0.05": "5 % Gaussian",
    "usarsim": "usarsim (±5 % uniform, 5 Hz scans)",
}
GOALS = ("speed in [0.5, 0.9] m/s", "speed in [0.15, 0.45] m/s")
ROBOTS = ("still", "driving")
#: The benchmark's reasons for the focus being on, or off, the target, in its order.
CASES = {
    "case_on_target": "on target",
    "case_hidden_from_the_laser": "hidden from the laser",
    "case_seen_no_track": "seen, no track",
    "case_young_track_goal_not_judged": "young track (< 1 s), goal not judged",
    "case_track_goal_not_judged": "older track, goal not judged",
    "case_no_focus": "no focus",
    "case_inhibited": "goal judged, region inhibited",
    "case_another_region_won": "goal judged, another region won",
}
AGES = {
    "no_track": "no track",
    "track_0_to_1_s": "track 0–1 s old",
    "track_1_to_2_s": "1–2 s",
    "track_2_to_4_s": "2–4 s",
    "track_over_4_s": "≥ 4 s",
}
WRITTEN_BY = "python benchmarks/bench_perception.py --csv docs/results/perception.csv"
CLUTTER_WRITTEN_BY = (
    "python benchmarks/bench_perception.py --modes tracker --sections clutter --csv docs/results/perception_clutter.csv"
)
MOTION_WRITTEN_BY = (
    "python benchmarks/bench_perception.py --modes tracker,window --sections motion --episodes 30 "
    "--csv docs/results/perception_motion.csv"
)
#: The motion section's scenes, as its CSV names them, and how the page names them.
SCENES = {"stop-and-go": "stop and go", "along-structure": "along structure"}


def _pair(first: float | None, second: float | None, digits: int = 2) -> str:
    return f"{number(first, digits)} / {number(second, digits)}"


def _rate(figures: Mapping[str, float], metric: str) -> str:
    """A figure of ``figures`` (a rate, a median) with its interval over the episodes where the
    CSV has one (``metric_low``, ``metric_high``; rows from before have none); "—" where it has
    no such figure."""
    if metric not in figures:
        return "—"
    low, high = figures.get(f"{metric}_low"), figures.get(f"{metric}_high")
    if low is None or high is None:
        return number(figures[metric])
    return interval(figures[metric], low, high)


def _rate_pair(still: Mapping[str, float], driving: Mapping[str, float], metric: str) -> str:
    """``"still / driving"``: ``_rate`` of ``metric`` in the figures of each robot mode."""
    return f"{_rate(still, metric)} / {_rate(driving, metric)}"


def summary_table(rows: Sequence[Mapping[str, str]]) -> str:
    """A row per figure, a column per kinematics mode, at 5 % Gaussian noise ("—": the mode
    has no such figure; "a / b": robot still / driving)."""
    speed = {
        (mode, robot): values(rows, section="speed", mode=mode, robot=robot, noise=NOISY)
        for mode in MODES
        for robot in ROBOTS
    }
    focus = {
        (mode, robot, goal): values(rows, section="focus", mode=mode, robot=robot, noise=NOISY, goal=goal)
        for mode in MODES
        for robot in ROBOTS
        for goal in GOALS
    }
    bound = {
        (robot, goal): values(rows, section="focus", mode=BOUND, robot=robot, noise=NOISY, goal=goal)
        for robot in ROBOTS
        for goal in GOALS
    }
    control = {mode: values(rows, section="control", mode=mode, noise=NOISY) for mode in MODES}
    cost = {mode: values(rows, section="cost", mode=mode, noise=NOISY) for mode in MODES}
    version_0 = values(rows, section="cost", mode=VERSION_0_TRACKER, noise=NOISY)

    def per_mode(cell) -> list[str]:
        return [cell(mode) for mode in MODES]

    def speed_pair(mode, metric):
        """still / driving of a speed figure; "—" where the mode has none."""
        pair = _pair(speed[(mode, "still")].get(metric), speed[(mode, "driving")].get(metric))
        return "—" if pair == "— / —" else pair

    def speed_rates(mode, metric):
        """still / driving share of a speed-section figure with its interval over the episodes."""
        if metric not in speed[(mode, "still")]:
            return "—"
        return _rate_pair(speed[(mode, "still")], speed[(mode, "driving")], metric)

    def focus_pair(mode, goal, metric):
        return _pair(focus[(mode, "still", goal)].get(metric), focus[(mode, "driving", goal)].get(metric))

    def focus_rates(mode, goal, metric):
        """still / driving focus rate with their intervals over the episodes."""
        return _rate_pair(focus[(mode, "still", goal)], focus[(mode, "driving", goal)], metric)

    def track_error(robot):
        return lambda mode: (
            "—"
            if "track_median_mps" not in speed[(mode, robot)]
            else _pair(speed[(mode, robot)]["track_median_mps"], speed[(mode, robot)]["track_p90_mps"])
        )

    def controller(name):
        def cell(mode):
            figures = control[mode]
            if f"success_{name}" not in figures:
                return "—"
            return f"{number(figures[f'success_{name}'])} ({number(figures[f'{name}_over_true_bearing'])}×)"

        return cell

    def bound_pair(goal, metric="focus_on_target"):
        """still / driving focus on target (``metric``) of the perfect-perception bound."""
        return _pair(bound[("still", goal)].get(metric), bound[("driving", goal)].get(metric))

    def sight_over_bound(mode, goal):
        """still / driving focus on target in sight ÷ the bound's; "—" where either is missing."""
        ratios = []
        for robot in ROBOTS:
            own = focus[(mode, robot, goal)].get("focus_on_target_in_sight")
            best = bound[(robot, goal)].get("focus_on_target_in_sight")
            ratios.append(own / best if own is not None and best else None)
        return _pair(*ratios)

    def goal_text(goal):
        return goal.removeprefix("speed in ").removesuffix(" m/s")

    true_bearing = number(control["tracker"].get("success_true_bearing"))
    random_actions = number(control["tracker"].get("success_random"))
    env_us = cost["tracker"].get("env_step_us")
    lines = [
        ["track speed error, median / p90 (m/s), robot still", *per_mode(track_error("still"))],
        ["track speed error, median / p90 (m/s), robot driving", *per_mode(track_error("driving"))],
        ["region speed error, median (m/s), still / driving", *per_mode(lambda m: speed_pair(m, "region_median_mps"))],
        [
            "static structure while driving, median / p90 (m/s)",
            *per_mode(
                lambda m: _pair(
                    speed[(m, "driving")].get("static_median_mps"), speed[(m, "driving")].get("static_p90_mps")
                )
            ),
        ],
        ["goal agreement, tracks, still / driving", *per_mode(lambda m: speed_pair(m, "goal_agreement_track"))],
        *[
            [label, *per_mode(lambda m, key=key: speed_rates(m, key))]
            for label, key in (
                (
                    f"phantom motion: steps with a confirmed track labelled moving > {FALSE_LABEL_M:g} m from every "
                    "mover, still / driving (95 % intervals over the episodes)",
                    "false_label_steps",
                ),
                (f"the same, one within {VIEW_RANGE_M:g} m of the robot", "false_label_near_steps"),
                ("the same, one at a speed the goal asks for", "false_in_band_steps"),
            )
            if any(key in figures for figures in speed.values())  # a CSV from before has none
        ],
        *[
            [
                f"focus on target, goal {goal_text(goal)}, still / driving (chance 0.125; 95 % intervals over "
                "the episodes)",
                *per_mode(lambda m, g=goal: focus_rates(m, g, "focus_on_target")),
            ]
            for goal in GOALS
        ],
        *[
            [
                f"the same ÷ the mode's noise-free figure, goal {goal_text(goal)}",
                *per_mode(lambda m, g=goal: focus_pair(m, g, "focus_over_noise_free")),
            ]
            for goal in GOALS
        ],
        *[
            [
                f"the same ÷ the perfect-perception bound (true kinematics: {bound_pair(goal)}), "
                f"goal {goal_text(goal)}",
                *per_mode(lambda m, g=goal: focus_pair(m, g, "focus_over_bound")),
            ]
            for goal in GOALS
            if any(bound.values())  # a CSV from before the bound has none
        ],
        *[
            [
                f"focus on target in sight (also within {SIGHT_BEARING_DEG:g}° of the heading, on ≥ {SIGHT_BEAMS} "
                f"laser beams), goal {goal_text(goal)}, still / driving",
                *per_mode(lambda m, g=goal: focus_rates(m, g, "focus_on_target_in_sight")),
            ]
            for goal in GOALS
            if any("focus_on_target_in_sight" in figures for figures in focus.values())
        ],
        *[
            [
                f"the same ÷ the perfect-perception bound in sight ({bound_pair(goal, 'focus_on_target_in_sight')}), "
                f"goal {goal_text(goal)}",
                *per_mode(lambda m, g=goal: sight_over_bound(m, g)),
            ]
            for goal in GOALS
            if any("focus_on_target_in_sight" in figures for figures in bound.values())
        ],
        [
            f"focus-steered controller, success (÷ true bearing's {true_bearing}; random actions {random_actions})",
            *per_mode(controller("focus")),
        ],
        ["memory controller, success: reads only the `focus` observation", *per_mode(controller("memory"))],
        [
            f"model step ÷ raw env step ({number(env_us, 1)} µs)",
            *per_mode(lambda m: number(cost[m].get("model_over_env"))),
        ],
        ["of which the compiled step", *per_mode(lambda m: number(cost[m].get("compiled_over_env")))],
        ["of which the tracker", *per_mode(lambda m: number(cost[m].get("tracker_over_env")))],
    ]
    if version_0:
        lines.append(
            [
                "the tracker's model step with version 0's defaults, same run (÷ raw env step; of which the tracker)",
                _pair(version_0.get("model_over_env"), version_0.get("tracker_over_env")),
                *["—"] * (len(MODES) - 1),
            ]
        )
    return table(["at 5 % Gaussian noise", *MODES], lines)


def cases_table(rows: Sequence[Mapping[str, str]]) -> str:
    """The tracker's steps with the target in view, by case; a row per noise setting,
    "still / driving" in each cell."""
    lines = []
    for noise, name in NOISE_NAMES.items():
        still = values(rows, section="focus", mode="tracker", robot="still", noise=noise, goal="")
        driving = values(rows, section="focus", mode="tracker", robot="driving", noise=noise, goal="")
        if still:
            lines.append([name, *(_pair(still.get(case), driving.get(case)) for case in CASES)])
    return table(["noise", *CASES.values()], lines)


def track_age_table(rows: Sequence[Mapping[str, str]]) -> str:
    """Focus on target by the age of the target's track (in brackets: the share of steps)."""
    lines = []
    for noise in (NOISY, NOISE_FREE):
        for robot in ROBOTS:
            figures = values(rows, section="focus", mode="tracker", robot=robot, noise=noise, goal="")
            lines.append(
                [
                    f"{NOISE_NAMES[noise]}, {robot}",
                    *(
                        f"{number(figures.get(f'focus_on_target_{age}'))} ({number(figures.get(f'steps_{age}'))})"
                        for age in AGES
                    ),
                ]
            )
    return table(["noise, robot", *AGES.values()], lines)


def noise_table(rows: Sequence[Mapping[str, str]]) -> str:
    """The tracker under each noise setting: speed error, goal agreement, focus, controllers."""
    lines = []
    for noise, name in NOISE_NAMES.items():
        still = values(rows, section="speed", mode="tracker", robot="still", noise=noise)
        driving = values(rows, section="speed", mode="tracker", robot="driving", noise=noise)
        focus = [
            _rate_pair(
                *(
                    values(rows, section="focus", mode="tracker", robot=robot, noise=noise, goal=goal)
                    for robot in ROBOTS
                ),
                "focus_on_target",
            )
            for goal in GOALS
        ]
        control = values(rows, section="control", mode="tracker", noise=noise)
        lines.append(
            [
                name,
                _pair(still.get("track_median_mps"), driving.get("track_median_mps")),
                _pair(still.get("goal_agreement_track"), driving.get("goal_agreement_track")),
                "; ".join(focus),
                number(control.get("success_focus")),
                number(control.get("success_memory")),
                _rate_pair(still, driving, "false_label_steps"),
            ]
        )
    return table(
        [
            "noise",
            "track speed error, median (m/s), still / driving",
            "goal agreement, tracks",
            "focus on target, goal [0.5, 0.9]; goal [0.15, 0.45] (still / driving)",
            "focus-steered controller",
            "memory controller",
            "phantom motion (steps), still / driving",
        ],
        lines,
    )


def clutter_table(rows: Sequence[Mapping[str, str]]) -> str:
    """A column per distractor count: focus on target and the controllers' success."""
    counts = sorted({int(row["distractors"]) for row in rows if row["distractors"]})
    figures = {
        n: {**values(rows, robot="driving", distractors=str(n)), **values(rows, robot="controller", distractors=str(n))}
        for n in counts
    }
    names = {
        "focus_on_target": "focus on target, robot driving (chance 0.125)",
        "success_memory": "memory controller (reads only the `focus` observation), success",
        "success_true_bearing": "true-bearing controller, success",
        "success_random": "random actions, success",
    }
    return table(
        ["distractors", *map(str, counts)],
        [[name, *(number(figures[n].get(metric)) for n in counts)] for metric, name in names.items()],
    )


def motion_table(rows: Sequence[Mapping[str, str]]) -> str:
    """Per scene, noise setting (those ``rows`` have) and robot mode, each kinematics mode's
    onset latency (s, and its median in the laser's scan intervals), false moving labels,
    recall of the moving walker and focus on it."""
    modes = sorted({row["mode"] for row in rows}, key=MODES.index)
    noises = [noise for noise in NOISE_NAMES if any(row["noise"] == noise for row in rows)]
    out = []
    for scene, scene_name in SCENES.items():
        for noise in noises:
            for robot in ROBOTS:
                for mode in modes:
                    f = values(rows, section="motion", mode=mode, robot=robot, noise=noise, scene=scene)
                    out.append(
                        [
                            scene_name,
                            NOISE_NAMES[noise],
                            robot,
                            mode,
                            number(f.get("latency_median_s")),
                            number(f.get("latency_p90_s")),
                            _rate(f, "latency_median_scans"),
                            number(f.get("false_label_steps")),
                            number(f.get("false_in_band_steps")),
                            number(f.get("moving_recall")),
                            number(f.get("focus_on_target")),
                        ]
                    )
    headers = [
        "scene",
        "noise",
        "robot",
        "mode",
        "start to goal judged, median s",
        "90th percentile s",
        "median in laser scans [95 % interval over the episodes]",
        "false moving labels",
        "of them in the goal's band",
        "walker as a moving track",
        "focus on the walker",
    ]
    return table(headers, out)


def page(root: Path, write_figures: bool = True) -> str:
    """The text of ``docs/results/perception.md`` under ``root`` (it has no figures)."""
    rows = read_rows(root, SOURCES[0].name, WRITTEN_BY)
    clutter = read_rows(root, SOURCES[1].name, CLUTTER_WRITTEN_BY)
    motion = read_rows(root, SOURCES[2].name, MOTION_WRITTEN_BY)
    return "\n".join(
        [
            "# Perception",
            "",
            banner(SOURCES),
            "How well each kinematics mode estimates motion, and how often the focus lands on the task's target, in "
            "the procedural 10 m arena with 3 distractors (96 episodes × 20 s per row, the goals in turn; "
            "the controllers on 40 seeds in "
            "the 8 m arena with 2 distractors). Speed error: movers within 5 m in front, in view for at least 1 s; "
            "goal agreement: the goal judged from the estimate equals the goal judged from the truth; focus on "
            "target: the share of the steps with the target in front and within 5 m at which the focus is its "
            "region; in sight: the same over the steps at which the laser can see the target (within "
            f"{SIGHT_BEARING_DEG:g}° of the heading, on {SIGHT_BEAMS} or more beams: the part of the view that "
            "perception is answerable for). The memory "
            "controller steers at the first remembered goal match of the `focus` observation: "
            "it sees nothing a policy does not see.",
            "",
            "## The kinematics modes at 5 % noise",
            "",
            summary_table(rows),
            "## The tracker under each noise setting",
            "",
            noise_table(rows),
            "## Why the focus misses the target",
            "",
            "The tracker's steps with the target in view, by what happened (still / driving, both goals):",
            "",
            cases_table(rows),
            "By the age of the target's track (in brackets: the share of the steps):",
            "",
            track_age_table(rows),
            "## Against clutter",
            "",
            "The RL comparison's arena (8 m, 3 rubble pieces per 100 m²) at 5 % noise:",
            "",
            clutter_table(clutter),
            "## Motion seen at once",
            "",
            "A walker that stands 2 s and then walks 1.5 m at 0.5–0.9 m/s (stop and go), or runs back and forth "
            "0.3–0.9 m in front of a wall or a row of rubble 2–5 m ahead (along structure); 30 episodes of 20 s per "
            "row, the goal speed in [0.5, 0.9] m/s. The latency runs from each start (after ≥ 1 s standing, in view) "
            "to the first step at which the goal is judged met in the walker's region (inf: more than a tenth of the "
            "starts never judged before the walker stopped; —: no starts), and its median in the laser's scan "
            "intervals (0.05 s; 0.2 s under `usarsim`). A false moving label is a confirmed "
            "track labelled moving more than 1.5 m from every mover (share of the steps); the walker counts as a "
            "moving track when one lies within 0.75 m of it while it moves within 3.5 m. The window modes keep no "
            "tracks.",
            "",
            motion_table(motion),
            "## Reproduce",
            "",
            "```bash",
            f"{WRITTEN_BY}            # about 9 minutes on 2 cores",
            f"{CLUTTER_WRITTEN_BY}",
            f"{MOTION_WRITTEN_BY}",
            "python tools/report.py render",
            "```",
            "",
        ]
    )
