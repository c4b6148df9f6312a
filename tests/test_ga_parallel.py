"""Same seed, same result: serial vs process pool vs Dask; SIGKILL + resume vs uninterrupted."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from growsim.errors import UserInputError
from growsim.ga import GA, HISTORY_COLUMNS, Bits, Genome, Real
from growsim.ga.problems import noisy_sphere, onemax, sphere

COLS = [c for c in HISTORY_COLUMNS if c != "seconds"]
G = Genome([Real("x", -3, 3, size=8)])


def _run(executor, batch_size=None):
    ga = GA(G, noisy_sphere, population=40, maximize=False, seed=11, batch_size=batch_size)
    return ga.run(generations=6, executor=executor, polish={"evaluations": 60})


def _same(a, b):
    pd.testing.assert_frame_equal(a.history[COLS], b.history[COLS])
    assert a.best.fitness == b.best.fitness
    assert np.array_equal(a.best.params, b.best.params)
    assert np.array_equal(a.fitness, b.fitness)


def test_process_pool_matches_serial(process_pool):
    serial = _run(None)
    _same(serial, _run(2))  # GA.run opens (and shuts) a pool of its own
    _same(serial, _run(process_pool, batch_size=7))
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(3) as ex:
        _same(serial, _run(ex, batch_size=5))


def test_dask_local_cluster_matches_serial(dask_client):
    serial = _run(None)
    _same(serial, _run(dask_client.get_executor(pure=False), batch_size=9))
    from growsim.experiment.executors import DaskPool

    _same(serial, _run(DaskPool(dask_client)))  # split by the cluster's 2 threads


def test_pools_say_their_size(process_pool, dask_client):
    """Where evaluations run is a :class:`growsim.ga.evaluate.Pool` that says how many
    run at once: the process pool ``open_executor(n)`` starts, a Dask client's
    (:class:`DaskPool`: the cluster's threads, asked of the client it holds); a bare
    executor is wrapped, of unknown size; the evaluator splits a population in 4 tasks
    per worker (the local CPUs when the pool cannot say)."""
    from concurrent.futures import ThreadPoolExecutor

    from growsim.experiment.executors import DaskPool, executor_workers
    from growsim.ga.evaluate import Evaluator, Pool, open_executor

    assert process_pool.workers == 2 and executor_workers(process_pool) == 2
    dask = DaskPool(dask_client)
    assert dask.workers == 2 and executor_workers(dask) == 2 and dask.client is dask_client
    assert dask.submit(sum, [1, 2]).result() == 3
    assert open_executor(dask) == (dask, False)
    with ThreadPoolExecutor(2) as ex:
        pool, owned = open_executor(ex)
        assert isinstance(pool, Pool) and pool.workers is None and not owned
        assert executor_workers(ex) is None and executor_workers(3) is None
        ev = Evaluator(sphere, executor=Pool(ex, workers=3))
        assert ev._workers() == 3
        assert Evaluator(sphere, executor=ex)._workers() == (os.cpu_count() or 2)
    with pytest.raises(UserInputError, match="workers"):
        Pool(ex, workers=0)


def test_the_session_cluster_leaves_the_environment_alone(dask_client):
    # its Nanny wrote its workers' variables into os.environ (conftest takes them back):
    # later tests' subprocesses must not start with PYTHONHASHSEED or OMP_NUM_THREADS=1
    assert dask_client.submit(os.getpid, pure=False).result() != os.getpid()
    assert "__DASK_PARENT_PID" not in os.environ


def _worker_environ(key):
    return os.environ.get(key)


# the session's cluster holds Dask's port 8787: this one moves (and Dask's retry drops a socket)
@pytest.mark.filterwarnings("ignore:Port 8787 is already in use", "ignore:unclosed <socket")
@pytest.mark.parametrize(("parent", "worker"), [("65536", None), ("131072", "131072")])
def test_local_cluster_workers_start_without_dasks_malloc_trim(monkeypatch, parent, worker):
    """Dask's default ``MALLOC_TRIM_THRESHOLD_=65536`` (pre-spawn-environ) makes every
    large array in a worker fault all its pages again; growsim's local cluster starts its
    workers without it, even after a cluster with Dask's defaults wrote that value into
    ``os.environ`` (65536: dropped), and keeps a value the user set (131072). Checked in
    the worker's environment, whatever the allocator does with it. (A cluster of its own,
    not the session's: the one started with that variable set; ``monkeypatch`` puts the
    variable back, so nothing leaks into later tests.)"""
    from dask import distributed

    from growsim.experiment.executors import local_cluster

    key = "MALLOC_TRIM_THRESHOLD_"
    monkeypatch.setenv(key, parent)
    with local_cluster(1) as cluster, distributed.Client(cluster) as client:
        seen = client.submit(_worker_environ, key, pure=False).result()
    assert seen == worker
    assert os.environ.get(key) == worker


# -- checkpoint / resume ---------------------------------------------------------------
CONFIGS = {
    "bits_islands_meta": dict(
        genome="Genome([Bits('b', 0, 1, bits=4, size=25)], diploid=True)",
        fitness="onemax",
        kw=dict(population=30, seed=5, islands=2, mutation="meta", migration_interval=3),
        run=dict(generations=40),
    ),
    "real_steady_polish": dict(
        genome="Genome([Real('x', -3, 3, size=8)])",
        fitness="sphere",
        kw=dict(population=20, seed=6, maximize=False, model="steady", offspring=6),
        run=dict(generations=40, polish={"evaluations": 100}),
    ),
}

SCRIPT = """
import sys, time
from growsim.ga import GA, Genome, Bits, Real
from growsim.ga.problems import onemax, sphere
cfg = {cfg}
ga = GA({genome}, {fitness}, **cfg["kw"])
# the pause only slows the child down so that it is killed mid-run
ga.run(checkpoint=sys.argv[1], callback=lambda ga, row: time.sleep(0.05), **cfg["run"])
"""


def _make(name):
    c = CONFIGS[name]
    ns = {"Genome": Genome, "Bits": Bits, "Real": Real}
    genome = eval(c["genome"], ns)
    return GA(genome, {"onemax": onemax, "sphere": sphere}[c["fitness"]], **c["kw"])


def _checkpoint_generation(path: Path) -> int:
    try:
        with np.load(path, allow_pickle=False) as z:
            return json.loads(str(z["meta"]))["generation"]
    except (OSError, ValueError, KeyError):
        return -1


@pytest.mark.parametrize("name", sorted(CONFIGS))
def test_sigkill_then_resume_gives_the_uninterrupted_history(tmp_path, name):
    c = CONFIGS[name]
    ck = tmp_path / "ck.npz"
    script = SCRIPT.format(cfg=repr(c), genome=c["genome"], fitness=c["fitness"])
    proc = subprocess.Popen([sys.executable, "-c", script, str(ck)])
    try:
        deadline = time.time() + 60
        while _checkpoint_generation(ck) < 8:
            assert proc.poll() is None, "the child ended before it could be killed"
            assert time.time() < deadline
            time.sleep(0.02)
        os.kill(proc.pid, signal.SIGKILL)
        assert proc.wait(30) == -signal.SIGKILL
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    killed_at = _checkpoint_generation(ck)
    assert 8 <= killed_at < c["run"]["generations"]
    assert not list(tmp_path.glob("*.tmp"))  # no half-written file left behind... or only ours
    resumed = _make(name).run(checkpoint=ck, resume=True, **c["run"])
    whole = _make(name).run(**c["run"])
    _same(resumed, whole)
    assert resumed.stop_reason == whole.stop_reason == "generations"
    # resuming a finished run changes nothing
    again = _make(name).run(checkpoint=ck, resume=True, **c["run"])
    _same(again, whole)


def test_resume_in_process_after_every_generation(tmp_path):
    ck = tmp_path / "c.npz"
    whole = GA(G, sphere, population=10, maximize=False, seed=3).run(generations=8)
    for stop in range(1, 8):
        ck.unlink(missing_ok=True)
        GA(G, sphere, population=10, maximize=False, seed=3).run(generations=stop, checkpoint=ck)
        part = GA(G, sphere, population=10, maximize=False, seed=3).run(
            generations=8, checkpoint=ck, resume=True
        )
        _same(part, whole)


def test_checkpoint_of_another_setup_is_refused(tmp_path):
    ck = tmp_path / "c.npz"
    GA(G, sphere, population=10, seed=3).run(generations=2, checkpoint=ck)
    with pytest.raises(UserInputError, match="population"):
        GA(G, sphere, population=12, seed=3).run(generations=4, checkpoint=ck, resume=True)
    ck.write_bytes(b"not a checkpoint")
    with pytest.raises(UserInputError, match="unreadable"):
        GA(G, sphere, population=10, seed=3).run(generations=4, checkpoint=ck, resume=True)
