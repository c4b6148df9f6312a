"""Honda trees in a mixture (issue 30): ``environment.stand.mode = "mixture"``.

The focal tree grows alone (Honda's tree does not grow by light) with its neighbours of
other genomes attached (``meta["neighbours"]``, :func:`growsim.models.honda.mixture`);
the light objective scores its leaves in one shadow map with theirs, its wood its own.
``docs/models/stand.md``.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from growsim.env import Environment
from growsim.errors import ConfigError, UserInputError
from growsim.experiment import load_plan, run
from growsim.models import get_model, honda
from growsim.objectives.light import LightObjective, mixture_stand
from growsim.phenotypes.plant import Plant, leaf_light

LIGHT = {"direction": [0.3, -1.0, 0.2], "diffuse": 0.5, "resolution": 256}
ZELKOVA = honda.PRESETS["zelkova"]
#: the zelkova on a trunk 20 m taller: its crown above the focal one's
TALL = {**ZELKOVA, "bd": 40.0}
#: a zelkova of 4 nutrient steps: a sapling under the focal crown
SMALL = {**ZELKOVA, "generations": 4}
QUICK = "experiments/quickstart.toml"


def env(spacing=20.0, neighbours=8, light=LIGHT, **stand):
    stand = {"mode": "mixture", "neighbours": neighbours, "spacing": spacing, **stand}
    return Environment.parse({"light": light, "stand": stand})


def objective(e=None, **options):
    return LightObjective(env=e or Environment.parse({"light": LIGHT}), wood_cost=0.0, **options)


def test_a_tree_among_tall_neighbours_gets_less_light_than_among_small_ones_or_alone():
    e = env()
    obj = objective(e)
    alone = objective().terms(honda.develop(ZELKOVA))
    tall = obj.terms(honda.mixture(ZELKOVA, [TALL] * 8, env=e))
    small = obj.terms(honda.mixture(ZELKOVA, [SMALL] * 8, env=e))
    assert tall["light"] < small["light"] < alone["light"]
    assert tall["light"] < 0.8 * small["light"]
    for t in (tall, small):  # the focal tree's own leaves and wood
        assert t["leaf_area"] == alone["leaf_area"]
        assert t["wood_volume"] == alone["wood_volume"]


def test_the_focal_tree_is_the_tree_alone_and_carries_its_neighbours():
    e = env(spacing=30.0, neighbours=3)
    t = honda.mixture(ZELKOVA, [TALL, SMALL, ZELKOVA], env=e)
    alone = honda.develop(ZELKOVA)
    assert np.array_equal(t.start, alone.start) and np.array_equal(t.end, alone.end)
    assert t.meta["stand"] == e.stand.mixture_xz(3).tolist()
    stand = mixture_stand(t)
    sizes = np.bincount(stand.data["plant"]).tolist()
    assert sizes == [
        alone.n_segments,
        *(honda.develop(p).n_segments for p in (TALL, SMALL, ZELKOVA)),
    ]
    for i, (x, z) in enumerate(t.meta["stand"]):  # each neighbour stands at its cell
        base = stand.subset(stand.data["plant"] == i).start[0]
        assert base.tolist() == [x, 0.0, z]


def test_a_mixture_of_copies_is_the_explicit_stands_focal_tree_bit_for_bit():
    e = env(spacing=25.0)
    mix = honda.mixture(ZELKOVA, None, env=e)
    got = objective(e).terms(mix)
    positions = e.stand.mixture_xz(3).tolist()
    ex = objective(
        Environment.parse({"light": LIGHT, "stand": {"mode": "explicit", "positions": positions}})
    )
    stand, _, light = ex.scored(honda.develop(ZELKOVA))
    assert light.resolution == objective(e).scored(mix)[2].resolution == 768
    focal = leaf_light(stand, light, judged=stand.data["plant"] == 0)
    assert got["light"] == focal.light and got["leaf_area"] == focal.area


@pytest.mark.parametrize("preset", ["zelkova", "ginkgo"])
def test_eight_copies_are_the_periodic_stand_of_one_ring(preset):
    """The 8 nearest cells are one periodic ring: the same map, the same light."""
    p = honda.PRESETS[preset]
    e = env(spacing=20.0)
    per = objective(
        Environment.parse(
            {"light": LIGHT, "stand": {"mode": "periodic", "spacing": 20.0, "rings": 1}}
        )
    )
    mix = objective(e)(honda.mixture(p, None, env=e))
    assert mix == pytest.approx(per(honda.develop(p)), rel=1e-12)


def test_develop_in_a_mixture_is_the_tree_among_its_copies():
    e = env(neighbours=2)
    model = get_model("honda")
    a, b = model.develop(ZELKOVA, env=e), model.mixture(ZELKOVA, [ZELKOVA] * 2, env=e)
    assert objective(e)(a) == objective(e)(b)
    assert "neighbours" not in model.develop(ZELKOVA).meta  # alone: as before


def test_a_saved_mixture_loads_and_scores_the_same(tmp_path):
    e = env(neighbours=3)
    t = honda.mixture(ZELKOVA, [TALL, SMALL, TALL], env=e)
    back = Plant.load(t.save(tmp_path / "mix.npz"))
    assert objective(e).terms(back) == objective(e).terms(t)


def test_the_wood_cost_is_the_focal_trees():
    e = env(neighbours=2)
    t = honda.mixture(ZELKOVA, [TALL, TALL], env=e)
    costly = LightObjective(env=e, wood_cost=0.5)
    assert costly(t) == objective(e)(t) - 0.5 * honda.develop(ZELKOVA).wood_volume()


OVER = [
    "environment.stand.mode=mixture", "environment.stand.neighbours=2",
    "environment.stand.spacing=25.0", "environment.stand.draws=2",
    "environment.light.resolution=64", "ga.population=6", "ga.generations=2",
    "model.params.generations=7", "output.mesh=[]", "output.screenshots=[]",
    "output.plot=false",
]  # fmt: skip


def test_a_honda_mixture_run_is_the_same_on_one_and_two_processes(tmp_path):
    run(QUICK, out=tmp_path / "serial", overrides=OVER, progress=False)
    run(QUICK, out=tmp_path / "pool", overrides=OVER, progress=False, workers=2)
    a = json.loads((tmp_path / "serial" / "best.json").read_text())
    b = json.loads((tmp_path / "pool" / "best.json").read_text())
    assert a["fitness"] == b["fitness"] and a["params"] == b["params"]


def test_the_neighbours_judge_the_score():
    """The same individual scores differently among different draws of neighbours, and
    the same on the same draw (common random numbers)."""
    f = load_plan(QUICK, OVER).fitness()
    lo = np.array([p.low for p in load_plan(QUICK, OVER).evolved])
    hi = np.array([p.high for p in load_plan(QUICK, OVER).evolved])
    x = np.random.default_rng(2).uniform(lo, hi, (6, len(lo)))
    seeds = np.arange(6, dtype=np.uint64)
    f.prepare(x, seeds)
    first = f(x, seeds)
    np.testing.assert_array_equal(f(x[:2], seeds[:2]), first[:2])
    f.prepare(x, seeds + 7)
    assert not np.array_equal(f(x, seeds), first)


def test_bad_input_names_the_key():
    e = env(neighbours=2)
    with pytest.raises(UserInputError, match=r"environment\.stand\.neighbours = 2: 1 "):
        honda.mixture(ZELKOVA, [TALL], env=e)
    with pytest.raises(UserInputError, match=r"honda\.f"):
        honda.mixture(ZELKOVA, [TALL, {**TALL, "f": 2.0}], env=e)
    with pytest.raises(ConfigError, match=r"environment\.stand\.neighbours"):
        load_plan(QUICK, [*OVER, "environment.stand.neighbours=6"])
    with pytest.raises(ConfigError, match=r"environment\.stand\.spacing"):
        load_plan(QUICK, [*OVER, "environment.stand.spacing=0"])
    with pytest.raises(ConfigError, match="projection"):
        LightObjective(env=e, shading="projection")


def test_a_plant_without_neighbours_in_a_mixture_is_refused_naming_the_mode():
    e = env(neighbours=2)
    lone = Plant.from_points([[0, 0, 0], [0, 1, 0]], [-1], [-1, 0], meta={"model": "x"})
    with pytest.raises(ConfigError, match=r"environment\.stand\.mode = 'mixture'"):
        objective(e)(lone)


def test_growsim_grow_places_different_honda_trees(tmp_path, capsys):
    """``--plants`` for Honda: each tree grown alone, placed at its position."""
    from growsim.cli import main

    png = tmp_path / "mix.png"
    argv = "grow honda --preset zelkova --stand 3 --spacing 30 --plants ginkgo,zelkova --json"
    argv = [*argv.split(), "--screenshot", str(png), "--size", "64"]
    assert main(argv) == 0
    plants = json.loads(capsys.readouterr().out)["plants"]
    sizes = [honda.develop(honda.PRESETS[p]).n_segments for p in ("ginkgo", "zelkova", "ginkgo")]
    assert [r["segments"] for r in plants] == sizes
    assert [r["x"] for r in plants] == [-30.0, 0.0, 30.0]
    assert png.stat().st_size > 0
