"""Fitting a model to pictures of a tree (``growsim fit-image``).

- :mod:`~growsim.fitting.setups`: what is fitted for each model (:class:`FitSetup`), the
  fit's config, the coarse-to-fine refinement and the arrangement search.

The pictures themselves are read and segmented by :mod:`growsim.pictures`.
"""
