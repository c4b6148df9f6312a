"""The segment rasteriser against its oracle (:mod:`naive.raster`)."""

from __future__ import annotations

import numpy as np
import pytest
from naive import raster as oracle

from growsim.errors import UserInputError
from growsim.kernels.raster import draw_segments, draw_segments_depth

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
    np.testing.assert_array_equal(got, oracle.draw_segments(a, b, width, H, W))


@pytest.mark.parametrize("seed", range(4))
def test_wide_lines_match_oracle(seed):
    rng = np.random.default_rng(100 + seed)
    H, W = 31, 23
    a, b = _random_segments(rng, 25, H, W)
    width = rng.uniform(0.2, 7.0, len(a))
    got = draw_segments(a, b, width, np.zeros((H, W), np.uint8))
    np.testing.assert_array_equal(got, oracle.draw_segments(a, b, width, H, W))


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
    np.testing.assert_array_equal(got, oracle.draw_segments(a, b, width, 7, 8))


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
    d0, i0 = oracle.draw_segments_depth(a, b, za, zb, width, H, W)
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
