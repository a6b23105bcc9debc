"""One episode's truth and the model's outputs, step by step: what the perception metrics read.

- ``record_episode``: run an attended environment under a policy and keep, per step, the
  movers' robot-frame positions and velocities, the model's region speeds and track
  speeds, its focus, the regions that see static structure only, and why the focus is or
  is not on the target (``EpisodeRecord``).
- ``static_regions``: the regions whose echoes all come from static structure.
- ``nearest_tracks`` / ``nearest_track`` / ``matched_track_speeds``: the model's confirmed
  tracks matched to the movers (within ``TRACK_MATCH_M``).
- ``target_case``: one step's entry of ``TARGET_CASES``.
- ``false_moving_tracks``: the confirmed tracks labelled moving that lie on no mover
  (phantom motion).

Positions in metres (robot frame: x forward, y left), speeds in m/s, times in seconds.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from attentive_gym.attention import Goal
from attentive_gym.attention.tracking.track_regions import MOVING_PROBABILITY
from attentive_gym.perception.controllers import Policy
from attentive_gym.perception.geometry import GRID, VIEW_RANGE_M, region_of, to_robot_frame

__all__ = [
    "EpisodeRecord",
    "record_episode",
    "static_regions",
    "nearest_tracks",
    "nearest_track",
    "matched_track_speeds",
    "target_case",
    "TARGET_CASES",
    "TRACK_MATCH_M",
    "SETTLE_S",
    "false_moving_tracks",
    "FALSE_LABEL_M",
    "MOVING_PROBABILITY",
]

#: The nearest confirmed track within this (m) of a mover is its track.
TRACK_MATCH_M = 0.75
#: A confirmed track labelled moving (its probability of moving above the tracker's
#: ``MOVING_PROBABILITY``) farther than ``FALSE_LABEL_M`` (m) from every mover is a false
#: label: phantom motion.
FALSE_LABEL_M = 1.5
#: A mover counts once it has been in view continuously this long (s); a track younger
#: than this has not been judged yet (``target_case``).
SETTLE_S = 1.0


@dataclass(frozen=True)
class EpisodeRecord:
    """Per-step truth and model output of one episode (T steps, M movers, J = 8 regions).

    Attributes:
        goal: the episode's goal.
        target: index of the target among the movers.
        t_s: ``(T,)`` time of each step (s).
        mover_xy: ``(T, M, 2)`` mover centres in the robot frame (m).
        mover_velocity: ``(T, M, 2)`` mover velocities in the world frame (m/s).
        region_speed: ``(T, J)`` the model's speed estimate per region (m/s).
        track_speed: ``(T, M)`` speed of each mover's matched confirmed track (m/s), NaN
            where none is within ``TRACK_MATCH_M``; None when the model produced no track
            in the whole episode (the modes without a tracker).
        focus: ``(T,)`` the focused region, −1 for none.
        static_region: ``(T, J)`` regions with an echo and no echo from a mover.
        target_case: ``(T,)`` why the focus is or is not on the target at each step, an
            index into ``TARGET_CASES`` (``target_case``); None when not recorded.
        target_track_age: ``(T,)`` age (s) of the target's track (``nearest_track``), NaN
            where it has none; None when not recorded.
        target_beams: ``(T,)`` int, how many laser beams of the step's scan hit the target;
            None when not recorded.
        false_label: ``(T, 3)`` bool, per step whether a track of ``false_moving_tracks``
            lies anywhere, one lies within ``VIEW_RANGE_M`` (in front or behind), and one's
            speed lies in the goal's range (all False without tracks); None when not
            recorded.
    """

    goal: Goal
    target: int
    t_s: np.ndarray
    mover_xy: np.ndarray
    mover_velocity: np.ndarray
    region_speed: np.ndarray
    track_speed: np.ndarray | None
    focus: np.ndarray
    static_region: np.ndarray
    target_case: np.ndarray | None = None
    target_track_age: np.ndarray | None = None
    target_beams: np.ndarray | None = None
    false_label: np.ndarray | None = None


#: ``(J, 180)`` which laser beams each region holds.
_REGION_BEAMS = GRID.beam_region[None, :] == np.arange(GRID.n_regions)[:, None]


def static_regions(laser_hits: np.ndarray, sonar_hits: np.ndarray, mover_ids: np.ndarray) -> np.ndarray:
    """``(J,)`` bool: the region's laser beams or front sonar have an echo, and none of them
    comes from a mover. ``laser_hits`` (180,) and ``sonar_hits`` (16,) are entity ids per
    reading (−1: no echo); ``mover_ids`` the movers' entity ids."""
    sonar = sonar_hits[GRID.region_sonar]
    mover_echo = (_REGION_BEAMS & np.isin(laser_hits, mover_ids)).any(axis=1) | np.isin(sonar, mover_ids)
    echo = (_REGION_BEAMS & (laser_hits >= 0)).any(axis=1) | (sonar >= 0)
    return echo & ~mover_echo


def false_moving_tracks(tracks, mover_xy: np.ndarray) -> np.ndarray:
    """``(n,)`` bool over ``tracks``' rows: confirmed, labelled moving (probability of moving
    above ``MOVING_PROBABILITY``) and farther than ``FALSE_LABEL_M`` from every mover's
    robot-frame position ``mover_xy`` ``(M, 2)`` (m)."""
    moving = np.asarray(tracks.confirmed, bool) & (np.asarray(tracks.moving_probability) > MOVING_PROBABILITY)
    positions = np.asarray(tracks.position_m, float).reshape(-1, 2)
    gaps = np.linalg.norm(positions[:, None, :] - np.asarray(mover_xy, float).reshape(1, -1, 2), axis=2)
    return moving & (gaps.min(axis=1, initial=np.inf) > FALSE_LABEL_M)


def nearest_tracks(tracks, xy: np.ndarray) -> np.ndarray:
    """``(M,)`` row in ``tracks`` of the confirmed track nearest to each robot-frame position
    ``xy`` (M, 2) (m), −1 where none lies within ``TRACK_MATCH_M``."""
    confirmed = np.flatnonzero(np.asarray(tracks.confirmed, bool))
    rows = np.full(len(xy), -1)
    if confirmed.size:
        positions = np.asarray(tracks.position_m, float).reshape(-1, 2)[confirmed]
        distance = np.linalg.norm(xy[:, None, :] - positions[None, :, :], axis=-1)
        nearest = distance.argmin(axis=1)
        close = distance[np.arange(len(xy)), nearest] <= TRACK_MATCH_M
        rows[close] = confirmed[nearest[close]]
    return rows


def matched_track_speeds(tracks, mover_xy: np.ndarray) -> np.ndarray:
    """``(M,)`` speed (m/s) of each mover's track (``nearest_tracks`` of its robot-frame
    position ``mover_xy`` (M, 2)), NaN where it has none."""
    rows = nearest_tracks(tracks, mover_xy)
    matched = np.full(len(mover_xy), np.nan)
    matched[rows >= 0] = np.asarray(tracks.speed_mps, float)[rows[rows >= 0]]
    return matched


#: Why the focus is or is not on the target's region at a step, checked in this order: the
#: focus is there; the perception misses the target (the laser does not see it; it sees it
#: but no confirmed track lies within ``TRACK_MATCH_M``; a track does, but the goal is not
#: judged to hold in the target's region, the track younger or older than ``SETTLE_S``);
#: or the goal is judged to hold there and the selection goes elsewhere (no focus at all;
#: the region is inhibited, M < 1; another region wins).
TARGET_CASES = (
    "on target",
    "hidden from the laser",
    "seen, no track",
    "young track, goal not judged",
    "track, goal not judged",
    "no focus",
    "inhibited",
    "another region won",
)


def nearest_track(tracks, xy: np.ndarray) -> int | None:
    """``nearest_tracks`` of one position ``xy`` (2,) (m): a row, or None."""
    row = int(nearest_tracks(tracks, np.reshape(xy, (1, 2)))[0])
    return None if row < 0 else row


def target_case(output, target_xy: np.ndarray, target_laser_beams: int) -> int:
    """The index in ``TARGET_CASES`` of a step: the model's ``output``, the target's
    robot-frame position ``target_xy`` (2,) (m) and how many laser beams hit it."""
    region = int(region_of(target_xy))
    if output.focus == region:
        return 0
    nearest = nearest_track(output.tracks, target_xy)
    if nearest is None:
        return 1 if target_laser_beams == 0 else 2
    if not output.goal_fulfilled[region]:
        return 3 if output.tracks.age_s[nearest] < SETTLE_S else 4
    if output.focus is None:
        return 5
    return 6 if output.M[region] < 1.0 else 7


def record_episode(env, seed: int, goal: Goal, policy: Policy, seconds: float) -> EpisodeRecord:
    """Run one episode of the attended ``env`` (reset with ``seed`` and ``goal``) under
    ``policy`` for ``seconds`` (s) or until it ends, and record every step after the reset.

    Raises:
        ValueError: for ``seconds`` not > 0.
    """
    if not seconds > 0.0:
        raise ValueError(f"seconds (the length of the episode to record, s) must be > 0, got {seconds!r}")
    obs, info = env.reset(seed=seed, options={"goal": goal})
    mover_ids = np.array([m.entity.id for m in env.unwrapped.world.movers])
    target_id = mover_ids[info["target_index"]]
    steps: list[tuple] = []
    tracked = False  # whether the model produced any track in the episode
    while info["time_s"] < seconds - 1e-9:
        obs, _, terminated, truncated, info = env.step(policy(obs, info))
        output = info["attention"]
        xy = to_robot_frame(info["mover_positions"], info["robot_pose"])
        tracks = getattr(output, "tracks", None)
        tracked = tracked or (tracks is not None and len(tracks.id) > 0)
        target_track = None if tracks is None else nearest_track(tracks, xy[info["target_index"]])
        target_beams = int(np.sum(info["laser_hits"] == target_id))
        phantoms = (False, False, False)
        if tracks is not None:
            false = false_moving_tracks(tracks, xy)
            if false.any():
                near = np.hypot(*np.asarray(tracks.position_m, float).reshape(-1, 2).T) < VIEW_RANGE_M
                in_band = any(goal.is_fulfilled(float(v)) for v in tracks.speed_mps[false])
                phantoms = (True, bool(np.any(false & near)), in_band)
        steps.append(
            (
                info["time_s"],
                xy,
                info["mover_velocities"],
                output.speeds_mps,
                np.full(len(xy), np.nan) if tracks is None else matched_track_speeds(tracks, xy),
                -1 if output.focus is None else output.focus,
                static_regions(info["laser_hits"], info["sonar_hits"], mover_ids),
                target_case(output, xy[info["target_index"]], target_beams),
                math.nan if target_track is None else tracks.age_s[target_track],
                target_beams,
                phantoms,
            )
        )
        if terminated or truncated:
            break
    t_s, xy, velocity, region_speed, track_speed, focus, static, case, age, beams, false = zip(*steps)
    return EpisodeRecord(
        goal=goal,
        target=int(info["target_index"]),
        t_s=np.array(t_s),
        mover_xy=np.array(xy),
        mover_velocity=np.array(velocity),
        region_speed=np.array(region_speed),
        track_speed=np.array(track_speed) if tracked else None,
        focus=np.array(focus),
        static_region=np.array(static),
        target_case=np.array(case) if tracked else None,
        target_track_age=np.array(age) if tracked else None,
        target_beams=np.array(beams, np.int64),
        false_label=np.array(false, bool).reshape(-1, 3),
    )
