"""Replay readings logged from a robot through the model (the numpy side of ``attentive-gym attend``).

- ``SensorLog`` / ``LogFormatError`` (of ``sensor_log``): a logged run's readings, and
  the error for a log that cannot be replayed.
- ``load_log``: read a ``.csv`` or ``.npz`` log or a ROS bag, with clear errors for
  malformed files.
- ``replay_log``: step a model over a log and record the trace.
- ``parse_goal``, ``parse_maps``: the command line's goal and map specifications.

Log formats (T readings; times in seconds, ranges in metres, strictly increasing t):

- CSV with a header row. Columns ``t``; ``sonar_0`` .. ``sonar_15`` (the whole ring) or
  ``sonar_0`` .. ``sonar_7`` (front sonars only); ``laser_0`` .. ``laser_179`` (beam 0
  rightmost); optionally ``v`` (linear velocity, m/s) and ``w`` (angular velocity,
  rad/s) for ego-motion compensation, both or neither. Columns may come in any order;
  other columns (not starting with ``sonar_`` or ``laser_``) are ignored.
- NPZ with arrays ``t`` (T,), ``sonar`` (T, 16) or (T, 8), ``laser`` (T, 180) and
  optionally ``odometry`` (T, 2) = (v m/s, w rad/s).

"No echo" readings must be logged as the sensor's maximum range (not inf or NaN).

ROS 1 ``.bag`` files and ROS 2 bags (a folder with ``metadata.yaml``, or its ``.db3`` or
``.mcap`` storage file) are read by ``attentive_gym.attention.io.rosbag`` (LaserScan, Range
and Odometry messages; the optional ``rosbags`` package).
"""

from __future__ import annotations

import csv
import os
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from attentive_gym.attention.config import MAP_ALIASES, MAP_NAMES, AttentionConfig
from attentive_gym.attention.goals import Feature, Goal, Relation
from attentive_gym.attention.io.rosbag import BAG_SUFFIXES, BagTopics, is_bag_path, read_bag
from attentive_gym.attention.io.sensor_log import LogFormatError, SensorLog
from attentive_gym.attention.io.trace import Trace, TraceRecorder
from attentive_gym.attention.model import AttentionModel
from attentive_gym.attention.regions import FRONT_SONARS, LASER_BEAMS, SONAR_RING

__all__ = ["SensorLog", "LogFormatError", "load_log", "replay_log", "parse_goal", "parse_maps"]


def load_log(
    path: str | os.PathLike, *, topics: BagTopics | None = None, config: AttentionConfig | None = None
) -> SensorLog:
    """Read a logged run: a ``.csv`` or ``.npz`` file (formats in the module docstring) or a
    ROS bag (``.bag``, ``.db3``, ``.mcap`` or a ROS 2 bag folder; ``rosbag.read_bag``).

    Args:
        path: the log.
        topics: bags only: which topics hold what (default: found by message type).
        config: bags only: the model whose ranges and sonar cones the bag's readings are
            converted for (default ``AttentionConfig()``).

    Raises:
        LogFormatError: for an unknown suffix, a missing or malformed column or array,
            wrong widths, NaN/inf, negative ranges or non-increasing times; for ``topics``
            with a CSV or NPZ log; for a bag as ``rosbag.read_bag`` says.
        OSError: when the file cannot be read.
    """
    path = Path(path)
    if is_bag_path(path):
        return read_bag(path, topics, config)
    if topics is not None:
        raise LogFormatError(
            f"{path}: topic options apply to ROS bags only ({', '.join(BAG_SUFFIXES)} or a ROS 2 bag folder)"
        )
    suffix = path.suffix.lower()
    if suffix == ".csv":
        return _load_csv(path)
    if suffix == ".npz":
        return _load_npz(path)
    raise LogFormatError(
        f"{path}: unknown log format {suffix!r}; allowed: .csv, .npz, {', '.join(BAG_SUFFIXES)} or a ROS 2 bag folder"
    )


def _load_csv(path: Path) -> SensorLog:
    with open(path, newline="") as handle:
        reader = csv.reader(handle)
        header = next(reader, None)
        if header is None:
            raise LogFormatError(f"{path}: empty file; expected a header row t,sonar_0..,laser_0..laser_179")
        header = [name.strip() for name in header]
        rows = [row for row in reader if row]
    column = {name: k for k, name in enumerate(header)}
    if len(column) != len(header):
        raise LogFormatError(f"{path}: duplicated column names in the header")
    sonar_names = sorted((n for n in header if n.startswith("sonar_")), key=lambda n: (len(n), n))
    laser_names = [n for n in header if n.startswith("laser_")]
    for n_sonar in (SONAR_RING, FRONT_SONARS):
        if set(sonar_names) == {f"sonar_{i}" for i in range(n_sonar)}:
            break
    else:
        raise LogFormatError(
            f"{path}: sonar columns must be sonar_0..sonar_{SONAR_RING - 1} or "
            f"sonar_0..sonar_{FRONT_SONARS - 1}; found {len(sonar_names)}: {sonar_names[:4]}..."
        )
    if set(laser_names) != {f"laser_{i}" for i in range(LASER_BEAMS)}:
        missing = sorted({f"laser_{i}" for i in range(LASER_BEAMS)} - set(laser_names), key=len)
        raise LogFormatError(
            f"{path}: laser columns must be laser_0..laser_{LASER_BEAMS - 1}; "
            f"found {len(laser_names)}, missing {missing[:5]}"
        )
    if "t" not in column:
        raise LogFormatError(f"{path}: missing the time column 't' (seconds)")
    has_v, has_w = "v" in column, "w" in column
    if has_v != has_w:
        raise LogFormatError(
            f"{path}: odometry needs both columns 'v' (m/s) and 'w' (rad/s), found only {'v' if has_v else 'w'}"
        )
    if not rows:
        raise LogFormatError(f"{path}: no readings after the header")
    wanted = ["t", *(f"sonar_{i}" for i in range(n_sonar)), *(f"laser_{i}" for i in range(LASER_BEAMS))]
    if has_v:
        wanted += ["v", "w"]
    index = [column[name] for name in wanted]
    table = np.empty((len(rows), len(wanted)))
    for r, row in enumerate(rows):
        if len(row) != len(header):
            raise LogFormatError(f"{path}: line {r + 2} has {len(row)} fields, the header has {len(header)}")
        try:
            table[r] = [float(row[k]) for k in index]
        except ValueError:
            bad = next(wanted[i] for i, k in enumerate(index) if not _is_float(row[k]))
            raise LogFormatError(f"{path}: line {r + 2}, column {bad}: {row[column[bad]]!r} is not a number") from None
    log = SensorLog(
        t=table[:, 0],
        sonar=table[:, 1 : 1 + n_sonar],
        laser=table[:, 1 + n_sonar : 1 + n_sonar + LASER_BEAMS],
        odometry=table[:, -2:] if has_v else None,
    )
    return log.check(str(path))


def _is_float(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _load_npz(path: Path) -> SensorLog:
    try:
        data = np.load(path, allow_pickle=False)
    except (ValueError, OSError) as err:
        raise LogFormatError(f"{path}: not a readable .npz archive ({err})") from None
    if not isinstance(data, np.lib.npyio.NpzFile):  # a single array saved with np.save, named .npz
        raise LogFormatError(
            f"{path}: holds one array, not an .npz archive of named arrays t, sonar, laser (np.savez writes one)"
        )
    with data:
        missing = [name for name in ("t", "sonar", "laser") if name not in data.files]
        if missing:
            raise LogFormatError(
                f"{path}: missing arrays {missing}; a log needs t (T,), sonar (T, 16|8), "
                f"laser (T, 180) and optionally odometry (T, 2)"
            )
        arrays = {}
        for name in ("t", "sonar", "laser", "odometry"):
            if name not in data.files:
                continue
            value = data[name]
            if not np.issubdtype(value.dtype, np.number) or np.issubdtype(value.dtype, np.complexfloating):
                raise LogFormatError(f"{path}: array {name} must be real numbers, got dtype {value.dtype}")
            arrays[name] = value.astype(float)
    return SensorLog(**arrays).check(str(path))


def replay_log(log: SensorLog, model: AttentionModel, recorder: TraceRecorder | None = None) -> Trace:
    """Reset ``model`` and step it over every reading of ``log``; returns the recorded trace.

    Odometry columns, when the log has them, are passed to ``step`` for ego-motion
    compensation; goals, weights and state set on ``model`` beforehand are kept. With the
    tracker, the trace records the robot's dead-reckoned pose at each step
    (``AttentionModel.odometry_pose``).
    """
    recorder = TraceRecorder(model.config) if recorder is None else recorder
    model.reset()
    odometry = log.odometry
    for k in range(log.t.shape[0]):
        sonar, laser = log.sonar[k], log.laser[k]
        output = model.step(float(log.t[k]), sonar, laser, None if odometry is None else odometry[k])
        recorder.append(output, sonar, laser, model.odometry_pose)
    return recorder.to_trace()


def parse_goal(spec: str) -> Goal:
    """A goal from ``FEATURE:RELATION:BOUNDS``.

    Examples: ``speed:between:0.5:0.9``, ``speed:greater:0.6``, ``distance:smaller:2``,
    ``speed:equal:0.7`` or ``speed:equal:0.7:0.05`` (with tolerance), ``direction:towards``
    (also ``direction:equal:towards``). Speeds in m/s, distances in m.

    Raises:
        ValueError: for a malformed specification or an invalid goal.
    """
    parts = [p.strip().lower() for p in spec.split(":")]
    usage = (
        "goal specification must be FEATURE:RELATION:BOUNDS, e.g. speed:between:0.5:0.9, "
        "speed:greater:0.6, distance:smaller:2, speed:equal:0.7[:tol], direction:towards"
    )
    if len(parts) < 2:
        raise ValueError(f"{usage}; got {spec!r}")
    feature = parts[0]
    if feature == Feature.DIRECTION.value:
        if len(parts) == 3 and parts[1] == Relation.EQUAL.value:
            parts = [feature, parts[2]]
        if len(parts) != 2:
            raise ValueError(f"{usage}; got {spec!r}")
        return Goal.direction_is(parts[1])
    relation, bounds = parts[1], parts[2:]
    try:
        numbers = [float(b) for b in bounds]
    except ValueError:
        raise ValueError(f"goal bounds must be numbers; got {spec!r}") from None
    expected = {"between": (2,), "greater": (1,), "smaller": (1,), "equal": (1, 2)}
    if relation not in expected:
        raise ValueError(f"unknown goal relation {relation!r} in {spec!r}; allowed: {', '.join(expected)}")
    if len(numbers) not in expected[relation]:
        counts = " or ".join(map(str, expected[relation]))
        raise ValueError(f"{usage}; {relation} takes {counts} bound(s), got {spec!r}")
    if relation == "between":
        return Goal.between(feature, *numbers)
    if relation == "equal":
        return Goal.equal(feature, *numbers)
    return Goal(feature, relation, lo=numbers[0])


def parse_maps(spec: str) -> Mapping[str, float]:
    """Map weights from ``F1,F3`` (weight 1 each) or ``F1=1,F4=2`` (names or aliases such as ``motion``).

    Returns:
        ``{"F1": w, ...}`` with the named maps only (the others are inactive).

    Raises:
        ValueError: for an unknown map, a map named twice or a weight that is not a number >= 0.
    """
    weights: dict[str, float] = {}
    for item in (part.strip() for part in spec.split(",")):
        if not item:
            continue
        name, _, value = item.partition("=")
        key = MAP_ALIASES.get(name.strip().lower(), name.strip().upper())
        if key not in MAP_NAMES:
            raise ValueError(
                f"unknown feature map {name.strip()!r} in {spec!r}; allowed: "
                f"{', '.join(MAP_NAMES)} or {', '.join(MAP_ALIASES)}"
            )
        if key in weights:
            raise ValueError(f"map {key} named twice in {spec!r}")
        try:
            weight = float(value) if value else 1.0
        except ValueError:
            raise ValueError(f"the weight of {key} must be a number, got {value!r}") from None
        if not (np.isfinite(weight) and weight >= 0.0):
            raise ValueError(f"the weight of {key} must be a finite number >= 0, got {value!r}")
        weights[key] = weight
    if not weights:
        raise ValueError(f"no feature map named in {spec!r}; e.g. F1,F3 or F1=1,F4=2")
    return weights
