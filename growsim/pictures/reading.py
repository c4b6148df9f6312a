"""Reading a picture file, and the checks every silhouette passes before it is fitted.

The lowest room of :mod:`growsim.pictures`: :func:`read_picture` opens a picture file (the
one place one is opened), :func:`load_picture` reads it (the one way: :func:`load_rgb` in
colour, :func:`load_gray` as grey levels) as a viewer shows it (:func:`viewed`: any format
Pillow reads, transparency over white, CMYK and ICC profiles to sRGB, 16-bit grey scaled,
turned by its EXIF orientation) at the working size (:data:`WORK_SIZE`), and
:func:`check_silhouette` refuses a silhouette that cannot be a tree. Both ways of reading a
picture into a silhouette use them: the grey-level threshold
(:func:`growsim.pictures.images.silhouette`) and the colour photo segmentation
(:func:`growsim.pictures.photo.segment_photo`).
"""

from __future__ import annotations

import functools
import io
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
    "STROKE",
    "WIDE_GREY",
    "WORK_SIZE",
    "check_silhouette",
    "forget",
    "load_gray",
    "load_picture",
    "load_rgb",
    "over_white",
    "picture_size",
    "read_picture",
    "viewed",
    "working_scale",
    "working_shape",
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


#: The working size: a picture whose long side is longer than this many pixels is reduced
#: when it is read (:func:`load_rgb`, :func:`load_gray`), before any check or segmentation
#: looks at it, so a 24-megapixel photograph costs what a 1-megapixel one does. Its size:
#: the fit's largest raster (``--sizes`` at most 1024 px) is never finer than the picture
#: it reads, and a twig one pixel wide at this size is a quarter of a raster pixel at 256
#: px (the photo setups' largest); the photo segmentation of a 1024 px picture takes
#: seconds, of a 6000 px one minutes.
WORK_SIZE = 1024

#: :func:`viewed`: the modes of grey levels with more than 8 bits, and their range (the
#: mode ``I``'s: 16 bits, as PNG, PGM and 16-bit TIFF files give it, unless the file
#: says otherwise; ``F``: ``[0, 1]`` when its values lie in it, else stretched from its
#: least to its largest value)
WIDE_GREY = ("I;16", "I;16L", "I;16B", "I;16N", "I", "F")

#: :func:`load_gray`: a working pixel whose block of picture pixels is inked this much (its
#: mean this share of the ink's contrast) is in a thick stroke: it and its neighbours take
#: their blocks' mean; other blocks crossed by ink take the ink's level (a line kept; two
#: 1-pixel lines crossing in a block of 2 x 2 pixels ink 3/4 of it)
STROKE = 0.8

#: :func:`load_picture`: a colour picture more than this many times the working size is
#: first reduced by a whole factor to at least this many times it, averaging sRGB values
#: (libjpeg's scaled decoding, Pillow's ``reduce``: fast), then in linear light. A 6000 px
#: JPEG photo read so differs from its exact mean in linear light by 0.15/255 on average,
#: 9/255 at the 99.9th percentile (1: decoded at a quarter, 0.2 s); 0.10 and 11 with 2
#: (decoded at a half, three times as long: more than a tenth of the segmentation's time)
OVERSAMPLE = 1


def working_shape(height: int, width: int) -> tuple[int, int]:
    """The ``(height, width)`` a picture of this size is read at: its own when its long
    side is at most :data:`WORK_SIZE` pixels, else scaled so that the long side is
    :data:`WORK_SIZE` (the aspect kept).

    Examples
    --------
    >>> working_shape(600, 800), working_shape(4000, 6000), working_shape(6000, 6000)
    ((600, 800), (683, 1024), (1024, 1024))
    """
    long = max(height, width)
    if long <= WORK_SIZE:
        return int(height), int(width)
    k = WORK_SIZE / long
    return max(1, round(height * k)), max(1, round(width * k))


def picture_size(path: str | os.PathLike) -> tuple[int, int]:
    """The ``(height, width)`` of the picture in the file at ``path`` as a viewer shows it
    (turned by its EXIF orientation), at its own size; only the file's header is read.
    ``working_shape(*picture_size(path))`` is the shape :func:`load_rgb` and
    :func:`load_gray` return: a position ``(x, y)`` in the picture's pixels is at
    ``(x, y) * working_scale(path)`` in theirs.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from PIL import Image
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "a.png"
    >>> Image.new("L", (3000, 2000), 255).save(p)
    >>> picture_size(p), load_gray(p).shape, working_scale(p)
    ((2000, 3000), (683, 1024), 0.3413333333333333)
    """

    def size(im):
        w, h = im.size
        return np.array((w, h) if _orientation(im) < 5 else (h, w))

    w, h = read_picture(path, size, check=False)
    return int(h), int(w)


def working_scale(path: str | os.PathLike) -> float:
    """Working pixels per picture pixel of the file at ``path`` (1 when it is read at its
    own size; :func:`picture_size`).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from PIL import Image
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "big.png"
    >>> Image.new("RGB", (2048, 1024), (200, 220, 255)).save(p)
    >>> working_scale(p)  # read at 1024 x 512
    0.5
    """
    h, w = picture_size(path)
    return working_shape(h, w)[1] / w


def load_rgb(path: str | os.PathLike, *, full: bool = False) -> np.ndarray:
    """A picture file as ``(H, W, 3)`` float64 RGB in ``[0, 1]`` (sRGB), as a viewer shows
    it (:func:`viewed`: any mode Pillow reads, transparency over white, turned upright),
    reduced to the working size (:func:`working_shape`, ``full``: at its own size) by
    averaging in linear light, as a camera of fewer pixels would have seen it. An
    unreadable or missing file raises :class:`UserInputError` naming it.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from PIL import Image
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "a.png"
    >>> Image.new("RGB", (4, 3), (255, 0, 0)).save(p)
    >>> load_rgb(p)[0, 0].tolist()
    [1.0, 0.0, 0.0]
    """
    return load_picture(path, gray=False, full=full)


def load_gray(path: str | os.PathLike, *, full: bool = False) -> np.ndarray:
    """A picture file as ``(H, W)`` float64 grey levels in ``[0, 1]`` (0 black, 1 white),
    as a viewer shows it (:func:`viewed`; colour by its luma, transparency over white,
    turned upright), reduced to the working size (:func:`working_shape`; ``full``: at its
    own size) keeping lines: each working pixel takes the mean of its block of picture
    pixels, but a block crossed by ink away from any thick stroke takes the ink's level,
    so a line one pixel wide stays a line at full contrast (averaged, it would fade into
    the paper, and the threshold, set between the paper and the strokes, would drop it)
    while the edges of thick strokes stay where the mean puts them
    (:data:`STROKE`). An unreadable or missing file raises :class:`UserInputError`
    naming it.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from PIL import Image
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "a.png"
    >>> Image.new("L", (4, 3), 255).save(p)
    >>> load_gray(p).shape
    (3, 4)
    """
    return load_picture(path, gray=True, full=full)


def load_picture(path: str | os.PathLike, *, gray: bool, full: bool = False) -> np.ndarray:
    """The one way a picture file is read: ``(H, W)`` grey levels (``gray``) or
    ``(H, W, 3)`` RGB, float64 in ``[0, 1]``, as a viewer shows it (:func:`viewed`, turned
    by its EXIF orientation), at the working size (:func:`working_shape`; ``full``: its
    own). :func:`load_rgb` and :func:`load_gray` say how each is reduced; a colour
    picture at least twice the working size is first reduced by a whole factor, not below
    :data:`OVERSAMPLE` times the working size (a JPEG decoded smaller by libjpeg, at a
    half, a quarter or an eighth; others by Pillow's ``reduce``, both averaging sRGB
    values), then averaged in linear light. The last few pictures read are remembered (a
    fit reads its picture to choose the segmentation, to segment it, and to draw the
    segmentation).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from PIL import Image
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "big.png"
    >>> Image.new("RGB", (2048, 1024), (200, 220, 255)).save(p)
    >>> load_picture(p, gray=True).shape, load_picture(p, gray=False, full=True).shape
    ((512, 1024), (1024, 2048, 3))
    """
    path = Path(path)
    try:
        st = path.stat()
        key = (str(path.absolute()), st.st_mtime_ns, st.st_size)
    except OSError:
        key = None  # read_picture says what is wrong with it
    if key is None:
        return _load(path, gray, full)
    return _remembered(key, gray, full).copy()


def forget() -> None:
    """Forget the pictures :func:`load_picture` remembers (to time a first reading).

    Examples
    --------
    >>> forget()  # the next reading of any picture opens its file again
    """
    _remembered.cache_clear()


@functools.lru_cache(maxsize=4)
def _remembered(key, gray: bool, full: bool) -> np.ndarray:
    """:func:`_load` of the file ``key`` (path, modification time, size), remembered."""
    out = _load(Path(key[0]), gray, full)
    out.flags.writeable = False
    return out


def _load(path: Path, gray: bool, full: bool) -> np.ndarray:
    """:func:`load_picture`, not remembered."""

    def convert(im):
        w, h = im.size
        th, tw = (h, w) if full else working_shape(h, w)
        box = (0.0, 0.0, float(w), float(h))
        if (th, tw) != (h, w) and im.format == "JPEG":
            # a drawing at its size (its lines kept), grey; a photo decoded smaller
            big = (OVERSAMPLE * tw, OVERSAMPLE * th)
            drafted = im.draft("L", None) if gray else im.draft(im.mode, big)
            if drafted is not None and not gray:
                box = tuple(float(v) for v in drafted[1])
        orientation = _orientation(im)
        pic = viewed(im, gray=gray)
        if (th, tw) == (h, w):
            a = np.asarray(pic)
            out = a / 255.0 if a.dtype == np.uint8 else a.astype(np.float64)
        elif gray:
            out = _reduce_keeping_lines(np.asarray(pic), (th, tw))
        else:
            k = int(min(box[2] / tw, box[3] / th) // OVERSAMPLE)
            if k >= 2:
                pic = pic.reduce(k)
                box = tuple(v / k for v in box)
            out = _reduce_in_linear_light(pic, (th, tw), box)
        if not gray and out.ndim == 2:
            out = np.repeat(out[..., None], 3, axis=2)
        return np.ascontiguousarray(_upright(out, orientation))

    out = read_picture(path, convert)
    if out.ndim != (2 if gray else 3):
        raise UserInputError(f"{path}: the image is empty")
    return out


def _orientation(im) -> int:
    """The EXIF orientation tag (274) of a PIL image, 1 (upright) without one."""
    try:
        value = int(im.getexif().get(274, 1))
    except (TypeError, ValueError, OSError, SyntaxError):
        return 1
    return value if 1 <= value <= 8 else 1


def _upright(a: np.ndarray, orientation: int) -> np.ndarray:
    """``a`` (rows first) as a viewer shows a picture of this EXIF orientation: the
    transpositions of :func:`PIL.ImageOps.exif_transpose` (2 mirrored, 3 turned half, 4
    flipped, 5 transposed, 6 to be turned a quarter right, 7 transversed, 8 a quarter
    left), done on the picture read at the working size."""
    if orientation in (5, 6, 7, 8):
        a = {5: a, 6: a[::-1], 7: a[::-1, ::-1], 8: a[:, ::-1]}[orientation].swapaxes(0, 1)
    elif orientation in (2, 3, 4):
        a = {2: a[:, ::-1], 3: a[::-1, ::-1], 4: a[::-1]}[orientation]
    return a


def viewed(im, *, gray: bool = False):
    """A PIL image as a viewer shows it, not turned (its EXIF orientation is
    :func:`load_picture`'s): a PIL image of mode ``L`` (``gray``: colour by its luma, ITU-R
    601, as Pillow converts it), ``RGB``, or ``F`` (grey levels of more than 8 bits, in
    ``[0, 1]``).

    * 1-bit, palette (``P``), ``L``, ``RGB`` and the other modes Pillow converts to RGB;
    * transparency (``LA``, ``RGBA``, ``PA``, a palette's or a colour's transparent
      entry) composited over white (:func:`over_white`);
    * CMYK (a print JPEG) by its embedded ICC profile to sRGB (Pillow's ImageCms), else
      by Pillow's ``(1 - C)(1 - K)``; an RGB picture with an embedded profile other than
      sRGB (Adobe RGB, Display P3) converted to sRGB the same way;
    * grey levels of more than 8 bits (:data:`WIDE_GREY`) scaled from their type's range,
      not clipped: ``I;16*`` 0-65535; ``I`` 0-65535 (16-bit PNG and PGM files as Pillow
      opens them) or the range a TIFF file's bits per sample and sample format give;
      ``F`` as it is when within ``[0, 1]``, else stretched from its least to its largest
      value. 16-bit colour is its 8 bits (Pillow reads 16-bit colour so).

    Examples
    --------
    >>> import numpy as np
    >>> from PIL import Image
    >>> deep = Image.fromarray(np.array([[0, 32768, 65535]], dtype=np.uint16))
    >>> deep.mode, np.asarray(viewed(deep)).round(3).tolist()
    ('I;16', [[0.0, 0.5, 1.0]])
    >>> np.asarray(viewed(Image.new("LA", (2, 1), (0, 0)), gray=True)).tolist()  # white
    [[255, 255]]
    """
    from PIL import Image

    mode = im.mode
    if mode in WIDE_GREY:
        return Image.fromarray(_wide_grey(im), mode="F")
    transparent = "transparency" in im.info or mode in ("LA", "La", "RGBA", "RGBa", "PA")
    if transparent:
        im = over_white(im).convert("RGB")
    elif mode in ("CMYK", "RGB"):
        im = _to_srgb(im) or im
    if gray or im.mode in ("L", "1"):
        return im.convert("L")
    return im.convert("RGB")


def _wide_grey(im) -> np.ndarray:
    """:func:`viewed` of grey levels of more than 8 bits: ``float32`` in ``[0, 1]``."""
    a = np.asarray(im)
    if im.mode == "F":
        a = a.astype(np.float32)
        finite = a[np.isfinite(a)]
        lo, hi = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
        if lo < 0.0 or hi > 1.0:
            a = (a - lo) / max(hi - lo, 1e-30)
        a = np.nan_to_num(a, nan=1.0, posinf=1.0, neginf=0.0)
    else:
        top = 65535.0
        if im.mode == "I":
            tags = getattr(im, "tag_v2", None) or {}
            bits = tags.get(258, (16,))
            bits = int(bits[0] if isinstance(bits, tuple) else bits)
            signed = tags.get(339, (1,))
            signed = int(signed[0] if isinstance(signed, tuple) else signed) == 2
            top = float(2 ** (bits - 1) - 1 if signed else 2**bits - 1)
        key = im.info.get("transparency")
        a = a.astype(np.float32) / np.float32(top)
        if isinstance(key, int):  # a transparent grey level: white
            a[np.asarray(im) == key] = 1.0
    return np.ascontiguousarray(np.clip(a, 0.0, 1.0), dtype=np.float32)


def _to_srgb(im):
    """An RGB or CMYK PIL image converted by its embedded ICC profile to sRGB (mode RGB),
    or ``None`` (no profile, an sRGB one, or one ImageCms cannot apply)."""
    icc = im.info.get("icc_profile")
    if not icc:
        return None if im.mode == "RGB" else im.convert("RGB")
    try:
        from PIL import ImageCms

        profile = ImageCms.ImageCmsProfile(io.BytesIO(icc))
        if im.mode == "RGB" and "srgb" in ImageCms.getProfileDescription(profile).lower():
            return None
        return ImageCms.profileToProfile(im, profile, ImageCms.createProfile("sRGB"),
                                         outputMode="RGB")  # fmt: skip
    except (ImportError, OSError, ValueError, TypeError):
        return None if im.mode == "RGB" else im.convert("RGB")


def _blocks(n: int, m: int) -> np.ndarray:
    """The first of the picture pixels each of ``m`` working pixels holds, ``n`` in all."""
    return np.floor(np.arange(m) * (n / m)).astype(np.int64)


def _reduce_keeping_lines(a: np.ndarray, shape) -> np.ndarray:
    """``(H, W)`` grey levels (uint8 or float in ``[0, 1]``) reduced to ``shape``, keeping
    lines: each working pixel holds a block of picture pixels and takes their mean, but a
    block holding ink (a level at least half as far from the background, the median of
    the picture's border, as the farthest level in the picture) with no block of a thick
    stroke (a mean at least :data:`STROKE` of the ink's) within one working pixel takes
    its level farthest from the background: a line thinner than a working pixel stays a
    line at full contrast, the edges of thick strokes stay where the mean puts them.
    float64 in ``[0, 1]``."""
    from scipy.ndimage import maximum_filter

    rows, cols = _blocks(a.shape[0], shape[0]), _blocks(a.shape[1], shape[1])
    # along the rows first: their pixels lie side by side in memory
    lo = np.minimum.reduceat(np.minimum.reduceat(a, cols, axis=1), rows, axis=0)
    hi = np.maximum.reduceat(np.maximum.reduceat(a, cols, axis=1), rows, axis=0)
    wide = np.uint32 if a.dtype == np.uint8 else np.float64  # sums of blocks of levels
    sums = np.add.reduceat(np.add.reduceat(a, cols, axis=1, dtype=wide), rows, axis=0)
    counts = np.outer(np.diff(np.r_[rows, a.shape[0]]), np.diff(np.r_[cols, a.shape[1]]))
    mean = sums / counts
    border = np.concatenate([a[0], a[-1], a[:, 0], a[:, -1]]).astype(np.float64)
    bg = float(np.median(border))
    lo, hi = lo.astype(np.float64), hi.astype(np.float64)
    far = np.where(bg - lo > hi - bg, lo, hi)
    ink = max(float(np.abs(far - bg).max()), 1e-12)
    inked = np.abs(far - bg) >= 0.5 * ink
    stroke = maximum_filter(np.abs(mean - bg) >= STROKE * ink, size=3)
    out = np.where(inked & ~stroke, far, mean)
    return out / 255.0 if a.dtype == np.uint8 else out


def _linear_table() -> np.ndarray:
    """sRGB levels 0-255 in linear light (IEC 61966-2-1), float32."""
    v = np.arange(256) / 255.0
    return np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4).astype(np.float32)


def _reduce_in_linear_light(pic, shape, box) -> np.ndarray:
    """A PIL image (``L``, ``RGB`` or ``F``, sRGB) reduced to ``shape`` by the mean of
    each working pixel's area in linear light (Pillow's box filter on each band; ``box``:
    the part of the image the picture covers, in its pixels): float64 sRGB in ``[0, 1]``."""
    from PIL import Image

    table = _linear_table()
    out = []
    for band in pic.split():
        a = np.asarray(band)
        if a.dtype == np.uint8:
            lin = table[a]
        else:
            a = np.clip(a, 0.0, 1.0)
            lin = np.where(a <= 0.04045, a / 12.92, ((a + 0.055) / 1.055) ** 2.4)
        band = Image.fromarray(np.ascontiguousarray(lin, dtype=np.float32), mode="F")
        band = band.resize((shape[1], shape[0]), Image.Resampling.BOX, box=box)
        out.append(np.asarray(band, dtype=np.float64))
    lin = np.clip(out[0] if len(out) == 1 else np.stack(out, axis=2), 0.0, 1.0)
    return np.where(lin <= 0.0031308, 12.92 * lin, 1.055 * lin ** (1 / 2.4) - 0.055)


def over_white(im):
    """A PIL image with its transparency composited over white (mode RGBA).

    Examples
    --------
    >>> from PIL import Image
    >>> over_white(Image.new("RGBA", (2, 1), (0, 0, 0, 0))).getpixel((0, 0))
    (255, 255, 255, 255)
    """
    from PIL import Image

    rgba = im.convert("RGBA")
    return Image.alpha_composite(Image.new("RGBA", rgba.size, (255, 255, 255, 255)), rgba)


def read_picture(path: str | os.PathLike, convert, *, check: bool = True) -> np.ndarray:
    """``convert(image)`` of the PIL image in the file at ``path`` (the one place a
    picture is opened; the image is not loaded yet, ``convert`` may ask for a scaled
    decoding first): a missing, unreadable, too large or (``check``) empty file raises
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
            out = convert(im)
    except Image.DecompressionBombError as exc:
        raise UserInputError(f"{path}: the image is too large ({exc})") from None
    except (UnidentifiedImageError, OSError, ValueError, SyntaxError) as exc:
        raise UserInputError(f"{path}: cannot read the image ({exc})") from None
    if check and out.size == 0:
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
