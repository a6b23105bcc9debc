"""Range noise: multiplicative relative noise on valid echoes, Gaussian or uniform.

- ``NOISE_MODELS``: the model names, ``("gaussian", "uniform")``.
- ``check_noise_model``: a model name, or ``ValueError`` naming the allowed ones.
- ``unit_noise``: the unit draws of a model (``N(0, 1)`` or ``U[-1, 1)``), a fixed number per reading.
- ``unit_noise_rows``: the same for N robots at once, row i from robot i's own generator.
- ``apply_range_noise``: ``r (1 + level d)`` on every reading below the maximum range, with
  ``d`` a unit draw, clipped to the sensor's limits; "no echo" readings stay exactly at the maximum.

The uniform model is USARSim's: its sensors apply their ``Noise`` setting ``a`` as
``(1 + RandRange(-a, a)) * reading``, so ``a = 0.05`` is ±5 % of the reading
(standard deviation ``a / sqrt(3)`` ≈ 2.9 %).
"""

from __future__ import annotations

import math

import numpy as np

from attentive_gym.sensors._checks import check_relative_std

__all__ = ["NOISE_MODELS", "apply_range_noise", "check_noise_model", "unit_noise", "unit_noise_rows"]

#: ``"gaussian"``: level = sigma of ``N(0, 1)`` draws; ``"uniform"``: level = half-width of ``U[-1, 1)`` draws.
NOISE_MODELS = ("gaussian", "uniform")


def check_noise_model(name: str, model) -> str:
    """``model`` itself, or ``ValueError`` (naming ``name``) unless it is one of ``NOISE_MODELS``."""
    if not isinstance(model, str) or model not in NOISE_MODELS:
        raise ValueError(f"{name} must be one of {list(NOISE_MODELS)}, got {model!r}")
    return model


def unit_noise(model: str, shape, rng: np.random.Generator, out: np.ndarray | None = None) -> np.ndarray:
    """Unit draws of noise model ``model``, one per reading.

    ``"gaussian"``: ``rng.standard_normal(shape)``; ``"uniform"``: ``2 rng.random(shape) - 1``,
    in [-1, 1). Either way exactly one draw per element, so the RNG stream does not depend
    on the readings or the noise level.

    Args:
        model: one of ``NOISE_MODELS``.
        shape: int or tuple, the readings' shape.
        rng: the generator the draws come from.
        out: a float64 array of ``shape`` to draw into (the same values as a new one gets),
            or None for a new array.

    Returns:
        float64 array of ``shape`` (``out`` when given).

    Raises:
        ValueError: for an unknown ``model``.
    """
    if model == "gaussian":
        return rng.standard_normal(shape, out=out)
    if model == "uniform":
        draws = rng.random(shape, out=out)
        draws *= 2.0
        draws -= 1.0
        return draws
    raise ValueError(f"noise model must be one of {list(NOISE_MODELS)}, got {model!r}")


def unit_noise_rows(model: str, rngs, out: np.ndarray, rows=None) -> np.ndarray:
    """Unit draws of noise model ``model`` into the rows of ``out``, row i from ``rngs[i]``.

    Row i gets the numbers ``unit_noise(model, K, rngs[i])`` would give, drawn in row order
    (a generator listed twice draws its rows in turn), with one call into each generator
    and, for ``"uniform"``, the scaling to ``[-1, 1)`` done once for the whole block.

    Args:
        model: one of ``NOISE_MODELS``.
        rngs: N generators (not checked: the caller checks them before drawing any).
        out: ``(N, K)`` C-contiguous float64 array, written.
        rows: the indices of the rows to draw, increasing (the other rows and their
            generators are left alone), or None for every row.

    Returns:
        ``out``.

    Raises:
        ValueError: for an unknown ``model``.
    """
    if model not in NOISE_MODELS:
        raise ValueError(f"noise model must be one of {list(NOISE_MODELS)}, got {model!r}")
    pairs = zip(rngs, out) if rows is None else ((rngs[i], out[i]) for i in rows)
    if model == "gaussian":
        for rng, row in pairs:
            rng.standard_normal(out=row)
        return out
    for rng, row in pairs:
        rng.random(out=row)
    block = out if rows is None else out[rows]
    block *= 2.0
    block -= 1.0
    if rows is not None:
        out[rows] = block
    return out


def apply_range_noise(
    ranges,
    relative_std: float,
    min_range_m: float,
    max_range_m: float,
    rng: np.random.Generator,
    model: str = "gaussian",
) -> np.ndarray:
    """Noisy copy of ``ranges``: ``r (1 + relative_std d)`` clipped to the limits.

    ``d`` is a unit draw of ``model`` (``unit_noise``): ``N(0, 1)`` for ``"gaussian"``
    (``relative_std`` is then sigma) or ``U[-1, 1)`` for ``"uniform"`` (``relative_std`` is
    then the half-width ``a``: every noisy reading lies within ``r (1 ± a)``).

    Readings at or beyond ``max_range_m`` mean "no echo" and stay exactly at
    ``max_range_m``; all others get the noise and are clipped to
    ``[min_range_m, max_range_m]``.

    RNG stream: exactly one draw per reading (a standard normal for ``"gaussian"``, a
    ``rng.random`` uniform for ``"uniform"``), whatever the readings and whatever
    ``relative_std`` (0 included), so the stream a simulation consumes does not depend on
    the noise level or on what the sensors see; with ``relative_std = 0`` the result equals
    the input (when it lies within the limits).

    Args:
        ranges: readings (m), any shape.
        relative_std: the noise level (sigma, or the uniform half-width), finite, in [0, 1).
        min_range_m: lower clip (m), finite, >= 0.
        max_range_m: the "no echo" value and upper clip (m), > ``min_range_m``.
        rng: the generator the draws come from.
        model: one of ``NOISE_MODELS``.

    Returns:
        float64 array of the shape of ``ranges`` (a new array).

    Raises:
        ValueError: for a bad level, limits or model. TypeError: if ``rng`` is not a Generator.

    Example:
        >>> noisy = apply_range_noise([2.0, 5.0], 0.05, 0.15, 5.0, np.random.default_rng(0), model="uniform")
        >>> bool(abs(noisy[0] - 2.0) <= 0.1), float(noisy[1])
        (True, 5.0)
    """
    sigma = check_relative_std("relative_std", relative_std)
    model = check_noise_model("model", model)
    if not (math.isfinite(min_range_m) and math.isfinite(max_range_m) and 0.0 <= min_range_m < max_range_m):
        raise ValueError(f"need finite 0 <= min_range_m < max_range_m, got {min_range_m!r} and {max_range_m!r}")
    if not isinstance(rng, np.random.Generator):
        raise TypeError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
    ranges = np.asarray(ranges, dtype=np.float64)
    noisy = ranges * (1.0 + sigma * unit_noise(model, ranges.shape, rng))
    np.clip(noisy, min_range_m, max_range_m, out=noisy)
    noisy[ranges >= max_range_m] = max_range_m
    return noisy
