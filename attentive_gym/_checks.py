"""Argument checks shared across the package's layers.

- ``check_int``: a Python ``int`` (not a bool) of at least some bound, or a ``ValueError``
  that names the argument and what is allowed.
"""

from __future__ import annotations

from typing import Any

__all__ = ["check_int"]


def check_int(name: str, value: Any, low: int) -> int:
    """``value`` itself, or ``ValueError`` unless it is an ``int`` (not a bool) ``>= low``."""
    if isinstance(value, bool) or not isinstance(value, int) or value < low:
        raise ValueError(f"{name} must be an integer >= {low}, got {value!r}")
    return value
