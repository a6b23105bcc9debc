"""Dates live in the dated notes: the README and the hand-written pages carry none, and each
note under docs/notes/ is dated once, at its top, with the date its name starts with (the
generated pages under docs/results/ say what they were generated from)."""

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DATE = re.compile(r"20\d\d-\d\d-\d\d")
#: A Markdown link's target, which may name a note's file (and so its date).
LINK_TARGET = re.compile(r"\]\([^)]*\)")
NOTES = sorted((ROOT / "docs" / "notes").glob("20*.md"))
PAGES = [
    ROOT / "README.md",
    *sorted(p for p in (ROOT / "docs").rglob("*.md") if not {"notes", "results", "_build"} & set(p.parts)),
]


def _dates(path: Path) -> list[str]:
    return DATE.findall(LINK_TARGET.sub("]()", path.read_text(encoding="utf-8")))


@pytest.mark.parametrize("path", PAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_pages_outside_the_notes_carry_no_dates(path):
    assert _dates(path) == [], f"{path.relative_to(ROOT)}: move dated material to docs/notes/"


def test_there_are_notes():
    assert NOTES


@pytest.mark.parametrize("path", NOTES, ids=lambda p: p.name)
def test_each_note_is_dated_once_at_its_top(path):
    date = DATE.match(path.name)
    assert date, f"{path.name}: a note's name starts with its date, YYYY-MM-DD-topic.md"
    lines = path.read_text(encoding="utf-8").splitlines()
    assert lines[0].startswith("# ") and lines[2] == f"*{date.group(0)}*", (
        f"{path.name}: a title, a blank line, then *{date.group(0)}*"
    )
    assert _dates(path) == [date.group(0)], f"{path.name}: dated more than once"
