"""Fitting trees to photos (issue 16): the photo segmentation and its refusals, one-picture
fits, leaves in the fitted spec, coarse-to-fine ``fit-image``."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from growsim.cli import main
from growsim.errors import UserInputError
from growsim.experiment import load_config
from growsim.fitting.setups import FIT_SETUPS, LEAF_MARGIN, PHOTO_SCORE, fit_config
from growsim.models import honda, ifs3d
from growsim.objectives.silhouette import SilhouetteObjective, plant_views
from growsim.phenotypes.plant import LEAF
from growsim.pictures.photo import segment_photo

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
from make_photos import EXTRA_PICTURES, PICTURES, make_photo

SKY, GROUND, BARK = (0.8, 0.87, 0.97), (0.36, 0.55, 0.25), (0.45, 0.35, 0.27)


def _scene(h=120, w=100, ground=100):
    rgb = np.ones((h, w, 3)) * SKY
    rgb[ground:] = GROUND
    return rgb


def _tree(rgb, top=20, bottom=108, col=50):
    rgb[top:bottom, col - 2 : col + 2] = BARK
    rgb[top + 15, col - 25 : col + 25] = BARK
    rgb[top + 30 : top + 32, col - 18 : col + 18] = BARK
    return rgb


@pytest.fixture(scope="module")
def photo(tmp_path_factory):
    """A 256 px JPEG render of a bare zelkova on a ground plane, and its true silhouette."""
    d = tmp_path_factory.mktemp("photo")
    _, truth, jpeg = make_photo(PICTURES[0], size=256)
    path = d / "zelkova.jpg"
    path.write_bytes(jpeg)
    return path, truth


def test_segmentation_of_a_render_matches_its_true_silhouette(photo):
    path, truth = photo
    seg = segment_photo(path)
    iou = (seg.tree & truth).sum() / (seg.tree | truth).sum()
    assert iou >= 0.9, iou  # 512 px: 0.96 (benchmarks/photo_fit.py)
    assert seg.horizon is not None and 0.6 * 256 < seg.horizon < 256
    assert not seg.ground[: seg.horizon - 5].any()  # no ground in the sky
    assert "ground from row" in seg.describe()


def test_synthetic_scene_ground_is_not_tree():
    seg = segment_photo(_tree(_scene()))
    assert seg.horizon == 100
    assert seg.tree[100:108, 48:52].all()  # the trunk's foot, in the ground band
    assert not seg.tree[100:, :40].any() and not seg.tree[:, :20].any()
    # a clean drawing (no ground): the same silhouette as the grey threshold
    from growsim.pictures.images import silhouette

    g = np.ones((60, 50))
    g[10:58, 24:26] = 0.1
    g[20, 10:40] = 0.1
    assert np.array_equal(segment_photo(g).tree, silhouette(g))


def test_thin_twigs_kept_and_broken_twigs_rejoin_the_tree():
    rgb = _tree(_scene())
    for k in range(12):  # a 1-pixel diagonal twig, paler towards its tip
        rgb[30 - k, 52 + k] = np.array(BARK) + (0.02 * (k - 7) if k > 7 else 0.0)
    rgb[2:20, 50] = BARK  # a leader above the trunk's top (row 20) ...
    rgb[[9, 16], 50] = SKY  # ... broken twice by a pixel as pale as the sky
    seg = segment_photo(rgb)
    diag = np.array([seg.tree[30 - k, 52 + k] for k in range(12)])
    assert diag.all(), np.nonzero(~diag)
    # the leader's top piece lies above the trunk piece's bounding box (with its margin):
    # it joins the tree across the gaps
    assert seg.tree[2:9, 50].all() and seg.tree[10:16, 50].all() and not seg.tree[9, 50]


def test_pale_bark_over_dark_ground_is_tree():
    """Below the horizon the background is the ground alone: bark there is tree even where
    its colour is near the sky's (the sky's model, extrapolated, used to take it)."""
    rgb = _tree(_scene())
    rgb[100:] = (0.30, 0.34, 0.20)  # a dark ground
    rgb[100:112, 48:52] = np.array(SKY) - 0.03  # the trunk's foot, lit, as pale as the sky
    seg = segment_photo(rgb)
    assert seg.tree[104:112, 48:52].all()


def _mixed(cover, tree=BARK, sky=SKY):
    """A pixel covered ``cover`` by the tree, as a camera sees it: the mean of the two
    colours in linear light (then sRGB again)."""
    from growsim.pictures.photo import linear_to_srgb, srgb_to_linear

    return linear_to_srgb(cover * srgb_to_linear(tree) + (1 - cover) * srgb_to_linear(sky))


def test_thin_twigs_are_tree_where_covered_at_least_half():
    """Twigs of known coverage on a known sky (each straddling two rows, mixed in linear
    light, with a little noise): the pixels covered at least half are tree, those covered
    0.3 or 0.45 are not, whatever the twig's width; the coverage read is the true one."""
    rgb = _scene()
    rgb[20:108, 47:53] = BARK  # a thick trunk (its inside gives the bark's colour)
    twigs = {34: (0.6, 0.3), 46: (0.45, 0.55), 58: (0.3, 0.7), 70: (0.4, 0.9)}
    for row, (upper, lower) in twigs.items():
        rgb[row, 53:90] = _mixed(upper)
        rgb[row + 1, 53:90] = _mixed(lower)
    rgb = np.clip(rgb + np.random.default_rng(1).normal(0, 0.004, rgb.shape), 0, 1)
    seg = segment_photo(rgb)
    for row, (upper, lower) in twigs.items():
        for r, cover in ((row, upper), (row + 1, lower)):
            got = seg.tree[r, 56:90]
            assert got.all() if cover >= 0.5 else not got.any(), (r, cover, got.mean())
            assert abs(np.median(seg.coverage[r, 56:90]) - cover) < 0.05, (r, cover)
    assert seg.tree[20:100, 47:53].all()
    # the same twig colours averaged as sRGB values (a render's anti-aliasing, not a
    # camera's) read darker: a pixel covered 0.45 is then taken (benchmarks/log/fitting.md)
    srgb = _scene()
    srgb[20:108, 47:53] = BARK
    srgb[46, 53:90] = 0.45 * np.array(BARK) + 0.55 * np.array(SKY)
    assert segment_photo(srgb).coverage[46, 60] > 0.5


@pytest.mark.parametrize("picture", EXTRA_PICTURES, ids=lambda p: p.name)
def test_segmentation_generalises_to_new_pictures(picture):
    """Pictures made after the thresholds were chosen (other species, seeds, skies)."""
    rgb, truth, _ = make_photo(picture, size=384)
    seg = segment_photo(rgb / 255.0)
    iou = (seg.tree & truth).sum() / (seg.tree | truth).sum()
    assert iou >= 0.93, iou  # 512 px: 0.985, 0.974 (benchmarks/log/fitting.md)


@pytest.mark.parametrize(
    "case, message",
    [
        ("clutter", "no sky along the top"),
        ("cut", "touches the picture's top edge"),
        ("floating", "no tree stands on the ground"),
        ("two", "other objects beside the tree"),
        ("faint", "hardly differs from its background"),
        ("blank", "uniform"),
    ],
)
def test_bad_segmentations_are_refused(case, message):
    rgb = _scene()
    if case == "clutter":
        rgb = _tree(rgb)
        rgb[:100] += np.random.default_rng(0).normal(0, 0.08, rgb[:100].shape)
        rgb = np.clip(rgb, 0, 1)
    elif case == "cut":
        rgb = _tree(rgb, top=0)
    elif case == "floating":
        rgb[30:60, 40:60] = BARK
    elif case == "two":
        rgb = _tree(rgb, col=30)
        rgb[40:100, 75:95] = (0.6, 0.2, 0.2)  # a big red box, apart from the tree
    elif case == "faint":  # no ground; the tree 12.9 Delta E darker than the sky
        rgb = np.ones((120, 100, 3)) * SKY
        rgb[20:120, 48:52] = np.array(SKY) - 0.14
        rgb[35, 25:75] = np.array(SKY) - 0.14
    elif case == "blank":
        rgb = np.ones((50, 50, 3))
    with pytest.raises(UserInputError, match=message):
        segment_photo(rgb, name="pic.jpg")


def test_a_faint_tree_is_settled_by_the_box_its_refusal_names():
    """A tree that hardly differs from its sky is refused naming ``--box`` (before: "use a
    picture with more contrast, or a mask"); with the box, GrabCut in it finds the tree
    (before: refused again)."""
    rgb = np.ones((120, 100, 3)) * SKY
    rgb[20:120, 48:52] = np.array(SKY) - 0.14
    rgb[35, 25:75] = np.array(SKY) - 0.14
    truth = np.zeros((120, 100), bool)
    truth[20:120, 48:52] = truth[35, 25:75] = True
    with pytest.raises(UserInputError, match=r"hardly differs.*give --box x0,y0,x1,y1"):
        segment_photo(rgb, name="pic.jpg")
    seg = segment_photo(rgb, name="pic.jpg", box=(20, 10, 80, 120))
    assert seg.method == "GrabCut in the box"
    assert (seg.tree & truth).sum() / (seg.tree | truth).sum() > 0.9


def test_mask_restricts_the_tree():
    rgb = _tree(_scene(), col=30)
    rgb[40:100, 75:95] = (0.6, 0.2, 0.2)
    mask = np.zeros(rgb.shape[:2])
    mask[:, :65] = 1.0
    seg = segment_photo(rgb, mask=mask)
    assert not seg.tree[:, 65:].any() and seg.tree[50, 30]


def test_one_picture_objective_frames_and_scores_the_front_alone(photo):
    path, _ = photo
    obj = SilhouetteObjective(front=str(path), views="front", segmentation="photo",
                              line_width="radius", size=32)  # fmt: skip
    assert obj.target.shape == (1, 32, 32) and set(obj.pictures) == {"front"}
    tree = honda.develop(honda.PRESETS["zelkova"])
    assert 0.5 < obj(tree) == obj.view_scores(tree)[0] <= 1.0
    # the front view's framing ignores the depth (the side is free; a bare tree: a leaf's
    # blade, facing up, is seen wider or narrower when the depth is stretched)
    tree = honda.develop({**honda.PRESETS["zelkova"], "leaves": 0})
    deep = tree.subset(np.ones(tree.n_segments, bool))
    deep.end[:, 2] *= 5.0
    deep.start[:, 2] *= 5.0
    assert np.array_equal(plant_views(deep, 32, "radius", views=1), obj.views(tree))
    with pytest.raises(Exception, match="views = 'front' fits the front picture alone"):
        SilhouetteObjective(front=str(path), side=str(path), views="front")
    with pytest.raises(Exception, match="apply to segmentation = 'threshold'"):
        SilhouetteObjective(front=str(path), side=str(path), segmentation="photo",
                            threshold=0.4)  # fmt: skip


def test_ifs3d_leaves_default_bare_and_fitted():
    bare = ifs3d.develop(ifs3d.PRESETS["table1"])
    assert bare.n_leaves == 0 and bare.n_segments == 3906
    leafy = ifs3d.develop({**ifs3d.PRESETS["table1"], "leaves": 2, "leaf_radius": 0.03})
    assert leafy.n_stems == 3906 and leafy.n_leaves == 2 * (5**5 + 5**4)
    assert (leafy.kind[3906:] == LEAF).all()
    np.testing.assert_array_equal(leafy.start[:3906], bare.start)
    # the population fast path leaves leafy rows out; the objective scores them one by one
    names = [p.name for p in ifs3d.PARAMS]
    rows = np.array(
        [[leafy.meta["params"][n] for n in names], [bare.meta["params"][n] for n in names]]
    )
    assert [r.tolist() for r, _, _ in ifs3d.map_groups(rows, names)] == [[1]]
    obj = SilhouetteObjective(target_model="ifs3d", target_preset="table1", size=32)
    np.testing.assert_allclose(obj.batch(ifs3d.MODEL, rows, names), [obj(leafy), obj(bare)])


def test_fit_config_fits_leaves_and_one_picture(photo):
    path, _ = photo
    for model, setup in FIT_SETUPS.items():
        cfg = load_config(fit_config(path, model=model, evaluations=500))
        assert set(setup.leaves) <= set(cfg.model.evolve)
        assert cfg.objective[0].views == "front" and cfg.objective[0].segmentation == "photo"
        assert cfg.objective[0].line_width == setup.line_width
        kept = load_config(fit_config(path, model=model, leaves=False))
        assert "leaves" not in kept.model.evolve
        if setup.bare:  # a bare tree: no leaves, none evolved
            bare = load_config(fit_config(path, model=model, leaves="bare"))
            assert bare.model.params["leaves"] == 0 and not set(setup.leaves) & set(
                bare.model.evolve
            )
            assert set(bare.model.evolve) == set(kept.model.evolve)
    with pytest.raises(UserInputError, match="--leaves"):
        fit_config("tree.jpg", model="honda", leaves="some")
    with pytest.raises(UserInputError, match="fit setup"):
        fit_config("tree.jpg", model="nope")
    with pytest.raises(UserInputError, match="--segmentation threshold"):
        fit_config("tree.jpg", threshold=0.4)


def _small_fit(path, out, refine: int, restarts: int, *more: str) -> list[str]:
    """fit-image arguments of a small Honda fit of ``path`` (200 evaluations, 32 -> 64 px)."""
    args = ["fit-image", str(path), "--model", "honda", "--out", str(out), "--quiet"]
    args += ["--evaluations", "200", "--sizes", "32,64", "--refine", str(refine)]
    return [*args, "--restarts", str(restarts), *more]


def test_fit_image_one_photo_coarse_to_fine(photo, tmp_path, capsys):
    path, _ = photo
    out = tmp_path / "fit"
    args = _small_fit(path, out, 40, 2, "--arrange", "40", "--blur", "0.7")
    assert main(args) == 0
    fit = json.loads((out / "fit.json").read_text())
    stages = [(s["size"], s["stage"]) for s in fit["stages"] if s["stage"] != "discrete"]
    assert stages == [(32, "ga"), (32, "arrange"), (64, "refine"), (64, "arrange")]
    assert fit["size"] == 64
    # a leafy tree's count of leaves a twig (the setup's range) is swept at every size, before
    # the arrangement
    swept = [(s["size"], s["evaluations"]) for s in fit["stages"] if s["stage"] == "discrete"]
    lo, hi = FIT_SETUPS["honda"].leaves["leaves"]
    n = hi - lo + 1  # every count of leaves a twig of the setup's range
    assert swept == ([(32, n), (64, n)] if fit["leaves"]["chosen"] == "leafy" else [])
    # a photo's searches score the shape score (blurred at the first size) and report the
    # binary NCC beside it; no search ends worse than it starts
    for st in fit["stages"][1:]:
        assert st["score"] >= st["score_start"] and 0.0 < st["ncc"] <= 1.0
    # every search starts where the one before it at that size ended
    last = fit["stages"][-1]
    assert last["stage"] == "arrange" and last["score_start"] == fit["stages"][-2]["score"]
    # the fitted arrangement regrows the fitted tree
    draws = np.array(fit["draws"])
    assert draws.shape[1] == 9
    tree = honda.develop(fit["params"], draws=draws)
    obj = SilhouetteObjective(front=str(path), views="front", segmentation="photo", size=64,
                              line_width="radius", **PHOTO_SCORE)  # fmt: skip
    assert obj.exact(tree) == pytest.approx(fit["ncc"], abs=1e-12)
    assert obj(tree) == pytest.approx(fit["score"], abs=1e-12)
    assert 0.3 < fit["ncc"] <= 1.0 and fit["views"] == ["front"]
    assert fit["area_ratio"]["front"] > 0
    for name in ("tree.glb", "silhouettes.png", "silhouette_front.png", "segmentation_front.png",
                 "bare-0/best.json", "bare-0/history.parquet", "leafy-1/best.json"):  # fmt: skip
        assert (out / name).is_file(), name
    # --leaves auto: a bare and a leafy tree fitted at the first size (two restarts each),
    # judged at the final size, the leafy one kept only if clearly better
    leaves = fit["leaves"]
    assert leaves["mode"] == "auto" and set(leaves["score"]) == {"bare", "leafy"}
    assert sorted(leaves["first_size"]) == [f"honda {k} seed {s}" for k in ("bare", "leafy")
                                            for s in (0, 1)]  # fmt: skip
    score = leaves["score"]
    kept = "leafy" if score["leafy"] > score["bare"] + LEAF_MARGIN else "bare"
    assert leaves["chosen"] == kept
    assert fit["params"]["leaves"] == 0 or kept == "leafy"  # a leafy fit may sweep to 0
    # both restarts of the kept kind went on to the final size, the better one kept
    runs = leaves["runs"]
    assert sorted(runs) == [f"honda {kept} seed {s}" for s in (0, 1)]
    assert fit["score"] == max(r["score"] for r in runs.values())
    used = np.asarray(Image.open(out / "silhouette_front.png")) < 128
    assert np.array_equal(used, segment_photo(path).tree)  # the silhouette used, as is
    text = capsys.readouterr().out
    assert "mean NCC" in text and "64 px refine" in text and "64 px arrange" in text


def test_fit_image_is_a_library_call(photo, tmp_path, capsys):
    """fit_image from Python (no argparse, nothing printed): what it returns is what it
    wrote, and the kept fit rebuilds its tree; bad options are refused before any work."""
    from growsim.files import jsonable
    from growsim.fitting import FitResult, fit_image

    path, _ = photo
    out = tmp_path / "fit"
    r = fit_image(path, out=out, model="honda", evaluations=200, sizes=(32,), leaves="bare",
                  restarts=1, arrange=20, progress=False)  # fmt: skip
    assert isinstance(r, FitResult) and capsys.readouterr().out == ""
    fit = json.loads((out / "fit.json").read_text())
    assert fit == json.loads(json.dumps(jsonable(r.summary)))
    assert [s["stage"] for s in r.stages] == ["ga", "arrange"] and r.size == 32
    assert r.params == fit["params"] and r.params["leaves"] == 0
    assert np.array_equal(r.draws, np.array(fit["draws"])) and r.draws.shape[1] == 9
    assert r.out == r.run == out and r.shape == out / "tree.glb"
    assert all(p.is_file() for p in r.files) and r.files[-1] == out / "fit.json"
    assert r.ncc == pytest.approx(r.stages[-1]["ncc"], abs=1e-12)
    again = r.plan.fitness().phenotype_of(r.x, draws=r.draws).phenotype
    assert r.plan.objectives[0].exact(again) == pytest.approx(r.ncc, abs=1e-12)
    assert np.array_equal(again.end, r.phenotype.end)
    for bad, message in (({"sizes": (64, 32)}, "increasing raster sizes"),
                         ({"leaves": "some"}, "--leaves"),
                         ({"evaluations": 10}, "--evaluations: at least 100")):  # fmt: skip
        with pytest.raises(UserInputError, match=message):
            fit_image(path, out=tmp_path / "never", model="honda", **bad)
    assert not (tmp_path / "never").exists()


def test_fit_image_carries_the_best_restarts_past_the_first_size(photo, tmp_path, capsys):
    """--carry N: of each kind's restarts, the N that scored best at the end of the first
    size go on to the finer sizes; every restart's first-size NCC is reported."""
    path, _ = photo
    out = tmp_path / "fit"
    args = _small_fit(path, out, 20, 3, "--arrange", "10", "--carry", "1")
    assert main(args) == 0
    leaves = json.loads((out / "fit.json").read_text())["leaves"]
    first = leaves["first_size"]
    assert len(first) == 6 and len(leaves["runs"]) == 1
    kind = leaves["chosen"]
    best = max((k for k in first if k.startswith(f"honda {kind}")), key=lambda k: first[k]["score"])
    assert list(leaves["runs"]) == [best]
    assert main([*args[:-2], "--carry", "-1"]) == 2
    assert "--carry: at least 0" in capsys.readouterr().err


def test_arrange_places_the_limbs_where_the_picture_has_them():
    """The search over Honda's random draws: a tree whose arrangement (seed 7) is not the
    fit's (seed 3) is matched better, the score never falls, the draws regrow the score;
    a model without the ``draws`` capability is left as it is; refine holds the draws."""
    from growsim.experiment import load_plan
    from growsim.fitting.setups import arrange, exact_score, refine

    small = {"generations": 7, "leaves": 0}
    cfg = {"model": {"kind": "honda", "preset": "zelkova", "evolve": {"f": [0.9, 1.0]},
                     "params": small},
           "objective": [{"kind": "silhouette", "target_model": "honda",
                          "target_preset": "zelkova", "views": "front", "size": 48,
                          "line_width": "radius",
                          "target_params": {**small, "seed": 7}}]}  # fmt: skip
    plan = load_plan(cfg)
    x = np.array([0.95])
    draws, score, start = arrange(plan, x, evaluations=300, seed=1)
    assert start == pytest.approx(exact_score(plan, x)) and score > start + 0.05
    assert score == pytest.approx(exact_score(plan, x, draws))
    # refining with the draws held starts where the arrangement ended
    _, s2, s2_start = refine(plan, x, evaluations=20, draws=draws)
    assert s2_start == pytest.approx(score) and s2 >= s2_start
    # continuing from given draws never ends worse
    again, s3, s3_start = arrange(plan, x, draws, evaluations=30, seed=2)
    assert s3_start == pytest.approx(score) and s3 >= score and again.shape == draws.shape
    ifs = {"model": {"kind": "ifs3d", "preset": "table1", "evolve": {"s_1": True}},
           "objective": [{"kind": "silhouette", "target_model": "ifs3d",
                          "target_preset": "table1", "size": 32}]}  # fmt: skip
    none, s4, s5 = arrange(load_plan(ifs), np.array([0.5]), evaluations=10)
    assert none is None and s4 == s5


def test_sweep_discrete_finds_the_count_of_leaves():
    """Every value of a discrete parameter is tried, the others fixed: a fit stuck at the
    wrong count of leaves finds the picture's; the score never falls; a fit without
    discrete parameters is left as it is."""
    from growsim.experiment import load_plan
    from growsim.fitting.setups import exact_score, sweep_discrete

    small = {"generations": 7}
    cfg = {"model": {"kind": "honda", "preset": "cherry", "params": small,
                     "evolve": {"leaves": True, "leaf_radius": [0.5, 3.0]}},
           "objective": [{"kind": "silhouette", "target_model": "honda", "size": 48,
                          "target_preset": "cherry", "line_width": "radius", "target_seed": 3,
                          "target_params": {**small, "leaves": 5,
                                            "leaf_radius": 1.5}}]}  # fmt: skip
    plan = load_plan(cfg)
    x, score, start, n = sweep_discrete(plan, np.array([1.0, 1.5]))
    assert x.tolist() == [5.0, 1.5] and score == pytest.approx(1.0) and start < 0.95
    assert n == 9 and score == pytest.approx(exact_score(plan, x))
    # already best: unchanged, never worse
    x2, s2, s2_start, _ = sweep_discrete(plan, x)
    assert x2.tolist() == x.tolist() and s2 == s2_start == pytest.approx(score)
    bare = {**cfg, "model": {**cfg["model"], "evolve": {"leaf_radius": [0.5, 3.0]}}}
    x3, s3, s3_start, n3 = sweep_discrete(load_plan(bare), np.array([1.0]))
    assert x3.tolist() == [1.0] and s3 == s3_start and n3 == 1


def test_fit_image_refuses_a_bad_photo_before_evolving(tmp_path, capsys):
    rgb = _tree(_scene(), top=0)
    bad = tmp_path / "cut.png"
    Image.fromarray(np.round(255 * rgb).astype(np.uint8)).save(bad)
    out = tmp_path / "never"
    assert main(["fit-image", str(bad), "--model", "honda", "--out", str(out)]) == 2
    assert "cut.png: the tree touches the picture's top edge" in capsys.readouterr().err
    assert not (out / "history.parquet").exists()
    # --mask keeps working: masking the top rows out lets it through to the checks
    mask = np.full(rgb.shape[:2], 255, np.uint8)
    mask[:5] = 0
    mpath = tmp_path / "mask.png"
    Image.fromarray(mask).save(mpath)
    cfg = fit_config(bad, model="honda", mask_front=mpath)
    assert cfg["objective"][0]["mask_front"] == str(mpath.absolute())


def test_fit_image_refuses_bad_arrange_and_blur(photo, tmp_path, capsys):
    path, _ = photo
    base = ["fit-image", str(path), "--model", "honda", "--out", str(tmp_path / "x")]
    assert main([*base, "--arrange", "-1"]) == 2
    assert "--arrange: at least 0" in capsys.readouterr().err
    assert main([*base, "--blur", "9"]) == 2  # 18 px at 128 (the next-to-last size)
    assert "--blur: expected 0 or more pixels, at most 16" in capsys.readouterr().err
    assert not (tmp_path / "x").exists()


def test_the_shape_score_is_not_won_by_a_blob_or_a_lone_trunk():
    """Binary NCC at 64 px pays a crown-covering blob and a lone trunk better than a tree
    whose limbs are a little off; the photo fits' shape score (pyramid, area and trunk
    width bands) ranks the near tree first."""
    from scipy.ndimage import binary_closing, binary_fill_holes, shift

    from growsim.kernels.views import ncc
    from growsim.objectives.silhouette import shape_score

    tree = honda.develop(honda.PRESETS["zelkova"], seed=3)
    target = plant_views(tree, 64, "radius", views=1)
    near = shift(target[0], (0, 2), order=0)[None]  # every limb two pixels off
    blob = binary_fill_holes(binary_closing(target[0] > 0, iterations=4)).astype(np.uint8)[None]
    trunk = np.zeros_like(target)
    cols = np.flatnonzero(target[0, -3:].any(axis=0))
    trunk[0, :, cols.min() : cols.max() + 1] = 1
    plain = {k: ncc(v, target) for k, v in (("near", near), ("blob", blob), ("trunk", trunk))}
    shaped = {k: shape_score(v, target, **PHOTO_SCORE)
              for k, v in (("near", near), ("blob", blob), ("trunk", trunk))}  # fmt: skip
    assert plain["blob"] > plain["near"]  # what the fits found before
    assert shaped["near"] > shaped["blob"] and shaped["near"] > shaped["trunk"]


def test_budget_scales_every_search_and_auto_fits_each_model(photo, tmp_path):
    """--budget X multiplies the first stage's, the refinements' and the arrangement
    searches' evaluations; --model auto (the default) fits every photo model at the first
    size and writes what it kept and why."""
    from growsim.fitting import fit_image

    path, _ = photo
    kw = dict(sizes=(32, 64), restarts=1, progress=False)
    r = fit_image(path, out=tmp_path / "half", model="honda", leaves="bare", budget=0.1, **kw)
    stages = {(s["size"], s["stage"]): s["evaluations"] for s in r.stages}
    assert stages[64, "refine"] == 100 and stages[64, "arrange"] == 100
    assert 750 <= stages[32, "ga"] <= 850  # 10 % of 7,500 (the GA ends whole generations)
    auto = fit_image(path, out=tmp_path / "auto", budget=0.05, **kw)
    s = auto.summary
    assert set(s["models"]) == {"ifs3d", "honda"} and auto.model in s["models"]
    assert s["choices"]["model"]["value"] == "auto" and "photo" in s["choices"]["model"]["why"]
    assert auto.model == max(s["models"], key=s["models"].get)
    assert (tmp_path / "auto" / "ifs3d-bare").is_dir()
    assert (tmp_path / "auto" / "honda-leafy").is_dir()
    for bad in (0, -1, 1000):
        with pytest.raises(UserInputError, match="--budget"):
            fit_image(path, out=tmp_path / "never", budget=bad)
    assert not (tmp_path / "never").exists()


@pytest.mark.parametrize("where", ["second GA", "finer size"])
def test_fit_image_resumes_an_interrupted_fit(photo, tmp_path, monkeypatch, capsys, where):
    """One --out holds one fit: a second fit there is refused before any work, naming
    what is there; --resume continues an interrupted fit from its runs' last finished
    stages to the same fit as an uninterrupted one, and refuses a finished fit."""
    from growsim.fitting import fit as fitting
    from growsim.fitting import runs

    path, _ = photo
    kw = dict(model="honda", evaluations=200, sizes=(32, 64), refine=20, arrange=20,
              restarts=2, workers=1, progress=False)  # fmt: skip
    whole = fitting.fit_image(path, out=tmp_path / "whole", **kw)
    drop = lambda stages: [{k: v for k, v in s.items() if k != "seconds"} for s in stages]  # noqa: E731
    if where == "second GA":  # the runs side by side on two processes: the same fit
        apart = fitting.fit_image(path, out=tmp_path / "apart", **{**kw, "workers": 2})
        assert apart.params == whole.params and drop(apart.stages) == drop(whole.stages)
        assert apart.summary["leaves"] == {
            **whole.summary["leaves"],
            "run": apart.summary["leaves"]["run"],
            "runs": apart.summary["leaves"]["runs"],
        }
    name, real = (
        ("evolve", runs.evolve) if where == "second GA" else ("size_stages", runs.size_stages)
    )
    calls = []

    def cut(*a, **k):
        calls.append(1)
        if (where == "second GA" and len(calls) == 2) or (where == "finer size" and a[1] == 1):
            raise KeyboardInterrupt
        return real(*a, **k)

    monkeypatch.setattr(runs, name, cut)
    with pytest.raises(KeyboardInterrupt):
        fitting.fit_image(path, out=tmp_path / "cut", **kw)
    monkeypatch.setattr(runs, name, real)
    with pytest.raises(UserInputError, match="fit-image --resume"):
        fitting.fit_image(path, out=tmp_path / "cut", **kw)
    assert main(["fit-image", "--resume", str(tmp_path / "cut"), "--model", "ifs3d"]) == 2
    assert "--resume: give the fit's directory alone (not --model)" in capsys.readouterr().err
    again = fitting.fit_image(out=tmp_path / "cut", resume=True, progress=False)
    assert again.params == whole.params and again.ncc == whole.ncc
    assert drop(again.stages) == drop(whole.stages)
    assert again.summary["leaves"]["first_size"] == whole.summary["leaves"]["first_size"]
    with pytest.raises(UserInputError, match="finished"):
        fitting.fit_image(out=tmp_path / "cut", resume=True)
