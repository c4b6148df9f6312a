"""Oracle of the stand kernels (:mod:`growsim.kernels.stand`): an explicit stand's
seedlings written plainly with NumPy, from one seedling copied to every position."""

from __future__ import annotations

import numpy as np

from growsim.kernels import hormone as K


def new_stand(modules, c, xz, ground):
    """Mirror of :func:`growsim.kernels.stand.new_stand` (fills ``modules``; returns N):
    the seedling :func:`growsim.kernels.hormone.new_plant` makes, copied to each row of
    ``xz`` standing on the ground at ``(x, ground, z)``, every copy a root of its own
    plant, its new length, radius and (growsim) leaf area from its row of constants ``c``
    ``(N, C)``."""
    K.new_plant(modules, c[0])
    n = len(xz)
    seed = {f: np.array(getattr(modules, f)[0], copy=True) for f in modules._fields}
    for f in ("R", "nutrient", "chlorophyll", "apex"):
        getattr(modules, f)[:n] = seed[f]
    modules.length[:n] = c[:, K.C_NEWLEN]
    modules.radius[:n] = c[:, K.C_NEWRAD]
    modules.leaf[:n] = np.where(c[:, K.C_PHYSICS] == K.GROWSIM, c[:, K.C_NEW_LEAF], 0.0)
    modules.drawn[:n] = np.maximum(modules.radius[:n], modules.leaf[:n] / (2 * modules.length[:n]))
    modules.plant[:n] = np.arange(n)
    modules.chlorophyll[:n] = 1.0
    modules.apex[:n] = True
    modules.origin[:n] = np.column_stack([xz[:, 0], np.full(n, ground), xz[:, 1]])
    return n
