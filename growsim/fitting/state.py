"""A fit's saved state in its ``--out``: :class:`FitState`, what ``--resume`` reads.

One directory holds one fit (:func:`check_fresh`). The state (:data:`FIT_STATE`, JSON)
keeps the fit's options (:class:`~growsim.fitting.options.FitOptions`, the pictures'
paths absolute), the stages of the fit finished (:data:`STAGES`) and, once the fits at
the first size are judged, what they decided (:class:`Decision`: which runs go on). Each
run keeps its own finished searches beside its results
(:data:`~growsim.fitting.runs.RUN_STATE`). The state has a ``version``
(:data:`STATE_VERSION`); a state written before versions (version 1: ``options`` and
``decided`` only) is read as one, a newer one is refused with a message saying so.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated, Any, Literal

from pydantic import Field, Strict, ValidationError

from growsim.errors import UserInputError
from growsim.files import atomic_write, jsonable
from growsim.fitting.options import FitOptions
from growsim.options import Options, validation_message

__all__ = [
    "FIT_STATE",
    "RECONSTRUCTION_STAGES",
    "STAGES",
    "STATE_VERSION",
    "Decision",
    "FitState",
    "check_fresh",
]

#: a fit's state in its ``--out``: the options it was started with (``--resume``)
FIT_STATE = "fit-state.json"

#: the version of :class:`FitState` written; 1: the state as written before it had one
STATE_VERSION = 2

#: the stages of a fit, in order (:mod:`growsim.fitting.stages`): what kind of picture and
#: which models; the silhouettes; the searches; the fitted tree grown; judged against the
#: pictures; the files written
STAGES = ("choose", "segment", "search", "grow", "judge", "write")

#: the stages of a reconstruction: the same, the tree reconstructed instead of searched
RECONSTRUCTION_STAGES = ("choose", "segment", "reconstruct", "grow", "judge", "write")


class Decision(Options):
    """What the fits at the first size decided (kept in the state, so a resumed fit carries
    the same runs on)."""

    first_size: dict[str, dict[str, float]] = Field(
        description="each run's binary NCC and score at the end of the first size, by label"
    )
    judged: dict[str, float] = Field(
        description="the score of the best run of each model and kind ('honda/bare'), judged "
        "at its model's final size"
    )
    kept: tuple[str, str] = Field(
        strict=False, description="the kept model and leaves mode ('bare', 'fit', 'keep')"
    )
    carried: list[Annotated[tuple[str, str, int], Strict(False)]] = Field(
        strict=False,
        description="the runs (model, leaves mode, seed) carried on to the finer sizes",
    )


class FitState(Options):
    """The state of a fit in its directory: its ``options``, the stages ``finished`` and
    the first size's ``decided`` runs. :meth:`read` reads it for ``--resume`` (an older
    version read as the new one), :meth:`write` writes it.

    Examples
    --------
    >>> s = FitState(options=FitOptions(front="/pics/tree.jpg"), finished=["choose"])
    >>> s.version, s.decided, s.finished
    (2, None, ['choose'])
    >>> s.done("segment").finished
    ['choose', 'segment']
    """

    version: int = Field(STATE_VERSION, description="the version of this state's form")
    options: FitOptions = Field(description="the options the fit was started with")
    finished: list[Literal[(*STAGES, "reconstruct")]] = Field(  # type: ignore[valid-type]
        default_factory=list, description="the stages of the fit finished, in order"
    )
    decided: Decision | None = Field(
        None, description="what the first size's fits decided; None: not yet judged"
    )

    def updated(self, **fields) -> FitState:
        """A copy with ``fields`` replaced, validated.

        Examples
        --------
        >>> s = FitState(options=FitOptions(front="t.png"))
        >>> d = {"first_size": {}, "judged": {"honda/bare": 0.8}, "kept": ["honda", "bare"],
        ...      "carried": [["honda", "bare", 0]]}
        >>> s.updated(decided=d).decided.carried
        [('honda', 'bare', 0)]
        """
        return FitState.model_validate({**self.model_dump(), **fields})

    def done(self, *stages: str) -> FitState:
        """A copy with ``stages`` finished too.

        Examples
        --------
        >>> FitState(options=FitOptions(front="t.png")).done("choose", "segment").finished
        ['choose', 'segment']
        """
        return self.updated(
            finished=[*self.finished, *(s for s in stages if s not in self.finished)]
        )

    def write(self, out_dir: Path) -> Path:
        """Write the state into the fit's directory ``out_dir`` (:data:`FIT_STATE`,
        atomically); returns its path.

        Examples
        --------
        >>> import tempfile
        >>> d = Path(tempfile.mkdtemp())
        >>> s = FitState(options=FitOptions(front="/pics/tree.jpg"))
        >>> FitState.read(d / "nowhere")  # doctest: +ELLIPSIS
        Traceback (most recent call last):
        ...
        growsim.errors.UserInputError: ...: no fit to resume here (no fit-state.json)
        >>> FitState.read(s.write(d).parent) == s
        True
        """
        text = json.dumps(jsonable(self.model_dump()), indent=1)
        return atomic_write(Path(out_dir) / FIT_STATE, text)

    @classmethod
    def read(cls, out_dir: Path) -> FitState:
        """The state of the fit in ``out_dir``, to resume it; refused (a
        :class:`~growsim.errors.UserInputError` saying why) when there is none, the fit
        finished, or the state cannot be read (a newer version, options no longer valid).
        A state of version 1 (written before states had a version) is read as this one.

        Examples
        --------
        >>> import tempfile
        >>> d = Path(tempfile.mkdtemp())
        >>> old = {"options": {"front": "/pics/tree.jpg", "model": "honda", "sizes": [32, 64]}}
        >>> _ = (d / FIT_STATE).write_text(json.dumps(old))
        >>> s = FitState.read(d)
        >>> s.version, s.options.model, s.options.sizes, s.finished
        (2, 'honda', [32, 64], ['choose', 'segment'])
        >>> _ = (d / FIT_STATE).write_text(json.dumps({"version": 9, **old}))
        >>> FitState.read(d)  # doctest: +ELLIPSIS
        Traceback (most recent call last):
        ...
        growsim.errors.UserInputError: ...: a fit state of version 9; this growsim reads ...
        """
        out_dir = Path(out_dir)
        path = out_dir / FIT_STATE
        if (out_dir / "fit.json").is_file():
            raise UserInputError(f"{out_dir}: this fit is finished (fit.json); nothing to resume")
        if not path.is_file():
            raise UserInputError(f"{out_dir}: no fit to resume here (no {FIT_STATE})")
        try:
            data = json.loads(path.read_text())
        except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
            raise UserInputError(f"{path}: not a fit's state ({exc})") from None
        if not isinstance(data, dict) or not isinstance(data.get("options"), dict):
            raise UserInputError(f"{path}: not a fit's state (no options)")
        version = data.get("version", 1)
        if version == 1:
            data = _from_version_1(data)
        elif version != STATE_VERSION:
            raise UserInputError(
                f"{path}: a fit state of version {version!r}; this growsim reads versions 1 to "
                f"{STATE_VERSION}: resume it with the growsim that started it, or fit again "
                "into a new --out"
            )
        where = f"{path}: cannot resume it"
        options = FitOptions.parse(data["options"], where=f"{where}, its options: ")
        try:
            return cls.model_validate({**data, "options": options})
        except ValidationError as exc:  # a damaged state: say where
            raise UserInputError(f"{where}: {validation_message(exc, '', cls)}") from None


def _from_version_1(data: dict[str, Any]) -> dict[str, Any]:
    """A state as written before states had a version (``options``: the fit's 24 options
    under their names, ``decided`` once judged) in the form of :class:`FitState`."""
    out = {"version": STATE_VERSION, "options": data["options"], "finished": ["choose", "segment"]}
    if data.get("decided") is not None:
        out["decided"] = data["decided"]
    return out


def check_fresh(out_dir: Path) -> None:
    """Refuse an ``--out`` that holds anything: one directory, one fit (an interrupted fit
    there: the refusal says how to go on with it).

    Examples
    --------
    >>> import tempfile
    >>> d = Path(tempfile.mkdtemp())
    >>> check_fresh(d / "new")
    >>> _ = (d / "notes.txt").write_text("")
    >>> check_fresh(d)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    growsim.errors.UserInputError: ... already holds files (notes.txt); a fit needs a new --out
    """
    if out_dir.exists() and (not out_dir.is_dir() or any(out_dir.iterdir())):
        held = sorted(p.name + ("/" if p.is_dir() else "") for p in out_dir.iterdir())
        shown = ", ".join(held[:4]) + (", ..." if len(held) > 4 else "")
        hint = (f"continue it with: growsim fit-image --resume {out_dir}; "
                if (out_dir / FIT_STATE).is_file() and not (out_dir / "fit.json").is_file()
                else "")  # fmt: skip
        raise UserInputError(
            f"{out_dir} already holds files ({shown}); {hint}a fit needs a new --out"
        )
