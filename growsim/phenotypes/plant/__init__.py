"""The plant phenotype in one room: the skeleton and its measures
(:mod:`~growsim.phenotypes.plant.plant`), its meshes (:mod:`~growsim.phenotypes.plant.mesh`),
views, screenshots and animations (:mod:`~growsim.phenotypes.plant.views`), its colours by
the environment (:mod:`~growsim.phenotypes.plant.colors`) and its architecture for other plant
software, an MTG file and a QSM cylinder table (:mod:`~growsim.phenotypes.plant.exchange`).

Importing the package loads only the skeleton (no pyvista): :func:`plant_mesh`,
:func:`render_grid`, :func:`to_mtg`, :func:`read_mtg`, :func:`to_qsm_table` and
:func:`qsm_table_to_plant` are exported lazily, imported on first use. ``exchange`` imports
``plant``, never the reverse. The modules import downwards only: ``plant`` (the class, and
:func:`cluster_leaves`, which builds one) -> ``views`` -> ``mesh`` -> ``colors``; the lower
three take a plant by its arrays and never import ``plant``, and ``plant`` imports ``views``
and ``mesh`` inside the methods that draw (they load numba and pyvista).

Examples
--------
>>> from growsim.phenotypes.plant import Plant
>>> Plant.from_points([[0, 0, 0], [0, 2, 0]], [-1], [-1, 0]).measures()["height"]
2.0
"""

from growsim.phenotypes.plant.leaves import LeafLight, leaf_light
from growsim.phenotypes.plant.plant import LEAF, STEM, Plant, cluster_leaves

__all__ = [
    "LEAF",
    "STEM",
    "LeafLight",
    "Plant",
    "cluster_leaves",
    "leaf_light",
    "plant_mesh",
    "qsm_table_to_plant",
    "read_mtg",
    "render_grid",
    "to_mtg",
    "to_qsm_table",
]

# Lazy exports: the drawing modules load numba and pyvista (and the file formats are
# needed by few), so they are imported on first use
# (``from growsim.phenotypes.plant import render_grid``). name -> module
_LAZY = {
    "plant_mesh": "growsim.phenotypes.plant.mesh",
    "render_grid": "growsim.phenotypes.plant.views",
    "to_mtg": "growsim.phenotypes.plant.exchange",
    "read_mtg": "growsim.phenotypes.plant.exchange",
    "to_qsm_table": "growsim.phenotypes.plant.exchange",
    "qsm_table_to_plant": "growsim.phenotypes.plant.exchange",
}


def __getattr__(name: str):
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'growsim.phenotypes.plant' has no attribute {name!r}")


def __dir__():
    return sorted([*globals(), *_LAZY])
