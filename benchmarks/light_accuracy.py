"""How close the shadow map comes to exact geometry, per resolution (JSON).

    python benchmarks/light_accuracy.py [--seeds 6] [--resolutions 32 64 128 256 512]

Two measures per resolution (pixels across each plant):

- ``agreement``: on random populations (the light tests' random trees: 3 plants of 40-90
  segments, a random direction from above), the share of segments whose lit/shadowed
  state (hard shadows, midpoint sample) equals the exact answer of the oracle
  ``tests/naive/light.py`` (does another capsule lie in front of the point, beyond the
  bias?), and ``net_overshade``: (segments the map shades and the oracle lights minus
  the other way round) / segments: 0 for an unbiased map;
- ``zelkova_mean_light``: the mean light per segment of Honda's zelkova preset under light
  from above: with the default bias (0.1 pixel) it hardly moves with the resolution; with
  a bias of 1.5 pixels (in world units, 1.5 x the pixel size) coarse maps let more light
  past near neighbours.

Per depth bias of ``--bias`` (pixels; default the library's and 1.5).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

from growsim.env.light import SHADOW_BIAS_PIXELS

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))


def random_scene(rng):
    """Three random trees (as the light tests build them) and a direction from above."""
    from test_light import population, random_direction

    start, end, radius, offsets = population(rng, 3, int(rng.integers(40, 90)))
    return start, end, radius, offsets, random_direction(rng)


def agreement(resolution: int, seeds: int, bias: float) -> dict:
    from naive.light import segment_exposure_into as exact

    from growsim.env.light import segment_light, view_basis

    same = total = over = 0
    for seed in range(seeds):
        start, end, radius, offsets, d = random_scene(np.random.default_rng(seed))
        got = segment_light(start, end, radius, offsets, d, resolution=resolution, bias=bias) > 0
        u, v = view_basis(d)
        segments, shadow = (start, end, radius, offsets), (resolution, bias, False, None)
        want = exact(segments, None, (u, v, d), 1, shadow) > 0
        # a segment along the light gets cos = 0 either way: judge the shadow only
        cos = np.linalg.norm(np.cross(end - start, d), axis=1) > 0
        got, want = got[cos], want[cos]
        same += int(np.sum(got == want))
        over += int(np.sum(~got & want) - np.sum(got & ~want))
        total += len(got)
    return {"agreement": round(same / total, 4), "net_overshade": round(over / total, 4)}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--seeds", type=int, default=6)
    ap.add_argument("--resolutions", type=int, nargs="+", default=[32, 64, 128, 256, 512])
    ap.add_argument("--bias", type=float, nargs="+", default=[SHADOW_BIAS_PIXELS, 1.5])
    args = ap.parse_args()
    from growsim.env import Light
    from growsim.models import honda

    tree = honda.develop(honda.PRESETS["zelkova"])
    out = {}
    for bias in args.bias:
        for res in args.resolutions:
            row = agreement(res, args.seeds, bias)
            light = Light(resolution=res, bias=bias)
            row["zelkova_mean_light"] = round(float(light.segment_light(tree).mean()), 4)
            out[f"bias {bias} px, resolution {res}"] = row
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
