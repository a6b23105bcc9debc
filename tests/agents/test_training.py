"""One run: outputs, determinism, evaluation rows, and resume after an interruption."""

import json

import numpy as np
import pytest
from stable_baselines3.common.callbacks import BaseCallback

from attentive_gym.agents.evaluation import evaluate_policy
from attentive_gym.agents.results import EVAL_COLUMNS, read_csv
from attentive_gym.agents.training import env_factory, is_done, load_model, train


class Interrupt(BaseCallback):
    """Raises once the run has passed ``at`` env steps (a stand-in for a kill)."""

    def __init__(self, at):
        super().__init__()
        self.at = at

    def _on_step(self):
        if self.num_timesteps > self.at:
            raise KeyboardInterrupt(f"interrupted at {self.num_timesteps}")
        return True


def _eval_table(run_dir):
    return [{k: v for k, v in row.items() if k != "wall_s"} for row in read_csv(run_dir / "eval.csv")]


def test_run_writes_outputs_and_is_deterministic(tmp_path, tiny):
    spec = tiny()
    metrics = train(spec, tmp_path / "a")
    for name in ("spec.json", "eval.csv", "final_model.zip", "metrics.json", "done", "checkpoint/model.zip"):
        assert (tmp_path / "a" / name).is_file(), name
    assert any((tmp_path / "a" / "tb").rglob("events.out.tfevents*"))
    assert metrics["env_steps"] == 384 and json.loads((tmp_path / "a" / "metrics.json").read_text())["env_steps"] == 384
    final = json.loads((tmp_path / "a" / "metrics.json").read_text())[
        "final"
    ]  # safe success and contact beside success
    assert 0 <= final["safe_success_rate"] <= final["success_rate"] <= 1 and final["mean_contact_s"] >= 0
    rows = read_csv(tmp_path / "a" / "eval.csv")
    assert list(rows[0]) == list(EVAL_COLUMNS)
    assert [r["env_steps"] for r in rows] == [0, 128, 256, 384]
    for row in rows:
        assert 0 <= row["success_rate"] <= 1 and row["n_episodes"] == 2 and 1 <= row["mean_episode_length"] <= 40
    train(spec, tmp_path / "b")
    assert _eval_table(tmp_path / "a") == _eval_table(tmp_path / "b")
    model_a, loaded_spec = load_model(tmp_path / "a")
    model_b, _ = load_model(tmp_path / "b" / "final_model.zip")
    assert loaded_spec == spec
    for pa, pb in zip(model_a.policy.parameters(), model_b.policy.parameters()):
        assert np.array_equal(pa.detach().numpy(), pb.detach().numpy())
    # a done run is not retrained; another spec into the same folder is refused
    assert train(spec, tmp_path / "a")["env_steps"] == 384
    with pytest.raises(ValueError, match="different spec"):
        train(spec.replace(seed=1), tmp_path / "a")


def test_resume_continues_the_step_count(tmp_path, tiny):
    spec = tiny(total_steps=640, checkpoint_every=256, eval_every=256)
    run_dir = tmp_path / "run"
    with pytest.raises(KeyboardInterrupt):
        train(spec, run_dir, callbacks=[Interrupt(at=400)])
    assert not is_done(run_dir)
    ckpt_steps = json.loads((run_dir / "checkpoint" / "meta.json").read_text())["env_steps"]
    assert ckpt_steps == 256  # last checkpoint before the interruption: at most one interval lost
    metrics = train(spec, run_dir)
    assert metrics["resumed_from"] == 256
    assert metrics["env_steps"] == train(spec, tmp_path / "straight")["env_steps"] == 640
    steps = [r["env_steps"] for r in read_csv(run_dir / "eval.csv")]
    assert steps == sorted(set(steps)) and steps[0] == 0 and steps[-1] == 640
    model, _ = load_model(run_dir)
    assert model.num_timesteps == 640
    result = evaluate_policy(model, env_factory(spec), 2, seed=5)
    assert result.n_episodes == 2


def test_a_linear_learning_rate_decays_over_the_budget_and_resumes_where_it_was(tmp_path, tiny):
    spec = tiny(
        total_steps=640,
        checkpoint_every=256,
        eval_every=256,
        algo_kwargs={**tiny.ppo_kwargs, "learning_rate": "lin_1e-3"},
    )
    straight = train(spec, tmp_path / "straight")
    with pytest.raises(KeyboardInterrupt):
        train(spec, tmp_path / "resumed", callbacks=[Interrupt(at=400)])
    checkpoint, _ = load_model(tmp_path / "resumed" / "checkpoint" / "model.zip")
    # SB3 updates after each rollout at the budget's fraction left: 1 - 256/640 at the checkpoint
    assert checkpoint.policy.optimizer.param_groups[0]["lr"] == pytest.approx(1e-3 * (1 - 256 / 640))
    assert train(spec, tmp_path / "resumed")["resumed_from"] == 256
    assert straight["env_steps"] == 640
    model, loaded_spec = load_model(tmp_path / "straight")
    assert loaded_spec.algo_kwargs["learning_rate"] == "lin_1e-3"
    assert model.policy.optimizer.param_groups[0]["lr"] == 0.0  # the end of the budget
    resumed, _ = load_model(tmp_path / "resumed")  # the decay goes on over the same budget
    assert resumed.lr_schedule(0.5) == model.lr_schedule(0.5) == pytest.approx(5e-4)
    assert resumed.policy.optimizer.param_groups[0]["lr"] == 0.0
    with pytest.raises(ValueError, match="lin_<number > 0>"):
        tiny(algo_kwargs={"learning_rate": "linear"})


def test_extend_trains_a_finished_run_on_to_a_larger_budget(tmp_path, tiny):
    spec = tiny()
    run_dir = tmp_path / "run"
    train(spec, run_dir)
    before = _eval_table(run_dir)
    longer = spec.replace(total_steps=640)
    with pytest.raises(ValueError, match="--extend"):
        train(longer, run_dir)
    assert is_done(run_dir, 384) and not is_done(run_dir, 640)
    with pytest.raises(ValueError, match="different spec"):  # only the budget may change, and only grow
        train(longer.replace(seed=1), run_dir, extend=True)
    with pytest.raises(ValueError, match="different spec"):
        train(spec.replace(total_steps=256), run_dir, extend=True)
    metrics = train(longer, run_dir, extend=True)
    assert metrics["resumed_from"] == 384 and metrics["env_steps"] == 640 and is_done(run_dir, 640)
    after = _eval_table(run_dir)
    assert after[: len(before)] == before and [r["env_steps"] for r in after[len(before) :]] == [512, 640]
    assert json.loads((run_dir / "spec.json").read_text())["total_steps"] == 640
    model, loaded_spec = load_model(run_dir)
    assert model.num_timesteps == 640 and loaded_spec == longer
    assert train(longer, run_dir, extend=True)["resumed_from"] == 384  # done: read, not retrained


def test_sac_resume_keeps_the_replay_buffer(tmp_path, tiny):
    spec = tiny(
        algo="sac",
        variant="raw",
        total_steps=120,
        n_envs=1,
        checkpoint_every=50,
        eval_every=60,
        algo_kwargs={"learning_starts": 20, "batch_size": 16, "buffer_size": 1000},
    )
    run_dir = tmp_path / "sac"
    with pytest.raises(KeyboardInterrupt):
        train(spec, run_dir, callbacks=[Interrupt(at=70)])
    assert (run_dir / "checkpoint" / "replay_buffer.pkl").is_file()
    metrics = train(spec, run_dir)
    assert metrics["resumed_from"] == 50 and metrics["env_steps"] == 120
    model, _ = load_model(run_dir)
    assert type(model).__name__ == "SAC" and model.num_timesteps == 120


def test_evaluate_policy_counts_episodes(tiny):
    class Forward:
        def predict(self, obs, state=None, episode_start=None, deterministic=True):
            n = len(obs["sonar"])
            return np.tile(np.array([1.0, 0.0], np.float32), (n, 1)), None

    spec = tiny()
    result = evaluate_policy(Forward(), env_factory(spec), 5, seed=1, n_parallel=2)
    again = evaluate_policy(Forward(), env_factory(spec), 5, seed=1, n_parallel=3)
    assert result.n_episodes == 5 and len(result.returns) == 5
    assert result.returns == pytest.approx(again.returns)  # episode i always gets seed + i
    assert result.mean_episode_length <= 40
    with pytest.raises(ValueError):
        evaluate_policy(Forward(), env_factory(spec), 0, seed=1)


def test_a_run_without_tensorboard_leaves_nothing_in_the_temp_directory(tmp_path, tiny, monkeypatch):
    import tempfile

    temp = tmp_path / "temp"
    temp.mkdir()
    monkeypatch.delenv("SB3_LOGDIR", raising=False)  # SB3 would otherwise make SB3-<date> folders here
    monkeypatch.setattr(tempfile, "tempdir", str(temp))
    train(tiny(total_steps=128), tmp_path / "run", tensorboard=False)
    assert [p.name for p in temp.iterdir() if p.name.startswith("SB3-")] == []
    assert (tmp_path / "run" / "metrics.json").is_file() and not (tmp_path / "run" / "tb").exists()


def test_the_thread_count_is_set_before_any_torch_operation(tmp_path, tiny, monkeypatch):
    """``validate_spec`` builds the algorithm (torch's first operations in a fresh run process): it must find
    torch already at the run's thread count, or the OpenMP pool starts with every core and its extra threads
    keep spinning after it shrinks (2-3x the CPU time of a training step, measured)."""
    import numba
    import torch

    import attentive_gym.agents.training as training

    seen = []
    validate = training.validate_spec
    monkeypatch.setattr(
        training,
        "validate_spec",
        lambda spec: seen.append((torch.get_num_threads(), numba.get_num_threads())) or validate(spec),
    )
    torch.set_num_threads(2)
    try:
        train(tiny(torch_threads=1, total_steps=128), tmp_path / "run", tensorboard=False)
    finally:
        torch.set_num_threads(1)
    assert seen == [(1, 1)]
