"""Motion seen at once: scenes where bodies start, stop and run along structure, and what the
model makes of them (issue 34's measures).

- ``stop_and_go_scene``: a walker that stands 2 s, walks 1.5 m, stands 2 s, walks back, and so
  on, starting 2–4 m in front of the robot, beside a standing victim and rubble.
- ``along_structure_scene``: a walker running back and forth 0.3–0.9 m in front of a wall or
  a row of rubble 2–5 m ahead.
- ``record_motion``: run one episode of an attended env on such a scene and keep, per step,
  the target's truth and the model's tracks, goal judgement and focus (``MotionRecord``).
- ``onset_latencies``: the time from each start of the target (after standing at least 1 s)
  to the first step at which the model judges the goal met in its region.
- ``motion_metrics``: latency percentiles (in seconds, and the median in the laser's scan
  intervals, so that 20 Hz and the ``usarsim`` profile's 5 Hz compare), the share of steps with a false moving label (a
  confirmed track labelled moving more than ``FALSE_LABEL_M`` from every mover, and one of
  them inside the goal's speed band), the recall of the moving target as a moving track, and
  the focus on the target while it is in view.

Positions in metres (robot frame: x forward, y left), speeds in m/s, times in seconds. A body
is in view within ``VIEW_RANGE_M``, |bearing| ≤ ``VIEW_BEARING_DEG`` and on ≥ 2 laser beams.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from attentive_gym.attention import Goal
from attentive_gym.perception.controllers import Policy
from attentive_gym.perception.geometry import region_of, to_robot_frame
from attentive_gym.perception.records import FALSE_LABEL_M, MOVING_PROBABILITY, TRACK_MATCH_M, false_moving_tracks
from attentive_gym.statistics import pooled_median_ci
from attentive_gym.world.scenario import (
    BoxRubble,
    CircleRubble,
    Leg,
    MoverSpec,
    PathBehaviour,
    Pose,
    Scenario,
    TaskSpec,
    WallSpec,
)

__all__ = [
    "SCENES",
    "stop_and_go_scene",
    "along_structure_scene",
    "MotionRecord",
    "record_motion",
    "onset_latencies",
    "motion_metrics",
    "FALSE_LABEL_M",
    "MOVING_MPS",
]

#: The goal of the scenes' task: the walker's speed band.
GOAL = Goal.between("speed", 0.5, 0.9)
#: The target moves when its speed exceeds this (m/s); it stands below ``STANDING_MPS``.
MOVING_MPS, STANDING_MPS = 0.3, 0.05
#: A start counts after the target stood this long (s).
STOOD_S = 1.0
#: The view: range (m), half-angle (degrees), fewest laser beams on the body.
VIEW_RANGE_M, VIEW_BEARING_DEG, VIEW_BEAMS = 5.0, 80.0, 2
#: The near-structure recall counts the moving target within this range (m).
NEAR_RANGE_M = 3.5
_WALKER, _STANDING = "walker", "standing"
_ARENA_HALF_M = 6.0


def _in_front(rng: np.random.Generator, range_m: tuple[float, float], bearing_deg: float) -> tuple[float, float]:
    r = rng.uniform(*range_m)
    b = math.radians(rng.uniform(-bearing_deg, bearing_deg))
    return r * math.cos(b), r * math.sin(b)


def _clear_point(rng, range_m, bearing_deg, taken, clearance_m: float = 1.2) -> tuple[float, float]:
    """A point ``_in_front`` at least ``clearance_m`` (m) from every segment ``((x, y), (x, y))``
    of ``taken`` (a body's path, or a point as a segment of length 0)."""
    while True:
        point = np.array(_in_front(rng, range_m, bearing_deg))
        if all(_segment_distance(point, np.array(a), np.array(b)) >= clearance_m for a, b in taken):
            return float(point[0]), float(point[1])


def _segment_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    ab = b - a
    along = 0.0 if not ab.any() else float(np.clip(np.dot(p - a, ab) / np.dot(ab, ab), 0.0, 1.0))
    return float(np.linalg.norm(p - (a + along * ab)))


def stop_and_go_scene(seed: int) -> Scenario:
    """A 12 m walled room, the robot at the centre facing +x; a walker 2–4 m ahead (bearing
    within ±60°) that stands 2 s, walks 1.5 m at 0.5–0.9 m/s in a random direction, stands
    2 s, walks back, and so on; a victim standing 2–5 m ahead and three round rubble pieces,
    each at least 1.2 m from the walker's path and from each other."""
    rng = np.random.default_rng([seed, 34, 1])
    x, y = _in_front(rng, (2.0, 4.0), 60.0)
    direction = rng.uniform(0.0, 2.0 * math.pi)
    to = (x + 1.5 * math.cos(direction), y + 1.5 * math.sin(direction))
    speed = float(rng.uniform(0.5, 0.9))
    walker = MoverSpec(
        _WALKER,
        "victim",
        Pose(x, y),
        PathBehaviour((Leg(to, speed, pause_s=2.0), Leg((x, y), speed, pause_s=2.0)), start_delay_s=2.0, loop=True),
    )
    path = ((x, y), to)
    sx, sy = _clear_point(rng, (2.0, 5.0), 70.0, [path])
    standing = MoverSpec(_STANDING, "victim", Pose(sx, sy))
    taken = [path, ((sx, sy), (sx, sy))]
    rubble = []
    for _ in range(3):
        centre = _clear_point(rng, (2.0, 5.0), 90.0, taken)
        rubble.append(CircleRubble(*centre, float(rng.uniform(0.15, 0.35))))
        taken.append((centre, centre))
    return _room(f"stop-and-go-{seed}", (), tuple(rubble), (walker, standing))


def along_structure_scene(seed: int) -> Scenario:
    """A 12 m walled room, the robot at the centre facing +x; 2–5 m ahead a wall across the
    view (even seeds) or a row of box rubble (odd seeds); a walker running back and forth
    along it, its surface 0.3–0.9 m in front of the structure, 1.5 m to each side of the
    robot's axis at 0.5–0.9 m/s."""
    rng = np.random.default_rng([seed, 34, 2])
    depth = float(rng.uniform(2.0, 5.0))
    gap = float(rng.uniform(0.3, 0.9))
    radius = 0.25
    walls: tuple[WallSpec, ...] = ()
    rubble: tuple[BoxRubble, ...] = ()
    if seed % 2 == 0:
        walls = (WallSpec((depth + 0.1, -3.0), (depth + 0.1, 3.0)),)  # its face at depth (0.2 m thick)
    else:
        rubble = tuple(BoxRubble(depth + 0.25, y, 0.5, 0.8) for y in np.arange(-2.5, 2.6, 1.0))
    x = depth - gap - radius
    speed = float(rng.uniform(0.5, 0.9))
    walker = MoverSpec(
        _WALKER,
        "victim",
        Pose(x, -1.5),
        PathBehaviour((Leg((x, 1.5), speed),), loop=True),
        radius_m=radius,
    )
    return _room(f"along-structure-{seed}", walls, rubble, (walker,))


def _room(name: str, walls, rubble, movers) -> Scenario:
    h = _ARENA_HALF_M
    return Scenario(
        name,
        (-h, -h, h, h),
        robot=Pose(0.0, 0.0, 0.0),
        enclosed=True,
        walls=walls,
        rubble=rubble,
        movers=movers,
        task=TaskSpec(_WALKER, GOAL, time_limit_s=60.0),
    )


#: The scenes by name.
SCENES = {"stop-and-go": stop_and_go_scene, "along-structure": along_structure_scene}


@dataclass(frozen=True)
class MotionRecord:
    """One episode of T steps.

    Attributes:
        t_s: ``(T,)`` step times (s).
        target_speed: ``(T,)`` the target's true speed (m/s).
        target_in_view: ``(T,)`` the target is in view (module docstring).
        target_near: ``(T,)`` in view and within ``NEAR_RANGE_M``.
        judged: ``(T,)`` the model judges the goal met in the target's region.
        on_target: ``(T,)`` the focus is the target's region.
        target_tracked_moving: ``(T,)`` a confirmed track labelled moving lies within
            ``TRACK_MATCH_M`` of the target.
        false_label: ``(T,)`` a confirmed track labelled moving lies more than
            ``FALSE_LABEL_M`` from every mover.
        false_in_band: ``(T,)`` one such track's speed lies in the goal's band.
        scan_interval_s: the laser's time between scans (s): the env's step where it scans
            every step.
    """

    t_s: np.ndarray
    target_speed: np.ndarray
    target_in_view: np.ndarray
    target_near: np.ndarray
    judged: np.ndarray
    on_target: np.ndarray
    target_tracked_moving: np.ndarray
    false_label: np.ndarray
    false_in_band: np.ndarray
    scan_interval_s: float


def record_motion(env, seed: int, policy: Policy, seconds: float) -> MotionRecord:
    """Run the attended ``env`` (built on a scene of ``SCENES``; the model with its tracker)
    from a reset with ``seed`` under ``policy`` for ``seconds`` (s), recording every step.

    Raises:
        ValueError: for ``seconds`` not > 0.
    """
    if not seconds > 0.0:
        raise ValueError(f"seconds (the episode's length, s) must be > 0, got {seconds!r}")
    obs, info = env.reset(seed=seed)
    target = info["target_index"]
    target_id = env.unwrapped.world.movers[target].entity.id
    lo, hi = GOAL.lo, GOAL.hi
    rows = []
    while info["time_s"] < seconds - 1e-9:
        obs, _, terminated, truncated, info = env.step(policy(obs, info))
        output = info["attention"]
        xy = to_robot_frame(info["mover_positions"], info["robot_pose"])
        target_xy = xy[target]
        distance = math.hypot(*target_xy)
        in_view = (
            distance < VIEW_RANGE_M
            and abs(math.degrees(math.atan2(target_xy[1], target_xy[0]))) <= VIEW_BEARING_DEG
            and int(np.sum(info["laser_hits"] == target_id)) >= VIEW_BEAMS
        )
        region = int(region_of(target_xy))
        tracks = output.tracks
        moving = tracks.confirmed & (tracks.moving_probability > MOVING_PROBABILITY)
        gaps = np.linalg.norm(tracks.position_m[:, None, :] - xy[None, :, :], axis=2)  # (n tracks, M)
        false = false_moving_tracks(tracks, xy)
        speed = float(np.linalg.norm(info["mover_velocities"][target]))
        rows.append(
            (
                info["time_s"],
                speed,
                in_view,
                in_view and distance < NEAR_RANGE_M,
                bool(output.goal_fulfilled[region]),
                output.focus == region,
                bool(np.any(moving & (gaps[:, target] < TRACK_MATCH_M))),
                bool(false.any()),
                bool(np.any(false & (tracks.speed_mps >= lo) & (tracks.speed_mps <= hi))),
            )
        )
        if terminated or truncated:
            break
    scan_interval_s = env.unwrapped.laser_scan_interval_s or env.unwrapped.dt
    return MotionRecord(*(np.array(column) for column in zip(*rows)), scan_interval_s=scan_interval_s)


def onset_latencies(record: MotionRecord) -> np.ndarray:
    """Per start of the target in view (it moves after standing at least ``STOOD_S``): the
    time (s) from the start to the first step at which the model judges the goal met in its
    region while it moves; ``inf`` where it stopped (or the episode ended) first."""
    latencies = []
    stood_since = None
    t, speed = record.t_s, record.target_speed
    k = 0
    while k < len(t):
        if speed[k] < STANDING_MPS:
            stood_since = t[k] if stood_since is None else stood_since
            k += 1
            continue
        if (
            speed[k] > MOVING_MPS
            and stood_since is not None
            and t[k] - stood_since >= STOOD_S
            and record.target_in_view[k]
        ):
            start, latency = t[k], math.inf
            while k < len(t) and speed[k] > STANDING_MPS:
                if record.judged[k] and record.target_in_view[k]:
                    latency = t[k] - start
                    break
                k += 1
            latencies.append(latency)
            while k < len(t) and speed[k] > STANDING_MPS:
                k += 1
        stood_since = None
        k += 1
    return np.array(latencies)


def motion_metrics(records: list[MotionRecord]) -> dict[str, float]:
    """The figures of ``records``: starts, the latencies' median and 90th percentile (s; inf
    when more than that share was never judged), their median in scan intervals (each latency
    over its record's ``scan_interval_s``) with its 95 % interval over the records
    (``attentive_gym.statistics.pooled_median_ci``), the share of starts judged, the shares of
    steps with a false moving label and with one in the goal's band, the recall of the moving
    target as a moving track (in view and within ``NEAR_RANGE_M``), and the focus on the
    target while it is in view."""
    per_record = [onset_latencies(record) for record in records]
    latencies = np.concatenate(per_record)
    scans_median, scans_low, scans_high = pooled_median_ci(
        [lat / record.scan_interval_s for lat, record in zip(per_record, records)]
    )
    steps = np.concatenate
    moving = steps([r.target_near & (r.target_speed > MOVING_MPS) for r in records])
    in_view = steps([r.target_in_view for r in records])
    return {
        "starts": float(len(latencies)),
        "latency_median_s": float(np.median(latencies)) if len(latencies) else math.nan,
        "latency_p90_s": float(np.quantile(latencies, 0.9, method="inverted_cdf")) if len(latencies) else math.nan,
        "latency_median_scans": scans_median,
        "latency_median_scans_low": scans_low,
        "latency_median_scans_high": scans_high,
        "starts_judged": float(np.mean(np.isfinite(latencies))) if len(latencies) else math.nan,
        "false_label_steps": float(np.mean(steps([r.false_label for r in records]))),
        "false_in_band_steps": float(np.mean(steps([r.false_in_band for r in records]))),
        "moving_recall": float(np.mean(steps([r.target_tracked_moving for r in records])[moving]))
        if moving.any()
        else math.nan,
        "focus_on_target": float(np.mean(steps([r.on_target for r in records])[in_view]))
        if in_view.any()
        else math.nan,
    }
