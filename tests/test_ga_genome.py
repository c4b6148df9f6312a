"""Genome codings: decode/encode, the seed papers' codings, kernels against their oracles."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from naive import ga as naive_ga

from growsim.errors import UserInputError
from growsim.ga import (
    OKUSA_WEIGHTS,
    Bits,
    Categorical,
    Genome,
    Integer,
    Real,
    genome_from_params,
)
from growsim.kernels import ga as K
from growsim.models.base import Param


def _all_patterns(b):
    v = np.arange(2**b)
    return ((v[:, None] >> np.arange(b - 1, -1, -1)) & 1).astype(np.uint8)


def test_weighted_coding_covers_okusa_range():
    # Okusa: 8 bits weighted 1, 5, 17, 26, 24, 16, 9, 2 sum to 0..100, "almost all" values
    g = Genome([Bits("v", 0, 100, coding="weighted")])
    assert g.fields[0].weights == tuple(float(w) for w in OKUSA_WEIGHTS)
    vals = np.round(g.decode(_all_patterns(8))[:, 0], 9)
    assert vals.min() == 0 and vals.max() == 100
    covered = set(vals.astype(int).tolist())
    assert np.allclose(vals, np.round(vals))  # integer sums
    assert set(range(101)) - covered == {4, 13, 87, 96}


def test_weighted_maps_linearly_into_range():
    g = Genome([Bits("speed", 5, 45, coding="weighted")])
    bits = np.zeros((1, 8), np.uint8)
    bits[0, 3] = 1  # weight 26 of 100
    assert g.decode(bits)[0, 0] == pytest.approx(5 + 0.26 * 40)


def test_fraction_coding_is_value_over_128():
    # Kuwahara et al.: 7 bits, value / 128 mapped into the range, high never reached
    g = Genome([Bits("s", 0.1, 0.7, bits=7, coding="fraction")])
    vals = g.decode(_all_patterns(7))[:, 0]
    assert np.allclose(vals, 0.1 + np.arange(128) / 128 * 0.6)
    assert vals.max() < 0.7


@pytest.mark.parametrize("coding", ["binary", "gray"])
def test_binary_gray_round_trip_every_value(coding):
    g = Genome([Bits("x", -3, 12, bits=6, coding=coding)])
    pats = _all_patterns(6)
    vals = g.decode(pats)
    assert np.allclose(np.sort(vals[:, 0]), -3 + np.arange(64) / 63 * 15)
    back = g.encode(vals)
    assert np.array_equal(back, pats)


def test_gray_neighbours_differ_by_one_bit():
    g = Genome([Bits("x", 0, 63, bits=6, coding="gray")])
    raw = g.encode(np.arange(64.0)[:, None])
    assert (np.abs(np.diff(raw.astype(int), axis=0)).sum(axis=1) == 1).all()


def test_diploid_phenotype_is_or():
    g = Genome([Bits("x", 0, 15, bits=4)], diploid=True)
    assert g.length == 8
    a = np.array([[1, 0, 0, 0, 0, 0, 1, 0]], np.uint8)  # chromosome 1000 | 0010 = 1010
    assert g.decode(a)[0, 0] == 10
    assert np.array_equal(g.encode(np.array([[10.0]])), [[1, 0, 1, 0, 1, 0, 1, 0]])


def test_real_integer_categorical_decode():
    g = Genome([Real("x", -1, 1, size=2), Integer("n", 2, 4), Categorical("c", ("a", "b", "c"))])
    assert g.names == ["x[0]", "x[1]", "n", "c"]
    raw = g.random(500, np.random.default_rng(3))
    d = g.decode(raw)
    assert set(np.unique(d[:, 2])) == {2.0, 3.0, 4.0}
    assert set(np.unique(d[:, 3])) == {0.0, 1.0, 2.0}
    assert (d[:, :2] >= -1).all() and (d[:, :2] <= 1).all()
    p = np.array([[0.5, -0.25, 3, 2]])
    assert np.array_equal(g.decode(g.encode(p)), p)
    assert g.named(p[0]) == {"x[0]": 0.5, "x[1]": -0.25, "n": 3, "c": "c"}


def test_integers_and_categories_in_bit_genomes():
    g = Genome([Bits("x", 0, 1, bits=3), Integer("n", 1, 5), Categorical("c", ("l", "r"))])
    assert g.length == 3 + 3 + 1
    d = g.decode(_all_patterns(7))
    assert set(np.unique(d[:, 1])) == {1, 2, 3, 4, 5}
    assert set(np.unique(d[:, 2])) == {0, 1}
    for n in range(1, 6):
        assert g.decode(g.encode(np.array([[0.0, n, 1]])))[0, 1] == n


@pytest.mark.parametrize(
    "bad",
    [
        lambda: Genome([]),
        lambda: Genome([Real("x", 1, 0)]),
        lambda: Genome([Real("x", 0, 1), Bits("b", 0, 1)]),
        lambda: Genome([Real("x", 0, 1), Real("x", 0, 2)]),
        lambda: Genome([Real("x", 0, 1)], diploid=True),
        lambda: Bits("b", 0, 1, coding="octal"),
        lambda: Bits("b", 0, 1, bits=0),
        lambda: Bits("b", 0, 1, weights=(1, 2)),
        lambda: Categorical("c", ("only",)),
        lambda: Real("x", 0, float("nan")),
        lambda: Integer("n", 0.5, 3),
    ],
)
def test_bad_genomes_raise_user_errors(bad):
    with pytest.raises(UserInputError):
        bad()


def test_encode_rejects_wrong_shape_names_columns():
    g = Genome([Real("a", 0, 1), Real("b", 0, 1)])
    with pytest.raises(UserInputError, match="a, b"):
        g.encode(np.zeros((2, 3)))


def test_genome_from_params():
    spec = [Param("s", 0.1, 0.7, 0.5), Param("n", 1, 9, 3, kind="int")]
    g = genome_from_params(spec)
    assert g.kind == "real" and g.names == ["s", "n"]
    gb = genome_from_params(spec, coding="bits", bits=7, bit_coding="fraction")
    assert gb.kind == "bits" and gb.length == 7 + 4
    d = gb.decode(gb.random(200, np.random.default_rng(0)))
    assert d[:, 1].min() >= 1 and d[:, 1].max() <= 9
    with pytest.raises(UserInputError):
        genome_from_params(spec, coding="hex")


def test_diversity():
    g = Genome([Real("x", 0, 2, size=2)])
    assert g.diversity(np.ones((5, 2))) == 0.0
    assert g.diversity(np.array([[0.0, 0], [2, 2]])) == pytest.approx(0.5)


# -- kernels against their oracles -----------------------------------------------------
def _mixed_bit_genome():
    return Genome(
        [
            Bits("a", -1, 1, bits=5, size=2, coding="binary"),
            Bits("b", 0, 10, bits=4, coding="gray"),
            Bits("c", 2, 17, coding="weighted"),
            Bits("d", 0.1, 0.7, bits=7, coding="fraction"),
            Bits("e", 0, 1, bits=3, coding="weighted", weights=(0.5, 0, 2)),
            Integer("n", 3, 9),
            Categorical("k", ("x", "y", "z")),
            Bits("f", 0, 1, bits=1, size=3),
        ]
    )


#: one individual of :func:`_mixed_bit_genome`, field by field, and its values worked by
#: hand from the Bits docstring's formulas (v the integer the bits spell, MSB first)
HAND_BITS = [
    (1, 0, 0, 1, 1),  # a[0] binary 5 bits in [-1, 1]: v = 19 -> -1 + 19/31 * 2
    (0, 0, 0, 0, 1),  # a[1]: v = 1 -> -1 + 1/31 * 2
    (0, 1, 1, 0),  # b Gray 4 bits in [0, 10]: binary 0100, v = 4 -> 4/15 * 10
    (1, 0, 0, 1, 0, 0, 0, 1),  # c Okusa weights in [2, 17]: 1 + 26 + 2 = 29 of 100
    (1, 0, 0, 0, 0, 0, 0),  # d fraction 7 bits in [0.1, 0.7]: 64/128
    (1, 1, 0),  # e weights (0.5, 0, 2) in [0, 1]: 0.5 of 2.5
    (1, 0, 0),  # n Integer 3..9, 7 values in 3 bits: v = 4 -> 3 + (4 * 7) // 8
    (1, 1),  # k Categorical of 3 in 2 bits: v = 3 -> (3 * 3) // 4
    (1,), (0,), (1,),  # f[0..2] one bit each in [0, 1]
]  # fmt: skip
HAND_VALUES = [7 / 31, -29 / 31, 8 / 3, 6.35, 0.4, 0.2, 6, 2, 1, 0, 1]
#: the first bit of each decoded column, counted by hand from the widths above
HAND_OFFSETS = [0, 5, 10, 14, 22, 29, 32, 35, 37, 38, 39]


def test_bit_layout_worked_by_hand():
    g = _mixed_bit_genome()
    assert g.names == ["a[0]", "a[1]", "b", "c", "d", "e", "n", "k", "f[0]", "f[1]", "f[2]"]
    assert g.length == g.n_bits == 40
    row = np.array([[b for gene in HAND_BITS for b in gene]], np.uint8)
    assert row.shape == (1, 40)
    np.testing.assert_allclose(g.decode(row)[0], HAND_VALUES, rtol=0, atol=1e-12)
    assert g.named(g.decode(row)[0])["k"] == "z"
    # every bit set: each column at its top (Integer 3 + (7 * 7) // 8 = 9, Gray 1111 = 10)
    ones = np.ones((1, 40), np.uint8)
    top = [1, 1, 10 * 10 / 15, 17, 0.1 + 0.6 * 127 / 128, 1, 9, 2, 1, 1, 1]
    np.testing.assert_allclose(g.decode(ones)[0], top, rtol=0, atol=1e-12)
    # one bit flipped at a time moves exactly the column that owns it
    base = g.decode(row)[0]
    for col, (first, gene) in enumerate(zip(HAND_OFFSETS, HAND_BITS)):
        for i in range(len(gene)):
            flip = row.copy()
            flip[0, first + i] ^= 1
            moved = np.flatnonzero(g.decode(flip)[0] != base)
            assert moved.tolist() in ([col], []), (col, i, moved)  # [] : a zero weight
    # the oracle's layout, from the fields alone, is the one counted by hand
    offset, nbits, *_ = naive_ga.layout(g.fields)
    assert offset.tolist() == HAND_OFFSETS
    assert nbits.tolist() == [len(gene) for gene in HAND_BITS]
    # and encode spells the same values back
    np.testing.assert_allclose(g.decode(g.encode(g.decode(row)))[0], HAND_VALUES, atol=1e-12)


def test_diploid_layout_worked_by_hand():
    # two chromosomes of x (4 bits) + n (0..2: 2 bits) side by side; expressed: the OR
    g = Genome([Bits("x", 0, 15, bits=4), Integer("n", 0, 2)], diploid=True)
    assert (g.n_bits, g.length) == (6, 12)
    raw = np.array([[1, 0, 0, 0, 0, 1, 0, 0, 1, 0, 1, 0]], np.uint8)
    # 1000 01 | 0010 10 = 1010 11: x = 10, n = (3 * 3) // 4 = 2
    assert g.decode(raw)[0].tolist() == [10, 2]
    assert g.phenotype_bits(raw)[0].tolist() == [1, 0, 1, 0, 1, 1]


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(0, 12))
def test_decode_kernel_matches_oracle(seed, n):
    g = _mixed_bit_genome()
    raw = g.random(n, np.random.default_rng(seed))
    want = naive_ga.decode_bits(raw, *naive_ga.layout(g.fields))
    assert np.allclose(g.decode(raw), want, rtol=0, atol=1e-12)


def test_decode_edge_cases_all_zeros_all_ones_and_unit_fast_path():
    g = _mixed_bit_genome()
    for v in (0, 1):
        raw = np.full((2, g.length), v, np.uint8)
        want = naive_ga.decode_bits(raw, *naive_ga.layout(g.fields))
        assert np.allclose(g.decode(raw), want)
    u = Genome([Bits("b", 2, 4, bits=1, size=5), Bits("f", 0, 1, bits=1, coding="fraction")])
    assert u._unit  # the one-bit fast path is the one checked here
    raw = _all_patterns(6)
    want = naive_ga.decode_bits(raw, *naive_ga.layout(u.fields))
    assert np.allclose(u.decode(raw), want)


@settings(max_examples=30, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    m=st.integers(0, 6),
    L=st.integers(1, 70),
    ncut=st.integers(0, 8),
    real=st.booleans(),
)
def test_cut_crossover_matches_oracle(seed, m, L, ncut, real):
    rng = np.random.default_rng(seed)
    if real:
        a, b = rng.random((m, L)), rng.random((m, L))
    else:
        a = rng.integers(0, 2, (m, L), dtype=np.uint8)
        b = rng.integers(0, 2, (m, L), dtype=np.uint8)
    counts = rng.integers(0, ncut + 1, m)
    ptr = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    # sorted cuts, repeats allowed (they cancel), positions 1..L-1 (0 and L are no-ops)
    cuts = np.concatenate(
        [np.sort(rng.integers(0, L + 1, c)) for c in counts] or [np.zeros(0, int)]
    ).astype(np.int64)
    c1, c2 = np.empty_like(a), np.empty_like(b)
    K.cut_crossover(a, b, c1, c2, ptr, cuts)
    w1, w2 = naive_ga.cut_crossover(a, b, ptr, cuts)
    assert np.array_equal(c1, w1) and np.array_equal(c2, w2)


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), m=st.integers(0, 5), L=st.integers(1, 200))
def test_word_crossover_matches_oracle(seed, m, L):
    rng = np.random.default_rng(seed)
    a = rng.integers(0, 2, (m, L), dtype=np.uint8)
    b = rng.integers(0, 2, (m, L), dtype=np.uint8)
    words = rng.integers(0, 2**64 - 1, (m, (L + 63) // 64), dtype=np.uint64, endpoint=True)
    c1, c2 = np.empty_like(a), np.empty_like(b)
    K.word_crossover(a, b, c1, c2, words)
    w1, w2 = naive_ga.word_crossover(a, b, words)
    assert np.array_equal(c1, w1) and np.array_equal(c2, w2)


def test_ones_per_locus_matches_oracle():
    rng = np.random.default_rng(5)
    for shape in [(0, 4), (1, 1), (7, 130)]:
        x = rng.integers(0, 2, shape, dtype=np.uint8)
        assert np.array_equal(K.ones_per_locus(x), naive_ga.ones_per_locus(x))


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), m=st.integers(0, 6), eta=st.floats(0.5, 40))
def test_sbx_kernel_matches_oracle(seed, m, eta):
    rng = np.random.default_rng(seed)
    L = 7
    low, high = -np.arange(1.0, L + 1), np.arange(1.0, L + 1) * 2
    top = np.nextafter(high, -np.inf)
    a = rng.uniform(low, high, (m, L))
    b = rng.uniform(low, high, (m, L))
    b[:, 0] = a[:, 0]  # equal parents: no crossing
    a[:, 1] = low[1]  # at the bounds
    b[:, 2] = top[2]
    r = [rng.random((m, L)) for _ in range(3)]
    c1, c2 = np.empty_like(a), np.empty_like(b)
    K.sbx(a, b, (low, high, top), eta, 0.5, tuple(r), c1, c2)
    w1, w2 = naive_ga.sbx(a, b, low, high, top, eta, 0.5, *r)
    assert np.allclose(c1, w1, rtol=1e-12, atol=1e-12)
    assert np.allclose(c2, w2, rtol=1e-12, atol=1e-12)


def test_all_patterns_helper_is_exhaustive():
    assert len({tuple(r) for r in _all_patterns(4)}) == 16
    assert set(itertools.chain.from_iterable(_all_patterns(2).tolist())) == {0, 1}
