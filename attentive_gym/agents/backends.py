"""Run many training runs in parallel: a spawn-context process pool (default) or Ray.

``run_many(jobs, backend, workers)`` submits ``run_job(spec_dict, run_dir)`` for each job
and yields one ``JobOutcome`` per job as it finishes. A run that raises is recorded in its
own ``run_dir/error.txt`` and reported as failed; the other runs go on (with the process
pool, a worker that dies outright fails only the runs it had, the pool is rebuilt for the
rest).
"""

from __future__ import annotations

import multiprocessing
import os
import traceback
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Iterator, Sequence

__all__ = ["BACKENDS", "JobOutcome", "run_job", "run_many", "ray_available"]

#: Backends of ``run_many``.
BACKENDS = ("process", "ray")


@dataclass(frozen=True)
class JobOutcome:
    """How one run ended: ``ok`` with its ``env_steps``, or not with the ``error`` text."""

    run_dir: str
    ok: bool
    env_steps: int | None = None
    error: str | None = None


def run_job(spec_dict: dict[str, Any], run_dir: str) -> JobOutcome:
    """Train one run (``training.train``) in this process; never raises for the run's own errors."""
    os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
    from attentive_gym.agents.config import RunSpec
    from attentive_gym.agents.results import write_text_atomic
    from attentive_gym.agents.training import train

    try:
        metrics = train(RunSpec.from_dict(spec_dict), run_dir)
        error_file = Path(run_dir) / "error.txt"
        error_file.unlink(missing_ok=True)
        return JobOutcome(run_dir, True, int(metrics["env_steps"]))
    except Exception as err:  # noqa: BLE001 - isolate the run, report it
        text = "".join(traceback.format_exception(err))
        try:
            write_text_atomic(Path(run_dir) / "error.txt", text)
        except OSError:
            pass
        return JobOutcome(run_dir, False, error=f"{type(err).__name__}: {err}")


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
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise ValueError(f"workers must be an integer >= 1, got {workers!r}")
    if backend == "ray" and not ray_available():
        raise ValueError("backend 'ray' needs Ray: pip install -e '.[ray]' (or pip install ray)")


def run_many(jobs: Sequence[tuple[dict[str, Any], str]], backend: str = "process", workers: int = 2) -> Iterator[JobOutcome]:
    """Run ``(spec_dict, run_dir)`` jobs with ``workers`` in parallel; yields outcomes as they finish."""
    _check(backend, workers)
    if not jobs:
        return
    if backend == "ray":
        yield from _run_ray(jobs, workers)
    else:
        yield from _run_pool(jobs, workers)


def _run_pool(jobs, workers, max_attempts: int = 2) -> Iterator[JobOutcome]:
    """A spawn pool; when a worker dies every unfinished run is retried in a new pool, up to
    ``max_attempts`` pools per run (the run that kills its worker fails, the others finish)."""
    pending = list(jobs)
    attempts = {run_dir: 0 for _, run_dir in jobs}
    while pending:
        context = multiprocessing.get_context("spawn")
        with ProcessPoolExecutor(max_workers=min(workers, len(pending)), mp_context=context) as pool:
            futures = {pool.submit(run_job, spec, run_dir): (spec, run_dir) for spec, run_dir in pending}
            pending = []
            not_done = set(futures)
            while not_done:
                done, not_done = wait(not_done, return_when=FIRST_COMPLETED)
                for future in done:
                    spec, run_dir = futures[future]
                    try:
                        yield future.result()
                    except BrokenProcessPool:
                        attempts[run_dir] += 1
                        if attempts[run_dir] >= max_attempts:
                            yield JobOutcome(run_dir, False, error="its worker process died (BrokenProcessPool)")
                        else:
                            pending.append((spec, run_dir))
                    except Exception as err:  # noqa: BLE001
                        yield JobOutcome(run_dir, False, error=f"{type(err).__name__}: {err}")


def _run_ray(jobs, workers) -> Iterator[JobOutcome]:
    import ray

    started = not ray.is_initialized()
    if started:
        ray.init(num_cpus=workers, include_dashboard=False, log_to_driver=False)
    try:
        remote = ray.remote(num_cpus=1, max_retries=0)(run_job)
        refs = {remote.remote(spec, run_dir): run_dir for spec, run_dir in jobs}
        not_done = list(refs)
        while not_done:
            done, not_done = ray.wait(not_done, num_returns=1)
            for ref in done:
                try:
                    yield ray.get(ref)
                except Exception as err:  # noqa: BLE001 - a worker crash (RayTaskError, WorkerCrashedError)
                    yield JobOutcome(refs[ref], False, error=f"{type(err).__name__}: {err}")
    finally:
        if started:
            ray.shutdown()
