"""Judging a reconstruction against its picture, as ``fit-image`` judges a fit: the Plant
drawn with its branches' widths (:func:`growsim.objectives.silhouette.plant_views`) and
framed as the picture's silhouette (:func:`growsim.pictures.images.frame_silhouettes`),
the binary NCC at 256 px (:func:`growsim.kernels.views.ncc`); at the picture's own size
(:func:`growsim.pictures.images.unframe`, as ``fit_<view>.png``): the area over the
picture's, the skeletons' precision and recall within a tolerance (the share of the
fit's skeleton pixels within ``tol`` pixels of the picture's, and the other way round),
the crowns' outlines' intersection over union
(:func:`growsim.objectives.silhouette.outlines`); a side view predicted from the front
alone, by the NCC of both blurred (:func:`growsim.kernels.views.blurred_ncc`) at 64 px.
"""

from __future__ import annotations

import numpy as np

from growsim.kernels.views import blurred_ncc, ncc
from growsim.objectives.silhouette import outlines, plant_views
from growsim.pictures.images import frame_silhouettes, unframe

__all__ = [
    "JUDGE_SIZE",
    "SIDE_SIGMA",
    "SIDE_SIZE",
    "fit_mask",
    "front_view",
    "judge",
    "skeleton_match",
]

#: the NCC's raster size, as fit-image's final size
JUDGE_SIZE = 256
#: the side view's size and blur (pixels) when predicted from the front alone
SIDE_SIZE = 64
SIDE_SIGMA = 1.0


def front_view(rec, mask, size: int = JUDGE_SIZE, side=None) -> np.ndarray:
    """The reconstruction ``rec``'s front view ``(1, size, size)``, drawn with its
    branches' widths where its picture shows it: framed as
    :func:`~growsim.pictures.images.frame_silhouettes` frames ``mask`` (with ``side``, the
    side picture framed with it), each point at the picture's pixel it was read from
    (:func:`~growsim.pictures.framing.picture_frame`), so what the picture shows and the
    reconstruction leaves out (a speck apart from the tree) moves nothing else.

    Examples
    --------
    >>> from growsim.reconstruction.build import reconstruct
    >>> m = np.zeros((60, 40), bool); m[10:60, 18:23] = True
    >>> view = front_view(reconstruct(m), m, 64)
    >>> view.shape, round(float(ncc(view, frame_silhouettes(m, None, 64, "radius"))), 2)
    ((1, 64, 64), 0.99)
    """
    return plant_views(rec.plant, size, "radius", views=1, frame=rec.frame(mask, size, side))


def fit_mask(rec, mask, view: int = 0, side=None) -> np.ndarray:
    """The reconstruction ``rec``'s view ``view`` (0 front, 1 side) at the picture's size
    and placement, as ``fit-image`` writes ``fit_<view>.png``: drawn at the picture's
    resolution (at most 1024 px; the front where the picture shows it,
    :func:`front_view`) and unframed onto ``mask`` (``side``: the side picture).

    Examples
    --------
    >>> from growsim.reconstruction.build import reconstruct
    >>> m = np.zeros((60, 40), bool); m[10:60, 18:23] = True
    >>> back = fit_mask(reconstruct(m), m)
    >>> back.shape, round(float((back & m).sum() / m.sum()), 2)
    ((60, 40), 0.99)
    """
    if view == 0:
        size = min(1024, max(mask.shape))
        return unframe(front_view(rec, mask, size)[0], mask)
    size = min(1024, max(max(x.shape) for x in (mask, side)))
    return unframe(plant_views(rec.plant, size, "radius", views=2)[1], mask, side, view=1)


def skeleton_match(fit: np.ndarray, target: np.ndarray, tol: float = 2.0) -> tuple[float, float]:
    """``(precision, recall)`` of ``fit``'s skeleton against ``target``'s (both masks of
    one size, skeletonised by :func:`skimage.morphology.skeletonize`): the share of each
    one's skeleton pixels within ``tol`` pixels of the other's.

    Examples
    --------
    >>> a = np.zeros((20, 20), bool); a[2:18, 9:12] = True
    >>> b = np.zeros((20, 20), bool); b[2:18, 10:13] = True
    >>> skeleton_match(a, b)
    (1.0, 1.0)
    """
    from scipy import ndimage
    from skimage.morphology import skeletonize

    sf, st = skeletonize(fit), skeletonize(target)
    if not sf.any() or not st.any():
        return 0.0, 0.0
    to_t = ndimage.distance_transform_edt(~st)
    to_f = ndimage.distance_transform_edt(~sf)
    return float((to_t[sf] <= tol).mean()), float((to_f[st] <= tol).mean())


def judge(rec, mask, side=None, *, tol: float = 2.0) -> dict:
    """The scores of the reconstruction ``rec`` against the front picture's ``mask`` (and
    the side picture's ``side``, when known): ``ncc`` at :data:`JUDGE_SIZE` (the front
    drawn where the picture shows it, :func:`front_view`), ``area`` ratio,
    ``precision`` and ``recall`` of the skeletons at ``tol`` pixels, ``outline_iou``,
    ``depth_to_width`` (the Plant's crown depth over its width), and with ``side``:
    ``side_blurred_ncc`` (at :data:`SIDE_SIZE`, blurred by :data:`SIDE_SIGMA`, both
    views framed together) and ``ncc_side`` at 256 px.

    Examples
    --------
    >>> from growsim.reconstruction.build import reconstruct
    >>> m = np.zeros((60, 40), bool); m[10:60, 18:23] = True
    >>> s = judge(reconstruct(m), m)
    >>> s["ncc"] > 0.9, round(s["area"], 1), s["precision"], s["recall"]
    (True, 1.0, 1.0, 1.0)
    """
    mask = np.asarray(mask, bool)
    plant = rec.plant
    target = frame_silhouettes(mask, None, JUDGE_SIZE, "radius")
    drawn = front_view(rec, mask)
    back = fit_mask(rec, mask)
    p, r = skeleton_match(back, mask, tol)
    fo, to = outlines(back[None])[0], outlines(mask[None])[0]
    out = {
        "ncc": float(ncc(drawn, target)),
        "area": float(back.sum()) / max(float(mask.sum()), 1.0),
        "precision": p,
        "recall": r,
        "outline_iou": float((fo & to).sum()) / max(float((fo | to).sum()), 1.0),
        "depth_to_width": float(plant.crown_depth()) / max(float(plant.crown_width()), 1e-12),
    }
    if side is not None:
        side = np.asarray(side, bool)
        t2 = frame_silhouettes(mask, side, SIDE_SIZE, "radius")
        v2 = plant_views(plant, SIDE_SIZE, "radius", views=2)
        out["side_blurred_ncc"] = float(blurred_ncc(v2[1:].astype(float), t2[1:], SIDE_SIGMA))
        t2 = frame_silhouettes(mask, side, JUDGE_SIZE, "radius")
        v2 = plant_views(plant, JUDGE_SIZE, "radius", views=2)
        out["ncc_side"] = float(ncc(v2[1:], t2[1:]))
    return out
