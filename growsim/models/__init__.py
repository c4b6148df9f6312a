"""Plant (and agent) models.

Every model is a module that publishes:

- ``NAME``: its registry name (``"honda"``, ``"ifs3d"``, ...);
- ``PARAMS``: a tuple of :class:`growsim.models.base.Param` (name, range, real/int,
  default), so the GA can evolve any of them;
- ``PRESETS``: a dict of named parameter sets (may be empty);
- ``develop(params, *, seed=0, env=None) -> Plant``: grow one phenotype.

:func:`get_model` finds a model module by name.
"""

from __future__ import annotations

import importlib
from types import ModuleType

from growsim.errors import UserInputError

#: registry name -> module path. One line per model.
MODELS: dict[str, str] = {
    "honda": "growsim.models.honda",
    "ifs3d": "growsim.models.ifs3d",
}

__all__ = ["MODELS", "get_model"]


def get_model(name: str) -> ModuleType:
    """Return the model module registered as ``name``.

    Examples
    --------
    >>> get_model("honda").NAME
    'honda'
    """
    try:
        path = MODELS[name]
    except KeyError:
        raise UserInputError(
            f"unknown model {name!r}; available: {', '.join(sorted(MODELS))}"
        ) from None
    return importlib.import_module(path)
