"""growsim's GA against DEAP (eaSimple) and pymoo (GA) on the same problems and budgets.

OneMax 1000 bits x population 1000 and Rastrigin-30D x population 1000, 20 generations
each, every library in this process, each run repeated (``--repeats``) with seeds 0, 1, ...
growsim uses its default operators for the coding. Prints JSON: per library and problem
the median milliseconds per generation (wall time of the whole run / 20, so initial
population and bookkeeping are included), the mean final best fitness, and ratios.

    .venv/bin/python benchmarks/ga_vs_peers.py [--repeats 3] [--generations 20]

``--overhead``: the per-generation overhead at populations 20, 50 and 100 on a microsecond
fitness (Sphere-10D): growsim's defaults, DEAP's (mu+lambda) GA of ``benchmarks/bbob.py``
and pymoo's GA, ms per generation (median over ``--repeats``; use ``--generations 200``).
DEAP's OneMax is lean (bits in ``array.array``, two-point crossover, flip 1/L, tournament
3, eaSimple) and its Rastrigin evaluates with ``math.cos``.
"""

from __future__ import annotations

import argparse
import array
import json
import math
import os
import platform
import random
import statistics
import time

import numpy as np

POP = 1000
ONEMAX_BITS = 1000
RASTRIGIN_DIM = 30
LOW, HIGH = -5.12, 5.12


def onemax_np(x):
    return x.sum(axis=1)


def rastrigin_np(x):
    return 10.0 * x.shape[1] + (x * x - 10.0 * np.cos(2.0 * np.pi * x)).sum(axis=1)


# -- growsim ---------------------------------------------------------------------------
def growsim_run(problem, gens, seed):
    from growsim.ga import GA, Bits, Genome, Real

    if problem == "onemax":
        g = Genome([Bits("b", 0, 1, bits=1, size=ONEMAX_BITS)])
        ga = GA(g, onemax_np, population=POP, maximize=True, seed=seed)
    else:
        g = Genome([Real("x", LOW, HIGH, size=RASTRIGIN_DIM)])
        ga = GA(g, rastrigin_np, population=POP, maximize=False, seed=seed)
    t = time.perf_counter()
    r = ga.run(generations=gens)
    return time.perf_counter() - t, float(r.best.fitness)


# -- DEAP ------------------------------------------------------------------------------
def _deap_creator():
    from deap import base, creator

    if not hasattr(creator, "FitMax"):
        creator.create("FitMax", base.Fitness, weights=(1.0,))
        creator.create("FitMin", base.Fitness, weights=(-1.0,))
        # a lean DEAP: bits in array.array (typecode "b"), reals in a list
        creator.create("IndBits", array.array, typecode="b", fitness=creator.FitMax)
        creator.create("IndMin", list, fitness=creator.FitMin)
    return creator


def deap_run(problem, gens, seed):
    from deap import algorithms, base, tools

    random.seed(seed)
    creator = _deap_creator()
    tb = base.Toolbox()
    if problem == "onemax":
        # DEAP's OneMax example made lean: array.array bits, two-point crossover, flip 1/L,
        # tournament 3, eaSimple (cxpb 0.5, mutpb 0.2)
        tb.register("attr", random.randint, 0, 1)
        tb.register("individual", tools.initRepeat, creator.IndBits, tb.attr, ONEMAX_BITS)
        tb.register("evaluate", lambda ind: (sum(ind),))
        tb.register("mate", tools.cxTwoPoint)
        tb.register("mutate", tools.mutFlipBit, indpb=1.0 / ONEMAX_BITS)
        tb.register("select", tools.selTournament, tournsize=3)
        best = max
    else:
        tb.register("attr", random.uniform, LOW, HIGH)
        tb.register("individual", tools.initRepeat, creator.IndMin, tb.attr, RASTRIGIN_DIM)
        cos, two_pi = math.cos, 2.0 * math.pi

        def rastrigin(ind):  # lean: math.cos on Python floats
            return (10.0 * len(ind) + sum(x * x - 10.0 * cos(two_pi * x) for x in ind),)

        tb.register("evaluate", rastrigin)
        tb.register("mate", tools.cxSimulatedBinaryBounded, low=LOW, up=HIGH, eta=15.0)
        tb.register(
            "mutate",
            tools.mutPolynomialBounded,
            low=LOW,
            up=HIGH,
            eta=20.0,
            indpb=1.0 / RASTRIGIN_DIM,
        )
        tb.register("select", tools.selTournament, tournsize=3)
        best = min
    tb.register("population", tools.initRepeat, list, tb.individual)
    pop = tb.population(n=POP)
    t = time.perf_counter()
    pop, _ = algorithms.eaSimple(pop, tb, cxpb=0.5, mutpb=0.2, ngen=gens, verbose=False)
    dt = time.perf_counter() - t
    return dt, float(best(ind.fitness.values[0] for ind in pop))


# -- pymoo -----------------------------------------------------------------------------
def pymoo_run(problem, gens, seed):
    from pymoo.algorithms.soo.nonconvex.ga import GA as PGA
    from pymoo.core.problem import Problem
    from pymoo.operators.crossover.pntx import TwoPointCrossover
    from pymoo.operators.mutation.bitflip import BitflipMutation
    from pymoo.operators.sampling.rnd import BinaryRandomSampling
    from pymoo.optimize import minimize

    if problem == "onemax":

        class OneMax(Problem):
            def __init__(self):
                super().__init__(n_var=ONEMAX_BITS, n_obj=1, xl=0, xu=1, vtype=bool)

            def _evaluate(self, x, out, *args, **kwargs):
                out["F"] = -x.sum(axis=1).astype(float)

        prob = OneMax()
        # pymoo's documented binary GA
        algo = PGA(
            pop_size=POP,
            sampling=BinaryRandomSampling(),
            crossover=TwoPointCrossover(),
            mutation=BitflipMutation(),
            eliminate_duplicates=True,
        )
        sign = -1.0
    else:

        class Rastrigin(Problem):
            def __init__(self):
                super().__init__(n_var=RASTRIGIN_DIM, n_obj=1, xl=LOW, xu=HIGH)

            def _evaluate(self, x, out, *args, **kwargs):
                out["F"] = rastrigin_np(x)

        prob = Rastrigin()
        algo = PGA(pop_size=POP, eliminate_duplicates=True)  # SBX + polynomial mutation
        sign = 1.0
    t = time.perf_counter()
    res = minimize(prob, algo, ("n_gen", gens), seed=seed, verbose=False)
    dt = time.perf_counter() - t
    return dt, float(sign * res.F[0])


RUNNERS = {"growsim": growsim_run, "deap": deap_run, "pymoo": pymoo_run}


# -- per-generation overhead at small populations ----------------------------------------
SMALL_DIM = 10


def _sphere_row(ind):
    return (sum(x * x for x in ind),)


def overhead_growsim(pop, gens, seed):
    from growsim.ga import GA, Genome, Real

    g = Genome([Real("x", -5.0, 5.0, size=SMALL_DIM)])
    ga = GA(g, lambda x: (x * x).sum(axis=1), population=pop, maximize=False, seed=seed)
    t = time.perf_counter()
    ga.run(generations=gens)
    return time.perf_counter() - t


def overhead_deap(pop, gens, seed):
    # the (mu+lambda) GA of benchmarks/bbob.py: blend 0.7, Gaussian 0.2, tournament 3
    from deap import algorithms, base, tools

    random.seed(seed)
    creator = _deap_creator()
    tb = base.Toolbox()
    tb.register("attr", random.uniform, -5.0, 5.0)
    tb.register("individual", tools.initRepeat, creator.IndMin, tb.attr, SMALL_DIM)
    tb.register("evaluate", _sphere_row)
    tb.register("mate", tools.cxBlend, alpha=0.5)
    tb.register("mutate", tools.mutGaussian, mu=0.0, sigma=1.0, indpb=1.0 / SMALL_DIM)
    tb.register("select", tools.selTournament, tournsize=3)
    p = [tb.individual() for _ in range(pop)]
    t = time.perf_counter()
    algorithms.eaMuPlusLambda(p, tb, pop, pop, 0.7, 0.2, gens - 1, verbose=False)
    return time.perf_counter() - t


def overhead_pymoo(pop, gens, seed):
    from pymoo.algorithms.soo.nonconvex.ga import GA as PGA
    from pymoo.core.problem import Problem
    from pymoo.optimize import minimize

    class Sphere(Problem):
        def __init__(self):
            super().__init__(n_var=SMALL_DIM, n_obj=1, xl=-5.0, xu=5.0)

        def _evaluate(self, x, out, *args, **kwargs):
            out["F"] = (x * x).sum(axis=1)

    t = time.perf_counter()
    minimize(Sphere(), PGA(pop_size=pop, eliminate_duplicates=True), ("n_gen", gens), seed=seed)
    return time.perf_counter() - t


def overhead(populations, gens, repeats) -> dict:
    """ms per generation at small populations on a microsecond fitness (Sphere-10D)."""
    overhead_growsim(20, 5, 99)  # warm-up (numba cache)
    out = {}
    for pop in populations:
        row = {}
        for lib, fn in (("growsim", overhead_growsim), ("deap", overhead_deap),
                        ("pymoo", overhead_pymoo)):  # fmt: skip
            ts = [fn(pop, gens, seed) / gens for seed in range(repeats)]
            row[lib] = round(statistics.median(ts) * 1e3, 3)
        row["deap_over_growsim"] = round(row["deap"] / row["growsim"], 1)
        row["pymoo_over_growsim"] = round(row["pymoo"] / row["growsim"], 1)
        out[f"population {pop}"] = row
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--generations", type=int, default=20)
    ap.add_argument("--libs", default="growsim,deap,pymoo", help="comma-separated subset")
    ap.add_argument(
        "--overhead",
        action="store_true",
        help="instead: ms per generation at populations 20, 50, 100 on Sphere-10D",
    )
    args = ap.parse_args(argv)
    if args.overhead:
        load0 = os.getloadavg()[0]
        res = overhead((20, 50, 100), args.generations, args.repeats)
        res["load_avg_1min"] = [load0, os.getloadavg()[0]]
        print(json.dumps(res, indent=2))
        return
    libs = [x.strip() for x in args.libs.split(",") if x.strip()]
    unknown = sorted(set(libs) - set(RUNNERS))
    if unknown or "growsim" not in libs:
        ap.error(f"--libs: need growsim, allowed {', '.join(RUNNERS)}; got {args.libs}")
    gens = args.generations
    # warm-up: numba compiles (or loads its cache) once, outside the timings
    growsim_run("onemax", 2, 99)
    growsim_run("rastrigin", 2, 99)
    out = {
        "machine": {
            "cpus": os.cpu_count(),
            "python": platform.python_version(),
            "load_avg_1min": os.getloadavg()[0],
        },
        "population": POP,
        "generations": gens,
        "repeats": args.repeats,
        "problems": {},
    }
    for problem in ("onemax", "rastrigin"):
        res = {}
        for lib in libs:
            fn = RUNNERS[lib]
            times, fits = [], []
            for seed in range(args.repeats):
                dt, f = fn(problem, gens, seed)
                times.append(dt)
                fits.append(f)
            res[lib] = {
                "ms_per_generation": round(statistics.median(times) / gens * 1e3, 3),
                "final_best_mean": round(statistics.fmean(fits), 2),
                "final_best_runs": [round(f, 2) for f in fits],
            }
        peers = [res[p] for p in ("deap", "pymoo") if p in res]
        if not peers:
            out["problems"][problem] = res
            continue
        fastest = min(p["ms_per_generation"] for p in peers)
        if problem == "onemax":
            best_peer = max(p["final_best_mean"] for p in peers)
            as_good = res["growsim"]["final_best_mean"] >= best_peer
        else:
            best_peer = min(p["final_best_mean"] for p in peers)
            as_good = res["growsim"]["final_best_mean"] <= best_peer
        res["speedup_vs_fastest_peer"] = round(fastest / res["growsim"]["ms_per_generation"], 2)
        res["best_peer_final"] = best_peer
        res["growsim_at_least_as_good"] = bool(as_good)
        res["floor_met"] = bool(as_good and res["speedup_vs_fastest_peer"] >= 10.0)
        out["problems"][problem] = res
    out["machine"]["load_avg_1min_end"] = os.getloadavg()[0]
    print(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
