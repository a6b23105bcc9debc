"""Hyperparameters for the RL Baselines3 Zoo (``rl-zoo3``), one entry per registered id.

- ``ppo.yml``: PPO with ``MultiInputPolicy`` and the project's own settings
  (``attentive_gym.agents.config.RunSpec.default_algo_kwargs``, 32 environments).
- ``ppo_lstm.yml``: RecurrentPPO (``--algo ppo_lstm``) with ``MultiInputLstmPolicy`` and the
  project's RecurrentPPO settings (4 environments).
- ``conf_file(algo)``: the path of an algorithm's file, for ``--conf-file``.

``--conf-file`` takes either the file (``attentive_gym/agents/rl_zoo/ppo.yml`` in a source
checkout) or the modules ``attentive_gym.agents.rl_zoo.ppo`` and
``attentive_gym.agents.rl_zoo.ppo_lstm``, whose ``hyperparams`` are the files' contents::

    python -m rl_zoo3.train --algo ppo --env AttentiveRescueFocus-v4 \\
        --gym-packages attentive_gym --conf-file attentive_gym.agents.rl_zoo.ppo --device cpu
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import yaml

__all__ = ["ZOO_ALGOS", "conf_file", "load_hyperparams"]

#: The rl-zoo3 algorithms with a file here.
ZOO_ALGOS = ("ppo", "ppo_lstm")
#: Top-level keys of the files that are not environment ids (shared settings).
_SHARED_KEYS = ("_project_defaults",)


def conf_file(algo: str) -> Path:
    """The hyperparameter file of ``algo`` (one of ``ZOO_ALGOS``)."""
    if algo not in ZOO_ALGOS:
        raise ValueError(f"no rl-zoo3 hyperparameters for {algo!r}; available: {list(ZOO_ALGOS)}")
    return Path(__file__).with_name(f"{algo}.yml")


def load_hyperparams(algo: str) -> dict[str, Any]:
    """Environment id → rl-zoo3 hyperparameters of ``algo``, as rl-zoo3 reads them."""
    data = yaml.safe_load(conf_file(algo).read_text(encoding="utf-8"))
    return {key: value for key, value in data.items() if key not in _SHARED_KEYS}
