"""growsim.experiment.run / sweep / Fitness end to end on tiny budgets (Honda + light)."""

from __future__ import annotations

import json
import pickle
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from conftest import ROOT
from conftest import growsim as _growsim

import growsim
from growsim.errors import UserInputError
from growsim.experiment import Fitness, build_fitness, load_config, load_run, run, sweep
from growsim.experiment.results import RunDir
from growsim.objectives.base import Objective
from growsim.phenotypes.plant import Plant

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
    assert summary["terms"] == best["terms"]
    assert set(terms) == {"score", "light", "leaf_area", "wood_volume"}
    assert terms["score"] == pytest.approx(terms["light"] - 1.0 * terms["wood_volume"])
    assert best["phenotype"] == summary["phenotype"] == "plant"
    # the glue is right: re-scoring the best parameters gives the recorded fitness
    f = build_fitness(cfg)
    x = np.array([[best["params"][n] for n in f.evolved]])
    assert f(x)[0] == pytest.approx(best["fitness"], rel=1e-12)
    assert Plant.load(r.out / "best_plant.npz").n_segments == r.best_plant.n_segments
    again = load_run(r.out)
    assert again.best_fitness == r.best_fitness and again.best_plant.n_segments > 0


def test_one_record_type_for_a_run_and_a_run_read_back(tiny_run, tmp_path):
    from growsim.experiment import RunRecord, RunResult, read_run

    assert RunResult is RunRecord
    again, read = load_run(tiny_run.out), read_run(tiny_run.out)
    for rec in (tiny_run, again, read):
        assert type(rec) is RunRecord
        assert rec.out == rec.path == tiny_run.out
    for rec in (again, read):
        assert rec.best == tiny_run.best and rec.summary == tiny_run.summary
        assert rec.config == tiny_run.config and rec.best_params == tiny_run.best_params
        assert rec.stop_reason == tiny_run.stop_reason == "generations"
        history_eq(rec.history, tiny_run.history)
    assert tiny_run.best == json.loads((tiny_run.out / "best.json").read_text())
    assert tiny_run.summary == json.loads((tiny_run.out / "summary.json").read_text())
    # the best phenotype grown again from best.json (no saved file) is the saved one
    import shutil

    copy = tmp_path / "copy"
    shutil.copytree(tiny_run.out, copy)
    (copy / "best_plant.npz").unlink()
    grown = read_run(copy).best_phenotype
    saved = Plant.load(tiny_run.out / "best_plant.npz")
    grown.save(tmp_path / "grown.npz")
    with np.load(tmp_path / "grown.npz") as a, np.load(tiny_run.out / "best_plant.npz") as b:
        assert a.files == b.files and all(np.array_equal(a[k], b[k]) for k in a.files)
    assert grown.n_segments == saved.n_segments


def test_load_plan_is_the_one_way_into_a_plan():
    from growsim.experiment import Config, ExperimentPlan, load_plan
    from growsim.experiment.load import read_config

    plan = load_plan(QUICK, TINY)
    data = plan.config.to_dict()
    for source in (QUICK, str(QUICK), data, plan.config, plan):
        other = load_plan(source, [] if source is plan else TINY)
        assert isinstance(other, ExperimentPlan)
        assert other.config.to_dict() == data
    assert load_plan(plan) is plan
    assert load_plan(plan, ["ga.population=6"]).config.ga.population == 6
    assert isinstance(read_config(plan), Config)
    assert build_fitness(plan).evolved == plan.fitness().evolved


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


class CountingHeight(Objective):
    name = "height"
    maximize = True

    def setup(self):
        self.calls = 0

    def __call__(self, plant):
        self.calls += 1
        return plant.height()


class BatchF(Objective):
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


def test_dask_local_cluster_gives_the_same_results(tiny_run, tmp_path, dask_cluster):
    # the session's local cluster, reached by its address
    address = dask_cluster.scheduler_address
    other = run(QUICK, tmp_path / "dask", overrides=TINY, scheduler=address, progress=False)
    history_eq(tiny_run.history, other.history)
    assert other.best_params == tiny_run.best_params
    assert other.summary["scheduler"] == address


# the session's cluster holds Dask's port 8787: this one moves (and Dask's retry drops a socket)
@pytest.mark.filterwarnings("ignore:Port 8787 is already in use", "ignore:unclosed <socket")
def test_scheduler_local_starts_its_own_cluster(tiny_run, tmp_path):
    # scheduler="local": growsim starts (and stops) a LocalCluster of `workers` processes
    other = run(QUICK, tmp_path / "local", overrides=TINY, scheduler="local", workers=1,
                progress=False)  # fmt: skip
    history_eq(tiny_run.history, other.history)
    assert other.best_params == tiny_run.best_params
    assert other.summary["scheduler"] == "local"


def test_light_objective_formula_and_environment():
    from growsim.env import Environment
    from growsim.errors import ConfigError
    from growsim.models.honda import PRESETS, develop
    from growsim.objectives.light import LightObjective
    from growsim.phenotypes.plant import leaf_light

    plant = develop(PRESETS["zelkova"])
    # the projection (the measure before the shadow map): intensity x leaf shadow - wood
    proj = {"shading": "projection", "resolution": 64}
    obj = LightObjective(wood_cost=0.5, **proj)
    area = plant.leaf_area((0.0, -1.0, 0.0), resolution=64)
    assert obj(plant) == pytest.approx(area - 0.5 * plant.wood_volume())
    env = Environment.model_validate({"light": {"intensity": 0.5, "direction": [1.0, -1.0, 0.0]}})
    bound = LightObjective(wood_cost=0.5, env=env, **proj)
    side = plant.leaf_area((1.0, -1.0, 0.0), resolution=64)
    assert bound(plant) == pytest.approx(0.5 * side - 0.5 * plant.wood_volume())
    mine = LightObjective(direction=[0, -1, 0], intensity=2.0, env=env, **proj)
    assert mine(plant) == pytest.approx(2.0 * area - 0.02 * plant.wood_volume())
    # the shadow map (default): the leaves' light from the environment's light - wood
    shadow = LightObjective(wood_cost=0.5, env=env)
    assert shadow(plant) == pytest.approx(
        leaf_light(plant, env.light).light - 0.5 * plant.wood_volume()
    )
    for bad in (
        {"half_saturation": 0},
        {"shading": "projection", "response": "saturating"},
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


# ---- the user report: sweeps reuse only their own runs, nothing written on refusal,
# ---- Ctrl-C during the artefacts, summary.json, fitness.png, .lock -------------------


def _tree_state(root: Path) -> dict[str, int]:
    """Every file under ``root`` with its modification time (to see nothing was written)."""
    return {str(p.relative_to(root)): p.stat().st_mtime_ns for p in sorted(root.rglob("*"))}


def test_sweep_refuses_run_dirs_made_with_another_config(tmp_path):
    sw = tmp_path / "sw"
    ov = [*TINY, "ga.generations=2"]
    df = sweep(QUICK, ["env.light=1.0,0.5"], repeats=1, out=sw, overrides=ov, progress=False)
    # a finished run with other settings is not returned as this sweep's result
    before = _tree_state(sw)
    with pytest.raises(UserInputError) as exc:
        sweep(
            QUICK,
            ["env.light=1.0,0.5"],
            repeats=1,
            out=sw,
            overrides=[*ov, "ga.population=6"],
            progress=False,
        )
    msg = str(exc.value)
    assert "\n" not in msg
    assert str(Path(df["out"][0])) in msg and "ga.population" in msg and "--out" in msg
    assert _tree_state(sw) == before  # nothing written
    # an interrupted run with other settings is not resumed with its old config
    (Path(df["out"][1]) / "summary.json").unlink()
    before = _tree_state(sw)
    with pytest.raises(UserInputError, match=r"objective\[0\]\.wood_cost"):
        sweep(
            QUICK,
            ["env.light=0.5"],
            repeats=1,
            out=sw,
            overrides=[*ov, "objective[0].wood_cost=0.5"],
            progress=False,
        )
    assert _tree_state(sw) == before
    # the same settings resume the interrupted run and reuse the finished one
    again = sweep(QUICK, ["env.light=1.0,0.5"], repeats=1, out=sw, overrides=ov, progress=False)
    pd.testing.assert_frame_equal(
        df.drop(columns=["wall_seconds"]), again.drop(columns=["wall_seconds"])
    )


def test_a_config_the_run_would_refuse_writes_nothing(tmp_path):
    from growsim.errors import ConfigError

    out = tmp_path / "g0"
    p = _growsim("run", QUICK, "--out", out, "--quiet", "--set", "ga.generations=0")
    assert p.returncode == 2, p.stderr
    assert p.stderr.startswith("growsim: error: ga.generations") and "Traceback" not in p.stderr
    assert not out.exists()
    # a polish taking the whole evaluation budget: refused by the schema too
    for ov in (["ga.generations=0"], ["ga.evaluations=50", "ga.polish={evaluations = 50}"]):
        with pytest.raises(ConfigError):
            run(QUICK, out, overrides=[*TINY, *ov], progress=False)
        assert not out.exists()


def _vtk_rendering_loaded(pid: int) -> bool:
    """True once process ``pid`` has mapped the Python module of VTK's rendering core
    (Linux's ``/proc``): the import of VTK's rendering modules is under way."""
    try:
        with open(f"/proc/{pid}/maps") as fh:
            return "vtkRenderingCore.cpython" in fh.read()
    except OSError:
        return False


# (best.glb, written between best.json and the VTK import, is covered by its neighbours)
@pytest.mark.parametrize("start", ["best.json", "vtk-import", "best_front.png"])
def test_ctrl_c_during_the_artefacts_ends_with_the_hint_and_resumes(tmp_path, start):
    # Ctrl-C, again and again, from the moment the run reaches ``start`` (its own
    # progress, never a fixed delay): best.json is written just before the artefacts
    # (best_plant.npz, meshes, VTK renders, fitness.png), best.glb just before VTK's
    # rendering modules are imported; "vtk-import": once the process has mapped VTK's
    # OpenGL module, i.e. during that import (a SIGINT there crashed the interpreter:
    # exit -11); best_front.png just before the side view's render (the side and iso
    # renders and fitness.png still to come)
    import os
    import signal
    import subprocess
    import sys
    import threading
    import time

    if start == "vtk-import" and not os.path.exists("/proc/self/maps"):
        pytest.skip("needs Linux's /proc to see the import")  # pragma: no cover

    out = tmp_path / "int"
    args = [QUICK, "--out", out, "--quiet"]
    for ov in (
        "ga.population=8",
        "ga.generations=2",
        "model.params.generations=6",
        "output.screenshots=['front', 'side', 'iso']",
        "output.size=[600, 600]",
        "output.mesh=['vtp', 'glb']",
    ):
        args += ["--set", ov]
    hint = f"growsim: to continue: growsim run --resume {out}"
    proc = subprocess.Popen(
        [sys.executable, "-m", "growsim", "run", *map(str, args)],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "MPLBACKEND": "Agg"},
        # Ctrl-C as a terminal delivers it, even when these tests run where it is ignored
        # (a background job): an ignored SIGINT is inherited, a default one is not
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    err: list[str] = []
    reader = threading.Thread(target=lambda: err.extend(proc.stderr), daemon=True)
    reader.start()
    try:
        t0 = time.monotonic()
        reached = (
            (lambda: _vtk_rendering_loaded(proc.pid))
            if start == "vtk-import"
            else (lambda: out.is_dir() and any(out.glob(start)))
        )
        while not reached():
            assert proc.poll() is None, "".join(err)
            assert time.monotonic() - t0 < 200, f"{start} did not appear"
            time.sleep(0.002)
        sent = 0
        # Ctrl-C over the artefact phase, again and again (each one during a file is held
        # until the file is written), until the process has ended: the Ctrl-Cs after the
        # first land in its clean-up (an interrupted VTK import crashed there: exit -11)
        while proc.poll() is None:
            proc.send_signal(signal.SIGINT)
            sent += 1
            time.sleep(0.05)
        rc = proc.wait(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    reader.join(timeout=10)
    text = "".join(err)
    assert sent >= 1
    assert rc == 130, (rc, text)
    assert hint in text and "Traceback" not in text, text
    assert not (out / "summary.json").exists() and not (out / ".lock").exists()
    assert not (out / "fitness.png").exists()  # stopped among the artefacts (the last one)
    assert not list(out.glob(".*.tmp*"))  # the file being written was finished or removed
    p = _growsim("run", "--resume", out, "--quiet")
    assert p.returncode == 0, p.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["warnings"] == []
    names = {q.name for q in out.iterdir()}
    assert {"best_front.png", "best_side.png", "best_iso.png", "best.vtp", "best.glb"} <= names
    assert "fitness.png" in names and ".lock" not in names


def test_summary_terms_are_the_source_of_the_best_fitness(tiny_run):
    # the objective's terms add up to the best fitness; the plant's shadow areas from
    # above use their own raster (256), and docs/quickstart.md says which resolution each
    # uses. The quickstart's objective (linear, the environment's light) gives
    # light_captured as its light term.
    s = tiny_run.summary
    cfg = load_config(tiny_run.out / "config.toml")
    light = s["terms"]["light"]
    score = light["light"] - cfg.objective[0].wood_cost * light["wood_volume"]
    assert light["score"] == pytest.approx(score, rel=1e-12)
    assert s["measures"]["light_captured"] == light["light"]
    assert s["best_fitness"] == pytest.approx(cfg.objective[0].weight * light["score"], rel=1e-12)
    doc = (ROOT / "docs" / "quickstart.md").read_text()
    section = doc[doc.index("## Look at the results") :]
    assert "`terms`" in section and "256" in section and "resolution" in section


def test_light_measures_are_absent_for_a_leafless_plant():
    from growsim.experiment import load_plan
    from growsim.experiment.runner import _measures

    plan = load_plan(QUICK)
    stems = Plant.from_points([[0, 0, 0], [0, 1, 0], [1, 2, 0]], [-1, 0], [-1, 0, 1])
    assert stems.n_leaves == 0
    m = _measures(stems, plan)
    assert m["n_leaves"] == 0 and m["height"] > 0
    assert "light_captured" not in m and "leaf_area_top" not in m
    leafy = growsim.models.get_model("honda").develop({"generations": 4})
    assert {"light_captured", "leaf_area_top"} <= set(_measures(leafy, plan))


def test_repeats_is_documented_as_sweep_only():
    from growsim.experiment.schema import ExperimentConfig

    desc = ExperimentConfig.model_fields["repeats"].description
    assert "growsim sweep only" in desc and "growsim run" in desc
    assert desc in (ROOT / "docs" / "configs.md").read_text()


def test_fitness_plot_shows_best_mean_and_best_so_far(tmp_path, monkeypatch):
    import matplotlib.pyplot as plt

    from growsim.experiment.results import plot_fitness

    figs = []
    real_close = plt.close
    monkeypatch.setattr(plt, "close", lambda fig=None: (figs.append(fig), real_close(fig)))
    h = pd.DataFrame(
        {
            "generation": [0, 1, 2, 3],
            "best": [1.0, 3.0, 3.0, 2.0],
            "mean": [0.5, 1.0, 2.0, 1.5],
            "worst": [-1e9, 0.0, 0.0, 0.0],
            "best_so_far": [1.0, 3.0, 3.0, 3.0],
        }
    )
    plot_fitness(h, tmp_path / "f.png")
    (ax,) = figs[0].axes
    lines = {ln.get_label(): ln for ln in ax.get_lines()}
    assert set(lines) == {"best", "mean", "best so far"}
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["best", "mean", "best so far"]
    best, so_far = lines["best"], lines["best so far"]
    # best so far lies on best wherever best improves: it must stay visible on top of it
    assert so_far.get_zorder() > best.get_zorder()
    assert so_far.get_linestyle() != best.get_linestyle()
    assert list(so_far.get_ydata()) == [1.0, 3.0, 3.0, 3.0]


def test_the_lock_file_is_removed_when_the_run_ends(tiny_run, tmp_path):
    assert not (tiny_run.out / ".lock").exists()
    rd = RunDir(tmp_path / "l")
    with rd.lock():
        assert rd.lock_path.is_file()
        with pytest.raises(UserInputError, match="in use"), RunDir(tmp_path / "l").lock():
            pass
        assert rd.lock_path.is_file()  # a refused second holder leaves the lock alone
    assert not rd.lock_path.exists()
    with rd.lock():  # and the directory can be locked again
        pass
    assert sorted(p.name for p in (tmp_path / "l").iterdir()) == []


def test_evaluations_run_on_one_blas_thread(monkeypatch):
    """A multi-threaded BLAS adds a long dot product's parts in another order: every
    evaluation runs on one BLAS thread, so serial, pool and Dask runs (Dask's workers
    have one) give the same sums."""
    from threadpoolctl import threadpool_info

    from growsim.experiment import load_plan
    from growsim.experiment.fitness import Fitness

    seen = []
    real = Fitness._evaluate

    def spy(self, x, seeds):
        seen.extend(i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas")
        return real(self, x, seeds)

    monkeypatch.setattr(Fitness, "_evaluate", spy)
    f = load_plan(QUICK, ["model.params.generations=4"]).fitness()
    f(np.array([[0.8, 80.0, 5.0, 0.2, 8.0, 4.0]]))
    assert seen and set(seen) == {1}
