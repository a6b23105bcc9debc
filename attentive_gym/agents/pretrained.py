"""Small trained policies shipped with the package, to try at once:
``attentive-gym evaluate --pretrained focus [--video DIR]``.

Each lives in ``attentive_gym/agents/pretrained/<variant>/`` as a run folder of ``train``
(``final_model.zip``, ``obs_normalization.npz``, ``spec.json``; under 1 MB together) with
``record.json``: how it was trained and the success it reached when it was shipped, on fixed
episodes, with a bootstrap interval over them. ``tools/ship_pretrained.py`` writes a folder
from a finished run; a test evaluates every shipped policy on its recorded episodes, so that a
change of the environment's defaults cannot silently break it.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

__all__ = ["PRETRAINED", "RECORD_FILE", "pretrained_record", "pretrained_run"]

#: The variants with a shipped policy.
PRETRAINED = ("raw", "focus")
#: The file of a shipped policy's record.
RECORD_FILE = "record.json"
_ROOT = Path(__file__).resolve().parent / "pretrained"


def pretrained_run(variant: str) -> Path:
    """The run folder of the policy shipped for ``variant`` (one of ``PRETRAINED``).

    Raises:
        ValueError: for a variant without a shipped policy (the message lists those with one).
    """
    if variant not in PRETRAINED:
        raise ValueError(f"no pretrained policy for {variant!r}; shipped: {', '.join(PRETRAINED)}")
    return _ROOT / variant


def pretrained_record(variant: str) -> dict[str, Any]:
    """The record of the policy shipped for ``variant``: ``env_id``, ``trained`` (seed, the
    run's ``total_steps``, env keywords), ``episodes`` and ``first_seed`` (the evaluation's episodes, seeds
    ``first_seed + i``), ``success_rate`` and ``success_ci`` ([low, high], 95 % bootstrap over
    the episodes)."""
    return json.loads((pretrained_run(variant) / RECORD_FILE).read_text(encoding="utf-8"))
