"""Optional dependencies, imported where they are used, with an error that names the extra to install.

- ``EXTRAS``: each optional top-level module → the distribution that provides it and the
  package extra that installs it.
- ``MissingExtraError``: the ``ImportError`` raised when such a module is not installed.
- ``require``: import an optional module, or raise ``MissingExtraError``.

The core (``pip install attentive_gym``) runs the environments and the attention library;
rendering needs the ``render`` extra (pygame), figures the ``plot`` extra (matplotlib), and
training or evaluating agents the ``agents`` extra (torch, stable-baselines3), and
recording videos the ``video`` extra (moviepy).
"""

from __future__ import annotations

import importlib
from types import ModuleType

__all__ = ["EXTRAS", "MissingExtraError", "require"]

#: Optional top-level module → (distribution on PyPI, extra of this package that installs it).
EXTRAS: dict[str, tuple[str, str]] = {
    "pygame": ("pygame", "render"),
    "matplotlib": ("matplotlib", "plot"),
    "torch": ("torch", "agents"),
    "stable_baselines3": ("stable-baselines3", "agents"),
    "moviepy": ("moviepy", "video"),
}


class MissingExtraError(ImportError):
    """An optional dependency is not installed; the message names the extra that installs it."""


def require(module: str, purpose: str) -> ModuleType:
    """Import ``module`` (a module of one of ``EXTRAS``' packages, e.g. ``"matplotlib.pyplot"``)
    and return it.

    Raises ``MissingExtraError`` when its package is not installed, with a message such as
    ``rendering needs pygame: pip install "attentive_gym[render]"`` (``purpose`` is the first
    words), and ``ValueError`` for a module outside ``EXTRAS``. An ``ImportError`` raised
    inside an installed package (a broken install) propagates unchanged.
    """
    top = module.partition(".")[0]
    if top not in EXTRAS:
        raise ValueError(f"{module!r} is not an optional dependency; allowed packages: {', '.join(EXTRAS)}")
    distribution, extra = EXTRAS[top]
    try:
        importlib.import_module(top)  # the package first: a cached submodule must not hide its absence
    except ModuleNotFoundError as error:
        if error.name != top:
            raise
        raise MissingExtraError(
            f'{purpose} needs {distribution}: pip install "attentive_gym[{extra}]"', name=top
        ) from error
    return importlib.import_module(module)
