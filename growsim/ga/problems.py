"""Standard test problems as picklable, vectorised fitnesses (benchmarks, tests, docs).

Each takes decoded parameters ``(n, p)`` and returns ``(n,)``; being module-level they
pickle by reference, so process pools and Dask workers can import them.
"""

from __future__ import annotations

import os
import signal
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

__all__ = ["Faulty", "noisy_sphere", "onemax", "rastrigin", "sphere"]


def onemax(x: np.ndarray) -> np.ndarray:
    """Number of ones (maximise); optimum ``p``.

    Examples
    --------
    >>> onemax(np.array([[1.0, 0.0, 1.0]])).tolist()
    [2.0]
    """
    return x.sum(axis=1)


def rastrigin(x: np.ndarray) -> np.ndarray:
    """Rastrigin, ``10 p + sum(x^2 - 10 cos(2 pi x))`` (minimise); optimum 0 at 0.

    Examples
    --------
    >>> float(rastrigin(np.zeros((1, 30)))[0])
    0.0
    """
    return 10.0 * x.shape[1] + (x * x - 10.0 * np.cos(2.0 * np.pi * x)).sum(axis=1)


def sphere(x: np.ndarray) -> np.ndarray:
    """Sum of squares (minimise); optimum 0 at 0.

    Examples
    --------
    >>> sphere(np.array([[1.0, 2.0]])).tolist()
    [5.0]
    """
    return (x * x).sum(axis=1)


def noisy_sphere(x: np.ndarray, seeds: np.ndarray) -> np.ndarray:
    """Sphere plus noise ``N(0, 0.01^2)`` drawn from each evaluation's seed: a stochastic
    fitness whose value depends only on the row and its seed, not on the worker.

    Examples
    --------
    >>> a = noisy_sphere(np.zeros((2, 3)), np.array([1, 1], dtype=np.uint64))
    >>> bool(a[0] == a[1])
    True
    """
    noise = np.array([np.random.default_rng(int(s)).normal() for s in seeds])
    return sphere(x) + 0.01 * noise


@dataclass(frozen=True)
class Faulty:
    """A fitness that fails on purpose, to test how a run takes failures: ``fitness``
    (a vectorised problem of this module), except that a batch holding a row whose first
    parameter is above ``above`` faults.

    ``fault``: ``"raise"`` raises ``RuntimeError`` (the row then fails alone);
    ``"exit"`` ends the process evaluating it (``os._exit(3)``) and ``"kill"`` sends it
    ``SIGKILL``, as a crash in native code would, but only in another process than
    ``home`` (the one that made it, default: this one), where they raise instead, so a
    serial run is not killed. ``once``: a file; the fault fires only while it does not
    exist, and creates it first (one fault per run, for a retry or a resume).

    Examples
    --------
    >>> f = Faulty(sphere, above=1.0)
    >>> f(np.array([[0.5, 0.0]])).tolist()
    [0.25]
    >>> f(np.array([[2.0, 0.0]]))
    Traceback (most recent call last):
    ...
    RuntimeError: Faulty: x[0] = 2 > 1
    """

    fitness: object
    above: float
    fault: str = "raise"
    once: str | None = None
    home: int = field(default_factory=os.getpid)

    def __call__(self, x: np.ndarray) -> np.ndarray:
        bad = x[:, 0] > self.above
        if bad.any() and self._fires():
            first = float(x[bad, 0][0])
            if self.fault != "raise" and os.getpid() != self.home:
                if self.fault == "exit":
                    os._exit(3)
                os.kill(os.getpid(), signal.SIGKILL)
            raise RuntimeError(f"Faulty: x[0] = {first:g} > {self.above:g}")
        return self.fitness(x)

    def _fires(self) -> bool:
        if self.once is None:
            return True
        try:
            Path(self.once).touch(exist_ok=False)
        except FileExistsError:
            return False
        return True
