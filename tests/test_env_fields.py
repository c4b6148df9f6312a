"""The environment on a plant: ``Environment.segment_table`` (light, loads, water per
segment), the fields carried onto meshes, coloured renders (a tree lit from the side is
brighter on that side, in the table and in the picture), and ``--color`` on the command
line (``grow`` and ``show``), bad options refused with nothing written."""

from __future__ import annotations

import json
import os

import numpy as np
import pandas as pd
import pytest
from conftest import ROOT
from PIL import Image

from growsim.cli import main
from growsim.env import Environment
from growsim.env.environment import SEGMENT_COLUMNS
from growsim.errors import UserInputError
from growsim.models import honda
from growsim.phenotypes.plant import LEAF, STEM, colors
from growsim.phenotypes.plant import views as viz
from growsim.phenotypes.plant.mesh import plant_mesh, triangle_segments

# light travelling +x, i.e. coming from -x: the -x side of a tree is the lit one
FROM_MINUS_X = Environment.model_validate({"light": {"direction": [1.0, 0.0, 0.0]}})
FROM_PLUS_X = Environment.model_validate({"light": {"direction": [-1.0, 0.0, 0.0]}})


@pytest.fixture(scope="module")
def tree():
    return honda.develop(honda.PRESETS["zelkova"])


def _x(plant):
    return (plant.start[:, 0] + plant.end[:, 0]) / 2.0


def test_table_columns_are_the_individual_passes(tree):
    env = Environment.model_validate(
        {"light": {"direction": [1.0, -0.5, 0.2], "intensity": 0.8}, "water": {"supply": 0.7}}
    )
    table = env.segment_table(tree)
    assert list(table.columns) == list(SEGMENT_COLUMNS)
    assert table.index.name == "segment" and table.index.tolist() == list(range(tree.n_segments))
    assert (table.kind == "leaf").to_numpy().tolist() == (tree.kind == LEAF).tolist()
    assert isinstance(table.kind.dtype, pd.CategoricalDtype)
    light = env.light.segment_light(tree)
    loads = env.gravity.loads(tree)
    flow = env.water.transport(tree, light, g=env.gravity.g)
    np.testing.assert_array_equal(table.light, light)
    np.testing.assert_array_equal(table.moment, loads.moment)
    np.testing.assert_array_equal(table.stress_ratio, loads.stress_ratio)
    np.testing.assert_array_equal(table.water, flow.received)
    np.testing.assert_array_equal(table.water_met, flow.met)
    assert table.light.max() <= 0.8 + 1e-12 and table.water.sum() == pytest.approx(flow.total)
    # the environment's keys reach the passes: less supply, less water met
    dry = Environment.model_validate({**env.model_dump(), "water": {"supply": 0.2}})
    assert dry.segment_table(tree).water_met.mean() < table.water_met.mean()


def test_table_of_a_mapping_and_bad_input():
    arrays = {
        "start": np.array([[0.0, 0, 0], [0, 1, 0]]),
        "end": np.array([[0.0, 1, 0], [1, 1, 0]]),
        "radius": np.array([0.1, 0.1]),
        "parent": np.array([-1, 0]),
    }
    table = Environment().segment_table(arrays)
    assert table.kind.tolist() == ["stem", "stem"] and len(table) == 2
    bad = {**arrays, "start": np.array([[np.nan, 0, 0], [0, 1, 0]])}
    with pytest.raises(UserInputError, match="start"):
        Environment().segment_table(bad)


def test_side_light_brightens_that_side_in_the_table(tree):
    x = _x(tree)
    lit = FROM_MINUS_X.segment_table(tree).light
    assert lit[x < 0].mean() > 1.3 * lit[x > 0].mean()
    back = FROM_PLUS_X.segment_table(tree).light
    assert back[x > 0].mean() > 1.3 * back[x < 0].mean()


def _sides(img: np.ndarray) -> tuple[float, float]:
    """Mean brightness of the plant's pixels left and right of its trunk (front view:
    screen right is +x); the trunk's own columns are left out."""
    mask = np.any(img < 235, axis=2)
    rows = np.flatnonzero(mask.any(1))
    trunk = np.flatnonzero(mask[rows[-1]]).mean()  # the lowest pixels are the trunk's
    band = 0.01 * img.shape[1]
    col = np.arange(img.shape[1])[None, :]
    lum = img.astype(float).mean(2)
    return lum[mask & (col < trunk - band)].mean(), lum[mask & (col > trunk + band)].mean()


def test_side_light_brightens_that_side_in_the_picture(tree):
    options = {"view": "front", "size": (300, 300), "color": "light", "legend": False}
    left, right = _sides(viz.render_image(tree, env=FROM_MINUS_X, light_arrow=False, **options))
    assert left > right + 8, (left, right)
    left, right = _sides(viz.render_image(tree, env=FROM_PLUS_X, light_arrow=False, **options))
    assert right > left + 8, (left, right)
    # the arrow comes from the light's side: its orange pixels are all left of the leaves
    # (drawn here on the plain bark and green leaves)
    img = viz.render_image(tree, env=FROM_MINUS_X, light_arrow=True, size=(300, 300))
    img = img.astype(int)
    orange = (img[..., 0] > 180) & (img[..., 1] > 80) & (img[..., 1] < 170) & (img[..., 2] < 60)
    green = img[..., 1] - img[..., 0] > 20
    assert orange.sum() > 50 and green.sum() > 50
    assert np.flatnonzero(orange.any(0)).max() < np.flatnonzero(green.any(0)).min()


def test_fields_ride_on_the_mesh_and_not_judged_segments_are_grey(tree):
    values = np.arange(tree.n_segments, dtype=float)
    mesh = plant_mesh(tree, sides=5, segments=2, fields={"v": values})
    seg = triangle_segments(tree, sides=5, segments=2)
    assert mesh.n_cells == seg.size
    np.testing.assert_array_equal(mesh.cell_data["v"], values[seg])
    merged = plant_mesh(tree, sides=5, segments=2, merge=True, fields={"v": values})
    np.testing.assert_array_equal(merged.cell_data["v"], values[seg])
    with pytest.raises(UserInputError, match="one value per segment"):
        plant_mesh(tree, fields={"v": values[:-1]})
    stress = colors.segment_colors(tree, "stress")
    assert np.isnan(stress[tree.kind == LEAF]).all()
    assert np.isfinite(stress[tree.kind == STEM]).all()
    water = colors.segment_colors(tree, "water", FROM_MINUS_X)
    table = FROM_MINUS_X.segment_table(tree)
    demand = table.light.to_numpy() * (tree.kind == LEAF)
    assert np.isnan(water[demand == 0]).all()
    np.testing.assert_array_equal(water[demand > 0], table.water_met[demand > 0])
    light = colors.segment_colors(tree, "light", FROM_MINUS_X)
    np.testing.assert_array_equal(light, table.light)
    scale = colors.color_scale("light", Environment.model_validate({"light": 0.25}))
    assert scale.clim == (0.0, 0.25)
    with pytest.raises(UserInputError, match="heat"):
        viz.render_image(tree, color="heat", size=(32, 32))
    with pytest.raises(UserInputError, match="needs a Plant"):
        viz.render_image(plant_mesh(tree), color="light", size=(32, 32))


def test_breaking_joints_are_red():
    bush = honda.develop(honda.PRESETS["e_wandering_bush"])  # breaks at its defaults
    img = viz.render_image(bush, color="stress", size=(200, 200), legend=False).astype(int)
    red = (img[..., 0] > 150) & (img[..., 1] < 60) & (img[..., 2] < 60)
    assert red.sum() > 20


def test_grow_color_writes_the_png(tmp_path, capsys):
    png = tmp_path / "lit.png"
    argv = ["grow", "honda", "--preset", "zelkova", "--light-direction", "1", "0", "0",
            "--color", "light", "--screenshot", str(png), "--size", "200", "--json"]  # fmt: skip
    assert main(argv) == 0
    assert json.loads(capsys.readouterr().out)["counts"]["leaves"] > 0
    img = np.asarray(Image.open(png).convert("RGB"))
    assert img.shape == (200, 200, 3)
    for color in ("stress", "water"):
        out = tmp_path / f"{color}.png"
        argv = ["grow", "honda", "--preset", "zelkova", "--color", color, "--water-supply",
                "0.5", "--screenshot", str(out), "--size", "64"]  # fmt: skip
        assert main(argv) == 0 and Image.open(out).size == (64, 64)
    plain, arrow = tmp_path / "plain.png", tmp_path / "arrow.png"
    base = ["grow", "honda", "--set", "generations=4", "--size", "64", "--screenshot"]
    assert main([*base, str(plain)]) == 0 and main([*base, str(arrow), "--light-arrow"]) == 0
    assert not np.array_equal(np.asarray(Image.open(plain)), np.asarray(Image.open(arrow)))


@pytest.mark.parametrize(
    "args,msg",
    [
        (["--color", "light", "--light-direction", "0", "0", "0"], "--light-direction 0 0 0"),
        (["--color", "light", "--light-direction", "nan", "1", "0"], "--light-direction nan"),
        (["--color", "light", "--light-intensity", "nan"], "--light-intensity nan"),
        (["--color", "light", "--light-intensity", "-1"], "--light-intensity -1"),
        (["--color", "water", "--water-supply", "-0.5"], "--water-supply -0.5"),
        (["--color", "light", "--screenshot", None], "--color light: grow draws it"),
        (["--light-arrow", "--screenshot", None], "--light-arrow"),
    ],
)
def test_grow_bad_color_options_exit_2_nothing_written(tmp_path, capsys, args, msg):
    if args[-1] is None:  # no --screenshot at all
        args = args[:-2]
    else:
        args = [*args, "--screenshot", str(tmp_path / "t.png")]
    assert main(["grow", "honda", "--set", "generations=3", *args]) == 2
    err = capsys.readouterr().err
    assert err.startswith("growsim: error:") and "Traceback" not in err
    assert msg in err, err
    assert os.listdir(tmp_path) == []


def test_unknown_color_is_refused_by_the_parser(tmp_path, capsys):
    for command in (["grow", "honda"], ["show", str(tmp_path)]):
        with pytest.raises(SystemExit) as exc:
            main([*command, "--color", "heat", "--screenshot", str(tmp_path / "t.png")])
        assert exc.value.code == 2
        err = capsys.readouterr().err
        assert err.startswith("growsim: error:") and "--color" in err and "heat" in err
        assert all(name in err for name in colors.COLORS)
    assert os.listdir(tmp_path) == []


def _fake_run(path, tree, direction):
    """A results directory as ``growsim run`` leaves it, as far as ``show`` reads it: the
    config with its ``[environment]``, ``best.json`` and the best plant."""
    path.mkdir()
    text = (ROOT / "experiments" / "quickstart.toml").read_text()
    assert "direction = [0.0, -1.0, 0.0]" in text
    text = text.replace("direction = [0.0, -1.0, 0.0]", f"direction = {list(direction)}")
    (path / "config.toml").write_text(text)
    (path / "best.json").write_text(json.dumps({"fitness": 1.0, "phenotype": "plant"}))
    tree.save(path / "best_plant.npz")
    return path


def test_show_colors_by_the_runs_environment(tmp_path, tree, capsys, monkeypatch):
    run = _fake_run(tmp_path / "run", tree, [1.0, 0.0, 0.0])
    png = tmp_path / "show.png"
    argv = ["show", str(run), "--color", "light", "--view", "front", "--size", "300",
            "--screenshot", str(png), "--no-light-arrow"]  # fmt: skip
    assert main(argv) == 0 and f"wrote {png}" in capsys.readouterr().out
    left, right = _sides(np.asarray(Image.open(png).convert("RGB"))[:245])  # above the bar
    assert left > right + 8, (left, right)  # the run's light comes from -x
    for color in ("stress", "water"):
        out = tmp_path / f"{color}.png"
        assert main(["show", str(run), "--color", color, "--size", "64", "--screenshot",
                     str(out)]) == 0  # fmt: skip
        assert Image.open(out).size == (64, 64)
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    assert main(["show", str(run), "--color", "water"]) == 2  # interactive: needs a display
    assert "no display" in capsys.readouterr().err
