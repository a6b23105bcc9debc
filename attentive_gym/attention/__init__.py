"""The attentional model as a standalone library: numpy arrays and numba-compiled kernels,
no gymnasium, no pymunk.

- ``AttentionModel`` / ``AttentionConfig`` / ``AttentionOutput`` / ``FocusView``: the
  model of docs/model.md, stepped with timestamped (seconds) sonar and laser readings (metres).
- ``ModelBatch``: many models of one configuration stepped in one parallel compiled call
  (what the vector envs use), with the numbers each model's own ``step`` gives.
- ``Goal`` and friends: top-down goals over speed, direction and distance.
- ``TraceRecorder`` / ``load_trace`` / ``Trace``: record a run to ``.npz`` and read it back.
- ``load_log`` / ``replay_log`` / ``SensorLog``: replay readings logged from a robot.

Its parts:

- the model (docs/model.md §1–§8 and §11), in this package's top modules: ``config``, ``regions``,
  ``memory`` (sensorial memory), ``kinematics`` (the window and literal modes),
  ``features`` and ``goals``, ``attentional_map``, ``working_memory``, ``model`` (the
  ``AttentionModel`` that steps them) and ``_numerics`` (the compiled arithmetic they share);
- ``tracking``: the tracker of the ``tracker`` mode (§10): segmentation, association,
  Kalman filters, and the tracks' regions;
- ``compiled``: a whole step as compiled kernels (``step_kernels``) over the records of
  ``records`` (the model's state in flat buffers, ``ModelState``), and ``batch``
  (``ModelBatch``) for many models at once;
- ``io``: sensor logs and their replay (``sensor_log``, ``replay``), ROS bags
  (``rosbag``, ``ros_readings``) and recorded traces (``trace``).

The modules of ``tracking``, ``compiled`` and ``io`` were once flat in this package; their
old paths (``attentive_gym.attention.tracker``, ...) still import, with a
``DeprecationWarning`` (``_moved``).

Example:
    >>> import numpy as np
    >>> from attentive_gym.attention import AttentionModel, Goal
    >>> model = AttentionModel()
    >>> model.set_goals(Goal.direction_is("towards"))
    >>> model.set_weights({"F1": 1.0, "goal_direction": 2.0})
    >>> out = model.step(0.0, np.full(16, 5.0), np.full(180, 20.0))
    >>> out.F.shape, out.focus
    ((6, 8), None)
"""

import importlib as _importlib
from types import ModuleType as _ModuleType

from attentive_gym.attention import _moved
from attentive_gym.attention.compiled.batch import ModelBatch
from attentive_gym.attention.config import (
    ATTENTIVE_STATES,
    LASER_PROFILES,
    MAP_ALIASES,
    MAP_NAMES,
    MODEL_VERSIONS,
    VERSION_0_FIELDS,
    VERSION_1_FIELDS,
    VERSION_2_FIELDS,
    AttentionConfig,
    check_model_version,
    parse_state,
    profile_config,
    version_fields,
)
from attentive_gym.attention.goals import Direction, Feature, Goal, Relation
from attentive_gym.attention.io.replay import load_log, parse_goal, parse_maps, replay_log
from attentive_gym.attention.io.sensor_log import SensorLog
from attentive_gym.attention.io.trace import Trace, TraceRecorder, load_trace
from attentive_gym.attention.model import (
    ORIGIN_BOTTOM_UP,
    ORIGIN_CODES,
    ORIGIN_TOP_DOWN,
    AttentionModel,
    AttentionOutput,
    FocusView,
)
from attentive_gym.attention.regions import Grid

_moved.install()  # the library's own modules import the new paths only

__all__ = [
    "ATTENTIVE_STATES",
    "LASER_PROFILES",
    "MAP_ALIASES",
    "MAP_NAMES",
    "MODEL_VERSIONS",
    "VERSION_0_FIELDS",
    "VERSION_1_FIELDS",
    "VERSION_2_FIELDS",
    "version_fields",
    "AttentionConfig",
    "check_model_version",
    "AttentionModel",
    "AttentionOutput",
    "Direction",
    "Feature",
    "FocusView",
    "Goal",
    "Grid",
    "ModelBatch",
    "ORIGIN_BOTTOM_UP",
    "ORIGIN_CODES",
    "ORIGIN_TOP_DOWN",
    "Relation",
    "SensorLog",
    "Trace",
    "TraceRecorder",
    "load_log",
    "load_trace",
    "parse_goal",
    "parse_maps",
    "parse_state",
    "profile_config",
    "replay_log",
]


def __getattr__(name: str) -> _ModuleType:
    """An old module path read as an attribute (``attentive_gym.attention.tracker``): imported
    through ``_moved``'s finder, which warns once and binds the moved module here."""
    if f"{__name__}.{name}" in _moved.MOVED:
        return _importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
