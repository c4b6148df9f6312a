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


def test_every_real_photograph_kept_names_its_source_and_licence():
    """A photograph is kept in ``benchmarks/data/real_photos/`` only with its row in
    ``SOURCES.md`` (where it comes from, under which licence)."""
    folder = ROOT / "benchmarks" / "data" / "real_photos"
    rows = [
        line for line in (folder / "SOURCES.md").read_text().splitlines() if line.startswith("| `")
    ]
    named = {re.match(r"\| `([^`]+)`", line).group(1): line for line in rows}
    photos = sorted(p.name for p in folder.iterdir() if p.suffix.lower() in {".jpg", ".png"})
    assert photos and all(p in named for p in photos), sorted(set(photos) - set(named))
    licence = re.compile(r"CC BY(-SA)? [0-9.]+|CC0|Public domain|MIT")
    assert all(licence.search(named[p]) for p in photos)
