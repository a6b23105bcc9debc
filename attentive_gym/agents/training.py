"""Train one SB3 policy (PPO, SAC or RecurrentPPO) on one observation variant, with evaluation and checkpoints.

``train(spec, run_dir)`` first checks that the run can start (``validate_spec``: one env is
built, the algorithm's keywords are checked) and writes nothing if it cannot. Then it writes
into ``run_dir``:

- ``spec.json``: the ``RunSpec`` (once the folder holds a checkpoint, a rerun into it must use
  the same spec, or, with ``extend``, the same with a larger ``total_steps``);
- ``eval.csv``: one row per evaluation (``results.EVAL_COLUMNS``), at 0, every
  ``spec.eval_every`` env steps and at the end;
- ``goal_choice.csv`` (``goal-action`` runs only): one row per evaluation
  (``goal_choice.goal_choice_columns``): the share of the evaluation's steps whose chosen goal
  is the task's, each menu entry's share, and each map weight's mean;
- ``checkpoint/model.zip`` (+ ``replay_buffer.pkl`` for SAC, + ``meta.json``, +
  ``obs_normalization.npz`` when ``spec.obs_scaling`` is ``"running"``): the latest
  checkpoint, every ``spec.checkpoint_every`` env steps;
- ``tb/``: TensorBoard logs (SB3's ``train/``, ``rollout/`` and our ``eval/`` scalars);
- ``final_model.zip`` (+ ``obs_normalization.npz``: the observation statistics that
  ``load_policy`` puts in front of it), ``metrics.json`` and, last of all, the ``done``
  marker.

Every file is written atomically (temp file + ``os.replace``). Calling ``train`` again on a
folder without ``done`` resumes from the checkpoint: the step count continues, the saved
model (with SAC's replay buffer and the observation statistics) is loaded, and evaluation
rows after the checkpoint are dropped, so an interrupted run loses at most one checkpoint
interval. PPO's rollout buffer cannot be saved by SB3, so checkpoints are taken at rollout
boundaries (after an update, before the next rollout) where it is empty; a resumed run
therefore ends at exactly the step count of an uninterrupted one. RecurrentPPO resumes the same way; its LSTM state
starts from zeros at the resumed run's first (fresh) episodes.

``train(..., extend=True)`` (``--extend``) trains a run on to a larger ``total_steps``, the
rest of its spec unchanged: a finished run resumes from its final checkpoint the same way,
and its final model, statistics and metrics are replaced at the new end; its evaluation
rows so far are kept. Like any resumed run, it does not replay, number for number, a run
trained straight to the larger budget (the envs restart, the random seed is re-drawn).
"""

from __future__ import annotations

import functools
import inspect
import json
import os
import signal
import sys
import time
import warnings
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import gymnasium as gym

from attentive_gym.agents.config import RunSpec
from attentive_gym.agents.evaluation import EVAL_SEED_OFFSET, evaluate_policy
from attentive_gym.agents.goal_choice import GOAL_CHOICE_FILE, GoalChoiceTally, goal_choice_columns
from attentive_gym.agents.normalization import STATS_FILE, NormalizedPolicy, load_stats, normalize, save_stats
from attentive_gym.agents.results import EVAL_COLUMNS, read_csv, write_csv_atomic, write_json_atomic, write_text_atomic
from attentive_gym.agents.stopping import raise_if_stopped, signals_blocked
from attentive_gym.agents.warm_start import check_warm_start, warm_start
from attentive_gym.wrappers.variants import make_env

__all__ = [
    "train",
    "validate_spec",
    "load_model",
    "load_policy",
    "env_factory",
    "eval_seed",
    "is_done",
    "budget_grows",
    "holds_progress",
    "checkpoint_steps",
    "DONE_MARKER",
    "RunResult",
]

DONE_MARKER = "done"
_CHECKPOINT = "checkpoint"
#: Constructor parameters of the SB3 algorithms that ``train`` sets itself (not ``algo_kwargs``).
_SET_BY_TRAIN = ("self", "policy", "env", "seed", "device", "verbose", "tensorboard_log", "_init_setup_model")


def env_factory(spec: RunSpec, **overrides: Any) -> Callable[..., gym.Env]:
    """A picklable zero-argument builder of one environment of ``spec`` (Dict observation)."""
    return functools.partial(
        make_env, spec.variant, version=spec.env_version, task=spec.task_version, **{**spec.env_kwargs, **overrides}
    )


def eval_seed(spec: RunSpec) -> int:
    """Seed of a run's first evaluation episode: ``10 000 + 1 000·seed`` (disjoint from training's)."""
    return EVAL_SEED_OFFSET + 1000 * spec.seed


def is_done(run_dir: str | os.PathLike, total_steps: int = 0) -> bool:
    """Whether ``run_dir`` holds a finished run (its ``done`` marker, which holds the run's
    env steps) of at least ``total_steps`` env steps."""
    marker = Path(run_dir) / DONE_MARKER
    return marker.is_file() and int(marker.read_text()) >= total_steps


def checkpoint_steps(run_dir: str | os.PathLike) -> int | None:
    """Env steps of ``run_dir``'s checkpoint (``None`` without one)."""
    meta = Path(run_dir) / _CHECKPOINT / "meta.json"
    return int(json.loads(meta.read_text())["env_steps"]) if meta.is_file() else None


def _algo_class(algo: str):
    """The SB3 class of ``algo``: ``PPO``, ``SAC`` or sb3-contrib's ``RecurrentPPO``."""
    if algo == "recurrent-ppo":
        try:
            from sb3_contrib import RecurrentPPO
        except ImportError:
            raise ValueError(
                "algo 'recurrent-ppo' needs sb3-contrib: pip install -e '.[agents]' (or pip install sb3-contrib)"
            ) from None
        return RecurrentPPO
    from stable_baselines3 import PPO, SAC

    return {"ppo": PPO, "sac": SAC}[algo]


def _policy_name(algo: str, observation_space: gym.Space) -> str:
    """The SB3 policy: ``MultiInput…`` for a ``Dict`` space, else ``Mlp…``; ``…LstmPolicy`` for RecurrentPPO."""
    inputs = "MultiInput" if isinstance(observation_space, gym.spaces.Dict) else "Mlp"
    return f"{inputs}{'Lstm' if algo == 'recurrent-ppo' else ''}Policy"


def _check_algo_kwargs(spec: RunSpec) -> None:
    """``algo_kwargs`` must name parameters of the algorithm's constructor that ``train`` leaves free."""
    algo_cls = _algo_class(spec.algo)
    reserved = sorted(set(spec.algo_kwargs) & set(_SET_BY_TRAIN))
    if reserved:
        raise ValueError(
            f"algo_kwargs: {', '.join(map(repr, reserved))} cannot be given: train sets the policy, "
            "env, seed (--seed), device, verbose and tensorboard_log itself"
        )
    parameters = inspect.signature(algo_cls.__init__).parameters
    allowed = sorted(name for name in parameters if name not in _SET_BY_TRAIN)
    unknown = sorted(set(spec.algo_kwargs) - set(allowed))
    if unknown:
        raise ValueError(
            f"algo_kwargs: {algo_cls.__name__} takes no {', '.join(map(repr, unknown))}; allowed: {', '.join(allowed)}"
        )


def _check_env_and_algo_values(spec: RunSpec) -> None:
    """Build one environment of ``spec`` and the algorithm on it, then close it: a bad
    ``env_kwargs`` keyword or value, or an ``algo_kwargs`` value the algorithm refuses (a
    string for ``n_steps``, say), raises ``ValueError`` naming which."""
    try:
        env = env_factory(spec)()
    except TypeError as err:  # an unknown env keyword: the user's input
        raise ValueError(f"env_kwargs: {err}") from None
    if spec.warm_start is not None:
        try:
            menu = len(env.get_wrapper_attr("goal_menu")) if spec.variant == "goal-action" else None
            check_warm_start(spec.warm_start, env.observation_space, env.action_space, menu)
        except ValueError:
            env.close()
            raise
    from stable_baselines3.common.vec_env import DummyVecEnv

    vec = DummyVecEnv([lambda: env])
    try:
        with warnings.catch_warnings():  # one env, not n_envs: no warning about the rollout's size
            warnings.simplefilter("ignore")
            _algo_class(spec.algo)(
                _policy_name(spec.algo, env.observation_space),
                vec,
                device="cpu",
                verbose=0,
                **spec.merged_algo_kwargs(),
            )
    except (TypeError, ValueError, AssertionError) as err:
        raise ValueError(
            f"algo_kwargs {json.dumps(spec.algo_kwargs, default=str)} are refused by {spec.algo}: {err}"
        ) from None
    finally:
        vec.close()


def validate_spec(spec: RunSpec) -> None:
    """Raise ``ValueError`` (one line, naming what is allowed) if ``spec`` cannot start; writes nothing.

    Checks that ``algo_kwargs`` are keywords of the algorithm (and sb3-contrib is installed for
    recurrent-ppo), then builds one environment with ``env_kwargs`` (a missing scenario, an
    unknown keyword or a bad value fail here) and the algorithm on it with ``algo_kwargs``
    (a value it refuses fails here), checks that the ``warm_start`` teacher can act on that
    environment, then closes them.
    """
    _check_algo_kwargs(spec)
    _check_env_and_algo_values(spec)


def _make_vec_env(spec: RunSpec):
    from stable_baselines3.common.vec_env import DummyVecEnv, SubprocVecEnv

    factory = env_factory(spec)
    if spec.vec_env == "native":
        from attentive_gym.vector.sb3 import NativeVecEnv

        return NativeVecEnv([factory() for _ in range(spec.n_envs)], info_keywords=_MONITOR_KEYWORDS)
    fns = [functools.partial(_monitored, factory) for _ in range(spec.n_envs)]
    if spec.vec_env == "subproc":
        # the env processes never see Ctrl-C (sent to the whole process group): this process stops them
        with signals_blocked([signal.SIGINT]):
            return SubprocVecEnv(fns, start_method="spawn")
    return DummyVecEnv(fns)


def _monitored(factory: Callable[[], gym.Env]) -> gym.Env:
    from stable_baselines3.common.monitor import Monitor

    return Monitor(factory(), info_keywords=_MONITOR_KEYWORDS)


#: ``info`` keys kept in each training episode's record (SB3's ``Monitor``).
_MONITOR_KEYWORDS = ("success",)


class RunResult(dict):
    """``metrics.json`` of a run as a dict (``env_steps``, ``final``: the last evaluation row, ...)."""


def _save_atomic_zip(model, path: Path) -> None:
    tmp = path.with_name(f".{path.stem}.tmp.zip")
    try:
        model.save(tmp)
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


def _write_checkpoint(model, run_dir: Path, wall_s: float, is_off_policy: bool, vec_normalize) -> None:
    folder = run_dir / _CHECKPOINT
    folder.mkdir(parents=True, exist_ok=True)
    if vec_normalize is not None:  # before the model: a checkpoint's model always has its statistics
        save_stats(vec_normalize, folder / STATS_FILE)
    if is_off_policy:
        tmp = folder / ".replay_buffer.tmp.pkl"
        model.save_replay_buffer(tmp)
        os.replace(tmp, folder / "replay_buffer.pkl")
    _save_atomic_zip(model, folder / "model.zip")
    write_json_atomic(folder / "meta.json", {"env_steps": int(model.num_timesteps), "wall_s": wall_s})


def _records_goal_choice(spec: RunSpec) -> bool:
    """Whether a run's evaluations write ``goal_choice.csv``: those of ``goal-action``."""
    return spec.variant == "goal-action"


def _make_callback(
    spec: RunSpec,
    run_dir: Path,
    rows: list[dict],
    choice_rows: list[dict],
    start_wall: float,
    eval_envs: list[gym.Env],
    vec_normalize,
):
    from stable_baselines3.common.callbacks import BaseCallback

    class RunCallback(BaseCallback):
        """Evaluates every ``eval_every`` and checkpoints every ``checkpoint_every`` env steps.

        Both happen at rollout starts (after the previous update), where PPO's rollout
        buffer is empty; the final evaluation and checkpoint happen at training end.
        """

        def __init__(self):
            super().__init__()
            self.t0 = time.perf_counter()
            self.last_eval = rows[-1]["env_steps"] if rows else None
            self.last_ckpt = None

        def wall(self) -> float:
            return start_wall + time.perf_counter() - self.t0

        def _on_training_start(self) -> None:
            self.last_ckpt = self.num_timesteps

        def _on_rollout_start(self) -> None:
            steps = self.num_timesteps
            if self.last_eval is None or steps - self.last_eval >= spec.eval_every:
                self.evaluate()
            if steps - self.last_ckpt >= spec.checkpoint_every:
                self.checkpoint()

        def _on_step(self) -> bool:
            raise_if_stopped()
            return True

        def _on_training_end(self) -> None:
            if self.last_eval != self.num_timesteps:
                self.evaluate()

        def evaluate(self) -> None:
            policy = self.model if vec_normalize is None else NormalizedPolicy(self.model, vec_normalize)
            menu_size = len(eval_envs[0].get_wrapper_attr("goal_menu")) if _records_goal_choice(spec) else None
            tally = None if menu_size is None else GoalChoiceTally(menu_size)
            result = evaluate_policy(
                policy, env_factory(spec), spec.eval_episodes, eval_seed(spec), envs=eval_envs, on_step=tally
            )
            run = {"variant": spec.variant, "seed": spec.seed, "env_steps": int(self.num_timesteps)}
            row = {**run, **result.row(), "wall_s": self.wall()}
            rows.append(row)
            write_csv_atomic(run_dir / "eval.csv", rows, EVAL_COLUMNS)
            if tally is not None:
                choice_rows.append({**run, **tally.row()})
                write_csv_atomic(run_dir / GOAL_CHOICE_FILE, choice_rows, goal_choice_columns(menu_size))
                self.logger.record("eval/task_goal_share", choice_rows[-1]["task_goal_share"])
            for key in (
                "success_rate",
                "safe_success_rate",
                "mean_return",
                "mean_collision_steps",
                "mean_contact_s",
                "mean_episode_length",
            ):
                self.logger.record(f"eval/{key}", row[key])
            self.last_eval = self.num_timesteps

        def checkpoint(self) -> None:
            _write_checkpoint(self.model, run_dir, self.wall(), spec.algo == "sac", vec_normalize)
            self.last_ckpt = self.num_timesteps

    return RunCallback()


def holds_progress(run_dir: Path) -> bool:
    """Whether ``run_dir`` holds training worth keeping: a checkpoint or the done marker."""
    return (run_dir / _CHECKPOINT / "model.zip").is_file() or is_done(run_dir)


def budget_grows(old: RunSpec, new: RunSpec) -> bool:
    """Whether ``new`` has ``old``'s settings (``RunSpec.same_settings``) with a larger
    ``total_steps`` (and any vectorisation, which changes no number): a run of ``old`` can be
    extended to ``new``."""
    stretched = old.replace(vec_env=new.vec_env, total_steps=new.total_steps)
    return new.total_steps > old.total_steps and stretched.same_settings(new)


def _bind_spec(spec: RunSpec, run_dir: Path, extend: bool) -> None:
    """Write ``run_dir/spec.json``, or check that the run already there has ``spec``.

    A different spec is refused once the folder holds progress (``holds_progress``), except,
    with ``extend``, a larger budget (``budget_grows``): the finished run's ``done`` marker
    is removed, then the new spec written, so that an interruption from here on leaves an
    unfinished run that resumes from its checkpoint. Before any progress, as after a start
    that failed, the folder is simply taken over.
    """
    path = run_dir / "spec.json"
    if path.is_file() and holds_progress(run_dir):
        old = RunSpec.from_dict(json.loads(path.read_text()))
        if old.replace(vec_env=spec.vec_env).same_settings(spec):  # the vectorisation changes no number
            return
        if not budget_grows(old, spec):
            raise ValueError(
                f"{run_dir} holds a run with a different spec ({path}: {old.differences(spec)}); "
                "use another --out folder"
            )
        if not extend:
            raise ValueError(
                f"{run_dir} holds a run of {old.total_steps} env steps with otherwise the same spec; "
                f"extend it to {spec.total_steps} (--extend) or use another --out folder"
            )
        (run_dir / DONE_MARKER).unlink(missing_ok=True)
    write_text_atomic(path, spec.to_json() + "\n")


def _logger_without_folder(verbose: int):
    """An SB3 logger that writes nowhere but, when ``verbose``, to stdout (SB3's default
    without TensorBoard also creates an empty folder under the temp directory)."""
    from stable_baselines3.common.logger import HumanOutputFormat, Logger

    return Logger(folder=None, output_formats=[HumanOutputFormat(sys.stdout)] if verbose else [])


def train(
    spec: RunSpec,
    run_dir: str | os.PathLike,
    *,
    progress_bar: bool = False,
    tensorboard: bool = True,
    verbose: int = 0,
    callbacks: Sequence[Any] = (),
    extend: bool = False,
) -> RunResult:
    """Train (or resume, or skip if ``done``) the run ``spec`` into ``run_dir``.

    Raises ``ValueError`` before writing anything when ``spec`` cannot start
    (``validate_spec``) or ``run_dir`` holds another run (with ``extend``, a run of the same
    spec but a smaller ``total_steps``, finished or not, is trained on to ``spec``'s budget
    from its latest checkpoint).

    Args:
        spec: the run.
        run_dir: its folder (created); see the module docstring for the files.
        progress_bar: SB3's progress bar (tqdm + rich).
        tensorboard: write TensorBoard logs under ``run_dir/tb``.
        verbose: SB3's verbosity.
        callbacks: extra SB3 callbacks (run after the evaluation/checkpoint one).
        extend: train a shorter run already in ``run_dir`` on (see above).

    Returns:
        The run's metrics (also in ``run_dir/metrics.json``).
    """
    import numba
    import torch

    run_dir = Path(run_dir)
    # before any torch operation (validate_spec builds the algorithm): an OpenMP pool started
    # with more threads keeps them spinning after set_num_threads shrinks it, which cost
    # 2-3x the CPU time of every training step
    torch.set_num_threads(spec.torch_threads)
    numba.set_num_threads(min(spec.torch_threads, numba.config.NUMBA_NUM_THREADS))  # the fleet's sensor sweep
    validate_spec(spec)
    run_dir.mkdir(parents=True, exist_ok=True)
    _bind_spec(spec, run_dir, extend)
    if is_done(run_dir):
        return RunResult(json.loads((run_dir / "metrics.json").read_text()))
    algo_cls = _algo_class(spec.algo)
    eval_envs = [env_factory(spec)() for _ in range(min(4, spec.eval_episodes))]
    vec = raw_vec = _make_vec_env(spec)
    ckpt = run_dir / _CHECKPOINT / "model.zip"
    vec_normalize = None
    if spec.obs_scaling == "running":
        stats = run_dir / _CHECKPOINT / STATS_FILE
        vec = vec_normalize = normalize(vec, stats if ckpt.is_file() and stats.is_file() else None)
    try:
        tb = str(run_dir / "tb") if tensorboard else None
        rows: list[dict] = []
        choice_rows: list[dict] = []
        start_wall = 0.0
        if ckpt.is_file():
            model = algo_cls.load(ckpt, env=vec, device="cpu", tensorboard_log=tb)
            if spec.algo == "sac" and (run_dir / _CHECKPOINT / "replay_buffer.pkl").is_file():
                model.load_replay_buffer(run_dir / _CHECKPOINT / "replay_buffer.pkl")
            meta_path = run_dir / _CHECKPOINT / "meta.json"
            start_wall = json.loads(meta_path.read_text())["wall_s"] if meta_path.is_file() else 0.0
            model.set_random_seed(spec.seed + model.num_timesteps)
            rows = _rows_until(run_dir / "eval.csv", model.num_timesteps)
            choice_rows = _rows_until(run_dir / GOAL_CHOICE_FILE, model.num_timesteps)
            resumed_from = int(model.num_timesteps)
        else:
            for leftover in ("eval.csv", GOAL_CHOICE_FILE):
                (run_dir / leftover).unlink(missing_ok=True)
            model = algo_cls(
                _policy_name(spec.algo, vec.observation_space),
                vec,
                seed=spec.seed,
                device="cpu",
                verbose=verbose,
                tensorboard_log=tb,
                **spec.merged_algo_kwargs(),
            )
            resumed_from = 0
            if spec.warm_start is not None:  # demonstrations cloned first; their env steps count
                model.num_timesteps = warm_start(model, raw_vec, vec_normalize, spec.warm_start, spec.seed)
        if tb is None:  # SB3's own logger would make an empty folder in the temp directory
            model.set_logger(_logger_without_folder(verbose))
        callback = _make_callback(spec, run_dir, rows, choice_rows, start_wall, eval_envs, vec_normalize)
        remaining = spec.total_steps - int(model.num_timesteps)
        t0 = time.perf_counter()
        if remaining > 0:
            from stable_baselines3.common.callbacks import CallbackList

            model.learn(
                remaining,
                callback=CallbackList([callback, *callbacks]),
                progress_bar=progress_bar,
                reset_num_timesteps=model.num_timesteps == 0,
                tb_log_name="tb",
            )
        elif not rows or rows[-1]["env_steps"] != model.num_timesteps:
            callback.init_callback(model)
            callback.evaluate()
        train_s = time.perf_counter() - t0
        _write_checkpoint(model, run_dir, callback.wall(), spec.algo == "sac", vec_normalize)
        if vec_normalize is not None:
            save_stats(vec_normalize, run_dir / STATS_FILE)
        _save_atomic_zip(model, run_dir / "final_model.zip")
        metrics = RunResult(
            spec=spec.to_dict(),
            run_name=spec.run_name,
            env_steps=int(model.num_timesteps),
            resumed_from=resumed_from,
            wall_s=callback.wall(),
            train_s_this_session=train_s,
            steps_per_s_this_session=(model.num_timesteps - resumed_from) / train_s if train_s > 0 else None,
            final=rows[-1] if rows else None,
            n_evals=len(rows),
        )
        write_json_atomic(run_dir / "metrics.json", metrics)
        write_text_atomic(run_dir / DONE_MARKER, f"{int(model.num_timesteps)}\n")
        return metrics
    finally:
        vec.close()
        for env in eval_envs:
            env.close()


def _rows_until(path: Path, env_steps: int) -> list[dict[str, Any]]:
    """The rows of a run's CSV at ``path`` up to ``env_steps`` (a checkpoint's: the later ones
    are evaluated again); none without the file."""
    return [row for row in read_csv(path) if row["env_steps"] <= env_steps] if path.is_file() else []


def find_spec(model_path: str | os.PathLike) -> tuple[Path, RunSpec]:
    """(model zip, its run's ``RunSpec``) for a run folder or a ``.zip`` inside one (or its ``checkpoint/``)."""
    path = Path(model_path)
    if path.is_dir():
        path = path / "final_model.zip"
    if not path.is_file():
        raise ValueError(f"no model at {model_path} (give a run folder or a .zip model)")
    for folder in (path.parent, path.parent.parent):
        if (folder / "spec.json").is_file():
            return path, RunSpec.from_dict(json.loads((folder / "spec.json").read_text()))
    raise ValueError(f"no spec.json next to {path} or in its parent folder; the model's run folder is needed")


def load_model(model_path: str | os.PathLike):
    """(SB3 model, ``RunSpec``) from a run folder or a ``.zip`` saved by ``train``."""
    path, spec = find_spec(model_path)
    return _load(path, spec), spec


def _load(path: Path, spec: RunSpec):
    """The SB3 model saved at ``path`` by a run of ``spec``."""
    return _algo_class(spec.algo).load(path, device="cpu")


def load_policy(model_path: str | os.PathLike):
    """(policy, ``RunSpec``) as ``load_model``, where the policy is what evaluation asks for
    actions: the model, behind its saved observation statistics (``NormalizedPolicy``) when
    the run normalised its observations.

    Raises:
        ValueError: when such a run's statistics (``obs_normalization.npz`` beside the
            ``.zip``) are missing.
    """
    path, spec = find_spec(model_path)
    model = _load(path, spec)
    if spec.obs_scaling != "running":
        return model, spec
    stats = path.parent / STATS_FILE
    if not stats.is_file():
        raise ValueError(f"{path} was trained on normalised observations, but {stats} is missing")
    return NormalizedPolicy(model, load_stats(stats, env_factory(spec))), spec
