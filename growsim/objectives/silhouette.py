"""Silhouette matching: normalised cross-correlation of front and side projections.

After Kuwahara, Shiwa & Kishino, "fitting a 3D fractal tree to front/side tree images
with a GA" (ATR TR-C-0135, 1996), eq. 3: per view, the normalised cross-correlation of the
plant's projection ``F`` and the target silhouette ``G``; on binary images it is

    NCC = |F and G| / sqrt(|F| |G|)

(1 when they coincide, 0 when disjoint). growsim reports the mean over the two views, in
``[0, 1]`` (the paper summed them). The paper's area-ratio rejection (a plant whose total
projected area is not within 0.5x-2x of the target's scores 0) is the option
``area_rejection``.

Framing: plant projections and target pictures are framed alike (see
:mod:`growsim.kernels.views` and :mod:`growsim.pictures.images`): one scale for both views that fits
the height into the ``size x size`` raster (or the half-width about the trunk base, if
tighter), the trunk base at the horizontal centre, the lowest point on the bottom row. So a
photo of any size and margin can be a target, and the score ignores the plant's absolute
size.

Plants are drawn as thin (1-pixel supercover) lines by default, the paper's rendering; with
``line_width = "radius"`` each segment is as wide as its tube.

``blur = sigma`` (pixels, default 0) scores a smoother landscape for the search: the plant
is drawn anti-aliased (each line sample's ink spread bilinearly, so the image moves
continuously with the parameters), both it and the target are blurred by a Gaussian of
``sigma`` pixels, and the score is the NCC of these grey-level images (the paper's eq. 3 in
its general form, ``<F, G> / (|F| |G|)``): a branch one pixel off still earns partial
credit. :meth:`SilhouetteObjective.exact` always gives the binary NCC, the figure to report.

Two terms make a score that a blob or a lone trunk cannot win (the photo fits' search,
:mod:`growsim.fitting`): ``scales = n`` averages the NCC over ``n`` levels of a Gaussian
pyramid (each level the previous one smoothed and halved, compared as grey levels, ``<F, G> / (|F|
|G|)``), so a branch a few pixels off earns credit at the coarser levels while the finest
level still asks for it in place; ``area_band = [lo, hi]`` multiplies the score by
``exp(-AREA_SLOPE * e)``, ``e`` the distance of ``log(|F| / |G|)`` (the areas of all the
views) outside ``[log lo, log hi]``: a crown-covering blob of twice the tree's area keeps
under a third of its score (:func:`shape_score`).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, ClassVar, Literal

import numpy as np
from pydantic import Field, field_validator, model_validator

from growsim.errors import ConfigError, GrowsimError, UserInputError
from growsim.kernels.ifs3d import score_population
from growsim.kernels.raster import draw_segments
from growsim.kernels.views import (
    blurred_ncc,
    frame_points,
    frame_view,
    ncc,
    render_antialiased,
    render_thin,
)
from growsim.models import get_model
from growsim.objectives.base import Objective, ObjectiveOptions
from growsim.phenotypes.plant import LEAF
from growsim.pictures.images import frame_silhouettes, picture_silhouettes

# The kernels (framing, rasters, NCC: growsim.kernels.views; the IFS population scorer) are
# imported where they are used: the config schema imports every objective's options, and a
# run that does not score silhouettes should not pay for loading them.

__all__ = [
    "AREA_SLOPE",
    "SilhouetteObjective",
    "SilhouetteOptions",
    "outlines",
    "phenotype_views",
    "plant_views",
    "shape_score",
    "trunk_widths",
]

#: :func:`trunk_widths`: the share of the rows, from the bottom, a view's foot is measured on
TRUNK_ROWS = 0.08

#: ``area_band``: the score is multiplied by ``exp(-AREA_SLOPE * e)``, ``e`` the distance of
#: the log area ratio outside the band (twice the band's top: x 0.125)
AREA_SLOPE = 3.0


def _pyramid(img: np.ndarray, levels: int) -> list[np.ndarray]:
    """``img`` ``(V, S, S)`` as float64, then each coarser level: the previous one smoothed
    by the binomial filter ``[1, 4, 6, 4, 1] / 16`` along both axes (edges clamped) and
    every second pixel kept (a Gaussian pyramid, after Burt and Adelson)."""
    from scipy.ndimage import convolve1d

    taps = np.array([1.0, 4.0, 6.0, 4.0, 1.0]) / 16.0
    out = [np.asarray(img, dtype=np.float64)]
    for _ in range(levels - 1):
        a = convolve1d(out[-1], taps, axis=1, mode="nearest")
        a = convolve1d(a, taps, axis=2, mode="nearest")
        out.append(a[:, ::2, ::2])
    return out


def trunk_widths(views, rows: float = TRUNK_ROWS) -> np.ndarray:
    """The width of each view ``(V, S, S)`` (> 0 the tree) at its foot: the mean count of
    tree pixels per row over the lowest ``rows`` share of the rows (the views are framed
    with the tree's lowest point on the bottom row, so this is the trunk's width, or a
    low crown's).

    Examples
    --------
    >>> a = np.zeros((1, 20, 20)); a[0, :, 9:12] = 1; a[0, :5, 2:18] = 1
    >>> trunk_widths(a).tolist()
    [3.0]
    """
    v = np.asarray(views) > 0
    n = max(1, round(rows * v.shape[1]))
    return v[:, -n:, :].sum(axis=2).mean(axis=1)


def outlines(views) -> np.ndarray:
    """Each view ``(V, S, S)`` (> 0 the tree) filled, row by row, from its leftmost to its
    rightmost tree pixel: the crown's outline, whatever the branches inside it do.

    Examples
    --------
    >>> a = np.zeros((1, 3, 5), np.uint8); a[0, 0, [1, 3]] = 1; a[0, 2, 2] = 1
    >>> outlines(a)[0].astype(int).tolist()
    [[0, 1, 1, 1, 0], [0, 0, 0, 0, 0], [0, 0, 1, 0, 0]]
    """
    v = np.asarray(views) > 0
    left = np.maximum.accumulate(v, axis=2)
    right = np.maximum.accumulate(v[..., ::-1], axis=2)[..., ::-1]
    return left & right


def _band_factor(ratio: float, band) -> float:
    """``exp(-AREA_SLOPE * e)``, ``e`` how far ``log(ratio)`` lies outside ``log(band)``."""
    lo, hi = band
    r = np.log(max(ratio, 1e-300))
    return float(np.exp(-AREA_SLOPE * max(0.0, np.log(lo) - r, r - np.log(hi))))


def shape_score(views, target, scales: int = 1, area_band=None, first: float | None = None,
                trunk_band=None, outline: bool = False):  # fmt: skip
    """The shape score of ``views`` against ``target`` (both ``(V, S, S)``, > 0 the tree):
    the mean over ``scales`` levels of a Gaussian pyramid (:func:`_pyramid`) of the mean
    over views of the grey-level NCC ``<F, G> / (|F| |G|)`` (``first``: the finest level's
    score, when computed otherwise, e.g. blurred), times the area term of ``area_band``
    ``(lo, hi)`` (``exp(-AREA_SLOPE * e)``, ``e`` how far ``log(|F| / |G|)`` lies outside
    ``[log lo, log hi]``; ``None``: none), times the same term of ``trunk_band`` for the
    ratio of the views' widths at their foot (:func:`trunk_widths`, summed over the views),
    and with ``outline`` times the intersection over union of the outlines
    (:func:`outlines`: a lone trunk in a wide crown's picture keeps a sliver of its score).
    At ``scales = 1`` without a band or outline, binary views score their binary NCC.

    Examples
    --------
    >>> a = np.zeros((1, 8, 8), np.uint8); a[0, :, 3] = 1   # a trunk
    >>> b = np.zeros_like(a); b[0, :, 4] = 1                # one pixel off
    >>> shape_score(b, a), round(shape_score(b, a, scales=3), 3)
    (0.0, 0.591)
    >>> blob = np.zeros_like(a); blob[0, :, 2:6] = 1         # 4x the area
    >>> round(shape_score(blob, a, scales=3), 3), round(shape_score(blob, a, 3, (0.8, 1.25)), 3)
    (0.817, 0.025)
    """
    f_levels = _pyramid(views, scales)
    g_levels = _pyramid(target, scales)
    total = 0.0
    for level, (f, g) in enumerate(zip(f_levels, g_levels)):
        if level == 0 and first is not None:
            total += first
            continue
        dot = (f * g).sum(axis=(1, 2))
        norm = np.sqrt((f * f).sum(axis=(1, 2)) * (g * g).sum(axis=(1, 2)))
        total += float(np.mean(np.where(norm > 0, dot / np.where(norm > 0, norm, 1.0), 0.0)))
    score = total / len(f_levels)
    if area_band is not None:
        ratio = float(f_levels[0].sum()) / max(float(g_levels[0].sum()), 1e-300)
        score *= _band_factor(ratio, area_band)
    if trunk_band is not None:
        ratio = trunk_widths(views).sum() / max(trunk_widths(target).sum(), 1e-300)
        score *= _band_factor(float(ratio), trunk_band)
    if outline:
        f, g = outlines(views), outlines(target)
        score *= float(np.count_nonzero(f & g)) / max(float(np.count_nonzero(f | g)), 1.0)
    return score


def plant_views(
    plant,
    size: int = 64,
    line_width: str = "thin",
    antialias: bool = False,
    views: int = 2,
    frame: tuple[float, float, float] | None = None,
) -> np.ndarray:
    """Front and side silhouettes ``(2, size, size)`` uint8 of any Plant, framed.

    The trunk base is the start of the first root segment (``parent == -1``). Every
    segment is drawn (stems and leaves). ``line_width``: ``"thin"`` (1-pixel lines) or
    ``"radius"`` (lines ``2 * radius`` wide, at least thin). ``antialias`` (thin lines
    only): float64 coverage in [0, 1] instead (see ``blur`` of :class:`SilhouetteObjective`).
    ``views = 1``: the front view alone ``(1, size, size)``, framed by the front's own
    extent (the side's width does not shrink it), as a single picture is framed.
    ``frame = (u_base, y_min, k)`` (with ``views = 1``): the front view placed by
    :func:`~growsim.kernels.views.frame_view` with these, not by its own extent (a tree
    drawn where its picture shows it, :func:`~growsim.pictures.framing.picture_frame`).

    Examples
    --------
    >>> from growsim.models import ifs3d
    >>> v = plant_views(ifs3d.develop(ifs3d.PRESETS["table1"]), 64)
    >>> v.shape, int(v[0, 63, 32]), int(v[0, 0, 32])  # trunk base and top of the trunk
    ((2, 64, 64), 1, 1)
    >>> plant_views(ifs3d.develop(ifs3d.PRESETS["table1"]), 64, views=1).shape
    (1, 64, 64)
    """
    size = int(size)
    if views not in (1, 2):
        raise UserInputError(f"plant_views: views must be 1 or 2, got {views!r}")
    aa = antialias and line_width == "thin"
    if plant.n_segments == 0:
        return np.zeros((views, size, size), dtype=np.float64 if aa else np.uint8)

    roots = np.flatnonzero(plant.parent < 0)
    base = plant.start[roots[0] if roots.size else 0]
    start, end = plant.start, plant.end
    if views == 1:
        # the framing's half-width is the larger of the two views': flatten the depth so
        # only the front's counts (the front view itself ignores z)
        start, end = start.copy(), end.copy()
        start[:, 2] = base[2]
        end[:, 2] = base[2]
    if frame is None:
        coords, k = frame_points(start, end, base, size)
        coords = coords[:views]
    elif views != 1:
        raise UserInputError(f"plant_views: a given frame places the front alone, got {views=}")
    else:
        k = float(frame[2])
        coords = np.empty((1, 2, plant.n_segments, 2))
        for i, p in enumerate((start, end)):
            coords[0, i, :, 0], coords[0, i, :, 1] = frame_view(p[:, 0], p[:, 1], *frame, size)
    if aa:
        return render_antialiased(coords, size)
    if line_width == "thin":
        return render_thin(coords, size)
    img = np.zeros((views, size, size), dtype=np.uint8)
    width = 2.0 * k * plant.radius
    leaf = plant.kind == LEAF
    for v in range(views):
        a, b, w = coords[v, 0], coords[v, 1], width
        if leaf.any():
            a, b, w = a.copy(), b.copy(), width.copy()
            a[leaf], b[leaf], w[leaf] = _leaf_blades(plant, leaf, a[leaf], b[leaf], w[leaf], v)
        draw_segments(a, b, w, img[v])
    return img


def _leaf_blades(plant, leaf, a, b, width, view):
    """Leaves drawn as their blades are seen (``line_width = "radius"``): a leaf is a
    flat hexagon facing up (:mod:`growsim.kernels.mesh`: across it a horizontal vector
    perpendicular to its axis, ``2 radius`` wide; 3/4 of its length x width rectangle);
    in a view its width is foreshortened by the across vector's share in the picture
    plane, and it is drawn as a capsule of that width and of the blade's projected
    area (shortened about its centre). A leaf seen edge-on is a line. ``a``, ``b``
    ``(m, 2)`` its projected end points, ``width`` ``(m,)`` its full width in pixels;
    ``view`` 0 front (picture x), 1 side (picture -z). Returns new ``a``, ``b``,
    ``width``."""
    d = plant.end[leaf] - plant.start[leaf]
    horiz = np.hypot(d[:, 0], d[:, 2])
    # across = (-dz, 0, dx) / horiz; a vertical leaf: the frame's first axis (x)
    share = np.where(
        horiz > 1e-12, np.abs(d[:, 2 if view == 0 else 0]) / np.maximum(horiz, 1e-300), 1.0
    )
    if view == 1:
        share = np.where(horiz > 1e-12, share, 0.0)
    w = width * share
    length = np.hypot(*(b - a).T)
    keep = np.clip(0.75 - 0.25 * np.pi * w / np.maximum(length, 1e-12), 0.0, 1.0)
    mid = 0.5 * (a + b)
    half = 0.5 * (b - a) * keep[:, None]
    return mid - half, mid + half, w


def phenotype_views(
    phenotype, size: int = 64, line_width: str = "thin", antialias: bool = False, views: int = 2
) -> np.ndarray:
    """The views of any phenotype this objective scores: a plant's (:func:`plant_views`),
    or, for a 2D phenotype (one with ``front_view(size)``, e.g. an IFS attractor,
    :class:`growsim.phenotypes.attractor.Attractor`), its one view ``(1, size, size)`` whatever
    ``views`` is (float64 when ``antialias``), framed as plants are.

    Examples
    --------
    >>> from growsim.models import ifs2d
    >>> phenotype_views(ifs2d.develop(ifs2d.PRESETS["fern"]), 32).shape
    (1, 32, 32)
    """
    if "front_view" in phenotype.capabilities:
        img = np.asarray(phenotype.front_view(int(size)))[None]
        return img.astype(np.float64) if antialias else img.astype(np.uint8)
    return plant_views(phenotype, size, line_width, antialias=antialias, views=views)


class SilhouetteOptions(ObjectiveOptions):
    """Options of the ``silhouette`` objective: a target (two pictures, or rendered from
    a model) and how silhouettes are drawn and compared."""

    kind: Literal["silhouette"] = Field("silhouette", description="the objective: silhouette")
    front: str | None = Field(None, description="front picture (path; with side)")
    side: str | None = Field(None, description="side picture (path; with front)")
    views: Literal["both", "front"] = Field(
        "both", description="'both': front and side views; 'front': the front alone (side free)"
    )
    segmentation: Literal["threshold", "photo"] = Field(
        "threshold",
        description="pictures to silhouettes: 'threshold' (grey levels) or 'photo' "
        "(colour: tree apart from sky and ground)",
    )
    mask_front: str | None = Field(None, description="mask picture of the front view")
    mask_side: str | None = Field(None, description="mask picture of the side view")
    box_front: list[float] | None = Field(
        None,
        min_length=4,
        max_length=4,
        description="[x0, y0, x1, y1]: the tree of a photo's front picture lies in this box "
        "(pixels of the picture as given)",
    )
    point_front: list[float] | None = Field(
        None,
        min_length=2,
        max_length=2,
        description="[x, y]: a pixel of the photo's front picture on the tree",
    )
    box_side: list[float] | None = Field(
        None, min_length=4, max_length=4, description="box_front of the side picture"
    )
    point_side: list[float] | None = Field(
        None, min_length=2, max_length=2, description="point_front of the side picture"
    )
    threshold: Literal["otsu"] | float = Field(
        "otsu", description="'otsu' or a grey level in (0, 1) that splits tree from background"
    )
    polarity: Literal["auto", "dark", "light"] = Field(
        "auto", description="'dark' tree on light, 'light' on dark, or 'auto'"
    )
    target_model: str | None = Field(None, description="render the target from this model")
    target_preset: str | None = Field(None, description="preset of target_model")
    target_params: dict[str, float] | None = Field(
        None, description="parameters of target_model (over the preset)"
    )
    target_seed: int = Field(0, description="seed the target is grown with")
    size: int = Field(64, ge=8, le=1024, description="raster size in pixels (Kuwahara et al.'s 64)")
    area_rejection: bool = Field(False, description="Kuwahara et al.'s 0.5x-2x area rule")
    line_width: Literal["thin", "radius"] = Field(
        "thin", description="'thin' 1-pixel lines, or 'radius': as wide as the tubes"
    )
    blur: float = Field(
        0.0, ge=0.0, le=16.0, description="search on views blurred by this sigma (pixels)"
    )
    scales: int = Field(
        1, ge=1, le=6, description="NCC averaged over this many levels of a Gaussian pyramid"
    )
    area_band: list[float] | None = Field(
        None,
        min_length=2,
        max_length=2,
        description="[lo, hi]: the score falls off outside this fit/target area ratio",
    )

    trunk_band: list[float] | None = Field(
        None,
        min_length=2,
        max_length=2,
        description="[lo, hi]: the score falls off outside this fit/target trunk width ratio",
    )

    outline: bool = Field(
        False, description="times the IoU of the fit's and the target's outlines (row spans)"
    )

    @field_validator("area_band", "trunk_band")
    @classmethod
    def _check_band(cls, v):
        if v is not None and not 0.0 < v[0] <= 1.0 <= v[1]:
            raise ValueError(f"expected [lo, hi] with 0 < lo <= 1 <= hi, got {list(v)}")
        return v

    @field_validator("box_front", "box_side")
    @classmethod
    def _check_box(cls, v):
        if v is not None and not (v[0] < v[2] and v[1] < v[3]):
            raise ValueError(f"expected [x0, y0, x1, y1] with x0 < x1 and y0 < y1, got {list(v)}")
        return v

    @field_validator("threshold")
    @classmethod
    def _check_threshold(cls, v):
        if v != "otsu" and not 0.0 < float(v) < 1.0:
            raise ValueError(f"expected 'otsu' or a number in (0, 1), got {v!r}")
        return v

    @model_validator(mode="after")
    def _one_target(self):
        pictures = self.front is not None or self.side is not None
        rendered = self.target_model is not None
        if pictures and rendered:
            raise ValueError(
                "give either pictures (front, side) or a rendered target (target_model), not both"
            )
        if not pictures and not rendered:
            raise ValueError(
                "no target: give front and side pictures, or target_model "
                "(with target_preset / target_params)"
            )
        if rendered and (self.mask_front is not None or self.mask_side is not None):
            raise ValueError("mask_front/mask_side: masks apply to pictures only")
        hints = ("box_front", "point_front", "box_side", "point_side")
        given = [h for h in hints if getattr(self, h) is not None]
        if given and (rendered or self.segmentation != "photo"):
            raise ValueError(f"{'/'.join(given)}: they apply to segmentation = 'photo' only")
        if not rendered and (
            self.target_preset is not None or self.target_params is not None or self.target_seed
        ):
            raise ValueError("target_preset/target_params/target_seed need target_model")
        if pictures:
            labels = ("front", "side") if self.views == "both" else ("front",)
            for label in labels:
                if getattr(self, label) is None:
                    raise ValueError(
                        f"{label}: the {label} view is missing (both front and side pictures "
                        "are needed; views = 'front' fits the front picture alone)"
                    )
            side_only = (self.side, self.mask_side, self.box_side, self.point_side)
            if self.views == "front" and any(v is not None for v in side_only):
                raise ValueError(
                    "side/mask_side/box_side/point_side: views = 'front' fits the front "
                    "picture alone"
                )
            if self.segmentation == "photo" and (
                self.threshold != "otsu" or self.polarity != "auto"
            ):
                raise ValueError(
                    "threshold/polarity: they apply to segmentation = 'threshold', not 'photo'"
                )
        return self


class SilhouetteObjective(Objective):
    """Match a plant's front and side silhouettes to target images (maximised, in [0, 1]).

    The target is either two pictures (``front`` and ``side`` paths, optional masks) or
    rendered from a model (``target_model`` with ``target_preset`` and/or
    ``target_params``; the paper's test case is ``target_model = "ifs3d"``,
    ``target_preset = "table1"``). Options (:class:`SilhouetteOptions`, all keyword, as in
    a config table):

    ``front``, ``side`` : paths of the two pictures (both, or neither);
    ``mask_front``, ``mask_side`` : optional mask pictures (white = look here);
    ``box_front``, ``point_front``, ``box_side``, ``point_side`` : a photo's hints, where
    the tree is (a box ``[x0, y0, x1, y1]`` around it, a point ``[x, y]`` on it; pixels of
    the picture as given), for a picture where one tree cannot be told apart;
    ``threshold`` : ``"otsu"`` (default) or a grey level in (0, 1);
    ``polarity`` : ``"auto"`` (default), ``"dark"`` (dark tree on light) or ``"light"``;
    ``target_model``, ``target_preset``, ``target_params``, ``target_seed`` : a rendered target;
    ``size`` : raster size in pixels, 8..1024 (default 64, the paper's);
    ``area_rejection`` : the paper's 0.5x-2x area rule (default false);
    ``line_width`` : ``"thin"`` (default) or ``"radius"``;
    ``views`` : ``"both"`` (default: front and side) or ``"front"`` (one picture, or the
    rendered target's front: the side is left free, see :func:`plant_views`);
    ``segmentation`` : ``"threshold"`` (default: grey levels, ``threshold`` and
    ``polarity``) or ``"photo"`` (:func:`growsim.pictures.photo.segment_photo`: the tree apart from
    sky and ground, in colour);
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
    >>> round(obj(ifs3d.develop(ifs3d.PRESETS["paper_gradient"])), 2) < 1.0
    True
    """

    name = "silhouette"
    maximize = True
    accepts = ("plant", "points2d")
    Options = SilhouetteOptions
    example: ClassVar[dict[str, Any]] = {
        "target_model": "ifs3d",
        "target_preset": "table1",
        "size": 32,
    }

    def setup(self) -> None:
        o = self.options
        self.size = o.size
        self.area_rejection = o.area_rejection
        self.line_width = o.line_width
        self.blur = o.blur
        self.scales = o.scales
        self.area_band = o.area_band
        self.trunk_band = o.trunk_band
        self.outline = o.outline
        self.n_views = 2 if o.views == "both" else 1
        #: the pictures' full-size silhouettes (view name -> (H, W) bool), as segmented
        self.pictures: dict[str, np.ndarray] = {}
        if o.target_model is None:
            self.source = {"front": str(Path(o.front))}
            if o.side is not None:
                self.source["side"] = str(Path(o.side))

            pictures = ("front", "side", "threshold", "polarity", "mask_front", "mask_side")
            pictures += ("segmentation", "box_front", "point_front", "box_side", "point_side")
            masks = picture_silhouettes(**o.model_dump(include=set(pictures)))
            self.pictures = dict(zip(("front", "side"), masks))
            # framed as the plant will be drawn
            side = masks[1] if len(masks) > 1 else None
            self.target = frame_silhouettes(masks[0], side, self.size, self.line_width)
        else:
            self.source = {"target_model": o.target_model, "target_preset": o.target_preset}
            self.target = self._render_target()
        areas = self.target.reshape(self.n_views, -1).sum(axis=1)
        for label, a in zip(("front", "side"), areas):
            if a == 0:
                raise UserInputError(f"silhouette: the {label} target silhouette is empty")
            if a == self.size * self.size:
                raise UserInputError(f"silhouette: the {label} target silhouette is all foreground")

    def _render_target(self) -> np.ndarray:

        o = self.options
        try:
            model = get_model(o.target_model)
        except UserInputError as exc:
            raise ConfigError(f"silhouette.target_model: {exc}") from None
        values: dict[str, float] = {}
        if o.target_preset is not None:
            try:
                values.update(model.preset(o.target_preset))
            except UserInputError as exc:
                raise ConfigError(f"silhouette.target_preset: {exc}") from None
        values.update(o.target_params or {})
        try:
            plant = model.develop(values, seed=o.target_seed, env=self.env)
        except GrowsimError as exc:
            raise ConfigError(f"silhouette.target_params: {exc}") from None
        target = phenotype_views(plant, self.size, self.line_width, views=self.n_views)
        if target.shape[0] < self.n_views:
            raise ConfigError(
                f"silhouette.views: target_model {o.target_model!r} grows a 2D picture (one "
                "view): set views = 'front'"
            )
        return target

    # ------------------------------------------------------------------ scoring
    def views(self, plant) -> np.ndarray:
        """The plant's framed silhouettes ``(V, size, size)`` uint8, as scored (``V = 2``,
        front and side, or 1 with ``views = "front"``)."""
        return phenotype_views(plant, self.size, self.line_width, views=self.n_views)

    def view_scores(self, plant) -> list[float]:
        """The binary NCC of each scored view (front, then side), in [0, 1]."""

        v = self.views(plant)
        return [ncc(v[i : i + 1], self.target[i : i + 1]) for i in range(len(v))]

    def __call__(self, plant) -> float:
        """Mean NCC over the scored views, in [0, 1] (blurred if ``blur > 0``)."""

        shaped = self.has_shape_terms
        if self.blur > 0.0:
            aa = phenotype_views(
                plant, self.size, self.line_width, antialias=True, views=self.n_views
            )
            # a 2D phenotype has one view: it meets the target's front
            score = blurred_ncc(aa, self.target[: len(aa)], self.blur, self.area_rejection)
            if shaped:
                score = self._shaped(aa, score)
            return score
        v = self.views(plant)
        score = ncc(v, self.target[: len(v)], self.area_rejection)
        if shaped:
            score = self._shaped(v, score)
        return score

    @property
    def has_shape_terms(self) -> bool:
        """Whether the score has shape terms (:func:`shape_score`)."""
        return (self.scales > 1 or self.area_band is not None or self.trunk_band is not None
                or self.outline)  # fmt: skip

    def _shaped(self, views, first: float) -> float:
        """The shape score of ``views`` (:func:`shape_score`), ``first`` its finest level."""
        return shape_score(views, self.target[: len(views)], self.scales, self.area_band,
                           first=first, trunk_band=self.trunk_band,
                           outline=self.outline)  # fmt: skip

    def area_ratios(self, plant) -> list[float]:
        """Each scored view's area over the target's (the fit's ``area_band`` measure)."""
        v = self.views(plant)
        return [float(v[i].sum()) / float(self.target[i].sum()) for i in range(len(v))]

    def exact(self, plant) -> float:
        """The binary mean NCC (the paper's eq. 3 on silhouettes), whatever ``blur`` is."""

        v = self.views(plant)
        return ncc(v, self.target[: len(v)], self.area_rejection)

    def batch(self, model, params, names, seeds=None) -> np.ndarray | None:
        """Fast path: score a whole ``(n, p)`` parameter matrix of an IFS model in one kernel.

        ``names`` label the columns of ``params`` (every model parameter). Applies to a
        model with the capability ``map_groups(params, names)`` (yielding ``(rows, maps
        (k, N, 4), depth)`` groups, see :func:`growsim.models.ifs3d.map_groups`), drawn
        thin, with one view or two. Returns ``(n,)`` float64, or ``None`` otherwise (other
        models, ``line_width = "radius"``): those are then developed and scored one by one.
        Rows ``map_groups`` does not yield (leafy trees) are developed and scored here.
        """
        fast = "map_groups" in model.capabilities
        shaped = self.has_shape_terms
        if not fast or self.line_width != "thin" or shaped:
            return None

        params = np.atleast_2d(np.asarray(params, dtype=np.float64))
        out = np.full(params.shape[0], np.nan)
        for rows, maps, depth in model.map_groups(params, names):
            out[rows] = score_population(maps, depth, self.target, self.area_rejection, self.blur)
        for i in np.flatnonzero(np.isnan(out)):
            values = dict(zip(names, params[i].tolist()))
            for p in model.param_spec(values):
                if p.kind == "int" and p.name in values:
                    values[p.name] = round(values[p.name])
            seed = {} if seeds is None else {"seed": int(seeds[i])}
            out[i] = self(model.develop(values, env=self.env, **seed))
        return out
