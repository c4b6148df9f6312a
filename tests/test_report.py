"""growsim.report.compare on synthetic run directories with known numbers."""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pandas as pd
import pytest
from scipy import stats

from growsim.errors import UserInputError
from growsim.experiment import load_config
from growsim.report import compare, group_runs
from growsim.results import RunDir, find_runs

BASE = {
    "model": {"kind": "honda", "evolve": {"f": True}},
    "objective": [{"kind": "light"}],
    "ga": {"population": 4, "generations": 3},
}


def fake_run(path, seed, best, light=1.0, gens=4):
    """A finished run directory whose numbers we know."""
    cfg = load_config(BASE, [f"experiment.seed={seed}", f"environment.light={light}"])
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
            "measures": {
                "height": 10.0 + best,
                "crown_width": 3.0,
                "segments": 7.0,
                "light_captured": 2.0 * best,
            },
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
    assert set(t.index) == {"light=1.0", "light=0.5"}
    row = t.loc["light=1.0"]
    assert row["runs"] == 3 and row["best"] == 12.0
    assert row["mean"] == pytest.approx(np.mean(a))
    half = stats.t.ppf(0.975, 2) * np.std(a, ddof=1) / math.sqrt(3)
    assert row["ci95"] == pytest.approx(half)
    assert row["height"] == pytest.approx(22.0) and row["light_captured"] == pytest.approx(24.0)
    s = c.stats.iloc[0]
    x, y = (a, b) if s["group_a"] == "light=1.0" else (b, a)
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
    assert "Welch" in text and "light=0.5" in text
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
