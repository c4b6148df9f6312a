"""A plant's architecture written for other plant software and read back
(``growsim.phenotypes.plant.exchange``): an MTG file (OpenAlea, L-Py) and a QSM cylinder
table (TreeQSM's fields, rTwig), for every plant model, to the last bit; the ``grow
--export`` of both; the example of ``docs/plant.md``, "Exchange", run as written."""

from __future__ import annotations

import json
import re

import numpy as np
import pandas as pd
import pytest
from conftest import ROOT

from growsim.cli import main
from growsim.env import Environment
from growsim.errors import UserInputError
from growsim.files import json_default
from growsim.models import MODELS, get_model
from growsim.phenotypes.plant import (
    LEAF,
    STEM,
    Plant,
    qsm_table_to_plant,
    read_mtg,
    to_mtg,
    to_qsm_table,
)

#: every plant model with a preset each (two for hormone: 2D and 3D), grown in the
#: environment its preset carries; ifs2d draws an attractor (points2d), not a plant
GROWN = [("honda", "zelkova"), ("hormone", "demo_2d"), ("hormone", "demo_3d"),
         ("ifs3d", "table1"), ("ifs3d", "paper_ga")]  # fmt: skip


def grown(name: str, preset: str) -> Plant:
    model = get_model(name)
    table = model.preset_environment(preset)
    env = Environment.model_validate(table) if table else None
    return model.develop(model.preset(preset), env=env)


def same_skeleton(a: Plant, b: Plant, tol: float = 1e-9) -> None:
    assert a.n_segments == b.n_segments
    np.testing.assert_array_equal(a.parent, b.parent)
    np.testing.assert_array_equal(a.kind, b.kind)
    np.testing.assert_array_equal(a.order, b.order)
    for name in ("start", "end", "radius"):
        np.testing.assert_allclose(getattr(a, name), getattr(b, name), rtol=0, atol=tol)
    np.testing.assert_allclose(a.radius_end(), b.radius_end(), rtol=0, atol=tol)


def test_every_plant_model_is_covered():
    plants = {n for n in MODELS if get_model(n).phenotype == "plant"}
    assert plants == {n for n, _ in GROWN}
    assert get_model("ifs2d").phenotype == "points2d"  # an attractor: no skeleton to write


@pytest.mark.parametrize(("name", "preset"), GROWN)
def test_mtg_and_qsm_table_round_trip(name, preset, tmp_path):
    plant = grown(name, preset)
    assert plant.n_segments > 1 or name != "hormone"
    back = read_mtg(to_mtg(plant, tmp_path / "p.mtg"))
    same_skeleton(plant, back, tol=0.0)  # every number written to the last bit
    assert back.meta == json.loads(json.dumps(plant.meta, default=json_default))
    table = to_qsm_table(plant, tmp_path / "p.csv")
    same_skeleton(plant, qsm_table_to_plant(tmp_path / "p.csv"), tol=0.0)
    same_skeleton(plant, qsm_table_to_plant(table))
    # without end.*, the far end is start + axis * length
    same_skeleton(plant, qsm_table_to_plant(table.drop(columns=["end.x", "end.y", "end.z"])))


def test_leaves_are_kept_as_a_kind_and_can_be_left_out(tmp_path):
    tree = grown("honda", "zelkova")
    assert tree.n_leaves == 282
    text = to_mtg(tree, tmp_path / "t.mtg").read_text()
    assert len(re.findall(r"^\t*\+L\d+\t", text, flags=re.M)) == 282
    assert text.count("\tleaf\n") == 282 and text.count("\tstem\n") == 125
    table = to_qsm_table(tree)
    assert (table["kind"] == LEAF).sum() == 282
    wood = to_qsm_table(tree, leaves=False)
    assert len(wood) == 125 and (wood["kind"] == STEM).all()
    stems = qsm_table_to_plant(wood)
    same_skeleton(tree.subset(tree.kind == STEM), stems)


def test_written_z_up_in_treeqsm_fields():
    tree = grown("honda", "zelkova")
    t = to_qsm_table(tree)
    assert list(t.columns[:19]) == [
        "radius", "length", "start.x", "start.y", "start.z", "axis.x", "axis.y", "axis.z",
        "end.x", "end.y", "end.z", "parent", "extension", "branch", "BranchOrder",
        "PositionInBranch", "added", "UnmodRadius", "kind",
    ]  # fmt: skip
    # growsim's y (up) is the table's z; its z is the table's -y
    np.testing.assert_array_equal(t["start.z"], tree.start[:, 1])
    np.testing.assert_array_equal(t["start.y"], -tree.start[:, 2])
    np.testing.assert_allclose(np.linalg.norm(t[["axis.x", "axis.y", "axis.z"]], axis=1), 1.0)
    np.testing.assert_allclose(t["length"], tree.lengths())
    assert t["parent"].iloc[0] == 0 and (t["parent"].iloc[1:] >= 1).all()
    # the trunk is branch 1; a branch's cylinders follow each other by extension
    assert t["branch"].iloc[0] == 1 and t["PositionInBranch"].iloc[0] == 1
    ext = t["extension"].to_numpy()
    for row in np.flatnonzero(ext):
        child = ext[row] - 1
        assert t["parent"].iloc[child] == row + 1
        assert t["branch"].iloc[child] == t["branch"].iloc[row]
        assert t["PositionInBranch"].iloc[child] == t["PositionInBranch"].iloc[row] + 1


def test_mtg_header_and_topology(tmp_path):
    tree = grown("honda", "zelkova")
    lines = to_mtg(tree, tmp_path / "t.mtg").read_text().splitlines()
    for section in ("CODE:\tFORM-A", "CLASSES:", "DESCRIPTION:", "FEATURES:", "MTG:"):
        assert section in lines
    head = next(i for i, ln in enumerate(lines) if ln.startswith("ENTITY-CODE"))
    names = [c for c in lines[head].split("\t")[1:] if c]
    assert names[:3] == ["XX", "YY", "ZZ"] and "TopDia" in names and "Order" in names
    assert lines[head + 1].split("\t")[0] == "/P1/S1"
    codes = [ln.strip().split("\t")[0] for ln in lines[head + 1 :]]
    continued = int((to_qsm_table(tree)["extension"] > 0).sum())
    assert sum(c.startswith("^<S") for c in codes) == continued
    assert all(re.fullmatch(r"/P1/S1|\^<[SL]\d+|\+[SL]\d+", c) for c in codes)
    # an MTG reader takes '+' for a branch: no number is written with one
    assert not any("e+" in ln for ln in lines[head + 1 :])


def test_a_stand_is_one_plant_a_root(tmp_path):
    tree = grown("honda", "h_columnar")
    stand = Plant.concat([tree, tree, tree], offsets=[[0, 0, 0], [30, 0, 0], [0, 0, 30]])
    text = to_mtg(stand, tmp_path / "s.mtg").read_text()
    assert [ln.split("\t")[0] for ln in text.splitlines() if ln.startswith("/P")] == [
        "/P1/S1", f"/P2/S{tree.n_segments + 1}", f"/P3/S{2 * tree.n_segments + 1}",
    ]  # fmt: skip
    same_skeleton(stand, read_mtg(tmp_path / "s.mtg"), tol=0.0)
    same_skeleton(stand, qsm_table_to_plant(to_qsm_table(stand)))


def test_reading_other_spellings_and_bad_files(tmp_path):
    tree = grown("hormone", "demo_2d")
    t = to_qsm_table(tree).rename(columns={"start.x": "start_x", "BranchOrder": "branch_order"})
    same_skeleton(tree, qsm_table_to_plant(t))
    with pytest.raises(UserInputError, match=r"no column 'start\.x'"):
        qsm_table_to_plant(pd.DataFrame({"parent": [0]}))
    f = to_mtg(tree, tmp_path / "t.mtg")
    f.write_text(f.read_text().replace("\tXX\t", "\tQQ\t"))
    with pytest.raises(UserInputError, match=r"line \d+: the segment has no XX, YY, ZZ"):
        read_mtg(f)
    (tmp_path / "x.mtg").write_text("not an MTG\n")
    with pytest.raises(UserInputError, match="not an MTG file"):
        read_mtg(tmp_path / "x.mtg")


def test_grow_exports_the_architecture(tmp_path, capsys):
    mtg, csv = tmp_path / "tree.mtg", tmp_path / "tree.csv"
    assert main(["grow", "honda", "--preset", "zelkova", "--export", str(mtg)]) == 0
    assert main(["grow", "honda", "--preset", "zelkova", "--export", str(csv)]) == 0
    tree = grown("honda", "zelkova")
    same_skeleton(tree, read_mtg(mtg), tol=0.0)
    same_skeleton(tree, qsm_table_to_plant(csv), tol=0.0)
    capsys.readouterr()
    assert main(["grow", "honda", "--export", str(tmp_path / "tree.txt")]) == 2
    assert ".mtg or .csv" in capsys.readouterr().err


def test_the_docs_example_runs_as_written(tmp_path, monkeypatch):
    text = (ROOT / "docs" / "plant.md").read_text()
    section = text[text.index("## Exchange") :]
    code = re.search(r"```python\n(.*?)```", section, flags=re.S).group(1)
    assert "to_mtg" in code and "qsm_table_to_plant" in code
    monkeypatch.chdir(tmp_path)
    exec(compile(code, "docs/plant.md", "exec"), {})
    assert (tmp_path / "zelkova.mtg").is_file() and (tmp_path / "zelkova.csv").is_file()
