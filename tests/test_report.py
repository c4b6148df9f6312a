"""growsim.report.compare on synthetic run directories with known numbers."""

from __future__ import annotations

import json
import math
import re
import warnings

import numpy as np
import pandas as pd
import pytest
from scipy import stats

from growsim import report
from growsim.cli import main as cli_main
from growsim.errors import UserInputError
from growsim.experiment import load_config
from growsim.experiment.results import RunDir, find_runs
from growsim.report import compare, group_runs, holm

BASE = {
    "model": {"kind": "honda", "evolve": {"f": True}},
    "objective": [{"kind": "light"}],
    "ga": {"population": 4, "generations": 3},
}


def fake_run(
    path,
    seed,
    best,
    light=1.0,
    gens=4,
    *,
    overrides=(),
    base=BASE,
    measures=None,
    terms=None,
    finished="2026-11-22T10:00:00+0000",
):
    """A finished run directory whose numbers we know."""
    cfg = load_config(base, [f"experiment.seed={seed}", f"environment.light={light}", *overrides])
    rd = RunDir(path)
    path.mkdir(parents=True)
    rd.write_text("config.toml", cfg.to_toml())
    g = np.arange(gens)
    curve = best * (g + 1) / gens
    rd.write_parquet(
        "history.parquet",
        pd.DataFrame(
            {
                "generation": g,
                "island": 0,
                "evaluations": (g + 1) * 4,
                "best": curve,
                "mean": curve / 2,
                "best_so_far": curve,
                "seconds": g * 0.1,
            }
        ),
    )
    rd.write_json("best.json", {"fitness": best, "params": {"f": 0.5}})
    if measures is None:
        measures = {
            "height": 10.0 + best,
            "crown_width": 3.0,
            "segments": 7.0,
            "light_captured": 2.0 * best,
        }
    rd.write_json(
        "summary.json",
        {
            "experiment": "experiment",
            "seed": seed,
            "best_fitness": best,
            "best_generation": gens - 1,
            "generations": gens,
            "evaluations": gens * 4,
            "wall_seconds": 1.5,
            "stop_reason": "generations",
            "finished": finished,
            "measures": measures,
            "terms": terms if terms is not None else {"light": {"score": best}},
        },
    )


@pytest.fixture
def sweep_dir(tmp_path):
    a = [10.0, 12.0, 11.0]
    b = [5.0, 6.0, 4.5]
    for s, v in enumerate(a):
        fake_run(tmp_path / "sw" / "light=1.0" / f"seed-{s}", s, v, light=1.0)
    for s, v in enumerate(b):
        fake_run(tmp_path / "sw" / "light=0.5" / f"seed-{s}", s, v, light=0.5)
    return tmp_path / "sw", a, b


def test_groups_table_ci_and_tests(sweep_dir, tmp_path):
    root, a, b = sweep_dir
    c = compare([root], tmp_path / "cmp", renders=False)
    t = c.table.set_index("group")
    assert set(t.index) == {"light.intensity=1.0", "light.intensity=0.5"}
    row = t.loc["light.intensity=1.0"]
    assert row["dirs"] == "light=1.0" and row["duplicates"] == 0
    assert row["runs"] == 3 and row["best"] == 12.0
    assert row["mean"] == pytest.approx(np.mean(a))
    half = stats.t.ppf(0.975, 2) * np.std(a, ddof=1) / math.sqrt(3)
    assert row["ci95"] == pytest.approx(half)
    # measures: mean +/- CI over the repeats
    assert row["height"] == pytest.approx(10.0 + np.mean(a))
    assert row["light_captured"] == pytest.approx(2.0 * np.mean(a))
    assert row["height_ci95"] == pytest.approx(half)
    s = c.stats.iloc[0]
    assert s["measure"] == "best_fitness"
    x, y = (a, b) if s["group_a"] == "light.intensity=1.0" else (b, a)
    assert s["welch_t_p"] == pytest.approx(stats.ttest_ind(x, y, equal_var=False).pvalue)
    assert s["mann_whitney_p"] == pytest.approx(stats.mannwhitneyu(x, y).pvalue)
    assert s["welch_t_p"] < 0.01
    for key in ("table", "stats", "runs", "curves", "html"):
        assert c.files[key].is_file()
    assert len(pd.read_csv(c.files["runs"])) == 6


def test_html_is_self_contained(sweep_dir, tmp_path):
    root, _, _ = sweep_dir
    c = compare([root], tmp_path / "cmp", renders=False)
    text = c.files["html"].read_text()
    assert "data:image/png;base64," in text
    assert "Welch" in text and "light.intensity=0.5" in text and "Holm" in text
    # no external resources: every src is an embedded data URI
    assert all(s.startswith("data:") for s in re.findall(r"src='([^']*)'", text))


def test_single_runs_are_grouped_by_config_up_to_seed(tmp_path):
    fake_run(tmp_path / "r1", 0, 3.0)
    fake_run(tmp_path / "r2", 1, 4.0)
    fake_run(tmp_path / "r3", 0, 9.0, light=0.2)
    groups = group_runs(find_runs([tmp_path / "r1", tmp_path / "r2", tmp_path / "r3"]))
    sizes = sorted(len(v) for v in groups.values())
    assert sizes == [1, 2]
    c = compare([tmp_path / "r1", tmp_path / "r3"], tmp_path / "cmp", renders=False)
    assert len(c.table) == 2 and len(c.stats) == 0  # no repeats: no test


def test_the_same_run_twice_counts_once(tmp_path):
    fake_run(tmp_path / "r1", 0, 3.0)
    assert len(find_runs([tmp_path / "r1", tmp_path])) == 1


def test_bad_dirs(tmp_path):
    with pytest.raises(UserInputError, match="no such directory"):
        compare([tmp_path / "nope"])
    (tmp_path / "empty").mkdir()
    with pytest.raises(UserInputError, match="no finished growsim run"):
        compare([tmp_path / "empty"])
    with pytest.raises(UserInputError, match="at least one"):
        compare([])


def test_identical_groups_give_p_one(tmp_path):
    for s in range(2):
        fake_run(tmp_path / "a" / f"seed-{s}", s, 1.0)
        fake_run(tmp_path / "b" / f"seed-{s}", s, 1.0, light=0.5)
    c = compare([tmp_path / "a", tmp_path / "b"], tmp_path / "cmp", renders=False)
    assert c.stats["welch_t_p"].iloc[0] == 1.0 and c.stats["mann_whitney_p"].iloc[0] == 1.0
    json.loads((tmp_path / "a" / "seed-0" / "summary.json").read_text())


def test_directories_without_runs_are_skipped_when_others_have_runs(tmp_path, caplog):
    fake_run(tmp_path / "r1", 0, 3.0)
    (tmp_path / "compare-old").mkdir()
    runs = find_runs([tmp_path / "r1", tmp_path / "compare-old"])
    assert len(runs) == 1
    assert "compare-old: no finished growsim run here; skipped" in caplog.text


# --- 1. a seed run twice is one run, not two repeats ----------------------------------


def test_duplicated_seeds_are_flagged_and_counted_once(tmp_path, caplog):
    # the same config and seed run twice per group: one run each, not two repeats
    fake_run(tmp_path / "a1", 0, 3.0, finished="2026-11-22T10:00:00+0000")
    fake_run(tmp_path / "a2", 0, 3.0, finished="2026-11-22T11:00:00+0000")
    fake_run(tmp_path / "b1", 0, 5.0, light=0.5)
    fake_run(tmp_path / "b2", 0, 5.0, light=0.5)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        c = compare([tmp_path], tmp_path / "cmp", renders=False)
    assert not [str(w.message) for w in caught]  # no scipy precision warning
    t = c.table.set_index("group")
    assert t["runs"].tolist() == [1, 1] and t["duplicates"].tolist() == [1, 1]
    assert t["ci95"].isna().all()  # n = 1: no CI, not a CI of 0
    assert len(c.stats) == 0  # and no test
    assert "seed 0 appears in 2 runs" in caplog.text
    assert any("not tested" in n for n in c.notes)
    # the latest finished is kept, the other names it
    r = c.runs.set_index("path")
    assert bool(r.loc[str(tmp_path / "a2"), "counted"])
    assert not bool(r.loc[str(tmp_path / "a1"), "counted"])
    assert r.loc[str(tmp_path / "a1"), "duplicate_of"] == str(tmp_path / "a2")
    assert "keeping " + str(tmp_path / "a2") in caplog.text
    assert "appears in 2 runs" in c.files["html"].read_text()


def test_a_duplicate_among_repeats_leaves_the_other_seeds(tmp_path):
    for s, v in enumerate([1.0, 2.0, 3.0]):
        fake_run(tmp_path / f"r{s}", s, v)
    fake_run(tmp_path / "again", 1, 2.0)
    c = compare([tmp_path], tmp_path / "cmp", renders=False)
    row = c.table.iloc[0]
    assert row["runs"] == 3 and row["duplicates"] == 1
    assert row["mean"] == pytest.approx(2.0)
    assert row["ci95"] == pytest.approx(stats.t.ppf(0.975, 2) * 1.0 / math.sqrt(3))


# --- 2. labels say what differs -------------------------------------------------------


def test_groups_are_labelled_by_what_differs_in_their_configs(tmp_path):
    fake_run(tmp_path / "quickstart", 0, 1.0)
    fake_run(tmp_path / "quickstart-2", 0, 2.0, light=0.5)
    fake_run(tmp_path / "quickstart-3", 0, 3.0, overrides=["ga.population=8"])
    fake_run(tmp_path / "quickstart-4", 1, 3.0, overrides=["ga.population=8"])
    groups = group_runs(find_runs([tmp_path]))
    assert set(groups) == {
        "light.intensity=1.0, ga.population=4",
        "light.intensity=0.5, ga.population=4",
        "light.intensity=1.0, ga.population=8",
    }
    assert len(groups["light.intensity=1.0, ga.population=8"]) == 2


def test_a_preset_labels_its_group_without_its_parameters(tmp_path):
    fake_run(tmp_path / "x1", 0, 1.0, overrides=["model.preset=zelkova"])
    fake_run(tmp_path / "x2", 0, 1.0, overrides=["model.preset=cherry", "ga.population=100"])
    assert set(group_runs(find_runs([tmp_path]))) == {
        "model.preset=zelkova, ga.population=4",
        "model.preset=cherry, ga.population=100",
    }


def test_short_names_are_unambiguous():
    u = {("a", "b", "c"), ("d", "b", "c"), ("ga", "population"), ("x", "y", "z")}
    names = report.configs.short_names(sorted(u), u)
    assert names[("a", "b", "c")] == "a.b.c" and names[("d", "b", "c")] == "d.b.c"
    assert names[("ga", "population")] == "ga.population"
    assert names[("x", "y", "z")] == "y.z"


def test_the_experiment_name_and_output_do_not_split_a_group(tmp_path):
    fake_run(tmp_path / "r1", 0, 1.0, overrides=["experiment.name=one"])
    fake_run(tmp_path / "r2", 1, 2.0, overrides=["experiment.name=two", "output.plot=false"])
    assert [len(v) for v in group_runs(find_runs([tmp_path])).values()] == [2]


# --- 3. families: tests only between comparable fitness ----------------------------------

IFS = {
    "model": {"kind": "ifs3d", "evolve": {"s_1": True}},
    "objective": [{"kind": "light"}],
    "ga": {"population": 4, "generations": 3},
}


def test_only_groups_of_one_family_are_tested(tmp_path):
    for s in range(3):
        fake_run(tmp_path / "a" / f"seed-{s}", s, 10.0 + s)
        fake_run(tmp_path / "b" / f"seed-{s}", s, 20.0 + s, light=0.5)
        # another objective option: another score, not comparable
        fake_run(
            tmp_path / "c" / f"seed-{s}", s, 30.0 + s, overrides=["objective[0].wood_cost=1.0"]
        )
        # another model
        fake_run(tmp_path / "d" / f"seed-{s}", s, 40.0 + s, base=IFS)
    c = compare([tmp_path], tmp_path / "cmp", renders=False)
    fams = c.table.groupby("family", sort=False)["group"].apply(list).to_dict()
    assert len(fams) == 3
    assert fams["honda / light (wood_cost=0.02)"] == ["light.intensity=0.5", "light.intensity=1.0"]
    assert len(fams["honda / light (wood_cost=1.0)"]) == 1
    assert len(fams["ifs3d / light"]) == 1
    pairs = set(zip(c.stats["group_a"], c.stats["group_b"]))
    assert pairs == {("light.intensity=0.5", "light.intensity=1.0")}
    assert set(c.stats["family"]) == {"honda / light (wood_cost=0.02)"}
    text = c.files["html"].read_text()
    assert text.count("<h2>") >= 3 + 2  # methods, one block per family, runs


# --- 4. Holm-Bonferroni ---------------------------------------------------------------


def test_holm_matches_r_p_adjust():
    # R: p.adjust(c(0.01, 0.04, 0.03, 0.005), "holm") -> 0.03 0.06 0.06 0.02
    np.testing.assert_allclose(holm([0.01, 0.04, 0.03, 0.005]), [0.03, 0.06, 0.06, 0.02])
    # R: p.adjust(c(0.02, 0.001, 0.04, 0.3, 0.01), "holm") -> 0.06 0.005 0.08 0.3 0.04
    np.testing.assert_allclose(holm([0.02, 0.001, 0.04, 0.3, 0.01]), [0.06, 0.005, 0.08, 0.3, 0.04])
    np.testing.assert_allclose(holm([0.5, 0.6]), [1.0, 1.0])  # capped at 1
    out = holm([0.01, float("nan"), 0.04])  # NaN: not a test, not counted
    assert math.isnan(out[1]) and out[0] == pytest.approx(0.02) and out[2] == pytest.approx(0.04)
    assert len(holm([])) == 0


def test_holm_matches_statsmodels():
    from statsmodels.stats import multitest

    p = np.random.default_rng(0).uniform(0, 0.2, 30)
    np.testing.assert_allclose(holm(p), multitest.multipletests(p, method="holm")[1])


def test_p_values_are_holm_adjusted_within_each_family(tmp_path):
    for g, light in enumerate((1.0, 0.5, 0.2)):
        for s in range(3):
            best = 10.0 * g + s + 0.1 * g * s
            fake_run(tmp_path / f"g{g}" / f"seed-{s}", s, best, light=light)
    c = compare([tmp_path], tmp_path / "cmp", renders=False)
    assert len(c.stats) == 3 * 3  # 3 pairs x (best fitness, height, light_captured)
    for col in ("welch_t_p", "mann_whitney_p"):
        np.testing.assert_allclose(c.stats[f"{col}_holm"], holm(c.stats[col]))
        assert (c.stats[f"{col}_holm"] >= c.stats[col]).all()


# --- 5. measures and terms tested too; zero variance without warnings --------------------


def test_measures_and_objective_terms_are_tested(tmp_path):
    a = [10.0, 12.0, 11.0, 13.0]
    b = [5.0, 6.0, 4.5, 5.5]
    for s, (x, y) in enumerate(zip(a, b)):
        for name, v, light in (("a", x, 1.0), ("b", y, 0.5)):
            fake_run(
                tmp_path / name / f"seed-{s}",
                s,
                v,
                light=light,
                measures={"height": 2 * v + s, "n_segments": 7.0, "crown_width": 3.0 - s},
                terms={"light": {"score": v, "leaf_area": v * v, "wood_volume": 1.0}},
            )
    c = compare([tmp_path], tmp_path / "cmp", renders=False)
    st = c.stats.set_index("measure")
    # constant in every run (n_segments, light.wood_volume), repeating best fitness
    # (light.score) or the same in both groups (crown_width): no or an all-1 test
    assert set(st.index) == {"best_fitness", "height", "crown_width", "light.leaf_area"}
    assert st.loc["crown_width", "welch_t_p"] == 1.0
    x = np.array([2 * v + s for s, v in enumerate(a)])
    y = np.array([2 * v + s for s, v in enumerate(b)])
    h = st.loc["height"]
    assert h["group_a"] == "light.intensity=0.5"  # sorted by the differing value
    assert h["welch_t_p"] == pytest.approx(stats.ttest_ind(y, x, equal_var=False).pvalue)
    assert h["mann_whitney_p"] == pytest.approx(stats.mannwhitneyu(y, x).pvalue)
    assert h["difference"] == pytest.approx(y.mean() - x.mean())
    ci = stats.ttest_ind(y, x, equal_var=False).confidence_interval()
    assert (h["diff_ci_low"], h["diff_ci_high"]) == pytest.approx((ci.low, ci.high))
    assert h["cliffs_delta"] == -1.0
    sp = math.sqrt((np.var(x, ddof=1) + np.var(y, ddof=1)) / 2)
    assert h["cohen_d"] == pytest.approx((y.mean() - x.mean()) / sp)
    la = st.loc["light.leaf_area"]
    assert la["mean_b"] == pytest.approx(np.mean(np.square(a)))
    t = c.table.set_index("group")
    assert t.loc["light.intensity=1.0", "light.leaf_area"] == pytest.approx(np.mean(np.square(a)))


def test_zero_variance_gives_no_warning(tmp_path):
    # constant within groups: equal (p = 1), different (Welch undefined), nearly equal
    for s in range(3):
        fake_run(tmp_path / "a" / f"seed-{s}", s, 1.0)
        fake_run(tmp_path / "b" / f"seed-{s}", s, 2.0, light=0.5)
        fake_run(tmp_path / "c" / f"seed-{s}", s, 1.0 + s * 1e-15, light=0.2)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        c = compare([tmp_path], tmp_path / "cmp", renders=False)
    assert not [str(w.message) for w in caught]
    st = c.stats[c.stats["measure"] == "best_fitness"].set_index(["group_a", "group_b"])
    ac = st.loc[("light.intensity=0.2", "light.intensity=1.0")]
    assert ac["welch_t_p"] == 1.0 and ac["mann_whitney_p"] == 1.0
    ab = st.loc[("light.intensity=0.5", "light.intensity=1.0")]
    assert math.isnan(ab["welch_t_p"]) and "zero variance" in ab["note"]
    assert 0 < ab["mann_whitney_p"] < 1 and ab["cliffs_delta"] == 1.0


def test_groups_with_one_seed_are_not_tested_and_it_is_said(tmp_path):
    for s in range(2):
        fake_run(tmp_path / "a" / f"seed-{s}", s, 1.0 + s)
        fake_run(tmp_path / "b" / f"seed-{s}", s, 3.0 + s, light=0.5)
    fake_run(tmp_path / "c", 0, 9.0, light=0.2)
    c = compare([tmp_path], tmp_path / "cmp", renders=False)
    assert "light.intensity=0.2" not in set(c.stats["group_a"]) | set(c.stats["group_b"])
    assert len(c.stats[c.stats["measure"] == "best_fitness"]) == 1
    assert any("light.intensity=0.2 has 1 run(s)" in n for n in c.notes)
    assert "Not tested (fewer than 2 runs" in c.files["html"].read_text()


# --- 6. curves: one panel per family ------------------------------------------------


def test_curves_have_one_panel_per_family(tmp_path):
    for s in range(2):
        fake_run(tmp_path / "a" / f"seed-{s}", s, 1000.0 + s)
        fake_run(tmp_path / "b" / f"seed-{s}", s, 900.0 + s, light=0.5)
        fake_run(tmp_path / "c" / f"seed-{s}", s, 0.5 + s / 10, base=IFS)
    fams = report.groups.families(find_runs([tmp_path]), [])
    fig = report.figures.curves_figure(fams)
    axes = [ax for ax in fig.axes if ax.get_visible()]
    assert [ax.get_title() for ax in axes] == [f.label for f in fams]
    assert [len(ax.get_lines()) for ax in axes] == [2, 1]
    assert axes[1].get_ylim()[1] < 1  # not on the same axis as the fitness around 1000
    assert axes[0].get_xlabel() == "evaluations"
    import matplotlib.pyplot as plt

    plt.close(fig)
    c = compare([tmp_path], tmp_path / "cmp", renders=False)
    from PIL import Image

    one = compare([tmp_path / "a"], tmp_path / "cmp1", renders=False)
    w2 = Image.open(c.files["curves"]).size[0]
    w1 = Image.open(one.files["curves"]).size[0]
    assert w2 > 1.5 * w1  # two panels side by side


# --- 7. the report goes beside the runs ----------------------------------------------


def test_report_goes_beside_the_runs_and_the_cli_says_where(tmp_path, monkeypatch, capsys):
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    for s in range(2):
        fake_run(tmp_path / "runs" / "a" / f"seed-{s}", s, 1.0 + s)
        fake_run(tmp_path / "runs" / "b" / f"seed-{s}", s, 5.0 + s, light=0.5)
    c = compare([tmp_path / "runs"], renders=False)
    out = c.files["html"].parent
    assert out.parent.resolve() == (tmp_path / "runs").resolve()
    assert out.name.startswith("compare-")
    assert not (elsewhere / "runs").exists()
    # two run directories side by side: their directory
    assert cli_main(["compare", str(tmp_path / "runs" / "a"), str(tmp_path / "runs" / "b"),
                     "--no-renders"]) == 0  # fmt: skip
    printed = capsys.readouterr().out
    where = re.search(r"report: (\S+)", printed).group(1)
    assert str(tmp_path / "runs" / "compare-") in where and where.endswith("report.html")
    assert "welch_t_p_holm" in printed and "honda / light" in printed


def test_runs_in_unrelated_places_report_to_runs(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    fake_run(tmp_path / "x" / "r1", 0, 1.0)
    fake_run(tmp_path / "y" / "r2", 0, 2.0, light=0.5)
    c = compare([tmp_path / "x" / "r1", tmp_path / "y" / "r2"], renders=False)
    assert c.files["html"].parent.parent == tmp_path / "runs" or (
        c.files["html"].parent.parent == __import__("pathlib").Path("runs")
    )


def test_html_reads_like_a_paper(tmp_path):
    for s in range(3):
        fake_run(tmp_path / "a" / f"seed-{s}", s, 10.0 + s)
        fake_run(tmp_path / "b" / f"seed-{s}", s, 20.0 + s, light=0.5)
    c = compare([tmp_path], tmp_path / "cmp", renders=False)
    text = c.files["html"].read_text()
    for phrase in ("Methods", "Holm", "Cliff", "Cohen", "95&nbsp;% CI", "± ", "(Holm)"):
        assert phrase in text
    assert "11 ± 2" in text or "11.0 ± 2.5" in text  # mean +/- CI of 10, 11, 12
