"""How much focus on target does the laser's noise allow? The tracker against an ideal estimator.

For the perception benchmark's focus episodes (10 m arena, 3 distractors, 5 % Gaussian noise,
seeds 0..N−1 with the task goals in turn; the robot still, then wandering), every step with
the target in the laser's sight (``perception.geometry.in_sight``) falls in a bin of the time
since the target came into sight. A sighting outlasts gaps of up to ``GAP_S`` (the tracker's
``track_coast_s``). Per robot mode, goal and bin, the script gives:

- the bin's share of the in-sight steps;
- the focus on target of the tracker (the default model) and of the perfect-perception bound
  (``perception.bound``);
- the share of the steps in which an **ideal estimator** judges the goal to hold.

The ideal estimator knows which echoes are the target's. It fits a straight line to the
target's centroids over the sighting's last ``IDEAL_WINDOW_S``, each weighted by its noise
(``centroid_variance``: docs/model.md §10's measurement covariance, along and across the line
of sight, averaged, since the records keep no heading to project the velocity). Its speed
estimate is normal around the truth with the fit's σ_v. The goal holds where the estimate
lies in the band and at least ``Z_STANDING`` σ_v above zero, which tells a mover from
standing structure (``judged_probability``).

The bound's focus × the ideal judged share estimates what a model reaches from the goal alone
with that judgement. A model also finds the target bottom-up, so this is a guide, not a
ceiling::

    python benchmarks/acquisition.py                       # 96 episodes, about a minute on 2 cores
    python benchmarks/acquisition.py --episodes 8 --seconds 10
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Sequence

import numpy as np

from attentive_gym.attention import AttentionConfig
from attentive_gym.attention.tracking.track_regions import speed_goal_probability
from attentive_gym.perception.bound import make_bound_env
from attentive_gym.perception.geometry import in_sight, region_of
from attentive_gym.perception.records import EpisodeRecord
from attentive_gym.perception.settings import PERCEPTION_ARENA, VARIANT, make_attentive_env
from attentive_gym.world.arena import DEFAULT_TASK_GOALS
from bench_perception import robot_records

#: Relative σ of the range noise, as the perception benchmark's main rows.
NOISE = 0.05
_CONFIG = AttentionConfig()
#: A sighting outlasts gaps up to this long (s): the tracker's default coast.
GAP_S = _CONFIG.track_coast_s
#: The ideal estimator's line fits at most this much of the sighting (s).
IDEAL_WINDOW_S = 2.0
#: The ideal estimator judges a body moving only this many σ_v above zero.
Z_STANDING = 2.0
#: Bins of the time since sighting (s).
AGE_BINS_S = (0.0, 0.25, 0.5, 1.0, 2.0, 4.0, math.inf)
_BEAM_STEP_RAD = math.radians(1.0)


def sighting_ages(t_s: np.ndarray, visible: np.ndarray, gap_s: float = GAP_S) -> np.ndarray:
    """``(T,)`` the time (s) since the current sighting began at each visible step, NaN
    elsewhere. A sighting goes on through gaps in ``visible`` of at most ``gap_s``."""
    ages = np.full(t_s.shape, np.nan)
    start, last = math.nan, -math.inf
    for k in np.flatnonzero(visible):
        if t_s[k] - last > gap_s:
            start = t_s[k]
        last = t_s[k]
        ages[k] = t_s[k] - start
    return ages


def centroid_variance(distance_m: np.ndarray, beams: np.ndarray, noise_rel: float = NOISE) -> np.ndarray:
    """The variance (m²) of a body's measured centre at ``distance_m`` on ``beams`` laser
    beams: the mean of docs/model.md §10's along (``σ(r)²/n + surface²``) and across
    (``surface² + (r Δβ)²/12``) the line of sight."""
    sigma = np.maximum(noise_rel * distance_m, _CONFIG.range_noise_floor_m)
    surface = _CONFIG.track_surface_sigma_m**2
    along = sigma**2 / np.maximum(beams, 1) + surface
    across = surface + (distance_m * _BEAM_STEP_RAD) ** 2 / 12.0
    return 0.5 * (along + across)


def ideal_speed_sigma(
    t_s: np.ndarray, visible: np.ndarray, ages: np.ndarray, variance: np.ndarray, window_s: float = IDEAL_WINDOW_S
) -> np.ndarray:
    """``(T,)`` σ (m/s) of the speed an ideal weighted line fit gives at each visible step,
    from the sighting's visible steps over the last ``window_s`` (``1/√Σ w (t − t̄)²``, w =
    1/``variance``); inf where one centroid is all there is, NaN where not visible."""
    sigma = np.full(t_s.shape, np.nan)
    for k in np.flatnonzero(visible):
        since = t_s[k] - min(ages[k], window_s)
        fit = visible & (t_s >= since - 1e-9) & (t_s <= t_s[k])
        w, t = 1.0 / variance[fit], t_s[fit]
        spread = float(np.sum(w * (t - np.sum(w * t) / np.sum(w)) ** 2))
        sigma[k] = 1.0 / math.sqrt(spread) if spread > 0.0 else math.inf
    return sigma


def judged_probability(
    sigma_mps: np.ndarray, speed_mps: np.ndarray, band: tuple[float, float], z: float = Z_STANDING
) -> np.ndarray:
    """The probability that an estimate normal around ``speed_mps`` with σ ``sigma_mps`` lies
    in ``band`` (m/s) and at least ``z`` σ above zero (the tracker's own normal band
    probability, ``track_regions.speed_goal_probability``); 0 for an infinite σ."""
    lo, hi = band
    return np.array(
        [
            speed_goal_probability(v, 0.0, s * s, 0.0, s * s, 1.0, max(lo, z * s), hi) if math.isfinite(s) else 0.0
            for s, v in zip(np.asarray(sigma_mps, float), np.asarray(speed_mps, float))
        ]
    )


def step_table(tracker: EpisodeRecord, bound: EpisodeRecord) -> np.ndarray:
    """``(n, 4)`` per in-sight step of one episode (the tracker's and the bound's records of the
    same seed): time since sighting (s), on target with the tracker, with the bound (0/1), and
    the ideal estimator's judged probability."""
    xy = tracker.mover_xy[:, tracker.target]
    visible = in_sight(xy, tracker.target_beams)
    region = region_of(xy)
    ages = sighting_ages(tracker.t_s, visible)
    variance = centroid_variance(np.hypot(xy[:, 0], xy[:, 1]), tracker.target_beams)
    sigma = ideal_speed_sigma(tracker.t_s, visible, ages, variance)
    speed = np.hypot(*tracker.mover_velocity[:, tracker.target].T)
    goal = tracker.goal
    judged = judged_probability(sigma[visible], speed[visible], (goal.lo, goal.hi))
    return np.column_stack(
        [ages[visible], tracker.focus[visible] == region[visible], bound.focus[visible] == region[visible], judged]
    )


def summarise(steps: np.ndarray) -> list[tuple[str, float, float, float, float]]:
    """Per bin of ``AGE_BINS_S`` with steps, then "all": (label, share of the steps, tracker's
    focus on target, the bound's, the ideal judged share)."""
    rows = []
    for lo, hi in zip(AGE_BINS_S, AGE_BINS_S[1:]):
        inside = (steps[:, 0] >= lo) & (steps[:, 0] < hi)
        if inside.any():
            label = f"{lo:g}–{hi:g} s" if math.isfinite(hi) else f"over {lo:g} s"
            rows.append((label, float(inside.mean()), *steps[inside, 1:].mean(axis=0)))
    rows.append(("all", 1.0, *steps[:, 1:].mean(axis=0)))
    return rows


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python benchmarks/acquisition.py", description=__doc__.split("\n")[0])
    parser.add_argument("--episodes", type=int, default=96, help="episodes per robot mode (default 96)")
    parser.add_argument("--seconds", type=float, default=20.0, help="length of each episode (s, default 20)")
    args = parser.parse_args(argv)
    if args.episodes < 1 or not args.seconds > 0.0:
        parser.error(f"--episodes must be >= 1 and --seconds > 0, got {args.episodes} and {args.seconds}")
    goals = tuple(DEFAULT_TASK_GOALS)
    models = {
        "tracker": make_attentive_env("tracker", NOISE, VARIANT, {}, sensor_noise=NOISE, **PERCEPTION_ARENA),
        "bound": make_bound_env(NOISE, {}, sensor_noise=NOISE, **PERCEPTION_ARENA),
    }
    print(
        f"in-sight steps by time since sighting, {100 * NOISE:g} % noise, {args.episodes} episodes; ideal: a line "
        f"over ≤ {IDEAL_WINDOW_S:g} s of the target's true centroids, ≥ {Z_STANDING:g} σ above zero"
    )
    by_model = {name: robot_records(env, args.episodes, args.seconds, goals) for name, env in models.items()}
    for (robot, tracked), (_, bounded) in zip(by_model["tracker"], by_model["bound"]):
        records = {"tracker": tracked, "bound": bounded}
        for goal in goals:
            pairs = [(a, b) for a, b in zip(records["tracker"], records["bound"]) if a.goal == goal]
            steps = np.concatenate([step_table(a, b) for a, b in pairs] or [np.zeros((0, 4))])
            print(f"\n{robot}, goal {goal}: {len(steps)} in-sight steps")
            if not len(steps):
                continue
            print("| since sighting | share | tracker | bound | ideal judged | bound × ideal |")
            print("|---|---|---|---|---|---|")
            for label, share, tracker, bound, ideal in summarise(steps):
                print(f"| {label} | {share:.3f} | {tracker:.3f} | {bound:.3f} | {ideal:.3f} | {bound * ideal:.3f} |")
    for env in models.values():
        env.close()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
