"""Traces of a run: record model outputs and readings, save and load them as ``.npz``.

- ``Trace``: the arrays of a run (frozen), plus the configuration that produced it.
- ``TraceRecorder``: appends ``AttentionOutput`` objects and readings; ``save`` writes
  the ``.npz`` atomically (temporary file + ``os.replace``).
- ``save_trace``: writes a ``Trace`` the same way.
- ``load_trace``: reads a ``.npz`` written by ``TraceRecorder.save`` (or by the
  experiments, which use the same format), checking names and shapes.

File format (T steps, J regions, N track rows over all steps), all arrays at the top
level of the ``.npz``:

==============  ============  ===============================================
name            shape, dtype  meaning
==============  ============  ===============================================
``t``           (T,) float    time of each step (s)
``O1``          (T, 8) float  front sonar readings (m)
``O2``          (T, 180)      laser readings (m)
``F``           (T, 6, J)     feature maps F1..F6 (inactive maps 0)
``C``           (T, J)        combined map
``C_BU``        (T, J)        its bottom-up part
``C_TD``        (T, J)        its top-down part
``M``           (T, J)        attentional map (gain)
``L``           (T, J)        saliency
``focus``       (T,) int64    focused region, −1 for none
``fired``       (T,) bool     a new course started
``origin``      (T,) int8     0 bottom-up, 1 top-down, −1 none
``config_json`` () str        the ``AttentionConfig`` as a JSON object
==============  ============  ===============================================

The tracks (``AttentionOutput.tracks``, robot frame at each step's time) vary in number
from step to step, so they are stored flat, one row per track and step, ordered by step
and, within a step, in the table's order; ``Trace.tracks_at(step)`` gives one step's
``TrackTable`` back. A step without tracks (every kinematics mode but "tracker") has no
rows. Files written before the tracks were recorded have none of these arrays and load
with no tracks; a file with only some of them is refused.

The robot's dead-reckoned pose (``AttentionModel.odometry_pose``, the frame the tracks
live in) is recorded where the recorder is given it (``replay.replay_log`` does, with the
tracker); files without it load with ``pose`` None.

==============  ============  ===============================================
name            shape, dtype  meaning
==============  ============  ===============================================
``pose``        (T, 3) float  x, y (m) and heading (rad) in the odometry frame
==============  ============  ===============================================

============================  ================  =====================================
name                          shape, dtype      meaning (``TrackTable`` field)
============================  ================  =====================================
``track_step``                (N,) int64        the step of the row, in [0, T), sorted
``track_id``                  (N,) int64        track id (``id``)
``track_position_m``          (N, 2) float      centre, x forward, y left (m)
``track_velocity_mps``        (N, 2) float      velocity over the ground (m/s)
``track_speed_mps``           (N,) float        its norm (m/s)
``track_moving_probability``  (N,) float        probability that the body moves
``track_covariance``          (N, 4, 4) float   covariance of (x, y, vx, vy)
``track_age_s``               (N,) float        time since the track's birth (s)
``track_confirmed``           (N,) bool         the track is confirmed
``track_region``              (N,) int64        region of its bearing (sonar grid), −1
============================  ================  =====================================
"""

from __future__ import annotations

import json
import numbers
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from attentive_gym._atomic import atomic_file
from attentive_gym.attention.config import AttentionConfig
from attentive_gym.attention.model import ORIGIN_CODES, AttentionOutput
from attentive_gym.attention.regions import FRONT_SONARS, LASER_BEAMS
from attentive_gym.attention.tracking.tracker import TrackTable

__all__ = ["Trace", "TraceRecorder", "load_trace", "save_trace", "TRACE_ARRAYS", "TRACK_ARRAYS", "POSE_ARRAY"]

#: Per-step arrays of a trace file (every file has them), in the order of the format table.
TRACE_ARRAYS: tuple[str, ...] = ("t", "O1", "O2", "F", "C", "C_BU", "C_TD", "M", "L", "focus", "fired", "origin")
_REGION_ARRAYS = ("C", "C_BU", "C_TD", "M", "L")
#: ``TrackTable`` field of each flat track array (the file's name is ``track_`` + field,
#: ``track_id`` for ``id``), its trailing shape and its dtype.
_TRACK_COLUMNS: tuple[tuple[str, tuple[int, ...], type], ...] = (
    ("id", (), np.int64),
    ("position_m", (2,), np.float64),
    ("velocity_mps", (2,), np.float64),
    ("speed_mps", (), np.float64),
    ("moving_probability", (), np.float64),
    ("covariance", (4, 4), np.float64),
    ("age_s", (), np.float64),
    ("confirmed", (), np.bool_),
    ("region", (), np.int64),
)
#: Track arrays of a trace file (files from before the tracker have none), in the order
#: of the format table.
TRACK_ARRAYS: tuple[str, ...] = ("track_step", *(f"track_{name}" for name, _, _ in _TRACK_COLUMNS))
#: The optional array of the robot's pose per step.
POSE_ARRAY = "pose"


def _no_tracks() -> dict[str, np.ndarray]:
    """The track arrays of a trace without tracks (N = 0)."""
    return {
        "track_step": np.zeros(0, np.int64),
        **{f"track_{name}": np.zeros((0, *shape), dtype) for name, shape, dtype in _TRACK_COLUMNS},
    }


def _track_field(name: str):
    return field(default_factory=lambda: _no_tracks()[name], repr=False)


@dataclass(frozen=True, eq=False)
class Trace:
    """The arrays of one run (see the module docstring for names, shapes and units).

    Attributes:
        config: the configuration as a plain dict (``AttentionConfig.to_dict()``).
        track_step, track_id, …: the tracks of every step, flat (``TRACK_ARRAYS``);
            empty by default. ``tracks_at(step)`` reads one step's back.
        pose: ``(T, 3)`` the robot's dead-reckoned pose at each step (x m, y m, heading
            rad; odometry frame), or None where it was not recorded.
    """

    t: np.ndarray
    O1: np.ndarray
    O2: np.ndarray
    F: np.ndarray
    C: np.ndarray
    C_BU: np.ndarray
    C_TD: np.ndarray
    M: np.ndarray
    L: np.ndarray
    focus: np.ndarray
    fired: np.ndarray
    origin: np.ndarray
    config: dict[str, Any]
    track_step: np.ndarray = _track_field("track_step")
    track_id: np.ndarray = _track_field("track_id")
    track_position_m: np.ndarray = _track_field("track_position_m")
    track_velocity_mps: np.ndarray = _track_field("track_velocity_mps")
    track_speed_mps: np.ndarray = _track_field("track_speed_mps")
    track_moving_probability: np.ndarray = _track_field("track_moving_probability")
    track_covariance: np.ndarray = _track_field("track_covariance")
    track_age_s: np.ndarray = _track_field("track_age_s")
    track_confirmed: np.ndarray = _track_field("track_confirmed")
    track_region: np.ndarray = _track_field("track_region")
    pose: np.ndarray | None = field(default=None, repr=False)

    @property
    def n_steps(self) -> int:
        """T, the number of steps."""
        return int(self.t.shape[0])

    @property
    def n_regions(self) -> int:
        """J, the number of attention regions."""
        return int(self.C.shape[1])

    @property
    def n_track_rows(self) -> int:
        """N, the number of track rows over all steps."""
        return int(self.track_step.shape[0])

    def arrays(self) -> dict[str, np.ndarray]:
        """The arrays by name: ``TRACE_ARRAYS``, then ``TRACK_ARRAYS``, then ``pose`` where recorded."""
        arrays = {name: getattr(self, name) for name in (*TRACE_ARRAYS, *TRACK_ARRAYS)}
        if self.pose is not None:
            arrays[POSE_ARRAY] = self.pose
        return arrays

    def tracks_at(self, step: int) -> TrackTable:
        """The tracks of step ``step`` (0 ≤ step < T; negative counts from the end), as
        ``AttentionOutput.tracks`` gave them: a read-only ``TrackTable`` viewing this
        trace's arrays. Empty for a step without tracks and for a file without tracks.

        Raises:
            TypeError: ``step`` is not an integer.
            ValueError: ``step`` is outside ``[-T, T)``.
        """
        if isinstance(step, bool) or not isinstance(step, numbers.Integral):
            raise TypeError(f"step must be an integer, got {step!r}")
        n = self.n_steps
        if not -n <= step < n:
            raise ValueError(f"step {step} is outside the trace's {n} steps (allowed: {-n} to {n - 1})")
        step = int(step) % n
        start, stop = np.searchsorted(self.track_step, (step, step + 1))
        arrays = {}
        for name, _, _ in _TRACK_COLUMNS:
            view = getattr(self, f"track_{name}")[start:stop]
            view.flags.writeable = False
            arrays[name] = view
        return TrackTable(**arrays)


class TraceRecorder:
    """Collects the outputs of a run and the readings that produced them.

    Args:
        config: the model's configuration, stored with the trace.

    Example:
        >>> recorder = TraceRecorder(model.config)          # doctest: +SKIP
        >>> recorder.append(model.step(t, sonar, laser), sonar, laser)   # doctest: +SKIP
        >>> recorder.save("run/trace.npz")                  # doctest: +SKIP
    """

    def __init__(self, config: AttentionConfig) -> None:
        self.config = config
        self._rows: dict[str, list] = {name: [] for name in (*TRACE_ARRAYS, *TRACK_ARRAYS, POSE_ARRAY)}

    def __len__(self) -> int:
        return len(self._rows["t"])

    def append(self, output: AttentionOutput, sonar, laser, pose=None) -> None:
        """Record one step: its output (tracks included) and the readings given to ``step``
        (front 8 sonars kept), and the robot's pose after it (``(3,)`` x m, y m, heading
        rad: ``AttentionModel.odometry_pose``) where given.

        Raises:
            ValueError: for a pose given at some steps and not at others.
        """
        rows = self._rows
        if len(self) and (pose is None) != (rows[POSE_ARRAY][0] is None):
            raise ValueError("give the robot's pose at every step of a trace or at none")
        tracks = output.tracks
        rows["track_step"].append(np.full(len(tracks), len(self), np.int64))
        for name, _, _ in _TRACK_COLUMNS:
            rows[f"track_{name}"].append(getattr(tracks, name))  # read-only arrays, new each step
        rows["t"].append(output.t)
        rows["O1"].append(np.asarray(sonar, dtype=float)[:FRONT_SONARS])
        rows["O2"].append(np.asarray(laser, dtype=float))
        for name in ("F", *_REGION_ARRAYS):
            rows[name].append(getattr(output, name))
        rows["focus"].append(-1 if output.focus is None else output.focus)
        rows["fired"].append(output.fired)
        rows["origin"].append(ORIGIN_CODES[output.origin])
        rows[POSE_ARRAY].append(None if pose is None else np.asarray(pose, dtype=float).reshape(3))

    def to_trace(self) -> Trace:
        """The recorded steps as a ``Trace``."""
        if not len(self):
            raise ValueError("the recorder holds no steps; append at least one output first")
        rows = self._rows
        arrays = {
            "t": np.asarray(rows["t"], dtype=float),
            "O1": np.stack(rows["O1"]),
            "O2": np.stack(rows["O2"]),
            "F": np.stack(rows["F"]),
            **{name: np.stack(rows[name]) for name in _REGION_ARRAYS},
            "focus": np.asarray(rows["focus"], dtype=np.int64),
            "fired": np.asarray(rows["fired"], dtype=bool),
            "origin": np.asarray(rows["origin"], dtype=np.int8),
            "track_step": np.concatenate(rows["track_step"]),
            **{
                f"track_{name}": np.concatenate(rows[f"track_{name}"]).astype(dtype, copy=False).reshape(-1, *shape)
                for name, shape, dtype in _TRACK_COLUMNS
            },
        }
        pose = None if rows[POSE_ARRAY][0] is None else np.stack(rows[POSE_ARRAY])
        return Trace(**arrays, config=self.config.to_dict(), pose=pose)

    def save(self, path: str | os.PathLike) -> Path:
        """Write the trace to ``path`` (``.npz``) atomically; returns the path."""
        return save_trace(self.to_trace(), path)


def save_trace(trace: Trace, path: str | os.PathLike) -> Path:
    """Write ``trace`` to ``path`` through a temporary file in the same folder and ``os.replace``."""
    with atomic_file(path, binary=True) as handle:
        np.savez(handle, **trace.arrays(), config_json=np.asarray(json.dumps(trace.config, sort_keys=True)))
    return Path(path)


def load_trace(path: str | os.PathLike) -> Trace:
    """Read a trace written by ``TraceRecorder.save``; a file without the track arrays
    (written before they were recorded) loads with no tracks.

    Raises:
        ValueError: when the file is not an .npz archive, when an array is missing or has the
            wrong shape, when only some of the track arrays are there, or when ``track_step``
            is not integers sorted within [0, T).
    """
    try:
        data = np.load(Path(path), allow_pickle=False)
    except (ValueError, OSError) as err:
        raise ValueError(f"{path}: not a readable .npz archive ({err})") from None
    if not isinstance(data, np.lib.npyio.NpzFile):
        raise ValueError(f"{path}: holds one array, not an attention trace (an .npz archive)")
    with data:
        missing = [name for name in (*TRACE_ARRAYS, "config_json") if name not in data.files]
        if missing:
            raise ValueError(f"{path}: not an attention trace, missing arrays {missing}")
        arrays = {name: data[name] for name in TRACE_ARRAYS}
        present = [name for name in TRACK_ARRAYS if name in data.files]
        if present and len(present) < len(TRACK_ARRAYS):
            absent = [name for name in TRACK_ARRAYS if name not in data.files]
            raise ValueError(
                f"{path}: has track arrays {present} but not {absent}; a trace has all of {list(TRACK_ARRAYS)} or none"
            )
        arrays.update({name: data[name] for name in present} if present else _no_tracks())
        pose = data[POSE_ARRAY] if POSE_ARRAY in data.files else None
        config = json.loads(str(data["config_json"]))
    n = arrays["t"].shape[0]
    n_regions = arrays["C"].shape[-1] if arrays["C"].ndim == 2 else -1
    expected = {
        "t": (n,),
        "O1": (n, FRONT_SONARS),
        "O2": (n, LASER_BEAMS),
        "F": (n, 6, n_regions),
        **{name: (n, n_regions) for name in _REGION_ARRAYS},
        "focus": (n,),
        "fired": (n,),
        "origin": (n,),
    }
    n_rows = arrays["track_step"].shape[0] if arrays["track_step"].ndim == 1 else -1
    expected["track_step"] = (n_rows,)
    expected.update({f"track_{name}": (n_rows, *shape) for name, shape, _ in _TRACK_COLUMNS})
    if pose is not None:
        arrays[POSE_ARRAY] = pose
        expected[POSE_ARRAY] = (n, 3)
    for name, shape in expected.items():
        if arrays[name].shape != shape:
            raise ValueError(f"{path}: array {name} has shape {arrays[name].shape}, expected {shape}")
    steps = arrays["track_step"]
    if not np.issubdtype(steps.dtype, np.integer):
        raise ValueError(f"{path}: array track_step has dtype {steps.dtype}, expected an integer dtype")
    if n_rows and (steps[0] < 0 or steps[-1] >= n or np.any(np.diff(steps) < 0)):
        raise ValueError(
            f"{path}: track_step must be sorted and within [0, {n}) (the steps), got values from "
            f"{steps.min()} to {steps.max()}"
        )
    return Trace(**arrays, config=config)
