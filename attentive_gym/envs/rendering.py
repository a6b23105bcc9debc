"""Drawing the rescue world with pygame (headless-safe).

- ``WorldRenderer``: draws the arena, walls, rubble, movers (the target outlined), the
  robot, its laser beams and sonar cones on an offscreen ``pygame.Surface``; returns an
  RGB array, or shows it in a window for ``render_mode="human"``.

Only ``pygame.display`` (and only for a window) is initialised, never ``pygame.init()``;
set ``SDL_VIDEODRIVER=dummy`` on machines without a display.
"""

from __future__ import annotations

import math
import os
from typing import Callable

import numpy as np

os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
import pygame  # noqa: E402

__all__ = ["WorldRenderer", "COLOURS"]

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

    def render(self, world, laser_points: np.ndarray, sonar_cones: list[np.ndarray], target_index: int | None,
               overlay: Callable[["WorldRenderer", pygame.Surface], None] | None = None) -> np.ndarray:
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
