"""The 3D IFS (fractal) tree of Kuwahara, Shiwa & Kishino (ATR TR-C-0135, 1996).

The tree is the trunk ``OS`` (from ``(0, 0, 0)`` to ``(0, 1, 0)``, y up) and every
composition of ``N`` contraction maps applied to it, to ``depth`` levels::

    w_n = Trans(0, y_n, 0) Rot_y(theta_y_n) Rot_z(-theta_z_n) Scale(s_n)

Parameters per map ``n = 1..N`` (named ``s_n``, ``y_n``, ``theta_z_n``, ``theta_y_n``):

- ``s_n``: length of the branch relative to its parent, ``[0.1, 0.7]``;
- ``y_n``: where on the parent the branch starts (fraction of its length): ``[0.3, 0.6]``
  for map 1 (the leader), ``[0.2, 1.0]`` for the others;
- ``theta_z_n``: tilt away from the parent's axis, ``[0, 90]`` degrees;
- ``theta_y_n``: azimuth about the parent's axis, degrees: ``[0, 360]`` for map 1; branch
  map ``k`` (``k = 2..N``) gets the ``(k-1)``-th of ``N - 1`` equal sectors (for ``N = 5``
  the quarters ``[0, 90], [90, 180], ...``), which removes the map-order symmetry.

These are the paper's ranges (its appendix code), generalised to any ``N``. Two integer
parameters complete the spec: ``n_maps`` (``N``, default 5) and ``depth`` (default 5: 3,906
segments). Fix them in a config; the GA evolves the map parameters.

Leaves (beyond the paper, for fitting leafy trees in pictures): ``leaves`` per leaf-bearing
branch (the tips and the branches whose children are all tips, as Honda's tree; default
0: the paper's bare tree) and ``leaf_radius`` (their size, in trunk lengths), drawn as
Honda's leaves (:func:`growsim.kernels.honda.leaves_kernel`, cut angle :data:`LEAF_CUT`).
"""

from __future__ import annotations

import itertools
from collections.abc import Iterator, Mapping
from typing import ClassVar

import numpy as np

from growsim.errors import ResourceError, UserInputError
from growsim.kernels.honda import leaves_kernel
from growsim.kernels.ifs3d import compose_tree, n_segments
from growsim.models.base import Model, Param, resolve_params
from growsim.phenotypes.plant import LEAF, STEM, Plant

__all__ = [
    "DEFAULT_DEPTH",
    "DEFAULT_N_MAPS",
    "LEAF_CUT",
    "LEAF_PARAMS",
    "MAX_SEGMENTS",
    "MODEL",
    "NAME",
    "PARAMS",
    "PRESETS",
    "RADIUS_RATIO",
    "check_size",
    "compare_maps",
    "develop",
    "map_groups",
    "maps_from_params",
    "param_spec",
]

NAME = "ifs3d"
DEFAULT_N_MAPS = 5
DEFAULT_DEPTH = 5
#: Largest tree :func:`develop` builds (about 10 MB of segment arrays per million).
MAX_SEGMENTS = 2_000_000
#: Segment radius as a fraction of the segment's length (a slender branch).
RADIUS_RATIO = 0.04
#: Cut angle of the leaves' hexagonal prism (Honda's ``leaf_cut`` default, degrees).
LEAF_CUT = 40.0

#: The leaves' parameters, after the maps in :func:`param_spec`: none by default (the
#: paper's bare tree), so a config that does not name them grows the paper's tree.
LEAF_PARAMS: tuple[Param, ...] = (
    Param("leaves", 0, 8, 0, kind="int", doc="leaves per leaf-bearing branch (0: bare)"),
    Param("leaf_radius", 0.0, 0.2, 0.02, doc="leaf hexagon radius, in trunk lengths"),
)

_FIELDS = ("s", "y", "theta_z", "theta_y")


def _map_params(n_maps: int) -> list[Param]:
    out = []
    for k in range(1, n_maps + 1):
        if k == 1:
            y_lo, y_hi, ty_lo, ty_hi = 0.3, 0.6, 0.0, 360.0
        else:
            sector = 360.0 / (n_maps - 1)
            y_lo, y_hi = 0.2, 1.0
            ty_lo, ty_hi = sector * (k - 2), sector * (k - 1)
        out += [
            Param(f"s_{k}", 0.1, 0.7, 0.5, doc=f"length ratio of branch {k}"),
            Param(f"y_{k}", y_lo, y_hi, round(0.5 * (y_lo + y_hi), 6), doc=f"start of branch {k}"),
            Param(f"theta_z_{k}", 0.0, 90.0, 0.0 if k == 1 else 45.0, unit="deg",
                  doc=f"tilt of branch {k}"),
            Param(f"theta_y_{k}", ty_lo, ty_hi, ty_lo, unit="deg", doc=f"azimuth of branch {k}"),
        ]  # fmt: skip
    return out


def param_spec(fixed: Mapping[str, float] | None = None) -> tuple[Param, ...]:
    """The parameter spec for ``fixed["n_maps"]`` maps (default 5).

    Returns ``n_maps``, ``depth`` (int params), then ``s_k, y_k, theta_z_k, theta_y_k`` for
    ``k = 1..n_maps``, then :data:`LEAF_PARAMS` (``leaves``, ``leaf_radius``).

    Examples
    --------
    >>> [p.name for p in param_spec({"n_maps": 2})][:6]
    ['n_maps', 'depth', 's_1', 'y_1', 'theta_z_1', 'theta_y_1']
    >>> len(param_spec()), param_spec()[-1].name
    (24, 'leaf_radius')
    """
    fixed = dict(fixed or {})
    head = (
        Param("n_maps", 1, 12, DEFAULT_N_MAPS, kind="int", doc="number of maps N"),
        Param("depth", 0, 10, DEFAULT_DEPTH, kind="int", doc="levels of composition"),
    )
    n_maps = int(head[0].check(fixed.get("n_maps", DEFAULT_N_MAPS), "ifs3d."))
    return (*head, *_map_params(n_maps), *LEAF_PARAMS)


#: The spec for the default ``N = 5``.
PARAMS = param_spec()


def _preset(rows, depth=DEFAULT_DEPTH) -> dict[str, float]:
    out = {"n_maps": float(len(rows)), "depth": float(depth)}
    for k, row in enumerate(rows, start=1):
        for f, v in zip(_FIELDS, row):
            out[f"{f}_{k}"] = float(v)
    # the paper's trees are bare
    out.update({p.name: float(p.default) for p in LEAF_PARAMS})
    return out


#: Named trees. ``table1``: the paper's test tree (its Table 1, a symmetric tree rendered to
#: make the target silhouettes); ``paper_ga`` and ``paper_gradient``: the paper's estimates
#: of it (its Table 2), by its GA (cross-correlation about 0.661) and by the
#: optimal-gradient method (about 0.756).
PRESETS: dict[str, dict[str, float]] = {
    "table1": _preset(
        [
            (0.50, 0.40, 0.0, 0.0),
            (0.50, 0.40, 45.0, 0.0),
            (0.50, 0.40, 45.0, 90.0),
            (0.50, 0.40, 45.0, 180.0),
            (0.50, 0.40, 45.0, 270.0),
        ]
    ),
    "paper_ga": _preset(
        [
            (0.409, 0.562, 36.563, 261.562),
            (0.480, 0.394, 71.719, 27.422),
            (0.423, 0.344, 5.625, 158.203),
            (0.522, 0.300, 37.969, 222.187),
            (0.423, 0.262, 46.406, 336.094),
        ]
    ),
    "paper_gradient": _preset(
        [
            (0.546, 0.373, 3.202, 291.578),
            (0.468, 0.505, 42.056, 3.229),
            (0.447, 0.467, 42.215, 92.449),
            (0.491, 0.460, 41.746, 182.266),
            (0.445, 0.470, 38.311, 272.716),
        ]
    ),
}


def maps_from_params(params: Mapping[str, float]) -> np.ndarray:
    """The ``(N, 4)`` map table ``(s, y, theta_z, theta_y)`` of a resolved parameter dict.

    Examples
    --------
    >>> maps_from_params(PRESETS["table1"])[2].tolist()
    [0.5, 0.4, 45.0, 90.0]
    """
    n = int(params.get("n_maps", DEFAULT_N_MAPS))
    try:
        return np.array(
            [[float(params[f"{f}_{k}"]) for f in _FIELDS] for k in range(1, n + 1)],
            dtype=np.float64,
        )
    except KeyError as exc:
        raise UserInputError(f"ifs3d: missing parameter {exc.args[0]}") from None


def check_size(n_maps: int, depth: int) -> int:
    """Segment count of a tree, or :class:`ResourceError` above :data:`MAX_SEGMENTS`.

    Examples
    --------
    >>> check_size(5, 5)
    3906
    """
    m = n_segments(n_maps, depth)
    if m > MAX_SEGMENTS:
        raise ResourceError(
            f"ifs3d: n_maps={n_maps}, depth={depth} needs {m:,} segments "
            f"(limit {MAX_SEGMENTS:,}); lower depth or n_maps"
        )
    return m


def map_groups(params, names) -> Iterator[tuple[np.ndarray, np.ndarray, int]]:
    """The rows of a parameter matrix as map tables, grouped by tree size.

    ``params`` ``(n, p)``: one parameter set per row, the columns labelled by ``names``:
    ``s_k, y_k, theta_z_k, theta_y_k`` for every map ``k``, and ``n_maps``, ``depth``
    (rounded; :data:`DEFAULT_N_MAPS`, :data:`DEFAULT_DEPTH` when absent). Yields, for each
    ``(n_maps, depth)`` in increasing order, ``(rows, maps, depth)``: the row indices
    ``(k,)``, their map tables ``(k, N, 4)`` (fields ordered as :func:`maps_from_params`)
    and the depth, ready for :func:`growsim.kernels.ifs3d.score_population`. Rows of
    leafy trees (``leaves`` and ``leaf_radius`` columns both positive) are not yielded: the
    population kernel draws bare trees only, so those are developed one by one. Raises
    :class:`ResourceError` for a tree above :data:`MAX_SEGMENTS` (:func:`check_size`) and
    :class:`UserInputError` for a missing map column.

    Examples
    --------
    >>> names = ["n_maps", "depth", "s_1", "y_1", "theta_z_1", "theta_y_1"]
    >>> params = [[1, 2, 0.5, 0.4, 0, 0], [1, 3, 0.6, 0.3, 10, 20], [1, 2, 0.7, 0.5, 0, 0]]
    >>> [(rows.tolist(), maps.shape, d) for rows, maps, d in map_groups(params, names)]
    [([0, 2], (2, 1, 4), 2), ([1], (1, 1, 4), 3)]
    """
    params = np.atleast_2d(np.asarray(params, dtype=np.float64))
    col = {name: i for i, name in enumerate(names)}
    n = params.shape[0]
    if "n_maps" in col:
        n_maps = np.round(params[:, col["n_maps"]]).astype(np.int64)
    else:
        n_maps = np.full(n, DEFAULT_N_MAPS)
    if "depth" in col:
        depth = np.round(params[:, col["depth"]]).astype(np.int64)
    else:
        depth = np.full(n, DEFAULT_DEPTH)
    bare = np.ones(n, dtype=bool)
    if "leaves" in col and "leaf_radius" in col:
        leafy = np.round(params[:, col["leaves"]]) > 0
        bare = ~(leafy & (params[:, col["leaf_radius"]] > 0.0))
    for N, d in sorted(set(zip(n_maps[bare].tolist(), depth[bare].tolist()))):
        rows = np.flatnonzero((n_maps == N) & (depth == d) & bare)
        check_size(N, d)
        maps = np.empty((rows.size, N, 4))
        for k in range(1, N + 1):
            for f, field in enumerate(_FIELDS):
                name = f"{field}_{k}"
                if name not in col:
                    raise UserInputError(f"ifs3d: missing parameter {name}")
                maps[:, k - 1, f] = params[rows, col[name]]
        yield rows, maps, d


def develop(params: Mapping[str, float] | None = None, *, seed: int = 0, env=None):
    """Build the IFS tree as a :class:`growsim.phenotypes.plant.Plant`.

        ``params``: any subset of :func:`param_spec` (for ``params["n_maps"]``); the rest take
        their defaults. The model is deterministic: ``seed`` is only recorded, ``env`` unused.
        Segment ``i`` is one composition of maps (order: level by level, see
        :mod:`growsim.kernels.ifs3d`); ``order`` is its level, ``radius`` is
        :data:`RADIUS_RATIO` times its length, ``data["scale"]`` its length ratio to the trunk.
    With ``leaves > 0`` the leaves follow the stems (``kind == LEAF``; ``parent`` their
    branch, ``order`` and ``data["scale"]`` its own).

        Examples
        --------
        >>> tree = develop(PRESETS["table1"])
        >>> tree.n_segments, round(tree.height(), 3)
        (3906, 1.0)
        >>> develop({**PRESETS["table1"], "leaves": 2}).n_leaves  # 2 on each of 3,750 branches
        7500
    """
    params = dict(params or {})
    spec = param_spec(params)
    p = resolve_params(spec, params, where="ifs3d.")
    n_maps = int(p["n_maps"])
    depth = int(p["depth"])
    check_size(n_maps, depth)
    maps = maps_from_params(p)
    start, end = compose_tree(maps, depth)
    m = start.shape[0]
    idx = np.arange(m, dtype=np.int64)
    level = np.zeros(m, dtype=np.int32)
    parent = np.full(m, -1, dtype=np.int64)
    off, size = 1, 1
    for k in range(1, depth + 1):
        size *= n_maps
        sl = slice(off, off + size)
        level[sl] = k
        prev_off = off - size // n_maps
        parent[sl] = prev_off + (idx[sl] - off) // n_maps
        off += size
    length = np.linalg.norm(end - start, axis=1)
    radius = RADIUS_RATIO * length
    kind = np.full(m, STEM, dtype=np.int8)
    if int(p["leaves"]) > 0 and p["leaf_radius"] > 0.0:
        la, lb, lr, lpar = leaves_kernel(
            start, end, parent, int(p["leaves"]), p["leaf_radius"], np.radians(LEAF_CUT)
        )
        start, end = np.concatenate([start, la]), np.concatenate([end, lb])
        radius = np.concatenate([radius, lr])
        parent = np.concatenate([parent, lpar])
        level = np.concatenate([level, level[lpar]])
        kind = np.concatenate([kind, np.full(la.shape[0], LEAF, dtype=np.int8)])
        length = np.concatenate([length, length[lpar]])  # a leaf's scale: its branch's
    return Plant(
        start=start,
        end=end,
        radius=radius,
        parent=parent,
        order=level,
        kind=kind,
        data={"scale": length},
        meta={"model": NAME, "params": p, "seed": int(seed)},
    )


def compare_maps(fitted, reference, *, azimuth_period: float = 360.0) -> dict:
    """Errors of fitted maps against reference maps, up to the order of the maps.

    ``fitted``, ``reference``: ``(N, 4)`` map tables ``(s, y, theta_z, theta_y)`` (see
    :func:`maps_from_params`). Over every pairing of fitted to reference maps, the one
    with the smallest worst error in units of the tolerances (0.05 in ``s`` and ``y``,
    5 degrees in the angles) is kept. Azimuths are compared on the circle; for a reference
    map without tilt (``theta_z = 0``, a leader whose subtree is a rotated copy of the
    tree) modulo ``azimuth_period`` (90 for the 4-fold symmetric Table 1 tree).

    Returns ``{"order": (N,) fitted index per reference map, "errors": (N, 4) absolute
    errors, "max_error": (4,) worst per field, "within": bool}`` (``within``: all errors
    inside the tolerances).

    Examples
    --------
    >>> import numpy as np
    >>> ref = maps_from_params(PRESETS["table1"])
    >>> fit = ref[[0, 2, 1, 4, 3]] + [0.01, -0.01, 1.0, 2.0]
    >>> compare_maps(fit, ref, azimuth_period=90)["within"]
    True
    """

    fitted = np.asarray(fitted, dtype=np.float64)
    reference = np.asarray(reference, dtype=np.float64)
    if fitted.shape != reference.shape or fitted.ndim != 2 or fitted.shape[1] != 4:
        raise UserInputError(
            f"compare_maps: expected two (N, 4) tables, got {fitted.shape} and {reference.shape}"
        )
    n = fitted.shape[0]
    if n > 8:
        raise UserInputError("compare_maps: at most 8 maps (it tries every pairing)")
    tol = np.array([0.05, 0.05, 5.0, 5.0])
    # err[i, j, f]: reference map i against fitted map j
    d = np.abs(reference[:, None, :] - fitted[None, :, :])
    period = np.where(reference[:, 2] == 0.0, float(azimuth_period), 360.0)[:, None]
    dy = np.mod(d[..., 3], period)
    d[..., 3] = np.minimum(dy, period - dy)
    worst = (d / tol).max(axis=2)
    perms = np.array(list(itertools.permutations(range(n))))
    cost = worst[np.arange(n)[None, :], perms].max(axis=1)
    best = perms[int(np.argmin(cost))]
    errors = d[np.arange(n), best]
    return {
        "order": best,
        "errors": errors,
        "max_error": errors.max(axis=0),
        "within": bool((errors <= tol).all()),
    }


class IFS3D(Model):
    """The IFS tree under the model contract (:class:`growsim.models.base.Model`):
    :func:`param_spec`, :data:`PRESETS` and :func:`develop` of this module, and the
    capability :meth:`map_groups` that the silhouette objective's population fast path
    uses.

    Examples
    --------
    >>> len(MODEL.param_spec({"n_maps": 3}))
    16
    """

    name = NAME
    phenotype = "plant"
    capabilities = frozenset({"map_groups"})
    params = PARAMS
    presets = PRESETS
    #: the names of 0.1 (they meant the paper, not a random seed): taken until 0.3
    preset_aliases: ClassVar[dict[str, str]] = {
        "seed_ga": "paper_ga",
        "seed_gradient": "paper_gradient",
    }

    def param_spec(self, fixed=None) -> tuple[Param, ...]:
        """See :func:`param_spec`."""
        return param_spec(fixed)

    def develop(self, params=None, *, seed=None, env=None) -> Plant:
        """See :func:`develop`."""
        return develop(params, seed=0 if seed is None else seed, env=env)

    def map_groups(self, params, names):
        """See :func:`map_groups`."""
        return map_groups(params, names)


#: The registered model (``growsim.models.MODELS["ifs3d"]``).
MODEL = IFS3D()
