"""The attentional model as a standalone library: numpy arrays and numba-compiled kernels,
no gymnasium, no pymunk.

- ``AttentionModel`` / ``AttentionConfig`` / ``AttentionOutput`` / ``FocusView``: the
  model of docs/model.md, stepped with timestamped (seconds) sonar and laser readings (metres).
- ``ModelBatch``: many models of one configuration stepped in one parallel compiled call
  (what the vector envs use), with the numbers each model's own ``step`` gives.
- ``Goal`` and friends: top-down goals over speed, direction and distance.
- ``TraceRecorder`` / ``load_trace`` / ``Trace``: record a run to ``.npz`` and read it back.
- ``load_log`` / ``replay_log`` / ``SensorLog``: replay readings logged from a robot.

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

from attentive_gym.attention.config import (
    ATTENTIVE_STATES,
    MAP_ALIASES,
    MAP_NAMES,
    AttentionConfig,
    parse_state,
)
from attentive_gym.attention.goals import Direction, Feature, Goal, Relation
from attentive_gym.attention.model import (
    ORIGIN_BOTTOM_UP,
    ORIGIN_CODES,
    ORIGIN_TOP_DOWN,
    AttentionModel,
    AttentionOutput,
    FocusView,
)
from attentive_gym.attention.batch import ModelBatch
from attentive_gym.attention.regions import Grid
from attentive_gym.attention.replay import SensorLog, load_log, parse_goal, parse_maps, replay_log
from attentive_gym.attention.trace import Trace, TraceRecorder, load_trace

__all__ = [
    "ATTENTIVE_STATES",
    "MAP_ALIASES",
    "MAP_NAMES",
    "AttentionConfig",
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
    "replay_log",
]
