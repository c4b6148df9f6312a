"""Views of plants: off-screen screenshots, interactive windows, turntables, growth
animations, image grids, and fitness plots.

Everything renders off-screen with pyvista (no display needed) except :func:`show`, which
needs one; VTK's warnings (e.g. "bad X server connection" without a display) are kept
quiet while rendering off-screen. Files are written atomically (temporary name, then
rename). The views (:data:`VIEWS`) and the size limits (:data:`MIN_SIZE`,
:data:`MAX_SIZE`, :func:`check_size`) are the ones of every command that renders.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from growsim.errors import UserInputError
from growsim.files import atomic_path, atomic_write
from growsim.plant import Plant

__all__ = [
    "MAX_SIZE",
    "MIN_SIZE",
    "VIEWS",
    "check_size",
    "growth_animation",
    "plot_fitness",
    "render_grid",
    "render_image",
    "screenshot",
    "show",
    "turntable",
]

#: the views of every command (``growsim grow --view``, ``growsim show --view``): camera
#: directions (from the camera towards the plant) and up vectors
VIEWS: dict[str, tuple[tuple[float, float, float], tuple[float, float, float]]] = {
    "front": ((0.0, 0.0, -1.0), (0.0, 1.0, 0.0)),
    "back": ((0.0, 0.0, 1.0), (0.0, 1.0, 0.0)),
    "side": ((-1.0, 0.0, 0.0), (0.0, 1.0, 0.0)),
    "top": ((0.0, -1.0, 0.0), (0.0, 0.0, -1.0)),
    "iso": ((-1.0, -0.6, -1.0), (0.0, 1.0, 0.0)),
}

#: the smallest and largest width or height of a rendered image, in pixels (every command)
MIN_SIZE = 16
MAX_SIZE = 4096

_BARK = (0.43, 0.32, 0.23)
_LEAF = (0.29, 0.55, 0.23)


def _mesh_of(plant_or_mesh, sides=6, segments=1):
    import pyvista as pv

    from growsim.mesh import plant_mesh

    if isinstance(plant_or_mesh, Plant):
        return plant_mesh(plant_or_mesh, sides=sides, segments=segments)
    if isinstance(plant_or_mesh, pv.DataSet):
        return plant_or_mesh
    raise UserInputError(f"expected a Plant or a pyvista mesh, got {type(plant_or_mesh).__name__}")


def check_size(size, label: str = "size") -> tuple[int, int]:
    """``size`` ``(width, height)`` as two ints in ``[MIN_SIZE, MAX_SIZE]``, else
    :class:`UserInputError` (``label`` names the option).

    Examples
    --------
    >>> check_size([640, 480.0])
    (640, 480)
    >>> check_size((8000, 100), "--size")
    Traceback (most recent call last):
    ...
    growsim.errors.UserInputError: --size 8000 100: each side must be in [16, 4096] pixels
    """
    try:
        w, h = (int(size[0]), int(size[1]))
        if len(size) != 2:
            raise ValueError
    except (TypeError, ValueError, IndexError):
        raise UserInputError(f"{label} must be (width, height), got {size!r}") from None
    if not (MIN_SIZE <= w <= MAX_SIZE and MIN_SIZE <= h <= MAX_SIZE):
        raise UserInputError(
            f"{label} {w} {h}: each side must be in [{MIN_SIZE}, {MAX_SIZE}] pixels"
        )
    return w, h


@contextlib.contextmanager
def _offscreen(w: int, h: int):
    """An off-screen pyvista Plotter of ``w x h`` pixels, closed on exit. VTK's warnings are
    off meanwhile (the global switch, restored after): without an X display VTK prints a
    coloured "bad X server connection" warning on every render, which means nothing for an
    off-screen render. Errors still show."""
    import pyvista as pv
    from vtkmodules.vtkCommonCore import vtkObject

    shown = vtkObject.GetGlobalWarningDisplay()
    vtkObject.GlobalWarningDisplayOff()
    pl = None
    try:
        pl = pv.Plotter(off_screen=True, window_size=(w, h))
        yield pl
    finally:
        if pl is not None:
            pl.close()
        vtkObject.SetGlobalWarningDisplay(shown)


def _add(pl, mesh) -> None:
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


def _camera(pl, bounds, view, zoom=1.0) -> None:
    if isinstance(view, str):
        if view not in VIEWS:
            raise UserInputError(f"unknown view {view!r}; choose from {', '.join(VIEWS)}")
        d, up = VIEWS[view]
    else:
        d, up = tuple(view), (0.0, 1.0, 0.0)
    d = np.asarray(d, float)
    d /= np.linalg.norm(d)
    b = np.asarray(bounds, float).reshape(3, 2)
    centre = b.mean(1)
    radius = max(float(np.linalg.norm(b[:, 1] - b[:, 0])) / 2.0, 1e-6)
    pl.camera.focal_point = centre
    pl.camera.position = centre - d * radius * 4.0
    pl.camera.up = up
    pl.enable_parallel_projection()
    pl.camera.parallel_scale = radius * 1.02 / zoom
    pl.reset_camera_clipping_range()


def render_image(plant_or_mesh, *, view="front", size=(800, 800), background="white"):
    """Render off-screen and return the image as an ``(H, W, 3)`` uint8 array.

    ``view``: one of :data:`VIEWS` or a direction ``(3,)`` the camera looks along.
    Orthographic projection, framed on the plant's bounding sphere.

    Examples
    --------
    >>> from growsim.models import honda
    >>> img = render_image(honda.develop({"generations": 4}), size=(64, 64))
    >>> img.shape
    (64, 64, 3)
    """
    w, h = check_size(size)
    mesh = _mesh_of(plant_or_mesh)
    with _offscreen(w, h) as pl:
        pl.set_background(background)
        _add(pl, mesh)
        if mesh.n_points:
            _camera(pl, mesh.bounds, view)
        img = pl.screenshot(return_img=True)
    return np.asarray(img)[..., :3].copy()


def _save_png(img: np.ndarray, path: Path) -> Path:
    from PIL import Image

    path = Path(path)
    if path.suffix.lower() != ".png":
        raise UserInputError(f"{path}: images are written as .png")
    return atomic_write(path, lambda fh: Image.fromarray(img).save(fh, format="PNG"))


def screenshot(plant_or_mesh, path, *, view="front", size=(800, 800), background="white") -> Path:
    """Render a plant or mesh off-screen to a PNG file.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from growsim.models import honda
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "t.png"
    >>> screenshot(honda.develop({"generations": 4}), f, view="iso", size=(64, 64)).exists()
    True
    """
    img = render_image(plant_or_mesh, view=view, size=size, background=background)
    return _save_png(img, path)


def show(plant_or_mesh, *, view="iso") -> None:
    """Open an interactive pyvista window (needs a display).

    Raises :class:`growsim.errors.UserInputError` when no display is available, saying to
    use :func:`screenshot` instead.

    Examples
    --------
    >>> from growsim.models import honda
    >>> show(honda.develop({"generations": 3}))  # doctest: +SKIP
    """
    import pyvista as pv

    if os.name != "nt" and not os.environ.get("DISPLAY") and not os.environ.get("WAYLAND_DISPLAY"):
        raise UserInputError(
            "no display available for an interactive window (DISPLAY is not set); "
            "write an image with growsim.viz.screenshot / --screenshot instead"
        )
    mesh = _mesh_of(plant_or_mesh)
    pl = pv.Plotter()
    _add(pl, mesh)
    if mesh.n_points:
        _camera(pl, mesh.bounds, view)
    pl.show()


def _frames_writer(path: Path, fps: int):
    import imageio.v2 as imageio

    suffix = path.suffix.lower()
    if suffix not in (".gif", ".mp4"):
        raise UserInputError(f"{path}: animations are written as .gif or .mp4")
    if suffix == ".mp4":
        try:
            import imageio_ffmpeg  # noqa: F401
        except ImportError:
            raise UserInputError(
                f"{path}: writing .mp4 needs the imageio-ffmpeg package; use .gif"
            ) from None
    parent = path.parent
    if not parent.is_dir():
        raise UserInputError(f"{path}: directory {parent} does not exist")

    def write(frames: list[np.ndarray]) -> Path:
        try:
            with atomic_path(path) as tmp:
                if suffix == ".gif":
                    imageio.mimsave(tmp, frames, duration=1000.0 / fps, loop=0)
                else:
                    imageio.mimsave(tmp, frames, fps=fps)
        except OSError as exc:
            raise UserInputError(f"{path}: cannot write ({exc})") from None
        return path

    return write


def turntable(
    plant_or_mesh, path, *, frames: int = 36, size=(400, 400), fps: int = 12, elevation=15.0
) -> Path:
    """A turntable animation (GIF, or MP4 with imageio-ffmpeg): the camera circles the
    plant in ``frames`` steps at ``elevation`` degrees.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from growsim.models import honda
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "t.gif"
    >>> turntable(honda.develop({"generations": 3}), f, frames=4, size=(48, 48)).exists()
    True
    """
    path = Path(path)
    write = _frames_writer(path, fps)
    frames = int(frames)
    if not 1 <= frames <= 3600:
        raise UserInputError(f"turntable frames: {frames} not in [1, 3600]")
    w, h = check_size(size)
    mesh = _mesh_of(plant_or_mesh)
    out = []
    with _offscreen(w, h) as pl:
        pl.set_background("white")
        _add(pl, mesh)
        el = np.radians(elevation)
        for i in range(frames):
            a = 2.0 * np.pi * i / frames
            d = (-np.cos(el) * np.sin(a), -np.sin(el), -np.cos(el) * np.cos(a))
            if mesh.n_points:
                _camera(pl, mesh.bounds, d)
            pl.render()
            out.append(np.asarray(pl.screenshot(return_img=True))[..., :3].copy())
    return write(out)


def growth_animation(
    plants: Sequence[Plant], path, *, view="front", size=(400, 400), fps: int = 4
) -> Path:
    """Animate a list of plants (e.g. one per generation) in one fixed frame (GIF/MP4).

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
    write = _frames_writer(path, fps)
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
    out = []
    for m in meshes:
        with _offscreen(w, h) as pl:
            pl.set_background("white")
            _add(pl, m)
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
) -> Path:
    """Several phenotypes (plants, meshes) side by side in one PNG (``columns`` per row,
    titles under each).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from growsim.models import honda
    >>> ps = [honda.develop({"generations": g}) for g in (2, 3)]
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "grid.png"
    >>> render_grid(ps, f, titles=["2", "3"], cell=(64, 64)).exists()
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
    from growsim.phenotype import Phenotype

    for i, p in enumerate(plants):
        if isinstance(p, Phenotype):
            img = p.render_image(view=view, size=(cw, ch))
        else:
            img = render_image(p, view=view, size=(cw, ch))
        x, y = (i % cols) * cw, (i // cols) * (ch + text_h)
        grid.paste(Image.fromarray(img), (x, y))
        if titles:
            draw.text((x + 4, y + ch + 2), str(titles[i]), fill=(0, 0, 0))
    return _save_png(np.asarray(grid), path)


def plot_fitness(history, path, *, title: str | None = None) -> Path:
    """Plot a GA history (a DataFrame with ``generation`` and some of ``best``, ``mean``,
    ``best_so_far``) to a PNG with matplotlib (Agg backend), with a legend: the best and
    the mean fitness of each generation and the best so far, drawn dashed on top (it
    lies on the best wherever the best improves). With an ``island`` column, islands are
    pooled: best is the max, mean the mean over islands. (``worst`` is not drawn: an
    evaluation that failed scores the worst value there is, which would flatten the
    rest.)

    Examples
    --------
    >>> import tempfile, pathlib, pandas as pd
    >>> h = pd.DataFrame({"generation": [0, 1, 2], "best": [1, 2, 3], "mean": [0, 1, 2]})
    >>> plot_fitness(h, pathlib.Path(tempfile.mkdtemp()) / "f.png").exists()
    True
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    if "generation" not in getattr(history, "columns", ()):
        raise UserInputError("plot_fitness: history needs a 'generation' column")
    # column, how islands are pooled, line style (best so far: dashed, on top)
    styles = {
        "best": ("max", {"color": "tab:blue", "linewidth": 2.5, "zorder": 2}),
        "mean": ("mean", {"color": "tab:orange", "linewidth": 1.5, "zorder": 2}),
        "best_so_far": (
            "max",
            {"color": "black", "linestyle": "--", "linewidth": 1.5, "zorder": 3},
        ),
    }
    cols = [c for c in styles if c in history.columns]
    if not cols:
        raise UserInputError("plot_fitness: history has none of best, mean, best_so_far")
    path = Path(path)
    if path.suffix.lower() != ".png":
        raise UserInputError(f"{path}: plots are written as .png")
    g = history.groupby("generation")
    fig, ax = plt.subplots(figsize=(6, 4), dpi=100)
    try:
        for c in cols:
            how, style = styles[c]
            s = g[c].agg(how)
            ax.plot(s.index, s.values, label=c.replace("_", " "), **style)
        ax.set_xlabel("generation")
        ax.set_ylabel("fitness")
        if title:
            ax.set_title(title)
        ax.grid(alpha=0.3)
        ax.legend()
        fig.tight_layout()
        atomic_write(path, lambda fh: fig.savefig(fh, format="png"))
    finally:
        plt.close(fig)
    return path
