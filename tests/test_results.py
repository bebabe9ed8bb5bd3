"""Result directories: refusal without --force, atomic files, the record's provenance."""

import json
import subprocess
from pathlib import Path

import numpy as np
import pytest

from fricstab.laws import ParameterError
from fricstab.io.results import ResultDir, git_revision, json_clean, versions


def test_record_carries_provenance(tmp_path):
    rd = ResultDir(tmp_path / "r", "toy").create()
    with rd.stage("work"):
        sum(range(10000))
    rd.write_npz("a.npz", x=np.arange(3.0))
    rd.write_png("f.png", lambda p: Path(p).write_bytes(b"\x89PNG\r\n\x1a\n"))
    doc = rd.finish({"value": np.float64(1.5), "bad": np.nan}, parameters={"n": 3}, seed=7,
                    argv=["toy", "--n", "3"])
    saved = json.loads((tmp_path / "r" / "toy.json").read_text())
    assert saved == json.loads(json.dumps(json_clean(doc)))
    assert saved["value"] == 1.5 and saved["bad"] is None          # no NaN in JSON
    assert saved["parameters"] == {"n": 3} and saved["seed"] == 7
    assert saved["protocol"] == "toy" and saved["command"] == "fricstab toy --n 3"
    for pkg in ("python", "numpy", "scipy", "numba", "sympy", "dask", "fricstab"):
        assert saved["versions"][pkg]
    assert set(saved["timings"]["work"]) == {"wall_s", "cpu_s"}
    assert saved["timings"]["work"]["wall_s"] >= 0 and saved["seconds"] >= 0
    assert saved["git"] is None or len(saved["git"]["revision"]) == 40
    assert not list((tmp_path / "r").glob(".*.tmp"))
    with np.load(tmp_path / "r" / "a.npz") as z:
        assert np.array_equal(z["x"], np.arange(3.0))


def test_existing_result_needs_force(tmp_path):
    rd = ResultDir(tmp_path, "toy").create()
    rd.finish({}, parameters={})
    with pytest.raises(ParameterError, match="already holds results.*--force"):
        ResultDir(tmp_path, "toy")
    with pytest.raises(ParameterError, match="complete result"):
        ResultDir(tmp_path, "toy", resume=True)
    ResultDir(tmp_path, "toy", force=True).create()
    assert not (tmp_path / "toy.json").exists()       # a forced rerun starts without a record
    ResultDir(tmp_path, "other")                      # another protocol may share the folder
    (tmp_path / "x.npz").write_bytes(b"")
    with pytest.raises(ParameterError, match="x.npz"):
        ResultDir(tmp_path, "toy2", outputs=["x.npz"])


def test_out_must_be_a_directory(tmp_path):
    (tmp_path / "file").write_text("")
    for bad in (tmp_path / "file", tmp_path / "file" / "sub"):
        with pytest.raises(ParameterError, match="--out"):
            ResultDir(bad, "toy")


def test_git_revision_never_fails(monkeypatch):
    def missing(*args, **kwargs):
        raise FileNotFoundError("git")
    monkeypatch.setattr(subprocess, "run", missing)
    assert git_revision.__wrapped__() is None
    assert versions()["numpy"] == np.__version__


def test_internal_error_is_one_line_and_logged(tmp_path, capsys, monkeypatch):
    from fricstab.cli import chain as chain_cli
    from fricstab.cli import main

    def bug(ns, argv):
        raise RuntimeError("a bug\nover two lines")

    monkeypatch.setattr(chain_cli, "_ramp", bug)
    (tmp_path / "o").mkdir()
    rc = main(["chain", "ramp", "--out", str(tmp_path / "o"), "--no-progress"])
    err = capsys.readouterr().err
    assert rc == 70 and err.count("\n") == 1 and "internal error: RuntimeError" in err
    assert "Traceback" in (tmp_path / "o" / "fricstab-error.log").read_text()
    assert main(["--debug", "chain", "ramp", "--out", str(tmp_path / "o")]) == 70
    assert "Traceback" in capsys.readouterr().err          # --debug shows it


def test_result_json_indexes_every_protocol_of_the_directory(tmp_path):
    for name, seed in (("make", 1), ("dos", 2)):
        rd = ResultDir(tmp_path, name).create()
        with rd.stage("work"):
            pass
        rd.finish({"value": seed}, parameters={"n": seed}, seed=seed)
    (tmp_path / "result.json").write_text("{truncated")      # a damaged index is rebuilt
    rd = ResultDir(tmp_path, "rigidity").create()
    rd.finish({"value": 3}, parameters={"n": 3}, seed=3)
    index = json.loads((tmp_path / "result.json").read_text())
    assert index["protocols"] == ["dos", "make", "rigidity"]
    for name, rec in index["records"].items():
        assert rec == json.loads((tmp_path / f"{name}.json").read_text())
        assert {"versions", "seed", "parameters", "timings"} <= rec.keys()
