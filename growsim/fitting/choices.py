"""What ``growsim fit-image`` chooses for the user: whether the pictures are drawings or
photos (:func:`picture_kind`), whether the tree is reconstructed or searched
(:func:`method_choice`), which models are fitted (:func:`candidates`), each model's
line width, raster sizes and leaves (:func:`model_choices`) and keywords
(:func:`fit_settings`), and which candidate is kept (:func:`kept_candidate`). Every
choice is a ``{"value": ..., "why": ...}`` that :func:`growsim.fitting.fit.fit_image`
prints and writes to ``fit.json``.
"""

from __future__ import annotations

from pathlib import Path

from growsim.errors import UserInputError
from growsim.fitting.options import LEAF_MODES, SEGMENTATIONS, FitOptions, flag, raster_sizes
from growsim.fitting.setups import FIT_SETUPS, LEAF_MARGIN, SIZES
from growsim.pictures.images import classify_picture

__all__ = [
    "SEARCH_OPTIONS",
    "SEGMENTATIONS",
    "candidates",
    "fit_settings",
    "kept_candidate",
    "method_choice",
    "model_choices",
    "picture_kind",
    "raster_sizes",
    "table_evaluations",
]


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


#: the options of the search alone (a model, its budgets, sizes, line width, leaves): one
#: given (not its default) has a photograph searched under ``method="auto"``
SEARCH_OPTIONS = ("model", "budget", "line_width", "sizes", "size", "leaves", "evaluations",
                  "refine", "arrange", "blur", "restarts", "carry")  # fmt: skip


def method_choice(options: FitOptions, drawing: bool) -> dict:
    """The ``method`` choice of a fit (``{"value", "why"}``, the value ``"reconstruct"`` or
    ``"search"``): as given, else (``"auto"``) a drawing searched (its lines are a model's:
    the exact search of the seed), a photograph reconstructed (the tree it shows,
    :func:`growsim.reconstruction.reconstruct`) unless an option of the search alone
    (:data:`SEARCH_OPTIONS`) is given. ``method="reconstruct"`` with such an option is
    refused (:class:`~growsim.errors.UserInputError` naming it).

    Examples
    --------
    >>> method_choice(FitOptions(front="t.jpg"), drawing=False)["value"]
    'reconstruct'
    >>> method_choice(FitOptions(front="t.jpg", model="honda"), drawing=False)["why"]
    'a photograph, an option of the search given (--model): searched'
    >>> method_choice(FitOptions(front="t.png"), drawing=True)["value"]
    'search'
    >>> method_choice(FitOptions(front="t.jpg", method="reconstruct", restarts=2), False)
    Traceback (most recent call last):
    ...
    growsim.errors.UserInputError: --restarts: an option of the search, not of --method reconstruct
    """
    fields = FitOptions.model_fields
    given = [k for k in SEARCH_OPTIONS if getattr(options, k) != fields[k].default]
    if options.method != "auto":
        if options.method == "reconstruct" and given:
            raise UserInputError(
                f"{flag(given[0])}: an option of the search, not of --method reconstruct"
            )
        return {"value": options.method, "why": "given"}
    if drawing:
        return {"value": "search", "why": "a drawing: its model's parameters searched"}
    if given:
        shown = ", ".join(flag(k) for k in given)
        why = f"a photograph, an option of the search given ({shown}): searched"
        return {"value": "search", "why": why}
    why = "a photograph: the tree it shows reconstructed; --method search searches a model's "
    why += "parameters instead"
    return {"value": "reconstruct", "why": why}


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
