"""The GA engine: convergence, generation models, islands, extinction, failures, polish."""

from __future__ import annotations

import dataclasses
import logging

import numpy as np
import pandas as pd
import pytest

from growsim.errors import GrowsimError, UserInputError
from growsim.ga import (
    GA,
    GENERATION_MODELS,
    HISTORY_COLUMNS,
    Bits,
    GAOptions,
    GAState,
    Genome,
    Integer,
    Real,
    evaluation_seeds,
)
from growsim.ga.problems import onemax, rastrigin, sphere

ONEMAX200 = Genome([Bits("b", 0, 1, bits=1, size=200)])
R10 = Genome([Real("x", -5.12, 5.12, size=10)])

#: documented in docs/ga.md: Rastrigin-10D, population 200, 100 generations, defaults
RASTRIGIN10_BOUND = 1.0


def test_onemax_200_is_solved():
    r = GA(ONEMAX200, onemax, population=100, seed=0).run(target=200, generations=300)
    assert r.stop_reason == "target"
    assert r.best.fitness == 200
    assert r.best.params.shape == (200,) and (r.best.params == 1).all()
    h = r.history
    assert list(h.columns) == HISTORY_COLUMNS
    assert h["best_so_far"].is_monotonic_increasing
    assert h["evaluations"].iloc[-1] == r.evaluations == 100 + 99 * (len(h) - 1)


@pytest.mark.parametrize("seed", [0, 1])
def test_rastrigin_10d_below_documented_bound(seed):
    r = GA(R10, rastrigin, population=200, maximize=False, seed=seed).run(generations=100)
    assert r.stop_reason == "generations" and r.generations == 100
    assert r.best.fitness < RASTRIGIN10_BOUND
    assert r.history["best_so_far"].is_monotonic_decreasing


def test_steady_state_reaches_target_and_stops():
    # Okusa's fish GA: population 10, the best mates, the worst is replaced, p_m = 0.06
    g = Genome([Bits("b", 0, 1, bits=1, size=30)])
    ga = GA(
        g,
        onemax,
        population=10,
        seed=3,
        model="steady",
        crossover="one_point",
        crossover_options={"rate": 1.0},
        mutation="bitflip",
        mutation_options={"rate": 0.06},
        selection="random",
    )
    r = ga.run(target=30, generations=5000)
    assert r.stop_reason == "target" and r.best.fitness == 30
    assert r.evaluations == 10 + 2 * (r.generations - 1)
    assert r.generations < 5000
    # the best is never replaced: the per-generation best never drops
    assert r.history["best"].is_monotonic_increasing


def test_mu_plus_lambda_and_elitism_keep_the_best():
    for model, kw in [("mu+lambda", {"offspring": 30}), ("generational", {"elite": 2})]:
        r = GA(R10, sphere, population=20, maximize=False, seed=1, model=model, **kw).run(
            generations=30
        )
        assert r.history["best"].is_monotonic_decreasing, model
        assert r.population.shape == (20, 10)


def test_generational_without_elite_can_lose_the_best_but_best_so_far_is_kept():
    r = GA(
        R10, rastrigin, population=10, maximize=False, seed=0, elite=0, model="generational"
    ).run(generations=40)
    h = r.history
    assert not h["best"].is_monotonic_decreasing
    assert h["best_so_far"].iloc[-1] == h["best"].min() == r.best.fitness


def test_elite_rate():
    ga = GA(R10, sphere, population=40, elite_rate=0.05, model="generational")
    assert ga.model.elite == 2 and ga.model.offspring == 38


def test_islands_history_and_migration():
    ga = GA(
        R10,
        sphere,
        population=12,
        maximize=False,
        seed=2,
        islands=3,
        migration_rate=0.25,
        migration_interval=2,
    )
    r = ga.run(generations=6)
    h = r.history
    assert len(h) == 18 and sorted(h["island"].unique()) == [0, 1, 2]
    assert r.population.shape == (36, 10)
    # every 2nd generation: the 3 best of island i replace the 3 worst of island i + 1
    ga2 = GA(
        R10,
        sphere,
        population=12,
        maximize=False,
        seed=2,
        islands=3,
        migration_rate=0.25,
        migration_interval=2,
    )
    ga2.tell(sphere(ga2.genome.decode(ga2.ask())))
    ga2.tell(sphere(ga2.genome.decode(ga2.ask())))
    pops = [p.copy() for p in ga2.state.pops]
    scores = [s.copy() for s in ga2.state.scores]
    ga2.migrate()
    for i in range(3):
        j = (i + 1) % 3
        best_i = pops[i][np.argsort(-scores[i])[:3]]
        worst_j = np.argsort(scores[j])[:3]
        keep_j = np.setdiff1d(np.arange(12), worst_j)
        assert np.array_equal(ga2.state.pops[j][worst_j], best_i)
        assert np.array_equal(ga2.state.pops[j][keep_j], pops[j][keep_j])
    # and tell() migrates on schedule: after generation 2 (not 1), as migrate() does
    runs = {}
    for interval in (2, 1000):
        ga3 = GA(
            R10,
            sphere,
            population=12,
            maximize=False,
            seed=2,
            islands=3,
            migration_rate=0.25,
            migration_interval=interval,
        )
        runs[interval] = ga3
        for _ in range(2):
            ga3.tell(sphere(ga3.genome.decode(ga3.ask())))
    assert all(np.array_equal(a, b) for a, b in zip(runs[2].state.pops, runs[1000].state.pops))
    for ga3 in runs.values():
        ga3.tell(sphere(ga3.genome.decode(ga3.ask())))
    assert not all(np.array_equal(a, b) for a, b in zip(runs[2].state.pops, runs[1000].state.pops))
    runs[1000].migrate()
    assert all(np.array_equal(a, b) for a, b in zip(runs[2].state.pops, runs[1000].state.pops))


def test_extinction_recreates_a_collapsed_population():
    g = Genome([Bits("b", 0, 1, bits=1, size=16)])
    kw = dict(
        population=8,
        seed=0,
        selection="truncation",
        selection_options={"fraction": 0.01},
        crossover_options={"rate": 0.0},
        mutation_options={"rate": 0.0},
    )
    r_off = GA(g, onemax, extinction=False, **kw).run(generations=6)
    assert r_off.history["diversity"].iloc[-1] == 0.0
    r_on = GA(g, onemax, extinction=True, **kw).run(generations=6)
    div = r_on.history["diversity"].to_numpy()
    zero = np.flatnonzero(div == 0)
    assert zero.size and (div[zero[0] + 1 :] > 0).any()  # re-created after collapsing
    assert r_on.history["best_so_far"].is_monotonic_increasing


def bad_rows(x):
    """Raises for any batch containing x[0] > 0.9; returns NaN where x[1] > 0.9."""
    if (x[:, 0] > 0.9).any():
        raise RuntimeError("boom")
    out = x.sum(axis=1)
    out[x[:, 1] > 0.9] = np.nan
    return out


def test_failures_are_isolated_counted_and_logged(caplog):
    g = Genome([Real("x", 0, 1, size=3)])
    with caplog.at_level(logging.WARNING, logger="growsim.ga"):
        r = GA(g, bad_rows, population=50, seed=0).run(generations=5)
    h = r.history
    assert h["failures"].iloc[0] > 0
    assert np.isfinite(r.best.fitness) and r.best.params[0] <= 0.9 and r.best.params[1] <= 0.9
    assert np.isfinite(h["best"]).all()
    assert "failed" in caplog.text and "boom" in caplog.text
    # failures get the worst fitness (-inf when maximising)
    fail = (r.population[:, 0] > 0.9) | (r.population[:, 1] > 0.9)
    assert (r.fitness[fail] == -np.inf).all() and np.isfinite(r.fitness[~fail]).all()


def always_fails(x):
    raise ValueError("fitness is broken: no model")


def test_every_first_generation_failure_is_a_clear_error():
    with pytest.raises(GrowsimError, match="no model"):
        GA(R10, always_fails, population=10).run(generations=3)
    with pytest.raises(GrowsimError, match="nan"):
        GA(R10, lambda x: np.full(len(x), np.nan), population=10).run(generations=3)


def test_seeds_come_from_the_global_evaluation_index():
    seen = []

    def fit(x, seeds):
        seen.append(np.array(seeds))
        return x.sum(axis=1)

    ga = GA(R10, fit, population=10, seed=4, model="generational")
    ga.run(generations=3)
    allseeds = np.concatenate(seen)
    assert allseeds.dtype == np.uint64 and len(allseeds) == 10 + 9 + 9
    assert len(set(allseeds.tolist())) == len(allseeds)
    assert np.array_equal(allseeds, evaluation_seeds(ga.eval_key, 0, len(allseeds)))


def row_sphere(row, seeds=None):
    return float((row * row).sum())


def test_per_individual_fitness_matches_vectorized():
    a = GA(R10, sphere, population=20, maximize=False, seed=5).run(generations=5)
    b = GA(
        R10, lambda r: float((r * r).sum()), population=20, maximize=False, seed=5, vectorized=False
    ).run(generations=5)
    c = GA(R10, row_sphere, population=20, maximize=False, seed=5, vectorized=False).run(
        generations=5
    )
    cols = [c for c in HISTORY_COLUMNS if c != "seconds"]
    pd.testing.assert_frame_equal(a.history[cols], b.history[cols])
    pd.testing.assert_frame_equal(a.history[cols], c.history[cols])


def test_same_seed_same_result_other_seed_differs():
    a = GA(R10, rastrigin, population=30, maximize=False, seed=8).run(generations=10)
    b = GA(R10, rastrigin, population=30, maximize=False, seed=8).run(generations=10)
    c = GA(R10, rastrigin, population=30, maximize=False, seed=9).run(generations=10)
    assert a.best.fitness == b.best.fitness and np.array_equal(a.best.params, b.best.params)
    assert a.best.fitness != c.best.fitness


def test_termination_rules():
    g = Genome([Real("x", -1, 1, size=2)])
    r = GA(g, sphere, population=10, maximize=False).run(evaluations=55)
    assert r.stop_reason == "evaluations" and r.evaluations >= 55 and r.evaluations < 64
    r = GA(g, lambda x: np.zeros(len(x)), population=10).run(stagnation=4, generations=100)
    assert r.stop_reason == "stagnation" and r.generations == 5
    r = GA(g, sphere, population=10, maximize=False).run(target=1e-2, generations=1000)
    assert r.stop_reason == "target" and r.best.fitness <= 1e-2
    r = GA(g, sphere, population=10).run(wall_time=0.05, generations=10**6)
    assert r.stop_reason == "wall_time"
    rows = []
    r = GA(g, sphere, population=10).run(
        generations=50, callback=lambda ga, row: rows.append(row) or row["generation"] == 3
    )
    assert r.stop_reason == "callback" and r.generations == 4 and len(rows) == 4
    assert set(HISTORY_COLUMNS) <= set(rows[0])
    assert GA(g, sphere, population=10).run().generations == 100  # default limit


def test_initial_individuals_enter_generation_zero():
    g = Genome([Real("x", -5, 5, size=4), Integer("n", 0, 3)])
    best = np.array([[0.0, 0, 0, 0, 0]])
    r = GA(g, sphere, population=30, maximize=False, seed=1, initial=best).run(generations=1)
    assert r.best.fitness == 0.0 and r.best.generation == 0
    with pytest.raises(UserInputError, match="x\\[2\\]"):
        GA(g, sphere, initial=[[0, 0, 9, 0, 0]])
    with pytest.raises(UserInputError, match="shape"):
        GA(g, sphere, initial=[[0, 0]])


def test_ask_tell_api():
    ga = GA(R10, sphere, population=10, maximize=False, seed=0, model="generational")
    with pytest.raises(GrowsimError, match="before ask"):
        ga.tell(np.zeros(10))
    raw = ga.ask()
    assert raw is ga.ask()  # asking twice gives the same genomes
    with pytest.raises(UserInputError, match="expected 10"):
        ga.tell(np.zeros(3))
    ga.tell(sphere(ga.genome.decode(raw)))
    assert ga.state.generation == 1 and ga.best.fitness == sphere(ga.genome.decode(raw)).min()
    assert len(ga.ask()) == 9  # population - elite


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"selection": "lottery"}, "available: .*tournament"),
        ({"crossover": "sbx", "crossover_options": {"etaa": 3}}, "sbx"),
        ({"mutation": "bitflip"}, "bitflip"),
        ({"model": "elitist"}, "model"),
        ({"elite": 10}, "elite"),
        ({"population": 1.5}, "population"),
        ({"islands": 0}, "islands"),
        ({"model": "generational", "offspring": 3}, "offspring"),
        ({"model": "steady", "offspring": 10}, "offspring"),
        ({"elite_rate": 1.0}, "elite_rate"),
        ({"selection": "rank", "selection_options": None, "mutation_options": []}, "mutation_opt"),
        ({"populaton": 10}, "populaton.*allowed: population, selection"),
    ],
)
def test_bad_settings_raise_user_errors(kwargs, match):
    with pytest.raises(UserInputError, match=match):
        GA(R10, sphere, **{"population": 10, **kwargs})


def test_bad_run_arguments():
    ga = GA(R10, sphere, population=10)
    with pytest.raises(UserInputError, match="generations"):
        ga.run(generations=0)
    with pytest.raises(UserInputError, match="polish"):
        ga.run(polish={"evals": 10})
    with pytest.raises(UserInputError, match="budget"):
        ga.run(evaluations=100, polish={"evaluations": 100})
    with pytest.raises(UserInputError, match="checkpoint"):
        ga.run(resume=True)


@pytest.mark.parametrize(
    ("polish", "match"),
    [
        ({"evaluations": 0}, r"polish\.evaluations"),
        ({"sigma": 2.0}, r"polish\.sigma"),
        ({"sigma": 0.1, "min_sigma": 0.2}, r"polish: min_sigma"),
        ({"batch": 2.5}, r"polish\.batch"),
        ("fast", "polish must be a dict"),
    ],
)
def test_bad_polish_options_name_the_key(polish, match):
    with pytest.raises(UserInputError, match=match):
        GA(R10, sphere, population=10).run(generations=2, polish=polish)


# -- options, generation models, state -------------------------------------------------
def test_options_object_and_keywords_make_the_same_ga():
    kw = dict(model="steady", offspring=4, islands=2, migration_interval=2)
    runs = [
        GA(R10, sphere, GAOptions(population=12, **kw), maximize=False, seed=3),
        GA(R10, sphere, maximize=False, seed=3, population=12, **kw),
        GA(R10, sphere, GAOptions(population=12, islands=5), maximize=False, seed=3, **kw),
    ]
    hist = [ga.run(generations=6).history.drop(columns="seconds") for ga in runs]
    pd.testing.assert_frame_equal(hist[0], hist[1])
    pd.testing.assert_frame_equal(hist[0], hist[2])
    assert runs[2].options == GAOptions(population=12, **kw)
    assert GA(R10, sphere).options.population == 50  # the one default, as in the config
    with pytest.raises(UserInputError, match="options must be a GAOptions"):
        GA(R10, sphere, 10)


@pytest.mark.parametrize("model", sorted(GENERATION_MODELS))
@pytest.mark.parametrize("mutation", ["bitflip", "meta"])
def test_every_generation_model_keeps_islands_whole(model, mutation):
    g = Genome([Bits("b", 0, 1, bits=1, size=30)])
    ga = GA(
        g,
        onemax,
        population=10,
        model=model,
        mutation=mutation,
        islands=2,
        seed=1,
        migration_interval=2,
        extinction=False,
    )
    assert ga.model.name == model
    for _ in range(5):
        ga.tell(onemax(ga.genome.decode(ga.ask())))
    st = ga.state
    for i in range(2):
        assert st.pops[i].shape == (10, 30) and st.scores[i].shape == (10,)
        assert np.array_equal(st.scores[i], onemax(g.decode(st.pops[i])))
        if mutation == "meta":
            assert st.strategies[i].shape == (10,) and (st.strategies[i] >= 1).all()
        else:
            assert st.strategies[i] is None
    assert len(ga.ask()) == 2 * ga.model.offspring
    assert st.evaluations == 20 + 4 * 2 * ga.model.offspring
    assert ga.history["best_so_far"].is_monotonic_increasing


def test_the_state_is_the_checkpoint(tmp_path):
    def make():
        g = Genome([Bits("b", 0, 1, bits=3, size=6)], diploid=True)
        return GA(g, onemax, population=10, islands=2, mutation="meta", seed=4)

    ga, ck = make(), tmp_path / "c.npz"
    ga.run(generations=5, checkpoint=ck)
    again = make()
    assert again.load_checkpoint(ck) == {"stop_reason": "generations", "polished": False}
    for f in dataclasses.fields(GAState):
        a, b = getattr(ga.state, f.name), getattr(again.state, f.name)
        if f.name == "rng":
            assert a.bit_generator.state == b.bit_generator.state
        elif f.name in ("pops", "scores", "strategies"):  # one array per island
            assert len(a) == len(b) == 2
            assert all(np.array_equal(x, y) for x, y in zip(a, b)), f.name
        elif isinstance(a, np.ndarray):
            assert np.array_equal(a, b), f.name
        else:
            assert a == b, f.name
    ga.ask()
    with pytest.raises(GrowsimError, match="asked but not told"):
        ga.save_checkpoint(ck)
    np.savez(ck, meta=np.array('{"version": 1}'))
    with pytest.raises(UserInputError, match="unknown version 1"):
        make().run(generations=6, checkpoint=ck, resume=True)


def test_operator_instances_and_all_models_run_with_every_coding():
    from growsim.ga import CROSSOVER, MUTATION, SELECTION

    g = Genome([Bits("b", 0, 1, bits=3, size=4)], diploid=True)
    for model in ("generational", "steady", "mu+lambda"):
        r = GA(
            g,
            onemax,
            population=12,
            model=model,
            seed=1,
            selection=SELECTION["rank"](),
            crossover=CROSSOVER["switch"](switch=0.2),
            mutation=MUTATION["meta"](),
        ).run(generations=8)
        assert r.best.fitness <= 4 and len(r.history) == 8


# -- polish ----------------------------------------------------------------------------
def test_polish_takes_a_close_fit_to_exact():
    g = Genome([Real("x", -5, 5, size=20)])
    ga = GA(g, sphere, population=40, maximize=False, seed=0)
    r0 = GA(g, sphere, population=40, maximize=False, seed=0).run(generations=30)
    r = ga.run(generations=30, polish={"evaluations": 3000})
    assert r0.best.fitness > 0.1
    assert r.best.fitness < 1e-6 * r0.best.fitness + 1e-8
    assert r.evaluations == r0.evaluations + 3000
    h = r.history
    assert set(h["phase"]) == {"ga", "polish"}
    assert h["best_so_far"].is_monotonic_decreasing
    assert h["evaluations"].iloc[-1] == r.evaluations


def staircase(x):
    """Piecewise constant (like a rasterised silhouette score): sphere on a 1e-3 grid."""
    return (np.round(x * 1000) ** 2).sum(axis=1) / 1e6


def test_polish_on_plateaus_and_between_bit_grid_points():
    g = Genome([Bits("x", -1.3, 2.1, bits=5, size=8)])
    r0 = GA(g, staircase, population=30, maximize=False, seed=1).run(generations=20)
    r = GA(g, staircase, population=30, maximize=False, seed=1).run(
        evaluations=r0.evaluations + 2000, polish={"evaluations": 2000}
    )
    # the 5-bit grid cannot reach 0 (step 0.11); polish leaves the grid
    assert r.best.fitness < 0.01 * r0.best.fitness
    assert r.evaluations == r0.evaluations + 2000
    assert np.allclose(r.best.params, 0, atol=0.01)


def test_polish_with_budget_counts_and_target():
    g = Genome([Real("x", -5, 5, size=5)])
    r = GA(g, sphere, population=20, maximize=False, seed=2).run(
        evaluations=1000, polish={"evaluations": 400}
    )
    assert r.evaluations <= 1000 + 19
    r = GA(g, sphere, population=20, maximize=False, seed=2).run(
        generations=5, target=1e-3, polish={"evaluations": 5000}
    )
    assert r.best.fitness <= 1e-3 and r.evaluations < 5 * 20 + 5000


def rotated_ellipsoid(x):
    """Ill-conditioned and non-separable (condition 1e4 along a rotated basis): what a
    coordinate-wise or isotropic step struggles with and CMA-ES learns."""
    d = x.shape[1]
    q, _ = np.linalg.qr(np.random.default_rng(99).standard_normal((d, d)))
    y = (x - 0.5) @ q
    return (y**2 * np.logspace(0, 4, d)).sum(axis=1)


def test_cmaes_polish_beats_the_es_on_a_rotated_ellipsoid_and_is_reproducible():
    g = Genome([Real("x", -5, 5, size=10)])

    def run(method, seed=3):
        ga = GA(g, rotated_ellipsoid, population=30, maximize=False, seed=seed)
        return ga.run(generations=10, polish={"evaluations": 3000, "method": method})

    es, cma_a, cma_b = run("es"), run("cmaes"), run("cmaes")
    assert cma_a.best.fitness < 1e-3 * es.best.fitness
    assert cma_a.best.fitness < 1e-6
    pd.testing.assert_frame_equal(
        cma_a.history.drop(columns="seconds"), cma_b.history.drop(columns="seconds")
    )
    assert cma_a.evaluations == es.evaluations
    h = cma_a.history
    assert (h[h.phase == "polish"]["diversity"] > 0).all()  # CMA-ES's step size
    assert np.all(cma_a.population >= -5) and np.all(cma_a.population <= 5)


def test_cmaes_polish_keeps_bounds_rounds_integers_and_names_bad_methods():
    g = Genome([Real("x", 0, 1, size=3), Integer("k", 0, 9)])
    seen = []

    def f(x):
        seen.append(x.copy())
        return ((x[:, :3] - 1.2) ** 2).sum(axis=1) + (x[:, 3] - 6.3) ** 2

    r = GA(g, f, population=10, maximize=False, seed=0).run(
        generations=3, polish={"evaluations": 500, "method": "cmaes", "sigma": 0.3}
    )
    allx = np.concatenate(seen)
    assert allx.min() >= 0 and allx[:, :3].max() <= 1 and allx[:, 3].max() <= 9
    assert np.all(allx[:, 3] == np.round(allx[:, 3]))
    assert np.allclose(r.best.params, [1, 1, 1, 6])
    with pytest.raises(UserInputError, match=r"polish\.method"):
        GA(g, f, population=10, seed=0).run(generations=2, polish={"method": "newton"})
