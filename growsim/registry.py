"""One registry helper for every kind of named plug-in: models, objectives, phenotypes,
GA operators and generation models.

A :class:`Registry` maps a name to an entry. An entry is given either as the object
itself or as a ``"module:attribute"`` string imported on first use (so listing the models
does not import numba kernels). Looking up a name that is not registered raises
:class:`growsim.errors.UserInputError` naming the kind and the names available: the one
place that message is written.
"""

from __future__ import annotations

import importlib
from collections.abc import Iterator, Mapping
from typing import Any, Generic, TypeVar

from growsim.errors import UserInputError

__all__ = ["Registry"]

T = TypeVar("T")


class Registry(Mapping[str, T], Generic[T]):
    """Name -> entry, with lazy ``"module:attribute"`` entries and one error message.

    A read-only :class:`~collections.abc.Mapping` (``name in reg``, ``sorted(reg)``,
    ``reg[name]``) plus :meth:`register` and :meth:`get`, which raises
    :class:`~growsim.errors.UserInputError` for an unknown name.

    Examples
    --------
    >>> reg = Registry("colour", {"red": "colorsys:rgb_to_hsv"})
    >>> reg.register("answer", 42)
    >>> sorted(reg), reg["answer"], reg.get("red").__name__
    (['answer', 'red'], 42, 'rgb_to_hsv')
    >>> reg.get("blue")
    Traceback (most recent call last):
    ...
    growsim.errors.UserInputError: unknown colour 'blue'; available: answer, red
    """

    def __init__(self, kind: str, entries: Mapping[str, Any] | None = None):
        self.kind = kind
        self._entries: dict[str, Any] = {}
        for name, entry in (entries or {}).items():
            self.register(name, entry)

    def register(self, name: str, entry: Any) -> None:
        """Add ``entry`` (an object, or a ``"module:attribute"`` string) under ``name``."""
        if not isinstance(name, str) or not name:
            raise ValueError(f"{self.kind} registry: a name must be a non-empty string")
        self._entries[name] = entry

    def get(self, name: str) -> T:  # type: ignore[override]
        """The entry registered as ``name``; :class:`UserInputError` if there is none."""
        try:
            entry = self._entries[name]
        except (KeyError, TypeError):
            raise UserInputError(
                f"unknown {self.kind} {name!r}; available: {', '.join(sorted(self._entries))}"
            ) from None
        if isinstance(entry, str) and ":" in entry:
            module, attr = entry.split(":", 1)
            entry = getattr(importlib.import_module(module), attr)
            self._entries[name] = entry
        return entry

    def __getitem__(self, name: str) -> T:
        if name not in self._entries:
            raise KeyError(name)
        return self.get(name)

    def __iter__(self) -> Iterator[str]:
        return iter(self._entries)

    def __len__(self) -> int:
        return len(self._entries)

    def __contains__(self, name: object) -> bool:
        return name in self._entries

    def __repr__(self) -> str:
        return f"Registry({self.kind!r}: {', '.join(self._entries)})"
