"""The options of a fit, declared once: :class:`FitOptions`.

Every option of :func:`growsim.fitting.fit.fit_image` is a field here, with its
description, limits and default: the function validates its keywords into a
:class:`FitOptions`, ``growsim fit-image`` builds its flags from the fields (the flag
``--line-width`` of the field ``line_width``; its short help, metavar and group from the
field's ``cli`` extra), and a fit's saved state (:class:`~growsim.fitting.state.FitState`)
keeps them under the same names. A bad value is refused with one line naming the flag
(``--restarts: at least 1, got 0``). How the fit runs, not what it fits (``out``,
``resume``, ``workers``, ``progress``), is no option of the fit.

The module imports no heavy library (the command line builds its parser from it).
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Any, Literal, get_args, get_origin

from pydantic import Field, ValidationError, field_validator

from growsim.errors import UserInputError
from growsim.options import Options

__all__ = [
    "HINTS",
    "LEAF_MODES",
    "METHODS",
    "PICTURES",
    "SEGMENTATIONS",
    "FitOptions",
    "flag",
    "parse_hint",
    "parse_threshold",
    "raster_sizes",
]

#: ``leaves`` of a fit: ``"auto"`` (a bare and a leafy tree fitted, the better kept),
#: ``"fit"`` (leaves fitted), ``"bare"`` (no leaves), ``"keep"`` (the setup's, fixed)
LEAF_MODES = ("auto", "fit", "bare", "keep")

#: ``method`` of a fit: ``"auto"`` (a drawing searched, a photograph reconstructed),
#: ``"reconstruct"`` (the tree the picture shows, :func:`growsim.reconstruction.reconstruct`)
#: or ``"search"`` (a model's parameters searched to match the picture)
METHODS = ("auto", "reconstruct", "search")

#: ``segmentation`` of a fit: ``"auto"`` (a drawing by the threshold, a photo by the photo
#: segmentation: :func:`~growsim.pictures.images.classify_picture`)
SEGMENTATIONS = ("auto", "photo", "threshold")

#: the options naming picture files (kept absolute in a fit's saved state)
PICTURES = ("front", "side", "mask_front", "mask_side")

#: a photo's hints where its tree is: option -> (numbers, the form a flag's value takes)
HINTS = {
    "box": (4, "x0,y0,x1,y1"),
    "point": (2, "x,y"),
    "box_side": (4, "x0,y0,x1,y1"),
    "point_side": (2, "x,y"),
}


def flag(name: str) -> str:
    """The command-line flag of option ``name``.

    Examples
    --------
    >>> flag("line_width"), flag("box_side")
    ('--line-width', '--box-side')
    """
    return "--" + name.replace("_", "-")


def raster_sizes(values) -> tuple[int, ...]:
    """The raster sizes of a coarse-to-fine fit, checked: increasing, each in 8..1024
    (``values``: ints, or a text such as ``"64,128,256"``). A bad list raises
    :class:`UserInputError`.

    Examples
    --------
    >>> raster_sizes("64,128, 256"), raster_sizes([32])
    ((64, 128, 256), (32,))
    >>> raster_sizes("128,64")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    growsim.errors.UserInputError: expected increasing raster sizes in 8..1024, ... got '128,64'
    """
    try:
        if isinstance(values, str):
            sizes = tuple(int(v) for v in values.replace(",", " ").split())
        else:
            sizes = tuple(int(v) for v in values)
    except (TypeError, ValueError):
        sizes = ()
    if not sizes or any(not 8 <= v <= 1024 for v in sizes) or list(sizes) != sorted(set(sizes)):
        raise UserInputError(
            f"expected increasing raster sizes in 8..1024, e.g. '64,128,256', got {values!r}"
        )
    return sizes


_THRESHOLD = "expected 'otsu' or a grey level between 0 (black) and 1 (white)"


def parse_threshold(text: str) -> str | float:
    """``--threshold``'s value: ``"otsu"`` or a grey level strictly between 0 (black) and
    1 (white); anything else raises :class:`UserInputError`.

    Examples
    --------
    >>> parse_threshold("otsu"), parse_threshold("0.4")
    ('otsu', 0.4)
    >>> parse_threshold("128")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    growsim.errors.UserInputError: expected 'otsu' or a grey level between ..., got '128'
    """
    if text == "otsu":
        return text
    try:
        value = float(text)
    except (TypeError, ValueError):
        value = math.nan
    if not 0.0 < value < 1.0:
        raise UserInputError(f"{_THRESHOLD}, got {text!r}")
    return value


def parse_hint(name: str, text: str) -> list[float]:
    """The value of the hint flag of option ``name`` (:data:`HINTS`): numbers separated by
    commas, pixels of the picture as given; a box's left before its right and its top
    above its bottom. A bad value raises :class:`UserInputError`.

    Examples
    --------
    >>> parse_hint("box", "10, 20,110,220"), parse_hint("point", "5,6")
    ([10.0, 20.0, 110.0, 220.0], [5.0, 6.0])
    >>> parse_hint("point", "a,b")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    growsim.errors.UserInputError: expected x,y (pixels of the picture, ...), got 'a,b'
    """
    n, form = HINTS[name]
    try:
        values = [float(v) for v in text.replace(" ", "").split(",")]
    except ValueError:
        values = []
    if len(values) != n or not all(math.isfinite(v) for v in values):
        raise UserInputError(
            f"expected {form} (pixels of the picture, separated by commas), got {text!r}"
        )
    _check_box(values, text)
    return values


def _check_box(values: list[float], given) -> None:
    if len(values) == 4 and not (values[0] < values[2] and values[1] < values[3]):
        raise UserInputError(
            f"expected x0,y0,x1,y1 with x0 < x1 and y0 < y1 (left, top, right, bottom), "
            f"got {given!r}"
        )


def _cli(help: str, metavar: str | None = None, group: str = "expert", **more) -> dict:
    """A field's ``cli`` extra: its flag's short help, metavar and group (``"main"`` or
    ``"expert"``; ``"positional"``: an argument without a flag), and how its text is read
    (``text``: ``"threshold"``, ``"sizes"`` or ``"hint"``; else by the field's type)."""
    return {"cli": {"help": help, "metavar": metavar, "group": group, **more}}


_PATH = "a picture file (PNG, JPEG, ...): a path, as text or os.PathLike"


class FitOptions(Options):
    """What a fit of :func:`~growsim.fitting.fit.fit_image` fits, and how: the pictures, the
    model, the searches' budgets, a photo's hints. ``None``: chosen by the picture (the
    model's own, :data:`~growsim.fitting.setups.FIT_SETUPS`; a drawing's
    :attr:`~growsim.fitting.setups.FitSetup.drawing`); ``fit.json``'s ``choices`` say what
    was chosen and why. Built by :meth:`parse` (a bad value raises
    :class:`~growsim.errors.UserInputError` naming the flag); sequences are taken for the
    lists, paths for the pictures.

    Examples
    --------
    >>> o = FitOptions.parse({"front": "tree.jpg", "model": "honda", "sizes": (32, 64)})
    >>> o.model, o.sizes, o.budget, o.leaves
    ('honda', [32, 64], 1.0, None)
    >>> FitOptions.parse({"front": "tree.jpg", "restarts": 0})
    Traceback (most recent call last):
    ...
    growsim.errors.UserInputError: --restarts: at least 1, got 0
    >>> FitOptions.parse({"front": "tree.jpg", "colour": "red"})  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    growsim.errors.UserInputError: unknown option 'colour'; the options: front, side, model, ...
    """

    front: str = Field(
        description=f"the tree's front picture ({_PATH})",
        json_schema_extra=_cli("the tree's front (PNG, JPEG, ...)", "PICTURE", "positional"),
    )
    side: str | None = Field(
        None,
        description=f"its side, seen from the right ({_PATH}); None: the front alone",
        json_schema_extra=_cli("its side (optional)", "SIDE", "positional"),
    )
    model: str = Field(
        "auto",
        description="the model fitted, a name of growsim.fitting.FIT_SETUPS; 'auto': every "
        "model that takes the picture's kind fitted at the first size, the best kept",
        json_schema_extra=_cli(
            "auto (each model that fits the picture's kind, the best kept), %(setups)s",
            "NAME",
            "main",
        ),
    )
    method: Literal[METHODS] = Field(  # type: ignore[valid-type]
        "auto",
        description="how the tree is fitted: 'reconstruct' (the tree the picture shows: its "
        "visible skeleton, lifted into 3D, twigs grown into its crown), 'search' (a model's "
        "parameters searched to match the picture); 'auto': a drawing searched, a photograph "
        "reconstructed",
        json_schema_extra=_cli(
            "auto (a drawing searched, a photograph reconstructed), reconstruct or search",
            "HOW",
            "main",
        ),
    )
    budget: float = Field(
        1.0,
        ge=0.01,
        le=100,
        description="every search's evaluations times this (a photo's search: about 90 s at 1 "
        "on 2 cores)",
        json_schema_extra=_cli(
            "every search's evaluations times X (default 1: a photo's search in about 90 s)",
            "X",
            "main",
        ),
    )
    seed: int = Field(
        0,
        ge=0,
        description="seed of the first restart (the next: seed + 1, ...)",
        json_schema_extra=_cli("random seed (default 0)", "N", "main"),
    )
    segmentation: Literal[SEGMENTATIONS] = Field(  # type: ignore[valid-type]
        "auto",
        description="how the tree is told apart: 'auto' (a drawing by a grey threshold, a "
        "photo by the photo segmentation), 'photo' or 'threshold'",
        json_schema_extra=_cli("auto, photo or threshold", "KIND"),
    )
    threshold: Literal["otsu"] | float = Field(
        "otsu",
        description="the threshold's grey level: 'otsu' (Otsu's) or a level strictly between "
        "0 (black) and 1 (white)",
        json_schema_extra=_cli(
            "otsu or a grey level between 0 (black) and 1 (white)", "otsu|LEVEL", text="threshold"
        ),
    )
    polarity: Literal["auto", "dark", "light"] = Field(
        "auto",
        description="the threshold's tree: 'auto', 'dark' or 'light' on its background",
        json_schema_extra=_cli("the tree auto, dark or light", "P"),
    )
    line_width: Literal["thin", "radius"] | None = Field(
        None,
        description="how the fitted tree is drawn: 'thin' (1-pixel lines) or 'radius' "
        "(branches at their width); None: chosen by the picture",
        json_schema_extra=_cli("thin (1-pixel lines) or radius (tubes)", "W"),
    )
    sizes: list[int] | None = Field(
        None,
        description="the raster sizes, coarse to fine, each 8..1024 (a text '64,128' too); "
        "None: chosen by the picture",
        json_schema_extra=_cli("raster sizes, coarse to fine", "PX,PX,..", text="sizes"),
    )
    size: int | None = Field(
        None,
        ge=8,
        le=1024,
        description="one raster size only, no refinement (over sizes)",
        json_schema_extra=_cli("one raster size (same as --sizes PX)", "PX"),
    )
    leaves: Literal[LEAF_MODES] | None = Field(  # type: ignore[valid-type]
        None,
        description="'auto' (a bare and a leafy tree fitted, the leafy kept if clearly "
        "better), 'fit', 'bare' or 'keep' (the setup's); None: chosen by the picture",
        json_schema_extra=_cli("%(choices)s (keep: the setup's)", "MODE"),
    )
    mask_front: str | None = Field(
        None,
        description="a mask picture of the front: only its white part may be tree",
        json_schema_extra=_cli("only its white part may be tree", "PIC"),
    )
    mask_side: str | None = Field(
        None,
        description="a mask picture of the side: only its white part may be tree",
        json_schema_extra=_cli("only its white part may be tree", "PIC"),
    )
    box: list[float] | None = Field(
        None,
        description="a photo's hint: a box [x0, y0, x1, y1] around its tree, pixels of the "
        "picture as given (where one tree cannot be told apart: the refusal names the hint)",
        json_schema_extra=_cli(
            "a photo: the tree is in this box (pixels; where several trees stand, or a tree "
            "in front of a wood)",
            "X0,Y0,X1,Y1",
            "main",
            text="hint",
        ),
    )
    box_side: list[float] | None = Field(
        None,
        description="the same as box, for the side picture",
        json_schema_extra=_cli("the same for the side picture", "X0,Y0,X1,Y1", "main", text="hint"),
    )
    point: list[float] | None = Field(
        None,
        description="a photo's hint: a pixel [x, y] on its tree (instead of box)",
        json_schema_extra=_cli(
            "a photo: a pixel on the tree (instead of --box)", "X,Y", "main", text="hint"
        ),
    )
    point_side: list[float] | None = Field(
        None,
        description="the same as point, for the side picture",
        json_schema_extra=_cli("the same for the side picture", "X,Y", "main", text="hint"),
    )
    evaluations: int | None = Field(
        None,
        ge=100,
        description="evaluations of the first stage (the setup's polish share kept)",
        json_schema_extra=_cli("evaluations of the first stage", "N"),
    )
    refine: int | None = Field(
        None,
        ge=0,
        description="evaluations of the refinement at each finer size (0: none)",
        json_schema_extra=_cli("evaluations of each finer size's refinement", "N"),
    )
    arrange: int | None = Field(
        None,
        ge=0,
        description="evaluations of each search of the branches' arrangement (0: none)",
        json_schema_extra=_cli("evaluations of the arrangement search", "N"),
    )
    blur: float | None = Field(
        None,
        ge=0,
        description="sigma of the searches' blur at the first size (pixels, scaled with the "
        "size; none at the last size; at most 16 at the next-to-last)",
        json_schema_extra=_cli("blur of the first size's search (pixels)", "SIGMA"),
    )
    restarts: int | None = Field(
        None,
        ge=1,
        description="fits of each kind of tree (seed, seed + 1, ...), the best kept",
        json_schema_extra=_cli("fits of each kind of tree, the best kept", "N"),
    )
    carry: int | None = Field(
        None,
        ge=0,
        description="how many restarts of the kept kind go on past the first size (0: all)",
        json_schema_extra=_cli("restarts carried past the first size (0: all)", "N"),
    )

    @field_validator(*PICTURES, mode="before")
    @classmethod
    def _path(cls, v):
        return os.fspath(v) if isinstance(v, os.PathLike) else v

    @field_validator("sizes", mode="before")
    @classmethod
    def _sizes(cls, v):
        return None if v is None else list(raster_sizes(v))

    @field_validator("threshold")
    @classmethod
    def _threshold(cls, v):
        if v != "otsu" and not 0.0 < v < 1.0:
            raise ValueError(f"{_THRESHOLD}, got {v!r}")
        return v

    @field_validator(*HINTS, mode="before")
    @classmethod
    def _hint(cls, v, info):
        if v is None:
            return v
        n = HINTS[info.field_name][0]
        try:
            values = [float(x) for x in v]
        except (TypeError, ValueError):
            values = []
        if len(values) != n or not all(math.isfinite(x) for x in values):
            raise ValueError(f"expected {n} numbers, got {v!r}")
        _check_box(values, v)
        return values

    @classmethod
    def parse(cls, data, where: str = "") -> FitOptions:
        """Validate ``data`` (a mapping of options); a problem raises
        :class:`~growsim.errors.UserInputError` with one line naming its flag (or the
        unknown key; ``where``: a prefix, e.g. the file the options were read from).

        Examples
        --------
        >>> FitOptions.parse({"front": "t.png", "budget": 1000})
        Traceback (most recent call last):
        ...
        growsim.errors.UserInputError: --budget: expected 0.01..100, got 1000
        >>> FitOptions.parse({"front": "t.png", "leaves": "some"})
        Traceback (most recent call last):
        ...
        growsim.errors.UserInputError: --leaves: expected one of auto, fit, bare, keep, got 'some'
        """
        try:
            return cls.model_validate(dict(data))
        except ValidationError as exc:
            raise UserInputError(where + _message(exc)) from None

    def absolute(self) -> FitOptions:
        """A copy whose pictures (:data:`PICTURES`) are absolute paths: as a fit's state
        keeps them, to go on from any directory.

        Examples
        --------
        >>> o = FitOptions(front="tree.jpg").absolute()
        >>> Path(o.front).is_absolute(), o.side
        (True, None)
        """
        paths = {k: getattr(self, k) for k in PICTURES}
        return self.model_copy(
            update={k: str(Path(v).absolute()) for k, v in paths.items() if v is not None}
        )

    def picture_keywords(self, segmentation: str) -> dict[str, Any]:
        """How the pictures are read: the keywords of
        :func:`~growsim.fitting.setups.fit_config` and
        :func:`~growsim.pictures.images.photo_segmentations` (the hints named by their
        view: ``box_front``, ...), with ``segmentation`` as chosen (never ``"auto"``).

        Examples
        --------
        >>> o = FitOptions(front="tree.jpg", point=[150, 120])
        >>> kw = o.picture_keywords("photo")
        >>> kw["point_front"], kw["box_side"], kw["segmentation"]
        ([150.0, 120.0], None, 'photo')
        """
        return dict(threshold=self.threshold, polarity=self.polarity,
                    mask_front=self.mask_front, mask_side=self.mask_side,
                    segmentation=segmentation, box_front=self.box, point_front=self.point,
                    box_side=self.box_side, point_side=self.point_side)  # fmt: skip

    @classmethod
    def cli(cls) -> dict[str, dict[str, Any]]:
        """Each option's command-line form: the ``cli`` extra of its field with its
        ``flag`` (``None`` for a positional), ``default`` and ``choices`` (a literal's
        values, else ``None``), in the fields' order.

        Examples
        --------
        >>> c = FitOptions.cli()
        >>> c["line_width"]["flag"], c["line_width"]["choices"], c["line_width"]["group"]
        ('--line-width', ('thin', 'radius'), 'expert')
        >>> c["front"]["flag"], c["budget"]["default"]
        (None, 1.0)
        """
        out = {}
        for name, f in cls.model_fields.items():
            form = dict(f.json_schema_extra["cli"])
            form["flag"] = None if form["group"] == "positional" else flag(name)
            form["default"] = None if f.is_required() else f.default
            # a literal's values are its choices ('otsu' or a number: read as a text)
            form["choices"] = _literal(f.annotation) if name != "threshold" else None
            out[name] = form
        return out


def _literal(annotation) -> tuple | None:
    """The values of the literal in ``annotation`` (``Literal[...]``, or one member of a
    union), ``None`` if it has none."""
    for a in (annotation, *get_args(annotation)):
        if get_origin(a) is Literal:
            return get_args(a)
    return None


def _bounds(name: str) -> tuple[Any, Any]:
    """The ``(ge, le)`` limits of field ``name`` (``None`` where it has none)."""
    ge = le = None
    for m in FitOptions.model_fields[name].metadata:
        ge = getattr(m, "ge", ge)
        le = getattr(m, "le", le)
    return ge, le


def _message(exc: ValidationError) -> str:
    """One line naming the flag of the first problem of a validation error of
    :class:`FitOptions`."""
    first = exc.errors(include_url=False)[0]
    name = str(first["loc"][0]) if first["loc"] else ""
    kind, got = first["type"], first.get("input")
    if kind == "extra_forbidden":
        return f"unknown option {name!r}; the options: {', '.join(FitOptions.model_fields)}"
    where = {"front": "PICTURE", "side": "SIDE"}.get(name) or flag(name)
    if kind == "missing":
        return f"{where}: required" if name != "front" else "no picture given"
    if kind in ("greater_than_equal", "less_than_equal"):
        ge, le = _bounds(name)
        if ge is not None and le is not None:
            return f"{where}: expected {ge:g}..{le:g}, got {got:g}"
        return f"{where}: at least {ge:g}, got {got}"
    if name == "threshold":
        return f"{where}: {_THRESHOLD}, got {got!r}"
    if kind == "literal_error":
        values = _literal(FitOptions.model_fields[name].annotation)
        return f"{where}: expected one of {', '.join(values)}, got {got!r}"
    text = first["msg"].removeprefix("Value error, ")
    return f"{where}: {text}" + ("" if "got " in text else f" (got {got!r})")
