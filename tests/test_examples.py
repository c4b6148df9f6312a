"""The ``examples/`` gallery runs (issue 28): each script at a small budget, in its own
working directory, as ``python examples/NAME.py ARGS`` runs it; each says what it shows."""

from __future__ import annotations

import ast
import runpy
import sys

import pytest
from conftest import ROOT
from PIL import Image

EXAMPLES = ROOT / "examples"
SMALL = ["--generations", "2", "--population", "8"]


def _run(name: str, args: list[str], monkeypatch, tmp_path):
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    monkeypatch.setattr(sys, "argv", [str(EXAMPLES / name), *args])
    namespace = runpy.run_path(str(EXAMPLES / name))  # defines main; __name__ is not main
    return namespace["main"](args)


def test_every_example_says_what_it_shows_and_is_tested():
    scripts = sorted(p.name for p in EXAMPLES.glob("*.py"))
    assert len(scripts) >= 4, scripts
    for name in scripts:
        doc = ast.get_docstring(ast.parse((EXAMPLES / name).read_text()))
        assert doc and "What it shows" in doc, f"examples/{name}: no docstring saying what it shows"
        assert f'"{name}"' in (ROOT / "tests" / "test_examples.py").read_text(), name


def test_grow_each_model(monkeypatch, tmp_path):
    written = _run("grow_each_model.py", ["--out", "pics", "--size", "96"], monkeypatch, tmp_path)
    names = {p.stem for p in written}
    assert {"honda_zelkova", "ifs3d_table1", "hormone_demo_3d", "ifs2d_fern", "fish_calm"} <= names
    for p in written:
        assert Image.open(p).size == (96, 96)


def test_grown_hormone_demo_branches():
    """The hormone demo genome, grown in its experiment's environment, is a branched plant."""
    namespace = runpy.run_path(str(EXAMPLES / "grow_each_model.py"))
    plant = namespace["grow"]("hormone", "demo_3d", "hormone_3d.toml")
    m = plant.measures()
    assert m["n_segments"] >= 100 and m["n_branch_points"] > 0


def test_run_experiment(monkeypatch, tmp_path):
    result = _run("run_experiment.py", ["--out", "run", *SMALL], monkeypatch, tmp_path)
    assert len(result.history) == 2 and (tmp_path / "run" / "summary.json").is_file()


@pytest.mark.slow
def test_compare_environments(monkeypatch, tmp_path):
    args = ["--out", "lights", "--repeats", "2", "--no-renders", *SMALL]
    result = _run("compare_environments.py", args, monkeypatch, tmp_path)
    assert len(result.table) == 2 and (tmp_path / "lights" / "compare" / "report.html").is_file()


def test_notebook_viewer_off_screen(monkeypatch, tmp_path):
    path = _run("notebook_viewer.py", ["--out", "tree.png"], monkeypatch, tmp_path)
    assert Image.open(path).size == (600, 600)
