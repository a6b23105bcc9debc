"""Drawing the rescue world with pygame (headless-safe).

- ``WorldRenderer``: draws the arena, walls, rubble, movers (the target outlined), the
  robot, its laser beams and sonar cones on an offscreen ``pygame.Surface``; returns an
  RGB array, or shows it in a window for ``render_mode="human"``.
- ``draw_key``: a small key (colour swatches with labels) in the corner of a frame
  farthest from a given point, e.g. the robot.

Only ``pygame.display`` (and only for a window) and ``pygame.font`` (for a key) are
initialised, never ``pygame.init()``; set ``SDL_VIDEODRIVER=dummy`` on machines without
a display. Importing this module without pygame (the ``render`` extra) raises
``attentive_gym._optional.MissingExtraError``.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Sequence

import numpy as np

from attentive_gym._optional import require

os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
pygame = require("pygame", "rendering")

__all__ = ["WorldRenderer", "COLOURS", "draw_key"]

COLOURS = {
    "floor": (245, 243, 238),
    "wall": (60, 60, 70),
    "rubble": (150, 120, 90),
    "victim": (215, 60, 60),
    "robot": (90, 110, 150),
    "attentive robot": (30, 140, 90),
    "target": (255, 200, 0),
    "laser": (220, 40, 40),
    "sonar": (60, 120, 220),
}
_MAX_WINDOW_PX = 640
#: The key's look (px): label font height, swatch side, padding inside, margin to the frame's edge.
_KEY_FONT_PX = 16
_KEY_SWATCH_PX = 12
_KEY_PAD_PX = 5
_KEY_MARGIN_PX = 6
_KEY_BACKGROUND = (255, 255, 255)
_KEY_BORDER = (120, 120, 120)
_KEY_TEXT = (20, 20, 20)


class WorldRenderer:
    """Draws a ``World`` and the latest sensor reading.

    Args:
        bounds: ``(x_min, y_min, x_max, y_max)`` in metres, the region drawn.
        window: open a window and show each frame (``render_mode="human"``).
        fps: frame rate of the window (``metadata["render_fps"]``).
    """

    def __init__(self, bounds: tuple[float, float, float, float], window: bool = False, fps: float = 20.0) -> None:
        x0, y0, x1, y1 = bounds
        self._scale = _MAX_WINDOW_PX / max(x1 - x0, y1 - y0)  # px per metre
        self._origin = (x0, y1)
        self.size = (int(round((x1 - x0) * self._scale)), int(round((y1 - y0) * self._scale)))
        self._surface = pygame.Surface(self.size)
        self._window = None
        self._clock = None
        self._fps = fps
        if window:
            pygame.display.init()
            self._window = pygame.display.set_mode(self.size)
            pygame.display.set_caption("attentive_gym")
            self._clock = pygame.time.Clock()

    def to_px(self, xy) -> tuple[int, int]:
        """World metres → surface pixels (y up in the world, down on screen)."""
        return (
            int(round((xy[0] - self._origin[0]) * self._scale)),
            int(round((self._origin[1] - xy[1]) * self._scale)),
        )

    def render(
        self,
        world,
        laser_points: np.ndarray,
        sonar_cones: list[np.ndarray],
        target_index: int | None,
        overlay: Callable[[WorldRenderer, pygame.Surface], None] | None = None,
    ) -> np.ndarray:
        """Draw one frame and return it as an ``(H, W, 3)`` uint8 array.

        Args:
            world: the ``World`` to draw.
            laser_points: ``(2, B, 2)``: the laser origin repeated and each beam's end (m).
            sonar_cones: one ``(P, 2)`` polygon (m) per sonar reading.
            target_index: index of the target mover, outlined.
            overlay: draws extra layers (e.g. the attention focus) after the world.
        """
        surface = self._surface
        surface.fill(COLOURS["floor"])
        cone_layer = pygame.Surface(self.size, pygame.SRCALPHA)
        for cone in sonar_cones:
            pygame.draw.polygon(cone_layer, (*COLOURS["sonar"], 40), [self.to_px(p) for p in cone])
        surface.blit(cone_layer, (0, 0))
        for entity, shape in world.static:
            self._draw_shape(surface, shape, COLOURS["wall" if entity.kind == "wall" else "rubble"])
        for i, mover in enumerate(world.movers):
            self._draw_shape(surface, mover.shape, COLOURS[mover.spec.kind])
            if i == target_index:
                self._draw_shape(surface, mover.shape, COLOURS["target"], width=3)
        origins, ends = laser_points
        for start, end in zip(origins[::2], ends[::2]):  # every other beam keeps the picture legible
            pygame.draw.line(surface, COLOURS["laser"], self.to_px(start), self.to_px(end), 1)
        self._draw_shape(surface, world.robot.shape, COLOURS["attentive robot"])
        x, y, heading = world.robot.pose
        nose = (x + 0.4 * math.cos(heading), y + 0.4 * math.sin(heading))
        pygame.draw.line(surface, (0, 0, 0), self.to_px((x, y)), self.to_px(nose), 2)
        if overlay is not None:
            overlay(self, surface)
        if self._window is not None:
            self._window.blit(surface, (0, 0))
            pygame.event.pump()
            pygame.display.flip()
            self._clock.tick(self._fps)
        return np.transpose(pygame.surfarray.array3d(surface), (1, 0, 2)).copy()

    def _draw_shape(self, surface: pygame.Surface, shape, colour, width: int = 0) -> None:
        body = shape.body
        if hasattr(shape, "get_vertices"):
            points = [self.to_px(body.local_to_world(v)) for v in shape.get_vertices()]
            pygame.draw.polygon(surface, colour, points, width)
        elif hasattr(shape, "a"):
            a, b = body.local_to_world(shape.a), body.local_to_world(shape.b)
            pygame.draw.line(surface, colour, self.to_px(a), self.to_px(b), max(2, int(2 * shape.radius * self._scale)))
        else:
            centre = body.local_to_world(shape.offset)
            pygame.draw.circle(surface, colour, self.to_px(centre), max(2, int(shape.radius * self._scale)), width)

    def close(self) -> None:
        if self._window is not None:
            pygame.display.quit()
            self._window = None


def draw_key(
    surface: pygame.Surface, entries: Sequence[tuple[str, tuple[int, int, int, int]]], avoid_px: tuple[int, int]
) -> pygame.Rect:
    """Draw a key on ``surface`` in the corner farthest from the pixel ``avoid_px``.

    Args:
        surface: the frame.
        entries: one row per ``(label, (r, g, b, a))``: a square swatch of that colour,
            blended at opacity ``a`` (0..255) over the key's white background, then the label.
        avoid_px: ``(x, y)`` pixel the key keeps away from (e.g. the robot's centre).

    Returns:
        The key's rectangle on ``surface`` (px).
    """
    if not pygame.font.get_init():
        pygame.font.init()
    font = pygame.font.Font(None, _KEY_FONT_PX)
    labels = [font.render(label, True, _KEY_TEXT) for label, _ in entries]
    row_px = max(_KEY_SWATCH_PX, *(label.get_height() for label in labels))
    width = 3 * _KEY_PAD_PX + _KEY_SWATCH_PX + max(label.get_width() for label in labels)
    height = _KEY_PAD_PX + len(entries) * (row_px + _KEY_PAD_PX)
    key = pygame.Surface((width, height))
    key.fill(_KEY_BACKGROUND)
    for row, ((_, colour), label) in enumerate(zip(entries, labels)):
        top = _KEY_PAD_PX + row * (row_px + _KEY_PAD_PX)
        swatch = pygame.Surface((_KEY_SWATCH_PX, _KEY_SWATCH_PX), pygame.SRCALPHA)
        swatch.fill(colour)
        key.blit(swatch, (_KEY_PAD_PX, top + (row_px - _KEY_SWATCH_PX) // 2))
        key.blit(label, (2 * _KEY_PAD_PX + _KEY_SWATCH_PX, top + (row_px - label.get_height()) // 2))
    pygame.draw.rect(key, _KEY_BORDER, key.get_rect(), 1)
    rect = _farthest_corner(surface.get_size(), key.get_size(), avoid_px)
    surface.blit(key, rect)
    return rect


def _farthest_corner(frame_px: tuple[int, int], size_px: tuple[int, int], avoid_px: tuple[int, int]) -> pygame.Rect:
    """A ``size_px`` rectangle in the corner of a ``frame_px`` frame (a margin in) whose
    centre is farthest from ``avoid_px``."""
    (frame_w, frame_h), (w, h) = frame_px, size_px
    corners = [
        pygame.Rect(x, y, w, h)
        for x in (_KEY_MARGIN_PX, frame_w - w - _KEY_MARGIN_PX)
        for y in (_KEY_MARGIN_PX, frame_h - h - _KEY_MARGIN_PX)
    ]
    return max(corners, key=lambda r: math.dist(r.center, avoid_px))
