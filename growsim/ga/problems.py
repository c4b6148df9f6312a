"""Standard test problems as picklable, vectorised fitnesses (benchmarks, tests, docs).

Each takes decoded parameters ``(n, p)`` and returns ``(n,)``; being module-level they
pickle by reference, so process pools and Dask workers can import them.
"""

from __future__ import annotations

import numpy as np

__all__ = ["noisy_sphere", "onemax", "rastrigin", "sphere"]


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
