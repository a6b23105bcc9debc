"""Keep numba's on-disk kernel cache in step with the package's source (internal).

numba's cache (``cache=True``, files ``*.nbi`` and ``*.nbc`` in each ``__pycache__``)
keys a compiled kernel on its own source file only. A kernel that calls a kernel of
another module keeps its cached copy, with the old callee compiled into it, after that
other module changes. An editable install that pulls new code would then run old and new
code mixed, silently.

``discard_stale_kernels`` guards against that: it fingerprints every Python source of the
package (their contents) and, when the fingerprint differs from the one stored beside the
cache, deletes the package's cached kernels, so numba compiles them afresh from the
current source. The package calls it once, at import, before any kernel runs.

Only the caches inside the package are checked (numba writes there whenever the package
folder is writable, as in an editable install); a cache that numba had to put elsewhere
(``NUMBA_CACHE_DIR``, or a user-wide folder for a read-only install) is left alone.
"""

from __future__ import annotations

import hashlib
import os
import tempfile
from pathlib import Path

__all__ = ["source_fingerprint", "discard_stale_kernels", "FINGERPRINT_FILE"]

#: The file, in the package's top ``__pycache__``, that holds the fingerprint of the
#: source the cached kernels were compiled from.
FINGERPRINT_FILE = "kernels.fingerprint"
_KERNEL_SUFFIXES = (".nbi", ".nbc")


def source_fingerprint(package_dir: Path) -> str:
    """A hex digest of the paths and contents of every ``*.py`` file under ``package_dir``."""
    digest = hashlib.sha256()
    for path in sorted(package_dir.rglob("*.py")):
        digest.update(path.relative_to(package_dir).as_posix().encode())
        digest.update(b"\0")
        digest.update(path.read_bytes())
        digest.update(b"\0")
    return digest.hexdigest()


def discard_stale_kernels(package_dir: Path) -> int:
    """Delete the cached kernels under ``package_dir`` if its source changed since they were
    stored; return how many files were deleted.

    Does nothing (and returns 0) when the stored fingerprint matches, or when the package
    folder cannot be written (then numba cannot cache there either). Safe when several
    processes import the package at once: a file another process deleted first is skipped,
    and numba recompiles a kernel whose cache file vanished.
    """
    cache_dir = package_dir / "__pycache__"
    stamp = cache_dir / FINGERPRINT_FILE
    current = source_fingerprint(package_dir)
    try:
        if stamp.read_text() == current:
            return 0
    except OSError:  # no stamp yet (a fresh install) or unreadable: treat as stale
        pass
    deleted = 0
    for folder in package_dir.rglob("__pycache__"):
        for path in folder.iterdir():
            if path.suffix in _KERNEL_SUFFIXES:
                try:
                    path.unlink()
                    deleted += 1
                except FileNotFoundError:
                    pass
                except OSError:
                    return deleted
    _write_atomically(stamp, current)
    return deleted


def _write_atomically(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` through a temporary file and ``os.replace``; give up quietly
    where the folder cannot be written."""
    try:
        path.parent.mkdir(exist_ok=True)
        handle, temporary = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.")
    except OSError:
        return
    try:
        with os.fdopen(handle, "w") as file:
            file.write(text)
        os.replace(temporary, path)
    except OSError:
        Path(temporary).unlink(missing_ok=True)
