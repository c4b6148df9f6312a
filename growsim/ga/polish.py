"""Local refinement of the best-so-far: an elitist (1+lambda) evolution strategy
(``method="es"``, the default) or CMA-ES with restarts (``method="cmaes"``).

Works in decoded parameter space normalised to the unit box (``u = (x - low) / (high -
low)``), so one step size suits every parameter and bit genomes can be refined between
their grid points. Each iteration samples ``batch`` candidates around the incumbent (one
vectorised fitness call, so it parallelises like a GA generation); half of them move all
coordinates (``N(0, sigma^2)``), half move a few random coordinates with a step scaled up
by ``sqrt(p / k)``, which is what finishes off a fit in which most parameters are already
right. The incumbent is replaced by the best candidate if it is **at least as good**, so
the search drifts across the plateaus of piecewise-constant fitnesses (rasterised
silhouettes); the step size follows the smoothed share of strictly improving candidates
toward 1/5 (Rechenberg's rule), and restarts at ``sigma`` after collapsing to ``min_sigma``.

``method="cmaes"`` runs the covariance matrix adaptation evolution strategy (Hansen,
"The CMA Evolution Strategy: A Tutorial"; the ``cma`` package) from the best, with step
``sigma`` in the same unit box, ``batch`` candidates per iteration, and restarts from the
best-so-far whenever it converges, each restart with twice the population (IPOP-CMA-ES,
Auger & Hansen, "A restart CMA evolution strategy with increasing population size"),
until the budget is spent. It learns correlations
between parameters, which is what escapes the basins where one parameter compensates for
another (measured on the IFS silhouette fit: ``docs/models/ifs3d.md``). Its normal draws
come from the polish's own ``numpy.random.Generator``, so it is reproducible.

Both are generators whose only inputs are that ``Generator`` (seeded from the run's seed)
and the scores sent back, so the GA's checkpoint holds the polish as its start and the
scores told so far (``GAState.polish_*``): :func:`polish_best` resumes by sending the
logged scores again, evaluating nothing, and the resumed polish is the uninterrupted
one bit for bit, whatever the method (no CMA-ES object is pickled).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, fields
from typing import Literal, get_args

import numpy as np
from pydantic import (
    ConfigDict,
    Field,
    StrictFloat,
    StrictInt,
    ValidationError,
    model_validator,
)
from pydantic import dataclasses as pydantic_dataclasses

from growsim.errors import GrowsimError, UserInputError
from growsim.ga.history import history_row
from growsim.ga.state import GAState
from growsim.options import validation_message

__all__ = ["METHODS", "PolishOptions", "PolishStep", "polish_best", "polish_steps"]

Method = Literal["es", "cmaes"]
#: polish methods: ``"es"`` (elitist (1+lambda)-ES), ``"cmaes"`` (CMA-ES with restarts)
METHODS = get_args(Method)


@pydantic_dataclasses.dataclass(
    frozen=True, config=ConfigDict(extra="forbid", validate_default=True, defer_build=True)
)
class PolishOptions:
    """Options of :func:`polish_steps` (the ``polish=`` dict of :meth:`GA.run`); strict
    per field, as :class:`~growsim.ga.GAOptions`.

    Examples
    --------
    >>> PolishOptions.from_dict({"evaluations": 500}).sigma
    0.05
    >>> PolishOptions.from_dict({"method": "newton"})
    Traceback (most recent call last):
    ...
    growsim.errors.UserInputError: polish.method: Input should be 'es' or 'cmaes' (got 'newton')
    """

    evaluations: StrictInt = Field(
        1000,
        ge=1,
        description="fitness evaluations of the polish (out of the run's budget)",
    )
    sigma: StrictFloat = Field(0.05, gt=0.0, le=1.0, description="first step size, in the unit box")
    batch: StrictInt | None = Field(
        None, ge=1, description="candidates per iteration (default max(8, 4 + 3 ln p))"
    )
    min_sigma: StrictFloat = Field(
        1e-7,
        gt=0.0,
        description="the es restarts at sigma when its step falls below this",
    )
    method: Method = Field(
        "es", description='"es" ((1+lambda)-ES) or "cmaes" (CMA-ES with restarts)'
    )

    @model_validator(mode="after")
    def _check(self):
        if not self.min_sigma < self.sigma:
            raise ValueError(f"min_sigma must be in (0, sigma), got {self.min_sigma}")
        return self

    @classmethod
    def from_dict(cls, d) -> PolishOptions:
        """Validate a ``polish=`` dict (``True`` = the defaults); :class:`UserInputError`
        names a bad key (``polish.<key>``)."""
        if d is True:
            d = {}
        if not isinstance(d, dict):
            raise UserInputError(f"polish must be a dict of options, got {d!r}")
        allowed = [f.name for f in fields(cls)]
        bad = sorted(set(d) - set(allowed))
        if bad:
            raise UserInputError(
                f"polish: unknown option(s) {', '.join(bad)}; allowed: {', '.join(sorted(allowed))}"
            )
        try:
            return cls(**d)
        except ValidationError as e:
            raise UserInputError(validation_message(e, "polish.")) from None


@dataclass
class PolishStep:
    """One polish iteration: ``candidates`` ``(k, p)`` decoded parameters to evaluate,
    ``sigma`` the step size they were drawn with.

    Examples
    --------
    >>> import numpy as np
    >>> PolishStep(np.zeros((8, 2)), 0.05).candidates.shape
    (8, 2)
    """

    candidates: np.ndarray
    sigma: float


def polish_steps(x0, score0, low, high, discrete, rng, options: PolishOptions):
    """A generator of :class:`PolishStep`; send back the ``(k,)`` scores (larger is
    better, ``-inf`` for failures) of each step's candidates; returns when the evaluation
    budget is spent. ``x0`` ``(p,)`` is the start (decoded), ``score0`` its score,
    ``low``/``high`` ``(p,)`` decoded bounds, ``discrete`` ``(p,)`` bool (rounded columns).

    The generator's return value (``StopIteration.value``) is ``(x_best, score_best)``.

    Examples
    --------
    >>> import numpy as np
    >>> f = lambda x: -((x - 0.3) ** 2).sum(axis=1)
    >>> x0 = np.array([0.9, 0.1])
    >>> gen = polish_steps(x0, f(x0[None])[0], np.zeros(2), np.ones(2), np.zeros(2, bool),
    ...                    np.random.default_rng(0), PolishOptions(evaluations=600))
    >>> step = next(gen)
    >>> try:
    ...     while True:
    ...         step = gen.send(f(step.candidates))
    ... except StopIteration as stop:
    ...     x, s = stop.value
    >>> bool(np.abs(x - 0.3).max() < 1e-3)
    True
    """
    low = np.asarray(low, dtype=np.float64)
    high = np.asarray(high, dtype=np.float64)
    span = np.where(high > low, high - low, 1.0)
    if options.method == "cmaes" and low.size >= 2:  # CMA-ES needs 2+ dimensions
        return (yield from _cmaes_steps(x0, score0, low, high, discrete, rng, options))
    p = low.size
    lam = options.batch or max(8, 4 + int(3 * np.log(max(p, 1))))
    u = (np.asarray(x0, dtype=np.float64) - low) / span
    s = float(score0)
    sigma = float(options.sigma)
    ps = 0.2
    budget = int(options.evaluations)
    used = 0
    while used < budget:
        k = min(lam, budget - used)
        z = rng.standard_normal((k, p))
        few = np.arange(k) % 2 == 1
        if p > 1 and few.any():
            # a few coordinates only: keep 1..3 of them, with a larger step
            nf = int(few.sum())
            kk = rng.integers(1, min(3, p) + 1, size=nf)
            keep = rng.random((nf, p)).argsort(axis=1) < kk[:, None]
            z[few] = np.where(keep, z[few] * np.sqrt(p / kk)[:, None], 0.0)
        cand_u = np.clip(u + sigma * z, 0.0, 1.0)
        cand = low + cand_u * span
        if discrete.any():
            cand[:, discrete] = np.clip(np.round(cand[:, discrete]), low[discrete], high[discrete])
        scores = yield PolishStep(cand, sigma)
        scores = np.asarray(scores, dtype=np.float64)
        used += k
        ok = np.where(np.isfinite(scores), scores, -np.inf)
        j = int(np.argmax(ok))
        frac = float((ok > s).mean())
        if ok[j] >= s:
            u = (cand[j] - low) / span
            s = float(ok[j])
        # 1/5 success rule on the smoothed success share
        ps = 0.7 * ps + 0.3 * frac
        sigma *= float(np.exp((ps - 0.2) / (0.8 * (1.0 + p / (2.0 * lam)))))
        sigma = min(sigma, 0.5)
        if sigma < options.min_sigma:
            sigma = float(options.sigma)
    return low + u * span, s


def _cmaes_steps(x0, score0, low, high, discrete, rng, options: PolishOptions):
    """CMA-ES in the unit box from ``x0``, restarted from the best whenever it stops."""
    import cma  # imported here: only this method needs it

    span = np.where(high > low, high - low, 1.0)
    p = low.size
    lam = options.batch or max(8, 4 + int(3 * np.log(max(p, 1))))
    best_u = np.clip((np.asarray(x0, dtype=np.float64) - low) / span, 0.0, 1.0)
    best_s = float(score0)
    budget = int(options.evaluations)
    used = 0
    opts = {
        "bounds": [0.0, 1.0],
        "popsize": lam,
        "verbose": -9,
        "seed": np.nan,  # never touch numpy's global generator ...
        "randn": lambda *shape: rng.standard_normal(shape),  # ... draw from ours
        "tolfun": 1e-9,
        "tolx": 1e-9 * options.sigma,
    }
    while used < budget:
        es = cma.CMAEvolutionStrategy(best_u.tolist(), float(options.sigma), opts)
        opts["popsize"] = min(2 * opts["popsize"], 64 * lam)  # IPOP: larger on restart
        while not es.stop() and used < budget:
            cand_u = np.clip(np.asarray(es.ask(), dtype=np.float64), 0.0, 1.0)
            k = min(len(cand_u), budget - used)
            cand = low + cand_u[:k] * span
            if discrete.any():
                cand[:, discrete] = np.clip(
                    np.round(cand[:, discrete]), low[discrete], high[discrete]
                )
            scores = yield PolishStep(cand, float(es.sigma))
            scores = np.asarray(scores, dtype=np.float64)
            used += k
            ok = np.where(np.isfinite(scores), scores, -np.inf)
            j = int(np.argmax(ok))
            if ok[j] > best_s:
                best_s, best_u = float(ok[j]), (cand[j] - low) / span
            if k < len(cand_u):
                break
            # cma minimises; failures get a large finite value it can rank
            worst = ok[np.isfinite(ok)].min() if np.isfinite(ok).any() else 0.0
            es.tell(list(cand_u), (-np.where(np.isfinite(ok), ok, worst - 1.0)).tolist())
    return low + best_u * span, best_s


def polish_best(
    state: GAState,
    genome,
    options: PolishOptions,
    rng: np.random.Generator,
    evaluate: Callable[[np.ndarray], np.ndarray],
    *,
    maximize: bool,
    target: float | None = None,
    on_row: Callable[[dict], object] | None = None,
    on_step: Callable[[], object] | None = None,
) -> None:
    """Refine the best-so-far of ``state`` in place with :func:`polish_steps`.

    ``evaluate(x)`` takes ``(k, p)`` decoded candidates and returns their ``(k,)`` fitness
    values (in the fitness's own orientation, NaN/inf failed) for the evaluations
    ``state.evaluations ..``; the polish counts them in ``state.evaluations``, moves the
    best-so-far (the genome's nearest raw point in ``best_raw``), adds ``"polish"``
    history rows (numbered on from ``state.generation``; ``diversity`` is the step size)
    and hands each to ``on_row``. It stops when the budget is spent or the best-so-far
    reaches ``target``.

    ``on_step()`` is called after each step, once ``state`` holds it (the GA writes its
    checkpoint there). ``state`` logs the polish's progress (``polish_x0``,
    ``polish_score0``, ``polish_scores``): given a state with a polish under way (loaded
    from a checkpoint), the same ``rng`` seed and ``options``, it re-creates the steps
    told so far by feeding :func:`polish_steps` the logged scores, evaluating nothing,
    then goes on, so the history and best are those of a polish never interrupted.

    Examples
    --------
    >>> import numpy as np
    >>> from growsim.ga import GAState, Genome, Real
    >>> g = Genome([Real("x", -1, 1, size=2)])
    >>> s = GAState.new(islands=1, rng=np.random.default_rng(0))
    >>> s.set_best(-0.5, np.array([0.5, 0.5]), np.array([0.5, 0.5]), 0)
    >>> polish_best(s, g, PolishOptions(evaluations=200), np.random.default_rng(1),
    ...        lambda x: (x**2).sum(axis=1), maximize=False)
    >>> s.evaluations, len(s.rows), bool(-s.best_score < 1e-3)
    (200, 25, True)

    Stopped after 10 steps and resumed from a copy of its state, it ends the same:

    >>> import copy
    >>> t = GAState.new(islands=1, rng=np.random.default_rng(0))
    >>> t.set_best(-0.5, np.array([0.5, 0.5]), np.array([0.5, 0.5]), 0)
    >>> class Stop(Exception): pass
    >>> def stop_at_10():
    ...     if len(t.rows) == 10:
    ...         raise Stop
    >>> try:
    ...     polish_best(t, g, PolishOptions(evaluations=200), np.random.default_rng(1),
    ...                 lambda x: (x**2).sum(axis=1), maximize=False, on_step=stop_at_10)
    ... except Stop:
    ...     saved = copy.deepcopy(t)
    >>> polish_best(saved, g, PolishOptions(evaluations=200), np.random.default_rng(1),
    ...             lambda x: (x**2).sum(axis=1), maximize=False)
    >>> def timeless(rows):
    ...     return [{k: v for k, v in r.items() if k != "seconds"} for r in rows]
    >>> timeless(saved.rows) == timeless(s.rows), saved.best_score == s.best_score
    (True, True)
    """
    sign = 1.0 if maximize else -1.0
    if state.polish_scores is None:  # a new polish, from the best-so-far
        state.polish_x0 = np.array(state.best_params, dtype=np.float64)
        state.polish_score0 = float(state.best_score)
        state.polish_scores = np.empty(0)
    steps = polish_steps(
        state.polish_x0,
        state.polish_score0,
        genome.param_low,
        genome.param_high,
        genome.discrete,
        rng,
        options,
    )
    gen = state.generation
    try:
        step = next(steps)
        gen, step = _replay(state, steps, step, gen)
        if step is None or state.reached(target, sign):
            return
        while True:
            t = time.perf_counter()
            x = step.candidates
            values = evaluate(x)
            ok = np.isfinite(values)
            score = np.where(ok, values * sign, -np.inf)
            state.evaluations += len(x)
            j = int(np.argmax(score))
            if score[j] > state.best_score:
                state.set_best(score[j], genome.encode(x[j][None, :])[0], x[j].copy(), gen)
            state.polish_scores = np.concatenate([state.polish_scores, score])
            seconds = time.perf_counter() - t
            state.elapsed += seconds
            row = history_row(
                gen,
                0,
                state.evaluations,
                score * sign,
                maximize=maximize,
                best_so_far=float(state.best_score * sign),
                diversity=step.sigma,
                seconds=seconds,
                failures=int((~ok).sum()),
                phase="polish",
            )
            state.rows.append(row)
            if on_row is not None:
                on_row(dict(row))
            if on_step is not None:
                on_step()
            gen += 1
            if state.reached(target, sign):
                break
            step = steps.send(score)
    except StopIteration:
        pass


def _replay(state: GAState, steps, step: PolishStep, gen: int):
    """Feed ``steps`` the scores ``state.polish_scores`` logged (the steps a resumed
    polish has done): ``(generation, next step)``, the step None if the polish had
    ended. :class:`GrowsimError` if the log does not fit the steps (another set-up)."""
    done = state.polish_scores
    n_rows = sum(1 for r in state.rows if r.get("phase") == "polish")
    a = n = 0
    try:
        while a < len(done):
            k = len(step.candidates)
            if a + k > len(done):
                break
            a, n, gen = a + k, n + 1, gen + 1
            step = steps.send(done[a - k : a])
    except StopIteration:
        step = None
    if a != len(done) or n != n_rows:
        raise GrowsimError(
            f"checkpoint: the polish's log ({len(done)} scores, {n_rows} steps) does not "
            f"fit its steps ({a} scores in {n} steps)"
        )
    return gen, step
