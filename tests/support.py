"""Helpers shared by several test folders (importable because ``tests/conftest.py`` puts
this folder on ``sys.path``; the tests run with ``--import-mode=importlib``)."""

import importlib.util
import sys
from pathlib import Path

import numpy as np

#: The folder of the benchmark scripts.
BENCHMARKS = Path(__file__).resolve().parents[1] / "benchmarks"


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


def load_benchmark(name: str):
    """The module of ``benchmarks/<name>.py``, registered in ``sys.modules`` under ``name``
    (dataclasses resolve their module by name). The folder is on ``sys.path`` while it
    loads, so that the script can import its siblings (``bench_env``, ``call_timer``)."""
    spec = importlib.util.spec_from_file_location(name, BENCHMARKS / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    sys.path.insert(0, str(BENCHMARKS))
    try:
        spec.loader.exec_module(module)
    finally:
        sys.path.remove(str(BENCHMARKS))
    return module
