"""Pictures of trees as silhouettes: reading a picture (a drawing by its grey levels, a
colour photo by its sky and ground), checking and framing it for a fit.

- :mod:`~growsim.pictures.images`: grey-level thresholds, the silhouettes of a front and
  a side picture by either segmentation;
- :mod:`~growsim.pictures.framing`: silhouettes framed for fitting, and back;
- :mod:`~growsim.pictures.kinds`: a drawing or a photo;
- :mod:`~growsim.pictures.photo`: colour photos, the tree apart from sky and ground, by
  the steps of the modules below it;
- :mod:`~growsim.pictures.hints`: the hints (``--box``, ``--point``) and the refusals;
- :mod:`~growsim.pictures.foot`: the trunk's foot, the trunk traced down to it and the flat
  pieces beyond it dropped;
- :mod:`~growsim.pictures.trunk`: the trunk below the skyline (GrabCut);
- :mod:`~growsim.pictures.record`: what the photo segmentation found, and its picture;
- :mod:`~growsim.pictures.crown`: the crown's region and its connected pieces;
- :mod:`~growsim.pictures.sky`: the sky behind the crown and the horizon at the working
  size;
- :mod:`~growsim.pictures.coverage`: each pixel's share covered by the tree;
- :mod:`~growsim.pictures.colours`: a per-picture colour model of the background
  against the tree;
- :mod:`~growsim.pictures.scene`: an outdoor photo's scene: the sky, the horizon's
  clutter, the objects standing on the ground;
- :mod:`~growsim.pictures.backdrop`: what lies behind the tree (the sky, a row's ground),
  filled in where the tree hides it;
- :mod:`~growsim.pictures.pixels`: drawings made of square pixels, read back pixel for
  pixel;
- :mod:`~growsim.pictures.reading`: opening a picture file, the checks every silhouette
  passes.

Each module imports only the ones listed after it (an import-linter contract).

Fitting a model to pictures is :mod:`growsim.fitting`, a layer above (it runs experiments).
"""
