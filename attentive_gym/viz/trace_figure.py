"""The figure of an attention trace in the paper's layout (Colombini et al., Figs. 3–7).

- ``plot_trace``: one panel per quantity (time on x, region s1..s8 or beam on y as a heat
  map), and the winner-takes-all output as a raster coloured by origin; all panels share
  one time axis. Below them, where the trace holds the robot's poses (a replayed log), a
  plan view of one scan in the odometry frame with the focus drawn in it (``plan_view``).
- ``panel_axes``: the panels' axes of such a figure (without the colour bars).
- ``PANELS``: the panel names it knows.

One orientation everywhere: every panel's y axis is the bearing (deg, counter-clockwise
from the heading), +90° (the robot's left, region s1, laser beam 179) at the top and -90°
(its right, s8, beam 0) at the bottom, as in the plan view with the robot heading along
+x. A region's row spans its bearings (s1 +70..+90°, s2 +40..+70°, ...), named on the
left and given in degrees on the right. The range panels' colours run from 0 to the
sensor's range (``laser_max_range_m``, ``sonar_max_range_m`` of the trace's configuration:
a replayed bag's laser range), and no echo is grey.

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
from attentive_gym.attention.regions import FRONT_SONARS, LASER_FOV_DEG, region_name
from attentive_gym.viz._rows import ORIGIN_STYLE, bearing_span, row_bearings_deg
from attentive_gym.viz.plan_view import draw_plan, plan_step

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
#: The configuration's maximum range (m) that scales each range panel's colours.
_RANGE_PANELS = {"O1": "sonar_max_range_m", "O2": "laser_max_range_m"}
_NO_ECHO_COLOUR = "0.8"
#: Laser beams named on the laser panel's left axis (beam 0 is rightmost).
_BEAM_TICKS = (0, 45, 90, 135, 179)
#: Bearings (deg) marked on the right axis of panels with one row per laser beam.
_BEARING_TICKS_DEG = (-90, -45, 0, 45, 90)
_ORIENTATION_NOTE = (
    "Bearings counter-clockwise from the heading: +90° is the robot's left (s1, top of every panel), "
    "-90° its right (s8, bottom)"
)
_PANEL_HEIGHT_IN = 1.6
#: Room kept above the panels for the orientation note (in).
_NOTE_HEIGHT_IN = 0.15
_PLAN_HEIGHT_IN = 4.2
#: The plan view's width (fraction of the figure's) and the margin above and below it
#: (fraction of its row's height).
_PLAN_WIDTH = 0.55
_PLAN_MARGIN = 0.12
#: Width of the colour-bar column relative to the panels' column.
_COLOURBAR_WIDTH = 0.02
_FIGURE_WIDTH_IN = 8.0
_DPI = 120


def plot_trace(
    trace: Trace | str | os.PathLike,
    panels: Sequence[str] = DEFAULT_PANELS,
    path: str | os.PathLike | None = None,
    plan: bool | None = None,
    plan_at: int | None = None,
):
    """Draw a trace: one row per panel, time (s) on the x axis, bearing on the y axis.

    Every panel shares one time axis of the same width: the heat maps' colour bars sit in
    a narrow column of their own, to the right of the panels.

    Args:
        trace: a ``Trace`` or the path of a trace ``.npz``.
        panels: names from ``PANELS``; ``F1``..``F6``, ``C``, ``M``, ``L`` and the
            observations are heat maps (front-sonar region s1..s8, or laser beam, at its
            bearings on y, left on top), ``WTA`` is a raster of the focus per step (blue
            circles bottom-up, red squares top-down; filled where a new course fired).
        path: where to save the figure (PNG, via the Agg canvas); None to only return it.
        plan: draw the plan view below the panels (``plan_view.draw_plan``); None: where
            the trace holds the robot's poses (``Trace.pose``, recorded by ``replay_log``).
        plan_at: the step the plan view shows, marked by a dotted line on every panel
            (default ``plan_view.plan_step``: the most salient step with a focus).

    Returns:
        The matplotlib ``Figure``; ``panel_axes(figure)`` are its panels, and the plan
        view is the axes labelled "plan".

    Raises:
        ValueError: for an unknown panel name or an empty panel list.
        ImportError: ``MissingExtraError`` when matplotlib (the ``plot`` extra) is missing.
    """
    require("matplotlib", "drawing an attention trace")
    if not isinstance(trace, Trace):
        trace = load_trace(trace)
    panels = _checked_panels(panels)
    plan = trace.pose is not None if plan is None else plan
    panels_height_in = _PANEL_HEIGHT_IN * len(panels)
    plan_height_in = _PLAN_HEIGHT_IN if plan else 0.0
    fig = _new_figure((_FIGURE_WIDTH_IN, panels_height_in + plan_height_in), pyplot=path is None)
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
            _draw_heat_map(ax, fig.add_subplot(grid[row, 1]), edges, trace, name)
        ax.set_title(_panel_title(trace, name), fontsize="small", loc="left")
        ax.tick_params(labelbottom=row == len(panels) - 1)
    ax.set_xlabel("t (s)")
    ax.set_xlim(edges[0], edges[-1])
    fig.suptitle(_ORIENTATION_NOTE, fontsize="small")
    height_in = panels_height_in + plan_height_in
    plan_share = plan_height_in / height_in
    fig.tight_layout(rect=(0.0, plan_share, 1.0, 1.0 - _NOTE_HEIGHT_IN / height_in))
    if plan:
        step = plan_step(trace) if plan_at is None else int(plan_at)
        draw_plan(fig.add_axes(_plan_rect(ax, plan_share), label="plan"), trace, step)
        for panel in panel_axes(fig):
            panel.axvline(trace.t[step], color="0.5", linestyle=":", linewidth=1.0)
    if path is not None:
        save_figure(fig, path, dpi=_DPI)
    return fig


def _plan_rect(last_panel, plan_share: float) -> tuple[float, float, float, float]:
    """The plan view's place (figure fractions: left, bottom, width, height) in the bottom
    ``plan_share`` of the figure: aligned with the panels' left edge, its legend to the right."""
    left = last_panel.get_position().x0
    bottom = _PLAN_MARGIN * plan_share
    return left, bottom, _PLAN_WIDTH, plan_share * (1.0 - 2.0 * _PLAN_MARGIN)


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


def _panel_title(trace: Trace, name: str) -> str:
    """The panel's title; a range panel's names the range its colours run to."""
    if name not in _RANGE_PANELS:
        return _TITLES[name]
    return f"{_TITLES[name]}, 0 to {trace.config[_RANGE_PANELS[name]]:g} m; grey: no echo"


def _draw_heat_map(ax, colourbar_ax, time_edges: np.ndarray, trace: Trace, name: str) -> None:
    """Panel ``name``'s values ``(T, N)`` as cells between ``time_edges`` ``(T + 1,)`` (s)
    and each row's bearings (deg) on y, with its colour bar in ``colourbar_ax``; a range
    panel's colours run from 0 to its sensor's range, no echo grey."""
    import matplotlib

    values = _panel_values(trace, name)
    bounds = row_bearings_deg(values.shape[1])
    order = np.argsort(bounds[:, 0], kind="stable")
    row_edges = np.append(bounds[order, 0], bounds[order[-1], 1])
    cells = values[:, order].T
    scale = {}
    if name in _RANGE_PANELS:
        max_range_m = float(trace.config[_RANGE_PANELS[name]])
        cells = np.ma.masked_greater_equal(cells, max_range_m - float(trace.config["no_echo_epsilon_m"]))
        scale = {"vmin": 0.0, "vmax": max_range_m}
    cmap = matplotlib.colormaps["viridis"].with_extremes(bad=_NO_ECHO_COLOUR)
    mesh = ax.pcolormesh(time_edges, row_edges, cells, shading="flat", cmap=cmap, **scale)
    ax.figure.colorbar(mesh, cax=colourbar_ax)
    _label_rows(ax, values.shape[1], _ROW_LABELS.get(name, "region"))


def _label_rows(ax, n_rows: int, label: str) -> None:
    """Label the y axis (bearing, deg; left on top) ``label``: 8 rows (the front-sonar
    regions, or the sonars) are named s1..s8 on the left and given their bearings on the
    right; laser beams keep their indices on the left, bearings on the right."""
    bounds = row_bearings_deg(n_rows)
    centres = bounds.mean(axis=1)
    ax.set_ylim(-LASER_FOV_DEG / 2.0, LASER_FOV_DEG / 2.0)
    ax.set_ylabel(label)
    bearings = ax.secondary_yaxis("right")
    if n_rows == FRONT_SONARS:
        ax.set_yticks(centres, [region_name(j) for j in range(FRONT_SONARS)], fontsize="x-small")
        bearings.set_yticks(centres, [bearing_span(low, high) for low, high in bounds], fontsize="x-small")
    else:
        ax.set_yticks(centres[list(_BEAM_TICKS)], [str(beam) for beam in _BEAM_TICKS], fontsize="x-small")
        bearings.set_yticks(_BEARING_TICKS_DEG, [f"{b:+d}°" if b else "0°" for b in _BEARING_TICKS_DEG])
        bearings.tick_params(labelsize="x-small")


def _panel_values(trace: Trace, name: str) -> np.ndarray:
    """``(T, N)`` the values of panel ``name``."""
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
    """The focus of every step at its region's centre bearing (deg), by origin."""
    centres = row_bearings_deg(trace.n_regions).mean(axis=1)
    for code, (colour, marker, label) in ORIGIN_STYLE.items():
        steps = trace.origin == code
        fired = steps & trace.fired
        held = steps & ~trace.fired
        ax.scatter(trace.t[held], centres[trace.focus[held]], s=10, marker=marker, facecolors="none", edgecolors=colour)
        ax.scatter(trace.t[fired], centres[trace.focus[fired]], s=18, marker=marker, color=colour, label=label)
    _label_rows(ax, trace.n_regions, "region")
    ax.legend(loc="lower right", bbox_to_anchor=(1.0, 1.0), ncol=2, fontsize="x-small", frameon=False)
