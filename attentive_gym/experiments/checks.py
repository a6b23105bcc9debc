"""The criteria of docs/model.md §9 as named pass/fail checks with measured values.

- ``Check``: one criterion's outcome (name, the criterion in words, passed, measured).
- ``check_experiment(result)``: the checks of the result's experiment, in order.
- ``CHECKS``: experiment name → the names of its checks (for tables and tests).

Every check reads an ``ExperimentResult``: the model's trace plus the noise-free truth of
the run (where the robots are, which sonar sees which robot). Ground-truth "speed" is the
quantity the run's kinematics mode estimates, over its window of the last K scans (K =
``slope_samples``; K = 2 for "literal"; a scan per step unless the sensor profile scans
less often):

- "window", "literal": the |radial speed| of a robot's centre over the window, what the
  least-squares (or two-sample) range rate estimates (docs/model.md §3);
- "tracker": the robot's full 2-D speed over the window (its displacement over the
  window's time), what the tracks' constant-velocity filters estimate (docs/model.md §10);
- "truth" (the perfect-perception bound, whose model runs as the tracker): the robot's
  instantaneous speed at the step, which is what it is fed; its regions and windows are
  the tracker's.

Which regions "see" a robot (its region(s), where the model puts its motion) follows the
mode: with "window" and "literal", every region whose sonar's echo comes from it (each
sonar measures its own range rate); with the tracker, while the laser sees the robot, the
one region of its centre's bearing (its track's centroid's region: a tracked body's
motion goes to one region; the laser reaches 20 m, the sonar 5 m), and otherwise the
regions whose sonar sees it (the sonar filters). A robot is "steady" in a region when the
region saw it at every step of the window. Exp02's criterion is about the target's entry
into *sonar* range and reads the sonar alone. Times are in seconds; regions are the 8
front-sonar regions, named in messages by the paper's sonars with their 0-based index,
e.g. "s4 (region 3)".
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

import numpy as np

from attentive_gym.attention import ORIGIN_CODES, AttentionConfig
from attentive_gym.attention.config import MAP_NAMES
from attentive_gym.attention.regions import nearest_sonar, region_name
from attentive_gym.experiments.registry import get_experiment
from attentive_gym.experiments.result import ExperimentResult
from attentive_gym.experiments.runner import TRUTH, experiment_model, run_experiment

__all__ = ["Check", "CHECKS", "check_experiment", "pass_rates"]

_TD, _BU = ORIGIN_CODES["top-down"], ORIGIN_CODES["bottom-up"]
_F1, _F3, _F4 = MAP_NAMES.index("F1"), MAP_NAMES.index("F3"), MAP_NAMES.index("F4")
_S4 = 3  # region of sonar s4 (+10°), where the paper's single targets are
_EPS = 1e-9
#: The bottom-up course's phases (s) and the top-down onset (s), docs/model.md §7 defaults.
_PRE, _EXC, _COURSE, _TD_ONSET = 0.15, 0.30, 0.60, 0.20
#: Below this true speed (m/s) a robot counts as turning round or stopped, not moving
#: (Exp03; Exp05's "leaves").
_MOVING_MPS = 0.3


@dataclass(frozen=True)
class Check:
    """The outcome of one criterion.

    Attributes:
        name: a short identifier, e.g. "first_winner_is_s4".
        criterion: the criterion of docs/model.md §9 it tests, in words.
        passed: whether the run meets it.
        measured: what was measured, in words with numbers (s, m/s, gain units).
    """

    name: str
    criterion: str
    passed: bool
    measured: str


# --- quantities of a run ------------------------------------------------------------------
class _Run:
    """Arrays of one result, with the helpers the checks share."""

    def __init__(self, result: ExperimentResult) -> None:
        self.result = result
        tr = result.trace
        self.trace, self.t, self.focus, self.fired, self.origin = tr, tr.t, tr.focus, tr.fired, tr.origin
        self.dt = float(tr.t[1] - tr.t[0])
        self.kinematics = str(tr.config.get("kinematics", "window"))
        self.tracked = self.kinematics == "tracker"
        self.truth = result.kinematics == TRUTH
        samples = 2 if self.kinematics == "literal" else int(tr.config["slope_samples"])
        # the window ending at step k: from the scan samples - 1 scans before the latest one
        # (the tracker reads the laser's scans, the range-rate modes the sonar's)
        times = result.laser_time_s if self.tracked else result.sonar_time_s
        steps = np.arange(len(tr.t))
        scan = np.r_[True, np.diff(times) > 0]
        scan_steps = np.flatnonzero(scan)
        self.latest = np.maximum.accumulate(np.where(scan, steps, 0))  # (T,) step of the latest scan
        index = np.searchsorted(scan_steps, self.latest)
        self.window_start = scan_steps[np.maximum(index - (samples - 1), 0)]  # (T,)
        self.window_full = index >= samples - 1  # (T,): the window holds its K scans
        self.positions = result.mover_positions  # (T, K, 2) true centres (m)
        self.ranges = np.linalg.norm(result.mover_positions, axis=2)  # (T, K) true centre ranges (m)
        # (T, K, 8): region n sees robot i (see the module docstring)
        self.sonar_sees = result.sees
        self.sees = result.sees
        if self.tracked:
            x, y = result.mover_positions[..., 0], result.mover_positions[..., 1]
            bearing = np.arctan2(y, x)
            in_laser = result.laser_sees & (np.abs(bearing) <= np.pi / 2)
            centre = nearest_sonar(bearing)[..., None] == np.arange(result.sees.shape[2])
            self.sees = np.where(in_laser[..., None], centre, result.sees)
        self.seen = self.sees.any(axis=2)  # (T, K): the model's motion sensors see the robot

    def steps(self, seconds: float) -> int:
        """A duration (s) in whole steps."""
        return int(round(seconds / self.dt))

    def mover(self, name: str) -> int:
        return self.result.mover_names.index(name)

    def motion_start(self, i: int) -> int:
        """First step at which robot i has left its start position."""
        moved = np.linalg.norm(self.result.mover_positions[:, i] - self.result.mover_positions[0, i], axis=1) > 1e-6
        return int(np.argmax(moved)) if moved.any() else len(self.t)

    def last_motion(self) -> int:
        """Last step at which any robot moved."""
        step = np.linalg.norm(np.diff(self.result.mover_positions, axis=0), axis=2).max(axis=1) > 1e-6
        return int(np.flatnonzero(step)[-1]) + 1 if step.any() else 0

    def speed(self, i: int, k: int) -> float:
        """Robot i's true speed over the window ending at step k (m/s): its |radial speed|,
        or with the tracker its 2-D speed; with the truth its speed at step k (see the module
        docstring)."""
        if self.truth:
            return float(np.linalg.norm(self.result.mover_velocities[k, i]))
        lo, hi = int(self.window_start[k]), int(self.latest[k])
        if self.tracked:
            moved = float(np.linalg.norm(self.positions[hi, i] - self.positions[lo, i]))
        else:
            moved = abs(self.ranges[hi, i] - self.ranges[lo, i])
        return moved / max((hi - lo) * self.dt, self.dt)

    def steady(self, i: int, k: int) -> bool:
        """Robot i was seen (``seen``) at every step of the window ending at k."""
        return bool(self.window_full[k]) and bool(self.seen[self.window_start[k] : k + 1, i].all())

    def regions_seeing(self, i: int, k: int) -> set[int]:
        """Regions that see robot i at step k (``sees``)."""
        return set(np.flatnonzero(self.sees[k, i]).tolist())

    def sonar_regions(self, i: int, k: int) -> set[int]:
        """Regions whose sonar sees robot i at step k."""
        return set(np.flatnonzero(self.sonar_sees[k, i]).tolist())

    def regions_steady(self, i: int, k: int) -> set[int]:
        """Regions that saw robot i at every step of the window ending at k."""
        if not self.window_full[k]:
            return set()
        return set(np.flatnonzero(self.sees[self.window_start[k] : k + 1, i].all(axis=0)).tolist())

    def fires(self) -> list[tuple[int, int, int]]:
        """(step, region, origin code) of every fire."""
        return [(int(k), int(self.focus[k]), int(self.origin[k])) for k in np.flatnonzero(self.fired)]

    def refractory(self, region: int, k: int) -> bool:
        """Region's latest bottom-up course is in its inhibition-of-return phase at step k."""
        starts = [s for s, j, o in self.fires() if j == region and o == _BU and s <= k]
        return bool(starts) and _EXC < self.t[k] - self.t[starts[-1]] <= _COURSE + _EPS


def _check(name: str, criterion: str, passed: bool, measured: str) -> Check:
    return Check(name, criterion, bool(passed), measured)


def _named(regions) -> str:
    """Regions (0-based indices) in words, e.g. "s3 (region 2), s6 (region 5)", or "none"."""
    return ", ".join(region_name(j, with_index=True) for j in regions) or "none"


def _refire_check(run: _Run, regions: set[int] | None = None) -> Check:
    gaps = {}
    for k, j, _ in run.fires():
        if regions is None or j in regions:
            gaps.setdefault(j, []).append(run.t[k])
    shortest = min((b - a for times in gaps.values() for a, b in zip(times, times[1:])), default=np.inf)
    where = "s4" if regions == {_S4} else "a region"
    return _check(
        "no_refire_within_600ms",
        f"{where} does not fire again within 600 ms",
        shortest > _COURSE + _EPS,
        f"shortest gap between fires at one region {shortest:.2f} s",
    )


def _ior_shown(run: _Run, k: int, j: int) -> bool:
    tau = run.t - run.t[k]
    phase = (tau > _EXC + _EPS) & (tau <= _COURSE + _EPS)
    return bool(phase.any()) and float(run.trace.M[phase, j].min()) < 1.0


# --- Exp01 ------------------------------------------------------------------------------
def _exp01(run: _Run) -> list[Check]:
    start = run.motion_start(0)
    M = run.trace.M[:, _S4]
    focused = np.flatnonzero(run.focus >= 0)
    first = int(focused[0]) if focused.size else None
    checks = [
        _check(
            "first_winner_is_s4",
            f"the first winner is {_named([_S4])}, a few (<= 5) steps after motion starts",
            first is not None and run.focus[first] == _S4 and 0 <= first - start <= 5,
            "no winner"
            if first is None
            else f"first winner {_named([run.focus[first]])} at {run.t[first]:.2f} s, "
            f"motion starts at {run.t[start]:.2f} s",
        )
    ]
    s4_fires = [k for k, j, _ in run.fires() if j == _S4]
    if s4_fires:
        tau = run.t - run.t[s4_fires[0]]
        pre = (tau >= 0) & (tau <= _PRE + _EPS)
        exc = (tau > _PRE + _EPS) & (tau <= _EXC + _EPS)
        ior = (tau > _EXC + _EPS) & (tau <= _COURSE + _EPS)
        ok = np.all(np.abs(M[pre] - 1) < _EPS) and np.all(M[exc] > 1) and np.all(M[ior] < 1)
        measured = (
            f"course at {run.t[s4_fires[0]]:.2f} s: M(s4) in [{M[pre].min():.2f}, {M[pre].max():.2f}] for 0-150 ms, "
            f"[{M[exc].min():.2f}, {M[exc].max():.2f}] for 150-300 ms, [{M[ior].min():.2f}, {M[ior].max():.2f}] "
            "for 300-600 ms"
        )
    else:
        ok, measured = False, "s4 never fires"
    checks.append(
        _check("s4_course_shape", "M at s4 shows 150 ms of nothing, 150 ms above 1, 300 ms below 1", ok, measured)
    )
    checks.append(_refire_check(run, {_S4}))
    static = run.last_motion()
    late = [run.t[k] for k, _, _ in run.fires() if k > static]
    checks.append(
        _check(
            "quiet_once_static",
            "nothing fires once the scene is static",
            not late and static < len(run.t) - run.steps(1.0),
            f"scene static from {run.t[min(static, len(run.t) - 1)]:.2f} s; {len(late)} fires after",
        )
    )
    far = sorted({int(j) for j in run.focus if j >= 0 and abs(j - _S4) > 1})
    checks.append(
        _check(
            "far_regions_never_win",
            "regions more than one away from s4 never win",
            not far,
            f"far regions that won: {_named(far)}",
        )
    )
    return checks


# --- Exp02 ------------------------------------------------------------------------------
def _exp02(run: _Run) -> list[Check]:
    start = run.motion_start(0)
    before = [k for k, _, _ in run.fires() if k < start]
    checks = [
        _check(
            "static_scene_fires",
            "the static scene already fires (laser discrepancy)",
            bool(before),
            f"{len(before)} fires before the target moves at {run.t[start]:.2f} s"
            + (f", the first at {run.t[before[0]]:.2f} s" if before else ""),
        )
    ]
    early = sorted({j for k, j, _ in run.fires() if run.t[k] < 3.0})
    checks.append(
        _check(
            "ior_visits_several_regions",
            "the focus visits several (>= 3) regions in the first 3 s",
            len(early) >= 3,
            f"regions fired in the first 3 s: {_named(early)}",
        )
    )
    checks.append(_refire_check(run))
    seen = np.flatnonzero(run.sonar_sees[:, 0].any(axis=1))
    if not seen.size:
        ok, measured = False, "the target never enters a front sonar's cone"
    elif seen[0] == 0:
        ok, measured = (
            False,
            (
                f"the target starts inside the cone(s) of {_named(sorted(run.sonar_regions(0, 0)))} "
                "(it must start outside them)"
            ),
        )
    else:
        k = int(seen[0])
        j = min(run.sonar_regions(0, k))
        F3 = run.trace.F[:, _F3, j]
        window = run.focus[k : k + run.steps(_COURSE) + 2]
        drawn = np.flatnonzero(window == j)
        ok = F3[k] > F3[k - 1] and drawn.size > 0
        measured = f"enters the cone of {_named([j])} at {run.t[k]:.2f} s, F3 {F3[k - 1]:.2f} -> {F3[k]:.2f}, " + (
            f"focus there after {drawn[0] * run.dt:.2f} s" if drawn.size else "focus not drawn within 650 ms"
        )
    checks.append(
        _check(
            "sonar_entry_draws_focus",
            "the target's entry into sonar range raises F3 in its region and draws the focus there",
            ok,
            measured,
        )
    )
    return checks


# --- Exp03 ------------------------------------------------------------------------------
def _exp03(run: _Run) -> list[Check]:
    weights = run.result.experiment.weights
    start = min(run.motion_start(i) for i in range(len(run.result.mover_names)))
    early = [k for k in range(start) if run.focus[k] >= 0]
    from_f1 = [
        k
        for k in early
        if weights["F1"] * run.trace.F[k, _F1, run.focus[k]] > weights["F3"] * run.trace.F[k, _F3, run.focus[k]]
    ]
    checks = [
        _check(
            "static_winners_from_F3",
            "before the robots move, every winner comes from F3",
            early and not from_f1,
            f"{len(early)} steps with a focus before {run.t[start]:.2f} s, {len(from_f1)} led by F1",
        )
    ]
    considered = failed = 0
    first_fail = None
    for k in range(len(run.t)):
        movers = [i for i in range(len(run.result.mover_names)) if run.steady(i, k) and run.speed(i, k) >= _MOVING_MPS]
        if not movers:
            continue
        regions = set().union(*(run.regions_steady(i, k) for i in movers))
        if not regions:
            continue
        considered += 1
        winner = int(run.trace.L[k].argmax())
        if winner not in regions and not all(run.refractory(j, k) for j in regions):
            failed += 1
            first_fail = first_fail if first_fail is not None else k
    checks.append(
        _check(
            "moving_robot_dominates_L",
            "once a robot moves in range its region dominates L except when refractory",
            considered and not failed,
            f"{considered} steps with a robot moving in range, {failed} where another region led L"
            + (f" (first at {run.t[first_fail]:.2f} s)" if first_fail is not None else ""),
        )
    )
    fires = run.fires()
    top_down = sum(o != _BU for _, _, o in fires)
    no_ior = [run.t[k] for k, j, _ in fires if run.t[k] + _COURSE <= run.t[-1] and not _ior_shown(run, k, j)]
    checks.append(
        _check(
            "bottom_up_with_ior",
            "winners are bottom-up and show inhibition of return",
            fires and not top_down and not no_ior,
            f"{len(fires)} fires, {top_down} not bottom-up, {len(no_ior)} without M < 1 at 300-600 ms",
        )
    )
    checks.append(_refire_check(run))
    return checks


# --- Exp04 ------------------------------------------------------------------------------
def _exp04(run: _Run) -> list[Check]:
    goal = run.result.experiment.goals[0]
    F4 = run.trace.F[:, _F4]
    holds = [k for k in range(len(run.t)) if run.regions_steady(0, k) and goal.is_fulfilled(run.speed(0, k))]
    misses = [k for k in holds if not np.all(F4[k, sorted(run.regions_steady(0, k))] == 1.0)]
    checks = [
        _check(
            "F4_is_1_while_goal_holds",
            "F4 is 1 in the target's region(s) while the goal holds",
            holds and not misses,
            f"goal holds at {len(holds)} steps, F4 < 1 at {len(misses)} of them",
        )
    ]
    at_target = [(k, j, o) for k, j, o in run.fires() if j in run.regions_seeing(0, k)]
    bottom_up = [run.t[k] for k, _, o in at_target if o != _TD]
    checks.append(
        _check(
            "winners_top_down",
            "the target's winners are top-down",
            at_target and not bottom_up,
            f"{len(at_target)} fires at the target, {len(bottom_up)} bottom-up",
        )
    )
    low = float(run.trace.M.min())
    k_low, j_low = np.unravel_index(int(np.argmin(run.trace.M)), run.trace.M.shape)
    checks.append(
        _check(
            "no_ior",
            "no inhibition of return (M never below 1)",
            low >= 1.0 - _EPS,
            f"min M = {low:.3f}" + (f" ({_named([j_low])} at {run.t[k_low]:.2f} s)" if low < 1.0 - _EPS else ""),
        )
    )
    checks.extend(_top_down_timing(run, [(k, j) for k, j, o in at_target if o == _TD]))
    checks.append(_combined_beats_single(run, holds))
    return checks


def _top_down_timing(run: _Run, td_fires: list[tuple[int, int]]) -> list[Check]:
    if not td_fires:
        return [
            _check("M_rises_within_onset", "M rises within 200 ms + a step of the fire", False, "no top-down fire"),
            _check(
                "release_within_two_steps",
                "the enhancement vanishes within two steps of the goal's end",
                False,
                "no top-down fire",
            ),
        ]
    k, j = td_fires[0]
    M, F4 = run.trace.M[:, j], run.trace.F[:, _F4, j]
    risen = np.flatnonzero(M[k:] > 1.0)
    delay = risen[0] * run.dt if risen.size else np.inf
    rise = _check(
        "M_rises_within_onset",
        "M rises within 200 ms + a step of the fire",
        delay <= _TD_ONSET + run.dt + _EPS,
        f"M > 1 at {_named([j])} {delay:.2f} s after the fire",
    )
    ends = np.flatnonzero(F4[k:] < 1.0)
    if not ends.size or k + ends[0] + 2 >= len(run.t):
        return [
            rise,
            _check(
                "release_within_two_steps",
                "the enhancement vanishes within two steps of the goal's end",
                False,
                "the goal never stops holding",
            ),
        ]
    end = k + int(ends[0])
    left = float(M[end + 2] - 1.0)
    return [
        rise,
        _check(
            "release_within_two_steps",
            "the enhancement vanishes within two steps of the goal's end",
            left < 0.01,
            f"goal ends at {run.t[end]:.2f} s; two steps later M - 1 = {left:.4f}",
        ),
    ]


def _combined_beats_single(run: _Run, holds: list[int]) -> Check:
    """Replay the readings with F1 alone and F4 alone and compare L at the target's region."""
    experiment = run.result.experiment
    singles = []
    for name in experiment.weights:
        singles.append(_replayed_L(run.result, {name: experiment.weights[name]}))
    best_single = np.maximum(*singles)[:, _S4]
    both = run.trace.L[:, _S4]
    steps = np.asarray(holds, dtype=int)
    wins = int(np.sum(both[steps] > best_single[steps])) if steps.size else 0
    return _check(
        "combined_L_exceeds_single",
        "L with F1 + F4 exceeds L with either alone (while the goal holds)",
        steps.size and wins == steps.size,
        f"at s4, L(F1+F4) > max(L(F1), L(F4)) at {wins} of {steps.size} steps"
        + (f"; median ratio {np.median(both[steps] / np.maximum(best_single[steps], _EPS)):.2f}" if steps.size else ""),
    )


def _replayed_L(result: ExperimentResult, weights: Mapping[str, float]) -> np.ndarray:
    """``(T, J)`` L of the run's model replayed on its readings (and, for ``TRUTH``, its
    truth) with ``weights`` in place of the experiment's; the experiment's goals (Exp04 has
    no goal changes)."""
    model = experiment_model(AttentionConfig.from_dict(result.trace.config), result.kinematics)
    model.set_weights(weights)
    model.set_goals(*result.experiment.goals)
    trace, L = result.trace, []
    for k, t in enumerate(trace.t):
        times = {"sonar_time_s": result.sonar_time_s[k], "laser_time_s": result.laser_time_s[k]}
        inputs = times if result.scan_times_given else {}
        if result.kinematics == TRUTH:
            inputs["truth"] = result.true_scene(k)
        L.append(model.step(t, trace.O1[k], trace.O2[k], **inputs).L)
    return np.stack(L)


# --- Exp05 ------------------------------------------------------------------------------
def _exp05(run: _Run) -> list[Check]:
    experiment = run.result.experiment
    fast, slow = run.mover("fast"), run.mover("slow")
    goal = experiment.goals[0]
    settle = run.steps(_TD_ONSET) + 2
    change_steps = [int(np.argmax(run.result.goal_index == n + 1)) for n in range(len(experiment.goal_changes))]
    considered, lost = 0, []
    for k in range(len(run.t)):
        after_change = any(0 <= k - c < settle for c in change_steps)
        if run.result.goal_index[k] and experiment.goals_at(run.t[k]) != experiment.goals or after_change:
            continue
        if run.steady(fast, k) and goal.is_fulfilled(run.speed(fast, k)):
            considered += 1
            if run.focus[k] not in run.regions_seeing(fast, k):
                lost.append(k)
    checks = [
        _check(
            "faster_holds_focus",
            "the faster robot holds the focus while present (and meeting the goal)",
            considered and not lost,
            f"{considered} steps, focus elsewhere at {len(lost)}"
            + (f" (first at {run.t[lost[0]]:.2f} s)" if lost else ""),
        )
    ]
    # the fast robot leaves when it stops being seen moving: it leaves sonar range moving,
    # and (tracker) stops in the laser's view at the end of its path
    seen_fast = np.flatnonzero([run.seen[k, fast] and run.speed(fast, k) >= _MOVING_MPS for k in range(len(run.t))])
    leave = int(seen_fast[-1]) + 1 if seen_fast.size else None
    if leave is None or leave >= len(run.t) or not run.seen[leave, slow]:
        ok, measured = False, "the slower robot is not in range when the faster one leaves"
    else:
        later = [k for k in range(leave, len(run.t)) if run.focus[k] in run.regions_seeing(slow, k)]
        delay = (later[0] - leave) * run.dt if later else np.inf
        ok = delay <= _TD_ONSET + 2 * run.dt + _EPS
        measured = f"faster robot leaves at {run.t[leave]:.2f} s; slower one wins {delay:.2f} s later"
    checks.append(
        _check(
            "slower_wins_after_fast_leaves",
            "when the faster robot leaves, the slower one wins within 200 ms + two steps",
            ok,
            measured,
        )
    )
    below = []
    td = [(k, j) for k, j, o in run.fires() if o == _TD]
    for k, j in td:
        following = [s for s, r, _ in run.fires() if r == j and s > k]
        stop = following[0] if following else len(run.t)
        if run.trace.M[k:stop, j].min() < 1.0 - _EPS:
            below.append(run.t[k])
    checks.append(
        _check(
            "top_down_never_below_1",
            "no course of top-down origin shows M < 1",
            td and not below,
            f"{len(td)} top-down courses, {len(below)} with M < 1",
        )
    )
    moves = []
    for c in change_steps:
        before = run.focus[c - 1]
        window = run.focus[c : c + settle + 1]
        moved = np.flatnonzero((window != before) & (window >= 0))
        moves.append(moved[0] * run.dt if moved.size else np.inf)
    checks.append(
        _check(
            "goal_change_moves_focus",
            "changing the goal moves the focus within 200 ms + two steps",
            moves and max(moves) <= _TD_ONSET + 2 * run.dt + _EPS,
            "focus moved "
            + ", ".join(f"{m:.2f} s" for m in moves)
            + " after the goal changes at "
            + ", ".join(f"{run.t[c]:.2f} s" for c in change_steps),
        )
    )
    return checks


_CHECKERS: Mapping[str, Callable[[_Run], list[Check]]] = MappingProxyType(
    {"exp01": _exp01, "exp02": _exp02, "exp03": _exp03, "exp04": _exp04, "exp05": _exp05}
)

#: Experiment name → the names of its checks, in order.
CHECKS: Mapping[str, tuple[str, ...]] = MappingProxyType(
    {
        "exp01": (
            "first_winner_is_s4",
            "s4_course_shape",
            "no_refire_within_600ms",
            "quiet_once_static",
            "far_regions_never_win",
        ),
        "exp02": (
            "static_scene_fires",
            "ior_visits_several_regions",
            "no_refire_within_600ms",
            "sonar_entry_draws_focus",
        ),
        "exp03": ("static_winners_from_F3", "moving_robot_dominates_L", "bottom_up_with_ior", "no_refire_within_600ms"),
        "exp04": (
            "F4_is_1_while_goal_holds",
            "winners_top_down",
            "no_ior",
            "M_rises_within_onset",
            "release_within_two_steps",
            "combined_L_exceeds_single",
        ),
        "exp05": (
            "faster_holds_focus",
            "slower_wins_after_fast_leaves",
            "top_down_never_below_1",
            "goal_change_moves_focus",
        ),
    }
)


def check_experiment(result: ExperimentResult) -> list[Check]:
    """The docs/model.md §9 checks of ``result``'s experiment, in the order of ``CHECKS``."""
    if not isinstance(result, ExperimentResult):
        raise ValueError(f"check_experiment takes an ExperimentResult, got {type(result).__name__}")
    return _CHECKERS[result.experiment.name](_Run(result))


def pass_rates(
    name: str,
    noise: float | None,
    seeds,
    *,
    kinematics: str = "tracker",
    profile: str | None = None,
    config: Mapping[str, Any] | None = None,
) -> dict[str, float]:
    """Fraction of runs of experiment ``name`` (one per seed) that pass each check.

    Args:
        name: "exp01" … "exp05".
        noise: the relative noise level (None: the profile's, see ``run_experiment``).
        seeds: the env seeds (ints >= 0), e.g. ``range(20)``.
        kinematics, profile, config: as in ``run_experiment``.

    Returns:
        Check name → pass rate in [0, 1], in the order of ``CHECKS[name]``.

    Raises:
        ValueError: for no seeds, or a bad argument of ``run_experiment``.
    """
    seeds = list(seeds)
    if not seeds:
        raise ValueError("pass_rates needs at least one seed")
    passed = {check: 0 for check in CHECKS[get_experiment(name).name]}
    for seed in seeds:
        result = run_experiment(name, noise=noise, seed=seed, kinematics=kinematics, profile=profile, config=config)
        for check in check_experiment(result):
            passed[check.name] += check.passed
    return {check: count / len(seeds) for check, count in passed.items()}
