"""One place for numba compile flags, so every kernel is cached and compiled alike."""

from __future__ import annotations

import numba

#: Options for every ``@numba.njit`` in growsim. ``cache=True`` writes compiled code next
#: to the module (set ``NUMBA_CACHE_DIR`` if the package directory is read-only).
JIT = {"cache": True, "nogil": True, "fastmath": False}


def njit(*args, **kwargs):
    """``numba.njit`` with growsim's flags; extra keyword arguments override them.

    Examples
    --------
    >>> from growsim.kernels.config import njit
    >>> @njit(cache=False)  # code typed at a prompt has no file to cache next to
    ... def add(a, b):
    ...     return a + b
    >>> add(1, 2)
    3
    """
    opts = {**JIT, **kwargs}
    if args and callable(args[0]):
        return numba.njit(**opts)(args[0])
    return numba.njit(*args, **opts)
