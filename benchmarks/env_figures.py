"""The images of docs/environment.md ("Seeing it"), regenerated with the commands it shows.

    python benchmarks/env_figures.py [--out docs/images] [--size 600]

Grows Honda's zelkova preset lit from the side (the light travels +x: it comes from -x)
and renders it three times with ``growsim grow --color``: by the light each segment
receives (with the light's arrow), by the stress ratio at each joint and by the share of
each segment's water demand met (the demand is the light received: with the arrow too).
Writes ``env_light.png``, ``env_stress.png`` and ``env_water.png`` (front view) and
prints, as JSON, the figures the page quotes from ``Environment.segment_table`` (mean
light on the tree's -x and +x sides, the share of leaves in full shade, the highest
stress ratio, the range of the water share met where there is demand). Deterministic:
the same preset, environment and size give the same images.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: the light travels +x: it comes from -x (the tree's left in the front view)
DIRECTION = ("1", "0", "0")
FIGURES = {"light": "env_light.png", "stress": "env_stress.png", "water": "env_water.png"}


def commands(out: Path, size: int) -> dict[str, list[str]]:
    """The ``growsim`` command line of each figure, by field (water follows the light: its
    figure shows the arrow too)."""
    out_argv = {}
    for color, name in FIGURES.items():
        argv = ["grow", "honda", "--preset", "zelkova", "--light-direction", *DIRECTION]
        argv += ["--color", color] + (["--light-arrow"] if color == "water" else [])
        argv += ["--view", "front", "--size", str(size), "--screenshot", str(out / name)]
        out_argv[color] = argv
    return out_argv


def figures() -> dict:
    """What the page quotes from the side-lit zelkova's segment table."""
    from growsim.env import Environment
    from growsim.models import honda

    tree = honda.develop(honda.PRESETS["zelkova"])
    env = Environment.model_validate({"light": {"direction": [float(v) for v in DIRECTION]}})
    table = env.segment_table(tree)
    x = (tree.start[:, 0] + tree.end[:, 0]) / 2.0
    demand = (table.kind == "leaf") & (table.light > 0)
    return {
        "segments": len(table),
        "light_mean_minus_x": round(float(table.light[x < 0].mean()), 3),
        "light_mean_plus_x": round(float(table.light[x > 0].mean()), 3),
        "leaves_in_shade": round(float((table.light[table.kind == "leaf"] == 0).mean()), 3),
        "stress_ratio_max": round(float(table.stress_ratio.max()), 3),
        "water_met_range": [
            round(float(table.water_met[demand].min()), 3),
            round(float(table.water_met[demand].max()), 3),
        ],
    }


def main() -> None:
    """Write the images and print the figures."""
    from growsim.cli import main as growsim

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", type=Path, default=ROOT / "docs" / "images", help="image directory")
    ap.add_argument("--size", type=int, default=600, help="image side in pixels")
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    written = []
    for argv in commands(args.out, args.size).values():
        if growsim([*argv]) != 0:
            raise SystemExit(f"failed: growsim {' '.join(argv)}")
        written.append(argv[-1])
    print(json.dumps({"images": written, **figures()}, indent=2))


if __name__ == "__main__":
    main()
