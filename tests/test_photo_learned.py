"""The tree below the horizon learned from the picture itself (issue 41): a round crown
whose lower half stands before a treeline of its colours, read pixel by pixel against the
row, ends along the horizon; the classifier learned on its upper half restores it."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage

import growsim.pictures.photo as photo
from growsim.pictures.learned import envelope, learned_below
from growsim.pictures.photo import segment_photo
from growsim.pictures.scene import Standing

HORIZON = 150


def _crown_before_treeline(seed=3, h=300, w=400):
    """A sky, a dark treeline with a ragged top along the horizon, a field; a round crown
    of leaves (two tones, in clumps of 4 pixels) over the horizon and its trunk. Returns
    the picture and the true silhouette."""
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[:h, :w]
    rgb = np.stack([0.55 + 0.25 * yy / h, 0.7 + 0.2 * yy / h, 0.95 + 0 * yy], -1)
    top = HORIZON - 25 + 6 * np.sin(xx[0] / 9.0) + 4 * np.sin(xx[0] / 3.3)
    band = (yy >= top[None, :]) & (yy < HORIZON + 10)
    haze = ndimage.gaussian_filter(rng.standard_normal((h, w)), 3)[..., None]
    rgb[band] = (np.array([0.25, 0.38, 0.3]) + 0.04 * haze)[band]
    field = yy >= HORIZON + 10
    rgb[field] = (np.array([0.45, 0.6, 0.25]) + 0.03 * rng.standard_normal((h, w, 1)))[field]
    crown = (yy - 100) ** 2 / 75**2 + (xx - 200) ** 2 / 90**2 < 1
    clumps = rng.random((h // 4 + 1, w // 4 + 1)) > 0.5
    tone = np.kron(clumps, np.ones((4, 4)))[:h, :w, None] * np.array([0.6, 1.0, 0.4])
    trunk = (xx > 192) & (xx < 208) & (yy > HORIZON) & (yy < 240)
    rgb[trunk] = [0.3, 0.22, 0.15]
    rgb[crown] = (np.array([0.12, 0.3, 0.08]) + 0.18 * tone)[crown]
    return np.clip(rgb, 0, 1), crown | trunk, crown


def _iou(a, b):
    return float((a & b).sum() / (a | b).sum())


def test_a_crown_before_a_treeline_is_whole(monkeypatch):
    """Measured (2026-12-07, leaves in clumps of 4 pixels): the silhouette's IoU 0.982, its
    trunk included, and its outline nowhere along the horizon; without the learned step
    0.599 and 62 % (the lower crown taken for the treeline, the classic fault of real
    photographs). With tones changing pixel by pixel, finer than a leaf clump at the
    working size, the crown's reading below the treeline is a speckle no part of which
    stands tall (``trunk.STAND``): it is refused, naming ``--box``."""
    rgb, truth, crown = _crown_before_treeline()
    seg = segment_photo(rgb)
    lower = crown & (np.arange(rgb.shape[0])[:, None] >= HORIZON)
    assert (seg.tree & lower).sum() >= 0.9 * lower.sum()
    assert _iou(seg.tree, truth) >= 0.9
    assert seg.ends_at_horizon() < 0.2
    # the treeline beside the crown is not taken
    beside = ~ndimage.binary_dilation(truth, iterations=3)
    assert (seg.tree & beside).sum() <= 0.01 * truth.sum()
    # without it, the silhouette ends along the horizon (what this step is for)
    monkeypatch.setattr(photo, "learned_below", lambda rgb, tree, low, *args: low)
    bare = segment_photo(rgb)
    assert _iou(bare.tree, truth) < 0.75 and bare.ends_at_horizon() > 0.4


def test_the_same_picture_gives_the_same_silhouette():
    rgb, _, _ = _crown_before_treeline(seed=5)
    assert np.array_equal(segment_photo(rgb).tree, segment_photo(rgb).tree)


@pytest.fixture
def crown_inputs():
    rgb, truth, crown = _crown_before_treeline()
    under = np.arange(crown.shape[0])[:, None] >= HORIZON
    obj = Standing(crown & ~under, int((crown & ~under).sum()), 25, HORIZON, 110, 290,
                   ((192, 208),))  # fmt: skip
    sky = ~truth & ~under & (rgb[..., 2] > 0.9)
    return rgb, crown, under, sky, obj


def test_a_whole_silhouette_is_left_as_it_is(crown_inputs):
    """The tree found below the cut already (its outline does not end along the horizon):
    nothing is learned, what was found is returned."""
    rgb, crown, under, sky, obj = crown_inputs
    low = crown & under
    out = learned_below(rgb, crown & ~under, low, under, sky, obj, np.ones_like(crown),
                        np.full(crown.shape[1], float(HORIZON)), 1.0)  # fmt: skip
    assert out is low


def test_what_is_learned_joins_the_tree_inside_its_envelope(crown_inputs):
    rgb, crown, under, sky, obj = crown_inputs
    above = crown & ~under
    cut = np.full(crown.shape[1], float(HORIZON))
    out = learned_below(rgb, above, np.zeros_like(crown), under, sky, obj, np.ones_like(crown),
                        cut, 1.0)  # fmt: skip
    assert not (out & above).any()
    assert not (out & ~envelope(above)).any()
    assert ndimage.label(out | above, np.ones((3, 3)))[1] == 1
    assert (out & crown).sum() >= 0.9 * (crown & under).sum()


def test_the_envelope_widens_below_the_crown():
    above = np.zeros((40, 40), bool)
    above[5:20, 15:25] = True
    env = envelope(above)
    widths = env.sum(axis=1)
    assert widths[10] == 10 and widths[20] == 12  # its own rows; one row below: a pixel more
    assert env[39].nonzero()[0].tolist() == list(range(5, 35))  # 20 rows below: 10 either side
    assert np.all(np.diff(widths[20:]) >= 0) and not env[:5].any()
