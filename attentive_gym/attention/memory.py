"""Sensorial memory (MODEL.md §2): ring buffers of the last W readings.

- ``SensorMemory``: the last ``W`` readings of O1 (8 front sonars) and O2 (180 laser
  beams), each with its timestamp, its validity and its ego-motion-compensated value;
  it answers the least-squares range rates of §3.

The two observation spaces are stored side by side in one row of ``8 + 180`` channels
(sonars first), so every per-element computation is a single array operation.
"""

from __future__ import annotations

import numpy as np

__all__ = ["SensorMemory"]


class SensorMemory:
    """Ring buffers of the last ``window`` readings of all channels, with timestamps.

    Per stored sample it keeps the raw reading (m), whether it was a no-echo reading,
    and the *compensated* value ``c = s − E``, where ``E`` is the cumulative range change
    that the robot's own motion would have produced on a static world (0 without ego-
    motion compensation). The slope of ``c`` is the range rate of the world itself.

    Args:
        window: W, samples kept (>= 2).
        n_channels: channels per sample (8 sonars + 180 beams = 188).
    """

    def __init__(self, window: int, n_channels: int) -> None:
        self.window = window
        self.n_channels = n_channels
        self._raw = np.zeros((window, n_channels))
        self._comp = np.zeros((window, n_channels))  # compensated values c (m)
        self._invalid = np.zeros((window, n_channels))  # no-echo flags as 0.0 / 1.0
        self._times = [0.0] * window
        self._ego_offset = np.zeros(n_channels)
        self._pos = -1
        self._count = 0

    def reset(self) -> None:
        """Forget every stored sample."""
        self._raw.fill(0.0)
        self._comp.fill(0.0)
        self._invalid.fill(0.0)
        self._ego_offset.fill(0.0)
        self._pos = -1
        self._count = 0

    @property
    def count(self) -> int:
        """Samples stored so far, at most ``window``."""
        return self._count

    @property
    def latest_time(self) -> float | None:
        """Time of the newest sample (s), or None when empty."""
        return self._times[self._pos] if self._count else None

    def latest(self) -> np.ndarray:
        """The newest raw row ``(n_channels,)`` (a view; read-only by contract)."""
        return self._raw[self._pos]

    def latest_invalid(self) -> np.ndarray:
        """No-echo flags of the newest row ``(n_channels,)`` as 0.0 / 1.0 (a view)."""
        return self._invalid[self._pos]

    def push(self, t_s: float, readings: np.ndarray, invalid: np.ndarray, ego_change: np.ndarray | None) -> None:
        """Store one sample.

        Args:
            t_s: its time (s), later than the previous sample's.
            readings: ``(n_channels,)`` ranges (m), clipped to each sensor's maximum.
            invalid: ``(n_channels,)`` bool, True for no-echo readings.
            ego_change: ``(n_channels,)`` range change (m) that the robot's motion since
                the previous sample would produce on a static world, or None for none.
        """
        pos = (self._pos + 1) % self.window
        self._pos = pos
        self._count = min(self._count + 1, self.window)
        self._times[pos] = t_s
        self._raw[pos] = readings
        if ego_change is not None:
            self._ego_offset += ego_change
        np.subtract(readings, self._ego_offset, out=self._comp[pos])
        self._invalid[pos] = invalid

    def range_rates(self, samples: int) -> np.ndarray:
        """Least-squares range rates over the last ``samples`` samples (m/s), ``(n_channels,)``.

        A channel whose window holds a no-echo reading (it switched between echo and no
        echo, or saw nothing) gets 0, as does every channel while fewer than two samples
        are stored. The window is the last ``min(samples, count)`` samples.
        """
        n = min(samples, self._count)
        if n < 2:
            return np.zeros(self.n_channels)
        window = self.window
        positions = [(self._pos - k) % window for k in range(n)]
        # least-squares slope weights (kinematics.slope_weights) on a handful of floats
        times = [self._times[p] for p in positions]
        mean = sum(times) / n
        centred = [x - mean for x in times]
        scale = 1.0 / sum(c * c for c in centred)
        weights = [0.0] * window
        in_window = [0.0] * window
        for p, c in zip(positions, centred):
            weights[p] = c * scale
            in_window[p] = 1.0
        rates = np.dot(np.array(weights), self._comp)
        rates *= np.dot(np.array(in_window), self._invalid) == 0.0
        return rates

    def chronological(self) -> tuple[np.ndarray, np.ndarray]:
        """The stored samples oldest first: times ``(n,)`` (s) and raw rows ``(n, n_channels)`` (m)."""
        order = [(self._pos - k) % self.window for k in range(self._count)][::-1]
        return np.asarray([self._times[p] for p in order], dtype=float), self._raw[order].copy()
