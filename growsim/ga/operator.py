"""The base of every GA operator (selection, crossover, mutation): a readable ``repr``
and the check that the operator can handle a genome's coding; :func:`make_operator`,
which builds one from a registry name and options; and :class:`Operators`, the three a
GA applies, with :meth:`Operators.mate`."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from growsim.errors import UserInputError

__all__ = ["Operator", "Operators", "make_operator"]


class Operator:
    """Base class: ``role`` names the operator family, ``name`` its registry name,
    ``kinds`` the genome kinds (``"bits"``, ``"real"``) it accepts.

    Examples
    --------
    >>> from growsim.ga.mutation import Gaussian
    >>> Gaussian(sigma=0.1)
    Gaussian(sigma=0.1, rate=None)
    """

    role = "operator"
    name = "operator"
    #: genome kinds the operator accepts
    kinds: tuple[str, ...] = ("bits", "real")

    def __repr__(self) -> str:
        opts = ", ".join(f"{a}={v!r}" for a, v in vars(self).items())
        return f"{type(self).__name__}({opts})"

    def check(self, genome) -> None:
        """Raise :class:`UserInputError` if the operator cannot handle ``genome``."""
        if genome.kind not in self.kinds:
            raise UserInputError(
                f"{self.role} {self.name!r} works on {' or '.join(self.kinds)} genomes, "
                f"not on a {genome.kind} genome"
            )


def make_operator(registry, spec: str | Operator, options: dict[str, Any]) -> Operator:
    """``spec`` itself if it is an operator instance, else ``registry[spec](**options)``;
    :class:`UserInputError` names an unknown name or bad options.

    Examples
    --------
    >>> from growsim.ga.selection import SELECTION
    >>> make_operator(SELECTION, "tournament", {"size": 3})
    Tournament(size=3)
    >>> make_operator(SELECTION, "tournament", {"sise": 3})  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    growsim.errors.UserInputError: selection 'tournament': bad options {'sise': 3} (...)
    """
    if isinstance(spec, Operator):
        return spec
    cls = registry.get(spec)
    try:
        return cls(**options)
    except TypeError as e:
        raise UserInputError(f"{cls.role} {spec!r}: bad options {options!r} ({e})") from None


@dataclass(frozen=True)
class Operators:
    """The selection, crossover and mutation a GA applies.

    Examples
    --------
    >>> import numpy as np
    >>> from growsim.ga import Genome, Real, SELECTION, CROSSOVER, MUTATION
    >>> g = Genome([Real("x", 0, 1, size=3)])
    >>> ops = Operators(SELECTION["random"](), CROSSOVER["sbx"](), MUTATION["polynomial"]())
    >>> kids, strategies = ops.mate(g.random(4, np.random.default_rng(0)), None,
    ...                             np.array([0, 1]), np.array([2, 3]), 3, g,
    ...                             np.random.default_rng(1))
    >>> kids.shape, strategies
    ((3, 3), None)
    """

    selection: Any
    crossover: Any
    mutation: Any

    def check(self, genome) -> None:
        """Raise :class:`UserInputError` if crossover or mutation (each an
        :class:`Operator`) cannot handle ``genome``."""
        for op in (self.crossover, self.mutation):
            op.check(genome)

    def mate(self, pop, strategy, parents_a, parents_b, n_off: int, genome, rng) -> tuple:
        """Crossover + mutation of the pairs ``(pop[parents_a], pop[parents_b])`` ->
        ``n_off`` children ``(n_off, L)`` and their strategies (each child gets its
        first parent's; None without self-adaptation). A crossover with ``takes_choice``
        gets the mutation's ``crossover_choice`` of the children's strategies and, if the
        mutation has them, their ``crossover_parameters`` (after its ``inherit``)."""
        strat = None
        if strategy is not None:
            strat = np.concatenate([strategy[parents_a], strategy[parents_b]])[:n_off]
        if self.crossover.takes_choice:
            # the mutation's per-child choice of crossover and its parameters (an adaptive
            # Portfolio's), if it makes them; the children's inherited values may be
            # redrawn first (jDE), so each child carries the parameters that made it
            if strat is not None:
                strat = self.mutation.inherit(strat, rng)
            choice = self.mutation.crossover_choice(strat)
            par = self.mutation.crossover_parameters(strat)
            kw = {"choice": choice} if par is None else {"choice": choice, "parameters": par}
            kids = self.crossover.cross_pairs(pop, parents_a, parents_b, n_off, rng, genome, **kw)
        else:
            kids = self.crossover.cross_pairs(pop, parents_a, parents_b, n_off, rng, genome)
        if kids is None:
            c1, c2 = self.crossover(pop[parents_a], pop[parents_b], rng, genome)
            # first children, then second children (one contiguous copy; interleaving them
            # with np.stack cost 0.2 ms more per generation at 1000 x 1000 bits)
            kids = np.concatenate([c1, c2])[:n_off]
        if self.mutation.self_adaptive:
            kids, strat = self.mutation(kids, rng, genome, strat)
        else:
            kids = self.mutation(kids, rng, genome)
        return kids, strat
