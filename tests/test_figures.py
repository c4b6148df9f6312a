"""One place for every measured figure: ``docs/figures.md``, generated from
``benchmarks/results/`` by ``benchmarks/figures.py``. A page that quotes a tabulated
figure writes it as the table does and cites its row, ``8.6 s ([figures](figures.md#id))``;
these tests fail when the table is stale against the result files, when a citation names
no row, or when the figure before a citation is not the row's."""

from __future__ import annotations

import re

import pytest
from conftest import ROOT, benchmark_module

FIGURES = benchmark_module("figures")
TABLE = ROOT / "docs" / "figures.md"
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
CITE = re.compile(r"\[figures\]\((?:\.\./)*(?:docs/)?figures\.md#([A-Za-z0-9_-]+)\)")


def citations(text: str):
    """``(row id, the text the citation follows)`` for every citation of a row: the text
    since the previous citation, table cell or paragraph (300 characters at most), with
    its line breaks read as spaces."""
    out, last = [], 0
    for m in CITE.finditer(text):
        start = max(last, m.start() - 300)
        before = text[start : m.start()]
        for stop in ("|", "\n\n"):
            if stop in before:
                before = before[before.rindex(stop) + len(stop) :]
        out.append((m.group(1), " ".join(before.split())))
        last = m.end()
    return out


def _rel(path) -> str:
    return path.relative_to(ROOT).as_posix()


def test_the_table_is_up_to_date():
    assert TABLE.read_text() == FIGURES.table(), "stale: python benchmarks/figures.py"


def test_every_row_reads_an_existing_result_file():
    for row in FIGURES.ROWS:
        assert (FIGURES.RESULTS / row.source.partition("#")[0]).is_file(), row.id
        assert re.fullmatch(r"[a-z0-9]+(?:-[a-z0-9]+)*", row.id), row.id


CITING = [p for p in PAGES if p != TABLE and CITE.search(p.read_text())]


@pytest.mark.parametrize("page", CITING, ids=_rel)
def test_a_page_shows_the_figure_of_every_row_it_cites(page):
    values = FIGURES.values()
    wrong = []
    for row, before in citations(page.read_text()):
        if row not in values:
            wrong.append(f"#{row}: no such row in docs/figures.md")
        elif values[row] not in before:
            wrong.append(f"#{row}: the table gives {values[row]!r}; the page: {before[-80:]!r}")
    assert not wrong, f"{_rel(page)}: " + "; ".join(wrong)


def test_the_pages_cite_the_table():
    """The entry pages quote their times from the table."""
    cited = {p: {row for row, _ in citations(p.read_text())} for p in CITING}
    by_name = {_rel(p): rows for p, rows in cited.items()}
    assert {"quickstart-run", "hormone-generation", "ga-onemax-vs-peers"} <= by_name["README.md"]
    assert {"quickstart-run", "fit-photo", "fit-drawing"} <= by_name["docs/models/index.md"]
    assert "quickstart-run" in by_name["docs/quickstart.md"]


def test_a_stale_figure_fails():
    values = FIGURES.values()
    row = FIGURES.ROWS[0].id
    cite = f"([figures](figures.md#{row}))"
    page = f"takes 0.0001 s {cite} and {values[row]} {cite}"
    found = citations(page)
    assert values[row] not in found[0][1] and values[row] in found[1][1]
