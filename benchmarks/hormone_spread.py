"""How far apart repeated runs of one environment end (issue 29's "runs that converge").

For one experiment config, one sweep variant (``--variant``, default: the config as it
is) and a block of seeds, runs the experiment once per seed (``--set`` overrides, e.g. a
GA setup to try) and prints one JSON line per run (best fitness, the run's numeric
measures, seconds) and a ``summary`` line: the coefficient of variation (sample standard
deviation over the mean) of the best fitness and of each measure across the seeds, the
mean and range of the best fitness, and the runs' mean seconds (one process each, run
one after the other on ``--jobs`` processes).

    python benchmarks/hormone_spread.py experiments/hormone_3d.toml --seeds 101-108 \\
        --variant ample --out runs/spread/base
    python benchmarks/hormone_spread.py experiments/hormone_3d.toml --seeds 101-108 \\
        --set ga.population=120 --set ga.generations=40 --out runs/spread/pop120
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np


def seed_block(text: str) -> list[int]:
    """``"101-108"`` -> ``[101, ..., 108]``; ``"1,5,9"`` -> ``[1, 5, 9]``."""
    if "-" in text:
        a, b = (int(v) for v in text.split("-"))
        return list(range(a, b + 1))
    return [int(v) for v in text.split(",")]


def variant_overrides(config: Path, variant: str | None) -> list[str]:
    """The ``--set`` overrides of the sweep variant ``variant`` of ``config``."""
    if variant is None:
        return []
    import tomllib

    variants = tomllib.loads(config.read_text()).get("sweep", {}).get("variants", [])
    for v in variants:
        if v.get("name") == variant:
            return [f"{k}={json.dumps(x)}" for k, x in (v.get("set") or {}).items()]
    raise SystemExit(f"--variant {variant!r}: not in {config}'s sweep variants")


def one(config: str, out: str, seed: int, overrides: list[str]) -> dict:
    """One run; its row."""
    from growsim.experiment import run

    shutil.rmtree(out, ignore_errors=True)
    t = time.perf_counter()
    r = run(config, out=out, seed=seed, overrides=overrides, progress=False)
    seconds = time.perf_counter() - t
    measures = {
        k: float(v)
        for k, v in (r.summary.get("measures") or {}).items()
        if isinstance(v, (int, float)) and not isinstance(v, bool)
    }
    return {"kind": "run", "seed": seed, "best_fitness": float(r.best_fitness),
            "seconds": round(seconds, 1), "measures": measures}  # fmt: skip


def cv(values) -> float:
    """Coefficient of variation (sample sd over the mean's magnitude)."""
    v = np.asarray(values, dtype=float)
    m = abs(float(v.mean()))
    return float(v.std(ddof=1) / m) if m > 0 and len(v) > 1 else float("nan")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("config")
    ap.add_argument("--seeds", default="101-108")
    ap.add_argument("--variant", default=None)
    ap.add_argument("--set", action="append", default=[], dest="overrides")
    ap.add_argument("--out", default="runs/spread")
    ap.add_argument("--jobs", type=int, default=1)
    a = ap.parse_args(argv)
    # no pictures, meshes or plots: the runs' figures only
    quiet = ["output.screenshots=[]", "output.mesh=[]", "output.plot=false"]
    overrides = quiet + variant_overrides(Path(a.config), a.variant) + a.overrides
    seeds = seed_block(a.seeds)
    load = os.getloadavg()[0]
    t = time.perf_counter()
    with ProcessPoolExecutor(a.jobs) as pool:
        futures = [pool.submit(one, a.config, f"{a.out}/seed-{s}", s, overrides) for s in seeds]
        rows = []
        for f in futures:
            rows.append(f.result())
            print(json.dumps(rows[-1]), flush=True)
    best = [r["best_fitness"] for r in rows]
    names = sorted(set.intersection(*(set(r["measures"]) for r in rows)))
    print(json.dumps({
        "kind": "summary", "config": a.config, "variant": a.variant, "set": a.overrides,
        "seeds": a.seeds, "cv_best": round(cv(best), 3),
        "best_mean": round(float(np.mean(best)), 1),
        "best_range": [round(min(best), 1), round(max(best), 1)],
        "cv_measures": {k: round(cv([r["measures"][k] for r in rows]), 3) for k in names},
        "run_seconds": round(float(np.mean([r["seconds"] for r in rows])), 1),
        "wall_seconds": round(time.perf_counter() - t, 1), "jobs": a.jobs,
        "load": round(load, 2),
    }), flush=True)  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
