"""The crown: the coarse scene's arrays at the working size (:func:`upsample`,
:func:`per_column`), the rows' spans (:func:`row_spans`) and the tree as the connected
pieces of the foreground around the standing object (:func:`connected_tree`).
"""

from __future__ import annotations

import numpy as np

__all__ = ["connected_tree", "per_column", "row_spans", "upsample"]

#: pieces of foreground this many pixels or less from the tree join it (a twig broken by
#: a pixel as pale as the sky)
GAP = 2
#: the crown's region reaches this share of its height around the rows' spans (faint twig
#: tips beyond the reduced picture's object join when joined to the tree)
CROWN_PAD = 0.05
#: the crown's region: the standing object of the coarse scene grown by this many coarse
#: pixels (twigs thinner than a coarse pixel, the texture's smoothing)
CROWN_MARGIN = 2
#: the crown region's pieces kept: those within this share of the standing object's
#: height of the tree's piece (specks of cloud left in the region are farther)
CROWN_REACH = 0.15


def upsample(coarse: np.ndarray, shape, scale: float) -> np.ndarray:
    """A coarse ``(h, w)`` array at the working ``shape``: each working pixel takes the
    coarse pixel it falls in (``scale`` coarse pixels a working pixel).

    Examples
    --------
    >>> upsample(np.arange(4).reshape(2, 2), (4, 4), 0.5).tolist()
    [[0, 0, 1, 1], [0, 0, 1, 1], [2, 2, 3, 3], [2, 2, 3, 3]]
    """
    h, w = coarse.shape[:2]
    r = np.minimum((np.arange(shape[0]) * scale).astype(np.int64), h - 1)
    c = np.minimum((np.arange(shape[1]) * scale).astype(np.int64), w - 1)
    return coarse[r[:, None], c[None, :]]


def per_column(coarse_rows: np.ndarray, width: int, scale: float) -> np.ndarray:
    """A coarse per-column row line at the working ``width``, in working rows.

    Examples
    --------
    >>> per_column(np.array([3.0, 5.0]), 4, 0.5).tolist()
    [6.0, 6.0, 10.0, 10.0]
    """
    c = np.minimum((np.arange(width) * scale).astype(np.int64), len(coarse_rows) - 1)
    return np.asarray(coarse_rows, dtype=np.float64)[c] / scale


def row_spans(mask: np.ndarray) -> np.ndarray:
    """Each row of ``mask`` filled from its leftmost to its rightmost pixel.

    Examples
    --------
    >>> m = np.zeros((2, 6), bool); m[0, [1, 4]] = True
    >>> row_spans(m).astype(int).tolist()
    [[0, 1, 1, 1, 1, 0], [0, 0, 0, 0, 0, 0]]
    """
    any_ = mask.any(axis=1)
    w = mask.shape[1]
    left = np.where(any_, mask.argmax(axis=1), w)
    right = np.where(any_, w - 1 - mask[:, ::-1].argmax(axis=1), -1)
    cols = np.arange(w)[None, :]
    return (cols >= left[:, None]) & (cols <= right[:, None])


def connected_tree(fg, obj, crown, origin, shape, scale):
    """The tree among the foreground ``fg`` of a crop at ``origin`` (step 5 of
    :func:`~growsim.pictures.photo.segment_photo`): the piece holding most of the standing object
    ``obj``, the pieces up to :data:`GAP` pixels from it and those in the ``crown`` region (the
    rows' spans of the object: its twigs and leaves, cut off by the threshold).

    Examples
    --------
    >>> from growsim.pictures.scene import find_scene
    >>> from growsim.pictures.scene import example_photo
    >>> rgb = example_photo()  # sky, ground strip, a trunk standing on it, a branch
    >>> obj = find_scene(rgb, np.ones((60, 50), bool)).objects[0]
    >>> fg = rgb[..., 0] == 0.4; fg[5, 5] = True                 # and a speck of dust
    >>> tree = connected_tree(fg, obj, np.zeros_like(fg), (0, 0), (60, 50), 1.0)
    >>> int(tree.sum()), bool(tree[5, 5])
    (143, False)
    """
    from scipy import ndimage
    from skimage.measure import label
    from skimage.morphology import disk

    labels = label(fg, connectivity=2)
    if labels.max() == 0:
        return fg
    core = upsample(obj.mask, shape, scale)[
        origin[0] : origin[0] + fg.shape[0], origin[1] : origin[1] + fg.shape[1]
    ]
    hits = np.bincount(labels[core & fg].ravel(), minlength=labels.max() + 1)
    hits[0] = 0
    sizes = np.bincount(labels.ravel())
    sizes[0] = 0
    main = int(np.argmax(hits)) if hits.max() > 0 else int(np.argmax(sizes))
    bridged = label(ndimage.binary_dilation(fg, disk(GAP)), connectivity=2)
    group = bridged == bridged[labels == main][0]
    # the crown region's pieces near the tree: within CROWN_REACH of its height of it
    rows = np.flatnonzero(core.any(axis=1))
    reach = max(float(GAP), CROWN_REACH * (rows.max() - rows.min() + 1 if rows.size else 0))
    near = ndimage.distance_transform_edt(~group) <= reach
    ids = np.unique(labels[(group | (crown & near)) & fg])
    return np.isin(labels, ids[ids > 0])
