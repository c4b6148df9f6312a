"""Fit trees to photos of trees: segmentation and fit quality, and their time.

For each test picture of ``benchmarks/make_photos.py`` (JPEG renders of growsim trees on
a ground plane under a sky, bare and leafy): the photo segmentation's IoU against the
true silhouette known from the render, then ``growsim fit-image PICTURE --model M`` from
that one picture (the picture's own model; coarse to fine, 64 -> 128 -> 256 px; a bare and
a leafy tree fitted, the better kept, ``--leaves auto``), and the fit's NCC against the
segmented silhouette at every stage, with seconds. Prints JSON.

    python benchmarks/photo_fit.py --out runs/photo-bench
    python benchmarks/photo_fit.py --only zelkova_bare --ifs-evaluations 5000
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from make_photos import PICTURES, write_set


def iou(a: np.ndarray, b: np.ndarray) -> float:
    """Intersection over union of two boolean masks."""
    return float((a & b).sum() / max((a | b).sum(), 1))


def figures(fit_dir, dest) -> list[Path]:
    """The worked example's images of docs/models/fitting.md from one fit's directory:
    ``fitting_photo.png`` (the picture and the silhouette found in it, side by side, at
    half size) and ``fitting_silhouettes.png`` (target and fit at the final size)."""
    from PIL import Image

    from growsim.files import atomic_write

    fit_dir, dest = Path(fit_dir), Path(dest)
    fit = json.loads((fit_dir / "fit.json").read_text())
    photo = Image.open(fit["pictures"]["front"]).convert("RGB")
    seg = Image.open(fit_dir / "segmentation_front.png").convert("RGB")
    w, h = photo.size
    both = Image.new("RGB", (w, h))
    both.paste(photo.resize((w // 2, h // 2), Image.LANCZOS), (0, 0))
    both.paste(seg.resize((w // 2, h // 2), Image.LANCZOS), (w // 2, 0))
    both = both.crop((0, 0, w, h // 2))
    paths = [dest / "fitting_photo.png", dest / "fitting_silhouettes.png"]
    atomic_write(paths[0], lambda fh: both.save(fh, format="PNG"))
    sil = Image.open(fit_dir / "silhouettes.png")
    atomic_write(paths[1], lambda fh: sil.save(fh, format="PNG"))
    return paths


def main(argv=None) -> int:
    from PIL import Image

    from growsim.cli import main as cli
    from growsim.photo import segment_photo

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="runs/photo-bench")
    ap.add_argument("--only", nargs="*", default=None, help="picture names")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument(
        "--ifs-evaluations",
        type=int,
        default=10_000,
        help="first-stage budget of the ifs3d fits (drawn at their radius)",
    )
    ap.add_argument("--honda-evaluations", type=int, default=None)
    ap.add_argument("--sizes", default="64,128,256")
    ap.add_argument("--leaves", default="auto", help="fit-image --leaves (default auto)")
    ap.add_argument(
        "--figures", nargs=2, default=None, metavar=("PICTURE", "DIR"),
        help="write the worked example's images of PICTURE's fit into DIR (docs/images)",
    )  # fmt: skip
    a = ap.parse_args(argv)  # fmt: skip
    out = Path(a.out)
    pics = [p for p in PICTURES if a.only is None or p.name in a.only]
    rows = write_set(out / "photos", pics)
    results = []
    for row in rows:
        truth = np.asarray(Image.open(row["truth"])) < 128
        t = time.perf_counter()
        seg = segment_photo(row["photo"])
        seg_seconds = time.perf_counter() - t
        fit_dir = out / "fits" / row["name"]
        args = ["fit-image", row["photo"], "--model", row["model"], "--out", str(fit_dir)]
        args += ["--quiet", "--seed", str(a.seed), "--sizes", a.sizes, "--leaves", a.leaves]
        budget = a.ifs_evaluations if row["model"] == "ifs3d" else a.honda_evaluations
        if budget is not None:
            args += ["--evaluations", str(budget)]
        code = cli(args)
        fit = json.loads((fit_dir / "fit.json").read_text()) if code == 0 else {}
        results.append(
            {
                "picture": row["name"],
                "model": row["model"],
                "iou": round(iou(seg.tree, truth), 4),
                "segmentation_seconds": round(seg_seconds, 3),
                "ncc": fit.get("ncc"),
                "ncc_by_size": {str(s["size"]): round(s["ncc"], 4) for s in fit.get("stages", [])},
                "seconds": fit.get("seconds"),
                "leaves": fit.get("params", {}).get("leaves"),
                "leaves_chosen": fit.get("leaves", {}).get("chosen"),
                "ncc_by_leaves": {
                    k: round(v, 4) for k, v in fit.get("leaves", {}).get("ncc", {}).items()
                },
            }
        )
        print(json.dumps(results[-1]), file=sys.stderr)
    summary = {
        "pictures": results,
        "mean_iou": round(float(np.mean([r["iou"] for r in results])), 4),
        "mean_ncc_final": round(float(np.mean([r["ncc"] for r in results])), 4),
        "mean_ncc_by_size": {
            size: round(float(np.mean([r["ncc_by_size"][size] for r in results])), 4)
            for size in results[0]["ncc_by_size"]
        },
        "mean_seconds": round(float(np.mean([r["seconds"] for r in results])), 1),
        "load_average": os.getloadavg(),
    }
    print(json.dumps(summary, indent=1))
    if a.figures is not None:
        figures(out / "fits" / a.figures[0], a.figures[1])
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
