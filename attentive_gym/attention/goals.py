"""Top-down goals: small, validated value objects (docs/model.md §5).

- ``Feature``: what a goal constrains (speed in m/s, distance in m, direction label).
- ``Relation``: ``EQUAL``, ``BETWEEN``, ``GREATER`` or ``SMALLER``.
- ``Direction``: the direction labels of docs/model.md §3 (towards −1, static 0, away +1).
- ``Goal``: one constraint, e.g. ``Goal.between("speed", 0.5, 0.9)``; it encodes to and
  decodes from a fixed-length float vector so that it can live in an observation or an
  action (``Goal.encode`` / ``Goal.decode``, layout in ``GOAL_ENCODING_FIELDS``).

Goals are immutable and validated at construction: an unknown feature or relation, a
negative or non-finite bound, ``lo > hi``, or a relation that does not apply to the
feature raises ``ValueError`` naming the problem and what is allowed.
"""

from __future__ import annotations

import enum
import math
import numbers
from dataclasses import dataclass

import numpy as np

__all__ = [
    "Feature",
    "Relation",
    "Direction",
    "Goal",
    "GOAL_ENCODING_SIZE",
    "GOAL_ENCODING_FIELDS",
    "DEFAULT_EQUAL_TOLERANCE",
]


class Feature(str, enum.Enum):
    """The quantity a goal constrains."""

    SPEED = "speed"  # m/s, the magnitude of a region's range rate
    DISTANCE = "distance"  # m, the nearest valid reading in a region
    DIRECTION = "direction"  # direction label: towards / static / away


class Relation(str, enum.Enum):
    """How a goal compares the feature with its bound(s)."""

    EQUAL = "equal"
    BETWEEN = "between"
    GREATER = "greater"
    SMALLER = "smaller"


class Direction(enum.IntEnum):
    """Direction labels of docs/model.md §3, with the same integer values as ``d_n``."""

    TOWARDS = -1  # range decreasing: approaching the robot
    STATIC = 0
    AWAY = 1  # range increasing: moving away


#: Default half-width of an ``EQUAL`` goal: m/s for speed, m for distance.
DEFAULT_EQUAL_TOLERANCE = {Feature.SPEED: 0.1, Feature.DISTANCE: 0.25}

_FEATURES = tuple(Feature)
_RELATIONS = tuple(Relation)
_DIRECTIONS = (Direction.TOWARDS, Direction.STATIC, Direction.AWAY)

#: Names of the entries of ``Goal.encode()``; an all-zero vector means "no goal".
GOAL_ENCODING_FIELDS: tuple[str, ...] = (
    *(f"feature={f.value}" for f in _FEATURES),
    *(f"relation={r.value}" for r in _RELATIONS),
    "lo",  # EQUAL: the value; BETWEEN: lower bound; GREATER/SMALLER: the threshold
    "hi",  # BETWEEN: upper bound; otherwise equal to lo
    "tolerance",  # EQUAL only, else 0
    *(f"direction={d.name.lower()}" for d in _DIRECTIONS),
)
GOAL_ENCODING_SIZE = len(GOAL_ENCODING_FIELDS)
_LO, _HI, _TOL = 7, 8, 9
_DIR0 = 10
#: float32 keeps ~7 significant digits; bounds are rounded to this many decimals on decode.
_DECODE_DECIMALS = 6


def _parse_enum(enum_type, value, what):
    if isinstance(value, enum_type):
        return value
    if isinstance(value, (bool, np.bool_)):  # True would read as the label 1
        value = repr(value)
    try:
        if isinstance(value, str):
            return enum_type(value.lower()) if issubclass(enum_type, str) else enum_type[value.upper()]
        return enum_type(value)
    except (ValueError, KeyError):
        allowed = ", ".join(repr(m.value if issubclass(enum_type, str) else m.name.lower()) for m in enum_type)
        raise ValueError(f"unknown {what} {value!r}; allowed: {allowed}") from None


def _check_bound(name: str, value) -> float:
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise ValueError(f"goal bound {name} must be a number, got {value!r}")
    value = float(value)
    if not math.isfinite(value):
        raise ValueError(f"goal bound {name} must be finite, got {value}")
    if value < 0.0:
        raise ValueError(f"goal bound {name} must be >= 0 (speeds and distances are magnitudes), got {value}")
    return value


@dataclass(frozen=True)
class Goal:
    """One top-down goal over speed (m/s), distance (m) or direction.

    Prefer the constructors: ``Goal.equal("speed", 0.7)``, ``Goal.between("speed", 0.5, 0.9)``,
    ``Goal.greater("speed", 0.6)``, ``Goal.smaller("distance", 2.0)``,
    ``Goal.direction("towards")``.

    Attributes:
        feature: the constrained quantity.
        relation: the comparison; direction goals are always ``EQUAL``.
        lo: EQUAL value, BETWEEN lower bound, or GREATER/SMALLER threshold (m/s or m);
            ``None`` for direction goals.
        hi: BETWEEN upper bound; equals ``lo`` for the other numeric relations.
        tolerance: EQUAL half-width (same unit as ``lo``); 0 for other relations.
        direction: the wanted direction label (direction goals only).
    """

    feature: Feature
    relation: Relation
    lo: float | None = None
    hi: float | None = None
    tolerance: float = 0.0
    direction: Direction | None = None

    def __post_init__(self) -> None:
        feature = _parse_enum(Feature, self.feature, "goal feature")
        relation = _parse_enum(Relation, self.relation, "goal relation")
        object.__setattr__(self, "feature", feature)
        object.__setattr__(self, "relation", relation)
        if feature is Feature.DIRECTION:
            if relation is not Relation.EQUAL:
                raise ValueError(f"direction goals only support relation 'equal', got {relation.value!r}")
            if self.direction is None:
                raise ValueError("a direction goal needs direction='towards', 'static' or 'away'")
            if self.lo is not None or self.hi is not None:
                raise ValueError("a direction goal takes no numeric bounds (lo/hi must be None)")
            object.__setattr__(self, "direction", _parse_enum(Direction, self.direction, "direction"))
            object.__setattr__(self, "tolerance", 0.0)
            return
        if self.direction is not None:
            raise ValueError(f"a {feature.value} goal takes no direction; use Goal.direction(...) for that")
        if self.lo is None:
            raise ValueError(f"a {feature.value} {relation.value} goal needs a bound lo")
        lo = _check_bound("lo", self.lo)
        if relation is Relation.BETWEEN:
            if self.hi is None:
                raise ValueError("a between goal needs both lo and hi")
            hi = _check_bound("hi", self.hi)
            if lo > hi:
                raise ValueError(f"a between goal needs lo <= hi, got lo={lo} > hi={hi}")
        else:
            if self.hi is not None and _check_bound("hi", self.hi) != lo:
                raise ValueError(f"a {relation.value} goal takes one bound; hi must be None or equal to lo")
            hi = lo
        tolerance = _check_bound("tolerance", self.tolerance)
        if relation is Relation.EQUAL and tolerance == 0.0:
            tolerance = DEFAULT_EQUAL_TOLERANCE[feature]
        elif relation is not Relation.EQUAL and tolerance != 0.0:
            raise ValueError(f"tolerance applies to equal goals only, not {relation.value}")
        object.__setattr__(self, "lo", lo)
        object.__setattr__(self, "hi", hi)
        object.__setattr__(self, "tolerance", tolerance)

    # --- constructors -------------------------------------------------------------
    @classmethod
    def equal(cls, feature: Feature | str, value: float, tolerance: float = 0.0) -> Goal:
        """``|x - value| <= tolerance`` (default tolerance: ``DEFAULT_EQUAL_TOLERANCE``)."""
        return cls(feature, Relation.EQUAL, lo=value, tolerance=tolerance)

    @classmethod
    def between(cls, feature: Feature | str, lo: float, hi: float) -> Goal:
        """``lo <= x <= hi``."""
        return cls(feature, Relation.BETWEEN, lo=lo, hi=hi)

    @classmethod
    def greater(cls, feature: Feature | str, threshold: float) -> Goal:
        """``x >= threshold``."""
        return cls(feature, Relation.GREATER, lo=threshold)

    @classmethod
    def smaller(cls, feature: Feature | str, threshold: float) -> Goal:
        """``x <= threshold``."""
        return cls(feature, Relation.SMALLER, lo=threshold)

    @classmethod
    def direction_is(cls, direction: Direction | str) -> Goal:
        """The region's direction label equals ``direction`` (towards, static, away)."""
        return cls(Feature.DIRECTION, Relation.EQUAL, direction=direction)

    # --- behaviour ----------------------------------------------------------------
    def is_fulfilled(self, value: np.ndarray | float) -> np.ndarray:
        """Elementwise: does ``value`` (m/s, m, or direction labels) satisfy the goal?"""
        x = np.asarray(value, dtype=float)
        if self.feature is Feature.DIRECTION:
            return x == float(self.direction)
        if self.relation is Relation.EQUAL:
            return np.abs(x - self.lo) <= self.tolerance
        if self.relation is Relation.BETWEEN:
            return (x >= self.lo) & (x <= self.hi)
        if self.relation is Relation.GREATER:
            return x >= self.lo
        return x <= self.lo

    def encode(self) -> np.ndarray:
        """The goal as a ``(GOAL_ENCODING_SIZE,)`` float32 vector (see ``GOAL_ENCODING_FIELDS``)."""
        vec = np.zeros(GOAL_ENCODING_SIZE, dtype=np.float32)
        vec[_FEATURES.index(self.feature)] = 1.0
        vec[len(_FEATURES) + _RELATIONS.index(self.relation)] = 1.0
        if self.feature is Feature.DIRECTION:
            vec[_DIR0 + _DIRECTIONS.index(self.direction)] = 1.0
        else:
            vec[_LO], vec[_HI], vec[_TOL] = self.lo, self.hi, self.tolerance
        return vec

    @classmethod
    def decode(cls, vector) -> Goal | None:
        """Inverse of ``encode``; an all-zero vector decodes to ``None`` (no goal).

        One-hot groups are read by their largest entry, so a policy's continuous output
        can be decoded too; bounds are clipped at 0, rounded to ``_DECODE_DECIMALS``
        decimals (so a float32 round trip gives back the same goal), and a BETWEEN with
        ``lo > hi`` is reordered.
        """
        try:
            vec = np.asarray(vector, dtype=float).reshape(-1)
        except (TypeError, ValueError):
            raise ValueError(f"a goal encoding must be {GOAL_ENCODING_SIZE} numbers, got {vector!r}") from None
        if vec.shape != (GOAL_ENCODING_SIZE,):
            raise ValueError(f"a goal encoding has {GOAL_ENCODING_SIZE} entries, got shape {np.shape(vector)}")
        if not np.all(np.isfinite(vec)):
            raise ValueError("a goal encoding must be finite")
        if not np.any(vec):
            return None
        feature = _FEATURES[int(np.argmax(vec[: len(_FEATURES)]))]
        if feature is Feature.DIRECTION:
            return cls.direction_is(_DIRECTIONS[int(np.argmax(vec[_DIR0:]))])
        relation = _RELATIONS[int(np.argmax(vec[len(_FEATURES) : _LO]))]
        lo, hi, tol = (round(max(float(v), 0.0), _DECODE_DECIMALS) for v in vec[_LO : _TOL + 1])
        if relation is Relation.BETWEEN:
            return cls.between(feature, min(lo, hi), max(lo, hi))
        if relation is Relation.EQUAL:
            return cls.equal(feature, lo, tolerance=tol)
        return cls(feature, relation, lo=lo)

    def __str__(self) -> str:
        if self.feature is Feature.DIRECTION:
            return f"direction == {self.direction.name.lower()}"
        unit = "m/s" if self.feature is Feature.SPEED else "m"
        if self.relation is Relation.BETWEEN:
            return f"{self.feature.value} in [{self.lo:g}, {self.hi:g}] {unit}"
        if self.relation is Relation.EQUAL:
            return f"{self.feature.value} == {self.lo:g} ± {self.tolerance:g} {unit}"
        sign = ">=" if self.relation is Relation.GREATER else "<="
        return f"{self.feature.value} {sign} {self.lo:g} {unit}"
