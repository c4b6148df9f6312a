"""The GA engine: ask/tell over one or more islands, and a ``run()`` loop on top.

Generation models (``model=``):

- ``"generational"``: ``population - elite`` children replace everyone but the ``elite``
  best (Kuwahara et al.'s GA keeps the best across generations);
- ``"steady"``: each generation the **best** individual mates with ``offspring`` selected
  partners and the children replace the **worst** (Okusa, "GA-tuned path control of a fish
  agent"; default 2 children a generation);
- ``"mu+lambda"``: ``offspring`` children (default ``population``) compete with their
  parents; the best ``population`` survive.

Islands evolve side by side (one evaluation batch for all of them); every
``migration_interval`` generations each island sends copies of its best
``migration_rate * population`` individuals to the next island on a ring, replacing the
worst. ``extinction``: an island whose population has collapsed (every genome the same) or
whose whole generation failed is re-created at random around its best individual
(Kuwahara et al.'s "extermination").
"""

from __future__ import annotations

import json
import logging
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from growsim.errors import GrowsimError, UserInputError
from growsim.files import atomic_write
from growsim.ga.crossover import CROSSOVER, Crossover
from growsim.ga.evaluate import Evaluator, evaluation_seeds
from growsim.ga.genome import Genome
from growsim.ga.mutation import MUTATION, Mutation
from growsim.ga.polish import PolishOptions, polish_steps
from growsim.ga.selection import SELECTION, Selection

__all__ = ["GA", "HISTORY_COLUMNS", "Individual", "Result"]

log = logging.getLogger("growsim.ga")

#: columns of :attr:`Result.history`, in order
HISTORY_COLUMNS = [
    "generation",
    "island",
    "evaluations",
    "best",
    "mean",
    "std",
    "worst",
    "best_so_far",
    "diversity",
    "seconds",
    "failures",
    "phase",
]

#: default operators per genome kind: the ones ``benchmarks/ga_vs_peers.py`` measures
DEFAULTS = {
    "bits": (("tournament", {"size": 4}), ("uniform", {"rate": 1.0}), ("bitflip", {})),
    "real": (("tournament", {"size": 4}), ("sbx", {"eta": 15.0}), ("polynomial", {})),
}

MODELS = ("generational", "steady", "mu+lambda")
_CHECKPOINT_VERSION = 1


@dataclass
class Individual:
    """One solution.

    Attributes
    ----------
    params : ``(p,)`` float64 decoded parameters (columns in genome order)
    fitness : float, as the fitness function returned it
    generation : int, the generation it was found in
    raw : ``(length,)`` raw genome (after a polish of a bit genome, the nearest grid point)
    names : list of str, the genome's column names

    Examples
    --------
    >>> import numpy as np
    >>> Individual(np.array([1.0]), 2.0, 0, np.array([1.0]), ["x"]).named
    {'x': 1.0}
    """

    params: np.ndarray
    fitness: float
    generation: int
    raw: np.ndarray
    names: list = field(default_factory=list)

    @property
    def named(self) -> dict:
        """``{name: value}`` for the decoded parameters."""
        return {n: float(v) for n, v in zip(self.names, self.params)}


@dataclass
class Result:
    """What :meth:`GA.run` returns.

    Attributes
    ----------
    best : :class:`Individual`, the best-so-far over the whole run (incl. polish)
    history : DataFrame, one row per generation and island (``HISTORY_COLUMNS``);
        ``phase`` is ``"ga"`` or ``"polish"``
    stop_reason : ``"generations"``, ``"evaluations"``, ``"target"``, ``"stagnation"``,
        ``"wall_time"`` or ``"callback"``
    evaluations : int, fitness evaluations spent (incl. polish)
    generations : int, GA generations done (the initial population is generation 0)
    population : ``(n_total, p)`` decoded final population (all islands)
    fitness : ``(n_total,)`` its fitness
    seconds : float, wall time of the run (all sessions, if resumed)

    Examples
    --------
    >>> import numpy as np
    >>> from growsim.ga import GA, Genome, Real
    >>> r = GA(Genome([Real("x", -1, 1)]), lambda x: -x[:, 0] ** 2, population=8).run(generations=3)
    >>> r.stop_reason, r.generations
    ('generations', 3)
    """

    best: Individual
    history: pd.DataFrame
    stop_reason: str
    evaluations: int
    generations: int
    population: np.ndarray
    fitness: np.ndarray
    seconds: float


def _make_op(kind: str, registry: dict, base: type, spec, options, default):
    if spec is None:
        spec, dflt = default
        options = {**dflt, **(options or {})}
    if isinstance(spec, base):
        if options:
            raise UserInputError(f"{kind}_options: given with an operator instance {spec!r}")
        return spec
    if isinstance(spec, str):
        if spec not in registry:
            raise UserInputError(
                f"{kind}: unknown operator {spec!r}; allowed: {', '.join(sorted(registry))}"
            )
        if options is not None and not isinstance(options, dict):
            raise UserInputError(f"{kind}_options must be a dict, got {options!r}")
        try:
            return registry[spec](**(options or {}))
        except TypeError as e:
            raise UserInputError(f"{kind} {spec!r}: bad options {options!r} ({e})") from None
    if callable(spec):
        return spec
    raise UserInputError(f"{kind} must be an operator name or instance, got {spec!r}")


def _int_opt(name, v, lo, allow_none=False):
    if v is None and allow_none:
        return None
    if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < lo:
        raise UserInputError(f"{name} must be an integer >= {lo}, got {v!r}")
    return int(v)


def _stats(values: np.ndarray, maximize: bool) -> dict:
    ok = np.isfinite(values)
    if not ok.any():
        return {"best": np.nan, "mean": np.nan, "std": np.nan, "worst": np.nan}
    v = values[ok]
    return {
        "best": float(v.max() if maximize else v.min()),
        "mean": float(v.mean()),
        "std": float(v.std()),
        "worst": float(v.min() if maximize else v.max()),
    }


class GA:
    """A generic genetic algorithm over a :class:`Genome`.

    Parameters
    ----------
    genome : Genome
    fitness : callable ``(n, p) float64 -> (n,)`` (``vectorized=True``) or ``(p,) -> float``;
        may take ``seeds=`` (see :mod:`growsim.ga.evaluate`); picklable for process pools.
    population : individuals per island
    maximize : bool
    seed : int, the run's seed (``numpy.random.SeedSequence(seed)``)
    selection, crossover, mutation : registry names (``SELECTION``, ``CROSSOVER``,
        ``MUTATION``) or operator instances; ``None`` = the defaults for the genome's kind
        (bits: tournament of 4, uniform crossover, bit-flip 1/L; reals: tournament of 4,
        SBX eta 15, polynomial mutation 1/p)
    selection_options, crossover_options, mutation_options : dicts of operator options
    model : ``"generational"``, ``"steady"`` or ``"mu+lambda"``
    elite, elite_rate : individuals kept by the generational model (``elite_rate`` wins)
    offspring : children per generation for ``"steady"`` (default 2) and ``"mu+lambda"``
        (default ``population``)
    islands, migration_rate, migration_interval : island model with ring migration
    extinction : re-create a collapsed island (see the module docstring)
    vectorized : see ``fitness``
    batch_size : rows per task on an executor (default: 4 tasks per worker)
    initial : ``(k, p)`` decoded parameters placed in generation 0 (round-robin on islands)

    Examples
    --------
    >>> import numpy as np
    >>> from growsim.ga import GA, Genome, Real
    >>> def sphere(x):
    ...     return (x**2).sum(axis=1)
    >>> ga = GA(Genome([Real("x", -5.12, 5.12, size=5)]), sphere, population=50,
    ...         maximize=False, seed=1)
    >>> r = ga.run(generations=40)
    >>> bool(r.best.fitness < 0.5), list(r.history.columns[:3])
    (True, ['generation', 'island', 'evaluations'])
    """

    def __init__(
        self,
        genome: Genome,
        fitness,
        population: int = 100,
        maximize: bool = True,
        seed: int = 0,
        selection=None,
        crossover=None,
        mutation=None,
        selection_options: dict | None = None,
        crossover_options: dict | None = None,
        mutation_options: dict | None = None,
        model: str = "generational",
        elite: int = 1,
        elite_rate: float | None = None,
        islands: int = 1,
        migration_rate: float = 0.1,
        migration_interval: int = 5,
        extinction: bool = True,
        vectorized: bool = True,
        batch_size: int | None = None,
        initial=None,
        offspring: int | None = None,
    ):
        if not isinstance(genome, Genome):
            raise UserInputError(f"genome must be a growsim.ga.Genome, got {genome!r}")
        if not callable(fitness):
            raise UserInputError(f"fitness must be callable, got {fitness!r}")
        self.genome = genome
        self.fitness = fitness
        self.n = _int_opt("population", population, 2)
        self.maximize = bool(maximize)
        self._sign = 1.0 if self.maximize else -1.0
        self.seed = _int_opt("seed", seed, 0)
        if model not in MODELS:
            raise UserInputError(f"model: unknown {model!r}; allowed: {', '.join(MODELS)}")
        self.model = model
        sel_d, cx_d, mut_d = DEFAULTS[genome.kind]
        self.selection: Selection = _make_op(
            "selection", SELECTION, Selection, selection, selection_options, sel_d
        )
        self.crossover: Crossover = _make_op(
            "crossover", CROSSOVER, Crossover, crossover, crossover_options, cx_d
        )
        self.mutation: Mutation = _make_op(
            "mutation", MUTATION, Mutation, mutation, mutation_options, mut_d
        )
        for op in (self.crossover, self.mutation):
            if hasattr(op, "check"):
                op.check(genome)
        if elite_rate is not None:
            if not 0.0 <= float(elite_rate) < 1.0:
                raise UserInputError(f"elite_rate must be in [0, 1), got {elite_rate}")
            elite = round(float(elite_rate) * self.n)
        self.elite = _int_opt("elite", elite, 0)
        if self.elite >= self.n:
            raise UserInputError(f"elite ({self.elite}) must be smaller than population ({self.n})")
        default_off = {"generational": self.n - self.elite, "steady": 2, "mu+lambda": self.n}
        if offspring is None:
            self.offspring = default_off[model]
        else:
            if model == "generational":
                raise UserInputError("offspring: the generational model makes population - elite")
            self.offspring = _int_opt("offspring", offspring, 1)
            if model == "steady" and self.offspring >= self.n:
                raise UserInputError(
                    f"offspring ({self.offspring}) must be smaller than population ({self.n}) "
                    "for the steady model (the best is never replaced)"
                )
        self.islands = _int_opt("islands", islands, 1)
        if not 0.0 <= float(migration_rate) <= 1.0:
            raise UserInputError(f"migration_rate must be in [0, 1], got {migration_rate}")
        self.migration_rate = float(migration_rate)
        self.migration_interval = _int_opt("migration_interval", migration_interval, 1)
        self.extinction = bool(extinction)
        self.vectorized = bool(vectorized)
        self.batch_size = _int_opt("batch_size", batch_size, 1, allow_none=True)
        self._initial = self._check_initial(initial)
        ss = np.random.SeedSequence(self.seed)
        ga_ss, eval_ss, polish_ss = ss.spawn(3)
        self.rng = np.random.default_rng(ga_ss)
        self._eval_key = int(eval_ss.generate_state(1, np.uint64)[0])
        self._polish_ss = polish_ss
        self._reset_state()

    # -- state ------------------------------------------------------------------------
    def _reset_state(self):
        self.generation = 0
        self.evaluations = 0
        self.pops: list = [None] * self.islands
        self.scores: list = [None] * self.islands
        self.strategies: list = [None] * self.islands
        self._reinit = [False] * self.islands
        self.best_score = -np.inf
        self.best_raw = None
        self.best_params = None
        self.best_generation = -1
        self.stagnant = 0
        self.rows: list[dict] = []
        self.elapsed = 0.0
        self._pending = None
        self._t_ask = None

    def _check_initial(self, initial):
        if initial is None:
            return None
        x = np.asarray(initial, dtype=np.float64)
        if x.ndim == 1:
            x = x[None, :]
        g = self.genome
        if x.ndim != 2 or x.shape[1] != g.n_params:
            raise UserInputError(
                f"initial: expected shape (k, {g.n_params}) for {', '.join(g.names)}, got {x.shape}"
            )
        if x.shape[0] > self.n * self.islands:
            raise UserInputError(
                f"initial: {x.shape[0]} rows but only {self.n * self.islands} places"
            )
        bad = ~np.isfinite(x) | (x < g.param_low) | (x > g.param_high)
        if bad.any():
            i, j = np.argwhere(bad)[0]
            raise UserInputError(
                f"initial[{i}]: {g.names[j]} = {x[i, j]!r} is outside "
                f"[{g.param_low[j]:g}, {g.param_high[j]:g}]"
            )
        return g.encode(x)

    def _fingerprint(self) -> dict:
        g = self.genome
        return {
            "names": g.names,
            "kind": g.kind,
            "length": g.length,
            "population": self.n,
            "islands": self.islands,
            "model": self.model,
            "maximize": self.maximize,
            "seed": self.seed,
            "elite": self.elite,
            "offspring": self.offspring,
            "operators": [repr(self.selection), repr(self.crossover), repr(self.mutation)],
        }

    # -- ask / tell -------------------------------------------------------------------
    def ask(self) -> np.ndarray:
        """The raw genomes to evaluate next: ``(m, length)``, all islands concatenated.

        Calling ``ask()`` twice without :meth:`tell` returns the same genomes.

        Examples
        --------
        >>> import numpy as np
        >>> from growsim.ga import GA, Genome, Real
        >>> ga = GA(Genome([Real("x", 0, 1, size=2)]), lambda x: x.sum(1), population=6)
        >>> raw = ga.ask()
        >>> ga.tell(ga.genome.decode(raw).sum(axis=1))
        >>> ga.generation
        1
        """
        if self._pending is not None:
            return self._pending["raw"]
        self._t_ask = time.perf_counter()
        parts = []
        info = []
        for i in range(self.islands):
            if self.pops[i] is None:
                x = self.genome.random(self.n, self.rng)
                if self._initial is not None:
                    mine = self._initial[i :: self.islands]
                    x[: len(mine)] = mine
                kind, extra = "init", None
            elif self._reinit[i]:
                x = self.genome.random(self.n - 1, self.rng)
                kind, extra = "reinit", None
            else:
                x, extra = self._breed(i)
                kind = self.model
            parts.append(x)
            info.append((kind, extra, len(x)))
        raw = np.concatenate(parts, axis=0)
        self._pending = {"raw": raw, "info": info}
        return raw

    def _mate(self, pop, score, strategy, parents_a, parents_b, n_off):
        """Crossover + mutation of pairs -> ``n_off`` children (and their strategies)."""
        c1, c2 = self.crossover(pop[parents_a], pop[parents_b], self.rng, self.genome)
        # first children, then second children (one contiguous copy; interleaving them
        # with np.stack cost 0.2 ms more per generation at 1000 x 1000 bits)
        kids = np.concatenate([c1, c2])[:n_off]
        strat = None
        if strategy is not None:
            strat = np.concatenate([strategy[parents_a], strategy[parents_b]])[:n_off]
        if getattr(self.mutation, "self_adaptive", False):
            kids, strat = self.mutation(kids, self.rng, self.genome, strat)
        else:
            kids = self.mutation(kids, self.rng, self.genome)
        return kids, strat

    def _breed(self, i):
        pop, score, strategy = self.pops[i], self.scores[i], self.strategies[i]
        n_off = self.offspring
        pairs = (n_off + 1) // 2
        if self.model == "steady":
            best = int(np.argmax(score))
            pa = np.full(pairs, best, dtype=np.int64)
            pb = self.selection(score, pairs, self.rng)
        else:
            idx = self.selection(score, 2 * pairs, self.rng)
            pa, pb = idx[0::2], idx[1::2]
        kids, strat = self._mate(pop, score, strategy, pa, pb, n_off)
        return kids, strat

    def tell(self, fitness) -> None:
        """Give the fitness ``(m,)`` of the genomes from :meth:`ask` (NaN/inf = failed).

        The values are in the fitness's own orientation (``maximize`` decides which is
        better); failures are ranked worst. Raises :class:`GrowsimError` if every
        individual of the first generation failed.
        """
        if self._pending is None:
            raise GrowsimError("tell() called before ask()")
        values = np.asarray(fitness, dtype=np.float64).reshape(-1)
        raw = self._pending["raw"]
        if values.shape[0] != raw.shape[0]:
            raise UserInputError(
                f"tell: expected {raw.shape[0]} fitness values, got {values.shape[0]}"
            )
        self._tell(values)

    def _tell(self, values):
        raw = self._pending["raw"]
        info = self._pending["info"]
        ok = np.isfinite(values)
        nfail = int((~ok).sum())
        if self.generation == 0 and nfail == len(values) and self.pops[0] is None:
            raise GrowsimError("the fitness failed for every individual of the first generation")
        score = np.where(ok, values * self._sign, -np.inf)
        self.evaluations += len(values)
        gen = self.generation
        a = 0
        for i, (kind, extra, m) in enumerate(info):
            x, s = raw[a : a + m], score[a : a + m]
            a += m
            self._merge(i, kind, x, s, extra)
        if self.islands > 1 and gen > 0 and gen % self.migration_interval == 0:
            self._migrate()
        improved = False
        for i in range(self.islands):
            j = int(np.argmax(self.scores[i]))
            if self.scores[i][j] > self.best_score:
                self.best_score = float(self.scores[i][j])
                self.best_raw = self.pops[i][j].copy()
                self.best_params = self.genome.decode(self.best_raw[None, :])[0]
                self.best_generation = gen
                improved = True
        self.stagnant = 0 if improved else self.stagnant + 1
        divs = [self.genome.diversity(p) for p in self.pops]
        for i in range(self.islands):
            if self.extinction:
                collapsed = divs[i] <= 1e-12
                failed = not np.isfinite(self.scores[i]).any()
                if collapsed or failed:
                    log.info(
                        "generation %d, island %d: extinction (population %s)",
                        gen,
                        i,
                        "collapsed" if collapsed else "failed",
                    )
                self._reinit[i] = bool(collapsed or failed)
        # the generation's wall time: from ask() to here (breeding, evaluation, merging)
        seconds = time.perf_counter() - self._t_ask if self._t_ask is not None else 0.0
        self.elapsed += seconds
        a = 0
        for i, (_, _, m) in enumerate(info):
            fails = int((~ok[a : a + m]).sum())
            a += m
            self._row(gen, i, divs[i], self.scores[i], seconds, fails)
        self.generation += 1
        self._pending = None

    def _merge(self, i, kind, x, s, strat):
        n = self.n
        adaptive = getattr(self.mutation, "self_adaptive", False)
        if kind == "init":
            self.pops[i], self.scores[i] = x.copy(), s.copy()
            self.strategies[i] = self.mutation.init_strategy(n, self.genome) if adaptive else None
            return
        pop, score, st = self.pops[i], self.scores[i], self.strategies[i]
        if kind == "reinit":
            b = int(np.argmax(score))
            self.pops[i] = np.concatenate([pop[b : b + 1], x])
            self.scores[i] = np.concatenate([score[b : b + 1], s])
            if adaptive:
                self.strategies[i] = np.concatenate(
                    [st[b : b + 1], self.mutation.init_strategy(n - 1, self.genome)]
                )
            self._reinit[i] = False
            return
        if self.model == "generational":
            keep = np.argsort(-score, kind="stable")[: self.elite]
            self.pops[i] = np.concatenate([pop[keep], x])
            self.scores[i] = np.concatenate([score[keep], s])
            if adaptive:
                self.strategies[i] = np.concatenate([st[keep], strat])
        elif self.model == "steady":
            worst = np.argsort(score, kind="stable")[: len(x)]
            pop, score = pop.copy(), score.copy()
            pop[worst], score[worst] = x, s
            self.pops[i], self.scores[i] = pop, score
            if adaptive:
                st = st.copy()
                st[worst] = strat
                self.strategies[i] = st
        else:  # mu+lambda
            allx = np.concatenate([pop, x])
            alls = np.concatenate([score, s])
            keep = np.argsort(-alls, kind="stable")[:n]
            self.pops[i], self.scores[i] = allx[keep], alls[keep]
            if adaptive:
                self.strategies[i] = np.concatenate([st, strat])[keep]

    def _migrate(self):
        k = max(1, round(self.migration_rate * self.n)) if self.migration_rate > 0 else 0
        k = min(k, self.n - 1)
        if k == 0:
            return
        out = []
        for i in range(self.islands):
            b = np.argsort(-self.scores[i], kind="stable")[:k]
            st = None if self.strategies[i] is None else self.strategies[i][b].copy()
            out.append((self.pops[i][b].copy(), self.scores[i][b].copy(), st))
        for i in range(self.islands):
            x, s, st = out[(i - 1) % self.islands]
            w = np.argsort(self.scores[i], kind="stable")[:k]
            self.pops[i][w], self.scores[i][w] = x, s
            if st is not None:
                self.strategies[i][w] = st

    def _user(self, score):
        """Scores (larger is better, -inf failed) back to the fitness's own orientation."""
        return score * self._sign

    def _row(self, gen, island, diversity, score, seconds, fails, phase="ga"):
        row = {"generation": gen, "island": island, "evaluations": self.evaluations}
        row.update(_stats(self._user(score), self.maximize))
        row["best_so_far"] = float(self._user(self.best_score))
        row["diversity"] = diversity
        row["seconds"] = seconds
        row["failures"] = fails
        row["phase"] = phase
        self.rows.append(row)

    def _summary_row(self) -> dict:
        """The last generation over all islands (the callback's ``row``)."""
        gen_rows = [r for r in self.rows if r["generation"] == self.rows[-1]["generation"]]
        if len(gen_rows) == 1:
            return dict(gen_rows[0])
        score = np.concatenate(self.scores)
        row = {
            "generation": gen_rows[0]["generation"],
            "island": -1,
            "evaluations": self.evaluations,
        }
        row.update(_stats(self._user(score), self.maximize))
        row["best_so_far"] = float(self._user(self.best_score))
        row["diversity"] = float(np.mean([r["diversity"] for r in gen_rows]))
        row["seconds"] = gen_rows[0]["seconds"]
        row["failures"] = int(sum(r["failures"] for r in gen_rows))
        row["phase"] = "ga"
        return row

    # -- results ----------------------------------------------------------------------
    @property
    def history(self) -> pd.DataFrame:
        """The per-generation history so far (``HISTORY_COLUMNS``)."""
        df = pd.DataFrame(self.rows, columns=HISTORY_COLUMNS)
        return df.astype(
            {"generation": "int64", "island": "int64", "evaluations": "int64", "failures": "int64"}
        )

    @property
    def best(self) -> Individual | None:
        """The best-so-far :class:`Individual` (None before the first :meth:`tell`)."""
        if self.best_raw is None:
            return None
        return Individual(
            self.best_params.copy(),
            float(self._user(self.best_score)),
            self.best_generation,
            self.best_raw.copy(),
            list(self.genome.names),
        )

    # -- checkpoint -------------------------------------------------------------------
    def save_checkpoint(self, path, stop_reason=None, polished=False) -> None:
        """Write the GA state (populations, scores, RNG state, history) to ``path``
        atomically (a temporary file in the same directory, then ``os.replace``)."""
        if self._pending is not None:
            raise GrowsimError("save_checkpoint: a generation was asked but not told")
        path = Path(path)
        meta = {
            "version": _CHECKPOINT_VERSION,
            "fingerprint": self._fingerprint(),
            "generation": self.generation,
            "evaluations": self.evaluations,
            "best_score": self.best_score,
            "best_generation": self.best_generation,
            "stagnant": self.stagnant,
            "reinit": self._reinit,
            "elapsed": self.elapsed,
            "rng": self.rng.bit_generator.state,
            "rows": self.rows,
            "stop_reason": stop_reason,
            "polished": polished,
        }
        arrays = {"meta": np.array(json.dumps(meta, default=_json_default))}
        for i in range(self.islands):
            if self.pops[i] is not None:
                arrays[f"pop{i}"] = self.pops[i]
                arrays[f"score{i}"] = self.scores[i]
            if self.strategies[i] is not None:
                arrays[f"strategy{i}"] = self.strategies[i]
        if self.best_raw is not None:
            arrays["best_raw"] = self.best_raw
            arrays["best_params"] = self.best_params
        path.parent.mkdir(parents=True, exist_ok=True)
        atomic_write(path, lambda f: np.savez(f, **arrays))

    def load_checkpoint(self, path) -> dict:
        """Restore the state written by :meth:`save_checkpoint`; returns its extra info
        (``stop_reason``, ``polished``). :class:`UserInputError` if it does not match."""
        path = Path(path)
        try:
            with np.load(path, allow_pickle=False) as z:
                data = {k: z[k] for k in z.files}
            meta = json.loads(str(data["meta"]))
        except (OSError, ValueError, KeyError) as e:
            raise UserInputError(f"checkpoint {path}: unreadable ({e})") from None
        if meta.get("version") != _CHECKPOINT_VERSION:
            raise UserInputError(f"checkpoint {path}: unknown version {meta.get('version')}")
        mine = json.loads(json.dumps(self._fingerprint()))
        if meta["fingerprint"] != mine:
            diff = [k for k in mine if meta["fingerprint"].get(k) != mine[k]]
            raise UserInputError(
                f"checkpoint {path} was written by a different GA set-up "
                f"(differs in: {', '.join(diff)})"
            )
        self._reset_state()
        self.generation = int(meta["generation"])
        self.evaluations = int(meta["evaluations"])
        self.best_score = float(meta["best_score"])
        self.best_generation = int(meta["best_generation"])
        self.stagnant = int(meta["stagnant"])
        self._reinit = [bool(b) for b in meta["reinit"]]
        self.elapsed = float(meta["elapsed"])
        self.rng.bit_generator.state = meta["rng"]
        self.rows = meta["rows"]
        for i in range(self.islands):
            if f"pop{i}" in data:
                self.pops[i] = data[f"pop{i}"]
                self.scores[i] = data[f"score{i}"]
            if f"strategy{i}" in data:
                self.strategies[i] = data[f"strategy{i}"]
        if "best_raw" in data:
            self.best_raw = data["best_raw"]
            self.best_params = data["best_params"]
        return {"stop_reason": meta.get("stop_reason"), "polished": bool(meta.get("polished"))}

    # -- the loop ---------------------------------------------------------------------
    def _stop(self, generations, evaluations, target, stagnation, wall_time, t0):
        if target is not None and self.best_raw is not None:
            b = self._user(self.best_score)
            if (b >= target) if self.maximize else (b <= target):
                return "target"
        if generations is not None and self.generation >= generations:
            return "generations"
        if evaluations is not None and self.evaluations >= evaluations:
            return "evaluations"
        if stagnation is not None and self.generation > 0 and self.stagnant >= stagnation:
            return "stagnation"
        if wall_time is not None and time.perf_counter() - t0 >= wall_time:
            return "wall_time"
        return None

    def run(
        self,
        generations: int | None = None,
        evaluations: int | None = None,
        target: float | None = None,
        stagnation: int | None = None,
        wall_time: float | None = None,
        executor=None,
        callback=None,
        checkpoint=None,
        resume: bool = False,
        polish: dict | None = None,
    ) -> Result:
        """Evolve until a stop condition holds; returns a :class:`Result`.

        Parameters
        ----------
        generations : stop after this many generations (generation 0, the random
            population, counts as one); default 100 when no other limit is given
        evaluations : stop once this many fitness evaluations are spent (incl. polish)
        target : stop when the best-so-far reaches it (>= when maximising, <= otherwise)
        stagnation : stop after this many generations without a better best-so-far
        wall_time : stop after this many seconds
        executor : None (serial), int (local processes) or a ``concurrent.futures.Executor``
        callback : ``callback(ga, row) -> bool``, after each generation; True stops the run
        checkpoint : path written atomically after every generation
        resume : continue from ``checkpoint`` if it exists (same history as uninterrupted)
        polish : options of a final local refinement of the best (``PolishOptions``:
            ``evaluations``, ``sigma``, ``batch``, ``min_sigma``)

        Examples
        --------
        >>> import numpy as np
        >>> from growsim.ga import GA, Genome, Bits
        >>> ga = GA(Genome([Bits("b", 0, 1, bits=1, size=50)]), lambda x: x.sum(1),
        ...         population=50, seed=2)
        >>> ga.run(target=50, generations=200).stop_reason
        'target'
        """
        popts = None if polish is None else PolishOptions.from_dict(polish)
        for name, v in (
            ("generations", generations),
            ("evaluations", evaluations),
            ("stagnation", stagnation),
        ):
            _int_opt(name, v, 1, allow_none=True)
        if wall_time is not None and not float(wall_time) > 0:
            raise UserInputError(f"wall_time must be > 0 seconds, got {wall_time}")
        if all(v is None for v in (generations, evaluations, target, stagnation, wall_time)):
            generations = 100
        ga_budget = evaluations
        if evaluations is not None and popts is not None:
            ga_budget = evaluations - popts.evaluations
            if ga_budget < 1:
                raise UserInputError(
                    f"polish.evaluations ({popts.evaluations}) leaves no evaluations of the "
                    f"budget ({evaluations}) for the GA"
                )
        if resume and checkpoint is None:
            raise UserInputError("resume=True needs a checkpoint path")
        polished = False
        if resume and Path(checkpoint).exists():
            polished = self.load_checkpoint(checkpoint)["polished"]
        elif self.generation > 0 or self._pending is not None:
            raise GrowsimError("run() on a GA that was already stepped; make a new GA")
        evaluator = Evaluator(self.fitness, self.vectorized, executor, self.batch_size)
        t0 = time.perf_counter() - self.elapsed
        try:
            reason = self._stop(generations, ga_budget, target, stagnation, wall_time, t0)
            while reason is None:
                raw = self.ask()
                x = self.genome.decode(raw)
                seeds = evaluation_seeds(self._eval_key, self.evaluations, len(x))
                out = evaluator(x, seeds)
                self._log_failures(out)
                if self.generation == 0 and self.pops[0] is None and out.failures == len(x):
                    raise GrowsimError(
                        "the fitness failed for every individual of the first generation: "
                        + out.errors[0][1]
                    )
                self._tell(out.values)
                reason = self._stop(generations, ga_budget, target, stagnation, wall_time, t0)
                if callback is not None and callback(self, self._summary_row()):
                    reason = reason or "callback"
                if checkpoint is not None:
                    self.save_checkpoint(checkpoint, stop_reason=reason)
            if popts is not None and self.best_raw is not None:
                if not polished:
                    self._polish(evaluator, popts, target, callback)
                    polished = True
                    if checkpoint is not None:
                        self.save_checkpoint(checkpoint, stop_reason=reason, polished=polished)
        finally:
            evaluator.close()
        return Result(
            best=self.best,
            history=self.history,
            stop_reason=reason,
            evaluations=self.evaluations,
            generations=self.generation,
            population=np.concatenate([self.genome.decode(p) for p in self.pops]),
            fitness=self._user(np.concatenate(self.scores)),
            seconds=time.perf_counter() - t0,
        )

    def _log_failures(self, out):
        if out.failures:
            log.warning(
                "generation %d: %d of %d evaluations failed (given the worst fitness); first: %s",
                self.generation,
                out.failures,
                len(out.values),
                out.errors[0][1],
            )
            for i, msg in out.errors:
                log.debug("generation %d, individual %d: %s", self.generation, i, msg)

    def _polish(self, evaluator, popts, target, callback):
        g = self.genome
        rng = np.random.default_rng(self._polish_ss)
        steps = polish_steps(
            self.best_params, self.best_score, g.param_low, g.param_high, g.discrete, rng, popts
        )
        gen = self.generation
        try:
            step = next(steps)
            while True:
                t = time.perf_counter()
                x = step.candidates
                seeds = evaluation_seeds(self._eval_key, self.evaluations, len(x))
                out = evaluator(x, seeds)
                self._log_failures(out)
                ok = np.isfinite(out.values)
                score = np.where(ok, out.values * self._sign, -np.inf)
                self.evaluations += len(x)
                j = int(np.argmax(score))
                if score[j] > self.best_score:
                    self.best_score = float(score[j])
                    self.best_params = x[j].copy()
                    self.best_raw = g.encode(x[j][None, :])[0]
                    self.best_generation = gen
                seconds = time.perf_counter() - t
                self.elapsed += seconds
                row = {"generation": gen, "island": 0, "evaluations": self.evaluations}
                row.update(_stats(self._user(score), self.maximize))
                row["best_so_far"] = float(self._user(self.best_score))
                row["diversity"] = step.sigma
                row["seconds"] = seconds
                row["failures"] = int((~ok).sum())
                row["phase"] = "polish"
                self.rows.append(row)
                if callback is not None:
                    callback(self, dict(row))
                gen += 1
                if self._stop(None, None, target, None, None, 0.0) == "target":
                    break
                step = steps.send(score)
        except StopIteration:
            pass


def _json_default(o):
    if isinstance(o, np.ndarray):
        return o.tolist()
    if isinstance(o, np.integer):
        return int(o)
    if isinstance(o, np.floating):
        return float(o)
    raise TypeError(f"not JSON serialisable: {type(o).__name__}")
