"""Warm starts: the teacher's demonstrations are cloned into the policy, counted in the
budget, deterministic, and refused where the teacher cannot act."""

import argparse
import json

import numpy as np
import pytest

from attentive_gym.agents import warm_start
from attentive_gym.agents.cli import _spec_from_args, add_train
from attentive_gym.agents.config import WARM_START_MIN_STEPS, RunSpec
from attentive_gym.agents.merged import HEADLINE_MODEL_VERSION, algo_tag
from attentive_gym.agents.results import read_csv
from attentive_gym.agents.training import _algo_class, _make_vec_env, _policy_name, train, validate_spec
from attentive_gym.attention import MODEL_VERSIONS
from attentive_gym.cli import main
from attentive_gym.perception.controllers import clearance_controller, privileged_clearance_controller
from attentive_gym.wrappers import make_env
from attentive_gym.wrappers.goal_action import DEFAULT_GOAL_MENU

PROXIMITY = {"time_limit_s": 2.0, "proximity": True}


@pytest.fixture
def small_demos(monkeypatch):
    """Demonstrations and cloning sized for a test: 256 env steps (one minibatch), 60 passes."""
    monkeypatch.setattr(warm_start, "BC_EPOCHS", 60)
    return 256


def _model_and_vec(spec):
    vec = _make_vec_env(spec)
    model = _algo_class("ppo")(
        _policy_name("ppo", vec.observation_space), vec, seed=spec.seed, device="cpu", **spec.merged_algo_kwargs()
    )
    return model, vec


def _action_error(model, demonstrations):
    """The mean squared gap between the policy's mean action and the teacher's labels."""
    import torch

    with torch.no_grad():
        inputs = {k: torch.as_tensor(v, dtype=torch.float32) for k, v in demonstrations.observations.items()}
        mean = model.policy.get_distribution(inputs).distribution.mean.numpy()
    return float(((mean - demonstrations.actions) ** 2).mean())


def test_the_labels_are_the_teachers_clean_actions_and_the_returns_discount_the_rewards(tiny):
    spec = tiny(variant="oracle", env_kwargs=PROXIMITY)
    vec = _make_vec_env(spec)
    try:
        demos = warm_start.collect_demonstrations(vec, "clearance", 100, seed=3)
    finally:
        vec.close()
    assert demos.actions.shape == (100, 2) and demos.returns.shape == (100,)
    assert {key: value.shape[0] for key, value in demos.observations.items()} == dict.fromkeys(demos.observations, 100)
    first = {key: value[0] for key, value in demos.observations.items()}  # env 0 at its first step
    assert np.array_equal(demos.actions[0], clearance_controller(first, {}))  # the label, not the noisy action
    assert np.isfinite(demos.returns).all()


def test_cloning_fits_the_policy_to_the_teacher(tiny, small_demos):
    spec = tiny(variant="oracle", env_kwargs=PROXIMITY, obs_scaling="none")
    model, vec = _model_and_vec(spec)
    try:
        demos = warm_start.collect_demonstrations(vec, "clearance", small_demos, seed=0)
        before = _action_error(model, demos)
        errors = warm_start.clone(model, demos, None, seed=0)
    finally:
        vec.close()
    after = _action_error(model, demos)
    assert after < 0.5 * before and errors["action_mse"] < before
    assert np.allclose(model.policy.log_std.detach().numpy(), np.log(warm_start.WARM_ACTION_STD))


def test_a_warm_started_run_counts_the_demonstrations_and_is_deterministic(tmp_path, tiny, monkeypatch, small_demos):
    monkeypatch.setattr(warm_start, "DEMO_STEPS", small_demos)
    spec = tiny(variant="oracle", env_kwargs=PROXIMITY, total_steps=512, warm_start="clearance")
    first, second = (train(spec, tmp_path / name, tensorboard=False) for name in ("a", "b"))
    rows = read_csv(tmp_path / "a" / "eval.csv")
    assert rows[0]["env_steps"] == small_demos  # the first evaluation follows the demonstrations
    assert first["env_steps"] == second["env_steps"] >= 512
    untimed = lambda table: [{k: v for k, v in row.items() if k != "wall_s"} for row in table]  # noqa: E731
    assert untimed(rows) == untimed(read_csv(tmp_path / "b" / "eval.csv"))
    assert json.loads((tmp_path / "a" / "spec.json").read_text())["warm_start"] == "clearance"


def test_in_goal_action_the_teacher_also_sets_the_tasks_goal_and_the_default_weights(tiny):
    """The label's motion is the privileged teacher's; its goal scores pick the episode's task
    goal (+1, the rest −1); its weights stand for 1 each; a goal off the menu picks no goal."""
    menu = DEFAULT_GOAL_MENU
    label = warm_start.goal_action_label(np.array([0.5, -0.2]), str(menu[2]), menu, 2.0)
    assert label.shape == (2 + len(menu) + 6,) and label.dtype == np.float32
    np.testing.assert_allclose(label[:2], [0.5, -0.2], rtol=1e-6)
    assert int(np.argmax(label[2 : 2 + len(menu)])) == 2 and sorted(label[2 : 2 + len(menu)])[:-1] == [-1.0] * 5
    np.testing.assert_array_equal(label[2 + len(menu) :], 0.0)  # (0 + 1) / 2 · 2 = weight 1
    assert int(np.argmax(warm_start.goal_action_label(np.zeros(2), "none", menu, 2.0)[2:8])) == menu.index(None)
    spec = tiny(variant="goal-action", env_kwargs={"time_limit_s": 2.0}, warm_start="privileged")
    vec = _make_vec_env(spec)
    try:
        demos = warm_start.collect_demonstrations(vec, "privileged", 64, seed=3)
    finally:
        vec.close()
    assert demos.actions.shape == (64, 14) and "proximity" in demos.observations
    for action, encoded in zip(demos.actions, demos.observations["goal"]):  # each label names its episode's goal
        np.testing.assert_array_equal(menu[int(np.argmax(action[2:8]))].encode(), encoded)
    assert float(np.abs(demos.actions[:, :2]).sum()) > 0.0


def test_a_warm_start_is_refused_where_the_teacher_cannot_act(tmp_path, tiny):
    with pytest.raises(ValueError, match=r"needs the observation entries \['memory', 'proximity'\]"):
        validate_spec(tiny(variant="raw", warm_start="clearance"))
    with pytest.raises(ValueError, match="proximity"):
        validate_spec(tiny(variant="oracle", env_kwargs={"proximity": False}, warm_start="clearance"))
    with pytest.raises(ValueError, match=r"needs the observation entries \['proximity'\] or \['sonar \(16,\)', 'laser"):
        validate_spec(tiny(variant="raw-stack", warm_start="privileged"))  # stacked readings
    with pytest.raises(ValueError, match="privileged"):
        validate_spec(tiny(variant="masked", warm_start="privileged"))  # masked readings
    validate_spec(tiny(variant="raw", warm_start="privileged"))  # raw readings: the privileged teacher acts
    with pytest.raises(ValueError, match="unknown warm_start 'teacher'; allowed: None, 'clearance', 'privileged'"):
        validate_spec(tiny(variant="oracle", env_kwargs=PROXIMITY, warm_start="teacher"))
    with pytest.raises(ValueError, match="warm_start applies to ppo only"):
        RunSpec(algo="sac", warm_start="clearance")
    out = tmp_path / "run"
    assert main(["train", "--variant", "raw", "--warm-start", "clearance", "--steps", "64", "--out", str(out)]) == 2
    assert not out.exists()


def test_warm_started_rows_carry_their_teacher_in_the_tag():
    plain = RunSpec(variant="oracle", env_version=HEADLINE_MODEL_VERSION, warm_start=None).to_dict()
    assert algo_tag({**plain, "warm_start": "clearance"}, "oracle") == algo_tag(plain, "oracle").replace(
        ", task v1", ", warm start clearance, task v1"
    )
    assert RunSpec.from_dict({k: v for k, v in plain.items() if k != "warm_start"}).warm_start is None


def test_ppo_warm_starts_from_the_privileged_teacher_by_default_where_it_can():
    long = {"total_steps": WARM_START_MIN_STEPS}
    for variant in ("raw", "saliency", "focus", "goal-action", "random-focus", "oracle"):
        assert RunSpec(variant=variant, **long).warm_start == "privileged", variant
    for variant in ("raw-stack", "masked"):
        assert RunSpec(variant=variant, **long).warm_start is None, variant
    assert RunSpec(variant="focus", env_kwargs={"proximity": False}, **long).warm_start is None
    assert RunSpec(variant="focus", task_version=0, **long).warm_start is None  # no proximity entry there
    assert RunSpec(variant="raw", total_steps=WARM_START_MIN_STEPS - 1).warm_start is None
    assert RunSpec(variant="raw", algo="sac", **long).warm_start is None
    assert RunSpec(variant="raw", warm_start=None, **long).warm_start is None
    base = RunSpec(variant="raw", **long)
    assert base.for_variant("raw-stack").warm_start is None and base.for_variant("focus").warm_start == "privileged"
    chosen = RunSpec(variant="oracle", warm_start="clearance", **long)
    assert chosen.for_variant("focus").warm_start == "clearance"


def test_the_command_line_warm_starts_by_default_and_none_turns_it_off():
    parser = argparse.ArgumentParser()
    add_train(parser.add_subparsers())
    parse = lambda *extra: parser.parse_args(["train", "--variant", "raw", "--steps", "300000", *extra])  # noqa: E731
    assert _spec_from_args(parse(), "raw", 0).warm_start == "privileged"
    assert _spec_from_args(parse("--warm-start", "none"), "raw", 0).warm_start is None
    stored = RunSpec(variant="raw", total_steps=300_000, warm_start=None).to_dict()
    assert _spec_from_args(parse(), "raw", 0, stored=stored).warm_start is None  # a trained folder keeps its own
    assert _spec_from_args(parse("--task", "0"), "raw", 0).task_version == 0
    assert _spec_from_args(parse(), "raw", 0).env_version == MODEL_VERSIONS[-1]
    assert _spec_from_args(parse("--model", "1"), "raw", 0).env_version == 1
    assert _spec_from_args(parse(), "raw", 0, stored={**stored, "env_version": 1}).env_version == 1
    with pytest.raises(SystemExit):
        parse("--model", "4")
    assert (
        _spec_from_args(parse(), "raw", 0, stored={k: v for k, v in stored.items() if k != "task_version"}).task_version
        == 0
    )


def test_the_privileged_teacher_on_raw_readings_acts_as_the_avoider_on_the_oracles_observation():
    """The same world seen as ``raw`` and as ``oracle`` with proximity: the privileged teacher,
    reading the truth from ``info`` and the proximity from the raw ranges, acts as the
    ``clearance`` avoider on the oracle's observation, step after step."""
    kwargs = {"arena_size_m": 8.0, "num_distractors": 2, "rubble_per_100m2": 3.0, "time_limit_s": 6.0}
    raw_env, oracle_env = make_env("raw", **kwargs), make_env("oracle", proximity=True, **kwargs)
    try:
        (raw, raw_info), (oracle, oracle_info) = raw_env.reset(seed=5), oracle_env.reset(seed=5)
        turned = 0
        for _ in range(120):
            action = privileged_clearance_controller(raw, raw_info)
            assert np.allclose(action, clearance_controller(oracle, oracle_info), atol=1e-4)
            assert np.allclose(action, privileged_clearance_controller(oracle, oracle_info), atol=1e-4)
            turned += abs(float(action[1])) > 0.1
            raw, _, done, cut, raw_info = raw_env.step(action)
            oracle, _, *_, oracle_info = oracle_env.step(action)
            if done or cut:
                break
        assert turned > 0  # the episode asked for steering, not only straight driving
    finally:
        raw_env.close()
        oracle_env.close()


def test_each_demonstration_is_labelled_from_its_own_steps_info(tiny, monkeypatch):
    """The teacher sees, beside each observation, the info of the same step: the reset's
    (time 0) at every episode's first observation, then the step's; two episodes per env."""
    seen = []

    def recording(obs, info):
        seen.append(float(info["time_s"]))
        return np.zeros(2, np.float32)

    monkeypatch.setitem(warm_start.WARM_STARTS, "recording", recording)
    spec = tiny(variant="raw", env_kwargs={**tiny.env_kwargs, "time_limit_s": 0.5})
    vec = _make_vec_env(spec)
    try:
        demos = warm_start.collect_demonstrations(vec, "recording", 2 * 25, seed=0)
    finally:
        vec.close()
    dt = 0.05
    times = np.array(seen).reshape(-1, spec.n_envs)  # (steps, envs)
    expected = (np.arange(times.shape[0]) % round(0.5 / dt)) * dt  # every env: 10 steps, then a new episode
    assert np.allclose(times, expected[:, None]) and len(demos.actions) == times.size
