"""Benchmark of ``growsim fit-image`` on drawings, with no flags (issue 27).

The Table 1 tree and random IFS trees (tree seeds 100.., parameters uniform within the
ranges, as ``benchmarks/ifs_fit.py --random-trees``) are drawn as scanned-style drawings:
growsim's own 64 px thin-line views enlarged (dark lines on light grey or white paper,
a margin, paper noise, a scanner's blur, PNG or JPEG), and fitted by
:func:`growsim.fitting.fit.fit_image` with its defaults (``segmentation="auto"``: the
drawing must be found a drawing and take the paper's path). Prints JSON lines:

- ``{"kind": "drawing", ...}`` per fit: the picture's size, margin, ``scale`` (the
  enlargement, whole or not), paper, views; the final NCC at 64 px (the fit's own score),
  ``ncc_picture``: the NCC of ``fit_<view>.png`` against ``silhouette_<view>.png`` at the
  picture's size; seconds of the whole call; ``target_exact``: whether the drawing frames
  back into the rendered 64 px views pixel for pixel; ``load``: the 1-minute load
  average; ``held_out``: a row the drawing setup was not tuned on; the choices made;
- with ``--random`` for each random tree also ``ncc_reference``: the best setup
  (``experiments/ifs_tree_best.toml``) fitted to the rendered 64 px target;
- ``{"kind": "classify", ...}`` per picture of ``--photos DIR`` (``benchmarks/make_photos.py``'s
  ``*.jpg`` must be photos, its ``*_truth.png`` silhouettes drawings);
- ``{"kind": "summary", ...}``: min NCC and max seconds of the Table 1 rows (all, tuned,
  held out), the max seconds over ``reference_seconds`` (a fixed workload timed before and
  after the fits, :func:`reference_seconds`: the machine is shared, compare ratios), the
  load, how many targets framed back exactly, the random trees' NCC minus the reference.

Usage::

    python benchmarks/drawing_fit.py                     # Table 1 drawings
    python benchmarks/drawing_fit.py --random 3 --photos runs/photos
    python benchmarks/drawing_fit.py --rows 2 3 4        # some rows only
"""

from __future__ import annotations

import argparse
import glob
import io
import json
import os
import tempfile
import time
from pathlib import Path

import numpy as np
from PIL import Image, ImageFilter

from growsim.models import ifs3d
from growsim.objectives.silhouette import plant_views

#: the Table 1 drawings: (picture size, margin, paper grey, scanner blur, format, views);
#: the enlargement is (size - 2 margin) / 64: whole (4x, 3.5x... see ``scale`` in the rows)
#: or not. The drawing setup (``FIT_SETUPS["ifs3d"].drawing``) was tuned on the rows up to
#: TUNED; the rest were held out (``"held_out": true`` in the rows)
TABLE1 = (
    (256, 32, 0.85, 0.0, "png", 2),
    (256, 32, 0.85, 0.0, "png", 1),
    (288, 32, 0.85, 0.0, "png", 2),  # 3.5x
    (147, 0, 1.0, 0.0, "png", 2),  # 2.3x
    (367, 20, 0.9, 0.0, "jpg", 2),  # 5.1x
    (256, 16, 1.0, 0.0, "png", 2),
    (512, 64, 0.85, 0.6, "jpg", 2),
    (300, 38, 0.9, 0.0, "jpg", 2),
    (128, 0, 1.0, 0.0, "png", 2),
    (224, 0, 1.0, 0.0, "jpg", 2),  # 3.5x
    (187, 20, 0.85, 0.0, "png", 2),  # 2.3x
    (327, 0, 0.85, 0.6, "jpg", 2),  # 5.1x
    (256, 16, 0.85, 0.0, "png", 1),  # 3.5x
    (122, 13, 1.0, 0.0, "png", 2),  # 1.5x
    (461, 3, 0.85, 0.0, "png", 2),  # 7.1x
)
TUNED = 5


def reference_seconds(repeats: int = 5) -> float:
    """Seconds of a fixed workload (developing the Table 1 tree and drawing its views 400
    times; the mean of ``repeats``): fit times divided by it compare across loads."""
    tree = ifs3d.PRESETS["table1"]
    plant_views(ifs3d.develop(tree), 64)  # compiled
    t0 = time.perf_counter()
    for _ in range(repeats * 400):
        plant_views(ifs3d.develop(tree), 64)
    return (time.perf_counter() - t0) / repeats


def _cpu() -> float:
    """CPU seconds of this process and its finished children (user and system): less
    sensitive to the load of a shared machine than wall-clock seconds."""
    t = os.times()
    return t.user + t.system + t.children_user + t.children_system


def _load() -> float:
    return round(os.getloadavg()[0], 2)


def drawing(view: np.ndarray, size: int, margin: int, paper: float, blur: float, fmt: str,
            seed: int = 0) -> bytes:  # fmt: skip
    """A 64 px thin-line view drawn as a scan: enlarged (nearest) to ``size - 2 margin``
    pixels, ink at 0.15 on ``paper``, paper noise, ``blur`` (a scanner's), PNG or JPEG."""
    inner = size - 2 * margin
    big = Image.fromarray(np.where(view > 0, 255, 0).astype(np.uint8))
    big = np.asarray(big.resize((inner, inner), Image.NEAREST)) > 127
    g = np.where(big, 0.15, paper)
    g = np.pad(g, margin, constant_values=paper)
    g = g + np.random.default_rng(seed).normal(0.0, 0.015, g.shape)
    im = Image.fromarray(np.round(255 * np.clip(g, 0, 1)).astype(np.uint8)).convert("RGB")
    if blur > 0:
        im = im.filter(ImageFilter.GaussianBlur(blur))
    buf = io.BytesIO()
    im.save(buf, format="JPEG" if fmt == "jpg" else "PNG", quality=90)
    return buf.getvalue()


def _ncc_files(out: Path, views: int) -> float:
    """NCC of ``fit_<view>.png`` against ``silhouette_<view>.png``, mean over views."""
    nccs = []
    for v in ("front", "side")[:views]:
        a = np.asarray(Image.open(out / f"silhouette_{v}.png")) < 128
        b = np.asarray(Image.open(out / f"fit_{v}.png")) < 128
        nccs.append(float(np.corrcoef(a.ravel(), b.ravel())[0, 1]))
    return round(float(np.mean(nccs)), 4)


def _exact(paths, views) -> bool:
    """Whether the drawings frame (thin lines, 64 px) into the rendered ``views``."""
    from growsim.pictures.images import read_silhouettes

    side = paths[1] if len(paths) > 1 else None
    framed = read_silhouettes(paths[0], side, size=64, line_width="thin",
                              views="both" if side else "front")  # fmt: skip
    return bool(np.array_equal(framed, np.asarray(views)))


def fit_drawing(plant, name: str, spec, tmp: Path) -> dict:
    """Draw ``plant``'s 64 px thin-line views (one view: the front framed alone, as one
    picture is) as ``spec`` and fit them with no options; its JSON row."""
    from growsim.fitting.fit import fit_image

    size, margin, paper, blur, fmt, n = spec
    views = plant_views(plant, 64, views=n)
    paths = []
    for i, v in enumerate(views):
        p = tmp / f"{name}-{size}-{margin}-{n}-{('front', 'side')[i]}.{fmt}"
        p.write_bytes(drawing(v, size, margin, paper, blur, fmt, seed=i))
        paths.append(p)
    out = tmp / f"fit-{name}-{size}-{margin}-{n}"
    t0, c0 = time.perf_counter(), _cpu()
    r = fit_image(*paths, out=out, progress=False)
    seconds, cpu = time.perf_counter() - t0, _cpu() - c0
    return {"kind": "drawing", "tree": name, "size": size, "margin": margin,
            "scale": round((size - 2 * margin) / 64, 3), "paper": paper,
            "blur": blur, "format": fmt, "views": n, "ncc": round(r.ncc, 4),
            "target_exact": _exact(paths, views), "load": _load(),
            "ncc_picture": _ncc_files(r.out, n), "seconds": round(seconds, 2),
            "cpu_seconds": round(cpu, 2),
            "choices": {k: c["value"] for k, c in r.summary["choices"].items()},
            "why": r.summary["choices"]["segmentation"]["why"]}  # fmt: skip


def reference(target: dict, drawn: list[Path], tmp: Path) -> tuple[float, bool]:
    """The best setup fitted to the rendered target (its NCC), and whether the drawings
    frame into that target exactly."""
    from growsim.experiment import run
    from growsim.fitting.setups import fit_config
    from growsim.objectives.silhouette import SilhouetteObjective

    rendered = {"kind": "silhouette", "target_model": "ifs3d", "target_params": target,
                "size": 64}  # fmt: skip
    cfg = fit_config(*drawn, line_width="thin", leaves=False, segmentation="threshold")
    exact = bool(
        np.array_equal(SilhouetteObjective(**{k: v for k, v in cfg["objective"][0].items()
                                              if k != "kind"}).target,
                       SilhouetteObjective(**{k: v for k, v in rendered.items()
                                              if k != "kind"}).target)
    )  # fmt: skip
    quiet = ["output.mesh=[]", "output.screenshots=[]", "output.plot=false"]
    r = run(dict(cfg, objective=[rendered]), tmp / f"ref-{id(target)}", overrides=quiet,
            progress=False)  # fmt: skip
    return round(float(r.best_fitness), 4), exact


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--random", type=int, default=0, help="random IFS trees to draw and fit")
    ap.add_argument("--photos", default=None, help="benchmarks/make_photos.py's directory")
    ap.add_argument("--no-table1", action="store_true")
    ap.add_argument(
        "--rows", type=int, nargs="*", default=None, help="only these rows of TABLE1 (0-based)"
    )
    a = ap.parse_args(argv)
    rows: list[dict] = []
    ref_before = reference_seconds()
    with tempfile.TemporaryDirectory() as d:
        tmp = Path(d)
        if not a.no_table1:
            plant = ifs3d.develop(ifs3d.PRESETS["table1"])
            for i, spec in enumerate(TABLE1):
                if a.rows and i not in a.rows:
                    continue
                rows.append(fit_drawing(plant, "table1", spec, tmp) | {"held_out": i >= TUNED})
                print(json.dumps(rows[-1]), flush=True)
        fixed = ("n_maps", "depth", "leaves", "leaf_radius")  # a bare tree, as the best setup
        evolved = [p for p in ifs3d.PARAMS if p.name not in fixed]
        for t in range(a.random):
            rng = np.random.default_rng(100 + t)
            target = {"n_maps": 5, "depth": 5} | {p.name: rng.uniform(p.low, p.high)
                                                  for p in evolved}  # fmt: skip
            row = fit_drawing(ifs3d.develop(target), f"random-{100 + t}", TABLE1[0], tmp)
            drawn = sorted(tmp.glob(f"random-{100 + t}-256-32-2-*.png"))
            row["ncc_reference"], exact = reference(target, drawn, tmp)
            assert exact == row["target_exact"]
            rows.append(row)
            print(json.dumps(row), flush=True)
        ref_after = reference_seconds()
    fits = [r for r in rows if r["kind"] == "drawing"]
    if a.photos:
        for p in sorted(glob.glob(str(Path(a.photos) / "*"))):
            if p.endswith((".jpg", ".png")):
                from growsim.pictures.images import classify_picture

                kind, why = classify_picture(p)
                expected = "drawing" if p.endswith("_truth.png") else "photo"
                rows.append({"kind": "classify", "picture": Path(p).name, "class": kind,
                             "expected": expected, "why": why})  # fmt: skip
                print(json.dumps(rows[-1]), flush=True)
    classified = [r for r in rows if r["kind"] == "classify"]
    t1 = [r for r in fits if r["tree"] == "table1"]
    rand = [r for r in fits if r["tree"] != "table1"]
    ref = 0.5 * (ref_before + ref_after)

    def part(held_out):
        rs = [r for r in t1 if r["held_out"] == held_out]
        return {"rows": len(rs), "min_ncc": min((r["ncc"] for r in rs), default=None),
                "max_seconds": max((r["seconds"] for r in rs), default=None)}  # fmt: skip

    summary = {
        "kind": "summary",
        "table1_min_ncc": min((r["ncc"] for r in t1), default=None),
        "table1_max_seconds": max((r["seconds"] for r in t1), default=None),
        "table1_max_cpu_seconds": max((r["cpu_seconds"] for r in t1), default=None),
        "table1_max_seconds_per_reference": (
            round(max(r["seconds"] for r in t1) / ref, 2) if t1 else None
        ),
        "table1_tuned": part(False),
        "table1_held_out": part(True),
        "targets_exact": sum(r["target_exact"] for r in fits),
        "fits": len(fits),
        "random_ncc_minus_reference": [round(r["ncc"] - r["ncc_reference"], 4) for r in rand],
        "reference_seconds": round(ref, 3),
        "reference_seconds_before_after": [round(ref_before, 3), round(ref_after, 3)],
        "load": _load(),
        "all_threshold": all(r["choices"]["segmentation"] == "threshold" for r in fits),
        "classified_right": sum(r["class"] == r["expected"] for r in classified),
        "classified": len(classified),
    }
    print(json.dumps(summary), flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
