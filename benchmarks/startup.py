"""Start-up cost of a run: from the command to the first generation.

    python benchmarks/startup.py [--repeats 5] [CONFIG ...]

For each config (default: the four reference experiments) a fresh Python process is
started that imports growsim, runs the config through :func:`growsim.experiment.run`
and stops at the first generation (the callback returns True). Start-up is the time
from starting the process to the moment generation 0 begins (the callback's time minus
the generation's own ``seconds``): interpreter and imports, config loading and
validation, planning, building the objectives (target images included) and the GA.
``in_run_ms`` is the same measured from the call to ``run()`` (imports excluded).
Warm numba cache (one discarded run first). Prints JSON: the median over ``--repeats``
per config.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CONFIGS = ["quickstart", "honda_silhouette", "ifs_tree_fit", "ifs_tree_best"]

CHILD = r"""
import json, sys, time
t_call = None
from growsim.experiment import run
first = {}
def cb(ga, row):
    if not first:
        first["t"] = time.time() - float(row["seconds"])
    return True
t_call = time.time()
run(sys.argv[1], out=sys.argv[2], progress=False, callback=cb,
    overrides=["output.mesh=[]", "output.screenshots=[]", "output.plot=false"])
print(json.dumps({"first": first["t"], "call": t_call}))
"""


def once(config: Path) -> dict:
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.time()
        out = subprocess.run(
            [sys.executable, "-c", CHILD, str(config), os.path.join(tmp, "run")],
            capture_output=True,
            text=True,
            check=True,
        )
    rec = json.loads(out.stdout.strip().splitlines()[-1])
    return {
        "startup_ms": (rec["first"] - t0) * 1e3,
        "in_run_ms": (rec["first"] - rec["call"]) * 1e3,
    }


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("configs", nargs="*")
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args()
    paths = [Path(c) for c in args.configs] or [ROOT / "experiments" / f"{c}.toml" for c in CONFIGS]
    result = {"load_1min": round(os.getloadavg()[0], 2)}
    for path in paths:
        once(path)  # warm the numba cache
        runs = [once(path) for _ in range(args.repeats)]
        result[path.stem] = {
            k: round(statistics.median(r[k] for r in runs), 1) for k in ("startup_ms", "in_run_ms")
        }
    print(json.dumps(result, indent=1))


if __name__ == "__main__":
    main()
