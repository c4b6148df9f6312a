"""What ``growsim fit-image`` chooses for the user: whether the pictures are drawings or
photos (:func:`picture_kind`), which models are fitted (:func:`candidates`), each model's
line width, raster sizes and leaves (:func:`model_choices`) and keywords
(:func:`fit_settings`), and which candidate is kept (:func:`kept_candidate`). Every
choice is a ``{"value": ..., "why": ...}`` that :func:`growsim.fitting.fit.fit_image`
prints and writes to ``fit.json``.
"""

from __future__ import annotations

from pathlib import Path

from growsim.errors import UserInputError
from growsim.fitting.setups import FIT_SETUPS, LEAF_MARGIN, LEAF_MODES, SIZES
from growsim.pictures.images import classify_picture

__all__ = [
    "SEGMENTATIONS",
    "candidates",
    "fit_settings",
    "kept_candidate",
    "model_choices",
    "picture_kind",
    "raster_sizes",
    "table_evaluations",
]


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


#: ``segmentation`` of :func:`fit_image`: ``"auto"`` (a drawing by the threshold, a photo by
#: the photo segmentation: :func:`~growsim.pictures.images.classify_picture`)
SEGMENTATIONS = ("auto", "photo", "threshold")


def picture_kind(front, side, segmentation) -> tuple[bool, dict]:
    """Whether the pictures are drawings, and the ``segmentation`` choice (``"auto"``: the
    threshold when every picture is a drawing,
    :func:`~growsim.pictures.images.classify_picture`, else the photo segmentation)."""

    if segmentation == "auto":
        kinds = [(p, *classify_picture(p)) for p in (front, side) if p is not None]
        drawing = all(k == "drawing" for _, k, _ in kinds)
        why = "; ".join(f"{Path(p).name}: {w}" for p, _, w in kinds)
        return drawing, {"value": "threshold" if drawing else "photo", "why": why}
    return segmentation == "threshold", {"value": segmentation, "why": "given"}


def candidates(model: str, drawing: bool, side) -> tuple[list[str], dict]:
    """The models fitted (``"auto"``: every setup whose ``kinds`` has the picture's kind and
    whose views take the pictures given) and the ``model`` choice."""
    if model != "auto":
        FIT_SETUPS.get(model)  # an unknown name is refused here
        return [model], {"value": model, "why": "given"}
    kind = "drawing" if drawing else "photo"
    names = [n for n, st in FIT_SETUPS.items()
             if kind in st.kinds and (side is None or "side" in st.views)]  # fmt: skip
    why = f"a {kind}: {', '.join(names)} fitted at the first size, the best kept"
    return names, {"value": "auto", "why": why}


def model_choices(setup, drawing: bool, line_width, sizes, size, leaves) -> dict:
    """What :func:`fit_image` chose for the user for one model's ``setup``, each ``{"value":
    ..., "why": ...}``, unless given: ``line_width`` (a drawing: ``"thin"``, the renderer's
    1-pixel lines; a photo: the model's), ``sizes`` (a drawing: the setup's
    :attr:`~growsim.fitting.setups.FitSetup.drawing` sizes; a photo:
    :data:`~growsim.fitting.setups.SIZES`) and ``leaves`` (a drawing: ``"keep"``, the
    setup's tree as the seed fitted it; a photo: ``"auto"``)."""
    choices: dict[str, dict] = {}
    kind = "a drawing" if drawing else "a photo"
    if line_width is not None:
        choices["line_width"] = {"value": line_width, "why": "given"}
    elif drawing:
        choices["line_width"] = {"value": "thin", "why": f"{kind}: 1-pixel lines, as drawn"}
    else:
        drawn = "branches at their width" if setup.line_width == "radius" else "thin lines"
        why = f"{kind}: the model's ({drawn})"
        choices["line_width"] = {"value": setup.line_width, "why": why}
    if size is not None:
        choices["sizes"] = {"value": [int(size)], "why": "given (--size)"}
    elif sizes is not None:
        choices["sizes"] = {"value": list(raster_sizes(sizes)), "why": "given"}
    elif drawing:
        why = f"{kind}: the lines frame exactly, no photo's refinement"
        choices["sizes"] = {"value": list(setup.drawing["sizes"]), "why": why}
    else:
        choices["sizes"] = {"value": list(SIZES), "why": f"{kind}: coarse to fine"}
    if leaves is not None:
        choices["leaves"] = {"value": leaves, "why": "given"}
    elif drawing:
        choices["leaves"] = {"value": "keep", "why": f"{kind}: the model's setup, as drawn"}
    else:
        why = f"{kind}: a bare and a leafy tree fitted at the first size, the leafy kept if "
        why += f"it scores {LEAF_MARGIN} more"
        choices["leaves"] = {"value": "auto", "why": why}
    return choices


def table_evaluations(setup) -> int:
    """The evaluations of a setup's first stage as its tables give them (the GA's budget,
    or its generations x population, plus the polish's)."""
    ga = setup.tables()["ga"]
    if ga.get("evaluations"):
        return int(ga["evaluations"])
    polish = ga.get("polish") or {}
    return int(ga["generations"] * ga["population"] * ga.get("islands", 1)) + int(
        polish.get("evaluations", 0)
    )


def fit_settings(name: str, drawing: bool, given: dict, budget: float) -> dict:
    """One model's settings of a fit: its setup, its choices (:func:`model_choices`) and its
    keywords, each the one given, else the setup's for the picture's kind (a drawing:
    :attr:`~growsim.fitting.setups.FitSetup.drawing`), the evaluations times ``budget``;
    checked. ``given``: the options given (a missing key or ``None``: not given).

    Examples
    --------
    >>> st = fit_settings("honda", False, {"restarts": 2}, 1.0)
    >>> st["restarts"], st["sizes"], st["leaves"]
    (2, (64, 128, 256), 'auto')
    """
    given = {
        k: given.get(k)
        for k in (
            "line_width",
            "sizes",
            "size",
            "leaves",
            "evaluations",
            "refine",
            "arrange",
            "blur",
            "restarts",
            "carry",
        )
    }
    setup = FIT_SETUPS.get(name)
    choices = model_choices(setup, drawing, given["line_width"], given["sizes"], given["size"],
                       given["leaves"])  # fmt: skip
    st = {"setup": setup, "choices": choices, "score": {} if drawing else dict(setup.score)}
    st.update((k, c["value"]) for k, c in choices.items())
    defaults = dict(restarts=setup.restarts, carry=setup.carry, evaluations=setup.evaluations,
                    refine=setup.refine, arrange=setup.arrange, blur=setup.blur)  # fmt: skip
    if drawing:  # the photos' budget is not a drawing's
        defaults["evaluations"] = None
        defaults.update((k, v) for k, v in setup.drawing.items() if k in defaults)
    for key, value in defaults.items():
        st[key] = value if given[key] is None else given[key]
    if budget != 1.0:
        if given["evaluations"] is None:
            base = st["evaluations"] or table_evaluations(setup)
            st["evaluations"] = max(100, round(budget * base))
        for key in ("refine", "arrange"):
            if given[key] is None:
                st[key] = round(budget * st[key])
    if st["leaves"] not in LEAF_MODES:
        raise UserInputError(
            f"--leaves: expected one of {', '.join(LEAF_MODES)}, got {st['leaves']!r}"
        )
    if st["restarts"] < 1:
        raise UserInputError(f"--restarts: at least 1, got {st['restarts']}")
    if st["carry"] < 0:
        raise UserInputError(f"--carry: at least 0, got {st['carry']}")
    if st["arrange"] < 0:
        raise UserInputError(f"--arrange: at least 0, got {st['arrange']}")
    st["sizes"] = sizes = raster_sizes(st["sizes"])
    widest = st["blur"] * (sizes[-2] if len(sizes) > 1 else sizes[0]) / sizes[0]
    if not (0.0 <= st["blur"] and widest <= 16.0):
        raise UserInputError(
            f"--blur: expected 0 or more pixels, at most 16 at the next-to-last size "
            f"(the blur grows with the size), got {st['blur']:g} ({widest:g} at that size)"
        )
    if st["leaves"] == "auto":
        # a bare and a leafy tree, when the model has leaves to choose
        if setup.leaves and setup.bare:
            st["modes"] = ("bare", "fit") if setup.auto_leafy else ("bare",)
        else:
            st["modes"] = ("keep",)
    else:
        st["modes"] = (st["leaves"],)
    return st


def kept_candidate(judged: dict, names) -> tuple[str, str]:
    """The ``(model, leaves mode)`` kept from ``judged`` ``{(model, mode): score}``: per
    model the leafy tree only if it beats the bare one by
    :data:`~growsim.fitting.setups.LEAF_MARGIN`, then the best model."""
    per_model = {}
    for m in names:
        modes = {mode: v for (mm, mode), v in judged.items() if mm == m}
        if "fit" in modes and "bare" in modes:
            mode = "fit" if modes["fit"] > modes["bare"] + LEAF_MARGIN else "bare"
        else:
            mode = max(modes, key=modes.get)
        per_model[m] = mode
    m = max(names, key=lambda m: judged[m, per_model[m]])
    return m, per_model[m]
