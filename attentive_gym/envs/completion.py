"""The completion of a step (or a reset) of k rescue environments at once, over arrays.

- ``INFO_KEYS``: the keys of ``AttentiveRescueEnv``'s info, in order.
- ``CompletedSteps``: k members' raw observations, rewards, terminations, truncations and info
  entries, each an array (or a list) with a leading member axis, and each member's own
  observation and info as views of those rows.
- ``complete_steps``: what ``AttentiveRescueEnv.complete_step`` returns, for k members in one
  pass; the single env's ``complete_step`` (k = 1) and a fleet's complete stage are this call.
- ``complete_resets``: the same for the members' first observation and info after a reset.

The numbers are those of one member computed alone, bit for bit: the reward's arithmetic runs
elementwise in the same order, and the target distance and the odometry's projection use
``math.hypot``, ``math.cos`` and ``math.sin`` member by member (NumPy's vectorised versions may
round differently).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from attentive_gym.envs.reward import rescue_rewards
from attentive_gym.sensors import SensorReading

if TYPE_CHECKING:
    from attentive_gym.envs.rescue_env import AttentiveRescueEnv

__all__ = ["INFO_KEYS", "CompletedSteps", "complete_resets", "complete_steps"]

#: The keys of ``AttentiveRescueEnv``'s info, in the order its info dict has them.
INFO_KEYS = (
    "time_s",
    "robot_pose",
    "robot_velocity",
    "mover_positions",
    "mover_velocities",
    "mover_names",
    "target_index",
    "target_distance_m",
    "collision",
    "success",
    "goal",
    "sonar_hits",
    "laser_hits",
    "sonar_time_s",
    "laser_time_s",
)
#: Info keys whose member value is a Python scalar: one number per member.
_SCALAR_KEYS = ("time_s", "target_index", "target_distance_m", "collision", "success", "sonar_time_s", "laser_time_s")
#: Info keys whose member value is a row of a ``(k, ...)`` block.
_ROW_KEYS = ("robot_pose", "robot_velocity", "sonar_hits", "laser_hits")
#: Info keys whose member values are kept as a list (their shapes may differ between members).
_LIST_KEYS = ("mover_positions", "mover_velocities", "mover_names", "goal")
#: s: the slack on "the time limit is reached" (world time is a product that can land below it).
_LIMIT_TOLERANCE_S = 1e-9


@dataclass(frozen=True, eq=False)
class CompletedSteps:
    """k members' completed steps, row j for member j.

    Attributes:
        observation: the raw observations as float32 blocks: ``"sonar"`` (k, 16) m,
            ``"laser"`` (k, R) m, ``"odometry"`` (k, 2) (m/s, rad/s, clipped to the
            observation space), ``"goal"`` (k, G) (``Goal.encode()``).
        reward: (k,) float64 rewards (0 for a reset).
        terminated: (k,) bool: the target was reached.
        truncated: (k,) bool: the time limit was reached without success.
        info: every key of ``INFO_KEYS``: ``time_s``, ``target_index`` (int64),
            ``target_distance_m``, ``collision``, ``success``, ``sonar_time_s`` and
            ``laser_time_s`` as (k,) arrays; ``robot_pose`` (k, 3), ``robot_velocity`` (k, 2)
            float64 and ``sonar_hits`` (k, 16), ``laser_hits`` (k, R) int64 blocks;
            ``mover_positions`` and ``mover_velocities`` (lists of (M, 2) float64 arrays),
            ``mover_names`` (tuples) and ``goal`` (texts) as lists of k.
    """

    observation: dict[str, np.ndarray]
    reward: np.ndarray
    terminated: np.ndarray
    truncated: np.ndarray
    info: dict[str, Any]

    def __len__(self) -> int:
        return len(self.reward)

    def observations(self) -> list[dict[str, np.ndarray]]:
        """Each member's observation dict, its entries views of the blocks' rows."""
        blocks = self.observation
        sonar, laser, odometry, goal = blocks["sonar"], blocks["laser"], blocks["odometry"], blocks["goal"]
        return [
            {"sonar": sonar[j], "laser": laser[j], "odometry": odometry[j], "goal": goal[j]} for j in range(len(self))
        ]

    def infos(self) -> list[dict[str, Any]]:
        """Each member's info dict, with ``AttentiveRescueEnv``'s types: Python scalars for the
        numbers and flags, views of the blocks' rows for the arrays."""
        info = self.info
        time_s, index, distance, collision, success, sonar_time, laser_time = (
            info[key].tolist() for key in _SCALAR_KEYS
        )
        pose, velocity, sonar_hits, laser_hits = (info[key] for key in _ROW_KEYS)
        positions, velocities, names, goal = (info[key] for key in _LIST_KEYS)
        return [
            {
                "time_s": time_s[j],
                "robot_pose": pose[j],
                "robot_velocity": velocity[j],
                "mover_positions": positions[j],
                "mover_velocities": velocities[j],
                "mover_names": names[j],
                "target_index": index[j],
                "target_distance_m": distance[j],
                "collision": collision[j],
                "success": success[j],
                "goal": goal[j],
                "sonar_hits": sonar_hits[j],
                "laser_hits": laser_hits[j],
                "sonar_time_s": sonar_time[j],
                "laser_time_s": laser_time[j],
            }
            for j in range(len(self))
        ]


def complete_steps(
    envs: Sequence[AttentiveRescueEnv], touched: Sequence[bool] | np.ndarray, fresh: SensorReading
) -> CompletedSteps:
    """The steps of ``envs`` completed once their worlds have moved: what each member's
    ``complete_step(touched[j], reading j)`` returns, as arrays.

    Args:
        envs: k ≥ 1 reset environments whose worlds have just stepped.
        touched: (k,) whether each robot touched anything during its step (``move``'s result).
        fresh: the new readings after the move as (k, ·) blocks: ``sonar`` (k, 16) and
            ``laser`` (k, R) float64 ranges (m), ``sonar_owner`` and ``laser_owner`` int64.

    Updates each member's scan hold, held reading and target distance.

    Raises:
        ValueError: for ``touched`` or ``fresh`` blocks without one row per member.
    """
    collided = np.asarray(touched, dtype=np.bool_)
    if collided.shape != (len(envs),):
        raise ValueError(f"touched must have one flag per env, shape ({len(envs)},); got shape {collided.shape}")
    previous = np.array([env._distance for env in envs])
    completed = _complete(envs, fresh, collided)
    distance = completed.info["target_distance_m"]
    has_task = completed.info["target_index"] >= 0
    reward, success = completed.reward, completed.info["success"]
    rows = slice(None) if has_task.all() else np.flatnonzero(has_task)
    reward[rows], success[rows] = rescue_rewards(
        [envs[j].reward_config for j in np.arange(len(envs))[rows]],
        np.array([env.dt for env in envs])[rows],
        previous[rows],
        distance[rows],
        collided[rows],
    )
    limit = np.array([env._limit_s for env in envs])
    completed.terminated[:] = success
    completed.truncated[:] = (completed.info["time_s"] >= limit - _LIMIT_TOLERANCE_S) & ~success
    return completed


def complete_resets(envs: Sequence[AttentiveRescueEnv], fresh: SensorReading) -> CompletedSteps:
    """The first observation and info of ``envs`` after their reset (no collision, no success,
    reward 0), from ``fresh`` as in ``complete_steps``; each member's scan hold scans."""
    return _complete(envs, fresh, np.zeros(len(envs), np.bool_))


def _complete(envs: Sequence[AttentiveRescueEnv], fresh: SensorReading, collided: np.ndarray) -> CompletedSteps:
    """Observations and info of ``envs`` now (reward 0, success False until the caller sets them)."""
    k = len(envs)
    for name in ("sonar", "laser", "sonar_owner", "laser_owner"):
        rows = getattr(fresh, name).shape[0] if getattr(fresh, name).ndim == 2 else -1
        if rows != k:
            raise ValueError(f"fresh.{name} must be a (k, ·) block with k = {k} rows (one per env), got {rows}")
    worlds = [env.world for env in envs]
    records = np.concatenate([world.state.world for world in worlds])
    now = np.ascontiguousarray(records["time_s"])
    pose = np.ascontiguousarray(records["robot_pose"])
    velocity = records["robot_velocity"]
    movers = np.concatenate([world.state.movers for world in worlds])
    ends = np.cumsum([len(world.state.movers) for world in worlds]).tolist()
    starts = [0, *ends[:-1]]

    odometry = np.empty((k, 2))
    odometry[:, 1] = velocity[:, 2]
    linear, distance, target_index, sonar_scans, laser_scans, holds = [], [], [], [], [], []
    for env, (vx, vy), (x, y, heading), start, now_s in zip(
        envs, velocity[:, :2].tolist(), pose.tolist(), starts, now.tolist()
    ):
        linear.append(vx * math.cos(heading) + vy * math.sin(heading))
        target = env._target_index
        if target is None:
            distance.append(math.inf)
            target_index.append(-1)
        else:
            tx, ty = movers["pose"][start + target, :2].tolist()
            distance.append(math.hypot(tx - x, ty - y))
            target_index.append(target)
        hold = env._scans
        sonar_scan, laser_scan = hold.scans(now_s)
        sonar_scans.append(sonar_scan)
        laser_scans.append(laser_scan)
        holds.append(hold)
    odometry[:, 0] = linear
    limits = np.array([env._odometry_limit for env in envs])
    observed_odometry = np.minimum(np.maximum(odometry, -limits), limits).astype(np.float32)

    sonar, sonar_owner = _held(fresh.sonar, fresh.sonar_owner, sonar_scans, holds, "sonar")
    laser, laser_owner = _held(fresh.laser, fresh.laser_owner, laser_scans, holds, "laser")
    for j, (env, hold) in enumerate(zip(envs, holds)):
        env._reading = hold.reading = SensorReading(sonar[j], laser[j], sonar_owner[j], laser_owner[j])
        env._distance = distance[j]
    goals = [env._goal_cached() for env in envs]
    positions = np.ascontiguousarray(movers["pose"][:, :2])
    velocities = np.ascontiguousarray(movers["velocity"])
    info = {
        "time_s": now,
        "robot_pose": pose,
        "robot_velocity": odometry,
        "mover_positions": [positions[a:b] for a, b in zip(starts, ends)],
        "mover_velocities": [velocities[a:b] for a, b in zip(starts, ends)],
        "mover_names": [world.mover_names for world in worlds],
        "target_index": np.array(target_index, dtype=np.int64),
        "target_distance_m": np.array(distance),
        "collision": collided,
        "success": np.zeros(k, np.bool_),
        "goal": [goal[2] for goal in goals],
        "sonar_hits": sonar_owner.copy(),
        "laser_hits": laser_owner.copy(),
        "sonar_time_s": np.array([hold.sonar_time_s for hold in holds]),
        "laser_time_s": np.array([hold.laser_time_s for hold in holds]),
    }
    observation = {
        "sonar": sonar.astype(np.float32),
        "laser": laser.astype(np.float32),
        "odometry": observed_odometry,
        "goal": np.array([goal[1] for goal in goals], dtype=np.float32),
    }
    return CompletedSteps(observation, np.zeros(k), np.zeros(k, np.bool_), np.zeros(k, np.bool_), info)


def _held(
    ranges: np.ndarray, owners: np.ndarray, scans: list[bool], holds: list, sensor: str
) -> tuple[np.ndarray, np.ndarray]:
    """One sensor's (k, ·) ranges and owners under the scan holds: the fresh rows of the members
    that scan (the fresh blocks themselves when all do), the held rows of the others."""
    if all(scans):
        return ranges, owners
    ranges, owners = ranges.copy(), owners.copy()
    for j, (scan, hold) in enumerate(zip(scans, holds)):
        if not scan:
            ranges[j] = getattr(hold.reading, sensor)
            owners[j] = getattr(hold.reading, f"{sensor}_owner")
    return ranges, owners
