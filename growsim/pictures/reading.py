"""Reading a picture file, and the checks every silhouette passes before it is fitted.

The lowest room of :mod:`growsim.pictures`: :func:`read_picture` opens a picture file (the
one place one is opened), :func:`load_gray` reads it as grey levels and
:func:`check_silhouette` refuses a silhouette that cannot be a tree. Both ways of reading a
picture into a silhouette use them: the grey-level threshold
(:func:`growsim.pictures.images.silhouette`) and the colour photo segmentation
(:func:`growsim.pictures.photo.segment_photo`).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from growsim.errors import UserInputError

__all__ = [
    "MAX_SHARE",
    "MAX_SPECK_DENSITY",
    "MAX_SPECK_SHARE",
    "MIN_PIXELS",
    "MIN_SHARE",
    "SPECK",
    "check_silhouette",
    "load_gray",
    "over_white",
    "read_picture",
]

# What :func:`check_silhouette` refuses. Measured on growsim's own drawings of trees (the
# Table 1 tree in 1-pixel lines or tubes at 32-512 pixels, Honda trees rendered with
# pyvista at 400 pixels) against uniform noise and random specks at densities 1-50 %:
#: fewer foreground pixels than this: too small (a dot, a few strokes)
MIN_PIXELS = 30
#: a smaller share of the picture (or of the mask's white part): too small (a 3-pixel
#: wide stick tree in a wide margin is 0.45 %, Honda renders 5 %; crop a distant tree)
MIN_SHARE = 0.002
#: a larger share: the silhouette fills the frame (a crown cropped to its outline covers
#: 60-80 %; a dark picture with a light edge, or the wrong polarity, more)
MAX_SHARE = 0.9
#: connected pieces (foreground 8-connected, background 4-connected) smaller than this
#: many pixels are specks
SPECK = 5
#: more than this share of the foreground in specks: too noisy (isolated dots; trees:
#: < 1 %, sparse specks: 20-100 %)
MAX_SPECK_SHARE = 0.2
#: more specks, of foreground or of background (holes), per picture pixel: too noisy (1-pixel
#: line drawings, whose crossings enclose tiny holes, reach 0.009; noise 0.034-0.06)
MAX_SPECK_DENSITY = 0.02


def load_gray(path: str | os.PathLike) -> np.ndarray:
    """A picture file as ``(H, W)`` float64 grey levels in ``[0, 1]`` (0 black, 1 white).

    Colour is converted by luminance; transparency is composited over white. An unreadable
    or missing file raises :class:`UserInputError` naming it.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from PIL import Image
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "a.png"
    >>> Image.new("L", (4, 3), 255).save(p)
    >>> load_gray(p).shape
    (3, 4)
    """

    def grey(im):
        if im.mode in ("RGBA", "LA", "PA") or "transparency" in im.info:
            im = over_white(im)
        return np.asarray(im.convert("L"), dtype=np.float64) / 255.0

    gray = read_picture(path, grey)
    if gray.ndim != 2:
        raise UserInputError(f"{Path(path)}: the image is empty")
    return gray


def over_white(im):
    """A PIL image with its transparency composited over white (mode RGBA)."""
    from PIL import Image

    rgba = im.convert("RGBA")
    return Image.alpha_composite(Image.new("RGBA", rgba.size, (255, 255, 255, 255)), rgba)


def read_picture(path: str | os.PathLike, convert) -> np.ndarray:
    """``convert(image)`` of the PIL image in the file at ``path`` (the one place a
    picture is opened): a missing, unreadable or empty file raises
    :class:`UserInputError` naming it.

    Examples
    --------
    >>> read_picture("no/such.png", np.asarray)
    Traceback (most recent call last):
    ...
    growsim.errors.UserInputError: no/such.png: image file not found
    """
    from PIL import Image, UnidentifiedImageError

    path = Path(path)
    if not path.is_file():
        raise UserInputError(f"{path}: image file not found")
    try:
        with Image.open(path) as im:
            im.load()
            out = convert(im)
    except (UnidentifiedImageError, OSError, ValueError) as exc:
        raise UserInputError(f"{path}: cannot read the image ({exc})") from None
    if out.size == 0:
        raise UserInputError(f"{path}: the image is empty")
    return out


def check_silhouette(fg, keep=None, *, name: str = "image", how: str = "") -> None:
    """Refuse, with :class:`UserInputError` naming ``name``, a silhouette ``fg`` ``(H, W)``
    bool that cannot be fitted as a tree; ``keep`` (optional, same shape) is the part of the
    picture looked at (a mask's white part), ``how`` says how ``fg`` was found.

    Refused: an empty silhouette; one covering the whole picture; a too small one (fewer
    than :data:`MIN_PIXELS` pixels, or under :data:`MIN_SHARE` of the picture: a dot would
    be framed into a block half the raster wide); one filling the frame (over
    :data:`MAX_SHARE`); a too noisy one (:func:`scipy.ndimage.label`: over
    :data:`MAX_SPECK_SHARE` of its pixels in specks, 8-connected pieces under :data:`SPECK`
    pixels, or more than :data:`MAX_SPECK_DENSITY` specks per pixel counting the
    background's 4-connected holes under :data:`SPECK` pixels: noise thresholded).

    Examples
    --------
    >>> import numpy as np
    >>> tree = np.zeros((60, 40), bool); tree[10:, 20] = True; tree[20, 10:30] = True
    >>> check_silhouette(tree)
    >>> check_silhouette(np.eye(10, dtype=bool), name="dot.png")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    growsim.errors.UserInputError: dot.png: the silhouette is too small: 10 pixels ...
    """
    fg = np.asarray(fg, dtype=bool)
    keep = np.ones(fg.shape, dtype=bool) if keep is None else np.asarray(keep, dtype=bool)
    fg = fg & keep
    how = f" ({how})" if how else ""
    n, area = int(fg.sum()), int(keep.sum())
    if n == 0:
        raise UserInputError(f"{name}: the silhouette is empty{how}")
    if n == area:
        raise UserInputError(
            f"{name}: the silhouette covers the whole picture{how}; is it a blank or uniform image?"
        )
    if n < MIN_PIXELS or n < MIN_SHARE * area:
        raise UserInputError(
            f"{name}: the silhouette is too small: {n} pixels (at least {MIN_PIXELS}, and "
            f"{100 * MIN_SHARE:g} % of the picture){how}; crop the picture closer to the tree"
        )
    if n > MAX_SHARE * area:
        raise UserInputError(
            f"{name}: the silhouette fills the frame: {100 * n / area:.0f} % of the picture "
            f"(at most {100 * MAX_SHARE:g} %){how}; is the tree cropped, or is --polarity wrong?"
        )
    from scipy import ndimage

    labels, _ = ndimage.label(fg, structure=np.ones((3, 3), dtype=bool))
    sizes = np.bincount(labels.ravel())[1:]
    specks = sizes < SPECK
    holes, _ = ndimage.label(keep & ~fg)
    hole_specks = np.bincount(holes.ravel())[1:] < SPECK
    in_specks = int(sizes[specks].sum()) / n
    density = (int(specks.sum()) + int(hole_specks.sum())) / area
    if in_specks > MAX_SPECK_SHARE or density > MAX_SPECK_DENSITY:
        raise UserInputError(
            f"{name}: the silhouette is too noisy: {100 * in_specks:.0f} % of its pixels in "
            f"{int(specks.sum())} specks of fewer than {SPECK} pixels (at most "
            f"{100 * MAX_SPECK_SHARE:g} %), {1000 * density:.1f} specks or pinholes per 1,000 "
            f"pixels (at most {1000 * MAX_SPECK_DENSITY:g}){how}; is it a photo of a tree "
            "against a plain background?"
        )
