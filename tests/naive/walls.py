"""Oracle of the wall kernels (:mod:`growsim.kernels.walls`): each wall's outward
direction from a module's pose, written plainly with NumPy."""

from __future__ import annotations

import numpy as np


def wall_frame(R, walls, dims):
    """Mirror of :func:`growsim.kernels.walls.wall_frame` (returns the array)."""
    if dims == 2:
        return np.stack([R[:, 0], -R[:, 0]])
    a = 2 * np.pi * np.arange(walls) / walls
    return np.cos(a)[:, None] * R[:, 0] + np.sin(a)[:, None] * R[:, 1]
