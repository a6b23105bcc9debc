"""``CallTimer``: the wall time spent inside one module-level function while code runs.

The benchmarks use it to time a compiled kernel inside the step that calls it (the sensor
sweep, the attentional models): the function is swapped for a timing wrapper on entry and
put back on exit, even when the code inside raises.
"""

from __future__ import annotations

import time
from types import ModuleType
from typing import Any

__all__ = ["CallTimer"]


class CallTimer:
    """Add up the wall time (s) of the calls to ``module.name`` made inside a ``with`` block.

    The module attribute is looked up at call time by its callers, so callers that import
    the module (``module.name(...)``, or a global of that module) are timed; a caller that
    bound the function to a name of its own beforehand is not.
    """

    def __init__(self, module: ModuleType, name: str) -> None:
        self.module, self.name, self.inner = module, name, getattr(module, name)
        self.seconds = 0.0
        self.calls = 0

    def __call__(self, *args: Any) -> Any:
        start = time.perf_counter()
        result = self.inner(*args)
        self.seconds += time.perf_counter() - start
        self.calls += 1
        return result

    def __enter__(self) -> CallTimer:
        setattr(self.module, self.name, self)
        return self

    def __exit__(self, *exc: object) -> None:
        setattr(self.module, self.name, self.inner)
