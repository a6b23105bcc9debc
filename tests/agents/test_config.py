"""RunSpec validation and the CLI's list parsers."""

import pytest

from attentive_gym.agents.config import RunSpec, default_eval_episodes, parse_seeds, parse_variants


def test_unknown_variant_lists_allowed_ones():
    with pytest.raises(ValueError, match=r"unknown variant 'nope'; allowed: \['raw', 'raw-stack', 'focus'"):
        RunSpec(variant="nope")
    with pytest.raises(ValueError, match="allowed"):
        parse_variants("raw,nope")


@pytest.mark.parametrize(
    "field, value",
    [
        ("total_steps", 0),
        ("total_steps", -5),
        ("total_steps", 1.5),
        ("seed", -1),
        ("seed", "3"),
        ("n_envs", 0),
        ("eval_episodes", 0),
        ("algo", "dqn"),
        ("vec_env", "threads"),
        ("env_kwargs", [1]),
    ],
)
def test_bad_values_raise(field, value):
    with pytest.raises(ValueError, match=field if field not in ("algo", "vec_env") else "unknown"):
        RunSpec(**{field: value})


def test_roundtrip_and_names():
    spec = RunSpec(variant="raw-stack", seed=3, env_kwargs={"arena_size_m": 8.0}, algo_kwargs={"n_steps": 128})
    assert RunSpec.from_dict(spec.to_dict()) == spec
    assert spec.run_name == "raw-stack-seed3"
    assert spec.merged_algo_kwargs()["n_steps"] == 128 and spec.merged_algo_kwargs()["batch_size"] == 512
    with pytest.raises(ValueError, match="unknown RunSpec field"):
        RunSpec.from_dict({**spec.to_dict(), "colour": 1})


def test_the_default_learning_rate_decays_and_older_specs_keep_their_constant_rate():
    from stable_baselines3.common.utils import LinearSchedule

    for algo in ("ppo", "recurrent-ppo"):
        spec = RunSpec(algo=algo)
        assert spec.algo_defaults == 3 and spec.default_algo_kwargs()["learning_rate"] == "lin_3e-4"
        schedule = spec.merged_algo_kwargs()["learning_rate"]
        assert isinstance(schedule, LinearSchedule) and schedule(1.0) == 3e-4 and schedule(0.0) == 0.0
        old = {key: value for key, value in spec.to_dict().items() if key != "algo_defaults"}  # a spec.json of before
        assert (
            RunSpec.from_dict(old).algo_defaults == 1
            and RunSpec.from_dict(old).merged_algo_kwargs()["learning_rate"] == 3e-4
        )
        assert RunSpec.from_dict(spec.to_dict()) == spec
    assert "learning_rate" not in RunSpec(algo="sac").default_algo_kwargs()
    assert RunSpec(algo_kwargs={"learning_rate": 1e-4}).merged_algo_kwargs()["learning_rate"] == 1e-4
    for bad in (0, 4, True, "2", 2.0):
        with pytest.raises(ValueError, match=r"unknown algo_defaults .*; allowed: \[1, 2, 3\]"):
            RunSpec(algo_defaults=bad)


def test_ppo_defaults_to_32_envs_of_64_step_rollouts_and_earlier_folders_keep_theirs():
    """algo_defaults 3: PPO trains 32 envs × 64 steps, minibatch 512 (2048 steps and 4 minibatches per
    epoch); RecurrentPPO and SAC keep 4 envs; a spec of algo_defaults 2 (or one without n_envs) keeps 4 × 256,
    minibatch 256; a count given stands."""
    spec = RunSpec()
    hyper = spec.hyper_parameters()
    assert (spec.n_envs, hyper["n_steps"], hyper["batch_size"], hyper["n_epochs"]) == (32, 64, 512, 5)
    recurrent = RunSpec(algo="recurrent-ppo")
    assert recurrent.n_envs == 4 and recurrent.hyper_parameters()["n_steps"] == 256
    assert RunSpec(algo="sac").n_envs == 4
    earlier = RunSpec(algo_defaults=2)
    hyper = earlier.hyper_parameters()
    assert (earlier.n_envs, hyper["n_steps"], hyper["batch_size"]) == (4, 256, 256)
    stored = {key: value for key, value in RunSpec(algo_defaults=2).to_dict().items() if key != "n_envs"}
    assert RunSpec.from_dict(stored).n_envs == 4
    assert RunSpec.from_dict(spec.to_dict()) == spec and spec.to_dict()["n_envs"] == 32
    assert RunSpec(n_envs=8).n_envs == 8
    asked = RunSpec(algo_defaults=2, n_envs=32, algo_kwargs={"n_steps": 64, "batch_size": 512})
    assert asked.same_settings(spec)  # a comparison asked for today's rollout by flags is today's setting
    with pytest.raises(ValueError, match="n_envs"):
        RunSpec(n_envs=0)


def test_runs_are_told_apart_by_their_hyper_parameters_not_by_how_they_were_asked_for():
    from attentive_gym.agents.training import budget_grows

    old = RunSpec(algo_defaults=1)  # a folder trained before the rate decayed by default
    decayed = RunSpec(algo_defaults=2)  # ... and one trained before PPO's rollout changed
    assert old.same_settings(decayed.replace(algo_kwargs={"learning_rate": 0.0003}))
    assert budget_grows(old, decayed.replace(algo_kwargs={"learning_rate": 3e-4}, total_steps=old.total_steps * 2))
    assert RunSpec(algo_kwargs={"learning_rate": "lin_0.0003"}).same_settings(RunSpec())
    assert not old.same_settings(decayed) and not budget_grows(old, decayed.replace(total_steps=old.total_steps * 2))
    assert (
        old.differences(decayed.replace(eval_every=5))
        == 'eval_every 10000 → 5, algo_kwargs.learning_rate 0.0003 → "lin_0.0003"'
    )
    assert not decayed.same_settings(RunSpec()) and decayed.differences(RunSpec()) == (
        "n_envs 4 → 32, algo_kwargs.n_steps 256 → 64, algo_kwargs.batch_size 256 → 512"
    )
    assert RunSpec().learning_rate() == "lin_0.0003" and RunSpec(algo="sac").learning_rate() == 3e-4


def test_recurrent_policy_kwargs_merge_key_by_key():
    """RecurrentPPO's 64-unit LSTM stays when other policy keywords are given, and goes
    when the size itself is; PPO has no default policy keywords to merge."""
    assert RunSpec(algo="recurrent-ppo").merged_algo_kwargs()["policy_kwargs"] == {"lstm_hidden_size": 64}
    spec = RunSpec(algo="recurrent-ppo", algo_kwargs={"policy_kwargs": {"net_arch": [32]}})
    assert spec.merged_algo_kwargs()["policy_kwargs"] == {"lstm_hidden_size": 64, "net_arch": [32]}
    spec = RunSpec(algo="recurrent-ppo", algo_kwargs={"policy_kwargs": {"lstm_hidden_size": 256}})
    assert spec.merged_algo_kwargs()["policy_kwargs"] == {"lstm_hidden_size": 256}
    assert "policy_kwargs" not in RunSpec(algo="ppo").merged_algo_kwargs()
    spec = RunSpec(algo="ppo", algo_kwargs={"policy_kwargs": {"net_arch": [32]}})
    assert spec.merged_algo_kwargs()["policy_kwargs"] == {"net_arch": [32]}


def test_parsers():
    assert parse_variants(" raw, focus ") == ("raw", "focus")
    assert parse_seeds("3") == (0, 1, 2)
    assert parse_seeds("4,7") == (4, 7)
    for bad in ("0", "-1", "a", "2,-3"):
        with pytest.raises(ValueError, match="seeds must be"):
            parse_seeds(bad)
    with pytest.raises(ValueError, match="no variant given"):
        parse_variants(" ")


@pytest.mark.parametrize(
    "text, message",
    [
        ("raw,", "empty item in the variant list 'raw,'"),
        (",raw", "empty item in the variant list ',raw'"),
        ("raw,,focus", "empty item in the variant list 'raw,,focus'"),
        ("raw,focus,raw", "variant 'raw' is listed twice in 'raw,focus,raw'"),
    ],
)
def test_variant_lists_with_empty_or_repeated_items_are_refused(text, message):
    with pytest.raises(ValueError, match=message):
        parse_variants(text)


@pytest.mark.parametrize(
    "text, message",
    [
        ("0,1,", "empty item in the seed list '0,1,'"),
        ("0,,1", "empty item in the seed list '0,,1'"),
        ("1,1", "seed 1 is listed twice in '1,1'"),
        ("0,2,02", "seed 2 is listed twice in '0,2,02'"),
    ],
)
def test_seed_lists_with_empty_or_repeated_items_are_refused(text, message):
    with pytest.raises(ValueError, match=message):
        parse_seeds(text)


def test_evaluation_episodes_follow_a_small_budget_and_reach_the_default_at_100k_steps():
    budgets = (1, 512, 9_999, 10_000, 20_000, 99_999, 100_000, 150_000, 1_000_000)
    assert [default_eval_episodes(steps) for steps in budgets] == [1, 1, 1, 2, 4, 19, 20, 20, 20]
    assert default_eval_episodes(100_000) == RunSpec.eval_episodes
    with pytest.raises(ValueError, match="total_steps must be an integer >= 1, got 0"):
        default_eval_episodes(0)
