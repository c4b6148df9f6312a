"""The plant phenotype in one room: the skeleton and its measures
(:mod:`~growsim.phenotypes.plant.plant`), its meshes (:mod:`~growsim.phenotypes.plant.mesh`),
views, screenshots and animations (:mod:`~growsim.phenotypes.plant.views`) and its colours by
the environment (:mod:`~growsim.phenotypes.plant.colors`).

Importing the package loads only the skeleton (no pyvista).

Examples
--------
>>> from growsim.phenotypes.plant import Plant
>>> Plant.from_points([[0, 0, 0], [0, 2, 0]], [-1], [-1, 0]).measures()["height"]
2.0
"""

from growsim.phenotypes.plant.plant import LEAF, STEM, LeafLight, Plant, leaf_light

__all__ = ["LEAF", "STEM", "LeafLight", "Plant", "leaf_light"]
