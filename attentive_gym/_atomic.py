"""Atomic file writes: a temporary file in the target's folder, then ``os.replace``.

- ``atomic_file``: a context manager that yields the temporary file's handle and puts the
  file in place when the block ends without an exception.
- ``save_figure``: a matplotlib figure saved through ``atomic_file``.
- ``refuse_existing``: a clear error, before anything is written, when a command would
  replace files that are already there.

A write that fails or is interrupted (an exception, Ctrl-C) leaves the previous file whole
and no temporary file behind. The new file keeps the permissions of the file it replaces,
or gets those of any newly created file (0o666 less the umask), not ``mkstemp``'s 0o600.
"""

from __future__ import annotations

import contextlib
import os
import stat
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import IO, Any

__all__ = ["atomic_file", "save_figure", "refuse_existing"]

#: Permissions of a newly created file before the umask.
_NEW_FILE_MODE = 0o666


@contextlib.contextmanager
def atomic_file(path: str | os.PathLike, binary: bool = False) -> Iterator[IO[Any]]:
    """Yield a handle whose contents replace ``path`` (folders created) when the block
    ends: text (UTF-8, newlines as written) or, with ``binary``, bytes."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    handle, temporary = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(handle, "wb") if binary else os.fdopen(handle, "w", encoding="utf-8", newline="") as file:
            yield file
            file.flush()
            os.fsync(file.fileno())
        os.chmod(temporary, _mode_for(path))
        os.replace(temporary, path)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise


def save_figure(fig, path: str | os.PathLike, **savefig_kwargs: Any) -> Path:
    """Save the matplotlib figure ``fig`` to ``path`` atomically, in the format its suffix
    names (``.png`` when it has none); ``savefig_kwargs`` go to ``Figure.savefig``."""
    path = Path(path)
    with atomic_file(path, binary=True) as file:
        fig.savefig(file, format=path.suffix[1:] or "png", **savefig_kwargs)
    return path


def refuse_existing(paths, flag: str = "--overwrite") -> None:
    """``ValueError`` naming those of ``paths`` that exist, and ``flag``, which replaces them."""
    existing = [str(path) for path in paths if Path(path).exists()]
    if existing:
        raise ValueError(f"{', '.join(existing)} already exist(s); pass {flag} to replace them, or write elsewhere")


def _mode_for(path: Path) -> int:
    """The permissions ``path``'s new contents get: those of the file there, else a new file's."""
    try:
        return stat.S_IMODE(os.stat(path).st_mode)
    except FileNotFoundError:
        mask = os.umask(0)
        os.umask(mask)
        return _NEW_FILE_MODE & ~mask
