"""Speed of the hormone-module model (JSON).

    NUMBA_NUM_THREADS=1 python benchmarks/hormone.py [--repeats 3] [--population 10000]

- ``module_steps``: one process, the population path (one kernel call grows a whole
  population: light from the shadow maps of the sun and its sky, water, hormones, growth,
  gravity; :func:`growsim.models.hormone.population`) in the configs' environment (sun a
  little off the vertical, half the light from the sky): module-steps per second (the sum
  over plants and steps of the modules alive, over the wall time), best of
  ``--repeats``, for populations of the demo genomes (2D, 3D) and of genomes drawn at
  random (what a first generation grows); also ``step_wise``, the same plants grown one
  :func:`growsim.models.hormone.grow` at a time (a Plant built after every step); and
  ``walls_module``: the same populations with ``environment.light.walls = "module"`` (one
  shadow-map point per module and light, shared by its walls; the two timed in turn,
  their ``speedup`` measured under one load).
- ``breakdown``: where a module-step's time goes (:func:`breakdown`): per module of a
  grown 2D and 3D demo plant, a whole step, the light (all its passes; the sun's; one sky
  direction's; with the walls sharing their module's exposure) and the hormone step
  alone.
- ``generation``: one generation of ``--population`` individuals in 3D at the model's
  default number of steps (40), scored by the ``nutrient`` objective through the
  experiment's fitness, serially and on a process pool of 2: random genomes (generation
  0) and the 3D demo genome with Gaussian noise (grown plants, as later generations).
"""

from __future__ import annotations

import argparse
import json
import os
import time

import numpy as np


def _rows(params_list):
    from growsim.models import hormone

    rows = [hormone.resolve_params(hormone.PARAMS, p) for p in params_list]
    return np.array([list(r.values()) for r in rows]), list(rows[0])


def _random_genes(rng, n, base):
    from growsim.models import hormone

    return [
        {**base, **{p.name: float(rng.uniform(p.low, p.high)) for p in hormone.GENES}}
        for _ in range(n)
    ]


def _noisy_genes(rng, n, base, sigma=0.1):
    from growsim.models import hormone

    out = []
    for _ in range(n):
        p = dict(base)
        for q in hormone.GENES:
            v = base.get(q.name, q.default) + sigma * (q.high - q.low) * rng.normal()
            p[q.name] = float(min(q.high, max(q.low, v)))
        out.append(p)
    return out


def module_steps(env, repeats: int) -> dict:
    from growsim.models import hormone

    rng = np.random.default_rng(0)
    out = {}
    cases = {
        "demo_2d": [hormone.PRESETS["demo_2d"]] * 20,
        "demo_3d": [hormone.PRESETS["demo_3d"]] * 10,
        "random_3d": _random_genes(rng, 200, {"dims": 3, "steps": 30}),
    }
    shared = _module_walls(env)
    for name, params in cases.items():
        rows, names = _rows(params)
        hormone.population(rows[:1], names, env)  # compile
        hormone.population(rows[:1], names, shared)
        best = {"exact": np.inf, "module": np.inf}
        tables = {}
        for _ in range(repeats):  # the two wall lights in turn: their ratio under one load
            for walls, e in (("exact", env), ("module", shared)):
                t0 = time.perf_counter()
                tables[walls] = hormone.population(rows, names, e)
                best[walls] = min(best[walls], time.perf_counter() - t0)
        ms = int(tables["exact"]["module_steps"].sum())
        ms_shared = int(tables["module"]["module_steps"].sum())
        t0 = time.perf_counter()
        stepwise = sum(sum(p.n_segments for p in hormone.grow(q, env=env)) for q in params[:5])
        t_step = time.perf_counter() - t0
        out[name] = {
            "plants": len(rows),
            "mean_modules": round(float(tables["exact"]["modules"].mean()), 1),
            "module_steps": ms,
            "seconds": round(best["exact"], 4),
            "module_steps_per_s": round(ms / best["exact"]),
            "step_wise_module_steps_per_s": round(stepwise / t_step),
            # environment.light.walls = "module": one exposure per module and light
            "walls_module": {
                "module_steps": ms_shared,
                "seconds": round(best["module"], 4),
                "module_steps_per_s": round(ms_shared / best["module"]),
                "speedup": round(ms_shared / best["module"] / (ms / best["exact"]), 3),
            },
        }
    return out


def _module_walls(env):
    """``env`` with ``light.walls = "module"`` (each module's walls share its exposure)."""
    return env.model_copy(update={"light": env.light.model_copy(update={"walls": "module"})})


def breakdown(env, repeats: int, dims: int = 3) -> dict:
    """Where a module-step's time goes, per module: the demo plant of ``dims`` grown until it
    holds its cap of modules (or 60 steps), then one more step timed from copies of that
    state (CPU time, best of ``repeats`` x 50): in full; with every light's weight 0 (no shadow map
    is drawn: the rest of the step); with the sun alone and with one sky direction alone
    (their maps' cost: the time over the step without light); and the hormone step alone
    (:func:`growsim.kernels.hormone.step_kernel`: synthesis, growth, branching)."""
    from growsim.kernels import hormone as K
    from growsim.models import hormone

    p = hormone.resolve_params(hormone.PARAMS, hormone.PRESETS[f"demo_{dims}d"])
    n, s = hormone.seedling(p, env)
    for _ in range(60):
        if n >= len(s["modules"].parent):  # the cap
            break
        n, _code = K.grow_step(n, *s.values())

    def copy():  # the scratch is shared, as in growth (left as given by every step)
        return {**s, "modules": K.Modules(*(a.copy() for a in s["modules"]))}

    def timed(fn) -> float:  # CPU time: a busy machine's other jobs do not count
        fn(copy())  # compile
        best = np.inf
        for _ in range(repeats):
            states = [copy() for _ in range(50)]
            t0 = time.process_time()
            for x in states:
                fn(x)
            best = min(best, (time.process_time() - t0) / 50)
        return best

    w = s["env"].weights

    def step(weights):
        def fn(x):
            x["env"] = x["env"]._replace(weights=weights)
            K.grow_step(n, *x.values())

        return fn

    def hormone_step(x):
        K.step_kernel(n, x["dims"], x["modules"], x["genes"], x["c"])

    def shared_step(x):  # environment.light.walls = "module"
        x["env"] = x["env"]._replace(shared=True)
        K.grow_step(n, *x.values())

    t = {"full": timed(step(w)), "no_light": timed(step(np.zeros_like(w)))}
    t["full_walls_module"] = timed(shared_step)
    for j in np.flatnonzero(w):
        t[f"pass_{j}"] = timed(step(np.where(np.arange(len(w)) == j, w, 0.0)))
    t["hormone_step"] = timed(hormone_step)
    us = {k: v / n * 1e6 for k, v in t.items()}
    return {
        "modules": n,
        "walls": s["modules"].hormone.shape[1],
        "light_passes": int(np.count_nonzero(w)),
        "us_per_module": {k: round(v, 3) for k, v in us.items()},
        "light_us_per_module": round(us["full"] - us["no_light"], 3),
        "light_us_per_module_walls_module": round(us["full_walls_module"] - us["no_light"], 3),
        "pass_us_per_module": [  # the sun's, then each sky direction's
            round(us[f"pass_{j}"] - us["no_light"], 3) for j in np.flatnonzero(w)
        ],
    }


def generation(population: int) -> dict:
    from concurrent.futures import ProcessPoolExecutor

    from growsim.experiment import load_plan
    from growsim.models import hormone

    rng = np.random.default_rng(1)
    out = {"population": population, "steps": 40}
    demo = hormone.PRESETS["demo_3d"]
    for name, params in (
        ("random", _random_genes(rng, population, {})),
        ("grown", _noisy_genes(rng, population, demo)),
    ):
        f = load_plan("experiments/hormone_3d.toml", ["model.params.steps=40"]).fitness()
        x = np.array([[p.get(n, demo.get(n)) for n in f.evolved] for p in params])
        f(x[:2])  # compile
        t0 = time.perf_counter()
        serial = f(x)
        t_serial = time.perf_counter() - t0
        with ProcessPoolExecutor(2) as pool:
            list(pool.map(f, [x[:2], x[2:4]]))  # start and compile the workers
            t0 = time.perf_counter()
            parts = list(pool.map(f, np.array_split(x, 8)))
            t_pool = time.perf_counter() - t0
        assert np.array_equal(np.concatenate(parts), serial, equal_nan=True)
        table = hormone.population(f.full_params(x[:200]), f.names, f.env)
        out[name] = {
            "serial_s": round(t_serial, 2),
            "pool2_s": round(t_pool, 2),
            "pool2_speedup": round(t_serial / t_pool, 2),
            "mean_modules_first_200": round(float(table["modules"].mean()), 1),
        }
    return out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--population", type=int, default=10000)
    ap.add_argument("--only", choices=["module_steps", "breakdown", "generation"])
    args = ap.parse_args()
    from growsim.env import Environment

    env = Environment.model_validate({"light": {"diffuse": 0.5, "direction": [0.3, -1, 0.2]}})
    out = {"numba_threads": os.environ.get("NUMBA_NUM_THREADS", "default")}
    load = os.getloadavg()[0]
    if args.only in (None, "module_steps"):
        out["module_steps"] = module_steps(env, args.repeats)
    if args.only in (None, "breakdown"):
        out["breakdown"] = {f"{d}d": breakdown(env, args.repeats, d) for d in (2, 3)}
    if args.only in (None, "generation"):
        out["generation"] = generation(args.population)
    out["load_1min"] = [round(load, 2), round(os.getloadavg()[0], 2)]
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
