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
- ``sizes``: where a module-step's time goes by plant size (:func:`sizes`): the 3D demo
  genome made to branch more (:data:`BIG`: shorter modules, 4 laterals, less upkeep; the
  demo itself levels off at about 450 modules) grown to a cap of 100, 300, 1,000 and
  3,000 modules (``max_modules``, up to 600 steps), then one step timed per module
  (CPU time): whole, the light and each of its passes, the rest, water, the hormone
  step, mechanics (thickening, gravity, the loads' design), placing and drawing.
- ``strictness``: not a timing but how strict issue 44's model check is
  (:func:`strictness`), judged by ``tests/test_hormone_speed.py``'s :func:`agreement` on
  its grown states (the share of modules whose light is within 2 %, of steps and of
  module-steps with the same growth decisions): one step with the shadow maps at 48 to
  192 px against the same step at 256 px, and the current step with the sun and the sky
  turned by 0.1 to 1 degree about the vertical against the current step.
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


#: the demo genome made to branch more, for plants of thousands of modules (``sizes``):
#: 1,000 modules after about 90 steps, 2,600 after 300 (the demo levels off near 450)
BIG = {"max_length": 0.2, "new_length": 0.1, "laterals": 4, "upkeep": 5.0, "leaf_upkeep": 0.5}


def _grown(p, env, cap, max_steps=600):
    """The plant of resolved parameters ``p`` with ``max_modules = cap`` grown in ``env``
    until it holds ``cap`` modules (or ``max_steps`` steps, or it stops: the module count
    before the stopping step): ``(n, state, steps)``."""
    from growsim.kernels import hormone as K
    from growsim.models import hormone

    n, s = hormone.seedling({**p, "max_modules": cap}, env)
    steps = 0
    while steps < max_steps and n < cap:
        steps += 1
        n2, code = K.grow_step(n, *s.values())
        if code not in (K.STOP_NONE, K.STOP_CAP):
            break
        n = n2
    return n, s, steps


def sizes(env, repeats: int, caps=(100, 300, 1000, 3000)) -> dict:
    """Where a 3D module-step's time goes by plant size: the :data:`BIG` genome grown to
    each cap (:func:`_grown`), then its next step timed part by part (:func:`_size_row`)."""
    from growsim.models import hormone

    p = hormone.resolve_params(hormone.PARAMS, {**hormone.PRESETS["demo_3d"], **BIG})
    out = {"genome": "demo_3d with " + json.dumps(BIG)}
    for cap in caps:
        n, s, steps = _grown(p, env, cap)
        out[str(cap)] = {"modules": n, "steps_grown": steps, **_size_row(n, s, repeats)}
    return out


def _size_row(n, s, repeats):
    """One step of the plant of ``n`` modules in state ``s`` (:func:`seedling`'s) timed
    from copies of it (CPU time, best of ``repeats``, each the mean over enough copies for
    about 0.1 s), per module in us: the whole step; the light kernel alone
    (:func:`~growsim.kernels.hormone_light.lights_kernel`, walls and leaves, every light;
    then one light at a time); the rest (whole less light); water, the hormone step,
    mechanics (thickening, gravity, the loads' design) and placing with drawing alone."""
    from growsim.kernels import hormone as K
    from growsim.kernels.hormone_light import LEAVES, WALLS, lights_kernel, module_ends
    from growsim.kernels.hormone_mechanics import design_kernel, gravity_kernel, thicken_kernel
    from growsim.kernels.water import transport_into_kernel

    m0, e = s["modules"], s["env"]
    w = e.weights

    def copy():
        return {**s, "modules": K.Modules(*(a.copy() for a in m0))}

    def timed(fn) -> float:
        fn(copy())  # compile
        t0 = time.process_time()
        fn(copy())
        k = max(3, min(200, int(0.1 / max(time.process_time() - t0, 1e-6))))
        best = np.inf
        for _ in range(repeats):
            states = [copy() for _ in range(k)]
            t0 = time.process_time()
            for x in states:
                fn(x)
            best = min(best, (time.process_time() - t0) / k)
        return best

    def step(x):
        K.grow_step(n, *x.values())

    def light(weights):  # the light kernel alone, on the placed and drawn plant
        def fn(x):
            lights_kernel(n, x["dims"], x["modules"], e._replace(weights=weights),
                          x["shifts"], x["scratch"], WALLS | LEAVES)  # fmt: skip

        return fn

    def hormone_step(x):
        K.step_kernel(n, x["dims"], x["modules"], x["genes"], x["c"])

    start = m0.origin[:n]
    ends = module_ends(n, m0.origin, m0.length, m0.R, np.empty((n, 3)))
    demand = s["c"][0, K.C_TRANSPIRATION] * m0.leaf[:n] * m0.leaf_light[:n]

    def water(x):
        m = x["modules"]
        transport_into_kernel(start, ends, m.radius[:n], m.parent[:n], demand,
                              e.supply * e.soil, e.resistance, e.lift, m.water[:n],
                              m.met[:n])  # fmt: skip

    def mechanics(x):
        m = x["modules"]
        thicken_kernel(n, m, x["c"])
        n2, _ = gravity_kernel(n, m, x["c"], x["strength_young"], e, False)
        design_kernel(n2, m, x["c"], x["strength_young"],
                      (e.density, e.leaf_mass_per_area, e.g, e.strength))  # fmt: skip

    def place_draw(x):
        m = x["modules"]
        K.place_kernel(n, m.parent, m.R, m.length, m.origin)
        K.drawn_kernel(n, m)

    t = {"full": timed(step), "light": timed(light(w))}
    lit = np.flatnonzero(w)
    for j in lit:
        t[f"pass_{j}"] = timed(light(np.where(np.arange(len(w)) == j, w, 0.0)))
    for name, fn in (("water", water), ("hormone_step", hormone_step),
                     ("mechanics", mechanics), ("place_draw", place_draw)):  # fmt: skip
        t[name] = timed(fn)
    us = {k: v / n * 1e6 for k, v in t.items()}
    parts = ("water", "hormone_step", "mechanics", "place_draw")
    return {
        "step_ms": round(t["full"] * 1e3, 3),
        "module_steps_per_s": round(n / t["full"]),
        "us_per_module": {
            "full": round(us["full"], 3),
            "light": round(us["light"], 3),
            # one light at a time (each with the kernel's own setup): the sun's, the sky's
            "light_passes": [round(us[f"pass_{j}"], 3) for j in lit],
            "rest": round(us["full"] - us["light"], 3),
            **{k: round(us[k], 3) for k in parts},
        },
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


def strictness(resolutions=(48, 64, 96, 128, 192), reference=256, turns=(0.1, 0.5, 1.0)):
    """Issue 44's check (``tests/test_hormone_speed.py``) applied to changes that leave the
    model as it is: one step of the current kernels at each of ``resolutions`` px against
    one at ``reference`` px, and with every light turned by ``turns`` degrees about the
    vertical against the current step, from the check's grown states."""
    import math
    import sys
    from pathlib import Path

    from growsim.kernels import hormone as K
    from growsim.kernels.light import shadow_scratch

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
    from test_hormone_speed import agreement, grown_states

    def at(res):
        def step(n, state):
            state["env"] = state["env"]._replace(resolution=res)
            state["scratch"] = shadow_scratch(res)
            return K.grow_step(n, *state.values())

        return step

    def turned(deg):
        c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
        rot = np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]]).T

        def step(n, state):
            e = state["env"]
            state["env"] = e._replace(dirs=e.dirs @ rot, us=e.us @ rot, vs=e.vs @ rot)
            return K.grow_step(n, *state.values())

        return step

    def judged(candidate, ref):
        a = agreement(candidate, ref, states)
        return {k: round(v, 3) for k, v in a.items() if k != "steps"}

    states = grown_states()
    return {
        "states": len(states),
        "modules": sum(n for n, _ in states),
        "resolution_against_256px": {str(r): judged(at(r), at(reference)) for r in resolutions},
        "turned_deg": {str(t): judged(turned(t), turned(0.0)) for t in turns},
    }


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--population", type=int, default=10000)
    ap.add_argument(
        "--only", choices=["module_steps", "breakdown", "sizes", "strictness", "generation"]
    )
    args = ap.parse_args()
    from growsim.env import Environment

    env = Environment.model_validate({"light": {"diffuse": 0.5, "direction": [0.3, -1, 0.2]}})
    out = {"numba_threads": os.environ.get("NUMBA_NUM_THREADS", "default")}
    load = os.getloadavg()[0]
    if args.only in (None, "module_steps"):
        out["module_steps"] = module_steps(env, args.repeats)
    if args.only in (None, "breakdown"):
        out["breakdown"] = {f"{d}d": breakdown(env, args.repeats, d) for d in (2, 3)}
    if args.only in (None, "sizes"):
        out["sizes"] = sizes(env, args.repeats)
    if args.only in (None, "strictness"):
        out["strictness"] = strictness()
    if args.only in (None, "generation"):
        out["generation"] = generation(args.population)
    out["load_1min"] = [round(load, 2), round(os.getloadavg()[0], 2)]
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
