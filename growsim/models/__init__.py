"""Models: what turns evolved parameters into a phenotype (a plant, a point cloud, a
trajectory).

Every model is a :class:`Model` (name, phenotype kind, parameter spec of :class:`Param`,
presets, ``develop``, optional ``grow``; both from :mod:`growsim.models.base`),
registered below by name. :func:`get_model` finds one. To add a model, see
``docs/extending.md``.
"""

from __future__ import annotations

from growsim.models.base import Model, Param
from growsim.registry import Registry

#: registry name -> the model (``"module:MODEL"``, imported on first use). One line per model.
MODELS: Registry[Model] = Registry(
    "model",
    {
        "honda": "growsim.models.honda:MODEL",
        "ifs3d": "growsim.models.ifs3d:MODEL",
        "fish": "growsim.models.fish:MODEL",
        "hormone": "growsim.models.hormone:MODEL",
        "ifs2d": "growsim.models.ifs2d:MODEL",
    },
)

__all__ = ["MODELS", "Model", "Param", "get_model"]


def get_model(name: str) -> Model:
    """Return the model registered as ``name`` (:class:`UserInputError` if there is none).

    Examples
    --------
    >>> get_model("honda").name
    'honda'
    """
    return MODELS.get(name)
