"""The hormone model's ground and how its plants are drawn: no module below the soil
(demo, mutant and random genomes, 2D and 3D, strong gravity), the soil in the config,
tissue colours from chlorophyll green to lignified brown, leaf blades, and renders with a
soil slab through the command line."""

from __future__ import annotations

import json

import numpy as np
import pytest
from PIL import Image

from growsim.cli import main
from growsim.env import Environment
from growsim.errors import ConfigError
from growsim.models import hormone
from growsim.phenotypes.plant import Plant, colors
from growsim.phenotypes.plant.mesh import (
    LEAF_CHLOROPHYLL,
    ground_mesh,
    leaf_modules,
    module_plant,
    plant_mesh,
    triangle_segments,
)

LIGHT = {"diffuse": 0.5, "direction": [0.3, -1.0, 0.2]}


def _env(height, g=30.0):
    return Environment.model_validate(
        {"light": LIGHT, "gravity": {"g": g}, "ground": {"height": height}}
    )


#: growth made cheap and stems unbreakable, so that plants grow large and reach down:
#: what these tests ask of the ground is geometry, not economy
CHEAP = {"build_cost": 2e4, "leaf_cost": 5.0, "wind": 0.0, "new_module_cost": 0.05,
         "strength_young": 1e9}  # fmt: skip


def _genomes(dims, rng):
    """The demo genome, mutants of it (turning on, every gene moved by an eighth of its
    range: evolved-like) and fully random genomes, grown cheaply (:data:`CHEAP`)."""
    base = {**hormone.PRESETS[f"demo_{dims}d"], "steps": 25, "max_modules": 120, **CHEAP}
    out = [base]
    for _ in range(10):
        p = {**base, "h8_bias": 3.0}
        for q in hormone.GENES:
            v = p.get(q.name, q.default) + rng.normal(0.0, 1.0) * (q.high - q.low) / 8
            p[q.name] = float(np.clip(v, q.low, q.high))
        out.append(p)
    for _ in range(4):
        out.append({**base, **{q.name: float(rng.uniform(q.low, q.high)) for q in hormone.GENES}})
    return out


@pytest.mark.parametrize("dims", [2, 3])
def test_no_module_grows_below_the_ground(dims):
    # the same genomes with the soil far below reach under y = 0; with the soil at the
    # base (and lowered by 0.3) no module end, at any step, is under it
    genomes = _genomes(dims, np.random.default_rng(dims))
    free = [hormone.develop(p, env=_env(-1e6)) for p in genomes]
    assert sum(int((p.end[:, 1] < -1e-6).sum()) for p in free) > 0
    for height in (0.0, -0.3):
        env = _env(height)
        touching = 0
        for p in genomes:
            for plant in hormone.grow(p, env=env):
                assert plant.start[:, 1].min() >= height - 1e-9
                assert plant.end[:, 1].min() >= height - 1e-9
                assert plant.meta["ground"] == height
            touching += int((np.abs(plant.end[:, 1] - height) < 1e-9).sum())
        if height == 0.0:
            assert touching > 0  # modules turned up to run along the soil
        # the population path (the GA's) grows the same plants
        rows = [hormone.resolve_params(hormone.PARAMS, p) for p in genomes]
        table = hormone.population(np.array([list(r.values()) for r in rows]), list(rows[0]), env)
        for i, p in enumerate(genomes):
            last = hormone.develop(p, env=env)
            assert table.modules[i] == last.n_segments
            assert table.total_nutrient[i] == last.meta["total_nutrient"] or (
                np.isnan(table.total_nutrient[i]) and np.isnan(last.meta["total_nutrient"])
            )


def test_the_ground_changes_a_plant_that_reaches_down_and_only_it():
    # the default soil at the plant's base: a plant that stays above grows the same with
    # the soil far below; one that reached under it grows differently
    genomes = _genomes(3, np.random.default_rng(3))
    changed = 0
    for p in genomes:
        free, grounded = hormone.develop(p, env=_env(-1e6)), hormone.develop(p, env=_env(0.0))
        if (free.end[:, 1] >= 0.0).all():
            np.testing.assert_array_equal(free.end, grounded.end)
        else:
            changed += 1
    assert changed > 0


def test_the_ground_is_part_of_the_environment():
    env = Environment.model_validate({"ground": {"height": -0.5}})
    assert env.ground.height == -0.5 and Environment().ground.height == 0.0
    assert hormone.environment_args(env).ground == -0.5
    with pytest.raises(ConfigError, match=r"environment\.ground\.height"):
        Environment.parse({"ground": {"height": 0.2}}, "environment.")
    with pytest.raises(ConfigError, match=r"environment\.ground\.depth"):
        Environment.parse({"ground": {"depth": 1.0}}, "environment.")


def test_tissue_colours_run_from_green_to_brown_with_lignin():
    g = np.linspace(0.0, 1.0, 11)
    rgb = colors.tissue_rgb(1.0 - g, g)  # chlorophyll lost as lignin comes (the model's)
    np.testing.assert_allclose(rgb[0], colors.GREEN_RGB)
    np.testing.assert_allclose(rgb[-1], colors.WOOD_RGB)
    r, gr, _ = rgb.T
    assert (np.diff(gr) < 0).all()  # less green
    assert (gr[:3] > r[:3] + 0.2).all() and (r[-3:] > gr[-3:]).all()  # green, then brown
    # lignin alone browns at any chlorophyll; chlorophyll alone greens young tissue
    for c in (0.0, 0.5, 1.0):
        col = colors.tissue_rgb(np.full(11, c), g)
        assert (np.diff(col[:, 1] - col[:, 0]) < 0).all()
    young = colors.tissue_rgb(np.linspace(0, 1, 5), np.zeros(5))
    assert (np.diff(young[:, 1] - young[:, 0]) > 0).all()


def _two_modules(**meta):
    """A wood module and a green one on top of it, as the hormone model makes them."""
    return Plant.from_points(
        [[0, 0, 0], [0, 1, 0], [0.3, 1.8, 0]], [-1, 0], [-1, 0, 1], radius=[0.06, 0.03],
        data={"chlorophyll": [0.1, 1.0], "lignin": [0.9, 0.0]}, meta=meta,
    )  # fmt: skip


def test_mesh_paints_modules_by_tissue_and_gives_green_ones_a_blade():
    plant = _two_modules(ground=-0.2)
    assert module_plant(plant) and leaf_modules(plant).tolist() == [False, True]
    mesh = plant_mesh(plant, sides=6)
    seg = triangle_segments(plant, sides=6)
    assert mesh.n_cells == seg.size == 2 * 6 + 2 * 6 + 6  # two tubes, one blade
    rgb = mesh.cell_data["rgb"].astype(float) / 255.0
    want = colors.tissue_rgb(plant.data["chlorophyll"], plant.data["lignin"])
    np.testing.assert_allclose(rgb, want[seg], atol=1 / 255)
    assert mesh.field_data["ground"].tolist() == [-0.2]
    # the blade lies along the green module, in the plant's plane (a flat, 2D plant)
    blade = mesh.points[-7:]
    assert np.allclose(blade[:, 2], 0.0) and np.ptp(blade[:, 1]) == pytest.approx(0.8, abs=1e-6)
    # and its kind is leaf; other plants get neither colours, blades nor soil
    assert mesh.point_data["kind"][-7:].tolist() == [1] * 7
    bare = Plant.from_points([[0, 0, 0], [0, 1, 0]], [-1], [-1, 0])
    m = plant_mesh(bare)
    assert "rgb" not in m.cell_data and "ground" not in m.field_data
    assert LEAF_CHLOROPHYLL == 0.5
    soil = ground_mesh(mesh.bounds, -0.2)
    assert soil.bounds[3] == pytest.approx(-0.2) and soil.bounds[2] < -0.2


def _share(img, rgb, tol=40):
    d = np.abs(img.astype(int) - np.array(rgb) * 255).max(axis=2)
    return float((d < tol).mean())


def test_renders_show_green_leaves_brown_wood_and_the_soil(tmp_path):
    from growsim.phenotypes.plant import views

    img = views.render_image(_two_modules(), view="front", size=(160, 160))
    assert _share(img, colors.WOOD_RGB) > 0.002  # the woody base
    assert _share(img, colors.GREEN_RGB) > 0.002  # the green module and its blade
    assert _share(img, colors.GROUND_RGB) > 0.003  # the soil strip
    honda_like = Plant.from_points([[0, 0, 0], [0, 1, 0]], [-1], [-1, 0])
    assert _share(views.render_image(honda_like, size=(96, 96)), colors.GROUND_RGB) == 0.0
    plants = list(hormone.grow({**hormone.PRESETS["demo_2d"], "steps": 6}, env=_env(0.0)))
    gif = views.growth_animation(plants, tmp_path / "g.gif", size=(64, 64))
    frame = np.asarray(Image.open(gif).convert("RGB"))
    assert _share(frame, colors.GROUND_RGB, tol=50) > 0.005
    assert views.turntable(plants[-1], tmp_path / "t.gif", frames=2, size=(48, 48)).exists()


@pytest.mark.parametrize("preset", ["demo_2d", "demo_3d"])
def test_grow_renders_a_hormone_plant_through_the_cli(tmp_path, capsys, preset):
    png, npz = tmp_path / f"{preset}.png", tmp_path / f"{preset}.npz"
    assert main(["grow", "hormone", "--preset", preset, "--set", "steps=12", "--screenshot",
                 str(png), "--save", str(npz), "--size", "200", "--json"]) == 0  # fmt: skip
    out = json.loads(capsys.readouterr().out)
    assert out["model"] == "hormone"
    img = np.asarray(Image.open(png).convert("RGB"))
    assert img.shape == (200, 200, 3)
    assert _share(img, colors.GROUND_RGB) > 0.005  # the soil strip
    assert _share(img, colors.GREEN_RGB, tol=60) > 0.005  # green modules and blades
    saved = Plant.load(npz)
    assert saved.meta["ground"] == 0.0 and module_plant(saved)


@pytest.mark.parametrize("dims", [2, 3])
def test_a_module_lying_on_the_soil_gets_no_light(dims):
    # a module whose end the soil holds (turned up to it) catches nothing at the next
    # step: a mat along the soil does not pay, the plant must stand up to catch light
    genomes = _genomes(dims, np.random.default_rng(10 + dims))
    on_soil = lit_above = 0
    for p in genomes:
        prev = None
        for plant in hormone.grow(p, env=_env(0.0)):
            if prev is not None and plant.n_segments >= prev.n_segments:
                k = prev.n_segments
                lying = np.abs(prev.end[:, 1]) < 1e-9
                light = plant.data["light"][:k]
                assert np.all(light[lying] == 0.0)
                on_soil += int(lying.sum())
                lit_above += int((light[~lying] > 0).sum())
            prev = plant
    assert on_soil > 0 and lit_above > 0
