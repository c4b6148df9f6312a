"""The 2D IFS plants of seed 002: chaos game against its oracles, the IFSP code's forms and
repair, the attractor phenotype, the Ochoa terms (kernels against their oracles, formulas
on hand-made pictures, plants of other models) and a species run end to end."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import ROOT
from naive import ifs2d as naive
from naive import ochoa as naive_ochoa

from growsim.errors import ConfigError, UserInputError
from growsim.kernels import ifs2d as K
from growsim.kernels import ochoa as KO
from growsim.kernels.views import ncc
from growsim.models import ifs2d
from growsim.objectives.ochoa import SPECIES, TERMS, OchoaObjective, ochoa_terms, plane_view
from growsim.phenotypes.attractor import Attractor, singular_values

FERN = ifs2d.TABLE1


# --------------------------------------------------------------------------- chaos game


def test_splitmix_matches_the_oracle():
    s = t = 12345
    for _ in range(50):
        s, z = K.splitmix64(np.uint64(s))
        t, w = naive.splitmix64(t)
        assert int(s) == t and int(z) == w


@pytest.mark.parametrize("seed", [0, 1, 2**63 + 5])
def test_chaos_game_replays_the_oracle_bit_for_bit(seed):
    maps, p = FERN[:, :6], FERN[:, 6]
    fast = K.chaos_game(maps, p, 3000, seed=seed, burn_in=7, start=(0.3, -0.2))
    slow = naive.chaos_game(maps, p, 3000, seed=seed, burn_in=7, start=(0.3, -0.2))
    np.testing.assert_array_equal(fast, slow)


def test_a_map_of_weight_zero_is_never_drawn():
    maps = [[0.5, 0, 0, 0.5, 0, 0], [0.5, 0, 0, 0.5, 10.0, 0]]
    pts = K.chaos_game(maps, [1.0, 0.0], 5000, seed=3, burn_in=0, start=(0.0, 0.0))
    assert np.all(pts == 0.0)
    np.testing.assert_array_equal(K.cumulative([0, 0]), [0.5, 1.0])


def _framed_view(points, size):
    return Attractor(points, [[0] * 6], [1.0]).front_view(size)


@pytest.mark.parametrize("preset", ["fern", "tree", "tree3", "tree6", "bush", "sierpinski"])
def test_chaos_game_draws_the_attractor_of_the_deterministic_renderer(preset):
    """Every pixel the deterministic renderer reaches, the chaos game's 100,000 points
    reach (recall); where depth k resolves the attractor to below a pixel (largest scale
    <= 0.75: 0.75^6..0.6^9 of its size), the two pictures agree (NCC >= 0.9). The fern's
    main map shrinks by only 0.85, so depth 8 leaves its tip coarse: recall only."""
    plant = ifs2d.develop(ifs2d.PRESETS[preset], seed=4)
    depth = {3: 9, 4: 8, 6: 6}[len(plant.maps)]
    start = ifs2d.fixed_point(plant.maps[int(np.argmax(plant.p))])
    exact = naive.all_maps(plant.maps, depth, start)
    # the same framing for both: the union's, so a pixel means the same place
    both = np.concatenate([plant.points, exact])
    a = Attractor(both, plant.maps, plant.p)
    bx, by, k = a.framing(64)
    from growsim.kernels.views import frame_view

    views = []
    for pts in (plant.points, exact):
        col, row = frame_view(pts[:, 0], pts[:, 1], bx, by, k, 64)
        views.append(K.points_raster(col, row, (64, 64))[None])
    chaos, exact_view = views
    assert (chaos & exact_view).sum() / exact_view.sum() >= 0.98
    if singular_values(plant.maps).max() <= 0.75:
        assert ncc(chaos, exact_view) >= 0.9


def test_points_raster_and_bounds_match_the_oracles():
    rng = np.random.default_rng(0)
    col, row = rng.uniform(-3, 40, 500), rng.uniform(-3, 30, 500)
    for count in (False, True):
        np.testing.assert_array_equal(
            K.points_raster(col, row, (28, 37), count=count),
            naive.points_raster(col, row, (28, 37), count=count),
        )
    pts = rng.normal(size=(300, 2))
    x0, x1, y0, y1, xl = K.bounds(pts)
    assert (x0, x1, y0, y1) == (pts[:, 0].min(), pts[:, 0].max(), pts[:, 1].min(), pts[:, 1].max())
    assert xl == pts[np.argmin(pts[:, 1]), 0]


def test_chaos_game_refuses_bad_input():
    with pytest.raises(ValueError, match="shape"):
        K.chaos_game([[1, 2, 3]], [1], 10)
    with pytest.raises(ValueError, match="probabilities"):
        K.chaos_game([[0.5, 0, 0, 0.5, 0, 0]], [-1.0], 10)


# --------------------------------------------------------------------------- the code


def test_paper_form_and_abcdef_form_are_inverse():
    rng = np.random.default_rng(1)
    abcd = rng.uniform(-1, 1, size=(20, 4))
    np.testing.assert_allclose(ifs2d.abcdef_form(ifs2d.paper_form(abcd)), abcd, atol=1e-12)
    table = np.column_stack([abcd[:5], rng.uniform(-2, 2, (5, 2)), rng.uniform(0, 1, 5)])
    for form in (0, 1):
        maps, p = ifs2d.code_from_params(ifs2d.params_from_code(table, form=form))
        np.testing.assert_allclose(maps, table[:, :6], atol=1e-10)
        np.testing.assert_allclose(p, table[:, 6], atol=1e-12)


def test_both_forms_draw_the_same_fern():
    a = ifs2d.develop(ifs2d.params_from_code(FERN, form=0), seed=2)
    b = ifs2d.develop(ifs2d.params_from_code(FERN, form=1), seed=2)
    np.testing.assert_allclose(a.points, b.points, atol=1e-9)


def test_repair_makes_every_map_contractive_and_normalises_weights():
    rng = np.random.default_rng(2)
    maps = np.column_stack([rng.uniform(-1, 1, (50, 4)), rng.uniform(-3, 3, (50, 2))])
    fixed, p = ifs2d.repair(maps, rng.uniform(0, 1, 50), 0.9)
    sv = singular_values(fixed)
    assert sv.max() <= 0.9 + 1e-12 and np.isclose(p.sum(), 1.0)
    untouched = singular_values(maps) <= 0.9
    np.testing.assert_array_equal(fixed[untouched], maps[untouched])
    np.testing.assert_array_equal(fixed[:, 4:], maps[:, 4:])  # shifts kept
    # a plant whose maps expand is drawn bounded
    params = ifs2d.params_from_code([[1.0, 0.9, -0.9, 1.0, 0.0, 1.0, 1.0]], form=1,
                                    iterations=2000)  # fmt: skip
    assert np.abs(ifs2d.develop(params).points).max() < 100


def test_the_fern_is_the_fern():
    fern = ifs2d.develop(ifs2d.PRESETS["fern"], seed=0)
    m = fern.measures()
    # Barnsley's fern: 0 <= y <= 10, -2.18 <= x <= 2.66; the tip is W2's fixed point
    assert 9.9 < m["height"] <= 10.0 and 2.1 < m["left"] < 2.2 and 2.6 < m["right"] < 2.7
    # the fixed point of W2 (the fern's tip) is on the attractor
    tip = np.asarray(ifs2d.fixed_point(FERN[1]))
    assert np.linalg.norm(fern.points - tip, axis=1).min() < 0.01
    bx, by = fern.base()  # the stem starts at the origin (sampled to within 0.1)
    assert bx == 0.0 and 0.0 <= by < 0.1
    # the stem (W1) holds about 1 % of the points, on x = 0, y in [0, 1.6]
    stem = (np.abs(fern.points[:, 0]) < 1e-12) & (fern.points[:, 1] <= 1.6)
    assert 0.005 < stem.mean() < 0.02


def test_develop_is_seeded_and_checks_parameters():
    p = {"iterations": 5000}
    a, b = ifs2d.develop(p, seed=1), ifs2d.develop(p, seed=1)
    np.testing.assert_array_equal(a.points, b.points)
    assert not np.array_equal(a.points, ifs2d.develop(p, seed=2).points)
    with pytest.raises(UserInputError, match=r"ifs2d\.r_1"):
        ifs2d.develop({"r_1": 2.0})
    with pytest.raises(UserInputError, match="unknown parameter"):
        ifs2d.develop({"n_maps": 2, "r_3": 0.5})


def test_attractor_round_trips_and_renders(tmp_path):
    fern = ifs2d.develop(ifs2d.PRESETS["fern"], seed=0)
    back = Attractor.load(fern.save(tmp_path / "fern.npz"))
    np.testing.assert_array_equal(back.points, fern.points)
    assert back.params == fern.params and back.meta == fern.meta
    img = fern.render_image(view="front", size=(90, 120))
    assert img.shape == (120, 90, 3)
    green = (img[..., 1].astype(int) > img[..., 0].astype(int) + 30).mean()
    assert 0.05 < green < 0.6  # a fern, neither empty nor a blob
    np.testing.assert_array_equal(fern.render_image(view="back", size=(90, 120)), img[:, ::-1])
    with pytest.raises(UserInputError, match="not an attractor"):
        from growsim.phenotypes.plant import Plant

        Attractor.load(Plant.from_points([[0, 0, 0], [0, 1, 0]], [-1], [-1, 0]).save(
            tmp_path / "p.npz"))  # fmt: skip


# --------------------------------------------------------------------------- Ochoa kernels


def _random_skeleton(rng, size=48):
    from skimage.morphology import skeletonize

    img = np.zeros((size, size), bool)
    for _ in range(6):  # random thick strokes
        a, b = rng.uniform(0, size, 2), rng.uniform(0, size, 2)
        t = np.linspace(0, 1, 200)[:, None]
        p = (a + (b - a) * t).astype(int)
        img[np.clip(p[:, 1], 0, size - 1), np.clip(p[:, 0], 0, size - 1)] = True
    from scipy import ndimage

    img = ndimage.binary_dilation(img, iterations=int(rng.integers(0, 3)))
    return np.ascontiguousarray(skeletonize(img), dtype=np.uint8), img.astype(np.uint8)


@pytest.mark.parametrize("seed", range(6))
def test_ochoa_kernels_match_their_oracles(seed):
    rng = np.random.default_rng(seed)
    skel, img = _random_skeleton(rng)
    for d in [(0.0, -1.0), (0.3, -1.0), (-1.0, -0.2), (1.0, 0.0)]:
        assert KO.shadow_bins(img, d) == naive_ochoa.shadow_bins(img, d)
    for it in (0, 1, 3):
        np.testing.assert_array_equal(KO.prune(skel, it), naive_ochoa.prune(skel, it))
    for many in (3, 4, 5):
        assert KO.junctions(skel, many) == naive_ochoa.junctions(skel, many)


def test_shadow_is_the_share_of_columns_from_above():
    img = np.zeros((10, 10), np.uint8)
    img[2:8, 3] = 1  # a vertical stick: one column
    img[5, 3:9] = 1  # a horizontal branch: six columns
    assert KO.shadow_bins(img) == (6, 10.0)
    # from the side, the rows count instead
    assert KO.shadow_bins(img, (1.0, 0.0)) == (6, 10.0)


# --------------------------------------------------------------------------- Ochoa terms


def _stick_and_branches(size=33, arms=2):
    """A stem up to row ``r`` forking into two diagonal arms (and, with ``arms=3``, the
    stem going on upright)."""
    img = np.zeros((size, size), np.uint8)
    c = size // 2
    r = size // 2
    img[r:, c] = 1
    for k in range(1, size // 2):
        img[r - k, c - k] = 1
        img[r - k, c + k] = 1
    if arms == 3:
        img[:r, c] = 1
    return img


def test_terms_follow_their_formulas():
    stick = np.zeros((33, 33), np.uint8)
    stick[:, 16] = 1
    t = ochoa_terms(stick, 4.0, height_ref=8.0)
    assert t["phototropism"] == 0.5 and t["stability"] == 1.0 and t["symmetry"] == 1.0
    assert t["light"] == pytest.approx(1 / 33)
    fork = ochoa_terms(_stick_and_branches(arms=2), 20.0, height_ref=8.0)
    assert fork["phototropism"] == 1.0
    assert fork["branch_points"] == 1 and fork["stability"] == 1.0  # a fork: 3 branches
    assert fork["symmetry"] == 1.0 and fork["light"] > 0.9
    three = ochoa_terms(_stick_and_branches(arms=3), 20.0)
    assert three["branch_points"] == 1 and three["stability"] == 0.0  # 4 branches at one point
    lopsided = _stick_and_branches(arms=2)
    lopsided[:, :10] = 0  # left reach 16 - 10 = 6 pixel centres, right 16
    assert ochoa_terms(lopsided, 1.0)["symmetry"] == pytest.approx(6.0 / 15.0)


def test_light_capture_reads_the_environment_light():
    from growsim.env.light import Light

    img = np.zeros((20, 20), np.uint8)
    img[5, 2:12] = 1  # a flat leaf: ten columns, one row
    above = ochoa_terms(img, 1.0, light=Light())["light"]
    side = ochoa_terms(img, 1.0, light=Light(direction=[1.0, 0.0, 0.0]))["light"]
    half = ochoa_terms(img, 1.0, light=Light(intensity=0.5))["light"]
    assert above == pytest.approx(0.5) and side == pytest.approx(1 / 20)
    assert half == pytest.approx(0.25)
    sky = ochoa_terms(img, 1.0, light=Light(diffuse=0.5))["light"]
    assert side < sky < above


def test_the_terms_work_on_plants_of_other_models():
    from growsim.models import honda

    obj = OchoaObjective(species="balanced", height=100.0)
    tree = honda.develop(honda.PRESETS["zelkova"])
    img, height = plane_view(tree, 128)
    assert img.shape == (128, 128) and height == pytest.approx(tree.height())
    t = obj.terms(tree)
    assert all(0.0 <= t[k] <= 1.0 for k in TERMS) and t["branch_points"] > 0
    assert obj(tree) == pytest.approx(np.mean([t[k] for k in TERMS]))


def test_species_and_weights():
    w = OchoaObjective(species="tree_one", weights={"symmetry": 0.0}).options.term_weights()
    assert w == {**SPECIES["tree_one"], "symmetry": 0.0}
    with pytest.raises(ConfigError, match="species"):
        OchoaObjective(species="oak")
    with pytest.raises(ConfigError, match="weights"):
        OchoaObjective(weights={"beauty": 1.0})
    with pytest.raises(ConfigError, match="weights"):
        OchoaObjective(weights=dict.fromkeys(TERMS, 0.0))
    plant = ifs2d.develop(ifs2d.PRESETS["tree"], seed=0)
    only_light = OchoaObjective(weights={"phototropism": 0, "stability": 0, "symmetry": 0})
    assert only_light(plant) == pytest.approx(only_light.terms(plant)["light"])


def test_ochoa_refuses_a_phenotype_without_a_2d_view():
    from growsim.models import get_model

    swim = get_model("fish").develop({"frames": 20}, seed=0)  # a trajectory: no front view
    assert "front_view" not in swim.capabilities
    with pytest.raises(UserInputError, match="no 2D view"):
        plane_view(swim, 32)


# --------------------------------------------------------------------------- species run


def test_species_run_end_to_end(tmp_path):
    from growsim.experiment.species import evolve_species

    overrides = ["ga.population=4", "ga.generations=3", "model.params.iterations=20000"]
    result, table = evolve_species(ROOT / "experiments/ifs_species.toml", out=tmp_path / "run",
                                   overrides=overrides)  # fmt: skip
    assert list(table["generation"]) == [0, 1, 2]
    assert table["fitness"].is_monotonic_increasing  # elite 1: the best survives
    for name in ("generations.png", "terms.png", "generations.parquet", "best_points2d.npz"):
        assert (result.out / name).stat().st_size > 0
    best = OchoaObjective(species="tree_one", height=2.0)(result.best_phenotype)
    assert best == pytest.approx(result.best_fitness)
    assert set(TERMS) <= set(result.summary["terms"]["ochoa"])


# --------------------------------------------------------------------------- silhouettes


def test_the_silhouette_objective_scores_attractors_against_a_2d_target():
    from growsim.objectives.silhouette import SilhouetteObjective

    obj = SilhouetteObjective(target_model="ifs2d", target_preset="fern", views="front", size=64)
    assert obj.target.shape == (1, 64, 64)
    fern = ifs2d.develop(ifs2d.PRESETS["fern"], seed=9)  # another sample of the same fern
    assert obj.exact(fern) > 0.97
    assert obj.exact(ifs2d.develop(ifs2d.PRESETS["tree"])) < 0.5
    blurred = SilhouetteObjective(target_model="ifs2d", target_preset="fern", views="front",
                                  blur=1.0)  # fmt: skip
    assert blurred(fern) > blurred(ifs2d.develop(ifs2d.PRESETS["bush"]))
    with pytest.raises(ConfigError, match="views = 'front'"):
        SilhouetteObjective(target_model="ifs2d", target_preset="fern")


def test_the_fit_setup_is_the_fern_fit_experiment():
    import tomllib

    with open(ROOT / "experiments/ifs_fern_fit.toml", "rb") as fh:
        cfg = tomllib.load(fh)
    tables = ifs2d.fit_tables()
    assert tables["model"] == cfg["model"] and tables["ga"] == cfg["ga"]
    assert tables["output"] == cfg["output"]


def test_fit_image_fits_a_2d_code_to_one_picture(tmp_path):
    import json

    from growsim.cli import main
    from growsim.fitting.setups import fit_config

    cfg = fit_config("fern.png", model="ifs2d")
    assert cfg["model"]["kind"] == "ifs2d" and cfg["objective"][0]["views"] == "front"
    with pytest.raises(UserInputError, match="one view"):
        fit_config("fern.png", "side.png", model="ifs2d")
    picture = tmp_path / "fern.png"
    ifs2d.develop(ifs2d.PRESETS["fern"]).screenshot(picture, view="front", size=(300, 300))
    out = tmp_path / "fit"
    args = ["fit-image", str(picture), "--model", "ifs2d", "--out", str(out), "--quiet",
            "--evaluations", "200", "--sizes", "64"]  # fmt: skip
    assert main(args) == 0
    fit = json.loads((out / "fit.json").read_text())
    assert fit["views"] == ["front"] and 0.0 < fit["ncc"] <= 1.0
    assert (out / "attractor.png").stat().st_size > 0


def test_collage_of_the_fern_is_the_fern():
    from growsim.objectives.collage import CollageObjective, collage

    obj = CollageObjective(target_model="ifs2d", target_preset="fern", size=64)
    fern = ifs2d.develop(ifs2d.PRESETS["fern"], seed=3)
    w = collage(obj.target, fern.maps, fern.framing(64))
    assert w.shape == obj.target.shape and (w & obj.target).sum() / w.sum() > 0.9
    assert obj(fern) > 0.9 > obj(ifs2d.develop(ifs2d.PRESETS["tree"]))
    # the collage judges the maps on the target: a map that misses it scores lower
    moved = dict(ifs2d.PRESETS["fern"], e_3=1.0)
    assert obj(ifs2d.develop(moved)) < obj(fern)


def test_the_fern_fit_experiment_compiles():
    from growsim.experiment import load_plan

    plan = load_plan(ROOT / "experiments/ifs_fern_fit.toml")
    assert [o.name for o in plan.objectives] == ["silhouette", "collage"]
    assert len(plan.evolved) == 28
    fern = ifs2d.develop({**ifs2d.PRESETS["fern"], "iterations": 20000})
    assert plan.objectives[0].exact(fern) > 0.99  # the same fern, the same points
