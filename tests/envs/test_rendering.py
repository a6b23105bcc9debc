"""The rgb_array picture's attention overlay: distinct colours for the two foci and the
saliency, and a key in the corner away from the robot."""

import itertools
import math
from types import SimpleNamespace

import numpy as np
import pygame
import pytest

from attentive_gym.attention import Grid
from attentive_gym.envs.rendering import draw_key
from attentive_gym.envs.rescue_env import AttentiveRescueEnv
from attentive_gym.wrappers.overlay import FOCUS_COLOURS, KEY, SALIENCY_COLOUR, draw_attention

_SALIENCY = np.array([0.1, 0.1, 0.4, 1.0, 0.4, 0.1, 0.1, 0.1])  # L per region, s4 the most salient
_KEY_BOX_PX = (200, 80)  # the corner area the key lies in (w, h)


def _frames(*outputs):
    """``(frames, robot_px)``: exp01's first picture drawn with each attention output, then
    without overlay; ``robot_px`` is the robot's centre on the picture."""
    env = AttentiveRescueEnv(scenario="exp01", render_mode="rgb_array")
    env.reset(seed=0)
    grid, robot_px, frames = Grid.make("sonar"), [], []

    def overlay(renderer, surface, output):
        robot_px.append(renderer.to_px(env.world.robot.pose[:2]))
        draw_attention(renderer, surface, env.world.robot.pose, grid, output)

    for output in outputs:
        env.render_overlay = lambda renderer, surface, output=output: overlay(renderer, surface, output)
        frames.append(env.render())
    env.render_overlay = None
    frames.append(env.render())
    env.close()
    return frames, robot_px[0]


def _focus(origin):
    return SimpleNamespace(L=_SALIENCY, focus=3, origin=origin)


def _farthest_corner_box(frame, point):
    """The ``_KEY_BOX_PX`` area in the corner of ``frame`` farthest from ``point`` (x, y px)."""
    (height, width), (w, h) = frame.shape[:2], _KEY_BOX_PX
    x, y = max(
        itertools.product((0, width - w), (0, height - h)),
        key=lambda corner: math.dist((corner[0] + w / 2, corner[1] + h / 2), point),
    )
    return frame[y : y + h, x : x + w]


def _count(frame, colour, tolerance=0):
    return int((np.abs(frame.astype(int) - colour).max(axis=-1) <= tolerance).sum())


def test_focus_outlines_and_saliency_have_far_apart_colours():
    colours = [*FOCUS_COLOURS.values(), SALIENCY_COLOUR]
    assert min(math.dist(a, b) for a, b in itertools.combinations(colours, 2)) > 150


def test_bottom_up_and_top_down_outlines_are_drawn_in_their_colours():
    (bottom_up, top_down, plain), _ = _frames(_focus("bottom-up"), _focus("top-down"))
    outline = np.any(bottom_up != top_down, axis=-1)  # the same sector, outlined in two colours
    assert outline.sum() > 50
    assert np.all(bottom_up[outline] == FOCUS_COLOURS["bottom-up"])
    assert np.all(top_down[outline] == FOCUS_COLOURS["top-down"])
    assert not np.array_equal(plain, bottom_up)


@pytest.mark.parametrize("origin", ["bottom-up", "top-down", None])
def test_the_key_is_drawn_in_the_corner_away_from_the_robot(origin):
    (attended, plain), robot_px = _frames(
        SimpleNamespace(L=_SALIENCY, focus=None if origin is None else 3, origin=origin)
    )
    corner, plain_corner = _farthest_corner_box(attended, robot_px), _farthest_corner_box(plain, robot_px)
    swatch_px = 12 * 12
    for _, (r, g, b, alpha) in KEY:
        shown = np.round(np.array([r, g, b]) * alpha / 255 + 255 * (1 - alpha / 255))  # over the key's white
        assert _count(corner, shown, tolerance=2) >= swatch_px > _count(plain_corner, shown, tolerance=2)
    dark = (attended.max(axis=-1) < 80) & ~(plain.max(axis=-1) < 80)  # the labels' text
    assert _farthest_corner_box(dark[..., None], robot_px).sum() > 50


@pytest.mark.parametrize(
    ("avoid", "quadrant"), [((10, 10), (1, 1)), ((390, 10), (0, 1)), ((10, 290), (1, 0)), ((390, 290), (0, 0))]
)
def test_draw_key_takes_the_corner_farthest_from_the_point(avoid, quadrant):
    surface = pygame.Surface((400, 300))
    rect = draw_key(surface, KEY, avoid)
    frame = np.transpose(pygame.surfarray.array3d(surface), (1, 0, 2))
    assert (rect.left >= 200, rect.top >= 150) == quadrant and (rect.right <= 200, rect.bottom <= 150) == (
        not quadrant[0],
        not quadrant[1],
    )
    assert _count(frame[rect.top : rect.bottom, rect.left : rect.right], FOCUS_COLOURS["top-down"]) >= 12 * 12
