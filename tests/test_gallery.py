"""Every picture of ``docs/images/`` is shown on a page and made by
``benchmarks/gallery.py`` (the one command that re-makes them: ``--list`` says how)."""

from __future__ import annotations

import re

from conftest import ROOT, benchmark_module

IMAGES = ROOT / "docs" / "images"
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]


def test_every_picture_is_shown_on_a_page():
    shown = set()
    for page in PAGES:
        shown |= set(re.findall(r"images/([\w.-]+\.(?:png|gif))", page.read_text()))
    unseen = sorted(p.name for p in IMAGES.iterdir() if p.name not in shown)
    assert not unseen, f"in docs/images/ but on no page: {unseen}"


def test_the_gallery_script_makes_every_picture():
    listed = set(benchmark_module("gallery").pictures())
    files = {p.name for p in IMAGES.iterdir()}
    assert files - listed == set(), f"not made by benchmarks/gallery.py: {sorted(files - listed)}"
    assert listed - files == set(), f"listed but missing: {sorted(listed - files)}"


def test_the_gallery_page_shows_every_picture():
    page = (ROOT / "docs" / "gallery.md").read_text()
    missing = [p.name for p in IMAGES.iterdir() if f"images/{p.name})" not in page]
    assert not missing, f"docs/gallery.md does not show {missing}"
