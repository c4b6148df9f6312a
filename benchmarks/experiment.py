"""Costs of the experiment layer: config loading, the fitness glue, a whole quickstart run.

    python benchmarks/experiment.py

Prints JSON:
- ``load_config_ms``: validate + resolve experiments/quickstart.toml (objectives built);
- ``quickstart_eval_ms``: one quickstart evaluation (grow a Honda tree, light raster);
- ``glue_overhead_us_per_individual``: what :class:`growsim.experiment.Fitness` adds on
  top of the objective's batch fast path (IFS fit config, 1000 individuals);
- ``quickstart_wall_s``: ``growsim run experiments/quickstart.toml`` in a subprocess
  (warm numba cache), artefacts included.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def best_of(fn, n=5):
    t = []
    for _ in range(n):
        t0 = time.perf_counter()
        fn()
        t.append(time.perf_counter() - t0)
    return min(t)


def main() -> None:
    from growsim.experiment import build_fitness, load_config

    quick = ROOT / "experiments" / "quickstart.toml"
    load_config(quick)
    t_load = best_of(lambda: load_config(quick))

    cfg = load_config(quick)
    f = build_fitness(cfg)
    rng = np.random.default_rng(0)
    lo = np.array([cfg.model.evolve[n][0] for n in f.evolved])
    hi = np.array([cfg.model.evolve[n][1] for n in f.evolved])
    x = lo + rng.random((200, len(lo))) * (hi - lo)
    f(x[:2])
    t_eval = best_of(lambda: f(x), 3) / len(x)

    out = {"load_config_ms": round(t_load * 1e3, 2), "quickstart_eval_ms": round(t_eval * 1e3, 3)}

    ifs = ROOT / "experiments" / "ifs_tree_fit.toml"
    if ifs.is_file():
        cfg = load_config(ifs)
        f = build_fitness(cfg)
        obj = f.objectives[0]
        n = 1000
        lo = np.array([cfg.model.evolve[k][0] for k in f.evolved])
        hi = np.array([cfg.model.evolve[k][1] for k in f.evolved])
        x = lo + rng.random((n, len(lo))) * (hi - lo)
        seeds = np.arange(n, dtype=np.uint64)
        full = f.full_params(x)
        model = f.model
        if obj.batch(model, full, f.names, f.model_seeds(full, seeds)) is not None:
            f(x, seeds)
            t_glue = best_of(lambda: f(x, seeds))
            t_raw = best_of(lambda: obj.batch(model, full, f.names, f.model_seeds(full, seeds)))
            out["ifs_batch_ms_per_1000"] = round(t_raw * 1e3, 2)
            out["glue_overhead_us_per_individual"] = round((t_glue - t_raw) / n * 1e6, 3)

    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        subprocess.run(
            [sys.executable, "-m", "growsim", "run", str(quick), "--out", f"{tmp}/q", "--quiet"],
            check=True,
            capture_output=True,
        )
        out["quickstart_wall_s"] = round(time.perf_counter() - t0, 2)
        s = json.loads(Path(f"{tmp}/q/summary.json").read_text())
        out["quickstart_ga_s"] = s["ga_seconds"]
        out["quickstart_evaluations"] = s["evaluations"]
    out["load_average"] = [round(v, 2) for v in os.getloadavg()]
    print(json.dumps({"benchmark": "experiment", **out}, indent=2))


if __name__ == "__main__":
    main()
