"""Scan rates: a sensor takes a new reading only every so often and holds it in between.

- ``SCAN_TOLERANCE_S``: the slack on "at least the interval has passed".
- ``scan_due``: whether a sensor with a scan interval scans at a given world time.
- ``ScanHold``: the reading each sensor returns under its interval, and when it was scanned.
"""

from __future__ import annotations

import math

from attentive_gym.sensors._checks import check_scan_interval
from attentive_gym.sensors.suite import SensorReading

__all__ = ["SCAN_TOLERANCE_S", "ScanHold", "scan_due"]

#: s: world time is ``steps * dt``, which can land a rounding error below a multiple of the
#: interval; this slack (far below any step) makes 0.2 s at dt 0.05 scan every 4th step exactly.
SCAN_TOLERANCE_S = 1e-9


def scan_due(now_s: float, last_scan_s: float, interval_s: float | None) -> bool:
    """Whether a sensor last scanned at ``last_scan_s`` (s; ``-inf``: never) scans at ``now_s`` (s).

    Always for ``interval_s=None`` (a scan every step); otherwise once at least
    ``interval_s`` (less ``SCAN_TOLERANCE_S``) has passed since the last scan.
    """
    return interval_s is None or now_s - last_scan_s >= interval_s - SCAN_TOLERANCE_S


class ScanHold:
    """The sonar and laser readings under their scan intervals: fresh at a scan, held in between.

    Each sensor scans at the first ``update`` after ``reset`` and then whenever ``scan_due``.
    The caller reads both sensors at every ``update``, whatever is due, so the RNG stream
    (the noise draws) does not depend on the intervals; a held reading is the noisy reading
    of its scan, returned unchanged (no new noise), owners included.

    Args:
        sonar_scan_interval_s: s between sonar scans, finite and > 0, or ``None`` for every step.
        laser_scan_interval_s: the same for the laser.

    Attributes:
        reading: the ``SensorReading`` the last ``update`` returned (``None`` before one).
        sonar_time_s: world time (s) of the scan the current sonar reading came from
            (``-inf`` before the first ``update``).
        laser_time_s: the same for the laser.

    Raises:
        ValueError: for a bad interval, naming it and what is allowed.

    Example:
        >>> import numpy as np
        >>> hold = ScanHold(laser_scan_interval_s=0.2)
        >>> fresh = [SensorReading(np.full(16, t), np.full(180, t), np.full(16, -1), np.full(180, -1))
        ...          for t in (0.0, 0.1, 0.2)]
        >>> [(float(hold.update(r, t).laser[0]), hold.laser_time_s) for r, t in zip(fresh, (0.0, 0.1, 0.2))]
        [(0.0, 0.0), (0.0, 0.0), (0.2, 0.2)]
    """

    def __init__(self, sonar_scan_interval_s: float | None = None, laser_scan_interval_s: float | None = None) -> None:
        self.sonar_scan_interval_s = check_scan_interval("sonar_scan_interval_s", sonar_scan_interval_s)
        self.laser_scan_interval_s = check_scan_interval("laser_scan_interval_s", laser_scan_interval_s)
        self._every_step = self.sonar_scan_interval_s is None and self.laser_scan_interval_s is None
        self.reset()

    def reset(self) -> None:
        """Forget the held readings: the next ``update`` scans both sensors."""
        self.reading: SensorReading | None = None
        self.sonar_time_s = self.laser_time_s = -math.inf

    def scans(self, now_s: float) -> tuple[bool, bool]:
        """Whether the sonar and the laser scan at world time ``now_s`` (s); the scan times of
        those that do become ``now_s``. The caller then stores the reading it composed from
        the fresh and the held rows as ``reading`` (``update`` does both for one reading; a
        batched step composes many members' readings at once).

        Example:
            >>> hold = ScanHold(sonar_scan_interval_s=0.2)
            >>> hold.scans(0.0), hold.scans(0.1), hold.sonar_time_s
            ((True, True), (False, True), 0.0)
        """
        if self._every_step:
            self.sonar_time_s = self.laser_time_s = now_s
            return True, True
        sonar_scans = scan_due(now_s, self.sonar_time_s, self.sonar_scan_interval_s)
        laser_scans = scan_due(now_s, self.laser_time_s, self.laser_scan_interval_s)
        if sonar_scans:
            self.sonar_time_s = now_s
        if laser_scans:
            self.laser_time_s = now_s
        return sonar_scans, laser_scans

    def update(self, fresh: SensorReading, now_s: float) -> SensorReading:
        """The reading at world time ``now_s`` (s), given ``fresh``, a new reading of both sensors.

        Returns ``fresh`` itself when both sensors scan, the held reading itself when
        neither does, and otherwise a new ``SensorReading`` with the scanning sensor's
        ranges and owners from ``fresh`` and the other's held arrays, unchanged.
        """
        sonar_scans, laser_scans = self.scans(now_s)
        if sonar_scans != laser_scans:
            sonar, laser = (fresh, self.reading) if sonar_scans else (self.reading, fresh)
            self.reading = SensorReading(sonar.sonar, laser.laser, sonar.sonar_owner, laser.laser_owner)
        elif sonar_scans:
            self.reading = fresh
        return self.reading
