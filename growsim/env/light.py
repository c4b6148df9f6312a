"""Light: the parallel light of ``[environment.light]`` and orthographic projection.

A :class:`Light` is a parallel source (``direction`` the light travels, ``intensity``)
with an optional ``diffuse`` share of sky light. The functions below work on plain
segment arrays (``(n, 3)`` end points and ``(n,)`` radii), so any skeleton can use
them, whatever model grew it:

- :func:`view_basis`: the image plane of an orthographic view along a direction;
- :func:`projected_area`: the area of the segments' orthographic shadow along a direction
  (each segment a tube of its radius, rasterised; overlaps count once);
- :meth:`Light.captured`: intensity times the shadow area along the light: the light a
  set of segments intercepts when they shade each other.

The shadow-map light (per-segment light with a z-buffer) grows from here.
"""

from __future__ import annotations

import math
from typing import Annotated

import numpy as np
from pydantic import AfterValidator, Field

from growsim.errors import UserInputError
from growsim.options import Options

__all__ = ["Direction", "Intensity", "Light", "check_direction", "projected_area", "view_basis"]


def check_direction(v: list[float]) -> list[float]:
    """``v`` if it is a finite non-zero 3-vector, else ``ValueError`` (for validators).

    Examples
    --------
    >>> check_direction([0.0, -1.0, 0.0])
    [0.0, -1.0, 0.0]
    """
    if len(v) != 3 or not all(math.isfinite(x) for x in v) or math.hypot(*v) == 0.0:
        raise ValueError(f"expected a finite non-zero 3-vector, got {v!r}")
    return v


#: a light direction: 3 finite numbers, not all zero (y up; ``[0, -1, 0]`` is from above)
Direction = Annotated[
    list[float], Field(min_length=3, max_length=3), AfterValidator(check_direction)
]
#: a light intensity (1 = full light)
Intensity = Annotated[float, Field(ge=0.0, le=1e6)]


class Light(Options):
    """``[environment.light]``: a parallel light from one direction, plus sky light.

    Examples
    --------
    >>> Light(intensity=0.5).direction
    [0.0, -1.0, 0.0]
    """

    direction: Direction = Field(
        default_factory=lambda: [0.0, -1.0, 0.0],
        description="direction the parallel light travels (y up: [0, -1, 0] is from above)",
    )
    intensity: Intensity = Field(1.0, description="light intensity (1 = full light)")
    diffuse: float = Field(
        0.0, ge=0.0, le=1.0, description="share of the light that comes from the whole sky"
    )

    def captured(self, start, end, radius, resolution: int = 256) -> float:
        """Light intercepted by the segments: ``intensity * projected_area`` along
        :attr:`direction` (segments that shade each other count once).

        Examples
        --------
        >>> import numpy as np
        >>> leaf = dict(start=np.zeros((1, 3)), end=np.array([[4.0, 0, 0]]), radius=np.array([0.5]))
        >>> round(Light(intensity=0.5).captured(**leaf, resolution=512), 2)
        2.39
        """
        area = projected_area(start, end, radius, self.direction, resolution)
        return float(self.intensity * area)


def view_basis(direction) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors ``(u, v)`` spanning the image plane of an orthographic view along
    ``direction`` ``(3,)``: ``u`` is horizontal (right), ``v`` is the screen's up as far as
    possible (world y, or world z when looking straight up or down).

    Examples
    --------
    >>> u, v = view_basis((0, 0, -1))   # the front view, looking along -z
    >>> u.round(3).tolist(), v.round(3).tolist()
    ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0])
    """
    d = np.asarray(direction, dtype=np.float64)
    d = d / np.linalg.norm(d)
    up = np.array([0.0, 1.0, 0.0]) if abs(d[1]) < 0.99 else np.array([0.0, 0.0, -1.0])
    u = np.cross(d, up)
    u /= np.linalg.norm(u)
    v = np.cross(u, d)
    # ``+ 0.0`` turns -0.0 into 0.0 so printed bases read cleanly.
    return u + 0.0, v / np.linalg.norm(v) + 0.0


def projected_area(start, end, radius, direction=(0.0, -1.0, 0.0), resolution: int = 256) -> float:
    """Area (world units²) of the orthographic shadow of segments along ``direction``.

    ``start``, ``end``: ``(n, 3)`` float arrays; ``radius``: ``(n,)``. Each segment is a
    tube of its radius; the shadow is rasterised with the shared kernel
    :func:`growsim.kernels.raster.draw_segments` on a ``resolution`` ² grid framing the
    shadow, and the covered pixels are counted. The default direction is light from
    straight above. Segments thinner than a pixel count as one pixel wide, so thin twigs
    are over-estimated by at most half a pixel on each side.

    Examples
    --------
    >>> import numpy as np
    >>> a, b = np.zeros((1, 3)), np.array([[4.0, 0.0, 0.0]])
    >>> round(projected_area(a, b, np.array([0.5]), resolution=512), 1)  # 4 x 1 + pi/4
    4.8
    """
    from growsim.kernels.raster import draw_segments

    d = np.asarray(direction, dtype=np.float64)
    if d.shape != (3,) or not np.all(np.isfinite(d)) or np.linalg.norm(d) == 0:
        raise UserInputError(
            f"projected_area: direction must be a non-zero 3-vector, got {direction!r}"
        )
    resolution = int(resolution)
    if resolution < 8 or resolution > 8192:
        raise UserInputError(f"projected_area: resolution {resolution} not in [8, 8192]")
    start = np.asarray(start, dtype=np.float64).reshape(-1, 3)
    end = np.asarray(end, dtype=np.float64).reshape(-1, 3)
    r = np.asarray(radius, dtype=np.float64).reshape(-1)
    if len(r) == 0:
        return 0.0
    u, v = view_basis(d)
    a = np.stack([start @ u, start @ v], axis=1)
    b = np.stack([end @ u, end @ v], axis=1)
    rmax = float(r.max())
    lo = np.minimum(a.min(0), b.min(0)) - rmax
    hi = np.maximum(a.max(0), b.max(0)) + rmax
    size = float((hi - lo).max())
    if size <= 0:
        return 0.0
    # Leave one pixel of margin each side so clipping never trims the shadow.
    pix = size / (resolution - 2)
    origin = lo - pix
    img = np.zeros((resolution, resolution), np.uint8)
    draw_segments(
        np.ascontiguousarray((a - origin) / pix),
        np.ascontiguousarray((b - origin) / pix),
        np.ascontiguousarray(2.0 * r / pix),
        img,
    )
    return float(np.count_nonzero(img)) * pix * pix
