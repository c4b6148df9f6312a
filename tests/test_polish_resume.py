"""A run stopped or killed during the polish resumes to the uninterrupted result, on any
executor: the polish checkpoints its progress (``GAState.polish_*``) and a resume replays
it (:func:`growsim.ga.polish.polish_best`) instead of starting the polish again."""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time

import numpy as np
import pandas as pd
import pytest
from conftest import ROOT

from growsim.errors import GrowsimError
from growsim.ga import GA, HISTORY_COLUMNS, Genome, Real
from growsim.ga.problems import noisy_sphere, sphere

COLS = [c for c in HISTORY_COLUMNS if c != "seconds"]
G = Genome([Real("x", -3, 3, size=6)])
GENERATIONS = 4


class Stop(Exception):
    """Raised by a callback to stop a run in the middle of the polish."""


class Counted:
    """``fitness`` counting the rows it evaluates (serial runs only)."""

    def __init__(self, fitness):
        self.fitness, self.rows = fitness, 0

    def __call__(self, x):
        self.rows += len(x)
        return self.fitness(x)


def _same(a, b):
    pd.testing.assert_frame_equal(a.history[COLS], b.history[COLS])
    assert a.best.fitness == b.best.fitness
    assert np.array_equal(a.best.params, b.best.params)
    assert np.array_equal(a.best.raw, b.best.raw)
    assert np.array_equal(a.fitness, b.fitness)
    assert (a.stop_reason, a.evaluations) == (b.stop_reason, b.evaluations)


def _polish(method):
    return {"evaluations": 96, "batch": 8, "method": method, "sigma": 0.2}


def _ga(fitness=sphere, **kw):
    ga = GA(G, fitness, population=10, maximize=False, seed=4, **kw)
    ga.checkpoint_share = 0.0  # a checkpoint after every polish step
    return ga


def _stop_at_polish_step(k):
    """A callback raising :class:`Stop` at the ``k``-th polish row (1-based), before that
    step is checkpointed: the checkpoint holds ``k - 1`` polish steps."""

    def callback(ga, row):
        if row.get("phase") == "polish":
            done = sum(r["phase"] == "polish" for r in ga.state.rows)
            if done == k:
                raise Stop

    return callback


def _checkpoint_meta(path):
    try:
        with np.load(path, allow_pickle=False) as z:
            return json.loads(str(z["meta"]))
    except (OSError, ValueError, KeyError):
        return None


def _polish_steps_in(path) -> int:
    meta = _checkpoint_meta(path)
    return -1 if meta is None else sum(r["phase"] == "polish" for r in meta["rows"])


@pytest.mark.parametrize("method", ["es", "cmaes"])
def test_a_stop_at_every_polish_step_resumes_to_the_uninterrupted_run(tmp_path, method):
    whole = _ga().run(generations=GENERATIONS, polish=_polish(method))
    steps = int((whole.history["phase"] == "polish").sum())
    assert steps == 12
    ck = tmp_path / "ck.npz"
    for k in range(1, steps + 1):
        ck.unlink(missing_ok=True)
        with pytest.raises(Stop):
            _ga().run(
                generations=GENERATIONS,
                polish=_polish(method),
                checkpoint=ck,
                callback=_stop_at_polish_step(k),
            )
        assert _polish_steps_in(ck) == k - 1  # the polish's own checkpoint, step by step
        meta = _checkpoint_meta(ck)
        counted = Counted(sphere)
        resumed = _ga(counted).run(
            generations=GENERATIONS, polish=_polish(method), checkpoint=ck, resume=True
        )
        _same(resumed, whole)
        # the steps on disk are replayed, not evaluated again
        assert counted.rows == whole.evaluations - meta["evaluations"]
        assert _checkpoint_meta(ck)["extra"] == {"stop_reason": "generations", "polished": True}


def test_a_polish_stopped_by_its_target_resumes_to_the_same_end(tmp_path):
    """The target is reached during the polish: killed after it is checkpointed, the
    resumed run ends there too (no further step)."""
    run = dict(generations=GENERATIONS, polish=_polish("es"), target=1.0)
    whole = _ga().run(**run)
    assert whole.stop_reason == "generations" and whole.best.fitness <= 1.0
    steps = int((whole.history["phase"] == "polish").sum())
    assert 1 < steps < 12
    ck = tmp_path / "ck.npz"
    # a checkpoint after the last step, not marked polished: as if killed right there
    ga = _ga()
    ga.save_checkpoint = _no_final_save(ga.save_checkpoint)
    ga.run(checkpoint=ck, **run)
    assert _polish_steps_in(ck) == steps
    assert _checkpoint_meta(ck)["extra"]["polished"] is False
    counted = Counted(sphere)
    resumed = _ga(counted).run(checkpoint=ck, resume=True, **run)
    _same(resumed, whole)
    assert counted.rows == 0


def test_a_ga_stopped_by_its_callback_resumes_in_the_polish(tmp_path):
    """The GA phase ended for a reason the limits cannot tell again (the callback): a
    resume in the polish goes on with the polish, not with more generations."""

    def enough(ga, row):
        return row.get("phase") == "ga" and row["generation"] == 2

    def enough_then_stop(ga, row):
        enough(ga, row)
        _stop_at_polish_step(3)(ga, row)
        return enough(ga, row)

    run = dict(generations=30, polish=_polish("es"))
    whole = _ga().run(callback=enough, **run)
    assert whole.stop_reason == "callback" and whole.generations == 3
    ck = tmp_path / "ck.npz"
    with pytest.raises(Stop):
        _ga().run(checkpoint=ck, callback=enough_then_stop, **run)
    resumed = _ga().run(checkpoint=ck, resume=True, **run)
    _same(resumed, whole)


def test_a_checkpoint_written_before_the_polish_log_existed_still_resumes(tmp_path):
    """A checkpoint of the same layout version written before the polish's fields were
    added (none of ``polish_*``) resumes as one not yet in the polish."""
    ck = tmp_path / "ck.npz"
    run = dict(generations=GENERATIONS, polish=_polish("es"))
    _ga().run(checkpoint=ck, generations=2)
    with np.load(ck, allow_pickle=False) as z:
        data = {k: z[k] for k in z.files}
    meta = json.loads(str(data["meta"]))
    assert meta.pop("polish_score0") is None and "polish_scores" not in data
    data["meta"] = np.array(json.dumps(meta))
    np.savez(ck, **data)
    _same(_ga().run(checkpoint=ck, resume=True, **run), _ga().run(**run))


def _no_final_save(save):
    def inner(path, stop_reason=None, polished=False):
        if not polished:
            save(path, stop_reason=stop_reason)

    return inner


def test_a_polish_log_of_another_set_up_is_refused(tmp_path):
    ck = tmp_path / "ck.npz"
    with pytest.raises(Stop):
        _ga().run(
            generations=GENERATIONS,
            polish=_polish("es"),
            checkpoint=ck,
            callback=_stop_at_polish_step(4),
        )
    # batch 5 instead of 8: the logged scores do not fit the steps
    with pytest.raises(GrowsimError, match="polish's log"):
        _ga().run(
            generations=GENERATIONS,
            polish={**_polish("es"), "batch": 5},
            checkpoint=ck,
            resume=True,
        )


# -- another executor --------------------------------------------------------------------
def _noisy(**kw):
    ga = GA(G, noisy_sphere, population=16, maximize=False, seed=9, **kw)
    ga.checkpoint_share = 0.0
    return ga


NOISY_RUN = dict(generations=GENERATIONS, polish=_polish("cmaes"))


@pytest.fixture(scope="module")
def stopped_in_polish(tmp_path_factory):
    """A serial run of the noisy sphere stopped at its 5th polish step: its checkpoint and
    the uninterrupted serial result."""
    ck = tmp_path_factory.mktemp("polish") / "serial.npz"
    with pytest.raises(Stop):
        _noisy().run(checkpoint=ck, callback=_stop_at_polish_step(5), **NOISY_RUN)
    assert _polish_steps_in(ck) == 4
    return ck, _noisy().run(**NOISY_RUN)


def test_started_serial_resumed_on_a_process_pool(stopped_in_polish, process_pool, tmp_path):
    ck, whole = stopped_in_polish
    mine = shutil.copy(ck, tmp_path / "ck.npz")
    resumed = _noisy(batch_size=3).run(
        checkpoint=mine, resume=True, executor=process_pool, **NOISY_RUN
    )
    _same(resumed, whole)


def test_started_serial_resumed_on_dask(stopped_in_polish, dask_client, tmp_path):
    ck, whole = stopped_in_polish
    mine = shutil.copy(ck, tmp_path / "ck.npz")
    resumed = _noisy(batch_size=5).run(
        checkpoint=mine, resume=True, executor=dask_client.get_executor(pure=False), **NOISY_RUN
    )
    _same(resumed, whole)


def test_started_on_a_pool_stopped_in_the_polish_resumed_serially(process_pool, tmp_path):
    ck = tmp_path / "ck.npz"
    with pytest.raises(Stop):
        _noisy().run(
            checkpoint=ck, executor=process_pool, callback=_stop_at_polish_step(3), **NOISY_RUN
        )
    resumed = _noisy().run(checkpoint=ck, resume=True, **NOISY_RUN)
    _same(resumed, _noisy().run(**NOISY_RUN))


# -- SIGKILL of a real run (the experiment runner) during the polish -------------------------
OVERRIDES = [
    "ga.population=8",
    "ga.generations=3",
    "ga.polish={evaluations = 160, batch = 8}",
    "output.mesh=[]",
    "output.screenshots=[]",
    "output.plot=false",
]
#: the child: a quickstart run whose callback writes a checkpoint after every polish
#: step, and holds the run at polish step KILL + 3 (so the kill lands in the polish
#: however fast the machine is); the test kills it once the checkpoint holds KILL steps
CHILD = """
import pathlib, sys, threading
from growsim.experiment import run

def hold(ga, row):
    ga.checkpoint_share = 0.0
    if sum(r["phase"] == "polish" for r in ga.state.rows) >= {hold}:
        (pathlib.Path(sys.argv[2]) / "held").touch()
        threading.Event().wait()  # until killed

run(sys.argv[1], out=sys.argv[2], overrides={overrides!r}, progress=False, callback=hold)
"""
KILL = 4


def _read_run(out):
    history = pd.read_parquet(out / "history.parquet").drop(columns="seconds")
    return history, json.loads((out / "best.json").read_text())


@pytest.mark.timeout(120)
def test_sigkill_during_the_polish_of_a_run_then_resume_on_a_pool(tmp_path):
    from growsim.experiment import run

    config = ROOT / "experiments" / "quickstart.toml"
    out = tmp_path / "killed"
    ck = out / "checkpoint.npz"
    child = CHILD.format(hold=KILL + 3, overrides=OVERRIDES)
    env = {**os.environ, "MPLBACKEND": "Agg"}
    proc = subprocess.Popen([sys.executable, "-c", child, str(config), str(out)], env=env)
    try:
        deadline = time.monotonic() + 90
        while _polish_steps_in(ck) < KILL:
            assert proc.poll() is None, "the run ended before it was killed"
            held = (out / "held").exists() and _polish_steps_in(ck) < KILL
            assert not held, f"held at polish step {KILL + 3}, checkpoint at {_polish_steps_in(ck)}"
            assert time.monotonic() < deadline, "no polish step reached the checkpoint"
            time.sleep(0.01)
        os.kill(proc.pid, signal.SIGKILL)
        assert proc.wait(30) == -signal.SIGKILL
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    steps = _polish_steps_in(ck)
    assert KILL <= steps <= KILL + 3
    assert not (out / "summary.json").exists()
    resumed = run(out=out, resume=True, workers=2, progress=False)
    assert resumed.summary["resumed"] is True
    whole = run(config, out=tmp_path / "whole", overrides=OVERRIDES, progress=False)
    h1, b1 = _read_run(out)
    h2, b2 = _read_run(whole.out)
    pd.testing.assert_frame_equal(h1, h2)
    assert (h1["phase"] == "polish").sum() == 20
    assert b1 == b2
