"""Fit trees to photos of trees: segmentation and fit quality, and their time.

For each test picture of ``benchmarks/make_photos.py`` (JPEG renders of growsim trees on
a ground plane under a sky, bare and leafy): the photo segmentation's IoU against the
true silhouette known from the render, then ``growsim fit-image PICTURE --model M`` from
that one picture (the picture's own model; coarse to fine, 64 -> 128 -> 256 px; a bare and
a leafy tree fitted, the better kept, ``--leaves auto``), and the fit's NCC against the
segmented silhouette at every stage, with seconds, and the picture's own tree scored the
same way (what a perfect search would reach). ``--extra`` adds the pictures made after the
segmentation was settled (``EXTRA_PICTURES``, reported apart); ``--random N`` with
``--segmentation-only`` adds N pictures drawn at random (``random_pictures``: other
species, arrangements, skies and bark, reported apart); ``--supersample``,
``--mix``, ``--lens-blur`` set the pictures' camera (``make_photos.py``); ``--arrange``, ``--blur``,
``--restarts`` are passed to ``fit-image`` (``--arrange 0 --blur 0``: the fit before the
arrangement search and the blurred score). Prints JSON.

    python benchmarks/photo_fit.py --out runs/photo-bench --extra
    python benchmarks/photo_fit.py --extra --figures cherry_leafy docs/images
    python benchmarks/photo_fit.py --extra --segmentation-figure docs/images
    python benchmarks/photo_fit.py --only zelkova_bare --ifs-evaluations 5000
    python benchmarks/photo_fit.py --out runs/photo-before --extra --arrange 0 --blur 0
    python benchmarks/photo_fit.py --extra --segmentation-only --supersample 3 --mix srgb
    python benchmarks/photo_fit.py --extra --segmentation-only --random 12

``comparison_figure`` draws the fits of two such runs side by side
(``docs/images/fitting_arrangement.png``).
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

from make_photos import (
    EXTRA_PICTURES,
    PICTURES,
    add_camera_options,
    camera_of,
    make_photo,
    plant_of,
    random_pictures,
    true_colours,
    write_set,
)


def iou(a: np.ndarray, b: np.ndarray) -> float:
    """Intersection over union of two boolean masks."""
    return float((a & b).sum() / max((a | b).sum(), 1))


def segmentation_table(pictures, camera: dict, limit: bool = True, apart=()) -> dict:
    """The photo segmentation alone: each picture made with ``camera``
    (:func:`make_photo`'s ``supersample``, ``blur``, ``linear``), its IoU against the true
    silhouette, and (``limit``) the IoU of the per-pixel decision at half coverage with
    the true colours (:func:`true_colours`: each pixel unmixed against the tree's and the
    background's own colours, so the JPEG's noise and the blur are all that is left);
    the mean and the least of both (of the pictures named in ``apart`` apart, as
    ``random_mean_iou`` ...), and the segmentation's seconds."""
    from growsim.pictures.photo import segment_photo, srgb_to_linear, unmix

    rows = []
    for pic in pictures:
        rgb8, truth, _ = make_photo(pic, **camera)
        t = time.perf_counter()
        seg = segment_photo(rgb8 / 255.0, name=pic.name)
        row = {"picture": pic.name, "iou": round(iou(seg.tree, truth), 4),
               "seconds": round(time.perf_counter() - t, 3)}  # fmt: skip
        if limit:
            tree, back = true_colours(pic, supersample=camera["supersample"],
                                      linear=camera["linear"])  # fmt: skip
            seen = srgb_to_linear(rgb8 / 255.0) if camera["linear"] else rgb8 / 255.0
            best = (unmix(seen, back, tree) >= 0.5) & (np.linalg.norm(tree - back, axis=-1) > 0.03)
            row["limit"] = round(iou(best, truth), 4)
        rows.append(row)
        print(json.dumps(row), file=sys.stderr)
    out = {"camera": camera, "pictures": rows}
    for prefix, sel in (("", [r for r in rows if r["picture"] not in apart]),
                        ("random_", [r for r in rows if r["picture"] in apart])):  # fmt: skip
        for key in ("iou", "limit") if limit and sel else ("iou",) if sel else ():
            out[f"{prefix}mean_{key}"] = round(float(np.mean([r[key] for r in sel])), 4)
            out[f"{prefix}min_{key}"] = round(float(np.min([r[key] for r in sel])), 4)
    out["load_average"] = os.getloadavg()
    return out


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


def error_figure(photos, dest, names, height: int = 420) -> Path:
    """``photo_segmentation.png`` in ``dest``: for each picture of ``names`` (in the
    directory ``photos``, with its ``_truth.png``), its crop around the tree with the
    segmentation's errors: black where segmentation and truth agree, red the tree pixels
    missed, blue the background taken for tree; the pictures side by side, each scaled to
    ``height`` pixels (nearest neighbour, so single pixels stay visible)."""
    from PIL import Image

    from growsim.files import atomic_write
    from growsim.pictures.photo import load_rgb, segment_photo

    panels = []
    for name in names:
        path = Path(photos) / f"{name}.jpg"
        truth = np.asarray(Image.open(Path(photos) / f"{name}_truth.png")) < 128
        tree = segment_photo(path).tree
        out = 0.35 * load_rgb(path) + 0.65
        out[truth & tree] = 0.0
        out[truth & ~tree] = (1.0, 0.0, 0.0)
        out[~truth & tree] = (0.0, 0.2, 1.0)
        rows, cols = np.nonzero(truth | tree)
        crop = out[max(rows.min() - 4, 0) : rows.max() + 5, max(cols.min() - 4, 0) : cols.max() + 5]
        im = Image.fromarray(np.round(255 * crop).astype(np.uint8))
        k = height / im.height
        panels.append(im.resize((max(1, round(im.width * k)), height), Image.NEAREST))
    sheet = Image.new(
        "RGB", (sum(p.width for p in panels) + 8 * (len(panels) - 1), height), "white"
    )
    x = 0
    for p in panels:
        sheet.paste(p, (x, 0))
        x += p.width + 8
    path = Path(dest) / "photo_segmentation.png"
    atomic_write(path, lambda fh: sheet.save(fh, format="PNG"))
    return path


def comparison_figure(fits, before, dest, names) -> Path:
    """``fitting_arrangement.png`` in ``dest``: for each picture of ``names`` one row of
    three silhouettes at the final size: the target, the fit of the run in ``before`` (a
    ``photo_fit.py --out`` directory, e.g. with ``--arrange 0 --blur 0``) and the fit of
    the run in ``fits``, each with its NCC; cut from the fits' ``silhouettes.png``."""
    from PIL import Image, ImageDraw

    from growsim.files import atomic_write

    rows = []
    for name in names:
        new, old = Path(fits) / "fits" / name, Path(before) / "fits" / name
        ims = [Image.open(d / "silhouettes.png").convert("RGB") for d in (new, old)]
        w = ims[0].width // 2
        ncc = [json.loads((d / "fit.json").read_text())["ncc"] for d in (old, new)]
        panels = [ims[0].crop((0, 0, w, ims[0].height)), ims[1].crop((w, 0, 2 * w, ims[1].height)),
                  ims[0].crop((w, 0, 2 * w, ims[0].height))]  # fmt: skip
        labels = [f"{name}: target", f"before: NCC {ncc[0]:.3f}", f"arranged: NCC {ncc[1]:.3f}"]
        row = Image.new("RGB", (3 * w + 16, ims[0].height), "white")
        for k, (panel, label) in enumerate(zip(panels, labels)):
            row.paste(panel, (k * (w + 8), 0))
            draw = ImageDraw.Draw(row)
            draw.rectangle((k * (w + 8), 0, k * (w + 8) + w - 1, 12), fill="white")
            draw.text((k * (w + 8) + 2, 0), label, fill="black")
        rows.append(row)
    sheet = Image.new("RGB", (rows[0].width, sum(r.height for r in rows) + 8 * (len(rows) - 1)),
                      "white")  # fmt: skip
    y = 0
    for r in rows:
        sheet.paste(r, (0, y))
        y += r.height + 8
    sheet = sheet.resize((sheet.width // 2, sheet.height // 2), Image.LANCZOS)
    path = Path(dest) / "fitting_arrangement.png"
    atomic_write(path, lambda fh: sheet.save(fh, format="PNG"))
    return path


def main(argv=None) -> int:
    from PIL import Image

    from growsim.errors import GrowsimError
    from growsim.fitting import fit_image
    from growsim.objectives.silhouette import SilhouetteObjective
    from growsim.pictures.photo import segment_photo

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
        "--arrange", type=int, default=None, help="fit-image --arrange (default: the model's)"
    )
    ap.add_argument(
        "--blur", type=float, default=None, help="fit-image --blur (default: the model's)"
    )
    ap.add_argument(
        "--restarts", type=int, default=None, help="fit-image --restarts (default: the model's)"
    )
    ap.add_argument(
        "--extra", action="store_true",
        help="also the EXTRA_PICTURES (made after the segmentation was tuned), reported apart",
    )  # fmt: skip
    ap.add_argument(
        "--figures", nargs=2, default=None, metavar=("PICTURE", "DIR"),
        help="write the worked example's images of PICTURE's fit into DIR (docs/images)",
    )  # fmt: skip
    ap.add_argument(
        "--segmentation-figure", default=None, metavar="DIR",
        help="write photo_segmentation.png (the errors of the two worst segmentations) into DIR",
    )  # fmt: skip
    ap.add_argument(
        "--random", type=int, default=0, metavar="N",
        help="with --segmentation-only: also N random pictures (make_photos.random_pictures), "
        "reported apart (random_mean_iou ...)",
    )  # fmt: skip
    ap.add_argument(
        "--segmentation-only", action="store_true",
        help="only the segmentation's IoU and its per-pixel limit (no fits, no files)",
    )  # fmt: skip
    add_camera_options(ap)
    a = ap.parse_args(argv)  # fmt: skip
    out = Path(a.out)
    ap_pics = PICTURES + (EXTRA_PICTURES if a.extra else ())
    pics = [p for p in ap_pics if a.only is None or p.name in a.only]
    if a.segmentation_only:
        drawn = [p for p in random_pictures(a.random) if a.only is None or p.name in a.only]
        table = segmentation_table(pics + drawn, camera_of(a), apart={p.name for p in drawn})
        print(json.dumps(table, indent=1))
        return 0
    rows = write_set(out / "photos", pics, **camera_of(a))
    results = []
    for pic, row in zip(pics, rows):
        truth = np.asarray(Image.open(row["truth"])) < 128
        t = time.perf_counter()
        seg = segment_photo(row["photo"])
        seg_seconds = time.perf_counter() - t
        # the picture's own tree against the same segmented silhouette: what a perfect
        # search would reach at each size
        plant = plant_of(pic)
        true_tree = {
            str(s): round(
                SilhouetteObjective(front=row["photo"], views="front", segmentation="photo",
                                    line_width="radius", size=s)(plant), 4)
            for s in (int(v) for v in a.sizes.split(","))
        }  # fmt: skip
        fit_dir = out / "fits" / row["name"]
        budget = a.ifs_evaluations if row["model"] == "ifs3d" else a.honda_evaluations
        try:
            fit = fit_image(row["photo"], out=fit_dir, model=row["model"], seed=a.seed,
                            sizes=a.sizes, leaves=a.leaves, evaluations=budget,
                            arrange=a.arrange, blur=a.blur, restarts=a.restarts,
                            progress=False).summary  # fmt: skip
        except GrowsimError as exc:  # a picture refused: reported, the others go on
            print(f"{row['name']}: {exc}", file=sys.stderr)
            fit = {}
        results.append(
            {
                "picture": row["name"],
                "model": row["model"],
                "iou": round(iou(seg.tree, truth), 4),
                "segmentation_seconds": round(seg_seconds, 3),
                "ncc": fit.get("ncc"),
                # the NCC at the end of each size (after its arrangement, if any)
                "ncc_by_size": {str(s["size"]): round(s["ncc"], 4) for s in fit.get("stages", [])},
                "stages": [
                    {k: (round(v, 4) if isinstance(v, float) else v) for k, v in st.items()}
                    for st in fit.get("stages", [])
                ],
                "seconds": fit.get("seconds"),
                "true_tree": true_tree,
                "seed": fit.get("params", {}).get("seed"),
                "picture_seed": int(plant.meta["params"].get("seed", -1)),
                "leaves": fit.get("params", {}).get("leaves"),
                "leaves_chosen": fit.get("leaves", {}).get("chosen"),
                "ncc_by_leaves": {
                    k: round(v, 4) for k, v in fit.get("leaves", {}).get("ncc", {}).items()
                },
            }
        )
        print(json.dumps(results[-1]), file=sys.stderr)

    def means(rs):
        return {
            "names": [r["picture"] for r in rs],
            "mean_iou": round(float(np.mean([r["iou"] for r in rs])), 4),
            "min_iou": round(float(np.min([r["iou"] for r in rs])), 4),
            "mean_ncc_final": round(float(np.mean([r["ncc"] for r in rs])), 4),
            "mean_ncc_by_size": {
                size: round(float(np.mean([r["ncc_by_size"][size] for r in rs])), 4)
                for size in rs[0]["ncc_by_size"]
            },
            "mean_true_tree": {
                size: round(float(np.mean([r["true_tree"][size] for r in rs])), 4)
                for size in rs[0]["true_tree"]
            },
            "mean_seconds": round(float(np.mean([r["seconds"] for r in rs])), 1),
        }

    main_set = [r for r in results if r["picture"] in {p.name for p in PICTURES}]
    extra = [r for r in results if r not in main_set]
    summary = {
        "pictures": results,
        **(means(main_set) if main_set else {}),
        "extra": means(extra) if extra else None,
        "camera": camera_of(a),
        "load_average": os.getloadavg(),
    }
    print(json.dumps(summary, indent=1))
    if a.figures is not None:
        figures(out / "fits" / a.figures[0], a.figures[1])
    if a.segmentation_figure is not None:
        # the two pictures the segmentation reads worst
        worst = sorted(results, key=lambda r: r["iou"])[:2]
        error_figure(out / "photos", a.segmentation_figure, [r["picture"] for r in worst], 830)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
