"""``SensorLog``: the readings of a logged run, checked; and ``LogFormatError``.

A log holds T readings: times (s, strictly increasing), the sonar ring or its front
sonars (m), the laser (m) and optionally odometry (v m/s, w rad/s). ``replay.load_log``
reads one from a CSV or NPZ file, ``rosbag.read_bag`` from a ROS bag; both return it
checked, and ``replay.replay_log`` steps a model over it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from attentive_gym.attention.model import MIN_TIME_STEP_S
from attentive_gym.attention.regions import FRONT_SONARS, LASER_BEAMS, SONAR_RING

__all__ = ["SensorLog", "LogFormatError"]


class LogFormatError(ValueError):
    """A sensor log that cannot be replayed; the message says what is wrong and what is allowed."""


@dataclass(frozen=True, eq=False)
class SensorLog:
    """Readings of a logged run, checked by ``check``.

    Attributes:
        t: ``(T,)`` times (s), strictly increasing.
        sonar: ``(T, 16)`` or ``(T, 8)`` sonar ranges (m).
        laser: ``(T, 180)`` laser ranges (m).
        odometry: ``(T, 2)`` robot velocity (v m/s, w rad/s) or None.
    """

    t: np.ndarray
    sonar: np.ndarray
    laser: np.ndarray
    odometry: np.ndarray | None = None

    def check(self, source: str = "log") -> SensorLog:
        """Validate shapes and values; returns self. Raises ``LogFormatError``."""
        n = self.t.shape[0] if self.t.ndim == 1 else -1
        if n < 1:
            raise LogFormatError(f"{source}: t must be a non-empty 1-D array of times (s), got shape {self.t.shape}")
        if self.sonar.shape not in ((n, SONAR_RING), (n, FRONT_SONARS)):
            raise LogFormatError(
                f"{source}: sonar must be ({n}, {SONAR_RING}) or ({n}, {FRONT_SONARS}), got {self.sonar.shape}"
            )
        if self.laser.shape != (n, LASER_BEAMS):
            raise LogFormatError(f"{source}: laser must be ({n}, {LASER_BEAMS}), got {self.laser.shape}")
        if self.odometry is not None and self.odometry.shape != (n, 2):
            raise LogFormatError(f"{source}: odometry must be ({n}, 2) = (v m/s, w rad/s), got {self.odometry.shape}")
        for name in ("t", "sonar", "laser", "odometry"):
            values = getattr(self, name)
            if values is None:
                continue
            bad = ~np.isfinite(values)
            if bad.any():
                row = int(np.argwhere(bad)[0][0])
                raise LogFormatError(
                    f"{source}: {name} holds NaN or inf (first at reading {row}); "
                    "log 'no echo' as the sensor's maximum range"
                )
        for name in ("sonar", "laser"):
            negative = getattr(self, name) < 0.0
            if negative.any():
                row = int(np.argwhere(negative)[0][0])
                raise LogFormatError(
                    f"{source}: {name} holds a negative range (first at reading {row}); ranges are >= 0 m"
                )
        steps = np.diff(self.t)
        if np.any(~(steps >= MIN_TIME_STEP_S)):
            row = int(np.flatnonzero(~(steps >= MIN_TIME_STEP_S))[0]) + 1
            raise LogFormatError(
                f"{source}: t must be strictly increasing (s, by at least {MIN_TIME_STEP_S:g} s "
                f"per reading); reading {row} has t={self.t[row]!r} after t={self.t[row - 1]!r}"
            )
        return self
