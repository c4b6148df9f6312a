"""The growsim command line as a user types it (subprocess): run, resume after SIGKILL,
sweep, compare, show, and exit code 2 with a one-line message for bad input."""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import time
from contextlib import redirect_stderr, redirect_stdout
from io import StringIO
from pathlib import Path

import numpy as np
import pandas as pd
from conftest import ROOT, growsim
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

QUICK = str(ROOT / "experiments" / "quickstart.toml")
TINY = [
    "--set",
    "ga.population=8",
    "--set",
    "ga.generations=3",
    "--set",
    "output.screenshots=[]",
    "--set",
    "output.mesh=['vtp']",
    "--set",
    "model.params.generations=6",
]


def assert_clean_error(p, needle):
    assert p.returncode == 2, (p.returncode, p.stdout, p.stderr)
    assert "Traceback" not in p.stderr, p.stderr
    err = [line for line in p.stderr.strip().splitlines() if line.startswith("growsim")]
    assert err and err[-1].startswith("growsim: error:"), p.stderr
    assert needle in err[-1], err[-1]


def test_run_then_show(tmp_path):
    out = tmp_path / "r"
    p = growsim("run", QUICK, "--out", out, *TINY)
    assert p.returncode == 0, p.stderr
    assert f"results in {out}/" in p.stdout and f"growsim show {out}" in p.stdout
    assert "gen/s" not in p.stderr and "it/s" not in p.stderr  # no bar: stderr is not a TTY
    assert (out / "summary.json").is_file() and (out / "fitness.png").is_file()
    png = tmp_path / "shot.png"
    p = growsim("show", out, "--screenshot", png, "--size", 200, 200)
    assert p.returncode == 0, p.stderr
    assert png.stat().st_size > 1000
    # coloured by the run's [environment]: the light each segment receives, with its arrow
    lit = tmp_path / "lit.png"
    p = growsim("show", out, "--color", "light", "--screenshot", lit, "--size", 200)
    assert p.returncode == 0, p.stderr
    assert lit.stat().st_size > 1000 and lit.read_bytes() != png.read_bytes()


#: bad input on the command line: the arguments and what the one-line error names
BAD_INPUT = [
    (["run", "nope.toml"], "nope.toml: no such config file"),
    (["run", QUICK, "--set", "ga.population=-3"], "ga.population: Input should be greater"),
    (["run", QUICK, "--set", "ga.popul=3"], "ga.popul: unknown key; allowed: population"),
    (["run", QUICK, "--set", "model.evolve.zz=true"], "model.evolve.zz: unknown parameter"),
    (["run", QUICK, "--set", "ga.population"], "expected key.path=value"),
    (["run", QUICK, "--workers", "0"], "--workers: expected an integer >= 1"),
    (["run", QUICK, "--scheduler", "foo"], "--scheduler: 'foo' is not 'local'"),
    (["run", QUICK, "--scheduler", "tcp://127.0.0.1:1"], "cannot reach tcp://127.0.0.1:1"),
    (["run"], "give a CONFIG to run, or --resume DIR"),
    (["run", "--resume", "/nonexistent/dir"], "nothing to resume"),
    (["sweep", QUICK, "--vary", "env.light"], "expected key.path=v1,v2"),
    (["sweep", QUICK, "--vary", "env.light=1,-1"], "environment.light"),
    (["compare", "/nonexistent/dir"], "no such directory"),
    (["show", "/nonexistent/dir"], "not a growsim results directory"),
]


def test_bad_input_exits_2_with_one_line(tmp_path):
    """Every case of :data:`BAD_INPUT` in its own process and working directory, as a user
    types it; the processes run side by side (each is mostly an interpreter's start, one
    waits for an unreachable scheduler), and every failing case is reported."""
    from concurrent.futures import ThreadPoolExecutor

    def case(i: int):
        cwd = tmp_path / str(i)
        cwd.mkdir()
        return cwd, growsim(*BAD_INPUT[i][0], cwd=cwd)

    with ThreadPoolExecutor(max_workers=4) as pool:
        done = list(pool.map(case, range(len(BAD_INPUT))))
    failed = []
    for (args, needle), (cwd, p) in zip(BAD_INPUT, done, strict=True):
        try:
            assert_clean_error(p, needle)
            assert not (cwd / "runs").exists()  # nothing written
        except AssertionError as exc:
            failed.append(f"{args}: {exc}")
    assert not failed, "\n".join(failed)


def test_bad_toml_file_exits_2(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[model]\nkind = 'honda'\n[[objective]]\nkind = light\n")
    assert_clean_error(growsim("run", bad), "invalid TOML")


def checkpoint_generation(run_dir: Path) -> int:
    """The generation a run directory's checkpoint reports; -1 before the first one (the
    file is replaced atomically, so it is read whole or not at all)."""
    try:
        with np.load(run_dir / "checkpoint.npz", allow_pickle=False) as z:
            return int(json.loads(str(z["meta"]))["generation"])
    except (OSError, ValueError, KeyError):
        return -1


def wait_until(ready, proc, what: str, timeout=120.0) -> None:
    """Poll ``ready()`` until it holds; fail if ``proc`` ends first or after ``timeout`` s
    (a bound for a stuck run, never the trigger: the run's own progress is)."""
    t0 = time.monotonic()
    while not ready():
        if proc.poll() is not None:
            raise AssertionError(f"the run ended before {what}: {proc.stderr.read()}")
        if time.monotonic() - t0 > timeout:
            raise AssertionError(f"{what}: not reached in {timeout} s")
        time.sleep(0.01)


def test_kill_and_resume_equals_uninterrupted(tmp_path):
    # 60 generations of 16 (~10 ms each): each kill waits for the generation the run's
    # checkpoint reports, so it lands where it means to on a loaded machine or a fast one
    args = [
        "--set",
        "ga.population=16",
        "--set",
        "ga.generations=60",
        "--set",
        "output.screenshots=[]",
        "--set",
        "output.mesh=[]",
        "--set",
        "output.plot=false",
        "--set",
        "objective[0].resolution=512",
    ]
    ref = tmp_path / "ref"
    assert growsim("run", QUICK, "--out", ref, "--quiet", *args).returncode == 0
    out = tmp_path / "killed"
    # SIGKILL at three points: as soon as the run directory exists (before the first
    # checkpoint, unless generation 0 beats the poll), once generation 3 is checkpointed,
    # and once generation 20 is (40 generations before the end)
    for stage, at in (("started", None), ("early", 3), ("later", 20)):
        before = checkpoint_generation(out)
        assert at is None or before < at, (stage, before)
        cmd = [sys.executable, "-m", "growsim", "run", "--quiet"]
        cmd += ["--resume", str(out)] if out.exists() else [QUICK, "--out", str(out), *args]
        proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        try:
            if at is None:
                wait_until((out / "config.toml").exists, proc, "config.toml")
            else:
                wait_until(lambda at=at: checkpoint_generation(out) >= at, proc, f"generation {at}")
            proc.send_signal(signal.SIGKILL)
            assert proc.wait(30) == -signal.SIGKILL
        finally:
            if proc.poll() is None:
                proc.kill()
                proc.wait()
    assert 20 <= checkpoint_generation(out) < 59
    assert not (out / "summary.json").exists(), "the run ended before the last kill"
    p = growsim("run", "--resume", out, "--quiet")
    assert p.returncode == 0, p.stderr
    a = pd.read_parquet(ref / "history.parquet").drop(columns=["seconds"])
    b = pd.read_parquet(out / "history.parquet").drop(columns=["seconds"])
    pd.testing.assert_frame_equal(a, b)
    assert json.loads((ref / "best.json").read_text()) == json.loads(
        (out / "best.json").read_text()
    )
    # resuming a finished run changes nothing
    p = growsim("run", "--resume", out, "--quiet")
    assert p.returncode == 0, p.stderr
    c = pd.read_parquet(out / "history.parquet").drop(columns=["seconds"])
    pd.testing.assert_frame_equal(a, c)


def test_sweep_then_compare(tmp_path):
    sw = tmp_path / "sw"
    p = growsim(
        "sweep",
        QUICK,
        "--vary",
        "env.light=1.0,0.5",
        "--repeats",
        2,
        "--out",
        sw,
        *TINY,
        "--set",
        "output.plot=false",
    )
    assert p.returncode == 0, p.stderr
    df = pd.read_csv(sw / "sweep.csv")
    assert len(df) == 4 and "best_fitness" in p.stdout
    cmp_dir = tmp_path / "cmp"
    p = growsim("compare", sw, "--out", cmp_dir)
    assert p.returncode == 0, p.stderr
    assert "light=1.0" in p.stdout and "welch_t_p" in p.stdout
    html = (cmp_dir / "report.html").read_text()
    assert html.count("data:image/png;base64,") == 2  # curves and renders
    assert (cmp_dir / "renders.png").stat().st_size > 1000


def test_a_second_run_on_the_same_out_refuses(tmp_path):
    out = tmp_path / "busy"
    proc = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "growsim",
            "run",
            QUICK,
            "--out",
            str(out),
            "--quiet",
            "--set",
            "ga.generations=1000000",
            "--set",
            "ga.population=8",
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        wait_until(lambda: checkpoint_generation(out) >= 0, proc, "generation 0")  # lock held
        p = growsim("run", QUICK, "--out", out)
        assert_clean_error(p, f"{out} is in use by another growsim run (pid {proc.pid})")
        p = growsim("run", "--resume", out)
        assert_clean_error(p, "in use by another growsim run")
        assert proc.poll() is None  # the first run was not disturbed
    finally:
        proc.send_signal(signal.SIGKILL)
        proc.wait()


# ---- fuzzing the command line in-process: malformed configs never give a traceback ----

QUICK_TEXT = Path(QUICK).read_text()


@settings(
    max_examples=120,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)
@given(
    edits=st.lists(
        st.tuples(
            st.integers(0, len(QUICK_TEXT)),
            st.integers(0, 12),
            st.sampled_from(["", "[", "]", "=", '"', "x", "-1", "\n", "1e9", "{", ".", "#"]),
        ),
        min_size=1,
        max_size=4,
    )
)
def test_fuzz_mangled_quickstart_exits_2_or_runs(tmp_path, monkeypatch, edits):
    import growsim.experiment.runner as ex
    from growsim.cli import main
    from growsim.errors import GrowsimError

    def no_run(*a, **k):  # a config that survives validation is not run here
        raise GrowsimError("VALID")

    monkeypatch.setattr(ex, "_run_locked", no_run)
    text = QUICK_TEXT
    for pos, cut, insert in edits:
        text = text[:pos] + insert + text[pos + cut :]
    cfg = tmp_path / f"c{abs(hash(text))}.toml"
    cfg.write_text(text)
    err = StringIO()
    with redirect_stderr(err), redirect_stdout(StringIO()):
        code = main(["run", str(cfg), "--out", str(tmp_path / f"o{abs(hash(text))}"), "--quiet"])
    lines = [ln for ln in err.getvalue().splitlines() if ln.strip()]
    assert code == 2, err.getvalue()
    assert len(lines) == 1 and lines[0].startswith("growsim: error: "), err.getvalue()


def test_an_interrupted_command_in_process_puts_ctrl_c_back(tmp_path, monkeypatch):
    """Called from Python, an interrupted command reports 130 and leaves Ctrl-C's handler
    as it found it: ignored, it would stay ignored in the caller and in every process the
    caller starts later (they inherit it), so none could be interrupted."""
    import growsim.experiment.runner as ex
    from growsim.cli import main

    def interrupted(*a, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr(ex, "_run_locked", interrupted)
    # Python's own handler, whatever this process inherited (a background job ignores it)
    signal.signal(signal.SIGINT, signal.default_int_handler)
    err = StringIO()
    with redirect_stderr(err):
        code = main(["run", QUICK, "--out", str(tmp_path / "o"), "--quiet"])
    assert code == 130 and "growsim: interrupted" in err.getvalue()
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
