"""Reconstructing a particular tree from its picture(s): the visible skeleton taken from
the silhouette, lifted into 3D, what the picture cannot show grown into the crown, and a
developmental model's parameters inferred from the result (issue 42).

The public face::

    from growsim.reconstruction import reconstruct, Reconstruction, infer_honda
    rec = reconstruct(front_mask, side_mask=None, height_m=None, leafy=None, seed=0)
    rec.plant, rec.skeleton2d, rec.assumptions, rec.method
    params = infer_honda(rec.plant)

One concept a module, each importing only the ones listed before it:

- :mod:`~growsim.reconstruction.skeleton`: the mask's medial axis as a rooted branch
  graph with radius profiles (pixels);
- :mod:`~growsim.reconstruction.lift`: the branches into 3D (a side picture or a
  stated prior);
- :mod:`~growsim.reconstruction.colonize`: the crown's envelope and space colonization
  into it;
- :mod:`~growsim.reconstruction.build`: :func:`reconstruct`, the Plant;
- :mod:`~growsim.reconstruction.stats`: branch statistics of any Plant;
- :mod:`~growsim.reconstruction.infer`: :func:`infer_honda`;
- :mod:`~growsim.reconstruction.judge`: the scores against the picture(s);
- :mod:`~growsim.reconstruction.drawing`: the skeleton over the photograph, target
  beside fit, the statistics side by side.

Examples
--------
>>> import numpy as np
>>> m = np.zeros((60, 40), bool); m[10:60, 18:23] = True
>>> rec = reconstruct(m, height_m=3.0)
>>> rec.plant.n_segments > 0, isinstance(rec, Reconstruction)
(True, True)
"""

from growsim.reconstruction.build import DEFAULT_HEIGHT, METHOD, Reconstruction, reconstruct
from growsim.reconstruction.colonize import ColonizeSettings
from growsim.reconstruction.drawing import (
    compare_statistics,
    fit_picture,
    skeleton_picture,
    trees_picture,
)
from growsim.reconstruction.infer import infer_honda
from growsim.reconstruction.judge import judge
from growsim.reconstruction.stats import branch_table, order_summary, tree_summary

__all__ = [
    "DEFAULT_HEIGHT",
    "METHOD",
    "ColonizeSettings",
    "Reconstruction",
    "branch_table",
    "compare_statistics",
    "fit_picture",
    "infer_honda",
    "judge",
    "order_summary",
    "reconstruct",
    "skeleton_picture",
    "tree_summary",
    "trees_picture",
]
