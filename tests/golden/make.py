"""Pin every shipped experiment at a small budget: ``python -m tests.golden.make``.

Runs each ``experiments/*.toml`` with the overrides of :data:`BUDGETS` (a few generations
of a small population, a short polish) into a temporary directory and writes
``tests/golden/<name>.json``: every history column but the wall-clock ``seconds`` (as
text: a float's shortest round-trip repr, so the comparison is bit for bit) and
``best.json`` (params, genome, fitness, terms).
``tests/test_golden.py`` re-runs the same and compares. Re-make the files only for a
change that is meant to alter results, and say so in the commit.
"""

from __future__ import annotations

import json
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
HERE = Path(__file__).resolve().parent

#: Small budgets per shipped experiment: enough generations to cross selection,
#: crossover, mutation, migration and the polish where the config has them.
BUDGETS: dict[str, list[str]] = {
    "quickstart": ["ga.population=12", "ga.generations=3"],
    "fish_tank": ["ga.population=6", "ga.generations=3"],
    "honda_silhouette": ["ga.population=10", "ga.generations=2", "ga.polish.evaluations=12"],
    "hormone_2d": ["ga.population=6", "ga.generations=2"],
    "hormone_3d": ["ga.population=6", "ga.generations=2"],
    "hormone_2d_paper_ga": ["ga.population=8", "ga.generations=2"],
    "hormone_3d_paper_ga": ["ga.population=8", "ga.generations=2"],
    "stand_density_2d": ["ga.population=6", "ga.generations=2"],
    # the dense variant: a periodic stand (the alone path is pinned by hormone_3d)
    "stand_density_3d": [
        "ga.population=6",
        "ga.generations=2",
        "environment.stand.mode=periodic",
        "environment.stand.spacing=1.0",
    ],
    "stand_mixture_2d": ["ga.population=6", "ga.generations=2", "model.params.steps=12"],
    "stand_mixture_3d": ["ga.population=10", "ga.generations=2", "model.params.steps=12"],
    "ifs_fern_fit": [
        "ga.population=10",
        "ga.generations=3",
        "ga.evaluations=100",
        "ga.polish.evaluations=40",
    ],
    "ifs_species": ["ga.population=6", "ga.generations=2"],
    "ifs_tree_best": [
        "ga.population=8",
        "ga.generations=3",
        "ga.evaluations=200",
        "ga.polish.evaluations=60",
    ],
    "ifs_tree_fit": ["ga.population=12", "ga.generations=2"],
}
#: outputs off: the golden pins the search, not the renders (tested elsewhere)
QUIET = ["output.mesh=[]", "output.screenshots=[]", "output.plot=false"]


def golden(name: str, out: Path) -> dict:
    """Run experiment ``name`` at its small budget into ``out``; its history and best."""
    import pandas as pd

    from growsim.experiment import run

    run(
        ROOT / "experiments" / f"{name}.toml",
        out=out,
        overrides=[*BUDGETS[name], *QUIET],
        progress=False,
    )
    history = pd.read_parquet(out / "history.parquet").drop(columns="seconds")
    best = json.loads((out / "best.json").read_text())
    return {
        "overrides": BUDGETS[name],
        "history_columns": list(history.columns),
        "history": history.astype(str).to_dict(orient="list"),
        "rows": len(history),
        "best": best,
    }


def main(names: list[str]) -> None:
    for name in names or sorted(BUDGETS):
        with tempfile.TemporaryDirectory() as tmp:
            data = golden(name, Path(tmp) / name)
        (HERE / f"{name}.json").write_text(json.dumps(data, indent=1, sort_keys=True) + "\n")
        print(name, data["rows"], "rows; best", data["best"].get("fitness"))


if __name__ == "__main__":
    main(sys.argv[1:])
