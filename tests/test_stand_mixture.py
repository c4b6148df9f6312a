"""Stands of different genomes and the mixture mode (``[environment.stand] mode =
"mixture"``): the hormone kernels' per-plant genes seen from the model, the neighbours
drawn from the population with common random numbers, the config's checks."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from growsim.env import Environment
from growsim.errors import ConfigError, UserInputError
from growsim.experiment import load_plan, run
from growsim.models import hormone as H

ENV2 = {"light": {"direction": [0.3, -1.0, 0.0], "diffuse": 0.5}}
DEMO2 = {**H.PRESETS["demo_2d"], "steps": 20, "max_modules": 80}
#: a neighbour that hardly grows: its first hormone (elongation) switched off
WEAK = {**DEMO2, "h0_bias": -4.0, "h0_gain": 0.0}
MIX = "experiments/stand_mixture_2d.toml"


def env2(stand=None):
    return Environment.parse({**ENV2, **({"stand": stand} if stand else {})})


def _same(a, b):
    return np.array_equal(a.start, b.start) and np.array_equal(a.data["nutrient"],
                                                               b.data["nutrient"])  # fmt: skip


def test_each_plant_of_a_stand_grows_by_its_own_genes():
    # a genome whose modules never elongate stays a short seedling beside the demo, in
    # either order: every module reads its own plant's row of genes
    env = env2()
    xz = np.array([[-1.0, 0.0], [1.0, 0.0]])
    for order in ([DEMO2, WEAK], [WEAK, DEMO2]):
        *_, stand = H.grow_stand(order, env=env, xz=xz)
        weak = stand.subset(stand.data["plant"] == order.index(WEAK))
        strong = stand.subset(stand.data["plant"] == order.index(DEMO2))
        assert strong.height() > 2 * weak.height() and strong.n_segments > weak.n_segments
    # a stand of one genome given once per plant is the stand of its copies, bit for bit
    *_, copies = H.grow_stand(DEMO2, env=env, xz=xz)
    *_, each = H.grow_stand([DEMO2, DEMO2], env=env, xz=xz)
    assert _same(copies, each)


def test_a_stand_refuses_genomes_that_grow_differently():
    xz = np.array([[-1.0, 0.0], [1.0, 0.0]])
    with pytest.raises(UserInputError, match=r"hormone\.steps"):
        list(H.grow_stand([DEMO2, {**DEMO2, "steps": 5}], env=env2(), xz=xz))
    with pytest.raises(UserInputError, match="2 genomes for 3 positions"):
        row = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
        list(H.grow_stand([DEMO2, DEMO2], env=env2(), xz=row))


def test_the_focal_plant_of_a_mixture_gains_from_weak_neighbours():
    env = env2({"mode": "mixture", "neighbours": 2, "spacing": 0.6})
    *_, among_weak = H.grow_mixture(DEMO2, [WEAK, WEAK], env=env)
    *_, among_copies = H.grow_mixture(DEMO2, None, env=env)
    alone = H.develop(DEMO2, env=env2())
    assert among_weak.meta["total_nutrient"] > among_copies.meta["total_nutrient"]
    assert alone.meta["total_nutrient"] > among_copies.meta["total_nutrient"]
    assert "plant" not in among_weak.data and among_weak.meta["stand"][0] == [0.0, 0.0]
    # the focal plant is its own modules: as many as its nutrient says
    assert np.isclose(among_weak.data["nutrient"].sum(), among_weak.meta["total_nutrient"])
    # develop in a mixture without a population: among copies of itself
    assert _same(H.develop(DEMO2, env=env), among_copies)


def test_mixture_positions_are_the_nearest_cells():
    s = Environment.parse({"stand": {"mode": "mixture", "neighbours": 8, "spacing": 2.0}}).stand
    xz = s.mixture_xz(3)
    assert xz[0].tolist() == [0.0, 0.0] and len(xz) == 9 == s.n_plants
    assert sorted(map(tuple, xz[1:].tolist())) == sorted(
        (i * 2.0, j * 2.0) for i in (-1, 0, 1) for j in (-1, 0, 1) if i or j
    )
    assert s.mixture_xz(2)[1:, 1].tolist() == [0.0] * 8  # a row in 2D
    assert np.abs(s.mixture_xz(2)[1:, 0]).max() == 8.0


def test_prepare_draws_the_same_neighbours_for_the_same_batch():
    f = load_plan(MIX, ["ga.population=8"]).fitness()
    lo = np.array([p.low for p in load_plan(MIX).evolved])
    hi = np.array([p.high for p in load_plan(MIX).evolved])
    x = np.random.default_rng(1).uniform(lo, hi, (8, len(lo)))
    seeds = np.arange(8, dtype=np.uint64) + 100
    f.prepare(x, seeds)
    first = f.neighbours.copy()
    assert first.shape == (2, 2, len(f.names))
    full = f.full_params(x)
    for draw in first:  # every neighbour is an individual of the batch, none twice
        rows = [int(np.flatnonzero((full == nb).all(axis=1))[0]) for nb in draw]
        assert len(set(rows)) == len(rows)
    f.prepare(x, seeds)
    np.testing.assert_array_equal(f.neighbours, first)
    f.prepare(x, seeds + 1)
    assert not np.array_equal(f.neighbours, first)
    # every individual is judged by the same draw: a batch scored whole or in parts
    f.prepare(x, seeds)
    whole = f(x, seeds)
    parts = np.concatenate([f(x[:3], seeds[:3]), f(x[3:], seeds[3:])])
    np.testing.assert_array_equal(whole, parts)


@pytest.mark.parametrize(
    ("overrides", "key"),
    [
        (["environment.stand.neighbours=8", "ga.population=8"], "environment.stand.neighbours"),
        (
            [
                "model.kind=ifs3d",
                "model.preset=table1",
                "model.params={}",
                "model.evolve={depth=true}",
            ],
            "environment.stand.mode",
        ),
    ],
)
def test_a_bad_mixture_is_refused_naming_the_key(overrides, key, tmp_path):
    with pytest.raises(ConfigError, match=key):
        load_plan(MIX, overrides)


def test_a_mixture_run_is_the_same_on_one_and_two_processes(tmp_path):
    over = ["ga.population=6", "ga.generations=2", "output.mesh=[]", "output.screenshots=[]",
            "output.plot=false", "model.params.steps=8"]  # fmt: skip
    run(MIX, out=tmp_path / "serial", overrides=over, progress=False)
    run(MIX, out=tmp_path / "pool", overrides=over, progress=False, workers=2)
    a = json.loads((tmp_path / "serial" / "best.json").read_text())
    b = json.loads((tmp_path / "pool" / "best.json").read_text())
    assert a["fitness"] == b["fitness"] and a["params"] == b["params"]


def test_a_mixture_sweep_and_its_garden(tmp_path):
    # mixture against monoculture: a sweep, then every genome grown in both gardens; in the
    # mixture garden among neighbours drawn from every evolved genome of the family
    import pandas as pd

    from growsim.experiment import sweep
    from growsim.report import compare

    tiny = ["ga.population=6", "ga.generations=2", "model.params.steps=8",
            "model.params.max_modules=30"]  # fmt: skip
    df = sweep(MIX, repeats=2, out=tmp_path / "sw", overrides=tiny, progress=False)
    assert sorted(df["sweep_variant"].unique()) == ["mixture", "monoculture"]
    c = compare([tmp_path / "sw"], tmp_path / "cmp", renders=False, garden=True)
    grown = pd.read_csv(c.files["garden"])
    assert len(grown) == 4 * 2
    name = {o: Path(p).parent.name for o, p in zip(grown.origin, grown.path)}
    grown = grown.assign(garden=grown.garden.map(name), origin=grown.origin.map(name))
    for row in grown[grown.origin == grown.garden].itertuples():
        # in its own garden: a monoculture scores what its run found; a mixture is judged by
        # other neighbours than in its run (the family's genomes), so only its sign is known
        best = json.loads((Path(row.path) / "best.json").read_text())
        if row.garden == "monoculture":
            assert row.fitness == pytest.approx(best["fitness"], rel=1e-12)
        assert np.isfinite(row.fitness)


def test_every_plant_of_a_stand_keeps_to_its_own_cap():
    # the stand's arrays hold max_modules per plant; no plant takes another's share
    p = {**DEMO2, "steps": 30, "max_modules": 25}
    xz = np.array([[-2.0, 0.0], [0.0, 0.0], [2.0, 0.0]])
    *_, stand = H.grow_stand([p, WEAK | {"steps": 30, "max_modules": 25}, p], env=env2(), xz=xz)
    counts = np.bincount(stand.data["plant"], minlength=3)
    assert counts.max() == 25 and counts[1] < 25, counts
    *_, focal = H.grow_mixture(p, [p, p], env=env2({"mode": "mixture", "neighbours": 2}))
    assert focal.n_segments <= 25
