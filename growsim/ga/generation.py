"""Generation models: how an island chooses parents and merges its children in, chosen by
name through :data:`GENERATION_MODELS` (``GA(model=...)``); and the ring migration
between islands.

- ``"generational"``: ``population - elite`` children replace everyone but the ``elite``
  best (Kuwahara et al.'s GA keeps the best across generations);
- ``"steady"``: each generation the **best** individual mates with ``offspring`` selected
  partners and the children replace the **worst** (Okusa, "GA-tuned path control of a
  fish agent"; default 2 children a generation);
- ``"mu+lambda"``: ``offspring`` children (default ``population``) compete with their
  parents; the best ``population`` survive.

A model works on one island's arrays: ``pop`` ``(n, L)`` raw genomes, ``score`` ``(n,)``
(larger is better, ``-inf`` failed) and ``strategy`` ``(n,)`` self-adaptive mutation
strategies or None; it never touches the GA's state.
"""

from __future__ import annotations

import numpy as np

from growsim.ga.operator import Operators
from growsim.registry import Registry

__all__ = [
    "GENERATION_MODELS",
    "GenerationModel",
    "Generational",
    "MuPlusLambda",
    "SteadyState",
    "migrate",
]


class GenerationModel:
    """Base class: ``population`` individuals per island, ``offspring`` children per
    generation (None = the model's default), ``elite`` kept by the generational model.

    A model raises :class:`ValueError` for an ``offspring`` it cannot use. Subclasses set
    ``name``, :meth:`default_offspring` and :meth:`merge`; :meth:`parents` pairs
    selected individuals.

    Examples
    --------
    >>> import numpy as np
    >>> from growsim.ga import Genome, Real, GAOptions
    >>> g = Genome([Real("x", 0, 1, size=2)])
    >>> model = GENERATION_MODELS.get("mu+lambda")(population=6, offspring=3)
    >>> rng = np.random.default_rng(0)
    >>> pop = g.random(6, rng)
    >>> kids, _ = model.breed(pop, pop.sum(1), None, GAOptions().operators("real"), g, rng)
    >>> new_pop, new_score, _ = model.merge(pop, pop.sum(1), None, kids, kids.sum(1), None)
    >>> kids.shape, new_pop.shape, bool(new_score.min() >= pop.sum(1).min())
    ((3, 2), (6, 2), True)
    """

    name = "model"

    def __init__(self, population: int, elite: int = 0, offspring: int | None = None):
        self.population = int(population)
        self.elite = int(elite)
        self.offspring = self.default_offspring() if offspring is None else int(offspring)
        self.check_offspring(self.offspring)

    def __repr__(self) -> str:
        return (
            f"{type(self).__name__}(population={self.population}, elite={self.elite}, "
            f"offspring={self.offspring})"
        )

    def default_offspring(self) -> int:
        """Children per generation when ``offspring`` is not given."""
        raise NotImplementedError

    def check_offspring(self, offspring: int) -> None:
        """Raise :class:`ValueError` if the model cannot make ``offspring`` children."""

    def parents(self, score: np.ndarray, pairs: int, ops: Operators, rng) -> tuple:
        """``(pairs,)`` indices of the first and of the second parents."""
        idx = ops.selection(score, 2 * pairs, rng)
        return idx[0::2], idx[1::2]

    def breed(self, pop, score, strategy, ops: Operators, genome, rng) -> tuple:
        """``offspring`` children ``(offspring, L)`` of the island and their strategies."""
        pa, pb = self.parents(score, (self.offspring + 1) // 2, ops, rng)
        return ops.mate(pop, strategy, pa, pb, self.offspring, genome, rng)

    def merge(self, pop, score, strategy, kids, kid_score, kid_strategy) -> tuple:
        """The island's next ``(pop, score, strategy)`` from itself and its scored
        children (``strategy`` and ``kid_strategy`` are None without self-adaptation)."""
        raise NotImplementedError


class Generational(GenerationModel):
    """Children replace all but the ``elite`` best.

    Examples
    --------
    >>> import numpy as np
    >>> m = Generational(population=4, elite=1)
    >>> pop, score, _ = m.merge(np.arange(4.0)[:, None], np.array([0.0, 3, 1, 2]), None,
    ...                         np.full((3, 1), 9.0), np.zeros(3), None)
    >>> m.offspring, pop[:, 0].tolist(), score.tolist()
    (3, [1.0, 9.0, 9.0, 9.0], [3.0, 0.0, 0.0, 0.0])
    """

    name = "generational"

    def default_offspring(self):
        return self.population - self.elite

    def check_offspring(self, offspring):
        if offspring != self.population - self.elite:
            raise ValueError(
                f"offspring ({offspring}): the generational model makes population - elite "
                f"= {self.population - self.elite} children"
            )

    def merge(self, pop, score, strategy, kids, kid_score, kid_strategy):
        keep = np.argsort(-score, kind="stable")[: self.elite]
        if strategy is not None:
            strategy = np.concatenate([strategy[keep], kid_strategy])
        return np.concatenate([pop[keep], kids]), np.concatenate([score[keep], kid_score]), strategy


class SteadyState(GenerationModel):
    """The best mates with ``offspring`` (default 2) selected partners; the children
    replace the worst (the best is never replaced, so ``offspring < population``).

    Examples
    --------
    >>> import numpy as np
    >>> m = SteadyState(population=4)
    >>> pop, score, _ = m.merge(np.arange(4.0)[:, None], np.array([0.0, 3, 1, 2]), None,
    ...                         np.full((2, 1), 9.0), np.full(2, 5.0), None)
    >>> m.offspring, pop[:, 0].tolist()
    (2, [9.0, 1.0, 9.0, 3.0])
    """

    name = "steady"

    def default_offspring(self):
        return 2

    def check_offspring(self, offspring):
        if offspring >= self.population:
            raise ValueError(
                f"offspring ({offspring}) must be smaller than population ({self.population}) "
                "for the steady model (the best is never replaced)"
            )

    def parents(self, score, pairs, ops, rng):
        best = int(np.argmax(score))
        return np.full(pairs, best, dtype=np.int64), ops.selection(score, pairs, rng)

    def merge(self, pop, score, strategy, kids, kid_score, kid_strategy):
        worst = np.argsort(score, kind="stable")[: len(kids)]
        pop, score = pop.copy(), score.copy()
        pop[worst], score[worst] = kids, kid_score
        if strategy is not None:
            strategy = strategy.copy()
            strategy[worst] = kid_strategy
        return pop, score, strategy


class MuPlusLambda(GenerationModel):
    """``offspring`` children (default ``population``) compete with their parents; the
    best ``population`` survive.

    Examples
    --------
    >>> import numpy as np
    >>> m = MuPlusLambda(population=2)
    >>> pop, score, _ = m.merge(np.array([[0.0], [1.0]]), np.array([0.0, 1.0]), None,
    ...                         np.array([[7.0], [8.0]]), np.array([5.0, -1.0]), None)
    >>> m.offspring, pop[:, 0].tolist(), score.tolist()
    (2, [7.0, 1.0], [5.0, 1.0])
    """

    name = "mu+lambda"

    def default_offspring(self):
        return self.population

    def merge(self, pop, score, strategy, kids, kid_score, kid_strategy):
        allx = np.concatenate([pop, kids])
        alls = np.concatenate([score, kid_score])
        keep = np.argsort(-alls, kind="stable")[: self.population]
        if strategy is not None:
            strategy = np.concatenate([strategy, kid_strategy])[keep]
        return allx[keep], alls[keep], strategy


#: name -> generation model class (``GENERATION_MODELS.get("steady")(population=10)``)
GENERATION_MODELS: Registry[type[GenerationModel]] = Registry(
    "generation model", {c.name: c for c in (Generational, SteadyState, MuPlusLambda)}
)


def migrate(pops: list, scores: list, strategies: list, k: int) -> None:
    """Ring migration, in place: copies of each island's ``k`` best replace the ``k``
    worst of the next island (strategies travel with their genomes).

    Examples
    --------
    >>> import numpy as np
    >>> pops = [np.array([[0.0], [1.0]]), np.array([[2.0], [3.0]])]
    >>> scores = [np.array([0.0, 1.0]), np.array([2.0, 3.0])]
    >>> migrate(pops, scores, [None, None], 1)
    >>> [p[:, 0].tolist() for p in pops]
    [[3.0, 1.0], [1.0, 3.0]]
    """
    if k == 0:
        return
    out = []
    for pop, score, st in zip(pops, scores, strategies):
        b = np.argsort(-score, kind="stable")[:k]
        out.append((pop[b].copy(), score[b].copy(), None if st is None else st[b].copy()))
    n = len(pops)
    for i in range(n):
        x, s, st = out[(i - 1) % n]
        w = np.argsort(scores[i], kind="stable")[:k]
        pops[i][w], scores[i][w] = x, s
        if st is not None:
            strategies[i][w] = st
