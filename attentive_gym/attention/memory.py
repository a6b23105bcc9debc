"""Sensorial memory (docs/model.md §2): ring buffers of the last W readings.

- ``SensorMemory``: the last ``W`` readings of O1 (8 front sonars) and O2 (180 laser
  beams), each with its timestamp, its validity and its ego-motion-compensated value;
  it answers the least-squares range rates of §3.

The two observation spaces are stored side by side in one row of ``8 + 180`` channels
(sonars first), so every per-element computation is a single array operation.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from attentive_gym.attention._numerics import vecmat

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
        # [raw readings (m), compensated values c (m), no-echo flags as 0.0 / 1.0], each
        # (window, n_channels); indexed where used (views kept as attributes would come
        # apart from it on a copy or pickle)
        self._samples = np.zeros((3, window, n_channels))
        self._times = np.zeros(window)  # (s)
        self._ego_offset = np.zeros(n_channels)
        # [position of the newest sample (-1 when empty), samples stored]
        self._state = np.array([-1, 0], dtype=np.int64)

    def reset(self) -> None:
        """Forget every stored sample."""
        self._samples.fill(0.0)
        self._ego_offset.fill(0.0)
        self._state[:] = (-1, 0)

    @property
    def buffers(self) -> tuple[np.ndarray, ...]:
        """``(state, times, samples, ego_offset)`` for ``push_sample`` and ``slope_rates`` in
        compiled callers (the arrays themselves, updated in place); ``samples`` is
        ``(3, window, n_channels)``: raw readings, compensated values, no-echo flags."""
        return self._state, self._times, self._samples, self._ego_offset

    @property
    def count(self) -> int:
        """Samples stored so far, at most ``window``."""
        return int(self._state[1])

    @property
    def latest_time(self) -> float | None:
        """Time of the newest sample (s), or None when empty."""
        return float(self._times[self._state[0]]) if self._state[1] else None

    def latest(self) -> np.ndarray:
        """The newest raw row ``(n_channels,)`` (a view; read-only by contract)."""
        return self._samples[0, self._state[0]]

    def push(self, t_s: float, readings: np.ndarray, invalid: np.ndarray, ego_change: np.ndarray | None) -> None:
        """Store one sample.

        Args:
            t_s: its time (s), later than the previous sample's.
            readings: ``(n_channels,)`` ranges (m), clipped to each sensor's maximum.
            invalid: ``(n_channels,)`` bool, True for no-echo readings.
            ego_change: ``(n_channels,)`` range change (m) that the robot's motion since
                the previous sample would produce on a static world, or None for none.
        """
        moved = ego_change is not None
        push_sample(*self.buffers, t_s, readings, invalid, ego_change if moved else self._ego_offset, moved)

    def range_rates(self, samples: int) -> np.ndarray:
        """Least-squares range rates over the last ``samples`` samples (m/s), ``(n_channels,)``.

        A channel whose window holds a no-echo reading (it switched between echo and no
        echo, or saw nothing) gets 0, as does every channel while fewer than two samples
        are stored. The window is the last ``min(samples, count)`` samples.
        """
        rates = np.empty(self.n_channels)
        slope_rates(self._state, self._times, self._samples, samples, rates)
        return rates

    def chronological(self) -> tuple[np.ndarray, np.ndarray]:
        """The stored samples oldest first: times ``(n,)`` (s) and raw rows ``(n, n_channels)`` (m)."""
        pos, count = (int(v) for v in self._state)
        order = [(pos - k) % self.window for k in range(count)][::-1]
        return self._times[order], self._samples[0][order]


@njit(cache=True)
def push_sample(state, times, samples, ego_offset, t_s, readings, invalid_now, ego_change, moved):
    """Store one sample in the ring buffers of ``SensorMemory.buffers`` (see ``push``).

    ``readings`` and ``ego_change`` are ``(n_channels,)`` metres, ``invalid_now``
    ``(n_channels,)`` bool, ``t_s`` seconds; ``ego_change`` is used only when ``moved``.
    """
    raw, comp, invalid = samples[0], samples[1], samples[2]
    window = raw.shape[0]
    pos = (state[0] + 1) % window
    state[0] = pos
    state[1] = min(state[1] + 1, window)
    times[pos] = t_s
    for c in range(raw.shape[1]):
        raw[pos, c] = readings[c]
        if moved:
            ego_offset[c] += ego_change[c]
        comp[pos, c] = readings[c] - ego_offset[c]
        invalid[pos, c] = 1.0 if invalid_now[c] else 0.0


@njit(cache=True)
def slope_rates(state, times, samples, n_samples, out):
    """Write ``SensorMemory.range_rates(n_samples)`` into ``out`` ``(n_channels,)`` (m/s).

    The slope weights (``kinematics.slope_weights``) of the last ``n = min(n_samples,
    count)`` times, newest first, with sequential sums; the weighted sum over the whole
    ring (weight 0 outside the window) in the order of ``np.dot`` (``_numerics.vecmat``).
    """
    comp, invalid = samples[1], samples[2]
    window = comp.shape[0]
    pos, count = state[0], state[1]
    n = min(n_samples, count)
    if n < 2:
        out[:] = 0.0
        return
    positions = np.empty(n, np.int64)  # ring positions, newest first
    total = 0.0
    for k in range(n):
        positions[k] = (pos - k) % window
        total += times[positions[k]]
    mean = total / n
    sum_sq = 0.0
    for k in range(n):
        c = times[positions[k]] - mean
        sum_sq += c * c
    scale = 1.0 / sum_sq
    weights = np.zeros(window)
    for k in range(n):
        weights[positions[k]] = (times[positions[k]] - mean) * scale
    vecmat(weights, comp, out)
    n_channels = comp.shape[1]
    seen_nothing = np.zeros(n_channels, np.bool_)
    for k in range(n):
        for c in range(n_channels):
            seen_nothing[c] |= invalid[positions[k], c] != 0.0
    for c in range(n_channels):
        out[c] *= 0.0 if seen_nothing[c] else 1.0
