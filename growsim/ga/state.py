"""Everything a GA run changes, in one dataclass, :class:`GAState`, which is also the
checkpoint: :meth:`GAState.save` and :meth:`GAState.load` walk its fields, so a new field
is saved and restored without being listed anywhere else.

Each field's ``metadata["store"]`` says how it is saved in the ``.npz`` checkpoint:
``"json"`` (the default) in the JSON ``meta`` entry, ``"rng"`` as the generator's state
there, ``"array"`` as an optional array, ``"arrays"`` as a list of optional arrays (one
per island), and ``None`` for the transient ask/tell hand-over, which is never saved (a
state with a pending generation refuses to be saved).
"""

from __future__ import annotations

import json
from dataclasses import MISSING, dataclass, field, fields
from pathlib import Path

import numpy as np

from growsim.errors import GrowsimError, UserInputError
from growsim.files import atomic_write, json_default

__all__ = ["CHECKPOINT_VERSION", "GAState", "Pending"]

#: version of the checkpoint layout; 2: the fields of :class:`GAState`, walked
CHECKPOINT_VERSION = 2


def _store(kind: str | None) -> dict:
    return {"store": kind}


@dataclass
class Pending:
    """A generation handed out by ``ask()`` and not yet told: ``raw`` ``(m, L)`` all
    islands' genomes, ``islands`` one ``(kind, strategies, count)`` per island (``kind``
    is ``"init"``, ``"reinit"`` or ``"breed"``), ``started`` the ``perf_counter`` at ask.

    Examples
    --------
    >>> import numpy as np
    >>> Pending(np.zeros((2, 3)), [("init", None, 2)], 0.0).raw.shape
    (2, 3)
    """

    raw: np.ndarray
    islands: list[tuple[str, np.ndarray | None, int]]
    started: float


@dataclass
class GAState:
    """The mutable state of a :class:`growsim.ga.GA`: counters, per-island populations,
    the best-so-far, the history rows and the random generator.

    ``pops[i]`` ``(n, L)`` raw genomes of island ``i`` (None before generation 0),
    ``scores[i]`` ``(n,)`` their scores (larger is better, ``-inf`` failed),
    ``strategies[i]`` ``(n,)`` self-adaptive mutation strategies (or None), ``reinit[i]``
    True when island ``i`` is re-created at its next ask (extinction). ``best_score`` is
    in the same larger-is-better orientation; ``best_raw`` ``(L,)`` and ``best_params``
    ``(p,)`` are the best genome and its decoded parameters.

    The polish's progress (None before it starts): ``polish_x0`` ``(p,)`` and
    ``polish_score0``, where it started, and ``polish_scores`` the scores of every
    candidate it has been told so far, in order (its input log: the polish is a function
    of these and of its own seed, so :func:`~growsim.ga.polish.polish_best` resumes it by
    replaying them without evaluating anything).

    Examples
    --------
    >>> import numpy as np, tempfile, pathlib
    >>> s = GAState.new(islands=2, rng=np.random.default_rng(0))
    >>> s.generation, s.pops, s.best_score
    (0, [None, None], -inf)
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "ck.npz"
    >>> s.save(path, {"seed": 0}, polished=False)
    >>> t, extra = GAState.load(path, {"seed": 0})
    >>> t.pops, extra, t.rng.random() == s.rng.random()
    ([None, None], {'polished': False}, True)
    >>> GAState.load(path, {"seed": 1})  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    growsim.errors.UserInputError: checkpoint ... set-up (differs in: seed)
    """

    rng: np.random.Generator = field(metadata=_store("rng"))
    generation: int = 0
    evaluations: int = 0
    pops: list[np.ndarray | None] = field(default_factory=list, metadata=_store("arrays"))
    scores: list[np.ndarray | None] = field(default_factory=list, metadata=_store("arrays"))
    strategies: list[np.ndarray | None] = field(default_factory=list, metadata=_store("arrays"))
    reinit: list[bool] = field(default_factory=list)
    best_score: float = -np.inf
    best_raw: np.ndarray | None = field(default=None, metadata=_store("array"))
    best_params: np.ndarray | None = field(default=None, metadata=_store("array"))
    best_generation: int = -1
    stagnant: int = 0
    rows: list[dict] = field(default_factory=list)
    elapsed: float = 0.0
    polish_x0: np.ndarray | None = field(default=None, metadata=_store("array"))
    polish_score0: float | None = None
    polish_scores: np.ndarray | None = field(default=None, metadata=_store("array"))
    pending: Pending | None = field(default=None, metadata=_store(None))

    @classmethod
    def new(cls, islands: int, rng: np.random.Generator) -> GAState:
        """The state before generation 0 of a run with ``islands`` islands."""
        return cls(
            rng=rng,
            pops=[None] * islands,
            scores=[None] * islands,
            strategies=[None] * islands,
            reinit=[False] * islands,
        )

    def set_best(self, score: float, raw: np.ndarray, params: np.ndarray, generation: int):
        """Make ``raw`` / ``params`` (score ``score``, found in ``generation``) the
        best-so-far."""
        self.best_score = float(score)
        self.best_raw = raw
        self.best_params = params
        self.best_generation = generation

    def reached(self, target: float | None, sign: float) -> bool:
        """Whether the best-so-far, in the fitness's own orientation (``best_score *
        sign``), has reached ``target`` (``>=`` when ``sign`` is 1, ``<=`` when -1).

        Examples
        --------
        >>> import numpy as np
        >>> s = GAState.new(1, np.random.default_rng(0))
        >>> s.set_best(-0.01, np.zeros(1), np.zeros(1), generation=3)  # minimising: 0.01
        >>> s.reached(0.1, sign=-1.0), s.reached(0.001, sign=-1.0), s.reached(None, -1.0)
        (True, False, False)
        """
        if target is None or self.best_raw is None:
            return False
        b = self.best_score * sign
        return b >= target if sign > 0 else b <= target

    # -- checkpoint -------------------------------------------------------------------
    def save(self, path, fingerprint: dict, **extra) -> None:
        """Write the state to ``path`` (``.npz``) atomically, with the set-up's
        ``fingerprint`` (checked by :meth:`load`) and ``extra`` JSON-able info."""
        if self.pending is not None:
            raise GrowsimError("save_checkpoint: a generation was asked but not told")
        meta = {"version": CHECKPOINT_VERSION, "fingerprint": fingerprint, "extra": extra}
        arrays = {}
        for f in fields(self):
            kind, value = f.metadata.get("store", "json"), getattr(self, f.name)
            if kind == "json":
                meta[f.name] = value
            elif kind == "rng":
                meta[f.name] = value.bit_generator.state
            elif kind == "array" and value is not None:
                arrays[f.name] = value
            elif kind == "arrays":
                meta[f.name] = len(value)
                arrays.update({f"{f.name}.{i}": a for i, a in enumerate(value) if a is not None})
        arrays["meta"] = np.array(json.dumps(meta, default=json_default))
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        atomic_write(path, lambda fh: np.savez(fh, **arrays))

    @classmethod
    def load(cls, path, fingerprint: dict) -> tuple[GAState, dict]:
        """The state saved in ``path`` and its ``extra`` info; :class:`UserInputError`
        if the file is unreadable, of another version or of another ``fingerprint``."""
        path = Path(path)
        try:
            with np.load(path, allow_pickle=False) as z:
                data = {k: z[k] for k in z.files}
            meta = json.loads(str(data["meta"]))
        except (OSError, ValueError, KeyError) as e:
            raise UserInputError(f"checkpoint {path}: unreadable ({e})") from None
        if meta.get("version") != CHECKPOINT_VERSION:
            raise UserInputError(f"checkpoint {path}: unknown version {meta.get('version')}")
        mine = json.loads(json.dumps(fingerprint, default=json_default))
        theirs = meta.get("fingerprint") or {}
        if theirs != mine:
            diff = [k for k in mine if theirs.get(k) != mine[k]]
            raise UserInputError(
                f"checkpoint {path} was written by a different GA set-up "
                f"(differs in: {', '.join(diff)})"
            )
        values = {}
        try:
            for f in fields(cls):
                kind = f.metadata.get("store", "json")
                if kind == "json":
                    if f.name in meta or f.default is MISSING:
                        values[f.name] = meta[f.name]
                    # else: a field newer than the file (the polish's), at its default
                elif kind == "rng":
                    st = meta[f.name]
                    rng = np.random.Generator(getattr(np.random, st["bit_generator"])())
                    rng.bit_generator.state = st
                    values[f.name] = rng
                elif kind == "array":
                    values[f.name] = data.get(f.name)
                elif kind == "arrays":
                    values[f.name] = [data.get(f"{f.name}.{i}") for i in range(meta[f.name])]
            extra = meta["extra"]
        except (KeyError, TypeError, ValueError, AttributeError) as e:
            raise UserInputError(f"checkpoint {path}: unreadable ({e!r})") from None
        return cls(**values), extra
