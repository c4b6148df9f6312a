"""Start-up cost of a run: from the command to the first generation.

    python benchmarks/startup.py [--repeats 5] [--baseline DIR] [CONFIG ...]

For each config (default: the four reference experiments) a fresh Python process is
started that imports growsim, runs the config through :func:`growsim.experiment.run`
and stops at the first generation (the callback returns True). Start-up is the time
from starting the process to the moment generation 0 begins (the callback's time minus
the generation's own ``seconds``): interpreter and imports, config loading and
validation, planning, building the objectives (target images included) and the GA.
``in_run_ms`` is the same measured from the call to ``run()`` (imports excluded).
Warm numba cache (one discarded run first). Prints JSON: the median over ``--repeats``
per config. ``--baseline DIR``: also run the growsim tree in ``DIR`` (e.g. a git worktree
of an older commit, put first on ``PYTHONPATH``), alternating with this one run by run so
both see the same machine load, and report the ratio.
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


def once(config: Path, tree: str | None = None) -> dict:
    env = dict(os.environ)
    config = config.resolve()
    if tree is not None:
        env["PYTHONPATH"] = os.pathsep.join([tree, env.get("PYTHONPATH", "")]).rstrip(os.pathsep)
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.time()
        out = subprocess.run(
            [sys.executable, "-c", CHILD, str(config), os.path.join(tmp, "run")],
            capture_output=True,
            text=True,
            check=True,
            env=env,
            cwd=tmp,  # not this checkout: ``python -c`` puts the working directory first
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
    ap.add_argument("--baseline", metavar="DIR", help="another growsim tree to compare with")
    args = ap.parse_args()
    names = args.configs or CONFIGS  # a path, or the name of a shipped experiment
    paths = [Path(c) if Path(c).is_file() else ROOT / "experiments" / f"{c}.toml" for c in names]
    trees = {"this": str(ROOT)}
    if args.baseline:
        trees["baseline"] = str(Path(args.baseline).resolve())
    result: dict = {"load_1min_before": round(os.getloadavg()[0], 2)}
    keys = ("startup_ms", "in_run_ms")
    for path in paths:
        # each tree runs its own copy of a shipped experiment (configs may have changed form)
        own = {
            name: Path(tree) / "experiments" / path.name
            if path.parent == ROOT / "experiments"
            and (Path(tree) / "experiments" / path.name).is_file()
            else path
            for name, tree in trees.items()
        }
        for name, tree in trees.items():
            once(own[name], tree)  # warm the numba cache
        runs: dict[str, list[dict]] = {name: [] for name in trees}
        for _ in range(args.repeats):
            for name, tree in trees.items():
                runs[name].append(once(own[name], tree))
        row = {
            name: {k: round(statistics.median(r[k] for r in rs), 1) for k in keys}
            for name, rs in runs.items()
        }
        if args.baseline:
            row["startup_ratio"] = round(
                row["this"]["startup_ms"] / row["baseline"]["startup_ms"], 3
            )
        result[path.stem] = row
    result["load_1min_after"] = round(os.getloadavg()[0], 2)
    print(json.dumps(result, indent=1))


if __name__ == "__main__":
    main()
