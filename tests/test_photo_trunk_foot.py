"""The trunk's foot (issue 41): a flat piece of ground joined at its foot (a shadow, a
strip of darker ground, mulch) is dropped, and the trunk's flare, its lean and the twigs
along it stay (:func:`growsim.pictures.foot.trim_foot`); a flat patch of ground below the
cut is not a hidden stretch of the trunk (``_hidden_trunk``)."""

from __future__ import annotations

import numpy as np
import pytest

import growsim.pictures.photo as photo
from growsim.pictures.foot import trim_foot

H, W, HORIZON = 240, 220, 195


def _standing(lean=0.0, foot=225):
    """A silhouette: an oval crown (rows 20-139), a trunk 13 pixels wide from row 120 to
    ``foot``, leaning ``lean`` pixels a row."""
    yy, xx = np.mgrid[:H, :W]
    crown = (yy - 80) ** 2 / 60**2 + (xx - 110) ** 2 / 80**2 < 1
    trunk = (np.abs(xx - 110 - lean * np.clip(yy - 120, 0, None)) <= 6) & (yy >= 120) & (yy < foot)
    return crown, trunk


def test_a_flat_strip_at_the_foot_is_dropped():
    crown, trunk = _standing()
    strip = np.zeros_like(trunk)
    strip[218:225, 40:104] = True  # a shadow cast to the left
    out = trim_foot(crown | trunk | strip)
    assert (out & trunk).sum() == trunk.sum() and (out & crown).sum() == crown.sum()
    # of the strip, at most the trunk's flare beside it stays (half its width)
    assert (out & strip).sum() <= 7 * 7


def test_what_only_the_strip_joined_goes_with_it():
    crown, trunk = _standing()
    strip = np.zeros_like(trunk)
    strip[220:225, 30:104] = True
    blob = np.zeros_like(trunk)
    blob[200:220, 30:40] = True  # standing on the strip's far end, apart from the tree
    out = trim_foot(crown | trunk | strip | blob)
    assert not (out & blob).any()


@pytest.mark.parametrize("lean", [0.0, 0.4, -0.4])
def test_a_trunk_s_flare_and_lean_stay(lean):
    """A foot twice as wide over its lowest rows, on a trunk leaning up to 0.4 pixels a
    row: nothing is dropped."""
    crown, trunk = _standing(lean=lean)
    yy, xx = np.mgrid[:H, :W]
    centre = 110 + lean * (yy - 120)
    flare = (np.abs(xx - centre) <= 6 + (yy - 215)) & (yy >= 215) & (yy < 225)
    tree = crown | trunk | flare
    assert (trim_foot(tree) == tree).all()


def test_twigs_along_the_trunk_and_a_crown_down_to_the_ground_stay():
    crown, trunk = _standing()
    twigs = np.zeros_like(trunk)
    for r in range(200, 222, 6):  # short shoots, each rising from the trunk
        for i in range(12):
            twigs[r - i, 116 + i] = twigs[r - i, 104 - i] = True
    tree = crown | trunk | twigs
    assert (trim_foot(tree) == tree).all()
    yy, xx = np.mgrid[:H, :W]
    skirt = (yy - 150) ** 2 / 75**2 + (xx - 110) ** 2 / 80**2 < 1  # no trunk seen: no waist
    strip = (yy >= 218) & (yy < 225) & (xx > 20) & (xx < 200)
    assert (trim_foot(skirt | strip) == (skirt | strip)).all()


def _shadow_at_the_foot(seed):
    """A picture: a sky, a grassy ground from the horizon (noisy), a crown of leaf clumps,
    a trunk of bark to row 224 and a dark shadow on the grass around its foot."""
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[:H, :W]
    crown, trunk = _standing()
    ground = yy >= HORIZON
    rgb = np.empty((H, W, 3))
    rgb[:] = [0.6, 0.75, 0.95]
    rgb[ground] = (np.array([0.35, 0.55, 0.2]) + 0.04 * rng.standard_normal((H, W, 1)))[ground]
    shadow = ((yy - 222) / 5.0) ** 2 + ((xx - 110) / 45.0) ** 2 <= 1
    shadow &= ~trunk & ground
    rgb[shadow] = (np.array([0.12, 0.17, 0.08]) + 0.03 * rng.standard_normal((H, W, 1)))[shadow]
    rgb[trunk] = (np.array([0.3, 0.22, 0.16]) + 0.03 * rng.standard_normal((H, W, 1)))[trunk]
    clumps = np.kron(rng.uniform(0.6, 1.4, (H // 4, W // 4 + 1, 1)), np.ones((4, 4, 1)))[:H, :W]
    rgb[crown] = (np.array([0.15, 0.35, 0.1]) * clumps)[crown]
    return np.clip(rgb, 0, 1), crown, trunk, shadow


@pytest.mark.parametrize("seed", [1, 2])
def test_a_shadow_beside_a_trunk_seen_is_no_hidden_trunk(seed):
    """The shadow's two halves lie either side of the trunk's foot, apart from the trunk
    that is seen down to them: bridged to the trunk's foot at the cut as a trunk hidden by
    a hedge would be, a wedge of grass and the shadow joined the tree (197 pixels of the
    shadow on both seeds). A half is flat (about 45 x 5 pixels): now none is."""
    rgb, crown, trunk, shadow = _shadow_at_the_foot(seed)
    seg = photo.segment_photo(rgb)
    assert (seg.tree & crown).sum() == crown.sum()
    assert (seg.tree & trunk).sum() >= 0.95 * trunk.sum()
    assert (seg.tree & shadow).sum() <= 0.05 * shadow.sum()
    assert (seg.tree & ~crown & ~trunk).sum() <= 0.05 * trunk.sum()


def test_segment_photo_drops_a_strip_joined_below_the_cut(monkeypatch):
    """Where the steps below the cut join a flat strip of ground to the trunk's foot, the
    silhouette has none of it, and ``fit.json``'s ``segmentation`` says how much went."""
    rgb, _, trunk, _ = _shadow_at_the_foot(1)
    strip = np.zeros_like(trunk)
    strip[219:225, 50:104] = True
    below_cut = photo.below_cut

    def with_strip(rgb, tree, under, *rest):
        low, spill = below_cut(rgb, tree, under, *rest)
        return low | (strip & under), spill

    monkeypatch.setattr(photo, "below_cut", with_strip)
    seg = photo.segment_photo(rgb)
    assert (seg.tree & strip).sum() <= 7 * 6 and (seg.tree & trunk).sum() >= 0.95 * trunk.sum()
    assert seg.record()["steps"]["trimmed_foot"] >= (strip & ~trunk).sum() - 7 * 6


def _tree_on_a_crest(seed, rut=(126, 132)):
    """A crown on a trunk standing on the skyline (a field's far edge, nothing behind it)
    and, in the field below its foot, a dark rut of the trunk's width: ``(rgb, tree)``."""
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[:200, :240]
    rgb = np.empty((200, 240, 3))
    rgb[:] = [0.6, 0.8, 0.92]
    field = yy >= 100
    rgb[field] = ([0.5, 0.33, 0.2] * rng.uniform(0.85, 1.15, (200, 240, 1)))[field]
    crown = (yy - 50) ** 2 / 38**2 + (xx - 120) ** 2 / 70**2 < 1
    leaves = np.kron(rng.uniform(0.6, 1.4, (50, 60, 1)), np.ones((4, 4, 1)))
    rgb[crown] = ([0.15, 0.12, 0.09] * leaves)[crown]
    trunk = (np.abs(xx - 120) <= 4) & (yy >= 80) & (yy < 101)
    rgb[trunk] = [0.12, 0.09, 0.07]
    dark = (np.abs(xx - 121) <= 5) & (yy >= rut[0]) & (yy < rut[1])
    rgb[dark] = [0.13, 0.1, 0.08]
    return np.clip(rgb + rng.normal(0, 0.01, rgb.shape), 0, 1), crown | trunk


def _trunk_behind_a_hedge(seed):
    """A crown above a hedge; its trunk, of the hedge's colour, crosses it unseen and
    stands on the grass below it: ``(rgb, tree)``."""
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[:200, :240]
    rgb = np.empty((200, 240, 3))
    rgb[:] = [0.6, 0.78, 0.95]
    hedge = (yy >= 92 + 2 * np.sin(xx / 4.0)) & (yy < 112)
    rgb[hedge] = ([0.16, 0.24, 0.1] * rng.uniform(0.8, 1.2, (200, 240, 1)))[hedge]
    rgb[yy >= 112] = ([0.45, 0.62, 0.25] * rng.uniform(0.9, 1.1, (200, 240, 1)))[yy >= 112]
    crown = (yy - 48) ** 2 / 36**2 + (xx - 120) ** 2 / 60**2 < 1
    leaves = np.kron(rng.uniform(0.6, 1.4, (50, 60, 1)), np.ones((4, 4, 1)))
    rgb[crown] = ([0.3, 0.2, 0.1] * leaves)[crown]
    trunk = (np.abs(xx - 120) <= 5) & (yy >= 75) & (yy < 150)
    rgb[trunk] = ([0.16, 0.24, 0.1] * rng.uniform(0.8, 1.2, (200, 240, 1)))[trunk]
    return np.clip(rgb + rng.normal(0, 0.01, rgb.shape), 0, 1), crown | trunk


@pytest.mark.parametrize("rut", [(118, 122), (126, 132), (130, 136)])
def test_a_speck_of_the_ground_far_below_the_foot_is_no_hidden_trunk(rut):
    """A tree standing on the skyline, a dark rut of its trunk's width in the field below:
    bridged to the foot as a trunk hidden by a hedge would be, the trunk ran on down
    through the open field to the rut (block 17's tree on a brown hill, its tree on an
    embankment; 187-359 false pixels here). A piece seen over less than a third of the
    stretch it would bridge is no trunk."""
    rgb, tree = _tree_on_a_crest(0, rut)
    found = photo.segment_photo(rgb).tree
    assert (found & ~tree)[101:].sum() <= 10 and (found & tree).sum() >= 0.98 * tree.sum()


@pytest.mark.parametrize("seed", range(2))
def test_a_trunk_of_the_hedge_s_colour_crossing_it_unseen_is_bridged(seed):
    """A trunk hidden by a hedge of its colour and seen again below it, on the grass, is
    bridged over the hedge to its foot."""
    rgb, tree = _trunk_behind_a_hedge(seed)
    found = photo.segment_photo(rgb).tree
    assert (found & tree)[92:112].sum() >= 0.95 * tree[92:112].sum()  # hidden, bridged
    assert (found & tree)[112:].sum() >= 0.95 * tree[112:].sum()
