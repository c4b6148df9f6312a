"""The figures of ``docs/models/hormone.md``.

    python benchmarks/hormone_figures.py                      # the demo genomes
    python benchmarks/hormone_figures.py --sweep runs/h2d --sweep runs/h3d

- ``hormone_demo.png``: the demo genomes grown in 2D and in 3D under the documented
  environment (sun a little from the side, half the light from the sky);
- for each ``--sweep`` (a ``growsim sweep`` of ``experiments/hormone_2d.toml`` or
  ``hormone_3d.toml``): the best plant of each environment side by side
  (``hormone_<name>_best.png``, as the paper's Fig. 3 and 4: each best run's genome grown
  again in its own environment) and the growth of each as an animation
  (``hormone_<name>_<variant>.gif``, one frame per step, one frame for the whole growth).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np
from PIL import Image

DOCS = Path(__file__).resolve().parents[1] / "docs" / "images"


def demo() -> dict:
    from growsim.env import Environment
    from growsim.models import hormone

    env = Environment.model_validate({"light": {"diffuse": 0.5, "direction": [0.3, -1, 0.2]}})
    tiles, out = [], {}
    for name, view in (("demo_2d", "front"), ("demo_3d", "iso")):
        plant = hormone.develop(hormone.PRESETS[name], env=env)
        tiles.append(plant.render_image(view=view, size=(400, 400)))
        out[name] = {
            "modules": plant.n_segments,
            "stopped": plant.meta["stopped"],
            "total_nutrient": round(plant.meta["total_nutrient"], 3),
            "height": round(plant.height(), 2),
            "crown_width": round(plant.crown_width(), 2),
        }
    path = DOCS / "hormone_demo.png"
    Image.fromarray(np.concatenate(tiles, axis=1)).save(path)
    out["image"] = str(path)
    return out


def best_of_sweep(sweep: Path) -> dict:
    """The best plant of each variant of a sweep: render side by side, GIF of each."""
    from growsim.experiment.load import load_plan
    from growsim.experiment.results import find_runs
    from growsim.phenotypes.plant.views import growth_animation, render_grid

    runs = find_runs([sweep])
    best = {}
    for r in runs:
        variant = r.path.parent.name
        if variant not in best or r.best_fitness > best[variant].best_fitness:
            best[variant] = r
    order = [v for v in ("ample", "half_water", "half_light") if v in best]
    order += sorted(set(best) - set(order))
    name = best[order[0]].config["experiment"]["name"]
    dims = int(best[order[0]].best["params"]["dims"])
    view = "front" if dims == 2 else "iso"
    plants, titles, out = [], [], {}
    for v in order:
        r = best[v]
        plan = load_plan(r.config)
        f = plan.fitness()
        params = f.param_dict(np.array([float(r.best["params"][n]) for n in f.names]))
        steps = list(plan.model.grow(params, env=f.env))
        last = steps[-1]
        plants.append(last)
        titles.append(f"{v.replace('_', ' ')}: {last.n_segments} modules")
        gif = growth_animation(steps, DOCS / f"{name}_{v}.gif", view=view, size=(260, 260), fps=6)
        out[v] = {
            "run": str(r.path),
            "fitness": round(r.best_fitness, 3),
            "modules": last.n_segments,
            "height": round(last.height(), 2),
            "crown_width": round(last.crown_width(), 2),
            "gif": str(gif),
        }
    grid = render_grid(plants, DOCS / f"{name}_best.png", titles=titles, view=view,
                       cell=(320, 320), columns=len(plants))  # fmt: skip
    out["image"] = str(grid)
    return out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--sweep", action="append", default=[], help="a hormone sweep directory")
    args = ap.parse_args()
    out = {"demo": demo()}
    for s in args.sweep:
        out[str(s)] = best_of_sweep(Path(s))
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
