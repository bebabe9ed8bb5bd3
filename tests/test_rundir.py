"""A result directory owns its run: lock, journal, manifest, fingerprint, signals."""

import json
import os
import signal
import subprocess
import sys

import numpy as np
import pytest

from fricstab.errors import ParameterError
from fricstab import signals
from fricstab.io import rundir
from fricstab.io.results import ResultDir


def _run(path, name="demo", force=False, resume=False, params=None, files=("a.npz",),
         finish=True):
    rd = ResultDir(path, name, force=force, resume=resume, fingerprint=params or {"x": 1})
    rd.create()
    for f in files:
        rd.write_npz(f, a=np.arange(3))
    if finish:
        return rd.finish({"n": 1}, parameters=params or {"x": 1})
    rd.close()
    return rd


def test_record_lists_every_file_with_size_and_hash_and_readers_check_it(tmp_path):
    doc = _run(tmp_path, files=("a.npz", "sub/b.npz"))
    assert set(doc["files"]) == {"a.npz", "sub/b.npz"}
    assert doc["fingerprint"]["parameters"] == {"x": 1}
    assert rundir.verify(tmp_path, "demo")["n"] == 1
    with open(tmp_path / "sub" / "b.npz", "ab") as fh:
        fh.write(b"x")
    with pytest.raises(ParameterError, match=r"sub/b.npz does not match the demo record"):
        rundir.verify(tmp_path, "demo")
    (tmp_path / "a.npz").unlink()
    with pytest.raises(ParameterError, match=r"a.npz is missing"):
        rundir.verify(tmp_path, "demo", files=["a.npz"])


def test_a_second_writer_is_refused_naming_the_holder(tmp_path):
    rd = ResultDir(tmp_path, "demo", fingerprint={}).create()
    with pytest.raises(ParameterError, match=rf"being written by another fricstab run \(pid "
                                              rf"{os.getpid()}"):
        ResultDir(tmp_path, "other", fingerprint={}).create()
    rd.close()
    ResultDir(tmp_path, "other", fingerprint={}).create().close()


def test_a_stale_lock_of_a_dead_process_is_taken_over(tmp_path):
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    (tmp_path / rundir.LOCK).write_text(json.dumps({"pid": dead.pid, "host": os.uname().nodename,
                                                    "start": None, "protocol": "x"}))
    ResultDir(tmp_path, "demo", fingerprint={}).create().close()
    assert not (tmp_path / rundir.LOCK).exists()


def test_force_removes_the_previous_run_and_nothing_else(tmp_path):
    _run(tmp_path, files=("a.npz", "frames/c1.npz", "frames/c2.npz"))
    (tmp_path / "notes.txt").write_text("mine")
    _run(tmp_path, name="other", files=("o.npz",))
    doc = _run(tmp_path, force=True, files=("a.npz",))
    assert set(doc["files"]) == {"a.npz"}
    assert not (tmp_path / "frames").exists()
    assert (tmp_path / "notes.txt").read_text() == "mine"
    assert rundir.verify(tmp_path, "other")


def test_an_interrupted_run_is_refused_then_resumed_or_removed(tmp_path):
    _run(tmp_path, files=("a.npz", "frames/c1.npz"), finish=False)
    with pytest.raises(ParameterError, match="an interrupted demo run"):
        ResultDir(tmp_path, "demo", fingerprint={"x": 1})
    with pytest.raises(ParameterError, match=r"other parameters \(x: 1 there, 2 now\)"):
        ResultDir(tmp_path, "demo", resume=True, fingerprint={"x": 2})
    with pytest.raises(ParameterError, match="no complete demo result"):
        rundir.verify(tmp_path, "demo")
    doc = _run(tmp_path, resume=True, files=("frames/c2.npz",))
    assert set(doc["files"]) == {"a.npz", "frames/c1.npz", "frames/c2.npz"}
    _run(tmp_path, files=("x.npz",), finish=False, force=True)
    assert not (tmp_path / "a.npz").exists() and not (tmp_path / "frames").exists()


def test_checkpoints_are_transient(tmp_path):
    rd = ResultDir(tmp_path, "demo", fingerprint={}).create()
    ck = rd.checkpoints()
    ck.mkdir()
    (ck / "ckpt_000000000001.npz").write_bytes(b"1")
    rd.write_npz("a.npz", a=np.zeros(1))
    doc = rd.finish({}, parameters={})
    assert not ck.exists() and set(doc["files"]) == {"a.npz"}


def test_a_hand_edited_journal_cannot_reach_outside(tmp_path):
    out = tmp_path / "out"
    _run(out, files=("a.npz",), finish=False)
    (tmp_path / "precious").write_text("keep")
    j = rundir.journal_path(out, "demo")
    doc = json.loads(j.read_text())
    doc["files"].append("../precious")
    j.write_text(json.dumps(doc))
    _run(out, force=True, files=("a.npz",))
    assert (tmp_path / "precious").read_text() == "keep"


def test_signals_become_a_flag_checked_between_chunks():
    with signals.interruptible():
        signals.check()
        os.kill(os.getpid(), signal.SIGTERM)
        assert signals.pending() == signal.SIGTERM
        with pytest.raises(signals.Interrupted) as err:
            signals.check(" at step 5")
        assert err.value.exit_code == 143 and "SIGTERM at step 5" in str(err.value)
    assert signals.pending() is None
