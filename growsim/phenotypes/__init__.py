"""What models grow: the phenotype contract and its kinds.

- :mod:`~growsim.phenotypes.base`: the contract (:class:`Phenotype`), the registry
  :data:`PHENOTYPES` and :func:`load_phenotype`;
- :mod:`~growsim.phenotypes.plant`: the plant skeleton with its meshes, views and colours;
- :mod:`~growsim.phenotypes.trajectory`: a swimmer's path;
- :mod:`~growsim.phenotypes.attractor`: a 2D IFS attractor (phenotype ``points2d``);
- :mod:`~growsim.phenotypes.stand`: several plants on one ground, measured
  (:func:`plant_table`, :func:`stand_measures`).

Examples
--------
>>> from growsim.phenotypes import PHENOTYPES
>>> sorted(PHENOTYPES)
['plant', 'points2d', 'trajectory']
"""

from growsim.phenotypes.base import PHENOTYPES, Phenotype, load_phenotype, saved_kind
from growsim.phenotypes.stand import plant_table, stand_measures

__all__ = [
    "PHENOTYPES",
    "Phenotype",
    "load_phenotype",
    "plant_table",
    "saved_kind",
    "stand_measures",
]
