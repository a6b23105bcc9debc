"""The versions of the rescue task: what an episode rewards and ends on, and what an agent senses nearby.

The robot, its sensors and the arena are the same in every version; a task version sets the
defaults of ``RewardConfig`` and whether the variants with the focus layout (``"focus"``,
``"goal-action"``, ``"random-focus"``, ``"oracle"``) carry the ``"proximity"`` entry:

| version | reward over ``RewardConfig()`` | ``proximity`` | registered ids |
|---|---|---|---|
| 0 | none (contact costs 2/s, never ends an episode) | no | ``AttentiveRescue-v0``; attended ``-v0``, ``-v1`` |
| 1 | ``contact_limit_s=1.0``, ``near_per_s=4.0``: safe rescue | yes | ``AttentiveRescue-v1``; ``-v2`` to ``-v4`` |

Version 1 is the default since the agents of version 0 won by ramming: in contact for a third
to a half of their steps (docs/results/safe_rescue.md). An episode of version 1 ends, without
success, once the robot has touched something for more than 1 s in all, so every success is
a safe one; a clearance below 0.3 m costs up to 4 per second, a warning before contact; and
the focus layout senses each region's nearest reading, since what it does not attend it
cannot otherwise avoid. Raw and its stacked readings carry no ``proximity`` entry in any
version: their laser and sonars hold it.

- ``TASK_VERSIONS`` / ``check_task_version``: the versions, and the check of one.
- ``task_reward(version, reward)``: the ``RewardConfig`` of a version, with the fields of a
  mapping (``{"collision_per_s": 10}``) set over its defaults.
- ``task_proximity(version)``: whether the focus layout carries ``"proximity"`` by default.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

from attentive_gym.envs.config_mappings import config_from
from attentive_gym.envs.reward import RewardConfig

__all__ = ["TASK_VERSIONS", "check_task_version", "task_reward", "task_proximity"]

#: The task's versions, oldest first; the last is the default.
TASK_VERSIONS = (0, 1)
#: Each version's fields over ``RewardConfig()``, and its focus layout's ``proximity``.
_REWARD_FIELDS: dict[int, dict[str, Any]] = {0: {}, 1: {"contact_limit_s": 1.0, "near_per_s": 4.0}}
_PROXIMITY = {0: False, 1: True}


def check_task_version(version: Any, name: str = "task") -> int:
    """``version`` if it is one of ``TASK_VERSIONS`` (an int, not a bool or a float).

    Raises:
        ValueError: any other value (the message names ``name`` and lists the versions).
    """
    if type(version) is not int or version not in TASK_VERSIONS:
        raise ValueError(f"{name} must be one of the task versions {list(TASK_VERSIONS)}, got {version!r}")
    return version


def task_reward(version: int, reward: RewardConfig | Mapping[str, Any] | None = None) -> RewardConfig:
    """The reward of task ``version``: ``reward`` itself when it is a ``RewardConfig``; else the
    version's defaults with the fields of the mapping ``reward`` (None: none) set over them.

    Raises:
        ValueError: an unknown version, or a field ``RewardConfig`` has not or refuses.
        TypeError: ``reward`` is neither a ``RewardConfig`` nor a mapping.
    """
    check_task_version(version)
    if isinstance(reward, RewardConfig):
        return reward
    fields = {} if reward is None else config_from("reward", reward)  # checked against RewardConfig's fields
    given = {} if reward is None else {key: getattr(fields, key) for key in reward}
    return dataclasses.replace(RewardConfig(), **{**_REWARD_FIELDS[version], **given})


def task_proximity(version: int) -> bool:
    """Whether, in task ``version``, the variants with the focus layout carry the
    ``"proximity"`` entry unless told otherwise."""
    return _PROXIMITY[check_task_version(version)]
