"""Reading photos and drawings of trees into silhouettes, and framing them for fitting.

A user's front and side pictures (PNG, JPEG, ... any size) become binary silhouettes:

1. :func:`~growsim.pictures.reading.load_gray`: the picture as grey levels in ``[0, 1]``
   as a viewer shows it (any format Pillow reads, transparent pixels over white, turned
   by its EXIF orientation), at the working size
   (:data:`~growsim.pictures.reading.WORK_SIZE`, its lines kept);
2. :func:`silhouette`: a threshold (Otsu's by default, or a number), the polarity (dark tree
   on a light background, light on dark, or ``"auto"``: the class that covers less of the
   picture's border is the tree), an optional mask picture (only its white part is looked
   at); then :func:`~growsim.pictures.reading.check_silhouette` refuses, naming the file, a
   silhouette that cannot be a tree: empty, too small, too noisy, or filling the frame (the
   thresholds in :mod:`growsim.pictures.reading`); a colour photo is segmented by
   :func:`growsim.pictures.photo.segment_photo` instead (:func:`picture_silhouettes`);
3. :func:`~growsim.pictures.framing.frame_silhouettes`: both views into ``(2, S, S)``
   rasters with the framing of rendered plants (:mod:`growsim.pictures.framing`).

What a picture is (a drawing or a photo) is :func:`~growsim.pictures.kinds.classify_picture`'s
answer; the framing's and the classification's names are importable from here too.
"""

from __future__ import annotations

import functools
import os
from pathlib import Path

import numpy as np

from growsim.errors import UserInputError
from growsim.files import atomic_write
from growsim.pictures.framing import COVER_SHARE, frame_silhouettes, frame_thin_lines, unframe
from growsim.pictures.kinds import classify_picture
from growsim.pictures.photo import segment_photo
from growsim.pictures.reading import check_silhouette, load_gray

__all__ = [
    "COVER_SHARE",
    "HINT_FLAGS",
    "classify_picture",
    "frame_silhouettes",
    "frame_thin_lines",
    "otsu_threshold",
    "photo_segmentations",
    "picture_silhouettes",
    "read_silhouettes",
    "silhouette",
    "silhouette_image",
    "unframe",
]


def otsu_threshold(gray: np.ndarray, bins: int = 256) -> float:
    """Otsu's threshold of grey levels ``gray`` (any shape, values in ``[0, 1]``).

    The level that maximises the between-class variance of the two classes it splits;
    pixels ``<= t`` form one class.

    Examples
    --------
    >>> import numpy as np
    >>> g = np.r_[np.full(50, 0.2), np.full(50, 0.8)]
    >>> 0.2 <= otsu_threshold(g) < 0.8
    True
    """
    g = np.asarray(gray, dtype=np.float64).ravel()
    hist, edges = np.histogram(g, bins=bins, range=(0.0, 1.0))
    p = hist / max(1, g.size)
    centres = 0.5 * (edges[:-1] + edges[1:])
    w0 = np.cumsum(p)
    m0 = np.cumsum(p * centres)
    mt = m0[-1]
    w1 = 1.0 - w0
    with np.errstate(divide="ignore", invalid="ignore"):
        between = (mt * w0 - m0) ** 2 / (w0 * w1)
    between[~np.isfinite(between)] = -1.0
    return float(edges[int(np.argmax(between)) + 1])


def silhouette(
    image,
    *,
    threshold: str | float = "otsu",
    polarity: str = "auto",
    mask=None,
    name: str = "image",
) -> np.ndarray:
    """A binary silhouette ``(H, W)`` bool of a grey picture (or a path to one).

    ``threshold``: ``"otsu"`` or a grey level in ``(0, 1)``; ``polarity``: ``"dark"`` (the
    tree is darker than the background), ``"light"``, or ``"auto"`` (the class covering less
    of the border is the tree; ties go to dark); ``mask``: optional picture or path of the
    same size, only its light part (> 0.5) is kept. ``name`` labels errors. Raises
    :class:`UserInputError` naming ``name`` (or the file) if the silhouette is empty, covers
    the whole picture, is too small, too noisy or fills the frame
    (:func:`~growsim.pictures.reading.check_silhouette`).

    Examples
    --------
    >>> import numpy as np
    >>> g = np.ones((50, 40)); g[10:, 20] = 0.0; g[20, 10:30] = 0.0  # trunk and a branch
    >>> int(silhouette(g).sum())  # 40 + 20 pixels, one shared
    59
    """
    if isinstance(image, (str, os.PathLike)):
        name = str(image)
        image = load_gray(image)
    gray = np.asarray(image, dtype=np.float64)
    if gray.ndim != 2 or gray.size == 0:
        raise UserInputError(f"{name}: expected a 2-D grey image, got shape {gray.shape}")
    if float(gray.max() - gray.min()) < 1e-6:
        raise UserInputError(f"{name}: the picture is uniform (blank): no silhouette to fit")
    keep = np.ones(gray.shape, dtype=bool)
    if mask is not None:
        mname = str(mask) if isinstance(mask, (str, os.PathLike)) else f"{name} mask"
        m = load_gray(mask) if isinstance(mask, (str, os.PathLike)) else np.asarray(mask, float)
        if m.shape != gray.shape:
            raise UserInputError(
                f"{mname}: mask size {m.shape[::-1]} differs from the image's {gray.shape[::-1]}"
            )
        keep = m > 0.5
        if not keep.any():
            raise UserInputError(f"{mname}: the mask keeps no pixel (it is all black)")
    if isinstance(threshold, str):
        if threshold != "otsu":
            raise UserInputError(f"{name}: threshold must be 'otsu' or a number, got {threshold!r}")
        t = otsu_threshold(gray[keep])
    else:
        t = float(threshold)
        if not 0.0 < t < 1.0:
            raise UserInputError(f"{name}: threshold must be in (0, 1), got {threshold!r}")
    dark = gray <= t
    if polarity == "auto":
        border = np.zeros(gray.shape, dtype=bool)
        border[[0, -1], :] = True
        border[:, [0, -1]] = True
        border &= keep
        if not border.any():
            border = keep
        polarity = "dark" if dark[border].mean() <= 0.5 else "light"
    if polarity == "dark":
        fg = dark
    elif polarity == "light":
        fg = ~dark
    else:
        raise UserInputError(
            f"{name}: polarity must be 'auto', 'dark' or 'light', got {polarity!r}"
        )
    fg = fg & keep
    check_silhouette(fg, keep, name=name, how=f"threshold {t:.3f}, polarity {polarity}")
    return fg


#: how pictures become silhouettes: ``"threshold"`` (:func:`silhouette`: grey levels) or
#: ``"photo"`` (:func:`growsim.pictures.photo.segment_photo`: colour, sky and ground)
SEGMENTATIONS = ("threshold", "photo")


def picture_silhouettes(
    front,
    side=None,
    *,
    segmentation: str = "threshold",
    threshold: str | float = "otsu",
    polarity: str = "auto",
    mask_front=None,
    mask_side=None,
    box_front=None,
    point_front=None,
    box_side=None,
    point_side=None,
) -> list[np.ndarray]:
    """The silhouettes ``(H, W)`` bool of a front picture and an optional side picture
    (paths or arrays), at the pictures' own size: :func:`silhouette`
    (``segmentation = "threshold"``, with ``threshold`` and ``polarity``) or
    :func:`growsim.pictures.photo.segment_photo` (``"photo"``, with each view's hints
    ``box_<view>`` ``(x0, y0, x1, y1)`` and ``point_<view>`` ``(x, y)`` where the tree
    is). Returns one or two masks.

    Examples
    --------
    >>> import numpy as np
    >>> g = np.ones((50, 40)); g[10:, 20] = 0.0; g[20, 10:30] = 0.0
    >>> [int(m.sum()) for m in picture_silhouettes(g, segmentation="photo")]
    [59]
    """
    found = photo_segmentations(
        front, side, segmentation=segmentation, threshold=threshold, polarity=polarity,
        mask_front=mask_front, mask_side=mask_side, box_front=box_front,
        point_front=point_front, box_side=box_side, point_side=point_side,
    )  # fmt: skip
    return [f.copy() if isinstance(f, np.ndarray) else f.tree.copy() for f in found]


def photo_segmentations(
    front,
    side=None,
    *,
    segmentation: str = "photo",
    threshold: str | float = "otsu",
    polarity: str = "auto",
    mask_front=None,
    mask_side=None,
    box_front=None,
    point_front=None,
    box_side=None,
    point_side=None,
) -> list:
    """What :func:`picture_silhouettes` found in each picture: a
    :class:`~growsim.pictures.photo.Segmentation` for a photo (``segmentation =
    "photo"``: the tree, the sky, the ground, how it was found), the silhouette array for a
    threshold. A picture file's result is remembered (the same picture, mask and hints
    are segmented once in a process): do not change what it returns.

    Examples
    --------
    >>> from growsim.pictures.scene import example_photo
    >>> rgb = example_photo()  # sky, ground strip, a trunk standing on it, a branch
    >>> seg = photo_segmentations(rgb)[0]
    >>> seg.method, seg.horizon, int(seg.tree.sum())
    ('sky and skyline', 50, 143)
    """
    if segmentation not in SEGMENTATIONS:
        raise UserInputError(
            f"segmentation: expected one of {', '.join(SEGMENTATIONS)}, got {segmentation!r}"
        )
    if front is None:
        raise UserInputError("the front view is missing")
    views = [(front, mask_front, "front", _hint(box_front), _hint(point_front))]
    if side is not None:
        views.append((side, mask_side, "side", _hint(box_side), _hint(point_side)))
    out = []
    for img, m, label, box, point in views:
        pic, mask = _file_key(img), _file_key(m)
        how = (label, segmentation, threshold, polarity, box, point)
        if pic is None or (m is not None and mask is None):  # arrays: not remembered
            out.append(_segment(img, m, *how))
        else:
            out.append(_segment_file(pic, mask, *how))
    return out


def _hint(value):
    """A box or point hint as a tuple of floats (hashable), or ``None``."""
    return None if value is None else tuple(float(v) for v in value)


#: the flags naming each view's hints in messages (``growsim fit-image``'s)
HINT_FLAGS = {"front": ("--box", "--point"), "side": ("--box-side", "--point-side")}


def _segment(img, mask, label, segmentation, threshold, polarity, box=None, point=None):
    """One picture's segmentation (:func:`photo_segmentations`): a
    :class:`~growsim.pictures.photo.Segmentation` or a threshold's silhouette."""
    if segmentation == "photo":
        flags = HINT_FLAGS.get(label, HINT_FLAGS["front"])
        return segment_photo(img, mask=mask, name=label, box=box, point=point, flags=flags)
    if box is not None or point is not None:
        raise UserInputError(f"{label}: a box or point hint applies to the photo segmentation")
    return silhouette(img, threshold=threshold, polarity=polarity, mask=mask, name=label)


def _file_key(path):
    """``(path, modification time, size)`` of a picture file, ``None`` for an array (or a
    missing file: read, and refused, without the cache)."""
    if path is None or isinstance(path, np.ndarray):
        return None
    try:
        st = os.stat(path)
    except (OSError, TypeError, ValueError):
        return None
    return str(Path(path).absolute()), st.st_mtime_ns, st.st_size


@functools.lru_cache(maxsize=8)
def _segment_file(picture, mask, label, segmentation, threshold, polarity, box, point):
    """:func:`_segment` of a picture file (``picture``, ``mask``: :func:`_file_key`),
    remembered: a fit compiles its objective at every size and for every candidate, and a
    photo's segmentation costs about a second. A file changed on disk is read again."""
    mask = None if mask is None else mask[0]
    return _segment(picture[0], mask, label, segmentation, threshold, polarity, box, point)


def read_silhouettes(
    front,
    side,
    *,
    size: int = 64,
    threshold: str | float = "otsu",
    polarity: str = "auto",
    mask_front=None,
    mask_side=None,
    line_width: str = "radius",
    segmentation: str = "threshold",
    views: str = "both",
    box_front=None,
    point_front=None,
    box_side=None,
    point_side=None,
) -> np.ndarray:
    """Front and side pictures (paths or arrays) to framed ``(2, size, size)`` uint8
    (``line_width``: how the model will be drawn, see :func:`frame_silhouettes`;
    ``segmentation`` and a photo's hints ``box_<view>``, ``point_<view>``: see
    :func:`picture_silhouettes`; ``views = "front"``: the front picture alone,
    ``(1, size, size)``).

    Examples
    --------
    >>> import numpy as np
    >>> g = np.ones((50, 40)); g[10:, 20] = 0.0; g[20, 10:30] = 0.0
    >>> read_silhouettes(g, g, size=16).shape
    (2, 16, 16)
    >>> read_silhouettes(g, None, size=16, views="front").shape
    (1, 16, 16)
    """
    if views not in ("both", "front"):
        raise UserInputError(f"views: expected 'both' or 'front', got {views!r}")
    if front is None or (side is None and views == "both"):
        missing = "front" if front is None else "side"
        raise UserInputError(f"the {missing} view is missing: both front and side are needed")
    masks = picture_silhouettes(
        front,
        side if views == "both" else None,
        segmentation=segmentation,
        threshold=threshold,
        polarity=polarity,
        mask_front=mask_front,
        mask_side=mask_side if views == "both" else None,
        box_front=box_front,
        point_front=point_front,
        box_side=box_side if views == "both" else None,
        point_side=point_side if views == "both" else None,
    )
    return frame_silhouettes(masks[0], masks[1] if len(masks) > 1 else None, size, line_width)


def silhouette_image(views, path: str | os.PathLike, *, titles=None, scale: int = 4) -> Path:
    """Write silhouettes side by side as a PNG (atomically); returns the path.

    ``views``: a sequence of ``(S, S)`` arrays (non-zero = foreground), drawn black on
    white, each scaled ``scale`` times with nearest-neighbour and separated by a grey bar;
    ``titles`` (optional) are written above them.

    Examples
    --------
    >>> import numpy as np, tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "v.png"
    >>> silhouette_image([np.eye(8), np.eye(8)[::-1]], p).exists()
    True
    """
    from PIL import Image, ImageDraw

    views = [np.asarray(v) for v in views]
    if not views:
        raise UserInputError("silhouette_image: no views to draw")
    tiles = []
    for v in views:
        tile = np.where(v > 0, 0, 255).astype(np.uint8)
        tiles.append(np.kron(tile, np.ones((scale, scale), dtype=np.uint8)))
    h = max(t.shape[0] for t in tiles)
    gap = np.full((h, max(2, scale)), 160, dtype=np.uint8)
    row = []
    for i, t in enumerate(tiles):
        if i:
            row.append(gap)
        pad = np.full((h, t.shape[1]), 255, dtype=np.uint8)
        pad[: t.shape[0]] = t
        row.append(pad)
    body = np.hstack(row)
    head = 14 if titles else 0
    canvas = np.full((body.shape[0] + head, body.shape[1]), 255, dtype=np.uint8)
    canvas[head:] = body
    im = Image.fromarray(canvas, mode="L")
    if titles:
        draw = ImageDraw.Draw(im)
        x = 0
        for t, title in zip(tiles, titles):
            draw.text((x + 2, 1), str(title), fill=0)
            x += t.shape[1] + gap.shape[1]
    return atomic_write(path, lambda fh: im.save(fh, format="PNG"))
