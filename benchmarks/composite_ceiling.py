"""How well could any segmentation do on the composites? (issue 41's IoU bars)

The composites of ``benchmarks/make_composites.py`` are judged by the IoU of the tree's
silhouette against the pixels the tree covers at least half. Thin twigs are one or two
pixels wide, so most of a bare tree's pixels are edge pixels, mixed with the background
and then blurred by the sensor's noise and the JPEG. This script measures the ceiling
that leaves: each composite is made again from its seed with what it was made of
(``make_composite(..., background=True)``: the picture without the tree, the tree's own
premultiplied colour and its coverage, in linear light), and each pixel of the photo as
saved is read by two oracles that know what no segmentation knows:

* **matting**: the background and the tree's colour at every pixel known, the pixel's
  coverage is its colour's projection onto the line from background to tree colour
  (linear light), and the silhouette is where that is at least one half; outside the
  tree's footprint the oracle says background. Only the noise and the JPEG stand between
  it and the true mask: no per-pixel method does better;
* **threshold**: the background known, the pixels differing from it by more than a
  threshold (Delta E, CIE 1976), the threshold chosen per picture with the true mask.

Also, for each picture, the IoU a silhouette one pixel too fat would score
(``edge_floor``, as ``photo_outdoor.py`` reports it), and with ``--results``
(``photo_outdoor.py``'s JSON for the same block) the tool's own IoU beside them.

    python benchmarks/composite_ceiling.py --composites tests/data/composites \\
        --results runs/b1.json --write benchmarks/results/composite_ceiling.jsonl
    python benchmarks/composite_ceiling.py --composites runs/composites_b2

Prints one JSON line per block (means, leafy and bare apart) and, with ``--rows``, one
per picture. The composites are made again (1-7 s each); the saved photo and mask are
checked to be the ones made again, byte for byte.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

#: thresholds tried for the oracle (Delta E)
THRESHOLDS = np.arange(0.5, 40.01, 0.5)


def oracle_iou(photo: np.ndarray, background: np.ndarray, truth: np.ndarray):
    """The threshold oracle: the best IoU against ``truth`` of the pixels of ``photo``
    (uint8 sRGB) differing from ``background`` (sRGB 0-255 floats) by more than a
    threshold, and that threshold.

    Examples
    --------
    >>> bg = np.full((20, 20, 3), 200.0); photo = bg.astype(np.uint8).copy()
    >>> photo[5:15, 9:11] = 60; truth = photo[..., 0] == 60
    >>> oracle_iou(photo, bg, truth)
    (1.0, 0.5)
    """
    from skimage.color import deltaE_cie76, rgb2lab

    d = deltaE_cie76(rgb2lab(photo / 255.0), rgb2lab(np.clip(background, 0, 255) / 255.0))
    best, at = -1.0, 0.0
    for t in THRESHOLDS:
        m = d > t
        v = float((m & truth).sum() / max((m | truth).sum(), 1))
        if v > best:
            best, at = v, float(t)
    return round(best, 4), at


def matting_iou(photo: np.ndarray, made: dict, truth: np.ndarray) -> float:
    """The IoU against ``truth`` of the matting oracle: ``photo`` (uint8 sRGB) read in
    linear light against ``made`` (``make_composite``'s: ``background``, ``tree``
    premultiplied, ``cover``); a pixel is tree where its projection onto the line from
    the background to the tree's colour is at least half way.

    Examples
    --------
    >>> bg = np.full((4, 4, 3), 0.5); tree = np.zeros((4, 4, 3)); cover = np.zeros((4, 4))
    >>> tree[1, :] = 0.1 * 0.8; cover[1, :] = 0.8          # a dark twig, 80 % covered
    >>> lin = tree + (1 - cover[..., None]) * bg
    >>> srgb = np.where(lin <= 0.0031308, 12.92 * lin, 1.055 * lin ** (1 / 2.4) - 0.055)
    >>> photo = np.round(255 * srgb).astype(np.uint8)
    >>> matting_iou(photo, {"background": bg, "tree": tree, "cover": cover}, cover >= 0.5)
    1.0
    """
    v = photo / 255.0
    obs = np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4)
    cover, bg = made["cover"], made["background"]
    on = cover > 0
    colour = np.where(on[..., None], made["tree"] / np.maximum(cover, 1e-12)[..., None], bg)
    line = colour - bg
    est = ((obs - bg) * line).sum(-1) / np.maximum((line * line).sum(-1), 1e-12)
    m = on & (est >= 0.5)
    return round(float((m & truth).sum() / max((m | truth).sum(), 1)), 4)


def main(argv=None) -> int:
    import make_composites as mc
    from photo_outdoor import edge_floor, read_mask

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--composites", default="tests/data/composites")
    ap.add_argument("--seed", type=int, default=None, help="the block's seed (index.json's)")
    ap.add_argument("--results", default=None, help="photo_outdoor.py's JSON for this block")
    ap.add_argument("--rows", action="store_true", help="print one line per picture too")
    ap.add_argument("--write", default=None, metavar="PATH", help="append the lines here")
    a = ap.parse_args(argv)
    src = Path(a.composites)
    index = json.loads((src / "index.json").read_text())
    seed = a.seed if a.seed is not None else index["seed"]
    specs = {s["name"]: s for s in mc.scene_specs(len(index["pictures"]), seed)}
    ours = {}
    if a.results:
        for r in json.loads(Path(a.results).read_text())["composites"]["rows"]:
            ours[r["name"]] = r.get("iou") if r.get("accepted") else None
    rows = []
    for pic in index["pictures"]:
        t = time.perf_counter()
        photo, truth, jpeg, _, made = mc.make_composite(
            specs[pic["name"]], index.get("supersample", mc.SUPERSAMPLE), background=True
        )
        same = jpeg == (src / pic["photo"]).read_bytes()
        saved = read_mask(src / pic["mask"])
        if not same or not np.array_equal(saved, truth):
            raise SystemExit(f"{pic['name']}: the composite made again differs from the saved one")
        best, at = oracle_iou(photo, 255.0 * mc.to_srgb(made["background"]), truth)
        row = {
            "name": pic["name"],
            "leafy": pic["leafy"],
            "matting_iou": matting_iou(photo, made, truth),
            "threshold_iou": best,
            "threshold": at,
            "edge_floor": edge_floor(truth),
            "ours": ours.get(pic["name"]),
            "seconds": round(time.perf_counter() - t, 1),
        }
        rows.append(row)
        if a.rows:
            print(json.dumps(row), flush=True)

    def mean(xs):
        xs = [x for x in xs if x is not None]
        return round(float(np.mean(xs)), 4) if xs else None

    summary = {"composites": str(src), "seed": seed, "pictures": len(rows)}
    for kind, leafy in (("leafy", True), ("bare", False)):
        part = [r for r in rows if r["leafy"] == leafy]
        accepted = [r for r in part if r["ours"] is not None]
        summary[kind] = {
            "matting_mean": mean([r["matting_iou"] for r in part]),
            "matting_min": min(r["matting_iou"] for r in part),
            "threshold_mean": mean([r["threshold_iou"] for r in part]),
            "edge_floor_mean": mean([r["edge_floor"] for r in part]),
            "ours_mean_accepted": mean([r["ours"] for r in accepted]),
            "matting_mean_same_pictures": mean([r["matting_iou"] for r in accepted]),
        }
    line = json.dumps(summary)
    print(line)
    if a.write:
        with open(a.write, "a") as f:
            f.write(line + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
