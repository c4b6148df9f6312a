"""Two trees whose crowns touch, one standing object of the scene (issue 41): split apart
by their colours (:func:`growsim.pictures.colours.split_touching`), the tree kept and the
split recorded when the other is small, refused naming the boxes of both when it is as
large; one tree of two colours (its limbs, its lit and shaded sides) stays whole.

The pictures are built here: a blue sky, a green ground strip, crowns as discs of
textured leaves on trunks standing on the ground.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from growsim.errors import UserInputError
from growsim.pictures.colours import split_touching
from growsim.pictures.photo import segment_photo
from growsim.pictures.scene import find_scene

H, W = 200, 300
SKY, GROUND = (0.55, 0.7, 0.95), (0.3, 0.45, 0.2)
ORANGE, GREEN, GREY = (0.8, 0.5, 0.15), (0.2, 0.42, 0.15), (0.5, 0.5, 0.48)


def _iou(a, b) -> float:
    return float((a & b).sum() / max((a | b).sum(), 1))


def _scene(trees, seed=0):
    """A picture of ``trees`` (each ``(x, crown row, radius, colour, trunk colour)``,
    drawn in order, the later in front) and each tree's true mask."""
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[0:H, 0:W]
    rgb = np.ones((H, W, 3)) * SKY
    rgb[165:] = GROUND
    masks = []
    for x, row, radius, colour, bark in trees:
        crown = (yy - row) ** 2 + (xx - x) ** 2 < radius**2
        # leaves: ragged edge, the sky showing through here and there at the rim
        rim = (yy - row) ** 2 + (xx - x) ** 2 > (0.8 * radius) ** 2
        crown &= ~(rim & (rng.random((H, W)) < 0.3))
        trunk = (abs(xx - x) <= 3) & (yy >= row) & (yy < 172)
        shade = 1.0 + 0.25 * rng.standard_normal((H, W, 1))
        rgb = np.where(trunk[..., None], bark, rgb)
        rgb = np.where(crown[..., None], np.clip(np.array(colour) * shade, 0, 1), rgb)
        mask = crown | trunk
        masks = [m & ~mask for m in masks] + [mask]
    rgb = np.clip(rgb + rng.normal(0.0, 0.01, rgb.shape), 0.0, 1.0)
    return rgb, masks


def test_a_small_tree_touching_the_crown_is_split_off():
    """A big orange tree and a smaller green one in front of its crown's foot: before the
    split, the silhouette held both."""
    rgb, (big, small) = _scene([(170, 80, 55, ORANGE, GREY), (105, 125, 30, GREEN, GREY)])
    assert len(find_scene(rgb).objects) == 1  # one standing object: the crowns touch
    assert len(split_touching(find_scene(rgb)).objects) == 2
    seg = segment_photo(rgb)
    assert _iou(seg.tree, big) >= 0.85
    assert (seg.tree & small).sum() < 0.05 * small.sum()
    assert len(seg.split) == 1 and seg.record()["split_off"] == [list(seg.split[0])]
    x0, y0, x1, _ = seg.split[0]
    assert x0 <= 80 and x1 >= 125 and y0 <= 100  # the green crown's box
    assert "a touching tree split off at" in seg.describe()


def test_two_touching_trees_as_large_are_refused_then_settled_by_a_hint():
    rgb, (left, right) = _scene([(95, 85, 50, GREEN, GREY), (190, 80, 52, ORANGE, GREY)])
    with pytest.raises(UserInputError, match="which is the tree") as err:
        segment_photo(rgb)
    message = str(err.value)
    assert "\n" not in message and "--point" in message
    boxes = [list(map(int, b.split(","))) for b in re.findall(r"--box (\d+,\d+,\d+,\d+)", message)]
    assert len(boxes) == 2 and boxes[0][0] < boxes[1][0]  # ready boxes, left to right
    for box, truth, other in ((boxes[0], left, right), (boxes[1], right, left)):
        seg = segment_photo(rgb, box=box)
        assert _iou(seg.tree, truth) >= 0.85, box
        assert (seg.tree & other).sum() < 0.05 * other.sum(), box
    rows, cols = np.nonzero(right)
    seg = segment_photo(rgb, point=(int(np.median(cols)), int(rows.min()) + 15))
    assert _iou(seg.tree, right) >= 0.85


@pytest.mark.parametrize(
    "trees",
    [
        # a crown on a thick grey trunk: two colours, the trunk thin and not standing apart
        [(150, 70, 50, ORANGE, (0.45, 0.45, 0.6))],
        # a lone green tree: one colour
        [(150, 80, 55, GREEN, GREY)],
    ],
)
def test_one_tree_of_two_colours_stays_whole(trees):
    rgb, (truth,) = _scene(trees)
    scene = find_scene(rgb)
    assert len(split_touching(scene).objects) == len(scene.objects)
    seg = segment_photo(rgb)
    assert seg.split == () and _iou(seg.tree, truth) >= 0.85


def test_a_crown_lit_on_one_side_stays_whole():
    """A crown yellow-orange on its sunlit side and brown-red on its shaded side: two hues
    touching all along, one tree."""
    rgb, (truth,) = _scene([(150, 80, 55, ORANGE, GREY)], seed=1)
    xx = np.arange(W)[None, :]
    shaded = truth & (xx > 150) & (np.arange(H)[:, None] < 140)
    rgb[shaded] = np.clip(rgb[shaded] * [0.8, 0.45, 0.6], 0, 1)
    scene = find_scene(rgb)
    assert len(split_touching(scene).objects) == len(scene.objects)
    assert segment_photo(rgb).split == ()
