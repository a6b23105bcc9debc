"""The compiled kernels of one attentional-model step (docs/model.md §2–§8).

A step is: ``load_row`` (input check), ``AttentionModel._ego_change`` (kinematics.scan_points,
numpy's arctan2, kinematics.ego_range_change) when the robot moved in the window modes, then
``attend_one`` on the sonar grid: ``sense`` (§2–§3), the tracker's ``track_step`` (§10) or
``window_kinematics``, ``sonar_grid_maps`` (§4–§6) and ``select`` (§7–§8: the courses of
``attentional_map`` and ``saliency``). On the laser grid the model calls ``sense``, the
tracker, numpy's F1–F3, ``goal_maps`` and ``select`` one by one.

``attend_many`` is the sonar grid's step for any number of models, one included: it takes
the models' state buffers, the layout's table and constants, the step's inputs and the
output records (``records``), and runs ``attend_record`` (``attend_one`` over one model's
rows) for each, in parallel over the models.

The kernels repeat the arithmetic of the numpy expressions they replace (features.py,
kinematics.py, memory.py) operation for operation, with sums in numpy's pairwise order and
matrix products in BLAS's order (see ``_numerics``), so a step gives the same floats.
Outputs are records allocated per step by the caller (users keep them).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from attentive_gym.attention._numerics import interp, pairwise_sum, shaped, vecmat
from attentive_gym.attention.attentional_map import (
    add_course,
    bottom_up_running,
    course_gains,
    release_courses,
    top_down_holding,
)
from attentive_gym.attention.compiled.records import (
    CONSTANT_FIELDS,
    DIMS,
    FLOAT_SCALARS,
    INT_SCALARS,
    OFFSET,
    REQUIRE_TARGET,
    RESULTS,
    SILENT_MAPS_OUT,
    STATE_FIELDS,
)
from attentive_gym.attention.features import goal_knots
from attentive_gym.attention.goals import Feature, Goal, Relation
from attentive_gym.attention.memory import push_sample, slope_rates
from attentive_gym.attention.regions import FRONT_SONARS, LASER_BEAMS
from attentive_gym.attention.tracking.tracker import STATE_FIELDS as TRACKER_FIELDS
from attentive_gym.attention.tracking.tracker import track_step

#: Columns of the goal plan, one row per top-down map (F4, F5, F6): the goal's kind
#: (``_INACTIVE`` for an inactive map), its bounds and tolerance, and the knots of its
#: graded table (``features.goal_knots``, at most 4).
_KIND, _LO, _HI, _TOLERANCE, _N_KNOTS, _XP, _FP, PLAN_COLUMNS = 0, 1, 2, 3, 4, 5, 9, 13
_INACTIVE, _EQUAL, _BETWEEN, _GREATER, _SMALLER, _DIRECTION = 0, 1, 2, 3, 4, 5

#: Kinds of goal (the first column of a goal plan row) by relation.
_KIND_OF_RELATION = {
    Relation.EQUAL: _EQUAL,
    Relation.BETWEEN: _BETWEEN,
    Relation.GREATER: _GREATER,
    Relation.SMALLER: _SMALLER,
}


def fulfilling_range(goal: Goal) -> tuple[float, float]:
    """The values ``[lo, hi]`` that fulfil a speed or distance goal (``Goal.is_fulfilled``)."""
    if goal.relation is Relation.EQUAL:
        return goal.lo - goal.tolerance, goal.lo + goal.tolerance
    if goal.relation is Relation.BETWEEN:
        return goal.lo, goal.hi
    if goal.relation is Relation.GREATER:
        return goal.lo, math.inf
    return -math.inf, goal.lo  # SMALLER


def goal_plan_row(goal: Goal, max_value: float | None) -> np.ndarray:
    """The goal plan row of an active top-down map (see ``PLAN_COLUMNS``)."""
    row = np.zeros(PLAN_COLUMNS)
    if goal.feature is Feature.DIRECTION:
        row[_KIND], row[_LO] = _DIRECTION, float(goal.direction)
        return row
    row[_KIND] = _KIND_OF_RELATION[goal.relation]
    row[_LO], row[_HI], row[_TOLERANCE] = goal.lo, goal.hi, goal.tolerance
    xp, fp = goal_knots(goal, max_value)
    row[_N_KNOTS] = len(xp)
    row[_XP : _XP + len(xp)] = xp
    row[_FP : _FP + len(fp)] = fp
    return row


#: Reading channels: the front sonars, then the laser beams.
N_CHANNELS = FRONT_SONARS + LASER_BEAMS


@njit(cache=True)
def load_row(sonar, laser, row):
    """Copy front sonars ``sonar[:8]``, the laser ``(180,)`` and rear sonars (``sonar[8:]``,
    or 0 for 8 sonars) into ``row`` ``(196,)``; False if any reading is NaN, ±inf or < 0."""
    n_front = 8
    n_laser = laser.shape[0]
    ok = True
    for i in range(row.shape[0]):
        if i < n_front:
            value = sonar[i]
        elif i < n_front + n_laser:
            value = laser[i - n_front]
        elif sonar.shape[0] > n_front:
            value = sonar[i - n_laser]
        else:
            value = 0.0
        row[i] = value
        if not (value >= 0.0 and value < np.inf):
            ok = False
    return ok


@njit(cache=True)
def sense(
    row, limits, state, times, samples, ego_offset, t, slope_samples, ego_change, moved, push, readings, valid, rates
):
    """§2–§3: clip the new readings to each sensor's maximum, store them in the memory
    (``SensorMemory.buffers``) and take the range rates.

    Args:
        row: ``(188,)`` new readings (m), sonars then beams.
        limits: ``(2, 188)`` per channel: the maximum range, and the reading from which
            on it means no echo (m).
        t: time (s); slope_samples: K of the slope, 0 to leave ``rates`` alone (the
            tracker fills them).
        ego_change: ``(188,)`` the ego-motion range change (m), used only when ``moved``.
        push: store the readings (False when no sensor has scanned since the last step).
        readings, valid, rates: ``(188,)`` outputs: clipped readings (m), echo flags, range
            rates (m/s).
    """
    n = row.shape[0]
    invalid_now = np.empty(n, np.bool_)
    for c in range(n):
        reading = min(row[c], limits[0, c])
        readings[c] = reading
        invalid_now[c] = reading >= limits[1, c]
        valid[c] = not invalid_now[c]
    if push:
        push_sample(state, times, samples, ego_offset, t, readings, invalid_now, ego_change, moved)
    if slope_samples > 0:
        slope_rates(state, times, samples, slope_samples, rates)


@njit(cache=True)
def window_kinematics(rates, valid, max_speed, epsilon, speeds, moving):
    """§3 from the window's range rates ``(188,)`` (m/s): speeds ``min(|v|, MAX_SPEED)``
    and moving flags (an echo whose ``|v| > ε``), into ``speeds``, ``moving`` ``(188,)``."""
    for c in range(rates.shape[0]):
        a = abs(rates[c])
        speeds[c] = min(a, max_speed)
        moving[c] = valid[c] and a > epsilon


@njit(cache=True)
def sonar_grid_maps(
    readings,
    valid,
    rates,
    speeds,
    moving,
    speed_probability,
    max_ranges,
    max_speed,
    epsilon,
    max_distance,
    laser_only,
    laser_max,
    beam_region,
    active,
    goal_plan,
    goal_options,
    combine,
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
):
    """§4–§6 of a step on the sonar grid (J = 8): F1–F3 with the region quantities, then
    ``goal_maps`` (``speed_probability`` ``(8,)``: the tracker's judgement of the speed
    goal per front sonar's channel, −1 where none). Every array after ``combine`` is an
    output."""
    labels = _sonar_grid_features(
        rates,
        speeds,
        readings,
        valid,
        max_ranges,
        max_speed,
        epsilon,
        max_distance,
        beam_region,
        active[0] > 0.0,
        active[1] > 0.0,
        active[2] > 0.0,
        laser_only,
        laser_max,
        F,
        region_speed,
        nearest,
        distances,
    )
    echo = nearest < np.inf
    for j in range(labels.shape[0]):
        directions[j] = np.int8(labels[j])
    goal_maps(
        F,
        region_speed,
        moving[: labels.shape[0]],
        speed_probability,
        labels,
        distances,
        echo,
        goal_plan,
        goal_options,
        combine,
        C_BU,
        C_TD,
        C,
        origins,
        fulfilled,
    )


@njit(cache=True)
def _sonar_grid_features(
    rates,
    speeds,
    readings,
    valid,
    max_ranges,
    max_speed,
    epsilon,
    max_distance,
    beam_region,
    do_f1,
    do_f2,
    do_f3,
    laser_only,
    laser_max,
    F,
    region_speed,
    nearest,
    distances,
):
    """§3's labels, F1–F3 (active rows of ``F`` only) and the region quantities on the
    sonar grid (8 front sonars then 180 beams in the channel vectors ``rates`` and
    ``speeds``, m/s).

    Writes ``F[0:3]`` and the ``(8,)`` region speeds (m/s), nearest valid readings (m, inf
    where none) and distances (m); returns the region direction labels ``(8,)`` (−1, 0, +1
    as floats).
    """
    n_sonar = 8
    n = rates.shape[0]
    n_laser = n - n_sonar
    labels = np.empty(n)
    columns = np.empty(n, np.int64)
    counts = np.zeros(6, np.int64)  # label counts per (space, column)
    for k in range(n):
        r = rates[k]
        a = abs(r)
        label = 0.0
        column = 2
        if a > epsilon:
            if r > 0.0:
                label, column = 1.0, 1
            elif r < 0.0:
                label, column = -1.0, 0
        labels[k] = label
        columns[k] = column
        counts[(0 if k < n_sonar else 3) + column] += 1
    for j in range(n_sonar):
        region_speed[j] = speeds[j]
    if do_f1:
        mean = pairwise_sum(region_speed, 0, n_sonar) / n_sonar
        for j in range(n_sonar):
            F[0, j] = abs(region_speed[j] - mean) / max_speed
    if do_f2:
        # rarity (N/count − 1)/(N − 1) as features.Spaces computes it, per (space, column)
        rarity = np.empty(6)
        for space, size in ((0, n_sonar), (1, n_laser)):
            size_f = float(size)
            scale, shift = size_f / (size_f - 1.0), 1.0 / (size_f - 1.0)
            for column in range(3):
                if counts[3 * space + column] > 0:
                    rarity[3 * space + column] = scale / counts[3 * space + column] - shift
        for j in range(n_sonar):
            F[1, j] = rarity[columns[j]]
        for i in range(n_laser):
            value = rarity[3 + columns[n_sonar + i]]
            j = beam_region[i]
            if value > F[1, j]:
                F[1, j] = value
    if do_f3:
        if laser_only:
            mean = pairwise_sum(readings, n_sonar, n_laser) / n_laser
            first = np.full(n_sonar, -np.inf)
            for i in range(n_laser):
                value = abs(readings[n_sonar + i] - mean) / laser_max
                j = beam_region[i]
                if value > first[j]:
                    first[j] = value
            for j in range(n_sonar):
                F[2, j] = first[j]
        else:
            # add.reduceat: the first element, then the pairwise sum of the rest
            sonar_mean = (readings[0] + pairwise_sum(readings, 1, n_sonar - 1)) / n_sonar
            laser_mean = (readings[n_sonar] + pairwise_sum(readings, n_sonar + 1, n_laser - 1)) / n_laser
            laser_part = np.full(n_sonar, -np.inf)
            for i in range(n_laser):
                k = n_sonar + i
                value = abs(readings[k] - laser_mean) / max_ranges[k]
                j = beam_region[i]
                if value > laser_part[j]:
                    laser_part[j] = value
            for j in range(n_sonar):
                F[2, j] = max(laser_part[j], abs(readings[j] - sonar_mean) / max_ranges[j])
    # region quantities: majority label of the beams where the sonar is static, nearest echo
    label_counts = np.zeros((n_sonar, 3), np.int64)
    for j in range(n_sonar):
        nearest[j] = np.inf
    for i in range(n_laser):
        k = n_sonar + i
        j = beam_region[i]
        label_counts[j, columns[k]] += 1
        if valid[k] and readings[k] < nearest[j]:
            nearest[j] = readings[k]
    directions = np.empty(n_sonar)
    for j in range(n_sonar):
        if labels[j] != 0.0:
            directions[j] = labels[j]
        else:
            best = 0
            for c in range(1, 3):
                if label_counts[j, c] > label_counts[j, best]:
                    best = c
            directions[j] = -1.0 if best == 0 else (1.0 if best == 1 else 0.0)
        if valid[j] and readings[j] < nearest[j]:
            nearest[j] = readings[j]
        distances[j] = min(nearest[j], max_distance)
    return directions


@njit(cache=True)
def _goal_holds(kind, lo, hi, tolerance, x):
    """``Goal.is_fulfilled`` for one value, the goal given by its plan row's columns."""
    if kind == _EQUAL:
        return abs(x - lo) <= tolerance
    if kind == _BETWEEN:
        return x >= lo and x <= hi
    if kind == _GREATER:
        return x >= lo
    if kind == _SMALLER:
        return x <= lo
    return x == lo  # _DIRECTION: the label equals the wanted direction


@njit(cache=True)
def goal_maps(
    F,
    region_speed,
    speed_target,
    speed_probability,
    labels,
    distances,
    echo,
    goal_plan,
    goal_options,
    combine,
    C_BU,
    C_TD,
    C,
    origins,
    fulfilled,
):
    """§5–§6 on any grid: the active top-down maps ``F[3:6]`` and the goal mask, then C.

    Args:
        F: ``(6, J)``; rows 3..5 of active maps are written (inactive ones stay 0).
        region_speed: ``(J,)`` m/s; speed_target: ``(J,)`` bool, regions a speed goal may
            hold at; speed_probability: ``(J,)`` the probability that the speed goal holds
            at the region's track (``track_regions.speed_goal_probability``), −1 where it is
            not judged so: where ≥ 0, the goal holds when it is at least ½ and F4 is
            ``min(1, 2 p)``, in place of the table over the region's speed.
        labels: ``(J,)`` direction labels as floats; distances: ``(J,)`` m;
            echo: ``(J,)`` bool, a valid reading in the region (the target of F5, F6).
        goal_plan: ``(3, PLAN_COLUMNS)``; goal_options: ``records.goal_options`` of the
            configuration (``td_require_target``, ``silent_goal_maps_out``).
        combine: ``(2, 3)`` the weights of C_BU (row 0) and C_TD (row 1), normaliser included.
        C_BU, C_TD, C: ``(J,)`` outputs; origins: ``(J,)`` int8, 1 where C_TD > C_BU;
        fulfilled: ``(J,)`` bool, every active goal holds (False without goals).
    """
    n_regions = F.shape[1]
    require_target = (goal_options & REQUIRE_TARGET) != 0
    silent_out = (goal_options & SILENT_MAPS_OUT) != 0
    any_goal = False
    silent_weight = 0.0  # the combination weight of the active top-down maps that are 0 everywhere
    for j in range(n_regions):
        fulfilled[j] = True
    for r in range(3):
        kind = goal_plan[r, _KIND]
        if kind == _INACTIVE:
            continue
        any_goal = True
        lo, hi, tolerance = goal_plan[r, _LO], goal_plan[r, _HI], goal_plan[r, _TOLERANCE]
        n_knots = int(goal_plan[r, _N_KNOTS])
        xp, fp = goal_plan[r, _XP : _XP + n_knots], goal_plan[r, _FP : _FP + n_knots]
        for j in range(n_regions):
            if r == 0:
                x, target = region_speed[j], speed_target[j]
            elif r == 1:
                x, target = labels[j], echo[j]
            else:
                x, target = distances[j], echo[j]
            if r == 0 and speed_probability[j] >= 0.0:  # judged by the track's probability
                ok = speed_probability[j] >= 0.5
                value = min(1.0, 2.0 * speed_probability[j])
            elif kind == _DIRECTION:
                ok = _goal_holds(kind, lo, hi, tolerance, x)
                value = 1.0 if ok else 0.0
            else:  # the graded table; 1 where the goal holds
                ok = _goal_holds(kind, lo, hi, tolerance, x)
                value = max(interp(x, xp, fp), 1.0 if ok else 0.0)
            if require_target:
                value *= 1.0 if target else 0.0
                ok = ok and target
            F[3 + r, j] = value
            fulfilled[j] = fulfilled[j] and ok
        if silent_out and F[3 + r].max() == 0.0:
            silent_weight += combine[1, r]
    if not any_goal:
        fulfilled[:] = False
    vecmat(combine[0], F[:3], C_BU)
    vecmat(combine[1], F[3:], C_TD)
    # with normalised weights (summing to 1), leaving the silent maps out of the normaliser
    # divides the rest by 1 - their weight
    if 0.0 < silent_weight < 1.0:
        scale = 1.0 / (1.0 - silent_weight)
        for j in range(n_regions):
            C_BU[j] *= scale
            C_TD[j] *= scale
    for j in range(n_regions):
        C[j] = C_BU[j] + C_TD[j]
        origins[j] = 1 if C_TD[j] > C_BU[j] else 0


@njit(cache=True)
def select(
    t, fulfilled, origins, C, gain, threshold, spread, params, bu_regions, bu_starts, td_regions, td_times, counts, M, L
):
    """§7–§8 with the courses (the arrays of ``CourseBook``, with room for one more of each
    kind): update the top-down holds at ``t`` (s), evaluate the courses' centre gains,
    ``saliency`` into ``M`` and ``L`` ``(J,)``, then start a course at the winner if it
    fires. Returns the winner ``argmax L`` and whether a course started.

    The winner is the focus when ``L[winner] >= threshold``; a top-down winner (``origins``)
    starts a held course where its goal is fulfilled and none is held there, a bottom-up
    one a course where none is running.
    """
    release_courses(t, fulfilled, params, bu_regions, bu_starts, td_regions, td_times, counts)
    gains = np.zeros(C.shape[0])
    if not course_gains(t, params, bu_regions, bu_starts, td_regions, td_times, counts, gains):
        gains = gains[:0]
    winner = saliency(gains, spread, C, gain, M, L)
    fired = False
    if L[winner] >= threshold:
        if origins[winner]:
            # a course is held while the goal holds, so one starts only where it holds
            fired = fulfilled[winner] and not top_down_holding(
                winner, params, bu_regions, bu_starts, td_regions, td_times, counts
            )
        else:
            fired = not bottom_up_running(winner, t, params, bu_regions, bu_starts, td_regions, td_times, counts)
        if fired:
            add_course(origins[winner] != 0, winner, t, params, bu_regions, bu_starts, td_regions, td_times, counts)
    return winner, fired


@njit(cache=True)
def saliency(gains, spread, C, gain, M, L):
    """§7–§8: ``M = max(0, 1 + gains @ G)`` (1 without courses: ``gains`` empty), then
    ``L = M · C · g``, into ``M`` and ``L`` ``(J,)``; returns the winner ``argmax L`` (ties
    to the lowest index)."""
    if gains.shape[0] == 0:
        M[:] = 1.0
    else:
        vecmat(gains, spread, M)
        for j in range(M.shape[0]):
            M[j] = max(1.0 + M[j], 0.0)
    winner = 0
    for j in range(M.shape[0]):
        L[j] = M[j] * C[j]
        if gain != 1.0:
            L[j] *= gain
        if L[j] > L[winner]:
            winner = j
    return winner


@njit(cache=True)
def attend_one(
    row,
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
    scan_history,
    centroid_history,
    centroid_count,
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
    goal_options,
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
    speed_probability,
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
):
    """One step of a model on the sonar grid (J = 8), in one call: ``sense``, then the
    tracker's ``track_step`` (``tracked``) or ``window_kinematics``, ``sonar_grid_maps`` and
    ``select``. Returns ``(winner, fired, n_tracks)``: the winner ``argmax L``, whether a
    course started, and the number of track rows written (0 without the tracker).

    The arguments, in groups (``AttentionModel`` holds them; ``batch.attend_many`` passes
    one row of each batched array):

    - ``sense``'s: the input row ``(188,)`` (m), the limits, the memory's buffers, the time
      ``t`` (s), and ``dt`` (s) since the previous step; the slope's K, the ego-motion
      change, whether it applies (``moved``), and whether to store the readings (``push``);
    - the tracker's: whether it runs (``tracked``), the odometry ``linear`` (m/s) and
      ``angular`` (rad/s), whether the laser and sonar readings are new scans, the speeds
      a speed goal wants ``(2,)`` (m/s), then ``Tracker.constants`` and ``Tracker.state``
      (placeholders when ``tracked`` is False);
    - the maps': maximum ranges ``(188,)`` (m), the maximum distance (m), ``laser_only``,
      the laser's maximum (m), the active weights ``(6,)``, the goal plan ``(3, PLAN_COLUMNS)``,
      ``goal_options`` (``records.goal_options``) and the combination weights ``(2, 3)``;
    - the selection's: the gain, the threshold, the spread ``(J, J)`` and
      ``CourseBook.arrays`` (with room for one more course of each kind);
    - the outputs, each a fresh array: ``readings``, ``valid``, ``rates``, ``speeds``, ``moving``
      ``(188,)``, ``region_slot`` and ``speed_probability`` ``(8,)``, ``F`` ``(6, J)``, then
      ``(J,)`` ``C_BU``, ``C_TD``, ``C``, region speeds, distances, nearest readings, origins, directions, goal flags,
      ``M`` and ``L``.
    """
    sense(
        row,
        limits,
        state,
        times,
        samples,
        ego_offset,
        t,
        slope_samples,
        ego_change,
        moved,
        push,
        readings,
        valid,
        rates,
    )
    n_tracks = 0
    if tracked:
        n_tracks = track_step(
            t,
            dt,
            linear,
            angular,
            laser_new,
            sonar_new,
            readings,
            valid,
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
            scan_history,
            centroid_history,
            centroid_count,
            sonar_x,
            sonar_P,
            sonar_hits,
            sonar_t,
            track_rows,
            track_covariance,
            rates,
            speeds,
            moving,
            region_slot,
            speed_probability,
        )
    else:
        window_kinematics(rates, valid, max_speed, epsilon, speeds, moving)
        region_slot[:] = -1
        speed_probability[:] = -1.0
    sonar_grid_maps(
        readings,
        valid,
        rates,
        speeds,
        moving,
        speed_probability,
        max_ranges,
        max_speed,
        epsilon,
        max_distance,
        laser_only,
        laser_max,
        beam_region,
        active,
        goal_plan,
        goal_options,
        combine,
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
    )
    winner, fired = select(
        t,
        fulfilled,
        origins,
        C,
        gain,
        threshold,
        spread,
        course_params,
        bu_regions,
        bu_starts,
        td_regions,
        td_times,
        counts,
        M,
        L,
    )
    return winner, fired, n_tracks


# --- the step over records (records.StateLayout, records.ModelState, records.output_dtype) ---
# rows of the layout's table
_ROW, _EGO, _ACTIVE, _GOAL_PLAN, _COMBINE, _GAIN, _WANTED_SPEED = (
    STATE_FIELDS.index(name) for name in ("row", "ego", "active", "goal_plan", "combine", "gain", "wanted_speed")
)
_MEMORY_STATE, _TIMES, _SAMPLES, _EGO_OFFSET = (
    STATE_FIELDS.index(name) for name in ("memory_state", "times", "samples", "ego_offset")
)
_BU_REGIONS, _BU_STARTS, _TD_REGIONS, _TD_TIMES, _COUNTS = (
    STATE_FIELDS.index(name) for name in ("bu_regions", "bu_starts", "td_regions", "td_times", "counts")
)
(
    _POSE,
    _ODOMETRY,
    _SONAR_POSE,
    _BOUNDS,
    _SEGMENTS,
    _CV_X,
    _CV_P,
    _STATIC_X,
    _STATIC_P,
    _P_MOVING,
    _ALIVE,
    _IDS,
    _HITS,
    _MISSES,
    _BORN_S,
    _FILTER_T,
    _SEEN_S,
    _EXTENT_M,
    _SEGMENT_OF,
    _COUNTERS,
    _SCAN_HISTORY,
    _CENTROID_HISTORY,
    _CENTROID_COUNT,
    _SONAR_X,
    _SONAR_P,
    _SONAR_HITS,
    _SONAR_T,
    _TRACK_ROWS,
    _TRACK_COVARIANCE,
) = (STATE_FIELDS.index(f"tracker.{name}") for name in TRACKER_FIELDS)
(
    _LIMITS,
    _MAX_RANGES,
    _SPREAD,
    _COURSE_PARAMS,
    _BEAM_COS,
    _BEAM_SIN,
    _SONAR_COS,
    _SONAR_SIN,
    _TRACKER_PARAMS,
    _FLOAT_SCALARS,
    _BEAM_REGION,
    _CONE_BOUNDS,
    _INT_SCALARS,
) = (len(STATE_FIELDS) + k for k in range(len(CONSTANT_FIELDS)))
# places in the scalar fields
_BEAM_STEP, _MAX_SPEED, _EPSILON, _MATCH_M, _MATCH_SIGMAS, _NOISE_REL, _NOISE_FLOOR, _MAX_DISTANCE, _LASER_MAX = (
    FLOAT_SCALARS.index(name)
    for name in (
        "beam_step_rad",
        "max_speed",
        "epsilon",
        "match_m",
        "match_sigmas",
        "noise_rel",
        "noise_floor_m",
        "max_distance",
        "laser_max",
    )
)
_THRESHOLD = FLOAT_SCALARS.index("threshold")
_WINNER, _FOCUS, _SALIENCY, _FIRED, _TOP_DOWN, _N_TRACKS = (
    RESULTS.index(name) for name in ("winner", "focus", "saliency", "fired", "top_down", "n_tracks")
)
_SLOPE_SAMPLES, _TRACKED, _CONFIRM_HITS, _LASER_ONLY, _GOAL_OPTIONS = (
    INT_SCALARS.index(name) for name in ("slope_samples", "tracked", "confirm_hits", "laser_only", "goal_options")
)


@njit(cache=True)
def _flat(buffer, table, k):
    """Field ``k`` of the layout's ``table`` in ``buffer`` ``(size,)``, flat."""
    offset = table[k, OFFSET]
    return buffer[offset : offset + table[k, DIMS] * table[k, DIMS + 1] * table[k, DIMS + 2]]


@njit(cache=True)
def _two(buffer, table, k):
    """Field ``k`` in ``buffer``, as its 2-D array."""
    return shaped(_flat(buffer, table, k), (table[k, DIMS], table[k, DIMS + 1]))


@njit(cache=True)
def _three(buffer, table, k):
    """Field ``k`` in ``buffer``, as its 3-D array."""
    return shaped(_flat(buffer, table, k), (table[k, DIMS], table[k, DIMS + 1], table[k, DIMS + 2]))


@njit(cache=True)
def attend_record(table, constant_floats, constant_ints, floats, ints, flags, step, out):
    """``attend_one`` for one model whose state is ``floats``, ``ints``, ``flags`` (its rows of
    the buffers, ``records.ModelState``), with the constants of ``constant_floats`` and
    ``constant_ints``, where the layout's ``table`` says; ``step`` ``(8,)`` holds the step's
    inputs (``records.STEP_COLUMNS``); writes every output into the record ``out``
    (``records.output_dtype``), ``F`` zeroed first."""
    fs = _flat(constant_floats, table, _FLOAT_SCALARS)
    ns = _flat(constant_ints, table, _INT_SCALARS)
    threshold = fs[_THRESHOLD]
    F = out.F
    F[:] = 0.0
    M, L, origins = out.M, out.L, out.origins
    winner, fired, n_tracks = attend_one(
        _flat(floats, table, _ROW)[:N_CHANNELS],
        _two(constant_floats, table, _LIMITS),
        _flat(ints, table, _MEMORY_STATE),
        _flat(floats, table, _TIMES),
        _three(floats, table, _SAMPLES),
        _flat(floats, table, _EGO_OFFSET),
        step[0],
        step[1],
        ns[_SLOPE_SAMPLES],
        _flat(floats, table, _EGO),
        step[2] != 0.0,
        step[3] != 0.0,
        ns[_TRACKED] != 0,
        step[4],
        step[5],
        step[6] != 0.0,
        step[7] != 0.0,
        _flat(floats, table, _WANTED_SPEED),
        _flat(constant_floats, table, _BEAM_COS),
        _flat(constant_floats, table, _BEAM_SIN),
        _flat(constant_floats, table, _SONAR_COS),
        _flat(constant_floats, table, _SONAR_SIN),
        fs[_BEAM_STEP],
        _flat(constant_floats, table, _TRACKER_PARAMS),
        ns[_CONFIRM_HITS],
        fs[_MAX_SPEED],
        fs[_EPSILON],
        _flat(constant_ints, table, _BEAM_REGION),
        _two(constant_ints, table, _CONE_BOUNDS),
        fs[_MATCH_M],
        fs[_MATCH_SIGMAS],
        fs[_NOISE_REL],
        fs[_NOISE_FLOOR],
        _flat(floats, table, _POSE),
        _flat(floats, table, _ODOMETRY),
        _flat(floats, table, _SONAR_POSE),
        _two(ints, table, _BOUNDS),
        _two(floats, table, _SEGMENTS),
        _two(floats, table, _CV_X),
        _three(floats, table, _CV_P),
        _two(floats, table, _STATIC_X),
        _three(floats, table, _STATIC_P),
        _flat(floats, table, _P_MOVING),
        _flat(flags, table, _ALIVE).view(np.bool_),
        _flat(ints, table, _IDS),
        _flat(ints, table, _HITS),
        _flat(ints, table, _MISSES),
        _flat(floats, table, _BORN_S),
        _flat(floats, table, _FILTER_T),
        _flat(floats, table, _SEEN_S),
        _flat(floats, table, _EXTENT_M),
        _flat(ints, table, _SEGMENT_OF),
        _flat(ints, table, _COUNTERS),
        _two(floats, table, _SCAN_HISTORY),
        _three(floats, table, _CENTROID_HISTORY),
        _flat(ints, table, _CENTROID_COUNT),
        _two(floats, table, _SONAR_X),
        _three(floats, table, _SONAR_P),
        _flat(ints, table, _SONAR_HITS),
        _flat(floats, table, _SONAR_T),
        _two(floats, table, _TRACK_ROWS),
        _three(floats, table, _TRACK_COVARIANCE),
        _flat(constant_floats, table, _MAX_RANGES),
        fs[_MAX_DISTANCE],
        ns[_LASER_ONLY] != 0,
        fs[_LASER_MAX],
        _flat(floats, table, _ACTIVE),
        _two(floats, table, _GOAL_PLAN),
        ns[_GOAL_OPTIONS],
        _two(floats, table, _COMBINE),
        _flat(floats, table, _GAIN)[0],
        threshold,
        _two(constant_floats, table, _SPREAD),
        _flat(constant_floats, table, _COURSE_PARAMS),
        _flat(ints, table, _BU_REGIONS),
        _flat(floats, table, _BU_STARTS),
        _flat(ints, table, _TD_REGIONS),
        _two(floats, table, _TD_TIMES),
        _flat(ints, table, _COUNTS),
        out.readings,
        out.valid.view(np.bool_),
        out.rates,
        out.speeds,
        out.moving.view(np.bool_),
        out.region_slot,
        out.speed_probability,
        F,
        out.C_BU,
        out.C_TD,
        out.C,
        out.region_speed,
        out.distances,
        out.nearest,
        origins,
        out.directions,
        out.fulfilled.view(np.bool_),
        M,
        L,
    )
    results = out.results
    results[_WINNER], results[_FOCUS] = winner, (winner if L[winner] >= threshold else -1)
    results[_SALIENCY], results[_FIRED], results[_TOP_DOWN] = L[winner], fired, origins[winner]
    results[_N_TRACKS] = n_tracks


@njit(cache=True, parallel=True)
def attend_many(members, table, constant_floats, constant_ints, floats, ints, flags, steps, outputs):
    """One step of the models ``members`` ``(n,)`` of a batch (``attend_record`` for each, in
    parallel over them when n > 1).

    Args:
        members: the rows of the models to step in the state buffers.
        table, constant_floats, constant_ints: the layout (``records.StateLayout``).
        floats, ints, flags: the state buffers ``(N, size)`` of the batch's N models
            (``records.ModelState``; one model's own state is a batch of one).
        steps: ``(n, 8)`` the stepped models' inputs (``records.STEP_COLUMNS``), in the
            order of ``members``.
        outputs: ``(n,)`` records (``records.output_dtype``), written in that order.
    """
    if members.shape[0] == 1:  # one model: no thread pool to start
        i = members[0]
        attend_record(table, constant_floats, constant_ints, floats[i], ints[i], flags[i], steps[0], outputs[0])
        return
    for j in prange(members.shape[0]):
        i = members[j]
        attend_record(table, constant_floats, constant_ints, floats[i], ints[i], flags[i], steps[j], outputs[j])
