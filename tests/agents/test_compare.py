"""The comparison: CI smoke test of its outputs, rerun after a kill, crash isolation, Ray."""

import json
import signal
import struct
from pathlib import Path

import pytest

from attentive_gym.agents.backends import ray_available, run_many
from attentive_gym.agents.compare import compare
from attentive_gym.agents.results import EVAL_COLUMNS, SUMMARY_COLUMNS, read_csv
from attentive_gym.cli import main

VARIANTS = ("raw", "focus")
SEEDS = (0, 1)


def _png_size(path):
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    return struct.unpack(">II", data[16:24])


@pytest.fixture(scope="module")
def compared(tmp_path_factory, tiny):
    out = tmp_path_factory.mktemp("cmp")
    argv = [
        "compare",
        "--variants",
        ",".join(VARIANTS),
        "--seeds",
        "2",
        "--steps",
        "256",
        "--n-envs",
        "2",
        "--eval-every",
        "128",
        "--eval-episodes",
        "2",
        "--env-kwargs",
        json.dumps(tiny.env_kwargs),
        "--algo-kwargs",
        json.dumps(tiny.ppo_kwargs),
        "--workers",
        "2",
        "--out",
        str(out),
    ]
    assert main(argv) == 0
    return out, argv


@pytest.mark.slow
def test_outputs_are_well_formed(compared):
    out, _ = compared
    rows = read_csv(out / "results.csv")
    assert list(rows[0]) == list(EVAL_COLUMNS)
    assert len(rows) == len(VARIANTS) * len(SEEDS) * 3  # eval at 0, 128, 256
    assert {(r["variant"], r["seed"]) for r in rows} == {(v, s) for v in VARIANTS for s in SEEDS}
    width, height = _png_size(out / "learning_curves.png")
    assert width > 300 and height > 200
    assert _png_size(out / "performance_profiles.png")[0] > 300
    summary = read_csv(out / "summary.csv")
    assert list(summary[0]) == list(SUMMARY_COLUMNS)
    assert [r["variant"] for r in summary] == list(VARIANTS)
    for row in summary:
        assert row["n_seeds"] == 2 and row["final_env_steps"] == 256
        assert row["final_success_ci_low"] <= row["final_success_mean"] <= row["final_success_ci_high"]
        assert 0 <= row["final_safe_success_mean"] <= row["final_success_mean"] and row["final_contact_s_mean"] >= 0
    table = (out / "summary.md").read_text().splitlines()
    assert len(table) == 2 + len(VARIANTS) and all(line.startswith("|") for line in table)
    assert "final safe success (≤ 1 s in contact)" in table[0] and "final contact time (s / episode)" in table[0]


@pytest.mark.slow
def test_rerun_after_a_kill_trains_only_the_missing_run(compared):
    out, argv = compared
    killed = out / "runs" / "focus-seed1"
    others = [p for p in (out / "runs").iterdir() if p != killed]
    stamps = {p: (p / "metrics.json").stat().st_mtime_ns for p in others}
    # what a kill leaves: no done marker, no final outputs; the checkpoint and spec remain
    for name in ("done", "metrics.json", "final_model.zip"):
        (killed / name).unlink()
    logs = []
    result = compare(VARIANTS, SEEDS, _spec_from(out), out, workers=2, log=logs.append)
    assert result.trained == ["focus-seed1"] and sorted(result.skipped) == sorted(p.name for p in others)
    assert (killed / "done").is_file()
    assert {p: (p / "metrics.json").stat().st_mtime_ns for p in others} == stamps
    assert len(read_csv(out / "results.csv")) == len(VARIANTS) * len(SEEDS) * 3
    # other settings into the same folder are refused
    assert main(argv + ["--steps", "512"]) == 2


def _spec_from(out):
    settings = json.loads((out / "compare.json").read_text())
    from attentive_gym.agents.config import RunSpec

    return RunSpec(variant=settings["variants"][0], seed=settings["seeds"][0], **settings["run"])


def _raw_argv(out, tiny, seeds, steps, *more):
    """``compare`` of raw on ``seeds`` (a count or a list) for ``steps`` env steps into ``out``,
    evaluated and checkpointed every 128 steps, then ``more`` options."""
    return [
        "compare",
        "--variants",
        "raw",
        "--seeds",
        seeds,
        "--steps",
        str(steps),
        "--n-envs",
        "2",
        "--eval-every",
        "128",
        "--checkpoint-every",
        "128",
        "--eval-episodes",
        "2",
        "--env-kwargs",
        json.dumps(tiny.env_kwargs),
        "--algo-kwargs",
        json.dumps(tiny.ppo_kwargs),
        "--workers",
        "1",
        "--out",
        str(out),
        *more,
    ]


@pytest.mark.slow
def test_extend_trains_a_finished_comparison_on_to_a_larger_budget(tmp_path, tiny):
    out = tmp_path / "cmp"

    def argv(steps, *more):
        return _raw_argv(out, tiny, "1", steps, *more)

    assert main(argv(256)) == 0
    settings = (out / "compare.json").read_text()
    before = read_csv(out / "results.csv")
    assert main(argv(384)) == 2 and (out / "compare.json").read_text() == settings  # refused, nothing written
    assert main(argv(384, "--eval-episodes", "3", "--extend")) == 2  # only the budget may change
    assert main(argv(384, "--extend")) == 0
    rows = read_csv(out / "results.csv")
    drop_wall = lambda table: [{k: v for k, v in r.items() if k != "wall_s"} for r in table]  # noqa: E731
    assert drop_wall(rows[: len(before)]) == drop_wall(before) and [r["env_steps"] for r in rows] == [0, 128, 256, 384]
    assert json.loads((out / "compare.json").read_text())["run"]["total_steps"] == 384
    assert json.loads((out / "runs" / "raw-seed0" / "metrics.json").read_text())["resumed_from"] == 256
    assert main(argv(256, "--extend")) == 2  # a budget never shrinks


@pytest.mark.slow
def test_more_seeds_train_beside_the_trained_ones(tmp_path, tiny):
    out = tmp_path / "cmp"

    def argv(seeds, *more):
        return _raw_argv(out, tiny, seeds, 128, *more)

    assert main(argv("1")) == 0  # seed 0
    stamp = (out / "runs" / "raw-seed0" / "metrics.json").stat().st_mtime_ns
    assert main(argv("1,2")) == 2  # a trained seed may not be dropped
    assert main(argv("0,1", "--eval-episodes", "3")) == 2  # nor the run settings change
    assert json.loads((out / "compare.json").read_text())["seeds"] == [0]
    assert main(argv("2")) == 0  # seeds 0 and 1
    assert (out / "runs" / "raw-seed0" / "metrics.json").stat().st_mtime_ns == stamp  # not retrained
    assert (out / "runs" / "raw-seed1" / "done").is_file()
    assert {r["seed"] for r in read_csv(out / "results.csv")} == {0, 1}
    assert json.loads((out / "compare.json").read_text())["seeds"] == [0, 1]


@pytest.mark.slow
def test_a_crashing_run_does_not_corrupt_the_others(tmp_path, tiny):
    good = tiny(total_steps=128)
    bad = tiny(total_steps=128, seed=1).to_dict() | {"env_kwargs": {"bogus_knob": 1}}
    outcomes = {
        o.run_dir: o
        for o in run_many([(good.to_dict(), str(tmp_path / "good")), (bad, str(tmp_path / "bad"))], workers=2)
    }
    assert outcomes[str(tmp_path / "good")].ok and (tmp_path / "good" / "done").is_file()
    failed = outcomes[str(tmp_path / "bad")]
    assert not failed.ok and "bogus_knob" in failed.error
    assert "Traceback" in (tmp_path / "bad" / "error.txt").read_text()
    assert not (tmp_path / "bad" / "done").exists()


def test_a_run_stopped_inside_a_compiled_call_is_stopped_not_failed(tmp_path, tiny, monkeypatch):
    """A stop signal's exception that numba wrapped in a SystemError must not be reported as the run's error."""
    from attentive_gym.agents import backends, stopping, training

    def fails_inside_numba(*_args, signalled: bool, **_kwargs):
        if signalled:
            stopping._received.append(signal.SIGTERM)  # what the SIGTERM handler records before it raises
        raise SystemError("CPUDispatcher(...) returned a result with an exception set")

    monkeypatch.setattr(training, "train", lambda *a, **k: fails_inside_numba(*a, signalled=True, **k))
    with pytest.raises(stopping.Interrupted) as stopped:
        backends.run_job(tiny().to_dict(), str(tmp_path / "run"))
    assert stopped.value.signum == signal.SIGTERM and not (tmp_path / "run" / "error.txt").exists()
    stopping._received.clear()
    monkeypatch.setattr(training, "train", lambda *a, **k: fails_inside_numba(*a, signalled=False, **k))
    failed = backends.run_job(tiny().to_dict(), str(tmp_path / "run"))  # no signal: a real failure, recorded
    assert not failed.ok and failed.error.startswith("SystemError") and (tmp_path / "run" / "error.txt").is_file()


def _run_processes_of(parent_pid):
    """Pids of ``parent_pid``'s spawned run processes (multiprocessing's resource tracker aside), from /proc."""
    pids = []
    for proc in Path("/proc").glob("[0-9]*"):
        try:
            ppid = int((proc / "stat").read_text().rsplit(")", 1)[1].split()[1])
            cmdline = (proc / "cmdline").read_bytes()
        except (OSError, IndexError):
            continue
        if ppid == parent_pid and b"spawn_main" in cmdline and b"resource_tracker" not in cmdline:
            pids.append(int(proc.name))
    return pids


@pytest.mark.slow
def test_a_run_whose_process_dies_fails_alone(tmp_path, tiny):
    import os
    import signal
    import threading
    import time

    def kill_the_first_run():
        deadline = time.monotonic() + 120
        while not (tmp_path / "r0" / "spec.json").is_file() and time.monotonic() < deadline:
            time.sleep(0.05)
        for pid in _run_processes_of(os.getpid()):
            os.kill(pid, signal.SIGKILL)

    jobs = [(tiny(total_steps=2048, seed=s).to_dict(), str(tmp_path / f"r{s}")) for s in (0, 1)]
    killer = threading.Thread(target=kill_the_first_run)
    killer.start()
    first, second = run_many(jobs, workers=1)
    killer.join()
    assert first.run_dir == jobs[0][1] and not first.ok and first.error == "its process died (exit status -9)"
    assert second.ok and second.env_steps == 2048 and (tmp_path / "r1" / "done").is_file()


def test_bad_backend_and_workers(tmp_path):
    with pytest.raises(ValueError, match="unknown backend"):
        list(run_many([], backend="threads"))
    with pytest.raises(ValueError, match="workers"):
        list(run_many([], workers=0))


@pytest.mark.slow
@pytest.mark.skipif(
    not ray_available(), reason="ray is not importable (install the 'ray' extra: pip install -e '.[ray]')"
)
def test_ray_backend_runs_the_same_jobs(tmp_path, tiny):
    import ray

    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        jobs = [(tiny(total_steps=128, seed=s).to_dict(), str(tmp_path / f"r{s}")) for s in (0, 1)]
        outcomes = list(run_many(jobs, backend="ray", workers=2))
    finally:
        ray.shutdown()
    assert sorted(o.run_dir for o in outcomes) == [j[1] for j in jobs]
    assert all(o.ok and o.env_steps == 128 for o in outcomes)
    assert read_csv(tmp_path / "r1" / "eval.csv")[-1]["env_steps"] == 128


@pytest.mark.slow
def test_a_killed_compare_process_reruns_only_the_missing_runs(tmp_path, tiny):
    """The real thing: SIGKILL the compare command's process group mid-way, then rerun it."""
    import os
    import signal
    import subprocess
    import sys
    import time

    out = tmp_path / "cmp"
    argv = [
        sys.executable,
        "-m",
        "attentive_gym.cli",
        "compare",
        "--variants",
        "raw,focus",
        "--seeds",
        "2",
        "--steps",
        "1024",
        "--n-envs",
        "2",
        "--eval-every",
        "512",
        "--eval-episodes",
        "2",
        "--checkpoint-every",
        "256",
        "--env-kwargs",
        json.dumps(tiny.env_kwargs),
        "--algo-kwargs",
        json.dumps(tiny.ppo_kwargs),
        "--workers",
        "2",
        "--out",
        str(out),
    ]
    proc = subprocess.Popen(argv, start_new_session=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 120
    while not list(out.glob("runs/*/done")) and time.monotonic() < deadline:
        time.sleep(0.2)
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()
    finished = {p.parent.name for p in out.glob("runs/*/done")}
    assert 1 <= len(finished) < 4
    stamps = {name: (out / "runs" / name / "metrics.json").stat().st_mtime_ns for name in finished}
    rerun = subprocess.run(argv, capture_output=True, text=True, timeout=300)
    assert rerun.returncode == 0, rerun.stderr
    assert f"{len(finished)} run(s) already done, {4 - len(finished)} to train" in rerun.stdout
    assert {name: (out / "runs" / name / "metrics.json").stat().st_mtime_ns for name in finished} == stamps
    rows = read_csv(out / "results.csv")
    assert len(rows) == 4 * 3 and all(r["env_steps"] <= 1024 for r in rows)  # evaluations at 0, 512 and 1024
    for run in (out / "runs").iterdir():
        steps = [r["env_steps"] for r in read_csv(run / "eval.csv")]
        assert steps == sorted(set(steps)) and steps[-1] == 1024


@pytest.mark.slow
def test_subproc_vec_env_inside_a_pool_worker(tmp_path, tiny):
    jobs = [(tiny(total_steps=256, vec_env="subproc").to_dict(), str(tmp_path / "sub"))]
    (outcome,) = run_many(jobs, workers=1)
    assert outcome.ok, outcome.error
