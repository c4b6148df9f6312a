"""Atomic file writes: every file growsim writes appears whole or not at all.

A temporary file is written in the target's directory, flushed to disk and renamed onto
the target (``os.replace``, atomic on POSIX), so a reader or a crash (SIGKILL included)
never sees half a file, and a failed write leaves the earlier file untouched.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import IO, Any

from growsim.errors import UserInputError

__all__ = ["atomic_path", "atomic_write"]


def _file_mode() -> int:
    # mkstemp makes 0600 files; what growsim writes is meant to be shared like any file
    # the user writes, so give it the permissions the umask allows
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


def _temp_beside(path: Path, suffix: str) -> str:
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        raise UserInputError(f"{path}: directory {parent} does not exist")
    try:
        fd, name = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=suffix, dir=parent)
    except OSError as exc:
        raise UserInputError(f"{path}: cannot write in {parent} ({exc.strerror})") from None
    os.fchmod(fd, _file_mode())
    os.close(fd)
    return name


def atomic_write(
    path: str | os.PathLike, data: str | bytes | Callable[[IO[Any]], Any], *, mode: str = "wb"
) -> Path:
    """Write ``data`` to ``path`` atomically and return ``path``.

    ``data`` is text (written as UTF-8), bytes, or a callable ``write(fileobj)`` that fills
    the open temporary file (opened with ``mode``: ``"wb"`` or ``"w"``). Raises
    :class:`UserInputError` naming ``path`` when its directory does not exist or is not
    writable.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> atomic_write(d / "x.json", "{}").read_text()
    '{}'
    >>> atomic_write(d / "a.txt", lambda f: f.write("hi"), mode="w").read_text()
    'hi'
    """
    path = Path(path)
    name = _temp_beside(path, ".tmp")
    try:
        if callable(data):
            with open(name, mode) as fh:
                data(fh)
                fh.flush()
                os.fsync(fh.fileno())
        else:
            raw = data.encode("utf-8") if isinstance(data, str) else bytes(data)
            with open(name, "wb") as fh:
                fh.write(raw)
                fh.flush()
                os.fsync(fh.fileno())
        os.replace(name, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(name)
        raise
    return path


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary path beside ``path`` with the same suffix, for writers that take
    a file name (VTK, imageio, Parquet); it is renamed onto ``path`` if the block succeeds
    and wrote a non-empty file, and deleted otherwise.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> with atomic_path(d / "a.txt") as tmp:
    ...     _ = tmp.write_text("hi")
    >>> (d / "a.txt").read_text()
    'hi'
    """
    path = Path(path)
    tmp = Path(_temp_beside(path, f".tmp{path.suffix}"))
    try:
        yield tmp
        if not tmp.is_file() or tmp.stat().st_size == 0:
            raise OSError(f"{path.name}: the writer produced no file")
        os.replace(tmp, path)
    finally:
        with contextlib.suppress(FileNotFoundError):
            tmp.unlink()
