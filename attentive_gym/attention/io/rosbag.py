"""Read a ROS 1 or ROS 2 bag as a ``SensorLog`` (``attentive-gym attend`` on a robot's own bag).

- ``is_bag_path``: whether a path names a bag (``.bag``, ``.db3``, ``.mcap`` or a folder).
- ``BagTopics`` / ``parse_bag_topics``: which topics hold what, from the command line's flags.
- ``ScanOptions`` / ``parse_scan_options``: the laser's mount, minimum range and masks,
  from the command line's flags.
- ``open_bag``: the bag's laser, sonars and odometry on one time base, with the mount
  and laser range used, the model's configuration for them, the scans at their own
  resolution (``RawScans``) and one line per assumption, drop or finding for the user
  (``BagReplay``); ``read_bag``: its readings alone.

Bags: ROS 1 ``.bag`` files; ROS 2 bag folders (``metadata.yaml`` beside ``.db3`` or
``.mcap`` storage files) or one storage file itself (its folder is opened when it holds
a ``metadata.yaml``). Read with ``rosbags`` (pure Python, no ROS install; the ``ros``
extra), imported only when a bag is read.

Messages (ROS 2 names; ROS 1's ``sensor_msgs/LaserScan`` etc. are the same):

- ``sensor_msgs/msg/LaserScan``: one topic, the time base: every scan is one step. Its
  beams are turned into robot-frame bearings with the laser's mount (yaw, upside down)
  and resampled onto the model's 180 beams over the front 180°
  (``ros_readings.ScanResampler``: nearest echo of the overlapping scan beams).
  Several topics (``BagTopics.more_lasers``, ``all_lasers``) are merged: the first is the
  time base and the model's origin; each further laser, placed with its own mount (its
  ``ScanOptions.more_mounts`` entry, else TF), gives its latest scan at or before each of
  the first's, its echoes placed in the robot frame and seen from the first laser's
  position (``_seen_from``); each model beam reads the nearest echo of all of them.
- ``tf2_msgs/msg/TFMessage`` (ROS 1 ``tf/tfMessage`` too), optional: the transforms from
  the scans' ``header.frame_id`` up to the base frame (the Odometry's ``child_frame_id``,
  else ``base_link`` or ``base_footprint``) give the laser's mount where ``ScanOptions``
  does not; ``odom -> base`` transforms give the odometry where no Odometry topic is
  logged (``ros_tf``). Without either, the configuration's mount applies.
- ``sensor_msgs/msg/Range``: sonars, one topic per transducer. By default 16 topics are
  the P2AT ring's sonars 0..15 and 8 topics its front sonars 0..7, in natural name order
  (digits compare as numbers: ``sonar_2`` before ``sonar_10``). With bearings (deg,
  one per topic) each topic stands in for the front sonar nearest in bearing (the nearest
  echo when several do; rear-facing ones are dropped) and the front sonars no topic
  stands in for read the laser. Without Range topics the 8 front sonars read the laser:
  the nearest echo in each sonar's cone (``AttentionConfig.sonar_cone_half_width_deg``).
- ``nav_msgs/msg/Odometry``: optional, one topic; ego-motion ``v = twist.twist.linear.x``
  (m/s), ``w = twist.twist.angular.z`` (rad/s).

Time: each message's header stamp, or the bag's receive time where the stamp is zero.
Sonars and odometry are read on the laser's stamps, each as its latest message at or
before the scan (zero-order hold); the scans before every sonar and odometry topic has
its first message are dropped. ``t`` is in seconds from the first kept scan. Stamps
must never decrease within a topic, and scans' must increase.

Masks: scan beams nearer than ``ScanOptions.min_range_m``, at robot-frame bearings inside
``ScanOptions.mask_deg``, and (unless ``keep_self_returns``) beams that hold a constant near
echo through the whole bag (``ros_readings.constant_near_beams``: the robot's own posts)
read no echo.

No echo: NaN, ±inf, a range below the message's ``range_min``/``min_range`` or at or
above its ``range_max``/``max_range`` (or beyond the model's maximum range), and a model
beam outside the scan read the model's maximum range (``AttentionConfig.laser_max_range_m``,
``sonar_max_range_m``), as the env's sensors do. A message whose limits are unset
(minimum >= maximum) is checked against the model's limits instead. With
``open_bag(..., sensor_range=True)`` the laser's no echo is the sensor's own range instead:
the scans' ``range_max`` where it is shorter than the configuration's (a 5.6 m Hokuyo reads
5.6 m, not 20 m), and ``BagReplay.config`` carries it to the model.
"""

from __future__ import annotations

import re
import struct
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from attentive_gym.attention.config import AttentionConfig
from attentive_gym.attention.io.ros_readings import (
    SELF_RETURN_NEAR_M,
    LaserMount,
    ScanResampler,
    bearings_in_intervals,
    constant_near_beams,
    front_sonar_slot,
    front_sonars_from_laser,
    latest_at_or_before,
    ranges_or_no_echo,
    share_of_scans_changing_together,
)
from attentive_gym.attention.io.ros_tf import (
    BASE_FRAMES,
    TF_TYPES,
    MountFromTf,
    OdometryPoses,
    mount_from_tf,
    odometry_from_tf,
    transforms_of,
)
from attentive_gym.attention.io.sensor_log import LogFormatError, SensorLog
from attentive_gym.attention.regions import FRONT_SONARS, LASER_BEAMS, LASER_FOV_DEG, SONAR_RING

__all__ = [
    "BAG_SUFFIXES",
    "LASER_TYPE",
    "RANGE_TYPE",
    "ODOMETRY_TYPE",
    "BagTopics",
    "ScanOptions",
    "BagReplay",
    "RawScans",
    "is_bag_path",
    "parse_bag_topics",
    "parse_scan_options",
    "open_bag",
    "read_bag",
]

#: Suffixes of bag files: ROS 1 bags, ROS 2 sqlite3 and MCAP storage files.
BAG_SUFFIXES = (".bag", ".db3", ".mcap")
#: The message types read, as rosbags names them for ROS 1 and ROS 2 alike.
LASER_TYPE = "sensor_msgs/msg/LaserScan"
RANGE_TYPE = "sensor_msgs/msg/Range"
ODOMETRY_TYPE = "nav_msgs/msg/Odometry"


@dataclass(frozen=True)
class BagTopics:
    """Which topics of a bag hold what; None: found by message type.

    Attributes:
        laser: the LaserScan topic (the first of several: the time base).
        more_lasers: further LaserScan topics, merged into the first's scans (``open_bag``).
        all_lasers: every LaserScan topic of the bag, in natural name order (the first the
            time base); not with ``laser`` or ``more_lasers``.
        sonars: the Range topics, in ring order (sonar 0 first) unless bearings are given.
        odometry: the Odometry topic.
        sonar_bearings_deg: one bearing (deg, counter-clockwise from the heading) per
            Range topic, in the order of ``sonars`` (or of the natural name order of the
            Range topics found), for sonars that are not the P2AT ring.

    Raises:
        ValueError: for an empty or repeated topic name, a non-finite bearing, not as
            many bearings as sonar topics, further lasers without a first one, or
            ``all_lasers`` with named lasers.
    """

    laser: str | None = None
    sonars: tuple[str, ...] | None = None
    odometry: str | None = None
    sonar_bearings_deg: tuple[float, ...] | None = None
    more_lasers: tuple[str, ...] = ()
    all_lasers: bool = False

    def __post_init__(self) -> None:
        for name, topic in (
            ("laser", self.laser),
            ("odometry", self.odometry),
            *(("laser", t) for t in self.more_lasers),
        ):
            if topic is not None and not topic.strip():
                raise ValueError(f"the {name} topic name is empty")
        if self.more_lasers and self.laser is None:
            raise ValueError("further laser topics need a first one (the time base)")
        lasers = [self.laser, *self.more_lasers]
        if len(set(lasers)) < len(lasers):
            raise ValueError(f"laser topics {sorted({t for t in lasers if lasers.count(t) > 1})} named more than once")
        if self.all_lasers and self.laser is not None:
            raise ValueError("--all-lasers takes every LaserScan topic; name them with --laser-topic A,B instead")
        if self.sonars is not None:
            if not self.sonars or not all(name.strip() for name in self.sonars):
                raise ValueError(f"sonar topics must be non-empty names, got {list(self.sonars)}")
            repeated = sorted({name for name in self.sonars if self.sonars.count(name) > 1})
            if repeated:
                raise ValueError(f"sonar topics {repeated} named more than once")
        if self.sonar_bearings_deg is not None:
            if not all(np.isfinite(b) for b in self.sonar_bearings_deg):
                raise ValueError(f"sonar bearings must be finite numbers (deg), got {list(self.sonar_bearings_deg)}")
            if self.sonars is not None and len(self.sonar_bearings_deg) != len(self.sonars):
                raise ValueError(
                    f"{len(self.sonar_bearings_deg)} sonar bearings for {len(self.sonars)} sonar topics; "
                    "give one bearing (deg) per topic"
                )


def parse_bag_topics(
    laser: str | None = None,
    sonars: str | None = None,
    odometry: str | None = None,
    sonar_bearings: str | None = None,
    all_lasers: bool = False,
) -> BagTopics | None:
    """``BagTopics`` from the command line's strings; None when none is given.

    Args:
        laser: a LaserScan topic, or several comma-separated (``/front/scan,/rear/scan``:
            merged, the first the time base).
        odometry: a topic name.
        sonars: comma-separated topic names, e.g. ``/sonar/0,/sonar/1``.
        sonar_bearings: comma-separated bearings (deg), e.g. ``90,50,30,10,-10,-30,-50,-90``.
        all_lasers: the ``--all-lasers`` switch.

    Raises:
        ValueError: for a bearing that is not a number, or as ``BagTopics``.
    """
    if laser is None and sonars is None and odometry is None and sonar_bearings is None and not all_lasers:
        return None
    bearings = None
    if sonar_bearings is not None:
        try:
            bearings = tuple(float(b) for b in sonar_bearings.split(","))
        except ValueError:
            raise ValueError(
                f"sonar bearings must be comma-separated numbers (deg), e.g. 90,50,30; got {sonar_bearings!r}"
            ) from None
    sonar_topics = None if sonars is None else tuple(name.strip() for name in sonars.split(","))
    first, *more = [None] if laser is None else [name.strip() for name in laser.split(",")]
    return BagTopics(first, sonar_topics, odometry, bearings, tuple(more), all_lasers)


#: The farthest a laser may sit from the robot's centre (m), as ``AttentionConfig`` allows.
_MAX_MOUNT_M = 5.0
_MOUNT_USAGE = (
    "--laser-mount must be X,Y,YAW_DEG: the laser's position (m, robot frame) and yaw (deg), e.g. 0.2,0,180, "
    "with ,upside-down after them for a laser mounted upside down; once per laser topic, in their order"
)
_MASK_USAGE = (
    "--mask-angles must be A:B[,C:D...] in degrees, robot frame (counter-clockwise from the heading), "
    "-180 <= A < B <= 180, e.g. 120:180,-180:-120"
)


@dataclass(frozen=True)
class ScanOptions:
    """How a bag's scans are placed on the robot and what of them is hidden.

    Attributes:
        mount_xy_yaw: the laser's position (m, robot frame) and yaw (deg), or None: from
            the bag's TF, else the configuration's.
        upside_down: whether the laser is mounted upside down, or None: from TF, else the
            configuration's.
        min_range_m: echoes nearer than this read no echo (m, >= 0).
        mask_deg: closed robot-frame bearing intervals ``(a, b)`` (deg, -180 <= a < b <= 180)
            whose beams read no echo.
        keep_self_returns: keep the beams holding a constant near echo through the bag
            (default: they are masked).
        more_mounts: the mounts of the second and further laser topics, in their order
            (empty: each from the bag's TF); the first laser's is ``mount_xy_yaw`` and
            ``upside_down``.

    Raises:
        ValueError: naming the flag, for a mount off the robot or not finite, a negative
            or non-finite minimum range, or a malformed interval.
    """

    mount_xy_yaw: tuple[float, float, float] | None = None
    upside_down: bool | None = None
    min_range_m: float = 0.0
    mask_deg: tuple[tuple[float, float], ...] = ()
    keep_self_returns: bool = False
    more_mounts: tuple[LaserMount, ...] = ()

    def __post_init__(self) -> None:
        given = [] if self.mount_xy_yaw is None else [self.mount_xy_yaw]
        for x, y, yaw in [*given, *((m.x_m, m.y_m, m.yaw_deg) for m in self.more_mounts)]:
            _check_mount(x, y, yaw)
        if self.more_mounts and self.mount_xy_yaw is None:
            raise ValueError("mounts of further lasers need the first laser's (--laser-mount once per laser)")
        if not (np.isfinite(self.min_range_m) and self.min_range_m >= 0.0):
            raise ValueError(f"--min-range must be a finite distance >= 0 (m), got {self.min_range_m:g}")
        for low, high in self.mask_deg:
            if not (-180.0 <= low < high <= 180.0):
                raise ValueError(f"{_MASK_USAGE}; got {low:g}:{high:g}")

    def mount(self, tf: MountFromTf | None, config: AttentionConfig) -> tuple[LaserMount, str]:
        """The mount used and where it came from, in words: these options, else ``tf``,
        else ``config``'s."""
        if tf is not None:
            fallback, source = tf.mount, tf.describe()
        else:
            fallback = LaserMount(
                config.laser_mount_x_m, config.laser_mount_y_m, config.laser_mount_yaw_deg, config.laser_upside_down
            )
            source = "the configuration's, as no TF in the bag leads from the laser's frame to a base frame"
        x, y, yaw = (fallback.x_m, fallback.y_m, fallback.yaw_deg) if self.mount_xy_yaw is None else self.mount_xy_yaw
        upside_down = fallback.upside_down if self.upside_down is None else self.upside_down
        given = [
            flag
            for flag, value in (("--laser-mount", self.mount_xy_yaw), ("--laser-upside-down", self.upside_down))
            if value is not None
        ]
        if given:
            rest = "position and yaw" if self.mount_xy_yaw is None else "upside down or not"
            source = f"{' and '.join(given)}" + (f"; {rest}: {source}" if len(given) < 2 else "")
        return LaserMount(float(x), float(y), float(yaw), bool(upside_down)), source

    def further_mount(self, index: int, tf: MountFromTf | None) -> tuple[LaserMount, str] | None:
        """The mount of further laser ``index`` (0: the second laser) and its source: these
        options, else ``tf``; None where neither gives one."""
        if self.more_mounts:
            return self.more_mounts[index], "--laser-mount"
        return None if tf is None else (tf.mount, tf.describe())


def _check_mount(x: float, y: float, yaw: float) -> None:
    """``ValueError`` for a laser position off the robot or a yaw beyond a turn either way."""
    if not all(np.isfinite(v) for v in (x, y, yaw)):
        raise ValueError(f"{_MOUNT_USAGE}; got non-finite numbers")
    if max(abs(x), abs(y)) > _MAX_MOUNT_M:
        raise ValueError(f"--laser-mount X and Y must lie within ±{_MAX_MOUNT_M:g} m of the robot's centre")
    if abs(yaw) > 360.0:
        raise ValueError(f"--laser-mount YAW_DEG must lie in [-360, 360] deg, got {yaw:g}")


def parse_scan_options(
    laser_mount: str | Sequence[str] | None = None,
    upside_down: bool = False,
    min_range: str | float | None = None,
    mask_angles: str | None = None,
    keep_self_returns: bool = False,
) -> ScanOptions | None:
    """``ScanOptions`` from the command line's values; None when none is given.

    Args:
        laser_mount: ``X,Y,YAW_DEG[,upside-down]`` (m, m, deg), or one such per laser
            topic, in their order (``--laser-mount`` given once per laser).
        upside_down: the ``--laser-upside-down`` switch, for the first laser (False: not given).
        min_range: a distance (m).
        mask_angles: ``A:B[,C:D...]`` (deg).
        keep_self_returns: the ``--keep-self-returns`` switch.

    Raises:
        ValueError: one line naming the flag and what it allows.
    """
    mounts = [laser_mount] if isinstance(laser_mount, str) else list(laser_mount or [])
    if not mounts and not upside_down and min_range is None and mask_angles is None and not keep_self_returns:
        return None
    first, *more = [_parse_mount(text) for text in mounts] or [None]
    return ScanOptions(
        mount_xy_yaw=None if first is None else (first.x_m, first.y_m, first.yaw_deg),
        upside_down=True if upside_down or (first is not None and first.upside_down) else None,
        more_mounts=tuple(more),
        min_range_m=0.0 if min_range is None else _parse_number(min_range, "--min-range must be a distance (m)"),
        mask_deg=() if mask_angles is None else _parse_mask(mask_angles),
        keep_self_returns=keep_self_returns,
    )


def _parse_number(text: str | float, usage: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise ValueError(f"{usage}; got {text}") from None


def _parse_mount(text: str) -> LaserMount:
    """``X,Y,YAW_DEG[,upside-down]`` as a mount (upright without the fourth part)."""
    parts = [part.strip() for part in text.split(",")]
    upside_down = len(parts) == 4 and parts[3].lower() == "upside-down"
    if len(parts) != 3 + upside_down:
        raise ValueError(f"{_MOUNT_USAGE}; got {text}")
    x, y, yaw = (_parse_number(part, _MOUNT_USAGE) for part in parts[:3])
    return LaserMount(x, y, yaw, upside_down)


def _parse_mask(text: str) -> tuple[tuple[float, float], ...]:
    intervals = []
    for item in text.split(","):
        bounds = item.split(":")
        if len(bounds) != 2:
            raise ValueError(f"{_MASK_USAGE}; got {text}")
        low, high = (_parse_number(bound, _MASK_USAGE) for bound in bounds)
        intervals.append((low, high))
    return tuple(intervals)


def is_bag_path(path: str | Path) -> bool:
    """True for a ``.bag``, ``.db3`` or ``.mcap`` path or a folder (a ROS 2 bag, or not one at all)."""
    path = Path(path)
    return path.suffix.lower() in BAG_SUFFIXES or path.is_dir()


@dataclass(frozen=True, eq=False)
class RawScans:
    """The kept scans at the laser's own resolution (not resampled), masked as the model's
    readings are: what the scans alone say, for checks independent of the model.

    Attributes:
        bearings_rad: ``(N,)`` robot-frame bearing of each scan beam (rad, counter-clockwise
            from the heading, seen from the laser's origin, wrapped to [-π, π)); with
            several lasers, the first laser's beams, then each further laser's (each seen
            from its own origin).
        ranges_m: ``(T, N)`` ranges (m) of the log's T scans; no echo, masked beams and
            self-returns read the log's no-echo range; a further laser's beams hold its
            latest scan at or before each of the first laser's.
    """

    bearings_rad: np.ndarray
    ranges_m: np.ndarray


@dataclass(frozen=True, eq=False)
class BagReplay:
    """A bag read for the model: its readings, the laser mount used, and what the user should know.

    Attributes:
        log: the checked readings.
        mount: the laser's mount the scans were placed with (its x, y belong in the
            model's ``AttentionConfig``: the tracker places echoes from there).
        notes: one line each: the topics used with their rates and drops, the mount and
            its source, masked beams, a laser range shorter than the model's, and the
            odometry's source or absence.
        config: the configuration the readings are for: the one given with this mount
            and the laser's no-echo range (``laser_max_range_m``) they were read with;
            build the model from it.
        raw: the scans at their own resolution (``RawScans``), None where a laser's scans
            change geometry (angle_min, angle_increment or beam count) along the way.
        mounts: each laser topic with its mount, the first (the time base, whose origin
            the merged beams are seen from) first.
    """

    log: SensorLog
    mount: LaserMount
    notes: tuple[str, ...]
    config: AttentionConfig
    raw: RawScans | None
    mounts: tuple[tuple[str, LaserMount], ...] = ()


def read_bag(
    path: str | Path,
    topics: BagTopics | None = None,
    config: AttentionConfig | None = None,
    options: ScanOptions | None = None,
) -> SensorLog:
    """A bag's readings as the model's; ``open_bag``'s log (arguments there)."""
    return open_bag(path, topics, config, options).log


def open_bag(
    path: str | Path,
    topics: BagTopics | None = None,
    config: AttentionConfig | None = None,
    options: ScanOptions | None = None,
    sensor_range: bool = False,
) -> BagReplay:
    """A bag's readings as the model's (message handling in the module docstring).

    Args:
        path: a ROS 1 ``.bag``, a ROS 2 bag folder, or a ``.db3`` / ``.mcap`` storage file.
        topics: which topics hold what (default: each found by its message type).
        config: the model the readings are for: its maximum ranges are "no echo", its
            sonar range and cone width turn the laser into sonars, its mount applies
            where neither ``options`` nor TF gives one (default ``AttentionConfig()``).
        options: the laser's mount, minimum range and masks (default ``ScanOptions()``).
        sensor_range: the laser's no echo is the scans' ``range_max`` where it is shorter
            than ``config.laser_max_range_m`` (the sensor as it is: a 5.6 m Hokuyo's no
            echo reads 5.6 m); False: the configuration's. ``BagReplay.config`` holds the
            range used either way.

    Returns:
        The ``BagReplay``: its log has sonar ``(T, 16)`` with 16 Range topics and no
        bearings, ``(T, 8)`` otherwise; odometry from an Odometry topic, else from TF.

    Raises:
        LogFormatError: for a bag that cannot be read, a missing topic or one of the wrong
            type (naming the topics and types found), no LaserScan message, stamps that go
            back, or a scan geometry that cannot be resampled; also when ``rosbags`` is
            not installed.
        FileNotFoundError: when ``path`` does not exist.
    """
    path = Path(path)
    topics = BagTopics() if topics is None else topics
    config = AttentionConfig() if config is None else config
    options = ScanOptions() if options is None else options
    if not path.exists():
        raise FileNotFoundError(f"{path}: no such bag file or folder")
    types, counts, (lasers, sonar_topics, odometry_topic, tf_topics), streams = _read_messages(path, topics)
    laser_topic = lasers[0]
    for topic in (*lasers, *sonar_topics, *([odometry_topic] if odometry_topic else [])):
        _check_time_order(path, topic, streams[topic].stamps, strict=topic in lasers)
    held = [topic for topic in (*lasers[1:], *sonar_topics, odometry_topic) if topic is not None]
    empty = [topic for topic in held if counts[topic] == 0]
    if empty:
        raise LogFormatError(f"{path}: {_topics_hold_no_message(empty)}; topics: {_listing(types, counts)}")
    static, dynamic = _transforms(streams, tf_topics)
    base_frames = _base_frames(streams[odometry_topic].frame if odometry_topic else "")
    transforms = [*static, *dynamic]
    tf_mount = mount_from_tf(transforms, streams[laser_topic].frame, base_frames) if transforms else None
    mount, mount_source = options.mount(tf_mount, config)
    further = _further_mounts(path, [streams[topic] for topic in lasers[1:]], transforms, base_frames, options)
    tf_odometry = None if odometry_topic else odometry_from_tf(dynamic, base_frames)
    scan_stamps = streams[laser_topic].stamps
    first = {topic: int(streams[topic].stamps[0]) for topic in held}
    if tf_odometry is not None:
        first[_tf_name(tf_odometry)] = int(tf_odometry.stamps[0])
    start = max(first.values(), default=scan_stamps[0])
    keep = scan_stamps >= start
    if tf_odometry is not None:
        keep &= scan_stamps <= tf_odometry.stamps[-1]
    if not keep.any():
        late = max(first, key=first.get)
        raise LogFormatError(
            f"{path}: no scan on {laser_topic} at or after the first message of {late}; "
            "the other lasers, sonars and odometry are read at the scans' stamps"
        )
    stamps = scan_stamps[keep]
    sensor_max_m = max(_scan_range_max(streams[topic]) for topic in lasers)
    no_echo = min(sensor_max_m, config.laser_max_range_m) if sensor_range else config.laser_max_range_m
    laser, raw, laser_notes = _laser_readings(path, streams[laser_topic], no_echo, mount, options)
    laser = laser[keep]
    raw = None if raw is None else RawScans(raw.bearings_rad, raw.ranges_m[keep])
    mount_notes = [f"laser mount{_of(lasers)}: {mount.describe()} ({mount_source})"]
    for stream, (other, source) in zip([streams[topic] for topic in lasers[1:]], further):
        beams, other_raw, notes = _laser_readings(path, stream, no_echo, other, options, origin=mount)
        laser = np.minimum(laser, latest_at_or_before(stamps, stream.stamps, beams))
        raw = _joined(raw, other_raw, stamps, stream.stamps)
        mount_notes.append(f"laser mount of {stream.topic}: {other.describe()} ({source})")
        laser_notes = [*laser_notes, *(f"{stream.topic}: {note}" for note in notes)]
    sonar = _sonar_readings(
        [streams[topic] for topic in sonar_topics], topics.sonar_bearings_deg, stamps, laser, config
    )
    odometry = None
    if odometry_topic is not None:
        stream = streams[odometry_topic]
        odometry = latest_at_or_before(stamps, stream.stamps, np.asarray(stream.fields, dtype=np.float64))
    elif tf_odometry is not None:
        odometry = tf_odometry.velocities_at(stamps)
    log = SensorLog(t=(stamps - stamps[0]) * 1e-9, sonar=sonar, laser=laser, odometry=odometry).check(str(path))
    dropped = _dropped(scan_stamps, start, first, tf_odometry)
    notes = (
        _summary(streams, lasers, sonar_topics, odometry_topic, tf_odometry, dropped, log),
        *mount_notes,
        *laser_notes,
        *_range_notes(sensor_max_m, no_echo, config),
        *_odometry_notes(log, odometry_topic, tf_odometry, no_echo),
    )
    model_config = replace(
        config,
        laser_mount_x_m=mount.x_m,
        laser_mount_y_m=mount.y_m,
        laser_mount_yaw_deg=mount.yaw_deg,
        laser_upside_down=mount.upside_down,
        laser_max_range_m=no_echo,
    )
    mounts = ((laser_topic, mount), *((topic, other) for topic, (other, _) in zip(lasers[1:], further)))
    return BagReplay(log, mount, notes, model_config, raw, mounts)


def _of(lasers: list[str]) -> str:
    """`` of /front/scan`` where several lasers are merged, else nothing."""
    return f" of {lasers[0]}" if len(lasers) > 1 else ""


def _further_mounts(
    path: Path, streams: list[_Stream], transforms: list, base_frames: tuple[str, ...], options: ScanOptions
) -> list[tuple[LaserMount, str]]:
    """The mount of each further laser and its source: ``options.more_mounts``, else TF.

    Raises:
        LogFormatError: for mounts given for some lasers but not all, or a laser that
            neither the options nor TF place on the robot.
    """
    if options.more_mounts and len(options.more_mounts) != len(streams):
        raise LogFormatError(
            f"{path}: {len(options.more_mounts) + 1} --laser-mount values for {len(streams) + 1} laser topics; "
            "give it once per laser, in the order of the topics (or once, for the first, the rest from TF)"
        )
    mounts = []
    for index, stream in enumerate(streams):
        tf = mount_from_tf(transforms, stream.frame, base_frames) if transforms else None
        found = options.further_mount(index, tf)
        if found is None:
            raise LogFormatError(
                f"{path}: no mount for the laser on {stream.topic}: no TF leads from its frame "
                f"{stream.frame or '(none)'} to a base frame; give --laser-mount once per laser, in topic order"
            )
        mounts.append(found)
    return mounts


def _joined(
    raw: RawScans | None, other: RawScans | None, stamps: np.ndarray, other_stamps: np.ndarray
) -> RawScans | None:
    """The first laser's raw scans with another's beams appended, each the other's latest
    scan at or before the first's ``stamps`` (ns); None where either is None."""
    if raw is None or other is None:
        return None
    held = latest_at_or_before(stamps, other_stamps, other.ranges_m)
    return RawScans(
        np.concatenate([raw.bearings_rad, other.bearings_rad]), np.concatenate([raw.ranges_m, held], axis=1)
    )


def _topics_hold_no_message(topics: list[str]) -> str:
    return f"topic {topics[0]} holds no message" if len(topics) == 1 else f"topics {', '.join(topics)} hold no message"


def _base_frames(odometry_child: str) -> tuple[str, ...]:
    """The robot's base frame names: the Odometry's ``child_frame_id`` first, where logged."""
    child = odometry_child.lstrip("/")
    return (child, *(frame for frame in BASE_FRAMES if frame != child)) if child else BASE_FRAMES


def _transforms(streams: dict[str, _Stream], tf_topics: list[str]) -> tuple[list, list]:
    """The ``/tf_static`` transforms (topics named ``*tf_static``) and the others, in bag order."""
    static, dynamic = [], []
    for topic in tf_topics:
        target = static if topic.rstrip("/").endswith("tf_static") else dynamic
        for transforms in streams[topic].fields:
            target.extend(transforms)
    return static, dynamic


def _tf_name(poses: OdometryPoses) -> str:
    return f"TF {poses.parent} -> {poses.child}"


def _dropped(scan_stamps: np.ndarray, start: int, first: dict[str, int], tf_odometry: OdometryPoses | None) -> str:
    """The scans dropped and why, in words ("" when none)."""
    parts = []
    early = int(np.count_nonzero(scan_stamps < start))
    if early:
        late = max(first, key=first.get)
        parts.append(f"{early} scan{'s' * (early > 1)} before the first message of {late}")
    if tf_odometry is not None:
        after = int(np.count_nonzero(scan_stamps > tf_odometry.stamps[-1]))
        if after:
            parts.append(f"{after} scan{'s' * (after > 1)} after the last {_tf_name(tf_odometry)}")
    return "; dropped " + " and ".join(parts) if parts else ""


def _rate_hz(stamps: np.ndarray) -> str:
    """A topic's mean message rate, ``10.0 Hz`` (``one message`` for a single one)."""
    if len(stamps) < 2 or stamps[-1] == stamps[0]:
        return f"{len(stamps)} message{'s' * (len(stamps) != 1)}"
    return f"{(len(stamps) - 1) / ((stamps[-1] - stamps[0]) * 1e-9):.1f} Hz"


def _summary(
    streams: dict[str, _Stream],
    lasers: list[str],
    sonar_topics: list[str],
    odometry_topic: str | None,
    tf_odometry: OdometryPoses | None,
    dropped: str,
    log: SensorLog,
) -> str:
    """One line: the topics used, their rates, the steps kept and the scans dropped."""
    if odometry_topic is not None:
        odometry = f"odometry {odometry_topic} ({_rate_hz(streams[odometry_topic].stamps)})"
    elif tf_odometry is not None:
        odometry = f"odometry from {_tf_name(tf_odometry)} ({_rate_hz(tf_odometry.stamps)})"
    else:
        odometry = "no odometry"
    if sonar_topics:
        rates = sorted({_rate_hz(streams[topic].stamps) for topic in sonar_topics})
        sonars = f"{len(sonar_topics)} sonar topics ({', '.join(rates)})"
    else:
        sonars = "front sonars read from the laser"
    duration = float(log.t[-1] - log.t[0])
    return (
        f"used: {_lasers_used(streams, lasers)}, {odometry}, {sonars}; "
        f"{len(log.t)} steps over {duration:.1f} s{dropped}"
    )


def _lasers_used(streams: dict[str, _Stream], lasers: list[str]) -> str:
    """``laser /scan (1265 scans, 10.0 Hz)``; several: ``lasers /front (...) merged with /rear (...)``."""
    used = [f"{topic} ({len(streams[topic].stamps)} scans, {_rate_hz(streams[topic].stamps)})" for topic in lasers]
    if len(used) == 1:
        return f"laser {used[0]}"
    return f"lasers {used[0]}, the time base, merged with {' and '.join(used[1:])}"


#: Without odometry, the share of scans changing together above which the robot seems to move.
_MOVING_SHARE = 0.2


def _scan_range_max(stream: _Stream) -> float:
    """The laser's range (m): the largest ``range_max`` its scans give (rounded to the
    millimetre: drivers store 5.6 m as float32), inf where none sets one (``range_max <= range_min``)."""
    limits = [range_max for _, _, range_min, range_max, _ in stream.fields if range_min < range_max]
    return round(max(limits), 3) if limits else float("inf")


def _range_notes(sensor_max_m: float, no_echo_m: float, config: AttentionConfig) -> list[str]:
    """One line where the laser's range is shorter than the configuration's: which no echo
    the readings use (nothing to say for a longer or unset one)."""
    if not sensor_max_m < config.laser_max_range_m:
        return []
    if no_echo_m == sensor_max_m:
        return [
            f"laser range: {sensor_max_m:g} m (the scans' range_max): no echo reads {sensor_max_m:g} m, "
            f"not the configuration's {config.laser_max_range_m:g} m"
        ]
    return [
        f"laser range: the scans' range_max is {sensor_max_m:g} m; no echo reads the configuration's "
        f"{config.laser_max_range_m:g} m (laser_max_range_m)"
    ]


def _odometry_notes(
    log: SensorLog, odometry_topic: str | None, tf_odometry: OdometryPoses | None, no_echo_m: float
) -> list[str]:
    """Without odometry: that a standing robot is assumed, and whether the scans say otherwise."""
    if odometry_topic is not None or tf_odometry is not None:
        return []
    notes = [
        "no odometry (no nav_msgs/Odometry topic, no TF odom -> base): a standing robot is assumed, so any "
        "motion of the robot itself reads as motion of everything it sees"
    ]
    share = share_of_scans_changing_together(log.laser, log.t, no_echo_m)
    if share >= _MOVING_SHARE:
        notes.append(
            f"the robot seems to move: most beams change together in {share:.0%} of the scans (over 1 s); "
            "its motion will read as the world's (give the bag's odometry with --odom-topic)"
        )
    return notes


@dataclass(frozen=True, eq=False)
class _Stream:
    """The messages of one topic, in bag order.

    Attributes:
        topic: its name.
        stamps: ``(M,)`` int64 header stamps (ns), the receive time where a stamp is zero
            (TF messages, which have no header: the receive time).
        fields: the ``_FIELDS`` value of each message.
        frame: the first message's frame (``_FRAME``: a scan's ``header.frame_id``, an
            Odometry's ``child_frame_id``), "" for other types or no message.
    """

    topic: str
    stamps: np.ndarray
    fields: list
    frame: str = ""


#: What is read of each message type: LaserScan ``(angle_min, angle_increment,
#: range_min, range_max, ranges)``; Range ``(range, min_range, max_range)``; Odometry
#: ``(v, w)`` (rad, m, m/s, rad/s); TF messages their transforms (``ros_tf.transforms_of``).
_FIELDS = {
    LASER_TYPE: lambda m: (
        float(m.angle_min),
        float(m.angle_increment),
        float(m.range_min),
        float(m.range_max),
        np.asarray(m.ranges, dtype=np.float64),
    ),
    RANGE_TYPE: lambda m: (float(m.range), float(m.min_range), float(m.max_range)),
    ODOMETRY_TYPE: lambda m: (float(m.twist.twist.linear.x), float(m.twist.twist.angular.z)),
}
#: The frame each message type is in: the scan's own, the odometry's robot frame.
_FRAME = {LASER_TYPE: lambda m: str(m.header.frame_id), ODOMETRY_TYPE: lambda m: str(m.child_frame_id)}


def _read_messages(path: Path, topics: BagTopics) -> tuple[dict[str, str], dict[str, int], tuple, dict[str, _Stream]]:
    """Open the bag, choose its topics and read their messages.

    Returns:
        ``(types, counts, (lasers, sonars, odometry, tf), streams)``: every topic's message
        type and count, the chosen topics (``_choose_topics``; ``tf``: every TF topic), and
        a ``_Stream`` per chosen topic.
    """
    try:
        from rosbags.highlevel import AnyReader, AnyReaderError
        from rosbags.typesys import Stores, get_typestore
    except ImportError:
        raise LogFormatError(
            f"{path}: reading ROS bags needs the rosbags package; install it with pip install 'attentive_gym[ros]'"
        ) from None
    source = path
    if path.is_dir() and not (path / "metadata.yaml").exists():
        raise LogFormatError(f"{path}: a folder is read as a ROS 2 bag, but it holds no metadata.yaml")
    if path.is_file() and path.suffix.lower() != ".bag" and (path.parent / "metadata.yaml").exists():
        source = path.parent  # the whole bag, as its metadata describes it
    try:
        # a bag without message definitions (early ROS 2) is read with ROS 2 Humble's types
        with AnyReader([source], default_typestore=get_typestore(Stores.ROS2_HUMBLE)) as reader:
            types = {name: info.msgtype for name, info in reader.topics.items()}
            counts = {name: info.msgcount for name, info in reader.topics.items()}
            lasers, sonar_topics, odometry_topic = _choose_topics(path, types, topics)
            tf_topics = sorted(name for name, kind in types.items() if kind in TF_TYPES)
            chosen = lasers, sonar_topics, odometry_topic, tf_topics
            for laser_topic in lasers:
                if counts[laser_topic] == 0:
                    raise LogFormatError(
                        f"{path}: topic {laser_topic} holds no {LASER_TYPE} message; topics: {_listing(types, counts)}"
                    )
            wanted = [*lasers, *sonar_topics, *([odometry_topic] if odometry_topic else []), *tf_topics]
            streams = _read_streams(reader, wanted)
    except AnyReaderError as err:
        raise LogFormatError(f"{path}: not a readable ROS bag ({_plain(err)}){_remedy(path)}") from None
    except (AssertionError, struct.error):  # the reader's own checks of a damaged file
        raise LogFormatError(
            f"{path}: not a readable ROS bag (its records do not match their declared sizes){_remedy(path)}"
        ) from None
    return types, counts, chosen, streams


def _plain(err: Exception) -> str:
    """An error's text on one line, without the Python tuples rosbags wraps causes in."""
    text = " ".join(str(err).split())
    return re.sub(r"\(\s*(['\"])(.*?)\1,?\s*\)", r"\2", text)


#: The first bytes of a ROS 1 bag.
_ROS1_MAGIC = b"#ROSBAG V2.0"


#: The first bytes of a ROS bag of format 1.2 (before ROS C Turtle), which rosbags cannot read.
_ROS_OLD_MAGIC = b"#ROSRECORD V1.2"


def _remedy(path: Path) -> str:
    """For a ROS 1 bag whose header is sound: ``rosbag reindex``, which rebuilds the index
    of a bag whose recording was cut short or damaged; for a bag of format 1.2, how to write
    it anew as 2.0."""
    if path.suffix.lower() != ".bag" or not path.is_file():
        return ""
    with open(path, "rb") as handle:
        magic = handle.read(len(_ROS_OLD_MAGIC))
    if magic.startswith(_ROS_OLD_MAGIC):
        return (
            "; it is a ROS bag of format 1.2, which only ROS 1's own tools read: "
            f"rosbag filter {path} {path.with_suffix('')}_v2.bag True writes it anew as format 2.0"
        )
    if not magic.startswith(_ROS1_MAGIC):
        return ""
    return (
        f"; a ROS 1 bag cut short while recording, or with a damaged index, can be repaired with: rosbag reindex {path}"
    )


def _choose_topics(path: Path, types: dict[str, str], topics: BagTopics) -> tuple[list[str], list[str], str | None]:
    """The laser topics (the time base first), the sonar topics in order and the odometry
    topic (or None)."""
    if not types:
        raise LogFormatError(f"{path}: the bag is empty (no topic); a log needs a {LASER_TYPE} topic")
    lasers = _laser_topics(path, types, topics)
    odometry = _one_topic(path, types, topics.odometry, ODOMETRY_TYPE, "--odom-topic", required=False)
    if topics.sonars is not None:
        for name in topics.sonars:
            _check_topic(path, types, name, RANGE_TYPE, "--sonar-topics")
        sonars = list(topics.sonars)
    else:
        sonars = sorted((name for name, kind in types.items() if kind == RANGE_TYPE), key=_natural_key)
    bearings = topics.sonar_bearings_deg
    if bearings is not None and len(bearings) != len(sonars):
        raise LogFormatError(
            f"{path}: {len(bearings)} sonar bearings for {len(sonars)} {RANGE_TYPE} topics "
            f"({', '.join(sonars) or 'none'}); give one bearing (deg) per topic"
        )
    if bearings is None and sonars and len(sonars) not in (FRONT_SONARS, SONAR_RING):
        raise LogFormatError(
            f"{path}: {len(sonars)} {RANGE_TYPE} topics ({', '.join(sonars)}) do not map onto the "
            f"P2AT ring, which takes {FRONT_SONARS} (front sonars) or {SONAR_RING} (whole ring); "
            "give their bearings with --sonar-bearings, or choose topics with --sonar-topics"
        )
    return lasers, sonars, odometry


def _laser_topics(path: Path, types: dict[str, str], topics: BagTopics) -> list[str]:
    """The LaserScan topics named (checked), every one with ``all_lasers`` (natural name
    order), else the only one."""
    if topics.all_lasers:
        found = sorted((name for name, kind in types.items() if kind == LASER_TYPE), key=_natural_key)
        if not found:
            raise LogFormatError(f"{path}: no {LASER_TYPE} topic; topics: {_listing(types)}")
        return found
    for name in topics.more_lasers:
        _check_topic(path, types, name, LASER_TYPE, "--laser-topic")
    first = _one_topic(path, types, topics.laser, LASER_TYPE, "--laser-topic", required=True, several="--all-lasers")
    return [first, *topics.more_lasers]


def _one_topic(
    path: Path, types: dict[str, str], named: str | None, kind: str, flag: str, required: bool, several: str = ""
) -> str | None:
    """The topic ``named`` (checked), else the only topic of message type ``kind``
    (``several``: the flag that takes them all, named in the error for several)."""
    if named is not None:
        _check_topic(path, types, named, kind, flag)
        return named
    found = [name for name, msgtype in sorted(types.items()) if msgtype == kind]
    if len(found) > 1:
        both = f", or all with {several}" if several else ""
        raise LogFormatError(f"{path}: {len(found)} {kind} topics ({', '.join(found)}); choose one with {flag}{both}")
    if not found and required:
        raise LogFormatError(f"{path}: no {kind} topic; topics: {_listing(types)}")
    return found[0] if found else None


def _check_topic(path: Path, types: dict[str, str], name: str, kind: str, flag: str) -> None:
    if name not in types:
        raise LogFormatError(f"{path}: no topic {name} (named by {flag}); topics: {_listing(types)}")
    if types[name] != kind:
        raise LogFormatError(
            f"{path}: topic {name} (named by {flag}) is {types[name]}, not {kind}; topics: {_listing(types)}"
        )


def _listing(types: dict[str, str], counts: dict[str, int] | None = None) -> str:
    """``/odom (nav_msgs/msg/Odometry), /scan (...)``, with message counts when given."""
    return (
        ", ".join(
            f"{name} ({kind}{f', {counts[name]} messages' if counts else ''})" for name, kind in sorted(types.items())
        )
        or "none"
    )


def _natural_key(name: str) -> list[tuple[int, int, str]]:
    """Sort key comparing the digit runs of a name as numbers (``sonar_2`` < ``sonar_10``)."""
    return [(0, int(part), "") if part.isdigit() else (1, 0, part) for part in re.split(r"(\d+)", name) if part]


def _read_streams(reader: Any, topics: Sequence[str]) -> dict[str, _Stream]:
    """A ``_Stream`` per topic of ``topics`` from an open rosbags ``AnyReader``."""
    stamps: dict[str, list[int]] = {topic: [] for topic in topics}
    fields: dict[str, list] = {topic: [] for topic in topics}
    frames: dict[str, str] = {}
    connections = [connection for connection in reader.connections if connection.topic in stamps]
    for connection, receive_ns, raw in reader.messages(connections=connections):
        message = reader.deserialize(raw, connection.msgtype)
        topic, kind = connection.topic, connection.msgtype
        if kind in TF_TYPES:
            stamps[topic].append(int(receive_ns))
            fields[topic].append(transforms_of(message, receive_ns))
            continue
        stamp_ns = int(message.header.stamp.sec) * 1_000_000_000 + int(message.header.stamp.nanosec)
        stamps[topic].append(stamp_ns or int(receive_ns))
        fields[topic].append(_FIELDS[kind](message))
        if topic not in frames and kind in _FRAME:
            frames[topic] = _FRAME[kind](message)
    return {
        topic: _Stream(topic, np.asarray(stamps[topic], dtype=np.int64), fields[topic], frames.get(topic, ""))
        for topic in topics
    }


def _check_time_order(path: Path, topic: str, stamps: np.ndarray, strict: bool) -> None:
    """Stamps (ns) that increase (``strict``) or never decrease, else ``LogFormatError``."""
    steps = np.diff(stamps)
    bad = steps <= 0 if strict else steps < 0
    if bad.any():
        k = int(np.flatnonzero(bad)[0]) + 1
        rule = "increase from scan to scan" if strict else "never decrease"
        raise LogFormatError(
            f"{path}: time goes backwards on {topic}: message {k} is stamped "
            f"{_seconds(stamps[k])} s after {_seconds(stamps[k - 1])} s; stamps must {rule}"
        )


def _seconds(stamp_ns: int) -> str:
    """A stamp (ns) as exact decimal seconds."""
    return f"{int(stamp_ns) // 1_000_000_000}.{int(stamp_ns) % 1_000_000_000:09d}"


def _laser_readings(
    path: Path,
    stream: _Stream,
    no_echo: float,
    mount: LaserMount,
    options: ScanOptions,
    origin: LaserMount | None = None,
) -> tuple[np.ndarray, RawScans | None, list[str]]:
    """``(M, 180)`` model laser ranges (m) of every scan of ``stream``, placed with ``mount``
    and masked as ``options`` says (no echo: ``no_echo`` m); the M scans at their own
    resolution where they share one geometry (else None); one line on what the laser covers
    and one on the self-returns masked (if any).

    ``origin``: None: the model's beams are seen from this laser (``ScanResampler``);
    else from ``origin``'s position, another laser's (``_seen_from``: a merged laser)."""
    beams = np.empty((len(stream.fields), LASER_BEAMS))
    raw = None
    by_geometry: dict[tuple[float, float, int], list[int]] = {}
    for k, (angle_min, increment, _, _, ranges) in enumerate(stream.fields):
        by_geometry.setdefault((angle_min, increment, len(ranges)), []).append(k)
    notes, self_returns = [], []
    for geometry, scans in by_geometry.items():
        angle_min, increment = mount.robot_frame_angles(geometry[0], geometry[1])
        try:
            resampler = ScanResampler.for_scan(angle_min, increment, geometry[2])
        except ValueError as err:
            raise LogFormatError(f"{path}: scan {scans[0]} on {stream.topic}: {err}") from None
        ranges = _valid_ranges([stream.fields[k] for k in scans], options.min_range_m, no_echo)
        bearings = angle_min + np.arange(geometry[2]) * increment
        hidden = bearings_in_intervals(bearings, options.mask_deg)
        if not options.keep_self_returns:
            found = constant_near_beams(ranges) & ~hidden
            if found.any():
                self_returns.append(_self_return_note(ranges[:, found], bearings[found], len(scans)))
            hidden |= found
        ranges[:, hidden] = no_echo
        if origin is None:
            beams[scans] = resampler.resample(ranges, no_echo)
        else:
            beams[scans] = _seen_from(origin, mount, bearings, ranges, no_echo)
        notes.append(_coverage_note(resampler, geometry, len(scans)))
        if len(by_geometry) == 1:
            raw = RawScans(np.mod(bearings + np.pi, 2.0 * np.pi) - np.pi, ranges)
    return beams, raw, [notes[0] if len(notes) == 1 else "; ".join(notes), *self_returns]


def _seen_from(
    origin: LaserMount, mount: LaserMount, bearings_rad: np.ndarray, ranges: np.ndarray, no_echo_m: float
) -> np.ndarray:
    """A laser's echoes on the model's 180 beams as seen from another point: each echo is
    placed in the robot frame from ``mount`` and read from ``origin``'s position; a model
    beam takes the nearest echo whose bearing falls in its 1° (no echo: ``no_echo_m``).

    Args:
        origin: the laser the model's beams are seen from (its x, y, m).
        mount: this laser's mount (its x, y, m).
        bearings_rad: ``(N,)`` robot-frame bearings of this laser's beams (rad).
        ranges: ``(M, N)`` ranges (m), no echo already ``no_echo_m``.
        no_echo_m: the no-echo range (m).

    Returns:
        ``(M, 180)`` ranges (m).
    """
    echo = ranges < no_echo_m
    x = mount.x_m - origin.x_m + ranges * np.cos(bearings_rad)
    y = mount.y_m - origin.y_m + ranges * np.sin(bearings_rad)
    beam = np.floor((np.degrees(np.arctan2(y, x)) + LASER_FOV_DEG / 2.0) * LASER_BEAMS / LASER_FOV_DEG).astype(int)
    seen = echo & (beam >= 0) & (beam < LASER_BEAMS)
    scan = np.broadcast_to(np.arange(ranges.shape[0])[:, None], ranges.shape)
    beams = np.full((ranges.shape[0], LASER_BEAMS), no_echo_m)
    np.minimum.at(beams, (scan[seen], beam[seen]), np.minimum(np.hypot(x, y)[seen], no_echo_m))
    return beams


def _valid_ranges(fields: list[tuple], min_range_m: float, no_echo_m: float) -> np.ndarray:
    """``(M, N)`` ranges (m) of scans of one geometry; outside each scan's valid interval
    (its own, or the model's where unset), or nearer than ``min_range_m``, no echo."""
    _, _, range_min, range_max, _ = zip(*fields)
    low, high = np.asarray(range_min)[:, None], np.asarray(range_max)[:, None]
    unset = ~(low < high)
    low, high = np.where(unset, 0.0, low), np.where(unset, no_echo_m, high)
    ranges = np.stack([f[4] for f in fields])
    return ranges_or_no_echo(ranges, np.maximum(low, min_range_m), high, no_echo_m)


def _coverage_note(resampler: ScanResampler, geometry: tuple[float, float, int], n_scans: int) -> str:
    """``laser: 726 beams over 255°, covers 180 of the model's 180 front beams``."""
    covered = LASER_BEAMS - int(resampler.uncovered.sum())
    span = abs(geometry[1]) * geometry[2]
    return (
        f"laser: {geometry[2]} beams over {np.degrees(span):.0f}° ({n_scans} scans), "
        f"covering {covered} of the model's {LASER_BEAMS} front beams (-90..90°, robot frame)"
    )


def _self_return_note(near: np.ndarray, bearings_rad: np.ndarray, n_scans: int) -> str:
    """One line on the self-return beams found: where (deg, robot frame) and how near (m)."""
    degrees = np.mod(np.degrees(bearings_rad) + 180.0, 360.0) - 180.0
    runs = np.split(degrees, np.flatnonzero(np.abs(np.diff(degrees)) > _RUN_GAP_DEG) + 1)
    where = ", ".join(f"{min(run):.1f}..{max(run):.1f}°" for run in runs)
    valid = near[near < SELF_RETURN_NEAR_M]
    return (
        f"self-returns: {len(degrees)} scan beams at {where} (robot frame) hold a constant "
        f"{valid.min():.2f}-{valid.max():.2f} m echo through all {n_scans} scans, the robot's own structure: "
        "masked as no echo (--keep-self-returns keeps them)"
    )


#: Self-return beams further apart than this (deg) are listed as separate runs.
_RUN_GAP_DEG = 2.0


def _sonar_readings(
    streams: list[_Stream],
    bearings_deg: tuple[float, ...] | None,
    stamps: np.ndarray,
    laser: np.ndarray,
    config: AttentionConfig,
) -> np.ndarray:
    """``(T, 16)`` or ``(T, 8)`` sonar ranges (m) at the scans' ``stamps`` (ns), ``laser`` ``(T, 180)``."""
    no_echo = config.sonar_max_range_m
    readings = []
    for stream in streams:
        value, low, high = np.asarray(stream.fields, dtype=np.float64).T
        unset = ~(low < high)
        ranges = ranges_or_no_echo(
            value, np.where(unset, config.sonar_min_range_m, low), np.where(unset, no_echo, high), no_echo
        )
        readings.append(latest_at_or_before(stamps, stream.stamps, ranges))
    if streams and bearings_deg is None:
        return np.stack(readings, axis=1)
    front = front_sonars_from_laser(laser, config.sonar_cone_half_width_deg, config.sonar_min_range_m, no_echo)
    slots = [front_sonar_slot(bearing, config.sonar_cone_half_width_deg) for bearing in bearings_deg or ()]
    for slot in sorted(set(slots) - {-1}):
        front[:, slot] = np.min([r for r, s in zip(readings, slots) if s == slot], axis=0)
    return front
