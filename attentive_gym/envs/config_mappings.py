"""The environment's settings objects from plain mappings, and back.

``AttentiveRescueEnv`` takes ``reward``, ``robot``, ``sonar`` and ``laser`` as their
dataclasses (``RewardConfig``, ``RobotConfig``, ``SonarConfig``, ``LaserConfig``) or as
mappings of their fields, so that JSON (``--env-kwargs '{"reward": {"collision_per_s": 10}}'``,
``spec.json``) can set them: fields left out keep the dataclass's defaults.

- ``config_from``: a keyword's value as its dataclass, every key checked first.
- ``config_as_mapping``: a dataclass as plain JSON values (every field; tuples as lists).
- ``env_kwargs_as_mappings``: keyword arguments with each of these settings resolved to
  ``config_as_mapping``'s form (what ``spec.json`` records).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

from attentive_gym.envs.reward import RewardConfig
from attentive_gym.sensors.laser import LaserConfig
from attentive_gym.sensors.sonar import SonarConfig
from attentive_gym.world.robot import RobotConfig

__all__ = ["CONFIG_KEYWORDS", "config_as_mapping", "config_from", "env_kwargs_as_mappings"]

#: The keyword arguments of ``AttentiveRescueEnv`` that take a settings dataclass.
CONFIG_KEYWORDS: Mapping[str, type] = {
    "reward": RewardConfig,
    "robot": RobotConfig,
    "sonar": SonarConfig,
    "laser": LaserConfig,
}


def config_from(keyword: str, value: Any) -> Any:
    """The settings dataclass of ``keyword`` (one of ``CONFIG_KEYWORDS``) that ``value`` gives.

    ``value`` is the dataclass itself (returned as is) or a mapping of some of its fields
    (the others keep their defaults).

    Raises:
        TypeError: ``value`` is neither the dataclass nor a mapping.
        ValueError: a key is no field of the dataclass (the message names it and lists the
            fields), or the dataclass refuses a value (its own message).
    """
    cls = CONFIG_KEYWORDS[keyword]
    if isinstance(value, cls):
        return value
    if not isinstance(value, Mapping):
        raise TypeError(f"{keyword} must be a {cls.__name__} or a mapping of its fields, got {type(value).__name__}")
    allowed = [field.name for field in dataclasses.fields(cls)]
    unknown = [key for key in value if key not in allowed]
    if unknown:
        raise ValueError(f"{keyword}: {cls.__name__} has no field(s) {unknown}; allowed: {allowed}")
    return cls(**value)


def config_as_mapping(config: Any) -> dict[str, Any]:
    """Every field of the settings dataclass ``config`` as plain JSON values (tuples as lists),
    so that it equals what ``json.loads`` reads back; ``config_from`` inverts it."""
    return {field.name: _as_json_value(getattr(config, field.name)) for field in dataclasses.fields(config)}


def env_kwargs_as_mappings(env_kwargs: Mapping[str, Any]) -> dict[str, Any]:
    """``env_kwargs`` with each of ``CONFIG_KEYWORDS`` it holds (a dataclass or a mapping)
    checked and replaced by ``config_as_mapping`` of its dataclass; other keys as given.

    Raises:
        TypeError, ValueError: as ``config_from``.
    """
    return {
        key: config_as_mapping(config_from(key, value)) if key in CONFIG_KEYWORDS else value
        for key, value in env_kwargs.items()
    }


def _as_json_value(value: Any) -> Any:
    """``value`` with its tuples, nested ones included, turned into lists."""
    if isinstance(value, (tuple, list)):
        return [_as_json_value(item) for item in value]
    return value
