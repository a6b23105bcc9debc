"""How many numba threads a fleet's compiled kernels run on: a rule measured on 2 cores.

- ``default_threads(num_envs)``: 1 below ``THREADED_FROM_ENVS`` members, else as many as
  there are idle cores, at most numba's current count (``NUMBA_NUM_THREADS``, or what
  ``numba.set_num_threads`` chose).
- ``idle_cores()``: the cores this process may run on, less the others' load.
- ``numba_threads(count)``: run a block with numba's thread count set to ``count``, then
  put the previous count back.

Why (``docs/vector.md``, native ``focus`` env, µs per env-step, OpenMP threading layer):
on 2 idle cores a second thread saves little at N = 16 (1.04-1.10× faster) and at most 1.2× from
N = 32 on; with one core busy in another process, 2 threads are 1.4-45× slower than one at every
N (the threads wait for each other on the shared core). So: serial for small fleets, and never
more threads than idle cores when the fleet is built.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterator

import numba

__all__ = ["THREADED_FROM_ENVS", "default_threads", "idle_cores", "numba_threads"]

#: The fewest members whose compiled stages run on more than one thread.
THREADED_FROM_ENVS = 32


def idle_cores() -> int:
    """The cores this process may run on, less the other processes' load (the 1-minute load
    average, rounded), at least 1."""
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        cores = os.cpu_count() or 1
    try:
        load = round(os.getloadavg()[0])
    except (AttributeError, OSError):  # no load average on this system
        load = 0
    return max(1, cores - load)


def default_threads(num_envs: int) -> int:
    """numba threads for a fleet of ``num_envs`` members: 1 below ``THREADED_FROM_ENVS``,
    else ``min(numba.get_num_threads(), idle_cores())``."""
    if num_envs < THREADED_FROM_ENVS:
        return 1
    return max(1, min(numba.get_num_threads(), idle_cores()))


@contextlib.contextmanager
def numba_threads(count: int) -> Iterator[None]:
    """Run the block with ``numba.set_num_threads(count)``, then put the previous count back
    (``count`` between 1 and ``numba.config.NUMBA_NUM_THREADS``)."""
    previous = numba.get_num_threads()
    if previous == count:
        yield
        return
    numba.set_num_threads(count)
    try:
        yield
    finally:
        numba.set_num_threads(previous)
