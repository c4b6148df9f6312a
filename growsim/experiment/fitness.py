"""The fitness of an experiment: the unit shipped to evaluation workers.

:class:`Fitness` develops each individual with the model, scores it with every
objective (or an objective's population fast path), weights and sums;
:meth:`Fitness.phenotype_of` is the one way to rebuild an individual from its evolved
values. It reads a plan by its attributes only, so this module imports no other module
of :mod:`growsim.experiment` (``plan`` builds a Fitness; ``load`` compiles plans).
"""

from __future__ import annotations

import hashlib
import sys
from collections.abc import Mapping, Sequence
from typing import Any, NamedTuple

import numpy as np
from threadpoolctl import ThreadpoolController

from growsim.ga.evaluate import GAFitness

__all__ = ["Fitness", "Individual", "one_blas_thread"]


class Individual(NamedTuple):
    """One individual rebuilt from its evolved values (:meth:`Fitness.phenotype_of`)."""

    #: every model parameter (fixed and evolved; integer parameters rounded)
    params: dict[str, float]
    #: the seed the model grows it with
    seed: int
    #: the grown phenotype (None when not grown)
    phenotype: Any


_BLAS = None


def one_blas_thread():
    """A context in which BLAS (numpy's ``@`` and ``dot``) runs on one thread.

    A multi-threaded BLAS splits a long dot product between its threads and adds the parts
    in another order, so the last bits of a sum depended on how many threads the process
    had: Dask starts its workers with ``OPENBLAS_NUM_THREADS=1``, a serial run or a forked
    pool used both cores, and a fit of big trees gave different histories on Dask
    (11090.317974392958 against ...969). Every evaluation runs in this context, so the
    same config and seed give the same numbers on every executor.

    Examples
    --------
    >>> import numpy as np
    >>> with one_blas_thread():
    ...     float(np.ones(3) @ np.ones(3))
    3.0
    """
    global _BLAS
    # the BLAS libraries loaded so far, found again after any import (scipy brings its
    # own OpenBLAS; a controller made before it was loaded would leave it at 2 threads)
    if _BLAS is None or _BLAS[0] != len(sys.modules):
        _BLAS = (len(sys.modules), ThreadpoolController())
    return _BLAS[1].limit(limits=1, user_api="blas")


class Fitness(GAFitness):
    """The fitness of an experiment: develop each individual, score it, weight and sum.

    Built from a plan (:class:`~growsim.experiment.plan.ModelPlan`: the model, its
    parameters, environment, noise and seed; the objectives and weights default to those
    of an ``ExperimentPlan``). It holds only picklable pieces, so process pools and Dask
    workers can run it. A :class:`growsim.ga.evaluate.GAFitness`: the GA's evaluator
    calls :meth:`prepare` once per batch (a mixture's draw of neighbours).
    ``__call__`` takes the GA's ``(n, k)`` matrix of evolved parameters (columns in
    ``evolved`` order) and returns ``(n,)`` float64 fitness values to maximise:
    ``sum_i weight_i * sign_i * score_i`` with ``sign_i = -1`` for objectives that
    minimise. The objectives are :class:`growsim.objectives.base.Objective` instances: an
    objective's :meth:`~growsim.objectives.base.Objective.batch` scores the whole
    ``(n, p)`` matrix of every model parameter at once when it returns an array.

    Examples
    --------
    >>> from growsim.experiment import load_plan
    >>> f = load_plan("experiments/quickstart.toml").fitness()
    >>> f.evolved
    ('f', 'theta0', 'theta_max', 'thq', 'b0', 'b_max')
    >>> f(np.array([[0.8, 80.0, 5.0, 0.2, 8.0, 4.0]])).shape
    (1,)
    """

    def __init__(
        self,
        plan,
        objectives: Sequence[Any] | None = None,
        weights: Sequence[float] | None = None,
    ):
        objectives = plan.objectives if objectives is None else objectives
        weights = plan.weights if weights is None else weights
        self.model = plan.model
        self.names = plan.names
        self.fixed = dict(plan.fixed)
        self.evolved = tuple(p.name for p in plan.evolved)
        self.objectives = list(objectives)
        self.weights = np.asarray(weights, dtype=np.float64)
        self.signs = np.array([1.0 if o.maximize else -1.0 for o in self.objectives])
        self.env = plan.environment
        self.noise = plan.noise
        self.seed = int(plan.seed)
        self.int_names = plan.int_names
        #: a mixture's neighbours ``(draws, k, p)`` (full parameters), drawn by
        #: :meth:`prepare` for the batch being evaluated; None: none drawn yet
        self.neighbours: np.ndarray | None = None
        col = {n: i for i, n in enumerate(self.names)}
        self._evolved_cols = np.array([col[n] for n in self.evolved], dtype=np.int64)
        self._base = np.array([self.fixed.get(n, np.nan) for n in self.names], dtype=np.float64)

    def full_params(self, x: np.ndarray) -> np.ndarray:
        """``(n, k)`` evolved values -> ``(n, p)`` values of every model parameter."""
        x = np.atleast_2d(np.asarray(x, dtype=np.float64))
        full = np.repeat(self._base[None, :], len(x), axis=0)
        full[:, self._evolved_cols] = x
        if self.int_names:
            for j, n in enumerate(self.names):
                if n in self.int_names:
                    full[:, j] = np.round(full[:, j])
        return full

    def param_dict(self, row: np.ndarray) -> dict[str, float]:
        """One row of :meth:`full_params` as the ``{name: value}`` dict a model develops."""
        return {n: float(v) for n, v in zip(self.names, row)}

    def model_seeds(self, full: np.ndarray, seeds: np.ndarray | None) -> np.ndarray:
        """``(n,)`` uint64 seeds the model develops each individual with."""
        n = len(full)
        if self.noise == "per-evaluation" and seeds is not None:
            # the GA's seeds use all 64 bits; models take seeds as int parameters, often
            # up to 2**31 - 1 (Honda's ``seed``): keep the top 31 bits
            return np.asarray(seeds, dtype=np.uint64) >> np.uint64(33)
        if "seed" in self.names:
            return full[:, self.names.index("seed")].astype(np.uint64)
        return np.full(n, self.seed, dtype=np.uint64)

    @property
    def mixture(self) -> bool:
        """Whether the plants are judged among neighbours drawn from the population
        (``environment.stand.mode = "mixture"``)."""
        return self.env.stand.mode == "mixture"

    def prepare(self, x: np.ndarray, seeds: np.ndarray | None = None) -> None:
        """Called by the GA's evaluator once for each batch it evaluates (a generation's
        new individuals, a polish step), in its own process, before the batch is split
        between workers. In a mixture, draw the neighbours that judge every individual
        of the batch: ``environment.stand.draws`` draws of ``neighbours`` individuals of
        ``x`` (without replacement when the batch holds enough, else with), from a
        generator seeded by the batch's evaluation seeds (or, without seeds, by the
        batch's values), so a resumed run and every executor draw the same (common
        random numbers). Otherwise nothing.

        Examples
        --------
        >>> from growsim.experiment import load_plan
        >>> f = load_plan("experiments/stand_mixture_2d.toml", ["ga.population=6"]).fitness()
        >>> x = np.random.default_rng(0).uniform(-1, 1, (6, len(f.evolved)))
        >>> f.prepare(x, np.arange(6, dtype=np.uint64))
        >>> f.neighbours.shape == (f.env.stand.draws, f.env.stand.neighbours, len(f.names))
        True
        """
        if not self.mixture:
            return

        full = self.full_params(x)
        stand = self.env.stand
        if seeds is not None:
            entropy = [int(s) for s in np.asarray(seeds, dtype=np.uint64)]
        else:
            entropy = int.from_bytes(hashlib.sha256(full.tobytes()).digest()[:16], "little")
        rng = np.random.default_rng(np.random.SeedSequence(entropy))
        n, k = len(full), stand.neighbours
        idx = np.stack([rng.choice(n, size=k, replace=n < k) for _ in range(stand.draws)])
        self.neighbours = full[idx]

    def develop(self, row: np.ndarray, seed: int, draw: int = 0):
        """Grow the phenotype of one full parameter row (in a mixture, among the
        neighbours of draw ``draw`` of :meth:`prepare`; before any draw, among copies of
        itself)."""
        params = self.param_dict(row)
        if not self.mixture:
            return self.model.develop(params, seed=int(seed), env=self.env)
        nb = None
        if self.neighbours is not None:
            nb = [self.param_dict(r) for r in self.neighbours[draw]]
        return self.model.mixture(params, nb, seed=int(seed), env=self.env)

    def phenotype_of(self, x, *, grow: bool = True, draws=None) -> Individual:
        """The one way to rebuild an individual from its ``(k,)`` evolved values ``x``
        (columns in :attr:`evolved` order; or a ``{name: value}`` mapping holding every
        evolved name, e.g. ``best.json``'s ``params``), as the evaluation built it: every
        parameter (integers rounded), the model's seed (``model.noise = "fixed"``: the
        ``seed`` parameter or the run's) and the phenotype (``grow=False``: None).
        ``draws``: the arrangement's draws for a model with the ``"draws"`` capability.

        Examples
        --------
        >>> from growsim.experiment import load_plan
        >>> f = load_plan("experiments/quickstart.toml").fitness()
        >>> ind = f.phenotype_of([0.8, 80.0, 5.0, 0.2, 8.0, 4.0])
        >>> ind.params["f"], ind.seed, ind.phenotype.phenotype
        (0.8, 3, 'plant')
        >>> f.phenotype_of(ind.params, grow=False) == ind._replace(phenotype=None)
        True
        """
        if isinstance(x, Mapping):
            x = [x[n] for n in self.evolved]
        row = self.full_params(np.asarray(x, dtype=np.float64)[None, :])[0]
        params = self.param_dict(row)
        seed = int(self.model_seeds(row[None, :], None)[0])
        if not grow:
            return Individual(params, seed, None)
        if draws is None:  # (in a mixture: among the last draw's first neighbours)
            return Individual(params, seed, self.develop(row, seed))
        grown = self.model.develop(params, seed=seed, env=self.env, draws=draws)
        return Individual(params, seed, grown)

    def terms(self, phenotype) -> dict[str, dict[str, float]]:
        """Each objective's score and named terms for one phenotype:
        ``{"<kind>": {"score": s, **terms}}`` (``"<kind>#2"``... for repeated kinds)."""
        out: dict[str, dict[str, float]] = {}
        for obj in self.objectives:
            key, k = obj.name, 2
            while key in out:
                key, k = f"{obj.name}#{k}", k + 1
            out[key] = {"score": float(obj(phenotype))}
            out[key].update({n: float(v) for n, v in obj.terms(phenotype).items()})
        return out

    def __call__(self, x: np.ndarray, seeds: np.ndarray | None = None) -> np.ndarray:
        with one_blas_thread():
            return self._evaluate(x, seeds)

    def _evaluate(self, x: np.ndarray, seeds: np.ndarray | None) -> np.ndarray:
        full = self.full_params(x)
        n = len(full)
        mseeds = self.model_seeds(full, seeds)
        total = np.zeros(n, dtype=np.float64)
        pending = []
        for obj, w, s in zip(self.objectives, self.weights, self.signs):
            vals = obj.batch(self.model, full, self.names, mseeds)
            if vals is None:
                pending.append((obj, w * s))
            else:
                total += w * s * np.asarray(vals, dtype=np.float64).reshape(n)
        if pending:
            # in a mixture: the mean over the draws of neighbours (:meth:`prepare`)
            draws = len(self.neighbours) if self.mixture and self.neighbours is not None else 1
            for i in range(n):
                score = 0.0
                for d in range(draws):
                    phenotype = self.develop(full[i], mseeds[i], d)
                    for obj, ws in pending:
                        score += ws * float(obj(phenotype))
                total[i] += score / draws
        return total
