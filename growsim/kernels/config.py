"""One place for numba compile flags, so every kernel is cached and compiled alike.

numba keys a cached function by its own source file only: a kernel that calls a kernel of
another file keeps the callee's old code, compiled in, when only the callee's file
changes (after an edit, or an upgrade in place). So the first import of this module
compares a hash of every growsim source that compiles kernels with the one recorded
beside the cache, and on a change drops growsim's cached kernels (they compile again,
once). See :func:`drop_stale_caches`.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

import numba

#: Options for every ``@numba.njit`` in growsim. ``cache=True`` writes compiled code next
#: to the module (set ``NUMBA_CACHE_DIR`` if the package directory is read-only).
JIT = {"cache": True, "nogil": True, "fastmath": False}

#: the growsim package directory
_ROOT = Path(__file__).resolve().parents[1]


def sources_hash(root: Path = _ROOT) -> str:
    """SHA-256 of every ``.py`` file under ``root`` that compiles kernels (mentions
    ``njit``), with its path.

    Examples
    --------
    >>> len(sources_hash())
    64
    """
    h = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        text = path.read_bytes()
        if b"njit" in text:
            h.update(path.relative_to(root).as_posix().encode())
            h.update(text)
    return h.hexdigest()


def drop_stale_caches(root: Path = _ROOT) -> bool:
    """Delete growsim's numba cache files (``*.nbi``, ``*.nbc`` in its ``__pycache__``
    directories, and under ``NUMBA_CACHE_DIR`` when set) when the kernels' sources changed
    since the hash recorded in ``growsim/kernels/__pycache__/numba-sources.sha256``;
    record the new hash. Returns whether caches were dropped. A read-only install is left
    as it is.

    Examples
    --------
    >>> drop_stale_caches()  # run at import already: the sources have not changed since
    False
    """
    stamp = root / "kernels" / "__pycache__" / "numba-sources.sha256"
    try:
        current = sources_hash(root)
        if stamp.exists() and stamp.read_text() == current:
            return False
        bases = [root]
        if numba.config.CACHE_DIR:
            bases.append(Path(numba.config.CACHE_DIR))
        for base in bases:
            for path in base.rglob("*.nb[ic]"):
                if base == root or "growsim" in path.as_posix():
                    path.unlink(missing_ok=True)
        stamp.parent.mkdir(exist_ok=True)
        tmp = stamp.with_suffix(f".{id(stamp)}.tmp")
        tmp.write_text(current)
        tmp.replace(stamp)
        return True
    except OSError:  # a read-only install: numba caches elsewhere, or not at all
        return False


drop_stale_caches()


def njit(*args, **kwargs):
    """``numba.njit`` with growsim's flags; extra keyword arguments override them.

    Examples
    --------
    >>> from growsim.kernels.config import njit
    >>> @njit(cache=False)  # code typed at a prompt has no file to cache next to
    ... def add(a, b):
    ...     return a + b
    >>> add(1, 2)
    3
    """
    opts = {**JIT, **kwargs}
    if args and callable(args[0]):
        return numba.njit(**opts)(args[0])
    return numba.njit(*args, **opts)
