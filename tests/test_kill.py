"""A run killed (SIGKILL: the OOM killer, a batch system's time limit, a closed terminal)
dies whole: none of its processes (pool workers, Dask's) is left 5 s later, its lock goes
with it, ``--resume`` starts at once and gives the uninterrupted run's result. For
``run --workers 2``, ``sweep --workers 2`` and ``fit-image`` on the process pool, and
``run --scheduler local`` on Dask, killed at several moments (the run starting, during
the generations, during the polish; a fit's first size and its refinement). Every kill
waits for the run's own files (checkpoints, a fit's saved stages), never for a time.
"""

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
from conftest import ROOT, growsim

QUICK = str(ROOT / "experiments" / "quickstart.toml")
#: a quickstart run long enough to be killed three times, with a polish to be killed in:
#: 200 steps of about 13 ms, so the polish outlasts the kill's polling whatever the
#: machine (with 12 steps, 0.16 s, a fast machine ended the run between two polls)
RUN = ["--set", "ga.population=16", "--set", "ga.generations=12",
       "--set", "ga.polish={evaluations = 1600, batch = 8}", "--set", "output.screenshots=[]",
       "--set", "output.mesh=[]", "--set", "output.plot=false",
       "--set", "objective[0].resolution=512"]  # fmt: skip
#: how long the processes of a killed run may outlive it
GRACE = 5.0


def children(pid: int) -> set[int]:
    """Every living descendant of ``pid`` (read from ``/proc``)."""
    found: set[int] = set()
    todo = [pid]
    while todo:
        p = todo.pop()
        try:
            tasks = os.listdir(f"/proc/{p}/task")
        except OSError:
            continue
        for t in tasks:
            try:
                with open(f"/proc/{p}/task/{t}/children") as f:
                    kids = {int(k) for k in f.read().split()}
            except OSError:
                continue
            todo.extend(kids - found)
            found |= kids
    return found


def alive(pid: int) -> bool:
    """True while ``pid`` runs (a zombie waiting to be reaped is dead)."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def wait_for(ready, proc, what: str, timeout: float = 180.0) -> None:
    """Poll ``ready()``; fail if ``proc`` ends first (a bound, never the trigger)."""
    t0 = time.monotonic()
    while not ready():
        assert proc.poll() is None, f"the run ended before {what}: {proc.stderr.read()}"
        assert time.monotonic() - t0 < timeout, f"{what}: not reached in {timeout} s"
        time.sleep(0.01)


def kill_whole(proc: subprocess.Popen, workers: int) -> None:
    """SIGKILL ``proc`` (after checking it has at least ``workers`` child processes) and
    assert that none of its processes is alive ``GRACE`` s later."""
    kids = children(proc.pid)
    assert len(kids) >= workers, f"expected >= {workers} workers, found {sorted(kids)}"
    proc.send_signal(signal.SIGKILL)
    assert proc.wait(30) == -signal.SIGKILL
    t0 = time.monotonic()
    while [k for k in kids if alive(k)] and time.monotonic() - t0 < GRACE:
        time.sleep(0.05)
    left = [k for k in kids if alive(k)]
    for k in left:  # not to leave them to the next test
        os.kill(k, signal.SIGKILL)
    assert not left, f"processes of the killed run alive {GRACE} s later: {left}"


def start(*args) -> subprocess.Popen:
    cmd = [sys.executable, "-m", "growsim", *map(str, args)]
    env = {**os.environ, "MPLBACKEND": "Agg"}
    return subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env=env)  # fmt: skip


def checkpoint_meta(run_dir: Path) -> dict | None:
    try:
        with np.load(run_dir / "checkpoint.npz", allow_pickle=False) as z:
            return json.loads(str(z["meta"]))
    except (OSError, ValueError, KeyError):
        return None


def generation(run_dir: Path) -> int:
    meta = checkpoint_meta(run_dir)
    return -1 if meta is None else int(meta["generation"])


def polish_steps(run_dir: Path) -> int:
    meta = checkpoint_meta(run_dir)
    return -1 if meta is None else sum(r["phase"] == "polish" for r in meta["rows"])


def same_run(a: Path, b: Path) -> None:
    ha = pd.read_parquet(a / "history.parquet").drop(columns=["seconds"])
    hb = pd.read_parquet(b / "history.parquet").drop(columns=["seconds"])
    pd.testing.assert_frame_equal(ha, hb)
    assert json.loads((a / "best.json").read_text()) == json.loads((b / "best.json").read_text())


def run_killed(out: Path, moments, executor: list[str], workers: int) -> None:
    """Start (then resume) ``growsim run`` on ``out`` and kill it whole at each of
    ``moments``: callables of the run directory and the generation it was at when this
    process started, True once the kill is due (and the run's workers are up)."""
    for due in moments:
        at = generation(out)
        args = ["--resume", out] if out.exists() else [QUICK, "--out", out, *RUN]
        proc = start("run", "--quiet", *args, *executor)
        try:
            ready = lambda due=due, proc=proc, at=at: (  # noqa: E731
                len(children(proc.pid)) >= workers and due(out, at)
            )
            wait_for(ready, proc, due.__name__)
            kill_whole(proc, workers)
        finally:
            if proc.poll() is None:
                proc.kill()
                proc.wait()


def started(out: Path, at: int) -> bool:
    """The workers are up: the run's first generation (of this process) under way."""
    return (out / "config.toml").exists()


def mid_run(out: Path, at: int) -> bool:
    """Past generation 4, and past where this process started."""
    return generation(out) >= max(4, at + 1)


def polishing(out: Path, at: int) -> bool:
    return polish_steps(out) >= 2


@pytest.fixture(scope="module")
def reference(tmp_path_factory) -> Path:
    """The uninterrupted run (serial: results do not depend on the executor)."""
    ref = tmp_path_factory.mktemp("kill") / "ref"
    p = growsim("run", QUICK, "--out", ref, "--quiet", *RUN)
    assert p.returncode == 0, p.stderr
    return ref


def test_run_on_a_pool_killed_three_times_dies_whole_and_resumes(tmp_path, reference):
    out = tmp_path / "killed"
    run_killed(out, [started, mid_run, polishing], ["--workers", "2"], workers=2)
    assert not (out / "summary.json").exists(), "the run ended before the last kill"
    t0 = time.monotonic()
    p = growsim("run", "--resume", out, "--quiet", "--workers", "2")
    assert p.returncode == 0, p.stderr
    assert "in use" not in p.stderr and time.monotonic() - t0 < 120
    same_run(reference, out)


def test_run_on_dask_killed_dies_whole_and_resumes(tmp_path, reference):
    out = tmp_path / "killed"
    run_killed(out, [mid_run], ["--scheduler", "local", "--workers", "2"], workers=2)
    p = growsim("run", "--resume", out, "--quiet")
    assert p.returncode == 0, p.stderr
    same_run(reference, out)


def test_sweep_on_a_pool_killed_dies_whole_and_resumes(tmp_path, reference):
    sweep = ["sweep", QUICK, "--vary", "env.light=1.0", "--repeats", "2", "--quiet",
             *RUN, "--workers", "2"]  # fmt: skip
    out = tmp_path / "sw"
    seeds = lambda seed: list(out.glob(f"*/seed-{seed}"))  # noqa: E731  (quickstart: seed 1)
    proc = start(*sweep, "--out", out)
    try:  # killed in the second run of the sweep, the first one finished
        wait_for(lambda: seeds(2) and generation(seeds(2)[0]) >= 2, proc, "run 2's generation 2")
        kill_whole(proc, workers=2)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    p = growsim(*sweep, "--out", out)
    assert p.returncode == 0, p.stderr
    (first,), (second,) = seeds(1), seeds(2)
    same_run(reference, first)  # the reference is the config's seed 1
    whole = tmp_path / "whole"
    p = growsim(*sweep, "--out", whole)
    assert p.returncode == 0, p.stderr
    same_run(whole / second.relative_to(out), second)


@pytest.fixture(scope="module")
def photo(tmp_path_factory) -> Path:
    from test_photo_fit import PICTURES, make_photo

    d = tmp_path_factory.mktemp("kill_photo")
    _, _, jpeg = make_photo(PICTURES[0], size=256)
    path = d / "zelkova.jpg"
    path.write_bytes(jpeg)
    return path


FIT = ["--model", "honda", "--evaluations", "1600", "--sizes", "32,64", "--refine", "200",
       "--arrange", "40", "--restarts", "2", "--seed", "3", "--quiet"]  # fmt: skip


def test_fit_image_killed_in_each_stage_dies_whole_and_resumes(tmp_path, photo):
    out = tmp_path / "fit"
    runs = lambda: [d for d in out.glob("*") if d.is_dir()]  # noqa: E731

    def first_size():  # every run's GA under way
        return len(runs()) >= 2 and all(generation(d) >= 1 for d in runs())

    def refinement():  # a run past its first size (its stages saved), another not yet done
        done = [d for d in runs() if (d / "fit-stages.json").is_file()]
        return bool(done) and not (out / "fit.json").exists()

    for due in (first_size, refinement):
        args = ["--resume", out] if out.exists() else [photo, "--out", out, *FIT]
        proc = start("fit-image", *args, *(["--workers", "2"] if not out.exists() else []))
        try:
            wait_for(due, proc, due.__name__)
            kill_whole(proc, workers=2)
        finally:
            if proc.poll() is None:
                proc.kill()
                proc.wait()
    assert not (out / "fit.json").exists(), "the fit ended before the last kill"
    p = growsim("fit-image", "--resume", out)
    assert p.returncode == 0, p.stderr
    whole = tmp_path / "whole"
    p = growsim("fit-image", photo, "--out", whole, *FIT, "--workers", "2")
    assert p.returncode == 0, p.stderr
    a, b = (json.loads((d / "fit.json").read_text()) for d in (out, whole))
    assert a["params"] == b["params"] and a["ncc"] == b["ncc"]


def test_a_lock_held_by_a_gone_runs_leftover_names_it(tmp_path):
    """A directory whose lock is held by a process its run left behind (the pid in the
    lock is gone): refused naming the process that holds it; once it ends, taken over."""
    from growsim.experiment.results import RunDir

    out = tmp_path / "r"
    out.mkdir()
    # a holder that names a pid that is gone, as a leftover of an older growsim would
    code = (
        "import fcntl, os, sys, time\n"
        f"fd = os.open({str(out / '.lock')!r}, os.O_RDWR | os.O_CREAT)\n"
        "fcntl.flock(fd, fcntl.LOCK_EX)\nos.pwrite(fd, b'999999999', 0)\n"
        "print('held', flush=True)\ntime.sleep(600)\n"
    )
    holder = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "held"
        with pytest.raises(Exception, match=rf"pid 999999999\) is gone.*pid {holder.pid}"):
            with RunDir(out).lock(resume=True):
                pass
    finally:
        holder.kill()
        holder.wait()
    with RunDir(out).lock(resume=True) as rd:
        assert rd.lock_path.read_text() == str(os.getpid())


def test_sigterm_ends_the_run_and_its_workers_and_it_resumes(tmp_path, reference):
    out = tmp_path / "termed"
    proc = start("run", "--quiet", QUICK, "--out", out, *RUN, "--workers", "2")
    try:
        wait_for(lambda: mid_run(out, -1), proc, "generation 4")
        kids = children(proc.pid)
        assert len(kids) >= 2
        proc.send_signal(signal.SIGTERM)
        assert proc.wait(60) == 143
        assert "growsim: terminated" in proc.stderr.read()
        t0 = time.monotonic()
        while [k for k in kids if alive(k)] and time.monotonic() - t0 < GRACE:
            time.sleep(0.05)
        assert not [k for k in kids if alive(k)]
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    p = growsim("run", "--resume", out, "--quiet")
    assert p.returncode == 0, p.stderr
    same_run(reference, out)


def _lock_holders(path: str) -> list[int]:
    from growsim.experiment.results import lock_holders

    return sorted(pid for pid, _ in lock_holders(path))


def test_a_pool_worker_holds_no_copy_of_its_runs_lock(tmp_path):
    from growsim.experiment.results import RunDir
    from growsim.ga import WorkerPool

    with RunDir(tmp_path / "r").lock() as rd, WorkerPool(1) as pool:
        holders = pool.submit(_lock_holders, str(rd.lock_path)).result()
    assert holders == [os.getpid()]


def test_the_watchdog_alone_ends_workers_whose_parent_died(tmp_path):
    """Where the kernel cannot be asked (no ``PR_SET_PDEATHSIG``), each worker's watchdog
    ends it once its parent is gone."""
    code = (
        "import os, time\n"
        "import growsim.ga.workers as w\n"
        "w._parent_death_signal = lambda sig: False  # as on a platform without prctl\n"
        "pool = w.WorkerPool(2)\n"
        "print(sorted({pool.submit(os.getpid).result() for _ in range(8)}), flush=True)\n"
        "time.sleep(600)\n"
    )
    proc = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
    try:
        assert proc.stdout.readline().strip()  # the pool is up
        kill_whole(proc, workers=2)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
