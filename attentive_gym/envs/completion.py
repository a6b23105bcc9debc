"""The completion of a step (or a reset) of k rescue environments at once, over arrays.

- ``INFO_KEYS``: the keys of ``AttentiveRescueEnv``'s info, in order.
- ``CompletedSteps``: k members' raw observations as (k, ·) blocks, their rewards,
  terminations, truncations and info entries (blocks, or lists of the members' values), and
  each member's own observation and info (views of the blocks' rows).
- ``complete_steps``: what ``AttentiveRescueEnv.complete_step`` returns, for k members in one
  pass; the single env's ``complete_step`` (k = 1) and a fleet's complete stage are this call.
- ``complete_resets``: the same for the members' first observation and info after a reset.

The numbers are those of one member computed alone, bit for bit: the scalars (odometry's
projection, target distance, reward, success, truncation) are computed member by member in
Python floats with ``math``'s functions (NumPy's vectorised ``cos`` or ``hypot`` may round
differently), the blocks (readings under the scan holds, float32 observations, hits) once for
all members.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from attentive_gym.envs.reward import contact_exceeded, rescue_reward
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
    "contact_s",
    "success",
    "goal",
    "sonar_hits",
    "laser_hits",
    "sonar_time_s",
    "laser_time_s",
)
#: Info keys whose member value is a row of a ``(k, ...)`` block.
_ROW_KEYS = ("robot_pose", "robot_velocity", "sonar_hits", "laser_hits")
#: Info keys kept as a list of the members' values, in ``INFO_KEYS``'s order.
_LIST_KEYS = tuple(key for key in INFO_KEYS if key not in _ROW_KEYS)
#: s: the slack on "the time limit is reached" (world time is a product that can land below it).
_LIMIT_TOLERANCE_S = 1e-9


@dataclass(eq=False)
class CompletedSteps:
    """k members' completed steps, entry j for member j.

    Attributes:
        observation: the raw observations as float32 blocks: ``"sonar"`` (k, 16) m,
            ``"laser"`` (k, R) m, ``"odometry"`` (k, 2) (m/s, rad/s, clipped to the
            observation space), ``"goal"`` (k, G) (``Goal.encode()``).
        rewards: k rewards (floats; 0 for a reset or a member without a task).
        terminations: k flags: the target was reached, or the contact limit passed
            (``RewardConfig.contact_limit_s``).
        truncations: k flags: the time limit was reached without termination.
        info: every key of ``INFO_KEYS``: ``robot_pose`` (k, 3), ``robot_velocity`` (k, 2)
            float64 and ``sonar_hits`` (k, 16), ``laser_hits`` (k, R) int64 blocks; the
            others lists of k member values as the single env's info has them (Python
            numbers and flags, ``(M, 2)`` arrays, name tuples, goal texts).

    The per-member numbers stay Python scalars: for the fleets this project runs (k ≤ a
    few dozen) a list is cheaper to fill and to read back per member than an array, and
    ``vector.batching`` makes the arrays a batched info needs in one call per key.
    """

    observation: dict[str, np.ndarray]
    rewards: list[float]
    terminations: list[bool]
    truncations: list[bool]
    info: dict[str, Any]

    def __len__(self) -> int:
        return len(self.rewards)

    def observations(self) -> list[dict[str, np.ndarray]]:
        """Each member's observation dict, its entries views of the blocks' rows."""
        blocks = self.observation
        sonar, laser, odometry, goal = blocks["sonar"], blocks["laser"], blocks["odometry"], blocks["goal"]
        return [
            {"sonar": sonar[j], "laser": laser[j], "odometry": odometry[j], "goal": goal[j]} for j in range(len(self))
        ]

    def infos(self) -> list[dict[str, Any]]:
        """Each member's info dict, with ``AttentiveRescueEnv``'s types: Python scalars for the
        numbers and flags, views of the blocks' rows for the robot's and the readings' arrays."""
        info = self.info
        pose, velocity, sonar_hits, laser_hits = (info[key] for key in _ROW_KEYS)
        return [
            {
                "time_s": time_s,
                "robot_pose": pose[j],
                "robot_velocity": velocity[j],
                "mover_positions": positions,
                "mover_velocities": velocities,
                "mover_names": names,
                "target_index": index,
                "target_distance_m": distance,
                "collision": collision,
                "contact_s": contact_s,
                "success": success,
                "goal": goal,
                "sonar_hits": sonar_hits[j],
                "laser_hits": laser_hits[j],
                "sonar_time_s": sonar_time,
                "laser_time_s": laser_time,
            }
            for j, (
                time_s,
                positions,
                velocities,
                names,
                index,
                distance,
                collision,
                contact_s,
                success,
                goal,
                sonar_time,
                laser_time,
            ) in enumerate(zip(*(info[key] for key in _LIST_KEYS)))
        ]


def complete_steps(envs: Sequence[AttentiveRescueEnv], touched: Sequence[bool], fresh: SensorReading) -> CompletedSteps:
    """The steps of ``envs`` completed once their worlds have moved: what each member's
    ``complete_step(touched[j], reading j)`` returns.

    Args:
        envs: k ≥ 1 reset environments whose worlds have just stepped.
        touched: k flags: whether each robot touched anything during its step (``move``'s result).
        fresh: the new readings after the move as (k, ·) blocks: ``sonar`` (k, 16) and
            ``laser`` (k, R) float64 ranges (m), ``sonar_owner`` and ``laser_owner`` int64.

    Updates each member's scan hold, held reading and target distance.

    Raises:
        ValueError: for ``touched`` or ``fresh`` without one entry or row per member.
    """
    if len(touched) != len(envs):
        raise ValueError(f"touched must have one flag per env ({len(envs)}), got {len(touched)}")
    return _complete(envs, fresh, touched, stepped=True)


def complete_resets(envs: Sequence[AttentiveRescueEnv], fresh: SensorReading) -> CompletedSteps:
    """The first observation and info of ``envs`` after their reset (no collision, no success,
    reward 0), from ``fresh`` as in ``complete_steps``; each member's scan hold scans."""
    return _complete(envs, fresh, [False] * len(envs), stepped=False)


def _complete(
    envs: Sequence[AttentiveRescueEnv], fresh: SensorReading, touched: Sequence[bool], stepped: bool
) -> CompletedSteps:
    """``complete_steps`` (``stepped``) or ``complete_resets`` of ``envs``."""
    k = len(envs)
    for name in ("sonar", "laser", "sonar_owner", "laser_owner"):
        block = getattr(fresh, name)
        if block.ndim != 2 or block.shape[0] != k:
            raise ValueError(f"fresh.{name} must be a (k, ·) block with k = {k} rows (one per env), got {block.shape}")
    time_s, positions, velocities, names, indices, distances, collisions, contacts, successes, goals = (
        [] for _ in range(10)
    )
    poses, odometry, observed, rewards, terminations, truncations, holds, encodings = [], [], [], [], [], [], [], []
    sonar_scans, laser_scans = [], []
    clearances = fresh.sonar.min(axis=1).tolist()  # each robot's nearest sonar reading now (m)
    for env, collided, clearance in zip(envs, touched, clearances):  # member by member: Python floats
        world = env.world
        state = world.state
        record = state.world
        now_s = record["time_s"].item(0)
        pose = record["robot_pose"][0]
        x, y, heading = pose.tolist()
        vx, vy, angular = record["robot_velocity"][0].tolist()
        linear = vx * math.cos(heading) + vy * math.sin(heading)
        linear_limit, angular_limit = env._odometry_limit  # the observation space's float32 bounds
        mover_xy = state.movers["pose"][:, :2].copy()
        target = env._target_index
        reward, success, ended = 0.0, False, False
        if not stepped:
            env._contact_steps = 0
        elif collided:
            env._contact_steps += 1
        contact_s = env._contact_steps * env.dt
        if target is None:
            distance = path = math.inf
        else:
            tx, ty = mover_xy[target].tolist()
            distance = math.hypot(tx - x, ty - y)
            path = distance if env._geodesic is None else env._geodesic(x, y, tx, ty)
            if stepped:
                progress = env._path_m - path
                reward, success = rescue_reward(env.reward_config, env.dt, progress, distance, collided, clearance)
                ended = contact_exceeded(env.reward_config, contact_s)
        env._path_m = path
        hold = env._scans
        sonar_scan, laser_scan = hold.scans(now_s)
        goal = env._goal_cached()
        time_s.append(now_s)
        poses.append(pose)
        odometry.append((linear, angular))
        observed.append(
            (min(max(linear, -linear_limit), linear_limit), min(max(angular, -angular_limit), angular_limit))
        )
        positions.append(mover_xy)
        velocities.append(state.movers["velocity"].copy())
        names.append(world.mover_names)
        indices.append(-1 if target is None else target)
        distances.append(distance)
        collisions.append(bool(collided))
        contacts.append(contact_s)
        successes.append(bool(success))
        goals.append(goal[2])
        encodings.append(goal[1])
        rewards.append(float(reward))
        terminations.append(bool(success or ended))
        truncations.append(bool(stepped and now_s >= env._limit_s - _LIMIT_TOLERANCE_S and not (success or ended)))
        sonar_scans.append(sonar_scan)
        laser_scans.append(laser_scan)
        holds.append(hold)
    sonar, sonar_owner = _held(fresh.sonar, fresh.sonar_owner, sonar_scans, holds, "sonar")
    laser, laser_owner = _held(fresh.laser, fresh.laser_owner, laser_scans, holds, "laser")
    for j, (env, hold) in enumerate(zip(envs, holds)):
        env._reading = hold.reading = SensorReading(sonar[j], laser[j], sonar_owner[j], laser_owner[j])
    info = {  # in INFO_KEYS's order
        "time_s": time_s,
        "robot_pose": np.array(poses),
        "robot_velocity": np.array(odometry),
        "mover_positions": positions,
        "mover_velocities": velocities,
        "mover_names": names,
        "target_index": indices,
        "target_distance_m": distances,
        "collision": collisions,
        "contact_s": contacts,
        "success": successes,
        "goal": goals,
        "sonar_hits": sonar_owner.copy(),
        "laser_hits": laser_owner.copy(),
        "sonar_time_s": [hold.sonar_time_s for hold in holds],
        "laser_time_s": [hold.laser_time_s for hold in holds],
    }
    observation = {
        "sonar": sonar.astype(np.float32),
        "laser": laser.astype(np.float32),
        "odometry": np.array(observed, dtype=np.float32),
        "goal": np.array(encodings, dtype=np.float32),
    }
    return CompletedSteps(observation, rewards, terminations, truncations, info)


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
