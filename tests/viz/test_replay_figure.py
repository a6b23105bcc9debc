"""The replay figure (``plot_trace``): one orientation in every panel (left, +90°, on top),
regions named with their bearings, range colours from the sensor's range, and the plan
view of a scan in the odometry frame with the focus. Read through matplotlib's artists,
not pixels."""

from __future__ import annotations

import matplotlib.patches as patches
import numpy as np
import pytest

from attentive_gym.attention import AttentionConfig
from attentive_gym.attention.io.trace import Trace
from attentive_gym.viz.trace_figure import PANELS, panel_axes, plot_trace

N_STEPS = 12
S1_SPAN, S8_SPAN = "+70..+90°", "-90..-70°"
REGION_SPANS = [S1_SPAN, "+40..+70°", "+20..+40°", "0..+20°", "-20..0°", "-40..-20°", "-70..-40°", S8_SPAN]


def _trace(focus=0, pose=None, laser_max_range_m=5.6, laser=None) -> Trace:
    """A trace of 12 steps at 10 Hz: focus on region ``focus`` (bottom-up) from step 2, a
    course fired there; the laser reads no echo but beam 179 (+89.5°, the far left) at 1 m."""
    config = AttentionConfig(laser_max_range_m=laser_max_range_m)
    if laser is None:
        laser = np.full((N_STEPS, 180), laser_max_range_m)
        laser[:, 179] = 1.0
    regions = np.tile(np.linspace(0.1, 0.8, 8), (N_STEPS, 1))
    focus_steps = np.where(np.arange(N_STEPS) >= 2, focus, -1)
    return Trace(
        t=0.1 * np.arange(N_STEPS),
        O1=np.full((N_STEPS, 8), 5.0),
        O2=laser,
        F=np.zeros((N_STEPS, 6, 8)),
        C=regions,
        C_BU=regions,
        C_TD=np.zeros((N_STEPS, 8)),
        M=np.ones((N_STEPS, 8)),
        L=regions * (np.arange(N_STEPS)[:, None] + 1.0),
        focus=focus_steps.astype(np.int64),
        fired=np.arange(N_STEPS) == 2,
        origin=np.where(focus_steps >= 0, 0, -1).astype(np.int8),
        config=config.to_dict(),
        pose=pose,
    )


def _bearing_labels(ax) -> dict[str, float]:
    """The right axis's labels (bearings) by text, at their y (deg)."""
    (secondary,) = ax.child_axes
    return {label.get_text(): label.get_position()[1] for label in secondary.get_yticklabels()}


def _names(ax) -> dict[str, float]:
    return {label.get_text(): label.get_position()[1] for label in ax.get_yticklabels()}


def test_every_panel_puts_the_robots_left_on_top():
    fig = plot_trace(_trace(), panels=PANELS, plan=False)
    for ax in panel_axes(fig):
        assert ax.get_ylim() == (-90.0, 90.0), ax.get_label()  # +90° (left) at the top
        if ax.get_label() == "O2":
            names = _names(ax)
            assert names["179"] > 0.0 > names["0"]  # beam 179 is the leftmost
            assert _bearing_labels(ax)["+90°"] == 90.0
            continue
        names = _names(ax)
        assert list(names) == [f"s{n}" for n in range(1, 9)]
        assert names["s1"] == 80.0 and names["s8"] == -80.0, ax.get_label()


def test_regions_carry_their_bearings_on_the_right():
    fig = plot_trace(_trace(), panels=("O1", "F1", "WTA"), plan=False)
    for ax in panel_axes(fig):
        labels = _bearing_labels(ax)
        assert list(labels) == REGION_SPANS
        assert labels[S1_SPAN] == _names(ax)["s1"] and labels[S8_SPAN] == _names(ax)["s8"]


def test_the_figure_says_what_s1_and_s8_mean():
    fig = plot_trace(_trace(), plan=False)
    note = fig.get_suptitle()
    assert "+90° is the robot's left (s1, top of every panel)" in note and "-90° its right (s8, bottom)" in note


def test_the_laser_panel_draws_the_leftmost_beam_at_the_top():
    fig = plot_trace(_trace(), panels=("O2",), plan=False)
    (mesh,) = panel_axes(fig)[0].collections
    rows = mesh.get_coordinates()[:, 0, 1]  # the cells' y edges (deg)
    echo_row = int(np.flatnonzero(~np.ma.getmaskarray(mesh.get_array())[:, 0])[0])
    assert (rows[echo_row], rows[echo_row + 1]) == (89.0, 90.0)
    assert mesh.get_array()[echo_row, 0] == 1.0


def test_range_colours_run_to_the_sensors_range_and_no_echo_is_masked():
    fig = plot_trace(_trace(laser_max_range_m=5.6), panels=("O1", "O2", "F1"), plan=False)
    sonar, laser, motion = panel_axes(fig)
    (laser_mesh,) = laser.collections
    assert (laser_mesh.norm.vmin, laser_mesh.norm.vmax) == (0.0, 5.6)
    assert np.ma.getmaskarray(laser_mesh.get_array()).sum() == 179 * N_STEPS  # every beam but the echo
    assert sonar.collections[0].norm.vmax == 5.0
    assert laser.get_title(loc="left") == "O2: laser (m), 0 to 5.6 m; grey: no echo"
    assert motion.get_title(loc="left") == "F1 motion"


def _plan(fig):
    (plan,) = [ax for ax in fig.axes if ax.get_label() == "plan"]
    return plan


def test_the_plan_view_draws_the_scan_and_the_focus_in_the_odometry_frame():
    pose = np.tile([1.0, 2.0, np.pi / 2], (N_STEPS, 1))  # at (1, 2) m, heading along +y
    fig = plot_trace(_trace(focus=0, pose=pose), plan_at=5)
    plan = _plan(fig)
    (wedge,) = [patch for patch in plan.patches if isinstance(patch, patches.Wedge)]
    mount_x = AttentionConfig().laser_mount_x_m
    assert wedge.center == pytest.approx((1.0, 2.0 + mount_x))  # the laser, ahead of the robot
    assert (wedge.theta1, wedge.theta2, wedge.r) == pytest.approx((160.0, 180.0, 5.6))  # s1 is the robot's left
    scan = [c for c in plan.collections if c.get_label() == "the scan"][0]
    echo_bearing = np.radians(89.5)  # beam 179 at 1 m, turned by the heading
    expected = (1.0 - np.sin(echo_bearing), 2.0 + mount_x + np.cos(echo_bearing))
    np.testing.assert_allclose(scan.get_offsets(), [expected], atol=1e-12)
    legend = [text.get_text() for text in plan.get_legend().get_texts()]
    assert "focus: s1 +70..+90° (bottom-up)" in legend and "laser range 5.6 m" in legend
    assert "odometry frame" in plan.get_title(loc="left") and "t = 0.5 s" in plan.get_title(loc="left")
    for ax in panel_axes(fig):  # the plan's step is marked on every panel
        assert any(np.allclose(line.get_xdata(), 0.5) for line in ax.get_lines())


def test_the_plan_view_shows_the_most_salient_focused_step_by_default():
    fig = plot_trace(_trace(pose=np.zeros((N_STEPS, 3))))
    assert "t = 1.1 s" in _plan(fig).get_title(loc="left")  # L grows with the step


def test_the_plan_view_comes_with_poses_and_can_be_asked_for_without():
    assert not any(ax.get_label() == "plan" for ax in plot_trace(_trace()).axes)
    plan = _plan(plot_trace(_trace(), plan=True))
    assert "robot frame: no poses in the trace" in plan.get_title(loc="left")


def test_the_winners_sit_at_their_regions_bearings():
    fig = plot_trace(_trace(focus=7), panels=("WTA",), plan=False)
    offsets = np.concatenate([c.get_offsets() for c in panel_axes(fig)[0].collections])
    np.testing.assert_array_equal(np.unique(offsets[:, 1]), [-80.0])  # s8: the robot's right, at the bottom


def test_the_replay_figure_renders(tmp_path):
    path = tmp_path / "trace.png"
    plot_trace(_trace(pose=np.zeros((N_STEPS, 3))), path=path)
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
