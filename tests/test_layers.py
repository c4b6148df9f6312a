"""The house's rules, read from the code: few modules at the top, no private names taken
across modules, capabilities asked for (never probed with ``getattr``), import-linter's
layers kept.

The checks parse ``growsim/`` with :mod:`ast` (nothing is imported but the two
``CAPABILITIES`` tuples). ``tests/`` is exempt from the private-name rule on purpose: a
test may reach a module's private helpers (an oracle test calls a private kernel, a
runner test its census) without making them part of anyone's interface.
"""

from __future__ import annotations

import ast
import subprocess
import sys
import tomllib
from pathlib import Path

from conftest import ROOT

from growsim.models.base import CAPABILITIES as MODEL_CAPABILITIES
from growsim.phenotypes.base import CAPABILITIES as PHENOTYPE_CAPABILITIES

PACKAGE = ROOT / "growsim"
#: the most modules directly in ``growsim/`` (``__init__`` and ``__main__`` included)
MAX_TOP_MODULES = 8


def _module_name(path: Path) -> str:
    parts = path.relative_to(ROOT).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


#: every module of growsim: dotted name -> path
MODULES = {_module_name(p): p for p in sorted(PACKAGE.rglob("*.py"))}


def _private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def _dotted(node: ast.AST) -> str | None:
    """``a.b.c`` of a Name/Attribute chain, else None."""
    parts = []
    while isinstance(node, ast.Attribute):
        parts.append(node.attr)
        node = node.value
    if not isinstance(node, ast.Name):
        return None
    parts.append(node.id)
    return ".".join(reversed(parts))


def private_uses(path: Path, text: str | None = None) -> list[str]:
    """Where the module at ``path`` (its source: ``text``, default the file's) takes
    another growsim module's private name: ``from growsim.x import _name``, or ``_name``
    read as an attribute of another growsim module (``import growsim.x as x; x._name``,
    ``from growsim import x; x._name``, ``growsim.x._name``)."""
    me = _module_name(path)
    tree = ast.parse(path.read_text() if text is None else text, filename=str(path))
    aliases: dict[str, str] = {}  # local name -> growsim module it stands for
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            if not (node.module == "growsim" or node.module.startswith("growsim.")):
                continue
            for a in node.names:
                full = f"{node.module}.{a.name}"
                if full in MODULES:  # a module imported from its package
                    aliases[a.asname or a.name] = full
                if _private(a.name) and node.module != me:
                    found.append(f"{path.relative_to(ROOT)}:{node.lineno}: from {full}")
        elif isinstance(node, ast.Import):
            for a in node.names:
                if a.name == "growsim" or a.name.startswith("growsim."):
                    if a.asname:
                        aliases[a.asname] = a.name
                    else:
                        aliases["growsim"] = "growsim"
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute) and _private(node.attr):
            base = _dotted(node.value)
            if base is None:
                continue
            head, _, rest = base.partition(".")
            module = aliases.get(head)
            if module is None:
                continue
            module = f"{module}.{rest}" if rest else module
            if module in MODULES and module != me:
                found.append(f"{path.relative_to(ROOT)}:{node.lineno}: {module}.{node.attr}")
    return found


def capability_probes(path: Path, text: str | None = None) -> list[str]:
    """Where the module at ``path`` (its source: ``text``, default the file's) probes a
    declared capability by name: ``getattr(x, "population", ...)`` or
    ``hasattr(x, "front_view")``."""
    names = set(MODEL_CAPABILITIES) | set(PHENOTYPE_CAPABILITIES)
    tree = ast.parse(path.read_text() if text is None else text, filename=str(path))
    found = []
    for node in ast.walk(tree):
        if (
            isinstance(node, ast.Call)
            and isinstance(node.func, ast.Name)
            and node.func.id in ("getattr", "hasattr")
            and len(node.args) >= 2
            and isinstance(node.args[1], ast.Constant)
            and node.args[1].value in names
        ):
            name = node.args[1].value
            found.append(f"{path.relative_to(ROOT)}:{node.lineno}: {node.func.id}(..., {name!r})")
    return found


def test_at_most_eight_modules_directly_in_growsim():
    top = sorted(p.name for p in PACKAGE.glob("*.py"))
    assert len(top) <= MAX_TOP_MODULES, top


def test_no_module_takes_another_modules_private_names():
    found = [hit for path in MODULES.values() for hit in private_uses(path)]
    assert not found, "\n".join(found)


def test_the_private_name_check_sees_every_form():
    # the checker itself, on a made-up source read as if it were growsim/ga/engine.py:
    # imports and attribute reads are caught; one's own private names and others' public
    # ones are not
    code = (
        "import growsim.ga.state as st\n"
        "import growsim.ga.options\n"
        "from growsim.kernels import ga\n"
        "from growsim.ga.operator import _x, public\n"
        "from growsim.ga.engine import _mine\n"
        "st._hidden(); ga._sbx(); st.public(); growsim.ga.options._spec\n"
    )
    hits = private_uses(PACKAGE / "ga" / "engine.py", code)
    assert sorted(h.split(": ", 1)[1] for h in hits) == [
        "from growsim.ga.operator._x",
        "growsim.ga.options._spec",
        "growsim.ga.state._hidden",
        "growsim.kernels.ga._sbx",
    ]


def test_no_capability_is_probed_with_getattr():
    """``"population" in model.capabilities``, never ``getattr(model, "population", None)``
    (the names of ``growsim.models.base.CAPABILITIES`` and
    ``growsim.phenotypes.base.CAPABILITIES``)."""
    found = [hit for path in MODULES.values() for hit in capability_probes(path)]
    assert not found, "\n".join(found)
    # the checker itself
    code = 'getattr(m, "population", None); hasattr(p, "front_view"); getattr(a, "kind")\n'
    hits = capability_probes(PACKAGE / "models" / "base.py", code)
    assert [h.split(": ", 1)[1] for h in hits] == [
        "getattr(..., 'population')",
        "hasattr(..., 'front_view')",
    ]


def test_import_linter_contracts_are_kept():
    """``lint-imports`` (the layers of ``[tool.importlinter]`` in pyproject.toml), as
    ``.ci/run`` runs it; about a quarter of a second."""
    exe = Path(sys.executable).with_name("lint-imports")  # import-linter is in [test]
    assert exe.exists(), "lint-imports is not installed next to this Python: pip install .[test]"
    p = subprocess.run([str(exe), "--no-cache"], cwd=ROOT, capture_output=True, text=True,
                       timeout=120)  # fmt: skip
    assert p.returncode == 0, p.stdout + p.stderr
    assert "0 broken" in p.stdout


def test_every_package_is_in_the_acyclic_siblings_contract():
    """Every package of growsim (``growsim`` itself and each directory of modules below
    it, however deep) is covered by an ``acyclic_siblings`` contract of
    ``[tool.importlinter]``: the modules and subpackages directly in it form no import
    circle. A new package cannot slip out of it."""
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["importlinter"]
    contracts = [c for c in config["contracts"] if c["type"] == "acyclic_siblings"]
    assert contracts, "no acyclic_siblings contract in [tool.importlinter]"

    def covered(package: str) -> bool:
        for c in contracts:
            if any(package == s or package.startswith(s + ".")
                   for s in c.get("skip_descendants", [])):  # fmt: skip
                continue
            for ancestor in c["ancestors"]:
                below = package.count(".") - ancestor.count(".")
                inside = package == ancestor or package.startswith(ancestor + ".")
                if inside and below <= c.get("depth", 10):  # import-linter's default depth
                    return True
        return False

    packages = sorted({".".join(p.parent.relative_to(ROOT).parts) for p in PACKAGE.rglob("*.py")})
    assert {"growsim", "growsim.phenotypes.plant"} <= set(packages), packages
    missing = [p for p in packages if not covered(p)]
    assert not missing, f"packages outside the acyclic_siblings contract: {missing}"


#: ``getattr``/``hasattr`` on something else than ``self``/``cls`` (or a module), and
#: private attributes of something else than ``self``/``cls``, that ``growsim/ga/`` and
#: ``growsim/experiment/`` keep on purpose: (module, source) -> why. Data read by name,
#: never a probe of another class's behaviour.
KEPT_PROBES = {
    ("growsim/experiment/docs.py", "getattr(m, 'metadata', None)"): (
        "pydantic's and annotated_types' constraint metadata, read as data for docs/configs.md"
    ),
    ("growsim/experiment/docs.py", "getattr(m, attr, None)"): "the same: ge, gt, le, lt, ...",
    ("growsim/experiment/docs.py", "getattr(m, 'pattern', None)"): "the same: a pattern",
    ("growsim/experiment/plan.py", "getattr(mp, f.name)"): (
        "a ModelPlan's dataclass fields copied by their declared names into an ExperimentPlan"
    ),
    ("growsim/experiment/results.py", "rec._phenotype"): (
        "RunRecord.of_run, the class's own constructor, sets the new record's cache"
    ),
}


def contract_probes(path: Path, text: str | None = None, kept=KEPT_PROBES) -> list[str]:
    """Where the module at ``path`` (its source: ``text``, default the file's) probes
    another object instead of using a declared contract: ``getattr``/``hasattr`` whose
    first argument is not ``self``, ``cls`` or a module it imports, and an attribute
    starting with ``_`` (not a dunder) of anything but ``self``/``cls`` or such a module
    (read or written), unless ``kept`` (default :data:`KEPT_PROBES`) lists it."""
    rel = path.relative_to(ROOT).as_posix()
    tree = ast.parse(path.read_text() if text is None else text, filename=str(path))
    modules = {
        (a.asname or a.name).partition(".")[0]
        for node in ast.walk(tree)
        if isinstance(node, ast.Import)
        for a in node.names
    }

    def own(node: ast.AST) -> bool:  # self, cls, or an imported module (os._exit)
        dotted = _dotted(node)
        if dotted is None:
            return False
        return dotted in ("self", "cls") or dotted.partition(".")[0] in modules

    found = []
    for node in ast.walk(tree):
        if (
            isinstance(node, ast.Call)
            and isinstance(node.func, ast.Name)
            and node.func.id in ("getattr", "hasattr")
            and node.args
            and not own(node.args[0])
        ) or (isinstance(node, ast.Attribute) and _private(node.attr) and not own(node.value)):
            hit = ast.unparse(node)
            if (rel, hit) not in kept:
                found.append(f"{rel}:{node.lineno}: {hit}")
    return found


def test_the_ga_and_experiment_probe_nothing():
    """The GA's contracts with its fitness and executors are declared
    (:class:`growsim.ga.evaluate.GAFitness`, :class:`growsim.ga.evaluate.Pool`), as are
    the operators' and the parameters': nothing in ``growsim/ga/`` or
    ``growsim/experiment/`` probes another object with ``getattr``/``hasattr`` or reads
    its private attributes (:data:`KEPT_PROBES`: the data read by name kept on purpose)."""
    paths = sorted((PACKAGE / "ga").rglob("*.py")) + sorted((PACKAGE / "experiment").rglob("*.py"))
    found = [hit for path in paths for hit in contract_probes(path)]
    assert not found, "\n".join(found)
    # every exception is still needed
    every = {
        (h.split(":", 1)[0], h.split(": ", 1)[1])
        for path in paths
        for h in contract_probes(path, kept={})
    }
    stale = [key for key in KEPT_PROBES if key not in every]
    assert not stale, f"KEPT_PROBES lists probes that are gone: {stale}"
    # the checker itself, on a made-up source read as if it were growsim/ga/evaluate.py
    code = (
        "import os\n"
        "import numpy as np\n"
        "getattr(self, 'a'); getattr(cls, name); getattr(np.random, 'PCG64'); os._exit(1)\n"
        "getattr(ex, '_max_workers', None); hasattr(op, 'check'); getattr(self.env, 's')\n"
        "ex._client; self._own; self.pool._n = 1; type(e).__name__\n"
    )
    hits = contract_probes(PACKAGE / "ga" / "evaluate.py", code)
    assert sorted(h.split(": ", 1)[1] for h in hits) == [
        "ex._client",
        "getattr(ex, '_max_workers', None)",
        "getattr(self.env, 's')",
        "hasattr(op, 'check')",
        "self.pool._n",
    ]


def _names_a_model(node: ast.AST) -> bool:
    """``args.model``, ``model.name``, ``self.model.name``, ``get_model(x).name`` or
    ``model_name``: an expression holding a model's registry name."""
    if isinstance(node, ast.Name):
        return node.id == "model_name"
    if not isinstance(node, ast.Attribute):
        return False
    if node.attr == "model":
        return True
    if node.attr != "name":
        return False
    inner = node.value.func if isinstance(node.value, ast.Call) else node.value
    dotted = _dotted(inner) or ""
    return "model" in dotted.rpartition(".")[2]


def _string_literal(node: ast.AST) -> bool:
    """``"hormone"`` or a tuple, list or set of string literals."""
    if isinstance(node, (ast.Tuple, ast.List, ast.Set)):
        return bool(node.elts) and all(_string_literal(e) for e in node.elts)
    return isinstance(node, ast.Constant) and isinstance(node.value, str)


def cli_domain_logic(path: Path, text: str | None = None) -> list[str]:
    """Where a module of ``growsim/cli/`` (its source: ``text``, default the file's) does
    what belongs to the library: imports NumPy (``import numpy``, ``from numpy ...``,
    function-local imports included; arrays are the library's) or compares a model's name
    to a string literal (``args.model == "hormone"``, ``model.name != "honda"``,
    ``args.model in ("a", "b")``, ``match args.model: case "fish"``): a model's
    particulars are asked of it as a declared capability (``"grow_stand" in
    model.capabilities``)."""
    tree = ast.parse(path.read_text() if text is None else text, filename=str(path))
    found = []  # (line, what)
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                if a.name == "numpy" or a.name.startswith("numpy."):
                    found.append((node.lineno, f"import {a.name}"))
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            if node.module == "numpy" or node.module.startswith("numpy."):
                found.append((node.lineno, f"from {node.module}"))
        elif isinstance(node, ast.Compare):
            operands = [node.left, *node.comparators]
            if any(map(_names_a_model, operands)) and any(map(_string_literal, operands)):
                found.append((node.lineno, ast.unparse(node)))
        elif isinstance(node, ast.Match) and _names_a_model(node.subject):
            for case in node.cases:
                pattern = case.pattern
                if isinstance(pattern, ast.MatchValue) and _string_literal(pattern.value):
                    found.append((pattern.lineno, f"match {ast.unparse(node.subject)}"))
    where = path.relative_to(ROOT)
    return [f"{where}:{line}: {what}" for line, what in sorted(found, key=lambda f: f[0])]


def test_the_cli_only_parses_calls_and_prints():
    """``growsim/cli/`` parses, calls the library and prints: no NumPy, and no branch on a
    model's name (a model declares what it can: ``growsim.models.base.CAPABILITIES``)."""
    cli = sorted((PACKAGE / "cli").glob("*.py"))
    found = [hit for path in cli for hit in cli_domain_logic(path)]
    assert not found, "\n".join(found)
    # the checker itself: NumPy imported in every form, names compared to literals; a
    # model's phenotype kind, a name compared to a variable and a capability asked are fine
    code = (
        "import numpy as np\n"
        "from numpy.linalg import norm\n"
        "def f(args, model, other):\n"
        "    import numpy\n"
        "    if args.model == 'hormone' or model.name != 'honda':\n"
        "        pass\n"
        "    if args.model in ('a', 'b') or 'fish' == get_model(x).name:\n"
        "        pass\n"
        "    if model.phenotype == 'plant' or args.model == other:\n"
        "        pass\n"
        "    if 'grow_stand' in model.capabilities:\n"
        "        pass\n"
        "    match args.model:\n"
        "        case 'ifs3d':\n"
        "            pass\n"
    )
    hits = cli_domain_logic(PACKAGE / "cli" / "grow.py", code)
    assert [h.split(": ", 1)[1] for h in hits] == [
        "import numpy",
        "from numpy.linalg",
        "import numpy",
        "args.model == 'hormone'",
        "model.name != 'honda'",
        "args.model in ('a', 'b')",
        "'fish' == get_model(x).name",
        "match args.model",
    ]
    assert cli_domain_logic(PACKAGE / "cli" / "grow.py", 'if args.model == "hormone": pass')


def test_building_the_command_line_imports_no_heavy_module():
    """``growsim --help`` builds every subcommand's parser: the cli's modules import the
    library in their commands' bodies (docs/design.md, "Imports"), so building it loads
    neither numba nor pandas nor pyvista."""
    code = (
        "import sys\n"
        "from growsim.cli import build_parser\n"
        "build_parser()\n"
        "print(sorted(m for m in ('numba', 'pandas', 'pyvista', 'scipy') if m in sys.modules))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "[]", out.stdout
