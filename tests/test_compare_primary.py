"""growsim compare with [compare] primary: primary, exploratory and replication tables,
power, variant names, discovery and confirmation blocks (sweep --block)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from scipy import stats
from test_report import BASE, fake_run

from growsim.cli import main as cli_main
from growsim.errors import ConfigError, UserInputError
from growsim.experiment import load_config
from growsim.report import compare, holm
from growsim.report.primary import hedges_g, seeds_for_power

ROOT = Path(__file__).resolve().parents[1]

VARIANTS = [
    {"name": "ample"},
    {"name": "half_water", "set": {"environment.light.intensity": 0.5}},
]
PRIMARY = [
    {"measure": "height", "expect": "ample > half_water"},
    {"measure": "wood_volume", "expect": "ample > half_water"},
]


def with_compare(primary=PRIMARY, variants=VARIANTS, **more):
    base = {**BASE, "sweep": {"variants": variants}}
    if primary is not None:
        base["compare"] = {"primary": primary, **more}
    return base


def make_block(root, seeds, values, base=None):
    """A sweep directory of two variants, one run per seed; ``values[variant]`` lists
    (height, wood_volume, leaves) per seed."""
    base = base or with_compare()
    for variant, light in (("ample", 1.0), ("half_water", 0.5)):
        for s, (h, w, leaves) in zip(seeds, values[variant]):
            fake_run(
                root / variant / f"seed-{s}",
                s,
                h / 2.0,
                light=light,
                base=base,
                measures={"height": h, "wood_volume": w, "leaves": leaves},
            )
    return root


DISCOVERY = {  # height and wood volume clearly higher in ample light; leaves the same
    "ample": [(10.0, 3.0, 5.0), (11.0, 3.2, 6.0), (12.0, 2.9, 7.0), (10.5, 3.1, 5.0)],
    "half_water": [(6.0, 1.0, 6.0), (5.5, 1.2, 5.0), (6.5, 0.9, 7.0), (6.2, 1.1, 6.0)],
}
CONFIRMATION = {  # height again; wood volume the other way round
    "ample": [(11.0, 1.0, 5.0), (10.0, 0.9, 6.0), (12.5, 1.1, 7.0), (11.5, 1.2, 6.0)],
    "half_water": [(6.5, 3.0, 6.0), (5.0, 3.1, 5.0), (6.0, 2.8, 6.0), (7.0, 3.2, 7.0)],
}


def column(values, variant, k):
    return np.array([v[k] for v in values[variant]])


def test_primary_tests_are_holm_corrected_over_themselves_alone(tmp_path):
    root = make_block(tmp_path / "d", [1, 2, 3, 4], DISCOVERY)
    c = compare([root], tmp_path / "cmp", renders=False)
    # groups named by their sweep variant
    assert list(c.table["group"]) == ["ample", "half_water"]
    p = c.primary.set_index("measure")
    assert list(p.index) == ["height", "wood_volume"]
    raw = [
        stats.ttest_ind(
            column(DISCOVERY, "ample", k), column(DISCOVERY, "half_water", k), equal_var=False
        ).pvalue
        for k in (0, 1)
    ]
    assert p["p"].tolist() == pytest.approx(raw)
    assert p["p_holm"].tolist() == pytest.approx(holm(raw).tolist())  # 2 tests, not all
    assert p["finding"].all() and p["as_expected"].all()
    assert (p["group_a"] == "ample").all() and (p["difference"] > 0).all()
    # the same tests in stats.csv are Holm over every test, so less significant
    s = c.stats.set_index("measure")
    assert (s.loc[["height", "wood_volume"], "welch_t_p_holm"].values >= p["p_holm"].values).all()
    files = {k: v.name for k, v in c.files.items()}
    assert files["primary"] == "primary.csv" and files["exploratory"] == "exploratory.csv"
    assert "replication" not in files
    back = pd.read_csv(c.files["primary"])
    assert back["finding"].tolist() == [True, True]


def test_every_other_test_is_exploratory_and_corrected_separately(tmp_path):
    root = make_block(tmp_path / "d", [1, 2, 3, 4], DISCOVERY)
    c = compare([root], tmp_path / "cmp", renders=False)
    e = c.exploratory
    assert set(e["role"]) == {"exploratory"}
    assert not {"height", "wood_volume"} & set(e["measure"])
    assert {"best_fitness", "leaves"} <= set(e["measure"])
    assert e["welch_t_p_holm"].tolist() == pytest.approx(holm(e["welch_t_p"]).tolist())
    assert len(e) + len(c.primary) == len(c.stats)
    text = Path(c.files["html"]).read_text()
    assert "<h2>Primary tests</h2>" in text
    assert text.index("Primary tests") < text.index("<b>Exploratory.</b>")
    assert "Exploratory: Best fitness" in text


def test_effect_size_and_seeds_for_power(tmp_path):
    root = make_block(tmp_path / "d", [1, 2, 3, 4], DISCOVERY)
    c = compare([root], tmp_path / "cmp", renders=False)
    r = c.primary.set_index("measure").loc["height"]
    x, y = column(DISCOVERY, "ample", 0), column(DISCOVERY, "half_water", 0)
    sd = math.sqrt((np.var(x, ddof=1) + np.var(y, ddof=1)) / 2)
    d = (x.mean() - y.mean()) / sd
    assert r["cohen_d"] == pytest.approx(d)
    assert r["hedges_g"] == pytest.approx(d * (1 - 3 / (4 * 8 - 9)))
    assert r["seeds_for_power"] == seeds_for_power(r["hedges_g"], 0.05, 0.8)
    assert r["power"] == 0.8 and r["alpha"] == 0.05


@pytest.mark.parametrize("g", [0.3, 0.8, 1.5, -2.5])
def test_seeds_for_power_matches_statsmodels(g):
    power_mod = pytest.importorskip("statsmodels.stats.power")
    n = power_mod.TTestIndPower().solve_power(effect_size=abs(g), alpha=0.05, power=0.8)
    assert seeds_for_power(g) == math.ceil(n - 1e-9)
    assert seeds_for_power(g, alpha=0.01, power=0.9) == math.ceil(
        power_mod.TTestIndPower().solve_power(effect_size=abs(g), alpha=0.01, power=0.9) - 1e-9
    )
    assert math.isnan(hedges_g(float("nan"), 4, 4))


def test_replication_table_says_which_findings_replicated(tmp_path, capsys):
    d = make_block(tmp_path / "d", [1, 2, 3, 4], DISCOVERY)
    k = make_block(tmp_path / "k", [5, 6, 7, 8], CONFIRMATION)
    out = tmp_path / "cmp"
    assert (
        cli_main(["compare", str(d), "--confirm", str(k), "--out", str(out), "--no-renders"]) == 0
    )
    printed = capsys.readouterr().out
    assert "1 of 2 discovery finding(s) replicated" in printed
    rep = pd.read_csv(out / "replication.csv").set_index("measure")
    assert rep.loc["height", "replicated"]
    assert rep.loc["height", "verdict"] == "replicated"
    assert rep.loc["height", "confirmation_n"] == "4, 4"
    # wood volume was a finding on the discovery block and goes the other way here
    assert rep.loc["wood_volume", "discovery_finding"]
    assert not rep.loc["wood_volume", "replicated"]
    assert not rep.loc["wood_volume", "same_direction"]
    assert rep.loc["wood_volume", "verdict"].startswith("not replicated: opposite direction")
    text = (out / "report.html").read_text()
    assert "<h2>Replication</h2>" in text and "1 of 2 discovery finding(s)" in text
    assert (out / "primary.csv").is_file() and (out / "exploratory.csv").is_file()


def test_a_finding_too_weak_on_the_fresh_block_does_not_replicate(tmp_path):
    d = make_block(tmp_path / "d", [1, 2, 3, 4], DISCOVERY)
    weak = {  # height a little higher in ample light, far from significant
        "ample": [(7.0, 3.0, 5.0), (5.0, 3.2, 6.0), (6.5, 2.9, 7.0), (6.0, 3.1, 5.0)],
        "half_water": [(6.0, 1.0, 6.0), (5.5, 1.2, 5.0), (6.5, 0.9, 7.0), (6.2, 1.1, 6.0)],
    }
    k = make_block(tmp_path / "k", [9, 10, 11, 12], weak)
    c = compare([d], tmp_path / "cmp", renders=False, confirm=[k])
    rep = c.replication.set_index("measure")
    assert rep.loc["height", "same_direction"] and not rep.loc["height", "replicated"]
    assert rep.loc["height", "verdict"].startswith("not replicated: p_holm = ")
    assert rep.loc["wood_volume", "replicated"]


def test_a_confirmation_must_use_fresh_seeds(tmp_path):
    d = make_block(tmp_path / "d", [1, 2, 3, 4], DISCOVERY)
    k = make_block(tmp_path / "k", [4, 5, 6, 7], CONFIRMATION)
    with pytest.raises(UserInputError, match=r"seed\(s\) 4 in the discovery runs"):
        compare([d], tmp_path / "cmp", renders=False, confirm=[k])
    assert not (tmp_path / "cmp").exists()


def test_confirm_needs_primary_tests(tmp_path):
    d = make_block(tmp_path / "d", [1, 2], DISCOVERY, base=with_compare(primary=None))
    k = make_block(tmp_path / "k", [3, 4], DISCOVERY, base=with_compare(primary=None))
    with pytest.raises(UserInputError, match="--confirm: no primary tests declared"):
        compare([d], tmp_path / "cmp", renders=False, confirm=[k])


def test_without_compare_section_compare_is_as_before(tmp_path):
    d = make_block(tmp_path / "d", [1, 2, 3], DISCOVERY, base=with_compare(primary=None))
    c = compare([d], tmp_path / "cmp", renders=False)
    assert c.primary is None and c.exploratory is None and c.replication is None
    assert set(c.files) == {"table", "stats", "runs", "curves", "html"}
    text = Path(c.files["html"]).read_text()
    assert "Primary tests" not in text and "Exploratory" not in text
    assert list(c.table["group"]) == ["ample", "half_water"]


def test_primary_from_a_config_for_runs_made_without_it(tmp_path):
    d = make_block(tmp_path / "d", [1, 2, 3], DISCOVERY, base=with_compare(primary=None))
    cfg = tmp_path / "exp.toml"
    cfg.write_text(load_config(with_compare()).to_toml())
    c = compare([d], tmp_path / "cmp", renders=False, primary=cfg)
    assert c.primary["measure"].tolist() == ["height", "wood_volume"]
    bare = tmp_path / "bare.toml"
    bare.write_text(load_config(with_compare(primary=None)).to_toml())
    with pytest.raises(UserInputError, match=r"declares no \[compare\] primary"):
        compare([d], tmp_path / "cmp2", renders=False, primary=bare)


def test_the_compare_section_does_not_split_groups(tmp_path):
    # the same variant with and without [compare]: one group
    make_block(tmp_path / "d", [1, 2], DISCOVERY, base=with_compare(primary=None))
    make_block(tmp_path / "e", [3, 4], DISCOVERY)
    c = compare([tmp_path / "d", tmp_path / "e"], tmp_path / "cmp", renders=False)
    assert c.table["runs"].tolist() == [4, 4]


@pytest.mark.parametrize(
    "compare_section, key, text",
    [
        (
            {"primary": [{"measure": "height", "expect": "ample > half_light"}]},
            "compare.primary[0].expect",
            "unknown variant 'half_light'",
        ),
        (
            {"primary": [{"measure": "height", "expect": "ample >> half_water"}]},
            "compare.primary[0].expect",
            "expected",
        ),
        (
            {"primary": [{"measure": "height", "expect": "ample > ample"}]},
            "compare.primary[0].expect",
            "a group against itself",
        ),
        (
            {"primary": [{"measure": "height", "expect": "ample > half_water", "dir": 1}]},
            "compare.primary[0].dir",
            "unknown key",
        ),
        ({"primary": [], "alpha": 1.5}, "compare.alpha", ""),
        ({"primary": [], "test": "t"}, "compare.test", ""),
    ],
)
def test_bad_compare_sections_name_the_key(compare_section, key, text):
    cfg = {**with_compare(primary=None), "compare": compare_section}
    with pytest.raises(ConfigError) as exc:
        load_config(cfg)
    msg = str(exc.value)
    assert msg.startswith(key + ":") and text in msg and "\n" not in msg


def test_unknown_measure_or_group_at_compare_names_the_key(tmp_path):
    bad = with_compare(primary=[{"measure": "heigth", "expect": "ample > half_water"}])
    d = make_block(tmp_path / "d", [1, 2], DISCOVERY, base=bad)
    with pytest.raises(ConfigError, match=r"^compare.primary\[0\].measure: unknown measure "):
        compare([d], tmp_path / "cmp", renders=False)
    assert not (tmp_path / "cmp").exists()
    # no [[sweep.variants]]: the names are checked against the groups at compare time
    loose = {**BASE, "compare": {"primary": [{"measure": "height", "expect": "a > b"}]}}
    for s in (1, 2):
        fake_run(tmp_path / "l" / f"r{s}", s, 1.0 + s, base=loose)
        fake_run(tmp_path / "l" / f"q{s}", s, 1.0 + s, light=0.5, base=loose)
    with pytest.raises(ConfigError, match=r"^compare.primary\[0\].expect: no group 'a'"):
        compare([tmp_path / "l"], tmp_path / "cmp", renders=False)


def test_a_group_with_one_run_is_reported_untested(tmp_path):
    d = make_block(tmp_path / "d", [1], DISCOVERY)
    c = compare([d], tmp_path / "cmp", renders=False)
    assert not c.primary["finding"].any()
    assert c.primary["note"].str.contains("not tested").all()


def test_sweep_blocks_use_fresh_seeds_and_ignore_the_compare_section(tmp_path):
    from growsim.experiment import sweep

    quick = ROOT / "experiments" / "quickstart.toml"
    tiny = ["ga.population=4", "ga.generations=2", "output.screenshots=[]", "output.mesh=[]"]
    tiny += ["output.plot=false", "experiment.seed=3"]
    kw = dict(repeats=2, overrides=tiny, progress=False)
    one = sweep(quick, out=tmp_path / "b1", **kw)
    two = sweep(quick, out=tmp_path / "b2", block=2, **kw)
    assert one["seed"].tolist() == [3, 4] and two["seed"].tolist() == [5, 6]
    assert sorted(p.name for p in (tmp_path / "b2" / "base").iterdir()) == ["seed-5", "seed-6"]
    # declaring primary tests afterwards does not make the finished runs other runs
    declared = [*tiny, 'compare.primary=[{measure = "height", expect = "a > b"}]']
    again = sweep(quick, out=tmp_path / "b1", **{**kw, "overrides": declared})
    assert again["best_fitness"].tolist() == one["best_fitness"].tolist()
    with pytest.raises(UserInputError, match="--block"):
        sweep(quick, out=tmp_path / "b3", block=0, **kw)


@pytest.mark.parametrize(
    "expect, sign, expected",
    [
        ("half_water < ample", -1, True),
        ("ample != half_water", 1, True),
        ("ample < half_water", 1, False),
    ],
)
def test_directions(tmp_path, expect, sign, expected):
    base = with_compare(primary=[{"measure": "height", "expect": expect}])
    d = make_block(tmp_path / "d", [1, 2, 3], DISCOVERY, base=base)
    r = compare([d], tmp_path / "cmp", renders=False).primary.iloc[0]
    assert np.sign(r["difference"]) == sign
    assert r["as_expected"] == expected and r["finding"] == expected
    assert r["p_holm"] == pytest.approx(r["p"])  # one primary test: nothing to correct


def test_cli_options_parse():
    from growsim.cli import build_parser

    a = build_parser().parse_args(["compare", "d1", "--confirm", "d2", "d3", "--primary", "x.toml"])
    assert a.dirs == ["d1"] and a.confirm == ["d2", "d3"] and a.primary == "x.toml"
    assert build_parser().parse_args(["sweep", "x.toml", "--block", "2"]).block == 2
    assert build_parser().parse_args(["sweep", "x.toml"]).block == 1


def test_shipped_hormone_configs_declare_primary_tests():
    for name in ("hormone_2d", "hormone_3d"):
        cfg = load_config(ROOT / "experiments" / f"{name}.toml")
        assert len(cfg.compare.primary) >= 2
        measures = {p.measure for p in cfg.compare.primary}
        assert "light_per_area" not in measures  # set by the environment, not a form
