"""The paper's five experiments: MODEL.md §9's criteria, the runner, the CLI and figures."""

import functools

import numpy as np
import pytest

from attentive_gym.cli import main
from attentive_gym.experiments import (
    CHECKS,
    EXPERIMENT_NAMES,
    check_experiment,
    get_experiment,
    pass_rates,
    run_experiment,
)

SEEDS = range(20)
NOISE = 0.05
MIN_PASS_RATE = 0.8

#: Criteria that do not reproduce under MODEL.md's reading, with the measured reason.
NOT_REPRODUCED_EXACT = {
    ("exp02", "ior_visits_several_regions"): "inhibition of return alternates the focus between the two most "
                                             "salient regions of the static room (2 and 5): while one is "
                                             "inhibited the other wins, and a third never does",
    ("exp03", "moving_robot_dominates_L"): "the wall's F3 region (s1) wins 8 of 260 steps with a robot moving in "
                                           "range while the robot's region is not refractory (its own excitation "
                                           "phase)",
    ("exp04", "combined_L_exceeds_single"): "C is the weighted mean of the active maps (MODEL.md §6), so with "
                                            "F4 = 1 adding F1 < 1 lowers C: L(F1+F4) is 0.81 x max(L(F1), L(F4))",
}


@functools.cache
def _exact(name):
    return {c.name: c for c in check_experiment(run_experiment(name))}


def _cases(table):
    for name in EXPERIMENT_NAMES:
        for check in CHECKS[name]:
            reason = table.get((name, check))
            marks = [pytest.mark.xfail(strict=True, reason=reason)] if reason else []
            yield pytest.param(name, check, marks=marks, id=f"{name}-{check}")


@pytest.mark.parametrize(("name", "check"), list(_cases(NOT_REPRODUCED_EXACT)))
def test_criterion_holds_exactly_without_noise(name, check):
    outcome = _exact(name)[check]
    assert outcome.passed, outcome.measured


@functools.cache
def _noisy_rates(name):
    return pass_rates(name, NOISE, SEEDS)


#: With 5 % noise, the least-squares range rate over K = 5 samples at 20 Hz has σ ≈ 6.3 × 5 % × range,
#: about 0.95 m/s at 3 m: speeds, F1 and F4 are dominated by noise wherever a sonar has an echo.
_SPEED_NOISE = "5 % range noise makes the K = 5 range-rate σ ≈ 0.6-0.95 m/s at 2-3 m: "
# with noise the static room's focus does wander over more than two regions
NOT_REPRODUCED_NOISY = {
    **{key: reason for key, reason in NOT_REPRODUCED_EXACT.items() if key != ("exp02", "ior_visits_several_regions")},
    ("exp01", "first_winner_is_s4"): _SPEED_NOISE + "the static target at 3 m already wins at 0.05 s (0/20 seeds)",
    ("exp01", "far_regions_never_win"): _SPEED_NOISE + "a saturated s4 speed lifts F1 = mean(s) = 0.125 > θ in "
                                        "every other region (10/20 seeds)",
    ("exp03", "static_winners_from_F3"): _SPEED_NOISE + "the wall's sonar echoes make F1 lead before the robots "
                                         "move (0/20 seeds)",
    ("exp03", "moving_robot_dominates_L"): _SPEED_NOISE + "static echoes compete with the moving robots (0/20)",
    ("exp04", "F4_is_1_while_goal_holds"): _SPEED_NOISE + "the measured speed leaves [0.5, 0.9] (0/20 seeds)",
    ("exp04", "winners_top_down"): _SPEED_NOISE + "F1 > F4 at some target winners, which fire bottom-up (0/20)",
    ("exp04", "no_ior"): _SPEED_NOISE + "bottom-up winners bring IOR (0/20 seeds)",
    ("exp04", "M_rises_within_onset"): _SPEED_NOISE + "the first top-down fire's hold is often released before "
                                       "its 200 ms onset (12/20 seeds)",
    ("exp05", "faster_holds_focus"): _SPEED_NOISE + "the slower robot's noisy speed meets GREATER(0.6) too and "
                                     "static echoes fire bottom-up (0/20 seeds)",
    ("exp05", "top_down_never_below_1"): _SPEED_NOISE + "bottom-up courses' IOR spreads into top-down regions "
                                         "(0/20 seeds)",
}


@pytest.mark.parametrize(("name", "check"), list(_cases(NOT_REPRODUCED_NOISY)))
def test_criterion_holds_in_80_percent_of_20_noisy_seeds(name, check):
    rate = _noisy_rates(name)[check]
    assert rate >= MIN_PASS_RATE, f"{check} passes in {rate:.0%} of {len(SEEDS)} seeds at {NOISE:.0%} noise"


def test_same_seed_gives_the_same_trace_bit_for_bit():
    a, b = run_experiment("exp05", noise=NOISE, seed=3), run_experiment("exp05", noise=NOISE, seed=3)
    for key, value in a.trace.arrays().items():
        assert np.array_equal(value, getattr(b.trace, key)), key
    c = run_experiment("exp05", noise=NOISE, seed=4)
    assert not np.array_equal(a.trace.O1, c.trace.O1)


def test_run_records_the_experiment_and_ground_truth():
    result = run_experiment("exp05")
    experiment = get_experiment("exp05")
    n = int(round(experiment.duration_s / 0.05)) + 1
    assert result.trace.n_steps == n and result.trace.F.shape == (n, 6, 8)
    assert result.mover_positions.shape == (n, 2, 2) and result.sees.shape == (n, 2, 8)
    assert result.mover_names == ("fast", "slow")
    change = experiment.goal_changes[0]
    assert result.goal_index[0] == 0 and result.goal_index[np.searchsorted(result.trace.t, change.t_s)] == 1
    assert experiment.goals_at(change.t_s) == change.goals and experiment.goals_at(0.0) == experiment.goals
    assert np.all(result.trace.F[:, [1, 2, 4, 5]] == 0.0)  # only F1 and F4 are active


@pytest.mark.parametrize("bad", [{"name": "exp6"}, {"name": None}, {"name": "exp01", "noise": -0.1},
                                 {"name": "exp01", "noise": float("nan")}, {"name": "exp01", "noise": 0.6},
                                 {"name": "exp01", "seed": -1}, {"name": "exp01", "seed": 1.5},
                                 {"name": "exp01", "seed": True}])
def test_bad_input_raises_a_clear_value_error(bad):
    with pytest.raises(ValueError, match="exp01, exp02, exp03, exp04, exp05|noise|seed"):
        run_experiment(**bad)


def test_out_dir_gets_the_trace_and_a_small_figure(tmp_path):
    from attentive_gym.attention import load_trace

    result = run_experiment("exp01", out_dir=tmp_path)
    assert [p.name for p in result.paths] == ["exp01.npz", "exp01.png"]
    trace = load_trace(tmp_path / "exp01.npz")
    assert np.array_equal(trace.L, result.trace.L)
    png = (tmp_path / "exp01.png").read_bytes()
    assert png.startswith(b"\x89PNG") and len(png) < 150_000


def test_cli_runs_one_experiment_and_reports_checks(tmp_path, capsys):
    assert main(["experiment", "exp01", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "exp01: 5/5 checks pass" in out and "PASS first_winner_is_s4" in out
    assert (tmp_path / "exp01.png").is_file() and (tmp_path / "exp01.npz").is_file()


def test_cli_all_runs_the_five(capsys):
    assert main(["experiment", "all", "--noise", "0.05", "--seed", "1"]) == 0
    out = capsys.readouterr().out
    assert all(f"{name}: " in out for name in EXPERIMENT_NAMES)


@pytest.mark.parametrize(("argv", "message"), [(["exp9"], "allowed: exp01"), (["exp01", "--noise", "2"], "noise"),
                                               (["exp01", "--seed", "-3"], "seed")])
def test_cli_bad_input_is_one_line_and_exit_2(argv, message, capsys):
    assert main(["experiment", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and message in err
