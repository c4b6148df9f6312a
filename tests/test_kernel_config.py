"""numba's cache keys a kernel by its own file: growsim drops its cached kernels when any
kernel source changes (a caller would otherwise keep a changed callee's old code). And the
kernel convention: every numba function in growsim/kernels/, at most ten arguments, an
oracle module in tests/naive/ per kernel module (``python tests/test_kernel_config.py`` lists
every numba function with its number of arguments)."""

import ast
import re

from conftest import ROOT

from growsim.kernels.config import drop_stale_caches, sources_hash


def test_a_changed_kernel_source_drops_every_cached_kernel(tmp_path):
    (tmp_path / "kernels" / "__pycache__").mkdir(parents=True)
    callee = tmp_path / "kernels" / "callee.py"
    callee.write_text("from x import njit\n")
    (tmp_path / "notes.py").write_text("no kernels here\n")
    cached = [
        tmp_path / "kernels" / "__pycache__" / f"caller.f-1.py311.{e}" for e in ("nbi", "nbc")
    ]
    for path in cached:
        path.write_bytes(b"old code")
    assert drop_stale_caches(tmp_path)  # no record yet: dropped, recorded
    assert not any(p.exists() for p in cached)
    for path in cached:
        path.write_bytes(b"new code")
    assert not drop_stale_caches(tmp_path)  # nothing changed: kept
    assert all(p.exists() for p in cached)
    (tmp_path / "notes.py").write_text("still no kernels\n")  # not a kernel source: kept
    assert not drop_stale_caches(tmp_path)
    h = sources_hash(tmp_path)
    callee.write_text("from x import njit  # changed\n")
    assert sources_hash(tmp_path) != h
    assert drop_stale_caches(tmp_path)
    assert not any(p.exists() for p in cached)


# -- the kernel convention (docs/design.md): where kernels live, how many arguments, oracles
#: the most arguments a kernel takes: state goes in a few typed tuples, not one by one
MAX_ARGS = 10
#: decorators that compile a function with numba
JIT_DECORATORS = {"njit", "jit", "vectorize", "guvectorize", "stencil", "cfunc"}


def _jit_functions():
    """``(path relative to the repository, function node)`` of every numba-compiled
    function under ``growsim/`` (by its decorator)."""
    for path in sorted((ROOT / "growsim").rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                continue
            for dec in node.decorator_list:
                f = dec.func if isinstance(dec, ast.Call) else dec
                name = f.attr if isinstance(f, ast.Attribute) else getattr(f, "id", "")
                if name in JIT_DECORATORS:
                    yield path.relative_to(ROOT), node
                    break


def _n_args(node) -> int:
    a = node.args
    return len(a.posonlyargs) + len(a.args) + len(a.kwonlyargs) + bool(a.vararg) + bool(a.kwarg)


def test_every_kernel_takes_at_most_ten_arguments():
    found = list(_jit_functions())
    assert len(found) > 50  # the parse finds the kernels
    over = [f"{p}:{n.name} ({_n_args(n)})" for p, n in found if _n_args(n) > MAX_ARGS]
    assert not over, f"kernels over {MAX_ARGS} arguments (pass state as tuples): {over}"


def test_every_kernel_lives_in_growsim_kernels():
    kernels = ROOT / "growsim" / "kernels"
    outside = [f"{p}:{n.name}" for p, n in _jit_functions() if (ROOT / p).parent != kernels]
    assert not outside, f"numba functions outside growsim/kernels/: {outside}"
    # nor compiled by a call (numba.njit(f)): numba and njit are imported in kernels/ only
    for path in sorted((ROOT / "growsim").rglob("*.py")):
        if path.parent == kernels:
            continue
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Import):
                names = [a.name.split(".")[0] for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                names = [(node.module or "").split(".")[0], *(a.name for a in node.names)]
            else:
                continue
            assert not {"numba", "njit"} & set(names), f"{path.relative_to(ROOT)}: {names}"


def test_every_kernel_module_has_its_oracle():
    """``tests/naive/<module>.py`` for every kernel module, with at least one function
    named after a function of the module, imported by a test."""
    tests = "".join(p.read_text() for p in (ROOT / "tests").glob("test_*.py"))
    modules = sorted({p.stem for p, _ in _jit_functions()})
    assert {"light", "capsule", "shadow_gl", "hormone"} <= set(modules)
    for name in modules:
        oracle = ROOT / "tests" / "naive" / f"{name}.py"
        assert oracle.is_file(), f"growsim/kernels/{name}.py has no oracle tests/naive/{name}.py"
        kernel = ast.parse((ROOT / "growsim" / "kernels" / f"{name}.py").read_text())
        own = {n.name for n in kernel.body if isinstance(n, ast.FunctionDef)}
        mirrors = {n.name for n in ast.parse(oracle.read_text()).body
                   if isinstance(n, ast.FunctionDef)}  # fmt: skip
        assert own & mirrors, f"tests/naive/{name}.py names no function of kernels/{name}.py"
        assert re.search(rf"from (tests\.)?naive(\.{name}| import {name}\b)", tests), (
            f"no test imports the oracle naive.{name}"
        )


if __name__ == "__main__":  # python tests/test_kernel_config.py: every kernel, its arguments
    rows = sorted(((_n_args(n), f"{p}:{n.name}") for p, n in _jit_functions()), reverse=True)
    for count, name in rows:
        print(f"{count:3d} {name}")
    print(f"{len(rows)} numba functions, {sum(c > MAX_ARGS for c, _ in rows)} over {MAX_ARGS}")
