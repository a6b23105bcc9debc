"""Run many training runs in parallel: one spawned process per run (default) or Ray tasks.

``run_many(jobs, backend, workers)`` runs ``run_job(spec_dict, run_dir)`` for each job, at
most ``workers`` at a time, and yields one ``JobOutcome`` per job as it finishes. A run that
raises is recorded in its own ``run_dir/error.txt`` and reported as failed; with the process
backend a process that dies outright fails only its own run. The other runs go on.

**Stopping.** While ``run_many`` runs, SIGINT (Ctrl-C) and SIGTERM raise ``Interrupted``:
the runs in progress are stopped (process backend: SIGTERM, then SIGKILL after
``STOP_GRACE_S``; Ray: their tasks are cancelled) and the queued runs never start. Run
processes ignore SIGINT themselves (Ctrl-C reaches the whole process group; the parent
decides) and stop quietly on SIGTERM. Every file of a run is written atomically, so a
stopped run's folder keeps its last checkpoint and running the same jobs again resumes it.
A signal whose exception a finalizer dropped is not lost: the wait loops here and the
training loop (every env step) call ``raise_if_stopped`` (``stopping``, where the signal
handling lives).
"""

from __future__ import annotations

import multiprocessing
import multiprocessing.connection
import os
import sys
import time
import traceback
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from attentive_gym._checks import check_int
from attentive_gym.agents.stopping import (
    STOP_SIGNALS,
    Interrupted,
    raise_if_stopped,
    raise_if_stopped_from,
    raise_on_stop_signals,
    signals_blocked,
    stop_on_sigterm_only,
    stop_signals_ignored,
)

# STOP_SIGNALS, Interrupted, raise_on_stop_signals, raise_if_stopped and signals_blocked live in
# ``stopping`` (which ``training`` imports too); they stay importable from here.
__all__ = [
    "BACKENDS",
    "STOP_SIGNALS",
    "STOP_GRACE_S",
    "Interrupted",
    "JobOutcome",
    "raise_on_stop_signals",
    "raise_if_stopped",
    "signals_blocked",
    "run_job",
    "run_many",
    "ray_available",
]

#: Backends of ``run_many``.
BACKENDS = ("process", "ray")
#: Seconds a stopped run's process gets to exit after SIGTERM before it is killed.
STOP_GRACE_S = 10.0
#: Seconds between two looks at the stop signals while waiting for runs (see ``stopping.raise_if_stopped``).
_POLL_S = 0.5


@dataclass(frozen=True)
class JobOutcome:
    """How one run ended: ``ok`` with its ``env_steps``, or not with the ``error`` text.

    ``wall_s``: the run's own wall time in this call, in seconds (``None`` if unknown: a crashed Ray worker).
    """

    run_dir: str
    ok: bool
    env_steps: int | None = None
    error: str | None = None
    wall_s: float | None = None


def run_job(spec_dict: dict[str, Any], run_dir: str) -> JobOutcome:
    """Train one run (``training.train``) in this process; never raises for the run's own errors."""
    os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
    from attentive_gym.agents.config import RunSpec
    from attentive_gym.agents.results import write_text_atomic
    from attentive_gym.agents.training import train

    start_s = time.perf_counter()
    try:
        # compare has checked its settings (compare.json) before queueing the job: a run of a
        # smaller budget in run_dir is one that the comparison extends
        metrics = train(RunSpec.from_dict(spec_dict), run_dir, extend=True)
        error_file = Path(run_dir) / "error.txt"
        error_file.unlink(missing_ok=True)
        return JobOutcome(run_dir, True, int(metrics["env_steps"]), wall_s=time.perf_counter() - start_s)
    except Exception as err:  # noqa: BLE001 - isolate the run, report it
        raise_if_stopped_from(err)
        text = "".join(traceback.format_exception(err))
        try:
            write_text_atomic(Path(run_dir) / "error.txt", text)
        except OSError:
            pass
        return JobOutcome(run_dir, False, error=f"{type(err).__name__}: {err}", wall_s=time.perf_counter() - start_s)


def ray_available() -> bool:
    """Whether ``import ray`` works (the ``ray`` extra: ``pip install -e .[ray]``)."""
    try:
        import ray  # noqa: F401
    except ImportError:
        return False
    return True


def _check(backend: str, workers: int) -> None:
    if backend not in BACKENDS:
        raise ValueError(f"unknown backend {backend!r}; allowed: {list(BACKENDS)}")
    check_int("workers", workers, 1)
    if backend == "ray" and not ray_available():
        raise ValueError("backend 'ray' needs Ray: pip install -e '.[ray]' (or pip install ray)")


def run_many(
    jobs: Sequence[tuple[dict[str, Any], str]], backend: str = "process", workers: int = 2
) -> Iterator[JobOutcome]:
    """Run ``(spec_dict, run_dir)`` jobs with ``workers`` in parallel; yields outcomes as they finish.

    Raises ``Interrupted`` on SIGINT or SIGTERM (see the module docstring); closing the
    generator early also stops the runs in progress.
    """
    _check(backend, workers)
    if not jobs:
        return
    if backend == "ray":
        yield from _run_ray(jobs, workers)
    else:
        yield from _run_processes(jobs, workers)


# --- process backend ---------------------------------------------------------------------
@dataclass(frozen=True)
class _RunProcess:
    """A run's process, the read end of the pipe its ``JobOutcome`` comes through, its start (monotonic s)."""

    run_dir: str
    process: multiprocessing.process.BaseProcess
    outcome: multiprocessing.connection.Connection
    start_s: float


def _job_process(spec_dict: dict[str, Any], run_dir: str, outcome: multiprocessing.connection.Connection) -> None:
    """A run process's entry: SIGINT ignored, SIGTERM stops the run quietly (exit status 143)."""
    stop_on_sigterm_only()
    try:
        outcome.send(run_job(spec_dict, run_dir))
    except Interrupted as stop:
        sys.exit(stop.exit_status)


def _start(context, spec_dict: dict[str, Any], run_dir: str) -> _RunProcess:
    """Start one run's process; call with the stop signals blocked (it inherits them blocked)."""
    reader, writer = context.Pipe(duplex=False)
    process = context.Process(target=_job_process, args=(spec_dict, run_dir, writer), name=Path(run_dir).name)
    process.start()
    writer.close()
    return _RunProcess(run_dir, process, reader, time.monotonic())


def _collect(run: _RunProcess) -> JobOutcome:
    """The outcome of a run whose process has exited."""
    run.process.join()
    try:
        return run.outcome.recv()
    except EOFError:  # it exited without sending one
        return JobOutcome(
            run.run_dir,
            False,
            error=f"its process died (exit status {run.process.exitcode})",
            wall_s=time.monotonic() - run.start_s,
        )
    finally:
        run.outcome.close()


def _stop(runs: Iterable[_RunProcess], grace_s: float = STOP_GRACE_S) -> None:
    """SIGTERM every run's process, SIGKILL those still alive after ``grace_s`` seconds."""
    runs = list(runs)
    with stop_signals_ignored():
        for run in runs:
            run.process.terminate()
        deadline = time.monotonic() + grace_s
        for run in runs:
            run.process.join(max(0.0, deadline - time.monotonic()))
            if run.process.is_alive():
                run.process.kill()
                run.process.join()
            run.outcome.close()


def _run_processes(jobs: Sequence[tuple[dict[str, Any], str]], workers: int) -> Iterator[JobOutcome]:
    """At most ``workers`` run processes at a time (spawn); a new one starts when one exits."""
    context = multiprocessing.get_context("spawn")
    queued = list(jobs)
    running: dict[int, _RunProcess] = {}  # process sentinel → run
    with raise_on_stop_signals():
        try:
            while queued or running:
                while queued and len(running) < workers:
                    with signals_blocked():  # registered before a stop signal can be delivered
                        run = _start(context, *queued.pop(0))
                        running[run.process.sentinel] = run
                for sentinel in multiprocessing.connection.wait(list(running), timeout=_POLL_S):
                    yield _collect(running.pop(sentinel))
                raise_if_stopped()
        finally:
            _stop(running.values())


# --- Ray backend --------------------------------------------------------------------------
def _run_ray(jobs: Sequence[tuple[dict[str, Any], str]], workers: int) -> Iterator[JobOutcome]:
    """Ray tasks; on a stop signal the unfinished ones are cancelled (their workers killed)."""
    import ray

    started = not ray.is_initialized()
    if started:
        ray.init(num_cpus=workers, include_dashboard=False, log_to_driver=False)  # installs its own signal handlers
    not_done: list = []
    try:
        with raise_on_stop_signals():
            try:
                remote = ray.remote(num_cpus=1, max_retries=0)(run_job)
                refs = {remote.remote(spec, run_dir): run_dir for spec, run_dir in jobs}
                not_done = list(refs)
                while not_done:
                    done, not_done = ray.wait(not_done, num_returns=1, timeout=_POLL_S)
                    for ref in done:
                        try:
                            yield ray.get(ref)
                        except Exception as err:  # noqa: BLE001 - a worker crash (RayTaskError, WorkerCrashedError)
                            yield JobOutcome(refs[ref], False, error=f"{type(err).__name__}: {err}")
                    raise_if_stopped()
            except KeyboardInterrupt:
                raise_if_stopped()  # ray.wait turns our Interrupted into a plain KeyboardInterrupt
                raise
    finally:
        with stop_signals_ignored():
            for ref in not_done:
                ray.cancel(ref, force=True)
            if started:
                ray.shutdown()
