"""growsim's default real-coded GA beside DEAP, pymoo and pycma on the COCO/BBOB suite.

The 24 noiseless BBOB functions (``cocoex``, suite ``"bbob"``; Hansen et al., "Real-
Parameter Black-Box Optimization Benchmarking 2009: Noiseless Functions Definitions"),
search box ``[-5, 5]^D``, instances 1-3, several seeds. Every algorithm runs once per
(function, dimension, instance, seed) up to the largest budget; the best-so-far is
recorded at every improvement, so the precision ``f - f_opt`` (floored at 1e-8, COCO's
final target) at each smaller budget and the evaluations to reach each of COCO's 51
targets ``10^2 .. 10^-8`` come from the same run (all algorithms here are budget-blind).

Algorithms (``--algorithms``):

- ``growsim``: ``GA(Genome([Real("x", -5, 5, size=D)]), f, population=P, maximize=False)``
  and nothing else: its defaults (``--growsim '{"model": ...}'`` tries other options);
- ``deap``: DEAP's ``eaMuPlusLambda`` (mu = lambda = P) as a user writes it: uniform
  initial population in the box, blend crossover (``cxBlend``, alpha 0.5) with probability
  0.7, Gaussian mutation (sigma 1 = 10 % of the range, each gene with probability 1/D)
  with probability 0.2, tournament of 3;
- ``pymoo-ga``: pymoo's ``GA(pop_size=P, eliminate_duplicates=True)`` (tournament, SBX,
  polynomial mutation, (mu+lambda) survival);
- ``pymoo-de``: pymoo's ``DE(pop_size=P)`` (DE/rand/1/bin);
- ``cma``: pycma's CMA-ES (the reference, not a GA) with its default population, from a
  uniform point in ``[-4, 4]^D`` with sigma 2, restarted with twice the population when it
  stops (IPOP-CMA-ES, Auger & Hansen 2005) until the budget is spent.

A **problem** is a (function, dimension) pair; its runs are instances x seeds. growsim is
**as good as** a peer on a problem when (a) its median final precision is at most the
peer's ("median"), or, the statistical reading, (b) a one-sided Mann-Whitney U test does
not find growsim's precisions larger than the peer's at the 5 % level ("not worse").
The bar compares growsim with the **better peer** of each problem among ``deap`` and
``pymoo-ga`` (the one with the smaller median).

    python benchmarks/bbob.py --dims 10,20 --budgets 100,400,1000 --seeds 0-4 --jobs 2 \\
        --out benchmarks/results/bbob.parquet
    python benchmarks/bbob.py --functions 1,8,15 --dims 10 --instances 1 --seeds 0  # quick
    python benchmarks/bbob.py --suite bits --seeds 0-4   # the bit suite (below)
    # runs not used to choose the defaults (seeds 10-13), all three budgets:
    P=1:10,2:10,3:10,1:11,2:11,3:11,1:12,2:12,3:12,1:13,2:13,3:13
    python benchmarks/bbob.py --pairs $P --budgets 100,400,1000 \
        --algorithms growsim,deap,pymoo-ga --out benchmarks/results/bbob_fresh.parquet

``--pairs 1:0,1:1,2:0`` runs those (instance, seed) pairs instead of instances x seeds.
``--suite bits``: OneMax, LeadingOnes, deceptive traps and an NK landscape on 100 bits
(``--bit-budget`` evaluations, ``--populations``), growsim's bit defaults and
``--variants`` beside DEAP's OneMax-example GA; prints solved runs, evaluations to the
optimum and median best per problem and population.

Prints JSON: the set-up, per (dimension, budget) the summary (problems where growsim is
as good as each peer and the better GA peer, by both readings; the aggregated ECDF: the
share of (run, target) pairs reached, COCO's runtime view), and per problem the median
precisions. ``--out`` saves the per-run table (parquet) and the JSON beside it;
``--cache`` re-uses the peers' runs of an earlier ``--out`` (growsim is always re-run);
``--summarise RUNS.parquet`` prints the summary of saved runs. ``halves`` in the JSON
measures how hard the bar's comparator is: each algorithm's median on half of the seeds
against the better GA peer's on the other half (a twin of pymoo's GA scores about half).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import random
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
import pandas as pd

LOW, HIGH = -5.0, 5.0
#: COCO's 51 targets 10^2 .. 10^-8 (five per decade)
TARGETS = 10.0 ** np.linspace(2, -8, 51)
FLOOR = 1e-8
PEERS = ("deap", "pymoo-ga")  # the bar's peers: the GAs


class Budget(Exception):
    """Raised by :class:`Recorder` when an algorithm asks for more than the budget."""


class Recorder:
    """Counts evaluations of a BBOB problem and records the best-so-far at each
    improvement: ``trace`` is a list of ``(evaluation, f - f_opt)``."""

    def __init__(self, problem, fopt: float, budget: int, strict: bool = True):
        self.problem, self.fopt, self.budget, self.strict = problem, fopt, budget, strict
        self.n = 0
        self.best = math.inf
        self.trace: list[tuple[int, float]] = []

    def one(self, x) -> float:
        if self.n >= self.budget:
            if self.strict:
                raise Budget
            return float(self.problem(np.asarray(x, dtype=np.float64)))
        self.n += 1
        f = float(self.problem(np.asarray(x, dtype=np.float64)))
        d = f - self.fopt
        if d < self.best:
            self.best = d
            self.trace.append((self.n, d))
        return f

    def many(self, X) -> np.ndarray:
        return np.array([self.one(x) for x in np.asarray(X, dtype=np.float64)])


# -- problems ----------------------------------------------------------------------------
_PROBLEMS: dict = {}


def problem(fid: int, dim: int, inst: int):
    """The cocoex problem and its optimal value (cached per process)."""
    key = (fid, dim, inst)
    if key not in _PROBLEMS:
        import cocoex

        suite = cocoex.Suite(
            "bbob", "", f"dimensions: {dim} function_indices: {fid} instance_indices: {inst}"
        )
        p = next(iter(suite))
        # f_opt is not exposed; the problem can write its optimum x, and f(x_opt) rounded to
        # 2 decimals is f_opt (BBOB's optimal values are multiples of 0.01)
        with tempfile.TemporaryDirectory() as d:
            cwd = os.getcwd()
            os.chdir(d)
            try:
                p._best_parameter("print")
                xopt = np.loadtxt("._bbob_problem_best_parameter.txt").reshape(-1)
            finally:
                os.chdir(cwd)
        fopt = round(float(p(xopt)), 2)
        _PROBLEMS[key] = (p, fopt)
    return _PROBLEMS[key]


# -- algorithms --------------------------------------------------------------------------
def run_growsim(rec: Recorder, dim, pop, seed, options):
    from growsim.ga import GA, Genome, Real

    rec.strict = (
        False  # a generation is evaluated whole; evaluations past the budget are not recorded
    )
    ga = GA(
        Genome([Real("x", LOW, HIGH, size=dim)]),
        rec.many,
        population=pop,
        maximize=False,
        seed=seed,
        **options,
    )
    ga.run(evaluations=rec.budget)


def run_deap(rec: Recorder, dim, pop, seed, options):
    from deap import algorithms, base, creator, tools

    random.seed(seed)
    if not hasattr(creator, "BBOBFit"):
        creator.create("BBOBFit", base.Fitness, weights=(-1.0,))
        creator.create("BBOBInd", list, fitness=creator.BBOBFit)
    tb = base.Toolbox()
    tb.register("attr", random.uniform, LOW, HIGH)
    tb.register("individual", tools.initRepeat, creator.BBOBInd, tb.attr, dim)
    tb.register("population", tools.initRepeat, list, tb.individual)
    tb.register("evaluate", lambda ind: (rec.one(ind),))
    tb.register("mate", tools.cxBlend, alpha=0.5)
    tb.register("mutate", tools.mutGaussian, mu=0.0, sigma=0.1 * (HIGH - LOW), indpb=1.0 / dim)
    tb.register("select", tools.selTournament, tournsize=3)
    algorithms.eaMuPlusLambda(
        tb.population(n=pop), tb, mu=pop, lambda_=pop, cxpb=0.7, mutpb=0.2, ngen=10**9,
        verbose=False,
    )  # fmt: skip


def _pymoo_problem(rec: Recorder, dim):
    from pymoo.core.problem import Problem

    class P(Problem):
        def __init__(self):
            super().__init__(n_var=dim, n_obj=1, xl=LOW, xu=HIGH)

        def _evaluate(self, x, out, *args, **kwargs):
            out["F"] = rec.many(x)

    return P()


def run_pymoo(rec: Recorder, dim, pop, seed, options, algo="ga"):
    from pymoo.optimize import minimize

    if algo == "ga":
        from pymoo.algorithms.soo.nonconvex.ga import GA

        alg = GA(pop_size=pop, eliminate_duplicates=True)
    else:
        from pymoo.algorithms.soo.nonconvex.de import DE

        alg = DE(pop_size=pop)
    minimize(_pymoo_problem(rec, dim), alg, ("n_evals", 10**12), seed=seed, verbose=False)


def run_cma(rec: Recorder, dim, pop, seed, options):
    import cma

    rng = np.random.default_rng(seed)
    popsize = 4 + int(3 * math.log(dim))
    while True:  # IPOP: restart with twice the population until the budget is spent
        es = cma.CMAEvolutionStrategy(
            rng.uniform(-4, 4, dim).tolist(),
            2.0,
            {"popsize": popsize, "verbose": -9, "seed": int(rng.integers(1, 2**31))},
        )
        while not es.stop():
            x = es.ask()
            es.tell(x, rec.many(x).tolist())
        popsize *= 2


RUNNERS = {
    "growsim": run_growsim,
    "deap": run_deap,
    "pymoo-ga": lambda *a: run_pymoo(*a, algo="ga"),
    "pymoo-de": lambda *a: run_pymoo(*a, algo="de"),
    "cma": run_cma,
}


def run_one(task: dict) -> dict:
    """One run: ``task`` has alg, fid, dim, inst, seed, pop, budget, options."""
    import warnings

    warnings.simplefilter("ignore")
    p, fopt = problem(task["fid"], task["dim"], task["inst"])
    rec = Recorder(p, fopt, task["budget"])
    t = time.perf_counter()
    try:
        RUNNERS[task["alg"]](rec, task["dim"], task["pop"], task["seed"], task["options"])
    except Budget:
        pass
    seconds = time.perf_counter() - t
    return {
        **{k: task[k] for k in ("alg", "label", "fid", "dim", "inst", "seed", "pop", "budget")},
        "evaluations": rec.n,
        "seconds": seconds,
        "trace_evals": [e for e, _ in rec.trace],
        "trace_prec": [d for _, d in rec.trace],
    }


# -- the bit suite ---------------------------------------------------------------------
#: bit problems (maximise; ``(n, L)`` 0/1 arrays -> ``(n,)``), length 100
BIT_LENGTH = 100


def onemax(b):
    return b.sum(axis=1)


def leading_ones(b):
    return np.argmin(np.concatenate([b, np.zeros((len(b), 1))], axis=1), axis=1).astype(float)


def trap(b, k=5):
    """Concatenated deceptive traps of ``k`` bits (Deb & Goldberg): a block of u ones scores
    k if u == k, else k - 1 - u."""
    u = b.reshape(len(b), -1, k).sum(axis=2)
    return np.where(u == k, k, k - 1 - u).sum(axis=1).astype(float)


def nk_landscape(inst: int, k: int = 4):
    """Kauffman's NK landscape, ``N = BIT_LENGTH``, each locus with its ``k`` next
    neighbours (circular), contributions uniform in [0, 1) from instance ``inst``'s seed."""
    n = BIT_LENGTH
    table = np.random.default_rng(1000 + inst).random((n, 2 ** (k + 1)))
    idx = (np.arange(n)[:, None] + np.arange(k + 1)[None, :]) % n
    weights = 2 ** np.arange(k, -1, -1)

    def f(b):
        code = (b[:, idx].astype(np.int64) * weights).sum(axis=2)
        return table[np.arange(n), code].mean(axis=1)

    return f


def bit_problem(name: str, inst: int):
    """``(fitness, optimum or None)`` of a bit problem."""
    if name == "nk":
        return nk_landscape(inst), None
    return {"onemax": onemax, "leading_ones": leading_ones, "trap": trap}[name], float(BIT_LENGTH)


def run_bits(task: dict) -> dict:
    """One growsim or DEAP run on the bit suite: best fitness within each budget."""
    fit, opt = bit_problem(task["fid"], task["inst"])
    budget, trace = task["budget"], []
    state = {"n": 0, "best": -np.inf}

    def record(b):
        b = np.asarray(b, dtype=np.float64)
        v = fit(b)
        for x in v:
            if state["n"] >= budget:
                break
            state["n"] += 1
            if x > state["best"]:
                state["best"] = float(x)
                trace.append((state["n"], float(x)))
        return v

    t = time.perf_counter()
    if task["alg"] == "growsim":
        from growsim.ga import GA, Bits, Genome

        g = Genome([Bits("b", 0, 1, bits=1, size=BIT_LENGTH)])
        GA(g, record, population=task["pop"], seed=task["seed"], **task["options"]).run(
            evaluations=budget, target=opt
        )
    else:  # DEAP's eaSimple as its OneMax example: two-point, flip 1/L, tournament 3
        from deap import algorithms, base, creator, tools

        random.seed(task["seed"])
        if not hasattr(creator, "BitFit"):
            creator.create("BitFit", base.Fitness, weights=(1.0,))
            creator.create("BitInd", list, fitness=creator.BitFit)
        tb = base.Toolbox()
        tb.register("attr", random.randint, 0, 1)
        tb.register("individual", tools.initRepeat, creator.BitInd, tb.attr, BIT_LENGTH)
        tb.register("evaluate", lambda ind: (float(record(np.array([ind]))[0]),))
        tb.register("mate", tools.cxTwoPoint)
        tb.register("mutate", tools.mutFlipBit, indpb=1.0 / BIT_LENGTH)
        tb.register("select", tools.selTournament, tournsize=3)
        pop = [tb.individual() for _ in range(task["pop"])]
        gens = 2 * budget // task["pop"] + 1  # the recorder stops counting at the budget
        algorithms.eaSimple(pop, tb, cxpb=0.7, mutpb=1.0, ngen=gens, verbose=False)
    return {
        **{k: task[k] for k in ("alg", "label", "fid", "inst", "seed", "pop", "budget")},
        "seconds": time.perf_counter() - t,
        "optimum": opt,
        "trace_evals": [e for e, _ in trace],
        "trace_best": [v for _, v in trace],
    }


def bit_suite(args) -> dict:
    """The bit suite: growsim's bit defaults (and ``--growsim`` variants) beside DEAP."""
    variants = {"default": {}}
    variants.update(json.loads(args.variants) if args.variants else {})
    tasks = []
    for name in ("onemax", "leading_ones", "trap", "nk"):
        for inst in _ints(args.instances):
            for seed in _ints(args.seeds):
                for pop in _ints(args.populations):
                    for label, opts in variants.items():
                        tasks.append({"alg": "growsim", "label": label, "options": opts,
                                      "fid": name, "inst": inst, "seed": seed, "pop": pop,
                                      "budget": args.bit_budget})  # fmt: skip
                    if "deap" in args.algorithms:
                        tasks.append({"alg": "deap", "label": "deap", "options": {},
                                      "fid": name, "inst": inst, "seed": seed, "pop": pop,
                                      "budget": args.bit_budget})  # fmt: skip
    if args.jobs > 1:
        with ProcessPoolExecutor(args.jobs) as ex:
            rows = list(ex.map(run_bits, tasks, chunksize=4))
    else:
        rows = [run_bits(t) for t in tasks]
    runs = pd.DataFrame(rows)
    out = {}
    for (name, pop, label), g in runs.groupby(["fid", "pop", "label"]):
        finals = [tb[-1] for tb in g["trace_best"]]
        opt = g["optimum"].iloc[0]
        hits = [te[-1] for te, tb in zip(g["trace_evals"], g["trace_best"]) if tb[-1] == opt]
        out.setdefault(f"{name} pop {pop}", {})[label] = {
            "median_best": float(np.median(finals)),
            "solved": f"{len(hits)}/{len(g)}",
            "median_evals_to_optimum": float(np.median(hits)) if hits else None,
        }
    return out, runs


# -- analysis ----------------------------------------------------------------------------
def precision_at(evals, precs, budget: int) -> float:
    """Best ``f - f_opt`` within ``budget`` evaluations, floored at :data:`FLOOR`."""
    best = math.inf
    for e, d in zip(evals, precs):
        if e > budget:
            break
        best = d
    return max(best, FLOOR)


def ecdf_share(df: pd.DataFrame, budget: int) -> float:
    """The share of (run, target) pairs reached within ``budget`` evaluations."""
    hit = 0
    for evals, precs in zip(df["trace_evals"], df["trace_prec"]):
        p = precision_at(evals, precs, budget)
        hit += int((TARGETS >= p * (1 - 1e-12)).sum())
    return hit / (len(df) * len(TARGETS)) if len(df) else float("nan")


def not_worse(a: np.ndarray, b: np.ndarray) -> bool:
    """One-sided Mann-Whitney U: True unless ``a`` is significantly larger than ``b``."""
    from scipy.stats import mannwhitneyu

    if np.all(a == a[0]) and np.all(b == a[0]):
        return True
    return bool(mannwhitneyu(a, b, alternative="greater").pvalue >= 0.05)


def summarise(runs: pd.DataFrame, budgets: list[int]) -> dict:
    """Per (dimension, budget): growsim against each peer and the better GA peer."""
    out: dict = {"summary": {}, "problems": {}}
    algs = [a for a in RUNNERS if a in set(runs["alg"])]
    for dim in sorted(set(runs["dim"])):
        for mult in budgets:
            key = f"{dim}D@{mult}"
            b = mult * dim
            sub = runs[runs["dim"] == dim]
            prec = {
                (a, f): np.array(
                    [precision_at(e, p, b) for e, p in zip(g["trace_evals"], g["trace_prec"])]
                )
                for (a, f), g in sub.groupby(["alg", "fid"])
            }
            fids = sorted(set(sub["fid"]))
            rows = {}
            counts = {}
            for f in fids:
                mine = prec.get(("growsim", f))
                if mine is None:
                    continue
                med = {a: float(np.median(prec[(a, f)])) for a in algs if (a, f) in prec}
                row = {"median": med}
                peers = [a for a in PEERS if a in med]
                if peers:
                    better = min(peers, key=lambda a: med[a])
                    row["better_peer"] = better
                    for a in [*algs, "better_peer"]:
                        if a == "growsim" or (a != "better_peer" and a not in med):
                            continue
                        ref = prec[(better if a == "better_peer" else a, f)]
                        c = counts.setdefault(a, {"median": 0, "not_worse": 0, "problems": 0})
                        c["problems"] += 1
                        c["median"] += int(med["growsim"] <= float(np.median(ref)))
                        c["not_worse"] += int(not_worse(mine, ref))
                rows[f"f{f}"] = row
            ecdf = {
                a: round(ecdf_share(sub[sub["alg"] == a], b), 4)
                for a in algs
                if (sub["alg"] == a).any()
            }
            for c in counts.values():
                c["share_median"] = round(c["median"] / c["problems"], 3)
                c["share_not_worse"] = round(c["not_worse"] / c["problems"], 3)
            out["summary"][key] = {"growsim_as_good_as": counts, "ecdf_share": ecdf}
            out["problems"][key] = rows
    return out


def halves(runs: pd.DataFrame, budgets: list[int]) -> dict:
    """How hard "as good as the better of two peers" is: the runs split by seed into two
    halves (seeds below / from the median seed); each algorithm's median on one half
    scored against the better GA peer's on the other half, both ways (wins of the
    problems). A statistical twin of a peer scores about half of the problems that peer
    leads, plus those it wins outright."""
    seeds = sorted(set(runs["seed"]))
    cut = seeds[len(seeds) // 2]
    half = {0: runs[runs["seed"] < cut], 1: runs[runs["seed"] >= cut]}
    out = {}
    for dim in sorted(set(runs["dim"])):
        for mult in budgets:
            b = mult * dim
            med = {}
            for h, df in half.items():
                for (a, f), g in df[df["dim"] == dim].groupby(["alg", "fid"]):
                    med[(h, a, f)] = float(
                        np.median(
                            [
                                precision_at(e, p, b)
                                for e, p in zip(g["trace_evals"], g["trace_prec"])
                            ]
                        )
                    )
            fids = sorted(set(runs.loc[runs["dim"] == dim, "fid"]))
            row = {}
            for a in ("growsim", *PEERS):
                wins = []
                for h in (0, 1):
                    if not all(
                        (h, a, f) in med and all((1 - h, q, f) in med for q in PEERS) for f in fids
                    ):
                        break
                    wins.append(
                        sum(med[(h, a, f)] <= min(med[(1 - h, q, f)] for q in PEERS) for f in fids)
                    )
                if len(wins) == 2:
                    row[a] = wins
            out[f"{dim}D@{mult}"] = row
    return {"seeds_split_at": int(cut), "wins_against_the_other_half": out}


def _ints(text: str) -> list[int]:
    out = []
    for part in text.split(","):
        if "-" in part:
            a, b = part.split("-")
            out.extend(range(int(a), int(b) + 1))
        elif part.strip():
            out.append(int(part))
    return out


def _report(runs, result: dict, out) -> None:
    """Print ``result`` as JSON; with ``out``, also write ``runs`` to ``out`` (Parquet)
    and the JSON beside it (``.json``), each atomically."""
    text = json.dumps(result, indent=1)
    if out:
        from growsim.files import atomic_path

        out = Path(out)
        out.parent.mkdir(parents=True, exist_ok=True)
        with atomic_path(out) as tmp:
            runs.to_parquet(tmp)
        with atomic_path(out.with_suffix(".json")) as tmp:
            Path(tmp).write_text(text)
    print(text)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dims", default="10,20")
    ap.add_argument("--functions", default="1-24")
    ap.add_argument("--instances", default="1-3")
    ap.add_argument("--seeds", default="0-4")
    ap.add_argument(
        "--pairs", help="instance:seed pairs instead of instances x seeds, e.g. 1:0,1:1,2:0"
    )
    ap.add_argument("--budgets", default="100,400", help="evaluations per dimension")
    ap.add_argument("--population", type=int, default=50)
    ap.add_argument("--algorithms", default="growsim,deap,pymoo-ga,pymoo-de,cma")
    ap.add_argument("--growsim", default="{}", help="JSON: GA options over the defaults")
    ap.add_argument("--label", default="default", help="name of the growsim options tried")
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--out", help="per-run table (.parquet); the JSON goes beside it")
    ap.add_argument("--cache", help="a parquet of an earlier --out: re-use its peers' runs")
    ap.add_argument("--quiet", action="store_true", help="print only the summary")
    ap.add_argument("--suite", choices=("bbob", "bits"), default="bbob")
    ap.add_argument("--populations", default="20,50,100", help="bit suite: populations")
    ap.add_argument("--bit-budget", type=int, default=20_000, help="bit suite: evaluations")
    ap.add_argument("--variants", help="bit suite: JSON {label: GA options} beside the defaults")
    ap.add_argument("--summarise", help="a parquet of an earlier --out: print its summary only")
    args = ap.parse_args(argv)
    if args.summarise:
        runs = pd.read_parquet(args.summarise)
        res = {**summarise(runs, _ints(args.budgets)), "halves": halves(runs, _ints(args.budgets))}
        if args.quiet:
            res.pop("problems")
        print(json.dumps(res, indent=1))
        return
    if args.suite == "bits":
        load0 = os.getloadavg()[0]
        summary, runs = bit_suite(args)
        setup = {
            "command": "python benchmarks/bbob.py " + " ".join(argv or os.sys.argv[1:]),
            "length": BIT_LENGTH,
            "budget": args.bit_budget,
            "load_avg_1min": [load0, os.getloadavg()[0]],
        }
        _report(runs, {"setup": setup, "problems": summary}, args.out)
        return
    algs = [a.strip() for a in args.algorithms.split(",") if a.strip()]
    bad = sorted(set(algs) - set(RUNNERS))
    if bad:
        ap.error(f"--algorithms: unknown {', '.join(bad)}; allowed {', '.join(RUNNERS)}")
    budgets = _ints(args.budgets)
    options = json.loads(args.growsim)
    if args.pairs:
        pairs = [tuple(int(v) for v in p.split(":")) for p in args.pairs.split(",")]
    else:
        pairs = [(i, s) for i in _ints(args.instances) for s in _ints(args.seeds)]
    tasks = []
    for dim in _ints(args.dims):
        for fid in _ints(args.functions):
            for inst, seed in pairs:
                for alg in algs:
                    tasks.append({
                        "alg": alg, "label": args.label if alg == "growsim" else alg,
                        "fid": fid, "dim": dim, "inst": inst, "seed": seed,
                        "pop": args.population, "budget": max(budgets) * dim,
                        "options": options if alg == "growsim" else {},
                    })  # fmt: skip
    rows = []
    if args.cache:
        # the peers' runs of an earlier --out, for the same problems, seeds and budget
        old = pd.read_parquet(args.cache)
        want = {(t["fid"], t["dim"], t["inst"], t["seed"], t["pop"], t["budget"]) for t in tasks}
        keys = ["fid", "dim", "inst", "seed", "pop", "budget"]
        mine = np.array([tuple(int(v) for v in k) in want for k in old[keys].values], bool)
        old = old[(old["alg"] != "growsim").to_numpy() & mine]
        have = {(a, *k) for a, *k in old[["alg", *keys]].values}
        tasks = [t for t in tasks if (t["alg"], *(t[k] for k in keys)) not in have]
        rows = old.to_dict("records")
    load0 = os.getloadavg()[0]
    t0 = time.perf_counter()
    if args.jobs > 1:
        with ProcessPoolExecutor(args.jobs) as ex:
            rows += list(ex.map(run_one, tasks, chunksize=4))
    else:
        rows += [run_one(t) for t in tasks]
    runs = pd.DataFrame(rows)
    for c in ("trace_evals", "trace_prec"):
        runs[c] = runs[c].map(list)
    result = {
        "setup": {
            "command": "python benchmarks/bbob.py " + " ".join(argv or os.sys.argv[1:]),
            "dims": _ints(args.dims),
            "functions": _ints(args.functions),
            "instance_seed_pairs": pairs,
            "budgets_per_dim": budgets,
            "population": args.population,
            "growsim_options": options,
            "runs_done_now": len(tasks),
            "seconds": round(time.perf_counter() - t0, 1),
            "load_avg_1min": [load0, os.getloadavg()[0]],
            "cpus": os.cpu_count(),
            "python": platform.python_version(),
        },
        "seconds_per_run": {
            a: round(float(g["seconds"].median()), 4) for a, g in runs.groupby("alg")
        },
        **summarise(runs, budgets),
        "halves": halves(runs, budgets),
    }
    if args.quiet:
        result.pop("problems")
    _report(runs, result, args.out)


if __name__ == "__main__":
    main()
