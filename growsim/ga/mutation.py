"""Mutation operators: change offspring in place.

A call ``op(x, rng, genome) -> x`` mutates the ``(m, L)`` raw offspring ``x`` (it may
modify and return the same array). Self-adaptive operators (``self_adaptive = True``)
also carry one strategy value per individual: ``op(x, rng, genome, strategy) -> (x,
strategy)``, with ``op.init_strategy(n, genome) -> (n,)`` for a new population; the engine
hands each child its first parent's strategy.
"""

from __future__ import annotations

import numpy as np

from growsim.errors import UserInputError
from growsim.ga.operator import Operator
from growsim.kernels import ga as K
from growsim.registry import Registry

__all__ = [
    "MUTATION",
    "BitFlip",
    "Gaussian",
    "MetaRate",
    "Mutation",
    "Polynomial",
    "Portfolio",
    "Reset",
    "SelfAdaptiveGaussian",
]


def _flip_positions(size: int, rate: float, rng) -> np.ndarray:
    """Flat positions of an independent Bernoulli(``rate``) draw over ``size`` loci, made
    without one random number per locus: the count is binomial and the places a sample
    without replacement (a 1000 x 1000 population at rate 1e-3 costs ~1000 draws, not 1e6)."""
    k = int(rng.binomial(size, rate))
    if k == 0:
        return np.zeros(0, dtype=np.int64)
    return rng.choice(size, size=k, replace=False)


class Mutation(Operator):
    """Base class: ``__call__(x (m, L), rng, genome) -> x``.

    Examples
    --------
    >>> import numpy as np
    >>> class Negate(Mutation):
    ...     name = "negate"
    ...     kinds = ("real",)
    ...     def __call__(self, x, rng, genome):
    ...         return -x
    >>> Negate()(np.ones((1, 2)), np.random.default_rng(0), None).tolist()
    [[-1.0, -1.0]]
    """

    role = name = "mutation"
    #: True when the operator evolves per-individual strategies: ``__call__(x, rng, genome,
    #: strategy) -> (x, strategy)``
    self_adaptive = False

    def __call__(self, x, rng, genome):
        raise NotImplementedError

    def inherit(self, strategy, rng):
        """The children's strategies before their crossover (default: as they are, no
        random draw)."""
        return strategy

    def crossover_choice(self, strategy) -> np.ndarray | None:
        """``(m,)`` bool: which children a choosing crossover treats its own way (default:
        None, no choice)."""
        return None

    def crossover_parameters(self, strategy) -> np.ndarray | None:
        """``(m, k)`` per-child parameters for a choosing crossover (default: None)."""
        return None


def _rate(op: str, rate, default: float) -> float:
    r = default if rate is None else float(rate)
    if not 0.0 <= r <= 1.0:
        raise UserInputError(f"mutation {op!r}: rate must be in [0, 1], got {rate}")
    return r


class BitFlip(Mutation):
    """Flip each bit independently with probability ``rate`` (default ``1 / L``); Okusa's
    fish GA uses 0.06 on every bit, Kuwahara et al. 0.001.

    Examples
    --------
    >>> import numpy as np
    >>> from growsim.ga import Genome, Bits
    >>> g = Genome([Bits("b", 0, 1, bits=1, size=1000)])
    >>> x = BitFlip(rate=0.1)(np.zeros((10, 1000), np.uint8), np.random.default_rng(0), g)
    >>> 900 < int(x.sum()) < 1100
    True
    """

    name = "bitflip"
    kinds = ("bits",)

    def __init__(self, rate: float | None = None):
        self.rate = None if rate is None else _rate(self.name, rate, 0.0)

    def __call__(self, x, rng, genome):
        r = _rate(self.name, self.rate, 1.0 / x.shape[1])
        flat = x.reshape(-1)
        pos = _flip_positions(flat.size, r, rng)
        flat[pos] ^= 1
        return x


class MetaRate(Mutation):
    """Self-adaptive ("meta") bit-flip rate, after Kuwahara et al.'s GA: each individual
    carries an inverse rate ``mu`` (an integer of ``bits`` bits, first ``round(1 / rate)``);
    on mutation each bit of ``mu`` flips with probability ``1 / mu``, then each genome bit
    flips with the new ``1 / mu`` (``mu`` is kept >= 1). Good rates spread with the
    genomes that carry them.

    Examples
    --------
    >>> import numpy as np
    >>> from growsim.ga import Genome, Bits
    >>> g = Genome([Bits("b", 0, 1, bits=1, size=64)])
    >>> op = MetaRate(rate=0.01)
    >>> s = op.init_strategy(4, g)
    >>> x, s2 = op(np.zeros((4, 64), np.uint8), np.random.default_rng(0), g, s)
    >>> s.tolist()
    [100.0, 100.0, 100.0, 100.0]
    """

    name = "meta"
    kinds = ("bits",)
    self_adaptive = True

    def __init__(self, rate: float | None = None, bits: int = 10):
        self.rate = None if rate is None else _rate(self.name, rate, 0.0)
        if isinstance(bits, bool) or int(bits) != bits or not 1 <= bits <= 30:
            raise UserInputError(f"mutation 'meta': bits must be an integer in 1..30, got {bits}")
        self.bits = int(bits)

    def init_strategy(self, n: int, genome) -> np.ndarray:
        """``(n,)`` float64 initial inverse rates ``mu``."""
        r = _rate(self.name, self.rate, 1.0 / genome.length)
        mu = min(max(1, round(1.0 / r)) if r > 0 else (1 << self.bits) - 1, (1 << self.bits) - 1)
        return np.full(int(n), float(mu))

    def __call__(self, x, rng, genome, strategy):
        m, L = x.shape
        mu = np.asarray(strategy, dtype=np.int64).copy()
        # mutate mu's own bits with probability 1/mu each
        shifts = np.arange(self.bits, dtype=np.int64)
        flips = rng.random((m, self.bits)) < (1.0 / np.maximum(mu, 1))[:, None]
        mu ^= (flips.astype(np.int64) << shifts).sum(axis=1)
        mu = np.maximum(mu, 1)
        # then the genome: one float32 draw per bit (each individual has its own rate)
        hit = rng.random((m, L), dtype=np.float32) < (1.0 / mu).astype(np.float32)[:, None]
        x ^= hit.view(np.uint8)
        return x, mu.astype(np.float64)


class Gaussian(Mutation):
    """Add ``N(0, (sigma (high - low))^2)`` to each gene with probability ``rate`` (default
    ``1 / p``); results are clipped to the bounds.

    Examples
    --------
    >>> import numpy as np
    >>> from growsim.ga import Genome, Real
    >>> g = Genome([Real("x", 0, 1, size=4)])
    >>> x = Gaussian(sigma=0.5, rate=1.0)(np.full((3, 4), 0.5), np.random.default_rng(0), g)
    >>> bool(((x >= 0) & (x <= 1)).all())
    True
    """

    name = "gaussian"
    kinds = ("real",)

    def __init__(self, sigma: float = 0.1, rate: float | None = None):
        if not float(sigma) > 0:
            raise UserInputError(f"mutation 'gaussian': sigma must be > 0, got {sigma}")
        self.sigma = float(sigma)
        self.rate = None if rate is None else _rate(self.name, rate, 0.0)

    def __call__(self, x, rng, genome):
        r = _rate(self.name, self.rate, 1.0 / x.shape[1])
        hit = rng.random(x.shape) < r
        step = rng.standard_normal(x.shape) * (self.sigma * (genome.high - genome.low))
        x = np.where(hit, x + step, x)
        return np.clip(x, genome.low, np.nextafter(genome.high, -np.inf))


class SelfAdaptiveGaussian(Mutation):
    """Self-adaptive Gaussian mutation: Schwefel's one step size
    per individual (Beyer & Schwefel, "Evolution strategies: a comprehensive
    introduction"), after a polynomial mutation of a few genes.

    Each individual carries a step ``s``: the length of its whole Gaussian step relative to
    the ranges (first ``sigma``). A child first gets Deb's bounded polynomial mutation
    (index ``polynomial_eta``) on each gene with probability ``polynomial_rate`` (default
    ``1 / p``; 0 = none): coordinate moves of every scale, which separable problems
    reward. Then it draws ``s' = s exp(tau N(0, 1))`` (``tau`` default ``1 / sqrt(p)``),
    kept in ``[min_sigma, max_sigma]``, and adds ``N(0, (s' (high - low) / sqrt(p))^2)`` to
    each gene with probability ``rate`` (default every gene: an isotropic step, which
    rotated problems cost no more than separable ones). Steps that produced surviving
    children spread with them, so the step size follows the landscape, down to the
    precision a sphere needs and up again on a slope. Results are clipped to the bounds.

    Examples
    --------
    >>> import numpy as np
    >>> from growsim.ga import Genome, Real
    >>> g = Genome([Real("x", 0, 1, size=4)])
    >>> op = SelfAdaptiveGaussian(sigma=0.2)
    >>> s = op.init_strategy(3, g)
    >>> x, s2 = op(np.full((3, 4), 0.5), np.random.default_rng(0), g, s)
    >>> s.tolist(), bool(((x >= 0) & (x <= 1)).all()), bool((s2 != 0.2).all())
    ([0.2, 0.2, 0.2], True, True)
    """

    name = "self_adaptive"
    kinds = ("real",)
    self_adaptive = True

    def __init__(
        self,
        sigma: float = 0.01,
        tau: float | None = None,
        rate: float | None = None,
        min_sigma: float = 1e-12,
        max_sigma: float = 1.0,
        polynomial_rate: float | None = None,
        polynomial_eta: float = 20.0,
    ):
        if not 0.0 < float(min_sigma) <= float(sigma) <= float(max_sigma):
            raise UserInputError(
                "mutation 'self_adaptive': need 0 < min_sigma <= sigma <= max_sigma, got "
                f"{min_sigma}, {sigma}, {max_sigma}"
            )
        if tau is not None and not float(tau) >= 0:
            raise UserInputError(f"mutation 'self_adaptive': tau must be >= 0, got {tau}")
        self.sigma = float(sigma)
        self.tau = None if tau is None else float(tau)
        self.rate = None if rate is None else _rate(self.name, rate, 0.0)
        self.min_sigma = float(min_sigma)
        self.max_sigma = float(max_sigma)
        self.polynomial_rate = (
            None if polynomial_rate is None else _rate(self.name, polynomial_rate, 0.0)
        )
        self.polynomial_eta = float(polynomial_eta)
        if not self.polynomial_eta >= 0:
            raise UserInputError(
                f"mutation 'self_adaptive': polynomial_eta must be >= 0, got {polynomial_eta}"
            )

    def init_strategy(self, n: int, genome) -> np.ndarray:
        """``(n,)`` float64 initial steps ``sigma``."""
        return np.full(int(n), self.sigma)

    def __call__(self, x, rng, genome, strategy):
        m, p = x.shape
        if strategy is None:  # children of parents without steps: the first step
            strategy = self.init_strategy(m, genome)
        # all draws up front, one numba pass over the genes (a fixed cost of ~20 us where
        # NumPy calls per step cost ~120 us at population 20)
        poly_rate = 1.0 / p if self.polynomial_rate is None else self.polynomial_rate
        gauss_rate = 1.0 if self.rate is None else self.rate
        r_hit = rng.random((m, p))
        r_u = rng.random((m, p))
        z_tau = rng.standard_normal(m)
        z = rng.standard_normal((m, p))
        r_gauss = rng.random((m, p)) if gauss_rate < 1.0 else np.zeros((m, p))
        out_x = np.empty((m, p))
        out_s = np.empty(m)
        rates = (1.0 / np.sqrt(p) if self.tau is None else self.tau, self.min_sigma,
                 self.max_sigma, poly_rate, self.polynomial_eta, gauss_rate)  # fmt: skip
        K.self_adaptive_mutation(
            np.ascontiguousarray(x, dtype=np.float64),
            (genome.low, genome.high, np.nextafter(genome.high, -np.inf)),
            np.asarray(strategy, dtype=np.float64),
            tuple(float(v) for v in rates),
            (r_hit, r_u, z_tau, z, r_gauss),
            out_x,
            out_s,
        )
        return out_x, out_s


class Portfolio(SelfAdaptiveGaussian):
    """An operator portfolio with a success-based choice, the real-coded default: the
    self-adaptive mutation of :class:`SelfAdaptiveGaussian` whose Gaussian move is either
    isotropic or coordinate-wise, and which also chooses between SBX and differential
    trials for the :class:`~growsim.ga.crossover.Differential` crossover.

    Each individual carries three strategy values ``(n, 3)``: its step ``s`` (as in
    :class:`SelfAdaptiveGaussian`), its move (1 isotropic: ``N(0, (s (high - low) /
    sqrt(p))^2)`` on every gene; 0 coordinate-wise: ``N(0, (s (high - low))^2)`` on each
    gene with probability ``1 / p``, a step of the same length along a few axes) and its
    crossover (1: its children are differential-evolution trials, 0: SBX children). A
    child inherits its first parent's three values; with probability ``switch`` it takes
    the other move, and (for its own children) the other crossover. The moves and
    crossovers whose children survive spread with them, so the mix follows the problem
    (self-adaptation of the operator choice; the idea of adaptive operator portfolios as
    in Qin & Suganthan's SaDE, "Self-adaptive differential evolution algorithm for
    numerical optimization", but carried by the individuals, so it is checkpointed with
    them). The first population has a share ``isotropic_share`` of isotropic movers and
    ``differential_share`` of DE crossers (spread evenly, without random draws). Every
    child first gets the polynomial mutation of ``polynomial_rate`` of its genes. With
    ``f_redraw`` or ``cr_redraw`` > 0 the individuals also carry their DE scale factor and
    crossover rate, redrawn jDE-style before each crossover (:meth:`inherit`).

    Coordinate moves keep a gene that sits on a bound there while others move (the
    linear slope of BBOB f5) and suit separable problems; isotropic moves suit rotated
    ones; differential trials suit rotated multimodal ones. Measured in benchmarks/log/ga.md.

    Examples
    --------
    >>> import numpy as np
    >>> from growsim.ga import Genome, Real
    >>> g = Genome([Real("x", 0, 1, size=4)])
    >>> op = Portfolio()
    >>> s = op.init_strategy(8, g)
    >>> s.shape, float(s[:, 1].mean()), float(s[:, 2].mean())
    ((8, 3), 0.5, 0.25)
    >>> x, s2 = op(np.full((8, 4), 0.5), np.random.default_rng(0), g, s)
    >>> bool(((x >= 0) & (x < 1)).all()), s2.shape, op.crossover_choice(s2).dtype
    (True, (8, 3), dtype('bool'))
    """

    name = "portfolio"
    #: the strategy's columns: step, move (1 isotropic), crossover (1 differential), and
    #: with an adaptive DE the trials' scale factor and crossover rate
    STEP, MOVE, CROSS, F, CR = 0, 1, 2, 3, 4

    def __init__(
        self,
        sigma: float = 0.01,
        tau: float | None = None,
        min_sigma: float = 1e-12,
        max_sigma: float = 1.0,
        polynomial_rate: float | None = None,
        polynomial_eta: float = 20.0,
        switch: float = 0.1,
        isotropic_share: float = 0.5,
        differential_share: float = 0.25,
        f_redraw: float = 0.0,
        cr_redraw: float = 0.0,
    ):
        super().__init__(sigma, tau, None, min_sigma, max_sigma, polynomial_rate, polynomial_eta)
        del self.rate  # every gene (isotropic) or 1/p of them (coordinate-wise)
        self.switch = _rate(self.name, switch, 0.0)
        self.isotropic_share = _rate(self.name, isotropic_share, 0.0)
        self.differential_share = _rate(self.name, differential_share, 0.0)
        self.f_redraw = _rate(self.name, f_redraw, 0.0)
        self.cr_redraw = _rate(self.name, cr_redraw, 0.0)

    @property
    def adaptive_de(self) -> bool:
        """True when individuals carry their own DE ``f`` and ``cr`` (jDE)."""
        return self.f_redraw > 0.0 or self.cr_redraw > 0.0

    def init_strategy(self, n: int, genome) -> np.ndarray:
        """``(n, 3)`` float64: steps ``sigma``; moves and crossovers spread evenly over
        the population at their shares (two low-discrepancy sequences). With an adaptive
        DE ``(n, 5)``: then ``f`` and ``cr``, NaN (the crossover's own) until redrawn."""
        n = int(n)
        i = np.arange(n, dtype=np.float64)

        # round(n share) ones, evenly spaced along the order given
        def spread(order, share):
            return np.floor((order + 1) * share) - np.floor(order * share)

        # the crossovers along a golden-ratio shuffle, so they do not follow the moves
        shuffled = np.argsort(np.argsort((i * 0.6180339887498949) % 1.0, kind="stable"))
        s = np.empty((n, 5 if self.adaptive_de else 3))
        s[:, self.STEP] = self.sigma
        s[:, self.MOVE] = spread(i, self.isotropic_share)
        s[:, self.CROSS] = spread(shuffled.astype(np.float64), self.differential_share)
        if self.adaptive_de:
            s[:, self.F :] = np.nan  # the crossover's own f and cr until redrawn
        return s

    def inherit(self, strategy, rng) -> np.ndarray:
        """The children's strategies ``(m, c)`` before their crossover: with an adaptive
        DE (``f_redraw``, ``cr_redraw`` > 0), each child draws a new ``f`` uniform in
        [0.1, 1] with probability ``f_redraw`` and a new ``cr`` uniform in [0, 1] with
        probability ``cr_redraw`` (jDE: Brest et al., "Self-adapting control parameters
        in differential evolution"); the values that made surviving children spread
        with them. Otherwise ``strategy`` itself, without a random draw."""
        if not self.adaptive_de or np.ndim(strategy) != 2 or strategy.shape[1] < 5:
            return strategy
        m = strategy.shape[0]
        hit = rng.random((2, m)) < np.array([[self.f_redraw], [self.cr_redraw]])
        new = rng.random((2, m))
        out = np.array(strategy, dtype=np.float64)
        out[:, self.F] = np.where(hit[0], 0.1 + 0.9 * new[0], out[:, self.F])
        out[:, self.CR] = np.where(hit[1], new[1], out[:, self.CR])
        return out

    def crossover_parameters(self, strategy) -> np.ndarray | None:
        """``(m, 2)`` each child's DE ``f`` and ``cr`` (NaN: the crossover's own), or None
        when the individuals carry none."""
        if strategy is None or np.ndim(strategy) != 2 or strategy.shape[1] < 5:
            return None
        return np.asarray(strategy)[:, self.F :]

    def crossover_choice(self, strategy) -> np.ndarray | None:
        """``(m,)`` bool: which children of parents with ``strategy`` ``(m, 3)`` are DE
        trials (None without strategies)."""
        if strategy is None or np.ndim(strategy) != 2:
            return None
        return np.asarray(strategy)[:, self.CROSS] == 1.0

    def __call__(self, x, rng, genome, strategy):
        m, p = x.shape
        if strategy is None:
            strategy = self.init_strategy(m, genome)
        strategy = np.ascontiguousarray(strategy, dtype=np.float64)
        poly_rate = 1.0 / p if self.polynomial_rate is None else self.polynomial_rate
        r_hit = rng.random((m, p))
        r_u = rng.random((m, p))
        z_tau = rng.standard_normal(m)
        z = rng.standard_normal((m, p))
        r_axis = rng.random((m, p))
        flip = rng.random((2, m)) < self.switch
        out_x = np.empty((m, p))
        out_s = np.empty((m, strategy.shape[1]))
        # one numba pass (the NumPy steps it replaces cost ~0.1 ms per generation at
        # population 20)
        rates = (1.0 / np.sqrt(p) if self.tau is None else self.tau, self.min_sigma,
                 self.max_sigma, poly_rate, self.polynomial_eta)  # fmt: skip
        K.portfolio_mutation(
            np.ascontiguousarray(x, dtype=np.float64),
            (genome.low, genome.high, np.nextafter(genome.high, -np.inf)),
            strategy,
            tuple(float(v) for v in rates),
            (r_hit, r_u, z_tau, z, r_axis, flip),
            out_x,
            out_s,
        )
        return out_x, out_s


class Polynomial(Mutation):
    """Deb's bounded polynomial mutation of index ``eta`` (larger = smaller steps), each
    gene with probability ``rate`` (default ``1 / p``).

    Examples
    --------
    >>> import numpy as np
    >>> from growsim.ga import Genome, Real
    >>> g = Genome([Real("x", -1, 1, size=4)])
    >>> Polynomial(rate=1.0)(np.zeros((2, 4)), np.random.default_rng(0), g).shape
    (2, 4)
    """

    name = "polynomial"
    kinds = ("real",)

    def __init__(self, eta: float = 20.0, rate: float | None = None):
        if not float(eta) >= 0:
            raise UserInputError(f"mutation 'polynomial': eta must be >= 0, got {eta}")
        self.eta = float(eta)
        self.rate = None if rate is None else _rate(self.name, rate, 0.0)

    def __call__(self, x, rng, genome):
        r = _rate(self.name, self.rate, 1.0 / x.shape[1])
        # only the hit genes are computed (about m of the m x p at the default rate)
        pos = _flip_positions(x.size, r, rng)
        if pos.size == 0:
            return x
        u = rng.random(pos.size)
        col = pos % x.shape[1]
        xl, xu = genome.low[col], genome.high[col]
        flat = x.reshape(-1)
        v = flat[pos]
        span = xu - xl
        e = self.eta + 1.0
        lo = u < 0.5
        # u < 0.5 moves down, else up; the (1 - delta)^(eta+1) terms keep the step in bounds
        with np.errstate(invalid="ignore"):
            v1 = 2.0 * u + (1.0 - 2.0 * u) * np.power(1.0 - (v - xl) / span, e)
            v2 = 2.0 * (1.0 - u) + 2.0 * (u - 0.5) * np.power(1.0 - (xu - v) / span, e)
            dq = np.where(lo, np.power(v1, 1.0 / e) - 1.0, 1.0 - np.power(v2, 1.0 / e))
        flat[pos] = np.clip(v + dq * span, xl, np.nextafter(xu, -np.inf))
        return x


class Reset(Mutation):
    """Replace each individual, with probability ``fraction``, by a new random one (Uehara
    et al.: "mutation creates new random individuals").

    Examples
    --------
    >>> import numpy as np
    >>> from growsim.ga import Genome, Real
    >>> g = Genome([Real("x", 5, 6, size=2)])
    >>> x = Reset(fraction=1.0)(np.zeros((3, 2)), np.random.default_rng(0), g)
    >>> bool((x >= 5).all())
    True
    """

    name = "reset"

    def __init__(self, fraction: float = 0.3):
        self.fraction = _rate(self.name, fraction, 0.0)

    def __call__(self, x, rng, genome):
        hit = rng.random(x.shape[0]) < self.fraction
        k = int(hit.sum())
        if k:
            x[hit] = genome.random(k, rng)
        return x


#: name -> mutation class (construct with the options, e.g. ``MUTATION["bitflip"](rate=0.06)``)
MUTATION: Registry[type[Mutation]] = Registry(
    "mutation operator",
    {
        c.name: c
        for c in (BitFlip, MetaRate, Gaussian, SelfAdaptiveGaussian, Portfolio, Polynomial, Reset)
    },
)
