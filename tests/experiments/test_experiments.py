"""The paper's five experiments: docs/model.md §9's criteria, the runner, the CLI and figures.

The criteria are tested in the tracker mode (the default), in the window mode (docs/model.md
§3) and with the perfect-perception bound ("truth": the model fed the simulator's true
kinematics): noise-free exactly, and in >= 80 % of 20 seeds at 5 % Gaussian noise. A criterion
that does not reproduce is a strict xfail carrying the measured reason, so a fix shows up.
"""

import ast
import csv
import functools
import json
import math
from pathlib import Path

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
from attentive_gym.experiments.table import (
    CAUSE_KINEMATICS,
    CAUSE_SETTINGS,
    COLUMNS,
    markdown,
    measure,
    measure_causes,
)
from support import load_tool

SEEDS = range(20)
NOISE = 0.05
MIN_PASS_RATE = 0.8
MODES = ("tracker", "window", "truth")

# --- why a criterion does not reproduce, measured (see docs/experiments.md) ---------
_MEAN = (
    "C is the weighted mean of the active maps (docs/model.md §6), so with F4 = 1 adding F1 < 1 lowers C: "
    "L(F1+F4) is 0.80 x max(L(F1), L(F4))"
)
_IOR_ALTERNATES = (
    "inhibition of return alternates the focus between the two most salient regions of the static "
    "room (s3 and s6, regions 2 and 5): while one is inhibited the other wins, and a third never does"
)
#: The tracker's speed lags every start and turn: with the start rules (model version 1) it
#: enters a goal's band 4-5 scans after a start, where the window mode's needs one.
_LAG = "the track's speed lags each start and turnaround by 0.2-0.3 s: "

NOT_REPRODUCED_EXACT = {
    "tracker": {
        ("exp02", "ior_visits_several_regions"): _IOR_ALTERNATES,
        ("exp03", "moving_robot_dominates_L"): _LAG + "a wall's F3 region leads L at 4 of 447 steps with a robot "
        "moving in range (the first at 1.10 s)",
        ("exp04", "F4_is_1_while_goal_holds"): _LAG + "F4 < 1 at 7 of 282 steps where the goal holds (the scans "
        "after the target's restart from its pause, 8.80-9.10 s)",
        ("exp04", "no_ior"): "the laser tracks the target from 7 m, so the top-down courses hold 7.25 s (0.65-7.90 s) "
        "and 6.85 s (9.15-16.00 s), past the 6 s vigilance onset: vigilance adaptation, not IOR, takes M to 0",
        ("exp04", "combined_L_exceeds_single"): _MEAN,
        ("exp05", "faster_holds_focus"): _LAG + "the focus is elsewhere at 3 of 224 steps (6.65-6.75 s, at "
        "the fast robot's turnaround, when the slow one wins)",
        ("exp05", "top_down_never_below_1"): "the laser tracks the fast robot from 7 m, so the course fired at 0.45 s "
        "holds 6.2 s, into vigilance, whose adaptation (recovering over 2 s) leaves M < 1 in all 4 top-down courses",
    },
    "window": {
        ("exp02", "ior_visits_several_regions"): _IOR_ALTERNATES,
        ("exp03", "moving_robot_dominates_L"): "the wall's F3 region (s1) wins 8 of 260 steps with a robot moving "
        "in range while the robot's region is not refractory (its own "
        "excitation phase)",
        ("exp04", "combined_L_exceeds_single"): _MEAN.replace("0.80", "0.81"),
    },
}

#: A top-down course held past vigilance's 6 s onset adapts (docs/model.md §7): M falls below 1.
_VIGILANCE = "the laser sees the target for the whole run, so a top-down course with perfect perception holds "
_TRUTH_EXACT = {
    ("exp02", "ior_visits_several_regions"): _IOR_ALTERNATES,
    ("exp03", "moving_robot_dominates_L"): "the wall's F3 region (s1) wins 18 of 447 steps with a robot moving in "
    "range while the robots' regions are not refractory (s1's own excitation phase, M = 1.4-1.7)",
    ("exp04", "no_ior"): _VIGILANCE + "7.15 s (0.55-7.70 s), past the 6 s vigilance onset: M falls to 0.03",
    ("exp04", "combined_L_exceeds_single"): _MEAN.replace("0.80", "0.81"),
    ("exp05", "faster_holds_focus"): _VIGILANCE + "from 0.05 s through the turnarounds, past the 6 s vigilance "
    "onset: the focus is elsewhere at 30 of 227 steps from 6.50 s",
    ("exp05", "top_down_never_below_1"): _VIGILANCE + "past the 6 s vigilance onset: M < 1 in all 3 top-down courses",
    ("exp05", "goal_change_moves_focus"): _VIGILANCE + "past the 6 s vigilance onset, so the slow robot's region "
    "holds the focus before the first goal change at 8.00 s, which then does not move it",
}
NOT_REPRODUCED_EXACT["truth"] = _TRUTH_EXACT

#: Window mode: with 5 % noise, the least-squares range rate over K = 5 samples at 20 Hz has
#: σ ≈ 6.3 × 5 % × range, about 0.95 m/s at 3 m: speeds, F1 and F4 are noise wherever a sonar has an echo.
_SPEED_NOISE = "5 % range noise makes the K = 5 range-rate σ ≈ 0.6-0.95 m/s at 2-3 m: "
_TRACK_NOISE = "5 % range noise (σ 0.35 m at 7 m) on the tracks: "
NOT_REPRODUCED_NOISY = {
    "tracker": {
        ("exp01", "first_winner_is_s4"): _LAG + "or the noise makes the static target win before it starts; 14/20 pass",
        ("exp01", "quiet_once_static"): "the track's speed takes ~0.5 s to fall after the target stops at 6 m "
        "(0.3-0.4 m/s at 8.5-8.65 s): s4 fires once or twice more (0/20 seeds)",
        ("exp03", "moving_robot_dominates_L"): _LAG + "and noisy F1 elsewhere: 35-68 of 447 steps (0/20 seeds)",
        ("exp04", "F4_is_1_while_goal_holds"): _LAG + "as noise-free, and noise: 14-33 steps (0/20 seeds)",
        ("exp04", "winners_top_down"): _TRACK_NOISE + "the target still at 7 m or a noisy F4 < 1 fires bottom-up "
        "at the target; with starts judged sooner, a bottom-up course fired at the start still runs when the "
        "goal is judged (1/20 seeds)",
        ("exp04", "no_ior"): "vigilance as noise-free, and bottom-up fires bring IOR (0/20 seeds)",
        ("exp04", "M_rises_within_onset"): _TRACK_NOISE + "the first top-down fire's hold is often released "
        "before its 200 ms onset (12/20 seeds)",
        ("exp04", "combined_L_exceeds_single"): _MEAN + " (0/20 seeds)",
        ("exp05", "faster_holds_focus"): _LAG + "as noise-free (0/20 seeds)",
        ("exp05", "top_down_never_below_1"): "vigilance as noise-free (1/20 seeds)",
    },
    "window": {
        **{
            key: reason
            for key, reason in NOT_REPRODUCED_EXACT["window"].items()
            if key != ("exp02", "ior_visits_several_regions")
        },  # with noise the room's focus wanders further
        ("exp01", "first_winner_is_s4"): _SPEED_NOISE + "the static target at 3 m already wins at 0.05 s (0/20)",
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
    },
    # with noise the room's focus wanders further, so IOR visits several regions (20/20 seeds)
    "truth": {key: reason for key, reason in _TRUTH_EXACT.items() if key != ("exp02", "ior_visits_several_regions")},
}


def _cases(table):
    for mode in MODES:
        for name in EXPERIMENT_NAMES:
            for check in CHECKS[name]:
                reason = table[mode].get((name, check))
                marks = [pytest.mark.xfail(strict=True, reason=reason)] if reason else []
                yield pytest.param(mode, name, check, marks=marks, id=f"{mode}-{name}-{check}")


@functools.cache
def _exact(mode, name):
    return {c.name: c for c in check_experiment(run_experiment(name, kinematics=mode))}


@pytest.mark.parametrize(("mode", "name", "check"), list(_cases(NOT_REPRODUCED_EXACT)))
def test_criterion_holds_exactly_without_noise(mode, name, check):
    outcome = _exact(mode, name)[check]
    assert outcome.passed, outcome.measured


@functools.cache
def _noisy_rates(mode, name):
    return pass_rates(name, NOISE, SEEDS, kinematics=mode)


@pytest.mark.parametrize(("mode", "name", "check"), list(_cases(NOT_REPRODUCED_NOISY)))
def test_criterion_holds_in_80_percent_of_20_noisy_seeds(mode, name, check):
    rate = _noisy_rates(mode, name)[check]
    assert rate >= MIN_PASS_RATE, f"{check} passes in {rate:.0%} of {len(SEEDS)} seeds at {NOISE:.0%} noise ({mode})"


def test_check_messages_name_regions_by_their_sonar_and_index():
    first = _exact("window", "exp01")["first_winner_is_s4"]
    assert first.passed and "s4 (region 3)" in first.criterion
    assert first.measured.startswith("first winner s4 (region 3) at ")
    assert _exact("window", "exp01")["far_regions_never_win"].measured == "far regions that won: none"
    assert (
        "regions fired in the first 3 s: s3 (region 2), s6 (region 5)"
        in _exact("window", "exp02")["ior_visits_several_regions"].measured
    )


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
    assert result.mover_positions.shape == result.mover_velocities.shape == (n, 2, 2)
    assert result.sees.shape == (n, 2, 8) and result.laser_sees.shape == (n, 2) and result.laser_sees[0].all()
    assert result.region_speeds.shape == (n, 8) and np.array_equal(result.sonar_time_s, result.trace.t)
    assert result.mover_names == ("fast", "slow")
    change = experiment.goal_changes[0]
    assert result.goal_index[0] == 0 and result.goal_index[np.searchsorted(result.trace.t, change.t_s)] == 1
    assert experiment.goals_at(change.t_s) == change.goals and experiment.goals_at(0.0) == experiment.goals
    assert np.all(result.trace.F[:, [1, 2, 4, 5]] == 0.0)  # only F1 and F4 are active
    assert result.kinematics == result.trace.config["kinematics"] == "tracker"
    assert not result.scan_times_given and result.profile is None


@pytest.mark.parametrize(("noise", "sigma"), [(0.0, 0.0), (0.05, 0.05), (0.2, 0.2)])
def test_the_model_assumes_the_runs_gaussian_sigma(noise, sigma):
    from attentive_gym.sensors import LaserConfig

    config = run_experiment("exp01", noise=noise, kinematics="window").trace.config
    assert config["range_noise_rel"] == sigma and config["ego_motion"] is None and config["kinematics"] == "window"
    assert (config["laser_mount_x_m"], config["laser_mount_y_m"]) == (LaserConfig().mount_x_m, LaserConfig().mount_y_m)


def test_usarsim_profile_holds_scans_and_passes_their_times():
    result = run_experiment("exp01", seed=2, profile="usarsim")
    assert (result.noise, result.noise_model, result.profile, result.scan_times_given) == (
        0.05,
        "uniform",
        "usarsim",
        True,
    )
    assert math.isclose(result.trace.config["range_noise_rel"], 0.05 / math.sqrt(3.0))
    scans = np.unique(result.laser_time_s)
    assert np.allclose(np.diff(scans), 0.2) and np.all(result.laser_time_s <= result.trace.t)
    held = np.flatnonzero(np.diff(result.sonar_time_s) == 0) + 1
    assert held.size and np.array_equal(result.trace.O1[held], result.trace.O1[held - 1])  # readings hold
    relative = np.abs(result.trace.O2 / run_experiment("exp01", profile="usarsim", noise=0.0).trace.O2 - 1)
    assert relative.max() <= 0.05 + 1e-9  # uniform ±5 %
    assert [c.name for c in check_experiment(result)] == list(CHECKS["exp01"])


def test_config_reaches_the_model():
    result = run_experiment("exp04", config={"normalise_combined": False, "threshold": 0.2, "range_noise_rel": 0.1})
    config = result.trace.config
    assert (config["normalise_combined"], config["threshold"], config["range_noise_rel"]) == (False, 0.2, 0.1)
    assert result.trace.C.max() > 1.0  # the weighted sum of F1 and F4, no longer their mean


@pytest.mark.parametrize(
    "bad",
    [
        {"name": "exp6"},
        {"name": None},
        {"name": "exp01", "noise": -0.1},
        {"name": "exp01", "noise": float("nan")},
        {"name": "exp01", "noise": 0.6},
        {"name": "exp01", "seed": -1},
        {"name": "exp01", "seed": 1.5},
        {"name": "exp01", "seed": True},
        {"name": "exp01", "kinematics": "kalman"},
        {"name": "exp01", "kinematics": None},
        {"name": "exp01", "profile": "usarsim2"},
        {"name": "exp01", "config": {"ego_motion": "odometry"}},
        {"name": "exp01", "config": {"kinematics": "window"}},
        {"name": "exp01", "config": {"no_such_field": 1}},
        {"name": "exp01", "config": [1]},
        {"name": "exp01", "config": {"threshold": -1.0}},
    ],
)
def test_bad_input_raises_a_clear_value_error(bad):
    with pytest.raises(
        ValueError, match="exp01, exp02, exp03, exp04, exp05|noise|seed|kinematics|profile|config|threshold"
    ):
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
    assert main(["experiment", "exp02", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "exp02: 3/4 checks pass" in out and "PASS static_scene_fires" in out
    assert (tmp_path / "exp02.png").is_file() and (tmp_path / "exp02.npz").is_file()
    before = (tmp_path / "exp02.png").read_bytes()
    assert main(["experiment", "exp02", "--noise", "0.05", "--out", str(tmp_path)]) == 2  # would replace them
    assert "exp02.npz" in capsys.readouterr().err and (tmp_path / "exp02.png").read_bytes() == before
    assert main(["experiment", "exp02", "--noise", "0.05", "--out", str(tmp_path), "--overwrite"]) == 0
    assert (tmp_path / "exp02.png").read_bytes() != before
    capsys.readouterr()
    assert main(["experiment", "exp01", "--kinematics", "window"]) == 0
    assert "exp01: 5/5 checks pass" in capsys.readouterr().out
    assert main(["experiment", "exp01", "--profile", "usarsim", "--seed", "3"]) == 0
    assert "exp01: " in capsys.readouterr().out


def test_cli_all_runs_the_five(capsys):
    assert main(["experiment", "all", "--noise", "0.05", "--seed", "1"]) == 0
    out = capsys.readouterr().out
    assert all(f"{name}: " in out for name in EXPERIMENT_NAMES)


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["exp9"], "allowed: exp01"),
        (["exp01", "--noise", "2"], "noise"),
        (["exp01", "--seed", "-3"], "seed"),
        (["exp01", "--kinematics", "kalman"], "kinematics must be one of"),
        (["all", "--profile", "gazebo"], "profile must be None or one of"),
    ],
)
def test_cli_bad_input_is_one_line_and_exit_2(argv, message, capsys):
    assert main(["experiment", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and message in err


def test_an_out_that_is_a_file_is_refused_before_any_run(tmp_path, capsys, monkeypatch):
    import attentive_gym.experiments.cli as experiment_cli

    monkeypatch.setattr(experiment_cli, "run_experiment", lambda *a, **k: pytest.fail("an experiment ran"))
    (tmp_path / "file").write_text("mine")
    assert main(["experiment", "all", "--out", str(tmp_path / "file")]) == 2
    assert "--out" in capsys.readouterr().err and (tmp_path / "file").read_text() == "mine"


def test_table_has_a_column_per_mode_and_the_profile():
    measured = measure(seeds=[0], names=("exp02",))
    text = markdown(measured, n_seeds=1)
    lines = text.splitlines()
    assert len(lines) == 2 + len(CHECKS["exp02"]) + 1
    assert all(line.count("|") == 3 + len(COLUMNS) for line in lines)
    assert "tracker, usarsim" in lines[0] and "| exp02 | `ior_visits_several_regions` | **fail**;" in text
    cell = measured[("exp02", "static_scene_fires")]
    assert all(cell["exact"].values()) and set(cell["rate"]) == set(COLUMNS)


def test_the_causes_rerun_every_check_with_the_tracker_and_the_bound_under_each_setting_over_the_config():
    rows = measure_causes(config={"threshold": 0.2}, names=("exp05",))
    assert [(row["kinematics"], row["setting"], row["check"]) for row in rows] == [
        (kinematics, label, check)
        for kinematics in CAUSE_KINEMATICS
        for label, _ in CAUSE_SETTINGS
        for check in CHECKS["exp05"]
    ]
    for row in rows:
        fields = dict(CAUSE_SETTINGS)[row["setting"]]
        assert json.loads(row["config"]) == {"threshold": 0.2, **fields} and row["noise_free"] in ("pass", "fail")
    outcome = {(row["kinematics"], row["setting"], row["check"]): row["noise_free"] for row in rows}
    for kinematics in CAUSE_KINEMATICS:  # no adaptation: M stays >= 1 on course
        assert outcome[(kinematics, "no vigilance", "top_down_never_below_1")] == "pass"


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--config", "[1]"], "config must be a mapping of AttentionConfig fields, got list"),
        (["--config", '"ab"'], "config must be a mapping"),
        (["--config", '{"treshold": 0.2}'], "unknown AttentionConfig field"),
        (["--workers", "0"], "workers must be an integer >= 1, got 0"),
        (["--noise", "0.9"], "noise must be a relative level in"),
    ],
)
def test_table_refuses_bad_flags_before_any_run(args, message, capsys, monkeypatch, tmp_path):
    from attentive_gym.experiments import table

    monkeypatch.setattr(table, "run_experiment", lambda *a, **k: pytest.fail("an experiment ran"))
    with pytest.warns(DeprecationWarning, match="use python tools/experiments_table.py"):
        assert table.main(["--seeds", "1", "--csv", str(tmp_path / "checks.csv"), *args]) == 2  # forwards to the tool
    assert message in capsys.readouterr().err and not (tmp_path / "checks.csv").exists()
    tool = load_tool("experiments_table")
    assert tool.main(["--seeds", "1", "--csv", str(tmp_path / "checks.csv"), *args]) == 2
    assert message in capsys.readouterr().err and not (tmp_path / "checks.csv").exists()


def test_the_deprecated_table_command_without_a_checkout_names_the_tool(monkeypatch, tmp_path):
    from attentive_gym.experiments import table

    monkeypatch.setattr(table, "_TOOLS", tmp_path / "tools")
    with pytest.warns(DeprecationWarning), pytest.raises(RuntimeError, match="tools/experiments_table.py"):
        table.main(["--seeds", "1"])


def test_the_tool_writes_the_measurement_as_rows_that_read_back(tmp_path, capsys, monkeypatch):
    from attentive_gym.experiments import table

    tool = load_tool("experiments_table")
    measured = measure(seeds=[0], names=("exp02",))
    calls = []
    monkeypatch.setattr(tool, "measure", lambda *args: calls.append(args) or measured)
    assert tool.main(["--seeds", "1", "--noise", "0.02", "--workers", "1", "--csv", str(tmp_path / "checks.csv")]) == 0
    assert calls == [(range(1), 0.02, None, 1)]
    with open(tmp_path / "checks.csv", newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert len(rows) == len(CHECKS["exp02"]) * len(COLUMNS)
    assert table.from_rows(rows) == (measured, 1, 0.02, {})
    assert markdown(measured, 1, 0.02) in capsys.readouterr().out


def test_noise_in_titles_keeps_its_digits():
    result = run_experiment("exp02", noise=0.025, seed=1)
    assert result.describe_noise() == "noise 2.5 %, seed 1"


def test_experiment_modules_import_without_a_cycle():
    """Each module of attentive_gym.experiments imports only modules before it (no cycle)."""
    folder = Path(__file__).resolve().parents[2] / "attentive_gym" / "experiments"
    graph = {}
    for path in folder.glob("*.py"):
        if path.stem == "__init__":
            continue
        imported = set()
        for node in ast.walk(ast.parse(path.read_text())):
            if (
                isinstance(node, ast.ImportFrom)
                and node.module
                and node.module.startswith("attentive_gym.experiments.")
            ):
                imported.add(node.module.rsplit(".", 1)[1])
        graph[path.stem] = imported
    done, active = set(), set()

    def visit(module, chain):
        assert module not in active, f"import cycle: {' -> '.join(chain)}"
        if module in done:
            return
        active.add(module)
        for other in graph.get(module, ()):
            visit(other, chain + [other])
        active.discard(module)
        done.add(module)

    for module in graph:
        visit(module, [module])


def test_the_perfect_perception_bound_sees_the_start_at_once_and_replays_its_own_truth():
    from attentive_gym.experiments.checks import _replayed_L

    result = run_experiment("exp01", kinematics="truth")
    assert result.kinematics == "truth" and result.trace.config["kinematics"] == "tracker"
    first = _exact("truth", "exp01")["first_winner_is_s4"]
    assert first.passed and first.measured == "first winner s4 (region 3) at 0.55 s, motion starts at 0.55 s"
    tracker = _exact("tracker", "exp01")["first_winner_is_s4"].measured
    assert "at 0.55 s, motion" not in tracker  # the tracker needs scans to see the start
    # the result's stored truth (laser_movers, robot_poses) is what the run fed the model
    replayed = _replayed_L(result, result.experiment.weights)
    assert np.array_equal(replayed, result.trace.L)
    beams = result.laser_movers[result.laser_sees[:, 0]]
    assert result.laser_movers.shape == (result.trace.n_steps, 180) and (beams == 0).any(axis=1).all()


def test_checks_read_the_truths_speed_at_the_step():
    from attentive_gym.experiments.checks import _Run

    result = run_experiment("exp04", kinematics="truth")
    run = _Run(result)
    k = int(np.argmax(np.linalg.norm(result.mover_velocities[:, 0], axis=1) > 0.1))  # the target starts
    assert run.speed(0, k) == pytest.approx(float(np.linalg.norm(result.mover_velocities[k, 0])))
    tracker = _Run(run_experiment("exp04", kinematics="tracker"))
    assert tracker.speed(0, k) < run.speed(0, k)  # the tracker's window average lags the start
