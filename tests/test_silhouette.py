"""The silhouette objective: options, targets, scoring any plant, the ifs3d fast path."""

from __future__ import annotations

import re

import numpy as np
import pytest
from conftest import ROOT
from PIL import Image

from growsim.errors import ConfigError, UserInputError
from growsim.kernels.views import ncc
from growsim.models import ifs3d
from growsim.objectives import get_objective
from growsim.objectives.silhouette import SilhouetteObjective, plant_views
from growsim.phenotypes.plant import Plant

NAMES = [p.name for p in ifs3d.PARAMS]


def _row(params):
    return [params[n] for n in NAMES]


@pytest.fixture(scope="module")
def table1_obj():
    return SilhouetteObjective(target_model="ifs3d", target_preset="table1")


def test_registered_and_scores_table1(table1_obj):
    assert get_objective("silhouette") is SilhouetteObjective
    assert table1_obj(ifs3d.develop(ifs3d.PRESETS["table1"])) == 1.0
    # docs/reproduction.md's Kuwahara row gives Table 2's estimates scored by this objective
    row = next(ln for ln in (ROOT / "docs" / "reproduction.md").read_text().splitlines()
               if ln.startswith("| Kuwahara: Table 2's estimates"))  # fmt: skip
    m = re.search(r"GA (0\.\d{3}), gradient (0\.\d{3})", row)
    assert m, row
    for name, doc in zip(("paper_ga", "paper_gradient"), m.groups()):
        s = table1_obj(ifs3d.develop(ifs3d.PRESETS[name]))
        assert s == pytest.approx(float(doc), abs=5e-4), (name, s, doc)


def test_batch_equals_call_for_ifs3d(table1_obj):
    rng = np.random.default_rng(1)
    spec = ifs3d.PARAMS
    rows = np.array(
        [[rng.uniform(p.low, p.high) for p in spec] for _ in range(6)]
        + [_row(ifs3d.PRESETS[k]) for k in ifs3d.PRESETS]
    )
    rows[:, 0], rows[:, 1] = 5, 5
    rows[:, NAMES.index("leaves")] = np.round(rows[:, NAMES.index("leaves")])  # some leafy
    got = table1_obj.batch(ifs3d.MODEL, rows, NAMES, np.zeros(len(rows), np.uint64))
    want = [table1_obj(ifs3d.develop(dict(zip(NAMES, r)))) for r in rows]
    np.testing.assert_allclose(got, want, atol=1e-12)
    # columns in any order; a smaller depth and fewer maps grouped apart
    perm = np.random.default_rng(0).permutation(len(NAMES))
    got2 = table1_obj.batch(ifs3d.MODEL, rows[:, perm], [NAMES[i] for i in perm])
    np.testing.assert_allclose(got2, got)
    spec3 = ifs3d.param_spec({"n_maps": 3})
    p3 = {p.name: p.default for p in spec3} | {"n_maps": 3, "depth": 4}
    names3 = [p.name for p in spec3]
    b3 = table1_obj.batch(ifs3d.MODEL, np.array([[p3[n] for n in names3]]), names3)
    assert b3[0] == pytest.approx(table1_obj(ifs3d.develop(p3)))


@pytest.mark.parametrize("blur", [0.0, 1.5])
def test_one_view_batch_equals_call(blur):
    """``views = "front"`` (one picture) takes the population kernel too, framing each
    tree by its front's own extent as the one-by-one path does."""
    obj = SilhouetteObjective(target_model="ifs3d", target_preset="table1", views="front",
                              blur=blur)  # fmt: skip
    rng = np.random.default_rng(4)
    rows = np.array([[rng.uniform(p.low, p.high) for p in ifs3d.PARAMS] for _ in range(6)])
    rows[:, NAMES.index("leaves")] = 0  # bare: every row through the kernel
    rows = np.vstack([rows, _row(ifs3d.PRESETS["table1"]), _row(ifs3d.PRESETS["paper_ga"])])
    rows[:, 0], rows[:, 1] = 5, 5
    got = obj.batch(ifs3d.MODEL, rows, NAMES)
    want = [obj(ifs3d.develop(dict(zip(NAMES, r)))) for r in rows]
    np.testing.assert_allclose(got, want, atol=1e-12)
    assert got[6] > 0.99


def test_blur_option_batch_equals_call_and_exact_is_binary(table1_obj):
    obj = SilhouetteObjective(target_model="ifs3d", target_preset="table1", blur=1.5)
    rng = np.random.default_rng(3)
    rows = np.array([[rng.uniform(p.low, p.high) for p in ifs3d.PARAMS] for _ in range(4)])
    rows[:, NAMES.index("leaves")] = np.round(rows[:, NAMES.index("leaves")])
    rows = np.vstack([rows, _row(ifs3d.PRESETS["table1"]), _row(ifs3d.PRESETS["paper_ga"])])
    rows[:, 0], rows[:, 1] = 5, 5
    got = obj.batch(ifs3d.MODEL, rows, NAMES)
    plants = [ifs3d.develop(dict(zip(NAMES, r))) for r in rows]
    np.testing.assert_allclose(got, [obj(p) for p in plants], atol=1e-12)
    # the true tree still scores near 1 (anti-aliased vs binary target), and far better
    # than the paper's estimates; exact() is the binary NCC whatever the blur
    assert got[4] > 0.99 and got[5] < got[4] - 0.1
    assert [obj.exact(p) for p in plants] == [table1_obj(p) for p in plants]
    # partial credit: blurred scores exceed binary ones away from the target
    assert (got[:4] > np.array([table1_obj(p) for p in plants[:4]])).all()


def test_batch_none_for_other_models(table1_obj):
    from growsim.models import get_model
    from growsim.models.base import Model

    class NamedOnly(Model):  # the name alone does not give the fast path: the capability does
        name = "ifs3d"

        def develop(self, params, *, seed=None, env=None):
            raise AssertionError("not developed here")

    other = get_model("honda")
    assert table1_obj.batch(other, np.zeros((2, 3)), ["a", "b", "c"]) is None
    assert table1_obj.batch(NamedOnly(), np.zeros((2, 3)), ["a", "b", "c"]) is None
    wide = SilhouetteObjective(target_model="ifs3d", target_preset="table1", line_width="radius")
    assert wide.batch(ifs3d.MODEL, np.array([_row(ifs3d.PRESETS["table1"])]), NAMES) is None
    assert wide(ifs3d.develop(ifs3d.PRESETS["table1"])) == 1.0


def test_batch_uses_the_map_groups_capability(table1_obj):
    class Renamed(type(ifs3d.MODEL)):  # any model declaring map_groups
        name = "my_ifs"

    assert "map_groups" in Renamed.capabilities
    rows = np.array([_row(ifs3d.PRESETS[k]) for k in ifs3d.PRESETS])
    got = table1_obj.batch(Renamed(), rows, NAMES)
    np.testing.assert_array_equal(got, table1_obj.batch(ifs3d.MODEL, rows, NAMES))
    assert got[0] == 1.0 and (got[1:] < 1.0).all()


def test_any_plant_scores():
    # a generic plant (not an IFS): an upright Y; scored against itself and a bent variant
    pts = [[0, 0, 0], [0, 1, 0], [-0.5, 1.6, 0.2], [0.5, 1.5, -0.3]]
    y = Plant.from_points(pts, parent=[-1, 0, 0], point_parent=[-1, 0, 1, 1])
    bent = Plant.from_points(
        [[0, 0, 0], [0, 1, 0], [-0.9, 1.1, 0.2], [0.5, 1.5, -0.3]],
        parent=[-1, 0, 0],
        point_parent=[-1, 0, 1, 1],
    )
    v = plant_views(y, 32)
    assert v.shape == (2, 32, 32) and v[0, 31, 16] == 1
    obj = SilhouetteObjective(target_model="ifs3d", target_preset="table1", size=32)
    obj.target = v  # score against the Y's own silhouette
    assert obj(y) == 1.0
    assert 0 < obj(bent) < 1.0
    assert obj(Plant.empty()) == 0.0


def test_ncc_and_area_rejection():
    a = np.zeros((2, 8, 8), np.uint8)
    a[:, 2, :] = 1
    assert ncc(a, a) == 1.0
    b = np.zeros_like(a)
    b[:, 5, :] = 1
    assert ncc(a, b) == 0.0
    big = np.ones_like(a)
    assert ncc(big, a) == pytest.approx(np.sqrt(8 / 64))
    assert ncc(big, a, area_rejection=True) == 0.0
    assert ncc(np.zeros_like(a), a) == 0.0


def test_area_rejection_in_batch():
    obj = SilhouetteObjective(target_model="ifs3d", target_preset="table1", area_rejection=True)
    sparse = dict(ifs3d.PRESETS["table1"]) | {f"s_{k}": 0.1 for k in range(1, 6)}
    plain = SilhouetteObjective(target_model="ifs3d", target_preset="table1")
    row = np.array([[sparse[n] for n in NAMES]])
    assert plain.batch(ifs3d.MODEL, row, NAMES)[0] > 0
    assert obj.batch(ifs3d.MODEL, row, NAMES)[0] == 0.0
    assert obj(ifs3d.develop(sparse)) == 0.0


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({}, "no target"),
        ({"target_model": "ifs3d", "size": 4}, "size"),
        ({"target_model": "ifs3d", "size": 64.0}, "size"),
        ({"target_model": "ifs3d", "line_width": "fat"}, "line_width"),
        ({"target_model": "ifs3d", "polarity": "dark-ish"}, "polarity"),
        ({"target_model": "ifs3d", "threshold": 1.5}, "threshold"),
        ({"target_model": "ifs3d", "area_rejection": "yes"}, "area_rejection"),
        ({"target_model": "nope"}, "target_model"),
        ({"target_model": "ifs3d", "target_preset": "oak"}, "target_preset"),
        ({"target_model": "ifs3d", "target_params": {"s_1": 5.0}}, "s_1"),
        ({"target_model": "ifs3d", "front": "a.png", "side": "b.png"}, "not both"),
        ({"front": "a.png"}, "side"),
        ({"side": "a.png"}, "front"),
        ({"target_preset": "table1"}, "target_model"),
        ({"target_model": "ifs3d", "mask_front": "m.png"}, "mask"),
        ({"target_model": "ifs3d", "blur": -1.0}, "blur"),
        ({"target_model": "ifs3d", "blur": "wide"}, "blur"),
        ({"target_model": "ifs3d", "area_band": [1.2, 0.8]}, "area_band"),
        ({"target_model": "ifs3d", "area_band": [0.8]}, "area_band"),
        ({"target_model": "ifs3d", "trunk_band": [0.0, 2.0]}, "trunk_band"),
        ({"target_model": "ifs3d", "scales": 0}, "scales"),
        ({"target_model": "ifs3d", "outline": "maybe"}, "outline"),
    ],
)
def test_bad_options(kwargs, match):
    with pytest.raises(ConfigError, match=match):
        SilhouetteObjective(**kwargs)


def test_picture_target_round_trip(tmp_path):
    """A target drawn as a big photo-like picture frames back onto the rendered target."""
    tree = ifs3d.develop(ifs3d.PRESETS["table1"])
    views = plant_views(tree, 64)
    paths = []
    for v, label in zip(views, ("front", "side")):
        # 5x up-sampled, dark on light, with a wide margin
        img = np.full((400, 500), 235, np.uint8)
        img[40:360, 90:410] = np.where(np.kron(v, np.ones((5, 5))) > 0, 30, 235)
        p = tmp_path / f"{label}.png"
        Image.fromarray(img).save(p)
        paths.append(p)
    obj = SilhouetteObjective(front=str(paths[0]), side=str(paths[1]))
    assert ncc(obj.target, views) > 0.9
    assert obj(tree) > 0.9
    assert obj(tree) > obj(ifs3d.develop(ifs3d.PRESETS["paper_ga"])) + 0.2


def test_bad_pictures(tmp_path):
    good = tmp_path / "good.png"
    img = np.full((50, 50), 255, np.uint8)
    img[10:50, 25] = 0
    Image.fromarray(img).save(good)
    blank = tmp_path / "blank.png"
    Image.fromarray(np.full((50, 50), 255, np.uint8)).save(blank)
    junk = tmp_path / "junk.png"
    junk.write_bytes(b"not an image")
    with pytest.raises(UserInputError, match=r"junk\.png"):
        SilhouetteObjective(front=str(good), side=str(junk))
    with pytest.raises(UserInputError, match=r"missing\.png"):
        SilhouetteObjective(front=str(tmp_path / "missing.png"), side=str(good))
    with pytest.raises(UserInputError, match=r"blank\.png"):
        SilhouetteObjective(front=str(good), side=str(blank))
    obj = SilhouetteObjective(front=str(good), side=str(good), size=16)
    assert obj.target[:, :, 8].all()


def test_leaves_are_drawn_as_their_blades_are_seen():
    """line_width = "radius": a leaf is a flat blade facing up (issue 16): seen edge-on
    (its axis along the view's x, the blade across it in depth) it is a line; seen
    face-on it is as wide as the blade, with 3/4 of its length x width."""
    from growsim.phenotypes.plant import LEAF, STEM, Plant

    # a trunk 0 -> 10 up, a leaf from its top along +x, 4 long, blade 2 * 0.8 wide
    pts = [[0, 0, 0], [0, 10, 0], [4, 10, 0]]
    plant = Plant.from_points(pts, parent=[-1, 0], point_parent=[-1, 0, 1],
                              radius=[0.05, 0.8], kind=[STEM, LEAF])  # fmt: skip
    front, side = plant_views(plant, 64, "radius")
    # the front sees the blade edge-on (across it is z): a one-pixel line
    leaf_rows = np.flatnonzero(front[:, 40:].any(axis=1))
    assert leaf_rows.size == 1
    # the side sees it face-on (across it is the view's u = -z) but foreshortened along
    # its axis (x is depth): the blade's width shows around the trunk's top
    assert np.flatnonzero(side.any(axis=0)).size >= 5
    # the thin-line drawing is unchanged (the seed's rendering)
    thin = plant_views(plant, 64, "thin")
    assert thin[0, leaf_rows[0], 40:].sum() > 0 and thin[1].any(axis=0).sum() == 1
