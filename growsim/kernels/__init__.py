"""Numba kernels: small, typed functions on arrays and scalars, no Python objects.

Every numba-compiled function of growsim lives here, one module per family, compiled by
:func:`njit` (``from growsim.kernels import njit``) with :data:`growsim.kernels.config.JIT`
options (``cache=True``). A kernel takes at most 10 arguments: state goes in a few typed
tuples (``segments = (start, end, radius, offsets)``,
:class:`growsim.kernels.hormone.Modules`, ...), parameters in one tuple or float64 array.
A module's plain public functions validate arrays and call its kernels; callers that build
the arrays themselves from validated objects (``env/``, ``models/``) call the entry
kernels directly. Each module ``m`` has a slow NumPy oracle ``tests/naive/m.py`` that its
kernels must match, its tests calling the entries production calls.
"""

__all__ = ["njit"]

# Lazy exports: ``import growsim.kernels`` loads no numba; a kernel module's
# ``from growsim.kernels import njit`` loads it from :mod:`growsim.kernels.config`.
_LAZY = {"njit": "growsim.kernels.config"}


def __getattr__(name: str):
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'growsim.kernels' has no attribute {name!r}")


def __dir__():
    return sorted([*globals(), *_LAZY])
