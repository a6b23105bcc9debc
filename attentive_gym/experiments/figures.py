"""Figures of an experiment in the paper's layout (Colombini et al., Figs. 3–7).

- ``experiment_figure(result)``: the experiment's panels (``Experiment.panels``: time on
  x, sonar region s1..s8 or laser beam on y as heat maps, winners as a raster) on one
  shared time axis, with the goal changes marked; the title names the noise and the
  kinematics mode.
- ``plot_experiment(result, path)``: that figure saved as a small PNG.

This module reads an ``ExperimentResult`` only; the runner imports it, never the reverse.
"""

from __future__ import annotations

import os
from pathlib import Path

from attentive_gym._atomic import save_figure
from attentive_gym._optional import require
from attentive_gym.experiments.result import ExperimentResult
from attentive_gym.viz.trace_figure import panel_axes, plot_trace

__all__ = ["experiment_figure", "plot_experiment", "FIGURE_DPI"]

#: Resolution of the saved figures (dots per inch); keeps each PNG near 100 KB.
FIGURE_DPI = 80


def experiment_figure(result: ExperimentResult):
    """The figure of ``result`` with its experiment's panels, goal changes as dashed
    vertical lines on every panel. A pyplot ``Figure``: ``plt.close`` it when done."""
    fig = plot_trace(result.trace, panels=result.experiment.panels)
    for change in result.experiment.goal_changes:
        for ax in panel_axes(fig):
            ax.axvline(change.t_s, color="white", linestyle="--", linewidth=1.0)
    fig.suptitle(f"{result.experiment.title} ({result.describe_noise()}; {result.kinematics})", fontsize="small")
    fig.tight_layout()
    return fig


def plot_experiment(result: ExperimentResult, path: str | os.PathLike, dpi: int = FIGURE_DPI) -> Path:
    """Save ``experiment_figure(result)`` as a PNG at ``path`` (``dpi`` dots per inch);
    returns the path written; ``MissingExtraError`` without matplotlib (the ``plot`` extra)."""
    plt = require("matplotlib.pyplot", "drawing an experiment's figure")
    fig = experiment_figure(result)
    try:
        return save_figure(fig, path, dpi=dpi)
    finally:
        plt.close(fig)
