"""Issue 39 (hardening), result directories: a refused run writes nothing, ``--force``
removes only what the previous run wrote, a second writer is told who holds the lock.

* A refused run (exit 2), wherever the refusal comes, leaves nothing new in
  ``--out``: no journal, record, index, packing, ``frames/``, and no ``--out``
  folder if it did not exist (:func:`fricstab.io.results.abandon_all`).
* ``--force`` removes exactly the files the previous run's record lists: a file
  someone put into one of the run's folders stays, and is not in the new manifest.
* A second writer is refused naming the holder (pid, host, command), not as an
  "interrupted run"; ``shear export`` onto a folder named like its file is refused.

Tiny systems: packings of 16 disks, a 4-disk chain ramp, a 20-disk shear cell.
"""

import hashlib
import json
import platform
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from fricstab.cli import main
from fricstab.io import rundir

SHEAR = ["--n", "20", "--strain", "0.001", "--dgamma", "1e-4", "--checkpoint-every", "5"]
AQS = ["--n", "16", "--strain", "0.004", "--dgamma", "1e-3"]


def _main(argv, capsys):
    rc = main([*argv, "--no-progress"] if argv[:2] != ["shear", "export"] else argv)
    return rc, capsys.readouterr().err


def _tree(folder):
    """Every file and folder under ``folder`` (hidden ones too), files with their SHA-256."""
    folder = Path(folder)
    if not folder.exists():
        return None
    return {str(p.relative_to(folder)): (hashlib.sha256(p.read_bytes()).hexdigest()
                                         if p.is_file() else "folder")
            for p in sorted(folder.rglob("*"))}


def _one_line_refusal(rc, err):
    assert rc == 2 and err.startswith("fricstab: error:") and err.count("\n") == 1, err


@pytest.fixture(scope="module")
def p16(tmp_path_factory):
    out = tmp_path_factory.mktemp("p16") / "P16"
    assert main(["packing", "make", "--n", "16", "--out", str(out), "--quiet",
                 "--no-progress"]) == 0
    return out


def _bad_packing(p16, tmp, what):
    d = dict(np.load(p16 / "packing.npz", allow_pickle=False))
    if what == "nan":
        d["pos"] = d["pos"].copy()
        d["pos"][3, 0] = np.nan
    else:
        d["box"] = np.float64(0.0)
    path = tmp / f"{what}.npz"
    np.savez(path, **d)
    return path


#: Commands refused by their input, some only once the computation has started.
REFUSED = {
    "make_phi_0.6": lambda p16, tmp: ["packing", "make", "--phi", "0.6", "--n", "16"],
    "rigidity_z_th": lambda p16, tmp: ["packing", "rigidity", "--packing", str(p16),
                                       "--z-th", "1000"],
    "rigidity_nan_position": lambda p16, tmp: ["packing", "rigidity", "--packing",
                                               str(_bad_packing(p16, tmp, "nan"))],
    "dos_zero_box": lambda p16, tmp: ["packing", "dos", "--packing",
                                      str(_bad_packing(p16, tmp, "box"))],
    "shear_n_4": lambda p16, tmp: ["shear", "run", "--n", "4", "--strain", "0.001",
                                   "--dgamma", "1e-4"],
    "aqs_n_4": lambda p16, tmp: ["packing", "aqs", "--n", "4", "--strain", "0.004",
                                 "--dgamma", "1e-3"],
}


@pytest.mark.parametrize("existing", [False, True], ids=["new_out", "existing_out"])
@pytest.mark.parametrize("case", sorted(REFUSED))
def test_refused_run_leaves_nothing_new_in_out(case, existing, p16, tmp_path, capsys):
    out = tmp_path / "D"
    if existing:   # a folder of the user's: it keeps its bytes, and gains nothing
        out.mkdir()
        (out / "notes.txt").write_text("mine\n")
    before = _tree(out)
    rc, err = _main([*REFUSED[case](p16, tmp_path), "--out", str(out)], capsys)
    _one_line_refusal(rc, err)
    assert _tree(out) == before, err


@pytest.mark.parametrize("force", [False, True], ids=["plain", "force"])
@pytest.mark.parametrize("argv", [["packing", "make", "--n", "16"],
                                  ["packing", "rigidity"],
                                  ["packing", "aqs", *AQS],
                                  ["chain", "ramp", "--n", "4", "--fx-max", "0.002"]],
                         ids=["make", "rigidity", "aqs", "ramp"])
def test_lock_of_another_hosts_writer_refuses_and_adds_nothing(argv, force, p16, tmp_path,
                                                                capsys):
    out = tmp_path / "Q"
    out.mkdir()
    for f in p16.iterdir():
        (out / f.name).write_bytes(f.read_bytes())
    (out / rundir.LOCK).write_text(json.dumps(
        {"pid": 1, "host": "another-host.invalid", "start": None, "protocol": "packing",
         "command": "packing make --n 16", "since": "2026-01-01T00:00:00"}))
    before = _tree(out)
    rc, err = _main([*argv, "--out", str(out), *(["--force"] if force else [])], capsys)
    _one_line_refusal(rc, err)
    assert "another-host.invalid" in err and "pid 1" in err
    assert _tree(out) == before


def test_refusal_after_the_directory_is_taken_is_undone(tmp_path, capsys, monkeypatch):
    """Structural: a ParameterError raised once the run has written files (here: at the
    record) still leaves nothing new, with and without an earlier result there."""
    import fricstab.io.results as results
    from fricstab.errors import ParameterError
    out = tmp_path / "R"
    argv = ["chain", "ramp", "--n", "4", "--fx-max", "0.002", "--out", str(out), "--quiet"]
    real = results.write_json

    def refuse(path, doc):
        if Path(path).name == "ramp.json":
            raise ParameterError("refused late")
        return real(path, doc)

    monkeypatch.setattr(results, "write_json", refuse)
    rc, err = _main(argv, capsys)
    _one_line_refusal(rc, err)
    assert not out.exists()
    monkeypatch.setattr(results, "write_json", real)
    assert _main(argv, capsys)[0] == 0
    (out / "notes.txt").write_text("mine\n")
    before = _tree(out)
    monkeypatch.setattr(results, "write_json", refuse)
    rc, err = _main([*argv[:-3], "--fx-max", "0.003", "--out", str(out), "--quiet", "--force"],
                    capsys)
    _one_line_refusal(rc, err)   # --force removed the old result; nothing new came
    after = _tree(out)
    assert set(after) <= set(before) and after["notes.txt"] == before["notes.txt"]
    assert all(after[k] == before[k] for k in after)
    assert not rundir.journal_path(out, "ramp").exists() and not (out / rundir.LOCK).exists()


# --force keeps what the previous run did not write --------------------------------------

#: command, protocol, the files planted into the run's folders (after a first run).
FORCED = {
    "ramp": (["chain", "ramp", "--n", "4", "--fx-max", "0.002"], "ramp",
             ["notes.txt", "ramp.npz.d/README"]),
    "rigidity": (["packing", "rigidity", "--n", "16"], "rigidity",
                 ["ishima/README", "notes/a.txt"]),
    "shear": (["shear", "run", *SHEAR], "shear", ["frames/README", "frames/mine/x.txt"]),
    "aqs": (["packing", "aqs", *AQS], "aqs", ["events/note.txt", "events/birth_99_lo/mine"]),
}


@pytest.mark.parametrize("case", sorted(FORCED))
def test_force_removes_exactly_what_the_previous_run_wrote(case, tmp_path, capsys):
    argv, protocol, planted = FORCED[case]
    out = tmp_path / case
    rc, err = _main([*argv, "--out", str(out), "--quiet"], capsys)
    assert rc == 0, err
    first = rundir.verify(out, protocol)
    for rel in planted:
        (out / rel).parent.mkdir(parents=True, exist_ok=True)
        (out / rel).write_text(f"{rel}: the user's\n")
    rc, err = _main([*argv, "--out", str(out), "--quiet", "--force"], capsys)
    assert rc == 0, err
    for rel in planted:
        assert (out / rel).read_text() == f"{rel}: the user's\n", rel
    second = rundir.verify(out, protocol)   # the new run is complete, and its own
    assert set(second["files"]) == set(first["files"])
    assert not set(planted) & set(second["files"])
    assert second["started"] >= first["started"]
    # and once more: the planted files are still not the run's, so --force keeps them
    rc, err = _main([*argv, "--out", str(out), "--quiet", "--force"], capsys)
    assert rc == 0, err
    assert all((out / rel).is_file() for rel in planted)


def test_force_of_an_interrupted_run_keeps_what_its_folder_held_before(tmp_path, capsys):
    """A journal lists the run's folders, not each file: what the folder held before the
    run took it (``kept``) survives ``--force``; the run's own files there go."""
    out = tmp_path / "S"
    (out / "frames").mkdir(parents=True)
    (out / "frames" / "README").write_text("mine\n")
    from fricstab.io.results import ResultDir
    rd = ResultDir(out, "shear").create()
    rd.register("frames", folder=True)
    (out / "frames" / "chunk_000000.npz").write_bytes(b"run's")
    rd.close()   # interrupted: the journal stays
    journal = json.loads(rundir.journal_path(out, "shear").read_text())
    assert journal["kept"] == ["frames/README"]
    rundir.remove_run(out, "shear")
    assert (out / "frames" / "README").read_text() == "mine\n"
    assert not (out / "frames" / "chunk_000000.npz").exists()
    assert not rundir.journal_path(out, "shear").exists()


# the lock holder, by name; export onto a folder ---------------------------------------------

def test_second_writer_is_told_who_holds_the_lock_not_an_interrupted_run(tmp_path, capsys):
    out = tmp_path / "W"
    out.mkdir()
    holder = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    try:
        (out / rundir.LOCK).write_text(json.dumps(
            {"pid": holder.pid, "host": platform.node(), "start": rundir._start_time(holder.pid),
             "protocol": "ramp", "command": "chain ramp --fx-max 0.1", "since": "now"}))
        rundir.write_journal(out, "ramp", None, ["ramp.npz"], [])   # the holder's run
        before = _tree(out)
        for extra in ([], ["--force"]):
            rc, err = _main(["chain", "ramp", "--n", "4", "--fx-max", "0.002", "--out",
                             str(out), *extra], capsys)
            _one_line_refusal(rc, err)
            assert f"pid {holder.pid}" in err and platform.node() in err, err
            assert "chain ramp --fx-max 0.1" in err and "interrupted" not in err, err
            assert _tree(out) == before
    finally:
        holder.kill()
        holder.wait()


@pytest.fixture(scope="module")
def shear_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("shear") / "S"
    assert main(["shear", "run", *SHEAR, "--out", str(out), "--quiet", "--no-progress"]) == 0
    return out


@pytest.mark.parametrize("fmt, name", [("extxyz", "frames.xyz"), ("lammps", "frames.dump")])
@pytest.mark.parametrize("force", [False, True], ids=["plain", "force"])
def test_export_onto_a_folder_named_like_its_file_is_refused(shear_run, fmt, name, force,
                                                             capsys):
    target = shear_run / name
    target.mkdir()
    (target / "mine.txt").write_text("mine\n")
    try:
        before = _tree(shear_run)
        rc, err = _main(["shear", "export", "--out", str(shear_run), "--format", fmt,
                         *(["--force"] if force else [])], capsys)
        _one_line_refusal(rc, err)
        assert name in err and "folder" in err
        assert _tree(shear_run) == before
    finally:
        (target / "mine.txt").unlink()
        target.rmdir()
