"""docs/model.md, the model's specification, cannot go stale silently.

Every ``AttentionConfig`` field has a row in its parameter table (§11) whose default is the
field's default; every "docs/model.md §N" cited in the code, the tests and the docs names a
section that exists; no citation points at a specification outside the repository.
"""

import ast
import dataclasses
import re
from pathlib import Path

import pytest

from attentive_gym.attention import AttentionConfig

ROOT = Path(__file__).resolve().parents[2]
DOC = ROOT / "docs" / "model.md"
TEXT = DOC.read_text(encoding="utf-8")
FIELDS = dataclasses.fields(AttentionConfig)
#: Section numbers of the doc: its "## N. Title" headings.
SECTIONS = {int(n) for n in re.findall(r"^## (\d+)\. ", TEXT, flags=re.M)}
#: A citation: "docs/model.md §3", "docs/model.md §1–§8", "docs/model.md §4, §5".
CITATION = re.compile(r"docs/model\.md((?:,? ?§\d+(?:\s?[–-]\s?§?\d+)?)+)")


def _section(number: int) -> str:
    match = re.search(rf"^## {number}\. .*?(?=^## \d+\. |\Z)", TEXT, flags=re.M | re.S)
    assert match, f"docs/model.md has no section {number}"
    return match.group(0)


def _parameter_rows() -> dict[str, str]:
    """Field name → its default cell, from the table of §11."""
    rows = re.findall(r"^\| `(\w+)` \| `([^`]*)` \|", _section(11), flags=re.M)
    names = [name for name, _ in rows]
    assert len(names) == len(set(names)), "a field has two rows in §11"
    return dict(rows)


def _cited_files() -> list[Path]:
    files = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
    for folder in ("attentive_gym", "tests", "benchmarks"):
        files += sorted((ROOT / folder).rglob("*.py"))
    return [f for f in files if f.is_file()]


def test_the_doc_keeps_the_numbered_sections():
    assert SECTIONS == set(range(1, 13))


def test_the_doc_cites_the_paper_in_full():
    flat = " ".join(TEXT.replace("\n>", "\n").split())
    for part in (
        "Esther L. Colombini",
        "Alexandre S. Simões",
        "Carlos H. C. Ribeiro",
        "Top-down and Bottom-up Feature Combination for Multi-sensor Attentive Robots",
        "arXiv:1307.5720",
    ):
        assert part in flat


@pytest.mark.parametrize("field", FIELDS, ids=lambda f: f.name)
def test_every_config_field_is_in_the_parameter_table_with_its_default(field):
    rows = _parameter_rows()
    assert field.name in rows, f"AttentionConfig.{field.name} has no row in docs/model.md §11"
    assert ast.literal_eval(rows[field.name]) == field.default, (
        f"docs/model.md §11 gives AttentionConfig.{field.name} the default {rows[field.name]}, "
        f"the code {field.default!r}"
    )


def test_the_parameter_table_names_only_config_fields():
    assert set(_parameter_rows()) == {f.name for f in FIELDS}


def test_every_citation_names_an_existing_section():
    bad = []
    for path in _cited_files():
        text = path.read_text(encoding="utf-8")
        for match in CITATION.finditer(text):
            numbers = [int(n) for n in re.findall(r"\d+", match.group(1))]
            if match.group(1).count("–") or match.group(1).count("-"):
                numbers = list(range(min(numbers), max(numbers) + 1))
            bad += [f"{path.relative_to(ROOT)}: {match.group(0)}" for n in numbers if n not in SECTIONS]
    assert not bad, f"citations of missing sections: {bad}"


def test_no_citation_points_outside_the_repository():
    """The specification is docs/model.md; an upper-case MODEL.md is a file the repository lacks."""
    stale = [
        f"{path.relative_to(ROOT)}:{i}"
        for path in _cited_files()
        if path != Path(__file__).resolve()
        for i, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1)
        if "MODEL.md" in line
    ]
    assert not stale, f"cite docs/model.md instead: {stale}"
