"""What the trace figure's panels and its plan view share: the bearings each row of a
panel covers, and the style of each focus origin."""

from __future__ import annotations

import numpy as np

from attentive_gym.attention.regions import FRONT_SONARS, LASER_BEAMS, LASER_FOV_DEG, Grid, region_name

#: Colour, marker and name of each focus origin (the trace's ``origin`` codes).
ORIGIN_STYLE = {0: ("tab:blue", "o", "bottom-up"), 1: ("tab:red", "s", "top-down")}


def row_bearings_deg(n_rows: int) -> np.ndarray:
    """``(n_rows, 2)`` the bearings (deg, low and high, counter-clockwise from the heading)
    each row covers: the 8 front-sonar regions (and the 8 front sonars: s1 +70..+90°), or
    the 180 laser beams (and the laser grid's regions: beam 0 -90..-89°)."""
    grid = Grid.make("sonar" if n_rows == FRONT_SONARS else "laser")
    beam_deg = LASER_FOV_DEG / LASER_BEAMS
    low = -LASER_FOV_DEG / 2.0
    return np.array([(low + s.start * beam_deg, low + s.stop * beam_deg) for s in grid.beam_slices])


def row_name(index: int, n_rows: int) -> str:
    """``s3`` for a front-sonar region, ``beam 42`` for a laser-grid region."""
    return region_name(index) if n_rows == FRONT_SONARS else f"beam {index}"


def bearing_span(low_deg: float, high_deg: float) -> str:
    """``+70..+90°``: a row's bearings, signed (0 unsigned)."""
    return f"{_signed(low_deg)}..{_signed(high_deg)}°"


def _signed(degrees: float) -> str:
    return f"{degrees:+.0f}" if round(degrees) else "0"
