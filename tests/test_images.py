"""Reading pictures into silhouettes and framing them."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from growsim.errors import UserInputError
from growsim.pictures.images import (
    classify_picture,
    frame_silhouettes,
    otsu_threshold,
    picture_silhouettes,
    read_silhouettes,
    silhouette,
    silhouette_image,
    unframe,
)
from growsim.pictures.reading import load_gray


def _tree_picture(h=120, w=90, dark=True):
    """A stick tree: trunk and two branches, drawn 3 px wide."""
    fg = np.zeros((h, w), bool)
    fg[40:h, w // 2 - 1 : w // 2 + 2] = True
    for i in range(30):
        fg[70 - i : 73 - i, w // 2 + i] = True
        fg[60 - i : 63 - i, w // 2 - i] = True
    rng = np.random.default_rng(0)
    g = np.where(fg, 0.15, 0.85) + rng.normal(0, 0.03, fg.shape)
    g = np.clip(g, 0, 1)
    return (g if dark else 1 - g), fg


def test_otsu_separates_two_levels():
    g, fg = _tree_picture()
    t = otsu_threshold(g)
    assert 0.2 < t < 0.8
    np.testing.assert_array_equal(g <= t, fg)


@pytest.mark.parametrize("dark", [True, False])
def test_polarity_auto(dark):
    g, fg = _tree_picture(dark=dark)
    np.testing.assert_array_equal(silhouette(g), fg)
    wrong = "light" if dark else "dark"
    # the wrong polarity makes the background the silhouette: 96 % of the picture
    with pytest.raises(UserInputError, match=f"fills the frame.*polarity {wrong}"):
        silhouette(g, polarity=wrong)
    block = np.ones((120, 90))
    block[20:100, 20:70] = 0.15  # 37 % dark, 63 % light: either polarity is a silhouette
    np.testing.assert_array_equal(silhouette(block, polarity="dark"), block < 0.5)
    np.testing.assert_array_equal(silhouette(block, polarity="light"), block > 0.5)


def test_fixed_threshold_and_mask():
    g, fg = _tree_picture()
    np.testing.assert_array_equal(silhouette(g, threshold=0.5), fg)
    mask = np.zeros_like(g)
    mask[:, :45] = 1.0  # keep the left half only
    sil = silhouette(g, mask=mask)
    assert sil[:, 46:].sum() == 0 and sil[:, :45].sum() == fg[:, :45].sum()
    with pytest.raises(UserInputError, match="mask size"):
        silhouette(g, mask=np.ones((3, 3)))
    with pytest.raises(UserInputError, match="all black"):
        silhouette(g, mask=np.zeros_like(g))


def test_empty_and_full_silhouettes_raise():
    with pytest.raises(UserInputError, match=r"white\.png: the picture is uniform"):
        silhouette(np.ones((10, 10)), name="white.png")
    nearly = np.ones((10, 10))
    nearly[0, 0] = 0.9
    with pytest.raises(UserInputError, match="empty"):
        silhouette(nearly, threshold=0.5)
    with pytest.raises(UserInputError, match="whole picture"):
        silhouette(nearly * 0.5, threshold=0.9, polarity="dark")
    with pytest.raises(UserInputError, match="threshold"):
        silhouette(nearly, threshold=2.0)
    with pytest.raises(UserInputError, match="polarity"):
        silhouette(np.eye(10), polarity="up")


def _speckles(p, shape=(200, 200), seed=0):
    """Black specks on white, each pixel black with probability ``p``."""
    return np.where(np.random.default_rng(seed).random(shape) < p, 0.0, 1.0)


def test_degenerate_silhouettes_are_refused(tmp_path):
    """One pixel, noise and a full frame are refused, naming the picture (fit-image used to
    "fit" a single pixel at NCC 0.80 and noise at 0.86)."""
    one = np.ones((100, 100))
    one[50, 50] = 0.0
    with pytest.raises(UserInputError, match=r"one\.png: the silhouette is too small: 1 "):
        silhouette(one, name="one.png")
    speck = np.ones((400, 400))
    speck[100:110, 200:210] = 0.0  # 100 pixels, but 0.06 % of the picture
    with pytest.raises(UserInputError, match=r"speck\.png: the silhouette is too small"):
        silhouette(speck, name="speck.png")
    uniform = np.random.default_rng(0).random((200, 200))
    with pytest.raises(UserInputError, match=r"noise\.png: the silhouette is too noisy"):
        silhouette(uniform, name="noise.png")
    for p in (0.03, 0.2, 0.4):  # sparse specks to near-connected noise
        with pytest.raises(UserInputError, match="too noisy"):
            silhouette(_speckles(p), name="specks.png")
    frame = np.zeros((60, 60))
    frame[[0, -1], :] = 1.0
    frame[:, [0, -1]] = 1.0  # a light border round a dark picture: 93 % foreground
    with pytest.raises(UserInputError, match=r"full\.png: the silhouette fills the frame"):
        silhouette(frame, name="full.png")
    # through files (fit-image): the message names the file
    Image.fromarray((one * 255).astype(np.uint8)).save(tmp_path / "dot.png")
    Image.fromarray((uniform * 255).astype(np.uint8)).save(tmp_path / "noise.png")
    g, _ = _tree_picture()
    with pytest.raises(UserInputError, match=r"dot\.png: the silhouette is too small"):
        read_silhouettes(g, tmp_path / "dot.png")
    with pytest.raises(UserInputError, match=r"noise\.png: the silhouette is too noisy"):
        read_silhouettes(tmp_path / "noise.png", g)


@pytest.mark.parametrize("size", [32, 64, 128, 256, 512])
@pytest.mark.parametrize("line_width", ["thin", "radius"])
def test_tree_silhouettes_are_accepted(size, line_width):
    """Trees drawn as growsim draws them (1-pixel lines whose crossings enclose many tiny
    holes, or tubes) pass the checks at every size, as do the stick tree and a margin."""
    from growsim.models import ifs3d
    from growsim.objectives.silhouette import plant_views

    views = plant_views(ifs3d.develop(ifs3d.PRESETS["table1"]), size, line_width)
    for v in views:
        np.testing.assert_array_equal(silhouette(np.where(v > 0, 0.1, 0.9)), v > 0)
    g, fg = _tree_picture()
    np.testing.assert_array_equal(silhouette(np.pad(g, 100, constant_values=0.85)), np.pad(fg, 100))


def test_load_gray_formats(tmp_path):
    rgb = np.zeros((6, 8, 3), np.uint8)
    rgb[..., 0] = 255
    Image.fromarray(rgb).save(tmp_path / "a.jpg")
    g = load_gray(tmp_path / "a.jpg")
    assert g.shape == (6, 8) and 0.2 < g.mean() < 0.4  # red luminance ~0.3
    rgba = np.zeros((6, 8, 4), np.uint8)
    rgba[2, 3] = [0, 0, 0, 255]  # one opaque black pixel, the rest transparent -> white
    Image.fromarray(rgba).save(tmp_path / "b.png")
    g = load_gray(tmp_path / "b.png")
    assert g[2, 3] == 0.0 and g.sum() == 47.0
    (tmp_path / "c.png").write_text("nope")
    with pytest.raises(UserInputError, match="cannot read"):
        load_gray(tmp_path / "c.png")
    with pytest.raises(UserInputError, match="not found"):
        load_gray(tmp_path / "d.png")


def test_frame_is_size_and_margin_invariant():
    _, fg = _tree_picture()
    small = frame_silhouettes(fg, fg, 32)
    # the same tree with a wide margin and 3x larger: the same framed silhouette
    big = np.zeros((3 * fg.shape[0] + 100, 3 * fg.shape[1] + 300), bool)
    big[60 : 60 + 3 * fg.shape[0], 200 : 200 + 3 * fg.shape[1]] = np.kron(fg, np.ones((3, 3)))
    framed = frame_silhouettes(big, big, 32)
    inter = (framed & small).sum()
    assert inter / np.sqrt(framed.sum() * small.sum()) > 0.9
    # trunk base at the bottom centre, top row reached
    assert small[0, 31, 16] == 1 and small[0, 0].any()


def test_frame_shares_scale_between_views():
    _, fg = _tree_picture()
    wide = np.zeros((120, 300), bool)
    wide[40:120, 149:152] = True
    wide[60, 20:280] = True  # a very wide side view constrains the common scale
    out = frame_silhouettes(fg, wide, 32)
    assert out[1, :, 0].any() or out[1, :, 31].any()  # the wide view touches the sides
    assert not out[0, 0].any()  # so the front view no longer reaches the top


def test_read_silhouettes_missing_view():
    g, _ = _tree_picture()
    with pytest.raises(UserInputError, match="side view is missing"):
        read_silhouettes(g, None)
    assert read_silhouettes(g, g, size=16).shape == (2, 16, 16)


def test_silhouette_image(tmp_path):
    p = silhouette_image([np.eye(8), np.ones((8, 8))], tmp_path / "s.png", titles=["a", "b"])
    im = np.asarray(Image.open(p))
    assert im.shape[0] == 14 + 32 and im.shape[1] == 32 + 4 + 32
    assert im[14:, 32 + 4 :].max() == 0  # the all-foreground view is black
    with pytest.raises(UserInputError):
        silhouette_image([np.eye(4)], tmp_path / "missing_dir" / "s.png")


@pytest.mark.parametrize("scale", [1, 3, 4, 7])
def test_thin_framing_inverts_the_thin_renderer(scale):
    # a line drawing of a tree at any scale (with a margin) frames into exactly the
    # silhouettes the thin renderer draws for it: the fit's target is the tree's own
    from growsim.models import honda, ifs3d
    from growsim.objectives.silhouette import plant_views

    rng = np.random.default_rng(scale)
    trees = [ifs3d.develop(ifs3d.PRESETS["table1"]), honda.develop(honda.PRESETS["ginkgo"])]
    while len(trees) < 5:
        bare = [p for p in ifs3d.PARAMS[2:] if p not in ifs3d.LEAF_PARAMS]
        tree = ifs3d.develop({p.name: rng.uniform(p.low, p.high) for p in bare})
        # a picture's trunk base is found in its lowest rows: trees standing on their base
        if min(tree.start[:, 1].min(), tree.end[:, 1].min()) >= 0.0:
            trees.append(tree)
    for tree in trees:
        views = plant_views(tree, 64)
        pics = [np.pad(np.kron(v, np.ones((scale, scale))) > 0, 17) for v in views]
        assert np.array_equal(frame_silhouettes(*pics, 64, line_width="thin"), views)
    # the area framing (for tubes drawn at their radius) fattens such lines
    assert not np.array_equal(frame_silhouettes(*pics, 64), views)


def test_picture_target_of_the_thin_objective_is_the_rendered_one(tmp_path):
    from PIL import Image

    from growsim.models import ifs3d
    from growsim.objectives.silhouette import SilhouetteObjective, plant_views

    tree = ifs3d.develop(ifs3d.PRESETS["table1"])
    paths = []
    for v, label in zip(plant_views(tree, 64), ("front", "side")):
        img = np.where(np.kron(v, np.ones((4, 4))) > 0, 20, 240).astype(np.uint8)
        Image.fromarray(np.pad(img, 30, constant_values=240)).save(tmp_path / f"{label}.png")
        paths.append(str(tmp_path / f"{label}.png"))
    obj = SilhouetteObjective(front=paths[0], side=paths[1])
    rendered = SilhouetteObjective(target_model="ifs3d", target_preset="table1")
    assert np.array_equal(obj.target, rendered.target) and obj(tree) == 1.0


def test_radius_framing_draws_branches_as_the_renderer_does():
    """A photo's silhouette is framed as tubes are drawn: a branch thinner than a raster
    pixel is one pixel wide (its skeleton), a thick one as wide as it is (pixels at least
    COVER_SHARE covered), not a pixel fatter (issue 16)."""
    from growsim.kernels.raster import draw_segments
    from growsim.pictures.images import COVER_SHARE

    assert 0.0 < COVER_SHARE <= 0.5
    pic = np.zeros((400, 400), bool)
    pic[0:400, 196:204] = True  # trunk 8 px: 1.3 raster px at 64
    pic[100:102, 60:340] = True  # a branch 2 px thick: a third of a raster pixel
    out = frame_silhouettes(pic, None, 64)[0]
    widths = out.sum(axis=1)
    branch_row = int(np.argmax(widths))
    assert widths[branch_row] >= 44  # the thin branch survives, one pixel thick
    assert out[branch_row - 1 : branch_row + 2].sum(axis=0).max() <= 3  # with the trunk
    assert set(widths[40:60].tolist()) <= {1, 2}  # the trunk: 1.3 px, not 2-3
    # the same trunk drawn as a tube of that width covers as many pixels
    tube = np.zeros((64, 64), np.uint8)
    k = 63.0 / 400
    draw_segments(np.array([[32.0, 63.5]]), np.array([[32.0, 0.5]]), np.array([8 * k]), tube)
    assert abs(int(tube[40:60].sum()) - int(widths[40:60].sum())) <= 20


def _photo(h=96, w=80, seed=0):
    """A small synthetic colour photo: a sky gradient, a green ground strip, a brown
    stick tree, camera noise."""
    _, fg = _tree_picture(h, w)
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 1.0, h)[:, None, None]
    rgb = (1 - t) * np.array([0.45, 0.65, 0.95]) + t * np.array([0.75, 0.85, 1.0])
    rgb = np.broadcast_to(rgb, (h, w, 3)).copy()
    rgb[int(0.85 * h) :] = (0.25, 0.5, 0.15)
    rgb[fg] = (0.35, 0.25, 0.18)
    return np.clip(rgb + rng.normal(0, 0.02, rgb.shape), 0, 1)


@pytest.mark.parametrize("dark", [True, False])
@pytest.mark.parametrize("paper", [0.85, 1.0])
def test_drawings_are_classified_drawings(dark, paper, tmp_path):
    g, fg = _tree_picture(dark=dark)
    if paper == 1.0:  # clean black on white, anti-aliased edges, saved as JPEG
        g = np.where(fg, 0.0, 1.0)
        g[1:] = 0.5 * (g[1:] + g[:-1])
    path = tmp_path / "d.jpg"
    Image.fromarray(np.round(255 * g).astype(np.uint8)).convert("RGB").save(path, quality=85)
    assert classify_picture(g)[0] == "drawing"
    kind, why = classify_picture(path)
    assert kind == "drawing" and "grey levels" in why


@pytest.mark.parametrize("seed", [0, 1])
def test_photos_are_classified_photos(seed, tmp_path):
    rgb = _photo(seed=seed)
    assert classify_picture(rgb)[0] == "photo"
    path = tmp_path / "p.jpg"
    Image.fromarray(np.round(255 * rgb).astype(np.uint8)).save(path, quality=80)
    kind, why = classify_picture(path)
    assert kind == "photo" and "colour" in why


@pytest.mark.parametrize("line_width", ["thin", "radius"])
def test_unframe_puts_the_framed_silhouette_back_in_place(line_width):
    _, fg = _tree_picture()
    side = np.fliplr(fg)
    framed = frame_silhouettes(fg, side, 64, line_width)
    for v, mask in enumerate((fg, side)):
        back = unframe(framed[v], fg, side, view=v, line_width=line_width)
        assert back.shape == mask.shape
        # the silhouette comes back where it was, a raster pixel (< 2 picture px) wider
        assert (back & mask).sum() >= 0.97 * mask.sum()
        assert back.sum() <= 2.5 * mask.sum()


def _enlarged(view, inner, margin, paper=0.85, fmt="png", tmp_path=None):
    """A 64 px view enlarged by nearest neighbour to ``inner`` px (any factor), ink at
    0.15 on ``paper`` with ``margin`` px around, paper noise; read back as a silhouette
    (through a PNG or JPEG file when ``tmp_path`` is given)."""
    im = Image.fromarray(np.where(view > 0, 255, 0).astype(np.uint8))
    big = np.asarray(im.resize((inner, inner), Image.NEAREST)) > 127
    g = np.pad(np.where(big, 0.15, paper), margin, constant_values=paper)
    g = np.clip(g + np.random.default_rng(inner).normal(0, 0.015, g.shape), 0, 1)
    if tmp_path is None:
        return silhouette(g)
    path = tmp_path / f"d{inner}.{fmt}"
    Image.fromarray(np.round(255 * g).astype(np.uint8)).convert("RGB").save(path, quality=90)
    return silhouette(path)


def _standing_trees(n, seed=0):
    """The Table 1 tree and random bare IFS trees standing on their base (a picture's
    trunk base is found in its lowest rows)."""
    from growsim.models import ifs3d

    rng = np.random.default_rng(seed)
    trees = [ifs3d.develop(ifs3d.PRESETS["table1"])]
    bare = [p for p in ifs3d.PARAMS[2:] if p not in ifs3d.LEAF_PARAMS]
    while len(trees) < n:
        tree = ifs3d.develop({p.name: rng.uniform(p.low, p.high) for p in bare})
        if min(tree.start[:, 1].min(), tree.end[:, 1].min()) >= 0.0:
            trees.append(tree)
    return trees


@pytest.mark.parametrize(
    "inner, margin",
    [(80, 0), (96, 13), (147, 0), (160, 31), (224, 20), (300, 7), (327, 40), (461, 3)],
)
def test_thin_framing_of_a_drawing_enlarged_by_a_fraction(inner, margin):
    """A render enlarged by nearest neighbour by a factor that is not whole (1.25x-7.2x:
    drawn pixels of alternating widths, a boundary rounded either way at a tie), with a
    margin, frames back into the render pixel for pixel, as a whole factor does; the
    fitted tree is put back onto the picture where the drawing's pixels are."""
    from growsim.objectives.silhouette import plant_views

    for tree in _standing_trees(3, seed=inner):
        views = plant_views(tree, 64)
        whole = [np.pad(np.kron(v, np.ones((4, 4))) > 0, margin) for v in views]
        big = [_enlarged(v, inner, margin) for v in views]
        assert np.array_equal(frame_silhouettes(*whole, 64, line_width="thin"), views)
        framed = frame_silhouettes(*big, 64, line_width="thin")
        assert np.array_equal(framed, views)
        for v in range(2):
            back = unframe(framed[v], *big, view=v, line_width="thin")
            assert np.array_equal(back, big[v])
        # one picture, the front alone (framed by its own extent)
        front = plant_views(tree, 64, views=1)
        big = _enlarged(front[0], inner, margin)
        assert np.array_equal(frame_silhouettes(big, None, 64, "thin"), front)


@pytest.mark.parametrize("paper, fmt", [(0.85, "png"), (1.0, "jpg"), (0.9, "jpg")])
def test_fractional_drawing_files_frame_back(paper, fmt, tmp_path):
    """The same through a file: grey or white paper, PNG or JPEG (3.5x, 2.3x, 5.1x)."""
    from growsim.objectives.silhouette import plant_views

    views = plant_views(_standing_trees(1)[0], 64)
    for inner, margin in ((224, 32), (147, 0), (327, 21)):
        big = [_enlarged(v, inner, margin, paper, fmt, tmp_path) for v in views]
        assert np.array_equal(frame_silhouettes(*big, 64, line_width="thin"), views)


def test_drawn_pixels_only_reads_pixel_drawings():
    from growsim.pictures.pixels import drawn_pixels

    raster = np.zeros((30, 30), np.uint8)
    raster[4:, 15] = 255
    raster[10, 5:26] = 255
    raster[np.arange(4, 14), np.arange(15, 25)] = 255
    for inner in (60, 69, 100, 137):
        big = np.asarray(Image.fromarray(raster).resize((inner, inner), Image.NEAREST)) > 127
        pixels, rows, cols = drawn_pixels(np.pad(big, 5), inner / 30)
        assert np.array_equal(pixels, raster[4:, 5:26] > 0)
        assert rows.shape == cols.shape == (inner + 10,)
    # a pen drawing (strokes 3 px wide at any slope) has no pixel grid: framed as lines
    _, fg = _tree_picture()
    assert drawn_pixels(fg, 3.0) is None
    assert drawn_pixels(np.pad(raster > 0, 5), 1.0) is None  # not enlarged


def test_picture_silhouettes_remembers_a_file_until_it_changes(tmp_path):
    """A picture file is segmented once (a fit compiles its objective many times), each
    call gets its own copy, and a file changed on disk is read again."""
    import os

    from growsim.pictures import images

    def save_gray(g, path):
        Image.fromarray(np.round(255 * g).astype(np.uint8)).save(path)

    g = np.ones((40, 30))
    g[5:, 15] = 0.0
    path = tmp_path / "tree.png"
    save_gray(g, path)
    images._segment_file.cache_clear()
    a = picture_silhouettes(str(path))[0]
    b = picture_silhouettes(path)[0]
    assert images._segment_file.cache_info().hits == 1
    a[:] = False  # the caller's copy: the cache is not touched
    assert np.array_equal(b, picture_silhouettes(path)[0]) and b.sum() == 35
    g[5:, 10] = 0.0
    save_gray(g, path)
    os.utime(path, ns=(1, 1))  # a new modification time, whatever the clock's resolution
    assert picture_silhouettes(path)[0].sum() == 70
