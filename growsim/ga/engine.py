"""The GA engine: :class:`GA`, ask/tell over one or more islands and a ``run()`` loop on
top.

Ask/tell is a template (as evosax's): the public :meth:`GA.ask` and :meth:`GA.tell` do
the bookkeeping (the pending generation, counters, best-so-far, stagnation, history rows)
and ``_ask`` / ``_tell`` the algorithm (each island's new genomes; merge, migration,
extinction). The parts live beside it: the options in :mod:`growsim.ga.options`, the
mutable state (which is the checkpoint) in :mod:`growsim.ga.state`, the generation models
and the migration in :mod:`growsim.ga.generation`, the history rows and results in
:mod:`growsim.ga.history` and the final local refinement in :mod:`growsim.ga.polish`.

Islands evolve side by side (one evaluation batch for all of them); every
``migration_interval`` generations each island sends copies of its best
``migration_rate * population`` individuals to the next island on a ring, replacing the
worst. ``extinction``: an island whose population has collapsed (every genome the same) or
whose whole generation failed is re-created at random around its best individual
(Kuwahara et al.'s "extermination").
"""

from __future__ import annotations

import logging
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

from growsim.errors import GrowsimError, UserInputError
from growsim.ga.evaluate import EvalOutcome, EvaluationError, Evaluator, evaluation_seeds
from growsim.ga.generation import migrate
from growsim.ga.genome import Genome
from growsim.ga.history import Individual, Result, history_frame, history_row, summary_row
from growsim.ga.options import GAOptions
from growsim.ga.polish import PolishOptions, polish_best
from growsim.ga.state import GAState, Pending

__all__ = ["GA"]

log = logging.getLogger("growsim.ga")


class GA:
    """A generic genetic algorithm over a :class:`Genome`.

    Parameters
    ----------
    genome : Genome
    fitness : callable ``(n, p) float64 -> (n,)`` (``vectorized=True``) or ``(p,) -> float``;
        may take ``seeds=`` (see :mod:`growsim.ga.evaluate`); picklable for process pools.
    options : :class:`~growsim.ga.GAOptions` (population, operators, generation model,
        elite, islands, migration, extinction, batch size); default: its defaults
    maximize : bool
    seed : int, the run's seed (``numpy.random.SeedSequence(seed)``)
    vectorized : see ``fitness``
    initial : ``(k, p)`` decoded parameters placed in generation 0 (round-robin on islands)
    **overrides : :class:`~growsim.ga.GAOptions` fields replacing those of ``options``
        (``GA(genome, f, population=20, model="steady")``)

    Attributes
    ----------
    options : the validated :class:`~growsim.ga.GAOptions`
    operators : :class:`~growsim.ga.operator.Operators` (selection, crossover, mutation)
    model : the :class:`~growsim.ga.generation.GenerationModel` (``model.offspring``,
        ``model.elite``)
    state : :class:`~growsim.ga.GAState`, everything a run changes (the checkpoint)

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
        options: GAOptions | None = None,
        *,
        maximize: bool = True,
        seed: int = 0,
        vectorized: bool = True,
        initial=None,
        **overrides,
    ):
        if not isinstance(genome, Genome):
            raise UserInputError(f"genome must be a growsim.ga.Genome, got {genome!r}")
        if not callable(fitness):
            raise UserInputError(f"fitness must be callable, got {fitness!r}")
        if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
            raise UserInputError(f"seed must be an integer >= 0, got {seed!r}")
        self.genome = genome
        self.fitness = fitness
        self.options = o = GAOptions.build(options, **overrides)
        self.maximize = bool(maximize)
        self.sign = 1.0 if self.maximize else -1.0
        self.seed = int(seed)
        self.vectorized = bool(vectorized)
        try:
            self.model = o.generation_model(genome.kind)
        except ValueError as err:  # an offspring the default model cannot use
            raise UserInputError(str(err)) from None
        self.operators = o.operators(genome.kind)
        self.operators.check(genome)
        self._initial = self._check_initial(initial)
        ga_ss, eval_ss, self._polish_ss = np.random.SeedSequence(self.seed).spawn(3)
        #: key of the evaluations' seeds (:func:`~growsim.ga.evaluation_seeds`)
        self.eval_key = int(eval_ss.generate_state(1, np.uint64)[0])
        self.state = GAState.new(o.islands, np.random.default_rng(ga_ss))
        self._decode_buf: np.ndarray | None = None

    def _check_initial(self, initial):
        if initial is None:
            return None
        x = np.asarray(initial, dtype=np.float64)
        if x.ndim == 1:
            x = x[None, :]
        g, places = self.genome, self.options.population * self.options.islands
        if x.ndim != 2 or x.shape[1] != g.n_params:
            raise UserInputError(
                f"initial: expected shape (k, {g.n_params}) for {', '.join(g.names)}, got {x.shape}"
            )
        if x.shape[0] > places:
            raise UserInputError(f"initial: {x.shape[0]} rows but only {places} places")
        bad = ~np.isfinite(x) | (x < g.param_low) | (x > g.param_high)
        if bad.any():
            i, j = np.argwhere(bad)[0]
            raise UserInputError(
                f"initial[{i}]: {g.names[j]} = {x[i, j]!r} is outside "
                f"[{g.param_low[j]:g}, {g.param_high[j]:g}]"
            )
        return g.encode(x)

    def _fingerprint(self) -> dict:
        g, o, ops = self.genome, self.options, self.operators
        return {
            "names": g.names,
            "kind": g.kind,
            "length": g.length,
            "population": o.population,
            "islands": o.islands,
            "model": self.model.name,
            "maximize": self.maximize,
            "seed": self.seed,
            "elite": self.model.elite,
            "offspring": self.model.offspring,
            "operators": [repr(ops.selection), repr(ops.crossover), repr(ops.mutation)],
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
        >>> ga.state.generation, len(ga.ask())  # mu+lambda (the reals' default): 6 children
        (1, 6)
        """
        if self.state.pending is not None:
            return self.state.pending.raw
        started = time.perf_counter()
        islands = self._ask()
        raw = np.concatenate([x for _, x, _ in islands], axis=0)
        self.state.pending = Pending(raw, [(k, st, len(x)) for k, x, st in islands], started)
        return raw

    def _ask(self) -> list[tuple]:
        """One ``(kind, raw (m, L), strategies)`` per island: a random population
        (``"init"``; with the ``initial`` rows), a random one but for the best
        (``"reinit"``, after an extinction) or the generation model's children."""
        st, n, out = self.state, self.options.population, []
        for i in range(self.options.islands):
            if st.pops[i] is None:
                x = self.genome.random(n, st.rng)
                if self._initial is not None:
                    mine = self._initial[i :: self.options.islands]
                    x[: len(mine)] = mine
                out.append(("init", x, None))
            elif st.reinit[i]:
                out.append(("reinit", self.genome.random(n - 1, st.rng), None))
            else:
                kids, strat = self.model.breed(
                    st.pops[i], st.scores[i], st.strategies[i], self.operators, self.genome, st.rng
                )
                out.append(("breed", kids, strat))
        return out

    def tell(self, fitness) -> None:
        """Give the fitness ``(m,)`` of the genomes from :meth:`ask` (NaN/inf = failed).

        The values are in the fitness's own orientation (``maximize`` decides which is
        better); failures are ranked worst. Updates the counters, the best-so-far and
        the history. Raises :class:`GrowsimError` if every individual of the first
        generation failed.

        Examples
        --------
        >>> import numpy as np
        >>> from growsim.ga import GA, Genome, Real
        >>> ga = GA(Genome([Real("x", 0, 1)]), lambda x: x[:, 0], population=4, seed=0)
        >>> ga.tell(np.zeros(4))
        Traceback (most recent call last):
        ...
        growsim.errors.GrowsimError: tell() called before ask()
        >>> ga.tell(np.arange(len(ga.ask())))
        >>> ga.best.fitness, ga.state.evaluations
        (3.0, 4)
        """
        st = self.state
        if st.pending is None:
            raise GrowsimError("tell() called before ask()")
        values = np.asarray(fitness, dtype=np.float64).reshape(-1)
        pending = st.pending
        if values.shape[0] != pending.raw.shape[0]:
            raise UserInputError(
                f"tell: expected {pending.raw.shape[0]} fitness values, got {values.shape[0]}"
            )
        ok = np.isfinite(values)
        if st.generation == 0 and not ok.any() and st.pops[0] is None:
            raise GrowsimError("the fitness failed for every individual of the first generation")
        score = np.where(ok, values * self.sign, -np.inf)
        st.evaluations += len(values)
        gen = st.generation
        divs = self._tell(pending, score)
        improved = False
        for i in range(self.options.islands):
            j = int(np.argmax(st.scores[i]))
            if st.scores[i][j] > st.best_score:
                raw = st.pops[i][j].copy()
                st.set_best(st.scores[i][j], raw, self.genome.decode(raw[None, :])[0], gen)
                improved = True
        st.stagnant = 0 if improved else st.stagnant + 1
        # the generation's wall time: from ask() to here (breeding, evaluation, merging)
        seconds = time.perf_counter() - pending.started
        st.elapsed += seconds
        a = 0
        for i, (_, _, m) in enumerate(pending.islands):
            st.rows.append(
                history_row(
                    gen,
                    i,
                    st.evaluations,
                    st.scores[i] * self.sign,
                    maximize=self.maximize,
                    best_so_far=float(st.best_score * self.sign),
                    diversity=divs[i],
                    seconds=seconds,
                    failures=int((~ok[a : a + m]).sum()),
                )
            )
            a += m
        st.generation += 1
        st.pending = None

    def _tell(self, pending: Pending, score: np.ndarray) -> list[float]:
        """Merge each island's scored genomes (``score`` larger is better), migrate on
        schedule and flag extinct islands; returns the islands' diversities."""
        st, n, genome = self.state, self.options.population, self.genome
        mutation = self.operators.mutation
        adaptive = mutation.self_adaptive
        a = 0
        for i, (kind, strat, m) in enumerate(pending.islands):
            x, s = pending.raw[a : a + m], score[a : a + m]
            a += m
            if kind == "init":
                st.pops[i], st.scores[i] = x.copy(), s.copy()
                st.strategies[i] = mutation.init_strategy(n, genome) if adaptive else None
            elif kind == "reinit":  # the island's best and n - 1 new random individuals
                b = int(np.argmax(st.scores[i]))
                st.pops[i] = np.concatenate([st.pops[i][b : b + 1], x])
                st.scores[i] = np.concatenate([st.scores[i][b : b + 1], s])
                if adaptive:
                    new = mutation.init_strategy(n - 1, genome)
                    st.strategies[i] = np.concatenate([st.strategies[i][b : b + 1], new])
                st.reinit[i] = False
            else:
                st.pops[i], st.scores[i], st.strategies[i] = self.model.merge(
                    st.pops[i], st.scores[i], st.strategies[i], x, s, strat
                )
        gen, o = st.generation, self.options
        if o.islands > 1 and gen > 0 and gen % o.migration_interval == 0:
            self.migrate()
        divs = [genome.diversity(p) for p in st.pops]
        if o.extinction:
            for i in range(o.islands):
                collapsed = divs[i] <= 1e-12
                failed = not np.isfinite(st.scores[i]).any()
                if collapsed or failed:
                    why = "collapsed" if collapsed else "failed"
                    log.info("generation %d, island %d: extinction (population %s)", gen, i, why)
                st.reinit[i] = bool(collapsed or failed)
        return divs

    def migrate(self) -> None:
        """Send copies of each island's best ``migration_rate * population`` (at least
        one, at most ``population - 1``) to replace the worst of the next island on the
        ring; :meth:`tell` does it every ``migration_interval`` generations.

        Examples
        --------
        >>> from growsim.ga import GA, Genome, Real
        >>> ga = GA(Genome([Real("x", 0, 1)]), lambda x: x[:, 0], population=4, islands=2,
        ...         migration_rate=0.25)
        >>> ga.tell(ga.genome.decode(ga.ask())[:, 0])
        >>> best0 = ga.state.pops[0][ga.state.scores[0].argmax()]
        >>> ga.migrate()
        >>> bool((ga.state.pops[1] == best0).all(axis=1).any())
        True
        """
        o, st = self.options, self.state
        k = max(1, round(o.migration_rate * o.population)) if o.migration_rate > 0 else 0
        migrate(st.pops, st.scores, st.strategies, min(k, o.population - 1))

    # -- results ----------------------------------------------------------------------
    @property
    def history(self) -> pd.DataFrame:
        """The per-generation history so far (``HISTORY_COLUMNS``)."""
        return history_frame(self.state.rows)

    @property
    def best(self) -> Individual | None:
        """The best-so-far :class:`Individual` (None before the first :meth:`tell`)."""
        st = self.state
        if st.best_raw is None:
            return None
        return Individual(
            st.best_params.copy(),
            float(st.best_score * self.sign),
            st.best_generation,
            st.best_raw.copy(),
            list(self.genome.names),
        )

    def _summary_row(self) -> dict:
        """The last generation over all islands (the callback's ``row``)."""
        st = self.state
        return summary_row(st.rows, np.concatenate(st.scores) * self.sign, self.maximize)

    # -- checkpoint -------------------------------------------------------------------
    def save_checkpoint(self, path, stop_reason=None, polished=False) -> None:
        """Write :attr:`state` to ``path`` atomically (see :meth:`GAState.save`)."""
        self.state.save(path, self._fingerprint(), stop_reason=stop_reason, polished=polished)

    #: the largest share of the polish's time its checkpoints may take: after a polish
    #: step, the checkpoint is written if the time since the last one is at least
    #: ``1 / share - 1`` times what that one took (0: after every step). A checkpoint
    #: holds the whole history, so late in a long run it costs more than a cheap step
    #: (measured: 25 ms with 1,300 rows, against 20 evaluations of a step).
    checkpoint_share: float = 0.05

    def _polish_saver(self, path, reason):
        """``on_step`` of the polish: writes the checkpoint (stop reason ``reason``) at
        most as often as :attr:`checkpoint_share` allows; None without ``path``."""
        if path is None:
            return None
        share = float(self.checkpoint_share)
        last_end = last_cost = 0.0

        def save():
            nonlocal last_end, last_cost
            t = time.perf_counter()
            if share > 0 and t - last_end < last_cost * (1.0 / share - 1.0):
                return
            self.save_checkpoint(path, stop_reason=reason)
            last_end = time.perf_counter()
            last_cost = last_end - t

        return save

    def load_checkpoint(self, path) -> dict:
        """Restore the state written by :meth:`save_checkpoint`; returns its extra info
        (``stop_reason``, ``polished``). :class:`UserInputError` if it does not match."""
        self.state, extra = GAState.load(path, self._fingerprint())
        return extra

    # -- the loop ---------------------------------------------------------------------
    def _stop(self, generations, evaluations, target, stagnation, wall_time, t0):
        st = self.state
        if st.reached(target, self.sign):
            return "target"
        if generations is not None and st.generation >= generations:
            return "generations"
        if evaluations is not None and st.evaluations >= evaluations:
            return "evaluations"
        if stagnation is not None and st.generation > 0 and st.stagnant >= stagnation:
            return "stagnation"
        if wall_time is not None and time.perf_counter() - t0 >= wall_time:
            return "wall_time"
        return None

    def _decode(self, raw: np.ndarray) -> np.ndarray:
        """``genome.decode(raw)`` into the buffer of the previous generation when nothing
        else holds it (the fitness kept no reference): a 1000 x 1000 population's fresh
        8 MB cost more in page faults than its decoding (measured 1.3-2.5 ms per
        generation)."""
        buf = self._decode_buf
        # references: the attribute, the local name and getrefcount's argument
        if buf is not None and sys.getrefcount(buf) > 3:
            buf = None
        del self._decode_buf
        self._decode_buf = x = self.genome.decode(raw, out=buf)
        return x

    def _evaluate(self, evaluator: Evaluator, x: np.ndarray, where: str = "") -> EvalOutcome:
        """Evaluate ``x`` ``(k, p)`` as the next ``k`` evaluations; log the failures.
        An :class:`EvaluationError` (the executor failed) names ``where`` (default: the
        generation)."""
        gen = self.state.generation
        # the seeds only for a fitness that takes them (they are a function of the index)
        seeds = (
            evaluation_seeds(self.eval_key, self.state.evaluations, len(x))
            if evaluator.with_seeds
            else None
        )
        try:
            out = evaluator(x, seeds)
        except EvaluationError as exc:
            e = self.state.evaluations
            where = where or f"generation {gen}"
            raise EvaluationError(
                f"{where}, evaluations {e + 1}-{e + len(x)}: {exc}"
            ) from exc.__cause__
        if out.failures:
            log.warning(
                "generation %d: %d of %d evaluations failed (given the worst fitness); first: %s",
                gen,
                out.failures,
                len(out.values),
                out.errors[0][1],
            )
            for i, msg in out.errors:
                log.debug("generation %d, individual %d: %s", gen, i, msg)
        return out

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
        checkpoint : path written atomically after every generation and every polish step
        resume : continue from ``checkpoint`` if it exists (same history as uninterrupted,
            whether it was written during the GA or the polish)
        polish : options of a final local refinement of the best (``PolishOptions``:
            ``evaluations``, ``sigma``, ``batch``, ``min_sigma``, ``method``)

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
            bad = isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 1
            if v is not None and bad:
                raise UserInputError(f"{name} must be an integer >= 1, got {v!r}")
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
        polished, saved_reason = False, None
        if resume and Path(checkpoint).exists():
            extra = self.load_checkpoint(checkpoint)
            polished, saved_reason = bool(extra["polished"]), extra.get("stop_reason")
        elif self.state.generation > 0 or self.state.pending is not None:
            raise GrowsimError("run() on a GA that was already stepped; make a new GA")
        evaluator = Evaluator(self.fitness, self.vectorized, executor, self.options.batch_size)
        t0 = time.perf_counter() - self.state.elapsed
        try:
            if self.state.polish_scores is not None:  # the GA had ended: the polish resumes
                reason = saved_reason
            else:
                reason = self._stop(generations, ga_budget, target, stagnation, wall_time, t0)
            while reason is None:
                out = self._evaluate(evaluator, self._decode(self.ask()))
                st = self.state
                if st.generation == 0 and st.pops[0] is None and out.failures == len(out.values):
                    raise GrowsimError(
                        "the fitness failed for every individual of the first generation: "
                        + out.errors[0][1]
                    )
                self.tell(out.values)
                reason = self._stop(generations, ga_budget, target, stagnation, wall_time, t0)
                if callback is not None and callback(self, self._summary_row()):
                    reason = reason or "callback"
                if checkpoint is not None:
                    self.save_checkpoint(checkpoint, stop_reason=reason)
            if popts is not None and self.state.best_raw is not None and not polished:
                polish_best(
                    self.state,
                    self.genome,
                    popts,
                    np.random.default_rng(self._polish_ss),
                    lambda x: self._evaluate(evaluator, x, "the polish").values,
                    maximize=self.maximize,
                    target=target,
                    on_row=None if callback is None else (lambda row: callback(self, row)),
                    on_step=self._polish_saver(checkpoint, reason),
                )
                if checkpoint is not None:
                    self.save_checkpoint(checkpoint, stop_reason=reason, polished=True)
        except BaseException:
            evaluator.close(abort=True)  # a stopped run ends its workers at once
            raise
        evaluator.close()
        st = self.state
        return Result(
            best=self.best,
            history=self.history,
            stop_reason=reason,
            evaluations=st.evaluations,
            generations=st.generation,
            population=np.concatenate([self.genome.decode(p) for p in st.pops]),
            fitness=np.concatenate(st.scores) * self.sign,
            seconds=time.perf_counter() - t0,
        )
