"""The guard against stale numba cache files (fricstab._numba.purge_stale_cache).

numba keys a cached function on its own source file only, so a change in a
kernel it inlines from another file would leave stale machine code: the
guard deletes the package's cached code whenever any of its sources changed.
"""

import os

import pytest

from fricstab._numba import purge_stale_cache


def _package(tmp_path):
    root = tmp_path / "pkg"
    (root / "sub" / "__pycache__").mkdir(parents=True)
    (root / "__pycache__").mkdir()
    (root / "a.py").write_text("x = 1\n")
    (root / "sub" / "b.py").write_text("y = 2\n")
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
    (root / "sub" / "b.py").write_text("y = 3\n")   # a callee's file changes
    assert purge_stale_cache(root) == 3
    assert not list(root.rglob("*.nb[ic]"))
    (root / "c.py").write_text("")                # a new source file counts too
    _cache_files(root)
    assert purge_stale_cache(root) == 3


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
