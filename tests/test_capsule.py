"""The capsule walk over a shadow map's occupied pixels (growsim.kernels.capsule) against
its oracle (tests/naive/capsule.py): every pixel tested, no walk."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from naive import capsule as naive

from growsim.kernels.capsule import walk_capsule


def random_map(rng, res, k):
    """A map of ``res`` pixels with queries in a random share of its pixels (1-3 each):
    the kernel's scratch and queries, built as the light kernels build them, and each
    query's pixel, depth and owner for the oracle."""
    W = (res + 63) // 64
    n = res * res
    head, occ = np.full(n, -1, np.int64), np.zeros(2 * res * W, np.uint64)
    near_z = rng.uniform(-5.0, 5.0, n)
    near_z[rng.random(n) < 0.3] = np.inf
    near_id = np.where(np.isfinite(near_z), rng.integers(0, 50, n), -1).astype(np.int64)
    pixels = np.flatnonzero(rng.random(n) < rng.uniform(0.05, 0.9))
    pix = np.repeat(pixels, rng.integers(1, 4, len(pixels)))
    m = len(pix)
    nxt = np.empty(m, np.int64)
    for q, p in enumerate(pix):
        i, j = divmod(int(p), res)
        occ[i * W + (j >> 6)] |= np.uint64(1) << np.uint64(j & 63)
        occ[(res + j) * W + (i >> 6)] |= np.uint64(1) << np.uint64(i & 63)
        nxt[q] = head[p]
        head[p] = q
    qz = rng.uniform(-5.0, 5.0, m)
    qown = rng.choice([-1, k, k + 1], m).astype(np.int64)
    return (head, occ, near_z, near_id), (nxt, qz, qown, rng.uniform(0.2, 1.0, m)), pix


def random_capsule(rng, res):
    """Ends in and around the map (some a point, level or upright), depths, a radius from
    a tenth of a pixel to half the map (half the capsules thin: walked line by line)."""
    ax, ay, bx, by = rng.uniform(-0.2 * res, 1.2 * res, 4)
    shape = rng.choice(4, p=[0.6, 0.1, 0.15, 0.15])
    if shape == 1:
        bx, by = ax, ay  # a point
    elif shape == 2:
        by = ay  # level
    elif shape == 3:
        bx = ax  # upright
    if rng.random() < 0.5:
        rr = float(rng.uniform(0.1, 2.0))
    else:
        rr = float(np.exp(rng.uniform(np.log(0.1), np.log(max(0.2, 0.5 * res)))))
    return (ax, ay, bx, by, *rng.uniform(-5.0, 5.0, 2)), rr


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), res=st.integers(2, 150), soft=st.booleans())
def test_walk_capsule_matches_oracle(seed, res, soft):
    rng = np.random.default_rng(seed)
    k = 7
    (head, occ, near_z, near_id), (nxt, qz, qown, expo), pix = random_map(rng, res, k)
    ends, rr = random_capsule(rng, res)
    bias, trans = float(rng.uniform(0.0, 0.5)), float(rng.uniform(0.0, 1.0))
    want_z, want_id, want_e = naive.walk_capsule(k, ends, rr, res, pix, qz, qown, bias, soft,
                                                 trans, near_z, near_id, expo)  # fmt: skip
    occ0 = occ.copy()
    walk_capsule(k, ends, rr, res, (head, occ, near_z, near_id), (nxt, qz, qown, expo), bias,
                 soft, trans)  # fmt: skip
    assert np.array_equal(occ, occ0)  # the occupancy is read, not written
    _, depth, tie = naive.coverage(ends, rr, res)
    fair = ~tie.ravel()  # a centre on the capsule's edge may fall either way
    if soft:
        ok = fair[pix] & (np.abs(depth.ravel()[pix] - (qz - bias)) > 1e-9)
        np.testing.assert_allclose(expo[ok], want_e[ok], rtol=1e-12)
    else:
        np.testing.assert_array_equal(near_id[fair], want_id[fair])
        np.testing.assert_allclose(near_z[fair], want_z[fair], rtol=0, atol=1e-9)


def test_a_capsule_covers_the_pixel_centres_within_its_radius():
    # a level capsule across an 8-pixel map at row 4, radius 0.6: row 4 only, columns 0-7
    res, k = 8, 3
    pix = np.arange(res * res)
    head, occ = np.empty(res * res, np.int64), np.zeros(2 * res, np.uint64)
    for p in pix:
        i, j = divmod(int(p), res)
        head[p] = p
        occ[i] |= np.uint64(1) << np.uint64(j)
        occ[res + j] |= np.uint64(1) << np.uint64(i)
    near_z, near_id = np.full(res * res, np.inf), np.full(res * res, -1)
    queries = (np.full(res * res, -1), np.zeros(res * res), np.full(res * res, -1),
               np.ones(res * res))  # fmt: skip
    walk_capsule(k, (0.5, 4.5, 7.5, 4.5, 1.0, 1.0), 0.6, res, (head, occ, near_z, near_id),
                 queries, 0.0, False, 1.0)  # fmt: skip
    assert np.flatnonzero(near_id == k).tolist() == list(range(32, 40))
