"""The numba thread count of a fleet's compiled stages: the measured default rule, an explicit
count, and the caller's count put back after each step."""

from __future__ import annotations

import numba
import numpy as np
import pytest

from attentive_gym.vector import Fleet, make_vector_env, threads
from attentive_gym.wrappers import make_env

SHORT = {"time_limit_s": 1.0, "arena_size_m": 8.0, "num_distractors": 2}


def test_small_fleets_run_serial_and_large_ones_on_the_idle_cores(monkeypatch):
    monkeypatch.setattr(threads, "idle_cores", lambda: 2)
    assert threads.default_threads(1) == threads.default_threads(threads.THREADED_FROM_ENVS - 1) == 1
    assert threads.default_threads(threads.THREADED_FROM_ENVS) == min(2, numba.get_num_threads())
    monkeypatch.setattr(threads, "idle_cores", lambda: 1)  # another process keeps a core busy
    assert threads.default_threads(256) == 1


def test_never_more_threads_than_numba_has(monkeypatch):
    monkeypatch.setattr(threads, "idle_cores", lambda: 64)
    previous = numba.get_num_threads()
    numba.set_num_threads(1)  # e.g. train's choice, or NUMBA_NUM_THREADS=1
    try:
        assert threads.default_threads(256) == 1
    finally:
        numba.set_num_threads(previous)


def test_idle_cores_is_at_least_one_and_at_most_the_cores(monkeypatch):
    monkeypatch.setattr(threads.os, "getloadavg", lambda: (50.0, 50.0, 50.0))
    assert threads.idle_cores() == 1
    monkeypatch.setattr(threads.os, "getloadavg", lambda: (0.0, 0.0, 0.0))
    assert threads.idle_cores() == len(threads.os.sched_getaffinity(0))


def test_a_fleet_steps_on_its_threads_and_puts_the_callers_count_back():
    fleet = Fleet([make_env("raw", **SHORT) for _ in range(2)], threads=1)
    assert fleet.threads == 1
    for env in fleet.envs:
        env.reset(seed=0)
    seen = []
    suite = fleet.bases[0].sensors
    read_batch = suite.read_batch
    suite.read_batch = lambda *args, **kwargs: seen.append(numba.get_num_threads()) or read_batch(*args, **kwargs)
    previous = numba.get_num_threads()
    fleet.step([0, 1], np.zeros((2, 2)))
    assert seen == [1] and numba.get_num_threads() == previous


@pytest.mark.parametrize("bad", [0, -1, 1.5, True, "2", numba.config.NUMBA_NUM_THREADS + 1])
def test_a_bad_thread_count_is_refused(bad):
    with pytest.raises(ValueError, match=r"threads must be an integer in \[1, "):
        Fleet([make_env("raw", **SHORT)], threads=bad)


def test_the_vector_envs_say_and_take_their_thread_count():
    assert make_vector_env(2, "raw", **SHORT).threads == 1  # a small fleet: serial
    assert make_vector_env(2, "raw", threads=1, **SHORT).threads == 1
    from attentive_gym.vector.sb3 import NativeVecEnv

    assert NativeVecEnv([make_env("raw", **SHORT)], threads=1).threads == 1
