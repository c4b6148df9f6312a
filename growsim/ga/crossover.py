"""Crossover operators: two parents -> two children, for whole populations of pairs.

A call ``op(a, b, rng, genome) -> (c1, c2)`` takes the parents ``a``, ``b`` (``(m, L)``
raw genomes: uint8 bits or float64 reals) and returns two ``(m, L)`` arrays of children.
``rate`` is the probability that a pair is crossed at all (otherwise the children are
copies of the parents). Cut-point and uniform operators work on any coding; ``mean``,
``blend``, ``sbx`` and ``differential`` need a real genome. Cut-point crossovers run in
the numba kernel ``cut_crossover``; uniform crossover in ``word_crossover``, which spends
one random bit (not one random float) per gene; ``differential`` also reads the
population (:meth:`Differential.cross_pairs`, through :meth:`Operators.mate`).
"""

from __future__ import annotations

import numpy as np

from growsim.errors import UserInputError
from growsim.ga.operator import Operator
from growsim.kernels import ga as K
from growsim.registry import Registry

__all__ = [
    "CROSSOVER",
    "SBX",
    "Blend",
    "Crossover",
    "Differential",
    "Mean",
    "NPoint",
    "OnePoint",
    "Switch",
    "TwoPoint",
    "Uniform",
]


def _check_prob(op: str, name: str, v: float, low_open=False) -> float:
    v = float(v)
    if not (0.0 <= v <= 1.0) or (low_open and v == 0.0):
        raise UserInputError(f"crossover {op!r}: {name} must be in [0, 1], got {v}")
    return v


class Crossover(Operator):
    """Base class. Subclasses implement ``_cross(a, b, rng, genome) -> (c1, c2)`` for the
    pairs that cross; the base applies ``rate`` and checks the coding.

    Examples
    --------
    >>> import numpy as np
    >>> class Swap(Crossover):
    ...     name = "swap"
    ...     def _cross(self, a, b, rng, genome):
    ...         return b.copy(), a.copy()
    >>> c1, c2 = Swap(rate=1.0)(np.zeros((2, 3)), np.ones((2, 3)), np.random.default_rng(0), None)
    >>> c1.tolist()
    [[1.0, 1.0, 1.0], [1.0, 1.0, 1.0]]
    """

    role = name = "crossover"
    #: True when :meth:`cross_pairs` takes the mutation's per-child ``choice`` (and
    #: ``parameters``): :meth:`growsim.ga.operator.Operators.mate` hands them over
    takes_choice = False

    def __init__(self, rate: float = 0.9):
        self.rate = _check_prob(self.name, "rate", rate)

    def cross_pairs(self, pop, ia, ib, n_off, rng, genome, **choice):
        """The fast path: the ``n_off`` children ``(n_off, L)`` of the pairs
        ``(pop[ia], pop[ib])`` written at once, or None (the default: no fast path; the
        pairs are gathered and crossed by ``__call__``)."""
        return None

    def __call__(self, a, b, rng, genome):
        a = np.ascontiguousarray(a)
        b = np.ascontiguousarray(b)
        if a.shape != b.shape:
            raise ValueError(f"parents differ in shape: {a.shape} vs {b.shape}")
        m = a.shape[0]
        if self.rate >= 1.0:
            return self._cross(a, b, rng, genome)
        go = rng.random(m) < self.rate
        c1, c2 = a.copy(), b.copy()
        if go.any():
            x1, x2 = self._cross(a[go], b[go], rng, genome)
            c1[go], c2[go] = x1, x2
        return c1, c2

    def cross(self, a, b, rng, genome):
        """Cross every pair ``(a[i], b[i])`` -> ``(c1, c2)``, whatever ``rate`` says (the
        caller chose the pairs that cross): the subclass's ``_cross``."""
        return self._cross(a, b, rng, genome)

    def _cross(self, a, b, rng, genome):
        raise NotImplementedError


def _by_cuts(a, b, ptr, cuts):
    c1 = np.empty_like(a)
    c2 = np.empty_like(b)
    K.cut_crossover(a, b, c1, c2, ptr.astype(np.int64), cuts.astype(np.int64))
    return c1, c2


def _distinct_cuts(m: int, L: int, n: int, rng) -> np.ndarray:
    """``(m, n)`` sorted cut positions, distinct within each row, uniform in ``1..L-1``."""
    n = min(n, L - 1)
    if n <= 0:
        return np.zeros((m, 0), dtype=np.int64)
    if 4 * n > L:
        # dense: the first n of a random permutation of the L-1 positions
        return np.sort(rng.random((m, L - 1)).argsort(axis=1)[:, :n] + 1, axis=1)
    cuts = np.sort(rng.integers(1, L, size=(m, n)), axis=1)
    while True:  # redraw the rows with a repeated position (rare when n << L)
        bad = (np.diff(cuts, axis=1) == 0).any(axis=1)
        if not bad.any():
            return cuts
        cuts[bad] = np.sort(rng.integers(1, L, size=(int(bad.sum()), n)), axis=1)


class NPoint(Crossover):
    """``points``-point crossover: distinct cut positions, children alternate parents.

    Examples
    --------
    >>> import numpy as np
    >>> from growsim.ga import Genome, Bits
    >>> g = Genome([Bits("b", 0, 1, bits=1, size=8)])
    >>> a, b = np.zeros((1, 8), np.uint8), np.ones((1, 8), np.uint8)
    >>> c1, c2 = NPoint(points=3, rate=1.0)(a, b, np.random.default_rng(0), g)
    >>> int((c1 + c2).min())
    1
    """

    name = "n_point"

    def __init__(self, points: int = 2, rate: float = 0.9):
        super().__init__(rate)
        if isinstance(points, bool) or int(points) != points or points < 1:
            raise UserInputError(
                f"crossover 'n_point': points must be an integer >= 1, got {points}"
            )
        self.points = int(points)

    def _cross(self, a, b, rng, genome):
        m, L = a.shape
        cuts = _distinct_cuts(m, L, self.points, rng)
        ptr = np.arange(m + 1, dtype=np.int64) * cuts.shape[1]
        return _by_cuts(a, b, ptr, cuts.reshape(-1))


class OnePoint(NPoint):
    """One-point crossover (Okusa's fish GA uses one or two points).

    Examples
    --------
    >>> import numpy as np
    >>> from growsim.ga import Genome, Bits
    >>> g = Genome([Bits("b", 0, 1, bits=1, size=4)])
    >>> c1, _ = OnePoint(rate=1.0)(np.zeros((2, 4), np.uint8), np.ones((2, 4), np.uint8),
    ...                             np.random.default_rng(0), g)
    >>> c1.shape
    (2, 4)
    """

    name = "one_point"

    def __init__(self, rate: float = 0.9):
        super().__init__(points=1, rate=rate)


class TwoPoint(NPoint):
    """Two-point crossover.

    Examples
    --------
    >>> TwoPoint().points
    2
    """

    name = "two_point"

    def __init__(self, rate: float = 0.9):
        super().__init__(points=2, rate=rate)


class Switch(Crossover):
    """Per-locus switching (Kuwahara et al.'s multi-point crossover): walking along the
    genome, the children switch source parent after each locus with probability
    ``switch``. The switch points are drawn as a Bernoulli process without a random draw
    per locus: their number is binomial, their places a sample without replacement.

    Examples
    --------
    >>> import numpy as np
    >>> from growsim.ga import Genome, Bits
    >>> g = Genome([Bits("b", 0, 1, bits=1, size=6)])
    >>> c1, c2 = Switch(switch=0.0)(np.zeros((1, 6), np.uint8), np.ones((1, 6), np.uint8),
    ...                             np.random.default_rng(0), g)
    >>> c1.tolist(), c2.tolist()
    ([[0, 0, 0, 0, 0, 0]], [[1, 1, 1, 1, 1, 1]])
    """

    name = "switch"

    def __init__(self, switch: float = 0.1, rate: float = 1.0):
        super().__init__(rate)
        self.switch = _check_prob(self.name, "switch", switch)

    def _cross(self, a, b, rng, genome):
        m, L = a.shape
        slots = m * (L - 1)
        if slots <= 0:
            return a.copy(), b.copy()
        kcut = int(rng.binomial(slots, self.switch))
        s = np.sort(rng.choice(slots, size=kcut, replace=False)) if kcut else np.zeros(0, int)
        pair = s // (L - 1)
        cuts = s % (L - 1) + 1
        ptr = np.zeros(m + 1, dtype=np.int64)
        np.cumsum(np.bincount(pair, minlength=m), out=ptr[1:])
        return _by_cuts(a, b, ptr, cuts)


class Uniform(Crossover):
    """Uniform crossover: each locus is swapped between the children with probability
    ``swap``. For ``swap=0.5`` one random 64-bit word drives 64 loci.

    Examples
    --------
    >>> import numpy as np
    >>> from growsim.ga import Genome, Bits
    >>> g = Genome([Bits("b", 0, 1, bits=1, size=100)])
    >>> c1, c2 = Uniform(rate=1.0)(np.zeros((1, 100), np.uint8), np.ones((1, 100), np.uint8),
    ...                            np.random.default_rng(0), g)
    >>> 30 < int(c1.sum()) < 70 and int((c1 + c2).min()) == 1
    True
    """

    name = "uniform"

    def __init__(self, swap: float = 0.5, rate: float = 0.9):
        super().__init__(rate)
        self.swap = _check_prob(self.name, "swap", swap)

    def cross_pairs(self, pop, ia, ib, n_off, rng, genome):
        """Fast path of :meth:`Operators.mate`: the ``n_off`` children of the pairs
        ``(pop[ia], pop[ib])`` (first children, then second children) straight from the
        population, for bit genomes at ``rate=1`` and ``swap=0.5``; None otherwise. The
        same random words as :meth:`__call__`, so the same children."""
        if self.rate < 1.0 or self.swap != 0.5 or pop.dtype != np.uint8:
            return None
        m, L = ia.shape[0], pop.shape[1]
        words = rng.integers(0, 2**64 - 1, size=(m, (L + 63) // 64), dtype=np.uint64, endpoint=True)
        kids = np.empty((n_off, L), dtype=np.uint8)
        K.byte_word_crossover_pairs(
            np.ascontiguousarray(pop), ia.astype(np.int64), ib.astype(np.int64), words, kids
        )
        return kids

    def _cross(self, a, b, rng, genome):
        m, L = a.shape
        if self.swap == 0.5:
            words = rng.integers(
                0, 2**64 - 1, size=(m, (L + 63) // 64), dtype=np.uint64, endpoint=True
            )
            c1 = np.empty_like(a)
            c2 = np.empty_like(b)
            if a.dtype == np.uint8:  # bit genomes: a branch-free byte-mask kernel
                K.byte_word_crossover(a, b, c1, c2, words)
            else:
                K.word_crossover(a, b, c1, c2, words)
            return c1, c2
        n = m * L
        kswap = int(rng.binomial(n, self.swap))
        mask = np.zeros(n, dtype=bool)
        mask[rng.choice(n, size=kswap, replace=False)] = True
        mask = mask.reshape(m, L)
        return np.where(mask, b, a), np.where(mask, a, b)


def _clip_raw(x, genome):
    # raw reals stay inside [low, high) so floor() keeps integer/categorical values valid
    return np.clip(x, genome.low, np.nextafter(genome.high, -np.inf))


class Mean(Crossover):
    """Intermediate crossover: both children are the element-wise mean of the parents
    (Uehara et al., "Plants that acquire a 3D structure by adapting to the environment").

    Examples
    --------
    >>> import numpy as np
    >>> from growsim.ga import Genome, Real
    >>> g = Genome([Real("x", 0, 4, size=2)])
    >>> Mean(rate=1.0)(np.array([[0.0, 2]]), np.array([[2.0, 4]]), np.random.default_rng(0), g)[0]
    array([[1., 3.]])
    """

    name = "mean"
    kinds = ("real",)

    def _cross(self, a, b, rng, genome):
        c = 0.5 * (a + b)
        return c, c.copy()


class Blend(Crossover):
    """BLX-alpha: each child gene uniform in ``[lo - alpha d, hi + alpha d]`` where
    ``lo, hi`` are the parents' genes and ``d = hi - lo``; clipped to the bounds.

    Examples
    --------
    >>> import numpy as np
    >>> from growsim.ga import Genome, Real
    >>> g = Genome([Real("x", -1, 1, size=3)])
    >>> c1, c2 = Blend()(np.zeros((4, 3)), np.full((4, 3), 0.5), np.random.default_rng(0), g)
    >>> bool((c1 >= -1).all() and (c1 <= 1).all())
    True
    """

    name = "blend"
    kinds = ("real",)

    def __init__(self, alpha: float = 0.5, rate: float = 0.9):
        super().__init__(rate)
        if not 0.0 <= float(alpha) <= 10.0:
            raise UserInputError(f"crossover 'blend': alpha must be in [0, 10], got {alpha}")
        self.alpha = float(alpha)

    def _cross(self, a, b, rng, genome):
        al = self.alpha
        u1 = rng.random(a.shape) * (1.0 + 2.0 * al) - al
        u2 = rng.random(a.shape) * (1.0 + 2.0 * al) - al
        d = b - a
        return _clip_raw(a + u1 * d, genome), _clip_raw(a + u2 * d, genome)


class SBX(Crossover):
    """Simulated binary crossover (Deb and Agrawal) in its bounded form: each gene is
    crossed with probability ``gene_rate``; the spread follows the polynomial
    distribution of index ``eta`` (larger = children closer to the parents); children's
    genes are swapped with probability 1/2.

    Examples
    --------
    >>> import numpy as np
    >>> from growsim.ga import Genome, Real
    >>> g = Genome([Real("x", 0, 1, size=5)])
    >>> rng = np.random.default_rng(0)
    >>> c1, c2 = SBX(rate=1.0)(rng.random((3, 5)), rng.random((3, 5)), rng, g)
    >>> c1.shape, bool(((c1 >= 0) & (c1 <= 1)).all())
    ((3, 5), True)
    """

    name = "sbx"
    kinds = ("real",)

    def __init__(self, eta: float = 15.0, gene_rate: float = 0.5, rate: float = 0.9):
        super().__init__(rate)
        if not float(eta) >= 0:
            raise UserInputError(f"crossover 'sbx': eta must be >= 0, got {eta}")
        self.eta = float(eta)
        self.gene_rate = _check_prob(self.name, "gene_rate", gene_rate)

    def _cross(self, a, b, rng, genome):
        # three uniforms per gene, drawn in this order (the oracle in tests/naive/ga.py
        # draws the same): gene crossed?, spread, swap children?
        r_act = rng.random(a.shape)
        r_u = rng.random(a.shape)
        r_flip = rng.random(a.shape)
        c1 = np.empty_like(a, dtype=np.float64)
        c2 = np.empty_like(b, dtype=np.float64)
        top = np.nextafter(genome.high, -np.inf)
        K.sbx(
            np.asarray(a, np.float64),
            np.asarray(b, np.float64),
            (genome.low, genome.high, top),
            self.eta,
            self.gene_rate,
            (r_act, r_u, r_flip),
            c1,
            c2,
        )
        return c1, c2


class Differential(Crossover):
    """Differential crossover, the real-coded default: some children are differential-
    evolution trials (Storn & Price, "Differential evolution: a simple and efficient
    heuristic for global optimization over continuous spaces"), the others SBX children.

    Children come as in :meth:`Operators.mate`: first the first children of the pairs
    ``(a, b)``, then the second children, made from ``(b, a)``. The child of ``(a, b)``
    is a DE trial when chosen: ``b`` with each gene, with probability ``cr`` (and at
    least one gene), taken from the donor ``a + f (x_r1 - x_r2)``, where ``x_r1``,
    ``x_r2`` are two random members of the population (the pairs themselves when called
    without one), clipped to the bounds. Difference vectors follow the population's
    spread and orientation, so the step shrinks as it converges and points along its
    valleys, which coordinate-wise SBX cannot do on rotated problems. Which children are
    trials: those whose ``a`` carries the DE choice of a self-adaptive ``portfolio``
    mutation (see :class:`~growsim.ga.mutation.Portfolio`), else each with probability
    ``share``. The others are SBX children (``eta``, ``gene_rate``; pairs crossed with
    probability ``rate``).

    Examples
    --------
    >>> import numpy as np
    >>> from growsim.ga import Genome, Real
    >>> g = Genome([Real("x", 0, 1, size=4)])
    >>> pop = np.random.default_rng(0).random((10, 4))
    >>> op = Differential(share=1.0)
    >>> kids = op.cross_pairs(pop, np.arange(3), np.arange(3, 6), 5, np.random.default_rng(1), g)
    >>> kids.shape, bool(((kids >= 0) & (kids < 1)).all())
    ((5, 4), True)
    """

    name = "differential"
    kinds = ("real",)
    #: :meth:`Operators.mate` hands :meth:`cross_pairs` the mutation's per-child choice
    takes_choice = True

    def __init__(
        self,
        f: float = 0.5,
        cr: float = 0.9,
        share: float = 0.5,
        eta: float = 15.0,
        gene_rate: float = 0.5,
        rate: float = 0.9,
    ):
        super().__init__(rate)
        if not 0.0 < float(f) <= 2.0:
            raise UserInputError(f"crossover 'differential': f must be in (0, 2], got {f}")
        self.f = float(f)
        self.cr = _check_prob(self.name, "cr", cr)
        self.share = _check_prob(self.name, "share", share)
        self.eta = float(eta)
        self.gene_rate = _check_prob(self.name, "gene_rate", gene_rate)
        self._sbx = SBX(eta=eta, gene_rate=gene_rate, rate=rate)

    def __repr__(self) -> str:
        opts = ", ".join(f"{a}={v!r}" for a, v in vars(self).items() if not a.startswith("_"))
        return f"{type(self).__name__}({opts})"

    def _trials(self, pool, base, target, rng, genome, parameters=None):
        """DE trials ``(k, p)``: rows ``target`` of ``pool`` with genes from ``base + f
        (x_r1 - x_r2)`` (``base``, ``target``: ``(k,)`` row indices; ``parameters``: None
        or ``(k, 2)`` per-trial ``f``, ``cr``, NaN = this crossover's; one numba pass)."""
        k, p = base.shape[0], pool.shape[1]
        r = rng.integers(0, pool.shape[0], size=(2, k))
        u = rng.random((k, p))
        forced = rng.integers(0, p, size=k)  # at least one gene from the donor
        f = np.full(k, self.f)
        cr = np.full(k, self.cr)
        if parameters is not None:
            f = np.where(np.isnan(parameters[:, 0]), f, parameters[:, 0])
            cr = np.where(np.isnan(parameters[:, 1]), cr, parameters[:, 1])
        out = np.empty((k, p))
        K.differential_trials(
            np.ascontiguousarray(pool, dtype=np.float64), (base, target, r[0], r[1]), u, forced,
            f, cr, (genome.low, genome.high, np.nextafter(genome.high, -np.inf)), out,
        )  # fmt: skip
        return out

    def cross_pairs(self, pop, ia, ib, n_off, rng, genome, choice=None, parameters=None):
        """The ``n_off`` children of the pairs ``(pop[ia], pop[ib])`` (first children,
        then second children), difference vectors drawn from ``pop``; ``choice``
        ``(n_off,)`` bool: which are DE trials (None: each with probability ``share``);
        ``parameters``: None or ``(n_off, 2)`` each child's own ``f``, ``cr`` (NaN: this
        crossover's), as an adaptive portfolio mutation carries them."""
        a, b = pop[ia], pop[ib]
        c1, c2 = self._sbx(a, b, rng, genome)
        kids = np.concatenate([c1, c2])[:n_off]
        de = rng.random(n_off) < self.share if choice is None else np.asarray(choice, bool)
        if de.any():
            base = np.concatenate([ia, ib])[:n_off][de].astype(np.int64)
            target = np.concatenate([ib, ia])[:n_off][de].astype(np.int64)
            par = None if parameters is None else np.asarray(parameters, np.float64)[de]
            kids[de] = self._trials(pop, base, target, rng, genome, par)
        return kids

    def _cross(self, a, b, rng, genome):
        c1, c2 = self._sbx.cross(a, b, rng, genome)
        m = a.shape[0]
        de = rng.random(2 * m) < self.share
        if de.any():
            pool = np.concatenate([a, b])
            kids = np.concatenate([c1, c2])
            rows = np.arange(2 * m, dtype=np.int64)
            kids[de] = self._trials(pool, rows[de], ((rows + m) % (2 * m))[de], rng, genome)
            c1, c2 = kids[:m], kids[m:]
        return c1, c2


#: name -> crossover class (construct with the options, e.g. ``CROSSOVER["sbx"](eta=10)``)
CROSSOVER: Registry[type[Crossover]] = Registry(
    "crossover operator",
    {
        c.name: c
        for c in (OnePoint, TwoPoint, NPoint, Uniform, Switch, Mean, Blend, SBX, Differential)
    },
)
