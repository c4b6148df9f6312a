"""The skeleton every plant shares: segment kinds, and the segment arrays the environment's
passes read, from a Plant or a mapping, checked.

Every pass (gravity, water, light) takes a :class:`growsim.phenotypes.plant.Plant` or any
mapping with the arrays ``start``, ``end`` ``(n, 3)``, ``radius``, ``parent`` ``(n,)`` (and
optionally ``kind``), stored parents first (``parent[i] < i``, -1 for a root) so that one pass from
the tips down (or from the roots up) visits every segment after (before) its children.
A bad array is refused here, naming the pass, the array and the segment, never deep in a
kernel.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from growsim.errors import UserInputError
from growsim.kernels.gravity import radius_end_kernel

__all__ = ["LEAF", "STEM", "checked_array", "radius_end", "skeleton_arrays"]

#: ``kind`` of a woody segment (trunk, branch, twig).
STEM = 0
#: ``kind`` of a leaf segment (its radius is half the blade width).
LEAF = 1


def checked_array(
    who: str,
    name: str,
    value,
    shape_tail: tuple[int, ...],
    n: int | None,
    *,
    dtype=np.float64,
    finite: bool = True,
):
    """``value`` as a contiguous ``dtype`` array of shape ``(n, *shape_tail)`` (finite,
    unless ``finite=False``), else :class:`UserInputError` naming ``who``, the array and
    the first bad segment.

    Examples
    --------
    >>> checked_array("water", "light", [1.0, 2.0], (), 2).tolist()
    [1.0, 2.0]
    >>> checked_array("water", "light", [1.0, float("nan")], (), 2)
    Traceback (most recent call last):
    ...
    growsim.errors.UserInputError: water: light: segment 1 is not finite
    """
    try:
        arr = np.ascontiguousarray(value, dtype=dtype)
    except (TypeError, ValueError) as exc:
        raise UserInputError(
            f"{who}: {name}: cannot convert to {np.dtype(dtype)} ({exc})"
        ) from None
    if arr.ndim != 1 + len(shape_tail) or arr.shape[1:] != shape_tail:
        want = "(n" + "".join(f", {s}" for s in shape_tail) + ")"
        raise UserInputError(f"{who}: {name}: expected shape {want}, got {arr.shape}")
    if n is not None and arr.shape[0] != n:
        raise UserInputError(f"{who}: {name}: has {arr.shape[0]} rows, expected {n}")
    # the sum of finite values is finite unless it overflows: one cheap pass, and the
    # row-by-row search only when the sum says something may be wrong
    if not finite or np.isfinite(np.add.reduce(arr, axis=None)):
        return arr
    bad = ~np.isfinite(arr).reshape(arr.shape[0], -1).all(1) if arr.size else np.zeros(0, bool)
    if bad.any():
        raise UserInputError(f"{who}: {name}: segment {int(np.flatnonzero(bad)[0])} is not finite")
    return arr


def radius_end(parent: np.ndarray, kind: np.ndarray, radius: np.ndarray) -> np.ndarray:
    """``(n,)`` radius at each segment's far end when a model gave none: the largest radius
    of its children of the same kind, capped by its own radius (a tip does not narrow).

    Examples
    --------
    >>> import numpy as np
    >>> radius_end(np.array([-1, 0]), np.zeros(2, np.int8), np.array([0.2, 0.1])).tolist()
    [0.1, 0.1]
    """

    parent = np.ascontiguousarray(parent, dtype=np.int64)
    kind = np.ascontiguousarray(kind, dtype=np.int8)
    radius = np.ascontiguousarray(radius, dtype=np.float64)
    return radius_end_kernel(parent, kind, radius, np.empty(len(radius)))


def skeleton_arrays(skeleton: Any, who: str, *, topology: bool = True) -> dict[str, Any]:
    """``start``, ``end``, ``radius``, ``parent``, ``kind`` (``None`` when not given) and
    ``data`` (a Plant's per-segment extras, or the mapping itself) of a Plant or a mapping,
    checked: shapes, finite coordinates and radii, radii >= 0, kinds 0 or 1, parents first.
    ``topology=False`` (a pass that needs no tree, e.g. the light): ``parent`` is neither
    required nor read (``None``).

    Examples
    --------
    >>> import numpy as np
    >>> a = skeleton_arrays({"start": np.zeros((1, 3)), "end": np.ones((1, 3)),
    ...                      "radius": [0.1], "parent": [-1]}, "gravity")
    >>> a["parent"].tolist(), a["kind"]
    ([-1], None)
    >>> skeleton_arrays({"start": np.zeros((2, 3)), "end": np.ones((2, 3)),
    ...                  "radius": [0.1, 0.1], "parent": [1, -1]}, "water")
    ... # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    growsim.errors.UserInputError: water: segment 0 has parent 1: parents must come before ...
    """
    if isinstance(skeleton, Mapping):
        get, data = skeleton.get, skeleton
    elif all(hasattr(skeleton, k) for k in ("start", "end", "radius")):

        def get(k, default=None):
            return getattr(skeleton, k, default)

        data = getattr(skeleton, "data", None) or {}
    else:
        raise UserInputError(
            f"{who}: expected a Plant or a mapping of segment arrays, got {type(skeleton).__name__}"
        )
    need = ("start", "end", "radius", "parent") if topology else ("start", "end", "radius")
    missing = [k for k in need if get(k) is None]
    if missing:
        raise UserInputError(f"{who}: missing segment arrays {missing}")
    start = checked_array(who, "start", get("start"), (3,), None)
    n = start.shape[0]
    end = checked_array(who, "end", get("end"), (3,), n)
    radius = checked_array(who, "radius", get("radius"), (), n)
    if n and radius.min() < 0:
        raise UserInputError(f"{who}: radius: segment {int(np.argmin(radius))} is negative")
    if not topology or get("parent") is None:  # not read (checked above when needed)
        parent = None
    else:
        parent = _parents(who, get("parent"), n)
    kind = get("kind")
    if kind is not None:
        kind = np.ascontiguousarray(kind, dtype=np.int8)
        if kind.shape != (n,) or np.any((kind != 0) & (kind != 1)):
            raise UserInputError(f"{who}: kind: expected (n,) values 0 (stem) or 1 (leaf)")
    return {
        "start": start,
        "end": end,
        "radius": radius,
        "parent": parent,
        "kind": kind,
        "data": data,
    }


def _parents(who: str, value, n: int) -> np.ndarray:
    try:
        parent = np.ascontiguousarray(value, dtype=np.int64)
    except (TypeError, ValueError) as exc:
        raise UserInputError(f"{who}: parent: cannot convert to int64 ({exc})") from None
    if parent.shape != (n,):
        raise UserInputError(f"{who}: parent: expected shape ({n},), got {parent.shape}")
    bad = (parent < -1) | (parent >= np.arange(n))
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise UserInputError(
            f"{who}: segment {i} has parent {int(parent[i])}: parents must come before their "
            "children (segments stored parents first: parent[i] < i, -1 for a root)"
        )
    return parent
