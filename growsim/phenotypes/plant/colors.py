"""Colouring a plant by its environment: the fields a view can paint its segments by
(:data:`COLORS`: the light each receives, the stress ratio at its joint, the share of its
water demand met), their scales (:func:`color_scale`), the values per segment
(:func:`segment_colors`, from :meth:`growsim.env.Environment.segment_table`) and the arrow
that shows the light's direction (:func:`light_arrow_mesh`).
:mod:`growsim.phenotypes.plant.views` draws
them (``growsim grow --color``, ``growsim show --color``).

Plants whose segments carry ``chlorophyll`` and ``lignin`` (the hormone model's modules)
are painted by what they are, by default: :func:`tissue_rgb` runs from chlorophyll green
(young) through a paler green (chlorophyll lost) to lignified brown (wood), and the soil
under them is :data:`GROUND_RGB`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from growsim.env import Environment
from growsim.errors import UserInputError
from growsim.phenotypes.base import Phenotype
from growsim.skeleton import LEAF

__all__ = [
    "ARROW_RGB",
    "COLORS",
    "GREEN_RGB",
    "GROUND_RGB",
    "NAN_RGB",
    "PALE_RGB",
    "WOOD_RGB",
    "ColorScale",
    "check_color",
    "color_scale",
    "environment_or_default",
    "light_arrow_mesh",
    "segment_colors",
    "tissue_rgb",
]

#: the fields a view can colour a plant's segments by (``--color``): the light each
#: receives, the stress ratio at its joint, the share of its water demand met
COLORS = ("light", "stress", "water")

NAN_RGB = (0.78, 0.78, 0.78)  # segments a field does not judge: light grey
ARROW_RGB = (0.93, 0.55, 0.05)  # the light arrow: orange

#: tissue colours (:func:`tissue_rgb`): full chlorophyll, no lignin (young, a leaf)
GREEN_RGB = (0.22, 0.58, 0.16)
#: no chlorophyll, no lignin (green tissue that lost its chlorophyll): pale yellow-green
PALE_RGB = (0.72, 0.74, 0.42)
#: full lignin (wood): bark brown
WOOD_RGB = (0.42, 0.28, 0.16)
#: the soil under a plant that grows on a ground
GROUND_RGB = (0.60, 0.50, 0.38)


def tissue_rgb(chlorophyll, lignin) -> np.ndarray:
    """``(n, 3)`` float64 RGB in ``[0, 1]``: the colour of tissue with ``chlorophyll`` and
    ``lignin`` (each ``(n,)``, clipped to ``[0, 1]``): the green of young tissue mixed
    towards :data:`PALE_RGB` as chlorophyll falls, ``PALE + c (GREEN - PALE)``, then
    towards :data:`WOOD_RGB` by the lignin, ``(1 - g) young + g WOOD``. A young module
    (``c = 1, g = 0``) is :data:`GREEN_RGB`, a lignified one (``g = 1``) bark brown.

    Examples
    --------
    >>> tissue_rgb([1.0, 0.5, 0.0], [0.0, 0.5, 1.0]).round(3).tolist()
    [[0.22, 0.58, 0.16], [0.445, 0.47, 0.225], [0.42, 0.28, 0.16]]
    """
    c = np.clip(np.asarray(chlorophyll, dtype=np.float64), 0.0, 1.0)[:, None]
    g = np.clip(np.asarray(lignin, dtype=np.float64), 0.0, 1.0)[:, None]
    young = np.array(PALE_RGB) + c * (np.array(GREEN_RGB) - np.array(PALE_RGB))
    return (1.0 - g) * young + g * np.array(WOOD_RGB)


@dataclass(frozen=True)
class ColorScale:
    """How a field of :data:`COLORS` is painted: the ``column`` of
    :meth:`growsim.env.Environment.segment_table` it shows, the scalar bar's ``title``, a
    matplotlib colormap ``cmap`` over ``clim``, the colour of values above the range
    (``above_color``, ``above_label`` beside the bar; ``None``: clipped to the top colour)
    and what the grey of a segment without a value means (``nan_label``, beside the bar;
    ``None``: every segment has one).
    """

    field: str
    column: str
    title: str
    cmap: str
    clim: tuple[float, float]
    above_color: str | None = None
    above_label: str | None = None
    nan_label: str | None = None


def check_color(color, label: str = "color") -> str | None:
    """``color`` if it is ``None`` or one of :data:`COLORS`, else :class:`UserInputError`
    naming ``label`` (the option).

    Examples
    --------
    >>> check_color("light"), check_color(None)
    ('light', None)
    >>> check_color("heat", "--color")
    Traceback (most recent call last):
    ...
    growsim.errors.UserInputError: --color 'heat': unknown field; choose from light, stress, water
    """
    if color is None or (isinstance(color, str) and color in COLORS):
        return color
    raise UserInputError(f"{label} {color!r}: unknown field; choose from {', '.join(COLORS)}")


def environment_or_default(env):

    if env is None:
        return Environment()
    if not isinstance(env, Environment):
        raise UserInputError(f"env: expected a growsim Environment, got {type(env).__name__}")
    return env


def color_scale(color: str, env=None) -> ColorScale:
    """The :class:`ColorScale` of field ``color`` (one of :data:`COLORS`) under ``env``
    (default ``Environment()``):

    - ``light``: the light received, ``0 .. env.light.intensity``, dark to bright
      (``inferno``);
    - ``stress``: the stress ratio at each stem's joint, ``0 .. 1`` (``cividis``); a joint
      that breaks (ratio ``>= 1``) is red, marked ``>= 1 breaks`` beside the bar; leaves
      are not judged (grey);
    - ``water``: the share of each segment's water demand met, ``0 .. 1`` (``viridis``);
      segments that demand nothing (stems, leaves in full shade) are grey.

    Examples
    --------
    >>> from growsim.env import Environment
    >>> s = color_scale("light", Environment.model_validate({"light": 0.5}))
    >>> s.column, s.clim, s.cmap
    ('light', (0.0, 0.5), 'inferno')
    >>> color_scale("stress").above_label
    '>= 1 breaks'
    """
    color = check_color(color)
    if color is None:
        raise UserInputError("color: choose a field from " + ", ".join(COLORS))
    env = environment_or_default(env)
    if color == "light":
        top = float(env.light.intensity) or 1.0
        return ColorScale("light", "light", "light received", "inferno", (0.0, top))
    if color == "stress":
        return ColorScale(
            "stress",
            "stress_ratio",
            "stress ratio (bending stress / strength)",
            "cividis",
            (0.0, 1.0),
            above_color="red",
            above_label=">= 1 breaks",
            nan_label="leaf",
        )
    return ColorScale(
        "water", "water_met", "water: share of demand met", "viridis", (0.0, 1.0),
        nan_label="no demand",
    )  # fmt: skip


def segment_colors(plant, color: str, env=None) -> np.ndarray:
    """``(n,)`` float64: the value of field ``color`` (one of :data:`COLORS`) each segment
    of ``plant`` is painted with, from ``env.segment_table(plant)`` (default environment:
    ``Environment()``); NaN where the field does not judge a segment (painted grey): the
    leaves for ``stress``, the segments without water demand for ``water``.

    Examples
    --------
    >>> from growsim.models import honda
    >>> tree = honda.develop(honda.PRESETS["zelkova"])
    >>> stress = segment_colors(tree, "stress")
    >>> bool(np.isnan(stress[tree.kind == 1]).all()), bool(np.nanmax(stress) < 1)
    (True, True)
    """

    scale = color_scale(color, env)
    # a plant: a phenotype of kind "plant" (the Plant class's module sits above this one)
    if not (isinstance(plant, Phenotype) and plant.phenotype == "plant"):
        raise UserInputError(
            f"color {color!r}: colouring needs a Plant (its segments), got {type(plant).__name__}"
        )
    table = environment_or_default(env).segment_table(plant)
    values = table[scale.column].to_numpy(dtype=np.float64, copy=True)
    if color == "stress":
        values[plant.kind == LEAF] = np.nan
    elif color == "water":
        no_demand = (table["water"].to_numpy() == 0) & (table["water_met"].to_numpy() == 1)
        values[no_demand] = np.nan
    return values


def light_arrow_mesh(bounds, direction):
    """An arrow (pyvista mesh) outside ``bounds`` on the light's side, pointing along the
    light's ``direction`` into the plant."""
    import pyvista as pv

    d = np.asarray(direction, float)
    d = d / np.linalg.norm(d)
    b = np.asarray(bounds, float).reshape(3, 2)
    centre, half = b.mean(1), np.maximum((b[:, 1] - b[:, 0]) / 2.0, 0.0)
    radius = max(float(np.linalg.norm(half)), 1e-6)
    # distance from the centre to the box's surface, going towards the light
    with np.errstate(divide="ignore"):
        exit_at = float(np.min(np.where(np.abs(d) > 1e-12, half / np.abs(d), np.inf)))
    length = 0.4 * radius
    tip = centre - d * (exit_at + 0.06 * radius)
    return pv.Arrow(
        start=tip - d * length,
        direction=d,
        scale=length,
        tip_length=0.3,
        tip_radius=0.12,
        shaft_radius=0.045,
    )
