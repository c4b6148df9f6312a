"""Speed of the environment's passes over whole populations (JSON).

    NUMBA_NUM_THREADS=1 python benchmarks/environment.py [--plants 1000] [--segments 300]
        [--resolutions 64 128 256] [--backends numba moderngl]
        [--only gravity water light crossover]

A population of random parents-first skeletons (``--plants`` x ``--segments``; 30 % leaves)
in one array. For each pass: the kernel alone (arrays prepared once, the output buffer
reused: the figure the issue's floors are about) and the public function on the whole
population (input checks included), in million segments per second, best of 20 (kernel)
or 5 (public) runs. Passes: gravity (``growsim.env.Gravity``: mass above, moments, stress
ratios and each plant's first break) and water (``growsim.env.water.transport``: subtree
demands up, shares down; demand 1 per leaf) and light (``growsim.env.light.segment_light``
on the whole population, light from above, one shadow map per plant: frames, render,
every segment's midpoint queried, cosines; hard and soft shadows with numba, hard with
moderngl; best of 10 at up to 256 pixels, else 3: a shared machine's noise is
one-sided; for numba also in CPU time, ``*_cpu_msegments_per_s``). ``--only
crossover``: moderngl's time over numba's for 1, 10 and 100 plants per call at 256, 512
and 1024 pixels (when moderngl wins).
"""

from __future__ import annotations

import argparse
import json
import os
import time

import numpy as np


def forest(n_plants: int, n_segments: int, seed: int = 0):
    """One :class:`growsim.phenotypes.plant.Plant` holding ``n_plants`` random trees, parents
    first."""
    from growsim.phenotypes.plant import Plant

    rng = np.random.default_rng(seed)
    plants = []
    for _ in range(n_plants):
        parent = np.array(
            [-1] + [int(rng.integers(max(0, s - 20), s)) for s in range(1, n_segments)]
        )
        d = rng.normal(size=(n_segments, 3)) * 0.3
        d[:, 1] = np.abs(d[:, 1])
        start = np.zeros((n_segments, 3))
        end = np.zeros((n_segments, 3))
        for s in range(n_segments):
            if parent[s] >= 0:
                start[s] = end[parent[s]]
            end[s] = start[s] + d[s]
        kind = (rng.random(n_segments) < 0.3).astype(np.int8)
        kind[0] = 0
        radius = rng.uniform(0.005, 0.1, n_segments)
        plants.append(Plant(start, end, radius, parent, np.zeros(n_segments, np.int32), kind))
    return Plant.concat(plants)


def best_of(fn, repeats: int, clock=time.perf_counter) -> float:
    """The shortest of ``repeats`` timed calls of ``fn`` (after one untimed call), by
    ``clock`` (wall time; ``time.process_time`` for this process's CPU time, which other
    jobs on a shared machine do not lengthen)."""
    fn()
    times = []
    for _ in range(repeats):
        t0 = clock()
        fn()
        times.append(clock() - t0)
    return min(times)


def gravity(plants, n_plants: int, n_segments: int) -> dict:
    from growsim.env import Gravity
    from growsim.kernels.gravity import first_break_kernel, loads_kernel

    g = Gravity()
    n = plants.n_segments
    radius_end = plants.radius_end()
    strength = np.full(n, g.strength)
    offsets = np.arange(0, n + 1, n_segments, dtype=np.int64)
    out = np.empty((4, n))

    def kernel():
        o = loads_kernel(
            plants.start, plants.end, plants.radius, radius_end, plants.parent, plants.kind,
            strength, (g.density, g.leaf_mass_per_area, g.g), out,
        )  # fmt: skip
        return first_break_kernel(o[3], offsets)

    t_kernel = best_of(kernel, 20)
    t_public = best_of(lambda: g.loads(plants), 5)
    return {
        "kernel_ms": round(t_kernel * 1e3, 2),
        "kernel_msegments_per_s": round(n / t_kernel / 1e6, 1),
        "public_ms": round(t_public * 1e3, 2),
        "public_msegments_per_s": round(n / t_public / 1e6, 1),
    }


def water(plants) -> dict:
    from growsim.env.water import LIFT, RESISTANCE, segment_demand, transport
    from growsim.kernels.water import transport_into_kernel

    n = plants.n_segments
    light = (plants.kind == 1).astype(np.float64)
    demand = segment_demand(plants.kind, light, plants.lengths(), 0.0)
    received, met = np.empty(n), np.empty(n)

    def kernel():
        transport_into_kernel(
            plants.start, plants.end, plants.radius, plants.parent, demand, 1.0,
            RESISTANCE, LIFT, received, met,
        )  # fmt: skip

    t_kernel = best_of(kernel, 20)
    t_public = best_of(lambda: transport(plants, light), 5)
    return {
        "kernel_ms": round(t_kernel * 1e3, 2),
        "kernel_msegments_per_s": round(n / t_kernel / 1e6, 1),
        "public_ms": round(t_public * 1e3, 2),
        "public_msegments_per_s": round(n / t_public / 1e6, 1),
    }


def light(plants, n_plants: int, n_segments: int, resolutions, backends) -> dict:
    """The shadow-map light through the whole pass (frames, render, query every segment's
    midpoint, cosines): the public :func:`growsim.env.light.segment_light` on the whole
    population, light from above, per resolution, shadow mode and backend."""
    from growsim.env.light import segment_light

    offsets = np.arange(0, plants.n_segments + 1, n_segments, dtype=np.int64)
    n = plants.n_segments
    out = {}
    for res in resolutions:
        row = {}
        for shadows, backend in (("hard", "numba"), ("soft", "numba"), ("hard", "moderngl")):
            if backend not in backends:
                continue
            try:
                t = best_of(
                    lambda s=shadows, b=backend, r=res: segment_light(
                        plants, offsets=offsets, resolution=r, shadows=s, backend=b
                    ),
                    10 if res <= 256 else 3,
                )
            except Exception as exc:  # no GL context: say why, keep the other figures
                row[f"{shadows}_{backend}"] = f"unavailable: {exc}"
                continue
            row[f"{shadows}_{backend}_ms"] = round(t * 1e3, 1)
            row[f"{shadows}_{backend}_msegments_per_s"] = round(n / t / 1e6, 2)
            if backend == "numba":  # one thread: its CPU time is its time on a free core
                cpu = best_of(
                    lambda s=shadows, r=res: segment_light(
                        plants, offsets=offsets, resolution=r, shadows=s
                    ),
                    10 if res <= 256 else 3,
                    time.process_time,
                )
                row[f"{shadows}_{backend}_cpu_msegments_per_s"] = round(n / cpu / 1e6, 2)
        out[str(res)] = row
    return out


def crossover(plant_counts=(1, 10, 100), resolutions=(256, 512, 1024)) -> list[dict]:
    """When moderngl wins: its time over numba's (hard shadows, the public function, best
    of 5) per number of plants per call and resolution; below 1 moderngl is faster."""
    from growsim.env.light import segment_light

    rows = []
    for k in plant_counts:
        plants = forest(k, 300)
        offsets = np.arange(0, k * 300 + 1, 300, dtype=np.int64)
        row = {"plants_per_call": k}
        for res in resolutions:
            t = {
                b: best_of(
                    lambda b=b, r=res, p=plants, o=offsets: segment_light(
                        p, offsets=o, resolution=r, backend=b
                    ),
                    5,
                )
                for b in ("numba", "moderngl")
            }
            row[f"moderngl_over_numba_{res}"] = round(t["moderngl"] / t["numba"], 2)
        rows.append(row)
    return rows


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--plants", type=int, default=1000)
    ap.add_argument("--segments", type=int, default=300)
    ap.add_argument("--resolutions", type=int, nargs="+", default=[64, 128, 256])
    ap.add_argument("--backends", nargs="+", default=["numba", "moderngl"])
    ap.add_argument("--only", choices=["gravity", "water", "light", "crossover"], nargs="+")
    args = ap.parse_args()
    plants = forest(args.plants, args.segments)
    result = {
        "plants": args.plants,
        "segments_per_plant": args.segments,
        "numba_threads": os.environ.get("NUMBA_NUM_THREADS", "default"),
        "load_1min": round(os.getloadavg()[0], 2),
    }
    only = args.only or ["gravity", "water", "light"]
    if "crossover" in only:
        result["crossover"] = crossover()
    if "gravity" in only:
        result["gravity"] = gravity(plants, args.plants, args.segments)
    if "water" in only:
        result["water"] = water(plants)
    if "light" in only:
        result["light"] = light(plants, args.plants, args.segments, args.resolutions, args.backends)
    print(json.dumps(result, indent=1))


if __name__ == "__main__":
    main()
