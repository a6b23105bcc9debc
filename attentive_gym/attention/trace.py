"""Traces of a run: record model outputs and readings, save and load them as ``.npz``.

- ``Trace``: the arrays of a run (frozen), plus the configuration that produced it.
- ``TraceRecorder``: appends ``AttentionOutput`` objects and readings; ``save`` writes
  the ``.npz`` atomically (temporary file + ``os.replace``).
- ``save_trace``: writes a ``Trace`` the same way.
- ``load_trace``: reads a ``.npz`` written by ``TraceRecorder.save`` (or by the
  experiments, which use the same format), checking names and shapes.

File format (T steps, J regions), all arrays at the top level of the ``.npz``:

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
"""

from __future__ import annotations

import json
import os
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from attentive_gym.attention.config import AttentionConfig
from attentive_gym.attention.model import ORIGIN_CODES, AttentionOutput
from attentive_gym.attention.regions import FRONT_SONARS, LASER_BEAMS

__all__ = ["Trace", "TraceRecorder", "load_trace", "save_trace", "TRACE_ARRAYS"]

#: Arrays of a trace file, in the order of the format table.
TRACE_ARRAYS: tuple[str, ...] = ("t", "O1", "O2", "F", "C", "C_BU", "C_TD", "M", "L", "focus", "fired", "origin")
_REGION_ARRAYS = ("C", "C_BU", "C_TD", "M", "L")
#: Permissions of a saved trace before the umask, as for any newly created file.
_FILE_MODE = 0o666


@dataclass(frozen=True, eq=False)
class Trace:
    """The arrays of one run (see the module docstring for names, shapes and units).

    Attributes:
        config: the configuration as a plain dict (``AttentionConfig.to_dict()``).
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

    @property
    def n_steps(self) -> int:
        """T, the number of steps."""
        return int(self.t.shape[0])

    @property
    def n_regions(self) -> int:
        """J, the number of attention regions."""
        return int(self.C.shape[1])

    def arrays(self) -> dict[str, np.ndarray]:
        """The arrays by name, in ``TRACE_ARRAYS`` order."""
        return {name: getattr(self, name) for name in TRACE_ARRAYS}


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
        self._rows: dict[str, list] = {name: [] for name in TRACE_ARRAYS}

    def __len__(self) -> int:
        return len(self._rows["t"])

    def append(self, output: AttentionOutput, sonar, laser) -> None:
        """Record one step: its output and the readings given to ``step`` (front 8 sonars kept)."""
        rows = self._rows
        rows["t"].append(output.t)
        rows["O1"].append(np.asarray(sonar, dtype=float)[:FRONT_SONARS])
        rows["O2"].append(np.asarray(laser, dtype=float))
        for name in ("F", *_REGION_ARRAYS):
            rows[name].append(getattr(output, name))
        rows["focus"].append(-1 if output.focus is None else output.focus)
        rows["fired"].append(output.fired)
        rows["origin"].append(ORIGIN_CODES[output.origin])

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
        }
        return Trace(**arrays, config=self.config.to_dict())

    def save(self, path: str | os.PathLike) -> Path:
        """Write the trace to ``path`` (``.npz``) atomically; returns the path."""
        return save_trace(self.to_trace(), path)


def save_trace(trace: Trace, path: str | os.PathLike) -> Path:
    """Write ``trace`` to ``path`` through a temporary file in the same folder and ``os.replace``."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as handle:
            np.savez(handle, **trace.arrays(), config_json=np.asarray(json.dumps(trace.config, sort_keys=True)))
        os.chmod(tmp, _FILE_MODE & ~_current_umask())  # mkstemp creates 0600; give the usual mode
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def _current_umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def load_trace(path: str | os.PathLike) -> Trace:
    """Read a trace written by ``TraceRecorder.save``.

    Raises:
        ValueError: when an array is missing or has the wrong shape.
    """
    with np.load(Path(path), allow_pickle=False) as data:
        missing = [name for name in (*TRACE_ARRAYS, "config_json") if name not in data.files]
        if missing:
            raise ValueError(f"{path}: not an attention trace, missing arrays {missing}")
        arrays = {name: data[name] for name in TRACE_ARRAYS}
        config = json.loads(str(data["config_json"]))
    n = arrays["t"].shape[0]
    n_regions = arrays["C"].shape[-1] if arrays["C"].ndim == 2 else -1
    expected = {
        "t": (n,), "O1": (n, FRONT_SONARS), "O2": (n, LASER_BEAMS), "F": (n, 6, n_regions),
        **{name: (n, n_regions) for name in _REGION_ARRAYS},
        "focus": (n,), "fired": (n,), "origin": (n,),
    }
    for name, shape in expected.items():
        if arrays[name].shape != shape:
            raise ValueError(f"{path}: array {name} has shape {arrays[name].shape}, expected {shape}")
    return Trace(**arrays, config=config)
