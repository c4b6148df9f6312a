"""How much of a transplanted genome's fitness its mechanics cost: each best genome of a
sweep's ``--origin`` variant grown in the ``--garden`` variant's environment with gravity
(``environment.gravity.g`` as configured) and without (``g = 0``; the wind still blows),
as JSON: per run the two fitnesses, their ratio, breaks and shed modules, why it stopped.

The check behind "genomes from half water grown in ample water reach at least half their
gravity-free fitness": a genome evolved where water was short, moved where it is ample,
grows faster than its stems thicken; in a model whose first break ends the plant that
genome collapses (the earlier model: 1,303 at home, 5,616 in ample water without gravity,
broken at step 9 with it).

    python benchmarks/hormone_gravity_probe.py runs/h3d --origin half_water --garden ample \\
        --json benchmarks/results/hormone_3d_gravity_probe.json
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from growsim.experiment.load import load_plan
from growsim.experiment.results import find_runs


def _grow(config: dict, env: dict, params: dict, g: float | None):
    env = json.loads(json.dumps(env))
    if g is not None:
        env.setdefault("gravity", {})["g"] = g
    fitness = load_plan({**config, "environment": env}).fitness()
    plant = fitness.phenotype_of(params).phenotype
    total = 0.0
    for t, w, s in zip(fitness.terms(plant).values(), fitness.weights, fitness.signs):
        total += float(w * s * t["score"])
    meta = plant.meta
    return total, {k: meta.get(k) for k in ("stopped", "breaks", "shed")}


def probe(sweep: Path, origin: str, garden: str) -> dict:
    """Each run of ``origin`` grown in ``garden``'s environment with and without gravity."""
    runs = find_runs([sweep])
    by_variant = {}
    for r in runs:
        by_variant.setdefault(Path(r.path).parent.name, []).append(r)
    env = by_variant[garden][0].config["environment"]
    rows = []
    for r in sorted(by_variant[origin], key=lambda r: r.summary["seed"]):
        with_g, meta = _grow(r.config, env, r.best["params"], None)
        without, _ = _grow(r.config, env, r.best["params"], 0.0)
        home, _ = _grow(r.config, r.config["environment"], r.best["params"], None)
        rows.append({"seed": r.summary["seed"], "home": home, "transplanted": with_g,
                     "gravity_free": without, "ratio": with_g / without if without else np.nan,
                     **meta})  # fmt: skip
    ratios = np.array([x["ratio"] for x in rows])
    return {
        "sweep": str(sweep),
        "origin": origin,
        "garden": garden,
        "runs": rows,
        "ratio_min": float(np.nanmin(ratios)),
        "ratio_median": float(np.nanmedian(ratios)),
    }


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("sweep", type=Path)
    ap.add_argument("--origin", default="half_water")
    ap.add_argument("--garden", default="ample")
    ap.add_argument("--json", type=Path)
    a = ap.parse_args(argv)
    out = probe(a.sweep, a.origin, a.garden)
    text = json.dumps(out, indent=1)
    if a.json:
        a.json.write_text(text + "\n")
    print(text)


if __name__ == "__main__":
    main()
