"""Helpers shared by several test folders (importable because ``tests/conftest.py`` puts
this folder on ``sys.path``; the tests run with ``--import-mode=importlib``)."""

import numpy as np


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
