"""Reading and writing scenarios as YAML or JSON.

- ``scenario_from_dict``: build a validated ``Scenario`` from plain data (keys = field names).
- ``scenario_to_dict``: the inverse, plain data that round-trips.
- ``load_scenario`` / ``save_scenario``: ``.yaml``, ``.yml`` or ``.json`` files.

Unions (rubble, behaviours) are tagged by a ``kind`` key (``box``/``circle``/``segment``;
``path``/``pursue``/``evade``). Any problem raises ``ValueError`` that names the place in
the file (``movers[1].behaviour.legs[0]``), the offending key, and what is allowed.
A minimal file::

    name: corridor
    bounds: [-5, -3, 5, 3]
    enclosed: true
    robot: {x_m: -4, y_m: 0, heading_deg: 0}
    rubble:
      - {kind: box, x_m: 1, y_m: 1, width_m: 0.5, height_m: 0.4}
    movers:
      - name: survivor
        kind: victim
        start: {x_m: 3, y_m: 0}
        behaviour: {kind: path, loop: true, legs: [{to: [3, 2], speed_mps: 0.7}]}
    task: {target: survivor, goal: {feature: speed, relation: between, lo: 0.5, hi: 0.9}}
"""

from __future__ import annotations

import dataclasses
import enum
import json
import os
import types
import typing
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import yaml

from attentive_gym._atomic import atomic_file
from attentive_gym.attention.goals import Goal
from attentive_gym.world.scenario import (
    BoxRubble,
    CircleRubble,
    EvadeBehaviour,
    PathBehaviour,
    PursueBehaviour,
    Scenario,
    SegmentRubble,
)

__all__ = ["scenario_from_dict", "scenario_to_dict", "load_scenario", "save_scenario", "SCENARIO_SUFFIXES"]

SCENARIO_SUFFIXES = (".yaml", ".yml", ".json")
_TAGGED = {
    "rubble": {"box": BoxRubble, "circle": CircleRubble, "segment": SegmentRubble},
    "behaviour": {"path": PathBehaviour, "pursue": PursueBehaviour, "evade": EvadeBehaviour},
}
_GOAL_KEYS = ("feature", "relation", "lo", "hi", "tolerance", "direction")


def _build(tp: Any, data: Any, where: str) -> Any:
    """Convert plain ``data`` to the annotated type ``tp``, naming ``where`` on errors."""
    origin = typing.get_origin(tp)
    if origin in (typing.Union, types.UnionType):
        options = [a for a in typing.get_args(tp) if a is not type(None)]
        if data is None:
            if len(options) < len(typing.get_args(tp)):
                return None
            raise ValueError(f"{where}: a value is required")
        if len(options) == 1:
            return _build(options[0], data, where)
        return _build_tagged(options, data, where)
    if origin is tuple:
        args = typing.get_args(tp)
        if not isinstance(data, (list, tuple)):
            raise ValueError(f"{where}: expected a list, got {type(data).__name__}")
        if len(args) == 2 and args[1] is Ellipsis:
            return tuple(_build(args[0], item, f"{where}[{i}]") for i, item in enumerate(data))
        if len(data) != len(args):
            raise ValueError(f"{where}: expected {len(args)} values, got {len(data)}")
        return tuple(_build(a, item, f"{where}[{i}]") for i, (a, item) in enumerate(zip(args, data)))
    if origin is typing.Literal:
        if data not in typing.get_args(tp):
            raise ValueError(f"{where}: must be one of {list(typing.get_args(tp))}, got {data!r}")
        return data
    if tp is Goal:
        return _build_goal(data, where)
    if dataclasses.is_dataclass(tp):
        return _build_dataclass(tp, data, where)
    if tp is float:
        if isinstance(data, bool) or not isinstance(data, (int, float)):
            raise ValueError(f"{where}: expected a number, got {data!r}")
        return float(data)
    if tp is bool:
        if not isinstance(data, bool):
            raise ValueError(f"{where}: expected true or false, got {data!r}")
        return data
    if tp is str:
        if not isinstance(data, str):
            raise ValueError(f"{where}: expected a string, got {data!r}")
        return data
    raise TypeError(f"{where}: unsupported annotation {tp!r}")  # a schema bug, not a user error


def _build_tagged(options: list, data: Any, where: str) -> Any:
    by_kind = {typing.get_args(typing.get_type_hints(cls)["kind"])[0]: cls for cls in options}
    if not isinstance(data, Mapping) or "kind" not in data:
        raise ValueError(f"{where}: needs a 'kind' key, one of {sorted(by_kind)}")
    if not isinstance(data["kind"], str) or data["kind"] not in by_kind:
        raise ValueError(f"{where}.kind: unknown {data['kind']!r}; allowed: {sorted(by_kind)}")
    return _build_dataclass(by_kind[data["kind"]], data, where)


def _build_dataclass(cls: type, data: Any, where: str) -> Any:
    if not isinstance(data, Mapping):
        raise ValueError(f"{where}: expected a mapping with keys {[f.name for f in dataclasses.fields(cls)]}")
    hints = typing.get_type_hints(cls)
    fields = {f.name: f for f in dataclasses.fields(cls)}
    unknown = sorted(set(data) - set(fields), key=repr)
    if unknown:
        raise ValueError(f"{where}: unknown key {unknown[0]!r}; allowed: {sorted(fields)}")
    required = [
        name
        for name, f in fields.items()
        if f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING
    ]
    missing = [name for name in required if name not in data]
    if missing:
        raise ValueError(f"{where}: missing key {missing[0]!r}; required: {required}")
    kwargs = {name: _build(hints[name], value, f"{where}.{name}") for name, value in data.items()}
    try:
        return cls(**kwargs)
    except ValueError as error:
        raise ValueError(f"{where}: {error}") from None


def _build_goal(data: Any, where: str) -> Goal:
    if not isinstance(data, Mapping):
        raise ValueError(f"{where}: a goal is a mapping with keys {list(_GOAL_KEYS)}")
    unknown = sorted(set(data) - set(_GOAL_KEYS), key=repr)
    if unknown:
        raise ValueError(f"{where}: unknown key {unknown[0]!r}; allowed: {list(_GOAL_KEYS)}")
    try:
        return Goal(**data)
    except (TypeError, ValueError) as error:
        raise ValueError(f"{where}: {error}") from None


def scenario_from_dict(data: Mapping[str, Any]) -> Scenario:
    """Build and validate a ``Scenario`` from plain data (see the module docstring)."""
    return _build_dataclass(Scenario, data, "scenario")


def _plain(value: Any) -> Any:
    if isinstance(value, Goal):
        data = {"feature": value.feature.value, "relation": value.relation.value}
        if value.direction is not None:
            data["direction"] = value.direction.name.lower()
        else:
            data.update(lo=value.lo, hi=value.hi, tolerance=value.tolerance)
        return data
    if dataclasses.is_dataclass(value):
        return {f.name: _plain(getattr(value, f.name)) for f in dataclasses.fields(value)}
    if isinstance(value, tuple):
        return [_plain(v) for v in value]
    if isinstance(value, enum.Enum):
        return value.value
    return value


def scenario_to_dict(scenario: Scenario) -> dict[str, Any]:
    """Plain data that ``scenario_from_dict`` turns back into an equal ``Scenario``."""
    return _plain(scenario)


def _check_suffix(path: Path) -> str:
    suffix = path.suffix.lower()
    if suffix not in SCENARIO_SUFFIXES:
        raise ValueError(f"scenario file {path} must end in one of {SCENARIO_SUFFIXES}")
    return suffix


def load_scenario(path: str | os.PathLike) -> Scenario:
    """Read a scenario from a ``.yaml``/``.yml``/``.json`` file."""
    path = Path(path)
    suffix = _check_suffix(path)
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError as error:
        raise ValueError(f"scenario file {path} is not UTF-8 text: {error}") from None
    try:
        data = json.loads(text) if suffix == ".json" else yaml.safe_load(text)
    except (json.JSONDecodeError, yaml.YAMLError) as error:
        raise ValueError(f"scenario file {path} is not valid {suffix[1:].upper()}: {error}") from None
    try:
        return scenario_from_dict(data)
    except ValueError as error:
        raise ValueError(f"{path}: {error}") from None


def save_scenario(scenario: Scenario, path: str | os.PathLike) -> Path:
    """Write ``scenario`` to a YAML or JSON file atomically; returns the path."""
    path = Path(path)
    suffix = _check_suffix(path)
    data = scenario_to_dict(scenario)
    text = json.dumps(data, indent=2) if suffix == ".json" else yaml.safe_dump(data, sort_keys=False)
    with atomic_file(path) as handle:
        handle.write(text)
    return path
