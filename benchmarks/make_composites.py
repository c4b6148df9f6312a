"""Outdoor test photos: modular-tree trees composited onto procedural skies and grounds.

Issue 41: ``fit-image`` should take the photographs people take (clouds, grey skies,
fields, hedges, hills, snow). The trees are grown and lit as ``benchmarks/make_mtree.py``
grows and lights them (modular-tree, MIT licence; its :data:`~make_mtree.SHAPES`, bark and
leaf colours, the long lens of ``benchmarks/make_photos.py``), but rendered **alone** on
black: each pixel is the mean of ``supersample x supersample`` samples, so the render
gives the tree's premultiplied linear colour ``P`` (the mean of the samples' linear
colour, 0 off the tree) and its coverage ``a`` (the share of samples on the tree) exactly,
no alpha to solve for. The photo is the composite in linear light,
``P + (1 - a) * background`` (what the sensor sums when the background is smooth over a
pixel), and the true silhouette ``<name>_mask.png`` is the pixels the tree covers at
least half (``a >= 0.5``; black tree on white, 1-bit PNG), as make_mtree's.

The backgrounds are made here with numpy/scipy only (nothing downloaded; fractal noise
from a power-law spectrum, sampled through a perspective for clouds and grounds):

* skies (:data:`SKIES`): ``plain``, ``gradient`` (a darker zenith), ``haze``,
  ``overcast`` (grey, mottled), ``sunset`` (warm horizon, a glow, streaks of cloud),
  ``cumulus`` (thresholded fractal clouds, lit from above, flatter toward the horizon),
  ``stormy`` (dark heavy clouds, pale gaps);
* grounds (:data:`GROUNDS`): ``grass``, ``crop_rows`` (rows receding to a vanishing
  point), ``soil`` (ploughed furrows), ``snow``, ``road`` (a road receding beside the
  tree), ``slope`` (grass, the horizon tilted 3-8 degrees), ``hills`` (hazy hills on
  the horizon);
* horizon clutter (:data:`CLUTTER`): ``hedge``, ``treeline`` (a line of distant trees
  across the whole width), ``fence``, ``buildings``, or none;
* hard cases (:data:`HARD`): ``second_tree`` (another tree, a little farther, touching
  or near the crown; the mask is the main tree only) and ``wood`` (a dense wood behind the
  tree, its top reaching well into the crown).

Leafy trees (green, dark, yellow-green, autumn) and bare ones; the light follows the sky
(sun and fill light; overcast and stormy skies light the tree softly, a sunset warmly);
sensor noise and JPEG (quality 80-90). Sizes 384-640 px on the long side, landscape,
square or portrait.

The first 24 pictures are a fixed plan (:data:`PLAN`): 12 scenes (a sky, a ground,
clutter, a hard case), each drawn twice with different trees (one bare, one leafy), one
of each pair ``held_out`` (seeded), the other ``discovery``; so both splits hold every
kind. Pictures beyond 24 (``--n``) draw their scene's kinds at random. ``index.json``
lists each picture's kinds, leafiness, size, whether it has a second tree or a treeline,
its split and everything it was made from.

    python benchmarks/make_composites.py --out tests/data/composites \\
        --sheet runs/composites_sheet.png          # the committed set (24)
    python benchmarks/make_composites.py --n 96 --out runs/composites   # a larger set

Deterministic for a seed (``--seed``).
"""

from __future__ import annotations

import argparse
import io
import json
import math
import sys
import time
from pathlib import Path

import numpy as np
from scipy import ndimage

sys.path.insert(0, str(Path(__file__).resolve().parent))
from make_mtree import BARKS, LEAVES, SHAPES, _jitter, tree_of
from make_photos import FOV, SUPERSAMPLE, _camera

SKIES = ("plain", "gradient", "haze", "overcast", "sunset", "cumulus", "stormy")
GROUNDS = ("grass", "crop_rows", "soil", "snow", "road", "slope", "hills")
CLUTTER = ("none", "hedge", "treeline", "fence", "buildings")
HARD = ("none", "second_tree", "wood")

#: The committed set's 12 scenes (sky, ground, clutter, hard case), each drawn twice.
PLAN = (
    ("plain", "grass", "none", "none"),
    ("gradient", "crop_rows", "hedge", "none"),
    ("haze", "soil", "treeline", "none"),
    ("overcast", "grass", "hedge", "none"),
    ("sunset", "hills", "none", "none"),
    ("cumulus", "grass", "fence", "none"),
    ("stormy", "crop_rows", "treeline", "none"),
    ("gradient", "snow", "hedge", "none"),
    ("overcast", "snow", "none", "none"),
    ("cumulus", "road", "buildings", "none"),
    ("gradient", "slope", "none", "second_tree"),
    ("cumulus", "hills", "none", "wood"),
)

LEAF_COLOURS = {**LEAVES, "autumn_red": (0.66, 0.26, 0.12)}
#: Sizes (long side) and aspect ratios (width / height).
LONG_SIDES = (384, 448, 512, 576, 640)
ASPECTS = (4 / 3, 3 / 2, 1.0, 3 / 4)


# ----------------------------------------------------------------------------- colour


def to_lin(v):
    """sRGB in [0, 1] to linear light (IEC 61966-2-1)."""
    v = np.clip(np.asarray(v, np.float64), 0, 1)
    return np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4)


def to_srgb(v):
    """Linear light to sRGB in [0, 1]."""
    v = np.clip(np.asarray(v, np.float64), 0, 1)
    return np.where(v <= 0.0031308, 12.92 * v, 1.055 * v ** (1 / 2.4) - 0.055)


def _mix(a, b, t):
    """``a`` to ``b`` (sRGB colours or images) by ``t``, in linear light, as sRGB."""
    t = np.asarray(t, np.float64)
    if t.ndim == 2:
        t = t[..., None]
    return to_srgb(to_lin(a) * (1 - t) + to_lin(b) * t)


def _jit(rng, colour, share=0.06):
    return np.clip(np.asarray(colour) * rng.uniform(1 - share, 1 + share, 3), 0, 1)


# ------------------------------------------------------------------------------ noise


def fractal(shape, rng, beta=2.2, stretch=(1.0, 1.0)):
    """Fractal noise of ``shape`` (zero mean, unit sigma), power spectrum ~ f^-beta
    (periodic). ``stretch`` (rows, columns) > 1 makes features longer along that axis."""
    h, w = shape
    fy = np.fft.fftfreq(h)[:, None] * stretch[0]
    fx = np.fft.rfftfreq(w)[None, :] * stretch[1]
    f = np.hypot(fx, fy)
    f[0, 0] = np.inf
    amp = np.maximum(f, 1.0 / max(h, w)) ** (-beta / 2)
    amp[0, 0] = 0.0
    spec = (rng.normal(size=f.shape) + 1j * rng.normal(size=f.shape)) * amp
    n = np.fft.irfft2(spec, s=(h, w))
    return (n - n.mean()) / (n.std() + 1e-12)


def fractal1d(n, rng, beta=2.0):
    """1-D fractal noise of length ``n`` (zero mean, unit sigma)."""
    f = np.fft.rfftfreq(n)
    amp = np.zeros_like(f)
    amp[1:] = f[1:] ** (-beta / 2)
    spec = (rng.normal(size=f.shape) + 1j * rng.normal(size=f.shape)) * amp
    x = np.fft.irfft(spec, n=n)
    return (x - x.mean()) / (x.std() + 1e-12)


def _sample(field, rows, cols):
    """``field`` (periodic) at fractional ``rows``, ``cols`` (bilinear)."""
    return ndimage.map_coordinates(field, [rows, cols], order=1, mode="grid-wrap")


def _smoothstep(x):
    x = np.clip(x, 0, 1)
    return x * x * (3 - 2 * x)


# ------------------------------------------------------------------------------- sky


def make_sky(kind, h, w, horizon, rng):
    """The sky, ``(h, w, 3)`` sRGB; ``horizon``: its mean row (the sky's bottom)."""
    r = np.arange(h, dtype=np.float64)[:, None] * np.ones((1, w))
    c = np.ones((h, 1)) * np.arange(w, dtype=np.float64)[None, :]
    t = np.clip(r / max(horizon, 1.0), 0, 1.2)  # 0 top, 1 horizon
    info = {}
    if kind == "plain":
        col = [(0.74, 0.83, 0.95), (0.86, 0.90, 0.95), (0.93, 0.94, 0.95), (0.64, 0.77, 0.93)]
        sky = np.broadcast_to(_jit(rng, col[rng.integers(len(col))], 0.03), (h, w, 3)).copy()
    elif kind == "gradient":
        top = _jit(rng, (0.36, 0.55, 0.86), 0.1)
        bottom = _jit(rng, (0.80, 0.87, 0.95), 0.03)
        sky = _mix(top, bottom, np.clip(t, 0, 1) ** rng.uniform(0.8, 1.6))
    elif kind == "haze":
        top = _jit(rng, (0.78, 0.83, 0.90), 0.03)
        bottom = _jit(rng, (0.93, 0.93, 0.91), 0.02)
        sky = _mix(top, bottom, np.clip(t, 0, 1) ** 0.7)
        sky = sky + 0.012 * fractal((h, w), rng, 3.0)[..., None]
    elif kind == "overcast":
        g = rng.uniform(0.62, 0.84)
        top = np.array([g, g + 0.01, g + 0.03]) * rng.uniform(0.88, 0.97)
        bottom = np.array([g, g + 0.005, g + 0.015]) * rng.uniform(1.0, 1.08)
        sky = _mix(top, np.clip(bottom, 0, 1), np.clip(t, 0, 1))
        mottle = fractal((h, w), rng, 2.6, stretch=(1.0, 2.5))
        sky = sky * (1 + rng.uniform(0.025, 0.05) * mottle)[..., None]
    elif kind == "sunset":
        top = _jit(rng, (0.38, 0.42, 0.64), 0.08)
        mid = _jit(rng, (0.86, 0.56, 0.44), 0.06)
        bottom = _jit(rng, (0.99, 0.80, 0.48), 0.03)
        tt = np.clip(t, 0, 1)
        sky = np.where(
            (tt < 0.55)[..., None], _mix(top, mid, tt / 0.55), _mix(mid, bottom, (tt - 0.55) / 0.45)
        )
        sx, sy = rng.uniform(0.1, 0.9) * w, horizon * rng.uniform(0.75, 0.95)
        glow = np.exp(-(((c - sx) / (0.25 * w)) ** 2 + ((r - sy) / (0.25 * h)) ** 2))
        sky = _mix(sky, (1.0, 0.93, 0.75), 0.6 * glow)
        d = _perspective_clouds(h, w, horizon, rng, beta=2.4, stretch=(1.0, 6.0))
        cover = _smoothstep((d - 1.0) / 0.8) * 0.8
        streak = _jit(rng, (0.62, 0.40, 0.44), 0.08)
        sky = _mix(sky, streak, cover)
        info["glow_column"] = round(float(sx), 1)
    elif kind in ("cumulus", "stormy"):
        stormy = kind == "stormy"
        if stormy:
            top, bottom = _jit(rng, (0.50, 0.53, 0.58), 0.05), _jit(rng, (0.72, 0.73, 0.74), 0.04)
        else:
            top, bottom = _jit(rng, (0.40, 0.60, 0.88), 0.08), _jit(rng, (0.78, 0.86, 0.95), 0.03)
        sky = _mix(top, bottom, np.clip(t, 0, 1) ** 1.2)
        d = _perspective_clouds(
            h, w, horizon, rng, beta=rng.uniform(2.3, 2.8), stretch=(1.0, rng.uniform(1.3, 2.2))
        )
        share = rng.uniform(0.55, 0.85) if stormy else rng.uniform(0.25, 0.5)
        th = np.quantile(d, 1 - share)
        cover = _smoothstep((d - th) / rng.uniform(0.4, 0.9))
        # lit from above: the more cloud just above a pixel, the darker its underside
        L = max(4, int(0.05 * h))
        above = ndimage.gaussian_filter(cover, (L / 2, L / 3), mode="nearest")
        above = np.concatenate([np.repeat(above[:1], L // 2, axis=0), above[: -(L // 2)]])
        dens = _smoothstep((d - th) / 2.5)
        shade = np.clip(0.6 * above + 0.5 * dens, 0, 1)
        if stormy:
            lit, dark = _jit(rng, (0.60, 0.62, 0.66), 0.05), _jit(rng, (0.22, 0.24, 0.29), 0.1)
        else:
            lit, dark = _jit(rng, (0.98, 0.98, 0.97), 0.01), _jit(rng, (0.64, 0.67, 0.74), 0.05)
        cloud = _mix(lit, dark, shade)
        sky = _mix(sky, cloud, cover)
        if stormy:
            sky = sky * (1 + 0.04 * fractal((h, w), rng, 2.8))[..., None]
        info["cloud_share"] = round(float(share), 3)
    else:
        raise ValueError(kind)
    return np.clip(sky, 0, 1), info


def _perspective_clouds(h, w, horizon, rng, beta=2.5, stretch=(1.0, 1.5)):
    """Cloud density seen in perspective: large overhead, smaller and flatter toward the
    horizon (a fractal sampled through rows compressed toward it)."""
    n = 512
    field = fractal((n, 2 * n), rng, beta, stretch)
    r = np.arange(h, dtype=np.float64)[:, None]
    c = np.arange(w, dtype=np.float64)[None, :]
    t = np.clip(r / max(horizon, 1.0), 0, 1)
    zoom = 1.0 + 2.0 * t**2  # features shrink toward the horizon
    rows = (n * 0.8) * (t + 0.9 * t**3) / 1.9 * (max(h, w) / 512)
    cols = (c - w / 2) * zoom * (n / 512) * 0.8 + n
    return _sample(field, rows + 0 * cols, cols + 0 * rows)


# ---------------------------------------------------------------------------- ground


def horizon_profile(kind, w, h0, rng, trunk_col):
    """The horizon's row at each column: level, tilted (``slope``) or hills."""
    x = np.arange(w, dtype=np.float64)
    info = {}
    if kind == "slope":
        ang = rng.uniform(3, 8) * rng.choice([-1, 1])
        info["slope_degrees"] = round(float(ang), 2)
        return h0 + math.tan(math.radians(ang)) * (x - trunk_col), info
    return np.full(w, float(h0)), info


def make_ground(kind, h, w, hz, rng, sky, f_bg, trunk=None):
    """Paint the ground below ``hz`` (row per column) onto ``sky`` (sRGB, modified);
    returns ``(image, info)``. Ground coordinates: camera height 1, ``X`` lateral, ``Z``
    depth (``f_bg`` px focal length); textures fade with distance, hazed to the sky's
    horizon colour."""
    r = np.arange(h, dtype=np.float64)[:, None]
    c = np.arange(w, dtype=np.float64)[None, :]
    hzr = hz[None, :]
    d = r - hzr  # rows below the horizon
    below = np.clip(d + 0.5, 0, 1)  # anti-aliased ground coverage
    dd = np.maximum(d, 0.5)
    X = (c - w / 2) / dd
    Z = f_bg / dd
    near = np.clip((d - 1.0) / 25.0, 0, 1)  # texture contrast (none at the horizon)
    # the haze's colour: the sky just above the horizon, smoothed along it (no streaks
    # of cloud running down into the ground)
    rows_above = np.clip(np.round(hz).astype(int)[None, :] - np.arange(2, 12)[:, None], 0, h - 1)
    haze_col = sky[rows_above, np.arange(w)[None, :]].mean(axis=0)
    haze_col = ndimage.gaussian_filter1d(haze_col, w / 6, axis=0, mode="nearest")[None]
    info = {}
    tex = fractal((256, 256), rng, 1.6)
    patches = fractal((256, 256), rng, 2.8)

    def texture(scale, field=tex):
        # the texture fades where a row steps over more than half a noise cell (aliasing)
        step = f_bg / dd**2 / scale * (256 / 256)
        aa = np.clip(1.0 - (step - 0.3) / 0.7, 0, 1)
        return _sample(field, Z / scale, X / scale + 0 * Z) * aa

    grassy = kind in ("grass", "slope", "hills", "road")
    if grassy or kind == "crop_rows":
        base = _jit(
            rng,
            [(0.34, 0.48, 0.22), (0.40, 0.52, 0.25), (0.30, 0.42, 0.20), (0.46, 0.52, 0.30)][
                rng.integers(4)
            ],
            0.05,
        )
        g = base * (1 + 0.10 * texture(8.0, patches)[..., None] * (0.3 + 0.7 * near[..., None]))
        g = g * (1 + 0.07 * texture(0.35)[..., None] * near[..., None])
    if kind == "crop_rows":
        crop = rng.integers(2)
        soil = _jit(rng, (0.42, 0.33, 0.24), 0.06)
        if crop == 0:
            rowcol = _jit(rng, (0.30, 0.46, 0.18), 0.06)
        else:
            rowcol = _jit(rng, (0.78, 0.68, 0.36), 0.05)
            soil = _jit(rng, (0.62, 0.52, 0.30), 0.05)
        spacing = rng.uniform(0.25, 0.5)
        x0 = rng.uniform(0, spacing)
        phase = np.sin(2 * np.pi * (X - x0) / spacing)
        period_px = spacing * dd
        fade = np.clip((period_px - 2.0) / 4.0, 0, 1)
        s = 0.5 + 0.5 * np.tanh(2.5 * phase) * fade
        g = _mix(soil, rowcol, s * 0.85 + 0.15 * (1 - fade))
        g = g * (1 + 0.06 * texture(0.3)[..., None] * near[..., None])
        info["crop"] = ["green", "wheat"][crop]
        info["row_spacing"] = round(float(spacing), 3)
    elif kind == "soil":
        base = _jit(rng, (0.45, 0.36, 0.27), 0.08)
        spacing = rng.uniform(0.3, 0.6)
        furrow = np.sin(2 * np.pi * Z / spacing)
        fade = np.clip((spacing * dd**2 / f_bg - 2.0) / 4.0, 0, 1)  # no aliasing
        g = base * (1 + 0.08 * furrow[..., None] * fade[..., None] * near[..., None])
        g = g * (1 + 0.10 * texture(0.25)[..., None] * near[..., None])
        g = g * (1 + 0.06 * texture(6.0, patches)[..., None])
    elif kind == "snow":
        base = _jit(rng, (0.91, 0.93, 0.97), 0.02)
        g = base * (1 + 0.025 * texture(3.0, patches)[..., None])
        g = g * (1 + 0.015 * texture(0.3)[..., None] * near[..., None])
        g = _mix(g, (0.72, 0.78, 0.90), 0.15 * np.clip(texture(5.0, patches), 0, 2)[..., None] / 2)
    elif grassy:
        pass
    else:
        raise ValueError(kind)
    if kind == "road":
        side = rng.choice([-1, 1])
        xt = 0.0 if trunk is None else (trunk[1] - w / 2) / max(trunk[0] - hz[int(trunk[1])], 1)
        x_road = xt + side * rng.uniform(2.5, 4.0)
        half = rng.uniform(1.2, 1.8)
        asphalt = _jit(rng, (0.40, 0.40, 0.42), 0.05)
        on = np.clip((half - np.abs(X - x_road)) * dd + 0.5, 0, 1)
        road = asphalt * (1 + 0.05 * texture(0.2)[..., None] * near[..., None])
        dash = (
            np.clip((0.06 - np.abs(X - x_road)) * dd + 0.5, 0, 1)
            * (np.sin(2 * np.pi * Z / 3.0) > 0)
            * np.clip((3.0 * dd**2 / f_bg - 3.0) / 4.0, 0, 1)
        )
        road = _mix(road, (0.92, 0.90, 0.84), dash)
        g = _mix(g, road, on)
        info["road_x"] = round(float(x_road), 2)
    # distance haze toward the horizon colour
    haze = np.exp(-d.clip(0) / rng.uniform(6, 14)) * 0.7
    g = _mix(np.clip(g, 0, 1), haze_col, haze)
    if trunk is not None and kind != "snow":
        g = _shadow(g, r, c, trunk, rng)
    elif trunk is not None:
        g = _shadow(g, r, c, trunk, rng, colour=(0.55, 0.62, 0.80))
    img = _mix(sky, g, below)
    return np.clip(img, 0, 1), info


def _shadow(g, r, c, trunk, rng, colour=None):
    """A soft shadow on the ground around the trunk's foot."""
    row, col, width = trunk
    sx = col + rng.uniform(-0.3, 0.3) * width
    e = ((c - sx) / (0.45 * width)) ** 2 + ((r - row - 1) / max(2.0, 0.02 * width)) ** 2
    s = rng.uniform(0.2, 0.4) * np.exp(-e)
    if colour is None:
        return g * (1 - s)[..., None]
    return _mix(g, np.asarray(colour) * 0.8, s)


def make_hills(img, hz, h0, rng, sky_horizon):
    """Hazy hills rising above the level horizon ``h0``; the new horizon (row per
    column)."""
    h, w, _ = img.shape
    r = np.arange(h, dtype=np.float64)[:, None]
    top = hz.copy()
    for layer in range(2):
        amp = rng.uniform(0.04, 0.10) * h * (1.0 if layer == 0 else 0.6)
        prof = fractal1d(w * 2, rng, rng.uniform(2.5, 3.5))[:w]
        prof = (prof - prof.min()) / (np.ptp(prof) + 1e-9)
        rows = h0 - amp * (0.25 + 0.75 * prof)
        colour = _mix(_jit(rng, (0.30, 0.42, 0.30), 0.08), sky_horizon, 0.55 - 0.25 * layer)
        cov = np.clip(r - rows[None, :] + 0.5, 0, 1) * (r < h0 + 1)
        shade = 1 + 0.05 * fractal((h, w), rng, 2.2)
        img = _mix(img, np.clip(colour * shade[..., None], 0, 1), cov)
        top = np.minimum(top, rows)
    return img, top


# --------------------------------------------------------------------------- clutter


def _band(img, bottom, topline, colour, rng, texture=0.08, haze_to=None, haze=0.0):
    """Paint a band between ``topline`` (row per column, anti-aliased) and ``bottom``."""
    h, w, _ = img.shape
    r = np.arange(h, dtype=np.float64)[:, None]
    cov = np.clip(r - topline[None, :] + 0.5, 0, 1) * np.clip(bottom[None, :] - r + 0.5, 0, 1)
    leafy = fractal((h, w), rng, 1.2)
    body = np.asarray(colour) * (1 + texture * leafy)[..., None]
    body = body * (0.85 + 0.15 * np.clip((r - topline[None, :]) / 6.0, 0, 1))[..., None] ** -0.3
    if haze_to is not None and haze > 0:
        body = _mix(np.clip(body, 0, 1), haze_to, haze)
    return _mix(img, np.clip(body, 0, 1), cov), cov


def _crowns(w, rng, mean_h, width_range, shapes=(0.5, 1.0, 1.6)):
    """A line of tree crowns: the height above the base at each column."""
    x = np.arange(w, dtype=np.float64)
    prof = np.zeros(w)
    pos = -width_range[1]
    while pos < w + width_range[1]:
        cw = rng.uniform(*width_range)
        ch = mean_h * rng.uniform(0.6, 1.35)
        u = (x - pos) / (cw / 2)
        shape = rng.choice(shapes)  # round, pointed or tall crowns
        prof = np.maximum(prof, ch * np.clip(1 - np.abs(u) ** (2 / shape), 0, 1) ** (0.5 * shape))
        pos += cw * rng.uniform(0.3, 0.7)
    slow = fractal1d(w * 2, rng, 2.0)[:w]
    jag = fractal1d(w * 2, rng, 0.8)[:w]
    prof = prof + 0.15 * mean_h * slow + 0.07 * mean_h * jag + rng.normal(0, 0.6, w)
    return np.maximum(prof, 0.25 * mean_h)


def add_clutter(kind, img, hz, base_row, rng, sky_horizon):
    """Horizon clutter: a hedge, a line of distant trees, a fence or low buildings;
    drawn between the horizon and the tree's foot (behind the tree)."""
    h, w, _ = img.shape
    x = np.arange(w, dtype=np.float64)
    gap = np.maximum(base_row - hz, 2.0)
    info = {}
    if kind == "none":
        return img, info
    if kind == "hedge":
        bottom = hz + gap * rng.uniform(0.15, 0.5)
        height = h * rng.uniform(0.02, 0.045)
        top = bottom - (
            gap * rng.uniform(0.15, 0.5) + height * (1 + 0.25 * fractal1d(w * 2, rng, 1.8)[:w])
        )
        top = top - 0.12 * height * np.abs(fractal1d(w * 2, rng, 0.6)[:w])
        colour = _jit(
            rng, [(0.16, 0.25, 0.12), (0.22, 0.30, 0.15), (0.13, 0.20, 0.11)][rng.integers(3)], 0.08
        )
        img, _ = _band(img, bottom, top, colour, rng, 0.18, sky_horizon, rng.uniform(0.0, 0.15))
        info["top_row"] = round(float(top.mean()), 1)
    elif kind == "treeline":
        bottom = hz + gap * rng.uniform(0.0, 0.15)
        height = h * rng.uniform(0.04, 0.09)
        top = bottom - _crowns(w, rng, height, (0.015 * w, 0.06 * w))
        colour = _jit(rng, (0.17, 0.24, 0.16), 0.1)
        img, _ = _band(img, bottom, top, colour, rng, 0.2, sky_horizon, rng.uniform(0.1, 0.3))
        info["top_row"] = round(float(top.mean()), 1)
    elif kind == "fence":
        bottom_row = hz + gap * rng.uniform(0.3, 0.6)
        height = max(6.0, (bottom_row.mean() - hz.mean()) * rng.uniform(1.0, 1.8))
        top = bottom_row - height
        spacing = rng.uniform(0.04, 0.08) * w
        wood = _jit(rng, (0.46, 0.40, 0.33), 0.08)
        pw = rng.uniform(1.5, 3.0)
        r = np.arange(h, dtype=np.float64)[:, None]
        phase = (x - rng.uniform(0, spacing)) % spacing
        post = np.clip(pw / 2 + 0.5 - np.abs(phase - spacing / 2), 0, 1)[None, :]
        vert = np.clip(r - top[None, :] + 0.5, 0, 1) * np.clip(bottom_row[None, :] - r + 0.5, 0, 1)
        cov = post * vert
        for k in (0.15, 0.5):
            rail = top + k * height
            cov = np.maximum(cov, np.clip(1.0 - np.abs(r - rail[None, :]), 0, 1) * 0.9)
        img = _mix(img, wood, cov)
        info["post_spacing"] = round(float(spacing), 1)
    elif kind == "buildings":
        n = rng.integers(2, 5)
        for _ in range(n):
            bw = rng.uniform(0.06, 0.2) * w
            bx = rng.uniform(-0.05, 1.0) * w
            bh = rng.uniform(0.03, 0.07) * h
            col = int(np.clip(bx + bw / 2, 0, w - 1))
            base = hz[col] + gap[col] * rng.uniform(0.0, 0.2)
            wall = _jit(
                rng,
                [(0.88, 0.86, 0.80), (0.62, 0.34, 0.26), (0.70, 0.70, 0.68), (0.84, 0.78, 0.62)][
                    rng.integers(4)
                ],
                0.05,
            )
            roof = _jit(rng, [(0.45, 0.22, 0.18), (0.30, 0.30, 0.33)][rng.integers(2)], 0.08)
            r = np.arange(h, dtype=np.float64)[:, None]
            inx = np.clip(np.minimum(x - bx, bx + bw - x) + 0.5, 0, 1)[None, :]
            wall_cov = inx * np.clip(r - (base - bh) + 0.5, 0, 1) * np.clip(base - r + 0.5, 0, 1)
            rh = bh * rng.uniform(0.3, 0.6)
            ridge = base - bh - rh * np.clip(1 - np.abs(x - bx - bw / 2) / (bw / 2 + 2), 0, 1)
            roof_cov = (
                np.clip(np.minimum(x - bx + 2, bx + bw + 2 - x) + 0.5, 0, 1)[None, :]
                * np.clip(r - ridge[None, :] + 0.5, 0, 1)
                * np.clip(base - bh - r + 0.5, 0, 1)
            )
            img = _mix(img, _mix(wall, sky_horizon, 0.2), wall_cov)
            img = _mix(img, _mix(roof, sky_horizon, 0.2), roof_cov)
            # windows
            nwin = max(1, int(bw / 14))
            for k in range(nwin):
                wx = bx + (k + 0.5) * bw / nwin
                wy = base - bh * 0.6
                win = np.clip(2.0 - np.abs(x - wx) + 0.5, 0, 1)[None, :] * np.clip(
                    2.0 - np.abs(r - wy) + 0.5, 0, 1
                )
                img = _mix(img, (0.20, 0.22, 0.26), win * 0.9)
        info["buildings"] = int(n)
    else:
        raise ValueError(kind)
    return np.clip(img, 0, 1), info


def add_wood(img, hz, base_row, crown_top, rng, sky_horizon):
    """A dense wood behind the tree: its top reaching 35-70 % up from the horizon to the
    crown's top."""
    w = img.shape[1]
    bottom = hz + np.maximum(base_row - hz, 2) * rng.uniform(0.05, 0.3)
    height = (hz.mean() - crown_top) * rng.uniform(0.35, 0.7)
    top = bottom - _crowns(w, rng, height, (0.04 * w, 0.12 * w), (0.5, 0.8, 1.0))
    colour = _jit(rng, (0.17, 0.25, 0.14), 0.1)
    img, _ = _band(img, bottom, top, colour, rng, 0.22, sky_horizon, rng.uniform(0.05, 0.2))
    return img, {"top_row": round(float(top.mean()), 1)}


# ------------------------------------------------------------------------------ tree


def tree_spec(rng, leafy: bool, sky: str, ground: str) -> dict:
    """A random modular-tree tree as make_mtree describes one (its keys), with the light."""
    shapes = list(SHAPES)
    if leafy and ground == "snow":
        shape = "conical"  # a leafy tree in snow: an evergreen
    else:
        shape = shapes[rng.integers(len(shapes))]
    s = SHAPES[shape]
    bark = list(BARKS)[rng.integers(len(BARKS))]
    if ground == "snow" and bark in ("pale", "pale_grey"):
        bark = "brown"
    leaf = list(LEAF_COLOURS)[rng.choice(len(LEAF_COLOURS), p=[0.3, 0.25, 0.15, 0.15, 0.15])]
    if shape == "conical":
        leaf = "dark_green"
    soft = sky in ("overcast", "stormy", "haze")
    return {
        "shape": shape,
        "leafy": bool(leafy),
        "trunk": _jitter(s["trunk"], rng, 0.15),
        "branches": [_jitter(b, rng, 0.2) for b in s["branches"]],
        "seeds": [int(x) for x in rng.integers(1, 100000, 1 + len(s["branches"]))],
        "leaf_preset": s["leaf"],
        "leaf_size": s["leaf_size"],
        "leaf_share": s["leaf_share"],
        "leaf_count": s["leaf_count"],
        "leaf_seed": int(rng.integers(1, 100000)),
        "yaw": round(float(rng.uniform(0, 360)), 1),
        "bark_name": bark,
        "bark": list(BARKS[bark]),
        "leaf_name": leaf,
        "leaf": list(LEAF_COLOURS[leaf]),
        "sun_azimuth": round(float(rng.uniform(-70, 70)), 1),
        "sun_elevation": round(
            float(rng.uniform(8, 20) if sky == "sunset" else rng.uniform(25, 60)), 1
        ),
        "sun": 0.35 if soft else 0.85,
        "fill": 0.55 if soft else 0.3,
        "sun_colour": [1.0, 0.78, 0.58] if sky == "sunset" else [1.0, 1.0, 1.0],
        "eye": round(float(rng.uniform(0.08, 0.22)), 3),
    }


def render_tree(spec: dict, size: int, supersample: int = SUPERSAMPLE):
    """The tree alone, ``size x size`` px: ``(P, a, horizon_row)``: its premultiplied
    linear colour (mean of the samples' linear colour, black off the tree), its coverage
    (share of samples on it), and the row where the ground's horizon crosses it (the
    camera's height on the tree)."""
    import pyvista as pv
    from vtkmodules.vtkCommonCore import vtkObject

    bark, leaves, colours = tree_of(spec)
    big = int(size) * int(supersample)
    bounds = np.array(bark.bounds if leaves is None else bark.merge(leaves).bounds)
    height = float(bounds[3])
    bounds[2] = 0.0
    shown = vtkObject.GetGlobalWarningDisplay()
    vtkObject.GlobalWarningDisplayOff()
    try:
        pl = pv.Plotter(off_screen=True, window_size=(big, big), lighting="none")
        pl.disable_anti_aliasing()
        pl.set_background("black")
        az, el = math.radians(spec["sun_azimuth"]), math.radians(spec["sun_elevation"])
        sun = np.array([math.sin(az) * math.cos(el), math.sin(el), math.cos(az) * math.cos(el)])
        pl.add_light(
            pv.Light(
                position=tuple(sun * 1000 * height),
                focal_point=(0, 0, 0),
                color=tuple(spec["sun_colour"]),
                intensity=spec["sun"],
                light_type="scene light",
            )
        )
        pl.add_light(
            pv.Light(
                position=(0, 0.3 * height, 1000 * height),
                focal_point=(0, 0, 0),
                color="white",
                intensity=spec["fill"],
                light_type="scene light",
            )
        )
        pl.add_mesh(
            bark, color=spec["bark"], ambient=0.3, diffuse=0.75, specular=0.1, smooth_shading=True
        )
        if leaves is not None:
            pl.add_mesh(leaves, scalars=colours, rgb=True, ambient=0.3, diffuse=0.75, specular=0.05)
        dist = _camera(pl, bounds.tolist(), big, spec["eye"], FOV)
        colour = np.asarray(pl.screenshot(return_img=True))[..., :3].astype(np.float64)
        pl.close()
        pl = pv.Plotter(off_screen=True, window_size=(big, big))
        pl.disable_anti_aliasing()
        pl.set_background("white")
        pl.add_mesh(bark, color="black", lighting=False)
        if leaves is not None:
            pl.add_mesh(leaves, color="black", lighting=False)
        _camera(pl, bounds.tolist(), big, spec["eye"], FOV)
        cover = np.asarray(pl.screenshot(return_img=True))[..., 0] < 128
        pl.close()
    finally:
        vtkObject.SetGlobalWarningDisplay(shown)
    f = int(supersample)
    lin = to_lin(colour / 255.0) * cover[..., None]
    P = lin.reshape(size, f, size, f, 3).mean(axis=(1, 3))
    a = cover.reshape(size, f, size, f).mean(axis=(1, 3))
    # the horizon: the image of the camera's height (angle 0); rows grow downward
    eye, cy = spec["eye"] * height, 0.46 * height
    pitch = math.atan2(cy - eye, dist)
    horizon = size / 2 + (size / 2) * math.tan(pitch) / math.tan(math.radians(FOV / 2))
    return P, a, float(horizon)


# ----------------------------------------------------------------------------- scene


def scene_specs(n: int = 24, seed: int = 20261205) -> list[dict]:
    """``n`` composite descriptions: the :data:`PLAN` first (pairs, one bare one leafy,
    one of each pair held out), then random scenes (pairs too)."""
    rng = np.random.default_rng(seed)
    specs = []
    for i in range(n):
        k = i // 2
        if i % 2 == 0:
            if k < len(PLAN):
                sky, ground, clutter, hard = PLAN[k]
            else:
                sky = SKIES[rng.integers(len(SKIES))]
                ground = GROUNDS[rng.integers(len(GROUNDS))]
                clutter = CLUTTER[rng.choice(len(CLUTTER), p=[0.3, 0.2, 0.2, 0.15, 0.15])]
                hard = HARD[rng.choice(len(HARD), p=[0.7, 0.15, 0.15])]
            held = [bool(h) for h in rng.permutation([0, 1])]
            bare_first = bool(rng.integers(2))
        leafy = (i % 2 == 0) != bare_first
        size = int(LONG_SIDES[rng.integers(len(LONG_SIDES))])
        aspect = float(ASPECTS[rng.choice(len(ASPECTS), p=[0.35, 0.25, 0.2, 0.2])])
        if hard == "second_tree":
            aspect = 3 / 2
        if aspect >= 1:
            w, h = size, int(np.rint(size / aspect))
        else:
            w, h = int(np.rint(size * aspect)), size
        tree = tree_spec(rng, leafy, sky, ground)
        second = None
        if hard == "second_tree":
            second = tree_spec(rng, bool(rng.integers(2)) if leafy else False, sky, ground)
            second.update(
                {
                    k: tree[k]
                    for k in ("sun_azimuth", "sun_elevation", "sun", "fill", "sun_colour", "eye")
                }
            )
        specs.append(
            {
                "name": f"c{i:02d}_{sky}_{ground}"
                + (f"_{clutter}" if clutter != "none" else "")
                + (f"_{hard}" if hard != "none" else "")
                + ("_leafy" if leafy else "_bare"),
                "split": "held_out" if held[i % 2] else "discovery",
                "sky": sky,
                "ground": ground,
                "clutter": clutter,
                "hard": hard,
                "leafy": bool(leafy),
                "width": w,
                "height": h,
                "second_tree": hard == "second_tree",
                "treeline": clutter in ("treeline", "hedge") or hard == "wood",
                "tree": tree,
                "second": second,
                "tree_height": round(float(rng.uniform(0.5, 0.85)), 3),
                "base_at": round(float(rng.uniform(0.86, 0.95)), 3),
                "centre_at": round(float(rng.uniform(0.4, 0.6)), 3),
                "second_scale": round(float(rng.uniform(0.55, 0.9)), 3),
                "second_distance": round(float(rng.uniform(1.1, 1.6)), 3),
                "second_overlap": round(float(rng.uniform(-0.05, 0.3)), 3),
                "f_bg": round(float(rng.uniform(500, 1100)), 1),
                "background_seed": int(rng.integers(1, 2**31)),
                "noise": round(float(rng.uniform(1.2, 2.5)), 2),
                "quality": int(rng.integers(80, 91)),
            }
        )
    return specs


def _paste(canvas_shape, arr, top, left):
    """``arr`` placed with its (0, 0) at (top, left) in a zero canvas (clipped); and
    whether all its non-zero content fitted."""
    h, w = canvas_shape[:2]
    out = np.zeros((h, w, *arr.shape[2:]), arr.dtype)
    r0, c0 = max(top, 0), max(left, 0)
    r1, c1 = min(top + arr.shape[0], h), min(left + arr.shape[1], w)
    if r1 <= r0 or c1 <= c0:
        return out, False
    out[r0:r1, c0:c1] = arr[r0 - top : r1 - top, c0 - left : c1 - left]
    return out, bool(np.isclose(out.sum(), arr.sum()))


def _bbox(a, thresh=0.02):
    rows = np.flatnonzero(a.max(axis=1) > thresh)
    cols = np.flatnonzero(a.max(axis=0) > thresh)
    return rows[0], rows[-1], cols[0], cols[-1]


def make_composite(spec: dict, supersample: int = SUPERSAMPLE, background: bool = False):
    """The composite photo: ``(rgb uint8, truth bool, jpeg bytes, info)``; with
    ``background``, also what it was made of, in linear light, before the sensor's noise
    and the JPEG: ``{"background": (H, W, 3), "tree": (H, W, 3) premultiplied, "cover":
    (H, W)}`` (the picture is ``tree + (1 - cover) * background``;
    ``benchmarks/composite_ceiling.py``)."""
    from PIL import Image

    W, H = spec["width"], spec["height"]
    rng = np.random.default_rng(spec["background_seed"])
    margin = 6
    # the main tree, scaled so that it fits with a margin
    frac = spec["tree_height"]  # the tree's height, share of the picture's
    S = int(np.rint(0.8 * H))
    P, a, hor = render_tree(spec["tree"], S, supersample)
    for _ in range(8):
        r0, r1, c0, c1 = _bbox(a)
        th, tw = r1 - r0 + 1, c1 - c0 + 1
        want = int(np.rint(S * frac * H / th))
        if abs(want - S) > 0.03 * S:
            S = want
            P, a, hor = render_tree(spec["tree"], S, supersample)
            continue
        if th + 2 * margin <= H * 0.95 and tw + 2 * margin <= W:
            break
        frac *= 0.9
    scale = S / H
    base = int(np.rint(spec["base_at"] * H))
    top = base - r1
    top = max(top, margin - r0)  # keep the crown inside
    if top + r1 > H - 3:
        top = H - 3 - r1
    centre = spec["centre_at"] * W
    if spec["second_tree"]:
        centre = W * (0.34 if spec["centre_at"] < 0.5 else 0.66)
    left = int(np.rint(centre - (c0 + c1) / 2))
    left = int(np.clip(left, margin - c0, W - margin - 1 - c1))
    Pm, fit1 = _paste((H, W, 3), P, top, left)
    am, fit2 = _paste((H, W), a, top, left)
    if not (fit1 and fit2):
        raise RuntimeError(f"{spec['name']}: the tree does not fit")
    base_row = top + r1
    trunk_col = float(
        np.average(np.arange(W), weights=am[base_row - 2 : base_row + 1].sum(0) + 1e-9)
    )
    crown_top = top + r0
    h0 = top + hor
    info = {
        "scale": round(scale, 3),
        "tree_px": [int(th), int(tw)],
        "horizon_row": round(float(h0), 1),
        "base_row": int(base_row),
    }
    # background
    hz, hinfo = horizon_profile(spec["ground"], W, h0, rng, trunk_col)
    info.update(hinfo)
    sky, sinfo = make_sky(spec["sky"], H, W, float(hz.mean()), rng)
    info.update(sinfo)
    sky_horizon = sky[int(np.clip(hz.min() - 3, 0, H - 1))].mean(axis=0)
    img, ginfo = make_ground(
        spec["ground"], H, W, hz, rng, sky, spec["f_bg"], trunk=(base_row, trunk_col, tw)
    )
    info.update(ginfo)
    if spec["ground"] == "hills":
        img, _ = make_hills(img, hz, h0, rng, sky_horizon)
    img, cinfo = add_clutter(spec["clutter"], img, hz, base_row, rng, sky_horizon)
    info.update({f"clutter_{k}": v for k, v in cinfo.items()})
    if spec["hard"] == "wood":
        img, winfo = add_wood(img, hz, base_row, crown_top, rng, sky_horizon)
        info.update({f"wood_{k}": v for k, v in winfo.items()})
    # a touch of lens softness on the background
    img = ndimage.gaussian_filter(img, (0.5, 0.5, 0))
    bg = to_lin(img)
    if spec["second_tree"]:
        s2 = spec["second_scale"]
        S2 = max(32, int(np.rint(S * s2)))
        P2, a2, _ = render_tree(spec["second"], S2, supersample)
        q0, q1, d0, d1 = _bbox(a2)
        b2 = h0 + (base_row - h0) / spec["second_distance"]
        top2 = int(np.rint(b2 - q1))
        top2 = max(top2, margin - q0)
        w2 = d1 - d0 + 1
        ov = spec["second_overlap"] * w2
        if centre < W / 2:  # the main tree on the left: the second on its right
            left2 = int(np.rint(left + c1 - ov - d0))
        else:
            left2 = int(np.rint(left + c0 + ov - d1))
        P2c, _ = _paste((H, W, 3), P2, top2, left2)
        a2c, fitted = _paste((H, W), a2, top2, left2)
        hz_lin = to_lin(sky_horizon)
        hz2 = rng.uniform(0.05, 0.2)
        P2c = P2c * (1 - hz2) + a2c[..., None] * hz2 * hz_lin
        bg = P2c + (1 - a2c[..., None]) * bg
        m2 = a2c >= 0.5
        info.update(
            {
                "second_px": [int(q1 - q0 + 1), int(w2)],
                "second_inside": fitted,
                "second_touches": bool(
                    (ndimage.binary_dilation(m2, iterations=2) & (am >= 0.5)).any()
                ),
            }
        )
    lin = Pm + (1 - am[..., None]) * bg
    rgb = 255.0 * to_srgb(lin)
    nrng = np.random.default_rng(spec["background_seed"] + 1)
    rgb = np.clip(rgb + nrng.normal(0.0, spec["noise"], rgb.shape), 0, 255)
    truth = am >= 0.5
    buf = io.BytesIO()
    Image.fromarray(np.round(rgb).astype(np.uint8)).save(
        buf, format="JPEG", quality=spec["quality"]
    )
    jpeg = buf.getvalue()
    photo = np.asarray(Image.open(io.BytesIO(jpeg)).convert("RGB"))
    if background:
        return photo, truth, jpeg, info, {"background": bg, "tree": Pm, "cover": am}
    return photo, truth, jpeg, info


# ------------------------------------------------------------------------------ sheet


def outline(mask: np.ndarray) -> np.ndarray:
    """The mask's outline (its pixels next to the background)."""
    return mask & ~ndimage.binary_erosion(mask, border_value=1)


def contact_sheet(out: Path, rows, path, thumb: int = 300, cols: int = 4) -> Path:
    """Every composite (left) beside itself with its mask's outline in red (right)."""
    from PIL import Image, ImageDraw

    cell_w, cell_h = 2 * thumb + 8, thumb + 16
    nrow = math.ceil(len(rows) / cols)
    sheet = Image.new("RGB", (cols * cell_w, nrow * cell_h), "white")
    draw = ImageDraw.Draw(sheet)
    for i, row in enumerate(rows):
        im = Image.open(out / row["photo"]).convert("RGB")
        mask = np.asarray(Image.open(out / row["mask"]).convert("L")) < 128
        k = thumb / max(im.size)
        size = (max(1, int(im.width * k)), max(1, int(im.height * k)))
        arr = np.asarray(im).copy()
        o = outline(mask)
        if int(1 / k) > 1:
            o = ndimage.binary_dilation(o, iterations=int(1 / k) - 1)
        arr[o] = (255, 0, 0)
        x, y = (i % cols) * cell_w, (i // cols) * cell_h
        sheet.paste(im.resize(size, Image.LANCZOS), (x, y))
        sheet.paste(Image.fromarray(arr).resize(size, Image.NEAREST), (x + thumb + 4, y))
        draw.text(
            (x + 2, y + thumb + 2),
            f"{row['name']} [{row['split'][0]}] {im.width}x{im.height}",
            fill="black",
        )
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    sheet.save(path)
    return Path(path)


def main(argv=None) -> int:
    from PIL import Image

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="tests/data/composites")
    ap.add_argument("--n", type=int, default=24, help="pictures (default 24: the plan)")
    ap.add_argument("--seed", type=int, default=20261205)
    ap.add_argument("--supersample", type=int, default=SUPERSAMPLE)
    ap.add_argument("--only", nargs="*", default=None, help="picture names")
    ap.add_argument("--sheet", default=None, metavar="PATH", help="write a contact sheet PNG")
    a = ap.parse_args(argv)
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    for spec in scene_specs(a.n, a.seed):
        row = {
            "name": spec["name"],
            "photo": f"{spec['name']}.jpg",
            "mask": f"{spec['name']}_mask.png",
            **{k: v for k, v in spec.items() if k != "name"},
        }
        rows.append(row)
        if a.only is not None and spec["name"] not in a.only:
            continue
        t = time.perf_counter()
        _, truth, jpeg, info = make_composite(spec, a.supersample)
        row["made"] = info
        (out / row["photo"]).write_bytes(jpeg)
        Image.fromarray(~truth).convert("1").save(out / row["mask"], optimize=True)
        print(
            f"{spec['name']}: {time.perf_counter() - t:.1f} s {json.dumps(info)}", file=sys.stderr
        )
    if a.only is not None:
        rows = [r for r in rows if r["name"] in a.only]
    index = {
        "generator": "benchmarks/make_composites.py: modular-tree (m_tree, MIT licence) trees "
        "composited in linear light onto procedural backgrounds",
        "seed": a.seed,
        "supersample": a.supersample,
        "fov": FOV,
        "mask": "black = tree (covered at least half), white = background",
        "pictures": rows,
    }
    if a.only is None:
        (out / "index.json").write_text(json.dumps(index, indent=1))
    result = {
        "out": str(out),
        "n": len(rows),
        "discovery": sum(r["split"] == "discovery" for r in rows),
        "held_out": sum(r["split"] == "held_out" for r in rows),
        "bytes": sum(p.stat().st_size for p in out.iterdir()),
    }
    if a.sheet:
        result["sheet"] = str(contact_sheet(out, rows, a.sheet))
    print(json.dumps(result, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
