"""Range noise: multiplicative Gaussian noise on valid echoes.

- ``apply_range_noise``: ``r (1 + sigma N(0, 1))`` on every reading below the maximum
  range, clipped to the sensor's limits; "no echo" readings stay exactly at the maximum.
"""

from __future__ import annotations

import math

import numpy as np

from attentive_gym.sensors._checks import check_relative_std

__all__ = ["apply_range_noise"]


def apply_range_noise(ranges, relative_std: float, min_range_m: float, max_range_m: float,
                      rng: np.random.Generator) -> np.ndarray:
    """Noisy copy of ``ranges``: ``r (1 + relative_std N(0, 1))`` clipped to the limits.

    Readings at or beyond ``max_range_m`` mean "no echo" and stay exactly at
    ``max_range_m``; all others get the noise and are clipped to
    ``[min_range_m, max_range_m]``.

    RNG stream: exactly one standard normal is drawn per reading, whatever the readings
    and whatever ``relative_std`` (0 included), so the stream a simulation consumes does
    not depend on the noise level or on what the sensors see; with ``relative_std = 0``
    the result equals the input (when it lies within the limits).

    Args:
        ranges: readings (m), any shape.
        relative_std: sigma, finite, in [0, 1).
        min_range_m: lower clip (m), finite, >= 0.
        max_range_m: the "no echo" value and upper clip (m), > ``min_range_m``.
        rng: the generator the normals come from.

    Returns:
        float64 array of the shape of ``ranges`` (a new array).

    Raises:
        ValueError: for a bad sigma or limits. TypeError: if ``rng`` is not a Generator.

    Example:
        >>> noisy = apply_range_noise([2.0, 5.0], 0.05, 0.15, 5.0, np.random.default_rng(0))
        >>> bool(abs(noisy[0] - 2.0) < 0.5), float(noisy[1])
        (True, 5.0)
    """
    sigma = check_relative_std("relative_std", relative_std)
    if not (math.isfinite(min_range_m) and math.isfinite(max_range_m) and 0.0 <= min_range_m < max_range_m):
        raise ValueError(f"need finite 0 <= min_range_m < max_range_m, got {min_range_m!r} and {max_range_m!r}")
    if not isinstance(rng, np.random.Generator):
        raise TypeError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
    ranges = np.asarray(ranges, dtype=np.float64)
    noisy = ranges * (1.0 + sigma * rng.standard_normal(ranges.shape))
    np.clip(noisy, min_range_m, max_range_m, out=noisy)
    noisy[ranges >= max_range_m] = max_range_m
    return noisy
