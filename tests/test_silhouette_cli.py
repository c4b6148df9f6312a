"""``growsim fit-image`` end to end (small budget) and its bad-input handling."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from growsim.cli import main
from growsim.cli.fit_image import fit_config
from growsim.experiment import load_config
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
        expected = "radius" if model == "honda" else "thin"
        assert cfg.objective[0].line_width == expected


@pytest.mark.slow
def test_a_photographed_honda_tree_scores_higher_drawn_at_its_radius(tmp_path):
    """A rendered (shaded, leafy) photo of a zelkova, front and side: the true tree drawn
    with its tubes' radius matches its own photo better than thin lines (why fit-image
    uses line_width = "radius" for Honda)."""
    from growsim import viz
    from growsim.models.honda import PRESETS, develop
    from growsim.objectives.silhouette import SilhouetteObjective

    tree = develop(PRESETS["zelkova"])
    front, side = tmp_path / "front.png", tmp_path / "side.png"
    viz.screenshot(tree, front, view="front", size=(400, 400))
    viz.screenshot(tree, side, view="side", size=(400, 400))
    score = {
        lw: SilhouetteObjective(front=str(front), side=str(side), line_width=lw)(tree)
        for lw in ("thin", "radius")
    }
    # measured at 600 px: thin 0.882, radius 0.936
    assert score["radius"] >= 0.9
    assert score["radius"] > score["thin"] + 0.02


def test_fit_image_end_to_end(pictures, tmp_path, capsys):
    out = tmp_path / "fit"
    code = main(["fit-image", *pictures, "--out", str(out), "--evaluations", "1500", "--quiet"])
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
