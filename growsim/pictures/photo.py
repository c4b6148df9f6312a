"""Colour photos of a tree: the tree apart from the sky and the ground.

:func:`segment_photo` turns a colour picture (a tree standing on a ground strip under a
sky) into the tree's silhouette, or refuses it naming the picture; :func:`load_rgb`
reads a picture in colour. :func:`growsim.pictures.images.picture_silhouettes` calls it for
``segmentation = "photo"``; the grey-level threshold and the framing for fitting are in
:mod:`growsim.pictures.images`, the checks every silhouette passes in
:mod:`growsim.pictures.reading`. The steps it runs live in their own modules: the coarse
scene (:mod:`~growsim.pictures.scene`), the sky and the band at the working size
(:mod:`~growsim.pictures.sky`), the crown (:mod:`~growsim.pictures.crown`), each pixel's
coverage (:mod:`~growsim.pictures.coverage`), the trunk (:mod:`~growsim.pictures.trunk`)
and its foot (:mod:`~growsim.pictures.foot`), the refusals and hints
(:mod:`~growsim.pictures.hints`) and what is recorded (:mod:`~growsim.pictures.record`);
the names users import from here
(:class:`~growsim.pictures.record.Segmentation`, :func:`segmentation_picture`,
:func:`srgb_to_linear`, :func:`linear_to_srgb`, :func:`unmix`) are theirs.
"""

from __future__ import annotations

import os
import time
from dataclasses import replace

import numpy as np

from growsim.errors import UserInputError
from growsim.pictures.backdrop import sky_background
from growsim.pictures.border import paint_over_border
from growsim.pictures.colours import (
    MIN_PIXELS,
    background_coloured,
    cloud_colours,
    crown_coloured,
    paler_clouds,
    split_touching,
)
from growsim.pictures.coverage import (
    MIN_DE,
    NOISE_K,
    RINGING_WINDOW,
    linear_to_srgb,
    robust_sigma,
    srgb_to_linear,
    tree_cover,
    unmix,
)
from growsim.pictures.crown import (
    CROWN_MARGIN,
    CROWN_PAD,
    connected_tree,
    per_column,
    row_spans,
    upsample,
)
from growsim.pictures.foot import traced_trunk, trim_foot
from growsim.pictures.hints import (
    BOXED_AT_EDGE,
    MAX_CLUTTER,
    MAX_EDGE_PIXELS,
    MAX_SPILL,
    MIN_CONTRAST,
    WOOD_ROUGH,
    choose_tree,
    hint_pixels,
    in_box,
    judge_edges,
)
from growsim.pictures.learned import learned_below
from growsim.pictures.pieces import split_at_neck, trim_skirt
from growsim.pictures.reading import check_silhouette, load_gray, load_rgb, working_scale
from growsim.pictures.record import CONFIDENT, Segmentation, segmentation_picture
from growsim.pictures.scene import find_scene
from growsim.pictures.sky import (
    SMOOTH_BAND,
    band_follow,
    band_shift,
    plain_sky,
    smooth_sky,
    thin_lines,
)
from growsim.pictures.trunk import below_cut, hanging_trunk

__all__ = [
    "Segmentation",
    "linear_to_srgb",
    "load_rgb",
    "segment_photo",
    "segmentation_picture",
    "srgb_to_linear",
    "unmix",
]

#: the clouds taken for the crown are found and the sky filled in again with them at
#: most this many times
CLOUD_ROUNDS = 2
#: before a treeline the crown below its top is read by colour in the tree's columns and
#: this share of its width either side (a crown's low sides spread wider than its top)
TREELINE_MARGIN = 0.1
#: ... and refused when what is read reaches the edge of those columns in more than this
#: share of the rows read (the clutter has the crown's colours: mist under a cloud taken
#: for the crown, a bare crown before bare trees)
TREELINE_SPILL = 0.5
#: ... and only for a crown of leaves: at least this share of its pixels above the
#: treeline's top fully covered (their 3 x 3 all the crown's); a bare crown's twigs are
#: mixed pixels whose colour is neither the crown's nor the treeline's
TREELINE_SOLID = 0.6
#: ... and refused unless the silhouette then reaches within this share of its height of
#: the row where the ground begins (the trunk found down to it; a crown read only above
#: a hillside's or a hedge's top is not the tree)
TREELINE_GROUND = 0.05


def _before_treeline(rgb, tree, below, scene, obj, keep, rows):
    """The tree found above a treeline's top (``tree``, ``below`` the cut excluded) with
    its crown below that top, down to where the ground begins (``scene.ground_line``):
    the pixels in the object's columns (and :data:`TREELINE_MARGIN` of its width either
    side) of the crown's colours rather than those of the treeline beside it in its rows
    (:func:`~growsim.pictures.colours.crown_coloured`), joined to the tree. ``None`` when
    the crown is of twigs (:data:`TREELINE_SOLID`), the colours do not tell them apart, or
    what they take reaches the edge of those columns in most rows
    (:data:`TREELINE_SPILL`)."""
    from scipy import ndimage
    from skimage.color import rgb2lab

    h, w = tree.shape
    s = scene.scale
    lo, hi = int(obj.left / s), int(np.ceil((obj.right + 1) / s))
    m = int(np.ceil(TREELINE_MARGIN * (hi - lo)))
    span = np.zeros((1, w), dtype=bool)
    span[0, max(0, lo - m) : min(w, hi + m)] = True
    sky = upsample(scene.sky, (h, w), s)
    rows_of = below & (rows <= scene.ground_line / s) & keep  # the treeline's rows
    beside = rows_of & ~span & ~sky
    zone = rows_of & span
    sure = ndimage.binary_erosion(tree & ~below, np.ones((3, 3), dtype=bool))
    if sure.sum() < TREELINE_SOLID * (tree & ~below).sum():
        return None  # a crown of twigs: its pixels mixed with the treeline's behind them
    low = crown_coloured(rgb2lab(rgb), sure, beside, zone)
    if low is None:
        return None
    joined, _ = ndimage.label(tree | low, np.ones((3, 3), dtype=bool))
    out = np.isin(joined, np.unique(joined[tree])) & (joined > 0)
    # reaching the edge of the columns read in most rows: the clutter has its colours
    rows_read = np.flatnonzero(zone.any(axis=1))
    edges = np.flatnonzero(span[0])[[0, -1]]
    at_edge = (out[rows_read][:, edges[0] : edges[0] + 3].any(axis=1)
               | out[rows_read][:, edges[1] - 2 : edges[1] + 1].any(axis=1))  # fmt: skip
    if len(rows_read) and at_edge.mean() > TREELINE_SPILL:
        return None
    return out


def segment_photo(
    image,
    *,
    mask=None,
    box=None,
    point=None,
    name: str = "image",
    flags: tuple[str, str] = ("--box", "--point"),
) -> Segmentation:
    """Find the tree in a colour picture: apart from the sky, the ground and the clutter
    along the horizon.

    ``image``: a path or an ``(H, W, 3)`` RGB (or ``(H, W)`` grey) array in ``[0, 1]``;
    ``mask``: optional picture or array of the same size, only its light part (> 0.5) may
    be tree; ``box`` ``(x0, y0, x1, y1)``: the tree lies in this box; ``point``
    ``(x, y)``: a pixel on the tree (the hints, in pixels of the picture as given: a file
    is read at its working size, :func:`~growsim.pictures.reading.working_scale`);
    ``name`` labels errors, ``flags`` names the hints in them. Colours are compared in
    CIELAB (:func:`skimage.color.rgb2lab`; Delta E, CIE76).

    1. **the scene** (:func:`~growsim.pictures.scene.find_scene`, on the picture reduced):
       the sky (smooth, connected to the top edge: clouds and gradients included), the
       skyline, the horizon's band of clutter (its lower envelope), the objects standing
       on the band and rising into the sky; the tree is the largest (or the one at the
       hint), its crown's region that object, its trunk's columns where it enters the
       band; an object that is two trees of clearly different colours whose crowns touch
       is split in two (:func:`~growsim.pictures.colours.split_touching`: the other's
       pixels are never the tree's, :attr:`Segmentation.split` records it; a box around
       one of them is read against the split of the whole picture);
    2. each pixel's **background**: in the crown's region the sky filled in from the sky
       around and between the branches (:func:`~growsim.pictures.backdrop.sky_background`,
       thin lines left out: :data:`~growsim.pictures.sky.THIN_DE`), the sky's pockets in the crown
       added to it; in the trunk's columns below the band's top each row's colour beside the trunk,
       interpolated across it (:func:`~growsim.pictures.backdrop.row_background`: the
       ground, a hedge, a field behind the trunk);
    3. the **fully covered** pixels: the interior (3 x 3 erosion) of those over a local
       threshold (:data:`~growsim.pictures.coverage.LOCAL_SHARE` of the strongest difference within
       :data:`~growsim.pictures.coverage.LOCAL_WINDOW` pixels,
       :data:`~growsim.pictures.coverage.THICK_SHARE` of the full difference of the nearest thick
       part, the JPEG ringing share :data:`~growsim.pictures.coverage.RINGING`, never under
       :data:`~growsim.pictures.coverage.NOISE_K` times the sky's noise or
       :data:`~growsim.pictures.coverage.MIN_DE`);
    4. each pixel's **coverage** by linear unmixing in linear light (a camera's pixel
       sums the light of what it sees): its colour is its background's plus the coverage
       times the tree's colour minus the background's; the tree's colour is the nearest
       fully covered pixel's (within :data:`~growsim.pictures.coverage.UNMIX_REACH`) darkened by
       :data:`~growsim.pictures.coverage.RIM_SHADE` (a round part's rim is darker than its inside),
       or the median of them all (a thin twig, never fully covered), or the colour of a pixel of its
       3 x 3 (of its :data:`~growsim.pictures.coverage.THIN_WINDOW` on a thin twig) farther from the
       background than that. A pixel is tree when covered at least
       :data:`~growsim.pictures.coverage.COVERAGE` (a half, as the true silhouette of a render is
       defined) and more than the sky's noise, or fully covered;
    4b. under a sky that is not plain, the **clouds** taken for the crown (pieces of the
       sky's colours, not the crown's: a per-picture colour model,
       :func:`~growsim.pictures.colours.background_coloured`; the sky's colours are its own
       pixels' and those of the clouds seen away from the tree,
       :func:`~growsim.pictures.colours.cloud_colours`: a sunset's streaks, a cumulus's
       rims) are sky: the sky is filled in again with them and steps 3-4 run again (at
       most :data:`CLOUD_ROUNDS` times). Under a plain gradient with clouds away from the
       tree (a sunset's streaks) the pieces of their colours in the crown are sky too, the
       crown still read against the gradient;
    5. **connectivity** (:func:`skimage.measure.label`, 8-connected): the tree is the
       piece that holds most of the standing object, the pieces up to
       :data:`~growsim.pictures.crown.GAP` pixels from it (a twig broken by a pixel as pale as the
       sky) and every piece in the crown's region; below the band's top, the trunk's pieces joined
       to it, bridged over gaps up to :data:`~growsim.pictures.trunk.TRUNK_GAP` of its height (a
       trunk the colour of the hedge behind it); a flat piece reaching out from the trunk's
       foot (a shadow, a strip of darker ground) is dropped
       (:func:`~growsim.pictures.foot.trim_foot`);
    6. before a treeline taller than :data:`~growsim.pictures.hints.MAX_CLUTTER` of the tree,
       with no box, a leafy crown's part below the treeline's top is read by colour against
       the treeline's beside it, down to where the ground begins (:func:`_before_treeline`),
       and the trunk below that as in step 5; refused, naming the box, when it cannot be.

    Refused with :class:`UserInputError` naming ``name`` (a bad segmentation is not
    fitted): no sky along the top edge, no object standing on the ground, other objects
    as tall and large as the tree without a hint (the message names the hint that settles
    it), a tree that hardly differs from its background
    (:data:`~growsim.pictures.hints.MIN_CONTRAST`; with a box, GrabCut in it), a tree cut
    off by the top or side edges (:data:`~growsim.pictures.hints.MAX_EDGE_PIXELS`; with a
    box, twig tips grazing the top edge are whole: :func:`~growsim.pictures.hints.grazing`),
    and every silhouette :func:`~growsim.pictures.reading.check_silhouette` refuses.

    Examples
    --------
    >>> import numpy as np
    >>> from growsim.pictures.scene import example_photo
    >>> rgb = example_photo()  # sky, ground strip, a trunk standing on it, a branch
    >>> seg = segment_photo(rgb)
    >>> seg.horizon, int(seg.tree.sum()), bool(seg.tree[52, 25]), bool(seg.tree[52, 5])
    (50, 143, True, False)
    """
    from scipy import ndimage
    from skimage.color import gray2rgb, rgb2lab
    from skimage.morphology import disk

    t_start = time.perf_counter()
    per_pixel = 1.0  # working pixels per pixel of the picture as given (the hints')
    if isinstance(image, (str, os.PathLike)):
        name = str(image)
        per_pixel = working_scale(image)
        image = load_rgb(image)
    rgb = np.asarray(image, dtype=np.float64)
    if rgb.ndim == 2:
        rgb = gray2rgb(rgb)
    if rgb.ndim != 3 or rgb.shape[2] != 3 or rgb.shape[0] < 8 or rgb.shape[1] < 8:
        raise UserInputError(f"{name}: expected an RGB picture of at least 8 x 8, got {rgb.shape}")
    if float(np.ptp(rgb)) < 1e-6:
        raise UserInputError(f"{name}: the picture is uniform (blank): no silhouette to fit")
    # a frame line or a mat around the photograph is not the scene: painted over
    rgb, border = paint_over_border(np.clip(rgb, 0.0, 1.0))
    h, w = rgb.shape[:2]
    keep = np.ones((h, w), dtype=bool)
    if mask is not None:
        mname = str(mask) if isinstance(mask, (str, os.PathLike)) else f"{name} mask"
        m = load_gray(mask) if isinstance(mask, (str, os.PathLike)) else np.asarray(mask, float)
        if m.shape != rgb.shape[:2]:
            raise UserInputError(
                f"{mname}: mask size {m.shape[::-1]} differs from the image's {rgb.shape[1::-1]}"
            )
        keep = m > 0.5
        if not keep.any():
            raise UserInputError(f"{mname}: the mask keeps no pixel (it is all black)")
    hint: dict = {}
    if box is not None:
        (x0, y0, x1, y1), given = hint_pixels(box, 4, per_pixel, (h, w), flags[0], name)
        inside = np.zeros((h, w), dtype=bool)
        inside[max(0, int(y0)) : int(np.ceil(y1)), max(0, int(x0)) : int(np.ceil(x1))] = True
        allowed = keep.copy()
        keep &= inside
        hint["box"] = given
    at = None
    if point is not None:
        (px, py), given = hint_pixels(point, 2, per_pixel, (h, w), flags[1], name)
        hint["point"] = given
        at = (px, py, *given)
    try:
        scene = split_touching(find_scene(rgb, keep, name=name, hint=flags[0]))
        s = scene.scale
        how = f"{len(scene.objects)} standing object(s)"
        coarse_at = None if at is None else (at[0] * s, at[1] * s, at[2], at[3])
        obj = choose_tree(scene, coarse_at, box is not None, name, flags, how, per_pixel)
    except UserInputError:
        if box is None:
            raise
        # no sky, or nothing standing out of it: the tree is what the box holds apart
        # from what lies around it (GrabCut)
        return replace(in_box(rgb, keep, None, hint, per_pixel, name, t_start), border=border)
    if box is not None and obj.apart is None:
        obj = _split_in_whole(rgb, allowed, obj, name, flags[0])
    if box is None and obj.apart is None and scene.ground and scene.roughness <= WOOD_ROUGH:
        # a small tree at a side edge joined to the tree by a neck, over a smooth horizon
        # (before a hedge or a treeline the piece may be theirs): split off
        for side, col in (("left", 0), ("right", scene.shape[1] - 1)):
            if obj.mask[:, col].sum() >= MAX_EDGE_PIXELS:
                obj = split_at_neck(obj, scene.cut, side) or obj
    if box is None and scene.ground:
        # the horizon's low clutter joined to it from a side edge: not the tree
        for side, col in (("left", 0), ("right", scene.shape[1] - 1)):
            trimmed = obj.mask[:, col].sum() >= MAX_EDGE_PIXELS and trim_skirt(obj, scene.cut, side)
            if trimmed:
                obj, skirt = trimmed
                keep = keep & ~upsample(skirt, (h, w), s)
    split: tuple = ()
    if obj.apart is not None:
        # another tree touching it, split off: its pixels are never the tree's
        keep = keep & ~upsample(obj.apart, (h, w), s)
        rr, cc = np.nonzero(obj.apart)
        k = 1.0 / s
        split = ((round(cc.min() * k), round(rr.min() * k), round((cc.max() + 1) * k),
                  round((rr.max() + 1) * k)),)  # fmt: skip
    # the object reaching the picture's side (the box's, with a box): a tree cut off, or
    # one merging with a wood or other trees that do
    w_c = scene.shape[1]
    left, right = 0, w_c - 1
    if box is not None:
        left = max(0, int(np.ceil(max(box[0], 0.0) * per_pixel * s)))
        right = min(w_c - 1, int(box[2] * per_pixel * s) - 1)
    touching = [side for side, col in (("left", left), ("right", right))
                if obj.mask[:, col].sum() >= MAX_EDGE_PIXELS]  # fmt: skip
    # the horizon's clutter as tall as a good part of the tree: it stands in front of a
    # wood (its crown's lower part, its trunk among trees of its colours)
    band_at = float(np.median(scene.band[obj.left : obj.right + 1]))
    clutter = (scene.ground_line - band_at) / max(scene.ground_line - obj.top, 1.0)
    wooded = scene.roughness > WOOD_ROUGH  # a hill's or a field's smooth edge: no wood
    treeline = (scene.ground and wooded and clutter > MAX_CLUTTER
                and (box is not None or not touching))  # fmt: skip
    before_wood = (
        f"{name}: the tree stands in front of a wood or a treeline as tall as "
        f"{100 * clutter:.0f} % of it: give {flags[0]} x0,y0,x1,y1 around the tree"
    )
    if treeline and box is not None:
        # the box holds the tree and the wood behind it: GrabCut, the sky known (away from
        # the crown's outline, which the reduced picture blurs)
        sky = ndimage.binary_erosion(scene.sky, disk(2 * CROWN_MARGIN), border_value=1)
        seg = in_box(rgb, keep, upsample(sky, (h, w), s), hint, per_pixel, name, t_start)
        return replace(seg, border=border)
    if touching and box is None:
        raise UserInputError(
            f"{name}: the tree reaches the picture's {touching[0]} edge, or merges with "
            "something that does (a wood, a hedge, other trees): if the whole tree is in the "
            f"picture give {flags[0]} x0,y0,x1,y1 around it, else take it from farther away"
        )

    # the tree's region at the working size: its crown above the cut
    cut = per_column(scene.cut, w, s)
    band = per_column(scene.band, w, s)
    shift = 0
    if scene.ground:
        # the band at the working size: where the colour changes most across it, near
        # the coarse line (the texture's smoothing moved it a few pixels up)
        lo, hi = int(obj.left / s), int(np.ceil((obj.right + 1) / s))
        away = np.r_[0:lo, hi:w]
        shift = band_shift(rgb, band, away, int(np.ceil(3.0 / s)) + 1)
        rise = band - cut
        band = band + shift
        if scene.roughness <= SMOOTH_BAND:  # a clean horizon, a hill: its own outline
            band = band_follow(rgb, band, away, int(np.ceil(2.0 / s)) + 1)
        cut = band - rise
    rows = np.arange(h)[:, None]
    below = rows >= cut[None, :]
    core = upsample(ndimage.binary_dilation(obj.mask, disk(CROWN_MARGIN)), (h, w), s)
    if shift > 0:  # down to the band found at the working size
        core[shift:] |= core[:-shift].copy()
    core &= ~below & keep
    # the crown's region: each row from the object's leftmost to its rightmost pixel (twigs
    # too pale for the reduced picture lie between its branches)
    hull = row_spans(core) & ~below & keep
    crown = hull | (upsample(obj.region, (h, w), s) & ~below & keep)
    # and around it, twigs too faint for the reduced picture (they join when joined)
    rr, cc = np.nonzero(hull)
    if len(rr):
        m = int(np.ceil(CROWN_PAD * (rr.max() - rr.min() + 1)))
        around = np.zeros((h, w), dtype=bool)
        around[max(0, rr.min() - m) : rr.max() + 1, max(0, cc.min() - m) : cc.max() + m + 1] = True
        crown |= ndimage.binary_dilation(hull, np.ones((3, 3), bool), iterations=m) & around
        crown &= ~below & keep
    rr, cc = np.nonzero(crown)
    pad = RINGING_WINDOW + 2
    r0, r1 = max(0, rr.min() - pad), min(h, rr.max() + pad + 1)
    c0, c1 = max(0, cc.min() - pad), min(w, cc.max() + pad + 1)
    crop = (slice(r0, r1), slice(c0, c1))
    part = rgb[crop]
    lab = rgb2lab(part)
    crown_c = crown[crop]
    # the sky's own pixels: the scene's sky, less the thin lines it lost
    sky_c = upsample(scene.sky, (h, w), s)[crop]
    thin = thin_lines(lab)
    region = (core | upsample(obj.region, (h, w), s))[crop]
    ref = sky_c & ~thin & ~region
    if ref.sum() < 16:
        ref = sky_c & ~thin
    if ref.sum() < 16:
        ref = ~crown_c
    # a plain sky (a smooth gradient, no clouds) is its quadratic model, faint twigs
    # and all left out; any other sky is filled in from its pixels around the tree
    bg, noise = plain_sky(lab, ref, sky_c & ~thin)
    plain = bg is not None
    if not plain:
        bg = sky_background(lab, ref)
    dist = np.linalg.norm(lab - bg, axis=-1)
    # the smooth pixels of the sky's colours in the crown are the sky seen through it (a
    # cloud behind the crown, or joined to it in the reduced picture)
    seen = crown_c & ~thin & smooth_sky(lab, ref)
    if plain:
        dist[seen] = 0.0
    else:
        noise = max(robust_sigma(dist[ref]), 0.25)
        # the sky's pockets in the crown (between leaves and twigs) join its pixels: those
        # differing little from the sky filled in, and the smooth ones of the sky's
        # colours (a cloud behind the crown)
        pockets = crown_c & ~thin & (dist < max(NOISE_K * noise, 0.5 * MIN_DE)) | seen
        if pockets.any():
            bg = sky_background(lab, ref | pockets)
            dist = np.linalg.norm(lab - bg, axis=-1)
    fg, coverage, floor = tree_cover(part, lab, bg, dist, noise, crown_c)
    # the colours of the clouds seen away from the tree (a sunset's streaks, a cumulus's
    # rims and shadows): the same clouds behind the crown have them
    afar = cloud_colours(rgb, scene, obj, keep)
    if not plain or len(afar) >= MIN_PIXELS:
        # clouds behind or beside the crown, taken for it: pieces of the sky's colours
        # (its own, the clouds' away from the tree); they are sky. Under a sky that is
        # not plain the sky is filled in again with them (the leaves beside them are read
        # against the cloud, not the blue sky around the crown); a plain gradient with
        # streaks of cloud is still the gradient around them
        clouds = np.zeros_like(fg)
        for _ in range(CLOUD_ROUNDS):
            more = background_coloured(lab, fg, ref, crown_c, extra=afar) & ~clouds
            if not more.any():
                break
            clouds |= more
            if not plain:
                bg = sky_background(lab, ref | pockets | clouds)
                dist = np.linalg.norm(lab - bg, axis=-1)
                fg, coverage, floor = tree_cover(part, lab, bg, dist, noise, crown_c)
            fg &= ~clouds
        if not plain:
            # and clouds paler than the sky behind a tree darker than it, whatever the
            # tree's colour (a grey bare tree's twigs against white cumulus)
            fg &= ~paler_clouds(lab, bg, fg, crown_c, hull[crop], afar, floor)
    tree_c = connected_tree(fg, obj, hull[crop], (r0, c0), (h, w), s)
    tree = np.zeros((h, w), dtype=bool)
    tree[crop] = tree_c
    distance = np.zeros((h, w))
    distance[crop] = np.where(crown_c, dist, 0.0)
    cover = np.zeros((h, w))
    cover[crop] = np.where(crown_c, coverage, 0.0)
    steps = ()  # what the steps below the cut added (pixels)
    if scene.ground and tree.any():
        # a crown hanging in the sky: its trunk, the sky's colour, between it and the cut
        tree |= hanging_trunk(rgb, tree, obj, cut, s)
        # below the cut: the trunk and what hangs low, apart from the ground and the
        # horizon's clutter by their colours (GrabCut, seeded by the crown above)
        sky = upsample(scene.sky, (h, w), s) & ~below & ~tree
        under = below
        if treeline:
            # before a treeline: the crown below its top told from it by their colours
            # (a red maple before green trees), down to where the ground begins; the
            # trunk below that as under a lone tree. Refused when colours do not tell
            tree = _before_treeline(rgb, tree, below, scene, obj, keep, rows)
            if tree is None:
                raise UserInputError(before_wood)
            under = below & (rows > scene.ground_line / s)
        low, spill = below_cut(rgb, tree, under, sky, obj, s, keep)
        # a silhouette ending along the horizon: the tree below it learned from the picture
        # (before a treeline the crown was read down to the ground: below, only its trunk)
        first = int(low.sum())
        if not treeline:
            low = learned_below(rgb, tree, low, under, sky, obj, keep, cut, s)
        # a trunk that stops short of its foot: carried on down along its two edges
        traced = traced_trunk(rgb, tree | low, under, keep)
        tree |= low | traced
        # a shadow or a strip of darker ground joined at the trunk's foot: not the tree
        trimmed = trim_foot(tree)
        steps = (("learned_below", int(low.sum()) - first), ("traced_trunk", int(traced.sum())),
                 ("trimmed_foot", int((tree & ~trimmed).sum())))  # fmt: skip
        tree = trimmed
        filled = np.flatnonzero(tree.any(axis=1))
        if (treeline or obj.lifted) and (
            scene.ground_line / s - filled[-1] > TREELINE_GROUND * (filled[-1] - filled[0] + 1)
        ):
            # not read down to where the ground begins: the trunk missed; with a box, the
            # tree is what the box holds apart from what lies around it (GrabCut)
            if box is not None:
                return replace(in_box(rgb, keep, None, hint, per_pixel, name, t_start),
                               border=border)  # fmt: skip
            raise UserInputError(
                before_wood if treeline else
                f"{name}: the tree's trunk cannot be told from what lies behind it under "
                f"its wide crown: give {flags[0]} x0,y0,x1,y1 around the tree"
            )  # fmt: skip
        if spill > MAX_SPILL and box is None:
            raise UserInputError(
                f"{name}: the tree's lower part cannot be told from what stands behind it "
                f"(a wood, a hedge, other trees of its colours reach out to both sides of it "
                f"in {100 * spill:.0f} % of the rows below the skyline): give {flags[0]} "
                f"x0,y0,x1,y1 around the tree"
            )
    if obj.foot is not None:  # the ground the sky's colour: nothing below the trunk's end
        tree[int(np.ceil((obj.foot + 2) / s)) :] = False
    how = (f"{how}, sky noise {noise:.1f}, threshold >= {floor:.1f} Delta E")  # fmt: skip
    if not tree.any():
        raise UserInputError(f"{name}: the silhouette is empty ({how})")
    # measured on the crown, above the cut (below it GrabCut told the tree apart)
    judged = tree & ~below if (tree & ~below).any() else tree
    contrast = float(np.median(distance[judged]))
    outline = judged & ~ndimage.binary_erosion(tree, np.ones((3, 3), dtype=bool))
    outline_contrast = float(np.median(distance[outline])) if outline.any() else contrast
    confidence = float(np.mean(distance[outline] > CONFIDENT * floor)) if outline.any() else 0.0
    horizon = None
    ground = np.zeros((h, w), dtype=bool)
    if scene.ground:
        tr, tc = np.nonzero(tree)
        foot = tc[tr >= tr.max() - max(1, 0.02 * (tr.max() - tr.min()))]
        horizon = round(float(band[int(np.clip(np.median(foot), 0, w - 1))]))
        ground = (rows >= band[None, :]) & ~tree
    k = 1.0 / s
    objects = tuple(
        (o.left * k, o.top * k, (o.right + 1) * k, (o.bottom + 1) * k)
        for o in [obj, *[o for o in scene.objects if o is not obj]]
    )
    seg = Segmentation(
        tree, ground, horizon, distance, floor, noise, contrast, cover,
        sky=upsample(scene.sky, (h, w), s) & ~tree, band=band, cut=cut,
        objects=tuple(tuple(round(v) for v in o) for o in objects), hint=hint or None,
        method="sky and skyline", outline_contrast=outline_contrast, confidence=confidence,
        seconds=time.perf_counter() - t_start, hint_scale=per_pixel, split=split,
        border=border, steps=steps,
    )  # fmt: skip
    if contrast < MIN_CONTRAST:
        if box is not None:  # the tree is what the box holds apart from around it (GrabCut)
            return replace(in_box(rgb, keep, None, hint, per_pixel, name, t_start), border=border)
        raise UserInputError(
            f"{name}: the tree hardly differs from its background: median colour difference "
            f"{contrast:.1f} Delta E (at least {MIN_CONTRAST:g}; {how}); give {flags[0]} "
            "x0,y0,x1,y1 around the tree, use a picture with more contrast, or a mask"
        )
    edges = (("top", int(tree[0].sum())), ("left", int(tree[: int(cut[0]), 0].sum())),
             ("right", int(tree[: int(cut[-1]), -1].sum())))  # fmt: skip
    settle = (
        BOXED_AT_EDGE
        if box is not None
        else "it is cut off, or merges with something that does (a wood, other "
        f"trees): if the whole tree is in the picture give {flags[0]} x0,y0,x1,y1 "
        "around it, else take it from farther away"
    )
    seg = judge_edges(seg, edges, box is not None, name, settle, how)
    check_silhouette(tree, keep, name=name, how=how)
    return seg


def _split_in_whole(rgb, allowed, obj, name, flag):
    """The standing object ``obj`` found in a box, less the tree touching it that the box
    reaches into (a box around one of two touching crowns holds a piece of the other's):
    the two split on the whole picture (where ``allowed``), the part the box holds most of
    is ``obj``; ``obj`` as it is when there is none."""
    try:
        whole = split_touching(find_scene(rgb, allowed, name=name, hint=flag))
    except UserInputError:
        return obj
    parts = [o for o in whole.objects if o.apart is not None and o.mask.shape == obj.mask.shape]
    if not parts:
        return obj
    best = max(parts, key=lambda o: int((o.mask & obj.mask).sum()))
    if (best.mask & obj.mask).sum() < 0.5 * obj.area:
        return obj
    return replace(obj, mask=obj.mask & ~best.apart, apart=best.apart)
