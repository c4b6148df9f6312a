"""Local refinement of the best-so-far: an elitist (1+lambda) evolution strategy.

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
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from growsim.errors import UserInputError

__all__ = ["PolishOptions", "PolishStep", "polish_steps"]


@dataclass(frozen=True)
class PolishOptions:
    """Options of :func:`polish_steps` (the ``polish=`` dict of :meth:`GA.run`).

    Examples
    --------
    >>> PolishOptions.from_dict({"evaluations": 500}).sigma
    0.05
    """

    evaluations: int = 1000
    sigma: float = 0.05
    batch: int | None = None
    min_sigma: float = 1e-7

    @classmethod
    def from_dict(cls, d) -> PolishOptions:
        """Validate a ``polish=`` dict; :class:`UserInputError` names a bad key."""
        if d is True:
            d = {}
        if not isinstance(d, dict):
            raise UserInputError(f"polish must be a dict of options, got {d!r}")
        allowed = {"evaluations", "sigma", "batch", "min_sigma"}
        bad = sorted(set(d) - allowed)
        if bad:
            raise UserInputError(
                f"polish: unknown option(s) {', '.join(bad)}; allowed: {', '.join(sorted(allowed))}"
            )
        o = cls(**d)
        if int(o.evaluations) != o.evaluations or o.evaluations < 1:
            raise UserInputError(f"polish.evaluations must be an integer >= 1, got {o.evaluations}")
        if not 0 < float(o.sigma) <= 1:
            raise UserInputError(f"polish.sigma must be in (0, 1], got {o.sigma}")
        if o.batch is not None and (int(o.batch) != o.batch or o.batch < 1):
            raise UserInputError(f"polish.batch must be an integer >= 1, got {o.batch}")
        if not 0 < float(o.min_sigma) < float(o.sigma):
            raise UserInputError(f"polish.min_sigma must be in (0, sigma), got {o.min_sigma}")
        return o


@dataclass
class PolishStep:
    """One polish iteration: ``candidates`` ``(k, p)`` decoded parameters to evaluate."""

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
