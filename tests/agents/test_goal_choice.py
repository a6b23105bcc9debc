"""goal_choice.csv: what a goal-action agent chooses at each evaluation, gathered by compare and drawn."""

import math

import pytest

from attentive_gym.agents.compare import collect
from attentive_gym.agents.goal_choice import (
    GOAL_CHOICE_FILE,
    WEIGHT_COLUMNS,
    GoalChoiceTally,
    goal_choice_columns,
    goal_share_columns,
)
from attentive_gym.agents.results import read_csv
from attentive_gym.agents.training import train
from attentive_gym.wrappers import DEFAULT_GOAL_MENU
from attentive_gym.wrappers.goal_action import DEFAULT_MAX_WEIGHT
from support import load_test_module

Interrupt = load_test_module("agents/test_training.py").Interrupt
K = len(DEFAULT_GOAL_MENU)
SHARES = goal_share_columns(K)


def _check_rows(run_dir):
    """The run's goal_choice.csv rows, checked against its eval.csv: one per evaluation, the
    evaluation's steps counted, shares and weights in range."""
    rows, evaluations = read_csv(run_dir / GOAL_CHOICE_FILE), read_csv(run_dir / "eval.csv")
    assert list(rows[0]) == list(goal_choice_columns(K))
    assert [r["env_steps"] for r in rows] == [r["env_steps"] for r in evaluations]
    for row, evaluation in zip(rows, evaluations):
        assert (row["variant"], row["seed"]) == ("goal-action", 0)
        assert row["n_steps"] == round(evaluation["n_episodes"] * evaluation["mean_episode_length"])
        shares = [row[column] for column in SHARES]
        assert all(0.0 <= share <= 1.0 for share in shares) and math.isclose(sum(shares), 1.0, abs_tol=1e-5)
        # the task's goal is one of the menu's two task goals (entries 1 and 2)
        assert 0.0 <= row["task_goal_share"] <= row["goal_share_1"] + row["goal_share_2"] + 1e-6
        assert all(0.0 <= row[column] <= DEFAULT_MAX_WEIGHT for column in WEIGHT_COLUMNS)
    return rows


def test_a_goal_action_run_writes_its_choices_and_compare_gathers_them(tmp_path, tiny):
    spec = tiny(variant="goal-action")
    run_dir = tmp_path / "runs" / spec.run_name  # where compare keeps it
    train(spec, run_dir, tensorboard=False)
    rows = _check_rows(run_dir)
    assert [r["env_steps"] for r in rows] == [0, 128, 256, 384]
    result = collect(tmp_path, [spec])
    assert read_csv(tmp_path / GOAL_CHOICE_FILE) == rows
    assert result.goal_choice_figure == tmp_path / "goal_choice.png"
    assert result.goal_choice_figure.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_resumed_goal_action_run_keeps_one_row_per_evaluation(tmp_path, tiny):
    spec = tiny(variant="goal-action", checkpoint_every=128)
    run_dir = tmp_path / "run"
    with pytest.raises(KeyboardInterrupt):
        train(spec, run_dir, tensorboard=False, callbacks=[Interrupt(at=300)])
    assert [r["env_steps"] for r in read_csv(run_dir / GOAL_CHOICE_FILE)] == [0, 128, 256]
    train(spec, run_dir, tensorboard=False)
    assert [r["env_steps"] for r in _check_rows(run_dir)] == [0, 128, 256, 384]


def test_other_variants_write_no_goal_choice(tmp_path, tiny):
    spec = tiny(variant="focus", total_steps=128)
    run_dir = tmp_path / "runs" / spec.run_name
    train(spec, run_dir, tensorboard=False)
    assert (run_dir / "eval.csv").is_file() and not (run_dir / GOAL_CHOICE_FILE).exists()
    assert collect(tmp_path, [spec]).goal_choice_figure is None and not (tmp_path / GOAL_CHOICE_FILE).exists()


def test_the_tally_counts_steps_and_refuses_infos_without_a_choice():
    tally = GoalChoiceTally(3)
    for choice, matches, weights in ((0, False, [0.0] * 6), (2, True, [2.0] * 6), (2, True, [1.0, 0, 0, 0, 0, 2.0])):
        tally({"goal_choice": choice, "goal_choice_matches": matches, "map_weights": weights})
    row = tally.row()
    assert row["n_steps"] == 3 and row["task_goal_share"] == pytest.approx(2 / 3)
    assert [row[c] for c in goal_share_columns(3)] == pytest.approx([1 / 3, 0.0, 2 / 3])
    assert [row[c] for c in WEIGHT_COLUMNS] == pytest.approx([1.0, 2 / 3, 2 / 3, 2 / 3, 2 / 3, 4 / 3])
    with pytest.raises(ValueError, match="GoalActionWrapper"):
        tally({"goal": "none"})
    with pytest.raises(ValueError, match=r"menu index in \[0, 3\), got -1"):
        tally({"goal_choice": -1, "goal_choice_matches": False, "map_weights": [1.0] * 6})
    with pytest.raises(ValueError, match="no evaluation step"):
        GoalChoiceTally(3).row()
    with pytest.raises(ValueError, match="menu_size"):
        GoalChoiceTally(0)


def _hand_made_rows():
    """Two seeds at 0 and 100 env steps: the task goal's share grows from 0.2 to 0.7 (0.6, 0.8
    by seed); entry 1 takes the chosen share, entry 0 the rest; F4's weight from 1 to 2."""
    rows = []
    for seed, final in ((0, 0.6), (1, 0.8)):
        for steps, share in ((0, 0.2), (100, final)):
            weights = {column: 1.0 for column in WEIGHT_COLUMNS} | {"mean_weight_F4": 1.0 + steps / 100}
            shares = {column: 0.0 for column in SHARES} | {"goal_share_0": 1.0 - share, "goal_share_1": share}
            rows.append(
                {"variant": "goal-action", "seed": seed, "env_steps": steps, "n_steps": 80, "task_goal_share": share}
                | shares
                | weights
            )
    return rows


def test_the_goal_choice_figure_draws_shares_and_weights_across_seeds(tmp_path, monkeypatch):
    from attentive_gym.agents import plots

    figures = []
    monkeypatch.setattr(plots, "_save", lambda fig, path, layout=True: figures.append(fig) or path)
    plots.plot_goal_choice(_hand_made_rows(), tmp_path / "goal_choice.png")
    (figure,) = figures
    goals, weights = figure.axes
    labels = [line.get_label() for line in goals.get_lines()]
    assert labels == ["the task's goal", "no goal", "speed in [0.5, 0.9] m/s", *labels[3:]] and len(labels) == 1 + K
    task = goals.get_lines()[0]
    assert task.get_xdata().tolist() == [0, 100] and task.get_ydata().tolist() == pytest.approx([0.2, 0.7])
    f4 = [line for line in weights.get_lines() if line.get_label().startswith("F4")][0]
    assert f4.get_label() == "F4 (goal speed)" and f4.get_ydata().tolist() == pytest.approx([1.0, 2.0])
    assert len(weights.get_lines()) == 6
    assert goals.get_ylim()[0] < 0.0 < 1.0 < goals.get_ylim()[1] <= 1.05
    assert weights.get_ylim()[1] == pytest.approx(1.03 * DEFAULT_MAX_WEIGHT)
    assert "share" in goals.get_ylabel() and "0 to 2" in weights.get_ylabel()
    assert goals.get_xlabel() == weights.get_xlabel() == "environment steps"


def test_the_goal_choice_figure_is_written_and_refuses_rows_it_cannot_draw(tmp_path):
    from attentive_gym.agents.plots import plot_goal_choice

    path = plot_goal_choice(_hand_made_rows(), tmp_path / "goal_choice.png")
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with pytest.raises(ValueError, match="no goal-choice rows"):
        plot_goal_choice([], tmp_path / "none.png")
    two = _hand_made_rows() + [{**_hand_made_rows()[0], "variant": "goal-action (sac)"}]
    with pytest.raises(ValueError, match="one variant"):
        plot_goal_choice(two, tmp_path / "two.png")
    with pytest.raises(ValueError, match="menu of 3 entries"):
        plot_goal_choice(_hand_made_rows(), tmp_path / "short.png", menu=DEFAULT_GOAL_MENU[:3])
