"""Drawing the attention's state over the world's picture.

``draw_attention`` shades each region's sector around the robot by its saliency L
(``SALIENCY_COLOUR``), outlines the focused region's sector (``FOCUS_COLOURS``: bottom-up
in orange, top-down in magenta) and draws a key of the three in the frame's corner
farthest from the robot. It needs pygame (the ``render`` extra), as ``envs.rendering`` does.
"""

from __future__ import annotations

import math

import numpy as np

from attentive_gym._optional import require
from attentive_gym.attention import AttentionOutput, Grid
from attentive_gym.attention.regions import laser_bearings_rad
from attentive_gym.envs.rendering import draw_key

pygame = require("pygame", "rendering")

__all__ = ["draw_attention", "SECTOR_RADIUS_M", "SALIENCY_COLOUR", "FOCUS_COLOURS", "KEY"]

#: Radius of the drawn region sectors (m).
SECTOR_RADIUS_M = 2.0
#: Shading of the saliency L (RGB), at opacity ``L / max(L)`` of ``_SALIENCY_MAX_ALPHA``.
SALIENCY_COLOUR = (0, 150, 160)
#: Outline of the focused region by origin (RGB).
FOCUS_COLOURS = {"bottom-up": (255, 120, 0), "top-down": (200, 0, 200)}
_SALIENCY_MAX_ALPHA = 150
#: The key's rows: label and swatch colour (RGBA), the saliency's at its full shading.
KEY: tuple[tuple[str, tuple[int, int, int, int]], ...] = (
    ("bottom-up focus", (*FOCUS_COLOURS["bottom-up"], 255)),
    ("top-down focus", (*FOCUS_COLOURS["top-down"], 255)),
    ("saliency L", (*SALIENCY_COLOUR, _SALIENCY_MAX_ALPHA)),
)
_FOCUS_OUTLINE_PX = 3
_HALF_BEAM_RAD = math.radians(0.5)


def draw_attention(renderer, surface: pygame.Surface, pose, grid: Grid, output: AttentionOutput) -> None:
    """Draw ``output`` (one model step) and the key on ``surface`` for a robot at ``pose``
    (x m, y m, heading rad)."""
    edges = _region_edges_rad(grid)
    _shade_saliency(renderer, surface, pose, edges, output.L)
    if output.focus is not None:
        right, left = edges[output.focus]
        outline = _sector(renderer, pose, right, left, SECTOR_RADIUS_M * 1.25)
        pygame.draw.polygon(surface, FOCUS_COLOURS[output.origin], outline, _FOCUS_OUTLINE_PX)
    draw_key(surface, KEY, renderer.to_px(pose[:2]))


def _region_edges_rad(grid: Grid) -> np.ndarray:
    """``(J, 2)`` bearings (rad, robot frame) of the right and left edge of each region."""
    beams = laser_bearings_rad()
    return np.array([[beams[s.start] - _HALF_BEAM_RAD, beams[s.stop - 1] + _HALF_BEAM_RAD] for s in grid.beam_slices])


def _sector(renderer, pose, right_rad: float, left_rad: float, radius_m: float) -> list[tuple[int, int]]:
    x, y, heading = pose
    angles = np.linspace(right_rad, left_rad, 8) + heading
    rim = [renderer.to_px((x + radius_m * math.cos(a), y + radius_m * math.sin(a))) for a in angles]
    return [renderer.to_px((x, y)), *rim]


def _shade_saliency(renderer, surface: pygame.Surface, pose, edges: np.ndarray, saliency: np.ndarray) -> None:
    """Shade region j's sector (``edges`` ``(J, 2)`` rad) at an opacity proportional to
    ``saliency[j] / max(saliency)`` (``saliency`` ``(J,)``, L in gain units)."""
    peak = max(float(saliency.max()), 1e-9)
    layer = pygame.Surface(surface.get_size(), pygame.SRCALPHA)
    for region, (right, left) in enumerate(edges):
        alpha = int(_SALIENCY_MAX_ALPHA * min(float(saliency[region]) / peak, 1.0))
        if alpha > 0:
            pygame.draw.polygon(layer, (*SALIENCY_COLOUR, alpha), _sector(renderer, pose, right, left, SECTOR_RADIUS_M))
    surface.blit(layer, (0, 0))
