"""Keep numba's on-disk kernel cache in step with the package's source (internal).

numba's cache (``cache=True``, files ``*.nbi`` and ``*.nbc`` in each ``__pycache__``)
keys a compiled kernel on its own source file only. A kernel that calls a kernel of
another module keeps its cached copy, with the old callee compiled into it, after that
other module changes. An editable install that pulls new code would then run old and new
code mixed, silently.

``discard_stale_kernels`` guards against that: it fingerprints the contents of the modules
a kernel can depend on (``kernel_sources``: every module that defines a kernel, and every
package module those import, transitively, since numba freezes the globals a kernel reads)
and, when the fingerprint differs from the one stored beside the cache, deletes the
package's cached kernels, so numba compiles them afresh from the current source. Edits
elsewhere (the agents, the CLI) keep the cache. The package calls it once, at import,
before any kernel runs.

``announce_compilation`` says so, once, when a kernel is compiled rather than loaded from
the cache (a fresh install, a cleared cache, or sources changed since): the command line
calls it, since the first run then spends about a minute compiling before any output.

Only the caches inside the package are checked (numba writes there whenever the package
folder is writable, as in an editable install); a cache that numba had to put elsewhere
(``NUMBA_CACHE_DIR``, or a user-wide folder for a read-only install) is left alone.
"""

from __future__ import annotations

import hashlib
import re
import sys
from pathlib import Path

from attentive_gym._atomic import atomic_file

__all__ = ["kernel_sources", "source_fingerprint", "discard_stale_kernels", "announce_compilation", "FINGERPRINT_FILE"]

#: The file, in the package's top ``__pycache__``, that holds the fingerprint of the
#: source the cached kernels were compiled from.
FINGERPRINT_FILE = "kernels.fingerprint"
_KERNEL_SUFFIXES = (".nbi", ".nbc")


#: A line that decorates a function as a compiled kernel (or a numba extension).
_KERNEL_DECORATOR = re.compile(r"^\s*@(?:numba\.)?(?:njit|jit|intrinsic|overload|vectorize|guvectorize)\b", re.M)
#: A module's absolute imports from its own package (``from pkg.x import y``, ``import pkg.x``).
_IMPORT = re.compile(r"^[ \t]*(?:from[ \t]+([\w.]+)[ \t]+import[ \t]+(\([^)]*\)|[^\n]*)|import[ \t]+([\w.]+))", re.M)


def kernel_sources(package_dir: Path) -> list[Path]:
    """The ``*.py`` files under ``package_dir`` that a compiled kernel can depend on: those
    that define one, and the package modules they import, transitively (sorted)."""
    return sorted(_kernel_texts(package_dir))


def _kernel_texts(package_dir: Path) -> dict[Path, str]:
    """``kernel_sources``' files and their texts, each file read once."""
    package = package_dir.name
    texts = {path: path.read_text(encoding="utf-8") for path in package_dir.rglob("*.py")}
    modules = {}
    for path in texts:
        parts = path.relative_to(package_dir).with_suffix("").parts
        parts = parts[:-1] if parts[-1] == "__init__" else parts
        modules[".".join((package, *parts))] = path
    pending = [path for path, text in texts.items() if _KERNEL_DECORATOR.search(text)]
    closure: set[Path] = set()
    while pending:
        path = pending.pop()
        if path in closure:
            continue
        closure.add(path)
        for source, names, plain in _IMPORT.findall(texts[path]):
            if plain:
                pending.extend(modules[m] for m in _prefixes(plain) if m in modules)
                continue
            pending.extend(modules[m] for m in _prefixes(source) if m in modules)
            for name in re.findall(r"\w+", names):  # a name imported from a package may be a module
                if f"{source}.{name}" in modules:
                    pending.append(modules[f"{source}.{name}"])
    return {path: texts[path] for path in closure}


def _prefixes(dotted: str) -> list[str]:
    """``a.b.c`` → ``[a, a.b, a.b.c]``: importing a module runs its packages' ``__init__``."""
    parts = dotted.split(".")
    return [".".join(parts[: i + 1]) for i in range(len(parts))]


def source_fingerprint(package_dir: Path) -> str:
    """A hex digest of the paths and contents of ``kernel_sources(package_dir)``."""
    digest = hashlib.sha256()
    texts = _kernel_texts(package_dir)
    for path in sorted(texts):
        digest.update(path.relative_to(package_dir).as_posix().encode())
        digest.update(b"\0")
        digest.update(texts[path].encode("utf-8"))
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
    """Write ``text`` to ``path`` atomically (``attentive_gym._atomic``); give up quietly
    where the folder cannot be written."""
    try:
        with atomic_file(path) as file:
            file.write(text)
    except OSError:
        pass


#: The notice ``announce_compilation`` prints.
COMPILE_NOTICE = (
    "attentive-gym: compiling the numba kernels (none cached for this version yet): about a minute, "
    "once; later runs load them from the cache"
)
#: Whether this process has the compile notice's listener installed, and has printed it.
_announcing = False
_announced = False


def announce_compilation() -> None:
    """Print ``COMPILE_NOTICE`` on ``sys.stderr``, once per process, when numba first
    compiles a kernel instead of loading it from its cache (numba's ``numba:compile`` event
    fires on a cache miss only). Calling it again does nothing."""
    global _announcing
    if _announcing:
        return
    from numba.core import event

    class CompileNotice(event.Listener):
        def on_start(self, _event) -> None:
            global _announced
            if not _announced:
                _announced = True
                print(COMPILE_NOTICE, file=sys.stderr, flush=True)

        def on_end(self, _event) -> None:
            pass

    event.register("numba:compile", CompileNotice())
    _announcing = True
