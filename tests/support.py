"""Helpers shared by several test folders (importable because ``tests/conftest.py`` puts
this folder on ``sys.path``; the tests run with ``--import-mode=importlib``)."""

import importlib.util
import sys
from pathlib import Path

import numpy as np

#: The folders of the benchmark scripts and of the repository's tools.
BENCHMARKS = Path(__file__).resolve().parents[1] / "benchmarks"
TOOLS = Path(__file__).resolve().parents[1] / "tools"


def assert_same(a, b):
    """Assert two nested structures of dicts, tuples, lists and arrays are equal, bit for bit."""
    if isinstance(a, dict):
        assert a.keys() == b.keys()
        for key in a:
            assert_same(a[key], b[key])
    elif isinstance(a, (tuple, list)):
        assert len(a) == len(b)
        for x, y in zip(a, b):
            assert_same(x, y)
    else:
        np.testing.assert_array_equal(a, b)


def load_script(folder: Path, name: str):
    """The module of ``<folder>/<name>.py``, registered in ``sys.modules`` under ``name``
    (dataclasses resolve their module by name; a module already loaded from that file is
    returned as it is, so that a test patches the module its siblings imported). The folder
    is on ``sys.path`` while it loads, so that the script can import its siblings
    (``bench_env``, ``page_text``)."""
    path = folder / f"{name}.py"
    loaded = sys.modules.get(name)
    if loaded is not None and getattr(loaded, "__file__", None) == str(path):
        return loaded
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    sys.path.insert(0, str(folder))
    try:
        spec.loader.exec_module(module)
    finally:
        sys.path.remove(str(folder))
    return module


def load_benchmark(name: str):
    """The module of ``benchmarks/<name>.py`` (``load_script``)."""
    return load_script(BENCHMARKS, name)


def load_tool(name: str):
    """The module of ``tools/<name>.py`` (``load_script``)."""
    return load_script(TOOLS, name)
