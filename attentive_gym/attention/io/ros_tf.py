"""A bag's TF transforms: the laser's mount, and odometry where no Odometry topic is logged.

- ``FrameTransform``: one transform of a ``tf2_msgs/TFMessage`` (or ROS 1 ``tf/tfMessage``).
- ``mount_from_tf``: the laser's ``LaserMount`` from the transforms that lead from its
  frame to the robot's base frame.
- ``odometry_from_tf``: the robot's velocity on the scans' stamps from the transforms of
  its base frame in an odometry frame (``odom -> base_link``).

Frames are compared without a leading ``/`` (ROS 1 names such as ``/base_link``). A
transform's rotation takes vectors of its child frame into its parent frame; its
translation is the child's origin in the parent frame (m).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np

from attentive_gym.attention.io.ros_readings import LaserMount

__all__ = [
    "TF_TYPES",
    "BASE_FRAMES",
    "FrameTransform",
    "transforms_of",
    "MountFromTf",
    "mount_from_tf",
    "OdometryPoses",
    "odometry_from_tf",
]

#: TF message types as rosbags names them: ROS 2 and ROS 1 tf2, and ROS 1's older tf.
TF_TYPES = ("tf2_msgs/msg/TFMessage", "tf/msg/tfMessage")
#: The robot's base frames (REP 105), in order of preference.
BASE_FRAMES = ("base_link", "base_footprint")
#: The longest chain of frames followed from the laser up to a base frame.
_MAX_CHAIN = 16
#: A laser tilted more than this (deg) from level (or from upside down) is reported.
_TILT_NOTE_DEG = 10.0


def frame_name(name: str) -> str:
    """A frame id without its leading ``/`` (``/base_link`` → ``base_link``)."""
    return name.lstrip("/")


@dataclass(frozen=True, eq=False)
class FrameTransform:
    """One transform: the child frame's pose in the parent frame.

    Attributes:
        parent, child: frame names (no leading ``/``).
        stamp_ns: its stamp (ns), the bag's receive time where the stamp is zero.
        translation: ``(3,)`` the child's origin in the parent frame (m).
        rotation: ``(3, 3)`` rotation matrix, child vectors → parent vectors.
    """

    parent: str
    child: str
    stamp_ns: int
    translation: np.ndarray
    rotation: np.ndarray


def transforms_of(message, receive_ns: int) -> list[FrameTransform]:
    """The transforms of a deserialized TF message."""
    found = []
    for entry in message.transforms:
        stamp = int(entry.header.stamp.sec) * 1_000_000_000 + int(entry.header.stamp.nanosec)
        t, q = entry.transform.translation, entry.transform.rotation
        found.append(
            FrameTransform(
                parent=frame_name(entry.header.frame_id),
                child=frame_name(entry.child_frame_id),
                stamp_ns=stamp or int(receive_ns),
                translation=np.array([t.x, t.y, t.z], dtype=np.float64),
                rotation=_rotation_matrix(q.x, q.y, q.z, q.w),
            )
        )
    return found


def _rotation_matrix(x: float, y: float, z: float, w: float) -> np.ndarray:
    """``(3, 3)`` rotation of a quaternion (normalised here; identity for a zero one)."""
    norm = float(np.sqrt(x * x + y * y + z * z + w * w))
    if norm == 0.0 or not np.isfinite(norm):
        return np.eye(3)
    x, y, z, w = x / norm, y / norm, z / norm, w / norm
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


@dataclass(frozen=True)
class MountFromTf:
    """The laser's mount read from TF.

    Attributes:
        mount: position, yaw and whether it is upside down (its z axis points down).
        base: the base frame reached.
        chain: the frames from the laser's up to ``base``.
        tilt_deg: how far the laser's scan plane leans from level (deg; 0 upright or
            exactly upside down); the scan is used as if level.
    """

    mount: LaserMount
    base: str
    chain: tuple[str, ...]
    tilt_deg: float

    def describe(self) -> str:
        """``from TF laser -> base_link``, with a note on a tilted laser."""
        if len(self.chain) == 1:
            text = f"from TF: the scans' frame is the base frame {self.base}"
        else:
            text = f"from TF {' -> '.join(self.chain)}"
        if self.tilt_deg > _TILT_NOTE_DEG:
            text += f"; the scan plane leans {self.tilt_deg:.0f}° from level and is used as if level"
        return text


def mount_from_tf(static: Iterable[FrameTransform], laser_frame: str, base_frames: Sequence[str]) -> MountFromTf | None:
    """The laser's mount from the transforms that lead from ``laser_frame`` up to the first
    of ``base_frames`` reached (each child's first transform); None when none leads there.

    Args:
        static: transforms, ``/tf_static``'s first; the first one of each child is used.
        laser_frame: the scans' ``header.frame_id``.
        base_frames: the robot's base frame names.
    """
    parents: dict[str, FrameTransform] = {}
    for transform in static:
        parents.setdefault(transform.child, transform)
    frame, chain = frame_name(laser_frame), [frame_name(laser_frame)]
    rotation, translation = np.eye(3), np.zeros(3)
    while frame not in base_frames:
        if frame not in parents or len(chain) > _MAX_CHAIN:
            return None
        step = parents[frame]
        rotation, translation = step.rotation @ rotation, step.rotation @ translation + step.translation
        frame = step.parent
        if frame in chain:  # a loop of transforms
            return None
        chain.append(frame)
    return MountFromTf(_mount(rotation, translation), frame, tuple(chain), _tilt_deg(rotation))


def _mount(rotation: np.ndarray, translation: np.ndarray) -> LaserMount:
    """The mount of a laser whose frame has ``rotation`` and origin ``translation`` in the base frame."""
    yaw = float(np.degrees(np.arctan2(rotation[1, 0], rotation[0, 0])))
    return LaserMount(
        x_m=float(translation[0]),
        y_m=float(translation[1]),
        yaw_deg=round(yaw, 6) + 0.0,  # a clean 180 rather than 179.99999999999997; no -0
        upside_down=bool(rotation[2, 2] < 0.0),
    )


def _tilt_deg(rotation: np.ndarray) -> float:
    """The angle (deg) between the laser's z axis and the base's vertical, up or down."""
    return float(np.degrees(np.arccos(min(1.0, abs(float(rotation[2, 2]))))))


@dataclass(frozen=True, eq=False)
class OdometryPoses:
    """The base frame's poses in an odometry frame, from TF.

    Attributes:
        parent, child: the odometry frame and the base frame.
        stamps: ``(P,)`` int64 stamps (ns), non-decreasing.
        poses: ``(P, 3)`` x, y (m) and heading (rad, unwrapped).
    """

    parent: str
    child: str
    stamps: np.ndarray
    poses: np.ndarray

    def velocities_at(self, stamps_ns: np.ndarray) -> np.ndarray:
        """``(T, 2)`` velocity (v m/s forward, w rad/s) over the interval before each of
        ``stamps_ns`` (ns, increasing, within the poses' span), from the poses linearly
        interpolated at those stamps; the first reads the second's (0 for one stamp)."""
        seconds = (self.stamps - self.stamps[0]) * 1e-9
        at = (np.asarray(stamps_ns, dtype=np.int64) - self.stamps[0]) * 1e-9
        x, y, heading = (np.interp(at, seconds, self.poses[:, k]) for k in range(3))
        dt = np.diff(at)
        middle = heading[:-1] + 0.5 * np.diff(heading)
        forward = np.cos(middle) * np.diff(x) + np.sin(middle) * np.diff(y)
        velocity = np.stack([forward / dt, np.diff(heading) / dt], axis=1)
        first = velocity[:1] if len(velocity) else np.zeros((1, 2))
        return np.concatenate([first, velocity])


def odometry_from_tf(dynamic: Iterable[FrameTransform], base_frames: Sequence[str]) -> OdometryPoses | None:
    """The poses of the base frame in an odometry frame (a parent whose last name part
    holds ``odom``, REP 105), for the first of ``base_frames`` that has at least two of
    them; None when none has.

    Args:
        dynamic: the ``/tf`` transforms, in bag order.
        base_frames: the robot's base frame names, in order of preference.
    """
    by_child: dict[str, list[FrameTransform]] = {}
    for transform in dynamic:
        if "odom" in transform.parent.rsplit("/", 1)[-1] and transform.child in base_frames:
            by_child.setdefault(transform.child, []).append(transform)
    for base in base_frames:
        found = sorted(by_child.get(base, []), key=lambda tr: tr.stamp_ns)
        if len(found) >= 2:
            headings = np.unwrap([np.arctan2(tr.rotation[1, 0], tr.rotation[0, 0]) for tr in found])
            positions = np.array([tr.translation[:2] for tr in found])
            poses = np.column_stack([positions, headings])
            stamps = np.array([tr.stamp_ns for tr in found], dtype=np.int64)
            return OdometryPoses(found[0].parent, base, stamps, poses)
    return None
