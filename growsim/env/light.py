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

- :func:`segment_light`, :func:`point_light`: the shadow-map light on each segment or at
  sample points with normals, hard or soft shadows, one map per plant of a population,
  on the CPU (numba, :mod:`growsim.kernels.light`) or through OpenGL
  (:mod:`growsim.env.shadow_gl`); :meth:`Light.segment_light` adds the sky
  (:func:`sky_directions`) and reads the settings of ``[environment.light]``.
"""

from __future__ import annotations

import math
import threading
from typing import Annotated, Literal

import numpy as np
from pydantic import AfterValidator, Field

from growsim.env.copies import copies_exposure
from growsim.env.shadow_gl import point_exposure_gl, segment_exposure_gl
from growsim.errors import UserInputError
from growsim.kernels import light as kernels
from growsim.kernels.light import shadow_scratch
from growsim.kernels.raster import draw_segments
from growsim.options import Options
from growsim.skeleton import LEAF, checked_array, skeleton_arrays

__all__ = [
    "DEFAULT_RESOLUTION",
    "SHADOW_BIAS_PIXELS",
    "Direction",
    "Intensity",
    "Light",
    "check_direction",
    "point_light",
    "projected_area",
    "segment_light",
    "sky_directions",
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

#: default depth bias of the shadow map, in pixels (times the pixel size: world units)
SHADOW_BIAS_PIXELS = 0.1
#: default shadow-map resolution (pixels across each plant)
DEFAULT_RESOLUTION = 64


class Light(Options):
    """``[environment.light]``: a parallel light from one direction, plus sky light.

    The light on a surface is ``intensity x ((1 - diffuse) x E(direction) + diffuse x
    sum_k w_k E(d_k))``: ``E(d)`` the exposure along ``d`` (1 in the open, 0 in a hard
    shadow, a transmitted share in a soft one; :func:`segment_light`) times Lambert's
    cosine, and ``(d_k, w_k)`` the :attr:`sky` directions of :func:`sky_directions`.

    Examples
    --------
    >>> Light(intensity=0.5).direction
    [0.0, -1.0, 0.0]
    >>> Light(shadows="soft", transmission=0.5).shadows
    'soft'
    """

    direction: Direction = Field(
        default_factory=lambda: [0.0, -1.0, 0.0],
        description="direction the parallel light travels (y up: [0, -1, 0] is from above)",
    )
    intensity: Intensity = Field(1.0, description="light intensity (1 = full light)")
    diffuse: float = Field(
        0.0, ge=0.0, le=1.0, description="share of the light that comes from the whole sky"
    )
    sky: int = Field(
        6, ge=1, le=256, description="directions of the sky light (the diffuse share), >= 1"
    )
    shadows: Literal["hard", "soft"] = Field(
        "hard",
        description="hard: binary shadow map; soft: each segment crossed passes `transmission`",
    )
    transmission: float = Field(
        0.25,
        ge=0.0,
        le=1.0,
        description="soft shadows: share of the light one segment crossed lets through",
    )
    resolution: int = Field(
        DEFAULT_RESOLUTION, ge=8, le=8192, description="shadow-map pixels across each plant"
    )
    bias: float = Field(
        SHADOW_BIAS_PIXELS, ge=0.0, le=100.0, description="shadow-map depth bias, in pixels"
    )
    backend: Literal["numba", "moderngl"] = Field(
        "numba", description="shadow map on the CPU (numba) or through OpenGL (moderngl)"
    )
    walls: Literal["exact", "module"] = Field(
        "exact",
        description="hormone model: each wall's light at its own point (exact), or one "
        "shadow-map point per module and light shared by its walls, each its own cosine "
        "(module: faster in 3D)",
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

    def directions(self) -> tuple[np.ndarray, np.ndarray]:
        """``(k, 3)`` unit directions and ``(k,)`` weights of this light: the direct beam
        (weight ``1 - diffuse``) and, when ``diffuse > 0``, the :attr:`sky` directions
        (weights ``diffuse x w_k``).

        Examples
        --------
        >>> d, w = Light(diffuse=0.25, sky=4).directions()
        >>> d.shape, round(float(w[0]), 2), round(float(w[1:] @ -d[1:, 1]), 2)
        ((5, 3), 0.75, 0.25)
        """
        d = np.asarray(self.direction, np.float64)
        d = (d / np.linalg.norm(d))[None, :]
        w = np.array([1.0 - self.diffuse])
        if self.diffuse > 0.0:
            sd, sw = sky_directions(self.sky)
            d = np.concatenate([d, sd])
            w = np.concatenate([w, self.diffuse * sw])
        return d, w

    def segment_light(
        self, skeleton, end=None, radius=None, offsets=None, samples: int = 1, resolution=None,
        shifts=None,
    ) -> np.ndarray:  # fmt: skip
        """``(n,)`` light on each segment of ``skeleton`` (a Plant, a mapping of arrays, or
        ``start`` with ``end`` and ``radius``), one shadow map per plant of ``offsets`` and
        direction: the weighted sum over :meth:`directions` of :func:`segment_light` with
        this light's intensity, shadows, transmission, resolution (or ``resolution``),
        bias and backend. ``shifts`` ``(k, 3)``: each plant is also shaded by its copies
        moved by these offsets (a periodic stand), which are not judged.

        Examples
        --------
        >>> from growsim.models import honda
        >>> tree = honda.develop(honda.PRESETS["zelkova"])
        >>> light = Light().segment_light(tree)
        >>> light.shape == (tree.n_segments,), bool(0 < light.mean() < 1)
        (True, True)
        >>> sky = Light(diffuse=0.5).segment_light(tree)  # the sky lights the shaded ones
        >>> bool((sky[light == 0] > 0).mean() > 0.5)
        True
        >>> near = [[15.0, 0, 0], [-15.0, 0, 0]]  # two copies 15 m away shade it
        >>> bool(Light().segment_light(tree, shifts=near).sum() < light.sum())
        True
        """
        dirs, weights = self.directions()
        out = None
        extra = {} if shifts is None else {"shifts": shifts}
        for d, w in zip(dirs, weights):
            if w == 0.0:
                continue
            part = segment_light(
                skeleton, end, radius, offsets, d, self.intensity * w,
                resolution or self.resolution, self.bias, samples, self.shadows,
                self.transmission, self.backend, **extra,
            )  # fmt: skip
            out = part if out is None else out + part
        return out

    def point_light(
        self, skeleton, end=None, radius=None, offsets=None, *, points, normals,
        point_offsets=None, resolution=None,
    ) -> np.ndarray:  # fmt: skip
        """``(m,)`` light at ``points`` with ``normals`` ``(m, 3)`` in the shadows of
        ``skeleton``: :func:`point_light` (same arguments) summed over :meth:`directions`
        (one kernel call for them all), with this light's settings.

        Examples
        --------
        >>> import numpy as np
        >>> leaf = dict(start=[[0.0, 2, 0]], end=[[2.0, 2, 0]], radius=[0.5])
        >>> Light(intensity=0.5).point_light(leaf, points=[[1.0, 0, 0]], normals=[[0, 1, 0]])
        array([0.])
        """
        dirs, weights = self.directions()
        return point_light(
            skeleton, end, radius, offsets, points=points, normals=normals,
            point_offsets=point_offsets, direction=dirs, intensity=self.intensity * weights,
            resolution=resolution or self.resolution, bias=self.bias, shadows=self.shadows,
            transmission=self.transmission, backend=self.backend,
        )  # fmt: skip

    def passes(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``(d, u, v, w)``: this light's unit directions ``(j, 3)`` (:meth:`directions`),
        their image planes ``u, v`` (:func:`view_basis`) and intensities ``w`` ``(j,)``
        (intensity times weight): the lights :func:`growsim.kernels.light.point_light_into`
        takes, for a model that calls it from its own kernel (the hormone model).

        Examples
        --------
        >>> d, u, v, w = Light(diffuse=0.5, sky=3, intensity=2.0).passes()
        >>> d.shape, u.shape, float(w[0])
        ((4, 3), (4, 3), 1.0)
        """
        dirs, weights = self.directions()
        return _shadow_passes("light", dirs, self.intensity * weights)


def sky_directions(count: int) -> tuple[np.ndarray, np.ndarray]:
    """``count`` directions of sky light (unit vectors travelling downwards, y up) and
    their weights, for a standard overcast sky.

    The directions are a Fibonacci lattice over the upper hemisphere (equal solid angles,
    ``cos(zenith) = 1 - (k + 0.5) / count``, azimuths turning by the golden angle); each
    weighs its CIE standard overcast radiance ``(1 + 2 cos z) / 3`` (Moon & Spencer 1942),
    normalised so that an open horizontal surface facing up receives 1:
    ``sum_k w_k cos z_k = 1``. One direction is straight down.

    Examples
    --------
    >>> d, w = sky_directions(6)
    >>> d.shape, bool(np.all(d[:, 1] < 0)), round(float(w @ -d[:, 1]), 12)
    ((6, 3), True, 1.0)
    >>> sky_directions(1)[0].tolist()
    [[0.0, -1.0, 0.0]]
    """
    count = int(count)
    if count < 1:
        raise UserInputError(f"sky: needs at least 1 direction, got {count}")
    if count == 1:
        return np.array([[0.0, -1.0, 0.0]]), np.array([1.0])
    k = np.arange(count)
    cz = 1.0 - (k + 0.5) / count
    sz = np.sqrt(1.0 - cz * cz)
    az = k * math.pi * (3.0 - math.sqrt(5.0))
    d = np.stack([sz * np.cos(az), -cz, sz * np.sin(az)], axis=1)
    w = (1.0 + 2.0 * cz) / 3.0
    return d, w / (w @ cz)


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
    """``start, end, radius, data, kind`` from a Plant, a mapping or arrays (``data`` the
    optional per-segment arrays: ``normal``, ``transmission``)."""
    if end is not None or radius is not None:
        skeleton = {"start": skeleton, "end": end, "radius": radius}
    a = skeleton_arrays(skeleton, where, topology=False)
    data = a["data"] if hasattr(a["data"], "get") else {}
    return a["start"], a["end"], a["radius"], data, a["kind"]


def _shadow_resolution(where: str, resolution) -> int:
    res = int(resolution)
    if res < 8 or res > 8192:
        raise UserInputError(f"{where}: resolution {res} not in [8, 8192]")
    return res


def _shadow_intensity(where: str, intensity) -> float:
    intensity = float(intensity)
    if not (math.isfinite(intensity) and intensity >= 0):
        raise UserInputError(f"{where}: intensity must be finite and >= 0, got {intensity!r}")
    return intensity


def _shadow_options(where, resolution, bias, shadows, backend) -> tuple[int, float]:
    """Checked ``(resolution, bias)`` of shadow-map passes (and the shadows and backend)."""
    res = _shadow_resolution(where, resolution)
    if not (math.isfinite(bias) and bias >= 0):
        raise UserInputError(f"{where}: bias must be a finite number >= 0, got {bias!r}")
    if shadows not in ("hard", "soft"):
        raise UserInputError(f"{where}: shadows must be 'hard' or 'soft', got {shadows!r}")
    if backend not in ("numba", "moderngl"):
        raise UserInputError(f"{where}: backend must be 'numba' or 'moderngl', got {backend!r}")
    if backend == "moderngl" and shadows == "soft":
        raise UserInputError(f"{where}: soft shadows need backend 'numba' (moderngl: hard only)")
    return res, float(bias)


def _shadow_settings(where, direction, intensity, resolution, bias, shadows, backend):
    """Checked ``(d, u, v, intensity, resolution, bias)`` of one shadow-map pass."""
    d = _shadow_direction(where, direction)
    intensity = _shadow_intensity(where, intensity)
    res, bias = _shadow_options(where, resolution, bias, shadows, backend)
    u, v = view_basis(d)
    return d, u, v, intensity, res, bias


def _shadow_passes(where, direction, intensity):
    """Checked ``(d, u, v, w)`` of one or several lights: ``(j, 3)`` unit directions and
    their image planes, ``(j,)`` intensities (one ``intensity`` broadcast to them all)."""
    dirs = np.asarray(direction, dtype=np.float64)
    dirs = dirs.reshape(1, -1) if dirs.ndim == 1 else dirs
    if dirs.ndim != 2 or len(dirs) == 0:
        raise UserInputError(f"{where}: direction must be (3,) or (j, 3), got {direction!r}")
    d = np.array([_shadow_direction(where, x) for x in dirs])
    w = np.asarray(intensity, dtype=np.float64).reshape(-1)
    if len(w) == 1:
        w = np.repeat(w, len(d))
    if len(w) != len(d):
        raise UserInputError(f"{where}: {len(w)} intensities for {len(d)} directions")
    w = np.array([_shadow_intensity(where, x) for x in w])
    basis = [view_basis(x) for x in d]
    u = np.array([b[0] for b in basis])
    v = np.array([b[1] for b in basis])
    return d, u, v, w


_SCRATCH = threading.local()


def _scratch(res: int) -> tuple:
    """This thread's shadow-map scratch of ``res`` pixels
    (:func:`growsim.kernels.light.shadow_scratch`), made once: the kernels leave it ready
    for the next call, and its pages stay mapped (a fresh one at 1024 px costs thousands
    of page faults a call). One per thread, as the kernels release the GIL."""
    cache = getattr(_SCRATCH, "maps", None)
    if cache is None:
        cache = _SCRATCH.maps = {}
    if res not in cache:
        cache[res] = shadow_scratch(res)
    return cache[res]


def _transmissions(where: str, data, transmission, n: int) -> np.ndarray:
    """``(n,)`` per-segment transmission: ``data["transmission"]`` or the scalar."""
    per = data.get("transmission")
    if per is not None:
        t = checked_array(where, "transmission", per, (), n)
    else:
        t = np.full(n, float(transmission))
    if t.size and (t.min() < 0.0 or t.max() > 1.0):
        bad = int(np.argmax((t < 0.0) | (t > 1.0)))
        raise UserInputError(f"{where}: transmission: segment {bad} is not in [0, 1]")
    return t


def segment_light(
    start,
    end=None,
    radius=None,
    offsets=None,
    direction=(0.0, -1.0, 0.0),
    intensity: float = 1.0,
    resolution: int = DEFAULT_RESOLUTION,
    bias: float = SHADOW_BIAS_PIXELS,
    samples: int = 1,
    shadows: str = "hard",
    transmission: float = 0.25,
    backend: str = "numba",
    shifts=None,
) -> np.ndarray:
    """Light on each segment from a parallel light through a shadow map.

    ``start`` is a :class:`growsim.phenotypes.plant.Plant`, a mapping of arrays (``start``, ``end``,
    ``radius``, optional ``kind``, ``normal`` and ``transmission``) or the ``(n, 3)`` start
    points with ``end`` ``(n, 3)`` and ``radius`` ``(n,)``. ``offsets`` ``(k + 1,)`` splits
    the segments into ``k`` plants (plant ``k`` is ``offsets[k]:offsets[k + 1]``; default one
    plant); each plant gets its own shadow map, so plants never shade each other.

    Per plant, the segments are rendered as capsules of their radius into an orthographic
    map along ``direction`` (``resolution`` pixels across the plant's shadow, framed as
    :func:`projected_area`; rules in :mod:`growsim.kernels.light`). A segment's sample
    points (``samples`` of them, at ``t = (i + 0.5) / samples`` of its axis; default its
    midpoint) get an exposure: with ``shadows="hard"``, 1 when the nearest thing at their
    pixel is the segment itself or lies at most ``bias`` pixels (times the pixel size, in
    depth) in front of them, else 0; with ``shadows="soft"``, the product of the
    ``transmission`` of every other segment lying in front of them by more than the bias
    (a per-segment ``transmission`` array in the skeleton overrides the scalar). Returns
    ``(n,)`` float64::

        light = intensity x (mean exposure of the samples) x cos

    with ``cos = |normal . d|`` for a LEAF whose skeleton gives a unit ``normal``
    (``data["normal"]``, two-sided blades) and otherwise the side of a cylinder,
    ``cos = sqrt(1 - (axis . d)^2)``, the sine of the angle between axis and light (its
    projected side area over its broadside area). End caps are not counted: in a skeleton
    they are joints. So a vertical stem under light from straight above gets 0.
    ``backend="moderngl"`` renders the hard map through OpenGL
    (:mod:`growsim.env.shadow_gl`).

    ``shifts`` ``(k, 3)`` (a periodic stand, :func:`growsim.kernels.stand.periodic_shifts`):
    every plant is also shaded by ``k`` copies of itself moved by these offsets. The
    copies' segments join the plant's map (framed over the plant and its copies, as an
    explicit stand of the same copies is) but are not judged: the result is the plant's
    ``(n,)``, as the same plant at the centre of an explicit stand of copies gets it.
    ``None`` (default) or no rows: the plant alone, bit for bit as without the argument.

    Raises :class:`growsim.errors.UserInputError` for a zero or non-finite direction, a
    non-finite coordinate, radius or normal (naming the array and row), a negative radius,
    bad offsets or a bad setting.

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
    >>> segment_light(start, end, r, shadows="soft", transmission=0.5).round(3).tolist()
    [1.0, 0.5, 0.0]
    >>> segment_light(start[2:], end[2:], r[2:], shifts=[[-5.0, 2, 0]]).tolist()  # a copy
    [0.0]
    """

    where = "segment_light"
    d, u, v, intensity, res, bias = _shadow_settings(
        where, direction, intensity, resolution, bias, shadows, backend
    )
    s, e, r, data, kind = _shadow_skeleton(where, start, end, radius)
    n = s.shape[0]
    off = _shadow_offsets(where, "offsets", offsets, n)
    samples = int(samples)
    if samples < 1:
        raise UserInputError(f"{where}: samples must be >= 1, got {samples}")
    normal = data.get("normal")
    if normal is None:  # no blades: every segment is a cylinder
        normal = np.empty((0, 3))
        use = np.empty(0, np.bool_)
    else:
        normal = checked_array(where, "normal", normal, (3,), n)
        norm = np.linalg.norm(normal, axis=1)
        use = norm > 0 if kind is None else (norm > 0) & (kind == LEAF)
        normal = np.ascontiguousarray(normal / np.where(norm > 0, norm, 1.0)[:, None])
    sh = None if shifts is None else checked_array(where, "shifts", shifts, (3,), None)
    if sh is not None and len(sh):  # shaded by copies that are not judged
        out = copies_exposure(
            (s, e, r, off), sh, (u, v, d), samples, (res, bias, shadows == "soft"),
            _transmissions(where, data, transmission, n) if shadows == "soft" else None,
            backend, _scratch(res),
        )  # fmt: skip
        return kernels.apply_cosines(s, e, normal, use, d, intensity, out)
    frames = kernels.plant_frames(s, e, r, off, u, v, res)
    if backend == "moderngl" and shadows == "hard":
        out = segment_exposure_gl(s, e, r, off, frames, u, v, d, res, bias, samples)
    else:
        soft = shadows == "soft"
        trans = _transmissions(where, data, transmission, n) if soft else np.empty(0)
        out = kernels.segment_exposure_into(
            (s, e, r, off), frames, (u, v, d), samples, (res, bias, soft, trans),
            _scratch(res), np.empty(n),
        )  # fmt: skip
    return kernels.apply_cosines(s, e, normal, use, d, intensity, out)


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
    intensity=1.0,
    resolution: int = DEFAULT_RESOLUTION,
    bias: float = SHADOW_BIAS_PIXELS,
    shadows: str = "hard",
    transmission: float = 0.25,
    backend: str = "numba",
) -> np.ndarray:
    """Light at sample points with normals (a module's walls), in the plants' shadows.

    The skeleton, ``offsets`` and the settings are as in :func:`segment_light`; ``points``
    and ``normals`` are ``(m, 3)``; ``point_offsets`` ``(k + 1,)`` assigns points
    ``point_offsets[k]:point_offsets[k + 1]`` to plant ``k`` (default: all points to the
    one plant). Returns ``(m,)`` float64 ``intensity x exposure x max(0, -n . d)`` (``n`` the
    unit normal; a surface facing the light has ``n . d < 0``). A point's exposure is
    judged against every segment of its plant (points outside the map are in the open).
    ``direction`` may also be ``(j, 3)`` with ``intensity`` ``(j,)``: the sum over the
    ``j`` lights, each with its own maps (a sun and its sky, :meth:`Light.point_light`),
    in one kernel call on the numba backend.

    Examples
    --------
    >>> import numpy as np
    >>> leaf = np.array([[0.0, 2, 0]]), np.array([[2.0, 2, 0]]), np.array([0.5])
    >>> ground = np.array([[1.0, 0, 0], [5, 0, 0]]); up = np.array([[0.0, 1, 0], [0, 1, 0]])
    >>> point_light(*leaf, points=ground, normals=up).tolist()  # under the leaf, in the open
    [0.0, 1.0]
    >>> point_light(*leaf, points=ground, normals=up, direction=(-1, -1, 0)).round(3).tolist()
    [0.707, 0.707]
    >>> point_light(*leaf, points=ground, normals=up, shadows="soft", transmission=0.2).tolist()
    [0.2, 1.0]
    >>> point_light(*leaf, points=ground, normals=up, direction=[(0, -1, 0), (-1, -1, 0)],
    ...             intensity=[1.0, 0.5]).round(3).tolist()  # two lights
    [0.354, 1.354]
    """

    where = "point_light"
    d, u, v, w = _shadow_passes(where, direction, intensity)
    res, bias = _shadow_options(where, resolution, bias, shadows, backend)
    s, e, r, data, _ = _shadow_skeleton(where, start, end, radius)
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
    if backend == "numba":
        soft = shadows == "soft"
        trans = _transmissions(where, data, transmission, s.shape[0]) if soft else np.empty(0)
        return kernels.point_light_into(
            (s, e, r, off), (pts, poff, nrm), (d, u, v, w), (res, bias, soft, trans),
            _scratch(res), np.empty(m), np.zeros((0, 3)),
        )  # fmt: skip

    out = np.zeros(m)
    for k in range(len(d)):
        if w[k] == 0.0:
            continue
        frames = kernels.plant_frames(s, e, r, off, u[k], v[k], res)
        part = point_exposure_gl(s, e, r, off, frames, pts, poff, u[k], v[k], d[k], res, bias)
        out += part * np.maximum(0.0, -(nrm @ d[k])) * w[k]
    return out
