"""What a release carries (issue 45, item 2): the licence the package declares, a citation
file of this version with the five source papers, a changelog section for this version,
and a references page giving each source paper with its year."""

from __future__ import annotations

import re
import tomllib

import pytest
from conftest import ROOT

import growsim

#: the five source papers: a name the references page gives each by, and its year (the
#: hormone paper's copy states none: the page must say so rather than give one)
SOURCE_PAPERS = {
    "Kuwahara, Shiwa & Kishino": "1996",
    "Okusa": "2003",
    "Liu & Zhang": "2011",
    "Endo": "1991",
    "Uehara, Akamine & Endo": "year not stated in the copy we have",
}


def test_license_is_the_mit_license_the_package_declares():
    text = (ROOT / "LICENSE").read_text()
    assert text.startswith("MIT License")
    assert "Copyright (c) 2026 the growsim developers" in text
    assert 'THE SOFTWARE IS PROVIDED "AS IS"' in text
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert project["license"] == {"text": "MIT"}


def _citation() -> dict:
    text = (ROOT / "CITATION.cff").read_text()
    try:
        import yaml
    except ImportError:  # a simple key check without PyYAML
        keys = dict(re.findall(r"^([a-z-]+):\s*(.*)$", text, flags=re.M))
        return {k: v.strip().strip('"') for k, v in keys.items()} | {
            "references": [None] * text.count("\n  - type:"),
            "authors": [{"name": "the growsim developers"}]
            if 'name: "the growsim developers"' in text
            else [],
        }
    return yaml.safe_load(text)


def test_citation_file_is_this_version():
    cff = _citation()
    assert str(cff["cff-version"]) == "1.2.0"
    assert cff["version"] == growsim.__version__
    assert str(cff["date-released"]) == "2026-12-05"
    assert cff["license"] == "MIT"
    assert cff["title"].startswith("growsim")
    assert cff["authors"] == [{"name": "the growsim developers"}]
    assert "repository-code" not in cff
    assert len(cff["references"]) == 5


def test_citation_references_the_five_papers():
    yaml = pytest.importorskip("yaml")
    refs = yaml.safe_load((ROOT / "CITATION.cff").read_text())["references"]
    families = [[a["family-names"] for a in r["authors"]] for r in refs]
    assert families == [
        ["Kuwahara", "Shiwa", "Kishino"], ["Okusa"], ["Liu", "Zhang"], ["Endo"],
        ["Uehara", "Akamine", "Endo"],
    ]  # fmt: skip
    assert [r.get("year") for r in refs] == [1996, 2003, 2011, 1991, None]
    assert "not stated" in refs[4]["notes"]
    for r in refs:  # CFF 1.2.0: every reference has a type, a title and authors
        assert {"type", "title", "authors"} <= set(r)


def test_changelog_has_a_section_for_this_version():
    text = (ROOT / "CHANGELOG.md").read_text()
    version = re.escape(growsim.__version__)
    m = re.search(rf"^## \[{version}\] - (\d{{4}}-\d{{2}}-\d{{2}})$", text, flags=re.M)
    assert m, f"no '## [{growsim.__version__}] - DATE' section"
    section = text[m.end() : text.index("\n## [", m.end())]
    for heading in ("### Added", "### Changed", "### Fixed"):
        assert heading in section
    assert f"v{growsim.__version__}" in section  # the tag that marks it
    assert "## [0.1.0]" in text


def test_references_page_gives_each_source_paper_with_its_year():
    text = (ROOT / "docs" / "references.md").read_text()
    papers = text[: text.index("\n## ", text.index("## The five source papers") + 1)]
    entries = re.findall(r"^- \*\*(.+?)\*\*", papers, flags=re.M)
    assert len(entries) == 5, entries
    for (name, year), entry in zip(SOURCE_PAPERS.items(), entries):
        assert entry == f"{name} ({year}).", entry
    for cited in ("Honda, P. B. Tomlinson", "Ochoa", "Barnsley", "Horn", "Shinozaki"):
        assert cited in text


def test_docs_cite_no_notes_the_repository_does_not_hold():
    pages = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
    for page in pages:
        text = page.read_text()
        assert "Hormone-module growth: facts" not in text, page
        assert not re.search(r"\b(?:design|research|team's) notes\b", text), page
