"""Pictures of trees as silhouettes: reading a picture (a drawing by its grey levels, a
colour photo by its sky and ground), checking and framing it for a fit.

- :mod:`~growsim.pictures.images`: reading, grey-level thresholds, checks, framing;
- :mod:`~growsim.pictures.photo`: colour photos, the tree apart from sky and ground.

Fitting a model to pictures is :mod:`growsim.fitting`, a layer above (it runs experiments).
"""
