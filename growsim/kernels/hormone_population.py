"""The population path of the hormone-module model: whole populations grown in one call,
each plant alone, through :func:`growsim.kernels.hormone.grow_step` (the ``nutrient``
objective's batch, :func:`growsim.models.hormone.population`); the oracle is
``tests/naive/hormone_population.py``.
"""

from __future__ import annotations

import numpy as np

from growsim.kernels.config import njit
from growsim.kernels.hormone import (
    STOP_BROKEN,
    STOP_NAN,
    STOP_NONE,
    STOP_STARVED,
    Modules,
    grow_step,
    new_plant,
    total,
)
from growsim.kernels.light import shadow_scratch

__all__ = ["grow_population"]


@njit
def grow_population(genes, c, strength_young, dims, walls, steps, cap, env):
    """Grow ``P`` plants (genes ``(P, H, 3 + J)``, constants ``c`` ``(P, N_CONSTANTS)``,
    ``strength_young`` ``(P,)``; the settings and the environment ``env``
    (:class:`Surroundings`) shared) for ``steps`` steps each, as
    :func:`growsim.models.hormone.grow` does one at a time, keeping no plant. Returns
    ``(total, modules, stop, module_steps)``, each ``(P,)``: the nutrient held at the end
    (NaN for a plant stopped by a NaN), the module count, the stop code (:data:`STOPS`:
    the last of cap, nan, broken, starved) and the modules alive summed over the steps.

    Examples
    --------
    >>> from growsim.env import Environment
    >>> from growsim.models.hormone import PARAMS, PRESETS, population, resolve_params
    >>> env = Environment.model_validate({"light": {"diffuse": 0.5}})
    >>> row = resolve_params(PARAMS, PRESETS["demo_2d"])
    >>> table = population(np.array([list(row.values())] * 2), list(row), env)
    >>> from growsim.models.hormone import develop
    >>> table.modules.tolist() == [develop(row, env=env).n_segments] * 2
    True
    """
    P = genes.shape[0]
    H = genes.shape[1]
    nutrient = np.empty(cap)
    modules = Modules(
        np.empty(cap, np.int64), np.empty((cap, 3, 3)), np.empty((cap, 3)), np.empty(cap),
        np.empty(cap), nutrient, np.empty(cap), np.empty(cap), np.empty(cap, np.bool_),
        np.empty(cap, np.int64), np.empty((cap, walls, H)), np.zeros((cap, walls)),
        np.zeros(cap), np.zeros(cap),
        np.zeros(cap, np.int64),  # plant: one at a time, row 0 of its own genes
        np.zeros(cap), np.zeros(cap), np.zeros(cap), np.zeros(cap), np.zeros(cap),
        np.zeros(2, np.int64),
    )  # fmt: skip
    scratch = shadow_scratch(env.resolution)
    alone = np.zeros((0, 3))  # no copies: every plant alone
    out_total = np.empty(P)
    out_modules = np.empty(P, np.int64)
    out_stop = np.zeros(P, np.int64)
    out_steps = np.zeros(P, np.int64)
    for p in range(P):
        cp = c[p]
        n = new_plant(modules, cp)
        stop = STOP_NONE
        for _ in range(steps):
            row = (genes[p : p + 1], c[p : p + 1], strength_young[p : p + 1])
            n, code = grow_step(n, dims, modules, scratch, *row, env, alone)
            out_steps[p] += n
            if code != STOP_NONE:
                stop = code
            if code == STOP_NAN or code == STOP_BROKEN or code == STOP_STARVED:
                break
        out_total[p] = np.nan if stop == STOP_NAN else total(nutrient, n)
        out_modules[p] = n
        out_stop[p] = stop
    return out_total, out_modules, out_stop, out_steps
