"""Generic pyvista helpers every picture of growsim uses, whatever the phenotype: the
views of every command (:data:`VIEWS`), the image size limits (:data:`MIN_SIZE`,
:data:`MAX_SIZE`, :func:`check_size`), an off-screen plotter with VTK's display warnings
quiet, a scene rendered to an image or shown in a window, aiming a camera along a view,
and writing a PNG or an animation atomically.

pyvista and imageio are imported on first use, so importing this module stays cheap.
"""

from __future__ import annotations

import contextlib
from pathlib import Path

import numpy as np

from growsim.errors import UserInputError
from growsim.files import atomic_path, atomic_write

__all__ = [
    "MAX_SIZE",
    "MIN_SIZE",
    "VIEWER_KEYS",
    "VIEWS",
    "aim_camera",
    "check_size",
    "frames_writer",
    "offscreen_plotter",
    "save_png",
    "scene_image",
    "show_scene",
    "view_vectors",
    "viewer_hint",
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
def offscreen_plotter(w: int, h: int):
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


def scene_image(draw, size, *, background="white") -> np.ndarray:
    """Render a scene off-screen: ``draw(plotter)`` fills it (meshes, camera); returns the
    ``(H, W, 3)`` uint8 image (``size`` is ``(W, H)``, checked by :func:`check_size`).

    Examples
    --------
    >>> import pyvista as pv
    >>> scene_image(lambda pl: pl.add_mesh(pv.Sphere()), (40, 30)).shape
    (30, 40, 3)
    """
    w, h = check_size(size)
    with offscreen_plotter(w, h) as pl:
        pl.set_background(background)
        draw(pl)
        img = pl.screenshot(return_img=True)
    return np.asarray(img)[..., :3].copy()


#: the key hint written in the corner of every interactive window
VIEWER_KEYS = "drag: rotate   shift+drag: pan   scroll: zoom   r: reset view   q: close"


def viewer_hint(pl) -> None:
    """Write :data:`VIEWER_KEYS` in the lower left corner of plotter ``pl``.

    Examples
    --------
    >>> import pyvista as pv
    >>> pl = pv.Plotter(off_screen=True, window_size=(64, 64))
    >>> viewer_hint(pl); pl.close()
    """
    pl.add_text(VIEWER_KEYS, position="lower_left", font_size=8, color="black")


def show_scene(draw, *, background="white", title: str | None = None) -> None:
    """Open an interactive pyvista window (needs a display) on the scene ``draw(plotter)``
    fills, titled ``title`` (default ``growsim``), with the keys' hint in a corner.

    Examples
    --------
    >>> import pyvista as pv
    >>> show_scene(lambda pl: pl.add_mesh(pv.Sphere()))  # doctest: +SKIP
    """
    import pyvista as pv

    pl = pv.Plotter()
    pl.set_background(background)
    draw(pl)
    viewer_hint(pl)
    pl.show(title=title or "growsim")


def view_vectors(view) -> tuple[np.ndarray, tuple]:
    """The unit direction a view looks along and its up vector: a name of :data:`VIEWS`,
    or a direction (up: +y).

    Examples
    --------
    >>> d, up = view_vectors((0, 0, -2))
    >>> d.tolist(), up
    ([0.0, 0.0, -1.0], (0.0, 1.0, 0.0))
    """
    if isinstance(view, str):
        if view not in VIEWS:
            raise UserInputError(f"unknown view {view!r}; choose from {', '.join(VIEWS)}")
        d, up = VIEWS[view]
    else:
        d, up = tuple(view), (0.0, 1.0, 0.0)
    d = np.asarray(d, float)
    return d / np.linalg.norm(d), up


def aim_camera(pl, centre, radius: float, view) -> None:
    """Point ``pl``'s camera at ``centre`` from four ``radius`` back along ``view``
    (:func:`view_vectors`): a scene of that radius seen whole.

    Examples
    --------
    >>> with offscreen_plotter(32, 32) as pl:
    ...     aim_camera(pl, (0, 0, 0), 1.0, (0, 0, -1))
    ...     [round(float(c), 3) for c in pl.camera.position]
    [0.0, 0.0, 4.0]
    """
    d, up = view_vectors(view)
    pl.camera.focal_point = np.asarray(centre, float)
    pl.camera.position = np.asarray(centre, float) - d * radius * 4.0
    pl.camera.up = up


def save_png(img: np.ndarray, path: Path) -> Path:
    """Write an ``(H, W, 3)`` (or grey ``(H, W)``) uint8 image to ``path`` (``.png``
    only), atomically.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> save_png(np.zeros((4, 4, 3), np.uint8), pathlib.Path(tempfile.mkdtemp()) / "a.png").name
    'a.png'
    """
    from PIL import Image

    path = Path(path)
    if path.suffix.lower() != ".png":
        raise UserInputError(f"{path}: images are written as .png")
    return atomic_write(path, lambda fh: Image.fromarray(img).save(fh, format="PNG"))


def frames_writer(path: Path, fps: int):
    """Check ``path`` (``.gif``, or ``.mp4`` with imageio-ffmpeg; its directory exists) and
    return ``write(frames) -> path``, which writes the frames atomically at ``fps``.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> write = frames_writer(pathlib.Path(tempfile.mkdtemp()) / "a.gif", fps=4)
    >>> write([np.zeros((8, 8, 3), np.uint8)] * 2).suffix
    '.gif'
    """
    import imageio.v2 as imageio

    suffix = path.suffix.lower()
    if suffix not in (".gif", ".mp4"):
        raise UserInputError(f"{path}: animations are written as .gif or .mp4")
    if suffix == ".mp4":
        try:
            import imageio_ffmpeg  # noqa: F401
        except ImportError:
            raise UserInputError(
                f"{path}: writing .mp4 needs the video extra "
                '(pip install "growsim[video]": imageio-ffmpeg); or use .gif'
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
