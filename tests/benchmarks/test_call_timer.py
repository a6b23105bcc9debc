"""``benchmarks/call_timer.py``: calls made inside the block are timed and counted, the
function's results pass through, and the module gets its function back, also after an error."""

from __future__ import annotations

import types

import pytest

from support import load_benchmark

CallTimer = load_benchmark("call_timer").CallTimer


def _module():
    module = types.ModuleType("timed_module")
    module.double = lambda x: 2 * x
    module.twice = lambda x: module.double(x) + module.double(x)  # calls through the module attribute
    return module


def test_counts_and_times_the_calls_made_inside_the_block():
    module = _module()
    original = module.double
    with CallTimer(module, "double") as timer:
        assert module.twice(3) == 12
    assert timer.calls == 2 and timer.seconds > 0.0
    assert module.double is original
    module.twice(1)
    assert timer.calls == 2  # nothing counted after the block


def test_puts_the_function_back_after_an_error():
    module = _module()
    original = module.double
    with pytest.raises(ZeroDivisionError):
        with CallTimer(module, "double"):
            module.double(1) / 0
    assert module.double is original
