"""Fitting a model to pictures of a tree (``growsim fit-image``).

- :mod:`~growsim.fitting.fit`: :func:`fit_image`, the whole fit as a library call
  (returns a :class:`FitResult`; the command only parses its arguments and prints);
- :mod:`~growsim.fitting.options`: its options, one schema (:class:`FitOptions`: the
  keywords, the command's flags and the saved state take their names from it);
- :mod:`~growsim.fitting.state`: a fit's saved state (:class:`FitState`: the options and
  the stages finished, what ``--resume`` reads);
- :mod:`~growsim.fitting.stages`: the fit's stages (choose, segment, reconstruct or search,
  grow, judge, write), each a function;
- :mod:`~growsim.fitting.choices`: what the fit chooses for the user (drawing or photo,
  the models, line width, sizes, leaves, keywords) and which candidate it keeps;
- :mod:`~growsim.fitting.runs`: one run through the raster sizes, and runs side by side;
- :mod:`~growsim.fitting.setups`: what is fitted for each model (:class:`FitSetup`), the
  fit's config, the coarse-to-fine refinement, the sweep of the discrete parameters and
  the arrangement search.

The pictures themselves are read and segmented by :mod:`growsim.pictures`. Importing
the package loads only the options (the command line builds its parser from
:class:`FitOptions`): :func:`fit_image`, :class:`FitResult`, :class:`FitState`,
:data:`FIT_SETUPS` and :class:`FitSetup` are exported lazily, imported on first use.

Examples
--------
>>> from growsim.fitting import FIT_SETUPS, fit_image
>>> sorted(FIT_SETUPS)
['honda', 'ifs2d', 'ifs3d']
"""

import importlib
from typing import TYPE_CHECKING

from growsim.fitting.options import FitOptions

if TYPE_CHECKING:  # the lazy exports, for readers and the API pages
    from growsim.fitting.fit import FitResult, fit_image
    from growsim.fitting.setups import FIT_SETUPS, FitSetup
    from growsim.fitting.state import FitState

__all__ = ["FIT_SETUPS", "FitOptions", "FitResult", "FitSetup", "FitState", "fit_image"]

# Lazy exports: the fit loads numba, pandas and SciPy (the state NumPy); the options do
# not. name -> module
_LAZY = {
    "FitResult": "growsim.fitting.fit",
    "fit_image": "growsim.fitting.fit",
    "FIT_SETUPS": "growsim.fitting.setups",
    "FitSetup": "growsim.fitting.setups",
    "FitState": "growsim.fitting.state",
}


def __getattr__(name: str):
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'growsim.fitting' has no attribute {name!r}")


def __dir__():
    return sorted([*globals(), *_LAZY])
