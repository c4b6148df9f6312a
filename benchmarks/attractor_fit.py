"""Benchmark of ``growsim fit-image --model ifs2d`` on pictures of classic IFS attractors
drawn by another program (issue 27): every picture of ``benchmarks/make_attractors.py``'s
``index.json`` fitted with the defaults (no option but the model), one fit at a time.

Prints JSON lines: per picture ``{"kind": "fit", "name", "split", "ncc" (at the size
the fit chose, its own score), "size", "ncc_256" (the fitted code's attractor scored
against the picture framed at 256 px: the silhouette objective at 256, thin lines),
"area_256" (the fit's black pixels over the target's there), "seconds", "choices",
"n_maps", "maps_used", "truth_ncc", "truth_ncc_256"}`` (the code the picture was drawn from,
``index.json``'s ``table``, drawn with the fit's chaos-game points and scored the same way:
the ceiling the binary NCC of a point cloud allows), then ``{"kind": "summary", "split",
...}`` per split (mean and minimum NCC, mean seconds). Usage::

    python benchmarks/make_attractors.py --out runs/attractors
    python benchmarks/attractor_fit.py --pictures runs/attractors --out runs/attractor_fit
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np


def score_at(picture, params: dict, size: int = 256) -> tuple[float, float]:
    """``(NCC, area ratio)`` of the attractor of ``params`` (an ifs2d fit's ``fit.json``
    parameters) against ``picture`` read as ``fit-image`` reads a drawing (grey threshold,
    thin lines), both framed at ``size`` px."""
    from growsim.experiment import load_plan
    from growsim.fitting.setups import fit_config
    from growsim.models import ifs2d
    from growsim.objectives.silhouette import phenotype_views

    cfg = fit_config(picture, model="ifs2d", size=size, segmentation="threshold",
                     line_width="thin")  # fmt: skip
    objective = load_plan(cfg).objectives[0]
    plant = ifs2d.develop(params)
    ncc = float(objective.view_scores(plant)[0])
    fit = phenotype_views(plant, size, "thin", views=1)[0]
    area = float(np.count_nonzero(fit)) / max(float(np.count_nonzero(objective.target[0])), 1.0)
    return ncc, area


def maps_used(params: dict, least: float = 0.01) -> int:
    """How many maps of a fitted code draw at least ``least`` of its points."""
    p = [params[f"p_{k}"] for k in range(1, int(params["n_maps"]) + 1)]
    return int(sum(v >= least * sum(p) for v in p))


def main(argv=None) -> None:
    from growsim.fitting.fit import fit_image
    from growsim.models import ifs2d

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--pictures", default="runs/attractors")
    ap.add_argument("--out", default="runs/attractor_fit")
    ap.add_argument("--only", nargs="*", help="names to fit (default: all)")
    ap.add_argument("--model", default="ifs2d")
    args = ap.parse_args(argv)
    pictures = Path(args.pictures)
    rows = json.loads((pictures / "index.json").read_text())
    out = Path(args.out)
    results = []
    for row in rows:
        if args.only and row["name"] not in args.only:
            continue
        fit_dir = out / row["name"]
        if fit_dir.exists():
            import shutil

            shutil.rmtree(fit_dir)
        t0 = time.perf_counter()
        r = fit_image(pictures / row["file"], out=fit_dir, model=args.model, progress=False)
        seconds = time.perf_counter() - t0
        ncc256, area256 = score_at(pictures / row["file"], r.summary["params"])
        table = np.array(row["table"], dtype=np.float64)
        # the shifts within the model's bounds: the attractor scaled, its picture the same
        table[:, 4:6] /= max(1.0, float(np.abs(table[:, 4:6]).max()) / 4.0)
        iterations = r.summary["params"]["iterations"]
        truth = ifs2d.params_from_code(table, contraction=0.999, iterations=iterations)
        res = {
            "kind": "fit",
            "name": row["name"],
            "split": row["split"],
            "ncc": round(r.ncc, 4),
            "size": r.size,
            "ncc_256": round(ncc256, 4),
            "area_256": round(area256, 3),
            "seconds": round(seconds, 1),
            "n_maps": int(r.summary["params"].get("n_maps", 0)),
            "maps_used": maps_used(r.summary["params"]),
            "truth_ncc": round(score_at(pictures / row["file"], truth, r.size)[0], 4),
            "truth_ncc_256": round(score_at(pictures / row["file"], truth)[0], 4),
            "choices": {k: c["value"] for k, c in r.summary["choices"].items()},
        }
        results.append(res)
        print(json.dumps(res), flush=True)
    for split in sorted({r["split"] for r in results}):
        part = [r for r in results if r["split"] == split]
        print(json.dumps({
            "kind": "summary",
            "split": split,
            "pictures": len(part),
            "mean_ncc": round(float(np.mean([r["ncc"] for r in part])), 4),
            "min_ncc": round(float(np.min([r["ncc"] for r in part])), 4),
            "mean_ncc_256": round(float(np.mean([r["ncc_256"] for r in part])), 4),
            "min_ncc_256": round(float(np.min([r["ncc_256"] for r in part])), 4),
            "mean_seconds": round(float(np.mean([r["seconds"] for r in part])), 1),
        }))  # fmt: skip


if __name__ == "__main__":
    main()
