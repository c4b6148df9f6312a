"""Honda trees in a stand (issue 30): the light objective with ``[environment.stand]``.

Periodic: the tree among its own copies (they shade it, only its leaves are judged);
explicit: the stand of copies is scored (every tree's leaves, shaded by all), as the
hormone model scores an explicit stand's nutrient. ``docs/models/stand.md``.
"""

from __future__ import annotations

from contextlib import redirect_stderr, redirect_stdout
from io import StringIO

import numpy as np
import pytest

from growsim.env import Environment
from growsim.errors import ConfigError
from growsim.models import honda
from growsim.objectives.light import LightObjective
from growsim.phenotypes.plant import leaf_light

LIGHT = {"direction": [0.3, -1.0, 0.2], "diffuse": 0.5, "resolution": 256}


def objective(stand=None, light=LIGHT, **options):
    env = {"light": light} if stand is None else {"light": light, "stand": stand}
    return LightObjective(env=Environment.parse(env), **options)


def tree(preset="zelkova"):
    return honda.develop(honda.PRESETS[preset])


@pytest.mark.parametrize("preset", ["zelkova", "ginkgo", "cherry"])
def test_periodic_score_is_below_alone_and_falls_with_density(preset):
    """Crowns 40 to 50 m wide: at 40 m they touch, at 20 m and 10 m they overlap."""
    t = tree(preset)
    alone = objective()(t)
    scores = [objective({"mode": "periodic", "spacing": s})(t) for s in (40.0, 20.0, 10.0)]
    assert alone > scores[0] > scores[1] > scores[2] > 0.0


def test_periodic_judges_only_the_focal_tree_and_keeps_its_wood():
    t = tree()
    alone = objective().terms(t)
    periodic = objective({"mode": "periodic", "spacing": 20.0}).terms(t)
    assert periodic["leaf_area"] == alone["leaf_area"]
    assert periodic["wood_volume"] == alone["wood_volume"]
    assert periodic["light"] < alone["light"]


def test_periodic_map_keeps_the_crowns_pixels():
    """The stand's map gets more pixels so the crown keeps its own: a tree far from its
    copies (no shade) scores as alone, within the map's pixel noise (here 3 %); lit by a
    map of ``resolution`` pixels over the whole stand it would score far more."""
    t = tree()
    alone = objective()(t)
    far = objective({"mode": "periodic", "spacing": 200.0})
    assert far.scored(t)[2].resolution == 4096  # 256 x (1 + 800 / 43) -> the most
    assert far(t) == pytest.approx(alone, rel=0.03)
    coarse = leaf_light(t, far.light, shifts=far.scored(t)[1]).light
    assert coarse > 1.05 * objective(wood_cost=0.0)(t)


def test_an_explicit_stand_of_one_at_the_origin_is_the_tree_alone_bit_for_bit():
    t = tree()
    one = objective({"mode": "explicit", "positions": [[0.0, 0.0]]})
    assert one.terms(t) == objective().terms(t)


def test_an_explicit_stand_scores_every_tree_shaded_by_all():
    t = tree()
    alone = objective().terms(t)
    obj = objective({"mode": "explicit", "rows": 3, "cols": 3, "spacing": 20.0})
    stand, shifts, light = obj.scored(t)
    assert shifts is None and stand.n_segments == 9 * t.n_segments
    assert sorted(set(stand.data["plant"].tolist())) == list(range(9))
    assert light.resolution == 768  # the crown keeps about its 256 pixels
    terms = obj.terms(t)
    assert terms["leaf_area"] == pytest.approx(9 * alone["leaf_area"])
    assert terms["wood_volume"] == pytest.approx(9 * alone["wood_volume"])
    assert terms["light"] < 9 * alone["light"]  # they shade each other
    # the stand's score is the sum over its trees of what each tree's leaves receive
    assert terms["light"] == pytest.approx(leaf_light(stand, light).light)
    sparse = objective({"mode": "explicit", "rows": 3, "cols": 3, "spacing": 40.0}).terms(t)
    assert terms["light"] < sparse["light"]


def test_a_stand_phenotype_is_scored_as_it_is():
    t = tree()
    obj = objective({"mode": "explicit", "rows": 2, "cols": 2, "spacing": 30.0})
    stand, _, _ = obj.scored(t)
    again, shifts, light = obj.scored(stand)
    assert again is stand and shifts is None and light is obj.light


def test_the_periodic_map_agrees_with_the_explicit_one_on_the_centre_tree():
    """The objective's periodic stand with three rings and its explicit 7 x 7 stand give
    the centre tree the same light: the same 49 trees in one map of the same pixels."""
    t = tree("ginkgo")
    periodic = objective({"mode": "periodic", "spacing": 30.0, "rings": 3})
    explicit = objective({"mode": "explicit", "rows": 7, "cols": 7, "spacing": 30.0})
    focal, shifts, light_p = periodic.scored(t)
    stand, _, light_e = explicit.scored(t)
    assert light_p.resolution == light_e.resolution
    n = t.n_segments
    centre = light_e.segment_light(stand)[24 * n : 25 * n]
    assert np.array_equal(light_p.segment_light(focal, shifts=shifts), centre)


def test_projection_in_a_stand_is_refused():
    with pytest.raises(ConfigError, match="shading = 'projection'"):
        objective({"mode": "periodic", "spacing": 20.0}, shading="projection")


CONFIG = """
[experiment]
name = "honda_stand_{mode}"
seed = 1

[model]
kind = "honda"
preset = "zelkova"
params = {{ generations = 7 }}

[model.evolve]
f = [0.5, 1.0]
theta0 = true

[environment.light]
direction = [0.3, -1.0, 0.2]
resolution = 64

[environment.stand]
mode = "{mode}"
spacing = 20.0
{extra}

[[objective]]
kind = "light"
wood_cost = 0.5

[ga]
population = 6
generations = 2

[output]
mesh = []
screenshots = []
"""


def _run(tmp_path, mode, extra=""):
    from growsim.cli import main

    cfg = tmp_path / f"{mode}.toml"
    cfg.write_text(CONFIG.format(mode=mode, extra=extra))
    err = StringIO()
    with redirect_stderr(err), redirect_stdout(StringIO()):
        code = main(["run", str(cfg), "--out", str(tmp_path / mode), "--quiet"])
    return code, err.getvalue()


@pytest.mark.parametrize(
    ("mode", "extra"),
    [("periodic", "rings = 1"), ("explicit", "rows = 2\ncols = 2"), ("mixture", "neighbours = 2")],
)
def test_growsim_run_evolves_honda_in_a_stand(tmp_path, mode, extra):
    code, err = _run(tmp_path, mode, extra)
    assert code == 0, err
    assert any((tmp_path / mode).rglob("*"))


def test_growsim_run_refuses_a_mixture_larger_than_the_population(tmp_path):
    code, err = _run(tmp_path, "mixture", "neighbours = 8")  # a population of 6
    assert code == 2 and "stand.neighbours" in err and len(err.strip().splitlines()) == 1, err
    assert not (tmp_path / "mixture").exists()


def test_grow_json_gives_each_placed_tree_its_light_in_the_stand(capsys):
    """``growsim grow honda --stand N --json``: each tree's light captured is its
    segments' light in the stand's one shadow map (the middle of a row of three, shaded
    from both sides, gets the least), and the shares sum to 1."""
    import json

    from growsim.cli import main

    assert main(["grow", "honda", "--preset", "zelkova", "--stand", "3", "--spacing", "20",
                 "--light-direction", "0.3", "-1", "0", "--json"]) == 0  # fmt: skip
    plants = json.loads(capsys.readouterr().out)["plants"]
    light = [p["light_captured"] for p in plants]
    assert min(light) > 0.0 and light[1] == min(light)
    assert sum(p["light_share"] for p in plants) == pytest.approx(1.0)
