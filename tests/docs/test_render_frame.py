"""``tools/render_frame.py``: the README's picture shows a top-down focus on the target."""

import math

import numpy as np
import pytest

from attentive_gym.attention import Grid
from attentive_gym.wrappers.overlay import FOCUS_COLOURS
from support import load_tool


@pytest.fixture(scope="module")
def tool():
    return load_tool("render_frame")


def _info(bearing_rad: float, heading_rad: float = 0.7) -> dict:
    """An env step's ``info`` with the target 3 m from a robot at (1, 2) at ``bearing_rad``."""
    angle = heading_rad + bearing_rad
    target = (1.0 + 3.0 * math.cos(angle), 2.0 + 3.0 * math.sin(angle))
    return {
        "robot_pose": np.array([1.0, 2.0, heading_rad]),
        "mover_positions": np.array([[9.0, 9.0], target]),
        "target_index": 1,
    }


@pytest.mark.parametrize("name", ["sonar", "laser"])
def test_the_target_is_in_the_one_region_that_spans_its_bearing(tool, name):
    grid = Grid.make(name)
    for bearing_deg in (0.3, -44.2, 80.2):
        info = _info(math.radians(bearing_deg))
        regions = [j for j, beams in enumerate(grid.beam_slices) if tool.target_in_region(info, beams)]
        assert len(regions) == 1, bearing_deg
        nearest = int(np.argmin(np.abs(grid.bearings_rad - math.radians(bearing_deg))))
        assert regions == [nearest]
    assert not any(tool.target_in_region(_info(math.pi), beams) for beams in grid.beam_slices)  # behind


@pytest.mark.parametrize("kwargs, message", [({"min_time_s": -1.0}, "min_time_s"), ({"max_steps": 0}, "max_steps")])
def test_bad_arguments_are_named(tool, kwargs, message):
    with pytest.raises(ValueError, match=message):
        tool.render_frame(**kwargs)


def test_the_default_frame_outlines_a_top_down_focus(tool, tmp_path):
    frame, time_s = tool.render_frame()
    assert frame.dtype == np.uint8 and frame.ndim == 3 and frame.shape[2] == 3
    assert time_s >= 2.0
    outline = np.all(frame == FOCUS_COLOURS["top-down"], axis=2)
    assert outline.sum() > 50
    path = tmp_path / "figures" / "frame.png"
    tool.save_png(frame, path)
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
