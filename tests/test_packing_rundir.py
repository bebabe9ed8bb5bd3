"""``fricstab packing ...`` results cannot go stale: one packing per directory, checked reads, locks.

Every packing command writes through :class:`fricstab.io.results.ResultDir`;
the packing that rigidity/dos/jacobian make is a ``packing`` record of its own
(:mod:`fricstab.cli.packing_source`).  Small packings (N = 16) keep it fast.
"""

import hashlib
import json
import os
import platform
import shutil
import subprocess
import sys

import numpy as np
import pytest

from fricstab.cli import main
from fricstab.io import rundir
from fricstab.scenes.packing import Packing, make_packing

N, PHI = 16, 0.88
SMALL = ["--n", str(N), "--phi", str(PHI)]


def _main(argv, capsys):
    rc = main(argv + ["--no-progress"])
    return rc, capsys.readouterr().err


def _snapshot(folder):
    """Every file under ``folder`` (hidden ones too) with its SHA-256."""
    return {str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(folder.rglob("*")) if p.is_file()}


def _one_line_error(rc, err):
    assert rc == 2 and err.startswith("fricstab: error:") and err.count("\n") == 1, err
    assert "Traceback" not in err


@pytest.fixture(scope="module")
def seed0(tmp_path_factory):
    out = tmp_path_factory.mktemp("seed0") / "d"
    assert main(["packing", "make", *SMALL, "--seed", "0", "--out", str(out),
                 "--no-progress", "--quiet"]) == 0
    return out


@pytest.fixture
def d(seed0, tmp_path):
    """A fresh copy of the seed-0 packing directory (make's record, manifest intact)."""
    out = tmp_path / "d"
    shutil.copytree(seed0, out)
    return out


def _seed_of_content(folder):
    """The seed whose packing ``packing.npz`` holds, found by remaking seeds 0 and 1."""
    stored = Packing.load(folder / "packing.npz")
    for seed in (0, 1):
        if np.array_equal(make_packing(N, PHI, seed).pos, stored.pos):
            return seed
    return None


def test_force_with_another_seed_replaces_packing_and_its_record_together(d, capsys):
    rc, err = _main(["packing", "rigidity", *SMALL, "--seed", "1", "--kt", "1", "--no-modes",
                     "--force", "--out", str(d)], capsys)
    assert rc == 0, err
    pk = json.loads((d / "packing.json").read_text())
    rg = json.loads((d / "rigidity.json").read_text())
    assert _seed_of_content(d) == 1 == pk["seed"] == rg["seed"]
    assert pk["fingerprint"]["parameters"]["seed"] == 1
    assert rg["packing"]["sha256"] == pk["files"]["packing.npz"]["sha256"]
    assert rg["packing"]["origin"] == "made"
    assert not (d / "packing.png").exists()     # the seed-0 record's figure went with it
    rundir.verify(d, "packing")
    rundir.verify(d, "rigidity")
    index = json.loads((d / "result.json").read_text())
    assert index["protocols"] == ["packing", "rigidity"]
    assert index["records"]["packing"]["seed"] == 1


def test_replacing_the_packing_removes_the_results_made_from_it(d, capsys):
    rc, err = _main(["packing", "dos", "--packing", str(d), "--kt", "1", "--bins", "5",
                     "--out", str(d)], capsys)
    assert rc == 0, err
    rc, err = _main(["packing", "make", *SMALL, "--seed", "1", "--force", "--out", str(d)],
                    capsys)
    assert rc == 0, err
    assert "removed dos.json" in err and err.count("\n") == 1
    assert not (d / "dos.json").exists() and not (d / "dos.npz").exists()
    assert json.loads((d / "result.json").read_text())["protocols"] == ["packing"]
    assert _seed_of_content(d) == 1


def test_a_rerun_with_another_packing_is_refused_without_force_nothing_written(d, capsys):
    before = _snapshot(d)
    rc, err = _main(["packing", "rigidity", *SMALL, "--seed", "1", "--kt", "1",
                     "--out", str(d)], capsys)
    _one_line_error(rc, err)
    assert "seed: 0 there, 1 now" in err and "--force" in err
    assert _snapshot(d) == before
    # a result read from another packing may not join this directory either
    other = d.parent / "other"
    assert main(["packing", "make", *SMALL, "--seed", "1", "--out", str(other),
                 "--no-progress", "--quiet"]) == 0
    rc, err = _main(["packing", "dos", "--packing", str(other), "--kt", "1", "--out", str(d)],
                    capsys)
    _one_line_error(rc, err)
    assert "packing.json" in err and "another packing" in err and "seed: 0 there, 1 now" in err
    assert _snapshot(d) == before


def test_the_same_make_parameters_reuse_the_packing(d, capsys):
    before = (d / "packing.json").read_bytes()
    rc, err = _main(["packing", "dos", *SMALL, "--seed", "0", "--kt", "1", "--bins", "5",
                     "--out", str(d)], capsys)
    assert rc == 0, err
    assert (d / "packing.json").read_bytes() == before and (d / "packing.png").is_file()
    doc = json.loads((d / "dos.json").read_text())
    assert doc["packing"]["origin"] == "reused" and doc["seed"] == 0


@pytest.mark.parametrize("damage", ["byte", "missing", "interrupted"])
@pytest.mark.parametrize("cmd", ["rigidity", "dos"])
def test_a_damaged_packing_is_refused_by_readers(d, tmp_path, capsys, damage, cmd):
    npz = d / "packing.npz"
    if damage == "byte":
        data = bytearray(npz.read_bytes())
        data[len(data) // 2] ^= 0x01
        npz.write_bytes(bytes(data))
    elif damage == "missing":
        npz.unlink()
    else:   # a run killed after removing the old record, before writing the new one
        rundir.journal_path(d, "packing").write_text(json.dumps({"files": ["packing.npz"]}))
        (d / "packing.json").unlink()
    out = tmp_path / "e"
    for source in (str(d), str(npz)):
        rc, err = _main(["packing", cmd, "--packing", source, "--kt", "1", "--out", str(out)],
                        capsys)
        _one_line_error(rc, err)
        assert ("interrupted" if damage == "interrupted" else "packing.npz") in err
        assert not out.exists()
    if damage == "byte":
        assert "does not match" in err


def test_a_packing_from_before_manifests_is_read_with_a_warning(d, tmp_path, capsys):
    record = json.loads((d / "packing.json").read_text())
    del record["files"], record[rundir.DIGEST]   # as written before manifests (and digests)
    record["record_version"] = 1
    (d / "packing.json").write_text(json.dumps(record))
    rc, err = _main(["packing", "dos", "--packing", str(d), "--kt", "1", "--bins", "5",
                     "--out", str(tmp_path / "e")], capsys)
    assert rc == 0 and err.startswith("fricstab: warning:") and "no manifest" in err
    (d / "packing.json").unlink()                # a bare packing.npz: also read, warned
    rc, err = _main(["packing", "dos", "--packing", str(d), "--kt", "1", "--bins", "5",
                     "--out", str(tmp_path / "f")], capsys)
    assert rc == 0 and "no packing record" in err


def test_a_directory_from_before_records_is_replaced_only_with_force(d, capsys):
    """Old ``rigidity --out d``: packing.npz and a rigidity.json without manifests."""
    (d / "packing.json").unlink()
    (d / "packing.png").unlink()
    (d / "kt_1").mkdir()
    (d / "kt_1" / "g.json").write_text("{}")
    (d / "rigidity.png").write_bytes(b"png")
    (d / "rigidity.json").write_text(json.dumps({
        "protocol": "rigidity", "packing_source": "made by this command (packing.npz)",
        "results": [{"folder": "kt_1"}]}))
    argv = ["packing", "dos", *SMALL, "--seed", "0", "--kt", "1", "--bins", "5",
            "--out", str(d)]
    before = _snapshot(d)
    rc, err = _main(argv, capsys)
    _one_line_error(rc, err)
    assert "packing.npz without a packing record" in err and _snapshot(d) == before
    rc, err = _main(argv + ["--force"], capsys)
    assert rc == 0 and "removed rigidity.json" in err, err
    assert not (d / "kt_1").exists() and not (d / "rigidity.png").exists()
    rundir.verify(d, "packing")
    doc = rundir.verify(d, "dos")
    assert doc["packing"]["origin"] == "made"
    assert json.loads((d / "result.json").read_text())["protocols"] == ["dos", "packing"]


@pytest.fixture
def sleeper():
    proc = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(120)"])
    yield proc
    proc.kill()
    proc.wait()


def _lock(folder, pid):
    (folder / rundir.LOCK).write_text(json.dumps({
        "pid": pid, "host": platform.node(), "start": None, "protocol": "rigidity",
        "command": "packing rigidity --out d", "since": "2026-01-01T00:00:00"}))


@pytest.mark.parametrize("argv", [["make", *SMALL, "--seed", "1", "--force"],
                                  ["dos", "--packing", "{d}", "--kt", "1", "--bins", "5"]])
def test_a_live_lock_refuses_a_second_writer_a_dead_one_is_taken_over(d, sleeper, capsys,
                                                                       argv):
    argv = ["packing", *[a.replace("{d}", str(d)) for a in argv], "--out", str(d)]
    _lock(d, sleeper.pid)
    before = _snapshot(d)
    rc, err = _main(argv, capsys)
    _one_line_error(rc, err)
    assert f"pid {sleeper.pid} on {platform.node()}" in err and "packing rigidity" in err
    assert _snapshot(d) == before
    sleeper.kill()
    sleeper.wait()
    rc, err = _main(argv, capsys)
    assert rc == 0, err
    assert not (d / rundir.LOCK).exists()


@pytest.mark.parametrize("where", ["make", "step_strain"])
def test_a_failed_force_rerun_leaves_no_record_of_deleted_files(d, capsys, monkeypatch, where):
    """Killed by a failure while making the new packing, or after: result.json and every
    record list only files that are there; what is left is the new packing or none."""
    from fricstab.cli import packing_common
    from fricstab.errors import ConvergenceError
    from fricstab.protocols import stepstrain
    rc, err = _main(["packing", "rigidity", "--packing", str(d), "--kt", "1", "--no-modes",
                     "--out", str(d)], capsys)
    assert rc == 0, err

    def fail(*args, **kwargs):
        raise ConvergenceError("no convergence (test)")

    if where == "make":
        monkeypatch.setattr(packing_common, "make_packing", fail)
    else:
        monkeypatch.setattr(stepstrain, "step_strain", fail)
    rc, err = _main(["packing", "rigidity", *SMALL, "--seed", "1", "--kt", "1", "--no-modes",
                     "--force", "--out", str(d)], capsys)
    assert rc == 4, err
    assert not (d / "rigidity.json").exists()
    # an index left without records is removed (fricstab.io.results.update_index)
    index = (json.loads((d / "result.json").read_text()) if (d / "result.json").exists()
             else {"protocols": [], "records": {}})
    assert index["protocols"] == ([] if where == "make" else ["packing"])
    for name, rec in index["records"].items():
        assert rundir.verify(d, name) == rec       # every file each record lists is there
    if where == "make":
        assert not (d / "packing.json").exists() and not (d / "packing.npz").exists()
        rc, err = _main(["packing", "dos", "--packing", str(d), "--out", str(d / "e")], capsys)
        _one_line_error(rc, err)
        assert "interrupted" in err
    else:
        assert _seed_of_content(d) == 1 == index["records"]["packing"]["seed"]


def test_every_record_holds_its_fingerprint_and_manifest(d, capsys):
    runs = [["rigidity", "--packing", str(d), "--kt", "1", "--no-modes"],
            ["dos", "--packing", str(d), "--kt", "1", "--bins", "5"],
            ["jacobian", "--packing", str(d), "--law", "charan"]]
    for argv in runs:
        rc, err = _main(["packing", *argv, "--out", str(d)], capsys)
        assert rc == 0, err
    expect = {"packing": {"packing.npz", "packing.png"},
              "rigidity": {"rigidity.png", "kt_1/g.json", "kt_1/jacobian_tilde.npz",
                           "kt_1/xi.npy", "kt_1/theta.npy", "kt_1/u.npy",
                           "kt_1/nonaffine_step.npy"},
              "dos": {"dos.npz", "dos.png"},
              "jacobian": {"state.npz", "jacobian.npz", "dofs.json", "mass.npy"}}
    sha = json.loads((d / "packing.json").read_text())["files"]["packing.npz"]["sha256"]
    for name, files in expect.items():
        rec = rundir.verify(d, name)
        assert set(rec["files"]) == files, name
        fp = rec["fingerprint"]
        assert len(fp["sha256"]) == 64 and fp["parameters"]["law"] in ("ishima", "charan")
        if name != "packing":
            assert fp["parameters"]["packing_sha256"] == sha == rec["packing"]["sha256"]
            assert "seed" not in fp["parameters"]   # the packing's content stands for it
    assert json.loads((d / "dos.json").read_text())["fingerprint"]["parameters"]["bins"] == 5
    assert not os.path.exists(d / rundir.LOCK)
