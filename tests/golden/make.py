"""Pin every shipped experiment at a small budget, and a small fit of a picture:
``python -m tests.golden.make [NAME ...]``.

Runs each ``experiments/*.toml`` with the overrides of :data:`BUDGETS` (a few generations
of a small population, a short polish) into a temporary directory and writes
``tests/golden/<name>.json``: every history column but the wall-clock ``seconds`` (as
text: a float's shortest round-trip repr, so the comparison is bit for bit) and
``best.json`` (params, genome, fitness, terms).
``tests/test_golden.py`` re-runs the same and compares. A fit of :data:`FITS`
(``growsim.fitting.fit_image`` on a drawing it makes) is pinned in
``tests/golden/fits/<name>.json``: its ``fit.json`` (but the seconds and the paths), the
run's ``best.json`` and a digest of each mask picture it writes (decoded pixels, not PNG
bytes; ``silhouettes.png``'s titles are a font's); ``tests/test_fit_golden.py``
compares. Re-make the files only for a change that is meant to alter results, and say
so in the commit.
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
    # the dry end of the gradient (its base, the full supply, is pinned by hormone_2d)
    "water_supply_2d": ["ga.population=6", "ga.generations=2", "environment.water.supply=0.3"],
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
#: small fits of a picture: name -> the keywords of fit_image (the picture: the Table 1
#: tree's front and side views at 64 px, drawn 4x on grey paper, as tests/test_silhouette_cli.py)
FITS: dict[str, dict] = {
    "fit_table1_drawing": {"evaluations": 300, "workers": 1},
}
#: where the fits' pins are
FIT_PINS = HERE / "fits"

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


def table1_drawing(where: Path) -> list[Path]:
    """The Table 1 tree's front and side drawn into ``where`` (its 64 px thin-line views
    enlarged 4x, dark on light grey, a 30 px margin): the pictures' paths."""
    import numpy as np
    from PIL import Image

    from growsim.models import ifs3d
    from growsim.objectives.silhouette import plant_views

    where.mkdir(parents=True, exist_ok=True)
    paths = []
    for view, label in zip(plant_views(ifs3d.develop(ifs3d.PRESETS["table1"]), 64),
                           ("front", "side")):  # fmt: skip
        img = np.where(np.kron(view, np.ones((4, 4))) > 0, 20, 240).astype(np.uint8)
        Image.fromarray(np.pad(img, 30, constant_values=240)).save(where / f"{label}.png")
        paths.append(where / f"{label}.png")
    return paths


def _without(x, keys=("seconds",)):
    """``x`` (JSON data) without the keys ``keys``, at any depth."""
    if isinstance(x, dict):
        return {k: _without(v, keys) for k, v in x.items() if k not in keys}
    if isinstance(x, list):
        return [_without(v, keys) for v in x]
    return x


def golden_fit(name: str, tmp: Path) -> dict:
    """Fit :data:`FITS` ``name`` in ``tmp``: its ``fit.json`` (no seconds; no paths: the
    pictures', the runs' directories), the run's ``best.json`` and the SHA-256 of each
    written picture's pixels."""
    import hashlib

    import numpy as np
    from PIL import Image

    from growsim.fitting import fit_image

    pictures = table1_drawing(tmp / "pictures")
    r = fit_image(*pictures, out=tmp / "fit", progress=False, **FITS[name])
    fit = _without(json.loads((r.out / "fit.json").read_text()), ("seconds", "pictures"))
    fit["leaves"] = _without(fit["leaves"], ("run", "out"))
    pixels = {
        p.name: hashlib.sha256(
            np.ascontiguousarray(np.asarray(Image.open(p))).tobytes()
        ).hexdigest()
        for p in r.files
        if p.name.startswith(("fit_", "silhouette_", "segmentation_"))  # no text drawn
    }
    return {
        "options": {k: v for k, v in FITS[name].items() if k != "workers"},
        "fit": fit,
        "best": json.loads((r.run / "best.json").read_text()),
        "pixels": pixels,
    }


#: how far a pinned number may lie from the one computed now, relative: a machine of
#: another CPU gives the same run to its last bits only (numpy's SIMD kernels and
#: OpenBLAS's differ by CPU: 2e-15 at most across the pins, seen on an AVX2 machine
#: against pins made on another); a change of behaviour moves them far more. A refactor
#: is checked bit for bit on one machine, before and after.
LAST_BITS = 1e-12


def differences(pinned, now, where: str = "") -> list[str]:
    """Where the JSON data ``now`` differs from ``pinned``: keys, lengths, texts and
    integers exactly; floats (and texts that are floats: a history's values) within
    :data:`LAST_BITS` relative. Empty when they match.

    >>> differences({"a": ["1.0000000000000002", "x"], "n": 3}, {"a": ["1.0", "x"], "n": 3})
    []
    >>> differences({"a": ["1.1"]}, {"a": ["1.0"]})
    ["a[0]: '1.1' != '1.0'"]
    """

    def number(x):
        if isinstance(x, int):  # bools too
            return None
        try:
            return float(x)
        except (TypeError, ValueError):
            return None

    if isinstance(pinned, dict) and isinstance(now, dict):
        if pinned.keys() != now.keys():
            return [f"{where}: keys {sorted(pinned)} != {sorted(now)}"]
        return [
            d for k in pinned for d in differences(pinned[k], now[k], f"{where}.{k}".lstrip("."))
        ]
    if isinstance(pinned, list) and isinstance(now, list):
        if len(pinned) != len(now):
            return [f"{where}: {len(pinned)} items != {len(now)}"]
        return [
            d
            for i, (a, b) in enumerate(zip(pinned, now))
            for d in differences(a, b, f"{where}[{i}]")
        ]
    a, b = number(pinned), number(now)
    if pinned == now or (
        a is not None and b is not None and abs(a - b) <= LAST_BITS * max(abs(a), abs(b))
    ):
        return []
    return [f"{where}: {pinned!r} != {now!r}"]


def main(names: list[str]) -> None:
    for name in names or [*sorted(BUDGETS), *sorted(FITS)]:
        with tempfile.TemporaryDirectory() as tmp:
            if name in FITS:
                data = golden_fit(name, Path(tmp))
                FIT_PINS.mkdir(exist_ok=True)
                path = FIT_PINS / f"{name}.json"
            else:
                data = golden(name, Path(tmp) / name)
                path = HERE / f"{name}.json"
        path.write_text(json.dumps(data, indent=1, sort_keys=True) + "\n")
        if name in FITS:
            print(name, "NCC", data["fit"]["ncc"])
        else:
            print(name, data["rows"], "rows; best", data["best"].get("fitness"))


if __name__ == "__main__":
    main(sys.argv[1:])
