"""The user pages (README.md, docs/) say what is and how to use it; how it got there (the
issues, their bars, the code before, the figures a newer one replaced) belongs in
``benchmarks/log/``, which this test does not read."""

from __future__ import annotations

import re

import pytest
from conftest import ROOT

PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]

#: what a user page must not say: a pattern and why
HISTORY = {
    r"\bissues?\s*#?\d+": "an issue number",
    r"\bissue-\d+": "an issue number",
    r"\bearlier code\b": "the code before",
    r"\bsuperseded\b": "a replaced figure",
    r"\bprevious kernel\b": "the code before",
    r"\bbefore (?:the|this) (?:step|refactor|change)\b": "the code before",
}

#: "bar" is history in a user page (an issue's target: "bar 1.5x", "the bar cannot be
#: met") except in these senses
BAR_OK = re.compile(
    r"\b(?:progress|scalar|colou?r|yellow|light's|a)\s+bars?\b(?!\s+(?:was|is|of\s+\d|\d))",
    re.IGNORECASE,
)


def _rel(path) -> str:
    return path.relative_to(ROOT).as_posix()


@pytest.mark.parametrize("page", PAGES, ids=_rel)
def test_user_pages_keep_no_history(page):
    text = page.read_text()
    found = [
        f"{why}: {m.group(0)!r}"
        for pattern, why in HISTORY.items()
        for m in re.finditer(pattern, text, flags=re.IGNORECASE)
    ]
    for m in re.finditer(r"\bbars?\b", text, flags=re.IGNORECASE):
        around = text[max(0, m.start() - 12) : m.end() + 12]
        if not any(
            ok.start() <= m.start() - max(0, m.start() - 12) < ok.end()
            for ok in BAR_OK.finditer(around)
        ):
            found.append(f"a bar (an issue's target?): {around!r}")
    assert not found, f"{_rel(page)}: history belongs in benchmarks/log/: {found}"


def test_the_bar_rule_tells_the_senses_apart():
    def flagged(text: str) -> bool:
        m = re.search(r"\bbars?\b", text)
        around = text[max(0, m.start() - 12) : m.end() + 12]
        off = max(0, m.start() - 12)
        return not any(ok.start() <= m.start() - off < ok.end() for ok in BAR_OK.finditer(around))

    assert not flagged("a progress bar on stderr")
    assert not flagged("with a labelled scalar bar")
    assert not flagged("lit from above (yellow bar)")
    assert flagged("1 ring 1.23x (bar 1.5x)")
    assert flagged("so the bar cannot be met")
    assert flagged("chaos-game speed (bar 50 M points/s)")
