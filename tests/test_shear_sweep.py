"""``fricstab shear sweep``: the mu_s sweep as a dask ensemble (issue 34).

A tiny sweep (40 disks, 100 frames, a few slips) on a real LocalCluster of two workers
equals, member by member, the same members run in this process; ``--resume``
recomputes only a missing member; a bad ``--mus`` is one line and exit 2.
"""

import json

import numpy as np
import pytest

from fricstab.cli import main
from fricstab.cli.shear import resolve_params, run_shear
from fricstab.cli.shear_sweep import QUANTITIES, _fingerprint, sweep_member
from fricstab.errors import ConvergenceError
from fricstab.io import rundir
from fricstab.io.ensemble import FINGERPRINT, load_member, member_key

TINY = ["--n", "40", "--strain", "0.01", "--dgamma", "1e-4", "--gamma0", "0.002"]
SCENE = {"n": 40, "strain": 0.01, "dgamma": 1e-4, "gamma0": 0.002}


def _sweep(out, *extra):
    return main(["shear", "sweep", "--out", str(out), "--quiet", "--no-progress", *TINY,
                 *extra])


def _members(out):
    return {p.name: p.stat().st_mtime_ns for p in (out / "members").glob("*.npz")}


@pytest.fixture(scope="module")
def local(tmp_path_factory):
    out = tmp_path_factory.mktemp("sweep") / "s"
    assert _sweep(out, "--mus", "0.3", "0.7", "--scheduler", "local", "--workers", "2") == 0
    return out


def test_local_cluster_members_equal_in_process_runs(local, tmp_path):
    rec = json.loads((local / "sweep.json").read_text())
    slips = 0
    assert rec["mus"] == [0.3, 0.7] and rec["seeds"] == [0]
    assert [r["mus"] for r in rec["results"]] == [0.3, 0.7]
    assert rundir.verify(local, "sweep")
    assert "## mu_s = 0.3" in (local / "sweep.md").read_text()
    for r in rec["results"]:
        m = r["mus"]
        assert (local / "runs" / f"mus{m!r}_seed0" / "shear.json").is_file()
        params = resolve_params(None, "quick", {**SCENE, "mus": m, "seed": 0})
        key, sha = member_key(f"mus{m!r}_seed0", _fingerprint(params))
        stored = load_member(local / "members" / f"{key}.npz")
        assert str(stored.pop(FINGERPRINT)) == sha    # the same parameters as this run's
        direct = sweep_member(params, str(tmp_path / f"mus{m!r}"), run_shear)
        # same seed, same code, one thread each: the worker's member is this one, exactly
        assert sorted(stored) == sorted(direct)
        for name, value in direct.items():
            assert np.array_equal(stored[name], value, equal_nan=True), name
        assert float(stored["mus"]) == m and int(stored["frames"]) == 101
        slips += int(stored["n_slip"])
        for name in QUANTITIES:   # the record's table is made of the stored members
            want = float(stored[name])
            got = r["quantities"][name]["values"][0]
            assert (got is None and np.isnan(want)) or got == want, name
    assert slips >= 1   # largest_drop is defined somewhere: compared as a number


def test_an_interrupted_member_run_continues_from_its_checkpoint(local, tmp_path,
                                                                  monkeypatch):
    """A member whose run stopped (a worker killed, Ctrl-C) resumes it: the same member."""
    from fricstab.io.checkpoint import Checkpointer
    params = {**resolve_params(None, "quick", {**SCENE, "mus": 0.3, "seed": 0}),
              "checkpoint_every": 30}
    save, saves = Checkpointer.save, []

    def dies_after_two(self, step, **arrays):
        save(self, step, **arrays)
        saves.append(step)
        if len(saves) == 2:
            raise ConvergenceError("killed for the test")

    out = tmp_path / "m"
    with monkeypatch.context() as m:
        m.setattr(Checkpointer, "save", dies_after_two)
        with pytest.raises(ConvergenceError):
            sweep_member(params, str(out), run_shear)
    assert saves == [30, 60] and not (out / "shear.json").exists()
    first_chunk = (out / "frames" / "chunk_000000.npz").stat().st_mtime_ns
    got = sweep_member(params, str(out), run_shear)   # the lock of the failed run was released
    # continued, not redone: the chunk written before the kill is the same file
    assert (out / "frames" / "chunk_000000.npz").stat().st_mtime_ns == first_chunk
    key, _ = member_key("mus0.3_seed0", _fingerprint(params))
    stored = load_member(local / "members" / f"{key}.npz")   # the uninterrupted member
    for name, value in got.items():
        assert np.array_equal(stored[name], value, equal_nan=True), name
    assert json.loads((out / "shear.json").read_text())["chunks"] == 4   # 30+30 | 30+11


def test_resume_recomputes_only_the_missing_member(tmp_path, monkeypatch, capsys):
    from fricstab.cli import shear_sweep

    def broken(doc):
        raise ConvergenceError("interrupted for the test")

    out = tmp_path / "s"
    with monkeypatch.context() as m:
        m.setattr(shear_sweep, "markdown", broken)
        assert _sweep(out, "--mus", "0.3", "0.7", "--scheduler", "inline") == 4
    assert not (out / "sweep.json").exists()
    before = _members(out)
    assert len(before) == 2
    gone, kept = sorted(before)
    runs = {n: (out / "runs" / n.rsplit("_", 1)[0] / "shear.json").stat().st_mtime_ns
            for n in before}
    (out / "members" / gone).unlink()
    assert _sweep(out, "--mus", "0.3", "0.7", "--scheduler", "inline") == 2
    assert "--resume" in capsys.readouterr().err                 # interrupted: refused
    assert _sweep(out, "--mus", "0.3", "0.7", "--scheduler", "inline", "--resume") == 0
    after = _members(out)
    assert set(after) == set(before) and after[kept] == before[kept]
    assert after[gone] != before[gone]
    again = {n: (out / "runs" / n.rsplit("_", 1)[0] / "shear.json").stat().st_mtime_ns
             for n in before}
    assert again[kept] == runs[kept] and again[gone] != runs[gone]   # only its run redone
    assert rundir.verify(out, "sweep")
    assert _sweep(out, "--mus", "0.3", "0.7", "--scheduler", "inline", "--resume") == 2
    assert "already holds a complete result" in capsys.readouterr().err


def test_window_steady_analyses_each_member_from_its_steady_start(local, tmp_path):
    """--window steady: each member analysed from steady_window's start on its own tau (kept
    as window_start, its verdict as steady), the same run as the default sweep's member but
    another member file (the window is in its fingerprint)."""
    from fricstab.analysis.shear import analyze
    from fricstab.analysis.stationarity import steady_window
    from fricstab.cli.shear_analyze import frames_of
    out = tmp_path / "s"
    assert _sweep(out, "--mus", "0.3", "--scheduler", "inline", "--window", "steady") == 0
    rec = json.loads((out / "sweep.json").read_text())
    assert rec["parameters"]["window"] == "steady"
    run = out / "runs" / "mus0.3_seed0"
    with np.load(run / "shear.npz") as z:
        start, info = steady_window(z["strain"], z["tau"], SCENE["gamma0"])
    (member,) = (out / "members").glob("*.npz")
    stored = load_member(member)
    assert float(stored["window_start"]) == start >= SCENE["gamma0"]
    assert float(stored["steady"]) == float(info["steady"])
    res = analyze(frames_of(run), start, progress=False)
    for name in ("n_phases", "n_slip", "phases_per_step"):
        assert float(stored[name]) == float(res.summary[name]), name
    q = rec["results"][0]["quantities"]
    assert q["window_start"]["values"] == [start]
    default = load_member(next((local / "members").glob("mus0.3_seed0_*.npz")))
    assert member.name != next((local / "members").glob("mus0.3_seed0_*.npz")).name
    assert float(default["window_start"]) == SCENE["gamma0"] and np.isnan(default["steady"])
    with np.load(local / "runs" / "mus0.3_seed0" / "shear.npz") as z:
        np.testing.assert_array_equal(z["tau"], np.load(run / "shear.npz")["tau"])


@pytest.mark.parametrize("mus, key", [(["0"], "--mus"), (["-1"], "--mus"), (["nan"], "--mus"),
                                      (["text"], "--mus"), (["0.3", "0.3"], "--mus 0.3"),
                                      (["inf"], "--mus")])
def test_bad_mus_is_one_line_and_exit_2_writing_nothing(tmp_path, capsys, mus, key):
    out = tmp_path / "o"
    assert main(["shear", "sweep", "--out", str(out), "--mus", *mus]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("fricstab: error:") and key in err
    assert err.count("\n") == 0 and "Traceback" not in err
    assert not out.exists()


def test_a_law_without_mus_is_refused_naming_it(tmp_path, capsys):
    assert main(["shear", "sweep", "--out", str(tmp_path / "o"), "--law", "hertz"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "--mus" in err and "hertz" in err
