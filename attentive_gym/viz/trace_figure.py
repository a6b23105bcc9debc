"""The figure of an attention trace in the paper's layout (Colombini et al., Figs. 3–7).

- ``plot_trace``: one panel per quantity (time on x, region or beam on y as a heat map),
  and the winner-takes-all output as a raster coloured by origin.
- ``PANELS``: the panel names it knows.

matplotlib is imported inside ``plot_trace`` only; saving renders with the Agg canvas
without touching pyplot's global backend.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Sequence

import numpy as np

from attentive_gym.attention.config import MAP_NAMES
from attentive_gym.attention.trace import Trace, load_trace

__all__ = ["plot_trace", "PANELS", "DEFAULT_PANELS"]

#: Panels ``plot_trace`` can draw: observations, feature maps, maps and the WTA raster.
PANELS: tuple[str, ...] = ("O1", "O2", *MAP_NAMES, "C", "C_BU", "C_TD", "M", "L", "WTA")
DEFAULT_PANELS: tuple[str, ...] = ("O1", "O2", "F1", "F3", "C", "L", "M", "WTA")
_TITLES = {
    "O1": "O1: front sonars (m)", "O2": "O2: laser (m)", "F1": "F1 motion", "F2": "F2 direction",
    "F3": "F3 distance", "F4": "F4 goal speed", "F5": "F5 goal direction", "F6": "F6 goal distance",
    "C": "C combined", "C_BU": "C bottom-up", "C_TD": "C top-down", "M": "M attentional map (gain)",
    "L": "L saliency", "WTA": "WTA winners",
}
_ORIGIN_STYLE = {0: ("tab:blue", "o", "bottom-up"), 1: ("tab:red", "s", "top-down")}
_PANEL_HEIGHT_IN = 1.6
_FIGURE_WIDTH_IN = 8.0
_DPI = 120


def plot_trace(trace: Trace | str | os.PathLike, panels: Sequence[str] = DEFAULT_PANELS,
               path: str | os.PathLike | None = None):
    """Draw a trace: one row per panel, time (s) on the x axis.

    Args:
        trace: a ``Trace`` or the path of a trace ``.npz``.
        panels: names from ``PANELS``; ``F1``..``F6``, ``C``, ``M``, ``L`` and the
            observations are heat maps (region or beam on y), ``WTA`` is a raster of the
            focus per step (blue circles bottom-up, red squares top-down; filled where a
            new course fired).
        path: where to save the figure (PNG, via the Agg canvas); None to only return it.

    Returns:
        The matplotlib ``Figure``.

    Raises:
        ValueError: for an unknown panel name or an empty panel list.
    """
    if not isinstance(trace, Trace):
        trace = load_trace(trace)
    panels = tuple(panels)
    unknown = [p for p in panels if p not in PANELS]
    if unknown or not panels:
        raise ValueError(f"unknown or no panels {unknown or list(panels)}; allowed: {', '.join(PANELS)}")
    size = (_FIGURE_WIDTH_IN, _PANEL_HEIGHT_IN * len(panels))
    if path is None:
        import matplotlib.pyplot as plt

        fig, axes = plt.subplots(len(panels), 1, sharex=True, figsize=size, squeeze=False)
    else:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        fig = Figure(figsize=size)
        FigureCanvasAgg(fig)
        axes = fig.subplots(len(panels), 1, sharex=True, squeeze=False)
    t = trace.t
    edges = _time_edges(t)
    for ax, name in zip(axes[:, 0], panels):
        if name == "WTA":
            _draw_wta(ax, trace)
        else:
            values = _panel_values(trace, name)
            mesh = ax.pcolormesh(edges, np.arange(values.shape[1] + 1) - 0.5, values.T, shading="flat",
                                 cmap="viridis")
            fig.colorbar(mesh, ax=ax, pad=0.01)
            ax.set_ylabel("beam" if name == "O2" else "region")
        ax.set_title(_TITLES[name], fontsize="small", loc="left")
    axes[-1, 0].set_xlabel("t (s)")
    axes[-1, 0].set_xlim(edges[0], edges[-1])
    fig.tight_layout()
    if path is not None:
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(path, dpi=_DPI)
    return fig


def _panel_values(trace: Trace, name: str) -> np.ndarray:
    if name in MAP_NAMES:
        return trace.F[:, MAP_NAMES.index(name), :]
    return getattr(trace, name)


def _time_edges(t: np.ndarray) -> np.ndarray:
    """Cell edges around each sample time (s) for a heat map; a single sample gets a 1 s wide cell."""
    if t.size == 1:
        return np.array([t[0] - 0.5, t[0] + 0.5])
    mid = (t[1:] + t[:-1]) / 2.0
    return np.concatenate([[t[0] - (mid[0] - t[0])], mid, [t[-1] + (t[-1] - mid[-1])]])


def _draw_wta(ax, trace: Trace) -> None:
    for code, (colour, marker, label) in _ORIGIN_STYLE.items():
        steps = trace.origin == code
        fired = steps & trace.fired
        held = steps & ~trace.fired
        ax.scatter(trace.t[held], trace.focus[held], s=10, marker=marker, facecolors="none", edgecolors=colour)
        ax.scatter(trace.t[fired], trace.focus[fired], s=18, marker=marker, color=colour, label=label)
    ax.set_ylim(-0.5, trace.n_regions - 0.5)
    ax.set_ylabel("region")
    ax.legend(loc="upper right", fontsize="x-small")
