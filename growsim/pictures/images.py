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
3. :func:`frame_silhouettes`: both views into ``(2, S, S)`` rasters with the framing of
   rendered plants (:mod:`growsim.kernels.views`: the same scale rule,
   :func:`~growsim.kernels.views.frame_scale`, and placement,
   :func:`~growsim.kernels.views.frame_view`): one common scale that fits the height into
   the raster unless the half-width around the trunk base is tighter, the trunk base at
   the horizontal centre, the lowest point on the bottom row. What differs from plants:
   each view is first scaled to unit height (the two pictures need not share a zoom); the
   trunk base is the middle of the silhouette's lowest rows. Two ways to place the
   picture's pixels, chosen to match how the model will be drawn (the silhouette
   objective's ``line_width``):

   - ``"radius"`` (tubes at their thickness; photos): drawn as the renderer draws a
     tube (:func:`growsim.kernels.raster.draw_segments`: every pixel its centre line
     crosses, and the pixels whose centre is within its radius): each input pixel's
     square is mapped (the lowest pixels' centres on the bottom row's centre line) and a
     raster pixel is set when the silhouette covers at least :data:`COVER_SHARE` of it,
     or when the silhouette's skeleton (its centre lines,
     :func:`skimage.morphology.skeletonize`) crosses it, so a branch thinner than a
     raster pixel is one pixel wide, as the renderer draws it, and a thick one is as
     wide as it is (setting every pixel a branch touches made the target about a pixel
     fatter than any drawn tree: the true tree of a photo scored 0.87 instead of 0.92
     at 256 px);
   - ``"thin"`` (1-pixel lines): the picture is read as a thin-line rendering, the exact
     inverse of :func:`growsim.kernels.views.render_thin`: strokes are one raster pixel
     wide, so the tree's extent runs between stroke centres, half a raster pixel inside
     the silhouette's outer edges; the renderer lights pixel ``floor(x)`` of a point at
     ``x`` and puts the trunk base on the raster's middle edge, so the trunk's pixel
     centre is half a pixel right of it; each input pixel's centre (sub-sampled when a
     picture pixel is larger than a raster pixel) sets the pixel it falls in. A line
     drawing of a tree at any scale is framed into exactly the silhouette the renderer
     draws for that tree (tested on enlarged renders of random IFS trees). A drawing made
     of square pixels (a raster enlarged by nearest neighbour by any factor, whole or
     not: its pixels then alternate between two widths) is first read back pixel for
     pixel (:func:`~growsim.pictures.pixels.drawn_pixels`: the lattice its edges lie
     on), so it frames back exactly too, whatever the factor (tested 1.25x-7.2x), margin,
     paper and format (PNG or JPEG). What no framing can know: a tree whose lowest point is not its
     trunk base (a branch hanging below it) is placed by its lowest rows.
"""

from __future__ import annotations

import functools
import os
from pathlib import Path

import numpy as np

from growsim.errors import UserInputError
from growsim.files import atomic_write
from growsim.kernels.views import MARGIN, frame_scale, frame_view
from growsim.pictures.photo import segment_photo
from growsim.pictures.pixels import drawn_pixels
from growsim.pictures.reading import check_silhouette, load_gray, load_rgb

__all__ = [
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

#: Share of the silhouette's height, at its bottom, whose pixels locate the trunk base.
BASE_BAND = 0.02
#: ``line_width = "radius"`` framing: a raster pixel at least this much covered by the
#: silhouette is set (measured on the photos of benchmarks/make_photos.py: the true
#: tree's NCC against its own framed silhouette at 64/128/256 px, zelkova 0.94/0.93/0.92
#: with 0.4, 0.93/0.91/0.91 with 0.5, 0.92/0.86/0.87 setting every pixel touched)
COVER_SHARE = 0.4


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


def _view_geometry(mask: np.ndarray):
    rows, cols = np.nonzero(mask)
    rmin, rmax = rows.min(), rows.max()
    h = max(float(rmax - rmin), 1.0)
    band = rows >= rmax - BASE_BAND * h
    base = float(cols[band].mean()) + 0.5
    hw = float(np.max(np.abs(cols + 0.5 - base))) / h
    return rows, cols, float(rmax), h, base, hw


def frame_silhouettes(
    front: np.ndarray, side: np.ndarray | None, size: int = 64, line_width: str = "radius"
) -> np.ndarray:
    """Frame two silhouettes ``(H1, W1)``, ``(H2, W2)`` bool into ``(2, size, size)`` uint8
    (``side = None``: the front alone, ``(1, size, size)``, framed by its own extent).

    ``line_width = "radius"``: each input pixel square is mapped to the raster; a raster
    pixel is set when the silhouette covers at least :data:`COVER_SHARE` of it or its
    skeleton crosses it (as the renderer draws tubes; thin branches survive
    down-sampling one pixel wide);
    ``"thin"``: the pictures are read as thin-line renderings (see the module docstring;
    :func:`frame_thin_lines`).

    Examples
    --------
    >>> import numpy as np
    >>> f = np.zeros((100, 60), bool); f[10:100, 30] = True
    >>> out = frame_silhouettes(f, f, 16)
    >>> out.shape, bool(out[0, :, 8].all())  # a vertical trunk fills the centre column
    ((2, 16, 16), True)
    >>> frame_silhouettes(f, None, 16).shape
    (1, 16, 16)
    """
    size = int(size)
    masks = (front,) if side is None else (front, side)
    if line_width == "thin":
        return frame_thin_lines(front, side, size=size)
    if line_width != "radius":
        raise UserInputError(f"line_width: expected 'thin' or 'radius', got {line_width!r}")
    from skimage.morphology import skeletonize

    out = np.zeros((len(masks), size, size), dtype=np.uint8)
    masks = [np.asarray(m, dtype=bool) for m in masks]
    geo = [_view_geometry(m) for m in masks]
    # both views at unit height: one scale for both, as a rendered plant's views
    k = frame_scale(1.0, max(g[5] for g in geo), size)
    for v, (rows, cols, rmax, h, base, _) in enumerate(geo):
        f = k / h  # raster pixels per input pixel
        # the skeleton's pixel centres set the pixel they fall in (a tube's centre line)
        sr, sc = np.nonzero(skeletonize(masks[v]))
        x, y = frame_view(sc + 0.5, rmax + 0.5 - sr, base, 0.0, f, size)
        sr, sc = np.floor(y + 0.5 * f).astype(np.int64), np.floor(x).astype(np.int64)
        ok = (sr >= 0) & (sr < size) & (sc >= 0) & (sc < size)
        out[v, sr[ok], sc[ok]] = 1
        cover = np.zeros((size, size))
        # the top edge of each input pixel, at height rmax + 1 - row above the lowest
        # pixels' bottom edge; half a pixel lower, so their centres sit on the bottom row
        x0, y0 = frame_view(cols, rmax + 1.0 - rows, base, 0.0, f, size)
        y0 = y0 + f * 0.5
        # the input square [x0, x0 + f) x [y0, y0 + f): rows grow downwards
        x1 = x0 + f
        y1 = y0 + f
        c0 = np.floor(x0).astype(np.int64)
        r0 = np.floor(y0).astype(np.int64)
        c1 = np.maximum(c0, np.ceil(x1).astype(np.int64) - 1)
        r1 = np.maximum(r0, np.ceil(y1).astype(np.int64) - 1)
        for dr in range(int((r1 - r0).max()) + 1):
            for dc in range(int((c1 - c0).max()) + 1):
                r = r0 + dr
                c = c0 + dc
                ok = (r <= r1) & (c <= c1) & (r >= 0) & (r < size) & (c >= 0) & (c < size)
                # the share of raster pixel (r, c) this input pixel covers
                share = np.clip(np.minimum(x1, c + 1) - np.maximum(x0, c), 0.0, None)
                share *= np.clip(np.minimum(y1, r + 1) - np.maximum(y0, r), 0.0, None)
                np.add.at(cover, (r[ok], c[ok]), share[ok])
        out[v][cover >= COVER_SHARE - 1e-9] = 1
        # the trunk base, where the renderer always draws it (the skeleton stops short
        # of a branch's end by its half-width)
        out[v, size - 1, size // 2] = 1
    return out


#: ``"thin"`` framing of a drawing enlarged by a fractional factor: a raster pixel whose
#: share covered by the strokes is below this, beside one covered at least
#: :data:`THIN_FULL`, is a stroke's sliver spilled over and is dropped
THIN_SLIVER = 0.5
THIN_FULL = 0.75


def _thin_geometry(masks, size: int):
    """Each view's geometry and raster pixels per picture pixel ``f`` of the thin-line
    framing (:func:`frame_thin_lines`)."""
    geo = []
    for m in masks:
        rows, cols = np.nonzero(np.asarray(m, dtype=bool))
        rmax = float(rows.max())
        height = rmax + 1.0 - float(rows.min())
        band = rows >= rmax - BASE_BAND * max(height - 1.0, 1.0)
        base = float(cols[band].mean()) + 0.5
        geo.append((rows, cols, rmax, height, base, float(cols.min()), float(cols.max() + 1)))
    f = [1.0] * len(masks)
    for _ in range(50):  # converges in a few steps: f changes h by 1/f only
        hs = [max(g[3] - 1.0 / fv, 1e-9) for g, fv in zip(geo, f)]
        hw = max(max(g[4] - g[5] - 1.0 / fv, g[6] - g[4]) / h for g, fv, h in zip(geo, f, hs))
        k = frame_scale(1.0, max(hw, 0.0), size)
        new = [k / h for h in hs]
        if np.allclose(new, f, rtol=0.0, atol=1e-12):
            break
        f = new
    return geo, f


def _thin_inputs(masks, size: int) -> list:
    """Each view's silhouette as the thin framing reads it: ``(mask, rows, cols)``, its
    drawn pixels when it is drawn in square pixels (:func:`drawn_pixels`, the scale its
    framing gives), else ``(mask, None, None)``."""
    masks = [np.asarray(m, dtype=bool) for m in masks]
    _, f = _thin_geometry(masks, size)
    out = []
    for m, fv in zip(masks, f):
        drawn = drawn_pixels(m, 1.0 / fv)
        out.append((m, None, None) if drawn is None else drawn)
    return out


def frame_thin_lines(front: np.ndarray, side: np.ndarray | None, size: int = 64) -> np.ndarray:
    """Frame two silhouettes read as thin-line renderings into ``(2, size, size)`` uint8:
    the inverse of :func:`growsim.kernels.views.render_thin` (see the module docstring);
    ``side = None``: the front alone, ``(1, size, size)``.

    A view drawn in square pixels (a raster enlarged by nearest neighbour, by a whole or
    fractional factor of at least :data:`~growsim.pictures.pixels.GRID_MIN_SCALE`) is
    first read back pixel for pixel (:func:`~growsim.pictures.pixels.drawn_pixels`) and
    framed from its drawn pixels: a render enlarged so frames back into the render
    exactly, whatever the factor and the margin.
    With ``f`` raster pixels per picture pixel, a view's extent runs between stroke
    centres: its height is ``H - 1/f`` (``H`` the silhouette's height in picture pixels,
    edge to edge), its half-width ``max(base - L - 1/f, R - base)`` (``L``, ``R`` the
    outer edges, ``base`` the trunk's centre), and ``f = k / height`` with the framing
    scale ``k`` of both views (:func:`growsim.kernels.views.frame_scale` at unit height):
    a fixed point, found by iteration. A picture pixel's centre ``(c, r)`` goes to
    ``col = size/2 + 1/2 + f (c - base)``, ``row = size - MARGIN - f (bottom - r)``,
    ``bottom`` the lowest stroke centre.

    Examples
    --------
    >>> import numpy as np
    >>> from PIL import Image
    >>> from growsim.models import ifs3d
    >>> from growsim.objectives.silhouette import plant_views
    >>> v = plant_views(ifs3d.develop(ifs3d.PRESETS["table1"]), 64)
    >>> big = [np.kron(x, np.ones((5, 5))) > 0 for x in v]  # a 320 x 320 drawing of it
    >>> bool((frame_thin_lines(*big, 64) == v).all())
    True
    >>> def enlarged(x, n):  # by 3.6, with a margin of 11 px
    ...     im = Image.fromarray(np.where(x > 0, 255, 0).astype(np.uint8))
    ...     return np.pad(np.asarray(im.resize((n, n), Image.NEAREST)) > 127, 11)
    >>> bool((frame_thin_lines(*[enlarged(x, 230) for x in v], 64) == v).all())
    True
    """

    masks = [m for m, _, _ in _thin_inputs((front,) if side is None else (front, side), size)]
    geo, f = _thin_geometry(masks, size)
    out = np.zeros((len(masks), size, size), dtype=np.uint8)
    for v, ((rows, cols, rmax, _, base, _, _), fv) in enumerate(zip(geo, f)):
        bottom = rmax + 1.0 - 0.5 / fv
        n = max(1, int(np.ceil(fv)))  # points per picture pixel side: no raster pixel skipped
        sub = (np.arange(n) + 0.5) / n
        hits = np.zeros((size, size))
        for a in sub:
            for b in sub:
                col = np.floor(0.5 * size + 0.5 + fv * (cols + a - base)).astype(np.int64)
                row = np.floor((size - MARGIN) - fv * (bottom - (rows + b))).astype(np.int64)
                ok = (row >= 0) & (row < size) & (col >= 0) & (col < size)
                np.add.at(hits, (row[ok], col[ok]), 1.0)
        out[v] = hits > 0
        if n == 1:
            # strokes drawn at a scale that is not a whole number of picture pixels per
            # raster pixel spill a sliver into the next raster pixel: a pixel covered
            # less than THIN_SLIVER beside one covered at least THIN_FULL is dropped
            from scipy.ndimage import maximum_filter

            cover = hits * fv * fv
            sliver = (cover < THIN_SLIVER) & (maximum_filter(cover, size=3) >= THIN_FULL)
            out[v][sliver] = 0
    return out


#: :func:`classify_picture`: a pixel is coloured when its chroma (max - min of R, G, B in
#: ``[0, 1]``) exceeds this
CHROMA = 0.08

#: :func:`classify_picture`: a drawing has at most this share of coloured pixels
MAX_COLOURED = 0.01

#: :func:`classify_picture`: a drawing has at least this share of its pixels within
#: :data:`MODE_REACH` of its two main grey levels (paper and ink: a bimodal histogram)
MIN_TWO_LEVELS = 0.9
MODE_REACH = 0.12

# A grey photo can be bimodal too (a pale sky over a dark ground, the tree between). What
# tells it from a drawing, measured on 57 drawings (growsim's, of the Table 1 tree, its
# renders and the attractors; scanned, blurred, noisy, JPEG at quality 50-90, enlarged to
# 3000 px) against 26 photos made grey (the benchmark's renders, 4 of them cropped above
# the ground, and 12 of scikit-image's):
#: a photo's bottom edge is ground under a sky: the median level of the bottom edge
#: differs from the top edge's by more than this share of the contrast between the two
#: main levels (the renders 0.77-1.0; drawings, whose paper runs all round, 0.006 at most)
GROUND_STEP = 0.5
#: a drawing has at most this share of its pixels in grey levels of their own: smooth (in
#: their 3 x 3, less than a quarter of the contrast), away from both main levels (by
#: :data:`GREY_REACH`, or 4 x the noise) and from the edges between them (7 x 7 px): a
#: sky's gradient, a lit branch (drawings at most 1.0 %; the photos without ground
#: 0.15-58 %)
MAX_OWN_GREYS = 0.02
GREY_REACH = 0.05
#: a drawing has at most this share of its pixels in texture: varying by a quarter of the
#: contrast in their 3 x 3 with no paper within 5 x 5 px (leaves, bark, grass; drawings
#: at most 0.9 %, their edges always border the paper; the photos 0.03-21 %). Two leafy
#: renders cropped above the ground (flat leaves on a smooth sky, 1.2 % and 0.15 % of
#: grey levels of their own, 0.5 % and 1.2 % texture) are still taken for drawings.
MAX_TEXTURE = 0.02


def classify_picture(image) -> tuple[str, str]:
    """``("drawing", why)`` for a drawing or silhouette, ``("photo", why)`` otherwise:
    what ``fit-image --segmentation auto`` reads a picture (path or array, grey ``(H, W)``
    or RGB ``(H, W, 3)`` in ``[0, 1]``; a file is read at the working size,
    :func:`~growsim.pictures.reading.load_rgb`) as. A drawing is near grey (at most
    :data:`MAX_COLOURED` of its pixels have a chroma above :data:`CHROMA`: no sky or
    ground colours), bimodal (at least :data:`MIN_TWO_LEVELS` of its pixels within
    :data:`MODE_REACH` of its two main grey levels: paper and ink) and, unlike a grey
    photo, made of these two levels and the edges between them: its bottom edge is paper
    as its top edge is (no ground under a sky, :data:`GROUND_STEP`), few pixels are in
    smooth grey levels of their own (a sky's gradient, :data:`MAX_OWN_GREYS`) or in
    texture (:data:`MAX_TEXTURE`). ``why``: the figures it looked at, for the messages
    and ``fit.json``.

    Examples
    --------
    >>> import numpy as np
    >>> g = np.full((40, 40), 0.85); g[5:, 20] = 0.1  # a trunk in ink on grey paper
    >>> classify_picture(g)[0]
    'drawing'
    >>> rgb = np.zeros((40, 40, 3)); rgb[:] = (0.5, 0.7, 1.0); rgb[30:] = (0.2, 0.6, 0.1)
    >>> classify_picture(rgb)
    ('photo', 'a photo: 100.0 % of pixels in colour')
    >>> grey = np.full((40, 40), 0.9); grey[32:] = 0.3; grey[8:34, 20] = 0.6  # on ground
    >>> classify_picture(grey)[0]
    'photo'
    """

    if isinstance(image, (str, os.PathLike)):
        rgb = load_rgb(image)
    else:
        rgb = np.asarray(image, dtype=np.float64)
        if rgb.ndim == 2:
            rgb = np.repeat(rgb[..., None], 3, axis=2)
        rgb = rgb[..., :3]
    coloured = float(np.mean(rgb.max(axis=2) - rgb.min(axis=2) > CHROMA))
    if coloured > MAX_COLOURED:
        return "photo", f"a photo: {100 * coloured:.1f} % of pixels in colour"
    grey = rgb.mean(axis=2)
    hist = np.bincount(np.clip((grey * 32).astype(np.int64), 0, 31).ravel(), minlength=32)
    first = int(np.argmax(hist))
    # the second level: the fullest bin away from the first
    away = hist.copy()
    lo, hi = max(0, first - 4), min(32, first + 5)
    away[lo:hi] = 0
    second = int(np.argmax(away))
    levels = np.array([first, second]) + 0.5
    near = np.abs(grey.ravel()[:, None] * 32 - levels[None, :]).min(axis=1) <= MODE_REACH * 32
    share = float(np.mean(near))
    if share < MIN_TWO_LEVELS:
        return "photo", (
            f"a grey photo: {100 * share:.0f} % of pixels near its two main grey levels"
        )
    ground, own, texture = _grey_photo_cues(grey, (first, second))
    if ground > GROUND_STEP:
        return "photo", (
            f"a grey photo: ground under a sky (its bottom edge's grey level differs from "
            f"its top edge's by {100 * ground:.0f} % of the contrast)"
        )
    if own > MAX_OWN_GREYS or texture > MAX_TEXTURE:
        return "photo", (
            f"a grey photo: {100 * own:.1f} % of pixels in smooth grey levels of their own "
            f"(a gradient, lit branches), {100 * texture:.1f} % in texture"
        )
    return "drawing", (
        f"a drawing: grey levels {levels[0] / 32:.2f} and {levels[1] / 32:.2f} hold "
        f"{100 * share:.0f} % of pixels, {100 * coloured:.1f} % in colour"
    )


def _grey_photo_cues(grey: np.ndarray, bins) -> tuple[float, float, float]:
    """What tells a grey photo from a drawing (:func:`classify_picture`), for grey levels
    ``(H, W)`` whose two main levels fall in the 1/32-wide ``bins``: the step from the top
    edge's level to the bottom edge's (share of the contrast, :data:`GROUND_STEP`), the
    share of pixels in smooth grey levels of their own (:data:`MAX_OWN_GREYS`) and the
    share in texture (:data:`MAX_TEXTURE`), on the picture's 3 x 3 median (no noise)."""
    from scipy import ndimage

    levels = []
    for k in bins:  # each level: the median of its bin and the bins beside it
        near = grey[(grey * 32 >= k - 1) & (grey * 32 < k + 2)]
        levels.append(float(np.median(near)) if near.size else (k + 0.5) / 32)
    a, b = levels
    contrast = max(abs(a - b), 1e-6)
    m = ndimage.median_filter(grey, 3)
    h, w = grey.shape
    strip = max(2, round(0.01 * min(h, w)))
    ground = abs(float(np.median(m[:strip])) - float(np.median(m[-strip:]))) / contrast
    edges = (m[:strip], m[-strip:], m[:, :strip], m[:, -strip:])
    paper = float(np.median(np.concatenate([e.ravel() for e in edges])))
    noise = 1.4826 * float(np.median(np.abs(grey - m)))
    reach = max(GREY_REACH, 4.0 * noise)
    varies = ndimage.maximum_filter(m, 3) - ndimage.minimum_filter(m, 3) >= 0.25 * contrast
    near_a = ndimage.maximum_filter(np.abs(m - a) < 0.25 * contrast, 7)
    near_b = ndimage.maximum_filter(np.abs(m - b) < 0.25 * contrast, 7)
    own = (np.abs(m - a) > reach) & (np.abs(m - b) > reach) & ~varies & ~(near_a & near_b)
    papery = ndimage.maximum_filter(np.abs(m - paper) < 0.25 * contrast, 5)
    return ground, float(np.mean(own)), float(np.mean(varies & ~papery))


def unframe(raster, front, side=None, *, view: int = 0, line_width: str = "radius"):
    """A framed ``(S, S)`` raster of view ``view`` (0 front, 1 side) back at the picture's
    size and placement: ``(H, W)`` bool, the inverse of :func:`frame_silhouettes` for the
    silhouettes ``front`` and ``side`` it framed (each picture pixel takes the raster pixel
    its centre falls in). ``fit-image`` writes the fitted tree so (``fit_<view>.png``),
    framed as the target's ``silhouette_<view>.png``.

    Examples
    --------
    >>> import numpy as np
    >>> f = np.zeros((100, 60), bool); f[10:100, 30] = True
    >>> back = unframe(frame_silhouettes(f, None, 16)[0], f)
    >>> back.shape, bool(back[10:, 30].all())
    ((100, 60), True)
    """
    raster = np.asarray(raster) > 0
    size = raster.shape[0]
    masks = [np.asarray(m, dtype=bool) for m in ((front,) if side is None else (front, side))]
    h, w = masks[view].shape
    r, c = np.mgrid[0:h, 0:w]
    r, c = r.ravel().astype(np.float64), c.ravel().astype(np.float64)
    if line_width == "thin":
        inputs = _thin_inputs(masks, size)
        geo, f = _thin_geometry([m for m, _, _ in inputs], size)
        _, _, rmax, _, base, _, _ = geo[view]
        fv = f[view]
        _, rows, cols = inputs[view]
        if rows is not None:  # drawn in square pixels: each picture pixel's drawn pixel
            r, c = rows[r.astype(np.int64)].astype(np.float64), cols[c.astype(np.int64)] * 1.0
        col = np.floor(0.5 * size + 0.5 + fv * (c + 0.5 - base))
        row = np.floor((size - MARGIN) - fv * (rmax + 1.0 - 0.5 / fv - (r + 0.5)))
    else:
        geo = [_view_geometry(m) for m in masks]
        k = frame_scale(1.0, max(g[5] for g in geo), size)
        _, _, rmax, hv, base, _ = geo[view]
        fv = k / hv
        x, y = frame_view(c + 0.5, rmax + 0.5 - r, base, 0.0, fv, size)
        row, col = np.floor(y + 0.5 * fv), np.floor(x)
    row, col = row.astype(np.int64), col.astype(np.int64)
    ok = (row >= 0) & (row < size) & (col >= 0) & (col < size)
    out = np.zeros(h * w, dtype=bool)
    out[ok] = raster[row[ok], col[ok]]
    return out.reshape(h, w)


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
    are segmented once in a process): do not change what it returns."""
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
