"""A trajectory: the path of an agent that swims in a tank (the fish of Okusa's thesis), as a
phenotype (:mod:`growsim.phenotypes`).

It holds, per frame (row 0 is the start), the centre, the orientation and speed, the
collisions counted there and the manoeuvre (0 straight, 1 turning, 2 pitching), with the
fish's body (its row of the kernel's fish table) and the tank it swam in. Pictures are
pyvista renders of the tank, its obstacles and the path as a tube coloured by time
(viridis: dark at the start, yellow at the end; the thesis's Fig. 1 drew red spheres where
the fish passed), black spheres where it collided and a green one at the start;
:meth:`Trajectory.animation` writes the swim as a GIF.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

import numpy as np

from growsim.errors import UserInputError
from growsim.files import atomic_path, atomic_write
from growsim.phenotypes.base import Phenotype
from growsim.render import (
    aim_camera,
    check_size,
    offscreen_plotter,
    scene_image,
    show_scene,
    view_vectors,
)

__all__ = ["Trajectory"]

_RED = (0.85, 0.12, 0.10)
_BLACK = (0.05, 0.05, 0.05)
_START = (0.10, 0.65, 0.20)
_OBSTACLE = (0.55, 0.58, 0.62)
_FISH = (0.95, 0.55, 0.05)
#: at most this many spheres draw a path
MAX_SPHERES = 400
#: at most this many points of the path are drawn (a long swim is thinned evenly)
MAX_PATH_POINTS = 4000
#: colours of the 4 colour genes (the fish in an animation)
FISH_COLORS = ((0.95, 0.55, 0.05), (0.20, 0.45, 0.85), (0.85, 0.20, 0.55), (0.35, 0.70, 0.30))
#: a fish circles forever when, over the second half of its frames, it turns more than
#: this share of the time or stays in a box smaller than this share of the tank's
#: smallest side
CIRCLING_TURNING = 0.5
CIRCLING_EXTENT = 0.25


class Trajectory(Phenotype):
    """The path of a swimming agent (see the module docstring).

    Examples
    --------
    >>> from growsim.models.fish import develop
    >>> t = develop({"frames": 300})
    >>> t.phenotype, t.n_frames, t.collisions == int(t.hits.sum())
    ('trajectory', 300, True)
    """

    phenotype = "trajectory"

    def __init__(
        self,
        positions,
        angles,
        hits,
        modes,
        body,
        size,
        spheres,
        cubes,
        params: dict[str, float] | None = None,
        meta: dict[str, Any] | None = None,
    ):
        self.positions = np.asarray(positions, dtype=np.float64).reshape(-1, 3)
        self.angles = np.asarray(angles, dtype=np.float64).reshape(len(self.positions), -1)
        self.hits = np.asarray(hits, dtype=np.int32).reshape(len(self.positions))
        self.modes = np.asarray(modes, dtype=np.int8).reshape(len(self.positions))
        self.body = np.asarray(body, dtype=np.float64).reshape(-1)
        self.size = np.asarray(size, dtype=np.float64).reshape(3)
        self.spheres = np.asarray(spheres, dtype=np.float64).reshape(-1, 4)
        self.cubes = np.asarray(cubes, dtype=np.float64).reshape(-1, 4)
        self.params = {k: float(v) for k, v in (params or {}).items()}
        self.meta = dict(meta or {})

    def __repr__(self) -> str:
        return f"Trajectory(frames={self.n_frames}, collisions={self.collisions})"

    @property
    def n_frames(self) -> int:
        """Frames swum (rows - 1)."""
        return len(self.positions) - 1

    @property
    def collisions(self) -> int:
        """Total collisions counted along the path."""
        return int(self.hits.sum())

    # ------------------------------------------------------------------ measures
    def measures(self, env=None) -> dict[str, float]:
        """``collisions``, ``frames``, ``path_length``, ``mean_speed``, ``turning_share``
        (frames turning), ``coverage`` (share of the tank's 40-px cells the centre visited),
        ``late_turning`` and ``late_extent`` (the second half: share turning, and the
        largest side of its bounding box over the tank's smallest side), ``circling`` (1
        when the fish circles forever: ``late_turning > 0.5`` or ``late_extent < 0.25``),
        and the genes.

        Examples
        --------
        >>> from growsim.models.fish import develop
        >>> m = develop({"frames": 400}).measures()
        >>> m["frames"], 0 <= m["coverage"] <= 1
        (400.0, True)
        """
        pos = self.positions
        steps = np.diff(pos, axis=0)
        n = self.n_frames
        half = pos[len(pos) // 2 :]
        late_modes = self.modes[len(pos) // 2 :]
        cells = np.maximum(np.ceil(self.size / 40.0), 1).astype(np.int64)
        idx = np.clip((pos / self.size * cells).astype(np.int64), 0, cells - 1)
        visited = len(np.unique(idx[:, 0] * cells[1] * cells[2] + idx[:, 1] * cells[2] + idx[:, 2]))
        late_turning = float(np.mean(late_modes == 1)) if len(late_modes) else 0.0
        late_extent = float(np.ptp(half, axis=0).max() / self.size.min()) if len(half) else 0.0
        out = {
            "collisions": float(self.collisions),
            "frames": float(n),
            "path_length": float(np.linalg.norm(steps, axis=1).sum()),
            "mean_speed": float(self.angles[1:, 2].mean()) if n else 0.0,
            "turning_share": float(np.mean(self.modes[1:] == 1)) if n else 0.0,
            "coverage": float(visited / cells.prod()),
            "late_turning": late_turning,
            "late_extent": late_extent,
            "circling": float(late_turning > CIRCLING_TURNING or late_extent < CIRCLING_EXTENT),
        }
        out.update({k: v for k, v in self.params.items()})
        return out

    # ------------------------------------------------------------------ persistence
    def save(self, path: str | os.PathLike) -> Path:
        """Write to ``path`` (``.npz``, compressed) atomically.

        Examples
        --------
        >>> import tempfile, pathlib
        >>> from growsim.models.fish import develop
        >>> f = pathlib.Path(tempfile.mkdtemp()) / "t.npz"
        >>> Trajectory.load(develop({"frames": 50}).save(f)).n_frames
        50
        """
        path = Path(path)
        if path.suffix != ".npz":
            raise UserInputError(f"{path}: a trajectory is saved as .npz")
        arrays = {
            "phenotype": np.array(self.phenotype),
            "positions": self.positions,
            "angles": self.angles,
            "hits": self.hits,
            "modes": self.modes,
            "body": self.body,
            "size": self.size,
            "spheres": self.spheres,
            "cubes": self.cubes,
            "params": np.array(json.dumps(self.params, sort_keys=True)),
            "meta": np.array(json.dumps(self.meta, sort_keys=True)),
        }
        return atomic_write(path, lambda fh: np.savez_compressed(fh, **arrays))

    @classmethod
    def load(cls, path: str | os.PathLike) -> Trajectory:
        """Read a trajectory written by :meth:`save`."""
        path = Path(path)
        try:
            with np.load(path, allow_pickle=False) as z:
                if str(z["phenotype"]) != cls.phenotype:
                    raise UserInputError(f"{path}: holds a {z['phenotype']}, not a trajectory")
                a = {k: z[k] for k in z.files}
        except (OSError, ValueError, KeyError) as exc:
            raise UserInputError(f"{path}: cannot read a trajectory ({exc})") from None
        return cls(
            a["positions"],
            a["angles"],
            a["hits"],
            a["modes"],
            a["body"],
            a["size"],
            a["spheres"],
            a["cubes"],
            params=json.loads(str(a["params"])),
            meta=json.loads(str(a["meta"])),
        )

    # ------------------------------------------------------------------ pictures
    def _sample(self, upto: int | None = None) -> np.ndarray:
        """Row indices of the path where collisions are drawn as spheres (at most
        :data:`MAX_SPHERES`)."""
        n = len(self.positions) if upto is None else max(1, min(upto, len(self.positions)))
        step = max(1, int(np.ceil(n / MAX_SPHERES)))
        return np.arange(0, n, step)

    def _radius(self) -> float:
        scale = self.body[3] if len(self.body) > 3 else 1.0
        hw = self.body[11] if len(self.body) > 11 else 1.0
        return float(max(hw * scale, 0.006 * self.size.max()))

    def _static(self, pl) -> None:
        """The tank's outline and its obstacles."""
        import pyvista as pv

        X, Y, Z = self.size
        pl.add_mesh(pv.Box(bounds=(0, X, 0, Y, 0, Z)).outline(), color="black", line_width=2)
        floor = pv.Plane(center=(X / 2, 0, Z / 2), direction=(0, 1, 0), i_size=X, j_size=Z)
        pl.add_mesh(floor, color=(0.80, 0.88, 0.95), opacity=0.5)
        for c in self.spheres:
            pl.add_mesh(pv.Sphere(radius=c[3], center=c[:3]), color=_OBSTACLE, opacity=0.6)
        for c in self.cubes:
            e = 2.0 * c[3]
            pl.add_mesh(
                pv.Cube(center=c[:3], x_length=e, y_length=e, z_length=e),
                color=_OBSTACLE,
                opacity=0.6,
            )

    def path_line(self, upto: int | None = None):
        """The path of the first ``upto`` frames (default: all) as a pyvista polyline with
        the point array ``frame`` (its row): at most :data:`MAX_PATH_POINTS` points, evenly
        thinned, the first and the last kept; ``None`` for fewer than two frames.

        Examples
        --------
        >>> from growsim.models.fish import develop
        >>> line = develop({"frames": 200}).path_line()
        >>> line.n_points, line.point_data["frame"][[0, -1]].tolist()
        (201, [0.0, 200.0])
        """
        import pyvista as pv

        n = len(self.positions) if upto is None else max(1, min(upto, len(self.positions)))
        step = max(1, int(np.ceil(n / MAX_PATH_POINTS)))
        idx = np.arange(0, n, step)
        if idx[-1] != n - 1:
            idx = np.append(idx, n - 1)
        if idx.size < 2:
            return None
        line = pv.lines_from_points(self.positions[idx])
        line.point_data["frame"] = idx.astype(float)
        return line

    def _path(self, pl, upto: int | None = None, legend: bool = True) -> None:
        """The path so far as a tube along the centres, coloured by time (the frame, on
        one scale from the start to the last frame), black spheres where it collided, the
        start a green sphere; with ``legend`` a scalar bar of the frames."""
        import pyvista as pv

        r = self._radius()
        line = self.path_line(upto)
        if line is not None:
            bar = {
                "title": "frame",
                "color": "black",
                "vertical": False,
                "position_x": 0.25,
                "position_y": 0.02,
                "width": 0.5,
                "height": 0.06,
                "n_labels": 2,
                "fmt": "%.0f",
                "title_font_size": 12,
                "label_font_size": 11,
            }
            pl.add_mesh(
                line.tube(radius=0.5 * r, n_sides=8),
                scalars="frame",
                cmap="viridis",
                clim=(0.0, float(max(len(self.positions) - 1, 1))),
                show_scalar_bar=bool(legend),
                scalar_bar_args=bar,
                ambient=0.35,
            )
        hit = self._sample(upto)
        hit = hit[self.hits[hit] > 0]
        if hit.size:
            pts = pv.PolyData(self.positions[hit])
            pl.add_mesh(pts.glyph(geom=pv.Sphere(radius=1.5 * r), scale=False, orient=False),
                        color=_BLACK)  # fmt: skip
        pl.add_mesh(pv.Sphere(radius=2 * r, center=self.positions[0]), color=_START)

    def _camera(self, pl, view) -> None:

        centre = self.size / 2.0
        aim_camera(pl, centre, float(np.linalg.norm(self.size)) / 2.0, view)
        d, up = view_vectors(view)
        pl.enable_parallel_projection()
        w, h = pl.window_size
        right = np.cross(d, np.asarray(up, float))
        if np.linalg.norm(right) < 1e-9:
            right = np.array([1.0, 0.0, 0.0])
        right /= np.linalg.norm(right)
        screen_up = np.cross(right, d)
        corners = np.array(np.meshgrid(*[[0, s] for s in self.size], indexing="ij"))
        corners = corners.reshape(3, -1).T - centre
        half_w = np.abs(corners @ right).max()
        half_h = np.abs(corners @ screen_up).max()
        pl.camera.parallel_scale = max(half_h, half_w * h / w) * 1.05
        pl.reset_camera_clipping_range()

    def render_image(self, *, view: str = "iso", size=(800, 800)) -> np.ndarray:
        """An ``(H, W, 3)`` render (pyvista, off-screen): tank, obstacles and the path.

        Examples
        --------
        >>> from growsim.models.fish import develop
        >>> develop({"frames": 200}).render_image(view="top", size=(64, 48)).shape
        (48, 64, 3)
        """

        return scene_image(lambda pl: self._scene(pl, view), size)

    def show(self, *, view: str = "iso", title: str | None = None) -> None:
        """An interactive pyvista window (needs a display), titled ``title``."""

        show_scene(lambda pl: self._scene(pl, view), title=title)

    def _scene(self, pl, view) -> None:
        self._static(pl)
        self._path(pl)
        self._camera(pl, view)

    def animation(
        self, path, *, frames: int = 48, view: str = "iso", size=(400, 400), fps: int = 12
    ) -> Path:
        """Write the swim as a GIF: ``frames`` pictures, the path growing and the fish (a
        sphere in its colour gene's colour) at its place.

        Examples
        --------
        >>> import tempfile, pathlib
        >>> from growsim.models.fish import develop
        >>> f = pathlib.Path(tempfile.mkdtemp()) / "swim.gif"
        >>> develop({"frames": 200}).animation(f, frames=3, size=(48, 48)).exists()
        True
        """
        import imageio.v2 as imageio
        import pyvista as pv

        path = Path(path)
        if path.suffix.lower() != ".gif":
            raise UserInputError(f"{path}: animations are written as .gif")
        if not path.parent.is_dir():
            raise UserInputError(f"{path}: directory {path.parent} does not exist")
        frames = int(frames)
        if not 1 <= frames <= 3600:
            raise UserInputError(f"animation frames: {frames} not in [1, 3600]")
        w, h = check_size(size)
        colour = FISH_COLORS[int(self.params.get("color", 0)) % len(FISH_COLORS)]
        out = []
        ends = np.linspace(1, len(self.positions), frames).astype(int)
        with offscreen_plotter(w, h) as pl:
            for end in ends:
                pl.clear()
                pl.set_background("white")
                self._static(pl)
                self._path(pl, upto=int(end))
                fish = pv.Sphere(radius=3 * self._radius(), center=self.positions[end - 1])
                pl.add_mesh(fish, color=colour)
                self._camera(pl, view)
                pl.render()
                out.append(np.asarray(pl.screenshot(return_img=True))[..., :3].copy())
        with atomic_path(path) as tmp:
            imageio.mimsave(tmp, out, duration=1000.0 / fps, loop=0, format="GIF")
        return path
