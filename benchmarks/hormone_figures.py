"""The figures of ``docs/models/hormone.md``: the demo genomes grown in 2D and in 3D under
the documented environment (sun a little from the side, half the light from the sky).

    python benchmarks/hormone_figures.py
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from PIL import Image

DOCS = Path(__file__).resolve().parents[1] / "docs" / "images"


def main() -> None:
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
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
