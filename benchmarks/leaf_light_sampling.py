"""How well one point stands for a hormone plant's foliage: the light its leaves are
credited with (one point its drawn radius above the higher end of each module's axis,
as the model lights them) against the mean light along the top of the foliage (the
middles of ``--points`` equal parts of the axis, moved out by the drawn radius across the
axis toward the sky; the top point for a module within 30 degrees of upright), both
area-weighted over the leaves, for the best plant of each run directory given (its
``best_plant.npz``, grown again alone in its run's light, through the model's shadow map).

One JSON line per run: ``modules``, ``leaf_area`` (m2), ``leaf_area_index``,
``one_point``, ``along_foliage``, ``over_twice`` (modules whose one point gets more than
twice their foliage's mean).

    python benchmarks/leaf_light_sampling.py runs/sm2i-b2/mixture/seed-13 runs/h2d/ample/seed-1
"""

from __future__ import annotations

import argparse
import json
import tomllib
from pathlib import Path

import numpy as np

from growsim.env import Environment
from growsim.kernels.light import point_light_into, shadow_scratch
from growsim.models.hormone import environment_args
from growsim.phenotypes.plant import Plant


def light_at(points, start, end, drawn, env) -> np.ndarray:
    """The light at ``points`` (facing up) through the shadow map of the capsules."""
    n = len(points)
    normals = np.zeros((n, 3))
    normals[:, 1] = 1.0
    trans = np.full(len(start), env.transmission) if env.soft else np.empty(0)
    return point_light_into(
        (start, end, drawn, np.array([0, len(start)])), (points, np.array([0, n]), normals),
        (env.dirs, env.us, env.vs, env.weights), (env.resolution, env.bias, env.soft, trans),
        shadow_scratch(env.resolution), np.empty(n), np.zeros((0, 3)),
    )  # fmt: skip


def sample(start, end, drawn, frac) -> np.ndarray:
    """Each module's point at ``frac`` of its axis on the top of its foliage (``None``:
    above its higher end)."""
    low_first = start[:, 1] <= end[:, 1]
    lo = np.where(low_first[:, None], start, end)
    hi = np.where(low_first[:, None], end, start)
    axis = hi - lo
    unit = axis / np.maximum(np.linalg.norm(axis, axis=1, keepdims=True), 1e-12)
    up = np.array([0.0, 1.0, 0.0]) - unit[:, 1:2] * unit
    sin = np.linalg.norm(up, axis=1)
    top = hi + drawn[:, None] * np.array([0.0, 1.0, 0.0])
    if frac is None:
        return top
    along = lo + frac * axis + drawn[:, None] * up / np.maximum(sin, 1e-12)[:, None]
    return np.where((sin > 0.5)[:, None], along, top)


def measure(run: Path, points: int) -> dict:
    """The one-point and along-the-foliage leaf light of ``run``'s best plant."""
    config = tomllib.loads((run / "config.toml").read_text())
    env = environment_args(Environment.model_validate(config.get("environment", {})))
    plant = Plant.load(run / "best_plant.npz")
    s, e, r = plant.start, plant.end, plant.radius
    area = np.asarray(plant.data["leaf_area"], dtype=np.float64)
    length = plant.lengths()
    drawn = np.maximum(r, np.divide(area, 2 * length, out=np.zeros_like(area), where=length > 0))
    one = light_at(sample(s, e, drawn, None), s, e, drawn, env)
    fracs = (np.arange(points) + 0.5) / points
    mean = np.mean([light_at(sample(s, e, drawn, f), s, e, drawn, env) for f in fracs], axis=0)
    w = area / area.sum()
    return {
        "run": str(run), "modules": int(plant.n_segments), "leaf_area": round(float(area.sum()), 3),
        "leaf_area_index": round(plant.measures()["leaf_area_index"], 3),
        "one_point": round(float(w @ one), 4), "along_foliage": round(float(w @ mean), 4),
        "over_twice": int((one > 2 * mean + 1e-9).sum()),
    }  # fmt: skip


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("runs", nargs="+", type=Path, help="run directories (best_plant.npz)")
    ap.add_argument("--points", type=int, default=6, help="points along each module")
    a = ap.parse_args(argv)
    for run in a.runs:
        print(json.dumps(measure(run, a.points)))


if __name__ == "__main__":
    main()
