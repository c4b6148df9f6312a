"""Fitting a model to pictures of a tree (``growsim fit-image``).

- :mod:`~growsim.fitting.fit`: :func:`fit_image`, the whole fit as a library call
  (returns a :class:`FitResult`; the command only parses its arguments and prints);
- :mod:`~growsim.fitting.choices`: what the fit chooses for the user (drawing or photo,
  the models, line width, sizes, leaves, keywords) and which candidate it keeps;
- :mod:`~growsim.fitting.setups`: what is fitted for each model (:class:`FitSetup`), the
  fit's config, the coarse-to-fine refinement, the sweep of the discrete parameters and
  the arrangement search.

The pictures themselves are read and segmented by :mod:`growsim.pictures`.

Examples
--------
>>> from growsim.fitting import FIT_SETUPS, fit_image
>>> sorted(FIT_SETUPS)
['honda', 'ifs2d', 'ifs3d']
"""

from growsim.fitting.fit import FitResult, fit_image
from growsim.fitting.setups import FIT_SETUPS, FitSetup

__all__ = ["FIT_SETUPS", "FitResult", "FitSetup", "fit_image"]
