"""The policies shipped with the package (``attentive_gym.agents.pretrained``) still do what their
record says on the current environment, and ``attentive-gym evaluate --pretrained`` runs them."""

import json

import pytest

from attentive_gym.agents.evaluation import evaluate_policy
from attentive_gym.agents.pretrained import PRETRAINED, pretrained_record, pretrained_run
from attentive_gym.agents.training import env_factory, load_policy
from attentive_gym.cli import main
from attentive_gym.registration import ID_VERSIONS, VARIANT_IDS


@pytest.mark.parametrize("variant", PRETRAINED)
def test_each_shipped_policy_still_reaches_its_recorded_success(variant):
    """Under 1 MB, recorded on today's environment id (a version bump must ship new ones), and
    on its recorded episodes its success lies within the interval recorded when it shipped."""
    run = pretrained_run(variant)
    assert sum(path.stat().st_size for path in run.iterdir()) <= 1_000_000
    record = pretrained_record(variant)
    assert record["env_id"] == VARIANT_IDS[variant]
    policy, spec = load_policy(run)
    assert spec.variant == variant and spec.task_version == ID_VERSIONS[record["env_id"]][1]
    result = evaluate_policy(policy, env_factory(spec), record["episodes"], record["first_seed"])
    low, high = record["success_ci"]
    assert low <= result.success_rate <= high, (result.success_rate, record)


def test_evaluate_runs_a_pretrained_policy_and_says_what_it_recorded(capsys):
    assert main(["evaluate", "--pretrained", "focus", "--episodes", "1", "--json"]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    assert lines[0].startswith(f"the pretrained focus policy ({VARIANT_IDS['focus']},")
    row = json.loads(lines[-1])
    assert row["variant"] == "focus" and row["n_episodes"] == 1


@pytest.mark.parametrize("argv", [["evaluate"], ["evaluate", "some_run", "--pretrained", "raw"]])
def test_evaluate_takes_a_model_or_a_pretrained_variant_not_both(argv, capsys):
    assert main(argv) == 2
    assert "give a run folder or .zip model, or --pretrained VARIANT (one of them)" in capsys.readouterr().err


def test_a_variant_without_a_shipped_policy_is_named_with_those_that_have_one():
    with pytest.raises(ValueError, match="no pretrained policy for 'oracle'; shipped: raw, focus"):
        pretrained_run("oracle")
