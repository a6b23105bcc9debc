"""Time courses of the attentional map M (docs/model.md §7) and the Global Attentive State."""

import math

import numpy as np
import pytest

from attentive_gym.attention import AttentionConfig, AttentionModel
from attentive_gym.attention.attentional_map import (
    CourseBook,
    attentional_map,
    bottom_up_gain,
    lateral_spread,
    rise_decay_kernel,
    top_down_gain,
)

CFG = AttentionConfig()
G = lateral_spread(8, CFG.lateral_sigma_regions)
EPS = 1e-9


def _m(book, t):
    gains = book.centre_gains(t)
    return np.ones(8) if gains is None else attentional_map(gains, G)


def test_kernel_peaks_at_one_and_lateral_spread_is_e_minus_2():
    taus = np.linspace(0.0, 0.15, 3001)
    h = [rise_decay_kernel(t, 0.15, 1 / 20, 1 / 2) for t in taus]
    assert max(h) == pytest.approx(1.0, abs=1e-6) and h[0] == 0.0 and min(h) >= 0.0
    assert taus[int(np.argmax(h))] == pytest.approx(0.15 * math.log(10) / 18, abs=1e-4)
    assert G[3, 4] == pytest.approx(math.exp(-2)) and G[3, 5] == pytest.approx(math.exp(-8))


def test_bottom_up_course_phases():
    book = CourseBook(CFG, 8)
    book.start_bottom_up(3, 10.0)
    for tau in np.arange(0.0, 0.9, 0.005):
        m = _m(book, 10.0 + tau)
        if tau <= 0.15 + EPS or tau > 0.6 + EPS:
            assert np.all(m == 1.0), tau
        elif tau <= 0.3 + EPS:
            assert m[3] > 1.0, tau
        else:
            assert m[3] < 1.0, tau
        if m[3] != 1.0:  # neighbours move by e^-2 of the centre
            assert (m[2] - 1) / (m[3] - 1) == pytest.approx(math.exp(-2))
            assert (m[4] - 1) / (m[3] - 1) == pytest.approx(math.exp(-2))
    assert book.empty
    assert bottom_up_gain(0.3, CFG) == pytest.approx(CFG.A_exc * rise_decay_kernel(0.15, 0.15, 1 / 20, 1 / 2))


def test_bottom_up_course_blocks_a_second_course_while_active():
    book = CourseBook(CFG, 8)
    book.start_bottom_up(2, 0.0)
    assert book.bottom_up_active(2, 0.6) and not book.bottom_up_active(2, 0.61)
    assert not book.bottom_up_active(3, 0.1)


def test_top_down_course_never_below_one_before_vigilance_and_vanishes_after_release():
    book = CourseBook(CFG, 8)
    book.start_top_down(5, 0.0)
    held = np.ones(8, bool)
    for t in np.arange(0.0, 3.0, 0.01):
        book.update_holds(t, held)
        m = _m(book, t)
        assert m.min() >= 1.0
        if t <= 0.2:
            assert m[5] == 1.0
        if t >= 0.2 + 5 * CFG.td_tau_on_s:
            assert m[5] == pytest.approx(1 + CFG.A_td, rel=1e-2)
    book.update_holds(3.0, np.zeros(8, bool))  # goal no longer fulfilled: release
    assert not book.top_down_held(5)
    assert _m(book, 3.0)[5] > 1.9
    assert _m(book, 3.1)[5] - 1.0 < 0.01 * CFG.A_td  # within ~100 ms
    assert np.all(_m(book, 3.4) == 1.0) and book.empty  # no IOR, course dropped


def test_a_book_grows_past_its_first_capacity_and_keeps_every_course():
    # 3 J courses of each kind at once: more than the 2 J rows a book starts with
    book = CourseBook(CFG, 8)
    for k in range(24):
        book.start_bottom_up(k % 8, 0.01 * k)
        book.start_top_down(k % 8, 0.01 * k)
    book.update_holds(0.3, np.arange(8) % 2 == 0)  # the odd regions' courses are released at 0.3 s
    t = 0.4
    expected = np.zeros(8)
    for k in range(24):
        expected[k % 8] += bottom_up_gain(t - 0.01 * k, CFG)
    for k in range(24):
        released = k % 2 == 1
        expected[k % 8] += top_down_gain((0.3 if released else t) - 0.01 * k, t - 0.3 if released else 0.0, CFG)
    np.testing.assert_allclose(book.centre_gains(t), expected, rtol=1e-12, atol=1e-15)
    assert book.top_down_held(0) and not book.top_down_held(1)
    assert book.bottom_up_active(7, t)


def test_vigilance_pushes_m_below_plateau_then_below_one_and_recovers_slowly():
    book = CourseBook(CFG, 8)
    book.start_top_down(1, 0.0)
    held = np.ones(8, bool)
    values = {}
    for t in np.arange(0.0, 12.0, 0.05):
        book.update_holds(t, held)
        values[round(t, 2)] = _m(book, t)[1]
    plateau = 1 + CFG.A_td
    assert values[5.95] == pytest.approx(plateau, rel=1e-6)
    assert values[6.5] < plateau - 0.1
    assert values[11.95] < 1.0  # adaptation (1.5 A_td) outgrows the enhancement
    book.update_holds(12.0, np.zeros(8, bool))
    after = [_m(book, 12.0 + dt)[1] for dt in (0.5, 1.0, 2.0, 4.0)]
    assert all(a < 1.0 for a in after) and after == sorted(after)  # below 1, recovering over seconds
    assert top_down_gain(6.0, 0.0, CFG) == pytest.approx(CFG.A_td * -math.expm1(-5.8 / CFG.td_tau_on_s))


def _f3_stimulus_run(dt, t_end=2.5, state="alert"):
    """Sonar 3 and its laser beams see an obstacle at 1 m from t = 1.0 s to 1.3 s; F3 only."""
    model = AttentionModel(AttentionConfig(ego_motion=None, state=state))
    model.set_weights(F3=1.0)
    out = {}
    for k in range(int(round(t_end / dt)) + 1):
        t = k * dt
        sonar, laser = np.full(16, 3.0), np.full(180, 8.0)
        if 1.0 - EPS <= t < 1.3 - EPS:
            sonar[3] = 1.0
            laser[90:110] = 1.0
        out[round(t, 6)] = model.step(t, sonar, laser)
    return out


def test_model_bottom_up_course_from_a_stimulus():
    out = _f3_stimulus_run(0.01)
    fires = [(t, o.focus) for t, o in out.items() if o.fired]
    assert fires == [(1.0, 3)]
    for t, o in out.items():
        tau = t - 1.0
        if tau <= 0.15 + EPS or tau > 0.6 + EPS:
            assert o.M[3] == 1.0, t
        elif tau <= 0.3 + EPS:
            assert o.M[3] > 1.0, t
        else:
            assert o.M[3] < 1.0, t
    assert out[1.0].origin == "bottom-up" and out[1.0].saliency == pytest.approx(0.35)


def test_m_is_identical_at_common_instants_for_any_step_size():
    runs = {dt: _f3_stimulus_run(dt) for dt in (0.01, 0.025, 0.05)}
    common = sorted(runs[0.05])
    assert len(common) == 51
    for t in common:
        for dt in (0.01, 0.025):
            np.testing.assert_allclose(runs[dt][t].M, runs[0.05][t].M, rtol=0, atol=1e-12)
            np.testing.assert_allclose(runs[dt][t].L, runs[0.05][t].L, rtol=0, atol=1e-12)
    assert any(runs[0.05][t].M[3] > 1.0 for t in common) and any(runs[0.05][t].M[3] < 1.0 for t in common)


def test_global_attentive_state_scales_saliency_and_lowers_the_threshold():
    alert = _f3_stimulus_run(0.05, t_end=1.0)[1.0]
    vigilant = _f3_stimulus_run(0.05, t_end=1.0, state="vigilant")[1.0]
    np.testing.assert_allclose(vigilant.L, 1.5 * alert.L)
    assert vigilant.gain == 1.5
    # a weak stimulus (C = 0.08) fires only when vigilant: 1.5 * 0.08 >= 0.1
    for state, fires in (("alert", False), ("vigilant", True), ("drowsy", False)):
        model = AttentionModel(AttentionConfig(ego_motion=None))
        model.set_weights(F3=1.0)
        model.set_state(state)
        sonar = np.full(16, 3.0)
        sonar[0] = 3.0 - 0.08 * 5 * 8 / 7  # |o - mean| / 5 m = 0.08 at sonar 0
        out = model.step(0.0, sonar, np.full(180, 8.0))
        assert out.C[0] == pytest.approx(0.08)
        assert out.fired is fires and (out.focus == 0) is fires
