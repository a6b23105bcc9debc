"""Read a ROS 1 or ROS 2 bag as a ``SensorLog`` (``attentive-gym attend`` on a robot's own bag).

- ``is_bag_path``: whether a path names a bag (``.bag``, ``.db3``, ``.mcap`` or a folder).
- ``BagTopics`` / ``parse_bag_topics``: which topics hold what, from the command line's flags.
- ``read_bag``: the bag's laser, sonars and odometry on one time base.

Bags: ROS 1 ``.bag`` files; ROS 2 bag folders (``metadata.yaml`` beside ``.db3`` or
``.mcap`` storage files) or one storage file itself (its folder is opened when it holds
a ``metadata.yaml``). Read with ``rosbags`` (pure Python, no ROS install; the ``ros``
extra), imported only when a bag is read.

Messages (ROS 2 names; ROS 1's ``sensor_msgs/LaserScan`` etc. are the same):

- ``sensor_msgs/msg/LaserScan``: one topic, the time base: every scan is one step. Its
  beams are resampled onto the model's 180 beams over the front 180°
  (``ros_readings.ScanResampler``: nearest echo of the overlapping scan beams).
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

No echo: NaN, ±inf, a range below the message's ``range_min``/``min_range`` or at or
above its ``range_max``/``max_range`` (or beyond the model's maximum range), and a model
beam outside the scan read the model's maximum range (``AttentionConfig.laser_max_range_m``,
``sonar_max_range_m``), as the env's sensors do. A message whose limits are unset
(minimum >= maximum) is checked against the model's limits instead.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from attentive_gym.attention.config import AttentionConfig
from attentive_gym.attention.io.ros_readings import (
    ScanResampler,
    front_sonar_slot,
    front_sonars_from_laser,
    latest_at_or_before,
    ranges_or_no_echo,
)
from attentive_gym.attention.io.sensor_log import LogFormatError, SensorLog
from attentive_gym.attention.regions import FRONT_SONARS, LASER_BEAMS, SONAR_RING

__all__ = [
    "BAG_SUFFIXES",
    "LASER_TYPE",
    "RANGE_TYPE",
    "ODOMETRY_TYPE",
    "BagTopics",
    "is_bag_path",
    "parse_bag_topics",
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
        laser: the LaserScan topic.
        sonars: the Range topics, in ring order (sonar 0 first) unless bearings are given.
        odometry: the Odometry topic.
        sonar_bearings_deg: one bearing (deg, counter-clockwise from the heading) per
            Range topic, in the order of ``sonars`` (or of the natural name order of the
            Range topics found), for sonars that are not the P2AT ring.

    Raises:
        ValueError: for an empty or repeated topic name, a non-finite bearing, or not as
            many bearings as sonar topics.
    """

    laser: str | None = None
    sonars: tuple[str, ...] | None = None
    odometry: str | None = None
    sonar_bearings_deg: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        for name, topic in (("laser", self.laser), ("odometry", self.odometry)):
            if topic is not None and not topic.strip():
                raise ValueError(f"the {name} topic name is empty")
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
    laser: str | None = None, sonars: str | None = None, odometry: str | None = None, sonar_bearings: str | None = None
) -> BagTopics | None:
    """``BagTopics`` from the command line's strings; None when none is given.

    Args:
        laser, odometry: topic names.
        sonars: comma-separated topic names, e.g. ``/sonar/0,/sonar/1``.
        sonar_bearings: comma-separated bearings (deg), e.g. ``90,50,30,10,-10,-30,-50,-90``.

    Raises:
        ValueError: for a bearing that is not a number, or as ``BagTopics``.
    """
    if laser is None and sonars is None and odometry is None and sonar_bearings is None:
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
    return BagTopics(laser, sonar_topics, odometry, bearings)


def is_bag_path(path: str | Path) -> bool:
    """True for a ``.bag``, ``.db3`` or ``.mcap`` path or a folder (a ROS 2 bag, or not one at all)."""
    path = Path(path)
    return path.suffix.lower() in BAG_SUFFIXES or path.is_dir()


def read_bag(path: str | Path, topics: BagTopics | None = None, config: AttentionConfig | None = None) -> SensorLog:
    """A bag's readings as the model's (message handling in the module docstring).

    Args:
        path: a ROS 1 ``.bag``, a ROS 2 bag folder, or a ``.db3`` / ``.mcap`` storage file.
        topics: which topics hold what (default: each found by its message type).
        config: the model the readings are for: its maximum ranges are "no echo", its
            sonar range and cone width turn the laser into sonars (default ``AttentionConfig()``).

    Returns:
        The checked ``SensorLog``: sonar ``(T, 16)`` with 16 Range topics and no
        bearings, ``(T, 8)`` otherwise; odometry when the bag has an Odometry topic.

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
    if not path.exists():
        raise FileNotFoundError(f"{path}: no such bag file or folder")
    types, counts, (laser_topic, sonar_topics, odometry_topic), streams = _read_messages(path, topics)
    for topic, stream in streams.items():
        _check_time_order(path, topic, stream.stamps, strict=topic == laser_topic)
    held = [topic for topic in (*sonar_topics, odometry_topic) if topic is not None]
    empty = [topic for topic in held if counts[topic] == 0]
    if empty:
        raise LogFormatError(f"{path}: topics {empty} hold no message; topics: {_listing(types, counts)}")
    scan_stamps = streams[laser_topic].stamps
    first = {topic: int(streams[topic].stamps[0]) for topic in held}
    keep = scan_stamps >= max(first.values(), default=scan_stamps[0])
    if not keep.any():
        late = max(first, key=first.get)
        raise LogFormatError(
            f"{path}: no scan on {laser_topic} at or after the first message of {late}; "
            "the sonars and odometry are read at the scans' stamps"
        )
    stamps = scan_stamps[keep]
    laser = _laser_readings(path, streams[laser_topic], config)[keep]
    sonar = _sonar_readings(
        [streams[topic] for topic in sonar_topics], topics.sonar_bearings_deg, stamps, laser, config
    )
    odometry = None
    if odometry_topic is not None:
        stream = streams[odometry_topic]
        odometry = latest_at_or_before(stamps, stream.stamps, np.asarray(stream.fields, dtype=np.float64))
    log = SensorLog(t=(stamps - stamps[0]) * 1e-9, sonar=sonar, laser=laser, odometry=odometry)
    return log.check(str(path))


@dataclass(frozen=True, eq=False)
class _Stream:
    """The messages of one topic, in bag order.

    Attributes:
        topic: its name.
        stamps: ``(M,)`` int64 header stamps (ns), the receive time where a stamp is zero.
        fields: the ``_FIELDS`` tuple of each message.
    """

    topic: str
    stamps: np.ndarray
    fields: list[tuple]


#: What is read of each message type: LaserScan ``(angle_min, angle_increment,
#: range_min, range_max, ranges)``; Range ``(range, min_range, max_range)``; Odometry
#: ``(v, w)`` (rad, m, m/s, rad/s).
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


def _read_messages(path: Path, topics: BagTopics) -> tuple[dict[str, str], dict[str, int], tuple, dict[str, _Stream]]:
    """Open the bag, choose its topics and read their messages.

    Returns:
        ``(types, counts, (laser, sonars, odometry), streams)``: every topic's message
        type and count, the chosen topics (``_choose_topics``), and a ``_Stream`` per
        chosen topic.
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
            chosen = laser_topic, sonar_topics, odometry_topic = _choose_topics(path, types, topics)
            if counts[laser_topic] == 0:
                raise LogFormatError(
                    f"{path}: topic {laser_topic} holds no {LASER_TYPE} message; topics: {_listing(types, counts)}"
                )
            wanted = [laser_topic, *sonar_topics, *([odometry_topic] if odometry_topic else [])]
            streams = _read_streams(reader, wanted)
    except AnyReaderError as err:
        raise LogFormatError(f"{path}: not a readable ROS bag ({' '.join(str(err).split())})") from None
    return types, counts, chosen, streams


def _choose_topics(path: Path, types: dict[str, str], topics: BagTopics) -> tuple[str, list[str], str | None]:
    """The laser topic, the sonar topics in order and the odometry topic (or None)."""
    if not types:
        raise LogFormatError(f"{path}: the bag is empty (no topic); a log needs a {LASER_TYPE} topic")
    laser = _one_topic(path, types, topics.laser, LASER_TYPE, "--laser-topic", required=True)
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
    return laser, sonars, odometry


def _one_topic(
    path: Path, types: dict[str, str], named: str | None, kind: str, flag: str, required: bool
) -> str | None:
    """The topic ``named`` (checked), else the only topic of message type ``kind``."""
    if named is not None:
        _check_topic(path, types, named, kind, flag)
        return named
    found = [name for name, msgtype in sorted(types.items()) if msgtype == kind]
    if len(found) > 1:
        raise LogFormatError(f"{path}: {len(found)} {kind} topics ({', '.join(found)}); choose one with {flag}")
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
    fields: dict[str, list[tuple]] = {topic: [] for topic in topics}
    connections = [connection for connection in reader.connections if connection.topic in stamps]
    for connection, receive_ns, raw in reader.messages(connections=connections):
        message = reader.deserialize(raw, connection.msgtype)
        stamp_ns = int(message.header.stamp.sec) * 1_000_000_000 + int(message.header.stamp.nanosec)
        stamps[connection.topic].append(stamp_ns or int(receive_ns))
        fields[connection.topic].append(_FIELDS[connection.msgtype](message))
    return {topic: _Stream(topic, np.asarray(stamps[topic], dtype=np.int64), fields[topic]) for topic in topics}


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


def _laser_readings(path: Path, stream: _Stream, config: AttentionConfig) -> np.ndarray:
    """``(M, 180)`` model laser ranges (m) of every scan of ``stream``."""
    no_echo = config.laser_max_range_m
    resamplers: dict[tuple[float, float, int], ScanResampler] = {}
    beams = np.empty((len(stream.fields), LASER_BEAMS))
    for k, (angle_min, increment, range_min, range_max, ranges) in enumerate(stream.fields):
        geometry = (angle_min, increment, len(ranges))
        if geometry not in resamplers:
            try:
                resamplers[geometry] = ScanResampler.for_scan(*geometry)
            except ValueError as err:
                raise LogFormatError(f"{path}: scan {k} on {stream.topic}: {err}") from None
        low, high = (range_min, range_max) if range_min < range_max else (0.0, no_echo)
        beams[k] = resamplers[geometry].resample(ranges_or_no_echo(ranges, low, high, no_echo), no_echo)
    return beams


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
