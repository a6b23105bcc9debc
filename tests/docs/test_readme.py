"""The README's Python examples run as written."""

import re
from pathlib import Path

import pytest

README = Path(__file__).resolve().parents[2] / "README.md"
EXAMPLES = re.findall(r"```python\n(.*?)```", README.read_text(encoding="utf-8"), flags=re.S)


def test_the_readme_has_python_examples():
    assert len(EXAMPLES) >= 2


@pytest.mark.parametrize("index", range(len(EXAMPLES)))
def test_readme_example_runs(index, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    exec(compile(EXAMPLES[index], f"README.md example {index}", "exec"), {"__name__": "readme_example"})


VARIANT_ROW = re.compile(r"^\| `([a-z-]+)` \| `(AttentiveRescue\w*-v\d+)` \| .* \| (\d+) \|$", flags=re.M)
PAGES_WITH_THE_VARIANT_TABLE = (README, README.parent / "docs" / "observations.md")


@pytest.mark.parametrize("page", PAGES_WITH_THE_VARIANT_TABLE, ids=lambda page: page.name)
def test_the_variant_tables_name_every_variant_with_its_id_and_observation_size(page):
    from attentive_gym.wrappers import make_env
    from attentive_gym.wrappers.variants import VARIANT_IDS, VARIANTS

    rows = VARIANT_ROW.findall(page.read_text(encoding="utf-8"))
    assert [variant for variant, _, _ in rows] == list(VARIANTS)
    for variant, env_id, size in rows:
        assert env_id == VARIANT_IDS[variant], (page.name, variant)
        env = make_env(variant, flatten=True)
        assert env.observation_space.shape == (int(size),), (page.name, variant)
        env.close()


def test_the_readmes_quick_run_is_what_compare_quick_trains():
    """The sentence before the README's ``attentive-gym compare --quick`` ("PPO on the raw sensors,
    on the attended focus, and on the oracle (...), 3 seeds each") names ``QUICK``'s variants, in
    its order, and its seed count; so does the later "3 seeds × 10 evaluation episodes"."""
    from attentive_gym.agents.config import QUICK, RunSpec
    from attentive_gym.wrappers.variants import VARIANTS

    text = README.read_text(encoding="utf-8")
    sentence = re.search(rf"{re.escape(RunSpec.algo.upper())} on ([^.]*?), (\d+) seeds each:", text)
    assert sentence, "the README no longer says what 'attentive-gym compare --quick' trains ('... N seeds each:')"
    words = re.findall(r"[a-z-]+", re.sub(r"\([^)]*\)", "", sentence[1]))  # an aside in brackets names no variant
    assert [word for word in words if word in VARIANTS] == list(QUICK["variants"])
    assert int(sentence[2]) == len(QUICK["seeds"])
    assert f"With {len(QUICK['seeds'])} seeds × {QUICK['eval_episodes']} evaluation episodes" in text
