"""A working memory of the last attended objects, dead-reckoned between fixations.

The focus shows one region at a time; reaching a moving body needs to know where it
is while attention is elsewhere. ``WorkingMemory`` keeps the last ``slots`` tracked
bodies that held the focus. Each entry is written only at a moment the body was
attended, from what attention saw then (its track's position, velocity, speed and
whether the goals held at its region); between fixations its position is dead-reckoned
with the track's last velocity and the robot's odometry pose. Nothing enters from a
track that was never attended.

``read`` gives one row per slot (``MEMORY_FIELDS``): cos and sin of the bearing (robot
frame, counter-clockwise from the heading), distance (m), speed (m/s), goal match (0/1)
and age (s since it was last attended). The bodies that matched the goal when they were
attended come first, then the others, each group most recently attended first: the
first row is the body the task asks for whenever attention has found one, in the same
place as the ``oracle`` variant's target, so a policy need not search the rows for it.
An empty slot is all zeros, which no filled slot is (cos² + sin² = 1); empty slots come
last.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from attentive_gym._checks import check_int

__all__ = ["MEMORY_FIELDS", "WorkingMemory"]

#: The columns of ``WorkingMemory.read``.
MEMORY_FIELDS = ("cos_bearing", "sin_bearing", "distance_m", "speed_mps", "goal_match", "age_s")


class WorkingMemory:
    """The last ``slots`` attended tracks.

    Args:
        slots: how many bodies are remembered (K ≥ 1).
        horizon_s: an entry not attended for longer than this (s, > 0) is forgotten.

    Positions live in the odometry frame of ``AttentionModel.odometry_pose`` (``pose``
    arguments: ``(3,)`` x m, y m, heading rad), so the robot's own motion is compensated
    by construction.
    """

    def __init__(self, slots: int = 3, horizon_s: float = 10.0) -> None:
        check_int("slots", slots, 1)
        if not (isinstance(horizon_s, (int, float)) and math.isfinite(horizon_s) and horizon_s > 0):
            raise ValueError(f"horizon_s must be a finite number > 0 (s), got {horizon_s!r}")
        self.slots = slots
        self.horizon_s = float(horizon_s)
        self._ids = np.full(slots, -1, np.int64)  # track id per slot, −1 empty
        self._state = np.zeros((slots, 4))  # x, y (m), vx, vy (m/s) in the odometry frame
        self._speed = np.zeros(slots)  # m/s, as attended
        self._match = np.zeros(slots)  # 1 where the goals held at the body's region
        self._time = np.zeros(slots)  # s, when last attended

    def reset(self) -> None:
        """Forget every entry."""
        self._ids[:] = -1

    def attend(
        self,
        t: float,
        pose: np.ndarray,
        track_id: int,
        position_m: np.ndarray,
        velocity_mps: np.ndarray,
        speed_mps: float,
        goal_match: bool,
    ) -> None:
        """Write the attended track ``track_id`` at time ``t`` (s) into the first slot.

        ``position_m`` ``(2,)`` and ``velocity_mps`` ``(2,)`` are in the robot frame at
        ``pose``; an entry of the same track moves to the front, the oldest falls out.
        """
        _attend(
            t,
            pose,
            track_id,
            position_m,
            velocity_mps,
            speed_mps,
            float(goal_match),
            self._ids,
            self._state,
            self._speed,
            self._match,
            self._time,
        )

    def read(self, t: float, pose: np.ndarray, max_distance_m: float) -> np.ndarray:
        """``(slots, 6)`` float32 rows of ``MEMORY_FIELDS`` at time ``t`` (s), the robot at
        ``pose``, goal matches first (see the module docstring); distances are clipped to
        ``max_distance_m``."""
        rows = np.zeros((self.slots, len(MEMORY_FIELDS)), np.float32)
        _read(
            t, pose, max_distance_m, self.horizon_s, self._ids, self._state, self._speed, self._match, self._time, rows
        )
        return rows


@njit(cache=True)
def _attend(t, pose, track_id, position_m, velocity_mps, speed_mps, goal_match, ids, state, speed, match, time):
    """``WorkingMemory.attend`` on its arrays: shift the entries newer than the track's own
    (or all but the oldest) back by one and write the track at the front, in the odometry frame."""
    last = ids.shape[0] - 1
    for k in range(ids.shape[0]):
        if ids[k] == track_id:
            last = k
            break
    for k in range(last, 0, -1):
        ids[k], speed[k], match[k], time[k] = ids[k - 1], speed[k - 1], match[k - 1], time[k - 1]
        state[k, :] = state[k - 1, :]
    c, s = math.cos(pose[2]), math.sin(pose[2])
    x, y = position_m[0], position_m[1]
    vx, vy = velocity_mps[0], velocity_mps[1]
    ids[0] = track_id
    state[0, 0], state[0, 1] = pose[0] + c * x - s * y, pose[1] + s * x + c * y
    state[0, 2], state[0, 3] = c * vx - s * vy, s * vx + c * vy
    speed[0], match[0], time[0] = speed_mps, goal_match, t


@njit(cache=True)
def _read(t, pose, max_distance_m, horizon_s, ids, state, speed, match, time, rows):
    """``WorkingMemory.read`` into ``rows`` ``(K, 6)`` (zeros on entry): dead-reckon each live
    entry to ``t`` and express it in the robot frame at ``pose``; the entries that matched
    the goal first, then the others, each in slot (recency) order."""
    c, s = math.cos(pose[2]), math.sin(pose[2])
    row = 0
    for matched_pass in range(2):
        for k in range(ids.shape[0]):
            age = t - time[k]
            if ids[k] < 0 or age > horizon_s or (match[k] == 1.0) != (matched_pass == 0):
                continue
            _read_entry(k, age, c, s, pose, max_distance_m, state, speed, match, rows[row])
            row += 1


@njit(cache=True)
def _read_entry(k, age, c, s, pose, max_distance_m, state, speed, match, out):
    """Entry ``k`` dead-reckoned over ``age`` seconds, in the robot frame at ``pose``
    (``c, s``: cos, sin of its heading), into the row ``out`` ``(6,)``."""
    dx = state[k, 0] + state[k, 2] * age - pose[0]
    dy = state[k, 1] + state[k, 3] * age - pose[1]
    forward, left = c * dx + s * dy, -s * dx + c * dy
    distance = math.hypot(forward, left)
    if distance > 0.0:
        out[0], out[1] = forward / distance, left / distance
    else:
        out[0] = 1.0
    out[2] = min(distance, max_distance_m)
    out[3], out[4], out[5] = speed[k], match[k], age
