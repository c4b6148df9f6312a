"""The shared view kernels against their oracles (:mod:`naive.views`)."""

from __future__ import annotations

import numpy as np
import pytest
from naive import views as oracle

from growsim.kernels import views as V

# ----------------------------------------------------------------------------- helpers


def _random_coords(rng, n_views, M, size, spread=1.0):
    """Segments ``(V, 2, M, 2)``: mostly inside the raster, some across its border."""
    lo, hi = -0.25 * spread * size, (1 + 0.25 * spread) * size
    c = rng.uniform(lo, hi, (n_views, 2, M, 2))
    short = rng.random(M) < 0.5  # many segments below a pixel, as in deep trees
    c[:, 1, short] = c[:, 0, short] + rng.normal(0, 0.7, (n_views, short.sum(), 2))
    return c


#: points and segments on the border of an 8 x 8 raster and on pixel edges
BORDER = np.array(
    [
        [[0.0, 0.0], [0.0, 0.0]],  # the top-left corner
        [[8.0, 4.0], [8.0, 6.0]],  # on the right border: outside (half-open pixels)
        [[0.0, 7.999], [7.999, 7.999]],  # along the bottom row
        [[4.0, 0.0], [4.0, 8.0]],  # a column edge, from border to border
        [[-1.0, 3.5], [9.0, 3.5]],  # across the whole raster
        [[0.5, 0.5], [7.5, 7.5]],  # pixel centre to pixel centre
        [[3.0, 3.0], [3.0, 3.0]],  # a point on a pixel corner
    ]
)


def _border_coords():
    seg = BORDER.transpose(1, 0, 2)  # (2, M, 2)
    return np.stack([seg, seg[:, ::-1, ::-1]])  # a second view, transposed and reversed


# ----------------------------------------------------------------------------- framing


@pytest.mark.parametrize(
    ("h", "hw", "size"),
    [(2.0, 0.5, 64), (1.0, 1.0, 64), (0.0, 0.0, 64), (0.0, 0.3, 16), (3.0, 0.0, 1), (1.0, 2.0, 9)],
)
def test_frame_scale_matches_oracle(h, hw, size):
    assert V.frame_scale(h, hw, size) == oracle.frame_scale(h, hw, size)


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("size", [1, 16, 65])
def test_frame_points_matches_oracle(seed, size):
    rng = np.random.default_rng(seed)
    M = [1, 5, 40, 300][seed]
    start = rng.normal(0, 1, (M, 3))
    end = start + rng.normal(0, 0.3, (M, 3))
    base = rng.normal(0, 0.1, 3) if seed % 2 else start[0]
    c, k = V.frame_points(start, end, base, size)
    c0, k0 = oracle.frame_points(start, end, base, size)
    assert c.shape == (2, 2, M, 2)
    np.testing.assert_allclose(c, c0, rtol=0, atol=1e-10)
    assert k == pytest.approx(k0, rel=1e-14)
    # every framed point lies inside the raster, the extremes on pixel centres
    assert c.min() >= V.MARGIN - 1e-9 and c.max() <= size - V.MARGIN + 1e-9
    rows = c[:, :, :, 1]
    assert rows.max() == pytest.approx(size - V.MARGIN)  # the lowest point, bottom row


def test_frame_points_degenerate():
    # a single point: no height, no width: scale 1, the point at the bottom centre
    c, k = V.frame_points(np.zeros((1, 3)), np.zeros((1, 3)), np.zeros(3), 16)
    assert k == 1.0 and c[:, :, 0].tolist() == [[[8.0, 15.5]] * 2] * 2
    # no segments
    c, k = V.frame_points(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(3), 16)
    assert c.shape == (2, 2, 0, 2) and k == 1.0
    c0, k0 = oracle.frame_points(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(3), 16)
    assert k0 == k and c0.shape == c.shape
    # a horizontal branch: the half-width constrains; side view mirrors z
    c, k = V.frame_points([[0, 0, 0]], [[0, 0, 2.0]], np.zeros(3), 8)
    assert k == pytest.approx(3.5 / 2) and c[1, 1, 0, 0] == pytest.approx(0.5)


def test_frame_view_matches_oracle():
    rng = np.random.default_rng(3)
    u, y = rng.normal(0, 5, (2, 50))
    got = V.frame_view(u, y, 0.3, -1.0, 2.5, 32)
    want = oracle.frame_view(u, y, 0.3, -1.0, 2.5, 32)
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)
    col, row = V.frame_view(np.zeros(0), np.zeros(0), 0.0, 0.0, 1.0, 4)
    assert col.shape == row.shape == (0,)


# ----------------------------------------------------------------------------- rendering


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("size", [1, 2, 24])
def test_render_thin_matches_oracle(seed, size):
    rng = np.random.default_rng(seed)
    c = _random_coords(rng, 1 + seed % 3, 30, size, spread=seed % 2)
    img = V.render_thin(c, size)
    assert img.shape == (c.shape[0], size, size) and img.dtype == np.uint8
    np.testing.assert_array_equal(img, oracle.render_thin(c, size))


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("size", [1, 2, 24])
def test_render_antialiased_matches_oracle(seed, size):
    rng = np.random.default_rng(seed + 10)
    c = _random_coords(rng, 1 + seed % 3, 30, size, spread=seed % 2)
    acc = V.render_antialiased(c, size)
    assert acc.shape == (c.shape[0], size, size) and acc.max() <= 1.0
    np.testing.assert_allclose(acc, oracle.render_antialiased(c, size), rtol=0, atol=1e-12)


def test_render_border_cases_match_oracle():
    c = _border_coords()
    thin = V.render_thin(c, 8)
    np.testing.assert_array_equal(thin, oracle.render_thin(c, 8))
    assert thin[0, 0, 0] == 1 and thin[0, 4:7, 7].sum() == 0  # x = 8 is outside
    assert thin[0, 7].all()  # the bottom row
    aa = V.render_antialiased(c, 8)
    np.testing.assert_allclose(aa, oracle.render_antialiased(c, 8), rtol=0, atol=1e-12)
    # one segment at a time, each alone in the raster
    for m in range(c.shape[2]):
        one = c[:, :, m : m + 1]
        np.testing.assert_array_equal(V.render_thin(one, 8), oracle.render_thin(one, 8))


def test_render_empty_and_one_pixel():
    # no segments: blank views; an empty (0 x 0) raster; a one-pixel raster
    none = np.zeros((2, 2, 0, 2))
    assert V.render_thin(none, 5).sum() == 0 and V.render_antialiased(none, 5).sum() == 0
    c = _border_coords()
    assert V.render_thin(c, 0).shape == (2, 0, 0)
    assert V.render_antialiased(c, 0).shape == (2, 0, 0)
    dot = np.array([[[[0.5, 0.5]], [[0.5, 0.5]]]])
    assert V.render_thin(dot, 1).tolist() == [[[1]]]
    assert V.render_antialiased(dot, 1).tolist() == [[[0.0]]]  # a point has no length
    line = np.array([[[[0.5, 0.0]], [[0.5, 1.0]]]])
    np.testing.assert_allclose(V.render_antialiased(line, 1), oracle.render_antialiased(line, 1))


def test_render_kernels_zero_their_buffers():
    c = _border_coords()
    img = np.full((2, 8, 8), 7, np.uint8)
    V.render_thin_kernel(c, img)
    np.testing.assert_array_equal(img, V.render_thin(c, 8))
    acc = np.full((2, 8, 8), 3.0)
    V.render_antialiased_kernel(c, acc)
    np.testing.assert_array_equal(acc, V.render_antialiased(c, 8))


# ----------------------------------------------------------------------------- blur


@pytest.mark.parametrize("seed", range(3))
@pytest.mark.parametrize("sigma", [0.3, 1.0, 2.5])
def test_blur_matches_oracle(seed, sigma):
    rng = np.random.default_rng(seed)
    shape = [(2, 12, 12), (1, 5, 9), (3, 4, 4)][seed]
    grey = rng.random(shape) * (rng.random(shape) < 0.3)
    binary = (grey > 0).astype(np.uint8)
    for img in (grey, binary):
        np.testing.assert_allclose(
            V.blur_views(img, sigma), oracle.blur_views(img, sigma), rtol=0, atol=1e-12
        )


def test_blur_edges():
    one = np.ones((1, 1, 1), np.uint8)
    assert V.blur_views(one, 1.0)[0, 0, 0] == pytest.approx(V.gaussian_taps(1.0)[3] ** 2)
    assert V.blur_views(np.zeros((2, 6, 6)), 1.5).sum() == 0.0
    assert V.blur_views(np.zeros((2, 0, 0)), 1.5).shape == (2, 0, 0)
    # ink on the border leaks out of the raster (zero outside)
    corner = np.zeros((1, 9, 9))
    corner[0, 0, 0] = 1.0
    b = V.blur_views(corner, 1.0)
    assert b.sum() < 0.5 and b[0, 0, 0] == b.max()
    np.testing.assert_allclose(b, oracle.blur_views(corner, 1.0), rtol=0, atol=1e-15)
    taps = V.gaussian_taps(0.5)
    assert taps.shape == (5,) and taps.sum() == pytest.approx(1.0)
    for bad in (0.0, -1.0, float("nan")):
        with pytest.raises(ValueError, match="sigma"):
            V.gaussian_taps(bad)


# ----------------------------------------------------------------------------- NCC


def _view_pairs(rng, n_views, size):
    f = (rng.random((n_views, size, size)) < rng.uniform(0.05, 0.5)).astype(np.uint8)
    g = (rng.random((n_views, size, size)) < rng.uniform(0.05, 0.5)).astype(np.uint8)
    g[:, : size // 2] |= f[:, : size // 2]  # some overlap
    return f, g


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("area", [False, True])
def test_ncc_matches_oracle(seed, area):
    rng = np.random.default_rng(seed)
    f, g = _view_pairs(rng, 1 + seed % 3, [1, 2, 7, 16, 16, 33][seed])
    got = V.ncc(f, g, area)
    assert 0.0 <= got <= 1.0
    assert got == pytest.approx(oracle.ncc(f, g, area), abs=1e-15)
    # the kernel as score_population calls it
    g_area = g.reshape(g.shape[0], -1).sum(1).astype(float)
    assert V.ncc_kernel(f, g, g_area, area) == got
    # non-zero is foreground, whatever the dtype
    assert V.ncc(f * 0.3, g * 5, area) == got


def test_ncc_edges():
    a = np.zeros((2, 4, 4), np.uint8)
    a[:, 1] = 1
    assert V.ncc(a, a) == 1.0 and V.ncc(a, a, True) == 1.0
    empty = np.zeros_like(a)
    for x, y in ((empty, a), (a, empty), (empty, empty)):
        for area in (False, True):
            assert V.ncc(x, y, area) == oracle.ncc(x, y, area) == 0.0
    one = np.ones((2, 1, 1), np.uint8)
    assert V.ncc(one, one) == 1.0 and V.ncc(np.zeros((2, 0, 0)), np.zeros((2, 0, 0))) == 0.0
    # area rule: 4x the target's area is rejected, 2x is not
    big = a.copy()
    big[:, 2:] = 1
    assert V.ncc(big, a, True) == 0.0 and V.ncc(big, a) > 0
    two = a.copy()
    two[:, 2] = 1
    assert V.ncc(two, a, True) == oracle.ncc(two, a, True) > 0


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("area", [False, True])
def test_blurred_ncc_matches_oracle(seed, area):
    rng = np.random.default_rng(seed + 50)
    size = [3, 12, 16, 20][seed]
    c = _random_coords(rng, 2, 15, size, spread=0.0)
    views = V.render_antialiased(c, size)
    target = V.render_thin(_random_coords(rng, 2, 15, size, spread=0.0), size)
    sigma = [0.5, 1.0, 1.5, 3.0][seed]
    want = oracle.blurred_ncc(views, target, sigma, area)
    assert V.blurred_ncc(views, target, sigma, area) == pytest.approx(want, abs=1e-12)
    # the kernel as score_population calls it (blurred target and its norms precomputed)
    taps = V.gaussian_taps(sigma)
    tb = V.blur_views(target, sigma)
    tb_norm = np.sqrt((tb * tb).sum(axis=(1, 2)))
    g_area = target.reshape(2, -1).sum(1).astype(float)
    scratch = np.empty((size, size)), np.empty(views.shape)
    got = V.blurred_ncc_kernel(views, taps, tb, tb_norm, *scratch, g_area, area)
    assert got == pytest.approx(want, abs=1e-12)


def test_blurred_ncc_edges():
    a = np.zeros((2, 8, 8))
    a[:, 4, 2:6] = 1.0
    assert V.blurred_ncc(a, a, 1.0) == pytest.approx(1.0)
    assert V.blurred_ncc(np.zeros_like(a), a, 1.0) == 0.0
    assert V.blurred_ncc(a, np.zeros_like(a), 1.0, True) == 0.0
    one = np.ones((2, 1, 1))
    assert V.blurred_ncc(one, one, 2.0) == pytest.approx(oracle.blurred_ncc(one, one, 2.0))
    # partial credit for a near miss, where the binary NCC gives none
    b = np.roll(a, 1, axis=1)
    assert V.ncc(a, b) == 0.0 and 0.5 < V.blurred_ncc(a, b, 1.0) < 1.0


# ----------------------------------------------------------------------------- checks


def test_input_checks():
    with pytest.raises(ValueError, match="coords"):
        V.render_thin(np.zeros((2, 3, 1, 2)), 8)
    with pytest.raises(ValueError, match="finite"):
        V.render_antialiased(np.full((1, 2, 1, 2), np.nan), 8)
    with pytest.raises(ValueError, match="size"):
        V.render_thin(np.zeros((1, 2, 1, 2)), -1)
    with pytest.raises(ValueError, match="size"):
        V.frame_points(np.zeros((1, 3)), np.zeros((1, 3)), np.zeros(3), 2.5)
    with pytest.raises(ValueError, match="shape"):
        V.frame_points(np.zeros((1, 2)), np.zeros((1, 2)), np.zeros(3), 8)
    with pytest.raises(ValueError, match="base"):
        V.frame_points(np.zeros((1, 3)), np.zeros((1, 3)), np.zeros(2), 8)
    with pytest.raises(ValueError, match="shape"):
        V.frame_view(np.zeros(3), np.zeros(2), 0.0, 0.0, 1.0, 8)
    with pytest.raises(ValueError, match="shape"):
        V.ncc(np.zeros((2, 4, 4)), np.zeros((2, 4, 5)))
    with pytest.raises(ValueError, match="V >= 1"):
        V.ncc(np.zeros((0, 4, 4)), np.zeros((0, 4, 4)))
    with pytest.raises(ValueError, match="shape"):
        V.blurred_ncc(np.zeros((4, 4)), np.zeros((4, 4)), 1.0)
    with pytest.raises(ValueError, match="img"):
        V.blur_views(np.zeros((4, 4)), 1.0)
