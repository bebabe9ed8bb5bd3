"""The guard against stale numba cache files (fricstab._numba.purge_stale_cache).

numba keys a cached function on its own source file only, so a change in a
kernel it inlines from another file would leave stale machine code: the
guard deletes the package's cached code whenever a source that compiled code
can depend on changed (a module that imports numba, or one such a module
imports from), and keeps it when only other modules (the command line, the
Python drivers) changed.
"""

import os

import pytest

from fricstab._numba import PACKAGE, jit_sources, purge_stale_cache


def _package(tmp_path):
    root = tmp_path / "pkg"
    (root / "sub" / "__pycache__").mkdir(parents=True)
    (root / "__pycache__").mkdir()
    (root / "a.py").write_text("from numba import njit\nfrom pkg.sub.b import Y\nx = 1\n")
    (root / "sub" / "b.py").write_text("Y = 2\n")
    (root / "sub" / "c.py").write_text("from ._numba import hot_jit\nfrom .d import Z\n")
    (root / "sub" / "d.py").write_text("Z = 3\n")
    (root / "cli.py").write_text("def version():\n    import numba\n    return 1\n")
    return root


def _cache_files(root):
    for name in ("sub/__pycache__/b.f-1.py311.nbi", "sub/__pycache__/b.f-1.py311.1.nbc",
                 "__pycache__/a.g-3.py311.nbi"):
        (root / name).write_bytes(b"machine code")
    (root / "sub" / "__pycache__" / "b.cpython-311.pyc").write_bytes(b"bytecode")


def test_cache_is_purged_when_any_source_changes_and_kept_otherwise(tmp_path):
    root = _package(tmp_path)
    _cache_files(root)
    assert purge_stale_cache(root) == 3          # no stamp yet: cached code of unknown sources
    assert (root / "sub" / "__pycache__" / "b.cpython-311.pyc").exists()   # Python's own kept
    _cache_files(root)
    assert purge_stale_cache(root) == 0          # same sources: the cache is kept
    assert (root / "sub" / "__pycache__" / "b.f-1.py311.1.nbc").exists()
    (root / "sub" / "b.py").write_text("Y = 3\n")   # a module jitted code imports from
    assert purge_stale_cache(root) == 3
    assert not list(root.rglob("*.nb[ic]"))
    _cache_files(root)
    (root / "sub" / "d.py").write_text("Z = 4\n")   # the same, by a relative import
    assert purge_stale_cache(root) == 3
    _cache_files(root)
    (root / "e.py").write_text("import numba\n")  # a new numba module counts too
    assert purge_stale_cache(root) == 3
    _cache_files(root)
    (root / "cli.py").write_text("def version():\n    import numba\n    return 2\n")
    (root / "f.py").write_text("w = 1\n")         # modules no compiled code reads: kept
    assert purge_stale_cache(root) == 0


def test_the_package_sources_compiled_code_depends_on():
    """Every module that defines jitted functions (it uses a ``*_jit`` decorator of
    fricstab._numba or numba's own) is watched, and the command line is not."""
    watched = {p.relative_to(PACKAGE).as_posix() for p in jit_sources()}
    for p in PACKAGE.rglob("*.py"):
        text = p.read_text()
        if "@hot_jit" in text or "@kernel_jit" in text or "@threads_jit" in text \
                or "@hot_inline_jit" in text or "numba.njit(" in text:
            assert p.relative_to(PACKAGE).as_posix() in watched, p
    assert {"engine/passes.py", "generated/charan.py", "_numerics.py"} <= watched
    assert "cli/__init__.py" not in watched and "cli/shear.py" not in watched


@pytest.mark.skipif(os.geteuid() == 0, reason="root may delete from a read-only directory")
def test_read_only_cache_directory_is_left_alone(tmp_path):
    root = _package(tmp_path)
    _cache_files(root)
    for d in (root / "__pycache__", root / "sub" / "__pycache__"):
        d.chmod(0o555)
    try:
        assert purge_stale_cache(root) == 0     # nothing deletable: no error, nothing claimed
    finally:
        for d in (root / "__pycache__", root / "sub" / "__pycache__"):
            d.chmod(0o755)
