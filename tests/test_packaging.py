"""The project files agree with pyproject.toml and with one another: the version is written
once, the changelog's latest release is that version, package data exists, and the citation
names the paper the docs cite."""

import re
from pathlib import Path

import pytest
import yaml

import attentive_gym

REPO = Path(__file__).resolve().parents[1]
tomllib = pytest.importorskip("tomllib")  # Python 3.11+


@pytest.fixture(scope="module")
def project():
    return tomllib.loads((REPO / "pyproject.toml").read_text())


def test_the_package_version_is_the_one_in_pyproject(project):
    assert attentive_gym.__version__ == project["project"]["version"]


def test_the_changelog_lists_unreleased_changes_above_the_current_version(project):
    headings = re.findall(r"^## \[([^\]]+)\]", (REPO / "CHANGELOG.md").read_text(), flags=re.MULTILINE)
    assert headings[:2] == ["Unreleased", project["project"]["version"]], headings


def test_the_license_file_is_the_mit_licence_pyproject_declares(project):
    assert project["project"]["license"] == "MIT"
    assert project["project"]["license-files"] == ["LICENSE"]
    assert (REPO / "LICENSE").read_text().startswith("MIT License\n\nCopyright (c) the attentive_gym authors\n")


def test_every_package_data_pattern_matches_a_file(project):
    for package, patterns in project["tool"]["setuptools"]["package-data"].items():
        folder = REPO.joinpath(*package.split("."))
        for pattern in patterns:
            assert list(folder.glob(pattern)), f"package data {package}: {pattern} matches nothing in {folder}"


def test_the_citation_lists_the_paper_the_model_docs_cite():
    citation = yaml.safe_load((REPO / "CITATION.cff").read_text())
    assert citation["cff-version"] == "1.2.0" and citation["type"] == "software"
    (paper,) = citation["references"]
    lines = (REPO / "docs" / "model.md").read_text().splitlines()
    model_doc = " ".join(" ".join(line.lstrip("> ") for line in lines).split())  # quoted lines joined
    assert f'"{paper["title"]}"' in model_doc
    assert "arXiv:1307.5720" in model_doc and paper["url"] == "https://arxiv.org/abs/1307.5720"
    authors = [f"{a['given-names']} {a['family-names']}" for a in paper["authors"]]
    assert authors == ["Esther L. Colombini", "Alexandre S. Simões", "Carlos H. C. Ribeiro"]
    assert all(name in model_doc for name in authors)
