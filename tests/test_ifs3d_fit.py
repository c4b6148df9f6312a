"""Fitting random IFS trees with the GA (small budget; the full figures are in the docs)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from growsim.ga import GA, genome_from_params
from growsim.models import ifs3d
from growsim.objectives.silhouette import SilhouetteObjective

EVOLVED = [p for p in ifs3d.PARAMS[2:] if p not in ifs3d.LEAF_PARAMS]
NAMES = ["n_maps", "depth"] + [p.name for p in EVOLVED]


class _Fitness:
    def __init__(self, obj):
        self.obj = obj

    def __call__(self, x):
        full = np.concatenate([np.full((len(x), 2), 5.0), x], axis=1)
        return self.obj.batch(ifs3d.MODEL, full, NAMES)


def _random_params(rng):
    return {"n_maps": 5, "depth": 5} | {p.name: rng.uniform(p.low, p.high) for p in EVOLVED}


@pytest.mark.slow
@pytest.mark.parametrize("tree_seed", [11])
def test_ga_fits_random_tree_small_budget(tree_seed):
    target = _random_params(np.random.default_rng(tree_seed))
    obj = SilhouetteObjective(target_model="ifs3d", target_params=target)
    genome = genome_from_params(EVOLVED, coding="real")
    # the real-coded GA before issue 15 changed the defaults (the measured figures below)
    old_ga = dict(model="generational", selection="tournament", selection_options={"size": 4},
                  crossover="sbx", mutation="polynomial")  # fmt: skip
    ga = GA(genome, _Fitness(obj), population=100, islands=2, seed=0, **old_ga)
    result = ga.run(evaluations=6000, polish={"evaluations": 2000, "sigma": 0.05})
    fitted = ifs3d.develop(dict(zip(NAMES, [5, 5, *result.best.params])))
    score = obj(fitted)
    assert score == pytest.approx(result.best.fitness)
    # a random tree scores ~0.4 on average against a target; at this budget (8,000
    # evaluations, 1/6 of the seed's) measured 0.79 for this tree, 0.72 for tree seed 12
    first = result.history.query("generation == 0")["best"].max()
    assert score >= 0.7
    assert score >= first + 0.1


@pytest.mark.slow
def test_best_setup_config_fits_table1_at_two_fifths_of_the_budget(tmp_path):
    """The best-setup config, run as a user runs it (config -> GA -> CMA-ES polish), at
    20,000 evaluations (the full 50,000 give NCC 0.977-0.998 over 5 seeds: docs)."""
    from growsim.experiment import run

    overrides = [
        "ga.evaluations=20000",
        'ga.polish={evaluations = 14000, sigma = 0.1, method = "cmaes", batch = 20}',
        "output.mesh=[]",
        "output.screenshots=[]",
    ]
    config = Path(__file__).resolve().parents[1] / "experiments" / "ifs_tree_best.toml"
    result = run(config, tmp_path / "r", overrides=overrides,
                 progress=False)  # fmt: skip
    h = result.history
    assert set(h["phase"]) == {"ga", "polish"}
    ga_best = h.loc[h.phase == "ga", "best_so_far"].max()
    # measured (seed 0): GA phase 0.851, after the CMA-ES polish 0.947; the GA alone at
    # the full 50,000 evaluations stalls at 0.88-0.92 (docs/models/ifs3d.md)
    assert result.best_fitness >= 0.93
    assert result.best_fitness >= ga_best + 0.05
    # the best plant in the results directory is the tree that scored it
    obj = SilhouetteObjective(target_model="ifs3d", target_preset="table1", size=64)
    assert obj(result.best_plant) == pytest.approx(result.best_fitness)


def test_a_pixel_identical_table1_tree_lies_outside_the_parameter_tolerance():
    """At 64x64 the Table 1 silhouettes cannot pin the leader's azimuth to 5 degrees.

    These maps were found by CMA-ES on the Table 1 target (seed 0, free azimuths:
    benchmarks/log/reproduction-history.md, "Identifiability"): both views equal the
    target's pixel for pixel (NCC exactly 1, also after rounding to 4 decimals and under
    1e-6 noise), yet the leader (the untilted map) is turned 5.4 degrees about the trunk
    beyond the 90-degree symmetry, more than the issue's 5-degree tolerance. No fit to these
    images can tell it from Table 1.
    """
    from growsim.kernels.ifs3d import compose_tree, render_views

    twin = np.array(
        [
            [0.5003, 0.3999, 44.9993, 89.942],
            [0.5048, 0.3953, 0.0024, 5.4112],
            [0.5003, 0.3997, 44.9566, 179.4978],
            [0.4999, 0.4, 44.9944, 270.011],
            [0.5005, 0.3999, 45.0109, 0.0963],
        ]
    )
    table1 = ifs3d.maps_from_params(ifs3d.PRESETS["table1"])
    views = [render_views(*compose_tree(m, 5), np.zeros(3), 64) for m in (twin, table1)]
    assert np.array_equal(views[0], views[1])
    cmp = ifs3d.compare_maps(twin, table1, azimuth_period=90.0)
    assert not cmp["within"]
    leader = cmp["errors"][0]  # reference map 1, the leader
    assert leader[3] == pytest.approx(5.41, abs=0.01)
    assert (leader[:3] <= [0.05, 0.05, 5.0]).all()
    others = cmp["errors"][1:]
    assert (others <= [0.005, 0.005, 0.6, 0.6]).all()
