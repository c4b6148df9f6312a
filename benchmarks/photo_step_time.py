"""The seconds one step of the photo segmentation adds to it: the tree below the horizon
learned from the photo (``--step learned_below``, :mod:`growsim.pictures.learned`; give
photographs whose silhouette ends along the horizon, where it runs) or the trunk carried
down along its edges (``--step traced_trunk``, :func:`growsim.pictures.foot.traced_trunk`)
or the flat pieces trimmed off the trunk's foot (``--step trim_foot``,
:func:`growsim.pictures.foot.trim_foot`).
Each photograph is segmented with and without the step, in turn, in one process, and the
seconds spent inside the step itself are summed (``inside``: what the difference of two
noisy totals cannot show for a short step). Prints JSON.

    python benchmarks/photo_step_time.py runs/photos_b4/*.jpg [--step traced_trunk]
        [--write results.json]
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import sys
import time

import numpy as np

import growsim.pictures.photo as photo
from growsim.errors import UserInputError

#: each step, and what stands for it when it is left out
STEPS = {
    "learned_below": lambda rgb, tree, low, *rest: low,
    "traced_trunk": lambda rgb, tree, under, keep: np.zeros_like(tree),
    "trim_foot": lambda tree: tree,
}


def _seconds(path, step, how) -> tuple[float, float] | None:
    """The segmentation's seconds and those spent inside ``how`` standing for ``step``."""
    inside = [0.0]

    def timed(*args):
        t = time.perf_counter()
        try:
            return how(*args)
        finally:
            inside[0] += time.perf_counter() - t

    setattr(photo, step, timed)
    t = time.perf_counter()
    try:
        photo.segment_photo(path)
    except UserInputError:
        return None
    return time.perf_counter() - t, inside[0]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], fromfile_prefix_chars="@")
    ap.add_argument("photos", nargs="+")
    ap.add_argument("--step", choices=sorted(STEPS), default="learned_below")
    ap.add_argument("--write", default=None, help="also write the JSON to this file")
    args = ap.parse_args()
    step = getattr(photo, args.step)
    rows = []
    for path in args.photos:
        _seconds(path, args.step, step)  # warm: imports, numba
        off = _seconds(path, args.step, STEPS[args.step])
        on = _seconds(path, args.step, step)
        if off is not None and on is not None:
            rows.append({"photo": os.path.basename(path), "without": round(off[0], 2),
                         "with": round(on[0], 2), "added": round(on[0] - off[0], 2),
                         "inside": round(on[1], 3)})  # fmt: skip
    added = sorted(r["added"] for r in rows)
    inside = sorted(r["inside"] for r in rows)
    out = {
        "machine": f"2-core VM, load {os.getloadavg()[0]:.1f}",
        "date": datetime.date.today().isoformat(),
        "step": args.step,
        "command": "`python " + " ".join(["benchmarks/photo_step_time.py", *sys.argv[1:]]) + "`",
        "photos": len(rows),
        "rows": rows,
        "added_min": added[0] if added else None,
        "added_median": added[len(added) // 2] if added else None,
        "added_max": added[-1] if added else None,
        "with_max": max((r["with"] for r in rows), default=None),
        "inside_min": inside[0] if inside else None,
        "inside_median": inside[len(inside) // 2] if inside else None,
        "inside_max": inside[-1] if inside else None,
    }
    text = json.dumps(out, indent=1)
    print(text)
    if args.write:
        with open(args.write, "w") as f:
            f.write(text + "\n")


if __name__ == "__main__":
    main()
