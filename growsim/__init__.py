"""growsim: an evolutionary plant-growth simulator.

One generic GA (:mod:`growsim.ga`) drives every model in :mod:`growsim.models`; every
plant model returns a :class:`growsim.plant.Plant`; experiments are TOML configs run by
:mod:`growsim.experiment` and the ``growsim`` command line.
"""

__version__ = "0.1.0"

__all__ = ["__version__"]
