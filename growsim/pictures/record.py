"""The segmentation record: what :func:`growsim.pictures.photo.segment_photo` found and
how (:class:`Segmentation`, its one line and its ``fit.json`` record), and the picture of
it (:func:`segmentation_picture`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Segmentation", "horizon_share", "segmentation_picture"]

#: the confidence reported: the share of the tree's outline that differs from its
#: background by more than this many times the threshold's floor
CONFIDENT = 2.0
#: a silhouette whose outline runs along the cut (the line above which the tree stands
#: out of the horizon's band) over at least this share of its width is flagged: the
#: crown below the horizon or the trunk may be missing (of 98 real lone trees judged by
#: eye, 25 of the 28 so flagged were wrong; ``benchmarks/log/fitting.md``)
ENDS_AT_HORIZON = 0.2
#: ... ending there: not on this share of the tree's height below the cut
HORIZON_DEPTH = 0.03


def horizon_share(tree: np.ndarray, cut) -> float:
    """The share of the width of ``tree`` (``(H, W)`` bool) where it ends at the ``cut``
    (rows per column): it is there 2 rows above the cut and not :data:`HORIZON_DEPTH` of
    its height below it.

    Examples
    --------
    >>> tree = np.zeros((60, 50), bool); tree[10:40, 10:40] = True  # cut off at 40
    >>> horizon_share(tree, np.full(50, 40.0))
    1.0
    """
    if not tree.any():
        return 0.0
    h, w = tree.shape
    rows, cols = np.nonzero(tree)
    d = max(2, round(HORIZON_DEPTH * (rows.max() - rows.min() + 1)))
    cut = np.round(np.asarray(cut)).astype(int)
    x = np.arange(w)
    ok = (cut >= 2) & (cut + d < h)
    above = np.zeros(w, dtype=bool)
    below = np.zeros(w, dtype=bool)
    above[ok] = tree[cut[ok] - 2, x[ok]]
    below[ok] = tree[cut[ok] + d, x[ok]]
    return float((above & ~below).sum() / (cols.max() - cols.min() + 1))


@dataclass(frozen=True)
class Segmentation:
    """What :func:`~growsim.pictures.photo.segment_photo` found: ``tree`` ``(H, W)`` bool (the
    silhouette), ``ground`` ``(H, W)`` bool (below the horizon's band, not tree), ``horizon`` (the
    band's row at the tree's trunk, ``None`` without ground), ``distance`` ``(H, W)``
    (each pixel's colour difference from its background, Delta E), ``threshold`` (the
    least one a fully covered pixel has, Delta E), ``sky_noise`` (robust sigma of the sky
    around its filled-in model, Delta E), ``contrast`` (the tree's median difference
    from its background, Delta E), ``coverage`` ``(H, W)`` (each pixel's estimated share
    covered by the tree, by linear unmixing; ``tree`` is where it is at least
    :data:`~growsim.pictures.coverage.COVERAGE`, before connectivity); and how it was found: ``sky``
    ``(H, W)`` bool, ``band`` (the top of the horizon's band per column, rows; ``H`` where there is
    no ground), ``cut`` (what rises above this line per column stands out of the band),
    ``objects`` (the boxes ``(x0, y0, x1, y1)`` of the standing objects, the tree's
    first), ``hint`` (``{"box": ...}``, ``{"point": ...}`` or ``None``, in working
    pixels), ``method``, ``outline_contrast`` (the median difference of the outline's
    pixels, Delta E) and ``confidence`` (the share of the outline differing from its
    background by more than :data:`CONFIDENT` times the threshold), ``seconds``,
    ``hint_scale`` (working pixels a pixel of the picture as given: the hint's), ``split``
    (the boxes of the trees whose crowns touched the tree's, split off it:
    :func:`~growsim.pictures.colours.split_touching`; their pixels are not the tree's),
    ``border`` (the lines of a frame around the photograph painted over, top, bottom,
    left, right: :func:`~growsim.pictures.border.paint_over_border`), ``grazes`` (the
    pixels of the top edge the tree touches, whole by the box:
    :func:`~growsim.pictures.hints.grazing`), ``steps`` (``(name, pixels)``: what the steps
    below the cut added, the tree learned below the horizon,
    :func:`~growsim.pictures.learned.learned_below`, and the trunk followed down,
    :func:`~growsim.pictures.foot.traced_trunk`).

    Examples
    --------
    >>> tree = np.zeros((60, 50), bool); tree[15:55, 24:27] = True   # a trunk
    >>> seg = Segmentation(tree, np.zeros((60, 50), bool), 50, np.zeros((60, 50)), 10.0,
    ...                    0.5, 40.0)
    >>> seg.record()["tree_box"], seg.record()["tree_pixels"]
    ([24, 15, 27, 55], 120)
    """

    tree: np.ndarray
    ground: np.ndarray
    horizon: int | None
    distance: np.ndarray
    threshold: float
    sky_noise: float
    contrast: float
    coverage: np.ndarray | None = None
    sky: np.ndarray | None = None
    band: np.ndarray | None = None
    cut: np.ndarray | None = None
    objects: tuple = ()
    hint: dict | None = None
    method: str = "sky and skyline"
    outline_contrast: float = 0.0
    confidence: float = 0.0
    seconds: float = 0.0
    hint_scale: float = 1.0
    split: tuple = ()
    border: tuple = (0, 0, 0, 0)
    grazes: int = 0
    steps: tuple = ()

    def ends_at_horizon(self) -> float:
        """The share of the tree's width where its silhouette ends at the cut
        (:func:`horizon_share`; 0 without a horizon).

        Examples
        --------
        >>> tree = np.zeros((60, 50), bool); tree[10:40, 10:40] = True  # cut off at 40
        >>> seg = Segmentation(tree, np.zeros((60, 50), bool), 45, np.zeros((60, 50)), 10.0,
        ...                    0.5, 40.0, band=np.full(50, 45.0), cut=np.full(50, 40.0))
        >>> round(seg.ends_at_horizon(), 2), "the trunk may be missing" in seg.describe()
        (1.0, True)
        >>> tree[40:55, 23:27] = True                                 # its trunk below
        >>> round(seg.ends_at_horizon(), 2)
        0.87
        """
        if self.cut is None or self.horizon is None:
            return 0.0
        return horizon_share(self.tree, self.cut)

    def describe(self) -> str:
        """One line: what was found (for messages and logs)."""
        ground = "no ground" if self.horizon is None else f"ground from row {self.horizon}"
        hint = "" if not self.hint else f", hint {_hint_text(self.hint)}"
        if self.split:
            boxes = " and ".join(",".join(map(str, b)) for b in self.split)
            hint += f", a touching tree split off at {boxes}"
        if self.grazes:
            hint += f", grazing the top edge ({self.grazes} pixels)"
        ends = self.ends_at_horizon()
        if ends >= ENDS_AT_HORIZON:
            hint += (f", its outline ending along the horizon over {100 * ends:.0f} % of its "
                     "width (the crown below it or the trunk may be missing)")  # fmt: skip
        return (
            f"photo segmentation ({self.method}{hint}): {ground}, {len(self.objects)} "
            f"standing object(s), sky noise {self.sky_noise:.1f}, tree/background threshold "
            f"{self.threshold:.1f}, contrast {self.contrast:.1f}, outline "
            f"{self.outline_contrast:.1f} (Delta E), confidence {self.confidence:.2f}"
        )

    def record(self) -> dict:
        """What was found, as plain values (``fit.json``'s ``segmentation``)."""
        h, w = self.tree.shape
        rows, cols = np.nonzero(self.tree)
        band = None
        if self.band is not None and self.horizon is not None:
            xs = np.linspace(0, w - 1, 9).round().astype(int)
            band = {"columns": xs.tolist(), "rows": [round(float(self.band[x]), 1) for x in xs]}
        return {
            "method": self.method,
            "hint": self.hint,
            "size": [w, h],
            "horizon": self.horizon,
            "band": band,
            "objects": [list(map(int, o)) for o in self.objects],
            "split_off": [list(map(int, b)) for b in self.split],
            "border": list(map(int, self.border)),
            "grazes_top": int(self.grazes),
            "tree_box": _box_of(rows, cols),
            "tree_pixels": int(rows.size),
            "sky_noise": round(self.sky_noise, 2),
            "threshold": round(self.threshold, 2),
            "contrast": round(self.contrast, 2),
            "outline_contrast": round(self.outline_contrast, 2),
            "confidence": round(self.confidence, 3),
            "ends_at_horizon": round(self.ends_at_horizon(), 3),
            "steps": {name: int(n) for name, n in self.steps},
            "seconds": round(self.seconds, 3),
        }


def _box_of(rows, cols):
    """``[x0, y0, x1, y1]`` around pixels at ``rows``, ``cols`` (``None``: none)."""
    if not len(rows):
        return None
    return [int(cols.min()), int(rows.min()), int(cols.max()) + 1, int(rows.max()) + 1]


def _hint_text(hint: dict) -> str:
    if "box" in hint:
        return "box " + ",".join(f"{v:g}" for v in hint["box"])
    return "point " + ",".join(f"{v:g}" for v in hint["point"])


def segmentation_picture(seg: Segmentation, rgb: np.ndarray) -> np.ndarray:
    """What :func:`~growsim.pictures.photo.segment_photo` found, to look at: ``(H, 2 W + 8, 3)``
    uint8, on the left the photo ``rgb`` (``(H, W, 3)`` in ``[0, 1]``, the picture segmented) with
    the tree's outline in red, on the right the labels: the sky blue, the ground and the
    horizon's clutter (below the band's top, yellow) brown, the tree red, the line above
    which an object stands out of the band dashed orange, the standing objects' boxes
    (the tree's green, the others orange) and the hint (a box or a cross, magenta).

    Examples
    --------
    >>> rgb = np.ones((60, 50, 3)) * [0.8, 0.9, 1.0]
    >>> rgb[50:] = [0.3, 0.5, 0.2]; rgb[15:55, 24:27] = [0.4, 0.3, 0.2]
    >>> tree = np.zeros((60, 50), bool); tree[15:55, 24:27] = True
    >>> ground = np.zeros((60, 50), bool); ground[50:] = ~tree[50:]
    >>> seg = Segmentation(tree, ground, 50, np.zeros((60, 50)), 10.0, 0.5, 40.0,
    ...                    band=np.full(50, 50.0), cut=np.full(50, 46.0),
    ...                    objects=((22, 14, 29, 47),), hint={"point": [25, 30]})
    >>> picture = segmentation_picture(seg, rgb)
    >>> picture.shape, picture[20, 23].tolist()  # the outline beside the trunk, red
    ((60, 108, 3), [255, 0, 0])
    """
    from PIL import Image, ImageDraw
    from scipy import ndimage

    rgb = np.clip(np.asarray(rgb, dtype=np.float64), 0.0, 1.0)
    if rgb.ndim == 2:
        rgb = np.repeat(rgb[..., None], 3, axis=2)
    h, w = seg.tree.shape
    if rgb.shape[:2] != (h, w):
        from skimage.transform import resize

        rgb = resize(rgb, (h, w), order=1, anti_aliasing=True)
    tree = seg.tree
    outline = ndimage.binary_dilation(tree, np.ones((3, 3), bool)) & ~tree
    left = rgb.copy()
    left[outline] = (1.0, 0.0, 0.0)
    grey = rgb.mean(axis=2, keepdims=True) * np.ones(3)
    right = 0.5 * grey + 0.5
    if seg.sky is not None:
        right[seg.sky] = 0.5 * grey[seg.sky] + 0.5 * np.array([0.35, 0.6, 1.0])
    right[seg.ground] = 0.5 * grey[seg.ground] + 0.5 * np.array([0.6, 0.45, 0.25])
    right[tree] = 0.3 * grey[tree] + 0.7 * np.array([0.9, 0.1, 0.1])
    gap = np.ones((h, 8, 3))
    im = Image.fromarray(np.round(255 * np.hstack([left, gap, right])).astype(np.uint8))
    draw = ImageDraw.Draw(im)
    off = w + 8
    if seg.band is not None and seg.horizon is not None:
        xs = np.arange(w)
        draw.line([(off + x, float(y)) for x, y in zip(xs, seg.band)], fill=(255, 220, 0))
        if seg.cut is not None:
            for x in range(0, w - 4, 8):
                draw.line([(off + x, float(seg.cut[x])), (off + x + 4, float(seg.cut[x + 4]))],
                          fill=(255, 140, 0))  # fmt: skip
    for i, (x0, y0, x1, y1) in enumerate(seg.objects):
        colour = (0, 170, 0) if i == 0 else (255, 140, 0)
        draw.rectangle([off + x0, y0, off + x1 - 1, y1 - 1], outline=colour)
    hint = seg.hint or {}
    for x0 in (0, off):
        if "box" in hint:
            b = [v * seg.hint_scale for v in hint["box"]]
            draw.rectangle([x0 + b[0], b[1], x0 + b[2], b[3]], outline=(255, 0, 255))
        if "point" in hint:
            px, py = (v * seg.hint_scale for v in hint["point"])
            r = max(3, w // 100)
            draw.line([(x0 + px - r, py), (x0 + px + r, py)], fill=(255, 0, 255), width=2)
            draw.line([(x0 + px, py - r), (x0 + px, py + r)], fill=(255, 0, 255), width=2)
    return np.asarray(im)
