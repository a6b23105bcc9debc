"""Old module paths kept importable with a ``DeprecationWarning``, for modules that moved (private).

A package whose modules moved calls ``install(moved)`` with a map of old dotted path → the
module's path now. One finder on ``sys.meta_path`` answers every registered old path (``import
pkg.old``, ``from pkg import old``, unpickling an object saved under an old path) with the module
at its new path, the same module object, after warning that it moved; the warning points at the
line that imported the old path. The new paths never warn: the finder knows only the old ones.
``attribute(package, name)`` serves a package's ``__getattr__`` for an old path read as an
attribute (``pkg.old`` after ``import pkg``).

The attention library (``attentive_gym.attention._moved``), the environments and the agents
register their moved modules here.
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import sys
import warnings
from collections.abc import Mapping, Sequence
from types import MappingProxyType, ModuleType

__all__ = ["MOVED", "attribute", "install"]

_moved: dict[str, str] = {}
#: Every registered old module path → the module's path now (read-only view).
MOVED: Mapping[str, str] = MappingProxyType(_moved)
#: Modules whose frames stand between an import statement and ``_import_moved``: this one,
#: importlib, and the packages of the old paths (their ``__getattr__``); grows with ``install``.
_passing: set[str] = {__name__, importlib.__name__}


def _import_moved(old: str) -> ModuleType:
    """The module that ``old`` (a key of ``MOVED``) names now, after a ``DeprecationWarning``
    that points at the line that imported ``old``."""
    new = _moved[old]
    warnings.warn(
        f"{old} moved to {new}; import it from there (the old path will be removed)",
        DeprecationWarning,
        stacklevel=_importer_level(),
    )
    return importlib.import_module(new)


def _importer_level() -> int:
    """``warnings.warn``'s stacklevel, in ``_import_moved``, of the first frame outside the
    import machinery: ``warnings`` skips the frames of ``importlib._bootstrap`` without
    counting them, and counts those of ``_passing`` (this module, a package's ``__getattr__``,
    ``importlib.import_module``)."""
    frame, level = sys._getframe(2), 2  # _import_moved's caller
    while frame is not None and frame.f_globals.get("__name__") in _passing:
        frame = frame.f_back
        while frame is not None and _is_bootstrap(frame):
            frame = frame.f_back
        level += 1
    return level


def _is_bootstrap(frame) -> bool:
    """Whether ``frame`` runs in ``importlib._bootstrap`` (the frames ``warnings`` skips)."""
    filename = frame.f_code.co_filename
    return "importlib" in filename and "_bootstrap" in filename


class _MovedLoader(importlib.abc.Loader):
    """Puts the module at its new path in ``sys.modules`` in place of the one being loaded,
    so that the import statement binds the moved module itself."""

    def create_module(self, spec: importlib.machinery.ModuleSpec) -> None:
        return None  # a placeholder module, replaced by exec_module

    def exec_module(self, module: ModuleType) -> None:
        sys.modules[module.__name__] = _import_moved(module.__name__)


class _MovedFinder(importlib.abc.MetaPathFinder):
    """Finds the old paths of ``MOVED`` only; every other name goes to the next finder."""

    _loader = _MovedLoader()

    def find_spec(self, fullname: str, path: Sequence[str] | None, target: ModuleType | None = None):
        if fullname not in _moved:
            return None
        return importlib.machinery.ModuleSpec(fullname, self._loader)


def install(moved: Mapping[str, str]) -> None:
    """Answer the old paths of ``moved`` (old dotted path → new) from now on; the finder goes
    first on ``sys.meta_path`` once, however often this is called.

    Raises:
        ValueError: an old path that is already registered for another new path.
    """
    for old, new in moved.items():
        if _moved.get(old, new) != new:
            raise ValueError(f"{old} is already registered as moved to {_moved[old]}, not {new}")
    _moved.update(moved)
    _passing.update(old.rpartition(".")[0] for old in moved)
    if not any(isinstance(finder, _MovedFinder) for finder in sys.meta_path):
        sys.meta_path.insert(0, _MovedFinder())


def attribute(package: str, name: str) -> ModuleType:
    """The moved module ``package.name`` read as an attribute of ``package`` (for the package's
    ``__getattr__``): imported through the finder, which warns once and binds it there.

    Raises:
        AttributeError: ``package.name`` is no registered old path.
    """
    if f"{package}.{name}" in _moved:
        return importlib.import_module(f"{package}.{name}")
    raise AttributeError(f"module {package!r} has no attribute {name!r}")
