"""The phenotype contract: what a model grows and what every later step may ask of it.

A model declares the kind of phenotype it returns (:attr:`growsim.models.base.Model.phenotype`,
e.g. ``"plant"``); an objective declares the kinds it can score
(:attr:`growsim.objectives.base.Objective.accepts`). Results, ``growsim show``, compare
and the report only use the methods below, so a new kind of phenotype (a 2D point cloud,
a fish's trajectory) works everywhere the day it is registered in :data:`PHENOTYPES`.

A phenotype:

- **saves and loads itself**: :meth:`Phenotype.save` writes one ``.npz`` file holding
  the entry ``phenotype`` (its kind); :func:`load_phenotype` reads any kind back;
- **reports named measures** (:meth:`Phenotype.measures`, as the reporters of mesa's
  DataCollector): scalars for summaries and comparisons, some of them needing the
  environment (e.g. light captured);
- **lists the artefacts it can write** for a run's ``[output]`` table
  (:meth:`Phenotype.artefacts`: file name -> writer; meshes and renders for a plant);
- **renders** to an ``(H, W, 3)`` image (:meth:`Phenotype.render_image`), to a PNG
  (:meth:`Phenotype.screenshot`) and in an interactive window (:meth:`Phenotype.show`);
- declares the optional capabilities it implements in :attr:`Phenotype.capabilities`
  (names in :data:`CAPABILITIES`): ``"front_view"``, its own 2D raster view
  (:meth:`Phenotype.front_view`; an attractor's points), which 2D scores read instead of
  drawing the phenotype's skeleton. Callers ask ``"front_view" in
  phenotype.capabilities``, never ``getattr``; the conformance suite checks that a
  phenotype overrides exactly the methods it declares.
"""

from __future__ import annotations

import abc
import os
from collections.abc import Callable
from pathlib import Path
from typing import Any, ClassVar

import numpy as np

from growsim.errors import UserInputError
from growsim.registry import Registry
from growsim.render import save_png

__all__ = ["CAPABILITIES", "PHENOTYPES", "Phenotype", "load_phenotype", "saved_kind"]

#: the optional capabilities a phenotype may declare (:attr:`Phenotype.capabilities`)
CAPABILITIES = ("front_view",)

#: phenotype kind -> class. One line per kind.
PHENOTYPES: Registry[type[Phenotype]] = Registry(
    "phenotype",
    {
        "plant": "growsim.phenotypes.plant:Plant",
        "trajectory": "growsim.phenotypes.trajectory:Trajectory",
        "points2d": "growsim.phenotypes.attractor:Attractor",
    },
)


class Phenotype(abc.ABC):
    """Base of every phenotype (see the module docstring for the contract).

    Subclasses set :attr:`phenotype` (their kind's name in :data:`PHENOTYPES`) and implement
    :meth:`save`, :meth:`load`, :meth:`measures` and :meth:`render_image`.

    Examples
    --------
    >>> from growsim.phenotypes.plant import Plant
    >>> p = Plant.from_points([[0, 0, 0], [0, 1, 0]], [-1], [-1, 0])
    >>> isinstance(p, Phenotype), p.phenotype, p.measures()["height"]
    (True, 'plant', 1.0)
    """

    #: the phenotype's kind: its name in :data:`PHENOTYPES` (also saved in its files)
    phenotype: ClassVar[str] = ""
    #: the optional capabilities implemented (names in :data:`CAPABILITIES`)
    capabilities: ClassVar[frozenset[str]] = frozenset()

    @abc.abstractmethod
    def save(self, path: str | os.PathLike) -> Path:
        """Write to ``path`` (``.npz``) atomically, with the entry ``phenotype`` (its kind)."""

    @classmethod
    @abc.abstractmethod
    def load(cls, path: str | os.PathLike) -> Phenotype:
        """Read a file written by :meth:`save`."""

    @abc.abstractmethod
    def measures(self, env=None) -> dict[str, float]:
        """Named scalar measures; ``env`` (a :class:`growsim.env.Environment`) adds the
        ones that depend on the world (e.g. light captured)."""

    @abc.abstractmethod
    def render_image(self, *, view: str = "iso", size=(800, 800)) -> np.ndarray:
        """An ``(H, W, 3)`` uint8 picture of the phenotype (``size`` is ``(W, H)``)."""

    def artefacts(self, output) -> dict[str, Callable[[Path], Any]]:
        """The files this phenotype writes for an ``[output]`` table: ``{file name:
        writer(path)}``, each writer writing ``path`` atomically. Default: one PNG per
        view in ``output.screenshots`` (``best_<view>.png``)."""
        size = tuple(output.size)
        return {
            f"best_{view}.png": (
                lambda path, view=view: self.screenshot(path, view=view, size=size)
            )
            for view in output.screenshots
        }

    def screenshot(self, path: str | os.PathLike, *, view: str = "iso", size=(800, 800)) -> Path:
        """Render to a PNG file (atomically; a name not ending ``.png`` is refused before
        rendering)."""

        path = Path(path)
        if path.suffix.lower() != ".png":
            raise UserInputError(f"{path}: images are written as .png")
        return save_png(self.render_image(view=view, size=size), path)

    def front_view(self, size: int = 64) -> np.ndarray:
        """Capability ``"front_view"``: the phenotype's own 2D view, ``(size, size)``
        uint8, 1 where it is, framed with its base on the centre column and bottom row."""
        raise NotImplementedError(f"phenotype {self.phenotype!r} has no 'front_view' capability")

    def show(self, *, view: str = "iso", title: str | None = None) -> None:
        """Open an interactive window (needs a display), titled ``title``. Default: the
        rendered image in a matplotlib window."""
        import matplotlib.pyplot as plt

        plt.imshow(self.render_image(view=view))
        plt.axis("off")
        plt.gcf().canvas.manager.set_window_title(title or "growsim")
        plt.show()


def saved_kind(path: str | os.PathLike) -> str:
    """The kind of phenotype saved in an ``.npz`` file (files from before the phenotype
    contract hold a plant)."""
    path = Path(path)
    try:
        with np.load(path, allow_pickle=False) as z:
            if "phenotype" in z.files:
                return str(z["phenotype"])
            return "plant"
    except (OSError, ValueError) as exc:
        raise UserInputError(f"{path}: cannot read a phenotype ({exc})") from None


def load_phenotype(path: str | os.PathLike) -> Phenotype:
    """Read any phenotype written by :meth:`Phenotype.save`, whatever its kind.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from growsim.phenotypes.plant import Plant
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "p.npz"
    >>> _ = Plant.from_points([[0, 0, 0], [0, 1, 0]], [-1], [-1, 0]).save(f)
    >>> load_phenotype(f)
    Plant(model='?', segments=1, leaves=0)
    """
    return PHENOTYPES.get(saved_kind(path)).load(path)
