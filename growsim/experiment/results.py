"""The results directory of a run: the one place that writes and reads it back.

:class:`RunDir` writes (atomic writes, a lock, the paths of every file) and builds
``best.json`` (:meth:`RunDir.write_best`) and ``summary.json``
(:meth:`RunDir.write_summary`) from the facts the runner passes;
:class:`RunRecord` is the one description of a run: what
:func:`growsim.experiment.run` returns, and what :func:`read_run` (also
:func:`load_run`) and :func:`find_runs` read back (``growsim show``, ``compare``,
``sweep`` and the Python API use them); :func:`best_phenotype` reads or regrows a run's
best; :func:`plot_fitness` draws a run's ``fitness.png``.

A run directory holds (see ``docs/design.md``)::

    config.toml        the resolved config (written first)
    checkpoint.npz     GA state incl. RNG state (the GA writes it every generation)
    history.parquet    one row per generation (and island)
    best.json          best genome, parameters, fitness, generation
    best_<kind>.npz    the best phenotype (best_plant.npz for plants); its artefacts
                       (best.vtp/.glb/..., best_<view>.png); fitness.png
    summary.json       written last: its presence marks a finished run
    .lock              held (flock) while a process writes here; removed when it ends

Every file is written to a temporary name in the same directory and renamed with
``os.replace``, so a reader (or a crash) never sees half a file.
"""

from __future__ import annotations

import contextlib
import dataclasses
import fcntl
import json
import logging
import os
import tomllib
from collections.abc import Callable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from growsim import __version__
from growsim.errors import UserInputError
from growsim.experiment.load import validate
from growsim.experiment.plan import plan_model
from growsim.experiment.schema import Config
from growsim.files import atomic_path, atomic_write, jsonable
from growsim.phenotypes import load_phenotype

#: The descriptors of the run locks this process holds. A process forked from this one
#: (a pool's worker) closes its copies as it starts (``os.register_at_fork``), so the lock
#: is its run's alone: it ends with the run, whatever its workers do.
_HELD_LOCKS: set[int] = set()


def _drop_inherited_locks() -> None:
    for fd in _HELD_LOCKS:
        with contextlib.suppress(OSError):
            os.close(fd)  # this copy only: the parent's lock stays held
    _HELD_LOCKS.clear()


os.register_at_fork(after_in_child=_drop_inherited_locks)


def _alive(pid: int) -> bool:
    """True when process ``pid`` exists (ours or another user's)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def lock_holders(path: str | Path) -> list[tuple[int, str]]:
    """``[(pid, command line)]`` of the processes that have the file ``path`` open (read
    from ``/proc``; ``[]`` where there is none, or nothing can be read).

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.NamedTemporaryFile() as f:
    ...     [pid for pid, _ in lock_holders(f.name)] == [os.getpid()]
    True
    """
    try:
        target = os.stat(path)
        pids = [int(p) for p in os.listdir("/proc") if p.isdigit()]
    except OSError:
        return []
    found = []
    for pid in pids:
        try:
            fds = os.listdir(f"/proc/{pid}/fd")
        except OSError:
            continue
        for fd in fds:
            try:
                if os.path.samestat(os.stat(f"/proc/{pid}/fd/{fd}"), target):
                    with open(f"/proc/{pid}/cmdline", "rb") as f:
                        cmd = f.read().replace(b"\0", b" ").decode(errors="replace").strip()
                    found.append((pid, cmd))
                    break
            except OSError:
                continue
    return found


__all__ = [
    "RunDir",
    "RunRecord",
    "RunResult",
    "best_phenotype",
    "best_plant",
    "find_runs",
    "load_run",
    "lock_holders",
    "plot_fitness",
    "read_run",
    "write_parquet",
]

log = logging.getLogger(__name__)


def write_parquet(path: str | Path, df) -> Path:
    """Write a DataFrame to Parquet atomically.

    Examples
    --------
    >>> import tempfile, pathlib, pandas as pd
    >>> p = write_parquet(pathlib.Path(tempfile.mkdtemp()) / "h.parquet", pd.DataFrame({"a": [1]}))
    >>> pd.read_parquet(p)["a"].tolist()
    [1]
    """
    with atomic_path(path) as tmp:
        df.to_parquet(tmp, index=False)
    return Path(path)


class RunDir:
    """Paths and atomic writers of one results directory, and its lock.

    Examples
    --------
    >>> import tempfile
    >>> rd = RunDir(tempfile.mkdtemp() + "/run")
    >>> with rd.lock():
    ...     rd.create_fresh()
    ...     _ = rd.write_json("best.json", {"fitness": 1.0})
    >>> rd.best_path.name
    'best.json'
    """

    def __init__(self, path: str | Path):
        self.path = Path(path)
        self._lock_fd: int | None = None

    config_path = property(lambda self: self.path / "config.toml")
    history_path = property(lambda self: self.path / "history.parquet")
    best_path = property(lambda self: self.path / "best.json")
    summary_path = property(lambda self: self.path / "summary.json")
    checkpoint_path = property(lambda self: self.path / "checkpoint.npz")

    def phenotype_path(self, kind: str = "plant") -> Path:
        """``best_<kind>.npz``: where the best phenotype of that kind is saved."""
        return self.path / f"best_{kind}.npz"

    lock_path = property(lambda self: self.path / ".lock")

    def is_complete(self) -> bool:
        """True when the run finished (summary.json exists)."""
        return self.summary_path.is_file()

    @contextlib.contextmanager
    def lock(self, resume: bool = False) -> Iterator[RunDir]:
        """Hold an exclusive lock on the directory; a second holder refuses at once (its
        message for ``resume``: no ``--out`` to change).

        The lock is an ``flock`` on ``.lock`` (which holds the pid): the kernel drops it
        when the process dies (even by SIGKILL), so a killed run leaves no stale lock to
        clean up (a ``.lock`` left by a killed run is taken over, and a warning names
        it). The lock is the run's alone: a process forked from it (a pool's worker)
        closes its copy as it starts. A lock held though the pid it names is gone (held by
        a process that run left behind) is refused naming the processes that hold it.
        When the block ends the file is removed while the lock is still held, then the
        lock released; a process that opened the old file meanwhile sees it was removed
        and takes a new one.

        Examples
        --------
        >>> import tempfile
        >>> rd = RunDir(tempfile.mkdtemp())
        >>> with rd.lock():
        ...     rd.lock_path.is_file()
        True
        >>> rd.lock_path.exists()
        False
        """

        try:
            self.path.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise UserInputError(f"--out {self.path}: cannot create ({exc.strerror})") from None
        if not self.path.is_dir():
            raise UserInputError(f"--out {self.path}: not a directory")
        while True:
            fd = os.open(self.lock_path, os.O_RDWR | os.O_CREAT, 0o644)
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                other = os.pread(fd, 64, 0).decode(errors="replace").strip() or "?"
                os.close(fd)
                raise UserInputError(self._refusal(other, resume)) from None
            except BaseException:
                os.close(fd)
                raise
            try:
                same = os.path.samestat(os.fstat(fd), os.stat(self.lock_path))
            except FileNotFoundError:
                same = False
            if same:
                break
            os.close(fd)  # its holder removed it as we opened it: lock the new one
        before = os.pread(fd, 64, 0).decode(errors="replace").strip()
        if before.isdigit() and int(before) != os.getpid():
            log.warning("%s: the run that held it (pid %s) is gone; taking it over", self.path,
                        before)  # fmt: skip
        try:
            os.ftruncate(fd, 0)
            os.pwrite(fd, str(os.getpid()).encode(), 0)
            self._lock_fd = fd
            _HELD_LOCKS.add(fd)
            yield self
        finally:
            _HELD_LOCKS.discard(fd)
            self._lock_fd = None
            try:
                with contextlib.suppress(FileNotFoundError):
                    os.unlink(self.lock_path)  # still locked: nobody else holds this file
            finally:
                os.close(fd)  # closing the descriptor releases the flock

    def _refusal(self, holder: str, resume: bool) -> str:
        """Why the lock cannot be taken, ``holder`` the pid the lock file names."""
        if holder.isdigit() and not _alive(int(holder)):
            others = [(p, c) for p, c in lock_holders(self.lock_path) if p != os.getpid()]
            named = "; ".join(f"pid {p} ({c[:80]})" for p, c in others) or "a process not shown"
            pids = " ".join(str(p) for p, _ in others)
            end = f"end them (kill {pids}), then " if pids else "end it, then "
            return (
                f"{self.path}: the run that held it (pid {holder}) is gone, but its lock is "
                f"still held by {named}, left behind by that run; {end}"
                f"{'resume' if resume else 'start again'}"
            )
        hint = "wait for it to end" if resume else "choose another --out"
        return f"{self.path} is in use by another growsim run (pid {holder}); {hint}"

    def read_config(self) -> dict[str, Any]:
        """The resolved config saved in ``config.toml``, as data.

        Examples
        --------
        >>> import tempfile
        >>> rd = RunDir(tempfile.mkdtemp())
        >>> _ = rd.write_text("config.toml", "[ga]\\npopulation = 8\\n")
        >>> rd.read_config()
        {'ga': {'population': 8}}
        """
        try:
            return tomllib.loads(self.config_path.read_text())
        except (OSError, ValueError) as exc:
            raise UserInputError(f"{self.config_path}: unreadable ({exc})") from None

    def create_fresh(self) -> None:
        """Check the directory holds no run yet (a fresh run must not mix with another)."""
        taken = [
            p.name
            for p in (self.config_path, self.summary_path, self.checkpoint_path, self.history_path)
            if p.exists()
        ]
        if taken:
            raise UserInputError(
                f"{self.path} already holds a run ({', '.join(taken)}); "
                f"resume it with: growsim run --resume {self.path}, or choose another --out"
            )

    def write_text(self, name: str, text: str) -> Path:
        """Atomically write a text file in the directory."""
        return atomic_write(self.path / name, text)

    def write_json(self, name: str, obj: Any) -> Path:
        """Atomically write ``obj`` as indented JSON."""
        return atomic_write(self.path / name, json.dumps(obj, indent=2, sort_keys=False) + "\n")

    def write_parquet(self, name: str, df) -> Path:
        """Atomically write a DataFrame as Parquet."""
        return write_parquet(self.path / name, df)

    def write_with(self, name: str, writer: Callable[[Path], Any]) -> Path:
        """Call ``writer(tmp_path)`` then rename the result onto ``name`` (for renderers)."""
        with atomic_path(self.path / name) as tmp:
            writer(tmp)
        return self.path / name

    def write_best(
        self,
        *,
        fitness: float,
        generation: int,
        params: Mapping[str, float],
        evolved: Sequence[str],
        model: str,
        phenotype: str,
        plant_seed: int,
        terms: Mapping[str, Mapping[str, float]],
        genome=None,
    ) -> dict[str, Any]:
        """Write ``best.json`` from the facts of the best individual; return its data.

        ``params``: every model parameter (integers as ints); ``evolved``: the evolved
        names (``best.json`` repeats their values under ``evolved``); ``phenotype``: its
        kind; ``plant_seed``: the seed it grows with; ``terms``: each objective's score
        and terms (:meth:`growsim.experiment.fitness.Fitness.terms`); ``genome``: the
        raw genome, when there is one.

        Examples
        --------
        >>> import tempfile
        >>> rd = RunDir(tempfile.mkdtemp())
        >>> best = rd.write_best(fitness=2.0, generation=1, params={"a": 0.5, "n": 3},
        ...                      evolved=["a"], model="m", phenotype="plant", plant_seed=1,
        ...                      terms={})
        >>> list(best), best["evolved"]
        (['fitness', 'generation', 'evolved', 'params', 'model', 'phenotype', 'plant_seed', \
'terms'], {'a': 0.5})
        """
        best: dict[str, Any] = {
            "fitness": float(fitness),
            "generation": int(generation),
            "evolved": {n: params[n] for n in evolved},
            "params": dict(params),
            "model": model,
            "phenotype": phenotype,
            "plant_seed": int(plant_seed),
            "terms": terms,
        }
        if genome is not None:
            best["genome"] = np.asarray(genome).tolist()
        best = jsonable(best)
        self.write_json("best.json", best)
        return best

    def write_summary(
        self,
        config: Config,
        best: Mapping[str, Any],
        history,
        *,
        evaluations: int,
        wall_seconds: float,
        ga_seconds: float,
        stop_reason: str,
        stops: Mapping[str, int],
        resumed: bool,
        started: str,
        finished: str,
        workers: int | None,
        scheduler: str | None,
        measures: Mapping[str, float],
        warnings: Sequence[str],
    ) -> dict[str, Any]:
        """Write ``summary.json`` (last: its presence marks a finished run) from the run's
        config, its best (:meth:`write_best`'s data), its history and the facts of the
        run; return its data.

        Examples
        --------
        >>> import tempfile, pandas as pd
        >>> from growsim.experiment import load_config
        >>> rd = RunDir(tempfile.mkdtemp())
        >>> cfg = load_config("experiments/quickstart.toml")
        >>> best = {"fitness": 2.0, "generation": 1, "phenotype": "plant", "terms": {}}
        >>> s = rd.write_summary(cfg, best, pd.DataFrame({"generation": [0, 1]}),
        ...     evaluations=20, wall_seconds=1.0, ga_seconds=0.5, stop_reason="generations",
        ...     stops={}, resumed=False, started="", finished="", workers=None,
        ...     scheduler=None, measures={}, warnings=[])
        >>> s["generations"], s["best_fitness"], rd.is_complete()
        (2, 2.0, True)
        """

        summary = {
            "experiment": config.experiment.name,
            "description": config.experiment.description,
            "model": config.model.kind,
            "phenotype": best["phenotype"],
            "objectives": [o.kind for o in config.objective],
            "seed": config.experiment.seed,
            "best_fitness": float(best["fitness"]),
            "best_generation": int(best["generation"]),
            "generations": int(history["generation"].max()) + 1 if len(history) else 0,
            "evaluations": int(evaluations),
            "wall_seconds": round(wall_seconds, 3),
            "ga_seconds": round(ga_seconds, 3),
            "history_seconds": float(history["seconds"].max()) if "seconds" in history else None,
            "stop_reason": str(stop_reason),
            "failures": int(history["failures"].sum()) if "failures" in history else 0,
            "stops": stops,
            "resumed": bool(resumed),
            "started": started,
            "finished": finished,
            "growsim_version": __version__,
            "workers": workers,
            "scheduler": scheduler,
            "measures": measures,
            "terms": best["terms"],
            "warnings": list(warnings),
        }
        summary = jsonable(summary)
        self.write_json("summary.json", summary)
        return summary


#: a record whose best phenotype has not been read yet
_UNREAD = object()


@dataclasses.dataclass
class RunRecord:
    """A run's results, the one description of a run: what :func:`growsim.experiment.run`
    returns (also named :data:`RunResult`) and what :func:`read_run` reads back.

    Fields: ``path`` (the results directory; also ``out``), ``config`` (the resolved
    config as data, as in ``config.toml``), ``best`` (``best.json``'s data), ``summary``
    (``summary.json``'s; None while unfinished) and ``history`` (DataFrame, one row per
    generation and island: generation, evaluations, best, mean, std, worst, best_so_far,
    diversity, seconds...; None when not read). Read from them: ``best_params`` (every
    model parameter of the best individual), ``best_fitness``, ``stop_reason``,
    ``finished``, and ``best_phenotype`` (also ``best_plant``): what the best grows, read
    or grown again on first use (None when that fails; :meth:`phenotype` raises
    instead).

    Examples
    --------
    >>> r = read_run("runs/quickstart-20261122-101500")  # doctest: +SKIP
    >>> r.best_fitness, r.phenotype().phenotype  # doctest: +SKIP
    (112.5, 'plant')
    >>> rec = RunRecord(Path("r"), {}, {"fitness": 2.0, "params": {"f": 0.5}})
    >>> rec.out, rec.best_fitness, rec.best_params, rec.finished, rec.stop_reason
    (PosixPath('r'), 2.0, {'f': 0.5}, False, '')
    """

    path: Path
    config: dict[str, Any]
    best: dict[str, Any]
    summary: dict[str, Any] | None = None
    history: Any = None
    _phenotype: Any = dataclasses.field(default=_UNREAD, init=False, repr=False, compare=False)

    @classmethod
    def of_run(cls, rd: RunDir, best, summary, history, phenotype) -> RunRecord:
        """The record of a run that just finished in ``rd`` (its best phenotype as grown:
        None when growing it failed)."""
        rec = cls(rd.path, rd.read_config(), best, summary, history)
        rec._phenotype = phenotype
        return rec

    @property
    def out(self) -> Path:
        """The results directory (``path``)."""
        return self.path

    @property
    def finished(self) -> bool:
        """True when the run finished (it has a summary)."""
        return self.summary is not None

    @property
    def best_fitness(self) -> float:
        """The best fitness of the run."""
        return float(self.best["fitness"])

    @property
    def best_params(self) -> dict[str, float]:
        """Every model parameter of the best individual (``best.json``'s ``params``)."""
        return self.best["params"]

    @property
    def stop_reason(self) -> str:
        """Why the GA stopped (``""`` while unfinished)."""
        return str((self.summary or {}).get("stop_reason", ""))

    @property
    def best_phenotype(self):
        """The best phenotype (see :meth:`phenotype`), or None when it cannot be had."""
        if self._phenotype is _UNREAD:
            try:
                self._phenotype = self.phenotype()
            except Exception as exc:  # the table and history stay readable without it
                log.warning("%s: the best phenotype could not be read: %s", self.path, exc)
                self._phenotype = None
        return self._phenotype

    @property
    def best_plant(self):
        """The best phenotype (named for plant models)."""
        return self.best_phenotype

    def phenotype(self):
        """The best phenotype: as the run grew it, else its saved ``best_<kind>.npz``,
        else grown again from ``best.json`` and the model of ``config.toml`` (no objective
        is built) by :meth:`growsim.experiment.fitness.Fitness.phenotype_of`."""
        if self._phenotype is not _UNREAD and self._phenotype is not None:
            return self._phenotype

        kind = self.best.get("phenotype", "plant")
        saved = RunDir(self.path).phenotype_path(kind)
        if saved.is_file():
            return load_phenotype(saved)
        mp = plan_model(validate(self.config, str(self.path / "config.toml")))
        return mp.fitness().phenotype_of(self.best["params"]).phenotype


#: the name :func:`growsim.experiment.run` users know: the same class as :class:`RunRecord`
RunResult = RunRecord


def _read_json(path: Path) -> dict:
    try:
        return json.loads(path.read_text())
    except (OSError, ValueError) as exc:
        raise UserInputError(f"{path}: unreadable ({exc})") from None


def read_run(path: str | Path, *, finished: bool = True, history: bool = True) -> RunRecord:
    """Read a results directory: config, best, summary and history.

    ``finished=True`` refuses a run without ``summary.json``; ``finished=False`` reads
    what is there (``best.json`` and ``config.toml`` at least, e.g. for ``growsim show``
    of a run still going).
    """
    rd = RunDir(path)
    if finished and not rd.summary_path.is_file():
        raise UserInputError(f"{rd.path}: not a finished growsim run (no summary.json)")
    if not rd.best_path.is_file() or not rd.config_path.is_file():
        raise UserInputError(f"{rd.path}: not a growsim results directory (no best.json)")
    config = rd.read_config()
    summary = _read_json(rd.summary_path) if rd.summary_path.is_file() else None
    frame = None
    if history and rd.history_path.is_file():
        try:
            frame = pd.read_parquet(rd.history_path)
        except (OSError, ValueError) as exc:
            raise UserInputError(f"{rd.history_path}: unreadable ({exc})") from None
    return RunRecord(rd.path, config, _read_json(rd.best_path), summary, frame)


def load_run(path: str | Path) -> RunRecord:
    """Read a finished results directory back (:func:`read_run` with its history): the
    same :class:`RunRecord` that :func:`growsim.experiment.run` returned.

    Examples
    --------
    >>> r = load_run("runs/quickstart-20261122-101500")  # doctest: +SKIP
    >>> r.best_plant.height()  # doctest: +SKIP
    41.2
    """
    return read_run(path)


def best_phenotype(path: str | Path):
    """The best phenotype of a results directory: its saved ``best_<kind>.npz``, or grown
    again from ``best.json`` and the model of ``config.toml`` (no objective is built).

    Examples
    --------
    >>> best_phenotype("runs/quickstart-20261122-101500").n_segments  # doctest: +SKIP
    1023
    """
    return read_run(path, finished=False, history=False).phenotype()


#: the name used before phenotypes other than plants existed
best_plant = best_phenotype


def find_runs(dirs: Sequence[str | Path]) -> list[RunRecord]:
    """Every finished run (a directory with ``summary.json``) in or under ``dirs``.

    Examples
    --------
    >>> find_runs(["runs/quickstart-20261122-101500"])  # doctest: +SKIP
    [RunRecord(path=PosixPath('runs/quickstart-20261122-101500'), ...)]
    """
    if not dirs:
        raise UserInputError("compare: give at least one results directory")
    seen: set[Path] = set()
    runs: list[RunRecord] = []
    skipped: list[Path] = []
    for d in dirs:
        d = Path(d)
        if not d.is_dir():
            raise UserInputError(f"{d}: no such directory")
        found = sorted(p.parent for p in d.rglob("summary.json"))
        if not found:
            # `growsim compare runs/*` also meets report directories: skip them, but say so
            skipped.append(d)
            continue
        for p in found:
            rp = p.resolve()
            if rp not in seen:
                seen.add(rp)
                runs.append(read_run(p))
    if not runs:
        where = ", ".join(str(d) for d in skipped)
        raise UserInputError(f"{where}: holds no finished growsim run (no summary.json)")
    for d in skipped:
        log.warning("%s: no finished growsim run here; skipped", d)
    return runs


def plot_fitness(history, path, *, title: str | None = None) -> Path:
    """Plot a GA history (a DataFrame with ``generation`` and some of ``best``, ``mean``,
    ``best_so_far``) to a PNG with matplotlib (Agg backend), with a legend: the best and
    the mean fitness of each generation and the best so far, drawn dashed on top (it
    lies on the best wherever the best improves). With an ``island`` column, islands are
    pooled: best is the max, mean the mean over islands. (``worst`` is not drawn: an
    evaluation that failed scores the worst value there is, which would flatten the
    rest.)

    Examples
    --------
    >>> import tempfile, pathlib, pandas as pd
    >>> h = pd.DataFrame({"generation": [0, 1, 2], "best": [1, 2, 3], "mean": [0, 1, 2]})
    >>> plot_fitness(h, pathlib.Path(tempfile.mkdtemp()) / "f.png").exists()
    True
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    if not isinstance(history, pd.DataFrame) or "generation" not in history.columns:
        raise UserInputError("plot_fitness: history needs a 'generation' column")
    # column, how islands are pooled, line style (best so far: dashed, on top)
    styles = {
        "best": ("max", {"color": "tab:blue", "linewidth": 2.5, "zorder": 2}),
        "mean": ("mean", {"color": "tab:orange", "linewidth": 1.5, "zorder": 2}),
        "best_so_far": (
            "max",
            {"color": "black", "linestyle": "--", "linewidth": 1.5, "zorder": 3},
        ),
    }
    cols = [c for c in styles if c in history.columns]
    if not cols:
        raise UserInputError("plot_fitness: history has none of best, mean, best_so_far")
    path = Path(path)
    if path.suffix.lower() != ".png":
        raise UserInputError(f"{path}: plots are written as .png")
    g = history.groupby("generation")
    fig, ax = plt.subplots(figsize=(6, 4), dpi=100)
    try:
        for c in cols:
            how, style = styles[c]
            s = g[c].agg(how)
            ax.plot(s.index, s.values, label=c.replace("_", " "), **style)
        ax.set_xlabel("generation")
        ax.set_ylabel("fitness")
        if title:
            ax.set_title(title)
        ax.grid(alpha=0.3)
        ax.legend()
        fig.tight_layout()
        atomic_write(path, lambda fh: fig.savefig(fh, format="png"))
    finally:
        plt.close(fig)
    return path
