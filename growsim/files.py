"""Atomic file writes: every file growsim writes appears whole or not at all; and the
conversion of NumPy values to JSON for the files written as JSON.

A temporary file is written in the target's directory, flushed to disk and renamed onto
the target (``os.replace``, atomic on POSIX), so a reader or a crash (SIGKILL included)
never sees half a file, and a failed write leaves the earlier file untouched.
"""

from __future__ import annotations

import contextlib
import math
import os
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import IO, Any

import numpy as np

from growsim.errors import UserInputError

__all__ = ["NON_FINITE", "atomic_path", "atomic_write", "json_default", "jsonable", "number"]


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


def json_default(o: Any) -> Any:
    """``default=`` of :func:`json.dumps` for NumPy scalars and arrays.

    Examples
    --------
    >>> import json, numpy as np
    >>> json.dumps({"a": np.float32(0.5), "b": np.arange(2)}, default=json_default)
    '{"a": 0.5, "b": [0, 1]}'
    """
    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    raise TypeError(f"{type(o).__name__} is not JSON-able")


#: how :func:`jsonable` writes non-finite floats (JSON has none)
NON_FINITE = ("nan", "inf", "-inf")


def number(v: Any) -> Any:
    """A value read back from :func:`jsonable`'s JSON: ``"nan"``, ``"inf"`` and ``"-inf"``
    as floats again, anything else as it is.

    Examples
    --------
    >>> number("nan"), number("-inf"), number(2.5), number("tall")
    (nan, -inf, 2.5, 'tall')
    """
    return float(v) if isinstance(v, str) and v in NON_FINITE else v


def jsonable(x: Any) -> Any:
    """``x`` as plain JSON data: NumPy values to Python, tuples to lists, keys to
    strings, and non-finite floats to strings (``"nan"``, ``"inf"``: JSON has none).

    Examples
    --------
    >>> import numpy as np
    >>> jsonable({1: (np.int64(2), float("nan")), "x": np.array([0.5])})
    {'1': [2, 'nan'], 'x': [0.5]}
    """
    if isinstance(x, dict):
        return {str(k): jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [jsonable(v) for v in x]
    if isinstance(x, np.ndarray):
        return jsonable(x.tolist())
    if isinstance(x, np.generic):
        return jsonable(x.item())
    if isinstance(x, float) and not math.isfinite(x):
        return str(x)
    return x
