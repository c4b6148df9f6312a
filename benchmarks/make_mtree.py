"""Test pictures from another generator: trees grown by ``modular-tree``, rendered as photos.

``modular-tree`` (MIT licence, PyPI ``modular-tree``, import ``m_tree``; source
github.com/GoodPie/modular_tree) grows a tree from a trunk node and chained branch nodes
(length, radius, start angle, density, splits, gravity, up attraction, crown shape, seeds)
and meshes it (``ManifoldMesher``). Each tree here is one of six shapes (:data:`SHAPES`:
columnar, spreading, weeping, aspen-like sparse and thin-branched, dense, conical: the
add-on's pine preset, a broad cone), its parameters jittered and its seeds drawn at
random, bare or leafy (modular-tree's Python module has no leaf-placing node: leaves of
its ``LeafShapeGenerator`` presets are scattered on the thin branches, each turned at
random), rendered with pyvista as
``benchmarks/make_photos.py`` renders growsim's trees: the same long lens (:data:`FOV`)
and framing, the same anti-aliasing (:data:`SUPERSAMPLE` x :data:`SUPERSAMPLE` samples a
pixel in linear light), sensor noise and JPEG; a sky (plain or a gradient), a ground strip,
a sun (a directional light: lit and shaded sides) with a dim fill light, bark from dark
brown to grey to pale, at 384, 512 or 768 px. The same camera renders the tree alone
(black, unlit, on white, the ground in white hiding what is below it) for the true
silhouette, ``<name>_mask.png`` (the pixels at least half covered).

    python benchmarks/make_mtree.py --out runs/mtree --sheet runs/mtree/sheet.png

``--side`` also renders each tree from its right (the camera turned 90 degrees about the
vertical: the picture's x is the tree's ``-z``, as growsim draws a side view):
``<name>_side.jpg`` and ``<name>_side_mask.png``, listed in ``sides.json`` (``index.json``
unchanged); ``--no-front`` renders only these (the front pictures kept as they are).

    python benchmarks/make_mtree.py --out runs/mtree --side --no-front --no-segment

Half the pictures (seeded, one of each pair of the same shape and leafiness) are
``held_out``: nobody tunes on them; the other half are ``discovery``. ``index.json`` lists
each picture's parameters and split; the photo segmentation's result on each (accepted or
refused with the reason, and its IoU against the mask) is printed and written to
``segmentation.json`` (``--no-segment``: not run).
"""

from __future__ import annotations

import argparse
import io
import json
import math
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from make_photos import FOV, SKIES, SUPERSAMPLE, _camera

#: The skies (top, bottom): make_photos' gradients and three plain ones.
ALL_SKIES = (
    *SKIES,
    ((0.78, 0.85, 0.95), (0.78, 0.85, 0.95)),
    ((0.90, 0.90, 0.89), (0.90, 0.90, 0.89)),
    ((0.66, 0.78, 0.93), (0.66, 0.78, 0.93)),
)
#: Bark colours: dark brown, brown, grey, pale grey, pale (birch-like).
BARKS = {
    "dark": (0.22, 0.19, 0.17),
    "brown": (0.38, 0.29, 0.22),
    "grey": (0.52, 0.52, 0.50),
    "pale_grey": (0.70, 0.69, 0.66),
    "pale": (0.84, 0.82, 0.77),
}
LEAVES = {
    "green": (0.24, 0.42, 0.16),
    "dark_green": (0.14, 0.28, 0.12),
    "yellow_green": (0.50, 0.58, 0.20),
    "autumn": (0.78, 0.50, 0.16),
}
SIZES = (384, 512, 768)

#: The shapes: trunk parameters and a chain of branch nodes (each the child of the one
#: before), with the leaf preset and the leaves' size (share of the tree's height) when leafy.
SHAPES: dict[str, dict] = {
    "columnar": {
        "trunk": {"length": 18, "start_radius": 0.35, "end_radius": 0.05, "shape": 0.8,
                  "up_attraction": 0.8, "randomness": 0.3},
        "branches": [
            {"start": 0.12, "end": 0.98, "length": 6.0, "density": 2.2, "start_angle": 22,
             "up_attraction": 0.8, "gravity_strength": 2, "stiffness": 0.4, "flatness": 0.2,
             "split_proba": 0.3, "split_angle": 20, "start_radius": 0.35, "randomness": 0.3,
             "crown_shape": "Flame"},
            {"start": 0.2, "end": 0.95, "length": 1.5, "density": 2.5, "start_angle": 30,
             "up_attraction": 0.5, "gravity_strength": 2, "stiffness": 0.3, "flatness": 0.3,
             "split_proba": 0.2, "start_radius": 0.5, "randomness": 0.4},
        ],
        "leaf": "Birch", "leaf_size": 0.022, "leaf_share": 0.4, "leaf_count": 5000,
    },
    "spreading": {
        "trunk": {"length": 7, "start_radius": 0.5, "end_radius": 0.15, "shape": 0.5,
                  "up_attraction": 0.5, "randomness": 1.0},
        "branches": [
            {"start": 0.15, "end": 0.95, "length": 8, "density": 1.8, "start_angle": 55,
             "gravity_strength": 6, "up_attraction": 0.45, "flatness": 0.35, "stiffness": 0.2,
             "split_proba": 0.65, "split_angle": 40, "start_radius": 0.4, "randomness": 0.5,
             "crown_shape": "Hemispherical"},
            {"start": 0.3, "end": 0.95, "length": 1.6, "density": 1.5, "start_angle": 40,
             "gravity_strength": 4, "up_attraction": 0.3, "flatness": 0.4, "stiffness": 0.2,
             "split_proba": 0.2, "start_radius": 0.4, "randomness": 0.5},
        ],
        "leaf": "Oak", "leaf_size": 0.035, "leaf_share": 0.5, "leaf_count": 7000,
    },
    "weeping": {
        "trunk": {"length": 8, "start_radius": 0.5, "end_radius": 0.15, "shape": 0.4,
                  "up_attraction": 0.8, "randomness": 1.0},
        "branches": [
            {"start": 0.3, "end": 0.9, "length": 8, "density": 1.2, "start_angle": 55,
             "gravity_strength": 5, "stiffness": 0.5, "up_attraction": 0.6, "flatness": 0.15,
             "split_proba": 0.5, "break_chance": 0.01, "start_radius": 0.7, "randomness": 0.3},
            {"start": 0.3, "end": 0.95, "length": 8, "density": 1.2, "start_angle": 65,
             "gravity_strength": 350, "stiffness": 0.1, "up_attraction": -0.8, "flatness": 0.0,
             "split_proba": 0.02, "break_chance": 0.005, "start_radius": 0.35,
             "end_radius": 0.02, "randomness": 0.2},
        ],
        "leaf": "Willow", "leaf_size": 0.03, "leaf_share": 0.45, "leaf_count": 7000,
    },
    "aspen": {
        "trunk": {"length": 16, "start_radius": 0.22, "end_radius": 0.03, "shape": 0.9,
                  "up_attraction": 0.7, "randomness": 0.4},
        "branches": [
            {"start": 0.35, "end": 0.97, "length": 4.0, "density": 1.2, "start_angle": 50,
             "gravity_strength": 4, "up_attraction": 0.35, "flatness": 0.4, "stiffness": 0.2,
             "split_proba": 0.15, "split_angle": 30, "start_radius": 0.3, "randomness": 0.5,
             "break_chance": 0.02},
        ],
        "leaf": "Birch", "leaf_size": 0.025, "leaf_share": 0.5, "leaf_count": 2000,
    },
    "dense": {
        "trunk": {"length": 11, "start_radius": 0.4, "end_radius": 0.08, "shape": 0.6,
                  "up_attraction": 0.6, "randomness": 0.8},
        "branches": [
            {"start": 0.2, "end": 0.95, "length": 6, "density": 2.5, "start_angle": 50,
             "gravity_strength": 8, "up_attraction": 0.35, "flatness": 0.3, "stiffness": 0.2,
             "split_proba": 0.5, "split_angle": 35, "start_radius": 0.45, "randomness": 0.5,
             "crown_shape": "Spherical"},
            {"start": 0.15, "end": 0.95, "length": 2.0, "density": 2.5, "start_angle": 45,
             "gravity_strength": 6, "up_attraction": 0.2, "flatness": 0.5, "stiffness": 0.2,
             "split_proba": 0.3, "start_radius": 0.45, "randomness": 0.5},
        ],
        "leaf": "Maple", "leaf_size": 0.025, "leaf_share": 0.4, "leaf_count": 7000,
    },
    "conical": {
        "trunk": {"length": 14, "start_radius": 0.3, "end_radius": 0.05, "shape": 1.0,
                  "up_attraction": 0.6, "randomness": 0.2},
        "branches": [
            {"start": 0.2, "end": 1.0, "length": 7, "density": 2.5, "start_angle": 60,
             "randomness": 0.5, "flatness": 0.5, "up_attraction": 0.0, "gravity_strength": 10,
             "stiffness": 0.1, "split_proba": 0.5, "split_radius": 0.8, "split_angle": 35,
             "break_chance": 0.01, "start_radius": 0.4, "crown_shape": "Conical"},
            {"start": 0.1, "end": 0.95, "length": 2, "density": 4.0, "start_angle": 45,
             "randomness": 0.5, "flatness": 1.0, "up_attraction": 0.0, "gravity_strength": 14,
             "stiffness": 0.1, "split_proba": 0.5, "split_radius": 0.8, "split_angle": 35,
             "break_chance": 0.02, "start_radius": 0.4},
        ],
        "leaf": "Willow", "leaf_size": 0.03, "leaf_share": 0.5, "leaf_count": 8000,
    },
}  # fmt: skip

_WRAPPED = {"length", "start_radius", "randomness", "start_angle"}
_NESTED = {
    "start": ("distribution", "start"), "end": ("distribution", "end"),
    "density": ("distribution", "density"), "gravity_strength": ("gravity", "strength"),
    "stiffness": ("gravity", "stiffness"), "up_attraction": ("gravity", "up_attraction"),
    "split_proba": ("split", "probability"), "split_radius": ("split", "radius"),
    "split_angle": ("split", "angle"), "crown_shape": ("crown", "shape"),
}  # fmt: skip


def _jitter(params: dict, rng, share: float) -> dict:
    """``params`` with each number scaled by a factor in ``1 +- share`` (angles, lengths,
    densities, gravity...; shares in [0, 1] stay in it)."""
    out = {}
    for k, v in params.items():
        if isinstance(v, (int, float)) and not isinstance(v, bool) and v != 0:
            v = float(v) * float(rng.uniform(1 - share, 1 + share))
            if k in ("start", "end", "stiffness", "flatness", "split_radius", "shape"):
                v = min(v, 1.0)
            v = round(v, 4)
        out[k] = v
    return out


def grow(trunk: dict, branches: list, seeds: list):
    """The modular-tree tree of these parameters: ``(vertices (n, 3) y up, triangles
    (m, 3), radius (n,))``."""
    import m_tree as mt

    tf = mt.TrunkFunction()
    for k, v in trunk.items():
        setattr(tf, k, v)
    tf.seed = int(seeds[0])
    parent = tf
    for params, seed in zip(branches, seeds[1:]):
        bf = mt.BranchFunction()
        for k, v in params.items():
            if k in _WRAPPED:
                v = mt.PropertyWrapper(mt.ConstantProperty(float(v)))
            if k == "crown_shape":
                v = getattr(mt.CrownShape, v)
            if k in _NESTED:
                setattr(getattr(bf, _NESTED[k][0]), _NESTED[k][1], v)
            else:
                setattr(bf, k, v)
        bf.seed = int(seed)
        parent.add_child(bf)
        parent = bf
    tree = mt.Tree()
    tree.set_trunk_function(tf)
    tree.execute_functions()
    mesher = mt.ManifoldMesher()
    mesher.radial_n_points = 8
    mesher.smooth_iterations = 1
    mesh = mesher.mesh_tree(tree)
    v = np.asarray(mesh.get_vertices(), np.float64).reshape(-1, 3)
    quads = np.asarray(mesh.get_polygons(), np.int64).reshape(-1, 4)
    tris = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    tris = tris[
        (tris[:, 0] != tris[:, 1]) & (tris[:, 1] != tris[:, 2]) & (tris[:, 0] != tris[:, 2])
    ]
    radius = np.asarray(mesh.get_float_attribute("radius"), np.float64)
    # z up -> y up (growsim's and make_photos' camera)
    return np.stack([v[:, 0], v[:, 2], -v[:, 1]], axis=1), tris, radius


def leaf_shape(preset: str):
    """One leaf of modular-tree's ``LeafShapeGenerator`` preset: ``(vertices (n, 3), triangles)``,
    its stalk at the origin, 1 long along -y, in the xy plane."""
    import m_tree as mt

    p = mt.get_leaf_preset(preset)
    g = mt.LeafShapeGenerator()
    for a in dir(p):
        if not a.startswith("_") and a != "name" and hasattr(g, a):
            setattr(g, a, getattr(p, a))
    g.enable_venation = False
    g.contour_resolution = 10
    m = g.generate()
    v = np.asarray(m.get_vertices(), np.float64).reshape(-1, 3)
    f = np.asarray(m.get_polygons(), np.int64).reshape(-1, 4)[:, :3]
    span = np.ptp(v[:, :2], axis=0).max()
    return (v - [0.0, 0.0, 0.0]) / max(span, 1e-9), f


def _rotations(rng, n):
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    w, x, y, z = q.T
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], -1),
        np.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], -1),
        np.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], -1),
    ], axis=1)  # fmt: skip


def scatter_leaves(verts, radius, preset, size, share, rng, count=5000):
    """Leaves on the thin branches: on the vertices whose radius is among the ``share``
    thinnest, ``size`` long (in the tree's units), turned at random: ``(vertices,
    triangles)`` of all of them."""
    lv, lf = leaf_shape(preset)
    thin = np.flatnonzero(radius <= np.quantile(radius, share))
    n = int(count)
    at = verts[rng.choice(thin, n)] + rng.normal(0, 0.3 * size, (n, 3))
    rot = _rotations(rng, n)
    scale = size * rng.uniform(0.7, 1.3, n)
    pts = np.einsum("nij,kj->nki", rot, lv) * scale[:, None, None] + at[:, None, :]
    faces = lf[None, :, :] + (np.arange(n) * lv.shape[0])[:, None, None]
    return pts.reshape(-1, 3), faces.reshape(-1, 3), lv.shape[0]


def picture_specs(n: int = 24, seed: int = 20261128) -> list[dict]:
    """``n`` picture descriptions: pairs of the same shape and leafiness (the shapes in
    turn, bare then leafy), one of each pair held out (seeded)."""
    rng = np.random.default_rng(seed)
    names = list(SHAPES)
    specs = []
    held = []
    for i in range(n):
        k = i // 2
        shape = names[k % len(names)]
        leafy = (k // len(names)) % 2 == 1
        if i % 2 == 0:
            held = [bool(h) for h in rng.permutation([0, 1])]
        s = SHAPES[shape]
        top, bottom = ALL_SKIES[rng.integers(len(ALL_SKIES))]
        bark = list(BARKS)[rng.integers(len(BARKS))]
        leaf = list(LEAVES)[rng.choice(len(LEAVES), p=[0.4, 0.25, 0.25, 0.1])]
        if shape == "conical":
            leaf = "dark_green"
        ground = np.clip(np.array([0.40, 0.50, 0.28]) + rng.normal(0, 0.05, 3), 0, 1)
        specs.append({
            "name": f"mt{i:02d}_{shape}_{'leafy' if leafy else 'bare'}",
            "split": "held_out" if held[i % 2] else "discovery",
            "shape": shape, "leafy": leafy,
            "size": int(SIZES[rng.integers(len(SIZES))]),
            "trunk": _jitter(s["trunk"], rng, 0.15),
            "branches": [_jitter(b, rng, 0.2) for b in s["branches"]],
            "seeds": [int(x) for x in rng.integers(1, 100000, 1 + len(s["branches"]))],
            "leaf_preset": s["leaf"], "leaf_size": s["leaf_size"],
            "leaf_share": s["leaf_share"], "leaf_count": s["leaf_count"],
            "leaf_seed": int(rng.integers(1, 100000)),
            "yaw": round(float(rng.uniform(0, 360)), 1),
            "sky_top": list(top), "sky_bottom": list(bottom),
            "bark_name": bark, "bark": list(BARKS[bark]),
            "leaf_name": leaf, "leaf": list(LEAVES[leaf]),
            "ground": ground.round(3).tolist(),
            "sun_azimuth": round(float(rng.uniform(-70, 70)), 1),
            "sun_elevation": round(float(rng.uniform(25, 60)), 1),
            "eye": round(float(rng.uniform(0.1, 0.25)), 3),
            "quality": int(rng.integers(72, 92)),
        })  # fmt: skip
    return specs


def side_spec(spec: dict) -> dict:
    """The spec seen from its tree's right: the tree turned by -90 degrees of yaw (a point
    ``(x, y, z)`` drawn at ``x' = -z``), everything else the same.

    >>> side_spec({"yaw": 10.0, "name": "a"})["yaw"]
    -80.0
    """
    return {**spec, "yaw": float(spec["yaw"]) - 90.0}


def tree_of(spec: dict):
    """The spec's meshes: ``(bark PolyData, leaves PolyData or None, leaf colours)``."""
    import pyvista as pv

    v, t, r = grow(spec["trunk"], spec["branches"], spec["seeds"])
    a = math.radians(spec["yaw"])
    rot = np.array([[math.cos(a), 0, math.sin(a)], [0, 1, 0], [-math.sin(a), 0, math.cos(a)]])
    v = v @ rot.T
    bark = pv.PolyData.from_regular_faces(v, t)
    if not spec["leafy"]:
        return bark, None, None
    rng = np.random.default_rng(spec["leaf_seed"])
    height = float(v[:, 1].max())
    lv, lt, per = scatter_leaves(v, r, spec["leaf_preset"], spec["leaf_size"] * height,
                                 spec["leaf_share"], rng, spec["leaf_count"])  # fmt: skip
    leaves = pv.PolyData.from_regular_faces(lv, lt)
    n = lv.shape[0] // per
    jitter = np.clip(np.asarray(spec["leaf"]) * rng.uniform(0.75, 1.2, (n, 1)), 0, 1)
    colours = np.repeat((255 * jitter).astype(np.uint8), per, axis=0)
    return bark, leaves, colours


def _views(spec, bark, leaves, colours, big):
    """Colour (lit, over sky and ground) and the tree's cover, ``big x big`` samples."""
    import pyvista as pv
    from vtkmodules.vtkCommonCore import vtkObject

    bounds = np.array(bark.bounds if leaves is None else bark.merge(leaves).bounds)
    height = float(bounds[3])
    bounds[2] = 0.0
    far = 80.0 * height * max(1.0, math.tan(math.radians(12.5)) / math.tan(math.radians(FOV / 2)))
    ground = pv.Plane(center=(0, 0, 0), direction=(0, 1, 0), i_size=far, j_size=far)
    shown = vtkObject.GetGlobalWarningDisplay()
    vtkObject.GlobalWarningDisplayOff()
    try:
        pl = pv.Plotter(off_screen=True, window_size=(big, big), lighting="none")
        pl.disable_anti_aliasing()
        pl.set_background(spec["sky_bottom"], top=spec["sky_top"])
        az, el = math.radians(spec["sun_azimuth"]), math.radians(spec["sun_elevation"])
        sun = np.array([math.sin(az) * math.cos(el), math.sin(el), math.cos(az) * math.cos(el)])
        pl.add_light(
            pv.Light(
                position=tuple(sun * 1000 * height),
                focal_point=(0, 0, 0),
                color="white",
                intensity=0.85,
                light_type="scene light",
            )
        )
        pl.add_light(
            pv.Light(
                position=(0, 0.3 * height, 1000 * height),
                focal_point=(0, 0, 0),
                color="white",
                intensity=0.3,
                light_type="scene light",
            )
        )
        pl.add_mesh(ground, color=spec["ground"], ambient=0.35, diffuse=0.65, specular=0.0)
        pl.add_mesh(bark, color=spec["bark"], ambient=0.3, diffuse=0.75, specular=0.1,
                    smooth_shading=True)  # fmt: skip
        if leaves is not None:
            pl.add_mesh(leaves, scalars=colours, rgb=True, ambient=0.3, diffuse=0.75,
                        specular=0.05)  # fmt: skip
        _camera(pl, bounds.tolist(), big, spec["eye"], FOV)
        colour = np.asarray(pl.screenshot(return_img=True))[..., :3].astype(np.float64)
        pl.close()
        pl = pv.Plotter(off_screen=True, window_size=(big, big))
        pl.disable_anti_aliasing()
        pl.set_background("white")
        pl.add_mesh(ground, color="white", lighting=False)
        pl.add_mesh(bark, color="black", lighting=False)
        if leaves is not None:
            pl.add_mesh(leaves, color="black", lighting=False)
        _camera(pl, bounds.tolist(), big, spec["eye"], FOV)
        cover = np.asarray(pl.screenshot(return_img=True))[..., 0] < 128
        pl.close()
    finally:
        vtkObject.SetGlobalWarningDisplay(shown)
    return colour, cover


def make_picture(spec: dict, supersample: int = SUPERSAMPLE):
    """The spec's photo: ``(rgb uint8, truth bool, jpeg bytes)``, as make_photos.make_photo."""
    from PIL import Image

    from growsim.pictures.photo import linear_to_srgb, srgb_to_linear

    size, f = spec["size"], int(supersample)
    bark, leaves, colours = tree_of(spec)
    colour, cover = _views(spec, bark, leaves, colours, f * size)
    lin = srgb_to_linear(colour / 255.0).reshape(size, f, size, f, 3).mean(axis=(1, 3))
    rgb = 255.0 * linear_to_srgb(lin)
    rng = np.random.default_rng(sum(spec["name"].encode()))
    rgb = np.clip(rgb + rng.normal(0.0, 1.5, rgb.shape), 0, 255)
    truth = cover.reshape(size, f, size, f).mean(axis=(1, 3)) >= 0.5
    buf = io.BytesIO()
    Image.fromarray(np.round(rgb).astype(np.uint8)).save(
        buf, format="JPEG", quality=spec["quality"]
    )
    jpeg = buf.getvalue()
    return np.asarray(Image.open(io.BytesIO(jpeg)).convert("RGB")), truth, jpeg


def segment(rows, out: Path) -> list[dict]:
    """The photo segmentation on each picture: accepted (IoU against the mask) or refused
    (the reason)."""
    from PIL import Image

    from growsim.pictures.photo import load_rgb, segment_photo

    res = []
    for row in rows:
        truth = np.asarray(Image.open(out / row["mask"]).convert("L")) < 128
        t = time.perf_counter()
        try:
            seg = segment_photo(load_rgb(out / row["photo"]), name=row["name"])
        except Exception as exc:  # a refusal is a result here
            r = {"name": row["name"], "split": row["split"], "accepted": False,
                 "reason": f"{type(exc).__name__}: {exc}"}  # fmt: skip
        else:
            iou = float((seg.tree & truth).sum() / max((seg.tree | truth).sum(), 1))
            r = {"name": row["name"], "split": row["split"], "accepted": True,
                 "iou": round(iou, 4),
                 "area_ratio": round(float(seg.tree.sum() / truth.sum()), 3)}  # fmt: skip
        r["seconds"] = round(time.perf_counter() - t, 2)
        print(json.dumps(r), file=sys.stderr)
        res.append(r)
    return res


def contact_sheet(out: Path, rows, path, thumb: int = 200, cols: int = 6) -> Path:
    """A PNG of all pictures as thumbnails, each with its name and split."""
    from PIL import Image, ImageDraw

    nrow = math.ceil(len(rows) / cols)
    sheet = Image.new("RGB", (cols * thumb, nrow * (thumb + 16)), "white")
    draw = ImageDraw.Draw(sheet)
    for i, row in enumerate(rows):
        im = Image.open(out / row["photo"]).convert("RGB").resize((thumb, thumb), Image.LANCZOS)
        x, y = (i % cols) * thumb, (i // cols) * (thumb + 16)
        sheet.paste(im, (x, y))
        draw.text(
            (x + 3, y + thumb + 2), f"{row['name']} {row['split'][0]} {row['size']}", fill="black"
        )
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    sheet.save(path)
    return Path(path)


def main(argv=None) -> int:
    from PIL import Image

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="runs/mtree")
    ap.add_argument("--n", type=int, default=24, help="pictures (default 24)")
    ap.add_argument("--seed", type=int, default=20261128)
    ap.add_argument("--supersample", type=int, default=SUPERSAMPLE)
    ap.add_argument("--only", nargs="*", default=None, help="picture names")
    ap.add_argument("--sheet", default=None, metavar="PATH", help="write a contact sheet PNG")
    ap.add_argument("--no-segment", action="store_true", help="skip the segmentation check")
    ap.add_argument("--side", action="store_true",
                    help="also render each tree from its right (<name>_side.jpg, "
                         "<name>_side_mask.png, sides.json)")  # fmt: skip
    ap.add_argument(
        "--no-front", action="store_true", help="with --side: render the side views only"
    )
    a = ap.parse_args(argv)
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    sides: list[dict] = []
    for spec in picture_specs(a.n, a.seed):
        row = {**spec, "photo": f"{spec['name']}.jpg", "mask": f"{spec['name']}_mask.png"}
        rows.append(row)
        if a.only is not None and spec["name"] not in a.only:
            continue
        t = time.perf_counter()
        if not (a.side and a.no_front):
            _, truth, jpeg = make_picture(spec, a.supersample)
            (out / row["photo"]).write_bytes(jpeg)
            Image.fromarray(np.where(truth, 0, 255).astype(np.uint8)).save(out / row["mask"])
        if a.side:
            _, truth, jpeg = make_picture(side_spec(spec), a.supersample)
            (out / f"{spec['name']}_side.jpg").write_bytes(jpeg)
            Image.fromarray(np.where(truth, 0, 255).astype(np.uint8)).save(
                out / f"{spec['name']}_side_mask.png"
            )
            sides.append({"name": spec["name"], "split": spec["split"],
                          "side_photo": f"{spec['name']}_side.jpg",
                          "side_mask": f"{spec['name']}_side_mask.png"})  # fmt: skip
        print(f"{spec['name']}: {time.perf_counter() - t:.1f} s", file=sys.stderr)
    if a.only is not None:
        rows = [r for r in rows if r["name"] in a.only]
    index = {"generator": "modular-tree (m_tree) 5.6.0, MIT licence", "seed": a.seed,
             "supersample": a.supersample, "fov": FOV, "pictures": rows}  # fmt: skip
    if a.only is None and not (a.side and a.no_front):
        (out / "index.json").write_text(json.dumps(index, indent=1))
    if a.side:
        old = json.loads((out / "sides.json").read_text()) if (out / "sides.json").is_file() else []
        done = {r["name"] for r in sides}
        sides = [r for r in old if r["name"] not in done] + sides
        (out / "sides.json").write_text(json.dumps(sorted(sides, key=lambda r: r["name"]),
                                                   indent=1))  # fmt: skip
    result = {"out": str(out), "n": len(rows),
              "discovery": [r["name"] for r in rows if r["split"] == "discovery"],
              "held_out": [r["name"] for r in rows if r["split"] == "held_out"]}  # fmt: skip
    if a.sheet:
        result["sheet"] = str(contact_sheet(out, rows, a.sheet))
    if not a.no_segment:
        seg = segment(rows, out)
        (out / "segmentation.json").write_text(json.dumps(seg, indent=1))
        ok = [r["iou"] for r in seg if r["accepted"]]
        result["segmentation"] = seg
        result["accepted"] = len(ok)
        result["mean_iou"] = round(float(np.mean(ok)), 4) if ok else None
        for split in ("discovery", "held_out"):
            s = [r["iou"] for r in seg if r["accepted"] and r["split"] == split]
            result[f"{split}_mean_iou"] = round(float(np.mean(s)), 4) if s else None
        result["load_average"] = os.getloadavg()
    print(json.dumps(result, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
