"""Genome codings: how a population array (the "raw" genomes) maps to parameter arrays.

Two raw representations, chosen by the fields:

- **real genomes** (only :class:`Real`, :class:`Integer`, :class:`Categorical` fields): raw
  is a ``(n, p)`` float64 array with one column per decoded value. Reals are stored as is;
  an integer field with values ``low..high`` is stored as a real in ``[low, high + 1)``
  and decoded by ``floor``; a categorical with ``k`` choices as a real in ``[0, k)``
  decoded to its index. Real-valued operators therefore work on every column.
- **bit genomes** (any :class:`Bits` field; integers and categoricals may join them, coded
  with the fewest bits): raw is a ``(n, L)`` uint8 array of 0/1, one byte per bit. One
  byte per bit (not packed) keeps every operator a simple loop; the numba kernels stream
  a 1000 x 1000 population in well under a millisecond, which measured faster than
  packing and unpacking around each NumPy-level step. ``diploid=True`` doubles ``L``:
  two chromosomes side by side, phenotype = bitwise OR (after Kuwahara et al., "Fitting a
  3D fractal tree to front/side tree images with a GA", ATR TR-C-0135).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from growsim.errors import UserInputError
from growsim.ga.history import std
from growsim.kernels import ga as K

__all__ = [
    "OKUSA_WEIGHTS",
    "Bits",
    "Categorical",
    "Genome",
    "Integer",
    "ParamLike",
    "Real",
    "genome_from_params",
]

#: per-bit weights of Okusa's fish genes (sum 100): "GA-tuned path control of a fish agent"
OKUSA_WEIGHTS = (1, 5, 17, 26, 24, 16, 9, 2)

_CODINGS = {
    "binary": K.CODE_BINARY,
    "gray": K.CODE_GRAY,
    "weighted": K.CODE_WEIGHTED,
    "fraction": K.CODE_FRACTION,
}


def _check_name(name) -> str:
    if not isinstance(name, str) or not name:
        raise UserInputError(f"genome field name must be a non-empty string, got {name!r}")
    return name


def _check_size(name, size) -> int:
    if isinstance(size, bool) or not isinstance(size, (int, np.integer)) or size < 1:
        raise UserInputError(f"genome field {name!r}: size must be an integer >= 1, got {size!r}")
    return int(size)


def _check_range(name, low, high) -> tuple[float, float]:
    try:
        lo, hi = float(low), float(high)
    except (TypeError, ValueError):
        raise UserInputError(
            f"genome field {name!r}: bounds must be numbers, got {low!r}, {high!r}"
        ) from None
    if not (np.isfinite(lo) and np.isfinite(hi)) or not lo < hi:
        raise UserInputError(
            f"genome field {name!r}: need finite low < high, got [{low!r}, {high!r}]"
        )
    return lo, hi


def _check_bounded(field, integer: bool) -> None:
    """Check the ``name``, ``low``, ``high`` and ``size`` of a :class:`Real`, :class:`Bits`
    or (``integer``) :class:`Integer` field and store them normalised: float bounds, or int
    bounds (which must be whole numbers), and an int size."""
    _check_name(field.name)
    lo, hi = _check_range(field.name, field.low, field.high)
    if integer:
        if lo != round(lo) or hi != round(hi):
            raise UserInputError(f"genome field {field.name!r}: integer bounds must be integers")
        lo, hi = int(lo), int(hi)
    object.__setattr__(field, "low", lo)
    object.__setattr__(field, "high", hi)
    object.__setattr__(field, "size", _check_size(field.name, field.size))


@dataclass(frozen=True)
class _Bounded:
    """The fields and checks :class:`Real` and :class:`Integer` share: ``size`` values in
    ``[low, high]``; ``_integer`` (a class attribute) asks for whole-number bounds, stored
    as ints."""

    name: str
    low: float
    high: float
    size: int = 1
    _integer = False

    def __post_init__(self):
        _check_bounded(self, self._integer)


@dataclass(frozen=True)
class Real(_Bounded):
    """A real field: ``size`` values in ``[low, high]``.

    Examples
    --------
    >>> Real("x", -5.12, 5.12, size=3).size
    3
    """


@dataclass(frozen=True)
class Integer(_Bounded):
    """An integer field: ``size`` values in ``low..high`` (both included; ``low``, ``high``
    are stored as ints).

    Examples
    --------
    >>> Integer("n", 1, 9).high
    9
    """

    _integer = True


@dataclass(frozen=True)
class Categorical:
    """A categorical field: ``size`` choices among ``choices``; decoded to the index.

    Examples
    --------
    >>> Categorical("colour", ("red", "green", "blue", "grey")).k
    4
    """

    name: str
    choices: tuple
    size: int = 1

    def __post_init__(self):
        _check_name(self.name)
        choices = tuple(self.choices) if not isinstance(self.choices, str) else ()
        if len(choices) < 2:
            raise UserInputError(
                f"genome field {self.name!r}: a categorical needs at least 2 choices"
            )
        object.__setattr__(self, "choices", choices)
        object.__setattr__(self, "size", _check_size(self.name, self.size))

    @property
    def k(self) -> int:
        """Number of choices."""
        return len(self.choices)


@dataclass(frozen=True)
class Bits:
    """A bit-coded field: ``size`` values of ``bits`` bits each, mapped into ``[low, high]``.

    Codings (``v`` the integer the bits spell, most significant bit first):

    - ``"binary"``: ``low + v / (2**bits - 1) * (high - low)``;
    - ``"gray"``: the same after Gray -> binary, so neighbouring values differ by one bit;
    - ``"fraction"``: ``low + v / 2**bits * (high - low)`` (Kuwahara et al.'s 7-bit genes,
      value / 128: ``high`` itself is never reached);
    - ``"weighted"``: ``low + sum(w_i b_i) / sum(w) * (high - low)``; the default weights
      are Okusa's 1, 5, 17, 26, 24, 16, 9, 2 (8 bits, sums 0..100, all but 4, 13, 87, 96),
      which spread each bit's influence more evenly than powers of two.

    Examples
    --------
    >>> Bits("speed", 5, 45, coding="weighted").weights
    (1.0, 5.0, 17.0, 26.0, 24.0, 16.0, 9.0, 2.0)
    >>> Bits("s", 0.1, 0.7, bits=7, coding="fraction").bits
    7
    """

    name: str
    low: float
    high: float
    bits: int = 8
    size: int = 1
    coding: str = "binary"
    weights: tuple | None = None

    def __post_init__(self):
        _check_bounded(self, integer=False)
        if self.coding not in _CODINGS:
            raise UserInputError(
                f"genome field {self.name!r}: unknown coding {self.coding!r}; "
                f"allowed: {', '.join(_CODINGS)}"
            )
        weights = self.weights
        if self.coding == "weighted" and weights is None:
            weights = OKUSA_WEIGHTS
        if weights is not None:
            if self.coding != "weighted":
                raise UserInputError(f"genome field {self.name!r}: weights need coding='weighted'")
            w = tuple(float(x) for x in weights)
            if not w or any(not np.isfinite(x) or x < 0 for x in w) or sum(w) <= 0:
                raise UserInputError(
                    f"genome field {self.name!r}: weights must be >= 0 with a positive sum"
                )
            object.__setattr__(self, "weights", w)
            object.__setattr__(self, "bits", len(w))
        b = self.bits
        if isinstance(b, bool) or not isinstance(b, (int, np.integer)) or not 1 <= b <= 52:
            raise UserInputError(
                f"genome field {self.name!r}: bits must be an integer in 1..52, got {b!r}"
            )
        object.__setattr__(self, "bits", int(b))


Field = Real | Integer | Categorical | Bits


@dataclass(frozen=True)
class _Column:
    """Internal: one decoded column and where it lives in the raw genome."""

    name: str
    field: Field
    offset: int  # raw column (real) or first bit (bits)
    nbits: int  # 0 for real genomes
    code: int
    low: float  # decoded lower bound
    high: float  # decoded upper bound
    k: int  # number of values for integer / categorical, else 0


class Genome:
    """An ordered list of fields: decodes and encodes whole populations at once.

    Parameters
    ----------
    fields : sequence of :class:`Real`, :class:`Integer`, :class:`Categorical`, :class:`Bits`
        Decoded columns follow the fields' order; a field of ``size > 1`` gives columns
        ``"name[0]"``, ``"name[1]"``, ...
    diploid : bool
        Bit genomes only: two chromosomes per individual, phenotype = bitwise OR.

    Attributes
    ----------
    kind : ``"real"`` or ``"bits"``
    names : list of str, ``(p,)`` decoded column names
    n_params : int, ``p``
    length : int, raw columns (``p`` for real genomes, total bits ``L`` for bit genomes,
        doubled when diploid)
    low, high : ``(length,)`` float64 raw bounds used by the operators (bits: 0 and 1)
    param_low, param_high : ``(p,)`` float64 decoded bounds

    Examples
    --------
    >>> import numpy as np
    >>> g = Genome([Real("x", -5.12, 5.12, size=2), Integer("n", 1, 3)])
    >>> g.names
    ['x[0]', 'x[1]', 'n']
    >>> raw = g.random(4, np.random.default_rng(0))
    >>> g.decode(raw).shape
    (4, 3)
    >>> b = Genome([Bits("a", 0, 1, bits=4, size=2, coding="gray")])
    >>> b.length, b.kind
    (8, 'bits')
    """

    def __init__(self, fields: Sequence[Field], diploid: bool = False):
        fields = list(fields)
        if not fields:
            raise UserInputError("a genome needs at least one field")
        for f in fields:
            if not isinstance(f, (Real, Integer, Categorical, Bits)):
                raise UserInputError(
                    f"genome fields must be Real, Integer, Categorical or Bits, got {f!r}"
                )
        seen = set()
        for f in fields:
            if f.name in seen:
                raise UserInputError(f"genome field {f.name!r} appears twice")
            seen.add(f.name)
        has_bits = any(isinstance(f, Bits) for f in fields)
        reals = [f.name for f in fields if isinstance(f, Real)]
        if has_bits and reals:
            raise UserInputError(
                f"genome mixes Real fields ({', '.join(reals)}) with Bits fields: "
                "code them all as Bits, or all as Real/Integer/Categorical"
            )
        if diploid and not has_bits:
            raise UserInputError("diploid=True needs a bit genome (Bits fields)")
        self.fields = tuple(fields)
        self.kind = "bits" if has_bits else "real"
        self.diploid = bool(diploid)
        cols: list[_Column] = []
        pos = 0
        for f in fields:
            for e in range(f.size):
                name = f.name if f.size == 1 else f"{f.name}[{e}]"
                if isinstance(f, Real):
                    cols.append(_Column(name, f, pos, 0, -1, f.low, f.high, 0))
                    pos += 1
                elif isinstance(f, (Integer, Categorical)):
                    kv = (f.high - f.low + 1) if isinstance(f, Integer) else f.k
                    lo = float(f.low) if isinstance(f, Integer) else 0.0
                    nb = max(1, math.ceil(math.log2(kv))) if has_bits else 0
                    code = K.CODE_INDEX if has_bits else -1
                    cols.append(_Column(name, f, pos, nb, code, lo, lo + kv - 1, kv))
                    pos += nb if has_bits else 1
                else:
                    code = _CODINGS[f.coding]
                    cols.append(_Column(name, f, pos, f.bits, code, f.low, f.high, 0))
                    pos += f.bits
        self._cols = cols
        self.names = [c.name for c in cols]
        self.n_params = len(cols)
        self.param_low = np.array([c.low for c in cols], dtype=np.float64)
        self.param_high = np.array([c.high for c in cols], dtype=np.float64)
        # integer-valued decoded columns (integers, categories)
        self.discrete = np.array([c.k > 0 for c in cols], dtype=bool)
        if self.kind == "real":
            self.n_bits = 0
            self.length = len(cols)
            self.low = self.param_low.copy()
            # integer/categorical raw values live in [low, low + k): floor decodes them
            self.high = np.where(self.discrete, self.param_high + 1.0, self.param_high)
            self.dtype = np.dtype(np.float64)
        else:
            self.n_bits = pos
            self.length = pos * (2 if diploid else 1)
            self.low = np.zeros(self.length)
            self.high = np.ones(self.length)
            self.dtype = np.dtype(np.uint8)
            self._offset = np.array([c.offset for c in cols], dtype=np.int64)
            self._nbits = np.array([c.nbits for c in cols], dtype=np.int64)
            self._code = np.array([c.code for c in cols], dtype=np.int64)
            self._k = np.array([c.k for c in cols], dtype=np.int64)
            self._dlow = np.array([c.low for c in cols], dtype=np.float64)
            self._dhigh = np.array([c.high if c.k == 0 else c.low for c in cols], dtype=np.float64)
            w = np.zeros(pos, dtype=np.float64)
            for c in cols:
                if c.code == K.CODE_WEIGHTED:
                    w[c.offset : c.offset + c.nbits] = c.field.weights
            self._weights = w
            # one-bit columns (e.g. OneMax) decode as low + bit * scale: a 7x faster kernel
            self._unit = bool((self._nbits == 1).all() and (self._code != K.CODE_INDEX).all())
            if self._unit:
                # one bit spells 0 or 1: v / (2**1 - 1) for binary/Gray/weighted, v / 2 for fraction
                full = np.where(self._code == K.CODE_FRACTION, 2.0, 1.0)
                self._unit_scale = (self._dhigh - self._dlow) / full

    def __repr__(self) -> str:
        extra = ", diploid=True" if self.diploid else ""
        return f"Genome({list(self.fields)!r}{extra})"

    # -- populations -------------------------------------------------------------------
    def random(self, n: int, rng: np.random.Generator) -> np.ndarray:
        """A uniformly random raw population ``(n, length)`` (float64 or uint8 bits).

        Examples
        --------
        >>> g = Genome([Bits("b", 0, 1, bits=1, size=5)])
        >>> g.random(2, np.random.default_rng(1)).shape
        (2, 5)
        """
        n = int(n)
        if self.kind == "bits":
            return rng.integers(0, 2, size=(n, self.length), dtype=np.uint8)
        x = rng.uniform(self.low, self.high, size=(n, self.length))
        # uniform() can round up to ``high``; keep raw values strictly inside for floor()
        return np.minimum(x, np.nextafter(self.high, -np.inf))

    def phenotype_bits(self, raw: np.ndarray) -> np.ndarray:
        """The expressed ``(n, n_bits)`` bits: OR of the two chromosomes if diploid."""
        if not self.diploid:
            return raw
        return raw[:, : self.n_bits] | raw[:, self.n_bits :]

    def decode(self, raw: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
        """Raw population ``(n, length)`` -> decoded parameters ``(n, p)`` float64, written
        into ``out`` if given (a C-contiguous ``(n, p)`` float64 array; the GA reuses one
        between generations, which spares a large population's fresh pages).

        Examples
        --------
        >>> g = Genome([Bits("s", 0.1, 0.7, bits=7, coding="fraction")])
        >>> float(g.decode(np.array([[1, 0, 0, 0, 0, 0, 0]], dtype=np.uint8))[0, 0])
        0.4
        """
        raw = self._check_raw(raw)
        shape = (raw.shape[0], self.n_params)
        if out is None or out.shape != shape or out.dtype != np.float64:
            out = np.empty(shape, dtype=np.float64)
        if self.kind == "real":
            np.copyto(out, raw)
            if self.discrete.any():
                d = self.discrete
                out[:, d] = np.clip(np.floor(out[:, d]), self.param_low[d], self.param_high[d])
            return out
        bits = self.phenotype_bits(raw)
        if self._unit:
            K.decode_unit_bits(np.ascontiguousarray(bits), self._dlow, self._unit_scale, out)
            return out
        K.decode_bits(
            np.ascontiguousarray(bits),
            self._offset,
            self._nbits,
            self._code,
            self._dlow,
            self._dhigh,
            self._k,
            self._weights,
            out,
        )
        return out

    def encode(self, params: np.ndarray) -> np.ndarray:
        """Decoded parameters ``(n, p)`` -> raw genomes ``(n, length)``: the nearest
        representable genome (for bits: nearest grid value; diploid: both chromosomes equal).

        Examples
        --------
        >>> g = Genome([Bits("x", 0, 10, bits=4, coding="gray")])
        >>> raw = g.encode(np.array([[4.0]]))
        >>> float(g.decode(raw)[0, 0])
        4.0
        """
        params = np.asarray(params, dtype=np.float64)
        if params.ndim == 1:
            params = params[None, :]
        if params.ndim != 2 or params.shape[1] != self.n_params:
            raise UserInputError(
                f"encode: expected an (n, {self.n_params}) array of "
                f"{', '.join(self.names)}, got shape {params.shape}"
            )
        if not np.isfinite(params).all():
            raise UserInputError("encode: parameters must be finite")
        p = np.clip(params, self.param_low, self.param_high)
        if self.kind == "real":
            out = p.copy()
            if self.discrete.any():
                d = self.discrete
                # the middle of the integer's raw cell [v, v + 1)
                out[:, d] = np.round(p[:, d]) + 0.5
            return out
        n = p.shape[0]
        bits = np.zeros((n, self.n_bits), dtype=np.uint8)
        for j, c in enumerate(self._cols):
            b = c.nbits
            full = 1 << b
            t = (p[:, j] - c.low) / ((c.high - c.low) if c.high > c.low else 1.0)
            if c.code == K.CODE_WEIGHTED:
                table = _weighted_sums(c.field.weights)
                target = t * sum(c.field.weights)
                v = np.abs(table[None, :] - target[:, None]).argmin(axis=1)
            elif c.code == K.CODE_FRACTION:
                v = np.minimum(np.round(t * full), full - 1).astype(np.int64)
            elif c.code == K.CODE_INDEX:
                # smallest integer whose floor(v * k / 2**b) is the wanted index
                idx = np.round(p[:, j] - c.low).astype(np.int64)
                v = -((-idx * full) // c.k)
            else:
                v = np.round(t * (full - 1)).astype(np.int64)
            v = np.asarray(v, dtype=np.int64)
            if c.code == K.CODE_GRAY:
                v = v ^ (v >> 1)
            shifts = np.arange(b - 1, -1, -1, dtype=np.int64)
            bits[:, c.offset : c.offset + b] = (v[:, None] >> shifts) & 1
        if self.diploid:
            bits = np.concatenate([bits, bits], axis=1)
        return bits

    def named(self, params: np.ndarray) -> dict:
        """One decoded row ``(p,)`` -> ``{name: value}`` (categoricals give their choice).

        Examples
        --------
        >>> g = Genome([Real("x", 0, 1), Categorical("c", ("a", "b"))])
        >>> g.named(np.array([0.5, 1.0]))
        {'x': 0.5, 'c': 'b'}
        """
        params = np.asarray(params, dtype=np.float64).reshape(-1)
        out = {}
        for c, v in zip(self._cols, params):
            if isinstance(c.field, Categorical):
                out[c.name] = c.field.choices[round(v)]
            elif isinstance(c.field, Integer):
                out[c.name] = round(v)
            else:
                out[c.name] = float(v)
        return out

    def diversity(self, raw: np.ndarray) -> float:
        """Population diversity in ``[0, 1]``; 0 when every genome is the same.

        Bits: the mean over loci of ``2 q (1 - q)`` (``q`` the share of ones), the expected
        fraction of loci at which two random individuals differ. Reals: the mean over
        columns of the standard deviation divided by the column's range.

        Examples
        --------
        >>> g = Genome([Bits("b", 0, 1, bits=1, size=2)])
        >>> g.diversity(np.array([[0, 1], [1, 1]], dtype=np.uint8))
        0.25
        """
        raw = np.asarray(raw)
        if raw.shape[0] == 0:
            return 0.0
        if self.kind == "bits":
            q = K.ones_per_locus(np.ascontiguousarray(raw)) / raw.shape[0]
            return float(np.mean(2.0 * q * (1.0 - q)))
        x = np.ascontiguousarray(raw, dtype=np.float64)
        return float(np.mean(std(x, axis=0) / (self.high - self.low)))

    def _check_raw(self, raw) -> np.ndarray:
        raw = np.asarray(raw)
        if raw.ndim != 2 or raw.shape[1] != self.length:
            raise UserInputError(
                f"expected a raw population of shape (n, {self.length}), got {raw.shape}"
            )
        if self.kind == "bits" and raw.dtype != np.uint8:
            raw = raw.astype(np.uint8)
        return raw


_WEIGHTED_CACHE: dict[tuple, np.ndarray] = {}


def _weighted_sums(weights: tuple) -> np.ndarray:
    """``(2**b,)`` sums of the weights for every bit pattern (most significant first)."""
    t = _WEIGHTED_CACHE.get(weights)
    if t is None:
        b = len(weights)
        v = np.arange(1 << b, dtype=np.int64)
        shifts = np.arange(b - 1, -1, -1)
        t = (((v[:, None] >> shifts) & 1) * np.asarray(weights)).sum(axis=1)
        _WEIGHTED_CACHE[weights] = t
    return t


class ParamLike(Protocol):
    """What :func:`genome_from_params` reads of a parameter (the GA knows no model:
    :class:`growsim.models.base.Param` is one)."""

    #: the field's name
    name: str
    #: the range ``[low, high]``
    low: float
    high: float
    #: ``"real"`` or ``"int"``
    kind: str


def genome_from_params(
    params: Sequence[ParamLike], coding: str = "real", bits: int = 8, bit_coding: str = "binary"
) -> Genome:
    """A genome for a model's parameter spec (a list of :class:`growsim.models.base.Param`).

    ``coding="real"`` gives :class:`Real` fields (``Integer`` for ``kind="int"``);
    ``coding="bits"`` gives :class:`Bits` fields of ``bits`` bits coded by ``bit_coding``
    (integer params become :class:`Integer` fields coded with the fewest bits).

    Examples
    --------
    >>> from growsim.models.base import Param
    >>> spec = [Param("s", 0.1, 0.7, 0.5), Param("n", 1, 5, 3, kind="int")]
    >>> genome_from_params(spec).names
    ['s', 'n']
    >>> genome_from_params(spec, coding="bits", bits=7, bit_coding="fraction").length
    10
    """
    if coding not in ("real", "bits"):
        raise UserInputError(f"genome coding must be 'real' or 'bits', got {coding!r}")
    fields: list[Field] = []
    for p in params:
        if p.kind == "int":
            fields.append(Integer(p.name, int(p.low), int(p.high)))
        elif coding == "real":
            fields.append(Real(p.name, p.low, p.high))
        else:
            fields.append(Bits(p.name, p.low, p.high, bits=bits, coding=bit_coding))
    return Genome(fields)
