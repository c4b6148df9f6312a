"""Slow NumPy oracle of :mod:`growsim.kernels.hormone_modules`: each module's radius in
the shadow map (its stem's or its foliage's)."""

from __future__ import annotations

import numpy as np


def drawn_kernel(n, modules):
    """Mirror of :func:`growsim.kernels.hormone.drawn_kernel`: the radius of the union of
    a module's stem and its foliage cylinder, whose side view ``2 r L`` is its leaf area."""
    L = modules.length[:n]
    foliage = np.where(L > 0, modules.leaf[:n] / (2 * np.where(L > 0, L, 1.0)), 0.0)
    modules.drawn[:n] = np.maximum(modules.radius[:n], foliage)
    return modules.drawn
