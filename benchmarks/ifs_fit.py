"""Benchmark of the ifs3d silhouette fit: kernel throughput and whole experiment runs.

Prints JSON lines:

- ``{"kind": "kernel", ...}``: evaluations per second of the batch kernel
  (``SilhouetteObjective.batch``: compose, frame, rasterise both views, NCC) on random
  trees, wall and CPU time, numba threads;
- one ``{"kind": "run", ...}`` per seed of each config: wall seconds, GA seconds,
  evaluations per second, best mean NCC, and the recovered parameters' worst errors
  against the target (up to map order; leader azimuth modulo 90 for Table 1);
- ``{"kind": "summary", ...}`` per config.

Usage::

    python benchmarks/ifs_fit.py                                   # kernel only
    python benchmarks/ifs_fit.py --config experiments/ifs_tree_fit.toml --seeds 0 1 2 3 4
    python benchmarks/ifs_fit.py --random-trees 10     # best setup on random targets
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
import time

import numba
import numpy as np

from growsim.models import get_model, ifs3d
from growsim.objectives.silhouette import SilhouetteObjective


def kernel(n: int = 1000, repeats: int = 5) -> dict:
    obj = SilhouetteObjective(target_model="ifs3d", target_preset="table1")
    rng = np.random.default_rng(0)
    spec = ifs3d.PARAMS
    names = [p.name for p in spec]
    pop = np.array([[rng.uniform(p.low, p.high) for p in spec] for _ in range(n)])
    pop[:, 0], pop[:, 1] = 5, 5
    obj.batch(get_model("ifs3d"), pop[:4], names)  # compile / load the cache
    best = np.inf
    cpu = np.inf
    for _ in range(repeats):
        t, c = time.perf_counter(), time.process_time()
        obj.batch(get_model("ifs3d"), pop, names)
        best = min(best, time.perf_counter() - t)
        cpu = min(cpu, time.process_time() - c)
    return {
        "kind": "kernel",
        "trees": n,
        "segments_per_tree": ifs3d.check_size(5, 5),
        "wall_s": round(best, 4),
        "cpu_s": round(cpu, 4),
        "evals_per_s": round(n / best, 1),
        "evals_per_cpu_s": round(n / cpu, 1),
        "threads": numba.get_num_threads(),
        "load_avg_1min": os.getloadavg()[0],
    }


def run_config(path: str, seeds: list[int]) -> list[dict]:
    from growsim.experiment import load_config, run

    rows = []
    for seed in seeds:
        cfg = load_config(path)
        obj = cfg.objective[0].model_dump()
        with tempfile.TemporaryDirectory() as d:
            t = time.perf_counter()
            r = run(cfg, out=os.path.join(d, "run"), seed=seed, progress=False)
            wall = time.perf_counter() - t
            summary = json.loads((r.out / "summary.json").read_text())
        params = r.best_params
        ref_params = dict(ifs3d.PRESETS[obj.get("target_preset", "table1")])
        ref_params.update(obj.get("target_params", {}) or {})
        fit = ifs3d.maps_from_params(params)
        ref = ifs3d.maps_from_params(ref_params)
        period = 90.0 if obj.get("target_preset") == "table1" else 360.0
        cmp = ifs3d.compare_maps(fit, ref, azimuth_period=period)
        plain = SilhouetteObjective(target_model="ifs3d", target_preset="table1")
        rows.append(
            {
                "kind": "run",
                "config": path,
                "seed": seed,
                "wall_s": round(wall, 2),
                "ga_s": summary.get("ga_seconds"),
                "evaluations": summary["evaluations"],
                "evals_per_s": round(summary["evaluations"] / summary["ga_seconds"], 1),
                "best_fitness": round(float(r.best_fitness), 4),
                "ncc": round(plain(ifs3d.develop(params)), 4),
                "within_tolerance": cmp["within"],
                "max_error_s_y_tz_ty": [round(float(x), 3) for x in cmp["max_error"]],
                "maps": np.round(fit[cmp["order"]], 3).tolist(),
                "load_avg_1min": os.getloadavg()[0],
            }
        )
        print(json.dumps(rows[-1]), flush=True)
    return rows


def random_trees(n: int, evaluations: int = 50_000) -> list[dict]:
    """The best setup (``growsim.fitting.setups.BEST_GA``: 4 islands of 100, real coding,
    CMA-ES polish) fitted to ``n`` random trees (tree seeds 100.., parameters uniform within
    the ranges)."""
    from growsim.fitting.setups import BEST_GA
    from growsim.ga import GA, genome_from_params

    evolved = [p for p in ifs3d.PARAMS if p.name not in ("n_maps", "depth")]
    names = ["n_maps", "depth"] + [p.name for p in evolved]

    def fitness_of(obj):
        def f(x):
            full = np.concatenate([np.full((len(x), 2), 5.0), x], 1)
            return obj.batch(get_model("ifs3d"), full, names)

        return f

    rows = []
    for t in range(n):
        rng = np.random.default_rng(100 + t)
        target = {"n_maps": 5, "depth": 5} | {p.name: rng.uniform(p.low, p.high) for p in evolved}
        obj = SilhouetteObjective(target_model="ifs3d", target_params=target)
        t0 = time.perf_counter()
        ga = GA(genome_from_params(evolved, coding="real"), fitness_of(obj),
                population=BEST_GA["population"], islands=BEST_GA["islands"], seed=0)  # fmt: skip
        share = BEST_GA["polish"]["evaluations"] / BEST_GA["evaluations"]
        polish = dict(BEST_GA["polish"], evaluations=int(evaluations * share))
        r = ga.run(evaluations=evaluations, polish=polish)
        rows.append({"kind": "random_tree", "tree_seed": 100 + t,
                     "ncc": round(float(r.best.fitness), 4), "evaluations": int(r.evaluations),
                     "wall_s": round(time.perf_counter() - t0, 2)})  # fmt: skip
        print(json.dumps(rows[-1]), flush=True)
    ncc = [r["ncc"] for r in rows]
    summary = {"kind": "random_summary", "mean": round(float(np.mean(ncc)), 4), "min": min(ncc)}
    summary["n_ge_0.9"] = sum(x >= 0.9 for x in ncc)
    print(json.dumps(summary), flush=True)
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--config", action="append", default=[])
    ap.add_argument("--seeds", type=int, nargs="+", default=[0])
    ap.add_argument("--trees", type=int, default=1000)
    ap.add_argument("--random-trees", type=int, default=0)
    args = ap.parse_args()
    print(json.dumps(kernel(args.trees)), flush=True)
    if args.random_trees:
        random_trees(args.random_trees)
    for path in args.config:
        rows = run_config(path, args.seeds)
        ncc = [r["ncc"] for r in rows]
        print(
            json.dumps(
                {
                    "kind": "summary",
                    "config": path,
                    "seeds": args.seeds,
                    "ncc_mean": round(float(np.mean(ncc)), 4),
                    "ncc_min": min(ncc),
                    "ncc_max": max(ncc),
                    "runs_ncc_ge_0.95": sum(x >= 0.95 for x in ncc),
                    "runs_within_tolerance": sum(r["within_tolerance"] for r in rows),
                    "wall_s_mean": round(float(np.mean([r["wall_s"] for r in rows])), 2),
                    "evals_per_s_mean": round(float(np.mean([r["evals_per_s"] for r in rows])), 1),
                }
            ),
            flush=True,
        )


if __name__ == "__main__":
    main()
