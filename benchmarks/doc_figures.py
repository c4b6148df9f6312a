"""The figures docs/quickstart.md prints, regenerated from real runs.

    python benchmarks/doc_figures.py [--sweep] [--json PATH]

Runs the quickstart (``experiments/quickstart.toml``, its own seed) and prints its best
fitness, generation, evaluations, evolved parameters and the best plant's objective terms
and ``light_captured`` as JSON; with ``--sweep``, also the light-direction sweep of the
quickstart page and docs/reproduction.md (light from above vs. at 45 degrees, 3 seeds
each) with each variant's mean +/- 95 % CI, Welch's and Mann-Whitney's p, and the range
over the runs of the best fitness's rise from generation 0 to the end (per cent). The
quickstart figures are deterministic (same config + seed, same result), and
``tests/test_doc_figures.py`` checks the page against a fresh run, so they cannot drift.
The sweep's figures are pinned instead: ``--json PATH`` also writes the JSON to ``PATH``
(``benchmarks/results/light_sweep.json``, with every run's best fitness and rise), which
``tests/test_reproduction_claims.py`` checks ``docs/reproduction.md`` against.
"""

from __future__ import annotations

import argparse
import json
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
QUICK = ROOT / "experiments" / "quickstart.toml"
NO_FILES = ["output.mesh=[]", "output.screenshots=[]", "output.plot=false"]


def quickstart(out: Path) -> dict:
    """The quickstart run's figures (no artefacts written)."""
    from growsim.experiment import run

    r = run(QUICK, out, overrides=NO_FILES, progress=False)
    best = json.loads((r.out / "best.json").read_text())
    return {
        "printed": f"quickstart: best fitness {r.best_fitness:.6g} (generation "
        f"{best['generation']}), {r.summary['evaluations']} evaluations",
        "best_fitness": round(r.best_fitness, 2),
        "best_generation": best["generation"],
        "evaluations": r.summary["evaluations"],
        "ga_seconds": r.summary["ga_seconds"],
        "evolved": {k: round(v, 2) for k, v in best["evolved"].items()},
        "terms": best["terms"],
        "light_captured": r.summary["measures"].get("light_captured"),
        "leaf_area_top": r.summary["measures"].get("leaf_area_top"),
    }


def light_sweep(out: Path) -> dict:
    """Light from above vs. at 45 degrees, 3 seeds each: mean, 95 % CI, Welch's and
    Mann-Whitney's p, the best fitness's rise from generation 0 (per cent, min and max)."""
    import pandas as pd
    from scipy import stats

    from growsim.experiment import sweep
    from growsim.report.statistics import ci95

    df = sweep(
        QUICK,
        ["env.light.direction=[[0, -1, 0], [1, -1, 0]]"],
        repeats=3,
        out=out,
        overrides=NO_FILES,
        progress=False,
    )
    groups = {label: g["best_fitness"].to_numpy() for label, g in df.groupby("variant")}
    out_rows = {
        label: {"mean": round(float(x.mean()), 1), "ci95": round(float(ci95(x)), 1)}
        for label, x in groups.items()
    }
    a, b = groups.values()
    out_rows["welch_p"] = round(float(stats.ttest_ind(a, b, equal_var=False).pvalue), 4)
    out_rows["mann_whitney_p"] = round(float(stats.mannwhitneyu(a, b).pvalue), 4)
    rises = []
    for run_dir in df["out"]:
        h = pd.read_parquet(Path(run_dir) / "history.parquet")
        first = float(h.loc[h["generation"] == 0, "best"].max())
        rises.append(100.0 * (float(h["best_so_far"].iloc[-1]) / first - 1.0))
    out_rows["rise_percent"] = [round(min(rises), 1), round(max(rises), 1)]
    out_rows["runs"] = [
        {"variant": v, "seed": int(s), "best_fitness": float(f), "rise_percent": r}
        for v, s, f, r in zip(df["variant"], df["seed"], df["best_fitness"], rises)
    ]
    return out_rows


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--sweep", action="store_true", help="also run the light sweep (6 runs)")
    ap.add_argument("--json", default=None, metavar="PATH", help="also write the JSON here")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        result = {"quickstart": quickstart(Path(tmp) / "q")}
        if args.sweep:
            result["light_sweep"] = light_sweep(Path(tmp) / "sweep")
    print(json.dumps(result, indent=1))
    if args.json:
        Path(args.json).write_text(json.dumps(result, indent=1) + "\n")


if __name__ == "__main__":
    main()
