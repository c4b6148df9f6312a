"""The segment rasteriser against a slow, obviously correct NumPy oracle."""

from __future__ import annotations

import numpy as np
import pytest

from growsim.errors import UserInputError
from growsim.kernels.raster import draw_segments, draw_segments_depth

# ----------------------------------------------------------------------------- oracle


def _axis_interval(a0, d, lo_edge):
    """t-interval where lo_edge <= a0 + t d < lo_edge + 1, as (lo, lo_closed, hi, hi_closed)."""
    n = a0.shape
    lo = np.full(n, -np.inf)
    hi = np.full(n, np.inf)
    lo_c = np.ones(n, bool)
    hi_c = np.ones(n, bool)
    with np.errstate(divide="ignore", invalid="ignore"):
        t_in = (lo_edge - a0) / d
        t_out = (lo_edge + 1 - a0) / d
    pos = d > 0
    neg = d < 0
    zero = d == 0
    lo[pos], hi[pos], hi_c[pos] = t_in[pos], t_out[pos], False
    lo[neg], lo_c[neg], hi[neg] = t_out[neg], False, t_in[neg]
    inside = (a0 >= lo_edge) & (a0 < lo_edge + 1)
    empty = zero & ~inside
    lo[empty], hi[empty] = 1.0, 0.0
    return lo, lo_c, hi, hi_c


def _intersect(*ivals):
    lo, lo_c, hi, hi_c = ivals[0]
    lo, lo_c, hi, hi_c = lo.copy(), lo_c.copy(), hi.copy(), hi_c.copy()
    for l2, lc2, h2, hc2 in ivals[1:]:
        gt = l2 > lo
        eq = l2 == lo
        lo_c = np.where(gt, lc2, np.where(eq, lo_c & lc2, lo_c))
        lo = np.maximum(lo, l2)
        lt = h2 < hi
        eq = h2 == hi
        hi_c = np.where(lt, hc2, np.where(eq, hi_c & hc2, hi_c))
        hi = np.minimum(hi, h2)
    return (lo < hi) | ((lo == hi) & lo_c & hi_c)


def naive_thin(a, b, H, W):
    """Per segment, the boolean (H, W) mask of pixel squares the segment touches."""
    ii, jj = np.meshgrid(np.arange(H, dtype=float), np.arange(W, dtype=float), indexing="ij")
    masks = []
    for (ax, ay), (bx, by) in zip(a, b):
        dx, dy = bx - ax, by - ay
        one = np.ones(ii.shape)
        ix = _axis_interval(ax * one, dx * one, jj)
        iy = _axis_interval(ay * one, dy * one, ii)
        unit = (
            np.zeros(ii.shape),
            np.ones(ii.shape, bool),
            np.ones(ii.shape),
            np.ones(ii.shape, bool),
        )
        masks.append(_intersect(ix, iy, unit))
    return masks


def naive_t(a, b, H, W):
    """Per segment, (squared distance, t) of each pixel centre to the segment."""
    cy, cx = np.meshgrid(np.arange(H) + 0.5, np.arange(W) + 0.5, indexing="ij")
    out = []
    for (ax, ay), (bx, by) in zip(a, b):
        dx, dy = bx - ax, by - ay
        L2 = dx * dx + dy * dy
        t = np.zeros(cx.shape) if L2 == 0 else np.clip(((cx - ax) * dx + (cy - ay) * dy) / L2, 0, 1)
        d2 = (ax + t * dx - cx) ** 2 + (ay + t * dy - cy) ** 2
        out.append((d2, t))
    return out


def naive_masks(a, b, width, H, W):
    thin = naive_thin(a, b, H, W)
    dt = naive_t(a, b, H, W)
    masks = []
    for k in range(len(a)):
        m = thin[k].copy()
        if width[k] > 1:
            m |= dt[k][0] <= (0.5 * width[k]) ** 2
        masks.append(m)
    return masks, dt


def naive_draw(a, b, width, H, W):
    masks, _ = naive_masks(a, b, width, H, W)
    out = np.zeros((H, W), np.uint8)
    for m in masks:
        out[m] = 1
    return out


def naive_depth(a, b, za, zb, width, H, W):
    masks, dt = naive_masks(a, b, width, H, W)
    depth = np.full((H, W), np.inf)
    ids = np.full((H, W), -1, np.int64)
    for k, m in enumerate(masks):
        z = za[k] + dt[k][1] * (zb[k] - za[k])
        upd = m & (z < depth)
        depth[upd] = z[upd]
        ids[upd] = k
    return depth, ids


# ----------------------------------------------------------------------------- tests


def _random_segments(rng, n, H, W, spread=1.3, short=False):
    a = rng.uniform(-0.3 * W, spread * W, (n, 2)) * [1, H / W]
    if short:
        b = a + rng.normal(0, 1.5, (n, 2))
    else:
        b = rng.uniform(-0.3 * W, spread * W, (n, 2)) * [1, H / W]
    return a, b


@pytest.mark.parametrize("seed", range(6))
def test_thin_lines_match_oracle(seed):
    rng = np.random.default_rng(seed)
    H, W = rng.integers(5, 40, 2)
    a, b = _random_segments(rng, 40, H, W, short=seed % 2 == 1)
    width = np.ones(len(a))
    got = draw_segments(a, b, width, np.zeros((H, W), np.uint8))
    np.testing.assert_array_equal(got, naive_draw(a, b, width, H, W))


@pytest.mark.parametrize("seed", range(4))
def test_wide_lines_match_oracle(seed):
    rng = np.random.default_rng(100 + seed)
    H, W = 31, 23
    a, b = _random_segments(rng, 25, H, W)
    width = rng.uniform(0.2, 7.0, len(a))
    got = draw_segments(a, b, width, np.zeros((H, W), np.uint8))
    np.testing.assert_array_equal(got, naive_draw(a, b, width, H, W))


EDGE = [
    # points, inside, on pixel edges, outside
    ([2.5, 2.5], [2.5, 2.5]),
    ([3.0, 3.0], [3.0, 3.0]),
    ([-0.5, 2.0], [-0.5, 2.0]),
    # axis-aligned on pixel boundaries (half-open: y = 3 belongs to row 3)
    ([0.0, 3.0], [7.0, 3.0]),
    ([2.0, 0.0], [2.0, 6.0]),
    ([7.0, 3.0], [0.0, 3.0]),
    # end points exactly on grid lines
    ([1.0, 1.2], [5.0, 4.7]),
    ([5.0, 1.2], [1.0, 4.7]),
    ([1.3, 5.0], [4.2, 1.0]),
    # fully outside, partly outside, huge coordinates
    ([-5.0, -5.0], [-1.0, -2.0]),
    ([-3.0, 2.5], [20.0, 4.1]),
    ([-1e12, 3.3], [1e12, 3.3]),
    ([3.3, -1e15], [3.7, 1e15]),
    ([8.0, 0.5], [9.0, 0.5]),
    # steep, shallow, tiny
    ([2.2, 0.1], [2.9, 7.9]),
    ([0.1, 2.2], [7.9, 2.9]),
    ([4.49, 4.49], [4.51, 4.52]),
]


@pytest.mark.parametrize(("a", "b"), EDGE)
@pytest.mark.parametrize("w", [1.0, 2.5])
def test_edge_cases_match_oracle(a, b, w):
    a = np.array([a], float)
    b = np.array([b], float)
    width = np.array([w])
    got = draw_segments(a, b, width, np.zeros((7, 8), np.uint8))
    np.testing.assert_array_equal(got, naive_draw(a, b, width, 7, 8))


def test_known_pictures():
    img = draw_segments(
        np.array([[0.5, 0.5]]), np.array([[3.5, 3.5]]), 1.0, np.zeros((4, 4), np.uint8)
    )
    np.testing.assert_array_equal(img, np.eye(4, dtype=np.uint8))
    img = draw_segments(
        np.array([[0.2, 0.5]]), np.array([[3.8, 2.5]]), 1.0, np.zeros((4, 4), np.uint8)
    )
    # a shallow line touches two rows in its middle columns
    assert img[:, 0].tolist() == [1, 0, 0, 0]
    assert img[:, 3].tolist() == [0, 0, 1, 0]
    assert img.sum() >= 5
    # a point
    img = draw_segments(
        np.array([[1.5, 2.5]]), np.array([[1.5, 2.5]]), 1.0, np.zeros((4, 4), np.uint8)
    )
    assert img.sum() == 1 and img[2, 1] == 1


def test_existing_pixels_untouched_and_width_scalar():
    out = np.zeros((5, 5), np.uint8)
    out[0, 0] = 1
    draw_segments(np.array([[4.5, 4.5]]), np.array([[4.5, 4.5]]), 1.0, out)
    assert out[0, 0] == 1 and out[4, 4] == 1 and out.sum() == 2
    draw_segments(np.zeros((0, 2)), np.zeros((0, 2)), np.zeros(0), out)
    assert out.sum() == 2


@pytest.mark.parametrize("seed", range(4))
def test_depth_matches_oracle(seed):
    rng = np.random.default_rng(7 + seed)
    H, W = 17, 29
    a, b = _random_segments(rng, 30, H, W, short=seed % 2 == 0)
    za = rng.uniform(-5, 5, len(a))
    zb = rng.uniform(-5, 5, len(a))
    width = rng.choice([1.0, 0.5, 3.0, 5.5], len(a))
    depth = np.full((H, W), np.inf)
    ids = np.full((H, W), -1, np.int64)
    draw_segments_depth(a, b, za, zb, width, depth, ids)
    d0, i0 = naive_depth(a, b, za, zb, width, H, W)
    np.testing.assert_allclose(depth, d0, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(ids, i0)
    # the covered set is the binary image's
    binary = draw_segments(a, b, width, np.zeros((H, W), np.uint8))
    np.testing.assert_array_equal(np.isfinite(depth), binary.astype(bool))


def test_depth_keeps_nearest():
    d = np.full((3, 3), np.inf)
    a = np.array([[0.5, 1.5], [0.5, 1.5]])
    b = np.array([[2.5, 1.5], [2.5, 1.5]])
    draw_segments_depth(a, b, np.array([2.0, 1.0]), np.array([2.0, 3.0]), 1.0, d)
    # the second segment is nearer at the left end, the first at the right end
    assert d[1].tolist() == [1.0, 2.0, 2.0]


@pytest.mark.parametrize(
    ("args", "msg"),
    [
        ((np.zeros((2, 3)), np.zeros((2, 3)), 1.0, np.zeros((4, 4), np.uint8)), "shape"),
        ((np.zeros((2, 2)), np.zeros((3, 2)), 1.0, np.zeros((4, 4), np.uint8)), "shape"),
        ((np.full((1, 2), np.nan), np.zeros((1, 2)), 1.0, np.zeros((4, 4), np.uint8)), "finite"),
        ((np.zeros((1, 2)), np.zeros((1, 2)), np.inf, np.zeros((4, 4), np.uint8)), "finite"),
        ((np.zeros((1, 2)), np.zeros((1, 2)), 1.0, np.zeros((4, 4), np.float32)), "uint8"),
        ((np.zeros((1, 2)), np.zeros((1, 2)), 1.0, np.zeros((4, 4, 2), np.uint8)), "2-D"),
    ],
)
def test_bad_input(args, msg):
    with pytest.raises(UserInputError, match=msg):
        draw_segments(*args)


def test_bad_depth_input():
    with pytest.raises(UserInputError, match="float64"):
        draw_segments_depth(
            np.zeros((1, 2)), np.zeros((1, 2)), 0.0, 0.0, 1.0, np.zeros((3, 3), np.uint8)
        )
    with pytest.raises(UserInputError, match="ids"):
        draw_segments_depth(
            np.zeros((1, 2)), np.zeros((1, 2)), 0.0, 0.0, 1.0, np.zeros((3, 3)), np.zeros((3, 3))
        )
    with pytest.raises(UserInputError, match="finite"):
        draw_segments_depth(np.zeros((1, 2)), np.zeros((1, 2)), np.nan, 0.0, 1.0, np.zeros((3, 3)))
