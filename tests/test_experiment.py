"""growsim.experiment.run / sweep / Fitness end to end on tiny budgets (Honda + light)."""

from __future__ import annotations

import json
import pickle
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import growsim
from growsim.errors import UserInputError
from growsim.experiment import Fitness, build_fitness, load_config, load_run, run, sweep
from growsim.plant import Plant
from growsim.results import RunDir

ROOT = Path(__file__).resolve().parents[1]
QUICK = ROOT / "experiments" / "quickstart.toml"
TINY = [
    "ga.population=8",
    "ga.generations=3",
    "output.screenshots=[]",
    "output.mesh=['vtp']",
    "output.plot=false",
    "model.params.generations=6",
]


def history_eq(a: pd.DataFrame, b: pd.DataFrame) -> None:
    pd.testing.assert_frame_equal(
        a.drop(columns=["seconds"]).reset_index(drop=True),
        b.drop(columns=["seconds"]).reset_index(drop=True),
    )


@pytest.fixture(scope="module")
def tiny_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("run") / "r"
    return run(QUICK, out, overrides=TINY, progress=False)


def test_run_writes_a_complete_results_directory(tiny_run):
    r = tiny_run
    names = {p.name for p in r.out.iterdir()}
    assert {
        "config.toml",
        "history.parquet",
        "best.json",
        "summary.json",
        "checkpoint.npz",
        "best_plant.npz",
        "best.vtp",
    } <= names
    assert not [n for n in names if n.endswith(".tmp") or ".tmp." in n]
    cfg = load_config(r.out / "config.toml")
    assert cfg.ga.population == 8 and cfg.model.params["generations"] == 6
    hist = pd.read_parquet(r.out / "history.parquet")
    assert list(hist["generation"]) == [0, 1, 2]
    assert {"evaluations", "best", "mean", "best_so_far", "seconds"} <= set(hist.columns)
    best = json.loads((r.out / "best.json").read_text())
    summary = json.loads((r.out / "summary.json").read_text())
    assert best["fitness"] == summary["best_fitness"] == r.best_fitness
    assert best["fitness"] == pytest.approx(hist["best_so_far"].max())
    assert summary["evaluations"] == hist["evaluations"].iloc[-1] >= 8 * 3 - 3
    assert summary["generations"] == 3
    assert summary["measures"]["n_segments"] == r.best_plant.n_segments
    # the objective's terms of the best, in best.json and summary.json
    terms = best["terms"]["light"]
    assert summary["terms"] == best["terms"] and set(terms) == {"score", "leaf_area", "wood_volume"}
    assert terms["score"] == pytest.approx(terms["leaf_area"] - 1.0 * terms["wood_volume"])
    assert best["phenotype"] == summary["phenotype"] == "plant"
    # the glue is right: re-scoring the best parameters gives the recorded fitness
    f = build_fitness(cfg)
    x = np.array([[best["params"][n] for n in f.evolved]])
    assert f(x)[0] == pytest.approx(best["fitness"], rel=1e-12)
    assert Plant.load(r.out / "best_plant.npz").n_segments == r.best_plant.n_segments
    again = load_run(r.out)
    assert again.best_fitness == r.best_fitness and again.best_plant.n_segments > 0


def test_same_seed_same_results_whatever_the_workers(tiny_run, tmp_path):
    other = run(QUICK, tmp_path / "w2", overrides=TINY, workers=2, progress=False)
    history_eq(tiny_run.history, other.history)
    a = json.loads((tiny_run.out / "best.json").read_text())
    b = json.loads((other.out / "best.json").read_text())
    assert a == b


def test_seed_changes_the_run(tiny_run, tmp_path):
    other = run(QUICK, tmp_path / "s", overrides=TINY, seed=7, progress=False)
    assert other.summary["seed"] == 7
    assert not np.array_equal(other.history["best"], tiny_run.history["best"])


def test_out_in_use_or_taken_is_refused(tiny_run, tmp_path):
    with pytest.raises(UserInputError, match="already holds a run"):
        run(QUICK, tiny_run.out, overrides=TINY, progress=False)
    rd = RunDir(tmp_path / "busy")
    with rd.lock(), pytest.raises(UserInputError, match="in use by another growsim run"):
        run(QUICK, tmp_path / "busy", overrides=TINY, progress=False)
    assert not (tmp_path / "busy" / "config.toml").exists()


def test_bad_config_writes_nothing(tmp_path):
    with pytest.raises(UserInputError):
        run(QUICK, tmp_path / "bad", overrides=["ga.population=0"], progress=False)
    assert not (tmp_path / "bad").exists()


def test_resume_a_stopped_run_gives_the_uninterrupted_result(tiny_run, tmp_path):
    # stop after the first generation through the callback, then resume
    out = tmp_path / "stopped"
    first = run(QUICK, out, overrides=TINY, progress=False, callback=lambda ga, row: True)
    assert first.summary["generations"] < 3
    (out / "summary.json").unlink()  # as if killed before the end
    resumed = run(None, out, resume=True, progress=False)
    history_eq(resumed.history, tiny_run.history)
    assert resumed.best_params == tiny_run.best_params
    with pytest.raises(UserInputError, match="nothing to resume"):
        run(None, tmp_path / "none", resume=True)


def test_callback_sees_every_generation(tmp_path):
    rows = []
    run(
        QUICK,
        tmp_path / "cb",
        overrides=TINY,
        progress=False,
        callback=lambda ga, row: rows.append(dict(row)),
    )
    assert [r["generation"] for r in rows] == [0, 1, 2]


def test_lazy_exports():
    assert growsim.run is run and growsim.sweep is sweep


def test_sweep_grid_and_reuse(tmp_path):
    df = sweep(
        QUICK,
        ["env.light=1.0,0.5"],
        repeats=2,
        out=tmp_path / "sw",
        overrides=[*TINY, "ga.generations=2"],
        progress=False,
    )
    assert len(df) == 4
    assert sorted(df["environment.light"].unique()) == [0.5, 1.0]
    assert (Path(df["out"][0]).parent.name, Path(df["out"][3]).parent.name) == (
        "light=1.0",
        "light=0.5",
    )
    assert sorted(df["seed"].unique()) == [1, 2]
    # light intensity scales the leaf term: fitness differs between variants
    by = df.groupby("environment.light")["best_fitness"].mean()
    assert by[1.0] > by[0.5]
    assert (tmp_path / "sw" / "sweep.csv").is_file()
    mtime = (Path(df["out"][0]) / "summary.json").stat().st_mtime_ns
    again = sweep(
        QUICK,
        ["env.light=1.0,0.5"],
        repeats=2,
        out=tmp_path / "sw",
        overrides=[*TINY, "ga.generations=2"],
        progress=False,
    )
    pd.testing.assert_frame_equal(df, again)
    assert (Path(df["out"][0]) / "summary.json").stat().st_mtime_ns == mtime
    with pytest.raises(UserInputError):
        sweep(QUICK, ["env.light=1.0,-2"], repeats=1, out=tmp_path / "sw2", overrides=TINY)
    assert not (tmp_path / "sw2").exists()


# ---- the Fitness glue, with fake objectives -----------------------------------------


class CountingHeight:
    name = "height"
    maximize = True

    def __init__(self):
        self.calls = 0

    def __call__(self, plant):
        self.calls += 1
        return plant.height()


class BatchF:
    """A batch objective on the raw parameter matrix: minimise f."""

    name = "batchf"
    maximize = False

    def __call__(self, plant):
        raise AssertionError("the batch path must be used")

    def batch(self, model, params, names, seeds):
        assert params.shape[1] == len(names) and len(seeds) == len(params)
        return params[:, list(names).index("f")] * 10.0


def _fitness(objectives, weights, noise="fixed"):
    import dataclasses

    from growsim.experiment import load_plan

    plan = dataclasses.replace(load_plan(QUICK), noise=noise, seed=3)
    return Fitness(plan, objectives, weights)


def test_fitness_weights_signs_and_batch_path():
    h = CountingHeight()
    fit = _fitness([h, BatchF()], [2.0, 0.5])
    x = np.array([[0.8, 20.0, 20.0, 0.3, 5.0, 2.0], [0.6, 10.0, 40.0, 0.1, 8.0, 1.0]])
    got = fit(x)
    heights = [
        fit.develop(row, s).height()
        for row, s in zip(fit.full_params(x), fit.model_seeds(fit.full_params(x), None))
    ]
    assert np.allclose(got, 2.0 * np.array(heights) - 0.5 * 10.0 * x[:, 0])
    assert h.calls == 2
    pickle.loads(pickle.dumps(fit))


def test_noise_modes():
    h = CountingHeight()
    x = np.array([[0.8, 20.0, 20.0, 0.3, 5.0, 2.0]] * 2)
    fixed = _fitness([h], [1.0])
    a = fixed(x, seeds=np.array([1, 2], dtype=np.uint64))
    assert a[0] == a[1]  # fixed: the model's own seed parameter, whatever the GA's seeds
    noisy = _fitness([h], [1.0], noise="per-evaluation")
    b = noisy(x, seeds=np.array([1 << 40, 2 << 40], dtype=np.uint64))
    assert b[0] != b[1]
    assert np.array_equal(b, noisy(x, seeds=np.array([1 << 40, 2 << 40], dtype=np.uint64)))
    big = np.array([2**64 - 1, 2**63 + 12345], dtype=np.uint64)  # the GA's full range
    assert np.all(noisy.model_seeds(noisy.full_params(x), big) < 2**31)
    c = noisy(x, seeds=big)
    assert np.all(np.isfinite(c)) and c[0] != c[1]


def test_dask_local_cluster_gives_the_same_results(tiny_run, tmp_path):
    pytest.importorskip("dask.distributed")
    other = run(
        QUICK, tmp_path / "dask", overrides=TINY, scheduler="local", workers=2, progress=False
    )
    history_eq(tiny_run.history, other.history)
    assert other.best_params == tiny_run.best_params
    assert other.summary["scheduler"] == "local"


def test_light_objective_formula_and_environment():
    from growsim.env import Environment
    from growsim.errors import ConfigError
    from growsim.models.honda import PRESETS, develop
    from growsim.objectives.light import LightObjective

    plant = develop(PRESETS["zelkova"])
    obj = LightObjective(wood_cost=0.5, resolution=64)
    area = plant.leaf_area((0.0, -1.0, 0.0), resolution=64)
    assert obj(plant) == pytest.approx(area - 0.5 * plant.wood_volume())
    env = Environment.model_validate({"light": {"intensity": 0.5, "direction": [1.0, -1.0, 0.0]}})
    bound = LightObjective(wood_cost=0.5, resolution=64, env=env)
    side = plant.leaf_area((1.0, -1.0, 0.0), resolution=64)
    assert bound(plant) == pytest.approx(0.5 * side - 0.5 * plant.wood_volume())
    mine = LightObjective(direction=[0, -1, 0], intensity=2.0, resolution=64, env=env)
    assert mine(plant) == pytest.approx(2.0 * area - 0.02 * plant.wood_volume())
    for bad in (
        {"wood_cost": -1},
        {"resolution": 8},
        {"resolution": 1.5},
        {"direction": [0, 0, 0]},
        {"intensity": "x"},
    ):
        with pytest.raises(ConfigError):
            LightObjective(**bad)


def test_live_history_is_written_during_a_run(tmp_path):
    from growsim.experiment.runner import Progress

    class FakeGA:
        history = pd.DataFrame({"generation": [0, 1], "best": [1.0, 2.0]})

    rd = RunDir(tmp_path)
    seen = []
    p = Progress(None, False, lambda ga, row: seen.append(row) or True, rd=rd, every=0.0)
    assert p(FakeGA(), {"generation": 1}) is True  # the user's callback can stop the run
    pd.testing.assert_frame_equal(pd.read_parquet(rd.history_path), FakeGA.history)
    slow = Progress(None, False, None, rd=RunDir(tmp_path / "x"), every=3600.0)
    slow(FakeGA(), {"generation": 0})
    assert not (tmp_path / "x" / "history.parquet").exists()


def test_per_evaluation_noise_is_reproducible_across_workers(tmp_path):
    ov = [*TINY, "model.noise='per-evaluation'"]
    a = run(QUICK, tmp_path / "a", overrides=ov, progress=False)
    b = run(QUICK, tmp_path / "b", overrides=ov, workers=2, progress=False)
    history_eq(a.history, b.history)
    assert a.summary["warnings"] == []
    if "failures" in a.history:  # no evaluation failed (e.g. on a seed out of range)
        assert a.history["failures"].sum() == 0


# ---- one compiled plan: each objective built once per run ---------------------------


def test_one_objective_construction_per_run(tmp_path, monkeypatch):
    from growsim.objectives.light import LightObjective

    made = []
    real_setup = LightObjective.setup

    def counting_setup(self):
        made.append(self)
        real_setup(self)

    monkeypatch.setattr(LightObjective, "setup", counting_setup)
    run(QUICK, tmp_path / "a", overrides=TINY, seed=4, progress=False)
    assert len(made) == 1
    made.clear()
    # resuming compiles the saved config once
    run(None, tmp_path / "a", resume=True, progress=False)
    assert len(made) == 1
    made.clear()
    # a sweep builds each variant's objectives once, whatever the repeats
    sweep(
        QUICK, ["env.light=1.0,0.5"], repeats=2, out=tmp_path / "sw", overrides=TINY, progress=False
    )
    assert len(made) == 2
    made.clear()
    # reading a results directory back grows the best plant with the model alone
    from growsim.experiment import best_phenotype

    (tmp_path / "a" / "best_plant.npz").unlink()
    assert best_phenotype(tmp_path / "a").n_segments > 0
    assert made == []


def test_objective_must_accept_the_phenotype(monkeypatch):
    from growsim.errors import ConfigError
    from growsim.models.honda import MODEL

    monkeypatch.setattr(type(MODEL), "phenotype", "trajectory")
    with pytest.raises(ConfigError, match=r"objective\[0\].*'light'.*plant.*'trajectory'"):
        load_config(QUICK)
