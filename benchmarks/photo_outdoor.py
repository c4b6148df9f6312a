"""The photo segmentation on outdoor photographs (issue 41): composites and real photos.

Two sets:

* **composites** (``--composites DIR``, default ``tests/data/composites``, made by
  ``benchmarks/make_composites.py``; ``--split discovery|held_out|all``): modular-tree
  trees on procedural skies (plain, gradients, haze, overcast, sunset, cumulus, stormy),
  grounds (grass, crop rows, soil, snow, road, slope, hills) and horizon clutter (hedge,
  treeline, fence, buildings), a second tree or a wood behind the crown, with their true
  masks. For each: :func:`growsim.pictures.photo.segment_photo` on the file, accepted or
  refused (the message; any other exception is reported as an ``error``), its IoU
  against the mask, the tree's area over the mask's, seconds, and the mask's
  ``edge_floor`` (:func:`edge_floor`: its IoU against itself grown by one pixel). Summary:
  how many accepted, mean IoU of the accepted (leafy and bare apart, and with refusals
  counted as IoU 0, with their mean edge floor), acceptance by sky, ground and clutter
  kind; for the hard ones (a second tree, a hedge, treeline or wood: ``second_tree`` or
  ``treeline`` in ``index.json``):
  ``right_or_refused``, segmented right (IoU >= :data:`RIGHT_IOU`) or refused, and how
  many were accepted wrong; a composite refused naming ``--box`` is segmented again with
  that hint as a user gives it (:func:`hint_box`): ``hint_iou`` (``with_the_hint``).
* **real photos** (``--photos DIR``, e.g. ``runs/photos``, never committed; the files'
  metadata from its ``sources.json`` when there): accepted or refused (the message),
  seconds, the tree's share of the picture; IoU when a ``<name>_mask.png`` (black tree
  on white) lies beside the photo. ``--fit``: ``growsim fit-image PHOTO --out DIR``
  (a subprocess, no other flags) on each accepted photo (``--fit-all``: on every photo,
  refused ones included, to see the tool's own message), reading its ``fit.json``: the
  NCC at 256 px, the area ratio of the fit (front), the model and leaves kept, and the
  wall seconds. ``--fit-composites`` does the same on the composites.

Prints one JSON document; ``--write`` also writes it to
``benchmarks/results/photo_outdoor.json`` (or ``--write PATH``). ``--sheet PATH`` draws
every picture beside its silhouette's outline (red; the true mask's in green on the
composites) and the fit (``silhouettes.png``) when run, with the verdict.

    python benchmarks/photo_outdoor.py --split all --sheet runs/photo_outdoor.png
    python benchmarks/photo_outdoor.py --split held_out --photos runs/photos --write
    python benchmarks/photo_outdoor.py --no-composites --photos runs/photos --fit \\
        --fit-out runs/photo_outdoor_fits --sheet runs/photo_outdoor_photos.png
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np

#: a hard composite (second tree, treeline) is segmented right at this IoU or more
RIGHT_IOU = 0.85
PHOTO_EXT = (".jpg", ".jpeg", ".png", ".webp", ".tif", ".tiff", ".bmp")
RESULTS = Path(__file__).resolve().parent / "results" / "photo_outdoor.json"


def iou(a: np.ndarray, b: np.ndarray) -> float:
    """Intersection over union of two boolean masks."""
    return float((a & b).sum() / max((a | b).sum(), 1))


def edge_floor(truth: np.ndarray) -> float:
    """The IoU of the true mask against itself grown by one pixel (8-connected): what a
    segmentation whose every edge lies one pixel out would score (thin twigs pay most)."""
    from scipy.ndimage import binary_dilation

    return round(iou(binary_dilation(truth, np.ones((3, 3), bool)), truth), 4)


def fit_to(mask: np.ndarray, shape) -> np.ndarray:
    """``mask`` resized (nearest) to ``shape`` when it differs (a segmentation that
    works on a reduced copy of a large photo may return its silhouette at that size)."""
    from PIL import Image

    if mask.shape == tuple(shape):
        return mask
    im = Image.fromarray(mask.astype(np.uint8) * 255).resize((shape[1], shape[0]), Image.NEAREST)
    return np.asarray(im) > 127


#: the margin of a hint's box around the true mask's bounds, a share of their size (a user
#: draws a box a little larger than the tree)
HINT_MARGIN = 0.05


def hint_box(truth: np.ndarray, photo: Path) -> tuple[int, int, int, int]:
    """``--box x0,y0,x1,y1`` around the true mask (:data:`HINT_MARGIN` wider each way), in
    the photo's pixels, clipped to the picture."""
    from PIL import Image

    w, h = Image.open(photo).size
    rows, cols = np.nonzero(truth)
    sy, sx = h / truth.shape[0], w / truth.shape[1]
    my = HINT_MARGIN * (rows.max() + 1 - rows.min())
    mx = HINT_MARGIN * (cols.max() + 1 - cols.min())
    return (max(0, int((cols.min() - mx) * sx)), max(0, int((rows.min() - my) * sy)),
            min(w, int(np.ceil((cols.max() + 1 + mx) * sx))),
            min(h, int(np.ceil((rows.max() + 1 + my) * sy))))  # fmt: skip


def read_mask(path: Path) -> np.ndarray:
    """A mask picture (black tree on white) as a boolean array, True on the tree."""
    from PIL import Image

    return np.asarray(Image.open(path).convert("L")) < 128


def segment(path: Path, name: str, box=None) -> tuple[dict, np.ndarray | None]:
    """``segment_photo`` on one file (``box``: the hint ``--box``, picture pixels): its
    row (accepted, or refused with the message) and the silhouette (None when refused)."""
    from growsim.errors import UserInputError
    from growsim.pictures.photo import segment_photo

    t = time.perf_counter()
    try:
        seg = segment_photo(path, name=name, box=box)
    except UserInputError as exc:
        return {
            "accepted": False,
            "refused": str(exc),
            "seconds": round(time.perf_counter() - t, 2),
        }, None
    except Exception as exc:  # a crash is not a refusal: reported apart
        return {
            "accepted": False,
            "error": f"{type(exc).__name__}: {exc}",
            "seconds": round(time.perf_counter() - t, 2),
        }, None
    row = {"accepted": True, "seconds": round(time.perf_counter() - t, 2)}
    tree = np.asarray(seg.tree, bool)
    row["tree_share"] = round(float(tree.mean()), 4)
    row["silhouette_size"] = [int(tree.shape[1]), int(tree.shape[0])]
    for key in ("method", "hint", "confidence"):
        if hasattr(seg, key):
            v = getattr(seg, key)
            row[key] = round(float(v), 3) if isinstance(v, float) else v
    return row, tree


def fit(path: Path, out: Path) -> dict:
    """``growsim fit-image PATH --out OUT`` (no other flags): its figures from fit.json."""
    import shutil

    shutil.rmtree(out, ignore_errors=True)
    out.parent.mkdir(parents=True, exist_ok=True)
    exe = Path(sys.executable).with_name("growsim")
    cmd = [str(exe) if exe.exists() else "growsim", "fit-image", str(path), "--out", str(out)]
    t = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True)
    row = {
        "fit_exit": p.returncode,
        "fit_seconds": round(time.perf_counter() - t, 1),
        "fit_dir": str(out),
    }
    if p.returncode != 0 or not (out / "fit.json").is_file():
        row["fit_message"] = (p.stderr.strip() or p.stdout.strip())[-600:]
        return row
    s = json.loads((out / "fit.json").read_text())
    ncc256 = [st.get("ncc") for st in s.get("stages", []) if st.get("size") == 256]
    row["ncc_256"] = round(float(ncc256[-1] if ncc256 else s["ncc"]), 4)
    if not ncc256 and s.get("size") != 256:
        row["ncc_size"] = s.get("size")
    area = s.get("area_ratio") or {}
    row["area_ratio"] = (
        round(float(area.get("front")), 3) if area.get("front") is not None else None
    )
    row["model"] = s.get("model")
    row["leaves"] = (s.get("leaves") or {}).get("chosen")
    return row


# ------------------------------------------------------------------------- composites


def run_composites(src: Path, split: str, only, do_fit: bool, fit_out: Path) -> dict:
    index = json.loads((src / "index.json").read_text())
    rows = []
    for pic in index["pictures"]:
        if split != "all" and pic["split"] != split:
            continue
        if only and pic["name"] not in only:
            continue
        truth = read_mask(src / pic["mask"])
        row = {
            "name": pic["name"],
            "split": pic["split"],
            "sky": pic["sky"],
            "ground": pic["ground"],
            "clutter": pic["clutter"],
            "hard": pic["hard"],
            "leafy": pic["leafy"],
            "size": [pic["width"], pic["height"]],
            "second_tree": pic["second_tree"],
            "treeline": pic["treeline"],
            "edge_floor": edge_floor(truth),
        }
        r, tree = segment(src / pic["photo"], pic["name"])
        row.update(r)
        if tree is not None:
            tree = fit_to(tree, truth.shape)
            row["iou"] = round(iou(tree, truth), 4)
            row["area_ratio"] = round(float(tree.sum() / max(truth.sum(), 1)), 3)
            row["missed"] = round(float((truth & ~tree).sum() / max(truth.sum(), 1)), 3)
            row["extra"] = round(float((tree & ~truth).sum() / max(truth.sum(), 1)), 3)
        if row["second_tree"] or row["treeline"]:
            row["right_or_refused"] = (not row["accepted"]) or row["iou"] >= RIGHT_IOU
        if "--box" in row.get("refused", ""):  # the hint the refusal names, as a user gives it
            box = hint_box(truth, src / pic["photo"])
            r2, tree2 = segment(src / pic["photo"], pic["name"], box=box)
            row["hint_box"] = list(box)
            row["hint_accepted"] = r2["accepted"]
            row["hint_method"] = r2.get("method")
            if tree2 is not None:
                row["hint_iou"] = round(iou(fit_to(tree2, truth.shape), truth), 4)
            else:
                row["hint_refused"] = r2.get("refused", r2.get("error"))
        if do_fit:
            row.update(fit(src / pic["photo"], fit_out / "composites" / pic["name"]))
        row["_photo"], row["_tree"], row["_truth"] = str(src / pic["photo"]), tree, truth
        print(json.dumps(_public(row)), file=sys.stderr, flush=True)
        rows.append(row)
    return {"dir": str(src), "split": split, "summary": composite_summary(rows), "rows": rows}


def _mean(xs):
    return round(float(np.mean(xs)), 4) if len(xs) else None


def composite_summary(rows) -> dict:
    acc = [r for r in rows if r["accepted"]]
    out = {
        "pictures": len(rows),
        "accepted": len(acc),
        "refused": sum("refused" in r for r in rows),
        "errors": sum("error" in r for r in rows),
        "mean_iou_accepted": _mean([r["iou"] for r in acc]),
        "mean_iou_refused_as_0": _mean([r.get("iou", 0.0) for r in rows]),
        "mean_seconds": _mean([r["seconds"] for r in rows]),
        "max_seconds": max((r["seconds"] for r in rows), default=None),
    }
    for leafy, label in ((True, "leafy"), (False, "bare")):
        sel = [r for r in rows if r["leafy"] == leafy]
        out[label] = {
            "pictures": len(sel),
            "accepted": sum(r["accepted"] for r in sel),
            "mean_iou_accepted": _mean([r["iou"] for r in sel if r["accepted"]]),
            "mean_iou_refused_as_0": _mean([r.get("iou", 0.0) for r in sel]),
            "mean_edge_floor": _mean([r["edge_floor"] for r in sel]),
        }
    hard = [r for r in rows if r["second_tree"] or r["treeline"]]
    out["hard"] = {
        "pictures": len(hard),
        "right_or_refused": sum(r["right_or_refused"] for r in hard),
        "segmented_right": sum(r["accepted"] and r["iou"] >= RIGHT_IOU for r in hard),
        "accepted_wrong": [r["name"] for r in hard if r["accepted"] and r["iou"] < RIGHT_IOU],
    }
    hinted = [r for r in rows if "hint_box" in r]
    out["with_the_hint"] = {
        "refused_naming_box": len(hinted),
        "accepted": sum(r["hint_accepted"] for r in hinted),
        "iou_at_least_0.85": sum(r.get("hint_iou", 0.0) >= RIGHT_IOU for r in hinted),
        "mean_iou_refused_as_0": _mean([r.get("hint_iou", 0.0) for r in hinted]),
    }
    easy = [r for r in rows if not (r["second_tree"] or r["treeline"])]
    out["plain_horizon"] = {
        "pictures": len(easy),
        "accepted": sum(r["accepted"] for r in easy),
        "iou_at_least_0.85": sum(r["accepted"] and r["iou"] >= RIGHT_IOU for r in easy),
    }
    for key in ("sky", "ground", "clutter", "hard"):
        kinds = {}
        for r in rows:
            k = kinds.setdefault(r[key], {"pictures": 0, "accepted": 0, "ious": []})
            k["pictures"] += 1
            k["accepted"] += int(r["accepted"])
            if r["accepted"]:
                k["ious"].append(r["iou"])
        out[f"by_{key}"] = {
            name: {
                "pictures": k["pictures"],
                "accepted": k["accepted"],
                "mean_iou_accepted": _mean(k["ious"]),
            }
            for name, k in sorted(kinds.items())
        }
    fits = [r for r in rows if "ncc_256" in r]
    if fits:
        out["fits"] = _fit_summary(fits)
    return out


def _fit_summary(fits) -> dict:
    areas = [r["area_ratio"] for r in fits if r.get("area_ratio") is not None]
    return {
        "fitted": len(fits),
        "mean_ncc_256": _mean([r["ncc_256"] for r in fits]),
        "area_min": min(areas, default=None),
        "area_max": max(areas, default=None),
        "area_within_0.7_1.4": sum(0.7 <= a <= 1.4 for a in areas),
        "mean_fit_seconds": _mean([r["fit_seconds"] for r in fits]),
        "max_fit_seconds": max(r["fit_seconds"] for r in fits),
    }


# ----------------------------------------------------------------------------- photos


def run_photos(src: Path, only, do_fit: bool, fit_all: bool, fit_out: Path) -> dict:
    sources = {}
    if (src / "sources.json").is_file():
        meta = json.loads((src / "sources.json").read_text())
        items = meta.get("photos", meta) if isinstance(meta, dict) else meta
        if isinstance(items, dict):
            items = [{"file": k, **v} for k, v in items.items()]
        sources = {m["file"]: m for m in items}
    files = sorted(
        p
        for p in src.iterdir()
        if p.suffix.lower() in PHOTO_EXT
        and not p.stem.endswith("_mask")
        and not p.name.startswith(".")
    )
    rows = []
    for p in files:
        if only and p.stem not in only and p.name not in only:
            continue
        m = sources.get(p.name, {})
        row = {"name": p.stem, "file": p.name}
        for key in ("shows", "leafy", "lone", "whole", "touching", "ordinary", "sky", "ground",
                    "licence", "repo"):  # fmt: skip
            if key in m:
                row[key] = m[key]
        r, tree = segment(p, p.name)
        row.update(r)
        mask = p.with_name(p.stem + "_mask.png")
        truth = read_mask(mask) if mask.is_file() else None
        if tree is not None and truth is not None:
            tree = fit_to(tree, truth.shape)
            row["iou"] = round(iou(tree, truth), 4)
            row["area_ratio_mask"] = round(float(tree.sum() / max(truth.sum(), 1)), 3)
        if do_fit and (row["accepted"] or fit_all):
            row.update(fit(p, fit_out / "photos" / p.stem))
        row["_photo"], row["_tree"], row["_truth"] = str(p), tree, truth
        print(json.dumps(_public(row)), file=sys.stderr, flush=True)
        rows.append(row)
    acc = [r for r in rows if r["accepted"]]
    summary = {
        "pictures": len(rows),
        "accepted": len(acc),
        "refused": sum("refused" in r for r in rows),
        "errors": sum("error" in r for r in rows),
        "mean_seconds": _mean([r["seconds"] for r in rows]),
        "max_seconds": max((r["seconds"] for r in rows), default=None),
    }
    lone = lone_summary(rows)
    if lone:
        summary["lone"] = lone
    with_mask = [r for r in acc if "iou" in r]
    if with_mask:
        summary["with_mask"] = len(with_mask)
        summary["mean_iou_accepted"] = _mean([r["iou"] for r in with_mask])
    fits = [r for r in rows if "ncc_256" in r]
    if fits:
        summary["fits"] = _fit_summary(fits)
    return {"dir": str(src), "summary": summary, "rows": rows}


def lone_summary(rows) -> dict:
    """The lone trees (``lone`` in ``sources.json``) accepted, in all and by how the
    picture shows them when it says (``whole``: the tree inside the frame, no edge cutting
    its crown or its foot; ``touching``: a wood, hedge, hill, building or another tree
    behind or against its crown; ``ordinary``: a photograph, not a print, a drawing or
    art): ``{"lone": [accepted, of], "whole": ..., "whole_clear": ...,
    "whole_touching": ..., "cut": ..., "odd": ...}``; empty when no row says ``lone``.

    Examples
    --------
    >>> rows = [{"lone": True, "whole": True, "touching": False, "ordinary": True,
    ...          "accepted": True},
    ...         {"lone": True, "whole": False, "touching": False, "ordinary": True,
    ...          "accepted": False}]
    >>> lone_summary(rows)["whole_clear"], lone_summary(rows)["cut"]
    ([1, 1], [0, 1])
    """
    lone = [r for r in rows if r.get("lone")]
    if not lone:
        return {}

    def count(sel):
        return [sum(bool(r["accepted"]) for r in sel), len(sel)]

    out = {"lone": count(lone)}
    if all("whole" in r for r in lone):
        usual = [r for r in lone if r.get("ordinary", True)]
        whole = [r for r in usual if r["whole"]]
        out["whole"] = count(whole)
        out["whole_clear"] = count([r for r in whole if not r.get("touching")])
        out["whole_touching"] = count([r for r in whole if r.get("touching")])
        out["cut"] = count([r for r in usual if not r["whole"]])
        out["odd"] = count([r for r in lone if not r.get("ordinary", True)])
    return out


# ------------------------------------------------------------------------------ sheet


def _outline(mask):
    from scipy import ndimage

    return mask & ~ndimage.binary_erosion(mask, border_value=1)


def _label(draw, xy, text, width_px):
    x, y = xy
    for i, line in enumerate(textwrap.wrap(text, max(10, width_px // 6))[:6]):
        draw.text((x + 3, y + 2 + 11 * i), line, fill="black")


def sheet(rows, path: Path, height: int = 220, cols: int = 2) -> Path:
    """Each picture, beside it the picture with the silhouette's outline (red; the true
    mask's in green) and the fit's ``silhouettes.png`` when there is one; the verdict."""
    from PIL import Image, ImageDraw
    from scipy import ndimage

    tiles = []
    for r in rows:
        im = Image.open(r["_photo"]).convert("RGB")
        k = height / im.height
        size = (max(1, round(im.width * k)), height)
        arr = np.asarray(im).copy()
        thick = max(1, int(np.rint(1 / k)))
        if r["_truth"] is not None:
            o = _outline(fit_to(r["_truth"], arr.shape[:2]))
            arr[ndimage.binary_dilation(o, iterations=thick - 1) if thick > 1 else o] = (0, 220, 0)
        if r["_tree"] is not None:
            o = _outline(fit_to(r["_tree"], arr.shape[:2]))
            arr[ndimage.binary_dilation(o, iterations=thick - 1) if thick > 1 else o] = (255, 0, 0)
        panels = [im.resize(size, Image.LANCZOS), Image.fromarray(arr).resize(size, Image.BOX)]
        fit_png = Path(r.get("fit_dir", "")) / "silhouettes.png"
        if r.get("fit_dir") and fit_png.is_file():
            f = Image.open(fit_png).convert("RGB")
            panels.append(f.resize((round(f.width * height / f.height), height), Image.LANCZOS))
        w = sum(p.width for p in panels) + 4 * (len(panels) - 1)
        tile = Image.new("RGB", (max(w, 360), height + 70), "white")
        x = 0
        for p in panels:
            tile.paste(p, (x, 0))
            x += p.width + 4
        if r["accepted"]:
            verdict = "accepted" + (f", IoU {r['iou']:.3f}" if "iou" in r else "")
            verdict += f", tree {100 * r['tree_share']:.1f}% of the picture"
        else:
            verdict = "REFUSED: " + r.get("refused", r.get("error", ""))
        if "ncc_256" in r:
            verdict += f"; fit NCC {r['ncc_256']:.3f}, area {r['area_ratio']}, {r['fit_seconds']} s"
        elif "fit_exit" in r:
            verdict += f"; fit-image exit {r['fit_exit']}"
        _label(
            ImageDraw.Draw(tile),
            (0, height),
            f"{r['name']} [{r.get('split', 'photo')}]: {verdict}",
            tile.width,
        )
        tiles.append(tile)
    if not tiles:
        raise SystemExit("no pictures for the sheet")
    cw = max(t.width for t in tiles)
    ch = max(t.height for t in tiles)
    page = Image.new("RGB", (cols * cw, math.ceil(len(tiles) / cols) * ch), "white")
    for i, t in enumerate(tiles):
        page.paste(t, ((i % cols) * cw, (i // cols) * ch))
    path.parent.mkdir(parents=True, exist_ok=True)
    page.save(path)
    return path


def _public(row) -> dict:
    return {k: v for k, v in row.items() if not k.startswith("_")}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--composites", default="tests/data/composites", help="make_composites' dir")
    ap.add_argument("--split", default="all", choices=["discovery", "held_out", "all"])
    ap.add_argument("--no-composites", action="store_true", help="skip the composites")
    ap.add_argument("--photos", default=None, help="a folder of real photos (runs/photos)")
    ap.add_argument("--only", nargs="*", default=None, help="picture names")
    ap.add_argument("--fit", action="store_true", help="fit-image on each accepted photo")
    ap.add_argument("--fit-all", action="store_true", help="fit-image on every photo")
    ap.add_argument("--fit-composites", action="store_true", help="fit-image on the composites")
    ap.add_argument("--fit-out", default="runs/photo_outdoor_fits")
    ap.add_argument("--sheet", default=None, metavar="PATH", help="contact sheet PNG")
    ap.add_argument(
        "--write",
        nargs="?",
        const=str(RESULTS),
        default=None,
        metavar="PATH",
        help="also write the JSON (default benchmarks/results/photo_outdoor.json)",
    )
    a = ap.parse_args(argv)
    result = {"load_average_start": [round(x, 2) for x in os.getloadavg()]}
    try:
        commit = subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"],
            capture_output=True,
            text=True,
            cwd=Path(__file__).resolve().parent,
        ).stdout.strip()
        dirty = subprocess.run(
            ["git", "status", "--porcelain", "growsim/pictures"],
            capture_output=True,
            text=True,
            cwd=Path(__file__).resolve().parent.parent,
        ).stdout.strip()
        result["commit"] = commit + ("+dirty(growsim/pictures)" if dirty else "")
    except OSError:
        pass
    import growsim.pictures.photo as photo_module

    result["segmentation_module"] = str(Path(photo_module.__file__).resolve())
    every = []
    fit_out = Path(a.fit_out)
    if not a.no_composites:
        comp = run_composites(Path(a.composites), a.split, a.only, a.fit_composites, fit_out)
        every += comp["rows"]
        result["composites"] = {**comp, "rows": [_public(r) for r in comp["rows"]]}
    if a.photos:
        ph = run_photos(Path(a.photos), a.only, a.fit or a.fit_all, a.fit_all, fit_out)
        every += ph["rows"]
        result["photos"] = {**ph, "rows": [_public(r) for r in ph["rows"]]}
    if a.sheet:
        result["sheet"] = str(sheet(every, Path(a.sheet)))
    result["load_average_end"] = [round(x, 2) for x in os.getloadavg()]
    text = json.dumps(result, indent=1)
    print(text)
    if a.write:
        Path(a.write).parent.mkdir(parents=True, exist_ok=True)
        Path(a.write).write_text(text + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
