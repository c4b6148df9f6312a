"""Figures that docs print from a run are checked against a fresh run, so they cannot drift
(regenerate them with ``python benchmarks/doc_figures.py``)."""

from __future__ import annotations

import json
import re

import pytest
from conftest import ROOT

from growsim.experiment import run


@pytest.mark.slow
def test_quickstart_page_shows_the_quickstart_run(tmp_path):
    page = (ROOT / "docs" / "quickstart.md").read_text()
    m = re.search(
        r"quickstart: best fitness ([-\d.e+]+) \(generation (\d+)\), (\d+) evaluations", page
    )
    assert m, "docs/quickstart.md: the first run's output line is missing"
    r = run(
        ROOT / "experiments" / "quickstart.toml",
        tmp_path / "q",
        overrides=["output.mesh=[]", "output.screenshots=[]", "output.plot=false"],
        progress=False,
    )
    best = json.loads((r.out / "best.json").read_text())
    # the line as `growsim run` prints it (best fitness to 6 significant digits)
    assert (m.group(1), int(m.group(2)), int(m.group(3))) == (
        f"{r.best_fitness:.6g}",
        best["generation"],
        r.summary["evaluations"],
    ), "regenerate: python benchmarks/doc_figures.py"
    theta = re.search(r"`theta0` near (\d+) degrees", page)
    assert theta and abs(float(theta.group(1)) - best["evolved"]["theta0"]) < 1.0
    # the terms example of "Where the best fitness comes from" is this run's
    section = page[page.index("### Where the best fitness comes from") :]
    quoted = dict(re.findall(r'"(score|light|leaf_area|wood_volume)": ([-\d.e+]+)', section))
    assert set(quoted) == {"score", "light", "leaf_area", "wood_volume"}, quoted
    for name, text in quoted.items():
        assert float(text) == best["terms"]["light"][name], f"regenerate: terms.light.{name}"
    top = re.search(r"`measures.leaf_area_top` \(([\d.]+) in that run\)", section)
    assert top and float(top.group(1)) == round(r.summary["measures"]["leaf_area_top"], 2)
    # and the page says what the objective measures
    first = page[page.index("## The first run") : page.index("## Look at the results")]
    assert "shadow map" in first and "blade area" in first
