"""The attended environments the perception benchmark measures, and its arenas.

- ``VARIANT``: the attended variant measured.
- ``PERCEPTION_ARENA``, ``CONTROL_ARENA``: the arenas of the perception sections and of the
  control section, as ``make_env`` keywords.
- ``make_attentive_env``: an attended environment with the model in a kinematics mode and
  told the sensors' noise.
"""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType
from typing import Any

from attentive_gym.wrappers import make_env

__all__ = ["PERCEPTION_TASK", "VARIANT", "PERCEPTION_ARENA", "CONTROL_ARENA", "make_attentive_env"]

#: The task version of every perception measurement (``envs.tasks``): the first one, whose
#: episodes end only at the target or the time limit, so that a contact never cuts a measured
#: course short. The readings, and with them the model's output, are the same in every task.
PERCEPTION_TASK = 0

#: The attended variant measured. The model and ``info["attention"]`` are the same in every
#: attended variant; "saliency" also passes the raw laser on, which ``Wander`` needs.
VARIANT = "saliency"
#: The arena of the speed and focus measurements: 10 m square, 3 distractors besides the target.
PERCEPTION_ARENA: Mapping[str, Any] = MappingProxyType({"arena_size_m": 10.0, "num_distractors": 3})
#: The arena of the controllers' success rates: 8 m square, 2 distractors besides the target.
CONTROL_ARENA: Mapping[str, Any] = MappingProxyType({"arena_size_m": 8.0, "num_distractors": 2})


def make_attentive_env(
    mode: str,
    range_noise_rel: float = 0.0,
    variant: str = VARIANT,
    attention_fields: Mapping[str, Any] = MappingProxyType({}),
    **env_kwargs: Any,
):
    """The attended environment ``variant`` (default ``VARIANT``; ``"focus"`` for an
    observation with the working memory) with the model in kinematics ``mode``, told that
    one reading's noise has relative σ ``range_noise_rel`` (dimensionless;
    ``AttentionConfig.range_noise_rel``), and with ``attention_fields``, more
    ``AttentionConfig`` fields (a candidate setting), over the current model's defaults for the
    environment's robot (``wrappers.attention.default_config``). ``env_kwargs`` go to ``make_env``: the
    sensors' noise itself (``sensor_noise``, ``sensor_profile``), the arena, the time limit.

    Raises:
        TypeError: when the installed environment does not accept a keyword of ``env_kwargs``.
        ValueError: for a field of ``attention_fields`` that ``AttentionConfig`` refuses.
    """
    fields = {"kinematics": mode, "range_noise_rel": range_noise_rel, **attention_fields}
    return make_env(variant, attention=fields, task=PERCEPTION_TASK, **env_kwargs)
