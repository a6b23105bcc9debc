"""The old module paths of the attention library, kept importable with a ``DeprecationWarning``.

The library's modules were flat under ``attentive_gym.attention`` before they were grouped
into ``tracking``, ``compiled`` and ``io``. ``install`` puts a finder on ``sys.meta_path``
that answers an old path (``import attentive_gym.attention.tracker``, ``from
attentive_gym.attention import tracker``, unpickling an object saved under an old path)
with the module at its new path, the same module object, after warning that it moved.
The new paths never warn: the finder knows only the old ones.
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import sys
import warnings
from collections.abc import Mapping, Sequence
from types import MappingProxyType, ModuleType

__all__ = ["MOVED", "install"]

_PACKAGE = "attentive_gym.attention"
#: Old module path → the module's path now.
MOVED: Mapping[str, str] = MappingProxyType(
    {
        f"{_PACKAGE}.{old}": f"{_PACKAGE}.{new}"
        for old, new in (
            ("tracker", "tracking.tracker"),
            ("kalman", "tracking.kalman"),
            ("association", "tracking.association"),
            ("segmentation", "tracking.segmentation"),
            ("track_regions", "tracking.track_regions"),
            ("step_kernels", "compiled.step_kernels"),
            ("batch", "compiled.batch"),
            ("replay", "io.replay"),
            ("rosbag", "io.rosbag"),
            ("ros_readings", "io.ros_readings"),
            ("trace", "io.trace"),
        )
    }
)
#: Modules whose frames stand between an import statement and ``_import_moved``.
_PASSING = frozenset({_PACKAGE, __name__, importlib.__name__})


def _import_moved(old: str) -> ModuleType:
    """The module that ``old`` (a key of ``MOVED``) names now, after a ``DeprecationWarning``
    that points at the line that imported ``old``."""
    new = MOVED[old]
    warnings.warn(
        f"{old} moved to {new}; import it from there (the old path will be removed)",
        DeprecationWarning,
        stacklevel=_importer_level(),
    )
    return importlib.import_module(new)


def _importer_level() -> int:
    """``warnings.warn``'s stacklevel, in ``_import_moved``, of the first frame outside the
    import machinery: ``warnings`` skips the frames of ``importlib._bootstrap`` without
    counting them, and counts those of ``_PASSING`` (this module, the package's
    ``__getattr__``, ``importlib.import_module``)."""
    frame, level = sys._getframe(2), 2  # _import_moved's caller
    while frame is not None and frame.f_globals.get("__name__") in _PASSING:
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
        if fullname not in MOVED:
            return None
        return importlib.machinery.ModuleSpec(fullname, self._loader)


def install() -> None:
    """Put the finder first on ``sys.meta_path`` (once, however often it is called)."""
    if not any(isinstance(finder, _MovedFinder) for finder in sys.meta_path):
        sys.meta_path.insert(0, _MovedFinder())
