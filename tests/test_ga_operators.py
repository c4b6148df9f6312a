"""Every registered operator: shapes, dtypes, bounds, determinism, and its statistics."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from growsim.errors import UserInputError
from growsim.ga import CROSSOVER, MUTATION, SELECTION, Bits, Genome, Integer, Real

BITS = Genome([Bits("b", 0, 1, bits=4, size=10)])  # L = 40
REAL = Genome([Real("x", -2, 3, size=6), Integer("n", 0, 4)])
GENOMES = {"bits": BITS, "real": REAL}


def _pop(genome, n, seed):
    return genome.random(n, np.random.default_rng(seed))


def _kinds(cls):
    return [k for k in ("bits", "real") if k in getattr(cls, "kinds", ("bits", "real"))]


# -- selection -------------------------------------------------------------------------
@pytest.mark.parametrize("name", sorted(SELECTION))
def test_selection_shapes_determinism_and_failures(name):
    op = SELECTION[name]()
    score = np.random.default_rng(0).normal(size=30)
    score[3] = -np.inf  # a failed individual
    a = op(score, 50, np.random.default_rng(7))
    b = op(score, 50, np.random.default_rng(7))
    assert a.shape == (50,) and a.dtype == np.int64
    assert np.array_equal(a, b)
    assert a.min() >= 0 and a.max() < 30
    if name != "random":
        big = op(score, 20000, np.random.default_rng(1))
        assert (big == 3).mean() < 0.02  # failures are (almost) never picked
    one = op(np.array([1.0]), 5, np.random.default_rng(0))
    assert (one == 0).all()


def test_linear_rank_frequencies():
    # Kuwahara et al.'s rank roulette: p_r proportional to the rank (pressure 2)
    n, k = 10, 200_000
    score = np.random.default_rng(1).permutation(n).astype(float) * 3.7 - 5
    op = SELECTION["rank"](pressure=2.0)
    counts = np.bincount(op(score, k, np.random.default_rng(2)), minlength=n)
    rank = np.argsort(np.argsort(score))
    expect = 2.0 * rank / (n * (n - 1)) * k
    assert np.allclose(op.probabilities(score).sum(), 1.0)
    sd = np.sqrt(expect + 1)
    assert (np.abs(counts - expect) < 5 * sd).all()
    assert counts[rank == 0].sum() == 0  # the worst has probability 0 at pressure 2


def test_roulette_and_sus_are_fitness_proportional():
    score = np.array([1.0, 2.0, 4.0, 8.0])
    w = (score - 1) + 0.07  # shifted so the worst keeps 1 % of the span
    p = w / w.sum()
    for name in ("roulette", "sus"):
        idx = SELECTION[name]()(score, 100_000, np.random.default_rng(3))
        freq = np.bincount(idx, minlength=4) / 100_000
        assert np.allclose(freq, p, atol=0.01), name
    # SUS: counts within 1 of expectation
    idx = SELECTION["sus"]()(score, 1000, np.random.default_rng(4))
    assert (np.abs(np.bincount(idx, minlength=4) - p * 1000) <= 1).all()


def test_tournament_and_truncation_pressure():
    score = np.arange(100.0)
    t = SELECTION["tournament"](size=4)(score, 50_000, np.random.default_rng(0))
    # P(winner <= r) = ((r + 1) / n)^size
    assert abs((t < 50).mean() - 0.5**4) < 0.01
    tr = SELECTION["truncation"](fraction=0.1)(score, 1000, np.random.default_rng(0))
    assert tr.min() >= 90


@pytest.mark.parametrize(
    ("name", "opts"),
    [("rank", {"pressure": 3}), ("tournament", {"size": 0}), ("truncation", {"fraction": 0})],
)
def test_selection_bad_options(name, opts):
    with pytest.raises(UserInputError, match=name):
        SELECTION[name](**opts)


# -- crossover -------------------------------------------------------------------------
@pytest.mark.parametrize("name", sorted(CROSSOVER))
@pytest.mark.parametrize("kind", ["bits", "real"])
def test_crossover_shapes_bounds_determinism(name, kind):
    cls = CROSSOVER[name]
    g = GENOMES[kind]
    op = cls()
    if kind not in _kinds(cls):
        with pytest.raises(UserInputError, match=name):
            op.check(g)
        return
    op.check(g)
    a, b = _pop(g, 21, 1), _pop(g, 21, 2)
    c1, c2 = op(a, b, np.random.default_rng(5), g)
    d1, d2 = op(a, b, np.random.default_rng(5), g)
    assert c1.shape == a.shape and c2.shape == b.shape
    assert c1.dtype == a.dtype and c2.dtype == b.dtype
    assert np.array_equal(c1, d1) and np.array_equal(c2, d2)
    for c in (c1, c2):
        assert (
            (c >= g.low).all() and (c < g.high).all()
            if kind == "real"
            else set(np.unique(c)) <= {0, 1}
        )
    assert np.array_equal(a, _pop(g, 21, 1))  # parents untouched
    # rate 0: the children are copies
    z1, z2 = cls(rate=0.0)(a, b, np.random.default_rng(5), g)
    assert np.array_equal(z1, a) and np.array_equal(z2, b)


POSITIONAL = ["one_point", "two_point", "n_point", "uniform", "switch"]


@settings(max_examples=20, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    name=st.sampled_from(POSITIONAL),
    m=st.integers(1, 8),
    L=st.integers(2, 90),
)
def test_positional_crossovers_exchange_genes(seed, name, m, L):
    # each locus of the two children holds the two parents' genes, one each
    g = Genome([Bits("b", 0, 1, bits=1, size=L)])
    rng = np.random.default_rng(seed)
    a, b = g.random(m, rng), g.random(m, rng)
    c1, c2 = CROSSOVER[name](rate=1.0)(a, b, rng, g)
    assert np.array_equal(np.sort(np.stack([a, b]), axis=0), np.sort(np.stack([c1, c2]), axis=0))


def _segments(m, L, name, **opts):
    g = Genome([Bits("b", 0, 1, bits=1, size=L)])
    a, b = np.zeros((m, L), np.uint8), np.ones((m, L), np.uint8)
    c1, _ = CROSSOVER[name](rate=1.0, **opts)(a, b, np.random.default_rng(11), g)
    return c1, np.abs(np.diff(c1.astype(int), axis=1)).sum(axis=1)


def test_cut_counts_of_point_crossovers():
    for name, opts, n in [
        ("one_point", {}, 1),
        ("two_point", {}, 2),
        ("n_point", {"points": 5}, 5),
    ]:
        _, switches = _segments(200, 50, name, **opts)
        assert (switches == n).all(), name
    # dense n-point (more than a quarter of the loci)
    _, switches = _segments(50, 12, "n_point", points=9)
    assert (switches == 9).all()


def test_switch_crossover_rate():
    # Kuwahara et al.: the children switch parent after each locus with the given rate
    m, L, r = 400, 101, 0.1
    _, switches = _segments(m, L, "switch", switch=r)
    assert abs(switches.mean() - r * (L - 1)) < 4 * np.sqrt(r * (1 - r) * (L - 1) / m)


def test_uniform_swap_rates():
    for swap in (0.5, 0.2):
        c1, _ = _segments(300, 200, "uniform", swap=swap)
        assert abs(c1.mean() - swap) < 0.01


def test_mean_and_blend_statistics():
    g = Genome([Real("x", -100, 100, size=4)])
    a, b = np.zeros((5000, 4)), np.ones((5000, 4))
    m1, m2 = CROSSOVER["mean"](rate=1.0)(a, b, np.random.default_rng(0), g)
    assert np.allclose(m1, 0.5) and np.allclose(m2, 0.5)
    c1, _ = CROSSOVER["blend"](alpha=0.5, rate=1.0)(a, b, np.random.default_rng(0), g)
    assert c1.min() >= -0.5 and c1.max() <= 1.5
    assert abs(c1.mean() - 0.5) < 0.01 and abs(c1.var() - 4 / 12) < 0.01


def test_sbx_children_spread_around_parents():
    g = Genome([Real("x", -100, 100, size=4)])
    a, b = np.full((5000, 4), -1.0), np.full((5000, 4), 1.0)
    c1, c2 = CROSSOVER["sbx"](eta=15, gene_rate=1.0, rate=1.0)(a, b, np.random.default_rng(0), g)
    # symmetric around the parents' mean; eta 15 keeps children near the parents
    assert abs((c1 + c2).mean()) < 0.02
    assert np.median(np.abs(c1)) == pytest.approx(1.0, abs=0.1)


# -- mutation --------------------------------------------------------------------------
@pytest.mark.parametrize("name", sorted(MUTATION))
@pytest.mark.parametrize("kind", ["bits", "real"])
def test_mutation_shapes_bounds_determinism(name, kind):
    cls = MUTATION[name]
    g = GENOMES[kind]
    op = cls()
    if kind not in _kinds(cls):
        with pytest.raises(UserInputError, match=name):
            op.check(g)
        return

    def go(seed):
        x = _pop(g, 40, 3)
        if op.self_adaptive:
            s = op.init_strategy(40, g)
            x, s = op(x, np.random.default_rng(seed), g, s)
            assert len(s) == 40 and ((s if s.ndim == 1 else s[:, 0]) > 0).all()
            return x
        return op(x, np.random.default_rng(seed), g)

    x, y = go(9), go(9)
    assert x.shape == (40, g.length) and x.dtype == g.dtype
    assert np.array_equal(x, y)
    if kind == "real":
        assert (x >= g.low).all() and (x < g.high).all()
    else:
        assert set(np.unique(x)) <= {0, 1}
    assert not np.array_equal(go(1), go(2)) or name == "reset"


@settings(max_examples=10, deadline=None)
@given(rate=st.floats(0.001, 0.3), seed=st.integers(0, 2**32 - 1))
def test_bitflip_rate(rate, seed):
    g = Genome([Bits("b", 0, 1, bits=1, size=500)])
    x = MUTATION["bitflip"](rate=rate)(
        np.zeros((200, 500), np.uint8), np.random.default_rng(seed), g
    )
    n = x.size
    assert abs(x.mean() - rate) < 5 * np.sqrt(rate * (1 - rate) / n)


def test_bitflip_default_rate_is_one_over_length():
    g = Genome([Bits("b", 0, 1, bits=1, size=200)])
    x = MUTATION["bitflip"]()(np.ones((2000, 200), np.uint8), np.random.default_rng(0), g)
    assert abs((1 - x).sum(axis=1).mean() - 1.0) < 0.1


def test_meta_rate_self_adapts_and_flips_at_its_rate():
    g = Genome([Bits("b", 0, 1, bits=1, size=1000)])
    op = MUTATION["meta"](rate=0.02, bits=10)
    s = op.init_strategy(300, g)
    assert (s == 50).all()
    x, s2 = op(np.zeros((300, 1000), np.uint8), np.random.default_rng(0), g, s)
    # mu's 10 bits each flip with probability 1/50: about 18 % of individuals change rate
    changed = (s2 != 50).mean()
    assert 0.1 < changed < 0.3
    same = s2 == 50
    assert abs(x[same].mean() - 0.02) < 0.003
    # each individual flips at its own (already mutated) rate 1 / mu
    mu0 = np.repeat([3.0, 20.0, 700.0], 100)
    x2, mu2 = op(np.zeros((300, 1000), np.uint8), np.random.default_rng(1), g, mu0)
    expect = (1000 / mu2).sum()
    assert abs(x2.sum() - expect) < 5 * np.sqrt(expect)
    assert x2[:100].mean() > 5 * x2[200:].mean()


def test_gaussian_and_polynomial_rates_and_steps():
    g = Genome([Real("x", -10, 10, size=50)])
    x0 = np.zeros((400, 50))
    x = MUTATION["gaussian"](sigma=0.01, rate=0.1)(x0.copy(), np.random.default_rng(0), g)
    hit = x != 0
    assert abs(hit.mean() - 0.1) < 0.01
    assert abs(x[hit].std() - 0.2) < 0.02  # sigma x range
    p = MUTATION["polynomial"](eta=20)(x0.copy(), np.random.default_rng(0), g)
    assert abs((p != 0).mean() - 1 / 50) < 0.005
    assert np.abs(p).max() < 20 and np.median(np.abs(p[p != 0])) < 1.0


def test_reset_replaces_a_fraction_of_individuals():
    g = Genome([Real("x", 5, 6, size=3)])
    x = MUTATION["reset"](fraction=0.3)(np.zeros((5000, 3)), np.random.default_rng(0), g)
    new = (x != 0).all(axis=1)
    assert abs(new.mean() - 0.3) < 0.03
    assert ((x == 0).all(axis=1) | new).all()  # whole individuals, never single genes
