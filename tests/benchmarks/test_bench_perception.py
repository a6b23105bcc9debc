"""Smoke test of ``benchmarks/bench_perception.py``: a tiny run gives metrics in range, and the
metrics tell a corrupted estimate, a perfect focus and a still robot apart."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from support import load_benchmark

from attentive_gym.attention import Goal

SEED = 0  # a seed whose first 2 s show a mover in front within 5 m for over 1 s
SECONDS = 2.0
GOAL = Goal.between("speed", 0.5, 0.9)  # a speed goal: goal agreement is defined


bench = load_benchmark("bench_perception")


@pytest.fixture(scope="module")
def records():
    """One 2 s window-mode episode, driving and still, noise-free."""
    env = bench.make_attentive_env("window", bench.NOISE_SETTINGS[0], **bench.PERCEPTION_ARENA)
    driving = bench.record_episode(env, SEED, GOAL, bench.Wander(SEED), SECONDS)
    still = bench.record_episode(env, SEED, GOAL, bench.stand_still, SECONDS)
    env.close()
    return driving, still


def test_metrics_are_finite_and_in_range(records):
    driving, _ = records
    metrics = bench.speed_metrics([driving])
    assert metrics["region_pairs"] > 0 and metrics["static_regions"] > 0
    for name in ("region_median_mps", "region_p90_mps", "region_rmse_mps", "static_median_mps", "static_p90_mps"):
        assert math.isfinite(metrics[name]) and metrics[name] >= 0.0, name
    assert metrics["region_median_mps"] <= metrics["region_p90_mps"]
    assert 0.0 <= metrics["goal_agreement_region"] <= 1.0
    for rate, steps in bench.focus_on_target([driving]).values():
        assert steps > 0 and 0.0 <= rate <= 1.0


def test_a_corrupted_estimate_has_a_larger_error(records):
    driving, _ = records
    real = bench.speed_metrics([driving])
    corrupted = bench.speed_metrics([dataclasses.replace(driving, region_speed=driving.region_speed + 1.0)])
    assert corrupted["region_pairs"] == real["region_pairs"]
    assert corrupted["region_median_mps"] > real["region_median_mps"]
    assert corrupted["region_rmse_mps"] > real["region_rmse_mps"]
    assert corrupted["static_median_mps"] == pytest.approx(real["static_median_mps"] + 1.0)


def test_the_true_speed_as_estimate_has_no_error(records):
    driving, _ = records
    visible = bench.in_view(driving.mover_xy)
    regions = bench.region_of(driving.mover_xy)
    true_speed = np.linalg.norm(driving.mover_velocity, axis=-1)
    perfect = driving.region_speed.copy()
    steps, movers = np.nonzero(visible)
    perfect[steps, regions[steps, movers]] = true_speed[steps, movers]
    # two movers in one region cannot both be right: keep the pairs alone in their region
    crowded = np.array([[np.sum(regions[k][visible[k]] == regions[k, m]) > 1 for m in range(visible.shape[1])]
                        for k in range(visible.shape[0])])
    record = dataclasses.replace(driving, region_speed=perfect, mover_xy=np.where(crowded[..., None], -1.0, driving.mover_xy))
    metrics = bench.speed_metrics([record])
    assert metrics["region_pairs"] > 0
    assert metrics["region_rmse_mps"] == pytest.approx(0.0, abs=1e-12)
    assert metrics["goal_agreement_region"] == 1.0


def test_a_focus_on_the_target_scores_one(records):
    driving, _ = records
    target_regions = bench.region_of(driving.mover_xy[:, driving.target])
    rates = bench.focus_on_target([dataclasses.replace(driving, focus=target_regions)])
    assert [rate for rate, _ in rates.values()] == [1.0]


def test_turns_and_view_time_select_pairs():
    steps = 80
    t_s = np.arange(1, steps + 1) * 0.05
    velocity = np.zeros((steps, 1, 2))
    velocity[:, 0] = (0.5, 0.0)
    velocity[40:, 0] = (0.0, 0.5)  # a 90° turn at step 40 (t = 2.05 s)
    xy = np.tile([[2.0, 0.0]], (steps, 1, 1))
    xy[:10] = (-2.0, 0.0)  # behind the robot until step 10 (in view from t = 0.55 s)
    record = bench.EpisodeRecord(GOAL, 0, t_s, xy, velocity, np.zeros((steps, 8)), None,
                                 np.full(steps, -1), np.zeros((steps, 8), bool))
    steady, transient = bench.pair_masks(record)
    # settled from t = 1.55 s (step 30); transient until 1 s after the turn (step 60)
    assert np.flatnonzero(steady[:, 0]).tolist() == list(range(30, 40)) + list(range(61, steps))
    assert np.flatnonzero(transient[:, 0]).tolist() == list(range(40, 61))


def test_still_robot_sees_static_structure_still(records):
    _, still = records
    metrics = bench.speed_metrics([still])
    assert metrics["static_median_mps"] == pytest.approx(0.0, abs=1e-9)  # noise-free, walls do not move


def test_controllers_and_csv(tmp_path):
    env = bench.make_attentive_env("window", bench.NOISE_SETTINGS[0], time_limit_s=1.0, **bench.CONTROL_ARENA)
    for make_policy in (lambda env, seed: bench.FocusController(env.unwrapped.dt),
                        lambda env, seed: bench.true_bearing_controller,
                        lambda env, seed: bench.RandomController(env.action_space, seed)):
        assert 0.0 <= bench.control_success(env, make_policy, [0]) <= 1.0
    focus_env = bench.make_attentive_env("tracker", bench.NOISE_SETTINGS[0], "focus", time_limit_s=1.0,
                                        **bench.CONTROL_ARENA)
    assert 0.0 <= bench.control_success(focus_env, lambda env, seed: bench.memory_controller, [0]) <= 1.0
    action = bench.steer(0.0)
    assert action.tolist() == [1.0, 0.0] and bench.steer(None).tolist() == [0.0, bench.SEARCH_SPIN]
    path = tmp_path / "out" / "figures.csv"
    bench.write_csv(path, [{"section": "speed", "mode": "window", "robot": "still", "noise": "gauss 0", "goal": "",
                            "metric": "region_median_mps", "value": 0.5}])
    assert path.read_text().splitlines()[1] == "speed,window,still,gauss 0,,region_median_mps,0.5,"
    assert [p.name for p in path.parent.iterdir()] == ["figures.csv"]


def test_memory_controller_steers_at_the_first_memory_row_only_when_it_matched_the_goal():
    memory = np.zeros((3, 6), np.float32)
    memory[0, :5] = [math.cos(0.5), math.sin(0.5), 2.0, 0.6, 1.0]  # 0.5 rad to the left, matched
    memory[1, :5] = [1.0, 0.0, 1.0, 0.3, 0.0]
    obs = {"memory": memory.ravel()}
    np.testing.assert_allclose(bench.memory_controller(obs, None), bench.steer(0.5), rtol=1e-6)
    memory[0, 4] = 0.0  # no goal match anywhere: search
    assert bench.memory_controller({"memory": memory.ravel()}, None).tolist() == bench.steer(None).tolist()


def _output(focus, fulfilled_region=None, inhibited=False, track_xy=None, track_age_s=2.0):
    """A stand-in for an ``AttentionOutput`` with one confirmed track at ``track_xy`` (none if None)."""
    from types import SimpleNamespace

    positions = np.zeros((0, 2)) if track_xy is None else np.array([track_xy], float)
    tracks = SimpleNamespace(confirmed=np.ones(len(positions), bool), position_m=positions,
                             age_s=np.full(len(positions), track_age_s))
    fulfilled = np.zeros(8, bool)
    if fulfilled_region is not None:
        fulfilled[fulfilled_region] = True
    M = np.ones(8)
    if inhibited:
        M[fulfilled_region] = 0.5
    return SimpleNamespace(focus=focus, tracks=tracks, goal_fulfilled=fulfilled, M=M)


def test_target_cases_tell_perception_from_selection():
    target = np.array([3.0, 0.1])  # region 3 (s4), 3 m ahead
    region = int(bench.region_of(target))
    assert region == 3
    case = bench.TARGET_CASES.index
    assert bench.target_case(_output(3), target, 5) == case("on target")
    assert bench.target_case(_output(1), target, 0) == case("hidden from the laser")
    assert bench.target_case(_output(1), target, 5) == case("seen, no track")
    assert bench.target_case(_output(1, track_xy=(3.0, 1.0)), target, 5) == case("seen, no track")  # 0.9 m off
    assert bench.target_case(_output(1, track_xy=(3.1, 0.1), track_age_s=0.5), target, 5) == case(
        "young track, goal not judged")
    assert bench.target_case(_output(1, track_xy=(3.1, 0.1)), target, 5) == case("track, goal not judged")
    assert bench.target_case(_output(None, 3, track_xy=(3.1, 0.1)), target, 5) == case("no focus")
    assert bench.target_case(_output(1, 3, inhibited=True, track_xy=(3.1, 0.1)), target, 5) == case("inhibited")
    assert bench.target_case(_output(1, 3, track_xy=(3.1, 0.1)), target, 5) == case("another region won")


def test_target_cases_of_a_tracker_episode_add_up_to_one():
    env = bench.make_attentive_env("tracker", bench.NOISE_SETTINGS[2], **bench.PERCEPTION_ARENA)
    record = bench.record_episode(env, SEED, GOAL, bench.stand_still, SECONDS)
    env.close()
    cases = bench.target_cases([record])
    assert sum(cases.values()) == pytest.approx(1.0)
    visible = bench.in_view(record.mover_xy[:, record.target])
    on_target = record.focus[visible] == bench.region_of(record.mover_xy[visible, record.target])
    assert cases["case_on_target"] == pytest.approx(on_target.mean())
    assert math.isnan(bench.target_cases([dataclasses.replace(record, target_case=None)])["case_on_target"])


def test_focus_after_turns_splits_the_steps_at_the_target_s_turns():
    steps = 60
    t_s = np.arange(1, steps + 1) * 0.0625  # steps of 1/16 s: 1 s after a step is exactly a step
    velocity = np.zeros((steps, 1, 2))
    velocity[:, 0] = (0.5, 0.0)
    velocity[30:, 0] = (-0.5, 0.0)  # the target reverses at step 30
    xy = np.tile([[2.0, 0.0]], (steps, 1, 1))  # in view, region 3 or 4 (on the axis)
    region = int(bench.region_of(xy[0, 0]))
    focus = np.full(steps, region)
    focus[30:47] = -1  # lost for the 17 steps within 1 s after the turn (its end included)
    record = bench.EpisodeRecord(GOAL, 0, t_s, xy, velocity, np.zeros((steps, 8)), None, focus,
                                 np.zeros((steps, 8), bool))
    rates = bench.focus_after_turns([record])
    assert rates == {"focus_on_target_after_turn": 0.0, "focus_on_target_otherwise": 1.0}


def test_focus_by_track_age_groups_the_steps_by_the_target_track_s_age():
    steps = 10
    xy = np.tile([[2.0, 0.0]], (steps, 1, 1))  # in view
    xy[9] = (-2.0, 0.0)  # behind the robot: not counted
    region = int(bench.region_of(xy[0, 0]))
    age = np.array([np.nan, np.nan, 0.2, 0.9, 1.0, 1.5, 3.0, 4.0, 9.0, 9.0])
    focus = np.array([region, -1, -1, region, region, region, -1, region, region, -1])
    record = bench.EpisodeRecord(GOAL, 0, np.arange(1, steps + 1) * 0.05, xy, np.zeros((steps, 1, 2)),
                                 np.zeros((steps, 8)), None, focus, np.zeros((steps, 8), bool), target_track_age=age)
    by_age = bench.focus_by_track_age([record])
    assert by_age["focus_on_target_no_track"] == 0.5
    assert by_age["focus_on_target_track_0_to_1_s"] == 0.5
    assert by_age["focus_on_target_track_1_to_2_s"] == 1.0  # an age of exactly 1 s falls in the upper bin
    assert by_age["focus_on_target_track_2_to_4_s"] == 0.0
    assert by_age["focus_on_target_track_over_4_s"] == 1.0
    assert by_age["steps_no_track"] == pytest.approx(2 / 9)
    assert sum(v for k, v in by_age.items() if k.startswith("steps_")) == pytest.approx(1.0)
    assert bench.focus_by_track_age([dataclasses.replace(record, target_track_age=None)]) == {}


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


def test_cost_times_the_compiled_step_inside_the_model_step():
    readings, goal = bench.record_readings(0.5)
    model = bench.AttentionModel(bench.AttentionConfig(range_noise_rel=0.05))
    model.set_goals(goal)
    compiled_step = bench.model_module.attend_one
    bench.time_model_us(model, readings)  # numba compiles
    total, compiled, tracker = bench.time_model_us(model, readings)
    assert bench.model_module.attend_one is compiled_step  # put back after its pass
    assert 0.0 < compiled < total and tracker > 0.0  # the compiled step was called, and is a part of the step


def test_focus_relative_to_noise_free_divides_by_the_same_mode_and_robot():
    quiet, noisy = bench.NOISE_SETTINGS[0].name, bench.NOISE_SETTINGS[2].name
    focus = {("tracker", "still", quiet): {"a": 0.8, "b": 0.0},
             ("tracker", "still", noisy): {"a": 0.6, "b": 0.1},
             ("tracker", "driving", noisy): {"a": 0.5, "b": 0.5}}  # no noise-free row: no ratio
    results = bench.Results()
    rows = bench._focus_relative_to_noise_free(results, focus, ["a", "b"])
    assert rows == [["tracker", "still", noisy, "0.750", "—"]]  # 0.6 / 0.8; b has no noise-free focus to divide by
    ratios = {row["goal"]: row["value"] for row in results.rows}
    assert ratios["a"] == pytest.approx(0.75) and math.isnan(ratios["b"])
