"""Trees in outdoor photographs (issue 41): the sky of any kind, the ground, the clutter
along the horizon; the hints (``--box``, ``--point``) that settle a picture where one tree
cannot be told apart; what a photo fit writes about how its tree was found.

The composites (``tests/data/composites``, ``benchmarks/make_composites.py``): modular-tree
renders on procedural outdoor backgrounds, each with its true mask; the thresholds were
tuned on the ``discovery`` split, the bars below are measured on ``held_out``.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from growsim.cli import main
from growsim.errors import UserInputError
from growsim.pictures.photo import segment_photo, segmentation_picture

DATA = Path(__file__).resolve().parent / "data" / "composites"
INDEX = json.loads((DATA / "index.json").read_text())["pictures"]
BY_NAME = {p["name"]: p for p in INDEX}
#: a hard composite (a second tree, a treeline, a wood) is right at this IoU
RIGHT = 0.8


def _mask(p) -> np.ndarray:
    return np.asarray(Image.open(DATA / p["mask"]).convert("L")) < 128


def _iou(a, b) -> float:
    return float((a & b).sum() / max((a | b).sum(), 1))


@pytest.fixture(scope="module")
def held_out():
    """Every held-out composite: its picture, whether it is hard, and what the
    segmentation made of it (the silhouette's IoU, or the refusal)."""
    rows = []
    for p in INDEX:
        if p["split"] != "held_out":
            continue
        try:
            seg = segment_photo(DATA / p["photo"])
            rows.append((p, _iou(seg.tree, _mask(p)), None))
        except UserInputError as exc:
            rows.append((p, None, str(exc)))
    return rows


def _hard(p) -> bool:
    return p["hard"] != "none" or p["second_tree"] or p["treeline"]


def test_held_out_composites_are_found_whole(held_out):
    """The lone trees (no second tree, no hedge, treeline or wood): every one accepted,
    the tree's silhouette close to the true one, leafy and bare. Measured (2026-12-05):
    leafy 0.82 (a sunset over hills 0.69, a cumulus sky 0.94 since the colour model:
    under issue 41's 0.92), bare 0.91 (its 0.85); benchmarks/log/fitting.md."""
    easy = [(p, iou) for p, iou, _ in held_out if not _hard(p)]
    assert [p["name"] for p, iou in easy if iou is None] == []
    for leafy, bar in ((True, 0.78), (False, 0.85)):
        ious = [iou for p, iou in easy if p["leafy"] == leafy]
        assert np.mean(ious) >= bar, (leafy, ious)


def test_hard_composites_are_right_or_refused_naming_a_hint(held_out):
    """A second tree, a hedge, a treeline, a wood: the tree is segmented right, or the
    picture is refused in one line naming the hint that settles it."""
    wrong = []
    for p, iou, message in held_out:
        if not _hard(p):
            continue
        if message is not None:
            assert "\n" not in message and ("--box" in message or "--point" in message), message
        elif iou < RIGHT:
            wrong.append((p["name"], round(iou, 3)))
    assert not wrong, wrong


def test_a_second_tree_is_refused_then_settled_by_a_hint():
    rgb, truth = _beside_a_tree_cut_by_the_frame(at=230)  # two whole trees
    with pytest.raises(UserInputError, match="which is the tree") as err:
        segment_photo(rgb)
    message = str(err.value)
    assert "--box" in message and "--point" in message and "\n" not in message
    for hint in ({"box": (56, 21, 165, 200)}, {"point": (110, 60)}):
        seg = segment_photo(rgb, **hint)
        assert _iou(seg.tree, truth) >= RIGHT, hint
        assert seg.hint == {k: [float(v) for v in val] for k, val in hint.items()}
        assert seg.record()["hint"] == seg.hint
    # a hint off the picture, or on no tree, is refused naming it
    with pytest.raises(UserInputError, match="--point 5000,10 lies outside the picture"):
        segment_photo(rgb, point=(5000, 10))
    with pytest.raises(UserInputError, match="no tree found at --point"):
        segment_photo(rgb, point=(5, 5))


def test_a_tree_before_a_wood_is_refused_then_settled_by_a_box():
    """A bare crown before a treeline (its twigs' pixels mixed with the treeline's
    colours) is refused naming the box; with a box a tree before a wood is GrabCut's."""
    p = BY_NAME["c12_stormy_crop_rows_treeline_bare"]
    with pytest.raises(UserInputError, match=r"in front of a wood.*--box"):
        segment_photo(DATA / p["photo"])
    p = BY_NAME["c23_cumulus_hills_wood_leafy"]
    truth = _mask(p)
    rows, cols = np.nonzero(truth)
    pad = 0.05 * max(np.ptp(rows), np.ptp(cols))
    box = (cols.min() - pad, rows.min() - pad, cols.max() + pad, rows.max() + pad)
    seg = segment_photo(DATA / p["photo"], box=box)
    assert _iou(seg.tree, truth) >= RIGHT and seg.method == "GrabCut in the box"


@pytest.mark.parametrize(
    "name",
    [
        # A pale bare tree under storm clouds before a treeline: GrabCut started from the
        # whole box took the treeline and lost the crown (IoU 0.06); started from each
        # row's background (the colours beside the box), it keeps the trunk and most of
        # the crown and leaves the treeline out.
        "c12_stormy_crop_rows_treeline_bare",
        # A pale bare tree before a dark wood as tall as most of it: GrabCut took the crown
        # as a solid blob, the wood between its twigs with it (IoU 0.24, twice as much wood
        # as tree); what is more like the wood beside the box than the twigs is left out.
        "c22_cumulus_hills_wood_bare",
    ],
)
def test_a_box_finds_a_bare_tree_before_a_treeline_or_a_wood(name):
    """Refused naming --box, then given the box a user draws (the true mask's bounds, 5 %
    wider each way): GrabCut in the box finds most of the tree, little of what is behind."""
    p = BY_NAME[name]
    with pytest.raises(UserInputError, match=r"--box"):
        segment_photo(DATA / p["photo"])
    truth = _mask(p)
    rows, cols = np.nonzero(truth)
    pad_r, pad_c = 0.05 * np.ptp(rows), 0.05 * np.ptp(cols)
    box = (cols.min() - pad_c, rows.min() - pad_r, cols.max() + pad_c, rows.max() + pad_r)
    seg = segment_photo(DATA / p["photo"], box=box)
    assert seg.method == "GrabCut in the box"
    assert _iou(seg.tree, truth) >= 0.4
    assert (seg.tree & ~truth).sum() <= 0.5 * truth.sum()


def test_a_box_leaves_no_pinholes_in_a_speckled_crown():
    """A crown with leaves here and there of a colour beside the box (dark rock): left out
    pixel by pixel they riddled it with pinholes, and a small cypress on its rock was
    refused as too noisy (21.8 pinholes per 1,000 pixels); pinholes stay, a gap as large
    as a patch of the wood does not."""
    from skimage.color import rgb2lab

    from growsim.pictures.hints import _row_background, apart_from_rows

    rng = np.random.default_rng(3)
    rgb = np.zeros((60, 80, 3))
    rgb[:] = [0.75, 0.8, 0.85]  # the sky
    rgb[:, ::6] = [0.25, 0.22, 0.2]  # dark rock in every row beside the box
    box = np.zeros((60, 80), bool)
    box[:, 20:60] = True
    yy, xx = np.mgrid[0:60, 0:80]
    crown = (yy - 30) ** 2 + (xx - 40) ** 2 < 15**2
    rgb[crown] = [0.2, 0.45, 0.15]
    speckled = crown & (rng.random((60, 80)) < 0.1)
    rgb[speckled] = [0.25, 0.22, 0.2]
    rgb[26:33, 36:43] = [0.25, 0.22, 0.2]  # a gap of 49 pixels: rock seen through it
    lab = rgb2lab(rgb)
    kept = apart_from_rows(lab, crown, _row_background(lab, box))
    assert not kept[26:33, 36:43].any()
    pinholes = speckled & ~kept
    assert pinholes.sum() <= 0.15 * speckled.sum()  # those by the gap go with it


def test_a_box_whose_colours_all_stand_beside_it_still_finds_the_tree():
    """Three like trees in a row and a box around the middle one: every colour in the box
    is found beside it in its rows, so no pixel starts as probably tree (OpenCV's GrabCut
    stopped with an assertion error, a traceback for the user): it starts from the box
    alone and finds the tree; a box holding only sky is refused in one line."""
    from growsim.pictures.hints import in_box

    rgb = np.ones((60, 90, 3)) * [0.8, 0.9, 1.0]
    yy, xx = np.mgrid[0:60, 0:90]
    for cx in (15, 45, 75):
        rgb[(yy - 25) ** 2 + (xx - cx) ** 2 < 80] = [0.2, 0.4, 0.1]
        rgb[30:50, cx - 1 : cx + 2] = [0.4, 0.3, 0.2]
    keep = np.zeros((60, 90), dtype=bool)
    keep[10:55, 32:58] = True
    seg = in_box(rgb, keep, None, {"box": [32, 10, 58, 55]}, 1.0, "trees.jpg", 0.0)
    assert seg.tree[25, 45] and seg.tree[45, 45] and not seg.tree[:, :32].any()
    sky = np.zeros((60, 90), dtype=bool)
    sky[:8] = True
    keep = np.zeros((60, 90), dtype=bool)
    keep[:8, 30:60] = True
    with pytest.raises(UserInputError, match=r"^sky.jpg: .*box"):
        in_box(rgb, keep, sky, {"box": [30, 0, 60, 8]}, 1.0, "sky.jpg", 0.0)


def _scene(h, w, zenith, horizon, ground_row, ground):
    """A sky graded from ``zenith`` to ``horizon`` over a ground of colour ``ground`` from
    row ``ground_row``: ``(rgb, yy, xx)``."""
    yy, xx = np.mgrid[0:h, 0:w]
    rgb = np.zeros((h, w, 3))
    rgb[:] = np.linspace(zenith, horizon, h)[:, None, :]
    rgb[ground_row:] = ground
    return rgb, yy, xx


def _meadow_tree(edge_tree: bool, cut_by_frame: bool = False):
    """A wide crown on a meadow under a blue sky, its low side reaching right; with
    ``edge_tree`` a small tree at the right edge touching that side; with
    ``cut_by_frame`` the crown itself runs past the right edge. ``(rgb, tree mask)``."""
    rng = np.random.default_rng(1)
    rgb, yy, xx = _scene(200, 300, [0.45, 0.62, 0.92], [0.72, 0.83, 0.97], 150, [0.35, 0.6, 0.2])
    cx = 230 if cut_by_frame else 130
    crown = ((yy - 85) / 55.0) ** 2 + ((xx - cx) / 95.0) ** 2 <= 1
    crown |= ((yy - 126) / 14.0) ** 2 + ((xx - 220) / 48.0) ** 2 <= 1
    trunk = (yy >= 120) & (yy < 153) & (xx >= 124) & (xx < 136)
    small = ((yy - 132) / 16.0) ** 2 + ((xx - 283) / 18.0) ** 2 <= 1
    small |= (yy >= 140) & (yy < 152) & (xx >= 290) & (xx < 294)
    rgb[crown | trunk | (small if edge_tree else False)] = [0.16, 0.32, 0.1]
    rgb[trunk] = [0.3, 0.22, 0.15]
    return np.clip(rgb + rng.normal(0, 0.02, rgb.shape), 0, 1), crown | trunk


def test_a_small_tree_at_the_edge_joined_by_a_neck_is_split_off():
    # the tree's low side touches a small tree standing at the right edge: it was refused
    # as reaching the edge; now the small tree is split off at the neck and recorded
    rgb, truth = _meadow_tree(edge_tree=True)
    seg = segment_photo(rgb)
    assert _iou(seg.tree, truth) >= 0.95
    assert len(seg.split) == 1 and seg.split[0][2] == 300
    # a crown cut by the frame is as tall at the edge as inside: still refused
    rgb, _ = _meadow_tree(edge_tree=False, cut_by_frame=True)
    with pytest.raises(UserInputError, match=r"right edge"):
        segment_photo(rgb)


def _tree_and_a_hedge(reach: int):
    """A leafy crown on a meadow and a hedge along the horizon (a fifth of the tree's
    height) from the picture's left edge to column ``reach`` (115: it touches the crown's
    lower left side; 105: it stands apart): ``(rgb, tree)``."""
    rng = np.random.default_rng(7)
    rgb, yy, xx = _scene(200, 320, [0.4, 0.6, 0.95], [0.7, 0.82, 0.97], 170, [0.45, 0.62, 0.25])
    leaves = np.kron(rng.uniform(0.5, 1.5, (50, 80, 1)), np.ones((4, 4, 1)))
    tree = ((yy - 92) / 60.0) ** 2 + ((xx - 130) / 50.0) ** 2 <= 1
    tree |= (yy >= 120) & (yy < 173) & (xx >= 125) & (xx < 135)
    hedge = (yy >= 146 + 5 * np.sin(xx / 7.0)) & (yy < 171) & (xx < reach) & ~tree
    rgb[tree] = ([0.18, 0.3, 0.12] * leaves)[tree]
    rgb[hedge] = ([0.12, 0.22, 0.1] * leaves)[hedge]
    return np.clip(rgb + rng.normal(0, 0.02, rgb.shape), 0, 1), tree


@pytest.mark.parametrize("reach", [115, 105])
def test_the_horizon_s_low_clutter_beside_the_tree_is_not_the_tree(reach):
    """A hedge along the horizon running to the left edge: touching the crown (block 2's
    beech over garden shrubs, block 6's tree over a playground's distant trees) it was
    taken with the tree, and the tree refused as reaching the edge; standing apart, it was
    taken as the crown's region (IoU 0.89). Now it is left out."""
    rgb, tree = _tree_and_a_hedge(reach)
    seg = segment_photo(rgb)
    assert _iou(seg.tree, tree) >= 0.93 and not seg.tree[:, :60].any()


def _tree_before_a_treeline(crown_colour):
    """A round crown of ``crown_colour`` on a meadow before a treeline of dark green
    crowns across the picture, as tall as two thirds of the tree: ``(rgb, tree)``."""
    rng = np.random.default_rng(11)
    rgb, yy, xx = _scene(240, 360, [0.4, 0.6, 0.95], [0.7, 0.82, 0.97], 200, [0.45, 0.62, 0.25])
    leaves = np.kron(rng.uniform(0.6, 1.4, (60, 90, 1)), np.ones((4, 4, 1)))
    wood = yy >= 95 + 12 * np.abs(np.sin(xx / 9.0)) + 6 * np.sin(xx / 23.0)
    rgb[wood & (yy < 200)] = ([0.1, 0.25, 0.1] * leaves)[wood & (yy < 200)]
    tree = ((yy - 105) / 70.0) ** 2 + ((xx - 180) / 60.0) ** 2 <= 1
    trunk = (yy >= 160) & (yy < 204) & (xx >= 175) & (xx < 186)
    rgb[tree] = (np.asarray(crown_colour) * leaves)[tree]
    rgb[trunk & ~tree] = [0.3, 0.22, 0.15]
    return np.clip(rgb + rng.normal(0, 0.02, rgb.shape), 0, 1), tree | trunk


def test_a_crown_of_its_own_colours_before_a_treeline_is_read_below_its_top():
    """A red crown before a green treeline two thirds its height (block 2's autumn ash,
    block 6's crabapple): its part below the treeline's top is read by its colours
    against the treeline's; refused before as standing before a wood. A green crown
    before the green treeline is still refused, naming the box."""
    rgb, tree = _tree_before_a_treeline([0.75, 0.22, 0.1])
    seg = segment_photo(rgb)
    assert _iou(seg.tree, tree) >= 0.9
    rgb, _ = _tree_before_a_treeline([0.15, 0.32, 0.12])
    with pytest.raises(UserInputError, match=r"in front of a wood or a treeline .* --box"):
        segment_photo(rgb)


def test_before_a_treeline_nothing_is_learned_below_the_ground(monkeypatch):
    """Before a treeline the crown is read down to where the ground begins; below it
    only the trunk stands, never a band of lawn learned as the crown's green (block 9's
    park pine): the learned step does not run there."""
    import growsim.pictures.photo as photo

    calls = []
    monkeypatch.setattr(photo, "learned_below", lambda rgb, tree, low, *a: calls.append(1) or low)
    rgb, tree = _tree_before_a_treeline([0.75, 0.22, 0.1])
    assert _iou(segment_photo(rgb).tree, tree) >= 0.9 and not calls


def _crown_resting_on_a_wood(seed):
    """A wide crown whose low side rests on a low wood across the picture, over a field
    of crop rows at a slant; its trunk stands in the field: ``(rgb, crown, trunk)``."""
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[:180, :240]
    rgb = np.empty((180, 240, 3))
    rgb[:] = [0.6, 0.75, 0.95]
    wood = (yy >= 95 + 3 * np.sin(xx / 7.0)) & (yy < 125)
    rgb[wood] = ([0.12, 0.25, 0.1] + 0.05 * rng.standard_normal((180, 240, 1)))[wood]
    rows = ((yy + 0.12 * xx) // 4) % 2 == 0
    field = np.where(rows[..., None], [0.55, 0.6, 0.3], [0.35, 0.45, 0.2])
    rgb[yy >= 125] = (field + 0.02 * rng.standard_normal((180, 240, 3)))[yy >= 125]
    crown = (yy - 65) ** 2 / 45**2 + (xx - 120) ** 2 / 85**2 < 1
    rgb[crown] = ([0.3, 0.55, 0.15] + 0.06 * rng.standard_normal((180, 240, 1)))[crown]
    trunk = (np.abs(xx - 120) <= 5) & (yy >= 100) & (yy < 165)
    rgb[trunk] = ([0.4, 0.3, 0.22] + 0.02 * rng.standard_normal((180, 240, 1)))[trunk]
    return np.clip(rgb, 0, 1), crown, trunk


@pytest.mark.parametrize("seed", range(3))
def test_under_a_crown_resting_on_a_wood_its_trunk_stands_not_stripes(seed):
    """The crown rests on the wood all along its low side, so the columns read against
    the row beside them span the whole window below it: read there, the wood's top came
    out as a stripe to both sides, and the trunk was lost along with it (0 of its 715
    pixels). Only what stands tall is kept there: the trunk, to its foot, and no row of
    the field's slanting rows."""
    rgb, crown, trunk = _crown_resting_on_a_wood(seed)
    tree = segment_photo(rgb).tree
    assert (tree & trunk).sum() >= 0.9 * trunk.sum() and (tree & crown).sum() >= 0.95 * crown.sum()
    assert (tree[125:] & ~trunk[125:]).sum() <= 0.05 * trunk.sum()


def _crown_hanging_over_grass_by_a_road(seed):
    """A crown of dark leaf clumps whose low side hangs below the horizon across most of
    its width, grass under it and left of it, a grey road right of it: ``(rgb, tree)``."""
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[:180, :260]
    rgb = np.empty((180, 260, 3))
    rgb[:] = [0.6, 0.72, 0.9]
    ground = yy >= 110
    rgb[ground] = ([0.42, 0.55, 0.22] + 0.03 * rng.standard_normal((180, 260, 1)))[ground]
    road = ground & (xx >= 205 - 0.3 * (yy - 110))
    rgb[road] = ([0.42, 0.42, 0.44] + 0.02 * rng.standard_normal((180, 260, 1)))[road]
    outline = ((yy - 70) ** 2 / 58**2 + (xx - 125) ** 2 / 85**2 < 1) & (yy < 132)
    clumps = np.kron(rng.uniform(0, 1, (45, 65)), np.ones((4, 4))) < np.where(yy < 95, 0.97, 0.6)
    crown = outline & clumps
    shade = np.kron(rng.uniform(0.6, 1.4, (45, 65, 1)), np.ones((4, 4, 1)))
    rgb[crown] = ([0.12, 0.22, 0.07] * shade)[crown]
    trunk = (np.abs(xx - 125) <= 6) & (yy >= 90) & (yy < 145)
    rgb[trunk] = [0.3, 0.2, 0.12]
    return np.clip(rgb + rng.normal(0, 0.01, rgb.shape), 0, 1), crown | trunk


@pytest.mark.parametrize("seed", [0, 4, 7])
def test_the_grass_under_a_crown_hanging_below_the_horizon_is_not_the_tree(seed):
    """The crown's low side hangs below the horizon across most of its width, so the
    trunk's columns span it all and the grass under it was read against the row's
    colours either side, grass and road: a block of grass was the tree (IoU 0.72-0.74
    for these seeds, block 7's road composite 0.66). Of the grass's colours seen beside
    the tree, only what is narrow in its row (a trunk) is spared now."""
    rgb, tree = _crown_hanging_over_grass_by_a_road(seed)
    found = segment_photo(rgb).tree
    assert _iou(found, tree) >= 0.95
    assert (found[110:] & ~tree[110:]).sum() <= 0.1 * tree[110:].sum()
    assert (found & tree)[132:].sum() >= 0.95 * tree[132:].sum()  # the trunk to its foot


def test_a_crown_is_told_from_a_hazy_treeline_of_its_colour_by_its_texture(monkeypatch):
    """A crown of leaf clumps before a hazy treeline of the same mean colour: the
    lightness's local spread tells them apart where the colour alone does not."""
    from scipy import ndimage
    from skimage.color import rgb2lab

    import growsim.pictures.colours as colours

    rng = np.random.default_rng(2)
    yy, xx = np.mgrid[:80, :120]
    green = np.array([0.2, 0.38, 0.15])
    clumps = np.kron(rng.uniform(0.55, 1.45, (20, 30, 1)), np.ones((4, 4, 1)))
    rgb = green * (1 + 0.5 * ndimage.gaussian_filter(rng.standard_normal((80, 120)), 4))[..., None]
    tree = ((yy - 40) / 36.0) ** 2 + ((xx - 60) / 30.0) ** 2 <= 1
    rgb[tree] = (green * clumps)[tree]
    lab = rgb2lab(np.clip(rgb + rng.normal(0, 0.01, rgb.shape), 0, 1))
    crown = ndimage.binary_erosion(tree & (yy < 30))  # the crown above the treeline's top
    clutter = (yy >= 30) & ((xx < 20) | (xx >= 100))  # the treeline beside it
    zone = (yy >= 30) & (xx >= 20) & (xx < 100)
    low = colours.crown_coloured(lab, crown, clutter, zone)
    assert (low & tree & zone).sum() >= 0.95 * (tree & zone).sum()
    assert (low & ~ndimage.binary_dilation(tree, iterations=3)).sum() <= 0.01 * (zone & ~tree).sum()
    monkeypatch.setattr(colours, "CROWN_TEXTURE", 0.0)
    assert colours.crown_coloured(lab, crown, clutter, zone) is None


def test_a_narrow_strip_of_treeline_beside_a_wide_crown_is_not_outvoted():
    """A wide crown, the treeline beside it a strip of a few columns (the northern
    catalpa's): each class's votes count per sample, so its few samples are not outvoted
    by the crown's many (counted plainly, the two were not told apart)."""
    from skimage.color import rgb2lab

    from growsim.pictures.colours import crown_coloured

    rng = np.random.default_rng(4)
    yy, xx = np.mgrid[:80, :200]
    rgb = np.array([0.3, 0.45, 0.2]) * rng.uniform(0.5, 1.5, (80, 200, 1))  # lit and shaded
    strip = xx >= 194
    rgb[strip] = (np.array([0.12, 0.22, 0.1]) * rng.uniform(0.7, 1.3, (80, 200, 1)))[strip]
    lab = rgb2lab(np.clip(rgb, 0, 1))
    zone = (yy >= 30) & (xx >= 150)
    low = crown_coloured(lab, (yy < 30) & (xx < 190), (yy >= 30) & strip, zone)
    assert (low & zone & (xx < 190)).mean() / (zone & (xx < 190)).mean() >= 0.99
    assert not (low & strip).any()


def _umbrella_tree():
    """A flat-topped crown (an acacia's) spanning 90 % of the picture over a savanna, the
    sky reaching the horizon only in the columns either side of it; its two trunks run
    farther below the horizon than the crown is tall: ``(rgb, tree)``."""
    rng = np.random.default_rng(5)
    rgb, yy, xx = _scene(200, 300, [0.35, 0.55, 0.9], [0.6, 0.75, 0.95], 110, [0.8, 0.7, 0.4])
    rgb[110:] *= rng.uniform(0.9, 1.1, (90, 300, 1))  # dry grass
    top = 40 + 0.0025 * (xx - 150) ** 2
    crown = (yy >= top) & (yy < 120 - 0.001 * (xx - 150) ** 2) & (xx >= 14) & (xx < 286)
    trunks = (yy >= 80) & (yy < 170) & ((np.abs(xx - 135) < 5) | (np.abs(xx - 160) < 5))
    leaves = np.kron(rng.uniform(0.5, 1.5, (50, 75, 1)), np.ones((4, 4, 1)))
    rgb[crown] = ([0.3, 0.45, 0.15] * leaves)[crown]
    rgb[trunks & ~crown] = [0.15, 0.12, 0.1]
    return np.clip(rgb + rng.normal(0, 0.015, rgb.shape), 0, 1), crown | trunks


def test_a_crown_wider_than_the_horizon_s_ends_stands_on_it():
    """A flat crown's top covers most columns' skyline, so the horizon's line was laid on
    it and nothing rose (block 9's acacia, block 5's guanacaste): refused. The horizon
    is the line with no sky below it, where it shows on both sides of the crown; the
    trunks are read below it, down to their feet."""
    rgb, tree = _umbrella_tree()
    seg = segment_photo(rgb)
    assert _iou(seg.tree, tree) >= 0.9
    assert seg.tree[160:170, 130:140].mean() > 0.8 and seg.tree[175:].sum() == 0


def _tree_to_the_top(cut: bool):
    """A round crown on a meadow whose twig tips touch the top edge (block 4's baobab and
    campus tree), or with ``cut`` a crown whose top is cut off by the frame.
    ``(rgb, tree mask)``."""
    rng = np.random.default_rng(3)
    rgb, yy, xx = _scene(200, 300, [0.4, 0.6, 0.95], [0.7, 0.82, 0.97], 170, [0.35, 0.6, 0.2])
    crown = ((yy - (52 if cut else 70)) / 58.0) ** 2 + ((xx - 150) / 80.0) ** 2 <= 1
    crown |= (np.abs(xx - 150 - 0.1 * yy) < 1.2) & (yy < 20)  # twigs up to the edge
    crown |= (np.abs(xx - 131 + 0.2 * yy) < 1.0) & (yy < 20)
    trunk = (yy >= 90) & (yy < 173) & (xx >= 144) & (xx < 156)
    # a crown is textured (clumps of leaves), the sky smooth
    leaves = np.kron(rng.uniform(0.4, 1.6, (50, 75, 1)), np.ones((4, 4, 1)))
    rgb[crown] = ([0.18, 0.3, 0.12] * leaves)[crown]
    rgb[trunk] = [0.3, 0.22, 0.15]
    return np.clip(rgb + rng.normal(0, 0.02, rgb.shape), 0, 1), crown | trunk


def test_with_a_box_twigs_grazing_the_top_edge_are_whole():
    """Twig tips touching the top edge may be a crown cut off: refused, naming the box;
    the box says the whole tree is in the picture, and the tree is fitted, the pixels it
    grazes recorded. A crown cut off by the frame, wide at the edge, is refused even so,
    the refusal saying what settles it with a box reaching that edge (a courtyard running
    on past it may have been taken with the tree: the box stopped short of it)."""
    rgb, truth = _tree_to_the_top(cut=False)
    with pytest.raises(UserInputError, match=r"top edge .*--box x0,y0,x1,y1"):
        segment_photo(rgb)
    seg = segment_photo(rgb, box=(40, 0, 260, 200))
    assert _iou(seg.tree, truth) >= 0.9 and seg.grazes == int(seg.tree[0].sum()) > 0
    assert "grazing the top edge" in seg.describe()
    rgb, _ = _tree_to_the_top(cut=True)
    with pytest.raises(UserInputError, match=r"top edge .*farther away.*stop the box"):
        segment_photo(rgb, box=(40, 0, 260, 200))


def _beside_a_tree_cut_by_the_frame(at: int):
    """A leafy tree in the middle of a meadow and another as large at column ``at`` (cut
    by the right edge from about 280). ``(rgb, the middle tree)``."""
    rng = np.random.default_rng(6)
    rgb, yy, xx = _scene(200, 320, [0.4, 0.6, 0.95], [0.7, 0.82, 0.97], 170, [0.35, 0.6, 0.2])
    leaves = np.kron(rng.uniform(0.4, 1.6, (50, 80, 1)), np.ones((4, 4, 1)))
    tree = ((yy - 80) / 50.0) ** 2 + ((xx - 110) / 45.0) ** 2 <= 1
    tree |= (yy >= 110) & (yy < 173) & (xx >= 105) & (xx < 115)
    other = ((yy - 85) / 50.0) ** 2 + ((xx - at) / 45.0) ** 2 <= 1
    other |= (yy >= 110) & (yy < 173) & (xx >= at - 5) & (xx < at + 5)
    rgb[tree | other] = ([0.18, 0.3, 0.12] * leaves)[tree | other]
    return np.clip(rgb + rng.normal(0, 0.02, rgb.shape), 0, 1), tree


def test_a_tree_cut_by_the_frame_is_no_rival_to_a_whole_one():
    """A tree as large as the tree but cut by the side edge (block 6's young tree beside a
    dark one at the left edge was refused as ambiguous): the photograph is of the whole
    one. Two whole trees are still ambiguous: refused, naming a box around each."""
    rgb, tree = _beside_a_tree_cut_by_the_frame(at=300)
    assert _iou(segment_photo(rgb).tree, tree) >= 0.9
    rgb, _ = _beside_a_tree_cut_by_the_frame(at=230)
    with pytest.raises(UserInputError, match=r"which is the tree\? give --box .* or --box "):
        segment_photo(rgb)


def _two_bare_trees(second: bool, at: int = 150):
    """Grey trees on grass under a blue gradient: a tall narrow one and, with ``second``,
    a short bushy one at column ``at`` whose crown touches its trunk (one colour: no hue
    tells them apart); without it, the tall one's low limb reaching down to the ground on
    its right instead. ``(rgb, the tall tree, the other or the limb)``."""
    rng = np.random.default_rng(4)
    rgb, yy, xx = _scene(240, 320, [0.45, 0.62, 0.92], [0.75, 0.84, 0.97], 200, [0.3, 0.55, 0.2])
    tall = ((yy - 90) / 70.0) ** 2 + ((xx - 120) / 16.0) ** 2 <= 1
    tall |= (yy >= 150) & (yy < 202) & (xx >= 116) & (xx < 124)
    if second:
        other = ((yy - 150) / 25.0) ** 2 + ((xx - at) / 28.0) ** 2 <= 1
        other |= (yy >= 170) & (yy < 202) & (xx >= at - 3) & (xx < at + 3)
    else:  # a low limb from the crown down to the ground, right of the trunk
        other = (np.abs((xx - 124) - (yy - 120) * 0.9) < 3) & (yy >= 120) & (yy < 202)
    rgb[tall | other] = [0.55, 0.53, 0.5]
    return np.clip(rgb + rng.normal(0, 0.02, rgb.shape), 0, 1), tall, other


def test_two_trees_of_one_colour_touching_are_told_apart_by_their_feet():
    """Two bare trees of one colour whose crowns touch, each on its own foot (block 4's
    second tree on a slope was accepted as one tree, IoU 0.35; here 0.64): the other split
    off (or, as tall as a rival, refused naming a box around each); a lone tree whose low
    limb reaches the ground beside its trunk (two feet, too small a part) stays one tree."""
    rgb, tall, other = _two_bare_trees(second=True)
    try:
        seg = segment_photo(rgb)
    except UserInputError as exc:  # as tall as a rival: which is the tree?
        assert "which is the tree? give --box" in str(exc) and " or --box " in str(exc)
    else:  # or the tall one alone, the other split off
        assert seg.split and _iou(seg.tree, tall) >= 0.9
        assert (seg.tree & other & ~tall).sum() < 0.15 * (other & ~tall).sum()
    rgb, tall, limb = _two_bare_trees(second=False)
    seg = segment_photo(rgb)
    assert not seg.split and _iou(seg.tree, tall | limb) >= 0.9


def _tree_on_snow():
    """A bare tree on snow as pale and smooth as the white sky above it, a dark road
    below the snow (the band): the trunk ends on the snow, above the band.
    ``(rgb, the tree)``."""
    rng = np.random.default_rng(5)
    rgb, yy, _ = _scene(240, 320, [0.62, 0.7, 0.78], [0.88, 0.9, 0.92], 200, [0.9, 0.91, 0.93])
    h, w = yy.shape
    road = yy >= 228
    rgb[road] = [0.42, 0.44, 0.48] + 0.04 * rng.standard_normal((int(road.sum()), 1))
    tree = np.zeros((h, w), bool)
    tree[120:206, 158:163] = True  # the trunk, down to the snow
    for k in range(14):  # bare limbs
        a = np.radians(-160 + 140 * k / 13)
        for t in np.linspace(0, 70, 300):
            r, c = int(125 + t * np.sin(a)), int(160 + t * np.cos(a))
            tree[max(0, r - 1) : r + 1, c : c + 2] = True
    rgb[tree] = [0.2, 0.2, 0.22]
    return np.clip(rgb + rng.normal(0, 0.01, rgb.shape), 0, 1), tree


def test_a_tree_on_snow_the_sky_s_colour_stands_where_its_trunk_ends():
    """Snow as pale and smooth as the sky is taken with the sky, so the tree floats above
    the band (block 4's toned snowy verge: "no tree stands on the ground"): a floating
    crown whose lowest part is a trunk's width stands where the trunk ends, and nothing
    below that is the tree."""
    rgb, tree = _tree_on_snow()
    seg = segment_photo(rgb)
    assert _iou(seg.tree, tree) >= 0.95
    assert not seg.tree[207:].any()


def test_clouds_and_a_treeline_are_not_the_tree():
    """A cumulus sky and buildings, a stormy sky over a treeline: the tree alone, its
    trunk down to the ground; the segmentation picture shows what was found."""
    for name in ("c18_cumulus_road_buildings_leafy", "c02_gradient_crop_rows_hedge_bare"):
        p = BY_NAME[name]
        seg = segment_photo(DATA / p["photo"])
        truth = _mask(p)
        assert _iou(seg.tree, truth) >= 0.88, name
        assert seg.horizon is not None and seg.tree[seg.horizon + 2 :].any()  # the trunk's foot
        assert not (seg.tree & seg.sky).any() and seg.confidence > 0.5
        rgb = np.asarray(Image.open(DATA / p["photo"]).convert("RGB")) / 255.0
        pic = segmentation_picture(seg, rgb)
        assert pic.shape == (p["height"], 2 * p["width"] + 8, 3) and pic.dtype == np.uint8
    record = seg.record()
    assert record["method"] == "sky and skyline" and record["horizon"] == seg.horizon
    assert record["tree_pixels"] == int(seg.tree.sum()) and len(record["band"]["rows"]) == 9


def test_clouds_behind_a_leafy_crown_are_sky():
    """Clouds seen through or beside a leafy crown differ from the sky filled in around
    them, so thresholds take them; the per-picture colour model gives them back to the
    sky, and the leaves beside them are read against the cloud (discovery composites,
    IoU before the colour model: stormy 0.836, cumulus 0.903)."""
    for name, bar in (("c13_stormy_crop_rows_treeline_leafy", 0.89),
                      ("c18_cumulus_road_buildings_leafy", 0.93)):  # fmt: skip
        p = BY_NAME[name]
        seg = segment_photo(DATA / p["photo"])
        assert _iou(seg.tree, _mask(p)) >= bar, name


def test_a_crown_whose_trunk_is_the_sky_colour_stands_on_its_foot():
    """A pale trunk before a pale sky is taken for sky, and the crown floats (today's
    stormy composites: refused, or IoU 0.04): the crown is the tree, standing on the
    trunk's foot found below the skyline, its trunk bridged up to it."""
    rng = np.random.default_rng(3)
    h, w = 240, 320
    rows, cols = np.mgrid[:h, :w]
    sky = np.array([0.78, 0.8, 0.82])
    rgb = np.ones((h, w, 3)) * sky
    ground = rows >= 190
    rgb[ground] = [0.75, 0.62, 0.3] + 0.05 * rng.standard_normal((int(ground.sum()), 1))
    leaves = ((rows - 90) ** 2 + (cols - 160) ** 2 < 60**2) & (rng.random((h, w)) < 0.8)
    rgb[leaves] = [0.15, 0.35, 0.12] * (0.7 + 0.6 * rng.random((int(leaves.sum()), 1)))
    trunk = (rows >= 140) & (rows < 200) & (cols >= 155) & (cols < 165)
    rgb[trunk] = sky
    seg = segment_photo(np.clip(rgb, 0.0, 1.0))
    assert _iou(seg.tree, leaves | trunk) > 0.95
    assert seg.horizon == 190 and seg.tree[140:200, 155:165].all()


def test_a_hill_reaching_the_side_edge_is_the_landscape_not_a_rival():
    """A hillside rising at the picture's side, larger than the tree and wider than tall:
    the landscape, not a second tree (before: refused, "which is the tree?")."""
    rng = np.random.default_rng(5)
    h, w = 240, 320
    rows, cols = np.mgrid[:h, :w]
    rgb = np.ones((h, w, 3)) * [0.6, 0.75, 0.95]
    ground = rows >= 190
    rgb[ground] = [0.35, 0.55, 0.2] + 0.04 * rng.standard_normal((int(ground.sum()), 1))
    hill = (rows >= 190 - (cols - 200).clip(0) * 0.8) & ~ground & (cols >= 200)
    rgb[hill] = [0.25, 0.35, 0.2] * (0.8 + 0.4 * rng.random((int(hill.sum()), 1)))
    leaves = ((rows - 120) ** 2 + (cols - 90) ** 2 < 30**2) & (rng.random((h, w)) < 0.8)
    rgb[leaves] = [0.15, 0.35, 0.12] * (0.7 + 0.6 * rng.random((int(leaves.sum()), 1)))
    trunk = (rows >= 140) & (rows < 195) & (abs(cols - 90) < 4)
    rgb[trunk] = [0.35, 0.25, 0.15]
    assert hill.sum() > (leaves | trunk).sum()
    seg = segment_photo(np.clip(rgb, 0.0, 1.0))
    assert _iou(seg.tree, leaves | trunk) > 0.95


def test_a_tree_on_a_hills_slope_is_not_before_a_wood():
    """A tree on top of a field rising across the picture: the slope below it is ground,
    not the clutter of a wood (before: refused, "in front of a wood ... as tall as 48 %");
    the field's edge is smooth, a wood's top is not."""
    rng = np.random.default_rng(7)
    h, w = 240, 360
    rows, cols = np.mgrid[:h, :w]
    rgb = np.ones((h, w, 3)) * [0.75, 0.75, 0.78]
    hill = rows >= 200 - 0.3 * cols
    rgb[hill] = [0.7, 0.65, 0.15] * (0.85 + 0.3 * rng.random((int(hill.sum()), 1)))
    leaves = ((rows - 55) ** 2 + (cols - 270) ** 2 < 28**2) & (rng.random((h, w)) < 0.8)
    rgb[leaves] = [0.2, 0.25, 0.15] * (0.7 + 0.6 * rng.random((int(leaves.sum()), 1)))
    trunk = (rows >= 80) & (rows < 124) & (abs(cols - 270) < 3)
    rgb[trunk] = [0.25, 0.2, 0.15]
    seg = segment_photo(np.clip(rgb, 0.0, 1.0))
    assert _iou(seg.tree, leaves | trunk) > 0.95


def test_a_frame_around_the_photo_is_painted_over():
    """A dark frame line around a photograph hid its sky along the top (before: "no sky
    along the top"); painted over, the tree is found as without it, and the record says
    so."""
    p = BY_NAME["c01_plain_grass_bare"]
    rgb = np.asarray(Image.open(DATA / p["photo"]).convert("RGB")) / 255.0
    framed = rgb.copy()
    framed[:3], framed[-3:], framed[:, :3], framed[:, -3:] = 0.1, 0.1, 0.1, 0.1
    plain, seg = segment_photo(rgb), segment_photo(framed)
    assert seg.record()["border"] == [3, 3, 3, 3] and plain.record()["border"] == [0, 0, 0, 0]
    assert _iou(seg.tree, plain.tree) > 0.95


@pytest.mark.parametrize(
    "flag, value, message",
    [
        ("--box", "1,2,3", "argument --box: expected x0,y0,x1,y1"),
        ("--box", "10,20,5,40", "argument --box: expected x0,y0,x1,y1 with x0 < x1"),
        ("--point", "a,b", "argument --point: expected x,y"),
        ("--point-side", "1", "argument --point-side: expected x,y"),
    ],
)
def test_hint_flags_are_parsed_with_clear_errors(flag, value, message, capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["fit-image", "tree.jpg", "--out", "o", flag, value])
    assert exit_.value.code == 2 and message in capsys.readouterr().err


def test_fit_with_a_hint_writes_how_the_tree_was_found(tmp_path, capsys):
    """A refused picture fitted with --point: fit.json records the segmentation (method,
    hint, horizon, contrast, confidence, where the outline ends along the horizon), the
    segmentation picture is written, and the fit's state keeps the hint for --resume."""
    rgb, _ = _beside_a_tree_cut_by_the_frame(at=230)  # two whole trees
    photo = tmp_path / "two_trees.png"
    Image.fromarray(np.round(255 * rgb).astype(np.uint8)).save(photo)
    out = tmp_path / "fit"
    args = ["fit-image", str(photo), "--out", str(out), "--quiet",
            "--model", "honda", "--evaluations", "200", "--sizes", "32,64", "--refine",
            "20", "--arrange", "10", "--restarts", "1", "--leaves", "bare"]  # fmt: skip
    assert main(args) == 2
    assert "which is the tree" in capsys.readouterr().err and not out.exists()
    assert main([*args, "--point", "110,60"]) == 0
    text = capsys.readouterr().out
    assert "front picture: the tree found by sky and skyline, --point 110,60" in text
    fit = json.loads((out / "fit.json").read_text())
    found = fit["segmentation"]["front"]
    assert found["hint"] == {"point": [110.0, 60.0]} and found["horizon"] is not None
    assert found["contrast"] > 15 and 0 < found["confidence"] <= 1
    # its trunk found down to the ground: not flagged as ending along the horizon
    assert found["ends_at_horizon"] < 0.2 and "ends along the horizon" not in text
    assert "segmentation_front.png" in fit["files"]
    pic = np.asarray(Image.open(out / "segmentation_front.png"))
    assert pic.shape == (200, 2 * 320 + 8, 3)
    state = json.loads((out / "fit-state.json").read_text())["options"]
    assert state["point"] == [110.0, 60.0] and state["box"] is None


def test_the_backdrop_s_old_names_still_import_with_a_warning():
    """``fill``, ``sky_background`` and ``row_background`` moved from ``scene`` to
    ``backdrop``: the old names give the same functions, with a DeprecationWarning."""
    from growsim.pictures import backdrop, scene

    for name in ("fill", "sky_background", "row_background"):
        with pytest.warns(DeprecationWarning, match=f"backdrop.{name}"):
            assert getattr(scene, name) is getattr(backdrop, name)
    with pytest.raises(AttributeError):
        scene.no_such_name  # noqa: B018
