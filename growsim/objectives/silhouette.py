"""Silhouette matching: normalised cross-correlation of front and side projections.

After Kuwahara, Shiwa & Kishino, "fitting a 3D fractal tree to front/side tree images
with a GA" (ATR TR-C-0135, 1996), eq. 3: per view, the normalised cross-correlation of the
plant's projection ``F`` and the target silhouette ``G``; on binary images it is

    NCC = |F and G| / sqrt(|F| |G|)

(1 when they coincide, 0 when disjoint). growsim reports the mean over the two views, in
``[0, 1]`` (the seed summed them). The seed's area-ratio rejection (a plant whose total
projected area is not within 0.5x-2x of the target's scores 0) is the option
``area_rejection``.

Framing: plant projections and target pictures are framed alike (see
:mod:`growsim.kernels.ifs3d` and :mod:`growsim.images`): one scale for both views that fits
the height into the ``size x size`` raster (or the half-width about the trunk base, if
tighter), the trunk base at the horizontal centre, the lowest point on the bottom row. So a
photo of any size and margin can be a target, and the score ignores the plant's absolute
size.

Plants are drawn as thin (1-pixel supercover) lines by default, the seed's rendering; with
``line_width = "radius"`` each segment is as wide as its tube.

``blur = sigma`` (pixels, default 0) scores a smoother landscape for the search: the plant
is drawn anti-aliased (each line sample's ink spread bilinearly, so the image moves
continuously with the parameters), both it and the target are blurred by a Gaussian of
``sigma`` pixels, and the score is the NCC of these grey-level images (the seed's eq. 3 in
its general form, ``<F, G> / (|F| |G|)``): a branch one pixel off still earns partial
credit. :meth:`SilhouetteObjective.exact` always gives the binary NCC, the figure to report.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from growsim.errors import ConfigError, GrowsimError, UserInputError
from growsim.kernels.ifs3d import (
    _render,
    _render_aa,
    blur_views,
    frame_points,
    score_population,
)
from growsim.kernels.raster import draw_segments

__all__ = ["SilhouetteObjective", "blurred_ncc", "ncc", "plant_views"]


def plant_views(
    plant, size: int = 64, line_width: str = "thin", antialias: bool = False
) -> np.ndarray:
    """Front and side silhouettes ``(2, size, size)`` uint8 of any Plant, framed.

    The trunk base is the start of the first root segment (``parent == -1``). Every
    segment is drawn (stems and leaves). ``line_width``: ``"thin"`` (1-pixel lines) or
    ``"radius"`` (lines ``2 * radius`` wide, at least thin). ``antialias`` (thin lines
    only): float64 coverage in [0, 1] instead (see ``blur`` of :class:`SilhouetteObjective`).

    Examples
    --------
    >>> from growsim.models import ifs3d
    >>> v = plant_views(ifs3d.develop(ifs3d.PRESETS["table1"]), 64)
    >>> v.shape, int(v[0, 63, 32]), int(v[0, 0, 32])  # trunk base and top of the trunk
    ((2, 64, 64), 1, 1)
    """
    size = int(size)
    aa = antialias and line_width == "thin"
    img = np.zeros((2, size, size), dtype=np.float64 if aa else np.uint8)
    if plant.n_segments == 0:
        return img
    roots = np.flatnonzero(plant.parent < 0)
    base = plant.start[roots[0] if roots.size else 0]
    coords, k = frame_points(plant.start, plant.end, base, size)
    if aa:
        _render_aa(coords, img)
    elif line_width == "thin":
        _render(coords, img)
    else:
        width = 2.0 * k * plant.radius
        for v in range(2):
            draw_segments(coords[v, 0], coords[v, 1], width, img[v])
    return img


def blurred_ncc(views, target, sigma: float, area_rejection: bool = False) -> float:
    """Mean over views of ``<Fb, Gb> / (|Fb| |Gb|)``, ``Fb``, ``Gb`` blurred by ``sigma`` px.

    ``views`` ``(V, S, S)``: grey levels in [0, 1] (e.g. anti-aliased); ``target``
    ``(V, S, S)`` binary. The area rule (``area_rejection``) compares the sums of the
    unblurred images, as :func:`ncc`.

    Examples
    --------
    >>> import numpy as np
    >>> a = np.zeros((2, 16, 16)); a[:, 8, 4:12] = 1
    >>> b = np.roll(a, 1, axis=1)  # one pixel lower: binary NCC 0
    >>> # a blurred line's profile is a Gaussian: overlap at 1 px is exp(-1 / (4 sigma^2))
    >>> ncc(a, b), round(blurred_ncc(a, b, 1.5), 3)
    (0.0, 0.895)
    """
    F = np.asarray(views, dtype=np.float64)
    G = (np.asarray(target) > 0).astype(np.uint8)
    Fb = blur_views(F, sigma)
    Gb = blur_views(G, sigma)
    scores = []
    for f, g in zip(Fb, Gb):
        nf, ng = float(np.sqrt((f * f).sum())), float(np.sqrt((g * g).sum()))
        scores.append(0.0 if nf == 0 or ng == 0 else float((f * g).sum()) / (nf * ng))
    if area_rejection:
        ratio = F.sum() / max(1, G.sum())
        if ratio < 0.5 or ratio > 2.0:
            return 0.0
    return float(np.mean(scores))


def ncc(views: np.ndarray, target: np.ndarray, area_rejection: bool = False) -> float:
    """Mean over views of binary NCC ``|F and G| / sqrt(|F| |G|)``, in ``[0, 1]``.

    ``views``, ``target``: ``(V, S, S)`` arrays (non-zero = foreground). A view with an
    empty projection scores 0. With ``area_rejection``, 0 unless the total area of
    ``views`` is within 0.5x-2x of the target's.

    Examples
    --------
    >>> import numpy as np
    >>> a = np.zeros((2, 4, 4), np.uint8); a[:, 1, :] = 1
    >>> b = a.copy(); b[:, 2, :] = 1
    >>> round(ncc(a, b), 4)  # |F and G| = 4, |F| = 4, |G| = 8
    0.7071
    """
    F = np.asarray(views) > 0
    G = np.asarray(target) > 0
    scores = []
    for f, g in zip(F, G):
        nf, ng = int(f.sum()), int(g.sum())
        scores.append(0.0 if nf == 0 or ng == 0 else int((f & g).sum()) / math.sqrt(nf * ng))
    if area_rejection:
        ratio = F.sum() / max(1, G.sum())
        if ratio < 0.5 or ratio > 2.0:
            return 0.0
    return float(np.mean(scores))


def _opt_str(name, value, allowed):
    if not isinstance(value, str) or value not in allowed:
        raise ConfigError(f"silhouette.{name}: expected one of {', '.join(allowed)}, got {value!r}")
    return value


class SilhouetteObjective:
    """Match a plant's front and side silhouettes to target images (maximised, in [0, 1]).

    The target is either two pictures (``front`` and ``side`` paths, optional masks) or
    rendered from a model (``target_model`` with ``target_preset`` and/or
    ``target_params``; the seed's test case is ``target_model = "ifs3d"``,
    ``target_preset = "table1"``). Options (all keyword, as in a config table):

    ``front``, ``side`` : paths of the two pictures (both, or neither);
    ``mask_front``, ``mask_side`` : optional mask pictures (white = look here);
    ``threshold`` : ``"otsu"`` (default) or a grey level in (0, 1);
    ``polarity`` : ``"auto"`` (default), ``"dark"`` (dark tree on light) or ``"light"``;
    ``target_model``, ``target_preset``, ``target_params``, ``target_seed`` : a rendered target;
    ``size`` : raster size in pixels, 8..1024 (default 64, the seed's);
    ``area_rejection`` : the seed's 0.5x-2x area rule (default false);
    ``line_width`` : ``"thin"`` (default) or ``"radius"``;
    ``blur`` : search on anti-aliased, Gaussian-blurred views, ``sigma`` in pixels
    (default 0: the binary NCC; see the module doc). :meth:`exact` is always binary.

    Bad options raise :class:`growsim.errors.ConfigError` naming the option; unreadable
    pictures, empty or full silhouettes, or a missing view raise before any evolution.

    Examples
    --------
    >>> from growsim.models import ifs3d
    >>> obj = SilhouetteObjective(target_model="ifs3d", target_preset="table1")
    >>> obj(ifs3d.develop(ifs3d.PRESETS["table1"]))
    1.0
    >>> round(obj(ifs3d.develop(ifs3d.PRESETS["seed_gradient"])), 2) < 1.0
    True
    """

    name = "silhouette"
    maximize = True

    def __init__(
        self,
        front: str | os.PathLike | None = None,
        side: str | os.PathLike | None = None,
        *,
        mask_front: str | os.PathLike | None = None,
        mask_side: str | os.PathLike | None = None,
        threshold: str | float = "otsu",
        polarity: str = "auto",
        target_model: str | None = None,
        target_preset: str | None = None,
        target_params: Mapping[str, float] | None = None,
        target_seed: int = 0,
        size: int = 64,
        area_rejection: bool = False,
        line_width: str = "thin",
        blur: float = 0.0,
    ):
        if isinstance(size, bool) or not isinstance(size, (int, np.integer)):
            raise ConfigError(f"silhouette.size: expected an integer, got {size!r}")
        if not 8 <= size <= 1024:
            raise ConfigError(f"silhouette.size: {size} is out of range [8, 1024]")
        if not isinstance(area_rejection, (bool, np.bool_)):
            raise ConfigError(
                f"silhouette.area_rejection: expected true/false, got {area_rejection!r}"
            )
        self.size = int(size)
        self.area_rejection = bool(area_rejection)
        self.line_width = _opt_str("line_width", line_width, ("thin", "radius"))
        if isinstance(blur, bool) or not isinstance(blur, (int, float, np.number)):
            raise ConfigError(f"silhouette.blur: expected a number of pixels, got {blur!r}")
        if not 0.0 <= float(blur) <= 16.0:
            raise ConfigError(f"silhouette.blur: {blur} is out of range [0, 16] pixels")
        self.blur = float(blur)
        polarity = _opt_str("polarity", polarity, ("auto", "dark", "light"))
        if isinstance(threshold, bool) or not (
            threshold == "otsu"
            or (isinstance(threshold, (int, float)) and 0.0 < float(threshold) < 1.0)
        ):
            raise ConfigError(
                f"silhouette.threshold: expected 'otsu' or a number in (0, 1), got {threshold!r}"
            )
        pictures = front is not None or side is not None
        rendered = target_model is not None
        if pictures and rendered:
            raise ConfigError(
                "silhouette: give either pictures (front, side) or a rendered target "
                "(target_model), not both"
            )
        if not pictures and not rendered:
            raise ConfigError(
                "silhouette: no target: give front and side pictures, or target_model "
                "(with target_preset / target_params)"
            )
        if rendered and (mask_front is not None or mask_side is not None):
            raise ConfigError("silhouette.mask_front/mask_side: masks apply to pictures only")
        if not rendered and (
            target_preset is not None or target_params is not None or target_seed != 0
        ):
            raise ConfigError("silhouette.target_preset/target_params need target_model")
        if pictures:
            for label, p in (("front", front), ("side", side)):
                if p is None:
                    raise ConfigError(
                        f"silhouette.{label}: the {label} view is missing "
                        "(both front and side pictures are needed)"
                    )
                if not isinstance(p, (str, os.PathLike)):
                    raise ConfigError(f"silhouette.{label}: expected a file path, got {p!r}")
            self.source = {"front": str(Path(front)), "side": str(Path(side))}
            from growsim.images import read_silhouettes

            self.target = read_silhouettes(
                front,
                side,
                size=self.size,
                threshold=threshold,
                polarity=polarity,
                mask_front=mask_front,
                mask_side=mask_side,
            )
        else:
            self.source = {"target_model": target_model, "target_preset": target_preset}
            self.target = self._render_target(
                target_model, target_preset, target_params, target_seed
            )
        areas = self.target.reshape(2, -1).sum(axis=1)
        for label, a in zip(("front", "side"), areas):
            if a == 0:
                raise UserInputError(f"silhouette: the {label} target silhouette is empty")
            if a == self.size * self.size:
                raise UserInputError(f"silhouette: the {label} target silhouette is all foreground")

    def _render_target(self, model_name, preset, params, seed) -> np.ndarray:
        from growsim.models import get_model

        if not isinstance(model_name, str):
            raise ConfigError(f"silhouette.target_model: expected a model name, got {model_name!r}")
        try:
            model = get_model(model_name)
        except UserInputError as exc:
            raise ConfigError(f"silhouette.target_model: {exc}") from None
        values: dict[str, float] = {}
        if preset is not None:
            presets = getattr(model, "PRESETS", {}) or {}
            if preset not in presets:
                raise ConfigError(
                    f"silhouette.target_preset: unknown preset {preset!r} of {model_name!r}; "
                    f"available: {', '.join(sorted(presets)) or '(none)'}"
                )
            values.update(presets[preset])
        if params is not None:
            if not isinstance(params, Mapping):
                raise ConfigError(f"silhouette.target_params: expected a table, got {params!r}")
            values.update(params)
        if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)):
            raise ConfigError(f"silhouette.target_seed: expected an integer, got {seed!r}")
        try:
            plant = model.develop(values, seed=int(seed))
        except GrowsimError as exc:
            raise ConfigError(f"silhouette.target_params: {exc}") from None
        return plant_views(plant, self.size, self.line_width)

    # ------------------------------------------------------------------ scoring
    def views(self, plant) -> np.ndarray:
        """The plant's framed silhouettes ``(2, size, size)`` uint8, as scored."""
        return plant_views(plant, self.size, self.line_width)

    def __call__(self, plant) -> float:
        """Mean NCC over the front and side views, in [0, 1] (blurred if ``blur > 0``)."""
        if self.blur > 0.0:
            aa = plant_views(plant, self.size, self.line_width, antialias=True)
            return blurred_ncc(aa, self.target, self.blur, self.area_rejection)
        return ncc(self.views(plant), self.target, self.area_rejection)

    def exact(self, plant) -> float:
        """The binary mean NCC (the seed's eq. 3 on silhouettes), whatever ``blur`` is."""
        return ncc(self.views(plant), self.target, self.area_rejection)

    def batch(self, model, params, names, seeds=None) -> np.ndarray | None:
        """Fast path for ``ifs3d``: score a whole ``(n, p)`` parameter matrix in one kernel.

        ``names`` label the columns of ``params`` (every model parameter). Returns ``(n,)``
        float64, or ``None`` for other models (or ``line_width = "radius"``), which are
        then developed and scored one by one.
        """
        if getattr(model, "NAME", None) != "ifs3d" or self.line_width != "thin":
            return None
        params = np.atleast_2d(np.asarray(params, dtype=np.float64))
        names = list(names)
        col = {n: i for i, n in enumerate(names)}
        n = params.shape[0]
        n_maps = np.round(params[:, col["n_maps"]]).astype(np.int64) if "n_maps" in col else None
        depth = np.round(params[:, col["depth"]]).astype(np.int64) if "depth" in col else None
        if n_maps is None:
            n_maps = np.full(n, model.DEFAULT_N_MAPS)
        if depth is None:
            depth = np.full(n, model.DEFAULT_DEPTH)
        out = np.zeros(n)
        for N, d in sorted(set(zip(n_maps.tolist(), depth.tolist()))):
            rows = np.flatnonzero((n_maps == N) & (depth == d))
            model.check_size(N, d)
            maps = np.empty((rows.size, N, 4))
            for k in range(1, N + 1):
                for f, field in enumerate(("s", "y", "theta_z", "theta_y")):
                    maps[:, k - 1, f] = params[rows, col[f"{field}_{k}"]]
            out[rows] = score_population(maps, d, self.target, self.area_rejection, self.blur)
        return out
