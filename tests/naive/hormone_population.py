"""Oracle of the hormone population kernel (:mod:`growsim.kernels.hormone_population`):
each plant grown on its own, step by step, with :func:`growsim.kernels.hormone.grow_step`
in fresh module arrays, and its totals read plainly."""

from __future__ import annotations

import numpy as np

from growsim.kernels import hormone as K
from growsim.kernels.light import shadow_scratch


def grow_population(genes, c, strength_young, dims, walls, steps, cap, env):
    """Mirror of :func:`growsim.kernels.hormone_population.grow_population`: ``(total,
    modules, stop, module_steps)``, one plant at a time in its own arrays."""
    P = len(genes)
    out = (np.empty(P), np.empty(P, np.int64), np.zeros(P, np.int64), np.zeros(P, np.int64))
    for p in range(P):
        modules = K.new_module_arrays(cap, walls, genes.shape[1])
        n = K.new_plant(modules, c[p])
        stop = K.STOP_NONE
        for _ in range(steps):
            n, code = K.grow_step(n, dims, modules, shadow_scratch(env.resolution),
                                  genes[p : p + 1], c[p : p + 1], strength_young[p : p + 1],
                                  env, np.zeros((0, 3)))  # fmt: skip
            out[3][p] += n
            stop = code if code != K.STOP_NONE else stop
            if code in (K.STOP_NAN, K.STOP_BROKEN):
                break
        out[0][p] = np.nan if stop == K.STOP_NAN else float(np.sum(modules.nutrient[:n]))
        out[1][p], out[2][p] = n, stop
    return out
