"""growsim: an evolutionary plant-growth simulator.

One generic GA (:mod:`growsim.ga`) drives every model in :mod:`growsim.models`; every
plant model returns a :class:`growsim.phenotypes.plant.Plant`; experiments are TOML configs run by
:mod:`growsim.experiment` and the ``growsim`` command line.
"""

__version__ = "0.2.0"

__all__ = ["__version__", "load_config", "load_plan", "run", "sweep"]

# Lazy exports: ``import growsim`` stays fast (no pydantic, pandas or numba at import);
# ``growsim.run`` imports the experiment layer on first use.
_LAZY = {"run", "sweep", "load_config", "load_plan"}


def __getattr__(name: str):
    if name in _LAZY:
        from growsim import experiment

        return getattr(experiment, name)
    raise AttributeError(f"module 'growsim' has no attribute {name!r}")


def __dir__():
    return sorted([*globals(), *_LAZY])
