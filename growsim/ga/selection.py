"""Selection operators: pick parent indices from a population's scores.

Every operator is a small class: options go to the constructor, and a call
``op(score, k, rng) -> (k,) int64`` picks ``k`` indices into ``score``. ``score`` is a
``(n,)`` float64 array oriented so that **larger is better** (the engine negates a
minimised fitness) and holds ``-inf`` for individuals whose fitness failed; every operator
gives them the smallest chance (zero where the scheme allows it).
"""

from __future__ import annotations

import numpy as np

from growsim.errors import UserInputError
from growsim.ga.operator import Operator
from growsim.registry import Registry

__all__ = [
    "SELECTION",
    "LinearRank",
    "RandomSelection",
    "Roulette",
    "Selection",
    "StochasticUniversal",
    "Tournament",
    "Truncation",
]


class Selection(Operator):
    """Base class: ``__call__(score (n,), k, rng) -> (k,) int64`` indices.

    Examples
    --------
    >>> import numpy as np
    >>> class Best(Selection):
    ...     name = "best"
    ...     def __call__(self, score, k, rng):
    ...         return np.full(k, np.argmax(score), dtype=np.int64)
    >>> Best()(np.array([1.0, 5.0, 2.0]), 2, np.random.default_rng(0)).tolist()
    [1, 1]
    """

    role = name = "selection"

    def __call__(self, score: np.ndarray, k: int, rng: np.random.Generator) -> np.ndarray:
        raise NotImplementedError


def _ranks(score: np.ndarray) -> np.ndarray:
    """Rank 0 for the worst ... n-1 for the best (stable: ties keep index order)."""
    order = np.argsort(score, kind="stable")
    r = np.empty(score.size, dtype=np.int64)
    r[order] = np.arange(score.size)
    return r


def _proportional_weights(score: np.ndarray) -> np.ndarray:
    """Fitness-proportional weights: scores shifted so the worst finite one weighs a
    small positive amount (so a population of equal scores is sampled uniformly);
    failed (-inf) individuals weigh 0."""
    ok = np.isfinite(score)
    w = np.zeros(score.size)
    if not ok.any():
        return np.ones(score.size)
    s = score[ok]
    lo, hi = s.min(), s.max()
    span = hi - lo
    # the worst finite individual keeps 1 % of the best's weight above it
    w[ok] = (s - lo) + (span * 0.01 if span > 0 else 1.0)
    return w


class LinearRank(Selection):
    """Linear-rank roulette (Kuwahara et al., "Fitting a 3D fractal tree to front/side tree
    images with a GA"): individuals are sorted by score and drawn with probability
    ``p_r = (2 - s) / n + 2 r (s - 1) / (n (n - 1))`` for rank ``r`` (0 = worst), where
    the pressure ``s`` in ``[1, 2]`` is the expected number of copies of the best.

    Examples
    --------
    >>> import numpy as np
    >>> LinearRank()(np.array([1.0, 3.0, 2.0]), 4, np.random.default_rng(0)).shape
    (4,)
    """

    name = "rank"

    def __init__(self, pressure: float = 2.0):
        if not 1.0 <= float(pressure) <= 2.0:
            raise UserInputError(f"selection 'rank': pressure must be in [1, 2], got {pressure}")
        self.pressure = float(pressure)

    def probabilities(self, score: np.ndarray) -> np.ndarray:
        """``(n,)`` selection probabilities."""
        n = score.size
        if n == 1:
            return np.ones(1)
        s = self.pressure
        r = _ranks(score)
        return (2.0 - s) / n + 2.0 * r * (s - 1.0) / (n * (n - 1.0))

    def __call__(self, score, k, rng):
        p = self.probabilities(score)
        c = np.cumsum(p)
        return np.minimum(np.searchsorted(c, rng.random(k) * c[-1], side="right"), score.size - 1)


class Roulette(Selection):
    """Fitness-proportional roulette on scores shifted to be positive.

    Examples
    --------
    >>> import numpy as np
    >>> Roulette()(np.array([1.0, 3.0]), 2, np.random.default_rng(0)).dtype
    dtype('int64')
    """

    name = "roulette"

    def __call__(self, score, k, rng):
        c = np.cumsum(_proportional_weights(score))
        idx = np.searchsorted(c, rng.random(k) * c[-1], side="right")
        return np.minimum(idx, score.size - 1).astype(np.int64)


class StochasticUniversal(Selection):
    """Stochastic universal sampling: ``k`` equally spaced pointers on the fitness-
    proportional wheel, one random offset; the expected counts of roulette with minimal
    spread. The picks are shuffled so pairs are not formed from neighbours.

    Examples
    --------
    >>> import numpy as np
    >>> sorted(StochasticUniversal()(np.array([1.0, 1.0]), 2, np.random.default_rng(0)).tolist())
    [0, 1]
    """

    name = "sus"

    def __call__(self, score, k, rng):
        c = np.cumsum(_proportional_weights(score))
        pointers = (rng.random() + np.arange(k)) * (c[-1] / k)
        idx = np.minimum(np.searchsorted(c, pointers, side="right"), score.size - 1)
        return rng.permutation(idx).astype(np.int64)


class Tournament(Selection):
    """Tournament of ``size`` individuals drawn with replacement; the best wins.

    Examples
    --------
    >>> import numpy as np
    >>> Tournament(size=3)(np.arange(5.0), 3, np.random.default_rng(0)).shape
    (3,)
    """

    name = "tournament"

    def __init__(self, size: int = 2):
        if isinstance(size, bool) or int(size) != size or size < 1:
            raise UserInputError(
                f"selection 'tournament': size must be an integer >= 1, got {size}"
            )
        self.size = int(size)

    def __call__(self, score, k, rng):
        cand = rng.integers(0, score.size, size=(k, self.size))
        win = np.argmax(score[cand], axis=1)
        return cand[np.arange(k), win].astype(np.int64)


class Truncation(Selection):
    """Truncation (elite) selection: uniform picks among the best ``fraction`` (at least
    one individual), as in Uehara et al.'s elite selection.

    Examples
    --------
    >>> import numpy as np
    >>> set(Truncation(0.5)(np.arange(4.0), 20, np.random.default_rng(0))) <= {2, 3}
    True
    """

    name = "truncation"

    def __init__(self, fraction: float = 0.5):
        if not 0.0 < float(fraction) <= 1.0:
            raise UserInputError(
                f"selection 'truncation': fraction must be in (0, 1], got {fraction}"
            )
        self.fraction = float(fraction)

    def __call__(self, score, k, rng):
        m = max(1, round(self.fraction * score.size))
        best = np.argsort(-score, kind="stable")[:m]
        return best[rng.integers(0, m, size=k)].astype(np.int64)


class RandomSelection(Selection):
    """Uniform random picks, blind to the scores.

    Examples
    --------
    >>> import numpy as np
    >>> bool(RandomSelection()(np.zeros(3), 5, np.random.default_rng(0)).max() < 3)
    True
    """

    name = "random"

    def __call__(self, score, k, rng):
        return rng.integers(0, score.size, size=k).astype(np.int64)


#: name -> selection class (construct with the options, e.g. ``SELECTION["tournament"](size=3)``)
SELECTION: Registry[type[Selection]] = Registry(
    "selection operator",
    {
        c.name: c
        for c in (
            LinearRank,
            Roulette,
            StochasticUniversal,
            Tournament,
            Truncation,
            RandomSelection,
        )
    },
)
