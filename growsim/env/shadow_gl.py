"""OpenGL (moderngl) backend of the shadow-map light: hard shadows on the GPU.

Same contract, rules and frames as the numba kernels' hard shadows
(:func:`growsim.kernels.light.segment_exposure_into`, the exposure part of
:func:`growsim.kernels.light.point_light_into`; see :mod:`growsim.kernels.light`): every
plant gets its own ``res`` x ``res`` map in the frame of
:func:`growsim.kernels.light.plant_frames`; segment ``k`` covers the pixels whose centre
lies within ``R = radius[k] / pix`` pixels of its projected axis (the true radius, as in
the numba kernels), with the depth
of the axis point nearest the pixel centre; each pixel keeps the nearest depth and that
segment's index; a sample is lit when outside the frame, on an empty pixel, on a pixel
its own segment holds, or when ``z - depth <= bias_pixels * pix``.

Design
------
- **Atlas.** One depth texture (``DEPTH_COMPONENT32F``; moderngl's 24-bit one when the
  driver refuses) and one ``R32I`` segment-id texture, side by side ``res`` x ``res``
  tiles, one tile per plant; plants beyond the atlas's capacity go in further batches.
  The atlas is at most :data:`ATLAS_SIDE` texels a side (and within the driver's
  texture and viewport limits).
- **Render.** One indexed draw per batch (per :data:`CHUNK_SEGMENTS` segments), two
  triangles per segment: an oriented rectangle around the capsule (grown by
  :data:`PAD_PIXELS` so the rasteriser never misses a pixel centre on its border),
  placed in its plant's tile by an offset in the vertex shader (no viewport switching).
  The vertex shader picks its corner from ``gl_VertexID & 3``; each segment's data is
  repeated on its four vertices (40 bytes each): the capsules are drawn as instances
  would be, one per segment, but faster than instanced 4-vertex strips on llvmpipe
  (such small instances also pack badly on GPUs). The fragment shader takes the pixel
  centre ``gl_FragCoord.xy - tile``, discards it outside the tile or farther than ``R``
  from the axis, and writes ``gl_FragDepth`` (the axis depth at the nearest point,
  normalised per plant to ``[0, 1/2]`` over the plant's own depth range, so the cleared
  value 1 means empty) and the segment's index. The depth test ``<`` keeps the nearest
  fragment, the first drawn (the lowest index) on a tie, as the numba z-buffer does.
- **Query.** The samples' pixels are found on the CPU in float64 (numba,
  :mod:`growsim.kernels.shadow_gl`: the same arithmetic as the numba kernels, so every
  sample picks the same pixel), then a
  transform-feedback pass (at most :data:`CHUNK_SAMPLES` samples each) ``texelFetch``-es
  the depth and id textures and returns one float per sample: 2 when lit for sure
  (outside the frame, empty pixel, own segment), else the pixel's normalised depth. The
  depth test is done back on the CPU in world units and float64:
  ``z - (zmin + depth * 2 (zmax - zmin)) <= bias_pixels * pix``.

One lazily created standalone context (EGL first, then the platform's default) with its
programs and buffers per process; calls are serialised by a lock
and make the context current on the calling thread (restoring the one that was). No
context, or a process forked from one that used it (the driver's state does not survive
``fork()``; workers must be started with ``spawn`` or ``forkserver``):
:class:`growsim.errors.ResourceError`.

Speed
-----
On Mesa's llvmpipe (2 cores) the backend runs at 0.4-1.4 Mseg/s for 1000 plants x 300
segments at 64-256 pixels, 2-3 times slower than the single-threaded numba kernels: the
software rasteriser's cost per triangle and per fragment dominates. It is ahead only for
one plant a call at 512 pixels and more (the numba kernels allocate ``res^2`` maps per
call) and at 1024 pixels for up to about 100 plants a call (even with 1000). It is meant
for real GPUs, where rasterising is nearly free and the CPU work left (vertices, sample
pixels and the final test, in numba: about 0.2 us a segment) bounds it.
"""

from __future__ import annotations

import ctypes
import math
import os
import sys
import threading

import numpy as np

from growsim.errors import ResourceError
from growsim.kernels.shadow_gl import (
    VERTEX_FLOATS,
    depth_ranges,
    point_queries,
    resolve_exposure,
    segment_queries,
    tile_vertices,
)

__all__ = [
    "ATLAS_SIDE",
    "CHUNK_SAMPLES",
    "CHUNK_SEGMENTS",
    "PAD_PIXELS",
    "point_exposure_gl",
    "renderer",
    "segment_exposure_gl",
]

#: largest side of the tile atlas, in texels (depth + id: 8 bytes a texel, 128 MiB at 4096)
ATLAS_SIDE = 4096
#: the capsule's rectangle is grown by this many pixels each way, so that pixel centres on
#: its border survive the rasteriser's snapping (the fragment shader's test is exact)
PAD_PIXELS = 0.125
#: segments per draw call (their vertices: 4 x 40 bytes each, 20 MiB)
CHUNK_SEGMENTS = 1 << 17
#: samples per query pass (12 bytes each, 12 MiB)
CHUNK_SAMPLES = 1 << 20

_RENDER_VS = """
#version 330
in vec4 ab;
in vec3 zr;
in vec2 tile;
in int sid;
uniform vec2 atlas;
uniform float pad;
flat out vec4 v_ab;
flat out vec3 v_zr;
flat out vec2 v_tile;
flat out int v_sid;
void main() {
    vec2 a = ab.xy;
    vec2 b = ab.zw;
    float r = zr.z + pad;
    vec2 d = b - a;
    float L = length(d);
    vec2 t = L > 0.0 ? d / L : vec2(1.0, 0.0);
    vec2 n = vec2(-t.y, t.x);
    int c = gl_VertexID & 3;
    vec2 base = (c & 2) != 0 ? b + t * r : a - t * r;
    vec2 pos = base + n * ((c & 1) != 0 ? r : -r);
    gl_Position = vec4((tile + pos) / atlas * 2.0 - 1.0, 0.0, 1.0);
    v_ab = ab;
    v_zr = zr;
    v_tile = tile;
    v_sid = sid;
}
"""

_RENDER_FS = """
#version 330
flat in vec4 v_ab;
flat in vec3 v_zr;
flat in vec2 v_tile;
flat in int v_sid;
uniform float res;
out int id;
void main() {
    vec2 p = gl_FragCoord.xy - v_tile;
    if (p.x < 0.0 || p.y < 0.0 || p.x >= res || p.y >= res) discard;
    vec2 a = v_ab.xy;
    vec2 d = v_ab.zw - a;
    vec2 e = p - a;
    float L2 = dot(d, d);
    float t = L2 > 0.0 ? clamp(dot(e, d) / L2, 0.0, 1.0) : 0.0;
    vec2 q = e - t * d;
    if (dot(q, q) > v_zr.z * v_zr.z) discard;
    gl_FragDepth = v_zr.x + t * (v_zr.y - v_zr.x);
    id = v_sid;
}
"""

_QUERY_VS = """
#version 330
uniform sampler2D depth_tex;
uniform isampler2D id_tex;
uniform int width;
in int texel;
in int own;
out float val;
void main() {
    val = 2.0;
    if (texel >= 0) {
        ivec2 xy = ivec2(texel % width, texel / width);
        float z = texelFetch(depth_tex, xy, 0).r;
        if (z < 1.0 && texelFetch(id_tex, xy, 0).r != own) val = z;
    }
}
"""

_GL_TEXTURE_2D = 0x0DE1
_GL_DEPTH_COMPONENT = 0x1902
_GL_FLOAT = 0x1406
_GL_DEPTH_COMPONENT24 = 0x81A6
_GL_DEPTH_COMPONENT32F = 0x8CAC
_GL_TEXTURE_DEPTH_SIZE = 0x884A
_GL_TEXTURE_DEPTH_TYPE = 0x8C16


class _GL:
    """The process's context, programs, atlas and buffers."""

    def __init__(self, moderngl, ctx):
        self.mgl = moderngl
        self.ctx = ctx
        self.pid = os.getpid()
        self.lock = threading.Lock()
        self.renderer = f"{ctx.info['GL_RENDERER']} (OpenGL {ctx.info['GL_VERSION']})"
        limits = (ctx.info["GL_MAX_TEXTURE_SIZE"], *ctx.info["GL_MAX_VIEWPORT_DIMS"])
        self.max_side = min(int(x) for x in limits)
        self.render = ctx.program(vertex_shader=_RENDER_VS, fragment_shader=_RENDER_FS)
        self.render["pad"] = PAD_PIXELS
        self.query = ctx.program(vertex_shader=_QUERY_VS, varyings=["val"])
        self.query["depth_tex"] = 0
        self.query["id_tex"] = 1
        self.vertices = ctx.buffer(reserve=1 << 20)
        self.queries = ctx.buffer(reserve=1 << 20)
        self.results = ctx.buffer(reserve=1 << 20)
        self.index = ctx.buffer(reserve=1 << 20)
        self.quads = 0
        self.render_vao = ctx.vertex_array(
            self.render,
            [(self.vertices, "4f 3f 2f 1i", "ab", "zr", "tile", "sid")],
            index_buffer=self.index,
            index_element_size=4,
        )
        self.query_vao = ctx.vertex_array(self.query, [(self.queries, "1i 1i", "texel", "own")])
        self.idle = ctx.framebuffer(color_attachments=[ctx.renderbuffer((1, 1))])
        self.size = (0, 0)
        self.depth = self.ids = self.fbo = None
        self.depth_bits = 0

    def reserve(self, segments, samples):
        """Room for ``segments`` segments a draw (their indices: two triangles each) and
        ``samples`` query results."""
        if self.quads < segments:
            quad = np.array([0, 1, 2, 1, 2, 3], np.int32)
            self.index.orphan(24 * segments)
            self.index.write(np.arange(segments, dtype=np.int32)[:, None] * 4 + quad)
            self.quads = segments
        if self.results.size < 4 * samples:
            self.results.orphan(4 * samples)

    def atlas(self, width, height):
        """An atlas of at least ``width`` x ``height`` texels: the current one if it fits
        and is not over 4 times as large, else a new one of exactly that size."""
        w, h = self.size
        if w >= width and h >= height and w * h <= 4 * width * height:
            return
        for obj in (self.fbo, self.depth, self.ids):
            if obj is not None:
                obj.release()
        ctx = self.ctx
        self.depth = ctx.depth_texture((width, height))
        self.depth_bits = 32 if _float_depth(ctx, self.depth.glo, width, height) else 24
        self.depth.compare_func = ""
        self.ids = ctx.texture((width, height), 1, dtype="i4")
        for tex in (self.depth, self.ids):
            tex.filter = (self.mgl.NEAREST, self.mgl.NEAREST)
            tex.repeat_x = tex.repeat_y = False
        self.fbo = ctx.framebuffer(color_attachments=[self.ids], depth_attachment=self.depth)
        self.size = (width, height)


def _float_depth(ctx, glo, width, height) -> bool:
    """Re-specify moderngl's depth texture ``glo`` (24-bit) as ``DEPTH_COMPONENT32F``
    through the context's own function loader; False (the texture left as it was) when
    that is not possible."""
    try:
        load = ctx.mglo._context.load
        proto = ctypes.WINFUNCTYPE if sys.platform == "win32" else ctypes.CFUNCTYPE
        vd, ui, i, ip = None, ctypes.c_uint, ctypes.c_int, ctypes.POINTER(ctypes.c_int)
        bind = proto(vd, ui, ui)(load("glBindTexture"))
        image = proto(vd, ui, i, i, i, i, i, ui, ui, ctypes.c_void_p)(load("glTexImage2D"))
        level = proto(vd, ui, i, ui, ip)(load("glGetTexLevelParameteriv"))
    except Exception:
        return False
    ctx.clear_errors()
    bind(_GL_TEXTURE_2D, glo)
    image(_GL_TEXTURE_2D, 0, _GL_DEPTH_COMPONENT32F, width, height, 0, _GL_DEPTH_COMPONENT,
          _GL_FLOAT, None)  # fmt: skip
    bits, kind = ctypes.c_int(0), ctypes.c_int(0)
    level(_GL_TEXTURE_2D, 0, _GL_TEXTURE_DEPTH_SIZE, ctypes.byref(bits))
    level(_GL_TEXTURE_2D, 0, _GL_TEXTURE_DEPTH_TYPE, ctypes.byref(kind))
    ok = ctx.error == "GL_NO_ERROR" and bits.value == 32 and kind.value == _GL_FLOAT
    if not ok:  # put back moderngl's storage
        image(_GL_TEXTURE_2D, 0, _GL_DEPTH_COMPONENT24, width, height, 0, _GL_DEPTH_COMPONENT,
              _GL_FLOAT, None)  # fmt: skip
        ctx.clear_errors()
    return ok


_STATE: dict = {}
_CREATING = threading.Lock()


def _context() -> _GL:
    """The process's :class:`_GL` (created on first use)."""
    gl = _STATE.get("gl")
    if gl is not None and gl.pid == os.getpid():
        return gl
    with _CREATING:
        return _create()


def _create() -> _GL:
    """Create the process's :class:`_GL` (unless another thread just did), or raise the
    :class:`ResourceError` saying why it cannot be."""
    gl = _STATE.get("gl")
    if gl is not None and gl.pid == os.getpid():
        return gl
    if gl is not None:  # a driver's threads and locks do not survive fork(): it would hang
        raise ResourceError(
            f"moderngl backend: this process was forked from one (pid {gl.pid}) that had "
            "already used OpenGL, whose driver state does not survive fork(); start worker "
            "processes with 'spawn' or 'forkserver', or use backend = \"numba\""
        )
    error = _STATE.get("error")
    if error is not None and error[0] == os.getpid():
        raise ResourceError(error[1])
    reasons = []
    try:
        import moderngl
    except Exception as exc:  # pragma: no cover - moderngl is a dependency
        reasons.append(f"import moderngl: {exc}")
    else:
        for backend in ("egl", None):
            kw = {"backend": backend} if backend else {}
            try:
                ctx = moderngl.create_standalone_context(require=330, **kw)
            except Exception as exc:
                reasons.append(f"{backend or 'default'}: {exc}".strip())
                continue
            try:
                gl = _GL(moderngl, ctx)
            except Exception as exc:
                reasons.append(f"{backend or 'default'}: {exc}".strip())
                ctx.release()
                continue
            _STATE.clear()
            _STATE["gl"] = gl
            return gl
    message = (
        "moderngl backend: no OpenGL 3.3+ context (EGL): "
        + "; ".join(r.replace("\n", " ") for r in reasons)
        + '; use backend = "numba"'
    )
    _STATE["error"] = (os.getpid(), message)
    raise ResourceError(message)


def renderer() -> str:
    """The OpenGL renderer this backend uses (creating its context if needed), e.g.
    ``"llvmpipe (LLVM 15.0.6, 256 bits) (OpenGL 4.5 (Core Profile) Mesa 22.3.6)"``;
    :class:`growsim.errors.ResourceError` when no OpenGL 3.3+ context can be created.

    Examples
    --------
    >>> isinstance(renderer(), str)
    True
    """
    return _context().renderer


# ---------------------------------------------------------------------------------------
# the passes


def _stream(buf, data: np.ndarray) -> None:
    """Write ``data`` to the start of ``buf``, a fresh store (orphaning: no wait for the
    draws still reading the old one) sized to it (a power of 2, at least 1 MiB)."""
    buf.orphan(1 << max(20, (data.nbytes - 1).bit_length()))
    buf.write(data)


def _layout(gl: _GL, res: int, plants: int) -> tuple[int, int]:
    """``(columns, rows)`` of the atlas's tiles for ``plants`` plants (capped)."""
    if res > gl.max_side:
        raise ResourceError(
            f"moderngl backend: resolution {res} is above the OpenGL limit {gl.max_side} "
            f'({gl.renderer}); use a lower resolution or backend = "numba"'
        )
    per_side = max(1, min(ATLAS_SIDE, gl.max_side) // res)
    cols = max(1, min(plants, per_side))
    rows = max(1, min(per_side, math.ceil(plants / cols)))
    return cols, rows


def _run(*args):
    """:func:`_run_once`; when the context has been lost under us (another library in the
    process, VTK's off-screen windows among them, may terminate the EGL display that every
    context of the process shares), the context is made anew and the pass run once more."""
    try:
        return _run_once(*args)
    except Exception as exc:
        if type(exc).__module__.split(".")[0] not in ("moderngl", "_moderngl"):
            raise
        with _CREATING:
            lost = _STATE.pop("gl", None)
            if lost is not None:
                try:
                    lost.ctx.release()
                except Exception:  # the context is gone already
                    pass
        return _run_once(*args)


def _run_once(start, end, radius, offsets, frames, u, v, d, res, bias_pixels, item_offsets,
              per, queries):  # fmt: skip
    """Render the maps batch by batch (as many plants as the atlas holds) and resolve the
    items of ``item_offsets`` (``per`` samples each); ``queries(batch, atlas, q, z)``
    fills the queries of items ``c0:c1`` (``batch`` ``(p0, p1, c0, c1)``, ``atlas``
    ``(cols, res, width)``: :mod:`growsim.kernels.shadow_gl`)."""
    k = offsets.shape[0] - 1
    out = np.ones(item_offsets[-1])
    if k <= 0 or item_offsets[-1] == item_offsets[0] or offsets[-1] == offsets[0]:
        return out  # nothing to shade or nothing shaded: every map is empty
    res = int(res)
    gl = _context()
    with gl.lock, gl.ctx:
        ctx, mgl = gl.ctx, gl.mgl
        cols, rows = _layout(gl, res, k)
        gl.atlas(cols * res, rows * res)
        width = gl.size[0]
        gl.render["atlas"] = gl.size
        gl.render["res"] = float(res)
        gl.query["width"] = width
        zinfo = np.empty((k, 2))
        items = max(1, CHUNK_SAMPLES // per)
        gl.reserve(min(CHUNK_SEGMENTS, int(offsets[-1] - offsets[0])), items * per)
        for p0 in range(0, k, cols * rows):
            p1 = min(k, p0 + cols * rows)
            if item_offsets[p1] == item_offsets[p0]:
                continue
            depth_ranges(start, end, offsets, d, p0, p1, zinfo)
            # clear the depth only (a pixel's id counts where its depth is below 1);
            # moderngl applies a framebuffer's masks when it is bound
            gl.fbo.color_mask = (False, False, False, False)
            gl.fbo.depth_mask = True
            gl.fbo.use()
            gl.fbo.clear(depth=1.0, viewport=(0, 0, cols * res, math.ceil((p1 - p0) / cols) * res))
            gl.fbo.color_mask = (True, False, False, False)
            gl.fbo.use()
            ctx.enable_only(mgl.DEPTH_TEST)
            ctx.depth_func = "<"
            for c0 in range(offsets[p0], offsets[p1], CHUNK_SEGMENTS):
                c1 = min(offsets[p1], c0 + CHUNK_SEGMENTS)
                vert = np.empty((4 * (c1 - c0), VERTEX_FLOATS), np.float32)
                tile_vertices((start, end, radius, offsets), frames, (u, v, d), (p0, p1, c0, c1),
                              (cols, res, width), zinfo, vert, vert.view(np.int32))  # fmt: skip
                _stream(gl.vertices, vert)
                gl.render_vao.render(mgl.TRIANGLES, vertices=6 * (c1 - c0))
            gl.idle.use()  # the atlas is read, not attached, while it is queried
            gl.depth.use(0)
            gl.ids.use(1)
            ctx.enable_only(mgl.NOTHING)
            for c0 in range(item_offsets[p0], item_offsets[p1], items):
                c1 = min(item_offsets[p1], c0 + items)
                m = (c1 - c0) * per
                q = np.empty((m, 2), np.int32)
                z = np.empty(m)
                queries((p0, p1, c0, c1), (cols, res, width), q, z)
                _stream(gl.queries, q)
                gl.query_vao.transform(gl.results, mgl.POINTS, vertices=m)
                val = np.frombuffer(gl.results.read(size=4 * m), np.float32)
                resolve_exposure(val, z, item_offsets, frames, zinfo, bias_pixels,
                                 (p0, p1, c0, c1), per, out)  # fmt: skip
    return out


def segment_exposure_gl(start, end, radius, offsets, frames, u, v, d, res, bias_pixels,
                        samples) -> np.ndarray:  # fmt: skip
    """Hard shadows on the GPU: each segment's share of its ``samples`` points (at ``t =
    (q + 0.5) / samples`` of its axis) that are lit, one map per plant: the result of
    :func:`growsim.kernels.light.segment_exposure_into` with hard shadows, ``(n,)``
    float64 (its ``segments``, ``plane`` and ``shadow`` here one argument each).
    :class:`growsim.errors.ResourceError` when no OpenGL 3.3+ context can be created.

    Examples
    --------
    >>> import numpy as np
    >>> from growsim.kernels.light import plant_frames
    >>> s = np.array([[0.0, 1, 0], [0, 0, 0]]); e = np.array([[1.0, 1, 0], [1, 0, 0]])
    >>> u, v, d = np.array([1.0, 0, 0]), np.array([0.0, 0, -1]), np.array([0.0, -1, 0])
    >>> r, off = np.full(2, 0.2), np.array([0, 2])
    >>> f = plant_frames(s, e, r, off, u, v, 64)
    >>> segment_exposure_gl(s, e, r, off, f, u, v, d, 64, 1.5, 4).tolist()
    [1.0, 0.0]
    """
    samples = int(samples)
    res = int(res)

    def queries(batch, atlas, q, z):
        segment_queries((start, end, radius, offsets), frames, (u, v, d), batch, atlas, samples,
                        q, z)  # fmt: skip

    return _run(start, end, radius, offsets, frames, u, v, d, res, bias_pixels, offsets,
                samples, queries)  # fmt: skip


def point_exposure_gl(start, end, radius, offsets, frames, points, point_offsets, u, v, d,
                      res, bias_pixels) -> np.ndarray:  # fmt: skip
    """Hard shadows at points on the GPU: 1 where point ``m`` (of plant ``p``:
    ``point_offsets[p] <= m < point_offsets[p + 1]``) is lit in plant ``p``'s map, else
    0 (outside the frame or on an empty pixel: lit): the exposure one light of
    :func:`growsim.kernels.light.point_light_into` weighs by its cosine (hard shadows),
    ``(m,)`` float64.

    Examples
    --------
    >>> import numpy as np
    >>> from growsim.kernels.light import plant_frames
    >>> s = np.array([[0.0, 1, 0]]); e = np.array([[1.0, 1, 0]]); r = np.array([0.2])
    >>> u, v, d = np.array([1.0, 0, 0]), np.array([0.0, 0, -1]), np.array([0.0, -1, 0])
    >>> off = np.array([0, 1]); f = plant_frames(s, e, r, off, u, v, 64)
    >>> pts = np.array([[0.5, 0, 0], [0.5, 2, 0], [3, 0, 0]])
    >>> point_exposure_gl(s, e, r, off, f, pts, np.array([0, 3]), u, v, d, 64, 1.5).tolist()
    [0.0, 1.0, 1.0]
    """
    res = int(res)

    def queries(batch, atlas, q, z):
        point_queries(points, point_offsets, frames, (u, v, d), batch, atlas, q, z)

    return _run(start, end, radius, offsets, frames, u, v, d, res, bias_pixels, point_offsets,
                1, queries)  # fmt: skip
