"""The plan view of a trace: one laser scan seen from above in the odometry frame, with
the focus drawn in it.

- ``plan_step``: the step a plan view shows by default, the most salient step with a focus.
- ``draw_plan``: draws the plan view of one step on a matplotlib axes.

The odometry frame is the one the model dead-reckons the robot's pose in (``Trace.pose``:
x, y in m, heading counter-clockwise from +x), fixed to the world at the replay's start: a
standing robot stays at the origin heading along +x, so its left is up, as in the trace's
panels. A trace without poses is drawn in the robot's frame. Echoes are placed from the
laser's mount (``laser_mount_x_m``, ``laser_mount_y_m`` of the trace's configuration) along
the model's beam bearings; no-echo beams are left out.

matplotlib is imported inside the functions only.
"""

from __future__ import annotations

import numpy as np

from attentive_gym.attention.io.trace import Trace
from attentive_gym.attention.regions import laser_bearings_rad
from attentive_gym.viz._rows import ORIGIN_STYLE, bearing_span, row_bearings_deg, row_name

__all__ = ["plan_step", "draw_plan"]

#: Scans spread evenly over the run whose echoes draw the surroundings (light grey).
_CONTEXT_SCANS = 60
#: Margin around the echoes and the path (m).
_MARGIN_M = 0.5
#: The robot's outline: a triangle pointing along its heading (m, robot frame).
_ROBOT_OUTLINE_M = np.array([[0.25, 0.0], [-0.15, 0.12], [-0.15, -0.12]])


def plan_step(trace: Trace) -> int:
    """The step of the run's highest saliency among the steps with a focus (the last step
    where no step has one)."""
    focused = np.flatnonzero(trace.focus >= 0)
    if focused.size == 0:
        return trace.n_steps - 1
    return int(focused[np.argmax(trace.L[focused].max(axis=1))])


def draw_plan(ax, trace: Trace, step: int) -> None:
    """Draw step ``step`` of ``trace`` seen from above on ``ax`` (m, equal axes): the scan
    in black, the focused region as a wedge out to the laser's range in its origin's
    colour, the laser's range over the front 180° dashed, the robot, its path, and the
    echoes of up to 60 scans over the run in grey.

    Raises:
        ValueError: for a step outside ``[0, T)``.
    """
    import matplotlib.patches as patches

    if not 0 <= step < trace.n_steps:
        raise ValueError(f"the plan view's step {step} is outside the trace's {trace.n_steps} steps")
    poses = np.zeros((trace.n_steps, 3)) if trace.pose is None else trace.pose
    pose = poses[step]
    context = np.unique(np.linspace(0, trace.n_steps - 1, min(trace.n_steps, _CONTEXT_SCANS)).round().astype(int))
    surroundings = np.concatenate([_echo_points(trace, k, poses[k]) for k in context])
    scan = _echo_points(trace, step, pose)
    origin = _to_frame(pose, _laser_origin(trace)[None, :])[0]
    range_m = float(trace.config["laser_max_range_m"])
    heading_deg = float(np.degrees(pose[2]))
    ax.scatter(*surroundings.T, s=1, color="0.75", label=f"echoes of {len(context)} scans over the run")
    ax.plot(poses[:, 0], poses[:, 1], color="0.3", linewidth=1.0, label="the robot's path")
    focus = int(trace.focus[step])
    if focus >= 0:
        low, high = row_bearings_deg(trace.n_regions)[focus]
        colour, _, origin_name = ORIGIN_STYLE[int(trace.origin[step])]
        ax.add_patch(
            patches.Wedge(
                origin,
                range_m,
                heading_deg + low,
                heading_deg + high,
                facecolor=colour,
                alpha=0.3,
                label=f"focus: {row_name(focus, trace.n_regions)} {bearing_span(low, high)} ({origin_name})",
            )
        )
    ax.add_patch(
        patches.Arc(
            origin,
            2 * range_m,
            2 * range_m,
            theta1=heading_deg - 90.0,
            theta2=heading_deg + 90.0,
            color="0.5",
            linestyle="--",
            linewidth=0.8,
            label=f"laser range {range_m:g} m",
        )
    )
    ax.scatter(*scan.T, s=4, color="black", label="the scan")
    ax.add_patch(patches.Polygon(_to_frame(pose, _ROBOT_OUTLINE_M), color="black", label="the robot"))
    _set_limits(ax, np.concatenate([surroundings, scan, poses[:, :2]]))
    ax.set_aspect("equal", adjustable="box")
    ax.set_anchor("W")
    frame = "robot frame: no poses in the trace" if trace.pose is None else "odometry frame"
    ax.set_title(f"plan view at t = {trace.t[step]:.1f} s ({frame}; m)", fontsize="small", loc="left")
    ax.tick_params(labelsize="x-small")
    ax.legend(loc="center left", bbox_to_anchor=(1.02, 0.5), fontsize="x-small", frameon=False)


def _laser_origin(trace: Trace) -> np.ndarray:
    """``(2,)`` the laser's position on the robot (m, robot frame)."""
    return np.array([trace.config["laser_mount_x_m"], trace.config["laser_mount_y_m"]], dtype=float)


def _echo_points(trace: Trace, step: int, pose: np.ndarray) -> np.ndarray:
    """``(E, 2)`` the echoes of step ``step``'s laser scan in the odometry frame (m)."""
    ranges = trace.O2[step]
    echo = ranges < float(trace.config["laser_max_range_m"]) - float(trace.config["no_echo_epsilon_m"])
    bearings = laser_bearings_rad(ranges.shape[0])[echo]
    robot_frame = _laser_origin(trace) + ranges[echo, None] * np.stack([np.cos(bearings), np.sin(bearings)], axis=1)
    return _to_frame(pose, robot_frame)


def _to_frame(pose: np.ndarray, points_m: np.ndarray) -> np.ndarray:
    """``(P, 2)`` robot-frame points (m) in the frame of ``pose`` (x m, y m, heading rad)."""
    c, s = np.cos(pose[2]), np.sin(pose[2])
    return points_m @ np.array([[c, s], [-s, c]]) + pose[:2]


def _set_limits(ax, points_m: np.ndarray) -> None:
    """Axes limits around ``points_m`` ``(P, 2)`` with a margin."""
    low, high = points_m.min(axis=0) - _MARGIN_M, points_m.max(axis=0) + _MARGIN_M
    ax.set_xlim(low[0], high[0])
    ax.set_ylim(low[1], high[1])
