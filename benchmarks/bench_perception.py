"""Perception benchmark: does the attentional model see motion and attend to the goal's target?

Run: ``python benchmarks/bench_perception.py [--modes tracker,window,literal] [--episodes 96]
[--seconds 20] [--control-episodes 40] [--sections speed,focus,control,cost,clutter,motion]
[--config JSON] [--csv PATH]``
(about 2 minutes on 2 quiet cores for the first four sections, which are the default;
``clutter`` adds about 5 minutes).

For each kinematics mode (``AttentionConfig(kinematics=...)``, docs/model.md §3 and §10), the
robot still or driving (a scripted wander, ``Wander``), and each sensor noise setting
(``NOISE_SETTINGS``: Gaussian σ = 0, 2 % and 5 %, and the env's ``sensor_profile="usarsim"``:
uniform ±5 %, 5 Hz scans), in the procedural 10 m arena with 3 distractors, it prints
markdown tables of:

1. ``speed``: the error of the speed estimate of the region a mover lies in against the
   mover's true speed, over (mover, step) pairs where the mover has been in front of the
   robot and within 5 m for at least 1 s; separately the pairs within 1 s after the mover
   turned; with tracks (``out.tracks``, tracker mode) the error of the nearest confirmed
   track too; the speed of regions whose echoes all come from static structure (should be
   ≈ 0); and how often "the goal holds" judged from the estimate agrees with the truth.
2. ``focus``: per default task goal, the fraction of the steps with the target in front and
   within 5 m at which the focus is the target's region (chance: 1/8), the same over the
   steps with the target in sight (also within 80° of the heading and on ≥ 2 laser beams:
   ``geometry.in_sight``), and each noisy setting's figure relative to the same mode's
   noise-free one (what the noise takes away).
   Beside the modes, per robot mode and noise setting, the perfect-perception bound
   (``perception.bound``): the same model and readings with the channels' kinematics taken
   from the simulator's truth (the movers the laser sees on ≥ 2 beams), on the same episodes
   (a raw environment stepped by the same policy: the same in-view steps); then each mode's
   figure over the bound's. Chance and the bound frame each figure.
3. ``control``: success rates in the 8 m arena with 2 distractors (seeds 0..N−1) of a
   controller steered by the latest top-down focus, of the same controller steered by the
   first row of the ``focus`` observation's working memory when it matched the goal
   (``memory_controller``: it reads nothing but the observation a policy gets), of the
   same controller steered by the true target bearing (a privileged oracle) and of random
   actions.
4. ``cost``: µs per ``AttentionModel.step`` (and of it, the tracker's step) on readings
   recorded from a driving episode at 5 % noise, beside a raw ``AttentiveRescue-v0`` step
   with random actions, measured in alternating rounds of the same run (medians); with the
   tracker, also the tracker with version 0's defaults (``attention.VERSION_0_FIELDS``), the
   cost that version 1's is held to.
5. ``clutter`` (only when asked for): in the RL comparison's arena (8 m, 3 rubble pieces
   per 100 m², 5 % noise) with 1, 2, 3 and 5 distractors, the focus on target of the
   driving robot and the success of the memory, true-bearing and random controllers: how
   perception and the attended observation hold up as bodies are added.
6. ``motion`` (only when asked for): on ``perception.motion``'s scenes (a walker that stops
   and goes; a walker 0.3–0.9 m in front of a wall or rubble 2–5 m ahead), noise-free and at
   5 % noise, robot still and driving: the latency from each start of the walker to the
   goal's first judgement in its region (median, 90th percentile, share judged before it
   stops), the share of steps with a false moving label (a confirmed track labelled moving
   more than 1.5 m from every mover; and one inside the goal's band), the walker's recall as
   a moving track within 3.5 m, and the focus on it while in view.

The controllers, the episode records and the metrics are ``attentive_gym.perception``'s
(tested there); this script sets the configurations up, prints the tables and writes the CSV.

Every random draw is seeded: the same command prints the same numbers (the timings aside).
A configuration the installed package does not accept yet (an unknown env keyword) is
reported as unavailable. ``--config '{"free_space_evidence": true}'`` measures a candidate
setting: more ``AttentionConfig`` fields for every attended env. ``--csv`` also writes the
figures as a tidy table (one row per configuration and metric). Nothing is asserted: measure, don't guess.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import statistics
import time
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from attentive_gym._atomic import atomic_file
from attentive_gym.attention import VERSION_0_FIELDS, AttentionConfig, AttentionModel, Goal
from attentive_gym.attention import model as model_module
from attentive_gym.attention.tracking.tracker import Tracker
from attentive_gym.perception import motion
from attentive_gym.perception.bound import SEEN_BEAMS, make_bound_env
from attentive_gym.perception.controllers import (
    FocusController,
    RandomController,
    Wander,
    control_success,
    memory_controller,
    stand_still,
    true_bearing_controller,
)
from attentive_gym.perception.geometry import GRID, SIGHT_BEAMS, SIGHT_BEARING_DEG, VIEW_RANGE_M
from attentive_gym.perception.metrics import (
    TRACK_AGE_BINS_S,
    TRANSIENT_S,
    FocusRate,
    case_key,
    focus_after_turns,
    focus_by_track_age,
    focus_on_target,
    speed_metrics,
    target_cases,
)
from attentive_gym.perception.records import SETTLE_S, TARGET_CASES, TRACK_MATCH_M, record_episode
from attentive_gym.perception.settings import (
    CONTROL_ARENA,
    PERCEPTION_ARENA,
    PERCEPTION_TASK,
    VARIANT,
    make_attentive_env,
)
from attentive_gym.world import arena
from attentive_gym.wrappers import make_env
from call_timer import CallTimer

MODES = ("tracker", "window", "literal")
SECTIONS = ("speed", "focus", "control", "cost", "clutter", "motion")
DEFAULT_SECTIONS = ("speed", "focus", "control", "cost")
ROBOT_MODES = ("still", "driving")

USARSIM_NOISE_HALF_WIDTH = 0.05  # the usarsim profile's uniform noise: ±5 % of the reading


@dataclass(frozen=True)
class NoiseSetting:
    """A sensor noise configuration.

    Attributes:
        name: the label printed in the tables.
        env_kwargs: keyword arguments of the environment that select it.
        sigma_rel: the relative σ of one reading (dimensionless), given to the model as
            ``AttentionConfig.range_noise_rel``.
    """

    name: str
    env_kwargs: Mapping[str, Any]
    sigma_rel: float


NOISE_SETTINGS = (
    NoiseSetting("gauss 0", {"sensor_noise": 0.0}, 0.0),
    NoiseSetting("gauss 0.02", {"sensor_noise": 0.02}, 0.02),
    NoiseSetting("gauss 0.05", {"sensor_noise": 0.05}, 0.05),
    NoiseSetting("usarsim", {"sensor_profile": "usarsim"}, USARSIM_NOISE_HALF_WIDTH / math.sqrt(3.0)),
)
CONTROL_NOISE = ("gauss 0.05", "usarsim")
COST_NOISE = "gauss 0.05"

CLUTTER_ARENA = {"arena_size_m": 8.0, "rubble_per_100m2": 3.0}  # the RL comparison's (docs/results/rl.md)
CLUTTER_DISTRACTORS = (1, 2, 3, 5)
CLUTTER_NOISE = "gauss 0.05"

#: Episodes per row of the speed and focus sections (seeds 0..N−1, the goals in turn). The
#: target is in the laser's sight in only some of them, so a rate over 24 episodes moved by
#: 0.2 between seed ranges; 96 give intervals about ±0.05 wide.
EPISODES = 96
COST_RECORD_S = 30.0  # length of the driving episode whose readings the cost section replays

MOTION_NOISE = ("gauss 0", "gauss 0.05", "usarsim")
#: More ``AttentionConfig`` fields for every attended env of the run (``--config``: a candidate setting).
ATTENTION_FIELDS: dict[str, Any] = {}


# ===================================================================== environments
def make_raw_env(noise: NoiseSetting, **env_kwargs: Any):
    """The raw environment of the perception measurements' task (``PERCEPTION_TASK``; no model,
    no checker wrappers)."""
    return make_env("raw", task=PERCEPTION_TASK, **noise.env_kwargs, **env_kwargs)


# ===================================================================== sections
@dataclass
class Results:
    """Every figure of the run as tidy rows: section, mode, robot, noise, goal, metric, value
    (and distractors, in the clutter section; scene, in the motion section)."""

    rows: list[dict[str, Any]] = field(default_factory=list)

    def add(self, section: str, config: Mapping[str, str], metrics: Mapping[str, float], goal: str = "") -> None:
        """Add one row per metric of ``metrics`` for configuration ``config``."""
        for metric, value in metrics.items():
            self.rows.append({"section": section, **config, "goal": goal, "metric": metric, "value": value})


def _noise(name: str) -> NoiseSetting:
    return next(setting for setting in NOISE_SETTINGS if setting.name == name)


def _fmt(value: float, digits: int = 3) -> str:
    """A number for a table cell; an em dash for NaN."""
    if isinstance(value, (int, np.integer)):
        return str(value)
    return "—" if value is None or not math.isfinite(value) else f"{value:.{digits}f}"


def markdown_table(headers: list[str], rows: list[list[str]]) -> str:
    """A markdown table with ``headers`` and string cells ``rows``."""
    lines = ["| " + " | ".join(headers) + " |", "|" + "---|" * len(headers)]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines)


def perception_records(modes: Iterable[str], episodes: int, seconds: float, goals: tuple[Goal, ...]):
    """Record ``episodes`` episodes (seeds 0.., goals in turn) per mode, noise setting and
    robot mode. Yields ``(mode, noise name, robot, records or the error that made the
    configuration unavailable)``."""
    for mode in modes:
        for noise in NOISE_SETTINGS:
            try:
                env = make_attentive_env(
                    mode, noise.sigma_rel, VARIANT, ATTENTION_FIELDS, **noise.env_kwargs, **PERCEPTION_ARENA
                )
            except TypeError as error:
                for robot in ROBOT_MODES:
                    yield mode, noise.name, robot, error
                continue
            for robot, records in robot_records(env, episodes, seconds, goals):
                yield mode, noise.name, robot, records
            env.close()


def robot_records(env, episodes: int, seconds: float, goals: tuple[Goal, ...]):
    """Per robot mode, the ``record_episode`` of ``env`` on seeds ``0..episodes-1`` (the goals
    in turn; the robot standing still or wandering): yields ``(robot, records)``."""
    for robot in ROBOT_MODES:
        policy = (lambda seed: stand_still) if robot == "still" else Wander
        yield (
            robot,
            [record_episode(env, seed, goals[seed % len(goals)], policy(seed), seconds) for seed in range(episodes)],
        )


#: The label of the perfect-perception bound's rows, in the place of a mode.
BOUND = "perfect perception"


def bound_records(episodes: int, seconds: float, goals: tuple[Goal, ...]):
    """``perception_records`` of the perfect-perception bound (``perception.bound``): the same
    episodes (seeds, goals, policies, noise settings, arena), recorded from a raw environment
    whose steps feed the model with the true kinematics. Yields ``(noise name, robot, records
    or the error that made the configuration unavailable)``."""
    for noise in NOISE_SETTINGS:
        try:
            env = make_bound_env(noise.sigma_rel, ATTENTION_FIELDS, **noise.env_kwargs, **PERCEPTION_ARENA)
        except TypeError as error:
            for robot in ROBOT_MODES:
                yield noise.name, robot, error
            continue
        for robot, records in robot_records(env, episodes, seconds, goals):
            yield noise.name, robot, records
        env.close()


#: (column header, metric key) of the speed table and of the track table.
SPEED_COLUMNS = (
    ("steady pairs", "region_pairs"),
    ("median", "region_median_mps"),
    ("p90", "region_p90_mps"),
    ("RMSE", "region_rmse_mps"),
    ("transient pairs", "transient_region_pairs"),
    ("transient median", "transient_region_median_mps"),
    ("transient RMSE", "transient_region_rmse_mps"),
    ("static median m/s", "static_median_mps"),
    ("static p90 m/s", "static_p90_mps"),
    ("goal agreement", "goal_agreement_region"),
)
TRACK_COLUMNS = (
    ("matched pairs", "track_pairs"),
    ("unmatched", "track_unmatched_frac"),
    ("median", "track_median_mps"),
    ("p90", "track_p90_mps"),
    ("RMSE", "track_rmse_mps"),
    ("transient median", "transient_track_median_mps"),
    ("transient RMSE", "transient_track_rmse_mps"),
    ("goal agreement", "goal_agreement_track"),
    ("false moving labels", "false_label_steps"),
    ("within 5 m", "false_label_near_steps"),
    ("in the goal's range", "false_in_band_steps"),
)


def _focus_metrics(focus: FocusRate, in_sight_only: bool) -> dict[str, float]:
    """The CSV metrics of one goal's ``focus_on_target`` figure: the rate, its interval over
    the episodes, and the steps it counts (in view, or with ``in_sight_only`` in sight)."""
    name, steps = (
        ("focus_on_target_in_sight", "target_in_sight_steps")
        if in_sight_only
        else ("focus_on_target", "target_in_view_steps")
    )
    return {name: focus.rate, f"{name}_low": focus.low, f"{name}_high": focus.high, steps: focus.steps}


def _focus_cells(in_view, in_sight, goal_names) -> list[str]:
    """A focus table's cells per goal: focus on target in view [interval] (steps); in sight."""
    missing = FocusRate(math.nan, math.nan, math.nan, 0, 0)

    def cell(focus: FocusRate) -> str:
        return f"{_fmt(focus.rate)} [{_fmt(focus.low)}, {_fmt(focus.high)}] ({focus.steps})"

    return [f"{cell(in_view.get(goal, missing))}; {cell(in_sight.get(goal, missing))}" for goal in goal_names]


def _cells(metrics: Mapping[str, float], columns) -> list[str]:
    """The table cells of ``metrics`` for ``columns``: m/s to 2 decimals, fractions to 3."""
    return [_fmt(metrics[key], 2 if key.endswith("_mps") else 3) for _, key in columns]


def print_perception(results: Results, modes, episodes: int, seconds: float, sections) -> None:
    """Sections 1–3: speed error, static structure, goal classification, focus on target."""
    goals = tuple(arena.DEFAULT_TASK_GOALS)
    goal_names = [str(goal) for goal in goals]
    speed_rows, track_rows, focus_rows, case_rows, age_rows = [], [], [], [], []
    focus_by_setting: dict[tuple[str, str, str], dict[str, float]] = {}  # (mode, robot, noise) → goal → rate
    for mode, noise, robot, records in perception_records(modes, episodes, seconds, goals):
        config = {"mode": mode, "robot": robot, "noise": noise}
        label = [mode, robot, noise]
        if isinstance(records, Exception):
            note = f"unavailable ({type(records).__name__}: {records})"
            speed_rows.append(label + [note] + [""] * (len(SPEED_COLUMNS) - 1))
            focus_rows.append(label + [note] + [""] * (len(goal_names) - 1))
            continue
        metrics = speed_metrics(records)
        if "speed" in sections:
            results.add("speed", config, metrics)
        speed_rows.append(label + _cells(metrics, SPEED_COLUMNS))
        if "track_pairs" in metrics:
            track_rows.append(label + _cells(metrics, TRACK_COLUMNS))
        focus = focus_on_target(records)
        focus_by_setting[(mode, robot, noise)] = {goal: figure.rate for goal, figure in focus.items()}
        sight = focus_on_target(records, in_sight_only=True)
        for goal in focus:
            if "focus" in sections:
                results.add("focus", config, _focus_metrics(focus[goal], in_sight_only=False), goal=goal)
                results.add("focus", config, _focus_metrics(sight[goal], in_sight_only=True), goal=goal)
        focus_rows.append(label + _focus_cells(focus, sight, goal_names))
        cases = target_cases(records)
        if not math.isnan(cases[case_key(TARGET_CASES[0])]):
            after_turns = focus_after_turns(records)
            if "focus" in sections:
                results.add("focus", config, {**cases, **after_turns})
            case_rows.append(
                label
                + [_fmt(cases[case_key(case)], 3) for case in TARGET_CASES]
                + [_fmt(after_turns[key], 3) for key in after_turns]
            )
        by_age = focus_by_track_age(records)
        if by_age:
            if "focus" in sections:
                results.add("focus", config, by_age)
            rates = [key for key in by_age if key.startswith("focus_on_target_")]
            age_rows.append(
                label
                + [
                    f"{_fmt(by_age[key])} ({_fmt(by_age['steps_' + key[len('focus_on_target_') :]], 2)})"
                    for key in rates
                ]
            )
    bound_by_setting: dict[tuple[str, str], dict[str, float]] = {}  # (robot, noise) → goal → rate
    if "focus" in sections:
        for noise, robot, records in bound_records(episodes, seconds, goals):
            label = [BOUND, robot, noise]
            if isinstance(records, Exception):
                focus_rows.append(
                    label + [f"unavailable ({type(records).__name__}: {records})"] + [""] * (len(goal_names) - 1)
                )
                continue
            focus = focus_on_target(records)
            sight = focus_on_target(records, in_sight_only=True)
            bound_by_setting[(robot, noise)] = {goal: figure.rate for goal, figure in focus.items()}
            for goal in focus:
                config = {"mode": BOUND, "robot": robot, "noise": noise}
                results.add("focus", config, _focus_metrics(focus[goal], in_sight_only=False), goal=goal)
                results.add("focus", config, _focus_metrics(sight[goal], in_sight_only=True), goal=goal)
            focus_rows.append(label + _focus_cells(focus, sight, goal_names))
    header = ["mode", "robot", "noise"]
    print(
        f"\n### Perception ({episodes} episodes × {seconds:g} s per row, seeds 0..{episodes - 1}, "
        f"10 m arena, 3 distractors; goals in turn: {', '.join(goal_names)})"
    )
    if "speed" in sections:
        print(
            "\nSpeed of the region a mover lies in vs its true speed, |error| in m/s, over (mover, step) pairs "
            f"in front within {VIEW_RANGE_M:g} m for ≥ {SETTLE_S:g} s; transient = within {TRANSIENT_S:g} s after "
            "a turn; static = regions whose echoes all come from static structure; goal agreement = "
            "`goal.is_fulfilled` of the estimate equals that of the truth (steady pairs, speed goals).\n"
        )
        print(markdown_table(header + [name for name, _ in SPEED_COLUMNS], speed_rows))
        if track_rows:
            print(
                f"\nTrack speed (nearest confirmed track within {TRACK_MATCH_M:g} m of the mover) vs true speed, "
                "|error| in m/s, same pairs; unmatched = fraction of steady pairs without a track.\n"
            )
            print(markdown_table(header + [name for name, _ in TRACK_COLUMNS], track_rows))
    if "focus" in sections:
        print(
            "\nFocus on target: fraction of the steps with the target in front within "
            f"{VIEW_RANGE_M:g} m at which the focus is the target's region (steps in brackets); then the same "
            f"over the steps with the target in sight (also within {SIGHT_BEARING_DEG:g}° of the heading and on "
            f"≥ {SIGHT_BEAMS} laser beams); "
            f"chance = 1/{GRID.n_regions} = {1 / GRID.n_regions:.3f}. `{BOUND}`: the bound, the same model and "
            "readings with the true kinematics of the movers the laser sees on "
            f"≥ {SEEN_BEAMS} beams, on the same episodes.\n"
        )
        print(markdown_table(header + [f"`{g}`" for g in goal_names], focus_rows))
        bound_rows = _focus_relative_to_bound(results, focus_by_setting, bound_by_setting, goal_names)
        if bound_rows:
            print(
                "\nFocus on target relative to the perfect-perception bound of the same robot and noise: how much "
                "of what the model's selection achieves with true kinematics each mode's perception leaves.\n"
            )
            print(markdown_table(header + [f"`{g}`" for g in goal_names], bound_rows))
        relative_rows = _focus_relative_to_noise_free(results, focus_by_setting, goal_names)
        if relative_rows:
            print(
                f"\nFocus on target relative to the same mode and robot noise-free (`{NOISE_SETTINGS[0].name}`): "
                "how much of the model's own noise-free focus each noise setting leaves.\n"
            )
            print(markdown_table(header + [f"`{g}`" for g in goal_names], relative_rows))
        if case_rows:
            print(
                "\nWhy the focus is or is not on the target, as fractions of the same steps (both goals; "
                f"`TARGET_CASES`): perception misses it (hidden from the laser; seen but no confirmed track within "
                f"{TRACK_MATCH_M:g} m; a track younger or older than {SETTLE_S:g} s, but the goal is not judged to "
                "hold in the target's region), or the goal holds there and the selection goes elsewhere. "
                f"Then the focus on target within {TRANSIENT_S:g} s after the target turned, and at the other "
                "steps.\n"
            )
            print(
                markdown_table(
                    header + list(TARGET_CASES) + ["on target after a turn", "on target otherwise"], case_rows
                )
            )
        if age_rows:
            bins = [
                f"{lo:g}–{hi:g} s" if math.isfinite(hi) else f"≥ {lo:g} s"
                for lo, hi in zip(TRACK_AGE_BINS_S, TRACK_AGE_BINS_S[1:])
            ]
            print(
                "\nFocus on target by the age of the target's track (the confirmed track nearest to it within "
                f"{TRACK_MATCH_M:g} m), both goals; each group's share of the steps in brackets. A young track's "
                "speed is not yet known well enough to judge the goal.\n"
            )
            print(markdown_table(header + ["no track"] + bins, age_rows))


def _focus_relative_to_noise_free(
    results: Results, focus_by_setting: Mapping[tuple[str, str, str], Mapping[str, float]], goal_names: list[str]
) -> list[list[str]]:
    """Rows of the focus on target of every noisy setting divided by that of the same mode and
    robot noise-free (NaN where either is undefined), each ratio also added to ``results``
    as ``focus_over_noise_free``."""
    rows = []
    for (mode, robot, noise), rates in focus_by_setting.items():
        noise_free = focus_by_setting.get((mode, robot, NOISE_SETTINGS[0].name))
        if noise == NOISE_SETTINGS[0].name or noise_free is None:
            continue
        cells = []
        for goal in goal_names:
            reference = noise_free.get(goal, math.nan)
            ratio = rates.get(goal, math.nan) / reference if reference > 0.0 else math.nan
            results.add(
                "focus", {"mode": mode, "robot": robot, "noise": noise}, {"focus_over_noise_free": ratio}, goal=goal
            )
            cells.append(_fmt(ratio))
        rows.append([mode, robot, noise] + cells)
    return rows


def _focus_relative_to_bound(
    results: Results,
    focus_by_setting: Mapping[tuple[str, str, str], Mapping[str, float]],
    bound_by_setting: Mapping[tuple[str, str], Mapping[str, float]],
    goal_names: list[str],
) -> list[list[str]]:
    """Rows of the focus on target of every mode's setting divided by the perfect-perception
    bound's of the same robot and noise (NaN where either is undefined), each ratio also
    added to ``results`` as ``focus_over_bound``."""
    rows = []
    for (mode, robot, noise), rates in focus_by_setting.items():
        bound = bound_by_setting.get((robot, noise))
        if bound is None:
            continue
        cells = []
        for goal in goal_names:
            reference = bound.get(goal, math.nan)
            ratio = rates.get(goal, math.nan) / reference if reference > 0.0 else math.nan
            results.add("focus", {"mode": mode, "robot": robot, "noise": noise}, {"focus_over_bound": ratio}, goal=goal)
            cells.append(_fmt(ratio))
        rows.append([mode, robot, noise] + cells)
    return rows


def print_clutter(results: Results, modes, episodes: int, seconds: float, control_episodes: int) -> None:
    """Section 5: focus on target (robot driving) and controller success per distractor count."""
    goals = tuple(arena.DEFAULT_TASK_GOALS)
    noise = _noise(CLUTTER_NOISE)
    seeds = range(control_episodes)
    rows, case_rows = [], []
    for distractors in CLUTTER_DISTRACTORS:
        world = {**CLUTTER_ARENA, "num_distractors": distractors}
        raw = make_raw_env(noise, **world)
        oracle = control_success(raw, lambda env, seed: true_bearing_controller, seeds)
        random = control_success(raw, lambda env, seed: RandomController(env.action_space, seed), seeds)
        raw.close()
        for mode in modes:
            env = make_attentive_env(mode, noise.sigma_rel, VARIANT, ATTENTION_FIELDS, **noise.env_kwargs, **world)
            records = [
                record_episode(env, seed, goals[seed % len(goals)], Wander(seed), seconds) for seed in range(episodes)
            ]
            per_goal = [(f.rate * f.steps, f.steps) for f in focus_on_target(records).values() if f.steps]
            on, steps = sum(on for on, _ in per_goal), sum(n for _, n in per_goal)  # both goals together
            focus = on / steps if steps else math.nan
            env.close()
            focus_env = make_attentive_env(
                mode, noise.sigma_rel, "focus", ATTENTION_FIELDS, **noise.env_kwargs, **world
            )
            memory = control_success(focus_env, lambda env, seed: memory_controller, seeds)
            focus_env.close()
            memory_ratio = memory / oracle if oracle else math.nan
            cases = target_cases(records)
            results.add(
                "clutter",
                {"mode": mode, "robot": "driving", "noise": noise.name, "distractors": distractors},
                {"focus_on_target": focus, "target_in_view_steps": int(steps), **cases},
            )
            if not math.isnan(cases[case_key(TARGET_CASES[0])]):
                case_rows.append([str(distractors), mode] + [_fmt(cases[case_key(case)]) for case in TARGET_CASES])
            results.add(
                "clutter",
                {"mode": mode, "robot": "controller", "noise": noise.name, "distractors": distractors},
                {
                    "success_memory": memory,
                    "success_true_bearing": oracle,
                    "success_random": random,
                    "memory_over_true_bearing": memory_ratio,
                },
            )
            rows.append(
                [
                    str(distractors),
                    mode,
                    f"{_fmt(focus)} ({int(steps)})",
                    _fmt(memory, 2),
                    _fmt(oracle, 2),
                    _fmt(random, 2),
                    _fmt(memory_ratio, 2),
                ]
            )
    print(
        f"\n### Clutter (8 m arena, 3 rubble pieces per 100 m², {noise.name} noise; focus on target: "
        f"{episodes} episodes × {seconds:g} s, robot driving, both goals; "
        f"controllers: {control_episodes} episodes)\n"
    )
    print(
        markdown_table(
            [
                "distractors",
                "mode",
                "focus on target (steps)",
                "memory controller",
                "true bearing",
                "random",
                "memory / true bearing",
            ],
            rows,
        )
    )
    if case_rows:
        print("\nWhy the focus is or is not on the target (`TARGET_CASES`, as in the focus section), robot driving:\n")
        print(markdown_table(["distractors", "mode", *TARGET_CASES], case_rows))


def print_motion(results: Results, modes, episodes: int, seconds: float) -> None:
    """Section 6: motion seen at once (``perception.motion``): per scene, noise setting and robot
    mode, the onset latency of the walker's starts to the goal's first judgement, the false
    moving labels, the walker's recall as a moving track, and the focus on it."""
    rows = []
    for scene_name, scene in motion.SCENES.items():
        for noise in map(_noise, MOTION_NOISE):
            for robot in ROBOT_MODES:
                for mode in modes:
                    records = []
                    for seed in range(episodes):
                        env = make_attentive_env(
                            mode, noise.sigma_rel, VARIANT, ATTENTION_FIELDS, **noise.env_kwargs, scenario=scene(seed)
                        )
                        policy = stand_still if robot == "still" else Wander(seed)
                        records.append(motion.record_motion(env, seed, policy, seconds))
                        env.close()
                    figures = motion.motion_metrics(records)
                    config = {"mode": mode, "robot": robot, "noise": noise.name, "scene": scene_name}
                    results.add("motion", config, figures, goal=str(motion.GOAL))
                    rows.append(
                        [scene_name, noise.name, robot, mode, str(int(figures["starts"]))]
                        + [_fmt(figures[key], 2) for key in _MOTION_COLUMNS]
                    )
    print(
        f"\n### Motion seen at once ({episodes} episodes × {seconds:g} s per row, seeds 0..{episodes - 1}; "
        f"goal {motion.GOAL}; a false label: a confirmed track labelled moving > {motion.FALSE_LABEL_M} m from "
        "every mover)\n"
    )
    headers = ["scene", "noise", "robot", "mode", "starts", *_MOTION_COLUMNS.values()]
    print(markdown_table(headers, rows))


_MOTION_COLUMNS = {
    "latency_median_s": "latency median s",
    "latency_p90_s": "latency p90 s",
    "latency_median_scans": "latency median scans",
    "starts_judged": "starts judged",
    "false_label_steps": "false label steps",
    "false_in_band_steps": "false in band steps",
    "moving_recall": "moving recall",
    "focus_on_target": "focus on target",
}


def print_control(results: Results, modes, episodes: int) -> None:
    """Section 4: success of the focus and memory controllers, the true-bearing oracle and
    random actions."""
    seeds = range(episodes)
    rows = []
    for noise_name in CONTROL_NOISE:
        noise = _noise(noise_name)
        try:
            raw = make_raw_env(noise, **CONTROL_ARENA)
        except TypeError as error:
            rows += [[mode, noise_name, f"unavailable ({type(error).__name__})", "", "", ""] for mode in modes]
            continue
        oracle = control_success(raw, lambda env, seed: true_bearing_controller, seeds)
        random = control_success(raw, lambda env, seed: RandomController(env.action_space, seed), seeds)
        for mode in modes:
            env = make_attentive_env(
                mode, noise.sigma_rel, VARIANT, ATTENTION_FIELDS, **noise.env_kwargs, **CONTROL_ARENA
            )
            focus = control_success(env, lambda env, seed: FocusController(env.unwrapped.dt), seeds)
            memory = control_success(
                make_attentive_env(
                    mode, noise.sigma_rel, "focus", ATTENTION_FIELDS, **noise.env_kwargs, **CONTROL_ARENA
                ),
                lambda env, seed: memory_controller,
                seeds,
            )
            ratio = focus / oracle if oracle else math.nan
            memory_ratio = memory / oracle if oracle else math.nan
            results.add(
                "control",
                {"mode": mode, "robot": "controller", "noise": noise_name},
                {
                    "success_focus": focus,
                    "success_memory": memory,
                    "success_true_bearing": oracle,
                    "success_random": random,
                    "focus_over_true_bearing": ratio,
                    "memory_over_true_bearing": memory_ratio,
                },
            )
            rows.append(
                [
                    mode,
                    noise_name,
                    _fmt(focus, 2),
                    _fmt(memory, 2),
                    _fmt(oracle, 2),
                    _fmt(random, 2),
                    _fmt(ratio, 2),
                    _fmt(memory_ratio, 2),
                ]
            )
    print(
        f"\n### Steering controllers (8 m arena, 2 distractors, {episodes} episodes, seeds 0..{episodes - 1}; "
        "success = target reached before the time limit)\n"
    )
    print("The true-bearing and random controllers do not use the model: their rates are the same in every mode.\n")
    print(
        "The memory controller reads only the `focus` observation: the first row of its working memory when "
        "that body matched the goal.\n"
    )
    print(
        markdown_table(
            [
                "mode",
                "noise",
                "focus controller",
                "memory controller",
                "true bearing (oracle)",
                "random",
                "focus / true bearing",
                "memory / true bearing",
            ],
            rows,
        )
    )


def record_readings(seconds: float, seed: int = 0) -> tuple[list[tuple], Goal]:
    """``(t s, sonar (16,), laser (180,), odometry (2,))`` of every step of a wander in the raw
    env at ``COST_NOISE`` (10 m arena, 3 distractors), for ``seconds`` (s) or until the
    episode ends, and the episode's goal."""
    env = make_raw_env(_noise(COST_NOISE), **PERCEPTION_ARENA)
    obs, info = env.reset(seed=seed)
    policy = Wander(seed)
    readings = []
    while info["time_s"] < seconds - 1e-9:
        obs, _, terminated, truncated, info = env.step(policy(obs, info))
        readings.append((info["time_s"], obs["sonar"].copy(), obs["laser"].copy(), obs["odometry"].copy()))
        if terminated or truncated:
            break
    return readings, env.goal


def time_model_us(model: AttentionModel, readings: list[tuple]) -> tuple[float, float, float]:
    """Wall-clock µs per ``model.step`` over ``readings`` (the model is reset first); of it,
    per call of the compiled step ``attend_many`` (timed in a second pass, so that timing it
    does not slow the first); and per step of a separate ``Tracker`` of the same
    configuration fed the same readings (the model's tracker runs inside its one compiled
    step; 0 without a tracker)."""
    model.reset()
    start = time.perf_counter()
    outputs = [model.step(t, sonar, laser, odometry) for t, sonar, laser, odometry in readings]
    elapsed = time.perf_counter() - start
    compiled = _compiled_step_us(model, readings)
    if model.config.kinematics != "tracker":
        return elapsed / len(readings) * 1e6, compiled, 0.0
    tracker = Tracker(model.config)
    wanted_speed = model.model_state.field("wanted_speed")
    channels = outputs[0]._sources[1].shape[0]
    rates, speeds, moving = np.empty(channels), np.empty(channels), np.empty(channels, np.bool_)
    inside, previous_t = 0.0, None
    for (t, _, _, odometry), output in zip(readings, outputs):
        clipped, valid = output._sources[1], output._sources[2]  # the readings the model's tracker took
        dt = 0.0 if previous_t is None else t - previous_t
        previous_t = t
        begin = time.perf_counter()
        tracker.step(
            t,
            dt,
            (float(odometry[0]), float(odometry[1])),
            True,
            True,
            clipped,
            valid,
            rates,
            speeds,
            moving,
            wanted_speed,
        )
        inside += time.perf_counter() - begin
    return elapsed / len(readings) * 1e6, compiled, inside / len(readings) * 1e6


def _compiled_step_us(model: AttentionModel, readings: list[tuple]) -> float:
    """µs per call of the model's compiled step (``attend_many``, with numba's dispatch of its
    arguments) over ``readings``, the model reset first: the part of ``model.step`` that no
    Python around it can save."""
    model.reset()
    with CallTimer(model_module, "attend_many") as compiled:
        for t, sonar, laser, odometry in readings:
            model.step(t, sonar, laser, odometry)
    return compiled.seconds / len(readings) * 1e6


def time_env_us(env, actions: list[np.ndarray]) -> float:
    """Wall-clock µs per ``env.step`` over ``actions``, resets excluded."""
    env.reset(seed=0)
    elapsed = 0.0
    for action in actions:
        start = time.perf_counter()
        _, _, terminated, truncated, _ = env.step(action)
        elapsed += time.perf_counter() - start
        if terminated or truncated:
            env.reset()
    return elapsed / len(actions) * 1e6


#: The cost section's label of the tracker with version 0's defaults, timed beside the others.
VERSION_0_TRACKER = "tracker (version 0)"


def print_cost(results: Results, modes, rounds: int) -> None:
    """Section 4: µs per model step per mode beside a raw env step, medians of alternating rounds;
    with the tracker, also the tracker with version 0's defaults (``VERSION_0_TRACKER``), the
    cost the model's version 1 is held to."""
    readings, goal = record_readings(COST_RECORD_S)
    noise_rel = _noise(COST_NOISE).sigma_rel
    configs = {mode: {"kinematics": mode, "range_noise_rel": noise_rel, **ATTENTION_FIELDS} for mode in modes}
    if "tracker" in modes:
        configs[VERSION_0_TRACKER] = {"kinematics": "tracker", "range_noise_rel": noise_rel, **VERSION_0_FIELDS}
    models = {}
    for mode, fields in configs.items():
        models[mode] = AttentionModel(AttentionConfig(**fields))  # as make_attentive_env's
        models[mode].set_goals(goal)
    env = make_raw_env(_noise(COST_NOISE), **PERCEPTION_ARENA)
    env.action_space.seed(0)
    actions = [env.action_space.sample() for _ in readings]
    parts = ("", " compiled", " tracker")
    times: dict[str, list[float]] = {f"{mode}{part}": [] for mode in models for part in parts}
    times["env"] = []
    for round_index in range(rounds + 1):  # round 0 warms up (numba compiles) and is dropped
        figures = {}
        for mode, model in models.items():
            for part, value in zip(parts, time_model_us(model, readings)):
                figures[f"{mode}{part}"] = value
        figures["env"] = time_env_us(env, actions)
        if round_index:
            for name, value in figures.items():
                times[name].append(value)
    env_us = statistics.median(times["env"])
    rows = []
    for mode in models:
        model_us, compiled_us = statistics.median(times[mode]), statistics.median(times[f"{mode} compiled"])
        metrics = {
            "model_step_us": model_us,
            "env_step_us": env_us,
            "model_over_env": model_us / env_us,
            "compiled_step_us": compiled_us,
            "compiled_over_env": compiled_us / env_us,
        }
        tracker_cells = ["—", "—"]
        if models[mode]._tracker is not None:
            tracker_us = statistics.median(times[f"{mode} tracker"])
            metrics.update(tracker_step_us=tracker_us, tracker_over_env=tracker_us / env_us)
            tracker_cells = [f"{tracker_us:.1f}", f"{tracker_us / env_us:.2f}"]
        results.add("cost", {"mode": mode, "robot": "driving", "noise": COST_NOISE}, metrics)
        rows.append(
            [
                mode,
                f"{model_us:.1f}",
                f"{compiled_us:.1f}",
                tracker_cells[0],
                f"{env_us:.1f}",
                f"{model_us / env_us:.2f}",
                f"{compiled_us / env_us:.2f}",
                tracker_cells[1],
            ]
        )
    print(
        f"\n### Model step cost (readings of a {len(readings)}-step driving episode at 5 % noise; "
        f"medians of {rounds} alternating rounds)\n"
    )
    print(
        markdown_table(
            [
                "mode",
                "model step µs",
                "of which the compiled step µs",
                "the tracker alone µs",
                "raw env step µs",
                "model / env step",
                "compiled step / env step",
                "tracker / env step",
            ],
            rows,
        )
    )


def write_csv(path: Path, rows: list[dict[str, Any]]) -> None:
    """Write the tidy ``rows`` to ``path`` atomically (a temporary file, then ``os.replace``)."""
    fields = ["section", "mode", "robot", "noise", "goal", "metric", "value", "distractors"]
    fields += ["scene"] if any("scene" in row for row in rows) else []  # the motion section's own column
    with atomic_file(path) as file:
        writer = csv.DictWriter(file, fieldnames=fields, restval="")
        writer.writeheader()
        writer.writerows(rows)


def _choices(text: str, allowed: tuple[str, ...]) -> list[str]:
    """A comma-separated list of names, each one of ``allowed``."""
    names = [name.strip() for name in text.split(",") if name.strip()]
    unknown = [name for name in names if name not in allowed]
    if unknown or not names:
        raise argparse.ArgumentTypeError(f"unknown or no names {unknown}; allowed: {', '.join(allowed)}")
    return names


def _attention_fields(text: str) -> dict[str, Any]:
    """``--config``: a JSON object of ``AttentionConfig`` fields, each checked by building one."""
    try:
        fields = json.loads(text)
    except json.JSONDecodeError as err:
        raise argparse.ArgumentTypeError(f"not JSON: {err}") from None
    if not isinstance(fields, dict):
        raise argparse.ArgumentTypeError(f"a JSON object of AttentionConfig fields, got {text!r}")
    try:
        AttentionConfig(**fields)
    except (TypeError, ValueError) as err:
        raise argparse.ArgumentTypeError(str(err)) from None
    return fields


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--modes", type=lambda s: _choices(s, MODES), default=list(MODES))
    parser.add_argument("--episodes", type=int, default=EPISODES, help="episodes per row of sections speed and focus")
    parser.add_argument("--seconds", type=float, default=20.0, help="length of those episodes (s)")
    parser.add_argument("--control-episodes", type=int, default=40, help="episodes per controller (seeds 0..N-1)")
    parser.add_argument("--rounds", type=int, default=5, help="timing rounds of the cost section")
    parser.add_argument(
        "--sections",
        type=lambda s: _choices(s, SECTIONS),
        default=list(DEFAULT_SECTIONS),
        help=f"comma-separated, of {', '.join(SECTIONS)} (default: {','.join(DEFAULT_SECTIONS)})",
    )
    parser.add_argument(
        "--config", type=_attention_fields, default={}, help="more AttentionConfig fields, a JSON object"
    )
    parser.add_argument("--csv", type=Path, default=None, help="also write the figures as a tidy CSV")
    args = parser.parse_args(argv)
    ATTENTION_FIELDS.update(args.config)
    if args.config:
        print(f"AttentionConfig fields beyond the defaults: {json.dumps(args.config, sort_keys=True)}")
    start = time.perf_counter()
    results = Results()
    if {"speed", "focus"} & set(args.sections):
        print_perception(results, args.modes, args.episodes, args.seconds, args.sections)
    if "control" in args.sections:
        print_control(results, args.modes, args.control_episodes)
    if "cost" in args.sections:
        print_cost(results, args.modes, args.rounds)
    if "clutter" in args.sections:
        print_clutter(results, args.modes, args.episodes, args.seconds, args.control_episodes)
    if "motion" in args.sections:
        print_motion(results, args.modes, args.episodes, args.seconds)
    if args.csv is not None:
        write_csv(args.csv, results.rows)
        print(f"\nwrote {len(results.rows)} rows to {args.csv}")
    print(f"\n(run time {time.perf_counter() - start:.0f} s)")


if __name__ == "__main__":
    main()
