"""A working memory of the last attended objects, dead-reckoned between fixations.

The focus shows one region at a time; reaching a moving body needs to know where it
is while attention is elsewhere. ``WorkingMemory`` keeps the last ``slots`` tracked
bodies that held the focus. Each entry is written only at a moment the body was
attended, from what attention saw then (its track's position, velocity, speed and
whether the goals held at its region); between fixations its position is dead-reckoned
with the track's last velocity and the robot's odometry pose. Nothing enters from a
track that was never attended.

``read`` gives one row per slot, most recently attended first (``MEMORY_FIELDS``):
cos and sin of the bearing (robot frame, counter-clockwise from the heading), distance
(m), speed (m/s), goal match (0/1) and age (s since it was last attended). An empty
slot is all zeros, which no filled slot is (cos² + sin² = 1).
"""

from __future__ import annotations

import math

import numpy as np

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
        if not isinstance(slots, int) or isinstance(slots, bool) or slots < 1:
            raise ValueError(f"slots must be an integer >= 1, got {slots!r}")
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

    def attend(self, t: float, pose: np.ndarray, track_id: int, position_m: np.ndarray, velocity_mps: np.ndarray,
               speed_mps: float, goal_match: bool) -> None:
        """Write the attended track ``track_id`` at time ``t`` (s) into the first slot.

        ``position_m`` ``(2,)`` and ``velocity_mps`` ``(2,)`` are in the robot frame at
        ``pose``; an entry of the same track moves to the front, the oldest falls out.
        """
        c, s = math.cos(pose[2]), math.sin(pose[2])
        x, y = position_m
        vx, vy = velocity_mps
        entry = (pose[0] + c * x - s * y, pose[1] + s * x + c * y, c * vx - s * vy, s * vx + c * vy)
        same = np.flatnonzero(self._ids == track_id)
        last = int(same[0]) if same.size else self.slots - 1
        for columns in (self._ids, self._state, self._speed, self._match, self._time):
            columns[1:last + 1] = columns[:last].copy()  # shift the newer entries back by one
        self._ids[0], self._state[0] = track_id, entry
        self._speed[0], self._match[0], self._time[0] = speed_mps, float(goal_match), t

    def read(self, t: float, pose: np.ndarray, max_distance_m: float) -> np.ndarray:
        """``(slots, 6)`` float32 rows of ``MEMORY_FIELDS`` at time ``t`` (s), the robot at
        ``pose``; distances are clipped to ``max_distance_m``."""
        rows = np.zeros((self.slots, len(MEMORY_FIELDS)), np.float32)
        c, s = math.cos(pose[2]), math.sin(pose[2])
        for k in range(self.slots):
            age = t - self._time[k]
            if self._ids[k] < 0 or age > self.horizon_s:
                continue
            x, y, vx, vy = self._state[k]
            dx, dy = x + vx * age - pose[0], y + vy * age - pose[1]
            forward, left = c * dx + s * dy, -s * dx + c * dy
            distance = math.hypot(forward, left)
            cos_b, sin_b = (forward / distance, left / distance) if distance > 0.0 else (1.0, 0.0)
            rows[k] = (cos_b, sin_b, min(distance, max_distance_m), self._speed[k], self._match[k], age)
        return rows
