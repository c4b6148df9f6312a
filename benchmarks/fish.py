"""Benchmark of the fish in a tank (Okusa's thesis): kernel speed, the 3 tanks x 20 repeats sweep,
and the results beside the thesis's (Okusa, "GA-tuned path control of a fish agent").

    python benchmarks/fish.py [--repeats 20] [--workers N] [--out DIR]

Prints one JSON object: fish-frames per second of the population kernel on one core
(random genomes, as a GA's first generation, in the small tank), the sweep's wall time
(``growsim sweep``), per tank the mean generations to a collision-free fish, the thesis's
Table 3 bins, the mean decoded genes (Table 4) beside the thesis's numbers, the count of
collision-free fish that circle forever, and runs that found no solution in a too small
tank (90 x 90 x 90: the 40 px margin leaves a 10 px start box).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
CONFIG = ROOT / "experiments" / "fish_tank.toml"
SEED = {  # Table 3 (generation bins) and Table 4 (means) of the thesis
    "small": {"generations": 9.8, "bins": [6, 8, 2, 1, 3], "scale": 6.734, "view": 72.65,
              "speed": 16.05, "angle": 146.15},
    "medium": {"generations": 7.4, "bins": [13, 2, 1, 0, 4], "scale": 7.503, "view": 78.0,
               "speed": 15.62, "angle": 151.9},
    "large": {"generations": 5.25, "bins": [12, 4, 4, 0, 0], "scale": 8.12, "view": 78.05,
              "speed": 11.58, "angle": 147.3},
}  # fmt: skip
#: the whole tank table is varied (``--vary environment.tank.preset=small,medium,large``
#: gives the same tanks: a tank that is its preset's is saved as the preset alone)
TANKS_VARY = 'environment.tank=[{preset="small"}, {preset="medium"}, {preset="large"}]'
BINS = ["0-5", "6-10", "11-15", "16-20", "21+"]


def frames_per_second(n: int = 200, frames: int = 20_000) -> float:
    """Fish-frames per second of the population kernel (best of 3), one core."""
    from growsim.env import Tank
    from growsim.kernels.fish import population_collisions
    from growsim.models.fish import PARAMS, fish_table

    tank = Tank.model_validate({"preset": "small"})
    rng = np.random.default_rng(0)
    rows = np.array([[p.default for p in PARAMS]] * n)
    for j, p in enumerate(PARAMS[:11]):
        rows[:, j] = rng.uniform(p.low, p.high, n)
        if p.kind == "int":
            rows[:, j] = np.round(rows[:, j])
    table = fish_table(rows, [p.name for p in PARAMS], tank)
    size, spheres, cubes = tank.arrays()
    seeds = np.arange(n, dtype=np.uint64)
    population_collisions(table[:2], seeds[:2], size, spheres, cubes, 10)  # compile/load
    best = 0.0
    for _ in range(3):
        t = time.perf_counter()
        population_collisions(table, seeds, size, spheres, cubes, frames)
        best = max(best, n * frames / (time.perf_counter() - t))
    return best


def bins(gens) -> list[int]:
    """Counts in the thesis's Table 3 bins."""
    g = np.asarray(gens)
    return [int(((g >= lo) & (g <= hi)).sum()) for lo, hi in
            ((0, 5), (6, 10), (11, 15), (16, 20), (21, 10**9))]  # fmt: skip


def too_small(repeats: int) -> int:
    """Runs (of ``repeats``) with no collision-free fish within 200 generations in a
    90 x 90 x 90 tank without obstacles."""
    from growsim.experiment import load_plan

    tank = "environment.tank={size=[90.0, 90.0, 90.0], obstacles=[]}"
    plan = load_plan(CONFIG, [tank])
    fails = 0
    for s in range(repeats):
        p = plan.with_seed(s)
        r = p.build_ga(p.fitness()).run(generations=200, target=0.0)
        fails += r.best.fitness != 0.0
    return fails


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=20)
    ap.add_argument("--workers", type=int, default=None, help="growsim sweep --workers")
    ap.add_argument("--out", default=None, help="sweep directory (default: a temporary one)")
    args = ap.parse_args()
    out = Path(args.out or tempfile.mkdtemp(prefix="fish-sweep-")) / "sweep"
    cmd = [sys.executable, "-m", "growsim", "sweep", str(CONFIG), "--vary",
           TANKS_VARY, "--repeats", str(args.repeats),
           "--out", str(out), "-q"]  # fmt: skip
    if args.workers:
        cmd += ["--workers", str(args.workers)]
    t = time.perf_counter()
    subprocess.run(cmd, check=True, cwd=ROOT)
    wall = time.perf_counter() - t
    result = {
        "fish_frames_per_second_one_core": round(frames_per_second()),
        "sweep_command": " ".join(cmd[2:]),
        "sweep_wall_seconds": round(wall, 1),
        "cpus": os.cpu_count(),
        "load": os.getloadavg(),
        "bins": BINS,
        "tanks": {},
    }
    for tank in ("small", "medium", "large"):
        rows = []
        for d in sorted(out.glob(f"*{tank}*/seed-*")):
            best = json.loads((d / "best.json").read_text())
            summary = json.loads((d / "summary.json").read_text())
            rows.append((best, summary))
        solved = [b for b, _ in rows if b["fitness"] == 0.0]
        gens = [b["generation"] for b in solved]
        mean = {k: float(np.mean([b["params"][k] for b in solved])) for k in
                ("scale", "view", "speed", "angle")}  # fmt: skip
        result["tanks"][tank] = {
            "runs": len(rows),
            "solved": len(solved),
            "max_generations": int(max(gens)) if gens else None,
            "mean_generations": round(float(np.mean(gens)), 2) if gens else None,
            "seed_mean_generations": SEED[tank]["generations"],
            "table3_bins": bins(gens),
            "seed_table3_bins": SEED[tank]["bins"],
            "table4_means": {k: round(v, 2) for k, v in mean.items()},
            "seed_table4_means": {k: SEED[tank][k] for k in mean},
            "circling_forever": int(sum(s["measures"].get("circling", 0) for _, s in rows)),
        }
    result["no_solution_in_90x90x90_tank"] = f"{too_small(args.repeats)} of {args.repeats}"
    print(json.dumps(result, indent=1))


if __name__ == "__main__":
    main()
