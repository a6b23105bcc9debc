"""Is the tracker's judgement of a speed goal calibrated? Its tracks set against the truth.

- ``judged_track_steps``: for every confirmed track at every step of an episode, the
  probability that the body's speed lies in a band, as the model judges it
  (``tracking.track_regions.speed_goal_probability`` of the track's velocity, covariance and
  probability of moving), the point rule it replaces (the track's speed, weighted by its
  probability of moving, inside the band), its probability of moving, and the truth of the
  mover it lies on (within ``records.TRACK_MATCH_M``; a track on no mover lies on
  structure: speed 0).
- ``reliability``: the judged probabilities binned (``BINS``): per bin, the count, the mean
  probability and the share truly in the band. A calibrated judgement has the two close.
- ``brier``: the mean squared error of a probability against the truth (lower is better).

Speeds in m/s.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable

import numpy as np

from attentive_gym.attention import Goal
from attentive_gym.attention.tracking.track_regions import speed_goal_probability
from attentive_gym.perception.geometry import to_robot_frame
from attentive_gym.perception.records import TRACK_MATCH_M

__all__ = ["judged_track_steps", "reliability", "brier", "BINS", "MOVING_MPS", "JUDGED_FIELDS"]

#: A mover faster than this (m/s) counts as truly moving.
MOVING_MPS = 0.1
#: The bins of a reliability table (the last one closed).
BINS = (0.0, 0.05, 0.2, 0.4, 0.6, 0.8, 0.95, 1.0001)
#: The arrays of ``judged_track_steps``, one entry per confirmed track and step:
#: ``probability`` (the model's judgement), ``point`` (0 or 1), ``moving`` (the track's
#: probability of moving), ``in_band`` and ``truly_moving`` (0 or 1, the truth), and
#: ``true_speed`` (m/s; 0 for a track on no mover).
JUDGED_FIELDS = ("probability", "point", "moving", "in_band", "truly_moving", "true_speed")


def judged_track_steps(
    env, band: tuple[float, float], seeds: Iterable[int], seconds: float, policy_of: Callable[[int], Callable]
) -> dict[str, np.ndarray]:
    """Run ``env`` (an attended environment whose model runs the tracker) for ``seconds`` (s)
    from each of ``seeds`` under ``policy_of(seed)`` (``policy(obs, info)`` → action), with
    the speed goal ``band`` ``(lo, hi)`` (m/s), and return ``JUDGED_FIELDS`` as float arrays
    ``(n,)`` over every confirmed track at every step."""
    lo, hi = band
    out: dict[str, list[float]] = {name: [] for name in JUDGED_FIELDS}
    for seed in seeds:
        policy = policy_of(seed)
        obs, info = env.reset(seed=seed, options={"goal": Goal.between("speed", lo, hi)})
        while info["time_s"] < seconds:
            obs, _, terminated, truncated, info = env.step(policy(obs, info))
            tracks = info["attention"].tracks
            if tracks is None:
                raise ValueError("judged_track_steps needs a model that runs the tracker (kinematics='tracker')")
            movers = to_robot_frame(info["mover_positions"], info["robot_pose"])
            speeds = np.linalg.norm(info["mover_velocities"], axis=1)
            for k in np.flatnonzero(tracks.confirmed):
                gaps = np.linalg.norm(movers - tracks.position_m[k], axis=1)
                true_speed = speeds[gaps.argmin()] if gaps.size and gaps.min() < TRACK_MATCH_M else 0.0
                p_moving = float(tracks.moving_probability[k])
                # the table's velocity is weighted by the probability of moving
                vx, vy = tracks.velocity_mps[k] / p_moving if p_moving > 0.0 else (0.0, 0.0)
                spread = tracks.covariance[k]
                out["probability"].append(
                    speed_goal_probability(vx, vy, spread[2, 2], spread[2, 3], spread[3, 3], p_moving, lo, hi)
                )
                out["point"].append(float(lo <= tracks.speed_mps[k] <= hi))
                out["moving"].append(p_moving)
                out["in_band"].append(float(lo <= true_speed <= hi))
                out["truly_moving"].append(float(true_speed > MOVING_MPS))
                out["true_speed"].append(float(true_speed))
            if terminated or truncated:
                break
    return {name: np.array(values, float) for name, values in out.items()}


def reliability(judged: np.ndarray, truth: np.ndarray) -> list[tuple[float, float, int, float, float]]:
    """Per non-empty bin of ``BINS``: ``(low, high, count, mean judged, share true)`` of the
    probabilities ``judged`` ``(n,)`` against the 0/1 ``truth`` ``(n,)``."""
    rows = []
    for low, high in zip(BINS[:-1], BINS[1:]):
        inside = (judged >= low) & (judged < high)
        if inside.any():
            share = float(truth[inside].mean())
            rows.append((low, min(high, 1.0), int(inside.sum()), float(judged[inside].mean()), share))
    return rows


def brier(judged: np.ndarray, truth: np.ndarray) -> float:
    """The Brier score: the mean of ``(judged − truth)²`` over ``(n,)`` arrays."""
    return float(np.mean((np.asarray(judged, float) - np.asarray(truth, float)) ** 2))
