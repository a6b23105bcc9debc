"""The RL results come from the committed CSVs, and batches merge into them: the library's
computations (``attentive_gym.agents.merged``) and ``tools/report.py``'s ``add`` and ``render``."""

import json
import math
import re
import shutil
import warnings
from pathlib import Path

import pytest

from attentive_gym.agents.merged import (
    budgets,
    clutter_targets,
    default_tag,
    labelled,
    merge_rows,
    summarise_by_setting,
    targets,
)
from attentive_gym.agents.results import (
    EVAL_COLUMNS,
    SAFE_COLUMNS,
    read_csv,
    summarise,
    summary_markdown,
    write_csv_atomic,
)
from attentive_gym.agents.sweep import sweep_tables
from support import load_tool

report = load_tool("report")
main, rl_page, headline = report.main, report.rl_page, report.headline
render_block = rl_page.results_markdown
#: The repository's results folder: the CSVs of the other pages come from there.
RESULTS = Path(__file__).resolve().parents[2] / "docs" / "results"
#: The tags of rows trained with today's defaults: an attended variant's (on the headline's model
#: version) and raw's or the oracle's (which run no model, so carry no model note).
TODAY, TODAY_UNNOTED = default_tag("focus"), default_tag("raw")
#: ``compare.json``'s run settings of a comparison trained with today's defaults.
TODAY_RUN = {
    "algo": "ppo",
    "algo_defaults": 3,
    "env_version": 2,
    "task_version": 1,
    "warm_start": "default",
    "total_steps": 1_000_000,
}


def _today(rows, **fields):
    """``rows`` tagged as trained with today's defaults (each variant's own tag), with ``fields``."""
    return [{**row, "algo": default_tag(row["variant"]), "obs_scaling": "running", **fields} for row in rows]


def _root(tmp_path, readme="# title\n\n{start}\nold\n{end}\n\nafter\n"):
    """A repository root with the committed perception, checks and performance CSVs, no RL
    rows and a README holding ``readme`` (``{start}``/``{end}``: the headline's markers)."""
    (tmp_path / "docs" / "results").mkdir(parents=True)
    for name in (
        "perception.csv",
        "perception_clutter.csv",
        "perception_motion.csv",
        "experiment_checks.csv",
        "experiment_causes.csv",
        "safe_rescue.csv",
        "real_bags.csv",
        "goal_choice.csv",
        "generalisation.csv",
        "performance.csv",
    ):
        shutil.copy(RESULTS / name, tmp_path / "docs" / "results" / name)
    if readme is not None:
        (tmp_path / "README.md").write_text(readme.format(start=headline.START, end=headline.END))
    return tmp_path


def _rows(levels, steps=(0, 100, 200)):
    """Evaluation rows: variant → per-seed final success, reached linearly from 0.1."""
    rows = []
    for variant, finals in levels.items():
        for seed, final in enumerate(finals):
            for k, step in enumerate(steps):
                success = 0.1 + (final - 0.1) * k / (len(steps) - 1)
                rows.append(
                    {
                        **{c: 0 for c in EVAL_COLUMNS},
                        "variant": variant,
                        "seed": seed,
                        "env_steps": step,
                        "success_rate": success,
                        "mean_return": success,
                    }
                )
    return rows


def test_targets_measure_speed_margin_and_gap_against_raw_and_oracle():
    rows = labelled(
        [
            {"algo": "ppo", "obs_scaling": "running", **r}
            for r in _rows(
                {
                    "raw": [0.40, 0.42, 0.44],
                    "oracle": [0.80, 0.82, 0.84],
                    "focus": [0.70, 0.72, 0.74],
                    "random-focus": [0.3, 0.3, 0.3],
                }
            )
        ]
    )
    (focus,) = targets(rows, summarise(rows))  # the controls and bounds are not "attended"
    assert focus["variant"] == "focus" and focus["above_raw"]
    assert focus["gap_closed"] == pytest.approx((0.72 - 0.42) / (0.82 - 0.42))
    # focus's mean curve 0.1 → 0.41 → 0.72 first reaches raw's final 0.42 at 200 of raw's 200 steps
    assert focus["steps_fraction"] == pytest.approx(1.0)


def test_merging_a_batch_replaces_its_runs_and_keeps_the_rest():
    old = [{"algo": "ppo", "obs_scaling": "running", **r} for r in _rows({"raw": [0.4, 0.5], "focus": [0.3]})]
    new = _rows({"focus": [0.6, 0.7]})
    merged = merge_rows(old, new, "ppo", ("variant", "seed"))
    focus = [r for r in merged if r["variant"] == "focus" and r["env_steps"] == 200]
    assert sorted(r["success_rate"] for r in focus) == pytest.approx([0.6, 0.7])
    assert len([r for r in merged if r["variant"] == "raw"]) == 6
    lstm = merge_rows(merged, _rows({"raw": [0.9]}), "recurrent-ppo", ("variant", "seed"))
    assert {r["variant"] for r in labelled(lstm)} == {"raw", "focus", "raw (recurrent-ppo)"}
    # rows from before the obs_scaling column are unscaled runs: kept beside the scaled ones
    before = merge_rows([{"algo": "ppo", **r} for r in _rows({"focus": [0.2]})], new, "ppo", ("variant", "seed"))
    assert {(r["obs_scaling"], r["seed"]) for r in before} == {("none", 0), ("running", 0), ("running", 1)}
    unscaled = merge_rows(before, _rows({"raw": [0.5]}), "recurrent-ppo", ("variant", "seed"), "none")
    assert {r["variant"] for r in labelled(unscaled)} == {"focus", "focus (unscaled)", "raw (recurrent-ppo, unscaled)"}


def test_targets_compare_within_one_algorithm_and_scaling():
    rows = labelled(
        [
            {"algo": "ppo", "obs_scaling": scaling, **r}
            for scaling, levels in (
                ("running", {"raw": [0.5, 0.5], "oracle": [0.9, 0.9], "focus": [0.7, 0.7]}),
                ("none", {"raw": [0.3, 0.3], "oracle": [0.5, 0.5], "focus": [0.4, 0.4]}),
            )
            for r in _rows(levels)
        ]
    )
    by_variant = {row["variant"]: row for row in targets(rows, summarise(rows))}
    assert by_variant.keys() == {"focus", "focus (unscaled)"}
    assert by_variant["focus"]["gap_closed"] == pytest.approx((0.7 - 0.5) / (0.9 - 0.5))
    assert by_variant["focus (unscaled)"]["gap_closed"] == pytest.approx((0.4 - 0.3) / (0.5 - 0.3))


def test_the_probability_of_improvement_is_taken_over_raw_of_the_same_setting():
    """Unscaled focus (0.4) beats unscaled raw (0.3) on every seed though it loses to the
    scaled raw (0.5); a setting without raw gets no probability; the table says which raw."""
    rows = labelled(
        [
            {"algo": algo, "obs_scaling": scaling, **r}
            for algo, scaling, levels in (
                ("ppo", "running", {"raw": [0.5, 0.5], "focus": [0.7, 0.7]}),
                ("ppo", "none", {"raw": [0.3, 0.3], "focus": [0.4, 0.4]}),
                ("sac", "running", {"focus": [0.6, 0.6]}),
            )
            for r in _rows(levels)
        ]
    )
    summary = summarise_by_setting(rows)
    by_variant = {row["variant"]: row for row in summary}
    assert [row["variant"] for row in summary] == ["raw", "focus", "raw (unscaled)", "focus (unscaled)", "focus (sac)"]
    assert by_variant["focus (unscaled)"]["prob_improvement"] == 1.0
    assert by_variant["focus (unscaled)"]["improvement_over"] == "raw (unscaled)"
    assert math.isnan(by_variant["focus (sac)"]["prob_improvement"])
    scaled_ppo = [row for row in rows if row["variant"] in ("raw", "focus")]
    assert by_variant["focus"] == summarise(scaled_ppo)[1]  # one setting: as summarise gives it
    assert "P(success > raw of its setting)" in summary_markdown(summary)


def test_attention_on_another_model_version_is_compared_with_raw_and_the_oracle_of_its_setting():
    """Raw and the oracle run no model, so their rows carry no model note: a focus on model
    version 1 (0.4, 0.4) is weighed against the raw (0.3) and oracle (0.5) of the same training
    setting, in the probability of improvement and in the share of the gap it closes."""
    rows = labelled(
        [
            {"algo": algo, "obs_scaling": "running", **r}
            for algo, levels in (
                ("ppo", {"raw": [0.3, 0.3], "oracle": [0.5, 0.5]}),
                ("ppo, model v1", {"focus": [0.4, 0.4]}),
                ("ppo, lr 1e-4, model v1", {"focus": [0.45, 0.45]}),
                ("ppo, lr 1e-4", {"raw": [0.5, 0.5], "oracle": [0.6, 0.6]}),
            )
            for r in _rows(levels)
        ]
    )
    summary = summarise_by_setting(rows)
    by_variant = {row["variant"]: row for row in summary}
    assert [row["variant"] for row in summary] == [
        "raw",
        "oracle",
        "focus (ppo, model v1)",
        "focus (ppo, lr 1e-4, model v1)",
        "raw (ppo, lr 1e-4)",
        "oracle (ppo, lr 1e-4)",
    ]
    assert by_variant["focus (ppo, model v1)"]["prob_improvement"] == 1.0  # beats raw (0.3)
    assert by_variant["focus (ppo, lr 1e-4, model v1)"]["prob_improvement"] == 0.0  # loses to its raw (0.5)
    gaps = {row["variant"]: row["gap_closed"] for row in targets(rows, summary)}
    assert gaps["focus (ppo, model v1)"] == pytest.approx(0.5)  # (0.4 - 0.3) / (0.5 - 0.3)
    assert gaps["focus (ppo, lr 1e-4, model v1)"] == pytest.approx(-0.5)  # (0.45 - 0.5) / (0.6 - 0.5)


def test_render_writes_the_pages_and_the_readme_headline_and_check_names_stale_files(tmp_path, capsys):
    results = tmp_path / "results.csv"
    levels = {
        "oracle": [0.9, 0.8, 0.85],
        "focus": [0.5, 0.6, 0.55],
        "raw": [0.4, 0.5, 0.45],
        "random-focus": [0.45, 0.5, 0.4],
    }
    write_csv_atomic(results, _rows(levels), EVAL_COLUMNS)
    (tmp_path / "compare.json").write_text(json.dumps({"run": TODAY_RUN}))  # today's defaults
    root = _root(tmp_path / "repo")
    comparison = root / "docs" / "results" / "rl_comparison.csv"
    assert main(["add", str(results), "--comparison", str(comparison)]) == 0
    assert len(read_csv(comparison)) == 36
    assert {(row["variant"], row["algo"]) for row in read_csv(comparison)} == {
        ("oracle", TODAY_UNNOTED),
        ("focus", TODAY),
        ("raw", TODAY_UNNOTED),
        ("random-focus", TODAY),
    }  # raw and the oracle run no model: their rows carry no model note
    assert read_csv(comparison)[0]["obs_scaling"] == "running"
    assert main(["render", "--check", "--root", str(root)]) == 1  # nothing rendered yet
    err = capsys.readouterr().err
    for name in ("rl.md", "perception.md", "checks.md", "performance.md", "README.md"):
        assert f"{name} differs from what the CSVs give" in err
    assert main(["render", "--root", str(root)]) == 0
    page = (root / "docs" / "results" / "rl.md").read_text()
    assert page.startswith(
        "# RL comparison\n\n_This page is generated by `python tools/report.py render` from "
        "`docs/results/rl_comparison.csv`"
    )
    assert f"| focus ({TODAY}) | 3 | 200 |" in page and "share of the raw → oracle gap closed" in page
    assert "target" not in page.split("## Reproduce")[0].replace("the target's true state", "")
    assert (
        page.index(f"| raw ({TODAY_UNNOTED}) |")
        < page.index(f"| focus ({TODAY}) |")
        < page.index(f"| oracle ({TODAY_UNNOTED}) |")
    )  # baseline, attended, bound
    assert "](../figures/rl_learning_curves.png)" in page and (root / "docs/figures/rl_learning_curves.png").is_file()
    profiles = page.split("## Today's defaults at 200 env steps: IQM, improvement and performance profiles")[1]
    assert "| focus | 0.55 [0.50, 0.60] | 0.00 [0.00, 0.00] | 0.94 [0.78, 1.00] |" in profiles  # IQM of 3: the middle
    assert "| focus | no, 0.25 | — |" in profiles  # (0.55 - 0.45) / (0.85 - 0.45); no safe success recorded
    assert "](../figures/rl_profiles.png)" in profiles and (root / "docs/figures/rl_profiles.png").is_file()
    readme = (root / "README.md").read_text()
    assert readme.startswith("# title") and readme.endswith("after\n") and "\nold\n" not in readme
    block = readme.split(headline.START)[1]
    assert [line.split(" | ")[0] for line in block.splitlines() if line.startswith("| ")][1:] == [
        "| raw",
        "| random-focus",
        "| focus",
        "| oracle",
    ]
    assert "| focus | 0.55 [" in block and "200 env steps each" in block
    assert "](docs/results/rl.md)" in block and "](docs/figures/rl_learning_curves.png)" in block
    assert main(["render", "--check", "--root", str(root)]) == 0
    (root / "docs" / "results" / "checks.md").write_text("edited by hand\n")
    assert main(["render", "--check", "--root", str(root)]) == 1
    assert capsys.readouterr().err.count("differs from what the CSVs give") == 1


def test_the_rl_page_sets_todays_rollout_beside_the_earlier_one_where_both_were_run(tmp_path):
    levels = {"raw": [0.4, 0.5], "random-focus": [0.4, 0.4], "focus": [0.7, 0.8], "oracle": [0.9, 0.9]}
    today = _today(_rows(levels))
    earlier = [{"algo": "ppo, lr lin_3e-4", "obs_scaling": "running", **row} for row in _rows(levels)]
    heading = "## Today's PPO rollout against the earlier one"
    assert heading not in render_block(today, [], tmp_path, write_figures=False)
    # the earlier rollout was run on the first task and model version 0 only, without a warm start:
    # today's rollout is set beside it in that setting
    assert heading not in render_block(today + earlier, [], tmp_path, write_figures=False)
    rollout_today = "ppo, lr lin_3e-4, 32 envs × 64 steps, batch 512"
    today_first = [{**row, "algo": rollout_today} for row in today]
    page = render_block(today + earlier + today_first, [], tmp_path, tmp_path)
    assert heading in page and "](rl_rollouts.png)" in page and (tmp_path / "rl_rollouts.png").is_file()


def test_runs_trained_on_count_at_every_budget_cut_to_it():
    rows = _rows({"raw": [0.4, 0.5], "focus": [0.6]}) + _rows({"focus": [0.8]}, steps=(0, 100, 200, 300, 400))[3:]
    (short, short_rows), (long, long_rows) = budgets(rows)
    assert (short, long) == (200, 400)
    assert sorted({(r["variant"], r["env_steps"]) for r in short_rows}) == sorted(
        {(v, s) for v in ("raw", "focus") for s in (0, 100, 200)}
    )
    assert {r["variant"] for r in long_rows} == {"focus"} and max(r["env_steps"] for r in long_rows) == 400
    assert len(long_rows) == 5  # the focus run's whole curve: its first 200 steps and the extension


def test_a_comparison_adds_to_the_clutter_table_as_one_distractor_count(tmp_path, capsys):
    results = tmp_path / "results.csv"
    write_csv_atomic(results, _rows({"raw": [0.4, 0.5], "focus": [0.6, 0.7]}), EVAL_COLUMNS)
    clutter = tmp_path / "clutter.csv"
    paths = ["--comparison", str(tmp_path / "rl.csv"), "--clutter-csv", str(clutter)]
    assert main(["add", str(results), "--num-distractors", "2", *paths]) == 2  # needs --clutter
    assert "needs --clutter" in capsys.readouterr().err and not clutter.exists()
    assert main(["add", str(results), "--clutter", "--num-distractors", "2", *paths]) == 0
    rows = read_csv(clutter)
    assert len(rows) == 12 and {r["num_distractors"] for r in rows} == {2}
    assert main(["add", str(clutter), "--clutter", "--num-distractors", "3", *paths]) == 2  # already has counts
    assert "has one" in capsys.readouterr().err


def test_bad_input_to_the_report_is_one_line(tmp_path, capsys):
    empty = tmp_path / "empty.csv"
    empty.write_text("variant,seed\n")
    assert main(["add", str(empty), "--comparison", str(tmp_path / "rl.csv")]) == 2
    assert "holds no rows" in capsys.readouterr().err
    root = _root(tmp_path / "repo", readme="no block here\n")
    write_csv_atomic(
        root / "docs/results/rl_comparison.csv",
        [{"algo": "ppo", **r} for r in _rows({"raw": [0.4]})],
        ("algo", *EVAL_COLUMNS),
    )
    assert main(["render", "--root", str(root)]) == 2
    assert "no '<!-- results-headline:start -->'" in capsys.readouterr().err


def test_report_refuses_files_that_would_merge_wrongly(tmp_path, capsys):
    comparison = tmp_path / "rl.csv"
    write_csv_atomic(
        comparison,
        [{"algo": "ppo", "obs_scaling": "running", **r} for r in _rows({"raw": [0.4]})],
        ("algo", "obs_scaling", *EVAL_COLUMNS),
    )
    before = comparison.read_bytes()
    sweep = tmp_path / "sweep" / "sweep.csv"
    write_csv_atomic(
        sweep,
        [{"num_distractors": n, **r} for n in (1, 5) for r in _rows({"raw": [0.9]})],
        ("num_distractors", *EVAL_COLUMNS),
    )
    assert main(["add", str(sweep), "--comparison", str(comparison)]) == 2  # forgot --clutter
    assert "it is a sweep's sweep.csv; add it with --clutter" in capsys.readouterr().err
    twice = tmp_path / "twice" / "results.csv"
    write_csv_atomic(twice, _rows({"raw": [0.9]}) * 2, EVAL_COLUMNS)
    assert main(["add", str(twice), "--comparison", str(comparison)]) == 2
    assert "holds the evaluation {'variant': 'raw', 'seed': 0, 'env_steps': 0} twice" in capsys.readouterr().err
    assert comparison.read_bytes() == before
    root = _root(tmp_path / "repo", readme="{end}\n{start}\n")  # markers in the wrong order
    shutil.copy(comparison, root / "docs/results/rl_comparison.csv")
    assert main(["render", "--root", str(root)]) == 2
    assert "the start marker before the end marker" in capsys.readouterr().err
    write_csv_atomic(root / "docs/results/rl_comparison.csv", _rows({"raw": [0.4]}), EVAL_COLUMNS)  # not added
    (root / "README.md").write_text(f"{headline.START}\n{headline.END}\n")
    assert main(["render", "--root", str(root)]) == 2
    assert "lacks the columns ['algo']" in capsys.readouterr().err and not (root / "docs" / "figures").exists()


def test_added_rows_are_tagged_with_the_comparisons_own_algorithm_and_a_wrong_tag_is_refused(tmp_path, capsys):
    results = tmp_path / "cmp" / "results.csv"
    write_csv_atomic(results, _rows({"raw": [0.4]}), EVAL_COLUMNS)
    (tmp_path / "cmp" / "compare.json").write_text(
        json.dumps({"run": {"algo": "recurrent-ppo", "obs_scaling": "none"}})
    )
    target = ["--comparison", str(tmp_path / "rl.csv")]
    for algo, message in (
        ("recurent-ppo", "must start with one of ppo, sac, recurrent-ppo"),
        ("ppo", "--algo 'ppo' contradicts the comparison's settings"),
    ):
        assert main(["add", str(results), "--algo", algo, *target]) == 2
        assert message in capsys.readouterr().err and not (tmp_path / "rl.csv").exists()
    assert main(["add", str(results), *target]) == 0
    assert {(r["algo"], r["obs_scaling"]) for r in read_csv(tmp_path / "rl.csv")} == {("recurrent-ppo", "none")}
    assert main(["add", str(results), "--algo", "recurrent-ppo, lr lin_3e-4", *target]) == 2  # not these runs' rate
    assert "does not name the runs' learning rate" in capsys.readouterr().err


def test_runs_with_a_decayed_learning_rate_are_tagged_with_it(tmp_path, capsys):
    """The default decays the rate (algo_defaults 2): such rows never share the plain 'ppo' tag of constant-rate
    runs."""
    target = ["--comparison", str(tmp_path / "rl.csv")]
    for folder, run in (
        ("old", {"algo": "ppo"}),  # written before algo_defaults: constant 3e-4
        ("new", {"algo": "ppo", "algo_defaults": 2}),
        ("constant", {"algo": "ppo", "algo_defaults": 2, "algo_kwargs": {"learning_rate": 3e-4}}),
        ("given", {"algo": "ppo", "algo_kwargs": {"learning_rate": "lin_1e-3"}}),
    ):
        results = tmp_path / folder / "results.csv"
        write_csv_atomic(results, _rows({"raw": [0.4]}), EVAL_COLUMNS)
        (tmp_path / folder / "compare.json").write_text(json.dumps({"run": run}))
    assert main(["add", str(tmp_path / "new" / "results.csv"), "--algo", "ppo", *target]) == 2
    assert "start the tag with it" in capsys.readouterr().err and not (tmp_path / "rl.csv").exists()
    assert main(["add", str(tmp_path / "new" / "results.csv"), "--algo", "ppo, lr lin_3e-4, 1M", *target]) == 0
    for folder in ("old", "new", "constant", "given"):
        assert main(["add", str(tmp_path / folder / "results.csv"), *target]) == 0
    assert {r["algo"] for r in read_csv(tmp_path / "rl.csv")} == {
        "ppo",
        "ppo, lr lin_3e-4",
        "ppo, lr lin_3e-4, 1M",
        "ppo, lr lin_1e-3",
    }


def test_rows_of_another_rollout_are_tagged_with_it_and_earlier_tags_stand():
    """algo_defaults 3's 32 envs × 64 steps, minibatch 512 (by default or by flags) name their rollout; the
    earlier rollout (4 × 256, minibatch 256, 5 epochs) adds nothing, so the rows already in the CSVs keep
    their tags; SAC's tag names no rollout."""
    from attentive_gym.agents.merged import algo_tag, default_tag

    today = "ppo, lr lin_3e-4, 32 envs × 64 steps, batch 512"
    assert algo_tag({"algo": "ppo", "algo_defaults": 3}) == today
    # the warm start, the task and the model from version 1 are noted, the model
    # on the variants that run it only; each variant of a comparison has its own default start
    assert default_tag("raw") == f"{today}, warm start privileged, task v1"
    assert default_tag() == default_tag("focus") == f"{today}, warm start privileged, task v1, model v2"
    assert algo_tag(TODAY_RUN, "random-focus") == f"{today}, warm start privileged, task v1, model v2"
    assert algo_tag(TODAY_RUN, "oracle") == f"{today}, warm start privileged, task v1"
    assert algo_tag(TODAY_RUN, "raw-stack") == f"{today}, task v1"  # no teacher reads stacked readings
    assert algo_tag(TODAY_RUN, "goal-action") == f"{today}, warm start privileged, task v1, model v2"
    by_flags = {"algo": "ppo", "algo_defaults": 2, "n_envs": 32, "algo_kwargs": {"n_steps": 64, "batch_size": 512}}
    assert algo_tag(by_flags) == today
    assert algo_tag({"algo": "ppo", "algo_defaults": 2, "n_envs": 4}) == "ppo, lr lin_3e-4"
    assert algo_tag({"algo": "ppo"}) == "ppo"
    assert algo_tag({"algo": "recurrent-ppo", "algo_defaults": 3}) == "recurrent-ppo, lr lin_3e-4"
    assert algo_tag({"algo": "sac", "algo_defaults": 3}) == "sac"
    assert algo_tag({**by_flags, "algo_kwargs": {"n_steps": 64, "batch_size": 512, "n_epochs": 10}}) == (
        f"{today}, 10 epochs"
    )


def test_a_tags_rate_is_compared_by_value_and_a_sweep_of_mixed_rates_is_refused(tmp_path, capsys):
    target = ["--comparison", str(tmp_path / "rl.csv")]
    results = tmp_path / "slow" / "results.csv"
    write_csv_atomic(results, _rows({"raw": [0.4]}), EVAL_COLUMNS)
    (tmp_path / "slow" / "compare.json").write_text(
        json.dumps({"run": {"algo": "ppo", "algo_defaults": 2, "algo_kwargs": {"learning_rate": 1e-4}}})
    )
    assert main(["add", str(results), "--algo", "ppo", *target]) == 2  # would merge with the constant-3e-4 rows
    assert "trained with the tag 'ppo, lr 0.0001'" in capsys.readouterr().err
    assert main(["add", str(results), "--algo", "ppo, lr 1e-4, short", *target]) == 0  # the same rate, spelt otherwise
    assert main(["add", str(results), "--algo", "ppo, lr fast", *target]) == 2
    assert "'lr fast' names no learning rate" in capsys.readouterr().err
    assert main(["add", str(results), *target]) == 0
    assert {r["algo"] for r in read_csv(tmp_path / "rl.csv")} == {"ppo, lr 1e-4, short", "ppo, lr 0.0001"}

    sweep = tmp_path / "sweep"
    write_csv_atomic(
        sweep / "sweep.csv",
        [{"num_distractors": n, **r} for n in (1, 5) for r in _rows({"raw": [0.9]})],
        ("num_distractors", *EVAL_COLUMNS),
    )
    for n, run in ((1, {"algo": "ppo"}), (5, {"algo": "ppo", "algo_defaults": 2})):
        (sweep / f"distractors-{n}").mkdir()
        (sweep / f"distractors-{n}" / "compare.json").write_text(json.dumps({"run": run}))
    clutter = ["--clutter-csv", str(tmp_path / "clutter.csv")]
    assert main(["add", str(sweep / "sweep.csv"), "--clutter", *clutter]) == 2
    assert (
        "distractors-1: 'ppo', None, distractors-5: 'ppo, lr lin_3e-4', None); add each point's results.csv "
        "with --clutter --num-distractors N"
    ) in capsys.readouterr().err
    assert not (tmp_path / "clutter.csv").exists()

    loose = tmp_path / "loose" / "results.csv"  # no compare.json beside it
    write_csv_atomic(loose, _rows({"raw": [0.4]}), EVAL_COLUMNS)
    assert main(["add", str(loose), "--comparison", str(tmp_path / "loose.csv")]) == 0
    assert "no compare.json beside" in capsys.readouterr().out


def test_render_writes_no_figure_when_the_readme_is_missing(tmp_path, capsys):
    root = _root(tmp_path, readme=None)
    write_csv_atomic(
        root / "docs/results/rl_comparison.csv",
        [{"algo": "ppo", **r} for r in _rows({"raw": [0.4]})],
        ("algo", *EVAL_COLUMNS),
    )
    assert main(["render", "--root", str(root)]) == 2
    assert "README.md" in capsys.readouterr().err and not (root / "docs" / "figures").exists()


def test_the_headline_needs_every_headline_variant_trained_with_todays_defaults():
    rows = [
        {"algo": "ppo", "obs_scaling": "running", **r}  # the constant rate: not today's default
        for r in _rows({"raw": [0.4], "random-focus": [0.5], "focus": [0.7], "oracle": [0.9]})
    ]
    with pytest.raises(ValueError, match="no budget with all of raw, random-focus, focus, oracle"):
        headline.rl_headline(rows)
    earlier = [{**row, "algo": "ppo, lr lin_3e-4"} for row in rows]  # the rollout before algo_defaults 3
    with pytest.raises(ValueError, match="no budget with all of raw, random-focus, focus, oracle"):
        headline.rl_headline(rows + earlier)
    with pytest.raises(ValueError, match="no budget with all of raw, random-focus, focus, oracle"):
        headline.rl_headline([{**row, "algo": TODAY_UNNOTED} for row in rows])  # attention on model version 0
    default = _today(rows)
    longer = _today(_rows({"focus": [0.8]}, (0, 100, 200, 300)), seed=1)
    budget, summary = headline.rl_headline(rows + default + longer)
    assert budget == 200  # the largest budget that every headline variant reached
    assert [row["variant"] for row in summary] == ["raw", "random-focus", "focus", "oracle"]
    # focus: seed 0 at its final 0.7, seed 1 cut at 200 steps, two thirds of its way from 0.1 to 0.8
    assert summary[2]["n_seeds"] == 2
    assert summary[2]["final_success_mean"] == pytest.approx((0.7 + 0.1 + 0.7 * 2 / 3) / 2)


def test_the_deprecated_module_warns_names_the_replacement_and_still_works(tmp_path):
    import importlib
    import sys

    sys.modules.pop("attentive_gym.agents.report", None)
    with pytest.warns(DeprecationWarning, match="attentive_gym.agents.merged .* tools/report.py"):
        old = importlib.import_module("attentive_gym.agents.report")
    assert old.merge_rows is merge_rows and old.labelled is labelled  # the public names are still there
    results = tmp_path / "results.csv"
    write_csv_atomic(results, _rows({"raw": [0.4]}), EVAL_COLUMNS)
    with pytest.warns(DeprecationWarning, match="python -m attentive_gym.agents.report is deprecated"):
        assert old.main(["add", str(results), "--comparison", str(tmp_path / "rl.csv")]) == 0
    assert len(read_csv(tmp_path / "rl.csv")) == 3
    rows = [{"algo": "ppo", "obs_scaling": "running", **r} for r in _rows({"raw": [0.4], "focus": [0.6]})]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(DeprecationWarning, match="render_block is deprecated"):
            old.render_block(rows, [], tmp_path, [], tmp_path, write_figures=False)
    with pytest.warns(DeprecationWarning):
        assert "| focus | 1 | 200 |" in old.render_block(rows, [], tmp_path, [], tmp_path, write_figures=False)


def test_clutter_targets_give_the_margin_and_gap_per_count_within_one_setting():
    rows = []
    for n, levels in (
        (1, {"raw": [0.4, 0.4], "oracle": [0.9, 0.9], "focus": [0.8, 0.8]}),
        (3, {"raw": [0.5, 0.5], "focus": [0.6, 0.6]}),  # no oracle at 3
        (5, {"raw": [0.5, 0.5], "oracle": [0.5, 0.5], "focus": [0.4, 0.4]}),
    ):  # oracle not above raw
        rows += [{"algo": "ppo", "obs_scaling": "running", "num_distractors": n, **r} for r in _rows(levels)]
    rows += [
        {"algo": "ppo", "obs_scaling": "none", "num_distractors": 1, **r}
        for r in _rows({"raw": [0.2, 0.2], "oracle": [0.6, 0.6], "focus": [0.3, 0.3]})
    ]
    found = {(r["variant"], r["num_distractors"]): r for r in clutter_targets(sweep_tables(labelled(rows)))}
    assert found.keys() == {("focus", 1), ("focus", 3), ("focus", 5), ("focus (unscaled)", 1)}
    assert found["focus", 1]["margin"] == pytest.approx(0.4)
    assert found["focus", 1]["gap_closed"] == pytest.approx(0.4 / 0.5)
    assert found["focus", 3]["margin"] == pytest.approx(0.1) and math.isnan(found["focus", 3]["gap_closed"])
    assert found["focus", 5]["margin"] == pytest.approx(-0.1) and math.isnan(found["focus", 5]["gap_closed"])
    assert found["focus (unscaled)", 1]["gap_closed"] == pytest.approx(0.1 / 0.4)  # against the unscaled raw and oracle


def test_a_clutter_point_trained_on_gets_a_table_of_its_own_budget(tmp_path):
    def sweep(levels, n, steps):
        return [{"algo": "ppo", "obs_scaling": "running", "num_distractors": n, **r} for r in _rows(levels, steps)]

    clutter = sweep({"raw": [0.5, 0.5], "focus": [0.7, 0.7]}, 1, (0, 100, 200)) + sweep(
        {"raw": [0.4, 0.4], "focus": [0.5, 0.5]}, 5, (0, 100, 200, 300, 400)
    )  # trained on at 5
    comparison = [{"algo": "ppo", "obs_scaling": "running", **r} for r in _rows({"raw": [0.5], "focus": [0.7]})]
    block = render_block(comparison, clutter, tmp_path, tmp_path, write_figures=False)
    first, second = block.split("## Against clutter")[1:3]
    assert first.startswith(" after 200 env steps") and second.startswith(" after 400 env steps")
    assert "| 1 distractor | 5 distractors |" in first
    assert "| 5 distractors |" in second and "1 distractor" not in second
    assert "| focus | 0.50 [0.50, 0.50] (n=2) |" in second  # its final, not its value at 200 steps (0.30)
    assert "| focus | 0.70 [0.70, 0.70] (n=2) | 0.30 [0.30, 0.30] (n=2) |" in first  # cut at 200 steps
    assert block.count("rl_clutter.png") == 1


def test_the_clutter_figure_draws_the_normalised_runs_when_there_are_some(tmp_path, monkeypatch):
    drawn = []
    monkeypatch.setattr(rl_page, "plot_success_vs_distractors", lambda summary, path, budget: drawn.append(summary))
    monkeypatch.setattr(rl_page, "plot_learning_curves", lambda rows, path, title=None: None)
    rows = _rows({"raw": [0.5, 0.5], "focus": [0.7, 0.7]})
    clutter = [{"algo": "ppo", "obs_scaling": "running", "num_distractors": 1, **r} for r in rows] + [
        {"algo": "ppo", "obs_scaling": "none", "num_distractors": 1, **r} for r in rows
    ]
    comparison = [{"algo": "ppo", "obs_scaling": "running", **r} for r in rows]
    block = render_block(comparison, clutter, tmp_path, tmp_path)
    assert {row["variant"] for row in drawn[0]} == {"raw", "focus"}
    assert "| focus (unscaled) |" in block  # the tables keep every run
    unscaled_only = [row for row in clutter if row["obs_scaling"] == "none"]
    render_block(comparison, unscaled_only, tmp_path, tmp_path)
    assert {row["variant"] for row in drawn[1]} == {"raw (unscaled)", "focus (unscaled)"}


def test_the_clutter_figure_names_its_budget_when_runs_were_trained_further(tmp_path, monkeypatch):
    budgets_drawn = []
    monkeypatch.setattr(
        rl_page, "plot_success_vs_distractors", lambda summary, path, budget: budgets_drawn.append(budget)
    )
    monkeypatch.setattr(rl_page, "plot_learning_curves", lambda rows, path, title=None: None)
    short, long = _rows({"raw": [0.5, 0.5]}), _rows({"focus": [0.7, 0.7]}, steps=(0, 100, 200, 300))
    clutter = [{"algo": "ppo", "obs_scaling": "running", "num_distractors": 1, **r} for r in short + long]
    comparison = [{"algo": "ppo", "obs_scaling": "running", **r} for r in short]
    render_block(comparison, clutter, tmp_path, tmp_path)
    assert budgets_drawn == [200]  # the figure shows the first budget, and says so
    render_block(comparison, clutter[:6], tmp_path, tmp_path)
    assert budgets_drawn[1] is None  # one budget: the title needs none


def test_each_training_setting_gets_a_learning_curve_figure_of_its_own_defaults_first(tmp_path, monkeypatch):
    drawn = {}
    monkeypatch.setattr(
        rl_page,
        "plot_learning_curves",
        lambda rows, path, title=None: drawn.setdefault(path.name, ({r["variant"] for r in rows}, title)),
    )
    rows = _rows({"raw": [0.5, 0.5], "focus": [0.7, 0.7]})
    comparison = (
        [{"algo": "recurrent-ppo", "obs_scaling": "running", **r} for r in rows]
        + _today(rows)
        + [{"algo": "ppo", "obs_scaling": "none", **r} for r in rows]
    )  # unscaled: in the tables only
    block = render_block(comparison, [], tmp_path, tmp_path)
    assert set(drawn) == {"rl_learning_curves.png", "rl_learning_curves_recurrent-ppo.png"}
    variants, title = drawn["rl_learning_curves.png"]  # RunSpec's default setting takes the plain name
    assert variants == {"raw", "focus"}  # one setting, named by the page: one line style
    assert title.startswith("today's defaults")
    assert drawn["rl_learning_curves_recurrent-ppo.png"][0] == {"raw (recurrent-ppo)", "focus (recurrent-ppo)"}
    assert block.index("rl_learning_curves.png") < block.index("rl_learning_curves_recurrent-ppo.png")
    assert "| focus (unscaled) |" in block
    drawn.clear()
    render_block(comparison[-len(rows) :], [], tmp_path, tmp_path)
    assert set(drawn) == {"rl_learning_curves.png"}  # no normalised runs: the unscaled ones, under the plain name
    drawn.clear()
    on_v0 = [{**row, "algo": TODAY_UNNOTED} for row in _today(rows) if row["variant"] == "focus"]
    render_block(_today(rows) + on_v0, [], tmp_path, tmp_path)
    assert set(drawn) == {
        "rl_learning_curves.png",
        f"rl_learning_curves_{re.sub('[^0-9A-Za-z]+', '-', TODAY_UNNOTED)}.png",
    }
    assert drawn[next(name for name in drawn if name != "rl_learning_curves.png")][0] == {
        f"raw ({TODAY_UNNOTED})",
        f"focus ({TODAY_UNNOTED})",
    }  # today's rollout with attention on model version 0: raw with the focus of that version


def test_a_variant_has_the_same_colour_in_every_figure():
    from attentive_gym.agents.plots import _line_styles

    alone = _line_styles(["focus (recurrent-ppo)", "oracle (recurrent-ppo)", "my-variant"])
    together = _line_styles(["raw", "raw-stack", "focus", "oracle", "my-variant (unscaled)"])
    assert alone["focus (recurrent-ppo)"]["color"] == together["focus"]["color"]
    assert alone["oracle (recurrent-ppo)"]["color"] == together["oracle"]["color"] != together["focus"]["color"]
    assert alone["my-variant"]["color"] == together["my-variant (unscaled)"]["color"]  # after the project's variants


def _v0(rows):
    """``rows`` as written before the safe-success measure: without ``SAFE_COLUMNS``."""
    return [{k: v for k, v in row.items() if k not in SAFE_COLUMNS} for row in rows]


def _safe(rows, contact_s=1.5):
    """``rows`` with half their success safe and ``contact_s`` s of contact per episode."""
    return [{**row, "safe_success_rate": row["success_rate"] / 2, "mean_contact_s": contact_s} for row in rows]


def test_runs_from_before_the_safe_success_measure_add_and_render_and_the_pages_say_so(tmp_path, capsys):
    levels = {"raw": [0.4, 0.5], "random-focus": [0.45, 0.5], "focus": [0.6, 0.8], "oracle": [0.9, 0.8]}
    (tmp_path / "compare.json").write_text(json.dumps({"run": TODAY_RUN}))
    results = tmp_path / "results.csv"
    write_csv_atomic(results, _v0(_rows(levels)), [c for c in EVAL_COLUMNS if c not in SAFE_COLUMNS])
    root = _root(tmp_path / "repo")
    comparison = root / "docs" / "results" / "rl_comparison.csv"
    assert main(["add", str(results), "--comparison", str(comparison)]) == 0
    assert all(math.isnan(row["safe_success_rate"]) for row in read_csv(comparison))  # empty cells, not 0
    assert main(["render", "--root", str(root)]) == 0
    page = (root / "docs" / "results" / "rl.md").read_text()
    block = (root / "README.md").read_text().split(headline.START)[1]
    assert rl_page.PREDATE_SAFE_SUCCESS in page and rl_page.PREDATE_SAFE_SUCCESS in block
    assert f"| focus ({TODAY}) | 2 | 200 | 0.70 [0.60, 0.80] | — |" in page
    assert "safe success rate" not in block.split(rl_page.PREDATE_SAFE_SUCCESS)[0]  # no column of dashes

    write_csv_atomic(results, _safe(_rows(levels)), EVAL_COLUMNS)  # the same runs, evaluated with the measure
    assert main(["add", str(results), "--comparison", str(comparison)]) == 0
    assert main(["render", "--root", str(root)]) == 0
    page = (root / "docs" / "results" / "rl.md").read_text()
    block = (root / "README.md").read_text().split(headline.START)[1]
    assert "predate" not in page and "predate" not in block
    assert f"| focus ({TODAY}) | 2 | 200 | 0.70 [0.60, 0.80] | 0.35 [0.30, 0.40] |" in page
    assert (
        "| variant | final success rate, mean [95 % CI] | final safe success rate (≤ 1 s in contact), mean [95 % CI] "
        "| final contact time (s / episode), mean [95 % CI] |"
    ) in block
    assert "| focus | 0.70 [0.60, 0.80] | 0.35 [0.30, 0.40] | 1.50 [1.50, 1.50] |" in block
    assert main(["render", "--check", "--root", str(root)]) == 0

    write_csv_atomic(results, _v0(_rows({"saliency": [0.5]})), [c for c in EVAL_COLUMNS if c not in SAFE_COLUMNS])
    assert main(["add", str(results), "--comparison", str(comparison)]) == 0
    assert main(["render", "--root", str(root)]) == 0
    page = (root / "docs" / "results" / "rl.md").read_text()
    assert "Runs whose safe success and contact time read — predate that measure (the v0 task)." in page
    assert rl_page.PREDATE_SAFE_SUCCESS not in page


def test_the_clutter_tables_show_safe_success_and_contact_time_where_the_rows_record_them(tmp_path):
    def sweep(rows):
        return [{"algo": "ppo", "obs_scaling": "running", "num_distractors": 1, **r} for r in rows]

    comparison = [{"algo": "ppo", "obs_scaling": "running", **r} for r in _rows({"raw": [0.5]})]
    rows = _rows({"raw": [0.5, 0.5], "focus": [0.7, 0.7]})
    block = render_block(comparison, sweep(_safe(rows, 2.5)), tmp_path, tmp_path, write_figures=False)
    safe = block.split("Final safe success (at most 1 s in contact; mean [95 % bootstrap CI])")[1]
    assert "| focus | 0.35 [0.35, 0.35] (n=2) |" in safe.split("Final contact time")[0]
    assert "| focus | 2.50 [2.50, 2.50] (n=2) |" in safe.split("Final contact time (s in contact per episode")[1]
    v0 = render_block(comparison, sweep(_v0(rows)), tmp_path, tmp_path, write_figures=False)
    assert "Final safe success" not in v0 and "Final contact time" not in v0
    assert "| focus | 0.70 [0.70, 0.70] (n=2) |" in v0
