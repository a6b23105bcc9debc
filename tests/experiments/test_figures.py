"""The trace and experiment figures: one time axis for every panel, rows named s1..s8,
and ``experiments.figures`` importable without the runner."""

import functools
import subprocess
import sys
from pathlib import Path

import matplotlib.pyplot as plt
import pytest

from attentive_gym.experiments import run_experiment
from attentive_gym.experiments.figures import experiment_figure
from attentive_gym.viz.trace_figure import PANELS, panel_axes, plot_trace

_SONAR_NAMES = [f"s{n}" for n in range(1, 9)]


@functools.cache
def _result(name):
    return run_experiment(name, kinematics="window")


def _assert_one_time_axis(fig, n_panels):
    fig.canvas.draw()
    axes = panel_axes(fig)
    assert len(axes) == n_panels
    extents = {(round(ax.get_position().x0, 6), round(ax.get_position().x1, 6)) for ax in axes}
    assert len(extents) == 1, f"panels span different widths: {sorted(extents)}"
    assert len({ax.get_xlim() for ax in axes}) == 1


def test_trace_figure_panels_share_one_time_axis(tmp_path):
    trace = _result("exp05").trace
    fig = plot_trace(trace, panels=PANELS, path=tmp_path / "trace.png")  # every heat map and the raster
    _assert_one_time_axis(fig, len(PANELS))
    assert panel_axes(fig)[0].get_xlim() == pytest.approx((trace.t[0] - 0.025, trace.t[-1] + 0.025))


@pytest.mark.parametrize("name", ["exp01", "exp05"])
def test_experiment_figure_panels_share_one_time_axis(name):
    fig = experiment_figure(_result(name))
    try:
        _assert_one_time_axis(fig, len(_result(name).experiment.panels))
    finally:
        plt.close(fig)


def test_region_rows_are_named_after_the_sonars(tmp_path):
    fig = plot_trace(_result("exp01").trace, panels=("O1", "O2", "F1", "WTA"), path=tmp_path / "trace.png")
    sonars, beams, motion, winners = panel_axes(fig)
    for ax in (sonars, motion, winners):
        assert [label.get_text() for label in ax.get_yticklabels()] == _SONAR_NAMES
    assert (sonars.get_ylabel(), beams.get_ylabel(), motion.get_ylabel()) == ("sonar", "beam", "region")
    assert "s1" not in [label.get_text() for label in beams.get_yticklabels()]


def test_figures_import_without_the_runner():
    """A fresh interpreter imports ``experiments.figures`` alone (the package's ``__init__``,
    which imports everything, left out): it never pulls in the runner or the checks."""
    package = Path(__file__).resolve().parents[2] / "attentive_gym" / "experiments"
    code = (
        "import sys, types\n"
        "package = types.ModuleType('attentive_gym.experiments')\n"
        f"package.__path__ = [{str(package)!r}]\n"
        "sys.modules['attentive_gym.experiments'] = package\n"
        "import attentive_gym.experiments.figures\n"
        "loaded = sorted(m for m in sys.modules if m.startswith('attentive_gym.experiments.'))\n"
        "print(loaded)\n"
        "assert loaded == ['attentive_gym.experiments.figures', 'attentive_gym.experiments.registry', "
        "'attentive_gym.experiments.result'], loaded\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
