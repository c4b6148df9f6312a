"""numba's cache keys a kernel by its own file: growsim drops its cached kernels when any
kernel source changes (a caller would otherwise keep a changed callee's old code)."""

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
