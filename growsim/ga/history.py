"""What a GA run records and returns: the history, one row per generation and island
(and per polish step), built by one function, :func:`history_row`, and collected into a
DataFrame by :func:`history_frame`; the best :class:`Individual`; the :class:`Result`.

Rows are plain dicts with the keys of :data:`HISTORY_COLUMNS`, in that order, so they go
to JSON (checkpoints) and to the ``callback(ga, row)`` of :meth:`growsim.ga.GA.run` as
they are.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

__all__ = [
    "HISTORY_COLUMNS",
    "Individual",
    "Result",
    "history_frame",
    "history_row",
    "stats",
    "std",
    "summary_row",
]

#: columns of :attr:`growsim.ga.Result.history`, in order
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

#: integer columns (typed explicitly so that an empty history has the same dtypes)
_INT_COLUMNS = {c: "int64" for c in ("generation", "island", "evaluations", "failures")}


def stats(values: np.ndarray, maximize: bool) -> dict:
    """``best``, ``mean``, ``std``, ``worst`` of the finite ``(n,)`` ``values`` (all NaN
    when none is finite); ``best`` is the largest when ``maximize``.

    Examples
    --------
    >>> import numpy as np
    >>> stats(np.array([1.0, 3.0, np.inf]), maximize=False)
    {'best': 1.0, 'mean': 2.0, 'std': 1.0, 'worst': 3.0}
    """
    ok = np.isfinite(values)
    if not ok.any():
        return {"best": np.nan, "mean": np.nan, "std": np.nan, "worst": np.nan}
    v = values if ok.all() else values[ok]
    hi, lo = float(np.maximum.reduce(v)), float(np.minimum.reduce(v))
    return {
        "best": hi if maximize else lo,
        "mean": float(np.add.reduce(v) / v.size),
        "std": float(std(v)),
        "worst": lo if maximize else hi,
    }


def std(a: np.ndarray, axis: int | None = None):
    """``numpy.std(a, axis=axis)`` of a float64 array, bit for bit, without NumPy's
    Python-level argument handling (~10 us less per call: a GA generation at population
    20 takes two). Only ``axis=None`` or ``axis=0``.

    Examples
    --------
    >>> import numpy as np
    >>> a = np.random.default_rng(0).random((5, 3))
    >>> bool(std(a) == a.std()), bool((std(a, axis=0) == a.std(axis=0)).all())
    (True, True)
    """
    n = a.shape[0] if axis == 0 else a.size
    # the operations of numpy's _var/_std, in their order: sum, divide, subtract,
    # square, sum, divide, sqrt
    m = np.add.reduce(a, axis=axis, keepdims=True)
    np.true_divide(m, n, out=m, casting="unsafe", subok=False)
    x = np.subtract(a, m)
    np.square(x, out=x)
    r = np.add.reduce(x, axis=axis)
    if isinstance(r, np.ndarray):
        np.true_divide(r, n, out=r, casting="unsafe", subok=False)
        return np.sqrt(r, out=r)
    r = r.dtype.type(r / n)
    return r.dtype.type(np.sqrt(r))


def history_row(
    generation: int,
    island: int,
    evaluations: int,
    values: np.ndarray,
    *,
    maximize: bool,
    best_so_far: float,
    diversity: float,
    seconds: float,
    failures: int,
    phase: str = "ga",
) -> dict:
    """One history row: ``values`` ``(n,)`` are the fitness values (in the fitness's own
    orientation, failures non-finite) the statistics are taken over.

    Examples
    --------
    >>> import numpy as np
    >>> row = history_row(3, 0, 40, np.array([1.0, 2.0]), maximize=True, best_so_far=2.5,
    ...                   diversity=0.1, seconds=0.01, failures=0)
    >>> list(row) == HISTORY_COLUMNS, row["best"], row["phase"]
    (True, 2.0, 'ga')
    """
    row = {"generation": generation, "island": island, "evaluations": evaluations}
    row.update(stats(values, maximize))
    row["best_so_far"] = best_so_far
    row["diversity"] = diversity
    row["seconds"] = seconds
    row["failures"] = failures
    row["phase"] = phase
    return row


def summary_row(rows: list[dict], values: np.ndarray, maximize: bool) -> dict:
    """The last generation of ``rows`` over all islands (``island = -1``): statistics of
    ``values`` (every island's fitness), mean diversity, summed failures. With one island,
    a copy of its row.

    Examples
    --------
    >>> import numpy as np
    >>> rows = [history_row(0, i, 8, np.array([i, 1.0]), maximize=True, best_so_far=1.0,
    ...                     diversity=0.5 * i, seconds=0.1, failures=i) for i in range(2)]
    >>> s = summary_row(rows, np.array([0.0, 1.0, 1.0, 1.0]), maximize=True)
    >>> s["island"], s["mean"], s["diversity"], s["failures"]
    (-1, 0.75, 0.25, 1)
    """
    last = rows[-1]
    gen_rows = [r for r in rows if r["generation"] == last["generation"]]
    if len(gen_rows) == 1:
        return dict(gen_rows[0])
    return history_row(
        gen_rows[0]["generation"],
        -1,
        last["evaluations"],
        values,
        maximize=maximize,
        best_so_far=last["best_so_far"],
        diversity=float(np.mean([r["diversity"] for r in gen_rows])),
        seconds=gen_rows[0]["seconds"],
        failures=int(sum(r["failures"] for r in gen_rows)),
    )


def history_frame(rows: list[dict]) -> pd.DataFrame:
    """The rows as a DataFrame with the columns :data:`HISTORY_COLUMNS` (counts as int64).

    Examples
    --------
    >>> import numpy as np
    >>> rows = [history_row(0, 0, 2, np.array([1.0, 2.0]), maximize=True, best_so_far=2.0,
    ...                     diversity=0.0, seconds=0.0, failures=0)]
    >>> df = history_frame(rows)
    >>> df.shape, str(df["generation"].dtype)
    ((1, 12), 'int64')
    """
    df = pd.DataFrame(rows, columns=HISTORY_COLUMNS)
    return df.astype(_INT_COLUMNS)


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
