"""Fitting random IFS trees with the GA (small budget; the full figures are in the docs)."""

from __future__ import annotations

import numpy as np
import pytest

from growsim.ga import GA, genome_from_params
from growsim.models import ifs3d
from growsim.objectives.silhouette import SilhouetteObjective

EVOLVED = [p for p in ifs3d.PARAMS if p.name not in ("n_maps", "depth")]
NAMES = ["n_maps", "depth"] + [p.name for p in EVOLVED]


class _Fitness:
    def __init__(self, obj):
        self.obj = obj

    def __call__(self, x):
        full = np.concatenate([np.full((len(x), 2), 5.0), x], axis=1)
        return self.obj.batch(ifs3d, full, NAMES)


def _random_params(rng):
    return {"n_maps": 5, "depth": 5} | {p.name: rng.uniform(p.low, p.high) for p in EVOLVED}


@pytest.mark.slow
@pytest.mark.parametrize("tree_seed", [11])
def test_ga_fits_random_tree_small_budget(tree_seed):
    target = _random_params(np.random.default_rng(tree_seed))
    obj = SilhouetteObjective(target_model="ifs3d", target_params=target)
    genome = genome_from_params(EVOLVED, coding="real")
    ga = GA(genome, _Fitness(obj), population=100, islands=2, seed=0)
    result = ga.run(evaluations=6000, polish={"evaluations": 2000, "sigma": 0.05})
    fitted = ifs3d.develop(dict(zip(NAMES, [5, 5, *result.best.params])))
    score = obj(fitted)
    assert score == pytest.approx(result.best.fitness)
    # a random tree scores ~0.4 on average against a target; at this budget (8,000
    # evaluations, 1/6 of the seed's) measured 0.79 for this tree, 0.72 for tree seed 12
    first = result.history.query("generation == 0")["best"].max()
    assert score >= 0.7
    assert score >= first + 0.1
