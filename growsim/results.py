"""The results directory of a run: atomic writes, a lock, the paths of every file.

A run directory holds (see ``ARCHITECTURE.md``)::

    config.toml        the resolved config (written first)
    checkpoint.npz     GA state incl. RNG state (the GA writes it every generation)
    history.parquet    one row per generation (and island)
    best.json          best genome, parameters, fitness, generation
    best_plant.npz     the best Plant; best.vtp/.glb/...; best_<view>.png; fitness.png
    summary.json       written last: its presence marks a finished run
    .lock              held (flock) while a process writes here

Every file is written to a temporary name in the same directory and renamed with
``os.replace``, so a reader (or a crash) never sees half a file.
"""

from __future__ import annotations

import contextlib
import json
import os
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

from growsim.errors import UserInputError
from growsim.files import atomic_path, atomic_write

__all__ = ["RunDir", "write_parquet"]


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
    lock_path = property(lambda self: self.path / ".lock")

    def is_complete(self) -> bool:
        """True when the run finished (summary.json exists)."""
        return self.summary_path.is_file()

    @contextlib.contextmanager
    def lock(self) -> Iterator[RunDir]:
        """Hold an exclusive lock on the directory; a second holder refuses at once.

        The lock is an ``flock`` on ``.lock``: the kernel drops it when the process dies
        (even by SIGKILL), so a killed run leaves no stale lock to clean up.
        """
        try:
            self.path.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise UserInputError(f"--out {self.path}: cannot create ({exc.strerror})") from None
        if not self.path.is_dir():
            raise UserInputError(f"--out {self.path}: not a directory")
        fd = os.open(self.lock_path, os.O_RDWR | os.O_CREAT, 0o644)
        try:
            import fcntl

            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                other = os.pread(fd, 64, 0).decode(errors="replace").strip() or "?"
                raise UserInputError(
                    f"{self.path} is in use by another growsim run (pid {other}); "
                    "choose another --out"
                ) from None
            os.ftruncate(fd, 0)
            os.pwrite(fd, str(os.getpid()).encode(), 0)
            self._lock_fd = fd
            yield self
        finally:
            self._lock_fd = None
            os.close(fd)  # closing the descriptor releases the flock

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
