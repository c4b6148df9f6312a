"""Figures that docs print from a run are checked against a fresh run, so they cannot drift
(regenerate them with ``python benchmarks/doc_figures.py``)."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from growsim.experiment import run

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.slow
def test_quickstart_page_shows_the_quickstart_run(tmp_path):
    page = (ROOT / "docs" / "quickstart.md").read_text()
    m = re.search(
        r"quickstart: best fitness ([\d.]+) \(generation (\d+)\), (\d+) evaluations", page
    )
    assert m, "docs/quickstart.md: the first run's output line is missing"
    r = run(
        ROOT / "experiments" / "quickstart.toml",
        tmp_path / "q",
        overrides=["output.mesh=[]", "output.screenshots=[]", "output.plot=false"],
        progress=False,
    )
    best = json.loads((r.out / "best.json").read_text())
    assert (float(m.group(1)), int(m.group(2)), int(m.group(3))) == (
        round(r.best_fitness, 2),
        best["generation"],
        r.summary["evaluations"],
    ), "regenerate: python benchmarks/doc_figures.py"
    theta = re.search(r"`theta0` near (\d+) degrees", page)
    assert theta and abs(float(theta.group(1)) - best["evolved"]["theta0"]) < 1.0
