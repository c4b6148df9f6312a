"""``fit-image`` reconstructs a photograph's tree by default (``--method auto``): the
reconstruction judged and written as a search's fit (``fit.json`` with the method, why and
the assumptions, the meshes, ``growsim show DIR``), the skeleton over the photograph, the
Honda parameters inferred (``model.json``, ``growsim grow honda --params``) and the
branch statistics beside the regrown tree's; a drawing is still searched."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from growsim.cli import build_parser, main
from growsim.errors import UserInputError
from growsim.experiment.results import best_phenotype
from growsim.fitting import FitOptions, fit_image
from growsim.fitting.stages import choose
from growsim.fitting.state import FIT_STATE, RECONSTRUCTION_STAGES
from growsim.phenotypes.plant import STEM

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
sys.path.insert(0, str(Path(__file__).resolve().parent))
from golden.make import table1_drawing
from make_photos import PICTURES, make_photo


@pytest.fixture(scope="module")
def photo(tmp_path_factory):
    """A 256 px JPEG render of a bare zelkova on a ground plane."""
    path = tmp_path_factory.mktemp("photo") / "zelkova.jpg"
    path.write_bytes(make_photo(PICTURES[0], size=256)[2])
    return path


@pytest.fixture(scope="module")
def fitted(photo, tmp_path_factory):
    """The photo fitted with no flags, as the command line does it: (out, printed)."""
    out = tmp_path_factory.mktemp("fit") / "fit"
    return out, fit_image(photo, out=out, progress=False)


def test_a_photo_with_no_flags_is_reconstructed_and_written_as_a_fit(fitted):
    out, r = fitted
    summary = json.loads((out / "fit.json").read_text())
    assert r.model == summary["model"] == "reconstruction" and summary["method"] == "reconstruct"
    assert summary["choices"]["method"]["value"] == "reconstruct"
    assert "photograph" in summary["choices"]["method"]["why"]
    assert summary["assumptions"]["method"] == summary["reconstruction"]["method"]
    assert "lift" in summary["assumptions"] and summary["size"] == 256
    assert summary["ncc"] > 0.8 and 0.8 <= summary["area_ratio"]["front"] <= 1.25
    meshes = ("tree.glb", "tree.obj", "tree.vtp")
    pictures = ("fit_front.png", "silhouette_front.png", "skeleton_front.png")
    written = (*meshes, *pictures, "model.json", "stats.csv", "best.json", "config.toml")
    for name in written:
        assert (out / name).is_file(), name
        assert name in summary["files"], name
    # one tree from one base: every stem but the trunk's first segment has a parent
    plant = r.phenotype
    assert int(((plant.parent < 0) & (plant.kind == STEM)).sum()) == 1
    assert int((plant.parent < 0).sum()) == 1
    # growsim show DIR reads the tree saved there
    assert best_phenotype(out).n_segments == plant.n_segments
    state = json.loads((out / FIT_STATE).read_text())
    assert state["finished"] == list(RECONSTRUCTION_STAGES)
    stats = pd.read_csv(out / "stats.csv")
    assert set(stats.tree) == {"photo", "honda"} and "all" in set(stats.order.astype(str))


def test_a_reconstruction_is_judged_and_drawn_where_the_picture_shows_it(tmp_path):
    # a speck beside the tree's foot widens the picture's frame: the reconstruction,
    # which leaves it out, is drawn where its picture shows it (fit_front.png over
    # silhouette_front.png), so its NCC is the clean picture's (stretched to the frame by
    # its own extent, 0.80)
    from PIL import Image
    from test_reconstruction import y_tree

    ncc = {}
    for name, speck in (("clean", False), ("speck", True)):
        m = y_tree()
        if speck:
            m[150:152, 5:7] = True
        picture = tmp_path / f"{name}.png"
        Image.fromarray(np.where(m, 0, 255).astype(np.uint8)).save(picture)
        out = tmp_path / name
        fit_image(picture, out=out, method="reconstruct", progress=False)
        ncc[name] = json.loads((out / "fit.json").read_text())["ncc"]
        fit = np.asarray(Image.open(out / "fit_front.png").convert("L")) < 128
        target = np.asarray(Image.open(out / "silhouette_front.png").convert("L")) < 128
        assert (fit & target).sum() / (fit | target).sum() >= 0.8
    assert ncc["speck"] >= ncc["clean"] - 0.01 and ncc["clean"] >= 0.9


def test_model_json_regrows_a_tree_of_this_kind(fitted, tmp_path, capsys):
    out, r = fitted
    model = json.loads((out / "model.json").read_text())
    assert model["model"] == "honda" and model["params"] == r.params
    glb = tmp_path / "kind.glb"
    args = ["grow", "honda", "--params", str(out / "model.json"), "--export", str(glb), "--json"]
    assert main(args) == 0
    grown = json.loads(capsys.readouterr().out)
    assert grown["params"]["f"] == pytest.approx(model["params"]["f"])
    assert glb.is_file()
    assert main(["grow", "ifs3d", "--params", str(out / "model.json")]) == 2
    assert "parameters of honda, not of ifs3d" in capsys.readouterr().err


def test_the_command_says_which_path_and_resumes_a_reconstruction(photo, tmp_path, capsys):
    out = tmp_path / "fit"
    assert main(["fit-image", str(photo), "--out", str(out), "-q"]) == 0
    printed = capsys.readouterr().out
    assert "method: reconstruct (a photograph" in printed and "--params" in printed
    first = json.loads((out / "fit.json").read_text())
    # interrupted after its reconstruction: --resume reconstructs it again, the same tree
    (out / "fit.json").unlink()
    state = json.loads((out / FIT_STATE).read_text())
    state["finished"] = ["choose", "segment", "reconstruct"]
    (out / FIT_STATE).write_text(json.dumps(state))
    assert main(["fit-image", "--resume", str(out), "-q"]) == 0
    again = json.loads((out / "fit.json").read_text())
    assert again["ncc_views"] == first["ncc_views"] and again["params"] == first["params"]


def test_a_drawing_is_searched_and_the_search_can_be_asked_for(photo, tmp_path):
    drawing = table1_drawing(tmp_path / "pictures")[0]
    assert choose(FitOptions(front=str(drawing))).method["value"] == "search"
    assert choose(FitOptions(front=str(photo))).method["value"] == "reconstruct"
    asked = choose(FitOptions(front=str(photo), method="search"))
    assert asked.method == {"value": "search", "why": "given"}
    # an option of the search alone: searched, and said why
    by_model = choose(FitOptions(front=str(photo), model="honda")).method
    assert by_model["value"] == "search" and "--model" in by_model["why"]
    with pytest.raises(UserInputError, match="--evaluations: an option of the search"):
        choose(FitOptions(front=str(photo), method="reconstruct", evaluations=200))
    args = build_parser().parse_args(["fit-image", "t.jpg", "--out", "o", "--method", "search"])
    assert args.method == "search"
    assert np.isin(FitOptions.cli()["method"]["choices"], ["auto", "reconstruct", "search"]).all()
