"""The tree's pixels told from their background, pixel by pixel: local thresholds on the
colour difference find the fully covered pixels, linear unmixing in linear light every
pixel's coverage (:func:`tree_cover`; sRGB and linear light: :func:`srgb_to_linear`,
:func:`linear_to_srgb`, :func:`unmix`). :func:`growsim.pictures.photo.segment_photo` reads
the crown against the sky behind it so, and :mod:`growsim.pictures.trunk` the trunk against
the ground beside it.
"""

from __future__ import annotations

import numpy as np

__all__ = ["linear_to_srgb", "robust_sigma", "srgb_to_linear", "tree_cover", "unmix"]

# How segment_photo tells the tree's pixels from their background. Measured on the
# benchmark's pictures (benchmarks/make_photos.py: JPEG renders of growsim trees on a
# ground plane under a sky), on composites of trees on outdoor backgrounds and on
# growsim's line drawings.
#: Fully covered pixels (the interior of the tree's thick parts) are found first by local
#: thresholds on the colour difference: this share of the strongest difference within a
#: window of this many pixels, never under NOISE_K times the background's noise nor MIN_DE
LOCAL_WINDOW = 7
LOCAL_SHARE = 0.3
#: JPEG compression rings beside a strong edge (up to the far side of its 8 x 8 block):
#: pixels under this share of the strongest difference within RINGING_WINDOW pixels are
#: background
RINGING = 0.15
RINGING_WINDOW = 17
NOISE_K = 5.0
#: beside a thick part (pixels whose whole 3 x 3 neighbourhood differs from the
#: background) a pixel differing by less than this share of the full difference within
#: LOCAL_WINDOW pixels is background
THICK_SHARE = 0.4
#: every pixel's coverage by linear unmixing in linear light: the tree's colour at a pixel
#: is the nearest fully covered pixel's up to this many pixels from it, the median of
#: the fully covered pixels beyond (thin twigs); a pixel is tree when covered at least
#: half (COVERAGE), as the true silhouette is defined
UNMIX_REACH = 3.0
COVERAGE = 0.5
#: a round part's surface turns away from the light toward its outline (Lambert's cosine
#: law), so a partly covered pixel at its rim sees a darker tree than the nearest fully
#: covered pixel inside: that colour darkened by this share in linear light. A Lambert
#: cylinder lit from the camera's side with a fifth ambient light is 0.42 darker on the
#: outer quarter of its width than on its middle half; 0.3 allows for light from other
#: sides.
RIM_SHADE = 0.3
#: a thin twig (no fully covered pixel within UNMIX_REACH) takes the colour of its most
#: covered pixel up to this many pixels along it (its best-centred pixel recurs every few
#: pixels along a slanted twig); near thick parts, of its 3 x 3 only
THIN_WINDOW = 3
MIN_DE = 10.0


def srgb_to_linear(v):
    """sRGB values in ``[0, 1]`` to linear light (IEC 61966-2-1), where colours mix as
    light does: a pixel a camera sees half covered by a branch has the mean of the
    branch's and the sky's linear colours, not of their sRGB values.

    Examples
    --------
    >>> round(float(srgb_to_linear(0.5)), 4), float(srgb_to_linear(1.0))
    (0.214, 1.0)
    """
    v = np.clip(np.asarray(v, dtype=np.float64), 0.0, 1.0)
    return np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4)


def linear_to_srgb(v):
    """Linear light in ``[0, 1]`` to sRGB values, the inverse of :func:`srgb_to_linear`.

    Examples
    --------
    >>> round(float(linear_to_srgb(srgb_to_linear(0.3))), 6)
    0.3
    """
    v = np.clip(np.asarray(v, dtype=np.float64), 0.0, 1.0)
    return np.where(v <= 0.0031308, 12.92 * v, 1.055 * v ** (1 / 2.4) - 0.055)


def unmix(colour, background, tree) -> np.ndarray:
    """Linear unmixing: the share ``a`` of each pixel covered by the tree, from
    ``colour = background + a (tree - background)`` (least squares over the channels);
    ``(H, W, C)`` arrays in one colour space (linear light for a camera's picture).

    Examples
    --------
    >>> sky, bark = np.array([0.8, 0.9, 1.0]), np.array([0.2, 0.15, 0.1])
    >>> px = (0.3 * bark + 0.7 * sky)[None, None]
    >>> round(float(unmix(px, sky[None, None], bark[None, None])[0, 0]), 6)
    0.3
    """
    fb = tree - background
    return np.einsum("ijk,ijk->ij", colour - background, fb) / np.maximum(
        np.einsum("ijk,ijk->ij", fb, fb), 1e-12
    )


def robust_sigma(x) -> float:
    """The robust standard deviation of ``x``: 1.4826 times the median absolute
    deviation from the median (0 for no values).

    Examples
    --------
    >>> robust_sigma([1.0, 2.0, 3.0, 4.0, 100.0])  # the outlier does not count
    1.4826
    """
    x = np.asarray(x, np.float64)
    return float(1.4826 * np.median(np.abs(x - np.median(x)))) if x.size else 0.0


def tree_cover(rgb, lab, bg, dist, noise, keep):
    """The tree's pixels by their difference from the background ``bg`` (CIELAB): fully
    covered pixels by local thresholds, then every pixel's coverage by linear unmixing
    (steps 3 and 4 of :func:`~growsim.pictures.photo.segment_photo`); returns ``(fg, coverage,
    floor)``.

    Examples
    --------
    >>> from skimage.color import rgb2lab
    >>> rgb = np.ones((20, 20, 3)) * [0.8, 0.9, 1.0]; rgb[5:15, 9:11] = [0.3, 0.25, 0.2]
    >>> lab, bg = rgb2lab(rgb), rgb2lab(np.ones((20, 20, 3)) * [0.8, 0.9, 1.0])
    >>> dist = np.linalg.norm(lab - bg, axis=-1)
    >>> fg, coverage, floor = tree_cover(rgb, lab, bg, dist, 0.5, np.ones((20, 20), bool))
    >>> int(fg.sum()), floor, round(float(coverage[10, 9]), 2)
    (20, 10.0, 1.0)
    """
    from scipy import ndimage
    from skimage.color import lab2rgb

    h, w = dist.shape
    dist = np.where(keep, dist, 0.0)
    floor = max(NOISE_K * noise, MIN_DE)
    local = ndimage.maximum_filter(dist, size=LOCAL_WINDOW, mode="nearest")
    # JPEG rings around strong edges up to the 8 x 8 block's far side
    ringing = ndimage.maximum_filter(dist, size=RINGING_WINDOW, mode="nearest")
    threshold = np.maximum(np.maximum(LOCAL_SHARE * local, RINGING * ringing), floor)
    # thick parts: the least difference of a 3 x 3 neighbourhood is the full difference of
    # a fully covered pixel; near them the share is THICK_SHARE of it. A thin twig has no
    # fully covered pixel (its eroded difference is the sky's) and keeps LOCAL_SHARE of its
    # own peak, so 1-pixel twigs are not erased.
    thick = ndimage.maximum_filter(
        ndimage.minimum_filter(dist, size=3, mode="nearest"), size=LOCAL_WINDOW, mode="nearest"
    )
    threshold = np.maximum(threshold, THICK_SHARE * thick)
    fg = (dist > threshold) & keep
    # fully covered pixels: the interior of what the thresholds take (a drawing's lines
    # one or two pixels wide have none: then those lines themselves)
    full = ndimage.binary_erosion(fg, np.ones((3, 3), dtype=bool))
    interior = full.copy()
    if not full.any():
        full = fg
    coverage = np.zeros((h, w))
    if not full.any():
        return fg, coverage, floor
    # every pixel's coverage by linear unmixing in linear light (a camera's pixel sums the
    # light of the tree and of the sky it sees): colour = background + a (tree -
    # background), the tree's colour the nearest fully covered pixel's, or, beyond
    # UNMIX_REACH (a thin twig, never fully covered), the median of them all
    light = srgb_to_linear(rgb)
    back = srgb_to_linear(lab2rgb(bg))
    reach, (ir, ic) = ndimage.distance_transform_edt(~full, return_indices=True)
    colour = np.where(
        (reach <= UNMIX_REACH)[..., None], light[ir, ic], np.median(light[full], axis=0)
    )
    rim = (reach > 0) & (reach <= UNMIX_REACH)
    colour = np.where(rim[..., None], (1.0 - RIM_SHADE) * colour, colour)
    coverage = unmix(light, back, colour)
    # a part's rim may be darker (or paler) still: where a pixel of the 3 x 3 (of the
    # THIN_WINDOW around a thin twig's pixel) is farther from the background than that
    # colour, its colour is the tree's
    k = THIN_WINDOW
    thin = reach > UNMIX_REACH
    pad = np.pad(coverage, k, mode="edge")
    lpad = np.pad(light, ((k, k), (k, k), (0, 0)), mode="edge")
    best = np.ones((h, w))
    for dy in range(2 * k + 1):
        for dx in range(2 * k + 1):
            a = pad[dy : dy + h, dx : dx + w]
            better = a > best
            if max(abs(dy - k), abs(dx - k)) > 1:
                better &= thin
            best = np.where(better, a, best)
            colour = np.where(better[..., None], lpad[dy : dy + h, dx : dx + w], colour)
    coverage = unmix(light, back, colour)
    fg = ((coverage >= COVERAGE) & (dist > NOISE_K * noise) | interior) & keep
    return fg, coverage, floor
