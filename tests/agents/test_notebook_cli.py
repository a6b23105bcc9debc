"""The notebook runs end to end; the train/evaluate command lines and their input errors."""

import json
import re
from pathlib import Path

import pytest

from attentive_gym.cli import main

NOTEBOOK = Path(__file__).resolve().parents[2] / "notebooks" / "train_and_compare.ipynb"


@pytest.mark.slow
def test_notebook_executes():
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    notebook = nbformat.read(NOTEBOOK, as_version=4)
    nbclient.NotebookClient(
        notebook, timeout=60, kernel_name="python3", resources={"metadata": {"path": str(NOTEBOOK.parent)}}
    ).execute()
    outputs = [o for cell in notebook.cells if cell.cell_type == "code" for o in cell.get("outputs", [])]
    assert not [o for o in outputs if o.get("output_type") == "error"]
    assert any("image/png" in o.get("data", {}) for o in outputs)


@pytest.fixture(scope="module")
def trained(tmp_path_factory, tiny):
    out = tmp_path_factory.mktemp("train") / "run"
    argv = [
        "train",
        "--variant",
        "focus",
        "--steps",
        "256",
        "--n-envs",
        "2",
        "--eval-episodes",
        "2",
        "--env-kwargs",
        json.dumps(tiny.env_kwargs),
        "--algo-kwargs",
        json.dumps(tiny.ppo_kwargs),
        "--no-progress",
        "--out",
        str(out),
    ]
    assert main(argv) == 0
    return out


def test_train_and_evaluate_commands(trained, capsys):
    assert (trained / "done").is_file() and (trained / "final_model.zip").is_file()
    capsys.readouterr()
    assert main(["evaluate", str(trained), "--episodes", "3", "--json"]) == 0
    row = json.loads(capsys.readouterr().out)
    assert row["variant"] == "focus" and row["n_episodes"] == 3 and 0 <= row["success_rate"] <= 1
    assert 0 <= row["safe_success_rate"] <= row["success_rate"] and row["mean_contact_s"] >= 0
    assert main(["evaluate", str(trained / "checkpoint" / "model.zip"), "--episodes", "1"]) == 0
    out = capsys.readouterr().out
    assert "success rate" in out and "safe success rate" in out and "(≤ 1 s in contact)" in out
    assert re.search(r"contact \d+\.\d s / episode", out)


def test_evaluate_records_a_video(trained, tmp_path):
    pytest.importorskip("moviepy", reason="--video needs moviepy (the 'video' extra)")
    assert main(["evaluate", str(trained), "--episodes", "1", "--video", str(tmp_path / "v")]) == 0
    videos = list((tmp_path / "v").glob("*.mp4"))
    assert videos and videos[0].stat().st_size > 0
    before = {path: path.stat().st_mtime_ns for path in videos}
    assert main(["evaluate", str(trained), "--episodes", "1", "--video", str(tmp_path / "v")]) == 2  # would overwrite
    assert {path: path.stat().st_mtime_ns for path in (tmp_path / "v").glob("*.mp4")} == before


@pytest.mark.parametrize(
    "argv, message",
    [
        (["train", "--variant", "nope"], "unknown variant 'nope'; allowed: ['raw'"),
        (["train", "--env-kwargs", "[1]"], "must be a JSON object"),
        (["train", "--env-kwargs", '{"bogus": 1}', "--steps", "64"], "unknown keyword argument"),
        (["evaluate", "no/such/run"], "no model at no/such/run"),
        (["compare", "--variants", "raw,nope"], "allowed"),
        (["compare", "--seeds", "0"], "seeds must be"),
        (["compare", "--threshold", "2"], "--threshold"),
    ],
)
def test_input_errors_exit_2_with_one_line(argv, message, capsys, tmp_path):
    assert main(argv + ["--out", str(tmp_path / "o")] if argv[0] != "evaluate" else argv) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1


def test_usage_errors_exit_2():
    for argv in (["train", "--steps", "0"], ["train", "--seed", "-1"], ["train", "--algo", "dqn"]):
        with pytest.raises(SystemExit) as exc:
            main(argv)
        assert exc.value.code == 2


def _captured_compare(monkeypatch, argv):
    import attentive_gym.agents.compare as compare_module

    calls = []
    monkeypatch.setattr(
        compare_module,
        "compare",
        lambda *args, **kwargs: (
            calls.append((args, kwargs)) or compare_module.CompareResult(Path("."), None, None, None, None)
        ),
    )
    assert main(argv) == 0
    (variants, seeds, base, out), kwargs = calls[0]
    return variants, seeds, base, out


def test_compare_quick_uses_the_quick_budget_and_explicit_options_win(monkeypatch, tmp_path):
    from attentive_gym.agents.compare import QUICK

    variants, seeds, base, out = _captured_compare(monkeypatch, ["compare", "--quick", "--out", str(tmp_path)])
    assert tuple(variants) == QUICK["variants"] and tuple(seeds) == QUICK["seeds"]
    assert (base.total_steps, base.eval_every, base.eval_episodes, base.checkpoint_every) == (
        QUICK["total_steps"],
        QUICK["eval_every"],
        QUICK["eval_episodes"],
        QUICK["checkpoint_every"],
    )
    assert base.env_kwargs == QUICK["env_kwargs"]
    variants, seeds, base, out = _captured_compare(
        monkeypatch,
        [
            "compare",
            "--quick",
            "--seeds",
            "1",
            "--steps",
            "1000",
            "--env-kwargs",
            '{"num_distractors": 1}',
            "--out",
            str(tmp_path),
        ],
    )
    assert tuple(seeds) == (0,) and base.total_steps == 1000 and base.env_kwargs == {"num_distractors": 1}
