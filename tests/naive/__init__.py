"""Test oracles: slow, obviously correct NumPy / plain-Python versions of growsim's kernels.

One module per kernel family, each function named after the kernel it is the oracle of
(``naive.views.render_thin`` mirrors :func:`growsim.kernels.views.render_thin`):

- :mod:`naive.ga`: the GA's kernels (:mod:`growsim.kernels.ga`);
- :mod:`naive.honda`: the Honda tree's growth, sag and leaves (:mod:`growsim.kernels.honda`);
- :mod:`naive.mesh`: the mesh kernel's tubes and leaves (:mod:`growsim.kernels.mesh`);
- :mod:`naive.ifs3d`: the IFS tree's maps, composition and population scores
  (:mod:`growsim.kernels.ifs3d`);
- :mod:`naive.views`: framing, thin and anti-aliased views, blur, NCC
  (:mod:`growsim.kernels.views`);
- :mod:`naive.raster`: the segment rasteriser (:mod:`growsim.kernels.raster`).

Tests import them as ``from naive.views import frame_points`` (pytest puts ``tests/`` on
``sys.path``; ``tests/`` itself is not a package).
"""
