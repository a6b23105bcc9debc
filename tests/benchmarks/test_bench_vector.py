"""Smoke test of ``benchmarks/bench_vector.py``'s floor section: the timed kernels are the
env's own (timed while it steps, put back after), the pymunk floor is a positive time, and a
section name it does not know is refused before anything runs."""

from __future__ import annotations

import math

import numpy as np
import pytest

from support import load_benchmark

bench = load_benchmark("bench_vector")


@pytest.fixture(scope="module")
def focus_fleet():
    env = bench.make_vector("focus", 2, "vector_entry_point")
    env.reset(seed=0)
    yield env
    env.close()


def test_timed_kernels_are_the_steps_own_and_are_put_back(focus_fleet):
    sensing_kernel, model_kernel = bench.sensor_suite._read_many_kernel, bench.model_batch.attend_many
    actions = np.zeros((2, 2), np.float32)
    with (
        bench.CallTimer(bench.sensor_suite, "_read_many_kernel") as sensing,
        bench.CallTimer(bench.model_batch, "attend_many") as models,
    ):
        for _ in range(3):
            focus_fleet.step(actions)
    assert sensing.calls == models.calls == 3  # one sweep and one batch of models a step, through the timers
    assert sensing.seconds > 0.0 and models.seconds > 0.0
    assert bench.sensor_suite._read_many_kernel is sensing_kernel
    assert bench.model_batch.attend_many is model_kernel


def test_pymunk_floor_is_a_positive_time(focus_fleet):
    floor = bench.pymunk_floor_us(focus_fleet.envs, steps=5)
    assert math.isfinite(floor) and floor > 0.0


def test_unknown_section_is_refused(capsys):
    with pytest.raises(SystemExit):
        bench.main(["--sections", "floor,speed"])
    assert "unknown section(s) speed" in capsys.readouterr().err
