"""Silhouettes framed for fitting: a front and a side silhouette into ``(2, S, S)`` rasters
(:func:`frame_silhouettes`, :func:`frame_thin_lines`), and a raster back at the picture's
size (:func:`unframe`).

:func:`frame_silhouettes` frames both views into ``(2, S, S)`` rasters with the framing of
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
  paper and format (PNG or JPEG). What no framing can know: a tree whose lowest point
  is not its trunk base (a branch hanging below it) is placed by its lowest rows.
"""

from __future__ import annotations

import numpy as np

from growsim.errors import UserInputError
from growsim.kernels.views import MARGIN, frame_scale, frame_view
from growsim.pictures.pixels import drawn_pixels

__all__ = ["COVER_SHARE", "frame_silhouettes", "frame_thin_lines", "picture_frame", "unframe"]

#: Share of the silhouette's height, at its bottom, whose pixels locate the trunk base.
BASE_BAND = 0.02
#: ``line_width = "radius"`` framing: a raster pixel at least this much covered by the
#: silhouette is set (measured on the photos of benchmarks/make_photos.py: the true
#: tree's NCC against its own framed silhouette at 64/128/256 px, zelkova 0.94/0.93/0.92
#: with 0.4, 0.93/0.91/0.91 with 0.5, 0.92/0.86/0.87 setting every pixel touched)
COVER_SHARE = 0.4


def _view_geometry(mask: np.ndarray):
    rows, cols = np.nonzero(mask)
    rmin, rmax = rows.min(), rows.max()
    h = max(float(rmax - rmin), 1.0)
    band = rows >= rmax - BASE_BAND * h
    base = float(cols[band].mean()) + 0.5
    hw = float(np.max(np.abs(cols + 0.5 - base))) / h
    return rows, cols, float(rmax), h, base, hw


def picture_frame(front: np.ndarray, side: np.ndarray | None = None, size: int = 256):
    """Where :func:`frame_silhouettes` (``line_width = "radius"``) puts the front
    picture's pixels: ``(base, rmax, f)``, the centre of the pixel in column ``c`` and row
    ``r`` of ``front`` landing at raster ``col = size / 2 + f (c + 0.5 - base)``,
    ``row = size - MARGIN - f (rmax - r)`` (``side``: the side picture framed with
    it, which shares the scale). A tree whose place in the picture is known (a
    reconstruction) is drawn so, where the picture shows it.

    Examples
    --------
    >>> f = np.zeros((101, 60), bool); f[0:101, 30] = True
    >>> picture_frame(f, None, 64)
    (30.5, 100.0, 0.63)
    """
    masks = [np.asarray(m, dtype=bool) for m in ((front,) if side is None else (front, side))]
    geo = [_view_geometry(m) for m in masks]
    k = frame_scale(1.0, max(g[5] for g in geo), int(size))
    _, _, rmax, h, base, _ = geo[0]
    return base, rmax, k / h


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
