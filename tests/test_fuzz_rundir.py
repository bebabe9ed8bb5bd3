"""Random sequences of run / kill / --force / --resume / edit-a-file / second writer.

The invariant (issue "Results that cannot go stale"): after every step the
result directory is one run's complete output, or the command (or a reader)
says why not.  Concretely, for the protocol under test:

* a command that exits 0 leaves a record whose manifest verifies
  (:func:`fricstab.io.rundir.verify`), whose fingerprint is that of the
  command's own parameters, no journal, no lock and no temporary file;
* a command that exits non-zero says so in one line; a refusal (exit 2)
  changes no byte of the directory;
* whenever a reader accepts the directory, it holds the output of the last
  run that succeeded, untouched since: a kill, a hand edit or an interrupted
  run makes readers refuse, naming why, until a run succeeds again.

A kill is simulated in-process at a random file write (``os.replace`` raises
a BaseException the command line does not catch, leaving the temporary file
as SIGKILL would); the killed process's lock stays behind with a dead pid.
Hand edits (issue 39): a byte of a listed file; the record (a parameter
changed, ``files`` or the digest ``record_sha256`` deleted): readers refuse;
the step counter of the latest checkpoint (checksum recomputed, as one who
knows the format would): ``--resume`` refuses until a run succeeds again.
For ``aqs`` (a 16-disk packing made once per module) a reader's acceptance
also means that the ``events/birth_*`` folders are those ``aqs.json`` lists,
each holding its birth.  ``FRICSTAB_FUZZ_EXAMPLES`` sets the number of
sequences (default 100; the aqs variant runs a tenth, at least 10).
"""

import json
import os
import platform
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from fricstab.cli import main
from fricstab.errors import ParameterError
from fricstab.io import rundir
from tests.test_harden_records import _edit_step, aqs_folders_match_record

EXAMPLES = int(os.environ.get("FRICSTAB_FUZZ_EXAMPLES", "100"))

#: Two parameter sets of each command (a fast ramp of 4 disks; short dynamics, 12 Verlet
#: steps with checkpoints every 5, or 24 steps with none; AQS of 4 or 5 strain steps with
#: births located at steps 3 and 4), and the fingerprint key that tells them apart:
#: (protocol, key, command line, variants, values, resumable, kill scale (m, c): a kill step
#: of count b kills at file write m*b + c; AQS at 3..21, its checkpoints at writes 4, 21).
CKPT = ["--checkpoint-every", "5"]
AQS = ["packing", "aqs", "--law", "charan", "--dgamma", "2e-3", "--tol", "5e-4",
       "--checkpoint-every", "2", "--packing", "{packing}"]
COMMANDS = {
    "ramp": ("ramp", "fx_max", ["chain", "ramp", "--n", "4"],
             [["--fx-max", "0.002"], ["--fx-max", "0.003"]], [0.002, 0.003], False, (1, 0)),
    "dynamics": ("dynamics", "duration_paper_units", ["chain", "dynamics", "--n", "4"],
                 [["--fx", "0.002", "--duration", "1", *CKPT],
                  ["--fx", "0.002", "--duration", "2"]],
                 [1.0, 2.0], True, (1, 0)),
    "aqs": ("aqs", "strain", AQS, [["--strain", "0.008"], ["--strain", "0.01"]],
            [0.008, 0.01], True, (3, 3)),
}
_PACKING = {}


def _packing(tmp_path_factory):
    """A 16-disk packing (made once per module; charan AQS births at strain steps 3, 4)."""
    if "path" not in _PACKING:
        pk = tmp_path_factory.mktemp("packing16") / "P16"
        assert main(["packing", "make", "--n", "16", "--out", str(pk), "--quiet",
                     "--no-progress"]) == 0
        _PACKING["path"] = str(pk)
    return _PACKING["path"]


def _argv(command, a, d, tmp_path_factory):
    """The command line of variant ``a`` of ``command`` into ``d``."""
    _, _, head, variants, _, _, _ = COMMANDS[command]
    head = [_packing(tmp_path_factory) if w == "{packing}" else w for w in head]
    return [*head, *variants[a % 2], "--out", str(d), "--quiet", "--no-progress"]


def _flags(command, flag):
    """``flag`` as a list, without ``--resume`` for a command that has none."""
    return [flag] if flag and (flag != "--resume" or COMMANDS[command][5]) else []


class Killed(BaseException):
    """What SIGKILL would do at a file write: nothing after it runs."""


def _snapshot(d):
    return {str(p.relative_to(d)): p.read_bytes() for p in sorted(Path(d).rglob("*"))
            if p.is_file()} if Path(d).exists() else None


def _dead_pid():
    proc = subprocess.Popen([sys.executable, "-c", "pass"])
    proc.wait()
    return proc.pid


def _reader(d, protocol):
    """The record a reader accepts, or the reason it refuses (a ParameterError)."""
    try:
        return rundir.verify(d, protocol), None
    except ParameterError as exc:
        return None, str(exc)


def _lock(d, pid, protocol, command):
    (d / rundir.LOCK).write_text(json.dumps(
        {"pid": pid, "host": platform.node(), "start": None, "protocol": protocol,
         "command": command}))


def _killed_run(monkeypatch, argv, limit):
    """Run ``argv`` in-process, killed at its (limit+1)-th file write; None if killed,
    else the exit status."""
    real, calls = os.replace, [0]

    def replace(src, dst):
        calls[0] += 1
        if calls[0] > limit:
            raise Killed()
        return real(src, dst)

    monkeypatch.setattr(os, "replace", replace)
    try:
        return main(argv)
    except Killed:
        return None
    finally:
        monkeypatch.setattr(os, "replace", real)


steps = st.one_of(
    st.tuples(st.just("run"), st.integers(0, 1), st.sampled_from(["", "--force", "--resume"])),
    st.tuples(st.just("kill"), st.integers(0, 1), st.integers(0, 6)),
    st.tuples(st.just("edit"), st.integers(0, 10 ** 6), st.integers(1, 255)),
    st.tuples(st.just("writer"), st.just(0), st.just(0)),
    st.tuples(st.just("record"), st.integers(0, 2), st.integers(0, 10 ** 6)),
    st.tuples(st.just("counter"), st.integers(0, 2), st.just(0)),
)
#: A record edited by hand: a parameter changed, the manifest or the digest deleted.
RECORD_EDITS = [lambda r: r["parameters"].update(edited=True),   # (twice: already edited)
                lambda r: r.pop("files", None), lambda r: r.pop(rundir.DIGEST, None)]
#: A checkpoint's step counter edited (checksum recomputed): (counter, renamed to match).
COUNTER_EDITS = [(-5, False), (10 ** 9, False), (10 ** 9, True)]


SETTINGS = dict(deadline=None,
                suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])


@pytest.mark.parametrize("command", ["dynamics", "ramp"])
@settings(max_examples=EXAMPLES, **SETTINGS)
@given(seq=st.lists(steps, min_size=1, max_size=6))
@example(seq=[("kill", 0, 6)])   # killed after its record: found by CI's run
@example(seq=[("run", 0, ""), ("edit", 3, 7), ("run", 1, "--force"), ("writer", 0, 0)])
# issue 39: a resumed run whose journal named checkpoints/ listed them in its record
@example(seq=[("kill", 0, 2), ("run", 0, "--resume")])
@example(seq=[("run", 0, ""), ("record", 1, 0), ("run", 0, ""), ("run", 1, "--force")])
@example(seq=[("kill", 0, 4), ("counter", 1, 0), ("run", 0, "--resume"), ("run", 0, "")])
def test_directory_is_one_runs_output_or_says_why_not(command, seq, tmp_path_factory, capsys,
                                                      monkeypatch):
    _sequence(command, seq, tmp_path_factory, capsys, monkeypatch)


# AQS: about 0.4 s CPU a run against 0.05 s for the chain commands, so a tenth of the
# sequences in the default run (10, ~10 s); FRICSTAB_FUZZ_EXAMPLES=1000 gives 100
@settings(max_examples=max(EXAMPLES // 10, 10), **SETTINGS)
@given(seq=st.lists(steps, min_size=1, max_size=6))
@example(seq=[("run", 0, ""), ("kill", 1, 6), ("run", 1, "--resume")])   # from step 4
@example(seq=[("kill", 1, 2), ("counter", 2, 0), ("run", 1, "--resume"), ("run", 1, "--force")])
def test_aqs_directory_and_its_event_folders(seq, tmp_path_factory, capsys, monkeypatch):
    _sequence("aqs", seq, tmp_path_factory, capsys, monkeypatch)


def _sequence(command, seq, tmp_path_factory, capsys, monkeypatch):
    """Run the steps ``seq`` of ``command`` into a new directory, checking the invariant."""
    protocol, key, _, _, values, _, scale = COMMANDS[command]
    d = tmp_path_factory.mktemp("fuzz") / "out"
    good = None            # the variant of the last run that succeeded, if untouched since
    counter = False        # a checkpoint's counter edited since: --resume must refuse
    for op, a, b in seq:
        argv = _argv(command, a, d, tmp_path_factory)
        if op == "run":
            before = _snapshot(d)
            rc = main(argv + _flags(command, b))
            err = capsys.readouterr().err
            if rc == 0:
                assert not (counter and b == "--resume"), "an edited checkpoint was resumed"
                rec, why = _reader(d, protocol)
                assert why is None, why
                assert rec["fingerprint"]["parameters"][key] == values[a]
                assert not rundir.journal_path(d, protocol).exists()
                assert not (d / rundir.LOCK).exists()
                assert not list(d.rglob("*.tmp"))
                good, counter = a, False
            else:
                assert err.startswith("fricstab: ") and err.count("\n") == 1, err
                if rc == 2:   # refused: nothing touched (but a dead writer's lock, taken over)
                    after = _snapshot(d)
                    if after is not None and before is not None:
                        assert after.pop(rundir.LOCK, None) in (None, before.pop(rundir.LOCK,
                                                                                 None))
                    assert after == before, err
        elif op == "kill":
            rc = _killed_run(monkeypatch, argv + ["--force"], scale[0] * b + scale[1])
            capsys.readouterr()
            counter = False    # --force removed the checkpoints
            if rc == 0:
                good = a
            elif rc is None and d.exists():   # the killed process's lock stays, pid dead
                _lock(d, _dead_pid(), protocol, "killed")
                rec, _ = _reader(d, protocol)
                if rec is not None and rec["fingerprint"]["parameters"][key] == values[a]:
                    good = a   # killed after its record was written: the run is complete
        elif op == "edit":
            rec, _ = _reader(d, protocol)
            files = sorted((rec or {}).get("files", {}))
            if not files:
                continue
            p = d / files[a % len(files)]
            data = bytearray(p.read_bytes())
            if not data:
                continue
            data[a % len(data)] ^= b
            p.write_bytes(bytes(data))
            rec, why = _reader(d, protocol)
            assert rec is None and files[a % len(files)] in why, why
            good = None
        elif op == "record":
            record = d / f"{protocol}.json"
            if not record.is_file():
                continue
            doc = json.loads(record.read_text())
            RECORD_EDITS[a](doc)
            record.write_text(json.dumps(doc, indent=b % 3))
            rec, why = _reader(d, protocol)
            assert rec is None and record.name in why and "--force" in why, why
            good = None
        elif op == "counter":
            ckpts = sorted((d / "checkpoints").glob("ckpt_*.npz")) \
                if (d / "checkpoints").is_dir() else []
            if not ckpts:
                continue
            _edit_step(ckpts[-1], *COUNTER_EDITS[a])   # the latest: the one --resume takes
            counter = True
        elif op == "writer":
            if not d.exists():
                continue
            _lock(d, os.getppid(), protocol, "another run")   # a live process
            before = _snapshot(d)
            rc = main(argv + ["--force"])
            err = capsys.readouterr().err
            assert rc == 2 and "being written by another fricstab run" in err, err
            assert _snapshot(d) == before
            (d / rundir.LOCK).unlink()
        # the invariant of every step: a reader accepts only the last good run, untouched
        rec, why = _reader(d, protocol) if d.exists() else (None, "no directory")
        if rec is not None:
            assert good is not None, "a reader accepts a directory no run completed"
            assert rec["fingerprint"]["parameters"][key] == values[good]
            if protocol == "aqs":   # the event folders are those aqs.json lists, and theirs
                aqs_folders_match_record(d)
        else:
            assert why
            good = None   # a kill that removed the old result: nothing to accept


refusals = st.tuples(st.sampled_from(["late", "host"]), st.integers(0, 1),
                     st.sampled_from(["", "--force", "--resume"]), st.integers(1, 8))


@pytest.mark.parametrize("command", ["dynamics", "ramp"])
@settings(max_examples=max(EXAMPLES // 4, 10), **SETTINGS)
@given(setup=st.lists(steps.filter(lambda s: s[0] in ("run", "kill")), max_size=3),
       refusal=refusals)
@example(setup=[], refusal=("late", 0, "", 1))   # a new --out: it is not created
@example(setup=[("run", 0, "")], refusal=("late", 1, "--force", 3))
def test_refused_runs_leave_nothing_new_in_out(command, setup, refusal, tmp_path_factory,
                                               capsys, monkeypatch):
    """Issue 39: a refused run (exit 2), wherever in the run the refusal comes, adds nothing
    to ``--out``: not the folder itself, no journal, record or file, no changed byte; a
    ``--force`` run refused after removing the old result leaves no new file either.

    ``late``: a ParameterError at the k-th file write (after the directory is taken);
    ``host``: the directory's lock held by a writer on another host.
    """
    from fricstab.io import results
    protocol = COMMANDS[command][0]
    d = tmp_path_factory.mktemp("refuse") / "out"
    for op, a, b in setup:   # an earlier state: a result, an interrupted run, or none
        argv = _argv(command, a, d, tmp_path_factory)
        if op == "run":
            main(argv + _flags(command, b))
        else:
            try:
                if _killed_run(monkeypatch, argv + ["--force"], b) is None and d.exists():
                    _lock(d, _dead_pid(), protocol, "killed")
            finally:
                results.release_all()
        capsys.readouterr()
    kind, a, flag, k = refusal
    if kind == "host" and not d.exists():
        d.mkdir()
    if kind == "host":
        (d / rundir.LOCK).write_text(json.dumps(
            {"pid": 1, "host": "elsewhere.invalid", "start": None, "protocol": protocol,
             "command": "another run"}))
    before = _snapshot(d)
    argv = _argv(command, a, d, tmp_path_factory) + _flags(command, flag)
    real, calls = os.replace, [0]

    def refuse(src, dst):
        calls[0] += 1
        if kind == "late" and calls[0] == k:
            raise ParameterError("refused late")
        return real(src, dst)

    monkeypatch.setattr(os, "replace", refuse)
    try:
        rc = main(argv)
    finally:
        monkeypatch.setattr(os, "replace", real)
    err = capsys.readouterr().err
    if rc != 2:
        assert kind == "late" and rc == 0, err   # the run completed in fewer writes
        return
    assert err.startswith("fricstab: error:") and err.count("\n") == 1, err
    after = _snapshot(d)
    if kind == "late" and before is not None:   # a dead writer's lock: any run takes it over
        assert after is not None
        assert after.pop(rundir.LOCK, None) in (None, before.pop(rundir.LOCK, None))
    if flag != "--force" or kind == "host":
        assert after == before, err
    else:   # --force removed the previous result; nothing new came
        assert (after is None) if before is None else after is not None, err
        assert all(before.get(name) == data for name, data in (after or {}).items()), err
    if after is not None:
        assert not list(d.rglob("*.tmp"))
