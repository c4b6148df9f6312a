"""``growsim fit-image`` with no flags on pictures of trees it did not grow (issue 27's bars).

For each picture of ``benchmarks/make_mtree.py``'s ``index.json`` in the splits asked
(``discovery``: tuned on; ``held_out``: never tuned on), :func:`growsim.fitting.fit.fit_image`
with its defaults (the model, bare or leafy, the segmentation: all chosen by the tool), and
prints one JSON line per picture:

- ``ncc``: the fit's binary NCC at its final size (256 px), as ``fit.json`` reports it;
- ``area``: the fit's area over the picture's tree at the picture's size
  (``fit_front.png`` against ``silhouette_front.png``); ``bare_fitted_bare`` for a bare tree;
- ``ceiling``: the picture's own silhouette seen at 64 px (framed at 64 px, each pixel
  enlarged 4 x 4) scored against itself at 256 px: what a fit exact at 64 px would reach;
- ``seconds`` of the whole call (wall), ``cpu_seconds`` (its processes' CPU time, the
  runs side by side on the cores included: a figure the machine's load does not change),
  the model and kind kept, the load average at the start;

then one ``summary`` line per split: mean NCC, mean ceiling, areas' range, how many fits are
within 0.7x-1.4x, bare trees fitted bare, the slowest fit. ``--sheet PATH`` draws every
picture's target beside its fit (``silhouettes.png`` of each fit) on one page.

    python benchmarks/make_mtree.py --out runs/mtree
    python benchmarks/mtree_fit.py --pictures runs/mtree --split held_out --out runs/mtree-fit \\
        --sheet docs/images/fitting_mtree_held_out.png
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import time
from pathlib import Path

import numpy as np

#: the issue's bounds on the fit's area over the picture's tree's
AREA_BOUNDS = (0.7, 1.4)


def ceiling(mask_path: Path) -> float:
    """The binary NCC at 256 px of the picture's own silhouette seen at 64 px."""
    from growsim.kernels.views import ncc
    from growsim.pictures.images import frame_silhouettes
    from growsim.pictures.reading import load_gray

    mask = load_gray(mask_path) < 0.5
    fine = frame_silhouettes(mask, None, 256, "radius")
    coarse = frame_silhouettes(mask, None, 64, "radius")
    up = np.kron(coarse[0], np.ones((4, 4), dtype=np.uint8))
    return float(ncc(up[None], fine[:1]))


def _cpu() -> float:
    """CPU seconds of this process and its finished children."""
    import resource

    own = resource.getrusage(resource.RUSAGE_SELF)
    kids = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime


def fit_one(picture: Path, out: Path, seed: int) -> dict:
    """Fit one picture with fit-image's defaults into ``out``; its row."""
    from growsim.fitting.fit import fit_image

    shutil.rmtree(out, ignore_errors=True)
    load = os.getloadavg()[0]
    t, cpu = time.perf_counter(), _cpu()
    r = fit_image(picture, out=out, seed=seed, progress=False)
    seconds, cpu = time.perf_counter() - t, _cpu() - cpu
    s = r.summary
    return {
        "ncc": round(r.ncc, 4),
        "area": round(s["area_ratio"]["front"], 3),
        "seconds": round(seconds, 1),
        "cpu_seconds": round(cpu, 1),
        "model": r.model,
        "leaves": s["leaves"]["chosen"],
        "models": {k: round(v, 4) for k, v in s["models"].items()},
        "load": round(load, 2),
        "fit": str(out),
    }


def summary(rows: list[dict], split: str) -> dict:
    """One split's figures."""
    areas = [r["area"] for r in rows]
    bare = [r for r in rows if not r["leafy"]]
    return {
        "kind": "summary",
        "split": split,
        "pictures": len(rows),
        "mean_ncc": round(float(np.mean([r["ncc"] for r in rows])), 4),
        "mean_ceiling": round(float(np.mean([r["ceiling"] for r in rows])), 4),
        "area_min": min(areas),
        "area_max": max(areas),
        "area_within": sum(AREA_BOUNDS[0] <= a <= AREA_BOUNDS[1] for a in areas),
        "bare_fitted_bare": f"{sum(r['leaves'] == 'bare' for r in bare)}/{len(bare)}",
        "max_seconds": max(r["seconds"] for r in rows),
        "mean_seconds": round(float(np.mean([r["seconds"] for r in rows])), 1),
        "max_cpu_seconds": max(r["cpu_seconds"] for r in rows),
        "mean_cpu_seconds": round(float(np.mean([r["cpu_seconds"] for r in rows])), 1),
    }


def sheet(rows: list[dict], path: Path) -> Path:
    """Every fit's ``silhouettes.png`` (target | fit), two to a row, with its figures."""
    from PIL import Image, ImageDraw, ImageFont

    font = ImageFont.load_default(size=16)  # readable at the page's width
    tiles = []
    for r in rows:
        im = Image.open(Path(r["fit"]) / "silhouettes.png").convert("RGB")
        im = im.resize((im.width // 2, im.height // 2))
        tile = Image.new("RGB", (im.width, im.height + 24), "white")
        tile.paste(im, (0, 0))
        label = f"{r['name']}: {r['model']} {r['leaves']}, NCC {r['ncc']:.3f}, area {r['area']:.2f}"
        ImageDraw.Draw(tile).text((6, im.height + 3), label, fill="black", font=font)
        tiles.append(tile)
    cols = 2
    w, h = tiles[0].size
    page = Image.new("RGB", (cols * w, -(-len(tiles) // cols) * h), "white")
    for i, im in enumerate(tiles):
        page.paste(im, ((i % cols) * w, (i // cols) * h))
    path.parent.mkdir(parents=True, exist_ok=True)
    page.convert("P", palette=Image.Palette.ADAPTIVE, colors=8).save(path, optimize=True)
    return path


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--pictures", default="runs/mtree", help="make_mtree.py's directory")
    ap.add_argument("--split", nargs="+", default=["discovery", "held_out"])
    ap.add_argument("--only", nargs="*", default=None, help="picture names")
    ap.add_argument("--out", default="runs/mtree-fit")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--sheet", default=None, help="PNG of every target beside its fit")
    a = ap.parse_args(argv)
    src = Path(a.pictures)
    index = json.loads((src / "index.json").read_text())
    rows_by = {s: [] for s in a.split}
    for pic in index["pictures"]:
        if pic["split"] not in rows_by or (a.only and pic["name"] not in a.only):
            continue
        row = {"kind": "fit", "name": pic["name"], "split": pic["split"],
               "shape": pic["shape"], "leafy": pic["leafy"]}  # fmt: skip
        row["ceiling"] = round(ceiling(src / f"{pic['name']}_mask.png"), 4)
        row.update(fit_one(src / f"{pic['name']}.jpg", Path(a.out) / pic["name"], a.seed))
        if not pic["leafy"]:
            row["bare_fitted_bare"] = row["leaves"] == "bare"
        print(json.dumps(row), flush=True)
        rows_by[pic["split"]].append(row)
    for split, rows in rows_by.items():
        if rows:
            print(json.dumps(summary(rows, split)), flush=True)
    if a.sheet:
        every = [r for rows in rows_by.values() for r in rows]
        print(json.dumps({"kind": "sheet", "path": str(sheet(every, Path(a.sheet)))}))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
