"""Numba kernels: small, typed functions on arrays and scalars, no Python objects.

Every kernel is compiled with :data:`growsim.kernels.config.JIT` options (``cache=True``)
and has a slow NumPy oracle in ``tests/`` that it must match.
"""
