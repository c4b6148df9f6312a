"""Slow NumPy oracle of :mod:`growsim.kernels.hormone_light`'s helpers: each module's
far end, and no light for a module lying on the soil."""

from __future__ import annotations

import numpy as np


def module_ends(n, origin, length, R, end):
    end[:n] = origin[:n] + length[:n, None] * R[:n, :, 2]
    return end


def soil_unlit(n, end, length, ground, wall_light, light, leaf_light, demand):
    on = np.flatnonzero(end[:n, 1] <= ground + 1e-9 * (1.0 + length[:n]))
    light[on] = 0.0
    leaf_light[on] = 0.0
    demand[on] = 0.0
    wall_light[on] = 0.0
