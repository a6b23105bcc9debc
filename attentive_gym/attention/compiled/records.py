"""The records a compiled attentional-model step reads and writes (docs/model.md §2–§10).

- ``StateLayout``: where each named array of a model's state, and each constant of its
  configuration, lies in a few flat buffers, as a table the kernels read.
- ``ModelState``: one model's state, three flat buffers (floats, integers, flags) whose
  named arrays are views (``field``); a ``ModelBatch`` hands each of its models a row of
  its own ``(N, ...)`` buffers.
- ``output_dtype``: the structured dtype of one step's outputs, one record per model.

A step's kernel (``step_kernels.attend_many``) then takes a handful of arrays, not one
argument per array: calling a compiled function costs about 70 ns per array argument.

The state fields (``STATE_FIELDS``) are, per model: the input row and the ego-motion
change; the goals' settings (active weights, goal plan, combination weights, gain, the
speeds a speed goal wants); the sensorial memory's buffers; the course book's arrays; the
tracker's state (``tracking.tracker.STATE_FIELDS``, of length 0 without a tracker). The
constant fields (``CONSTANT_FIELDS``) are the configuration's arrays and scalars, shared by
every model of the configuration. Flags are stored as uint8 (numba's records cannot hold
bool) and viewed as bool.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from attentive_gym.attention.tracking.tracker import STATE_FIELDS as TRACKER_FIELDS

__all__ = [
    "StateLayout",
    "ModelState",
    "STATE_FIELDS",
    "CONSTANT_FIELDS",
    "FLOAT_SCALARS",
    "INT_SCALARS",
    "REQUIRE_TARGET",
    "SILENT_MAPS_OUT",
    "goal_options",
    "STEP_COLUMNS",
    "output_dtype",
    "OUTPUT_ARRAYS",
    "KEPT_OUTPUTS",
    "RESULTS",
]

#: The model's own fields: the input row (196,) m (front sonars, beams, rear sonars), the
#: ego-motion change (188,) m, the active map weights (6,), the goal plan
#: (3, PLAN_COLUMNS), the weights of C (2, 3), the gain g (1,) and the speeds a speed goal
#: wants (2,) m/s.
MODEL_FIELDS = ("row", "ego", "active", "goal_plan", "combine", "gain", "wanted_speed")
#: The sensorial memory's (``SensorMemory.buffers``): ring position and count (2,), times
#: (W,) s, samples (3, W, 188), ego-motion offset (188,) m.
MEMORY_FIELDS = ("memory_state", "times", "samples", "ego_offset")
#: The course book's (``CourseBook.arrays`` less its parameters), capacity C rows.
COURSE_FIELDS = ("bu_regions", "bu_starts", "td_regions", "td_times", "counts")
#: Every state field, in the kernels' order (the tracker's names prefixed ``tracker.``).
STATE_FIELDS = (*MODEL_FIELDS, *MEMORY_FIELDS, *COURSE_FIELDS, *(f"tracker.{name}" for name in TRACKER_FIELDS))
#: The configuration's scalars stored as floats: beam step (rad), maximum speed and
#: direction ε (m/s), sonar-to-laser match (m), jump σs, range noise (relative, floor m),
#: maximum distance (m), the laser's maximum range (m), the focus threshold.
FLOAT_SCALARS = (
    "beam_step_rad",
    "max_speed",
    "epsilon",
    "match_m",
    "match_sigmas",
    "noise_rel",
    "noise_floor_m",
    "max_distance",
    "laser_max",
    "threshold",
)
#: The configuration's scalars stored as integers: the slope's K, whether the tracker runs,
#: its confirmation hits, ``laser_only``, the top-down maps' options (``goal_options``).
INT_SCALARS = ("slope_samples", "tracked", "confirm_hits", "laser_only", "goal_options")
#: The bits of ``goal_options``: ``td_require_target`` and ``silent_goal_maps_out``.
REQUIRE_TARGET, SILENT_MAPS_OUT = 1, 2


def goal_options(config) -> int:
    """The top-down maps' options of an ``AttentionConfig`` as the kernels take them: the
    bits ``REQUIRE_TARGET`` (``td_require_target``) and ``SILENT_MAPS_OUT``
    (``silent_goal_maps_out``)."""
    return REQUIRE_TARGET * bool(config.td_require_target) | SILENT_MAPS_OUT * bool(config.silent_goal_maps_out)


#: The constant fields: per-channel limits (2, 188) m, maximum ranges (188,) m, the
#: lateral spread (J, J), the course parameters (16,), beam and front-sonar cosines and
#: sines, the tracker's parameter vector (25,), the float scalars; then the integer ones:
#: each beam's region (180,), the sonar cones' beam bounds (8, 2), the integer scalars.
CONSTANT_FIELDS = (
    "limits",
    "max_ranges",
    "spread",
    "course_params",
    "beam_cos",
    "beam_sin",
    "sonar_cos",
    "sonar_sin",
    "tracker_params",
    "float_scalars",
    "beam_region",
    "cone_bounds",
    "int_scalars",
)
#: The columns of a step's input row (float64; flags as 0.0 / 1.0): time (s), time since
#: the previous step (s), ego-motion applies, store the readings, odometry linear (m/s) and
#: angular (rad/s), new laser scan, new sonar scan.
STEP_COLUMNS = ("t", "dt", "moved", "push", "linear", "angular", "laser_new", "sonar_new")

#: Buffer kinds of a table row: the state's floats, integers and flags, the constants'
#: floats and integers.
FLOAT, INT, FLAG, CONSTANT_FLOAT, CONSTANT_INT = range(5)
#: Columns of the layout's table: kind, offset in its buffer, then up to 3 dimensions
#: (1 where the array has fewer).
KIND, OFFSET, DIMS = 0, 1, 2
_MAX_DIMS = 3
_STATE_KINDS = {np.dtype(np.float64): FLOAT, np.dtype(np.int64): INT, np.dtype(np.bool_): FLAG}
_BUFFER_DTYPES = (np.float64, np.int64, np.uint8)


class StateLayout:
    """Where each state and constant field lies in its buffer (one per configuration and
    course capacity; models with the same layout can share a batch).

    Args:
        shapes: every name of ``STATE_FIELDS`` to its ``(dtype, shape)`` (float64, int64 or
            bool; at most 3 dimensions).
        constants: every name of ``CONSTANT_FIELDS`` to its array (float64 up to
            ``tracker_params`` and ``float_scalars``, int64 after).

    Attributes:
        table: ``(len(STATE_FIELDS) + len(CONSTANT_FIELDS), 5)`` int64, read-only: per
            field its kind, offset and dimensions (see ``KIND``, ``OFFSET``, ``DIMS``).
        constant_floats, constant_ints: the constants' buffers, read-only.
        sizes: entries per model in the float, integer and flag buffers.
        course_capacity: rows of the course arrays.
    """

    def __init__(self, shapes: Mapping[str, tuple[np.dtype, tuple[int, ...]]], constants: Mapping[str, np.ndarray]):
        if set(shapes) != set(STATE_FIELDS) or set(constants) != set(CONSTANT_FIELDS):
            raise ValueError("a state layout takes every state field and every constant field, by name")
        table = np.zeros((len(STATE_FIELDS) + len(CONSTANT_FIELDS), DIMS + _MAX_DIMS), np.int64)
        ends = [0] * 5
        self.shapes: dict[str, tuple[np.dtype, tuple[int, ...]]] = {}
        for k, name in enumerate(STATE_FIELDS):
            dtype, shape = np.dtype(shapes[name][0]), tuple(shapes[name][1])
            self._place(table, k, ends, _STATE_KINDS[dtype], shape)
            self.shapes[name] = (dtype, shape)
        constant_floats, constant_ints = [], []
        for k, name in enumerate(CONSTANT_FIELDS, len(STATE_FIELDS)):
            value = np.asarray(constants[name])
            kind = CONSTANT_INT if value.dtype.kind in "iub" else CONSTANT_FLOAT
            self._place(table, k, ends, kind, value.shape)
            (constant_ints if kind == CONSTANT_INT else constant_floats).append(value.ravel())
        self.table = _read_only(table)
        self.constant_floats = _read_only(np.concatenate(constant_floats).astype(np.float64))
        self.constant_ints = _read_only(np.concatenate(constant_ints).astype(np.int64))
        self.sizes = tuple(ends[:3])
        self.course_capacity = self.shapes["bu_regions"][1][0]
        self._slices = {name: (int(table[k, KIND]), int(table[k, OFFSET])) for k, name in enumerate(STATE_FIELDS)}

    @staticmethod
    def _place(table: np.ndarray, k: int, ends: list[int], kind: int, shape: tuple[int, ...]) -> None:
        if len(shape) > _MAX_DIMS:
            raise ValueError(f"a record field has at most {_MAX_DIMS} dimensions, got shape {shape}")
        table[k, KIND], table[k, OFFSET] = kind, ends[kind]
        table[k, DIMS : DIMS + _MAX_DIMS] = (*shape, *(1,) * (_MAX_DIMS - len(shape)))
        ends[kind] += math.prod(shape)

    def fits(self, other: StateLayout) -> bool:
        """Whether a state of layout ``other`` can be loaded into one of this layout: the same
        fields and constants, and at least as many course rows."""
        if other is self:
            return True
        if self.course_capacity < other.course_capacity:
            return False
        for name in STATE_FIELDS:
            (dtype, shape), (other_dtype, other_shape) = self.shapes[name], other.shapes[name]
            rows = name in COURSE_FIELDS[:4]
            if dtype != other_dtype or (shape[1:] if rows else shape) != (other_shape[1:] if rows else other_shape):
                return False
        return np.array_equal(self.constant_floats, other.constant_floats) and np.array_equal(
            self.constant_ints, other.constant_ints
        )

    def allocate(self, n_models: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Zeroed float64, int64 and uint8 buffers ``(n_models, size)`` for ``n_models`` states."""
        return tuple(np.zeros((n_models, size), dtype) for size, dtype in zip(self.sizes, _BUFFER_DTYPES))

    def view(self, buffers: tuple[np.ndarray, np.ndarray, np.ndarray], name: str) -> np.ndarray:
        """The field ``name`` of ``STATE_FIELDS`` in a state's ``buffers`` (each ``(1, size)``),
        as a view of its shape and dtype."""
        kind, offset = self._slices[name]
        dtype, shape = self.shapes[name]
        flat = buffers[kind][0, offset : offset + math.prod(shape)]
        return (flat.view(np.bool_) if kind == FLAG else flat).reshape(shape)


class ModelState:
    """One model's per-step state: the fields of ``STATE_FIELDS`` in three flat buffers.

    Args:
        layout: where each field lies.
        buffers: float64, int64 and uint8 arrays ``(1, size)`` (``layout.sizes``), C-contiguous;
            a fresh zeroed set when None. A batch passes rows ``[i : i + 1]`` of its own
            ``(N, size)`` buffers.

    ``field(name)`` is a view: writing it writes the state. ``holds(array)`` tells whether
    an array is a view of these buffers (a model's arrays stop being so when they are
    replaced: a copy, an unpickled model, a course book that grew).
    """

    def __init__(self, layout: StateLayout, buffers: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None):
        if buffers is None:
            buffers = layout.allocate(1)
        for buffer, size, dtype in zip(buffers, layout.sizes, _BUFFER_DTYPES):
            if buffer.shape != (1, size) or buffer.dtype != dtype or not buffer.flags.c_contiguous:
                raise ValueError(
                    f"state buffers must be C-contiguous {[np.dtype(d).name for d in _BUFFER_DTYPES]} arrays of "
                    f"shapes {[(1, s) for s in layout.sizes]}, got {buffer.dtype} {buffer.shape}"
                )
        self.layout = layout
        self.floats, self.ints, self.flags = buffers
        # the arrays that own the buffers' memory: every view of them has one of these as base
        self._owners = tuple(b if b.base is None else b.base for b in buffers)

    def field(self, name: str) -> np.ndarray:
        """The state field ``name`` (one of ``STATE_FIELDS``), a view."""
        return self.layout.view((self.floats, self.ints, self.flags), name)

    def holds(self, array: np.ndarray) -> bool:
        """Whether ``array`` is a view of one of this state's buffers (or of the batch
        buffers they are rows of)."""
        base, (floats, ints, flags) = array.base, self._owners
        return base is not None and (base is floats or base is ints or base is flags)

    def __getstate__(self) -> dict:
        """Pickled without the owners of the buffers (a batch's whole buffers)."""
        state = vars(self).copy()
        del state["_owners"]
        return state

    def __setstate__(self, state: dict) -> None:
        vars(self).update(state)
        self._owners = tuple(b if b.base is None else b.base for b in (self.floats, self.ints, self.flags))

    def load(self, arrays: Mapping[str, np.ndarray]) -> None:
        """Copy ``arrays`` (every state field by name) into the state; a course array may be
        shorter than the layout's capacity (its first rows are filled)."""
        for name in STATE_FIELDS:
            value = arrays[name]
            self.field(name)[: value.shape[0]] = value


def _read_only(array: np.ndarray) -> np.ndarray:
    array.flags.writeable = False
    return array


#: The outputs of one step, with their dtype and shape (J the regions); first those an
#: ``AttentionOutput`` keeps: clipped readings, echo flags, range rates (188,); the
#: tracker's slot behind each front sonar (8,); F (6, J); C_BU, C_TD, C, region speeds,
#: distances, nearest readings (J,); origins, directions (J,) int8; goal flags (J,); M, L;
#: then the channels' speeds and moving flags (188,), and the tracker's probability that
#: the speed goal holds at each front sonar's track (8,; −1 where not judged so).
OUTPUT_ARRAYS = (
    ("readings", np.float64, "channels"),
    ("valid", np.bool_, "channels"),
    ("rates", np.float64, "channels"),
    ("region_slot", np.int64, "sonars"),
    ("F", np.float64, "maps"),
    ("C_BU", np.float64, "regions"),
    ("C_TD", np.float64, "regions"),
    ("C", np.float64, "regions"),
    ("region_speed", np.float64, "regions"),
    ("distances", np.float64, "regions"),
    ("nearest", np.float64, "regions"),
    ("origins", np.int8, "regions"),
    ("directions", np.int8, "regions"),
    ("fulfilled", np.bool_, "regions"),
    ("M", np.float64, "regions"),
    ("L", np.float64, "regions"),
    ("speeds", np.float64, "channels"),
    ("moving", np.bool_, "channels"),
    ("speed_probability", np.float64, "sonars"),
)
#: How many of ``OUTPUT_ARRAYS`` an ``AttentionOutput`` keeps (the first ones).
KEPT_OUTPUTS = 16


#: The results of a step in a record's ``results`` (float64, exact for the integers): the
#: winner ``argmax L``, the focus (the winner when ``L[winner]`` reaches the threshold, else
#: −1), the saliency ``L[winner]``, whether a course started (1.0), the winner's origin (1.0
#: top-down) and the number of track rows written.
RESULTS = ("winner", "focus", "saliency", "fired", "top_down", "n_tracks")


def output_dtype(n_regions: int, n_channels: int, n_sonars: int) -> np.dtype:
    """The record of one model's step: ``OUTPUT_ARRAYS`` (bool ones as uint8) and
    ``results`` ``(len(RESULTS),)``."""
    shapes = {"channels": (n_channels,), "sonars": (n_sonars,), "maps": (6, n_regions), "regions": (n_regions,)}
    fields = [(name, np.uint8 if dtype is np.bool_ else dtype, shapes[kind]) for name, dtype, kind in OUTPUT_ARRAYS]
    return np.dtype([*fields, ("results", np.float64, (len(RESULTS),))], align=True)
