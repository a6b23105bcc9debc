"""Helpers shared by several test folders (importable because ``tests/conftest.py`` puts
this folder on ``sys.path``; the tests run with ``--import-mode=importlib``)."""

import importlib.util
from pathlib import Path

import numpy as np

from attentive_gym._scripts import load_script

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


def load_benchmark(name: str):
    """The module of ``benchmarks/<name>.py`` (``load_script``)."""
    return load_script(BENCHMARKS, name)


def load_tool(name: str):
    """The module of ``tools/<name>.py`` (``load_script``)."""
    return load_script(TOOLS, name)


def load_test_module(path: str):
    """The test module at ``path`` under ``tests/`` (e.g. ``"attention/test_rosbag.py"``, whose
    ROS message and bag writers the bag tests share), loaded by file path: the suite's import
    mode keeps test modules from importing each other by name."""
    name = "tests_" + path.removesuffix(".py").replace("/", "_")
    spec = importlib.util.spec_from_file_location(name, Path(__file__).parent / path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
