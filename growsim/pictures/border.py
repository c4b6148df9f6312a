"""A border around a photograph: a thin frame line or a narrow mat along its edges, put
there by whoever framed the picture, not part of the scene (:func:`paint_over_border`).

A border hides the sky along the top edge (the scene needs it,
:func:`~growsim.pictures.scene.find_scene`) and draws a sharp edge around the picture;
painted over with the picture's own outermost line inside it, the scene reaches the
edges again. Colours are compared in CIELAB (Delta E, CIE76).
"""

from __future__ import annotations

import numpy as np

__all__ = ["BORDER_DE", "BORDER_SHARE", "BORDER_SPREAD", "BORDER_UNLIKE", "paint_over_border"]

#: a border is at most this share of the picture's side wide
BORDER_SHARE = 0.03
#: ... each of its lines one colour: its pixels within this of the line's median (90th
#: percentile, Delta E; a JPEG's ringing beside a sharp edge included)
BORDER_SPREAD = 8.0
#: ... the lines within this of the outermost one's colour (Delta E), and most
#: (BORDER_UNLIKE) of the first line inside the border farther from it (a plain sky
#: along the top edge is one colour too, and so is the line inside it)
BORDER_DE = 10.0
BORDER_UNLIKE = 0.5


def _width(lab_lines: np.ndarray, most: int) -> int:
    """The border's width (lines) along one side, ``lab_lines`` ``(n, m, 3)`` its lines
    from the edge inwards: the lines of one colour from the edge, at most ``most``,
    followed by a line unlike it along a good part of it; 0 when there is none."""
    colour = np.median(lab_lines[0], axis=0)
    k = 0
    while k < min(most, len(lab_lines) - 1):
        line = lab_lines[k]
        own = np.linalg.norm(line - np.median(line, axis=0), axis=-1)
        if np.percentile(own, 90) > BORDER_SPREAD:
            break
        if np.linalg.norm(np.median(line, axis=0) - colour) > BORDER_DE:
            break
        k += 1
    if k == 0 or k >= len(lab_lines):
        return 0
    unlike = np.mean(np.linalg.norm(lab_lines[k] - colour, axis=-1) > BORDER_DE)
    return k if unlike >= BORDER_UNLIKE else 0


def paint_over_border(rgb: np.ndarray) -> tuple[np.ndarray, tuple[int, int, int, int]]:
    """``rgb`` ``(H, W, 3)`` in ``[0, 1]`` with its border painted over: on each side, the
    lines of one colour along the edge (each line's pixels within :data:`BORDER_SPREAD`
    of its median, the lines within :data:`BORDER_DE` of the outermost one, at most
    :data:`BORDER_SHARE` of the side) when the picture inside differs from them by more
    than :data:`BORDER_DE` along :data:`BORDER_UNLIKE` of the side, replaced by the first
    line inside.
    Returns the picture and the border's width ``(top, bottom, left, right)``, in lines
    (all 0, and ``rgb`` itself, when there is none: a plain sky reaching the top edge is
    one colour but does not stop).

    Examples
    --------
    >>> rgb = np.ones((100, 120, 3)) * [0.6, 0.75, 0.95]               # a blue sky
    >>> rgb[70:] = [0.3, 0.5, 0.2]                                     # the ground
    >>> framed = rgb.copy(); framed[:2] = 1.0; framed[-2:] = 1.0       # a white frame
    >>> framed[:, :2] = 1.0; framed[:, -2:] = 1.0
    >>> out, border = paint_over_border(framed)
    >>> border, bool(np.allclose(out, rgb))
    ((2, 2, 2, 2), True)
    >>> paint_over_border(rgb)[1]                                      # no frame
    (0, 0, 0, 0)
    """
    from skimage.color import rgb2lab

    h, w = rgb.shape[:2]
    widths = []
    for n, lines in (
        (h, lambda k: rgb[:k]),
        (h, lambda k: rgb[::-1][:k]),
        (w, lambda k: rgb[:, :k].transpose(1, 0, 2)),
        (w, lambda k: rgb[:, ::-1][:, :k].transpose(1, 0, 2)),
    ):
        most = int(BORDER_SHARE * n)
        widths.append(_width(rgb2lab(lines(most + 1)), most) if most >= 1 else 0)
    top, bottom, left, right = widths
    if not any(widths):
        return rgb, (0, 0, 0, 0)
    out = rgb.copy()
    if top:
        out[:top] = out[top]
    if bottom:
        out[h - bottom :] = out[h - bottom - 1]
    if left:
        out[:, :left] = out[:, left : left + 1]
    if right:
        out[:, w - right :] = out[:, w - right - 1 : w - right]
    return out, (top, bottom, left, right)
