"""Pictures of trees as silhouettes: reading a picture (a drawing by its grey levels, a
colour photo by its sky and ground), checking and framing it for a fit.

- :mod:`~growsim.pictures.images`: grey-level thresholds, framing, the silhouettes of a
  front and a side picture by either segmentation;
- :mod:`~growsim.pictures.photo`: colour photos, the tree apart from sky and ground;
- :mod:`~growsim.pictures.scene`: an outdoor photo's scene: the sky, the horizon's
  clutter, the objects standing on the ground;
- :mod:`~growsim.pictures.pixels`: drawings made of square pixels, read back pixel for
  pixel;
- :mod:`~growsim.pictures.reading`: opening a picture file, the checks every silhouette
  passes.

Each module imports only the ones listed after it (an import-linter contract).

Fitting a model to pictures is :mod:`growsim.fitting`, a layer above (it runs experiments).
"""
