"""The seconds the learned step (``growsim.pictures.learned.learned_below``) adds to a
photo's segmentation, on photographs whose silhouette ends along the horizon (where it
runs): each segmented with and without it, in turn, in one process. Prints JSON.

    python benchmarks/learned_below_time.py runs/photos_b4/*.jpg [--write results.json]
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import sys
import time

import growsim.pictures.photo as photo
from growsim.errors import UserInputError


def _seconds(path, learned) -> float | None:
    photo.learned_below = learned
    t = time.perf_counter()
    try:
        photo.segment_photo(path)
    except UserInputError:
        return None
    return time.perf_counter() - t


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], fromfile_prefix_chars="@")
    ap.add_argument("photos", nargs="+")
    ap.add_argument("--write", default=None, help="also write the JSON to this file")
    args = ap.parse_args()
    learned = photo.learned_below
    rows = []
    for path in args.photos:
        _seconds(path, learned)  # warm: imports, numba
        off = _seconds(path, lambda rgb, tree, low, *rest: low)
        on = _seconds(path, learned)
        if off is not None and on is not None:
            rows.append({"photo": os.path.basename(path), "without": round(off, 2),
                         "with": round(on, 2), "added": round(on - off, 2)})  # fmt: skip
    added = sorted(r["added"] for r in rows)
    out = {
        "machine": f"2-core VM, load {os.getloadavg()[0]:.1f}",
        "date": datetime.date.today().isoformat(),
        "command": "`python " + " ".join(["benchmarks/learned_below_time.py", *sys.argv[1:]]) + "`",
        "photos": len(rows),
        "rows": rows,
        "added_min": added[0] if added else None,
        "added_median": added[len(added) // 2] if added else None,
        "added_max": added[-1] if added else None,
        "with_max": max((r["with"] for r in rows), default=None),
    }
    text = json.dumps(out, indent=1)
    print(text)
    if args.write:
        with open(args.write, "w") as f:
            f.write(text + "\n")


if __name__ == "__main__":
    main()
