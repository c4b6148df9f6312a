"""Views of plants: off-screen screenshots, interactive windows, turntables, growth
animations and image grids.

Everything renders off-screen with pyvista (no display needed) except :func:`show`, which
needs one; VTK's warnings (e.g. "bad X server connection" without a display) are kept
quiet while rendering off-screen. Files are written atomically (temporary name, then
rename). The views and the size limits are :mod:`growsim.render`'s, those of every
command that renders.

The environment on a plant: :func:`render_image`, :func:`screenshot` and :func:`show` take
``color=`` one of :data:`COLORS` (``"light"``, ``"stress"``, ``"water"``) and an
``env`` (:class:`growsim.env.Environment`): each segment is painted flat by its value in
``env.segment_table(plant)`` (:mod:`growsim.phenotypes.plant.colors`: the fields, their
scales, the arrow) with a labelled scalar bar, and ``light_arrow`` draws the light's direction
(an arrow from the
light's side into the plant; on by default when colouring by light). ``growsim grow
--color`` and ``growsim show --color`` are these.

A plant of modules (the hormone model's: :func:`growsim.phenotypes.plant.mesh.module_plant`)
is drawn by tissue in every view here: each module green to brown by its chlorophyll and
lignin, the modules that act as leaves with a leaf blade, on a soil slab at the ground's
height (:func:`growsim.phenotypes.plant.mesh.ground_mesh`). Other plants keep bark and
leaves, with no soil.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from growsim.errors import UserInputError
from growsim.phenotypes.base import Phenotype
from growsim.phenotypes.plant.colors import (
    ARROW_RGB,
    GROUND_RGB,
    NAN_RGB,
    check_color,
    color_scale,
    environment_or_default,
    light_arrow_mesh,
    segment_colors,
)
from growsim.phenotypes.plant.mesh import ground_mesh, is_plant, plant_mesh
from growsim.render import (
    check_size,
    frames_writer,
    offscreen_plotter,
    save_png,
    scene_image,
    view_vectors,
    viewer_hint,
)

__all__ = [
    "growth_animation",
    "render_grid",
    "render_image",
    "screenshot",
    "show",
    "turntable",
]

_BARK = (0.43, 0.32, 0.23)
_LEAF = (0.29, 0.55, 0.23)

_LEGEND_MARGIN = 0.16  # share of the image height kept free for the scalar bar


def _mesh_of(plant_or_mesh, sides=6, segments=1):
    import pyvista as pv

    if is_plant(plant_or_mesh):
        return plant_mesh(plant_or_mesh, sides=sides, segments=segments)
    if isinstance(plant_or_mesh, pv.DataSet):
        return plant_or_mesh
    raise UserInputError(f"expected a Plant or a pyvista mesh, got {type(plant_or_mesh).__name__}")


def _union(a, b):
    a, b = np.asarray(a, float).reshape(3, 2), np.asarray(b, float).reshape(3, 2)
    return np.stack([np.minimum(a[:, 0], b[:, 0]), np.maximum(a[:, 1], b[:, 1])], 1).ravel()


def _scene(pl, plant_or_mesh, color=None, env=None, light_arrow=None, legend=True):
    """Add a plant (or mesh) to ``pl``: plain bark and leaves, or coloured by ``color``
    with its scalar bar (``legend``), and the light arrow. Returns ``(bounds to frame or
    None, framing options of _camera)``: a coloured view or one with the arrow is framed
    tight, with room for the scalar bar below."""
    color = check_color(color)
    if light_arrow is None:
        light_arrow = color == "light"
    env = environment_or_default(env) if (color is not None or light_arrow) else None
    margin = 0.0
    if color is None:
        mesh = _mesh_of(plant_or_mesh)
        _add(pl, mesh)
    else:
        values = segment_colors(plant_or_mesh, color, env)
        scale = color_scale(color, env)
        mesh = plant_mesh(plant_or_mesh, fields={color: values})
        if mesh.n_cells and color in mesh.cell_data:
            bar = {
                "title": scale.title,
                "color": "black",
                "vertical": False,
                "position_x": 0.15,
                "position_y": 0.02,
                "width": 0.7,
                "height": 0.09,
                "n_labels": 5,
                "fmt": "%.2g",
                "title_font_size": 14,
                "label_font_size": 12,
                "nan_annotation": scale.nan_label is not None,
                "above_label": scale.above_label,
            }
            pl.add_mesh(
                mesh,
                scalars=color,
                preference="cell",
                cmap=scale.cmap,
                clim=scale.clim,
                nan_color=NAN_RGB,
                above_color=scale.above_color,
                show_scalar_bar=bool(legend),
                scalar_bar_args=bar,
                ambient=0.55,
                diffuse=0.45,
                specular=0.0,
            )
            if legend:
                margin = _LEGEND_MARGIN
                pl.scalar_bar.SetTextPositionToPrecedeScalarBar()  # labels under the bar
                if scale.nan_label is not None:
                    pl.scalar_bar.SetNanAnnotation(scale.nan_label)
    bounds = mesh.bounds if mesh.n_points else None
    if bounds is not None and "ground" in mesh.field_data:
        _add_ground(pl, bounds, float(mesh.field_data["ground"][0]))
    if light_arrow and bounds is not None:
        arrow = light_arrow_mesh(bounds, env.light.direction)
        pl.add_mesh(arrow, color=ARROW_RGB, ambient=0.3)
        bounds = _union(bounds, arrow.bounds)
    return bounds, {"bottom": margin, "tight": color is not None or bool(light_arrow)}


def _add_ground(pl, bounds, height) -> None:
    """Draw the soil slab under ``bounds`` at ``height``. The view stays framed on the
    plant alone (the soil may run out of the picture): a render lies where
    :func:`growsim.report.figures.render_frame` says, soil or not."""
    pl.add_mesh(ground_mesh(bounds, height), color=GROUND_RGB, ambient=0.3, diffuse=0.6,
                specular=0.0)  # fmt: skip


def _add(pl, mesh) -> None:
    if mesh.n_cells and "rgb" in mesh.cell_data:  # a plant of modules: by tissue
        pl.add_mesh(mesh, scalars="rgb", rgb=True, preference="cell", ambient=0.25,
                    diffuse=0.75, specular=0.0)  # fmt: skip
        return
    kind = np.asarray(mesh.point_data["kind"]) if "kind" in mesh.point_data else None
    if kind is None or mesh.n_cells == 0:
        if mesh.n_points:
            pl.add_mesh(mesh, color=_BARK)
        return
    tris = mesh.regular_faces
    for value, color in ((0, _BARK), (1, _LEAF)):
        sel = tris[kind[tris[:, 0]] == value]
        if sel.shape[0]:
            import pyvista as pv

            pl.add_mesh(pv.PolyData.from_regular_faces(mesh.points, sel), color=color)


def _camera(pl, bounds, view, zoom=1.0, bottom=0.0, tight=False) -> None:
    """Frame ``bounds`` (orthographic) looking along ``view``: on its bounding sphere (the
    same scale from every side), or with ``tight`` on the box's outline as seen (a still
    image with a legend). ``bottom``: share of the image height kept free below the plant
    (for a scalar bar)."""
    d, up = view_vectors(view)
    b = np.asarray(bounds, float).reshape(3, 2)
    centre = b.mean(1)
    radius = max(float(np.linalg.norm(b[:, 1] - b[:, 0])) / 2.0, 1e-6)
    screen_up = np.asarray(up, float) - np.dot(up, d) * d
    if np.linalg.norm(screen_up) < 1e-9:  # looking along up: any screen up will do
        screen_up = np.cross(d, [1.0, 0.0, 0.0] if abs(d[0]) < 0.9 else [0.0, 0.0, 1.0])
    screen_up /= np.linalg.norm(screen_up)
    half = radius * 1.02 / zoom
    if tight:
        right = np.cross(d, screen_up)
        corners = np.array(np.meshgrid(*b, indexing="ij")).reshape(3, -1).T - centre
        x, y = corners @ right, corners @ screen_up
        centre = centre + right * (x.max() + x.min()) / 2 + screen_up * (y.max() + y.min()) / 2
        w, h = pl.window_size
        half = max(np.ptp(y) / 2, np.ptp(x) / 2 * h / w, 1e-6) * 1.04 / zoom
    scale = half / (1.0 - bottom)
    centre = centre - screen_up * (scale - half)  # the plant touches the top; the rest below
    pl.camera.focal_point = centre
    pl.camera.position = centre - d * radius * 4.0
    pl.camera.up = up
    pl.enable_parallel_projection()
    pl.camera.parallel_scale = scale
    pl.reset_camera_clipping_range()


def render_image(
    plant_or_mesh,
    *,
    view="front",
    size=(800, 800),
    background="white",
    color=None,
    env=None,
    light_arrow=None,
    legend=True,
    frame=None,
):
    """Render off-screen and return the image as an ``(H, W, 3)`` uint8 array.

    ``view``: one of :data:`VIEWS` or a direction ``(3,)`` the camera looks along.
    Orthographic projection, framed on the plant's bounding sphere, or on the box
    ``frame`` (``(xmin, xmax, ymin, ymax, zmin, zmax)``) when given: plants rendered with
    one frame are drawn at one scale.

    ``color``: ``None`` (bark and leaves) or a field of :data:`COLORS` to paint each
    segment of a Plant by (:func:`segment_colors`) under ``env`` (an
    :class:`growsim.env.Environment`, default ``Environment()``), with a scalar bar below
    the plant when ``legend``. ``light_arrow`` (default: when ``color == "light"``) draws
    ``env.light.direction`` as an orange arrow coming from the light's side.

    Examples
    --------
    >>> from growsim.models import honda
    >>> img = render_image(honda.develop({"generations": 4}), size=(64, 64))
    >>> img.shape
    (64, 64, 3)
    >>> from growsim.env import Environment
    >>> side = Environment.model_validate({"light": {"direction": [1, 0, 0]}})
    >>> img = render_image(honda.develop({"generations": 4}), size=(64, 64), color="light",
    ...                    env=side)
    >>> img.shape
    (64, 64, 3)
    """

    def draw(pl):
        bounds, framing = _scene(pl, plant_or_mesh, color, env, light_arrow, legend)
        if frame is not None:
            _camera(pl, frame, view, **framing)
        elif bounds is not None:
            _camera(pl, bounds, view, **framing)

    return scene_image(draw, size, background=background)


def screenshot(plant_or_mesh, path, **options) -> Path:
    """Render a plant or mesh off-screen to a PNG file (``options``: those of
    :func:`render_image`: ``view``, ``size``, ``background``, ``color``, ``env``,
    ``light_arrow``, ``legend``).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from growsim.models import honda
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "t.png"
    >>> screenshot(honda.develop({"generations": 4}), f, view="iso", size=(64, 64)).exists()
    True
    >>> g = f.with_name("stress.png")
    >>> screenshot(honda.develop({"generations": 4}), g, size=(64, 64), color="stress").exists()
    True
    """
    path = Path(path)
    if path.suffix.lower() != ".png":
        raise UserInputError(f"{path}: images are written as .png")
    return save_png(render_image(plant_or_mesh, **options), path)


def show(plant_or_mesh, *, view="iso", color=None, env=None, light_arrow=None, title=None) -> None:
    """Open an interactive pyvista window (needs a display), titled ``title`` (default
    ``growsim``), with the keys' hint (:data:`growsim.render.VIEWER_KEYS`); ``color``,
    ``env`` and ``light_arrow`` as in :func:`render_image` (with the scalar bar).

    Raises :class:`growsim.errors.UserInputError` when no display is available, saying to
    use :func:`screenshot` instead.

    Examples
    --------
    >>> from growsim.models import honda
    >>> show(honda.develop({"generations": 3}))  # doctest: +SKIP
    >>> show(honda.develop({"generations": 3}), color="water")  # doctest: +SKIP
    """
    import pyvista as pv

    check_color(color)
    if os.name != "nt" and not os.environ.get("DISPLAY") and not os.environ.get("WAYLAND_DISPLAY"):
        raise UserInputError(
            "no display available for an interactive window (DISPLAY is not set); "
            "write an image with growsim.phenotypes.plant.views.screenshot / --screenshot instead"
        )
    pl = pv.Plotter()
    bounds, framing = _scene(pl, plant_or_mesh, color, env, light_arrow, True)
    if bounds is not None:
        _camera(pl, bounds, view, **framing)
    viewer_hint(pl)
    pl.show(title=title or "growsim")


def turntable(
    plant_or_mesh, path, *, frames: int = 36, size=(400, 400), fps: int = 12, elevation=15.0
) -> Path:
    """A turntable animation (GIF, or MP4 with the video extra, ``growsim[video]``): the
    camera circles the plant in ``frames`` steps at ``elevation`` degrees.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from growsim.models import honda
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "t.gif"
    >>> turntable(honda.develop({"generations": 3}), f, frames=4, size=(48, 48)).exists()
    True
    """
    path = Path(path)
    write = frames_writer(path, fps)
    frames = int(frames)
    if not 1 <= frames <= 3600:
        raise UserInputError(f"turntable frames: {frames} not in [1, 3600]")
    w, h = check_size(size)
    mesh = _mesh_of(plant_or_mesh)
    out = []
    with offscreen_plotter(w, h) as pl:
        pl.set_background("white")
        _add(pl, mesh)
        bounds = mesh.bounds if mesh.n_points else None
        if bounds is not None and "ground" in mesh.field_data:
            _add_ground(pl, bounds, float(mesh.field_data["ground"][0]))
        el = np.radians(elevation)
        for i in range(frames):
            a = 2.0 * np.pi * i / frames
            d = (-np.cos(el) * np.sin(a), -np.sin(el), -np.cos(el) * np.cos(a))
            if bounds is not None:
                _camera(pl, bounds, d)
            pl.render()
            out.append(np.asarray(pl.screenshot(return_img=True))[..., :3].copy())
    return write(out)


def growth_animation(
    plants: Sequence, path, *, view="front", size=(400, 400), fps: int = 4
) -> Path:
    """Animate a list of plants (e.g. one per generation) in one fixed frame (GIF; MP4 with
    the video extra, ``growsim[video]``).

    The camera frames the union of all plants' bounding boxes, so growth is visible.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from growsim.models import honda
    >>> ps = [honda.develop({"generations": g}) for g in (1, 2, 3)]
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "g.gif"
    >>> growth_animation(ps, f, size=(48, 48)).exists()
    True
    """
    path = Path(path)
    write = frames_writer(path, fps)
    plants = list(plants)
    if not plants:
        raise UserInputError("growth_animation: no plants given")
    w, h = check_size(size)
    meshes = [_mesh_of(p) for p in plants]
    nonempty = [m for m in meshes if m.n_points]
    if not nonempty:
        raise UserInputError("growth_animation: every plant is empty")
    b = np.array([m.bounds for m in nonempty]).reshape(-1, 3, 2)
    bounds = np.stack([b[:, :, 0].min(0), b[:, :, 1].max(0)], axis=1).ravel()
    ground = next((float(m.field_data["ground"][0]) for m in nonempty
                   if "ground" in m.field_data), None)  # fmt: skip
    soil = ground_mesh(bounds, ground) if ground is not None else None  # one for all frames
    out = []
    for m in meshes:
        with offscreen_plotter(w, h) as pl:
            pl.set_background("white")
            _add(pl, m)
            if soil is not None:
                pl.add_mesh(soil, color=GROUND_RGB, ambient=0.3, diffuse=0.6, specular=0.0)
            _camera(pl, bounds, view)
            out.append(np.asarray(pl.screenshot(return_img=True))[..., :3].copy())
    return write(out)


def render_grid(
    plants: Sequence,
    path,
    *,
    titles: Sequence[str] | None = None,
    view="front",
    cell=(300, 300),
    columns: int | None = None,
    same_scale: bool = False,
) -> Path:
    """Several phenotypes (plants, meshes) side by side in one PNG (``columns`` per row,
    titles under each); with ``same_scale``, plants (each growing from its own base) all
    framed on the box that holds every one of them: one scale for all.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from growsim.models import honda
    >>> ps = [honda.develop({"generations": g}) for g in (2, 3)]
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "grid.png"
    >>> render_grid(ps, f, titles=["2", "3"], cell=(64, 64)).exists()
    True
    >>> render_grid(ps, f, cell=(64, 64), same_scale=True).exists()
    True
    """
    from PIL import Image, ImageDraw

    plants = list(plants)
    if not plants:
        raise UserInputError("render_grid: no plants given")
    if titles is not None and len(titles) != len(plants):
        raise UserInputError(f"render_grid: {len(titles)} titles for {len(plants)} plants")
    cw, ch = check_size(cell, "cell")
    cols = int(columns or min(4, len(plants)))
    rows = -(-len(plants) // cols)
    text_h = 18 if titles else 0
    grid = Image.new("RGB", (cols * cw, rows * (ch + text_h)), "white")
    draw = ImageDraw.Draw(grid)
    frame = None
    if same_scale:
        ends = np.concatenate([np.concatenate([p.start, p.end]) for p in plants if p.n_segments])
        low, high = ends.min(axis=0), ends.max(axis=0)
        frame = np.column_stack([low, high]).ravel()
    for i, p in enumerate(plants):
        if frame is not None:
            img = render_image(p, view=view, size=(cw, ch), frame=frame)
        elif isinstance(p, Phenotype):
            img = p.render_image(view=view, size=(cw, ch))
        else:
            img = render_image(p, view=view, size=(cw, ch))
        x, y = (i % cols) * cw, (i // cols) * (ch + text_h)
        grid.paste(Image.fromarray(img), (x, y))
        if titles:
            draw.text((x + 4, y + ch + 2), str(titles[i]), fill=(0, 0, 0))
    return save_png(np.asarray(grid), path)
