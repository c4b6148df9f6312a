"""2D IFS plants (Liu & Zhang, "IFS and genetic algorithm studying in simulation
of plant", Lanzhou University of Technology, 2011).

A plant is an IFSP code: ``N`` affine maps with probabilities ``{(W_n, p_n)}``, in the
paper's form

    W_n(x, y) = [[r cos(theta), -q sin(phi)], [r sin(theta), q cos(phi)]] (x, y) + (e, f)

(``r``, ``q`` the scales along x and y, ``theta``, ``phi`` their rotations, ``e``, ``f``
the shift), or in the usual ``a b c d e f`` form, ``x' = a x + b y + e``,
``y' = c x + d y + f``. Its phenotype is the attractor drawn by the chaos game
(:class:`growsim.phenotypes.attractor.Attractor`; kernel :mod:`growsim.kernels.ifs2d`).

Parameters (:func:`param_spec`):

- ``n_maps`` (int, 1..12, default 4): ``N``. A map whose weight ``p_k`` is 0 is never
  drawn, so a GA can switch maps off: the number of maps in use varies within ``N``;
- ``form`` (int, 0 or 1): the parameters of each map: 0, the paper's ``r_k, q_k, theta_k,
  phi_k`` (degrees); 1, ``a_k, b_k, c_k, d_k``; then ``e_k, f_k`` and the weight ``p_k``;
- ``iterations`` (default 100,000, as the paper's figure), ``burn_in`` (points dropped
  first, default 100);
- ``contraction`` (default 0.95): the largest singular value a map may have.

Repair (documented in ``docs/models/ifs2d.md``): the weights are normalised
(``p_k / sum p``; all zero: equal); a map whose linear part has a largest singular value
``sigma > contraction`` is scaled by ``contraction / sigma`` (its shift kept), so every map
is a contraction and the chaos game stays bounded. The phenotype records the repaired
code. The chaos game starts at the fixed point of the most probable map, a point of the
attractor, so the burn-in is a safety margin rather than a need.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping

import numpy as np

from growsim.errors import ResourceError, UserInputError
from growsim.kernels.ifs2d import chaos_game
from growsim.models.base import Model, Param, resolve_params
from growsim.phenotypes.attractor import Attractor, singular_values

__all__ = [
    "DEFAULT_N_MAPS",
    "FIT_N_MAPS",
    "FORMS",
    "IFS2D",
    "MAX_N_MAPS",
    "MAX_POINTS",
    "MODEL",
    "NAME",
    "PARAMS",
    "PRESETS",
    "TABLE1",
    "abcdef_form",
    "code_from_params",
    "develop",
    "fit_tables",
    "fixed_point",
    "paper_form",
    "param_spec",
    "params_from_code",
    "repair",
    "seed_form",
]

NAME = "ifs2d"
DEFAULT_N_MAPS = 4
MAX_N_MAPS = 12
#: Maps of a fit to a picture (:func:`fit_tables`): the classic attractors have 2-6 (the
#: fern and the maple leaf 4, Bourke's tree 6); a map of weight 0 is switched off
FIT_N_MAPS = 6
#: Largest attractor :func:`develop` draws (points).
MAX_POINTS = 20_000_000
#: fields of a map in each ``form``, then the shared ``e``, ``f``, ``p``
FORMS = (("r", "q", "theta", "phi"), ("a", "b", "c", "d"))
_SHARED = ("e", "f", "p")

#: The paper's Table 1 (the fern), rows ``(a, b, c, d, e, f, p)``.
TABLE1 = np.array(
    [
        [0.0, 0.0, 0.0, 0.16, 0.0, 0.0, 0.01],
        [0.85, 0.04, -0.04, 0.85, 0.0, 1.6, 0.85],
        [0.2, -0.26, 0.23, 0.22, 0.0, 1.6, 0.07],
        [-0.15, 0.28, 0.26, 0.24, 0.0, 0.44, 0.07],
    ]
)


def paper_form(abcd) -> np.ndarray:
    """``(N, 4)`` ``(r, q, theta, phi)`` (degrees, the paper's form) of ``(N, 4)``
    ``(a, b, c, d)`` rows: ``r = hypot(a, c)``, ``theta = atan2(c, a)``, ``q = hypot(b, d)``,
    ``phi = atan2(-b, d)``.

    Examples
    --------
    >>> paper_form([[0.0, -0.5, 0.5, 0.0]]).round(6).tolist()
    [[0.5, 0.5, 90.0, 90.0]]
    """
    m = np.asarray(abcd, dtype=np.float64).reshape(-1, 4)
    a, b, c, d = m.T
    out = np.column_stack(
        [
            np.hypot(a, c),
            np.hypot(b, d),
            np.degrees(np.arctan2(c, a)),
            np.degrees(np.arctan2(-b, d)),
        ]
    )
    return out + 0.0  # no negative zeros


def seed_form(abcd) -> np.ndarray:
    """:func:`paper_form`, by its name of 0.1 (deprecated: it goes in 0.3)."""
    warnings.warn(
        "ifs2d.seed_form is now ifs2d.paper_form; the old name goes in 0.3",
        DeprecationWarning,
        stacklevel=2,
    )
    return paper_form(abcd)


def abcdef_form(rqtp) -> np.ndarray:
    """``(N, 4)`` ``(a, b, c, d)`` of ``(N, 4)`` ``(r, q, theta, phi)`` rows (degrees): the
    paper's matrix ``[[r cos theta, -q sin phi], [r sin theta, q cos phi]]``.

    Examples
    --------
    >>> abcdef_form([[0.5, 0.5, 90.0, 90.0]]).round(6).tolist()
    [[0.0, -0.5, 0.5, 0.0]]
    """
    m = np.asarray(rqtp, dtype=np.float64).reshape(-1, 4)
    r, q, th, ph = m[:, 0], m[:, 1], np.radians(m[:, 2]), np.radians(m[:, 3])
    return np.column_stack([r * np.cos(th), -q * np.sin(ph), r * np.sin(th), q * np.cos(ph)]) + 0.0


def _map_params(n_maps: int, form: int, defaults: np.ndarray) -> list[Param]:
    out = []
    for k in range(1, n_maps + 1):
        row = defaults[k - 1] if k <= len(defaults) else None
        if form == 0:
            d = paper_form(row[:4])[0] if row is not None else (0.3, 0.3, 0.0, 0.0)
            out += [
                Param(f"r_{k}", 0.0, 1.0, round(float(d[0]), 6), doc=f"x scale of map {k}"),
                Param(f"q_{k}", 0.0, 1.0, round(float(d[1]), 6), doc=f"y scale of map {k}"),
                Param(f"theta_{k}", -180.0, 180.0, round(float(d[2]), 6), unit="deg",
                      doc=f"rotation of the x axis by map {k}"),
                Param(f"phi_{k}", -180.0, 180.0, round(float(d[3]), 6), unit="deg",
                      doc=f"rotation of the y axis by map {k}"),
            ]  # fmt: skip
        else:
            d = row[:4] if row is not None else (0.3, 0.0, 0.0, 0.3)
            out += [
                Param(f"{n}_{k}", -1.0, 1.0, float(v), doc=f"matrix entry {n} of map {k}")
                for n, v in zip("abcd", d)
            ]
        e, f, p = (row[4], row[5], row[6]) if row is not None else (0.0, 0.0, 0.1)
        out += [
            Param(f"e_{k}", -5.0, 5.0, float(e), doc=f"x shift of map {k}"),
            Param(f"f_{k}", -5.0, 5.0, float(f), doc=f"y shift of map {k}"),
            Param(f"p_{k}", 0.0, 1.0, float(p), doc=f"probability weight of map {k}"),
        ]
    return out


def param_spec(fixed: Mapping[str, float] | None = None) -> tuple[Param, ...]:
    """The parameter spec for ``fixed["n_maps"]`` maps in ``fixed["form"]``.

    Returns ``n_maps``, ``form``, ``iterations``, ``burn_in``, ``contraction``, then per
    map ``k``: the four fields of the form (:data:`FORMS`), ``e_k``, ``f_k``, ``p_k``.
    Defaults: the fern of the paper's Table 1 for maps 1-4.

    Examples
    --------
    >>> [p.name for p in param_spec({"n_maps": 1})][5:]
    ['r_1', 'q_1', 'theta_1', 'phi_1', 'e_1', 'f_1', 'p_1']
    >>> [p.name for p in param_spec({"n_maps": 1, "form": 1})][5:9]
    ['a_1', 'b_1', 'c_1', 'd_1']
    """
    fixed = dict(fixed or {})
    head = (
        Param("n_maps", 1, MAX_N_MAPS, DEFAULT_N_MAPS, kind="int", doc="number of maps N"),
        Param("form", 0, 1, 0, kind="int", doc="0: r q theta phi (the paper's); 1: a b c d"),
        Param("iterations", 1, MAX_POINTS, 100_000, kind="int", doc="chaos-game points drawn"),
        Param("burn_in", 0, 100_000, 100, kind="int", doc="chaos-game points dropped first"),
        Param("contraction", 0.1, 0.999, 0.95, doc="largest singular value a map may have"),
    )
    n_maps = int(head[0].check(fixed.get("n_maps", DEFAULT_N_MAPS), "ifs2d."))
    form = int(head[1].check(fixed.get("form", 0), "ifs2d."))
    return (*head, *_map_params(n_maps, form, TABLE1))


#: The spec for the default fern (4 maps, the paper's form).
PARAMS = param_spec()


def params_from_code(table, *, form: int = 0, **extra: float) -> dict[str, float]:
    """Model parameters of an IFSP code ``table`` ``(N, 7)`` rows ``(a, b, c, d, e, f, p)``.

    ``form`` as the model's (0: the paper's ``r q theta phi``; 1: ``a b c d``); ``extra``
    fixed values (``iterations``, ...) are added.

    Examples
    --------
    >>> p = params_from_code(TABLE1)
    >>> p["n_maps"], round(p["r_2"], 4), round(p["theta_2"], 3), p["f_2"]
    (4.0, 0.8509, -2.694, 1.6)
    """
    t = np.asarray(table, dtype=np.float64)
    if t.ndim != 2 or t.shape[1] != 7 or not 1 <= t.shape[0] <= MAX_N_MAPS:
        raise UserInputError(f"ifs2d: an IFSP code is (N, 7) rows a b c d e f p, got {t.shape}")
    if form not in (0, 1):
        raise UserInputError(f"ifs2d: form must be 0 or 1, got {form!r}")
    lin = paper_form(t[:, :4]) if form == 0 else t[:, :4]
    out: dict[str, float] = {"n_maps": float(t.shape[0]), "form": float(form)}
    for k in range(t.shape[0]):
        for name, v in zip(FORMS[form] + _SHARED, (*lin[k], *t[k, 4:])):
            out[f"{name}_{k + 1}"] = round(float(v), 12) + 0.0
    out.update({k: float(v) for k, v in extra.items()})
    return out


def code_from_params(params: Mapping[str, float]) -> tuple[np.ndarray, np.ndarray]:
    """The raw code of resolved parameters: maps ``(N, 6)`` rows ``(a, b, c, d, e, f)`` and
    weights ``(N,)`` (neither repaired nor normalised; see :func:`repair`).

    Examples
    --------
    >>> maps, p = code_from_params(params_from_code(TABLE1))
    >>> np.allclose(maps, TABLE1[:, :6]), p.tolist()
    (True, [0.01, 0.85, 0.07, 0.07])
    """
    n = int(params.get("n_maps", DEFAULT_N_MAPS))
    form = int(params.get("form", 0))
    try:
        lin = np.array([[float(params[f"{f}_{k}"]) for f in FORMS[form]] for k in range(1, n + 1)])
        rest = np.array([[float(params[f"{f}_{k}"]) for f in _SHARED] for k in range(1, n + 1)])
    except KeyError as exc:
        raise UserInputError(f"ifs2d: missing parameter {exc.args[0]}") from None
    abcd = abcdef_form(lin) if form == 0 else lin
    return np.column_stack([abcd, rest[:, :2]]), rest[:, 2].copy()


def repair(maps, p, contraction: float = 0.95) -> tuple[np.ndarray, np.ndarray]:
    """Repaired code: each map's linear part scaled down to a largest singular value of
    at most ``contraction`` (shift kept), weights normalised (all zero: equal).

    The largest singular value of ``[[a, b], [c, d]]`` is
    ``sqrt((s + sqrt(s^2 - 4 det^2)) / 2)``, ``s = a^2 + b^2 + c^2 + d^2``.

    Examples
    --------
    >>> m, p = repair([[2.0, 0, 0, 0.5, 1.0, 0.0]], [0.0], 0.9)
    >>> m.tolist(), p.tolist()
    ([[0.9, 0.0, 0.0, 0.225, 1.0, 0.0]], [1.0])
    """
    maps = np.array(maps, dtype=np.float64).reshape(-1, 6)
    p = np.asarray(p, dtype=np.float64).reshape(-1)
    if p.shape[0] != maps.shape[0] or (p < 0).any() or not np.isfinite(p).all():
        raise UserInputError(f"ifs2d: weights must be {maps.shape[0]} numbers >= 0, got {p}")
    sigma = singular_values(maps)
    scale = np.where(sigma > contraction, contraction / np.maximum(sigma, 1e-300), 1.0)
    maps[:, :4] *= scale[:, None]
    total = p.sum()
    p = np.full_like(p, 1.0 / len(p)) if total == 0 else p / total
    return maps, p


def fixed_point(row) -> tuple[float, float]:
    """The fixed point of one contractive map ``(a, b, c, d, e, f)``: ``(I - A)^-1 (e, f)``.

    Examples
    --------
    >>> x, y = fixed_point([0.85, 0.04, -0.04, 0.85, 0.0, 1.6])  # the tip of the fern
    >>> round(x, 4), round(y, 4)
    (2.6556, 9.9585)
    """
    a, b, c, d, e, f = (float(v) for v in row[:6])
    det = (1.0 - a) * (1.0 - d) - b * c
    if det == 0.0:
        return (e, f)
    return ((1.0 - d) * e + b * f) / det, (c * e + (1.0 - a) * f) / det


def _preset(table, **extra) -> dict[str, float]:
    return params_from_code(np.asarray(table, dtype=np.float64), **extra)


#: Named plants, each an IFSP code (rows a b c d e f p), in the paper's form:
#: ``fern``: the paper's Table 1; ``tree``: a binary fractal tree (a thin trunk, two
#: branches turned by 30 degrees at 0.6 scale; the start of growsim's "fractal tree one"
#: species); ``tree3``: the same with a third, upright branch ("fractal tree two");
#: ``tree6``: a six-map tree with a forked trunk and a dense crown; ``bush``: a four-map
#: bush; ``sierpinski``: the triangle (no plant: a check of the renderer).
PRESETS: dict[str, dict[str, float]] = {
    "fern": _preset(TABLE1),
    "tree": _preset(
        [
            [0.03, 0.0, 0.0, 0.5, 0.0, 0.0, 0.10],
            [0.52, -0.3, 0.3, 0.52, 0.0, 0.5, 0.45],
            [0.52, 0.3, -0.3, 0.52, 0.0, 0.5, 0.45],
        ]
    ),
    "tree3": _preset(
        [
            [0.03, 0.0, 0.0, 0.45, 0.0, 0.0, 0.10],
            [0.5, -0.35, 0.35, 0.5, 0.0, 0.45, 0.30],
            [0.5, 0.35, -0.35, 0.5, 0.0, 0.45, 0.30],
            [0.4, 0.0, 0.0, 0.45, 0.0, 0.45, 0.30],
        ]
    ),
    "tree6": _preset(
        [
            [0.05, 0.0, 0.0, 0.6, 0.0, 0.0, 0.10],
            [0.05, 0.0, 0.0, -0.5, 0.0, 1.0, 0.10],
            [0.46, -0.321, 0.386, 0.383, 0.0, 0.6, 0.20],
            [0.47, -0.154, 0.171, 0.423, 0.0, 1.0, 0.20],
            [0.433, 0.275, -0.25, 0.476, 0.0, 1.0, 0.20],
            [0.421, 0.257, -0.353, 0.306, 0.0, 0.7, 0.20],
        ]
    ),
    "bush": _preset(
        [
            [0.14, 0.01, 0.0, 0.51, -0.08, -1.31, 0.10],
            [0.43, 0.52, -0.45, 0.5, 1.49, -0.75, 0.35],
            [0.45, -0.49, 0.47, 0.47, -1.62, -0.74, 0.35],
            [0.49, 0.0, 0.0, 0.51, 0.02, 1.62, 0.20],
        ]
    ),
    "sierpinski": _preset(
        [
            [0.5, 0.0, 0.0, 0.5, 0.0, 0.0, 1.0],
            [0.5, 0.0, 0.0, 0.5, 1.0, 0.0, 1.0],
            [0.5, 0.0, 0.0, 0.5, 0.5, 1.0, 1.0],
        ]
    ),
}


def develop(params: Mapping[str, float] | None = None, *, seed: int = 0, env=None):
    """Draw the attractor of an IFSP code: a :class:`growsim.phenotypes.attractor.Attractor`.

    ``params``: any subset of :func:`param_spec` (for ``params["n_maps"]`` and
    ``params["form"]``); the rest default (the fern). ``seed`` seeds the chaos game;
    ``env`` is unused (a 2D IFS grows in no environment; the Ochoa terms read its light).

    Examples
    --------
    >>> a = develop(PRESETS["fern"], seed=1)
    >>> a.points.shape, round(a.height(), 1)
    ((100000, 2), 10.0)
    """

    params = dict(params or {})
    p = resolve_params(param_spec(params), params, where="ifs2d.")
    n = int(p["iterations"])
    if n > MAX_POINTS:  # the spec's bound; kept as the one place the size is checked
        raise ResourceError(f"ifs2d: iterations = {n:,} exceeds {MAX_POINTS:,}")
    raw_maps, raw_p = code_from_params(p)
    maps, prob = repair(raw_maps, raw_p, p["contraction"])
    start = fixed_point(maps[int(np.argmax(prob))])
    points = chaos_game(maps, prob, n, seed=int(seed), burn_in=int(p["burn_in"]), start=start)
    return Attractor(points, maps, prob, params=p, meta={"model": NAME, "seed": int(seed)})


def fit_tables(maps: int | None = None) -> dict:
    """The ``[model]``, ``[ga]`` and ``[output]`` tables that fit a code to one picture of
    an attractor. ``maps = None``: those of ``experiments/ifs_fern_fit.toml`` (a test
    keeps them equal): every parameter of 4 maps is evolved (28 numbers), each weight at
    least 0.01. ``maps = N``: ``N`` maps whose weights may reach 0, which switches a map
    off, so the search chooses how many of them the picture needs (``growsim fit-image
    picture.png --model ifs2d`` runs :data:`FIT_N_MAPS`: a 3-map triangle and Bourke's
    6-map tree alike). Both: 20,000 chaos-game points a plant, maps kept below 0.9;
    40,000 evaluations, a GA of 100, then 28,000 of CMA-ES (``fit-image`` runs half of
    that on a drawing: ``FIT_SETUPS["ifs2d"].drawing``).

    Examples
    --------
    >>> t = fit_tables()
    >>> t["model"]["kind"], t["ga"]["evaluations"], t["ga"]["polish"]["method"]
    ('ifs2d', 40000, 'cmaes')
    >>> t["model"]["params"]["n_maps"], t["model"]["evolve"]["p_?"]
    (4, [0.01, 1.0])
    >>> t = fit_tables(FIT_N_MAPS)
    >>> t["model"]["params"]["n_maps"], t["model"]["evolve"]["p_?"]
    (6, [0.0, 1.0])
    >>> fit_tables(13)
    Traceback (most recent call last):
    ...
    growsim.errors.UserInputError: ifs2d: maps must be 1..12, got 13
    """
    if maps is not None and not 1 <= int(maps) <= MAX_N_MAPS:
        raise UserInputError(f"ifs2d: maps must be 1..{MAX_N_MAPS}, got {maps}")
    n_maps = 4 if maps is None else int(maps)
    least = 0.01 if maps is None else 0.0
    return {
        "model": {
            "kind": NAME,
            "params": {"n_maps": n_maps, "iterations": 20000, "burn_in": 100, "contraction": 0.9},
            "evolve": {
                "r_?": True,
                "q_?": True,
                "theta_?": True,
                "phi_?": True,
                "e_?": [-1.0, 1.0],
                "f_?": [0.0, 2.0],
                "p_?": [least, 1.0],
            },
        },
        "ga": {
            "coding": "real",
            "population": 100,
            "evaluations": 40000,
            "generations": 1000,
            "model": "generational",
            "elite": 2,
            "selection": "tournament",
            "selection_options": {"size": 4},
            "crossover": "sbx",
            "crossover_options": {"rate": 0.9, "eta": 15.0},
            "mutation": "polynomial",
            "mutation_options": {"eta": 20.0},
            "islands": 1,
            "extinction": True,
            "polish": {"method": "cmaes", "evaluations": 28000, "sigma": 0.1, "batch": 20},
        },
        "output": {"screenshots": ["front"], "size": [600, 600]},
    }


class IFS2D(Model):
    """The 2D IFS plant under the model contract: :func:`param_spec`, :data:`PRESETS`,
    :func:`develop` (an :class:`growsim.phenotypes.attractor.Attractor`, phenotype ``"points2d"``).

    Examples
    --------
    >>> MODEL.phenotype, len(MODEL.param_spec()), sorted(MODEL.presets)[:2]
    ('points2d', 33, ['bush', 'fern'])
    """

    name = NAME
    phenotype = "points2d"
    params = PARAMS
    presets = PRESETS

    def param_spec(self, fixed=None) -> tuple[Param, ...]:
        """See :func:`param_spec`."""
        return param_spec(fixed)

    def develop(self, params=None, *, seed=None, env=None):
        """See :func:`develop` (``seed`` None: 0)."""
        return develop(params, seed=0 if seed is None else int(seed), env=env)


#: The registered model (``growsim.models.MODELS["ifs2d"]``).
MODEL = IFS2D()
