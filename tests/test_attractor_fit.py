"""Fitting pictures of classic IFS attractors drawn by another program (issue 27, bar 3):
``benchmarks/make_attractors.py`` draws them (its own chaos game, no growsim), ``fit-image
--model ifs2d`` reads them as drawings and fits a code."""

from __future__ import annotations

import ast
import json
import sys

import numpy as np
from conftest import ROOT

from growsim.cli import main
from growsim.pictures.images import classify_picture

sys.path.insert(0, str(ROOT / "benchmarks"))
import make_attractors


def test_the_drawing_program_is_independent_of_growsim():
    tree = ast.parse((ROOT / "benchmarks/make_attractors.py").read_text())
    imported = {a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
    imported |= {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)}
    assert not any(m and m.startswith("growsim") for m in imported)
    splits = [s for s, _, _ in make_attractors.TABLES.values()]
    assert splits.count("discovery") == 3 and splits.count("held-out") >= 3
    # the chaos game draws the attractor: Sierpinski's points lie in its triangle, corners
    # (0, 0), (2, 0), (1, 1.732) (the maps' fixed points)
    pts = make_attractors.chaos_game(make_attractors.TABLES["sierpinski"][2], 2000)
    x, y = pts.T
    assert (y >= -1e-9).all() and (y <= 1.732 + 1e-9).all()
    assert (x >= y / 1.732 - 1e-6).all() and (x <= 2.0 - y / 1.732 + 1e-6).all()
    assert y.max() > 1.6 and x.min() < 0.1 and x.max() > 1.9


def test_an_attractor_picture_is_a_drawing_and_is_fitted(tmp_path):
    rows = make_attractors.make(tmp_path / "pictures", ["maple"])
    index = json.loads((tmp_path / "pictures/index.json").read_text())
    assert index == rows and index[0]["split"] == "discovery"
    picture = tmp_path / "pictures/maple.png"
    assert classify_picture(picture)[0] == "drawing"
    out = tmp_path / "fit"
    assert main(["fit-image", str(picture), "--model", "ifs2d", "--out", str(out), "-q",
                 "--evaluations", "800"]) == 0  # fmt: skip
    fit = json.loads((out / "fit.json").read_text())
    assert fit["choices"]["segmentation"]["value"] == "threshold"
    assert fit["choices"]["line_width"]["value"] == "thin"
    # a small budget already draws a leaf-shaped cloud (the full default: 0.92)
    assert fit["ncc"] > 0.75, fit["ncc"]
    assert np.isclose(fit["ncc"], fit["stages"][-1]["ncc"])


def test_fit_image_fits_six_switchable_maps_with_half_the_budget_on_a_drawing(tmp_path):
    from growsim.experiment import load_plan
    from growsim.fitting.setups import FIT_SETUPS, fit_config
    from growsim.models import ifs2d

    setup = FIT_SETUPS.get("ifs2d")
    assert setup.drawing["sizes"] == (64,)
    assert setup.drawing["evaluations"] == ifs2d.fit_tables()["ga"]["evaluations"] // 2
    tables = setup.tables()
    assert tables["model"]["params"]["n_maps"] == ifs2d.FIT_N_MAPS == 6
    assert tables["model"]["evolve"]["p_?"] == [0.0, 1.0]
    assert tables["ga"] == ifs2d.fit_tables()["ga"]
    make_attractors.make(tmp_path, ["sierpinski"])
    cfg = fit_config(tmp_path / "sierpinski.png", model="ifs2d", segmentation="threshold",
                     line_width="thin")  # fmt: skip
    assert len(load_plan(cfg).evolved) == 7 * 6


def test_a_map_switched_off_leaves_the_attractor_of_the_others():
    from growsim.models import ifs2d

    six = np.vstack([ifs2d.TABLE1, [[0.5, 0.0, 0.0, 0.5, 3.0, 3.0, 0.0]] * 2])
    a4 = ifs2d.develop(ifs2d.params_from_code(ifs2d.TABLE1, iterations=5000), seed=2)
    a6 = ifs2d.develop(ifs2d.params_from_code(six, iterations=5000), seed=2)
    assert np.array_equal(a4.points, a6.points)
