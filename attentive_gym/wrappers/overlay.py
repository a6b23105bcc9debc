"""Drawing the attention's state over the world's picture.

``draw_attention`` shades each region's sector around the robot by its saliency L and
outlines the focused region's sector (bottom-up focus in orange, top-down in magenta).
"""

from __future__ import annotations

import math

import numpy as np
import pygame

from attentive_gym.attention import AttentionOutput, Grid
from attentive_gym.attention.regions import laser_bearings_rad

__all__ = ["draw_attention", "SECTOR_RADIUS_M"]

#: Radius of the drawn region sectors (m).
SECTOR_RADIUS_M = 2.0
_SALIENCY_COLOUR = (250, 150, 20)
_FOCUS_COLOURS = {"bottom-up": (255, 120, 0), "top-down": (200, 0, 200)}
_HALF_BEAM_RAD = math.radians(0.5)


def _region_edges_rad(grid: Grid) -> np.ndarray:
    """``(J, 2)`` bearings (rad, robot frame) of the right and left edge of each region."""
    beams = laser_bearings_rad()
    return np.array([[beams[s.start] - _HALF_BEAM_RAD, beams[s.stop - 1] + _HALF_BEAM_RAD] for s in grid.beam_slices])


def _sector(renderer, pose, right_rad: float, left_rad: float, radius_m: float) -> list[tuple[int, int]]:
    x, y, heading = pose
    angles = np.linspace(right_rad, left_rad, 8) + heading
    rim = [renderer.to_px((x + radius_m * math.cos(a), y + radius_m * math.sin(a))) for a in angles]
    return [renderer.to_px((x, y)), *rim]


def draw_attention(renderer, surface: pygame.Surface, pose, grid: Grid, output: AttentionOutput) -> None:
    """Draw ``output`` (one model step) on ``surface`` for a robot at ``pose`` (x m, y m, heading rad)."""
    edges = _region_edges_rad(grid)
    peak = max(float(output.L.max()), 1e-9)
    layer = pygame.Surface(surface.get_size(), pygame.SRCALPHA)
    for region, (right, left) in enumerate(edges):
        alpha = int(150 * min(float(output.L[region]) / peak, 1.0))
        if alpha > 0:
            pygame.draw.polygon(layer, (*_SALIENCY_COLOUR, alpha), _sector(renderer, pose, right, left, SECTOR_RADIUS_M))
    surface.blit(layer, (0, 0))
    if output.focus is not None:
        right, left = edges[output.focus]
        outline = _sector(renderer, pose, right, left, SECTOR_RADIUS_M * 1.25)
        pygame.draw.polygon(surface, _FOCUS_COLOURS[output.origin], outline, 3)
