"""Guards of a recording: the stamp names the code that ran; oversubscribed threads named.

An edit on disk while a computation runs: its stamp names the code that ran.

A long run (a precursor path, an Ishima piece, a claim) hashes the modules it executed when
it saves; a file edited meanwhile must not lend the run its new hashes.  The fingerprint
hashes such a file from the text this process loaded (``SNAPSHOT``), or, where that is
unknown, records ``EDITED`` (stale at once).
"""

import os
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from claims import fingerprint as fp  # noqa: E402

import fricstab.errors  # noqa: E402

M = "fricstab/errors.py"


def _mtime():
    return (fp.ROOT / M).stat().st_mtime


def test_an_untouched_file_is_hashed_as_it_is(monkeypatch):
    monkeypatch.setattr(fp, "STARTED", _mtime() + 10)
    assert fp._source(M, fp.ROOT) == ((fp.ROOT / M).read_text(), False)


def test_a_file_edited_while_running_is_hashed_as_loaded(monkeypatch):
    text = (fp.ROOT / M).read_text()
    loaded = text + "\n_GONE = 1\n"      # the text before the "edit" (a constant: the frame)
    monkeypatch.setattr(fp, "STARTED", _mtime() - 10)
    monkeypatch.setitem(fp.SNAPSHOT, M, (loaded, _mtime() - 20))
    assert fp._source(M, fp.ROOT) == (loaded, False)
    with fp.Tracer() as tracer:
        fricstab.errors.check_real("x", 1.0, 0.0)
    units = fp.code_units(tracer)
    assert units[M]["check_real"] == fp.unit_hashes(loaded)["check_real"]
    # the edit removed a constant: the frame the run saw is not the file's
    assert M in fp.units_changed(units)


def test_a_file_edited_before_the_snapshot_is_stale_at_once(monkeypatch):
    monkeypatch.setattr(fp, "STARTED", _mtime() - 10)
    monkeypatch.setitem(fp.SNAPSHOT, M, ((fp.ROOT / M).read_text(), _mtime() - 5))
    with fp.Tracer() as tracer:
        fricstab.errors.check_real("x", 1.0, 0.0)
    units = fp.code_units(tracer)
    assert set(units[M].values()) == {fp.EDITED}
    assert M in fp.units_changed(units)


@pytest.mark.skipif(not Path("/proc/uptime").exists(), reason="the start time is read from /proc")
def test_the_process_start_is_never_late_and_hardly_early(tmp_path):
    """A file written just before a process starts (``git clone`` then ``pytest``) is not an
    edit while it ran.  A child process's STARTED lies between the moment before it was
    spawned, less the estimate's margin (two clock ticks and two hundredths of a second of
    /proc/uptime: 0.04 s at 100 ticks/s) and as much again for the floors of both readings,
    and the moment it imported the module (it is never later than that).
    The old estimate from /proc/stat's whole-second ``btime`` less a second was 1-2 s early."""
    import subprocess
    import time
    tick = 1.0 / os.sysconf("SC_CLK_TCK")
    before = time.time()
    out = subprocess.run([sys.executable, "-c", "import sys, time; sys.path.insert(0, "
                          f"{str(HERE)!r}); from claims import fingerprint as fp; "
                          "print(fp.STARTED, time.time())"],
                         capture_output=True, text=True, check=True).stdout.split()
    started, imported = float(out[0]), float(out[1])
    assert before - 4 * (tick + 0.01) <= started <= imported


def test_a_module_imported_after_the_snapshot_ran_its_text(monkeypatch):
    """A file written after the process started but before the snapshot (a clone just before
    pytest): its module, imported after the snapshot from the unchanged file, ran the
    snapshot's text; imported before it, the text that ran is unknown; and a file changed
    since the snapshot is unknown either way."""
    text = (fp.ROOT / M).read_text()
    monkeypatch.setattr(fp, "STARTED", _mtime() - 10)
    monkeypatch.setitem(fp.SNAPSHOT, M, (text, _mtime()))
    monkeypatch.setattr(fp, "PRELOADED", frozenset())
    assert fp._source(M, fp.ROOT) == (text, False)
    monkeypatch.setattr(fp, "PRELOADED", frozenset({M}))
    assert fp._source(M, fp.ROOT) == (text, True)
    monkeypatch.setattr(fp, "PRELOADED", frozenset())
    monkeypatch.setitem(fp.SNAPSHOT, M, (text, _mtime() - 5))
    assert fp._source(M, fp.ROOT) == (text, True)


def test_another_root_is_never_snapshotted(tmp_path):
    (tmp_path / "fricstab").mkdir()
    (tmp_path / M).write_text("X = 1\n")
    assert fp._source(M, tmp_path) == ("X = 1\n", False)


def test_reproduce_warns_of_oversubscribed_threads():
    import reproduce
    ones = {v: "1" for v in reproduce.THREAD_VARS}
    busy = reproduce.oversubscribed(load=3.0, cores=2, env={})
    assert busy and "NUMBA_NUM_THREADS=1" in busy and "load 3.0 on 2 cores" in busy
    assert reproduce.oversubscribed(load=3.0, cores=2, env=ones) is None
    assert reproduce.oversubscribed(load=0.1, cores=2, env={}) is None
    assert reproduce.oversubscribed(load=3.0, cores=1, env={}) is None
