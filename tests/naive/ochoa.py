"""Oracles of the Ochoa-term kernels (:mod:`growsim.kernels.ochoa`): NumPy and SciPy's
labelling, by the definitions of the kernel module's docstring."""

from __future__ import annotations

import numpy as np
from scipy import ndimage

EIGHT = np.ones((3, 3), dtype=int)


def degree(skel) -> np.ndarray:
    """Skeleton neighbours of every pixel (8-neighbourhood), 0 off the skeleton."""
    s = (np.asarray(skel) != 0).astype(int)
    return (ndimage.convolve(s, EIGHT, mode="constant") - s) * s


def shadow_bins(img, direction=(0.0, -1.0)) -> tuple[int, float]:
    """Distinct one-pixel bins across the light holding a foreground pixel centre, and
    the raster's shadow length."""
    img = np.asarray(img) != 0
    d = np.asarray(direction, dtype=float)
    ux, uy = d / np.hypot(*d)
    S0, S1 = img.shape
    i, j = np.nonzero(img)
    s = -uy * (j + 0.5) + ux * (S0 - i - 0.5)
    s0 = min(0.0, -uy * S1) + min(0.0, ux * S0)
    frame = S1 * abs(uy) + S0 * abs(ux)
    bins = np.clip(np.floor(s - s0).astype(int), 0, int(np.ceil(frame)) + 1)
    return len(np.unique(bins)), float(frame)


def prune(skel, iterations) -> np.ndarray:
    """End pixels (degree <= 1) removed, all at once, ``iterations`` times."""
    s = (np.asarray(skel) != 0).astype(np.uint8)
    for _ in range(iterations):
        ends = (s == 1) & (degree(s) <= 1)
        if not ends.any():
            break
        s[ends] = 0
    return s


def junctions(skel, many=4) -> tuple[int, int]:
    """Branching points (8-connected groups of degree >= 3 pixels touching >= 3 groups of
    other skeleton pixels) and those with >= ``many`` such groups."""
    s = np.asarray(skel) != 0
    J = s & (degree(s) >= 3)
    labels, n = ndimage.label(J, structure=EIGHT)
    points = with_many = 0
    for k in range(1, n + 1):
        cluster = labels == k
        ring = ndimage.binary_dilation(cluster, structure=EIGHT) & s & ~J
        _, branches = ndimage.label(ring, structure=EIGHT)
        if branches >= 3:
            points += 1
            with_many += branches >= many
    return points, int(with_many)
