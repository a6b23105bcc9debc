"""``benchmarks/bench_perception.py``'s own sections: tiny runs print their tables and tidy CSV
rows (the controllers and metrics it uses are tested in ``tests/perception``)."""

from __future__ import annotations

import math

import pytest

from support import load_benchmark

bench = load_benchmark("bench_perception")


def test_the_perception_tables_and_their_csv_rows(tmp_path, capsys):
    results = bench.Results()
    bench.print_perception(results, ["window"], episodes=1, seconds=1.5, sections=["speed", "focus"])
    out = capsys.readouterr().out
    assert "### Perception (1 episodes × 1.5 s per row" in out and "Focus on target relative" in out
    for noise in bench.NOISE_SETTINGS:
        assert f"| window | still | {noise.name} |" in out and f"| window | driving | {noise.name} |" in out
        for robot in bench.ROBOT_MODES:  # the bound beside the modes, and each mode over it
            assert f"| {bench.BOUND} | {robot} | {noise.name} |" in out
    assert "Focus on target relative to the perfect-perception bound" in out
    bound = [row for row in results.rows if row["mode"] == bench.BOUND]
    rates = ("focus_on_target", "focus_on_target_in_sight")
    assert {row["metric"] for row in bound} == {
        *rates,
        *(f"{rate}_{end}" for rate in rates for end in ("low", "high")),
        "target_in_view_steps",
        "target_in_sight_steps",
    }
    # one goal in one episode: in view and in sight, a rate, its interval and a step count each
    assert len(bound) == 8 * len(bench.NOISE_SETTINGS) * len(bench.ROBOT_MODES)
    # one episode gives no interval
    assert all(math.isnan(row["value"]) for row in bound if row["metric"].endswith(("_low", "_high")))
    steps = {
        (row["mode"] == bench.BOUND, row["robot"], row["noise"]): row["value"]
        for row in results.rows
        if row["metric"] == "target_in_view_steps"
    }
    assert all(steps[(True, robot, noise)] == steps[(False, robot, noise)] for _, robot, noise in steps)  # same steps
    assert any(row["metric"] == "focus_over_bound" for row in results.rows)
    assert {row["section"] for row in results.rows} == {"speed", "focus"}
    assert {row["noise"] for row in results.rows} == {noise.name for noise in bench.NOISE_SETTINGS}
    path = tmp_path / "out" / "figures.csv"
    bench.write_csv(path, results.rows)
    lines = path.read_text().splitlines()
    assert lines[0] == "section,mode,robot,noise,goal,metric,value,distractors" and len(lines) == len(results.rows) + 1


def test_write_csv_writes_tidy_rows_atomically(tmp_path):
    path = tmp_path / "out" / "figures.csv"
    bench.write_csv(
        path,
        [
            {
                "section": "speed",
                "mode": "window",
                "robot": "still",
                "noise": "gauss 0",
                "goal": "",
                "metric": "region_median_mps",
                "value": 0.5,
            }
        ],
    )
    assert path.read_text().splitlines()[1] == "speed,window,still,gauss 0,,region_median_mps,0.5,"
    assert [p.name for p in path.parent.iterdir()] == ["figures.csv"]


def test_clutter_section_reports_each_distractor_count(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(bench, "CLUTTER_ARENA", {**bench.CLUTTER_ARENA, "time_limit_s": 1.0})
    monkeypatch.setattr(bench, "CLUTTER_DISTRACTORS", (1, 3))
    built = []  # the distractor count of every env the section makes

    def spy(make):
        def wrapped(*args, **kwargs):
            env = make(*args, **kwargs)
            built.append(env.unwrapped.arena.num_distractors)
            return env

        return wrapped

    monkeypatch.setattr(bench, "make_raw_env", spy(bench.make_raw_env))
    monkeypatch.setattr(bench, "make_attentive_env", spy(bench.make_attentive_env))
    results = bench.Results()
    bench.print_clutter(results, ["tracker"], episodes=1, seconds=1.0, control_episodes=1)
    assert built == [1, 1, 1, 3, 3, 3]  # raw, attended, focus per count
    by_count = {}
    for row in results.rows:
        assert row["section"] == "clutter" and row["noise"] == bench.CLUTTER_NOISE
        by_count.setdefault(row["distractors"], {})[row["metric"]] = row["value"]
    assert sorted(by_count) == [1, 3]
    for metrics in by_count.values():
        for name in ("success_memory", "success_true_bearing", "success_random"):
            assert metrics[name] in (0.0, 1.0)  # one episode each
        assert metrics["target_in_view_steps"] >= 0
        assert math.isnan(metrics["focus_on_target"]) or 0.0 <= metrics["focus_on_target"] <= 1.0
    table = capsys.readouterr().out
    assert "| 1 | tracker |" in table and "| 3 | tracker |" in table
    path = tmp_path / "clutter.csv"
    bench.write_csv(path, results.rows)
    assert path.read_text().splitlines()[1].endswith(",1")  # the distractor count, last column


def test_motion_section_reports_each_scene_noise_and_robot(tmp_path, capsys):
    results = bench.Results()
    bench.print_motion(results, ["tracker"], episodes=1, seconds=1.0)
    configs = {(row["scene"], row["noise"], row["robot"]) for row in results.rows}
    assert configs == {
        (scene, noise, robot)
        for scene in ("stop-and-go", "along-structure")
        for noise in bench.MOTION_NOISE
        for robot in bench.ROBOT_MODES
    }
    for row in results.rows:
        assert row["section"] == "motion" and row["mode"] == "tracker"
        if row["metric"] in ("false_label_steps", "false_in_band_steps"):
            assert 0.0 <= row["value"] <= 1.0
    table = capsys.readouterr().out
    assert "| stop-and-go | gauss 0 | still | tracker |" in table
    path = tmp_path / "motion.csv"
    bench.write_csv(path, results.rows)
    assert path.read_text().splitlines()[1].endswith(",stop-and-go")  # the scene, last column


def test_cost_times_the_compiled_step_inside_the_model_step():
    readings, goal = bench.record_readings(0.5)
    model = bench.AttentionModel(bench.AttentionConfig(range_noise_rel=0.05))
    model.set_goals(goal)
    compiled_step = bench.model_module.attend_many
    bench.time_model_us(model, readings)  # numba compiles
    total, compiled, tracker = bench.time_model_us(model, readings)
    assert bench.model_module.attend_many is compiled_step  # put back after its pass
    # the compiled step was called (its time is taken in a pass of its own, so it is not
    # compared with the step's: on a loaded machine either pass can be the slower)
    assert compiled > 0.0 and total > 0.0 and tracker > 0.0


def test_cost_times_the_asked_configuration_beside_version_0(monkeypatch, capsys):
    """The cost section builds its models from ``--config``'s fields (a candidate is timed, not
    the defaults) and times the tracker with version 0's defaults in the same rounds."""
    built = []

    class RecordingModel(bench.AttentionModel):
        def __init__(self, config):
            built.append(config)
            super().__init__(config)

    monkeypatch.setattr(bench, "AttentionModel", RecordingModel)
    monkeypatch.setattr(bench, "COST_RECORD_S", 0.5)
    monkeypatch.setattr(bench, "ATTENTION_FIELDS", {"free_space_lags_s": (0.1, 0.3)})
    results = bench.Results()
    bench.print_cost(results, ["tracker"], rounds=1)
    assert [config.free_space_lags_s for config in built] == [(0.1, 0.3), bench.AttentionConfig().free_space_lags_s]
    assert built[0].free_space_evidence and not built[1].free_space_evidence  # version 1's, then version 0's
    assert {row["mode"] for row in results.rows} == {"tracker", bench.VERSION_0_TRACKER}
    assert f"| {bench.VERSION_0_TRACKER} |" in capsys.readouterr().out


def test_focus_relative_to_noise_free_divides_by_the_same_mode_and_robot():
    quiet, noisy = bench.NOISE_SETTINGS[0].name, bench.NOISE_SETTINGS[2].name
    focus = {
        ("tracker", "still", quiet): {"a": 0.8, "b": 0.0},
        ("tracker", "still", noisy): {"a": 0.6, "b": 0.1},
        ("tracker", "driving", noisy): {"a": 0.5, "b": 0.5},
    }  # no noise-free row: no ratio
    results = bench.Results()
    rows = bench._focus_relative_to_noise_free(results, focus, ["a", "b"])
    assert rows == [["tracker", "still", noisy, "0.750", "—"]]  # 0.6 / 0.8; b has no noise-free focus to divide by
    ratios = {row["goal"]: row["value"] for row in results.rows}
    assert ratios["a"] == pytest.approx(0.75) and math.isnan(ratios["b"])


def test_focus_relative_to_bound_divides_by_the_same_robot_and_noise():
    quiet, noisy = bench.NOISE_SETTINGS[0].name, bench.NOISE_SETTINGS[2].name
    focus = {
        ("tracker", "still", quiet): {"a": 0.6, "b": 0.3},
        ("window", "still", quiet): {"a": 0.4, "b": 0.3},
        ("tracker", "driving", noisy): {"a": 0.5, "b": 0.5},
    }  # no bound of the driving robot at that noise: no ratio
    bound = {("still", quiet): {"a": 0.8, "b": 0.0}}
    results = bench.Results()
    rows = bench._focus_relative_to_bound(results, focus, bound, ["a", "b"])
    assert rows == [["tracker", "still", quiet, "0.750", "—"], ["window", "still", quiet, "0.500", "—"]]
    ratios = [(row["mode"], row["goal"], row["value"]) for row in results.rows]
    assert all(row["metric"] == "focus_over_bound" for row in results.rows)
    assert ratios[0] == ("tracker", "a", pytest.approx(0.75)) and math.isnan(ratios[1][2])
