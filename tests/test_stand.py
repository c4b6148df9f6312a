"""The stand (issue 30, first part): ``[environment.stand]``, an explicit stand of hormone
plants grown together under one light, its measures, save/load and ``growsim grow
--stand``."""

from __future__ import annotations

import json
from contextlib import redirect_stderr, redirect_stdout
from io import StringIO

import numpy as np
import pytest

from growsim.env import Environment, Stand
from growsim.errors import ConfigError
from growsim.kernels import hormone as K
from growsim.kernels import stand as KS
from growsim.models import hormone as H
from growsim.phenotypes.plant import Plant
from growsim.phenotypes.stand import PLANT_COLUMNS, plant_table, stand_measures

ENV3 = H.PRESET_ENVIRONMENTS["demo_3d"]
DEMO3 = {**H.PRESETS["demo_3d"], "steps": 15, "max_modules": 120}
DEMO2 = {**H.PRESETS["demo_2d"], "steps": 15, "max_modules": 120}


def env_with(stand=None, base=ENV3):
    return Environment.parse({**base, **({"stand": stand} if stand else {})})


# ---------------------------------------------------------------- [environment.stand]
def test_default_is_alone_and_one_plant():
    env = Environment()
    assert env.stand.mode == "alone" and env.stand.n_plants == 1
    assert env.stand.xz().tolist() == [[0.0, 0.0]]


def test_layouts_give_the_positions():
    grid = Stand.parse({"mode": "explicit", "rows": 2, "cols": 3, "spacing": 2.0})
    assert grid.n_plants == 6 and grid.ground_area() == 24.0
    assert np.allclose(grid.xz().mean(axis=0), 0.0)
    row = Stand.parse({"mode": "explicit", "layout": "row", "count": 4, "spacing": 0.5})
    assert row.xz()[:, 1].tolist() == [0.0] * 4 and np.allclose(np.diff(row.xz()[:, 0]), 0.5)
    rand = {"mode": "explicit", "layout": "random", "count": 20, "density": 4.0, "seed": 3}
    a, b = Stand.parse(rand).xz(), Stand.parse(rand).xz()
    assert np.array_equal(a, b) and np.abs(a).max() <= np.sqrt(20 / 4.0) / 2
    given = Stand.parse({"mode": "explicit", "positions": [[0, 0], [1, 2]]})
    assert given.xz().tolist() == [[0.0, 0.0], [1.0, 2.0]]


@pytest.mark.parametrize(
    ("table", "key"),
    [
        ({"mode": "explicit", "spacing": 0.0}, "spacing"),
        ({"mode": "explicit", "spacing": -1.0}, "spacing"),
        ({"mode": "explicit", "spacing": 0.01}, "spacing"),  # overlapping plants
        ({"mode": "explicit", "positions": [[0, 0], [0.01, 0]]}, "positions"),
        ({"mode": "explicit", "positions": [[0, 0], [2000, 0]]}, "positions"),  # out of reach
        ({"mode": "explicit", "rows": 100, "cols": 100, "spacing": 50.0}, "spacing"),
        ({"mode": "explicit", "positions": [[0, 0, 0]]}, "positions"),
        ({"mode": "explicit", "layout": "random", "count": 500, "density": 1e4}, "density"),
        ({"mode": "mixture", "neighbours": 0}, "neighbours"),
        ({"mode": "mixture", "draws": 0}, "draws"),
        ({"mode": "mixture", "spacing": 0.0}, "spacing"),
        ({"mode": "periodic", "rings": 0}, "rings"),
        ({"mode": "crowd"}, "mode"),
        ({"spacing_m": 1.0}, "spacing_m"),
    ],
)
def test_bad_stand_is_refused_naming_the_key(table, key):
    with pytest.raises(ConfigError, match=key):
        Environment.parse({"stand": table})


# ---------------------------------------------------------------- growing a stand
def test_a_stand_of_one_at_the_origin_is_the_plant_alone_bit_for_bit():
    env = env_with()
    alone = H.develop(DEMO3, env=env)
    *_, stand = H.grow_stand(DEMO3, env=env, xz=np.zeros((1, 2)))
    assert np.array_equal(alone.start, stand.start) and np.array_equal(alone.end, stand.end)
    assert alone.meta["total_nutrient"] == stand.meta["total_nutrient"]
    assert stand.data["plant"].tolist() == [0] * stand.n_segments


def test_a_plant_moved_alone_grows_the_same_shape_moved():
    env = env_with()
    alone = H.develop(DEMO3, env=env)
    *_, moved = H.grow_stand(DEMO3, env=env, xz=np.array([[2.0, -1.0]]))
    assert moved.n_segments == alone.n_segments
    assert np.allclose(moved.start - [2.0, 0.0, -1.0], alone.start, atol=1e-6)


def test_every_module_belongs_to_its_roots_plant():
    env = env_with({"mode": "explicit", "rows": 2, "cols": 2, "spacing": 1.0})
    *_, stand = H.grow_stand(DEMO3, env=env)
    which, parent = stand.data["plant"], stand.parent
    assert which[:4].tolist() == [0, 1, 2, 3] and (parent[:4] == -1).all()
    kids = parent >= 0
    assert (which[kids] == which[parent[kids]]).all()
    base = np.asarray(stand.meta["stand"])
    assert np.allclose(stand.start[:4][:, [0, 2]], base)
    assert np.isclose(sum(stand.meta["plant_nutrient"]), stand.meta["total_nutrient"])


def test_neighbours_shade_each_other():
    """The centre of a dense 3 x 3 stand catches less light per leaf area than the same
    genome alone; a sparse stand's centre less than alone too, but more than the dense."""
    alone = plant_table(H.develop(DEMO3, env=env_with()))
    dense = {"mode": "explicit", "rows": 3, "cols": 3, "spacing": 0.6}
    sparse = {**dense, "spacing": 3.0}
    *_, d = H.grow_stand(DEMO3, env=env_with(dense))
    *_, s = H.grow_stand(DEMO3, env=env_with(sparse))
    lpla = [alone.light_per_leaf_area[0], *(plant_table(t).light_per_leaf_area[4] for t in (s, d))]
    assert lpla[0] > lpla[2] and lpla[1] > lpla[2], lpla


def test_a_2d_stand_stands_in_a_row_and_refuses_z():
    env = env_with({"mode": "explicit", "layout": "row", "count": 3, "spacing": 1.0},
                   H.PRESET_ENVIRONMENTS["demo_2d"])  # fmt: skip
    *_, stand = H.grow_stand(DEMO2, env=env)
    assert np.allclose(stand.start[:, 2], 0.0) and set(stand.data["plant"].tolist()) == {0, 1, 2}
    grid = env_with({"mode": "explicit", "rows": 2, "cols": 2}, H.PRESET_ENVIRONMENTS["demo_2d"])
    with pytest.raises(ValueError, match="z must be 0"):
        next(H.grow_stand(DEMO2, env=grid))


# ---------------------------------------------------------------- periodic
def _grown(preset, steps, resolution):
    e = dict(H.PRESET_ENVIRONMENTS[preset])
    e["light"] = {**e["light"], "resolution": resolution}
    p = H.resolve_params(H.PARAMS, {**H.PRESETS[preset], "steps": steps})
    n, s = H.seedling(p, Environment.parse(e))
    for _ in range(steps):
        n, _ = K.grow_step(n, *s.values())
    m = s["modules"]
    K.place_kernel(n, m.parent, m.R, m.length, m.origin)
    return n, s, int(p["dims"])


@pytest.mark.parametrize(("preset", "steps"), [("demo_3d", 30), ("demo_3d", 15), ("demo_2d", 30)])
@pytest.mark.parametrize("spacing", [1.0, 2.0])
def test_periodic_light_agrees_with_an_explicit_7x7_stand_of_copies(preset, steps, spacing):
    """The focal plant's light among two rings of copies (periodic, the default) against
    the centre of an explicit 7 x 7 stand of the same copies (one shadow map of all 49):
    its total light within 3 % and its light per module within 10 % of the mean light
    (mean absolute difference), at a 2048-pixel map. Issue 30's bar (per segment within
    2 %) is not met: the two shadow maps span different widths, so their pixels differ
    (benchmarks/log/stand.md)."""
    n, s, dims = _grown(preset, steps, 2048)
    m, env, scratch = s["modules"], s["env"], s["scratch"]
    explicit = K.walls_light(n, dims, m, env, KS.periodic_shifts(spacing, 3, dims), scratch)
    periodic = K.walls_light(n, dims, m, env, KS.periodic_shifts(spacing, 2, dims), scratch)
    a, b = periodic.reshape(n, -1).mean(1), explicit.reshape(n, -1).mean(1)
    assert abs(a.sum() / b.sum() - 1.0) < 0.03
    assert np.abs(a - b).mean() / b.mean() < 0.10


def test_periodic_kernel_with_no_copies_is_the_plant_alone():
    env = Environment.parse(H.PRESET_ENVIRONMENTS["demo_3d"])
    p = H.resolve_params(H.PARAMS, {**H.PRESETS["demo_3d"], "steps": 20})
    n, s = H.seedling(p, env)
    for _ in range(20):
        n, _ = K.grow_step(n, *s.values())
    plain = H.develop(p, env=env)
    assert n == plain.n_segments and np.array_equal(plain.start, s["modules"].origin[:n])
    assert np.array_equal(plain.data["light"], s["modules"].light[:n])


def test_a_dense_periodic_stand_gains_less_than_the_plant_alone():
    env = env_with({"mode": "periodic", "spacing": 0.5})
    alone = H.develop(DEMO3, env=env_with())
    *_, dense = H.grow_periodic(DEMO3, env=env)
    *_, sparse = H.grow_periodic(DEMO3, env=env, spacing=5.0)
    assert dense.meta["total_nutrient"] < sparse.meta["total_nutrient"]
    assert dense.meta["total_nutrient"] < alone.meta["total_nutrient"]
    assert dense.meta["rings"] == 2 and dense.meta["spacing"] == 0.5


def test_the_nutrient_objective_scores_the_plant_among_its_copies():
    from growsim.models import get_model
    from growsim.objectives.nutrient import NutrientObjective

    env = env_with({"mode": "periodic", "spacing": 0.6})
    model = get_model("hormone")
    plant = model.develop(DEMO3, env=env)  # develop honours the stand
    *_, periodic = H.grow_periodic(DEMO3, env=env)
    assert plant.meta["total_nutrient"] == periodic.meta["total_nutrient"]
    alone = model.develop(DEMO3, env=env_with())
    assert plant.meta["total_nutrient"] < alone.meta["total_nutrient"]
    obj = NutrientObjective(env=env)
    assert obj(plant) == pytest.approx(plant.meta["total_nutrient"])
    row = H.resolve_params(H.PARAMS, DEMO3)
    assert obj.batch(model, np.array([list(row.values())]), list(row)) is None  # plant by plant


# ---------------------------------------------------------------- measures, save, load
def test_measures_per_plant_and_per_stand(tmp_path):
    env = env_with({"mode": "explicit", "rows": 2, "cols": 2, "spacing": 1.0})
    *_, stand = H.grow_stand(DEMO3, env=env)
    t = plant_table(stand)
    assert list(t.columns) == list(PLANT_COLUMNS) and len(t) == 4
    assert np.isclose(t.light_share.sum(), 1.0) and (t.height > 0).all()
    assert (t.crown_width > 0).all() and np.allclose(t.height_to_width, t.height / t.crown_width)
    m = stand_measures(stand, env.stand.ground_area())
    assert m["plants"] == 4.0 and np.isclose(m["leaf_area_index"], t.leaf_area.sum() / 4.0)
    assert 0.0 <= m["light_inequality"] < 1.0
    back = Plant.load(stand.save(tmp_path / "stand.npz"))
    assert np.array_equal(back.data["plant"], stand.data["plant"])
    assert back.meta["stand"] == stand.meta["stand"]
    assert plant_table(back).equals(t)


# ---------------------------------------------------------------- growsim grow --stand
def _grow(args):
    from growsim.cli import main

    out, err = StringIO(), StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        code = main(["grow", "hormone", *args])
    return code, out.getvalue(), err.getvalue()


def test_grow_stand_renders_and_reports(tmp_path):
    png = tmp_path / "stand.png"
    code, out, err = _grow(["--preset", "demo_3d", "--set", "steps=10", "--stand", "2x2",
                            "--spacing", "1.5", "--screenshot", str(png), "--size", "200",
                            "200", "--json"])  # fmt: skip
    assert code == 0, err
    info = json.loads(out)
    assert info["stand"]["plants"] == 4.0 and len(info["plants"]) == 4
    assert png.stat().st_size > 0


def test_grow_stand_gif_one_frame_per_step(tmp_path):
    from PIL import Image

    gif = tmp_path / "stand.gif"
    code, out, err = _grow(["--preset", "demo_2d", "--set", "steps=6", "--stand", "3",
                            "--gif", str(gif), "--size", "64", "64"])  # fmt: skip
    assert code == 0 and "animation:" in out, err
    with Image.open(gif) as im:
        assert im.n_frames == 6 and im.size == (64, 64)
    bad = tmp_path / "stand.png"
    code, _, err = _grow(["--preset", "demo_2d", "--stand", "3", "--gif", str(bad)])
    assert code != 0 and "--gif" in err and not bad.exists()


def test_grow_stand_of_different_plants(tmp_path):
    best = tmp_path / "best.json"  # a run's best.json: its params
    best.write_text(json.dumps({"params": {"h0_gain": 0.0, "steps": 99}, "fitness": 1.0}))
    code, out, err = _grow(["--preset", "demo_2d", "--set", "steps=10", "--stand", "4",
                            "--plants", f"demo_2d,{best}", "--json"])  # fmt: skip
    assert code == 0, err
    plants = json.loads(out)["plants"]
    # the file's plant does not elongate (h0_gain 0); --set steps wins over the file's
    assert [p["segments"] > 1 for p in plants] == [True, False, True, False]
    for args, says in (
        (["--plants", "demo_2d"], "--plants: only with --stand"),
        (["--stand", "2", "--plants", "nothing.json"], "--plants nothing.json"),
        (["--stand", "2", "--plants", "demo_2d,demo_3d"], "hormone.dims"),
    ):
        code, _, err = _grow(["--preset", "demo_2d", *args])
        assert code != 0 and says in err, err


def test_grow_stand_of_another_model_places_copies(tmp_path):
    from growsim.cli import main

    out = StringIO()
    with redirect_stdout(out), redirect_stderr(StringIO()):
        code = main(["grow", "honda", "--preset", "zelkova", "--stand", "3", "--spacing",
                     "30", "--json"])  # fmt: skip
    info = json.loads(out.getvalue())
    assert code == 0 and info["stand"]["plants"] == 3.0
    assert [p["x"] for p in info["plants"]] == [-30.0, 0.0, 30.0]
    assert len({p["segments"] for p in info["plants"]}) == 1  # copies


@pytest.mark.parametrize(
    ("args", "says"),
    [
        (["--stand", "0x3"], "--stand 0x3"),
        (["--stand", "axb"], "--stand axb"),
        (["--stand", "3x3", "--spacing", "0"], "spacing"),
        (["--stand", "3x3", "--spacing", "0.001"], "spacing"),
        (["--spacing", "1"], "--spacing"),
    ],
)
def test_grow_stand_bad_input_writes_nothing(tmp_path, args, says):
    png = tmp_path / "x.png"
    code, _, err = _grow([*args, "--screenshot", str(png)])
    assert code != 0 and says in err and not png.exists()


def test_new_stand_matches_its_oracle():
    from naive import stand as naive_stand

    rng = np.random.default_rng(3)
    xz = rng.uniform(-2, 2, (5, 2))
    c = rng.uniform(0.05, 0.2, (5, K.N_CONSTANTS))  # each plant its own constants
    a, b = K.new_module_arrays(8, 6), K.new_module_arrays(8, 6)
    for m in (a, b):  # a used array: the stand overwrites what it sets
        for f in m._fields:
            getattr(m, f)[...] = 7
    assert KS.new_stand(a, c, xz, -0.2) == naive_stand.new_stand(b, c, xz, -0.2) == 5
    fields = ("parent", "R", "origin", "length", "radius", "nutrient", "chlorophyll", "apex",
              "plant")  # fmt: skip
    for f in fields:
        np.testing.assert_array_equal(getattr(a, f)[:5], getattr(b, f)[:5], err_msg=f)
    assert (a.parent[:5] == -1).all() and np.allclose(a.origin[:5, 1], -0.2)
    assert a.plant[:5].tolist() == [0, 1, 2, 3, 4] and a.length[3] == c[3, K.C_NEWLEN]
