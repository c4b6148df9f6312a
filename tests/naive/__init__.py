"""Test oracles: slow, obviously correct NumPy / plain-Python versions of growsim's kernels.

One module per kernel module (``naive.<m>`` for ``growsim.kernels.<m>``), each function
named after the kernel it is the oracle of (``naive.views.render_thin`` mirrors
:func:`growsim.kernels.views.render_thin`), written from the formula, not line by line;
``tests/test_kernel_config.py`` checks that every kernel module has one:

- :mod:`naive.capsule`: the capsule walk over a shadow map's occupied pixels;
- :mod:`naive.fish`: the fish's swim and collision count;
- :mod:`naive.ga`: the GA's decoding, crossovers and mutations;
- :mod:`naive.gravity`: loads at joints, first break, end radii;
- :mod:`naive.honda`: the Honda tree's growth, sag and leaves;
- :mod:`naive.hormone`: the hormone-module model's walls, placement and step;
- :mod:`naive.ifs2d`: the chaos game, its random stream and raster;
- :mod:`naive.ifs3d`: the IFS tree's maps, composition and population scores;
- :mod:`naive.light`: the shadow-map light's frames, exposures (the production entries
  ``segment_exposure_into``, ``point_light_into``), cosines, and a pixel-by-pixel z-buffer;
- :mod:`naive.mesh`: the mesh kernel's tubes and leaves;
- :mod:`naive.ochoa`: the Ochoa tree's shadow bins, pruning and junctions;
- :mod:`naive.raster`: the segment rasteriser;
- :mod:`naive.shadow_gl`: the OpenGL backend's CPU side (vertices, texels, depth test);
- :mod:`naive.trunk`: the traced trunk's scores (edges, inside colour) and path;
- :mod:`naive.views`: framing, thin and anti-aliased views, blur, NCC;
- :mod:`naive.water`: the water's sub-tree demand and distribution.

Tests import them as ``from naive.views import frame_points`` (pytest puts ``tests/`` on
``sys.path``; ``tests/`` itself is not a package).
"""
