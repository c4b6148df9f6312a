"""Numba kernels: small, typed functions on arrays and scalars, no Python objects.

Every numba-compiled function of growsim lives here, one module per family, compiled with
:data:`growsim.kernels.config.JIT` options (``cache=True``). A kernel takes at most 10
arguments: state goes in a few typed tuples (``segments = (start, end, radius, offsets)``,
:class:`growsim.kernels.hormone.Modules`, ...), parameters in one tuple or float64 array.
A module's plain public functions validate arrays and call its kernels; callers that build
the arrays themselves from validated objects (``env/``, ``models/``) call the entry
kernels directly. Each module ``m`` has a slow NumPy oracle ``tests/naive/m.py`` that its
kernels must match, its tests calling the entries production calls.
"""
