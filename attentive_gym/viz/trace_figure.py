"""The figure of an attention trace in the paper's layout (Colombini et al., Figs. 3–7).

- ``plot_trace``: one panel per quantity (time on x, region s1..s8 or beam on y as a heat
  map), and the winner-takes-all output as a raster coloured by origin; all panels share
  one time axis.
- ``panel_axes``: the panels' axes of such a figure (without the colour bars).
- ``PANELS``: the panel names it knows.

matplotlib is imported inside the functions only; saving renders with the Agg canvas
without touching pyplot's global backend.
"""

from __future__ import annotations

import os
from collections.abc import Sequence

import numpy as np

from attentive_gym._atomic import save_figure
from attentive_gym._optional import require
from attentive_gym.attention.config import MAP_NAMES
from attentive_gym.attention.io.trace import Trace, load_trace
from attentive_gym.attention.regions import FRONT_SONARS, region_name

__all__ = ["plot_trace", "panel_axes", "PANELS", "DEFAULT_PANELS"]

#: Panels ``plot_trace`` can draw: observations, feature maps, maps and the WTA raster.
PANELS: tuple[str, ...] = ("O1", "O2", *MAP_NAMES, "C", "C_BU", "C_TD", "M", "L", "WTA")
DEFAULT_PANELS: tuple[str, ...] = ("O1", "O2", "F1", "F3", "C", "L", "M", "WTA")
_TITLES = {
    "O1": "O1: front sonars (m)",
    "O2": "O2: laser (m)",
    "F1": "F1 motion",
    "F2": "F2 direction",
    "F3": "F3 distance",
    "F4": "F4 goal speed",
    "F5": "F5 goal direction",
    "F6": "F6 goal distance",
    "C": "C combined",
    "C_BU": "C bottom-up",
    "C_TD": "C top-down",
    "M": "M attentional map (gain)",
    "L": "L saliency",
    "WTA": "WTA winners",
}
_ROW_LABELS = {"O1": "sonar", "O2": "beam"}
_ORIGIN_STYLE = {0: ("tab:blue", "o", "bottom-up"), 1: ("tab:red", "s", "top-down")}
_PANEL_HEIGHT_IN = 1.6
#: Width of the colour-bar column relative to the panels' column.
_COLOURBAR_WIDTH = 0.02
_FIGURE_WIDTH_IN = 8.0
_DPI = 120


def plot_trace(
    trace: Trace | str | os.PathLike, panels: Sequence[str] = DEFAULT_PANELS, path: str | os.PathLike | None = None
):
    """Draw a trace: one row per panel, time (s) on the x axis.

    Every panel shares one time axis of the same width: the heat maps' colour bars sit in
    a narrow column of their own, to the right of the panels.

    Args:
        trace: a ``Trace`` or the path of a trace ``.npz``.
        panels: names from ``PANELS``; ``F1``..``F6``, ``C``, ``M``, ``L`` and the
            observations are heat maps (front-sonar region s1..s8, or laser beam, on y),
            ``WTA`` is a raster of the focus per step (blue circles bottom-up, red squares
            top-down; filled where a new course fired).
        path: where to save the figure (PNG, via the Agg canvas); None to only return it.

    Returns:
        The matplotlib ``Figure``; ``panel_axes(figure)`` are its panels.

    Raises:
        ValueError: for an unknown panel name or an empty panel list.
        ImportError: ``MissingExtraError`` when matplotlib (the ``plot`` extra) is missing.
    """
    require("matplotlib", "drawing an attention trace")
    if not isinstance(trace, Trace):
        trace = load_trace(trace)
    panels = _checked_panels(panels)
    fig = _new_figure((_FIGURE_WIDTH_IN, _PANEL_HEIGHT_IN * len(panels)), pyplot=path is None)
    grid = fig.add_gridspec(len(panels), 2, width_ratios=(1.0, _COLOURBAR_WIDTH))
    edges = _time_edges(trace.t)
    first = None
    for row, name in enumerate(panels):
        ax = fig.add_subplot(grid[row, 0], sharex=first, label=name)
        if first is None:
            first = ax
        if name == "WTA":
            _draw_wta(ax, trace)
        else:
            _draw_heat_map(ax, fig.add_subplot(grid[row, 1]), edges, _panel_values(trace, name), name)
        ax.set_title(_TITLES[name], fontsize="small", loc="left")
        ax.tick_params(labelbottom=row == len(panels) - 1)
    ax.set_xlabel("t (s)")
    ax.set_xlim(edges[0], edges[-1])
    fig.tight_layout()
    if path is not None:
        save_figure(fig, path, dpi=_DPI)
    return fig


def panel_axes(fig) -> list:
    """The panels' axes of a ``plot_trace`` figure, top to bottom (colour bars left out)."""
    return [ax for ax in fig.axes if ax.get_label() in PANELS]


def _checked_panels(panels: Sequence[str]) -> tuple[str, ...]:
    panels = tuple(panels)
    unknown = [p for p in panels if p not in PANELS]
    if unknown or not panels:
        raise ValueError(f"unknown or no panels {unknown or list(panels)}; allowed: {', '.join(PANELS)}")
    return panels


def _new_figure(size_in: tuple[float, float], pyplot: bool):
    """An empty figure of ``size_in`` (inches): pyplot's (shown in notebooks), or one on
    its own Agg canvas that leaves pyplot alone."""
    if pyplot:
        import matplotlib.pyplot as plt

        return plt.figure(figsize=size_in)
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=size_in)
    FigureCanvasAgg(fig)
    return fig


def _draw_heat_map(ax, colourbar_ax, time_edges: np.ndarray, values: np.ndarray, name: str) -> None:
    """``values`` ``(T, N)`` as cells between ``time_edges`` ``(T + 1,)`` (s), row n on y,
    with its colour bar in ``colourbar_ax``."""
    mesh = ax.pcolormesh(time_edges, np.arange(values.shape[1] + 1) - 0.5, values.T, shading="flat", cmap="viridis")
    ax.figure.colorbar(mesh, cax=colourbar_ax)
    _label_rows(ax, values.shape[1], _ROW_LABELS.get(name, "region"))


def _label_rows(ax, n_rows: int, label: str) -> None:
    """Label the y axis ``label``; 8 rows (the front-sonar regions, or the sonars) are named
    s1..s8, other rows (laser beams) keep their indices."""
    ax.set_ylabel(label)
    if n_rows == FRONT_SONARS:
        ax.set_yticks(range(FRONT_SONARS), [region_name(j) for j in range(FRONT_SONARS)], fontsize="x-small")


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
    _label_rows(ax, trace.n_regions, "region")
    ax.legend(loc="upper right", fontsize="x-small")
