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

from growsim.env.skeleton import checked_array, skeleton_arrays
from growsim.errors import UserInputError
from growsim.options import Options

__all__ = [
    "SHADOW_BIAS_PIXELS",
    "Direction",
    "Intensity",
    "Light",
    "check_direction",
    "point_light",
    "projected_area",
    "segment_light",
    "view_basis",
]


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

    def segment_light(
        self,
        skeleton,
        end=None,
        radius=None,
        offsets=None,
        resolution: int = 256,
        bias: float = 1.5,
        samples: int = 1,
    ) -> np.ndarray:
        """``(n,)`` light on each segment of ``skeleton`` (a Plant, a mapping of arrays, or
        ``start`` with ``end`` and ``radius``) from this light, hard shadows, one shadow map
        per plant of ``offsets``: :func:`segment_light` with :attr:`direction` and
        :attr:`intensity` (the ``diffuse`` share is not used yet).

        Examples
        --------
        >>> from growsim.models import honda
        >>> tree = honda.develop(honda.PRESETS["zelkova"])
        >>> light = Light().segment_light(tree)
        >>> light.shape == (tree.n_segments,), bool(0 < light.mean() < 1)
        (True, True)
        """
        return segment_light(
            skeleton, end, radius, offsets, self.direction, self.intensity, resolution, bias,
            samples,
        )  # fmt: skip

    def point_light(self, skeleton, *args, **options) -> np.ndarray:
        """``(m,)`` light at ``points`` with ``normals`` ``(m, 3)`` in the shadows of
        ``skeleton``: :func:`point_light` (same arguments) with :attr:`direction` and
        :attr:`intensity`.

        Examples
        --------
        >>> import numpy as np
        >>> leaf = dict(start=[[0.0, 2, 0]], end=[[2.0, 2, 0]], radius=[0.5])
        >>> Light(intensity=0.5).point_light(leaf, points=[[1.0, 0, 0]], normals=[[0, 1, 0]])
        array([0.])
        """
        return point_light(
            skeleton, *args, direction=self.direction, intensity=self.intensity, **options
        )


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


# --------------------------------------------------------------------------- shadow-map light

#: default depth bias of the shadow map, in pixels (times the pixel size: world units)
SHADOW_BIAS_PIXELS = 1.5


def _shadow_direction(where: str, direction) -> np.ndarray:
    d = np.asarray(direction, dtype=np.float64)
    if d.shape != (3,) or not np.all(np.isfinite(d)) or np.linalg.norm(d) == 0:
        raise UserInputError(
            f"{where}: direction must be a finite non-zero 3-vector, got {direction!r}"
        )
    return d / np.linalg.norm(d)


def _shadow_offsets(where: str, name: str, offsets, n: int) -> np.ndarray:
    if offsets is None:
        return np.array([0, n], np.int64)
    off = np.ascontiguousarray(offsets, dtype=np.int64)
    if off.ndim != 1 or len(off) < 1 or off[0] != 0 or off[-1] != n or np.any(np.diff(off) < 0):
        raise UserInputError(
            f"{where}: {name} must rise from 0 to {n} (plant k is offsets[k]:offsets[k + 1]), "
            f"got {offsets!r}"
        )
    return off


def _shadow_skeleton(where: str, skeleton, end, radius):
    """``start, end, radius, normal or None, kind or None`` from a Plant, a mapping or arrays."""
    if end is not None or radius is not None:
        skeleton = {"start": skeleton, "end": end, "radius": radius}
    a = skeleton_arrays(skeleton, where, topology=False)
    n = a["start"].shape[0]
    normal = a["data"].get("normal") if hasattr(a["data"], "get") else None
    if normal is not None:
        normal = checked_array(where, "normal", normal, (3,), n)
    return a["start"], a["end"], a["radius"], normal, a["kind"]


def _shadow_resolution(where: str, resolution) -> int:
    res = int(resolution)
    if res < 8 or res > 8192:
        raise UserInputError(f"{where}: resolution {res} not in [8, 8192]")
    return res


def segment_light(
    start,
    end=None,
    radius=None,
    offsets=None,
    direction=(0.0, -1.0, 0.0),
    intensity: float = 1.0,
    resolution: int = 256,
    bias: float = SHADOW_BIAS_PIXELS,
    samples: int = 1,
) -> np.ndarray:
    """Light on each segment from a parallel light, with hard shadows (a shadow map).

    ``start`` is a :class:`growsim.plant.Plant`, a mapping of arrays (``start``, ``end``,
    ``radius``, optional ``kind`` and ``normal``) or the ``(n, 3)`` start points with
    ``end`` ``(n, 3)`` and ``radius`` ``(n,)``. ``offsets`` ``(k + 1,)`` splits the
    segments into ``k`` plants (plant ``k`` is ``offsets[k]:offsets[k + 1]``; default one
    plant); each plant gets its own shadow map, so plants never shade each other.

    Per plant, the segments are rendered as capsules of their radius into an orthographic
    z-buffer along ``direction`` (``resolution`` pixels across the plant's shadow, framed as
    :func:`projected_area`). A segment's sample points (``samples`` of them, at
    ``t = (i + 0.5) / samples`` of its axis; default its midpoint) are lit when the nearest
    thing at their pixel is the segment itself or lies at most ``bias`` pixels (times the
    pixel size, in depth) in front of them. Returns ``(n,)`` float64::

        light = intensity x (share of samples lit) x cos

    with ``cos = |normal . d|`` for a LEAF whose skeleton gives a unit ``normal``
    (``data["normal"]``, two-sided blades) and otherwise the side of a cylinder,
    ``cos = sqrt(1 - (axis . d)^2)``, the sine of the angle between axis and light (its
    projected side area over its broadside area). End caps are not counted: in a skeleton
    they are joints. So a vertical stem under light from straight above gets 0.

    Raises :class:`growsim.errors.UserInputError` for a zero or non-finite direction, a
    non-finite coordinate, radius or normal (naming the array and row), a negative radius
    or bad offsets.

    Examples
    --------
    >>> import numpy as np
    >>> start = np.array([[0.0, 2, 0], [0, 0, 0], [5, 0, 0]])
    >>> end = np.array([[1.0, 2, 0], [1, 0, 0], [5, 1, 0]])
    >>> r = np.full(3, 0.3)
    >>> segment_light(start, end, r).round(3).tolist()  # the lower leaf is in the shade
    [1.0, 0.0, 0.0]
    >>> segment_light(start, end, r, direction=(1, 0, 0)).round(3).tolist()  # from the side
    [0.0, 0.0, 1.0]
    >>> segment_light(start, end, r, offsets=[0, 1, 3]).round(3).tolist()  # two plants
    [1.0, 1.0, 0.0]
    """
    from growsim.kernels.light import segment_light_kernel
    from growsim.plant import LEAF

    where = "segment_light"
    d = _shadow_direction(where, direction)
    s, e, r, normal, kind = _shadow_skeleton(where, start, end, radius)
    n = s.shape[0]
    off = _shadow_offsets(where, "offsets", offsets, n)
    res = _shadow_resolution(where, resolution)
    if not (math.isfinite(bias) and bias >= 0):
        raise UserInputError(f"{where}: bias must be a finite number >= 0, got {bias!r}")
    samples = int(samples)
    if samples < 1:
        raise UserInputError(f"{where}: samples must be >= 1, got {samples}")
    intensity = float(intensity)
    if not (math.isfinite(intensity) and intensity >= 0):
        raise UserInputError(f"{where}: intensity must be finite and >= 0, got {intensity!r}")
    if normal is None:
        normal = np.zeros((n, 3))
        use = np.zeros(n, np.bool_)
    else:
        norm = np.linalg.norm(normal, axis=1)
        use = norm > 0 if kind is None else (norm > 0) & (kind == LEAF)
        normal = np.ascontiguousarray(normal / np.where(norm > 0, norm, 1.0)[:, None])
    u, v = view_basis(d)
    out = np.empty(n)
    return segment_light_kernel(
        s, e, r, off, normal, use, u, v, d, intensity, res, float(bias), samples, out
    )


def point_light(
    start,
    end=None,
    radius=None,
    offsets=None,
    *,
    points,
    normals,
    point_offsets=None,
    direction=(0.0, -1.0, 0.0),
    intensity: float = 1.0,
    resolution: int = 256,
    bias: float = SHADOW_BIAS_PIXELS,
) -> np.ndarray:
    """Light at sample points with normals, in the plants' hard shadows.

    The skeleton and ``offsets`` are as in :func:`segment_light`; ``points`` and
    ``normals`` are ``(m, 3)``; ``point_offsets`` ``(k + 1,)`` assigns points
    ``point_offsets[k]:point_offsets[k + 1]`` to plant ``k`` (default: all points to the
    one plant). Returns ``(m,)`` float64 ``intensity x lit x max(0, -n . d)`` (``n`` the
    unit normal; a surface facing the light has ``n . d < 0``). A point is lit when no part
    of its plant lies more than ``bias`` pixels in front of it at its pixel of the plant's
    shadow map (points outside the map are lit).

    Examples
    --------
    >>> import numpy as np
    >>> leaf = np.array([[0.0, 2, 0]]), np.array([[2.0, 2, 0]]), np.array([0.5])
    >>> ground = np.array([[1.0, 0, 0], [5, 0, 0]]); up = np.array([[0.0, 1, 0], [0, 1, 0]])
    >>> point_light(*leaf, points=ground, normals=up).tolist()  # under the leaf, in the open
    [0.0, 1.0]
    >>> point_light(*leaf, points=ground, normals=up, direction=(-1, -1, 0)).round(3).tolist()
    [0.707, 0.707]
    """
    from growsim.kernels.light import point_light_kernel

    where = "point_light"
    d = _shadow_direction(where, direction)
    s, e, r, _, _ = _shadow_skeleton(where, start, end, radius)
    off = _shadow_offsets(where, "offsets", offsets, s.shape[0])
    pts = checked_array(where, "points", points, (3,), None)
    m = pts.shape[0]
    nrm = checked_array(where, "normals", normals, (3,), m)
    norm = np.linalg.norm(nrm, axis=1)
    if m and norm.min() == 0:
        raise UserInputError(f"{where}: normals: row {int(np.argmin(norm))} is zero")
    nrm = np.ascontiguousarray(nrm / norm[:, None]) if m else nrm
    if point_offsets is None:
        if len(off) != 2:
            raise UserInputError(f"{where}: point_offsets is required with several plants")
        poff = np.array([0, m], np.int64)
    else:
        poff = _shadow_offsets(where, "point_offsets", point_offsets, m)
        if len(poff) != len(off):
            raise UserInputError(
                f"{where}: point_offsets has {len(poff) - 1} plants, offsets {len(off) - 1}"
            )
    res = _shadow_resolution(where, resolution)
    if not (math.isfinite(bias) and bias >= 0):
        raise UserInputError(f"{where}: bias must be a finite number >= 0, got {bias!r}")
    intensity = float(intensity)
    if not (math.isfinite(intensity) and intensity >= 0):
        raise UserInputError(f"{where}: intensity must be finite and >= 0, got {intensity!r}")
    u, v = view_basis(d)
    out = np.empty(m)
    return point_light_kernel(
        s, e, r, off, pts, nrm, poff, u, v, d, intensity, res, float(bias), out
    )
