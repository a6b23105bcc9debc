"""Figures of an experiment in the paper's layout (Colombini et al., Figs. 3–7).

- ``plot_experiment(result, path)``: the experiment's panels (``Experiment.panels``: time
  on x, region or beam on y as heat maps, winners as a raster) with the goal changes
  marked, saved as a small PNG; the title names the noise and the kinematics mode.
"""

from __future__ import annotations

import os
from pathlib import Path

from attentive_gym.experiments.result import ExperimentResult
from attentive_gym.viz.trace_figure import plot_trace

__all__ = ["plot_experiment", "FIGURE_DPI"]

#: Resolution of the saved figures (dots per inch); keeps each PNG near 100 KB.
FIGURE_DPI = 80


def plot_experiment(result: ExperimentResult, path: str | os.PathLike, dpi: int = FIGURE_DPI) -> Path:
    """Draw ``result`` with its experiment's panels and save it as a PNG at ``path``.

    Goal changes are dashed vertical lines on every panel. Returns the path written.
    """
    import matplotlib.pyplot as plt

    fig = plot_trace(result.trace, panels=result.experiment.panels)
    try:
        for change in result.experiment.goal_changes:
            for ax in (ax for ax in fig.axes if ax.get_label() != "<colorbar>"):
                ax.axvline(change.t_s, color="white", linestyle="--", linewidth=1.0)
        fig.suptitle(f"{result.experiment.title} ({result.describe_noise()}; {result.kinematics})", fontsize="small")
        fig.tight_layout()
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(path, dpi=dpi)
    finally:
        plt.close(fig)
    return path
