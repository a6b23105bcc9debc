"""``ModelBatch``: attentional models of one configuration, stepped together in one compiled call.

A batch holds its models' state (sensorial memory, courses, tracker) as arrays with a
leading model axis, and each model's own arrays become views of its row, so a model
stays a whole ``AttentionModel``: its ``reset``, ``set_goals`` or a lone ``step`` act on the
batch's rows. ``ModelBatch.step`` checks every model's reading (``ValueError`` as
``AttentionModel.step`` raises it, before any model changes), then runs
``step_kernels.attend_one`` for every model in one parallel call (``attend_many``), and
returns each model's ``AttentionOutput``: the same numbers as each model's ``step``, bit
for bit (every model's arithmetic is its own).

A model whose arrays stop being views of the batch (a course book that grew, a copy, an
unpickled batch) is taken back in at the next step. Only the sonar grid is batched (the
laser grid computes F1–F3 in numpy).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numba import njit, prange

from attentive_gym.attention.compiled.step_kernels import attend_one, new_output_arrays
from attentive_gym.attention.model import AttentionModel, AttentionOutput
from attentive_gym.attention.tracking.tracker import STATE_FIELDS

__all__ = ["ModelBatch", "attend_many", "batching_problem"]

#: The state arrays of a model that a batch holds, by owner: the model itself (its input
#: row and ego-motion change), its sensorial memory, its course book and its tracker.
_MODEL_FIELDS = ("_row", "_ego")
_MEMORY_FIELDS = ("_state", "_times", "_samples", "_ego_offset")
_COURSE_FIELDS = ("_bu_regions", "_bu_starts", "_td_regions", "_td_times", "_counts")
_GROWING_COURSE_FIELDS = _COURSE_FIELDS[:4]  # (capacity, ...) arrays


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
        config = models[0].config
        self.models = models
        self.config = config
        self._tracked = models[0]._tracker is not None
        self._arrays: dict[str, np.ndarray] = {}
        self._take_in(range(len(models)))

    def __len__(self) -> int:
        return len(self.models)

    # --- state ---------------------------------------------------------------------------
    def _owners(self, model: AttentionModel) -> tuple[tuple[object, tuple[str, ...]], ...]:
        """``(object, attribute names)`` of every state array of ``model``."""
        owners = ((model, _MODEL_FIELDS), (model._memory, _MEMORY_FIELDS), (model._courses, _COURSE_FIELDS))
        return owners + (((model._tracker, STATE_FIELDS),) if self._tracked else ())

    def _take_in(self, indices) -> None:
        """Copy the state of the models ``indices`` into the batch (allocating it, or growing
        the courses' capacity, when needed) and make their arrays views of their rows."""
        capacity = max(m._courses._bu_regions.shape[0] for m in self.models)
        if not self._arrays or capacity > self._arrays["_bu_regions"].shape[1]:
            self._allocate(capacity)
            indices = range(len(self.models))
        for i in indices:
            for owner, names in self._owners(self.models[i]):
                for name in names:
                    value = getattr(owner, name)
                    row = self._arrays[name][i]
                    row[: value.shape[0]] = value
                    setattr(owner, name, row)
            self.models[i]._gather_kernel_arrays()

    def _allocate(self, capacity: int) -> None:
        """Fresh batched arrays, the courses with room for ``capacity`` of each kind."""
        n = len(self.models)
        arrays = {}
        for owner, names in self._owners(self.models[0]):
            for name in names:
                value = getattr(owner, name)
                shape = value.shape
                if name in _GROWING_COURSE_FIELDS:
                    shape = (capacity, *shape[1:])
                arrays[name] = np.zeros((n, *shape), value.dtype)
        self._arrays = arrays

    def _detached(self) -> list[int]:
        """The models whose arrays are no longer views of the batch (each owner's first array
        tells: an owner's arrays are taken in and replaced together). Written out rather than
        looped over ``_owners``: it runs every step, for every model."""
        arrays = self._arrays
        row, memory, courses = arrays[_MODEL_FIELDS[0]], arrays[_MEMORY_FIELDS[0]], arrays[_COURSE_FIELDS[0]]
        tracker = arrays[STATE_FIELDS[0]] if self._tracked else None
        return [
            i
            for i, model in enumerate(self.models)
            if getattr(model, _MODEL_FIELDS[0]).base is not row
            or getattr(model._memory, _MEMORY_FIELDS[0]).base is not memory
            or getattr(model._courses, _COURSE_FIELDS[0]).base is not courses
            or (tracker is not None and getattr(model._tracker, STATE_FIELDS[0]).base is not tracker)
        ]

    def _make_course_room(self) -> None:
        """Room for one more course of each kind in every model (the kernel cannot grow arrays)."""
        counts, capacity = self._arrays["_counts"], self._arrays["_bu_regions"].shape[1]
        if counts.max() >= capacity:
            for model in self.models:
                model._courses.reserve()  # the models that are full grow: the batch follows
            self._take_in(range(len(self.models)))

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
                ``AttentionModel.step`` raises it for any model's reading; no model changes
                then.
        """
        members = range(len(self.models)) if members is None else members
        if len(readings) != len(members):
            raise ValueError(f"{len(members)} models to step take {len(members)} readings, got {len(readings)}")
        if len(set(members)) != len(members) or not all(0 <= i < len(self.models) for i in members):
            raise ValueError(f"members must be distinct indices in [0, {len(self.models)}), got {list(members)}")
        models = [self.models[i] for i in members]
        detached = self._detached()
        if detached:
            self._take_in(detached)
        checked = [model._checked(*reading) for model, reading in zip(models, readings)]
        self._make_course_room()
        steps = [model._advance(*inputs) for model, inputs in zip(models, checked)]
        if not steps:
            return []
        (t, dt, moved, push, linear, angular, laser_new, sonar_new) = (np.array(column) for column in zip(*steps))
        first = self.models[0]
        cfg = self.config
        arrays = self._arrays
        if self._tracked:
            state = tuple(arrays[name] for name in STATE_FIELDS)
        else:  # an idle tracker's arrays, as a batch of one
            state = tuple(array[None] for array in first._tracker_state)
        outputs = new_output_arrays(first.grid.n_regions, (len(models),))
        winners = np.empty(len(models), np.int64)
        fired = np.empty(len(models), np.bool_)
        n_tracks = np.empty(len(models), np.int64)
        attend_many(
            np.asarray(members, np.int64),
            arrays["_row"],
            first._limits,
            arrays["_state"],
            arrays["_times"],
            arrays["_samples"],
            arrays["_ego_offset"],
            t,
            dt,
            first._slope_samples,
            arrays["_ego"],
            moved,
            push,
            self._tracked,
            linear,
            angular,
            laser_new,
            sonar_new,
            np.array([m._wanted_speed for m in models]),
            *first._tracker_constants,
            *state,
            first._max_ranges,
            cfg.max_distance_m,
            cfg.laser_only,
            cfg.laser_max_range_m,
            np.array([m._active for m in models]),
            np.array([m._goal_plan for m in models]),
            cfg.td_require_target,
            np.array([m._combine for m in models]),
            np.array([m._gain for m in models]),
            cfg.threshold,
            first._spread,
            first._courses.params,
            arrays["_bu_regions"],
            arrays["_bu_starts"],
            arrays["_td_regions"],
            arrays["_td_times"],
            arrays["_counts"],
            *outputs,
            winners,
            fired,
            n_tracks,
        )
        # zip over the batched arrays hands out each model's row views (faster than indexing each)
        return [
            model._output(step[0], arrays, winner, was_fired, count)
            for model, step, arrays, winner, was_fired, count in zip(
                models, steps, zip(*outputs), winners.tolist(), fired.tolist(), n_tracks.tolist()
            )
        ]


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


@njit(cache=True, parallel=True)
def attend_many(
    members,
    rows,
    limits,
    state,
    times,
    samples,
    ego_offset,
    t,
    dt,
    slope_samples,
    ego_change,
    moved,
    push,
    tracked,
    linear,
    angular,
    laser_new,
    sonar_new,
    wanted_speed,
    beam_cos,
    beam_sin,
    sonar_cos,
    sonar_sin,
    beam_step_rad,
    tracker_params,
    confirm_hits,
    max_speed,
    epsilon,
    beam_region,
    cone_bounds,
    match_m,
    match_sigmas,
    noise_rel,
    noise_floor_m,
    pose,
    odometry,
    sonar_pose,
    bounds,
    segments,
    cv_x,
    cv_P,
    static_x,
    static_P,
    p_moving,
    alive,
    ids,
    hits,
    misses,
    born_s,
    filter_t,
    seen_s,
    extent_m,
    segment_of,
    counters,
    sonar_x,
    sonar_P,
    sonar_hits,
    sonar_t,
    track_rows,
    track_covariance,
    max_ranges,
    max_distance,
    laser_only,
    laser_max,
    active,
    goal_plan,
    require_target,
    combine,
    gain,
    threshold,
    spread,
    course_params,
    bu_regions,
    bu_starts,
    td_regions,
    td_times,
    counts,
    readings,
    valid,
    rates,
    speeds,
    moving,
    region_slot,
    F,
    C_BU,
    C_TD,
    C,
    region_speed,
    distances,
    nearest,
    origins,
    directions,
    fulfilled,
    M,
    L,
    winners,
    fired,
    n_tracks,
):
    """``attend_one`` for the models ``members`` ``(n,)`` of a batch, in parallel over them.

    Its arguments are ``attend_one``'s, with a leading axis:

    - the models' state (input rows ``(N, 196)``, of which ``attend_one`` takes the first
      188 channels; the memory, ego-motion change, tracker and course arrays) over all N
      models of the batch, indexed by ``members``;
    - the step's inputs (times, flags, odometry, the goal's arrays, the gain) and the
      outputs over the n stepped models, in the order of ``members``;
    - none for the configuration's constants: ``limits``, ``slope_samples``, ``tracked``, the
      tracker's constants, ``max_ranges``, ``max_distance``, ``laser_only``, ``laser_max``,
      ``require_target``, ``threshold``, ``spread`` and ``course_params``.

    When ``tracked`` is False the tracker's state is one idle tracker's, with a model axis
    of length 1. Writes each stepped model's results into ``winners``, ``fired`` and
    ``n_tracks`` ``(n,)``.
    """
    n_channels = readings.shape[1]
    for j in prange(members.shape[0]):
        i = members[j]
        k = i if tracked else np.int64(0)  # the idle tracker's row: never written
        winners[j], fired[j], n_tracks[j] = attend_one(
            rows[i][:n_channels],
            limits,
            state[i],
            times[i],
            samples[i],
            ego_offset[i],
            t[j],
            dt[j],
            slope_samples,
            ego_change[i],
            moved[j],
            push[j],
            tracked,
            linear[j],
            angular[j],
            laser_new[j],
            sonar_new[j],
            wanted_speed[j],
            beam_cos,
            beam_sin,
            sonar_cos,
            sonar_sin,
            beam_step_rad,
            tracker_params,
            confirm_hits,
            max_speed,
            epsilon,
            beam_region,
            cone_bounds,
            match_m,
            match_sigmas,
            noise_rel,
            noise_floor_m,
            pose[k],
            odometry[k],
            sonar_pose[k],
            bounds[k],
            segments[k],
            cv_x[k],
            cv_P[k],
            static_x[k],
            static_P[k],
            p_moving[k],
            alive[k],
            ids[k],
            hits[k],
            misses[k],
            born_s[k],
            filter_t[k],
            seen_s[k],
            extent_m[k],
            segment_of[k],
            counters[k],
            sonar_x[k],
            sonar_P[k],
            sonar_hits[k],
            sonar_t[k],
            track_rows[k],
            track_covariance[k],
            max_ranges,
            max_distance,
            laser_only,
            laser_max,
            active[j],
            goal_plan[j],
            require_target,
            combine[j],
            gain[j],
            threshold,
            spread,
            course_params,
            bu_regions[i],
            bu_starts[i],
            td_regions[i],
            td_times[i],
            counts[i],
            readings[j],
            valid[j],
            rates[j],
            speeds[j],
            moving[j],
            region_slot[j],
            F[j],
            C_BU[j],
            C_TD[j],
            C[j],
            region_speed[j],
            distances[j],
            nearest[j],
            origins[j],
            directions[j],
            fulfilled[j],
            M[j],
            L[j],
        )
