"""AttentionModel: API, input validation, outputs and short scenarios (docs/model.md §6–§8)."""

import dataclasses

import numpy as np
import pytest

from attentive_gym.attention import AttentionConfig, AttentionModel, Direction, Goal
from support import assert_same


def _target_run(model, speed=0.7, start=4.0, steps=40, dt=0.05, stop_at=None):
    """Sonar 3 (and its laser beams) see a target approaching at ``speed`` m/s; the rest is static."""
    outs = []
    for k in range(steps):
        t = k * dt
        moving_t = t if stop_at is None else min(t, stop_at)
        r = start - speed * moving_t
        sonar, laser = np.full(16, 4.5), np.full(180, 8.0)
        sonar[3] = r
        laser[95:100] = r
        outs.append(model.step(t, sonar, laser))
    return outs


def test_exp01_like_first_winner_is_the_moving_region_and_it_does_not_refire_within_600_ms():
    model = AttentionModel(AttentionConfig(ego_motion=None, kinematics="window"))
    model.set_weights(F1=1.0)
    outs = _target_run(model, speed=0.5)
    fired = [(round(o.t, 2), o.focus, o.origin) for o in outs if o.fired]
    assert fired[0] == (0.05, 3, "bottom-up")
    times = [t for t, j, _ in fired if j == 3]
    assert all(b - a > 0.6 for a, b in zip(times, times[1:]))
    assert all(j == 3 for _, j, _ in fired)
    o = outs[1]
    assert o.view.region == 3 and o.view.bearing_rad == pytest.approx(np.radians(10))
    assert o.view.range_rate_mps == pytest.approx(-0.5) and o.view.direction is Direction.TOWARDS
    assert o.view.sonar_range_m == pytest.approx(3.975) and o.view.distance_m == pytest.approx(3.975)
    assert o.view.laser_beams.tolist() == list(range(90, 110)) and o.view.laser_ranges_m.shape == (20,)
    assert o.view.features[0] == pytest.approx(o.F[0, 3])


def test_exp04_like_top_down_course_without_ior_and_fast_release():
    model = AttentionModel(AttentionConfig(ego_motion=None, kinematics="window"))
    model.set_goals(Goal.between("speed", 0.5, 0.9))
    model.set_weights(F1=1.0, F4=1.0)
    outs = _target_run(model, speed=0.7, steps=60, stop_at=1.5)
    first = next(o for o in outs if o.fired)
    assert (first.focus, first.origin, round(first.t, 2)) == (3, "top-down", 0.05)
    assert first.F[3, 3] == 1.0 and first.goal_fulfilled[3] and first.origins[3] == 1
    held = [o for o in outs if 0.05 < o.t < 1.5]
    assert all(o.M[3] >= 1.0 for o in held)  # no IOR
    assert next(o for o in outs if o.M[3] > 1.0).t <= first.t + 0.2 + 0.05 + 1e-9
    released = next(o for o in outs if o.t > 1.5 and not o.goal_fulfilled[3])
    later = [o for o in outs if released.t + 0.1 - 1e-9 <= o.t]
    assert later and all(o.M[3] - 1.0 < 0.01 for o in later)
    assert sum(o.fired for o in outs) == 1
    # after the stop the decelerating target still wins for a step or two (graded F4),
    # but where the goal does not hold no new top-down course starts
    assert any(o.focus == 3 and not o.goal_fulfilled[3] for o in outs)


def test_combined_map_normalisation_and_origins():
    model = AttentionModel(AttentionConfig(ego_motion=None, balance_groups=False))
    model.set_goals(Goal.smaller("distance", 2.0))
    model.set_weights({"distance": 1.0, "goal_distance": 3.0})
    sonar, laser = np.full(16, 4.5), np.full(180, 8.0)
    sonar[6] = 1.0
    out = model.step(0.0, sonar, laser)
    np.testing.assert_allclose(out.C, (out.F[2] + 3 * out.F[5]) / 4)
    np.testing.assert_allclose(out.C, out.C_BU + out.C_TD)
    far = 1 - (4.5 - 2.0) / (20.0 - 2.0)  # F6 SMALLER(2 m) above the bound, nearest echo 4.5 m
    np.testing.assert_allclose(out.F[5], [far] * 6 + [1.0, far])
    assert out.origins.tolist() == [1] * 8 and out.goal_fulfilled.tolist() == [False] * 6 + [True, False]
    assert out.focus == 6 and out.origin == "top-down"
    raw = AttentionModel(AttentionConfig(ego_motion=None, normalise_combined=False, balance_groups=False))
    raw.set_goals(Goal.smaller("distance", 2.0))
    raw.set_weights(F3=1.0, F6=3.0)
    np.testing.assert_allclose(raw.step(0.0, sonar, laser).C, 4 * out.C)


def test_balanced_groups_let_a_fulfilled_goal_weigh_as_much_as_the_bottom_up_maps():
    # sonar s7 (index 6) sees a body at 1 m: F3 there is |1 − mean| / 5 m = 0.6125, and the
    # goal "distance < 2 m" holds there only
    sonar, laser = np.full(16, 4.5), np.full(180, 8.0)
    sonar[6] = 1.0
    outputs = {}
    for balance in (True, False):
        model = AttentionModel(AttentionConfig(ego_motion=None, balance_groups=balance))
        model.set_goals(Goal.smaller("distance", 2.0))
        model.set_weights(F3=2.0, F6=1.0)
        outputs[balance] = model.step(0.0, sonar, laser)
    balanced, plain = outputs[True], outputs[False]
    assert balanced.F[2, 6] == pytest.approx(0.6125) and balanced.F[5, 6] == 1.0
    # balanced: F6's weight scaled from 1 to the bottom-up total 2, Z = 4
    np.testing.assert_allclose(balanced.C_BU, 2 * balanced.F[2] / 4)
    np.testing.assert_allclose(balanced.C_TD, 2 * balanced.F[5] / 4)
    # as given: Z = 3, and the body's bottom-up evidence (2 × 0.6125) outvotes the goal (1)
    np.testing.assert_allclose(plain.C_BU, 2 * plain.F[2] / 3)
    np.testing.assert_allclose(plain.C_TD, plain.F[5] / 3)
    assert (balanced.focus, balanced.origin) == (6, "top-down")
    assert (plain.focus, plain.origin) == (6, "bottom-up")
    # without a goal there is nothing to balance: the bottom-up weights act alone
    alone = AttentionModel(AttentionConfig(ego_motion=None))
    alone.set_weights(F3=2.0, F6=1.0)
    np.testing.assert_allclose(alone.step(0.0, sonar, laser).C_BU, 2 * balanced.F[2] / 2)


def test_a_goal_map_that_holds_nowhere_can_be_left_out_of_the_normaliser():
    sonar, laser = np.full(16, 4.5), np.full(180, 8.0)
    sonar[6] = 1.0

    def step(goal, **weights):
        """One step under ``goal`` (None: bottom-up) with each value of silent_goal_maps_out."""
        outputs = []
        for silent_out in (False, True):
            model = AttentionModel(AttentionConfig(ego_motion=None, silent_goal_maps_out=silent_out))
            model.set_goals(*([] if goal is None else [goal]))
            model.set_weights(**weights)
            outputs.append(model.step(0.0, sonar, laser))
        return outputs

    bottom_up, _ = step(None, F3=2.0, F4=1.0)
    # nothing moves: a speed goal holds nowhere and F4 is 0 everywhere
    counted, left_out = step(Goal.between("speed", 0.5, 0.9), F3=2.0, F4=1.0)
    assert not left_out.F[3].any() and bottom_up.C_BU.max() > 0.0
    # counted, the silent goal halves the bottom-up evidence (Z = 4 instead of 2) ...
    np.testing.assert_allclose(counted.C, bottom_up.C / 2)
    # ... left out, the combined map is the bottom-up one
    np.testing.assert_allclose(left_out.C, bottom_up.C)
    np.testing.assert_allclose(left_out.C_BU, bottom_up.C_BU)
    # where a goal's map is not 0 everywhere, it counts as before
    counted, left_out = step(Goal.smaller("distance", 2.0), F3=2.0, F6=1.0)
    assert left_out.F[5, 6] == 1.0
    np.testing.assert_array_equal(left_out.C, counted.C)
    with pytest.raises(ValueError, match="needs normalise_combined=True"):
        AttentionConfig(silent_goal_maps_out=True, normalise_combined=False)


def test_balanced_groups_stay_finite_for_subnormal_weights():
    model = AttentionModel(AttentionConfig(ego_motion=None))
    model.set_goals(Goal.smaller("distance", 2.0))
    model.set_weights(F3=1e6, F6=5e-324)
    sonar, laser = np.full(16, 4.5), np.full(180, 8.0)
    sonar[6] = 1.0
    out = model.step(0.0, sonar, laser)
    assert np.isfinite(out.C).all() and out.C_TD[6] == pytest.approx(0.5)


def test_top_down_map_without_goal_is_inactive_and_settings_are_readable():
    model = AttentionModel()
    assert model.active_maps == ("F1", "F2", "F3") and model.goals == ()
    model.set_goals(Goal.direction_is("towards"), Goal.greater("speed", 0.3))
    assert model.active_maps == ("F1", "F2", "F3", "F4", "F5")
    assert [g.feature.value for g in model.goals] == ["speed", "direction"]
    model.set_weights([1, 0, 0, 2, 0, 0])
    assert dict(model.weights) == {"F1": 1.0, "F2": 0.0, "F3": 0.0, "F4": 2.0, "F5": 0.0, "F6": 0.0}
    assert model.active_maps == ("F1", "F4")
    model.set_weights()
    assert model.weights["F6"] == 1.0
    model.set_state(1.2)
    assert model.state == 1.2
    with pytest.raises(TypeError):
        model.weights["F1"] = 3.0
    model.set_goals()
    assert model.goals == ()


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda m: m.set_goals(Goal.greater("speed", 0.1), Goal.smaller("speed", 0.5)), "at most one goal per feature"),
        (lambda m: m.set_goals("speed>0.5"), "set_goals takes Goal objects"),
        (lambda m: m.set_weights({"F7": 1.0}), "unknown feature map 'F7'"),
        (lambda m: m.set_weights(F1=-1.0), r"weight of F1 must be a number in \[0, 1e\+06\]"),
        (lambda m: m.set_weights({"F1": 1.0}, motion=2.0), "map F1 is given more than one weight"),
        (lambda m: m.set_weights([1, 2]), "needs 6 entries"),
        (lambda m: m.set_state("asleep"), "unknown attentive state"),
    ],
)
def test_invalid_settings(call, message):
    with pytest.raises(ValueError, match=message):
        call(AttentionModel())


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ((0.1, np.full(7, 3.0), np.full(180, 8.0)), "sonar must hold 16 ring or 8 front"),
        ((0.1, np.full(16, 3.0), np.full(179, 8.0)), "laser must hold 180"),
        ((0.1, np.r_[np.nan, np.full(15, 3.0)], np.full(180, 8.0)), r"sonar readings must be finite.*\[0\]"),
        ((0.1, np.full(16, 3.0), np.r_[np.full(179, 8.0), np.inf]), r"laser readings.*\[179\]"),
        ((0.1, np.full(16, 3.0), np.r_[-1.0, np.full(179, 8.0)]), "laser readings must be finite ranges >= 0"),
        ((0.0, np.full(16, 3.0), np.full(180, 8.0)), "t must increase"),
        ((-1.0, np.full(16, 3.0), np.full(180, 8.0)), "t must increase"),
        ((float("nan"), np.full(16, 3.0), np.full(180, 8.0)), "t must be a finite time"),
        (("1.0", np.full(16, 3.0), np.full(180, 8.0)), "t must be the reading's time in seconds"),
        ((0.1, np.full(16, 3.0), np.full(180, 8.0), (0.5,)), "odometry must be"),
        ((0.1, np.full(16, 3.0), np.full(180, 8.0), (0.5, np.inf)), "odometry must be 2 finite numbers"),
        ((0.1, np.full(16, 3.0 + 1j), np.full(180, 8.0)), "sonar must be an array of ranges.*dtype complex128"),
        ((0.1, np.ones(16, bool), np.full(180, 8.0)), "sonar must be an array of ranges.*dtype bool"),
        ((0.1, np.full(16, 3.0), np.array(["8"] * 180)), "laser must be an array of ranges.*dtype <U1"),
        ((0.1, [object()] * 16, np.full(180, 8.0)), "sonar must be an array of ranges.*dtype object"),
    ],
)
def test_invalid_readings_raise_and_leave_state_unchanged(args, message):
    model = AttentionModel()
    model.step(0.0, np.full(16, 3.0), np.full(180, 8.0))
    with pytest.raises(ValueError, match=message):
        model.step(*args)
    assert model.step(0.1, np.full(8, 3.0), np.full(180, 8.0)).t == 0.1  # still usable


def test_a_scan_given_without_a_time_counts_as_taken_at_its_step():
    model = AttentionModel()
    model.step(0.0, np.full(16, 3.0), np.full(180, 8.0))  # no scan times: fresh scans at t = 0
    with pytest.raises(ValueError, match="laser_time_s=-5.0 is before the previous scan's time 0.0"):
        model.step(0.1, np.full(16, 3.0), np.full(180, 8.0), laser_time_s=-5.0)


@pytest.mark.parametrize(
    "build",
    [lambda: Goal.greater("speed", True), lambda: Goal.greater("speed", "0.5"), lambda: Goal.direction_is(True)],
)
def test_goals_refuse_bools_and_strings_for_numbers_and_labels(build):
    with pytest.raises(ValueError, match="must be a number|unknown direction"):
        build()


def test_view_of_takes_an_integer_region():
    out = AttentionModel().step(0.0, np.full(16, 3.0), np.full(180, 8.0))
    assert out.view_of(np.int64(2)).region == 2
    for bad in (3.5, True, 8, -1):
        with pytest.raises(ValueError, match=r"region must be an integer index in \[0, 8\)"):
            out.view_of(bad)


def test_heavy_weights_are_refused_before_the_combined_map_could_overflow():
    model = AttentionModel()
    model.set_goals(Goal.greater("speed", 0.5))
    with pytest.raises(ValueError, match=r"weight of F1 must be a number in \[0, 1e\+06\]"):
        model.set_weights({"F1": 1e308, "F3": 1e308, "F4": 1.0})
    model.set_weights({"F1": 1e6, "F3": 1e6, "F4": 1.0})
    outputs = _target_run(model, steps=30)
    assert all(np.isfinite(out.C).all() and np.isfinite(out.L).all() for out in outputs)


def test_no_echo_readings_and_clipping():
    model = AttentionModel(AttentionConfig(ego_motion=None))
    model.set_goals(Goal.greater("distance", 1.0))
    sonar, laser = np.full(16, 7.0), np.full(180, 25.0)  # beyond max: clipped, no echo
    out = model.step(0.0, sonar, laser)
    assert out.F[5].tolist() == [0.0] * 8  # no echo anywhere: no target for the goal
    assert out.distances_m.tolist() == [20.0] * 8 and out.focus is None and out.view is None
    sonar[2] = 2.0
    out = model.step(0.05, sonar, laser)
    assert (
        out.F[5, 2] == 1.0
        and out.distances_m[2] == 2.0
        and out.goal_fulfilled.tolist() == [False] * 2 + [True] + [False] * 5
    )


def test_reset_clears_memory_and_courses_but_keeps_settings():
    model = AttentionModel(AttentionConfig(ego_motion=None))
    model.set_weights(F1=1.0)
    model.set_goals(Goal.direction_is("away"))
    _target_run(model, steps=5)
    model.reset()
    out = model.step(0.0, np.full(16, 3.0), np.full(180, 8.0))  # time may start over
    assert np.all(out.M == 1.0) and out.focus is None
    assert model.goals == (Goal.direction_is("away"),) and model.weights["F1"] == 1.0


def test_laser_grid_has_180_regions():
    model = AttentionModel(AttentionConfig(grid="laser", ego_motion=None))
    model.set_weights(F3=1.0)
    sonar, laser = np.full(16, 4.5), np.full(180, 8.0)
    laser[40] = 1.0
    out = model.step(0.0, sonar, laser)
    assert out.F.shape == (6, 180) and out.focus == 40
    assert out.view.laser_beams.tolist() == [40] and out.view.bearing_rad == pytest.approx(np.radians(-49.5))
    assert out.M.shape == (180,)


def test_deep_copies_of_outputs_are_equal_and_independent():
    import copy

    model = AttentionModel(AttentionConfig(ego_motion=None, kinematics="window"))
    model.set_weights(F1=1.0)
    out = _target_run(model, speed=0.5, steps=2)[1]
    assert out.view is not None  # cached on first access; the copy rebuilds its own
    clone = copy.deepcopy(out)
    assert clone == out and clone is not out
    assert clone.view is not out.view
    assert_same(dataclasses.astuple(clone.view), dataclasses.astuple(out.view))
    for name in (
        "F",
        "C",
        "C_BU",
        "C_TD",
        "origins",
        "M",
        "L",
        "goal_fulfilled",
        "directions",
        "speeds_mps",
        "distances_m",
    ):
        assert not np.shares_memory(getattr(clone, name), getattr(out, name)), name
    for mine, theirs in zip(clone._sources[1:], out._sources[1:]):
        assert not np.shares_memory(mine, theirs)
    clone.L[:] = -1.0
    assert np.all(out.L >= 0.0)
    grid = out._sources[0]
    assert clone._sources[0] is grid and copy.deepcopy(grid) is grid
    with pytest.raises(ValueError, match="read-only"):
        grid.beam_region[0] = 3


def test_subnormal_weights_give_finite_maps():
    """Found by hypothesis: 1/Σw overflows for subnormal weights; C = Σ w F / Σ w stays finite."""
    model = AttentionModel()
    model.set_weights([5e-324] * 6)
    model.set_goals(Goal.between("speed", 0.5, 0.9))
    for k in range(3):
        out = model.step(0.05 * k, np.full(16, 3.0 - 0.1 * k), np.full(180, 8.0), (0.2, 0.0))
    assert np.isfinite(out.C).all() and np.isfinite(out.L).all() and np.isfinite(out.M).all()


def test_outputs_and_views_built_without_their_init_have_every_field_in_order():
    # the step and view_of fill these frozen dataclasses' fields directly (their __init__ is slow):
    # a field added to either class must be filled there too
    from attentive_gym.attention import AttentionOutput, FocusView

    model = AttentionModel(AttentionConfig(ego_motion=None))
    model.set_goals(Goal.between("speed", 0.5, 0.9))
    out = _target_run(model, speed=0.7, steps=30)[-1]
    assert list(vars(out)) == [f.name for f in dataclasses.fields(AttentionOutput)]
    assert AttentionOutput(**vars(out)) == out
    for region in range(8):
        view = out.view_of(region)
        assert list(vars(view)) == [f.name for f in dataclasses.fields(FocusView)]
        rebuilt = FocusView(**vars(view))
        for name, value in vars(view).items():
            np.testing.assert_equal(getattr(rebuilt, name), value, err_msg=name)
    assert out.view_of(3).track_id is not None  # the view of the target's region names its track
