"""The package discards numba's cached kernels when its source changes (``_kernel_cache``)."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import attentive_gym
from attentive_gym._kernel_cache import FINGERPRINT_FILE, discard_stale_kernels, kernel_sources, source_fingerprint

_KERNEL = "from numba import njit\nfrom pkg.constants import X\n\n@njit(cache=True)\ndef f():\n    return X\n"


def _package(root: Path) -> Path:
    package = root / "pkg"
    (package / "sub" / "__pycache__").mkdir(parents=True)
    (package / "__pycache__").mkdir()
    (package / "__init__.py").write_text("")
    (package / "sub" / "__init__.py").write_text("")
    (package / "sub" / "kernels.py").write_text(_KERNEL)
    (package / "constants.py").write_text("X = 1\n")
    (package / "cli.py").write_text("from pkg.sub import kernels\n")
    return package


def _kernel_files(package: Path) -> list[Path]:
    return sorted(p for p in package.rglob("*") if p.suffix in (".nbi", ".nbc"))


def _add_kernel_files(package: Path) -> None:
    (package / "__pycache__" / "mod.f-10.py311.nbi").write_bytes(b"index")
    (package / "sub" / "__pycache__" / "kernels.g-3.py311.1.nbc").write_bytes(b"data")


def test_kernels_are_kept_while_the_source_is_unchanged_and_discarded_when_it_changes(tmp_path):
    package = _package(tmp_path)
    _add_kernel_files(package)
    assert discard_stale_kernels(package) == 2  # no fingerprint yet: nothing vouches for them
    assert _kernel_files(package) == []
    assert (package / "__pycache__" / FINGERPRINT_FILE).read_text() == source_fingerprint(package)

    _add_kernel_files(package)  # compiled from the current source
    assert discard_stale_kernels(package) == 0
    assert len(_kernel_files(package)) == 2

    (package / "cli.py").write_text("from pkg.sub import kernels  # no kernel depends on this module\n")
    assert discard_stale_kernels(package) == 0
    assert len(_kernel_files(package)) == 2

    (package / "constants.py").write_text("X = 2\n")  # a global a kernel reads changes
    assert discard_stale_kernels(package) == 2
    assert _kernel_files(package) == []


def test_kernel_sources_are_the_kernel_modules_and_what_they_import(tmp_path):
    package = _package(tmp_path)
    names = [p.relative_to(package).as_posix() for p in kernel_sources(package)]
    assert names == ["__init__.py", "constants.py", "sub/kernels.py"]  # not cli.py: no kernel imports it


def test_the_fingerprint_follows_contents_and_paths_only(tmp_path):
    package = _package(tmp_path)
    before = source_fingerprint(package)
    (package / "sub" / "kernels.py").write_text(_KERNEL)  # rewritten, same content: a new mtime
    assert source_fingerprint(package) == before
    (package / "sub" / "kernels.py").rename(package / "sub" / "other.py")
    assert source_fingerprint(package) != before


def test_importing_the_package_stamps_its_cache_with_the_current_source():
    package = Path(attentive_gym.__file__).parent
    stamp = package / "__pycache__" / FINGERPRINT_FILE
    assert stamp.read_text() == source_fingerprint(package)


_OUTER = """
from numba import njit
from pkg.inner import inner

@njit(cache=True)
def outer():
    return inner() + 0
"""
_INNER = """
from numba import njit

@njit(cache=True)
def inner():
    return {value}
"""
_RUN = """
import sys
from pathlib import Path
sys.path.insert(0, {root!r})
if {guard}:
    from attentive_gym._kernel_cache import discard_stale_kernels
    discard_stale_kernels(Path({root!r}) / "pkg")
from pkg.outer import outer
print(outer())
"""


def _outer_result(root: Path, guard: bool) -> int:
    script = _RUN.format(root=str(root), guard=guard)
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=300, check=True)
    return int(done.stdout.split()[-1])


def test_a_changed_callee_in_another_module_reaches_the_cached_caller(tmp_path):
    """numba alone keeps the caller's cached copy of the old callee; the guard does not."""
    package = tmp_path / "pkg"
    package.mkdir()
    (package / "__init__.py").write_text("")
    (package / "outer.py").write_text(textwrap.dedent(_OUTER))
    (package / "inner.py").write_text(textwrap.dedent(_INNER.format(value=1)))
    assert _outer_result(tmp_path, guard=True) == 1  # compiles and caches both kernels

    (package / "inner.py").write_text(textwrap.dedent(_INNER.format(value=2)))
    assert _outer_result(tmp_path, guard=False) == 1  # numba's own check: the stale caller
    assert _outer_result(tmp_path, guard=True) == 2
