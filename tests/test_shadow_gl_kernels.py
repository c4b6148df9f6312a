"""The OpenGL backend's CPU kernels (growsim.kernels.shadow_gl) against their oracles
(tests/naive/shadow_gl.py); no OpenGL needed (the backend itself: test_light_gl.py)."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from naive import shadow_gl as naive

from growsim.env.light import view_basis
from growsim.kernels import shadow_gl as K
from growsim.kernels.light import plant_frames


def scene(rng):
    """Plants of random segments (some plants empty, some segments points), a direction,
    the plants' frames, a batch of plants ``p0:p1`` with a chunk ``c0:c1`` of its
    segments, and an atlas ``(cols, res, width)``."""
    k = int(rng.integers(1, 7))
    offsets = np.concatenate([[0], np.cumsum(rng.integers(0, 12, k))]).astype(np.int64)
    n = int(offsets[-1])
    start = rng.normal(size=(n, 3)) * 3
    end = start + rng.normal(size=(n, 3))
    point = rng.random(n) < 0.1
    end[point] = start[point]
    radius = rng.uniform(0.0, 0.4, n)
    d = rng.normal(size=3)
    d /= np.linalg.norm(d)
    u, v = view_basis(d)
    res = int(rng.integers(8, 64))
    frames = plant_frames(start, end, radius, offsets, u, v, res)
    p0 = int(rng.integers(0, k))
    p1 = int(rng.integers(p0 + 1, k + 1))
    c0 = int(rng.integers(offsets[p0], offsets[p1] + 1))
    c1 = int(rng.integers(c0, offsets[p1] + 1))
    cols = int(rng.integers(1, p1 - p0 + 1))
    atlas = (cols, res, cols * res + int(rng.integers(0, 3)))
    return (start, end, radius, offsets), frames, (u, v, d), (p0, p1, c0, c1), atlas


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_vertices_match_oracle(seed):
    rng = np.random.default_rng(seed)
    segments, frames, plane, batch, atlas = scene(rng)
    start, end, _, offsets = segments
    c0, c1 = batch[2:]
    k = len(offsets) - 1
    zinfo = K.depth_ranges(start, end, offsets, plane[2], 0, k, np.full((k, 2), np.nan))
    np.testing.assert_array_equal(
        zinfo, naive.depth_ranges(start, end, offsets, plane[2], 0, k, np.zeros((k, 2)))
    )
    assert np.all(zinfo[:, 1] >= 0)
    out = np.zeros((4 * (c1 - c0), K.VERTEX_FLOATS), np.float32)
    K.tile_vertices(segments, frames, plane, batch, atlas, zinfo, out, out.view(np.int32))
    want = naive.tile_vertices(segments, frames, plane, batch, atlas, zinfo)
    np.testing.assert_array_equal(out.view(np.int32), want.view(np.int32))  # bit for bit
    # the normalised depths lie in [0, 1/2]: the cleared 1 means empty
    assert np.all((out[:, 4:6] >= 0) & (out[:, 4:6] <= 0.5))


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), samples=st.integers(1, 4))
def test_queries_match_oracle(seed, samples):
    rng = np.random.default_rng(seed)
    segments, frames, plane, batch, atlas = scene(rng)
    p0, p1, c0, c1 = batch
    q = np.zeros(((c1 - c0) * samples, 2), np.int32)
    z = np.zeros((c1 - c0) * samples)
    K.segment_queries(segments, frames, plane, batch, atlas, samples, q, z)
    want_q, want_z = naive.segment_queries(segments, frames, plane, batch, atlas, samples)
    np.testing.assert_array_equal(q, want_q)
    np.testing.assert_array_equal(z, want_z)
    inside = q[:, 0] >= 0
    assert np.all(q[inside, 0] < atlas[2] * atlas[1] * (p1 - p0))
    # points: around the batch's plants, many outside their frames
    offsets = segments[3]
    counts = rng.integers(0, 20, len(offsets) - 1)
    point_offsets = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    points = rng.normal(size=(int(point_offsets[-1]), 3)) * 4
    m0 = int(rng.integers(point_offsets[p0], point_offsets[p1] + 1))
    m1 = int(rng.integers(m0, point_offsets[p1] + 1))
    q = np.zeros((m1 - m0, 2), np.int32)
    z = np.zeros(m1 - m0)
    K.point_queries(points, point_offsets, frames, plane, (p0, p1, m0, m1), atlas, q, z)
    want_q, want_z = naive.point_queries(points, point_offsets, frames, plane, (p0, p1, m0, m1),
                                         atlas)  # fmt: skip
    np.testing.assert_array_equal(q, want_q)
    np.testing.assert_array_equal(z, want_z)


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), per=st.integers(1, 4))
def test_resolve_matches_oracle(seed, per):
    rng = np.random.default_rng(seed)
    segments, frames, _, batch, _ = scene(rng)
    offsets = segments[3]
    c0, c1 = batch[2:]
    k = len(offsets) - 1
    zinfo = np.column_stack([rng.normal(size=k), rng.uniform(0.0, 5.0, k)])
    m = (c1 - c0) * per
    val = rng.uniform(0.0, 0.5, m).astype(np.float32)
    val[rng.random(m) < 0.3] = 2.0  # lit for sure
    z = rng.normal(size=m) * 3
    bias = float(rng.uniform(0.0, 2.0))
    out = np.full(int(offsets[-1]), -1.0)
    K.resolve_exposure(val, z, offsets, frames, zinfo, bias, batch, per, out)
    want = naive.resolve_exposure(val, z, offsets, frames, zinfo, bias, batch, per,
                                  np.full(int(offsets[-1]), -1.0))  # fmt: skip
    np.testing.assert_array_equal(out, want)
    assert np.all(out[c0:c1] >= 0)  # every item of the chunk resolved


def test_texel_counts_rows_of_the_atlas():
    frame = np.array([-1.0, -2.0, 0.25])
    pu, pv = np.array([-1.0, 0.0, 0.99, 2.0, -1.01]), np.array([-2.0, -1.0, -0.01, -2.0, -2.0])
    got = [K.texel(a, b, frame, 12, 24, 12, 40) for a, b in zip(pu, pv)]
    assert got == naive.texel(pu, pv, frame, 12, 24, 12, 40).tolist()
    assert got == [12 * 40 + 24, (12 + 4) * 40 + 24 + 4, (12 + 7) * 40 + 24 + 7, -1, -1]
