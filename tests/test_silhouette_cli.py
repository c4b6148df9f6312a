"""``growsim fit-image`` end to end (small budget) and its bad-input handling."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from conftest import ROOT
from PIL import Image

from growsim.cli import build_parser, main
from growsim.experiment import load_config
from growsim.fitting.setups import fit_config
from growsim.models import ifs3d
from growsim.objectives.silhouette import plant_views


@pytest.fixture(scope="module")
def pictures(tmp_path_factory):
    d = tmp_path_factory.mktemp("pics")
    views = plant_views(ifs3d.develop(ifs3d.PRESETS["table1"]), 64)
    paths = []
    for v, label in zip(views, ("front", "side")):
        img = np.where(np.kron(v, np.ones((4, 4))) > 0, 20, 240).astype(np.uint8)
        img = np.pad(img, 30, constant_values=240)
        p = d / f"{label}.png"
        Image.fromarray(img).save(p)
        paths.append(str(p))
    return paths


def test_fit_config_is_valid(pictures):
    for model in ("ifs3d", "honda"):
        cfg = load_config(fit_config(*pictures, model=model, evaluations=3000))
        assert cfg.model.kind == model
        assert cfg.objective[0].front == pictures[0]
        assert cfg.objective[0].line_width == "radius"  # photos: branches at their width


def test_fit_image_runs_the_best_setup(pictures):
    """``fit-image --model ifs3d`` and ``experiments/ifs_tree_best.toml`` resolve to the same
    GA (budget, islands, polish) and model: one setup, not two copies that drift apart."""
    fit = load_config(fit_config(*pictures, leaves=False)).to_dict()
    best = load_config(ROOT / "experiments" / "ifs_tree_best.toml").to_dict()
    assert fit["ga"] == best["ga"]
    assert fit["model"] == best["model"]
    # the fit's runs write no meshes or screenshots: fit-image writes the kept fit's
    assert fit["output"]["mesh"] == [] and fit["output"]["screenshots"] == []
    assert best["ga"]["evaluations"] == 50_000
    assert best["ga"]["polish"]["evaluations"] == 35_000
    # the GA runs until the evaluation budget, not the schema's default 20 generations
    ga = best["ga"]
    generations_needed = (50_000 - 35_000) / (ga["population"] * ga["islands"])
    assert ga["generations"] > generations_needed
    # the experiment file is the package's copy (growsim/data), not a second definition
    shipped = ROOT / "growsim" / "data" / "ifs_tree_best.toml"
    assert (ROOT / "experiments" / "ifs_tree_best.toml").resolve() == shipped.resolve()


def test_fit_config_scales_the_budget_and_keeps_the_split(pictures):
    for model, share in (("ifs3d", 0.7), ("honda", 0.2)):
        ga = load_config(fit_config(*pictures, model=model, evaluations=200_000)).ga
        assert ga.evaluations == 200_000
        assert ga.polish.evaluations == int(200_000 * share)
        # generations never cut the GA's share of the budget short
        per_generation = ga.population * ga.islands
        assert ga.generations * per_generation >= 200_000 - ga.polish.evaluations


@pytest.mark.slow
def test_fit_image_budget_split_is_what_runs(pictures, tmp_path):
    """30 % GA, 70 % CMA-ES polish, read back from the run's history (phase column): of
    1,000 evaluations the GA spends its 300 (up to a generation more: it stops at a
    generation's end), then the polish exactly its 700; at 50,000, 15,000 and 35,000.
    One size (64 px): the first stage only."""
    out = tmp_path / "fit"
    args = ["fit-image", *pictures, "--out", str(out), "--evaluations", "1000", "--size", "64"]
    assert main([*args, "--quiet", "--leaves", "fit"]) == 0  # one run (auto: bare and leafy)
    h = pd.read_parquet(out / "history.parquet")
    assert set(h["phase"]) == {"ga", "polish"}
    ga_evaluations = h.loc[h.phase == "ga", "evaluations"].max()
    polish_evaluations = h["evaluations"].max() - ga_evaluations
    assert 300 <= ga_evaluations < 300 + 4 * 100  # islands x population
    assert polish_evaluations == 700


@pytest.mark.slow
def test_a_photographed_honda_tree_scores_higher_drawn_at_its_radius(tmp_path):
    """A rendered (shaded, leafy) photo of a zelkova, front and side: the true tree drawn
    with its tubes' radius matches its own photo better than thin lines (why fit-image
    uses line_width = "radius" for Honda)."""
    from growsim.models.honda import PRESETS, develop

    score = _own_render_scores(develop(PRESETS["zelkova"]), tmp_path)
    # measured at 400 px (issue 16: targets framed by cover and skeleton, leaves drawn as
    # their blades are seen): thin 0.840, radius 0.933
    assert score["radius"] >= 0.9
    assert score["radius"] > score["thin"] + 0.02


def test_fit_image_line_width_option(pictures, capsys):
    parse = build_parser().parse_args
    args = parse(["fit-image", *pictures, "--out", "o", "--line-width", "radius"])
    assert (
        load_config(fit_config(*pictures, line_width=args.line_width)).objective[0].line_width
        == "radius"
    )
    args = parse(["fit-image", *pictures, "--out", "o", "--model", "honda", "--line-width", "thin"])
    cfg = fit_config(*pictures, model="honda", line_width=args.line_width)
    assert load_config(cfg).objective[0].line_width == "thin"
    assert parse(["fit-image", *pictures, "--out", "o"]).line_width is None  # the model's
    with pytest.raises(SystemExit):
        parse(["fit-image", *pictures, "--out", "o", "--line-width", "fat"])
    assert "--line-width" in capsys.readouterr().err


@pytest.mark.slow
def test_a_rendered_ifs3d_tree_scores_higher_drawn_at_its_radius(tmp_path):
    """growsim's own render of the Table 1 tree (tubes 0.04 x their length wide): the true
    tree matches it better drawn at its radius (docs/models/ifs3d.md, when to use which)."""
    score = _own_render_scores(ifs3d.develop(ifs3d.PRESETS["table1"]), tmp_path)
    # measured: thin 0.856, radius 0.907 (issue 16: targets framed by cover and skeleton;
    # 0.964 when every pixel a branch touched was set, which fattened photos of thin trees)
    assert score["radius"] >= 0.89
    assert score["radius"] > score["thin"] + 0.05


def test_fit_image_end_to_end(pictures, tmp_path, capsys):
    out = tmp_path / "fit"
    args = ["fit-image", *pictures, "--out", str(out), "--evaluations", "1500", "--quiet"]
    code = main([*args, "--line-width", "thin", "--sizes", "64", "--leaves", "fit"])
    assert code == 0
    for name in ("tree.glb", "silhouettes.png", "best.json", "summary.json", "history.parquet"):
        assert (out / name).is_file(), name
    text = capsys.readouterr().out
    ncc = float(text.split("mean NCC ")[1].split()[0])
    assert 0.5 < ncc <= 1.0
    im = Image.open(out / "silhouettes.png")
    assert im.size[0] > 4 * 64


def test_fit_image_bad_picture_fails_before_evolution(pictures, tmp_path, capsys):
    blank = tmp_path / "blank.png"
    Image.fromarray(np.full((40, 40), 255, np.uint8)).save(blank)
    out = tmp_path / "never"
    code = main(["fit-image", pictures[0], str(blank), "--out", str(out), "--quiet"])
    assert code == 2
    err = capsys.readouterr().err
    assert "blank.png" in err and "uniform" in err
    assert not (out / "history.parquet").exists()
    code = main(["fit-image", pictures[0], str(tmp_path / "nope.png"), "--out", str(out)])
    assert code == 2 and "nope.png" in capsys.readouterr().err
    # degenerate pictures: a single black pixel, uniform noise (fitted at NCC 0.80 and 0.86
    # before they were refused)
    dot = np.full((100, 100), 255, np.uint8)
    dot[50, 50] = 0
    Image.fromarray(dot).save(tmp_path / "dot.png")
    noise = np.random.default_rng(0).integers(0, 256, (200, 200)).astype(np.uint8)
    Image.fromarray(noise).save(tmp_path / "noise.png")
    for bad, what in (
        ("dot.png", "the silhouette is too small"),
        ("noise.png", "no sky along the top"),
    ):
        code = main(["fit-image", pictures[0], str(tmp_path / bad), "--out", str(out)])
        err = capsys.readouterr().err
        assert code == 2 and f"{bad}: " in err and what in err, err
        assert not (out / "history.parquet").exists()


def test_fit_on_the_table1_pictures_is_the_fit_on_the_rendered_target(pictures, tmp_path):
    # the pictures of line drawings frame into the rendered target itself, so a fit to the
    # pictures is the best config's fit, evaluation for evaluation
    from growsim.experiment import run

    cfg = fit_config(*pictures, evaluations=1200, line_width="thin", leaves=False)
    rendered = dict(
        cfg,
        objective=[
            {"kind": "silhouette", "target_model": "ifs3d", "target_preset": "table1", "size": 64}
        ],
    )
    quiet = ["output.mesh=[]", "output.screenshots=[]", "output.plot=false"]
    a = run(cfg, tmp_path / "pictures", overrides=quiet, progress=False)
    b = run(rendered, tmp_path / "rendered", overrides=quiet, progress=False)
    pd.testing.assert_frame_equal(
        a.history.drop(columns=["seconds"]), b.history.drop(columns=["seconds"])
    )
    assert a.best_fitness == b.best_fitness


def _own_render_scores(tree, tmp_path) -> dict[str, float]:
    """The tree scored against growsim's own 400 px renders of it, drawn thin and at
    its radius."""
    from growsim.objectives.silhouette import SilhouetteObjective
    from growsim.phenotypes.plant import views as viz

    front, side = tmp_path / "front.png", tmp_path / "side.png"
    viz.screenshot(tree, front, view="front", size=(400, 400))
    viz.screenshot(tree, side, view="side", size=(400, 400))
    return {
        lw: SilhouetteObjective(front=str(front), side=str(side), line_width=lw)(tree)
        for lw in ("thin", "radius")
    }


def test_a_drawing_with_no_flags_takes_the_fast_exact_path(pictures, tmp_path, capsys):
    """A drawing (dark lines on light grey) fitted with no flags: classified a drawing,
    read by the threshold, fitted in thin lines at 64 px, the choices printed and kept in
    fit.json, the fit written framed as the target (``fit_front.png``)."""
    import json

    out = tmp_path / "fit"
    assert main(["fit-image", pictures[0], "--out", str(out), "-q"]) == 0
    printed = capsys.readouterr().out
    summary = json.loads((out / "fit.json").read_text())
    choices = {k: v["value"] for k, v in summary["choices"].items()}
    assert choices == {"segmentation": "threshold", "model": "auto", "line_width": "thin",
                       "sizes": [64], "leaves": "keep"}  # fmt: skip
    # a drawing of one view: the 3D IFS fitted first matched it, so the 2D IFS was not
    assert summary["models"].keys() == {"ifs3d"} and summary["model"] == "ifs3d"
    assert "the next models were not fitted" in summary["choices"]["model"]["why"]
    assert "a drawing" in summary["choices"]["segmentation"]["why"]
    assert "segmentation: threshold (" in printed
    assert [s["size"] for s in summary["stages"]] == [64]
    assert summary["ncc"] >= 0.95
    assert "fit_front.png" in summary["files"]
    target = np.asarray(Image.open(out / "silhouette_front.png")) < 128
    fit = np.asarray(Image.open(out / "fit_front.png")) < 128
    assert fit.shape == target.shape
    assert np.corrcoef(fit.ravel(), target.ravel())[0, 1] >= 0.9


def test_quiet_is_accepted_short_and_long():
    for flag in ("-q", "--quiet"):
        assert build_parser().parse_args(["fit-image", "f.png", "--out", "o", flag]).quiet
