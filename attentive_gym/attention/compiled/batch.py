"""``ModelBatch``: attentional models of one configuration, stepped together in one compiled call.

A batch holds its models' states (``records.ModelState``) as rows of three ``(N, size)``
buffers and hands each model its rows through the model's public seam,
``AttentionModel.bind_state``; the model's arrays are views of them, so a model stays a
whole ``AttentionModel``: its ``reset``, ``set_goals`` or a lone ``step`` act on the batch's
rows. ``ModelBatch.step`` checks every model's reading (``ValueError`` as
``AttentionModel.step`` raises it, before any model changes), then runs
``step_kernels.attend_many`` for the stepped models in one parallel call, and returns
each model's ``AttentionOutput`` (views of one ``(n,)`` output record): the same numbers
as each model's ``step``, bit for bit (every model's arithmetic is its own).

A model whose state is no longer the batch's rows (``AttentionModel.model_state``: a
course book that grew, a copy, an unpickled batch) is bound again at its next step. Only
the sonar grid is batched (the laser grid computes F1–F3 in numpy).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from attentive_gym.attention.compiled.records import ModelState, output_dtype
from attentive_gym.attention.compiled.step_kernels import N_CHANNELS, attend_many
from attentive_gym.attention.model import AttentionModel, AttentionOutput, outputs_of_records
from attentive_gym.attention.regions import FRONT_SONARS

__all__ = ["ModelBatch", "batching_problem"]


class ModelBatch:
    """Models of one configuration on the sonar grid, stepped as one.

    Args:
        models: the models (at least one, distinct); their state moves into the batch.

    Raises:
        ValueError: for no model, a repeated model, models with different configurations,
            or a model on the laser grid.
    """

    def __init__(self, models: Sequence[AttentionModel]) -> None:
        models = list(models)
        problem = batching_problem(models)
        if problem is not None:
            raise ValueError(problem)
        self.models = models
        self.config = models[0].config
        self._record_dtype = output_dtype(models[0].grid.n_regions, N_CHANNELS, FRONT_SONARS)
        self._bind_all()

    def __len__(self) -> int:
        return len(self.models)

    # --- state ---------------------------------------------------------------------------
    def _bind_all(self) -> None:
        """Fresh buffers for every model's state, with the largest course capacity of any
        model, each model bound to its rows."""
        layouts = [model.model_state.layout for model in self.models]
        layout = max(layouts, key=lambda candidate: candidate.course_capacity)
        self._layout = layout
        self._buffers = layout.allocate(len(self.models))
        self._states = [
            ModelState(layout, tuple(buffer[i : i + 1] for buffer in self._buffers)) for i in range(len(self.models))
        ]
        for model, state in zip(self.models, self._states):
            model.bind_state(state)

    def _bind_moved(self, members: Sequence[int]) -> None:
        """Bind again the models ``members`` whose state is no longer their rows (all models,
        in new buffers, when one needs more course room or the layout changed)."""
        moved = [i for i in members if self.models[i].model_state is not self._states[i]]
        if not moved:
            return
        if any(self.models[i].model_state.layout is not self._layout for i in moved):
            self._bind_all()
            return
        for i in moved:
            self.models[i].bind_state(self._states[i])

    # --- stepping --------------------------------------------------------------------------
    def step(self, readings: Sequence[tuple], members: Sequence[int] | None = None) -> list[AttentionOutput]:
        """Step the models ``members`` (default: all, in order) on their readings.

        Args:
            readings: one ``(t, sonar, laser, odometry, sonar_time_s, laser_time_s)`` per
                stepped model, as ``AttentionModel.step`` takes them.
            members: the indices of the models to step, each at most once.

        Returns:
            The stepped models' ``AttentionOutput``, in the order of ``members``; each model
            has advanced as its own ``step`` would advance it.

        Raises:
            ValueError: for readings that do not match ``members``, or as
                ``AttentionModel.step`` raises it for a model's reading, the message
                prefixed with the model's index ("model 3: ..."); no model changes then.
        """
        members = range(len(self.models)) if members is None else members
        if len(readings) != len(members):
            raise ValueError(f"{len(members)} models to step take {len(members)} readings, got {len(readings)}")
        if len(set(members)) != len(members) or not all(0 <= i < len(self.models) for i in members):
            raise ValueError(f"members must be distinct indices in [0, {len(self.models)}), got {list(members)}")
        models = [self.models[i] for i in members]
        checked = []
        for i, model, reading in zip(members, models, readings):
            try:
                checked.append(model._checked(*reading))
            except ValueError as error:
                raise ValueError(f"model {i}: {error}") from None
        self._bind_moved(members)
        steps = [model._advance(*inputs) for model, inputs in zip(models, checked)]
        if not steps:
            return []
        records = np.empty(len(models), self._record_dtype)
        layout = self._layout
        attend_many(
            np.asarray(members, np.int64),
            layout.table,
            layout.constant_floats,
            layout.constant_ints,
            *self._buffers,
            np.array(steps, np.float64),
            records,
        )
        return outputs_of_records(records, models, [step[0] for step in steps])


def batching_problem(models: Sequence[AttentionModel]) -> str | None:
    """Why ``models`` cannot form a ``ModelBatch`` (the message of its ``ValueError``), None
    when they can."""
    if not models:
        return "a model batch needs at least one model"
    if len({id(m) for m in models}) != len(models):
        return "a model batch takes each model once"
    for i, model in enumerate(models):
        if not isinstance(model, AttentionModel):
            return f"model {i} is a {type(model).__name__}, not an AttentionModel"
        if model.config != models[0].config:
            return f"model {i}'s configuration differs from model 0's; a batch shares one configuration"
    if models[0].grid.is_laser:
        return "only models on the sonar grid can be batched (AttentionConfig(grid='sonar'))"
    return None
