"""Evaluation of a population: serial, in a process pool, or on any ``Executor`` (Dask).

The fitness sees decoded parameters ``(n, p)`` and returns ``(n,)`` (or, with
``vectorized=False``, one row -> one float). If its signature has a ``seeds`` parameter it
also receives the evaluations' seeds (``(n,)`` uint64, or one int per row), derived from
the run's seed and the evaluation's global index by :func:`evaluation_seeds`, so the result
does not depend on how the population is split across workers.

The two contracts of the GA with what it is given, declared here:

- :class:`GAFitness`: a fitness the GA evaluates. Any callable is one; a fitness whose
  values depend on the whole batch subclasses :class:`GAFitness` and overrides
  :meth:`GAFitness.prepare` (the base's does nothing).
- :class:`Pool`: where evaluations run, an executor together with how many evaluations
  it runs at once (:attr:`Pool.workers`). :func:`open_executor` turns what ``GA.run``'s
  ``executor=`` accepts (None, a process count, any ``concurrent.futures.Executor``, a
  :class:`Pool`) into one; :class:`growsim.experiment.DaskPool` is a Dask
  client's.

Failures of the fitness never crash a run: a vectorized batch that raises is re-evaluated
one row at a time to find the culprit(s); a row that raises or returns NaN/inf is reported
as failed (in a worker as in the main process). A failure of the executor itself (a worker
process that died, a task Dask gave up on) stops the evaluation with an
:class:`EvaluationError` naming the cause.
"""

from __future__ import annotations

import abc
import inspect
import logging
import math
import os
from concurrent.futures import Executor, Future
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass, field

import numpy as np

from growsim.errors import GrowsimError, UserInputError
from growsim.ga.workers import WorkerPool

__all__ = [
    "EvalOutcome",
    "EvaluationError",
    "Evaluator",
    "GAFitness",
    "Pool",
    "evaluate_batch",
    "evaluation_seeds",
    "open_executor",
    "wants_seeds",
]

log = logging.getLogger("growsim.ga")

_M1 = np.uint64(0xBF58476D1CE4E5B9)
_M2 = np.uint64(0x94D049BB133111EB)
_GOLDEN = np.uint64(0x9E3779B97F4A7C15)


def evaluation_seeds(key: int, start: int, n: int) -> np.ndarray:
    """``(n,)`` uint64 seeds for evaluations ``start .. start + n - 1`` of a run whose
    evaluation key is ``key`` (drawn once from the run's ``SeedSequence``).

    SplitMix64 of ``key + index * golden``: a bijective mix, so distinct indices give
    distinct seeds, computed for a whole population at once (a ``SeedSequence`` per
    individual costs ~10 us each).

    Examples
    --------
    >>> s = evaluation_seeds(12345, 0, 3)
    >>> s.dtype, len(set(s.tolist()))
    (dtype('uint64'), 3)
    >>> bool(evaluation_seeds(12345, 2, 1)[0] == s[2])
    True
    """
    idx = np.arange(start, start + n, dtype=np.uint64)
    with np.errstate(over="ignore"):
        z = np.uint64(key) + (idx + np.uint64(1)) * _GOLDEN
        z = (z ^ (z >> np.uint64(30))) * _M1
        z = (z ^ (z >> np.uint64(27))) * _M2
        return z ^ (z >> np.uint64(31))


def wants_seeds(fitness) -> bool:
    """True if ``fitness`` accepts a keyword ``seeds``.

    Examples
    --------
    >>> wants_seeds(lambda x, seeds: x), wants_seeds(lambda x: x)
    (True, False)
    """
    try:
        sig = inspect.signature(fitness)
    except (TypeError, ValueError):
        return False
    return "seeds" in sig.parameters


def _call_row(fitness, row, seed, with_seeds):
    return fitness(row, seeds=int(seed)) if with_seeds else fitness(row)


def evaluate_batch(fitness, x, seeds, vectorized: bool, with_seeds: bool):
    """Evaluate one batch; never raises because of the fitness.

    Parameters
    ----------
    fitness : callable
    x : ``(m, p)`` float64 decoded parameters
    seeds : ``(m,)`` uint64 or None
    vectorized : bool
        True: ``fitness(x[, seeds=seeds]) -> (m,)``; False: one call per row.
    with_seeds : bool

    Returns
    -------
    values : ``(m,)`` float64, NaN where the evaluation failed
    errors : list of ``(row, message)`` for the failed rows

    Examples
    --------
    >>> import numpy as np
    >>> v, err = evaluate_batch(lambda x: 1 / x[:, 0], np.array([[1.0], [0.0]]), None, True, False)
    >>> v.tolist(), err[0][0]
    ([1.0, nan], 1)
    """
    m = x.shape[0]
    values = np.full(m, np.nan)
    errors: list[tuple[int, str]] = []
    if vectorized:
        try:
            with np.errstate(all="ignore"):
                out = fitness(x, seeds=seeds) if with_seeds else fitness(x)
            out = np.asarray(out, dtype=np.float64).reshape(-1)
            if out.shape != (m,):
                raise ValueError(f"fitness returned shape {out.shape} for {m} individuals")
            values[:] = out
        except Exception:
            for i in range(m):
                try:
                    with np.errstate(all="ignore"):
                        one = (
                            fitness(x[i : i + 1], seeds=seeds[i : i + 1])
                            if with_seeds
                            else (fitness(x[i : i + 1]))
                        )
                    one = np.asarray(one, dtype=np.float64).reshape(-1)
                    if one.shape != (1,):
                        raise ValueError(f"fitness returned shape {one.shape} for 1 individual")
                    values[i] = one[0]
                except Exception as e:
                    errors.append((i, f"{type(e).__name__}: {e}"))
    else:
        for i in range(m):
            try:
                with np.errstate(all="ignore"):
                    v = _call_row(fitness, x[i], None if seeds is None else seeds[i], with_seeds)
                values[i] = float(v)
            except Exception as e:
                errors.append((i, f"{type(e).__name__}: {e}"))
    bad = ~np.isfinite(values)
    if bad.any():
        known = {i for i, _ in errors}
        for i in np.flatnonzero(bad):
            if int(i) not in known:
                errors.append((int(i), f"fitness returned {values[i]}"))
        values[bad] = np.nan
        errors.sort()
    return values, errors


class GAFitness(abc.ABC):
    """A fitness the GA evaluates, with what it may declare beyond being callable.

    Any callable ``f(x) -> values`` (``f(x, seeds=...)`` to receive the evaluations'
    seeds; ``vectorized=False``: one row -> one float) is a fitness: the GA calls nothing
    else on it. A fitness whose values depend on the whole batch being evaluated (plants
    judged among neighbours drawn from the population) subclasses this class and
    overrides :meth:`prepare`, which the evaluator calls once per batch, in its own
    process, before splitting the batch between workers, so every worker judges with
    the same draw (:class:`growsim.experiment.fitness.Fitness` is one).

    Examples
    --------
    >>> import numpy as np
    >>> class Shifted(GAFitness):
    ...     shift = 0.0
    ...     def __call__(self, x):
    ...         return x.sum(axis=1) + self.shift
    ...     def prepare(self, x, seeds):
    ...         self.shift = float(x.mean())
    >>> Evaluator(Shifted())(np.ones((2, 2)), None).values.tolist()
    [3.0, 3.0]
    """

    @abc.abstractmethod
    def __call__(self, x: np.ndarray, *args, **kwargs):
        """``(n, p)`` decoded parameters -> ``(n,)`` values (or one row -> one float);
        a ``seeds`` parameter in the signature receives the evaluations' seeds."""

    def prepare(self, x: np.ndarray, seeds: np.ndarray | None) -> None:  # noqa: B027
        """Called once for each batch the evaluator evaluates (a generation's new
        individuals, a polish step), with its ``(n, p)`` parameters and ``(n,)`` seeds
        (None when the fitness takes none), in the evaluator's process, before the batch
        is split between workers. The default does nothing."""


class Pool(Executor):
    """Where a GA's evaluations run: an executor, and how many evaluations it runs at
    once (:attr:`workers`; None when it cannot say, and the evaluator counts the local
    CPUs). A ``concurrent.futures.Executor`` itself (``submit``, ``map``, ``shutdown``,
    ``with``), delegating to the executor it holds; ``shutdown`` shuts that executor
    down, which only the pool's opener does (:func:`open_executor`'s ``owned``).

    Examples
    --------
    >>> from concurrent.futures import ThreadPoolExecutor
    >>> with Pool(ThreadPoolExecutor(2), workers=2) as pool:
    ...     list(pool.map(abs, [-1, 2])), pool.workers
    ([1, 2], 2)
    """

    def __init__(self, executor: Executor, workers: int | None = None, *, terminate=None):
        if workers is not None and (isinstance(workers, bool) or int(workers) < 1):
            raise UserInputError(f"workers must be None or an integer >= 1, got {workers!r}")
        self._terminate = terminate
        self._executor = executor
        self._workers = None if workers is None else int(workers)

    @property
    def workers(self) -> int | None:
        """How many evaluations run at once (None: unknown)."""
        return self._workers

    def submit(self, fn, /, *args, **kwargs) -> Future:
        """``fn(*args, **kwargs)`` on the executor."""
        return self._executor.submit(fn, *args, **kwargs)

    def shutdown(self, wait: bool = True, *, cancel_futures: bool = False) -> None:
        """Shut the executor down."""
        self._executor.shutdown(wait=wait, cancel_futures=cancel_futures)

    def terminate(self) -> None:
        """End the pool now, for a stopped run: the ``terminate`` it was given (a
        :class:`~growsim.ga.workers.WorkerPool`'s: its workers killed), else a shutdown
        that cancels what has not started and does not wait."""
        if self._terminate is not None:
            self._terminate()
        else:
            self.shutdown(wait=False, cancel_futures=True)


def open_executor(executor) -> tuple[Pool | None, bool]:
    """``(pool, owned)`` for an executor argument: None (serial) passes through; a
    :class:`Pool` passes through; any other ``concurrent.futures.Executor`` is wrapped in
    a :class:`Pool` of unknown size (``owned`` False: the caller's to shut down); an int
    ``n`` starts a local process pool of ``n`` workers that the caller shuts down
    (``owned`` True).

    Examples
    --------
    >>> ex, owned = open_executor(2)
    >>> ex.submit(sum, [1, 2]).result(), ex.workers, owned
    (3, 2, True)
    >>> ex.shutdown()
    >>> open_executor(None)
    (None, False)
    """
    if executor is None or isinstance(executor, Pool):
        return executor, False
    if isinstance(executor, Executor):
        return Pool(executor), False
    if isinstance(executor, (int, np.integer)) and not isinstance(executor, bool):
        if executor < 1:
            raise UserInputError(f"executor: need >= 1 worker processes, got {executor}")

        pool = WorkerPool(int(executor))
        return Pool(pool, int(executor), terminate=pool.terminate), True
    raise UserInputError(
        "executor must be None, a number of processes or a "
        f"concurrent.futures.Executor, got {executor!r}"
    )


class EvaluationError(GrowsimError):
    """The executor failed to evaluate a batch (not the fitness, whose failures are
    counted): a worker process died, a task was lost. The message names the cause; the
    run stops (exit code 1), and its checkpoint resumes it.

    Examples
    --------
    >>> raise EvaluationError("a worker process died")
    Traceback (most recent call last):
    ...
    growsim.ga.evaluate.EvaluationError: a worker process died
    """

    exit_code = 1


def _executor_failure(exc: BaseException, n: int, tasks: int) -> str:
    """The message of an :class:`EvaluationError` for ``exc``, raised by an executor's
    future while ``n`` individuals were evaluated in ``tasks`` tasks."""

    what = f"{type(exc).__name__}: {exc}".rstrip(": ")
    if isinstance(exc, BrokenProcessPool):
        why = (
            "a worker process died (killed by a signal, out of memory, os._exit or a crash "
            "in native code)"
        )
    elif type(exc).__name__ == "KilledWorker":  # dask.distributed, not imported here
        why = "Dask gave up on a task: every worker that ran it died"
    else:
        why = "the executor failed"
    return f"{why} while {n} individuals were evaluated in {tasks} tasks ({what})"


@dataclass
class EvalOutcome:
    """Fitness values of a population and its failures.

    ``values``: ``(n,)`` float64 with NaN for failures; ``errors``: ``[(row, message)]``.
    """

    values: np.ndarray
    errors: list = field(default_factory=list)

    @property
    def failures(self) -> int:
        """Number of failed evaluations."""
        return len(self.errors)


class Evaluator:
    """Evaluates decoded populations with a fitness, serially or on an executor.

    Parameters
    ----------
    fitness : callable (a :class:`GAFitness` or any callable), picklable for process
        pools and Dask
    vectorized : bool
    executor : None (serial), int (a local process pool of that many workers, owned and
        shut down by :meth:`close`), a :class:`Pool` or any ``concurrent.futures.Executor``
        (on Dask: :class:`growsim.experiment.DaskPool`)
    batch_size : rows per task; default: the population split into 4 tasks per worker
        (:attr:`Pool.workers`; the local CPUs when the pool cannot say)

    A :class:`GAFitness`'s :meth:`~GAFitness.prepare` is called once per batch, in this
    process, before the batch is split between workers
    (:meth:`growsim.experiment.fitness.Fitness.prepare`).

    Examples
    --------
    >>> import numpy as np
    >>> ev = Evaluator(lambda x: x.sum(axis=1))
    >>> ev(np.ones((3, 2)), np.zeros(3, np.uint64)).values.tolist()
    [2.0, 2.0, 2.0]
    """

    def __init__(self, fitness, vectorized=True, executor=None, batch_size=None):
        if not callable(fitness):
            raise UserInputError(f"fitness must be callable, got {fitness!r}")
        self.fitness = fitness
        self.vectorized = bool(vectorized)
        self.with_seeds = wants_seeds(fitness)
        self._prepare = fitness.prepare if isinstance(fitness, GAFitness) else None
        self.executor, self._own = open_executor(executor)
        self._n_workers: int | None = None
        if batch_size is not None and (int(batch_size) != batch_size or batch_size < 1):
            raise UserInputError(f"batch_size must be an integer >= 1, got {batch_size}")
        self.batch_size = None if batch_size is None else int(batch_size)

    def _workers(self) -> int:
        """The pool's workers (asked once), else the local CPUs."""
        if self._n_workers is None:
            n = self.executor.workers
            self._n_workers = int(n) if n else (os.cpu_count() or 2)
        return self._n_workers

    def __call__(self, x: np.ndarray, seeds: np.ndarray | None) -> EvalOutcome:
        """Evaluate ``x`` ``(n, p)`` with ``seeds`` ``(n,)`` uint64 (None when the fitness
        takes none) -> :class:`EvalOutcome`."""
        n = x.shape[0]
        s = seeds if self.with_seeds else None
        if self._prepare is not None and n:  # a fitness that depends on the batch
            self._prepare(x, s)
        if self.executor is None or n == 0:
            v, err = evaluate_batch(self.fitness, x, s, self.vectorized, self.with_seeds)
            return EvalOutcome(v, err)
        bs = self.batch_size or max(1, math.ceil(n / (4 * self._workers())))
        starts = list(range(0, n, bs))
        futs = [
            self.executor.submit(
                evaluate_batch,
                self.fitness,
                x[a : a + bs],
                None if s is None else s[a : a + bs],
                self.vectorized,
                self.with_seeds,
            )
            for a in starts
        ]
        values = np.empty(n)
        errors = []
        try:
            for a, f in zip(starts, futs):
                v, err = f.result()
                values[a : a + len(v)] = v
                errors.extend((a + i, msg) for i, msg in err)
        # the executor's failure (evaluate_batch never raises for the fitness's
        # exceptions); a SystemExit here came from a worker, not from this process
        except (Exception, SystemExit) as exc:
            for f in futs:
                f.cancel()
            raise EvaluationError(_executor_failure(exc, n, len(futs))) from exc
        return EvalOutcome(values, errors)

    def close(self, abort: bool = False) -> None:
        """Shut down a process pool this evaluator created: after its running tasks, or
        at once (``abort``: a run stopped by an exception, Ctrl-C or SIGTERM; its workers
        killed, :meth:`Pool.terminate`)."""
        if self._own and self.executor is not None:
            if abort:
                self.executor.terminate()
            else:
                self.executor.shutdown(wait=True, cancel_futures=True)
            self.executor = None
            self._own = False
