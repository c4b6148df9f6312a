"""Grow one plant of each model from a preset and save a picture of each.

What it shows: the Python side of ``growsim grow MODEL --preset P --screenshot P.png``.
``get_model(name)`` gives a model, ``model.preset(name)`` its named parameters,
``model.develop(params, env=...)`` grows the phenotype (a ``Plant`` for honda, ifs3d and
hormone; an attractor for ifs2d; a trajectory for the fish), and every phenotype has
``measures()`` and ``screenshot(path)``. The hormone demo genomes are grown in the
environment of their experiment (``growsim.load_plan(config).environment``: the sun a
little off the vertical, light from the sky), the world their docs picture them in.

    python examples/grow_each_model.py --out pictures
"""

from __future__ import annotations

import argparse
from pathlib import Path

import growsim
from growsim.models import get_model

EXPERIMENTS = Path(__file__).resolve().parents[1] / "experiments"

#: (model, preset, the experiment whose environment it grows in, or None)
PLANTS = [
    ("honda", "zelkova", None),
    ("ifs3d", "table1", None),
    ("hormone", "demo_2d", "hormone_2d.toml"),
    ("hormone", "demo_3d", "hormone_3d.toml"),
    ("ifs2d", "fern", None),
    ("fish", "calm", None),
]


def grow(model_name: str, preset: str, experiment: str | None = None):
    """The phenotype of ``model_name``'s ``preset`` (in ``experiment``'s environment)."""
    model = get_model(model_name)
    env = growsim.load_plan(EXPERIMENTS / experiment).environment if experiment else None
    return model.develop(model.preset(preset), env=env)


def main(argv=None) -> list[Path]:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="runs/examples/models", help="picture directory")
    parser.add_argument("--size", type=int, default=480, help="picture size in pixels")
    args = parser.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    written = []
    for model_name, preset, experiment in PLANTS:
        phenotype = grow(model_name, preset, experiment)
        m = phenotype.measures()
        size = m.get("n_segments", m.get("n_points", m.get("frames")))
        path = phenotype.screenshot(
            out / f"{model_name}_{preset}.png", view="front", size=(args.size, args.size)
        )
        print(f"{model_name:8s} {preset:8s} {phenotype.phenotype:10s} size {size:>9,.0f}  {path}")
        written.append(path)
    return written


if __name__ == "__main__":
    main()
