"""The command line under stress: Ctrl-C and SIGTERM, specs checked before anything is written,
help texts with the real defaults, integer options, and progress lines with an ETA."""

import json
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path
from types import SimpleNamespace

import pytest

from attentive_gym.agents.backends import JobOutcome
from attentive_gym.agents.cli import _spec_from_args
from attentive_gym.agents.config import QUICK, STEPS_PER_EVAL_EPISODE, RunSpec
from attentive_gym.agents.results import read_csv
from attentive_gym.cli import _SUBCOMMANDS, build_parser, main
from attentive_gym.progress import Progress, format_duration

#: Seconds a stopped command may take to exit (the runs' processes must be gone by then).
STOP_WITHIN_S = 10.0


def _tiny_options(tiny, steps=2048):
    """Options of a run of ``steps`` env steps in 40-step episodes, one env, a checkpoint every 256 steps."""
    return [
        "--steps",
        str(steps),
        "--n-envs",
        "1",
        "--eval-every",
        "512",
        "--eval-episodes",
        "1",
        "--checkpoint-every",
        "256",
        "--env-kwargs",
        json.dumps(tiny.env_kwargs),
        "--algo-kwargs",
        json.dumps(tiny.ppo_kwargs),
    ]


def _command(*args):
    return [sys.executable, "-m", "attentive_gym.cli", *args]


def _start(argv):
    """The command in a new process group (as a shell runs a foreground job)."""
    env = {**os.environ, "SDL_VIDEODRIVER": "dummy"}
    return subprocess.Popen(
        argv, start_new_session=True, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env
    )


def _wait_for(path: Path, proc, timeout_s=120.0):
    deadline = time.monotonic() + timeout_s
    while not path.is_file():
        assert proc.poll() is None, proc.communicate()
        assert time.monotonic() < deadline, f"{path} never appeared"
        time.sleep(0.05)


def _stop(proc, signum, whole_group):
    """Send ``signum`` (to the process group, as Ctrl-C does, or to the process alone); (stdout, stderr, seconds)."""
    start = time.monotonic()
    if whole_group:
        os.killpg(proc.pid, signum)
    else:
        proc.send_signal(signum)
    out, err = proc.communicate(timeout=60)
    return out, err, time.monotonic() - start


def _live_processes_in_group(pgid):
    """Pids of the processes (zombies aside) in process group ``pgid``, from /proc."""
    pids = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            state, _ppid, group = stat.read_text().rsplit(")", 1)[1].split()[:3]
        except (OSError, IndexError):
            continue
        if int(group) == pgid and state != "Z":
            pids.append(int(stat.parent.name))
    return pids


def _assert_group_ends(pgid, timeout_s=STOP_WITHIN_S):
    deadline = time.monotonic() + timeout_s
    while _live_processes_in_group(pgid):
        assert time.monotonic() < deadline, f"processes left running: {_live_processes_in_group(pgid)}"
        time.sleep(0.1)


# --- Ctrl-C and SIGTERM ------------------------------------------------------------------
@pytest.mark.slow
def test_ctrl_c_stops_compare_at_once_and_the_same_command_resumes(tmp_path, tiny):
    out = tmp_path / "cmp"
    argv = _command(
        "compare",
        "--variants",
        "raw",
        "--seeds",
        "2",
        "--workers",
        "1",
        "--out",
        str(out),
        *_tiny_options(tiny, steps=1024),
    )
    proc = _start(argv)
    checkpoint = out / "runs" / "raw-seed0" / "checkpoint" / "meta.json"
    _wait_for(checkpoint, proc)
    stdout, stderr, took_s = _stop(proc, signal.SIGINT, whole_group=True)

    assert proc.returncode == 130, stderr
    assert took_s < STOP_WITHIN_S
    assert "Traceback" not in stdout + stderr
    assert re.search(
        r"^attentive-gym compare: interrupted by SIGINT; 0/2 runs done in .*; rerun the same command "
        r"to train only the 2 missing one\(s\)",
        stderr,
        re.MULTILINE,
    ), stderr
    assert sorted(p.name for p in (out / "runs").iterdir()) == ["raw-seed0"]  # the queued run never started
    assert not (out / "runs" / "raw-seed0" / "done").exists()
    _assert_group_ends(proc.pid)

    kept_steps = json.loads(checkpoint.read_text())["env_steps"]
    rerun = subprocess.run(argv, capture_output=True, text=True, timeout=300)
    assert rerun.returncode == 0, rerun.stderr
    resumed = json.loads((out / "runs" / "raw-seed0" / "metrics.json").read_text())
    fresh = json.loads((out / "runs" / "raw-seed1" / "metrics.json").read_text())
    assert resumed["resumed_from"] == kept_steps > 0 and resumed["env_steps"] == fresh["env_steps"] == 1024
    assert fresh["resumed_from"] == 0


@pytest.mark.slow
def test_sigterm_to_compare_alone_stops_its_run_processes(tmp_path, tiny):
    out = tmp_path / "cmp"
    proc = _start(
        _command(
            "compare",
            "--variants",
            "raw,focus",
            "--seeds",
            "1",
            "--workers",
            "1",
            "--out",
            str(out),
            *_tiny_options(tiny),
        )
    )
    _wait_for(out / "runs" / "raw-seed0" / "spec.json", proc)
    stdout, stderr, took_s = _stop(proc, signal.SIGTERM, whole_group=False)
    assert proc.returncode == 143 and took_s < STOP_WITHIN_S, stderr
    assert "Traceback" not in stdout + stderr
    assert "attentive-gym compare: interrupted by SIGTERM; 0/2 runs done" in stderr
    assert sorted(p.name for p in (out / "runs").iterdir()) == ["raw-seed0"]
    _assert_group_ends(proc.pid)  # no run process trains on, orphaned


@pytest.mark.slow
def test_ctrl_c_stops_train_keeping_its_checkpoint(tmp_path, tiny):
    out = tmp_path / "run"
    argv = ["train", "--variant", "raw", "--no-progress", "--out", str(out), *_tiny_options(tiny)]
    proc = _start(_command(*argv))
    checkpoint = out / "checkpoint" / "meta.json"
    _wait_for(checkpoint, proc)
    stdout, stderr, took_s = _stop(proc, signal.SIGINT, whole_group=True)
    assert proc.returncode == 130 and took_s < STOP_WITHIN_S, stderr
    assert "Traceback" not in stdout + stderr
    kept_steps = json.loads(checkpoint.read_text())["env_steps"]
    assert (
        f"attentive-gym train: interrupted by SIGINT; the checkpoint at {kept_steps} env steps is kept in {out}; "
        "rerun the same command to resume from it"
    ) in stderr
    assert main(argv) == 0
    assert json.loads((out / "metrics.json").read_text())["resumed_from"] == kept_steps


def test_a_stop_signal_dropped_by_a_finalizer_is_raised_at_the_next_check(monkeypatch):
    """pymunk frees its spaces in a cffi callback: a handler's exception raised there is dropped."""
    from attentive_gym.agents.stopping import Interrupted, raise_if_stopped, raise_on_stop_signals

    reported = []
    monkeypatch.setattr(sys, "unraisablehook", reported.append)  # what would print "Exception ignored ..."

    class SignalledWhileFreed:
        def __del__(self):
            os.kill(os.getpid(), signal.SIGINT)  # the handler runs here, inside the finalizer
            time.sleep(0.01)

    with pytest.raises(Interrupted) as stopped, raise_on_stop_signals():
        SignalledWhileFreed()  # freed at once: its finalizer drops the Interrupted
        raise_if_stopped()
    assert stopped.value.signum == signal.SIGINT
    assert reported == []
    raise_if_stopped()  # the record ends with the block


def test_after_a_stop_a_finalizers_error_is_not_reported_and_before_it_it_is(monkeypatch):
    """A stop can cut a compilation short; the finalizers of what it left (llvmlite's objects)
    may then fail during the teardown: no "Exception ignored ... Traceback" after a stop, but
    the same error without one is reported as ever."""
    from attentive_gym.agents import stopping

    reported = []
    monkeypatch.setattr(sys, "unraisablehook", reported.append)

    class FailsWhenFreed:
        def __del__(self):
            raise RuntimeError("a finalizer's own failure")

    with stopping.raise_on_stop_signals():
        FailsWhenFreed()
        assert [type(u.exc_value) for u in reported] == [RuntimeError]  # no stop: reported
        reported.clear()
        with pytest.raises(stopping.Interrupted):
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(1.0)
        FailsWhenFreed()
        assert reported == []  # after the stop: a consequence of it, not reported
    monkeypatch.setattr(sys, "unraisablehook", reported.append)
    stopping.quiet_teardown()  # what the command line does once a stop ended its work
    FailsWhenFreed()
    assert reported == []


def test_a_stop_signal_wrapped_by_a_compiled_callee_leaves_as_interrupted():
    """numba turns a handler's exception raised inside a compiled call into a SystemError."""
    from attentive_gym.agents.stopping import Interrupted, raise_on_stop_signals

    def compiled_call():
        try:
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(1.0)
        except Interrupted as err:
            raise SystemError("CPUDispatcher(...) returned a result with an exception set") from err

    with pytest.raises(Interrupted) as stopped, raise_on_stop_signals():
        compiled_call()
    assert stopped.value.signum == signal.SIGTERM
    with pytest.raises(SystemError), raise_on_stop_signals():  # without a stop signal an error stays itself
        raise SystemError("a real failure")


# --- validation before anything is written ---------------------------------------------
@pytest.mark.parametrize(
    "options, message",
    [
        (["--env-kwargs", '{"time_limit_s": 2, "bogus": 1}'], "env_kwargs: unknown keyword argument(s) ['bogus']"),
        (["--env-kwargs", '{"scenario": "no/such.yaml"}'], "scenario file no/such.yaml does not exist"),
        (["--algo-kwargs", '{"n_step": 64}'], "algo_kwargs: PPO takes no 'n_step'; allowed: batch_size, "),
        (["--algo-kwargs", '{"seed": 3}'], "algo_kwargs: 'seed' cannot be given"),
        (["--algo", "sac", "--algo-kwargs", '{"n_epochs": 3}'], "algo_kwargs: SAC takes no 'n_epochs'"),
        (["--algo-kwargs", '{"n_steps": "abc"}'], 'algo_kwargs {"n_steps": "abc"} are refused by ppo: '),
        (["--algo-kwargs", '{"ent_coef": NaN}'], "--algo-kwargs holds NaN, which is not a finite number"),
        (["--algo-kwargs", '{"policy_kwargs": {"net_arch": [Infinity]}}'], "--algo-kwargs holds Infinity"),
        (["--algo-kwargs", "{bad"], "--algo-kwargs is not valid JSON"),
        (["--algo-kwargs", "[1]"], "--algo-kwargs must be a JSON object or a .json file"),
        (["--env-kwargs", ""], "--env-kwargs is empty"),
    ],
)
def test_train_refuses_a_bad_spec_before_writing_anything(options, message, tmp_path, capsys):
    out = tmp_path / "run"
    assert main(["train", "--variant", "raw", "--steps", "64", "--out", str(out), *options]) == 2
    err = capsys.readouterr().err
    assert err.startswith("attentive-gym train: error: ") and message in err and err.count("\n") == 1
    assert not out.exists()


def test_the_misspelt_keyword_message_lists_the_allowed_ones(tmp_path, capsys):
    assert main(["train", "--steps", "64", "--algo-kwargs", '{"n_step": 64}', "--out", str(tmp_path / "r")]) == 2
    allowed = capsys.readouterr().err.split("allowed: ")[1].strip().split(", ")
    assert "n_steps" in allowed and "ent_coef" in allowed and "seed" not in allowed and "env" not in allowed


def test_the_same_folder_works_once_the_typo_is_fixed(tmp_path, tiny):
    out = tmp_path / "run"
    fixed = ["train", "--variant", "raw", "--no-progress", "--out", str(out), *_tiny_options(tiny, steps=128)]
    typo = [*fixed, "--algo-kwargs", '{"n_step": 64}']  # the last --algo-kwargs wins
    assert main(typo) == 2
    assert main(fixed) == 0 and (out / "done").is_file()


def test_a_folder_without_progress_is_taken_over_but_one_with_a_checkpoint_is_not(tmp_path, tiny):
    spec = tiny(total_steps=128)
    failed_start = tmp_path / "failed"
    failed_start.mkdir()
    (failed_start / "spec.json").write_text(spec.replace(seed=5).to_json())  # what an old failed start left
    from attentive_gym.agents.training import train

    assert train(spec, failed_start)["env_steps"] == 128
    assert RunSpec.from_dict(json.loads((failed_start / "spec.json").read_text())) == spec
    with pytest.raises(ValueError, match="holds a run with a different spec"):
        train(spec.replace(seed=5), failed_start)


def test_compare_checks_every_variant_before_training_any(tmp_path, capsys):
    out = tmp_path / "cmp"
    # the weights suit the attended variant 'focus' but not 'raw', which comes second
    argv = [
        "compare",
        "--variants",
        "focus,raw",
        "--seeds",
        "2",
        "--steps",
        "128",
        "--n-envs",
        "1",
        "--env-kwargs",
        '{"weights": {"F1": 1.0}}',
        "--out",
        str(out),
    ]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "attentive-gym compare: error: variant 'raw' has no attention" in err and err.count("\n") == 1
    assert not out.exists()
    assert main(["compare", "--steps", "128", "--algo-kwargs", '{"n_step": 64}', "--out", str(out)]) == 2
    assert "PPO takes no 'n_step'" in capsys.readouterr().err and not out.exists()


@pytest.mark.parametrize(
    "flag, message",
    [("--variants", "no variant given"), ("--seeds", "seeds must be"), ("--distractors", "distractor counts must be")],
)
def test_compare_refuses_an_empty_list_instead_of_taking_the_default(flag, message, tmp_path, capsys):
    out = tmp_path / "cmp"
    assert main(["compare", flag, "", "--steps", "64", "--out", str(out)]) == 2
    assert message in capsys.readouterr().err and not out.exists()


def test_non_finite_algo_kwargs_are_refused_in_python_too(tiny):
    with pytest.raises(ValueError, match=r"algo_kwargs\['ent_coef'\] must hold finite numbers, got nan"):
        tiny(algo_kwargs={"ent_coef": float("nan")})


def test_extending_needs_only_the_new_budget_and_a_mismatch_names_the_field(tmp_path, tiny, capsys):
    out = tmp_path / "run"
    options = [
        "train",
        "--variant",
        "raw",
        "--no-progress",
        "--out",
        str(out),
        "--n-envs",
        "2",
        "--eval-episodes",
        "1",
        "--env-kwargs",
        json.dumps(tiny.env_kwargs),
        "--algo-kwargs",
        json.dumps(tiny.ppo_kwargs),
    ]
    assert main([*options, "--steps", "128"]) == 0  # eval every 12, checkpoint every 25 (steps/10, steps/5)
    assert main([*options, "--steps", "256"]) == 2
    assert (
        "holds a run of 128 env steps with otherwise the same spec; extend it to 256 (--extend)"
        in capsys.readouterr().err
    )
    assert main([*options, "--steps", "256", "--extend"]) == 0
    spec = RunSpec.from_dict(json.loads((out / "spec.json").read_text()))
    assert (spec.total_steps, spec.eval_every, spec.checkpoint_every) == (256, 12, 25)
    assert main([*options, "--steps", "256", "--eval-episodes", "2"]) == 2
    assert "(eval_episodes 1 → 2)" in capsys.readouterr().err.replace(str(out / "spec.json") + ": ", "")


def test_a_folder_trained_before_the_rate_decayed_by_default_resumes_and_extends_with_its_constant_rate(tmp_path, tiny):
    out = tmp_path / "run"
    options = [
        "train",
        "--variant",
        "raw",
        "--no-progress",
        "--out",
        str(out),
        "--n-envs",
        "2",
        "--eval-episodes",
        "1",
        "--env-kwargs",
        json.dumps(tiny.env_kwargs),
        "--algo-kwargs",
        json.dumps(tiny.ppo_kwargs),
    ]
    assert main([*options, "--steps", "128"]) == 0
    stored = json.loads((out / "spec.json").read_text())
    assert stored["algo_defaults"] == 3
    del stored["algo_defaults"]  # as train wrote it before 2026-12-03
    (out / "spec.json").write_text(json.dumps(stored))
    assert main([*options, "--steps", "256", "--extend"]) == 0
    spec = RunSpec.from_dict(json.loads((out / "spec.json").read_text()))
    assert spec.algo_defaults == 1 and spec.merged_algo_kwargs()["learning_rate"] == 3e-4
    constant = {**tiny.ppo_kwargs, "learning_rate": 3e-4}  # the same rate asked for in words: the same run
    assert main([*options[:-1], json.dumps(constant), "--steps", "384", "--extend"]) == 0
    assert (
        main(
            [
                *options,
                "--steps",
                "512",
                "--algo-kwargs",
                json.dumps({**tiny.ppo_kwargs, "learning_rate": 1e-3}),
                "--extend",
            ]
        )
        == 2
    )
    assert (
        main(
            [
                "train",
                "--variant",
                "raw",
                "--no-progress",
                "--out",
                str(tmp_path / "new"),
                "--steps",
                "128",
                "--n-envs",
                "2",
                "--eval-episodes",
                "1",
                "--env-kwargs",
                json.dumps(tiny.env_kwargs),
                "--algo-kwargs",
                json.dumps(tiny.ppo_kwargs),
            ]
        )
        == 0
    )
    assert json.loads((tmp_path / "new" / "spec.json").read_text())["algo_defaults"] == 3  # a new folder: the latest


@pytest.mark.slow
def test_compare_resumes_with_another_vec_env_or_threshold_and_a_failed_start_does_not_lock_the_folder(
    tmp_path, tiny, capsys
):
    out = tmp_path / "cmp"
    options = [
        "compare",
        "--variants",
        "raw",
        "--seeds",
        "1",
        "--workers",
        "1",
        "--out",
        str(out),
        "--n-envs",
        "2",
        "--eval-episodes",
        "1",
        "--steps",
        "128",
        "--env-kwargs",
        json.dumps(tiny.env_kwargs),
    ]
    (out).mkdir()
    (out / "compare.json").write_text(json.dumps({"variants": ["focus"], "seeds": [3], "run": {}, "threshold": 0.5}))
    assert main([*options, "--algo-kwargs", json.dumps(tiny.ppo_kwargs)]) == 0  # no run held progress: taken over
    assert main([*options, "--algo-kwargs", json.dumps(tiny.ppo_kwargs), "--vec", "dummy", "--threshold", "0.3"]) == 0
    assert "1 run(s) already done, 0 to train" in capsys.readouterr().out
    assert json.loads((out / "compare.json").read_text())["threshold"] == 0.3
    assert main([*options, "--algo-kwargs", json.dumps({**tiny.ppo_kwargs, "n_epochs": 2})]) == 2
    err = capsys.readouterr().err
    assert "holds a comparison with other settings" in err and "algo_kwargs.n_epochs 1 → 2" in err
    assert err.count("→") == 1  # only algo_kwargs differs


# --- the evaluation a budget pays for --------------------------------------------------
def _spec_of(argv):
    """The first ``RunSpec`` that ``train`` or ``compare`` would run for ``argv``, in an empty folder."""
    args = build_parser().parse_args(argv)
    return _spec_from_args(args, "focus", 0, dict(QUICK) if getattr(args, "quick", False) else {})


def test_a_small_budget_evaluates_on_fewer_episodes_and_long_runs_keep_their_defaults():
    assert _spec_of(["train", "--steps", "512"]).eval_episodes == 1
    assert _spec_of(["train", "--steps", "20000"]).eval_episodes == 4
    assert _spec_of(["train", "--steps", "512", "--eval-episodes", "7"]).eval_episodes == 7  # an explicit count stands
    quick = (QUICK["eval_episodes"], QUICK["eval_every"], QUICK["checkpoint_every"])
    for argv, settings in [
        (["train"], (20, 10_000, 20_000)),
        (["train", "--steps", "1_000_000"], (20, 100_000, 200_000)),
        (["compare"], (20, 10_000, 20_000)),
        (["compare", "--steps", "250000"], (20, 25_000, 50_000)),
        (["compare", "--quick"], quick),
    ]:
        spec = _spec_of(argv)
        assert (spec.eval_episodes, spec.eval_every, spec.checkpoint_every) == settings, argv


def test_a_smoke_train_keeps_its_first_evaluation_and_evaluates_two_episodes_in_all(tmp_path, tiny, capsys):
    """``train --steps 512`` (one PPO rollout of 32 × 64 env steps): an evaluation at 0 and one at the end, of one
    episode each (it was 20 each, many times the run's training at hundreds of env steps an episode)."""
    out = tmp_path / "smoke"
    assert (
        main(
            ["train", "--steps", "512", "--no-progress", "--env-kwargs", json.dumps(tiny.env_kwargs), "--out", str(out)]
        )
        == 0
    )
    printed = capsys.readouterr().out
    assert "focus-seed0: 512 env steps, evaluated on 1 episode at 0 env steps, every 51 and at the end" in printed
    assert re.search(
        r"final success rate \d\.\d\d, safe success rate \d\.\d\d \(≤ 1 s in contact\), contact \d+\.\d s / episode",
        printed,
    )
    rows = read_csv(out / "eval.csv")
    assert [(row["env_steps"], row["n_episodes"]) for row in rows] == [(0, 1), (2048, 1)]


def test_a_resumed_run_keeps_its_evaluation_episodes_when_the_flag_is_left_out(tmp_path, tiny):
    """A folder trained with ``--eval-episodes 3`` resumes and extends without the flag, as with ``--eval-every``."""
    out = tmp_path / "run"
    options = [
        "train",
        "--variant",
        "raw",
        "--no-progress",
        "--out",
        str(out),
        "--n-envs",
        "2",
        "--env-kwargs",
        json.dumps(tiny.env_kwargs),
        "--algo-kwargs",
        json.dumps(tiny.ppo_kwargs),
    ]
    assert main([*options, "--steps", "128", "--eval-episodes", "3"]) == 0
    assert main([*options, "--steps", "256", "--extend"]) == 0
    assert json.loads((out / "spec.json").read_text())["eval_episodes"] == 3
    assert read_csv(out / "eval.csv")[-1]["n_episodes"] == 3


# --- help texts and option parsing -----------------------------------------------------
@pytest.mark.parametrize("command", [None, *_SUBCOMMANDS])
def test_help_texts_show_real_defaults(command, capsys):
    with pytest.raises(SystemExit) as exited:
        main([command, "--help"] if command else ["--help"])
    assert exited.value.code == 0
    text = capsys.readouterr().out
    assert "%%" not in text and "default: None" not in text


def test_compare_help_names_the_plain_and_the_quick_budget(capsys):
    with pytest.raises(SystemExit):
        main(["compare", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "95 % CI" in text
    assert f"(default: {RunSpec.total_steps}; {QUICK['total_steps']} with --quick)" in text
    assert (
        f"(default: steps/{STEPS_PER_EVAL_EPISODE}, at least 1, at most {RunSpec.eval_episodes}; "
        f"{QUICK['eval_episodes']} with --quick)"
    ) in text
    assert f"(default: 5; {len(QUICK['seeds'])} with --quick)" in text


@pytest.mark.parametrize(
    "argv, message",
    [
        (["train", "--steps", "0"], "argument --steps: expected an integer >= 1, got '0'"),
        (["train", "--steps", "1e5"], "argument --steps: expected an integer >= 1, got '1e5'"),
        (["train", "--seed", "-1"], "argument --seed: expected an integer >= 0, got '-1'"),
        (["evaluate", "run", "--seed", "x"], "argument --seed: expected an integer >= 0, got 'x'"),
    ],
)
def test_integer_options_name_the_allowed_range(argv, message, capsys):
    with pytest.raises(SystemExit) as exited:
        main(argv)
    assert exited.value.code == 2 and message in capsys.readouterr().err


def test_integer_options_accept_underscores_and_zero_seeds():
    args = build_parser().parse_args(["train", "--steps", "100_000", "--seed", "0"])
    assert (args.steps, args.seed) == (100_000, 0)


# --- progress lines ----------------------------------------------------------------------
def test_progress_lines_count_and_estimate():
    now = [0.0]
    progress = Progress(3, clock=lambda: now[0])
    now[0] = 60.0
    assert progress.line("a") == "[1/3] a (elapsed 1m00s, ETA 2m00s)"
    now[0] = 90.0
    assert progress.line("b") == "[2/3] b (elapsed 1m30s, ETA 45s)"
    now[0] = 7500.0
    assert progress.line("c") == "[3/3] c (elapsed 2h05m)"
    assert [format_duration(s) for s in (0, 0.4, 59.6, 61, 3600)] == ["0s", "0s", "1m00s", "1m01s", "1h00m"]


def test_compare_logs_each_runs_own_time_and_an_eta(monkeypatch, tmp_path, tiny):
    import attentive_gym.agents.compare as compare_module

    def finished_runs(jobs, backend, workers):
        (_, first), (_, second) = jobs
        yield JobOutcome(first, True, 256, wall_s=123.0)
        yield JobOutcome(second, False, error="RuntimeError: boom", wall_s=4.0)

    monkeypatch.setattr(compare_module, "run_many", finished_runs)
    logs = []
    result = compare_module.compare(("raw",), (0, 1), tiny(), tmp_path, log=logs.append)
    assert re.fullmatch(r"\[1/2\] raw-seed0: done, 256 env steps in 2m03s \(elapsed \d+s, ETA \d+s\)", logs[0]), logs
    assert re.fullmatch(r"\[2/2\] raw-seed1: FAILED after 4s: RuntimeError: boom \(elapsed \d+s\)", logs[1]), logs
    assert result.trained == ["raw-seed0"] and list(result.failed) == ["raw-seed1"]


def test_experiment_all_prints_one_progress_line_per_experiment(monkeypatch, capsys):
    import attentive_gym.experiments.cli as experiment_cli
    from attentive_gym.experiments import EXPERIMENT_NAMES

    monkeypatch.setattr(experiment_cli, "run_experiment", lambda name, **_: SimpleNamespace(paths=()))
    monkeypatch.setattr(
        experiment_cli, "check_experiment", lambda result: [SimpleNamespace(passed=True, name="check", measured="1")]
    )
    assert main(["experiment", "all"]) == 0
    captured = capsys.readouterr()
    lines = captured.err.splitlines()
    assert "\r" not in captured.err and len(lines) == len(EXPERIMENT_NAMES)
    for i, (line, name) in enumerate(zip(lines, EXPERIMENT_NAMES), 1):
        eta = r", ETA \d+s" if i < len(EXPERIMENT_NAMES) else ""
        assert re.fullmatch(
            rf"\[{i}/{len(EXPERIMENT_NAMES)}\] {name}: 1/1 checks pass in \d+s \(elapsed \d+s{eta}\)", line
        ), line
    assert f"{EXPERIMENT_NAMES[0]}: 1/1 checks pass" in captured.out
