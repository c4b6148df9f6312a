"""The base of every table of options a user writes: config sections, the environment,
objective options, GA options.

An :class:`Options` is a frozen pydantic model: unknown keys are refused, types are
strict (a TOML string ``"50"`` is not silently a number; ints are accepted for floats),
defaults are validated too, and a value, once built, never changes (copies with
``model_copy(update=...)``). Its fields, with their ``description`` and limits, are the
one declaration of the options: :mod:`growsim.experiment.docs` writes ``docs/configs.md``
from them.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from typing import Any, get_args

from pydantic import BaseModel, ConfigDict, ValidationError

from growsim.errors import ConfigError

__all__ = ["Options", "fields_of", "key_path", "option_classes", "validation_message"]


class Options(BaseModel):
    """Base of option tables: strict, frozen, unknown keys refused.

    Lists are used instead of tuples for vectors because strict tuples reject TOML arrays.

    Examples
    --------
    >>> from pydantic import Field
    >>> class Pot(Options):
    ...     size: float = Field(1.0, gt=0, description="pot size")
    >>> Pot(size=2).size
    2.0
    >>> Pot.model_validate({"colour": "red"})  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    pydantic_core._pydantic_core.ValidationError: 1 validation error for Pot
    colour
      Extra inputs are not permitted [type=extra_forbidden, input_value='red', input_type=str]...
    """

    model_config = ConfigDict(
        extra="forbid", strict=True, validate_default=True, frozen=True, defer_build=True
    )

    @classmethod
    def parse(cls, data: Mapping[str, Any], where: str = ""):
        """Validate ``data``; a problem raises :class:`~growsim.errors.ConfigError` with
        one line naming its key path, prefixed by ``where`` (e.g. ``"objective[0]."``).

        Examples
        --------
        >>> from pydantic import Field
        >>> class Pot(Options):
        ...     size: float = Field(1.0, gt=0, description="pot size")
        >>> Pot.parse({"size": -1}, where="pot.")
        Traceback (most recent call last):
        ...
        growsim.errors.ConfigError: pot.size: Input should be greater than 0 (got -1)
        """
        try:
            return cls.model_validate(dict(data))
        except ValidationError as exc:
            raise ConfigError(validation_message(exc, where, cls)) from None


def key_path(loc: Sequence[Any]) -> str:
    """``("objective", 0, "weight")`` -> ``"objective[0].weight"``.

    Examples
    --------
    >>> key_path(["ga", "population"]), key_path(["objective", 1, "kind"])
    ('ga.population', 'objective[1].kind')
    """
    out = ""
    for part in loc:
        if isinstance(part, int):
            out += f"[{part}]"
        else:
            out += ("." if out else "") + str(part)
    return out or "(top level)"


def fields_of(cls) -> dict[str, Any]:
    """The fields of a pydantic model or pydantic dataclass (empty for anything else).

    Examples
    --------
    >>> list(fields_of(Options))
    []
    """
    return getattr(cls, "__pydantic_fields__", None) or {}


def option_classes(annotation) -> list[type]:
    """The options classes an annotation holds (``X``, ``X | None``, ``list[A | B]``...).

    Examples
    --------
    >>> class Pot(Options):
    ...     size: float = 1.0
    >>> option_classes(list[Pot] | None) == [Pot]
    True
    """
    out, stack = [], [annotation]
    while stack:
        cand = stack.pop()
        if isinstance(cand, type) and fields_of(cand):
            out.append(cand)
        else:
            stack.extend(get_args(cand))
    return out


def _kind_tags(cls: type[BaseModel]) -> tuple:
    kind = fields_of(cls).get("kind")
    return get_args(kind.annotation) if kind is not None else ()


def _model_at(root: type[BaseModel], loc: Sequence[Any]) -> type[BaseModel] | None:
    """The options class at the raw pydantic location ``loc`` under ``root`` (for
    'unknown key' messages); a discriminated union's tag in ``loc`` picks its member."""
    cands = _candidates(root, loc)
    return cands[0] if len(cands) == 1 else None


def _candidates(root: type[BaseModel], loc: Sequence[Any]) -> list[type[BaseModel]]:
    cands = [root]
    for part in loc:
        if isinstance(part, int):
            continue
        tagged = [c for c in cands if part in _kind_tags(c)]
        if tagged and not any(part in fields_of(c) for c in cands):
            cands = tagged
            continue
        holder = next((c for c in cands if part in fields_of(c)), None)
        if holder is None:
            return []
        cands = option_classes(fields_of(holder)[part].annotation)
    return cands


def _is_tag(root: type[BaseModel], loc: Sequence[Any], i: int) -> bool:
    """Whether ``loc[i]`` is a tag pydantic inserted (not a key the user wrote)."""
    part = loc[i]
    if not isinstance(part, str) or i == 0 or not isinstance(loc[i - 1], int):
        return False
    cands = _candidates(root, loc[:i])
    return len(cands) > 1 and any(part in _kind_tags(c) for c in cands)


_UNION_TAGS = {"bool", "int", "float", "str", "list", "dict", "none"}


def _clean_loc(loc: Sequence[Any], root: type[BaseModel]) -> list[Any]:
    """Drop what pydantic inserts into a location: union branches (``...f.int``) and the
    tag of a discriminated union (``objective.0.light.wood_cost``)."""
    out: list[Any] = []
    for i, part in enumerate(loc):
        if isinstance(part, str) and (
            "[" in part or part in _UNION_TAGS or part.startswith("function-")
        ):
            continue
        if _is_tag(root, loc, i):
            continue
        out.append(part)
    return out


def validation_message(exc: ValidationError, where: str = "", root=None) -> str:
    """One line naming the key path of the first problem of a pydantic error (and how
    many more there are): unknown keys list the allowed ones.

    Examples
    --------
    >>> from pydantic import Field
    >>> class Pot(Options):
    ...     size: float = 1.0
    >>> try:
    ...     Pot.model_validate({"colour": "red"})
    ... except Exception as exc:
    ...     validation_message(exc, "pot.", Pot)
    'pot.colour: unknown key; allowed: size'
    """
    root = root or BaseModel
    errors = exc.errors(include_url=False)
    if not errors:  # pragma: no cover - pydantic always lists one
        return where.rstrip(".") or "invalid"
    first = errors[0]
    loc = _clean_loc(first["loc"], root)
    kind = first["type"]
    path = where + key_path(loc) if loc else where.rstrip(".")
    if not loc and kind == "value_error":  # a rule between keys: its message names them
        text = first["msg"].removeprefix("Value error, ")
        msg = f"{path}: {text}" if path else text
    elif kind in ("extra_forbidden", "unexpected_keyword_argument"):
        holder = _model_at(root, first["loc"][:-1]) if root is not BaseModel else None
        allowed = list(fields_of(holder)) if holder is not None else None
        msg = f"{path}: unknown key" + (f"; allowed: {', '.join(allowed)}" if allowed else "")
    elif kind in ("missing", "union_tag_not_found"):
        if kind == "union_tag_not_found":
            path += "." + first.get("ctx", {}).get("discriminator", "kind").strip("'")
        msg = f"{path}: required key missing"
    elif kind == "union_tag_invalid":
        ctx = first.get("ctx", {})
        what = next((p for p in reversed(loc) if isinstance(p, str)), "value")
        tags = sorted(t.strip().strip("'") for t in str(ctx.get("expected_tags", "")).split(","))
        msg = (
            f"{path}.{ctx.get('discriminator', 'kind').strip(chr(39))}: unknown {what} "
            f"{ctx.get('tag')!r}; available: {', '.join(tags)}"
        )
    else:
        text = re.sub(r" or instance of \w+", "", first["msg"].removeprefix("Value error, "))
        same = [e for e in errors if _clean_loc(e["loc"], root) == loc]
        tags = {e["loc"][-1] for e in same if len(e["loc"]) > len(loc)}
        if len(same) > 1 and tags == {"int", "float"}:  # the int | float of model.params
            text = "expected a number"
        got = first.get("input")
        got_s = repr(got)
        if len(got_s) > 60:
            got_s = got_s[:57] + "..."
        shown = isinstance(got, dict) or "got " in text or type(got).__name__ == "ArgsKwargs"
        msg = f"{path}: {text}" + ("" if shown else f" (got {got_s})")
    n_more = len({tuple(_clean_loc(e["loc"], root)) for e in errors} - {tuple(loc)})
    if n_more:
        msg += f" (and {n_more} more problem{'s' if n_more > 1 else ''})"
    return msg
