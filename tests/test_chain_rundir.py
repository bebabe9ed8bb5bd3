"""Chain results that cannot go stale: fingerprints, member keys, --force, --resume, exit 4.

Every chain record carries the fingerprint of its parameters (the validated
scene, the law and its parameters included); ``waves`` members are keyed by a
hash of their own fingerprint and recomputed when missing, damaged or made
with other parameters; ``--force`` removes what the previous run wrote and a
failed forced run leaves no record of removed files.
"""

import json

import numpy as np

from fricstab.cli import main
from fricstab.errors import ConvergenceError
from fricstab.io import rundir
from fricstab.io.ensemble import FINGERPRINT, load_member, member_key, run_ensemble

WAVES = ["chain", "waves", "--n", "4", "--realizations", "2", "--scheduler", "inline",
         "--no-progress", "--quiet"]


def _waves(out, *extra, fx=("0.005",), duration="5"):
    return main([*WAVES, "--fx", *fx, "--duration", duration, "--out", str(out), *extra])


def _members(out):
    return {p.name: p.stat().st_mtime_ns for p in (out / "members").glob("*.npz")}


def _record(out, name):
    return json.loads((out / f"{name}.json").read_text())


def test_waves_force_with_another_duration_recomputes_every_member(tmp_path, capsys):
    out = tmp_path / "w"
    assert _waves(out) == 0
    first = _members(out)
    assert len(first) == 2 and all(n.startswith(("fx0.005_seed0_", "fx0.005_seed1_"))
                                   for n in first)
    (out / "notes.txt").write_text("mine")
    assert _waves(out, duration="6") == 2                    # no --force: refused
    assert "already holds results" in capsys.readouterr().err
    assert _waves(out, "--force", duration="6") == 0
    second = _members(out)
    assert len(second) == 2 and not set(first) & set(second)   # new keys, old files gone
    rec = _record(out, "waves")
    assert rec["duration_paper_units"] == 6.0
    assert rec["fingerprint"]["parameters"]["duration_paper_units"] == 6.0
    assert sorted(rec["files"]) == sorted(["waves.npz", "waves.png"]
                                          + [f"members/{n}" for n in second])
    assert rundir.verify(out, "waves")
    assert (out / "notes.txt").read_text() == "mine"          # not the run's: kept


def test_waves_fx_equal_to_six_digits_get_distinct_members(tmp_path):
    out = tmp_path / "w"
    assert _waves(out, fx=("0.0050000001", "0.0050000002")) == 0
    names = _members(out)
    assert len(names) == 4                                    # 2 F_x x 2 seeds, none shared
    assert all(n.startswith("fx0.005_seed") for n in names)   # {:g} alone would collide
    fps = {str(load_member(out / "members" / n)[FINGERPRINT]) for n in names}
    assert len(fps) == 4 and all(fp[:12] in " ".join(names) for fp in fps)
    rec = _record(out, "waves")
    assert [r["fx"] for r in rec["results"]] == [0.0050000001, 0.0050000002]
    with np.load(out / "waves.npz") as z:
        assert {"tau_fx0.0050000001", "tau_fx0.0050000002"} <= set(z.files)


CALLS = []


def counted(x):
    CALLS.append(x)
    return {"y": np.array([x, 2.0 * x])}


def test_a_damaged_or_foreign_member_is_recomputed_and_the_others_kept(tmp_path):
    keys = {x: member_key(f"x{x}", {"x": x}) for x in range(4)}
    members = {k: {"x": x} for x, (k, _) in keys.items()}
    fps = dict(keys.values())
    CALLS.clear()
    first = run_ensemble(counted, members, tmp_path, scheduler="inline", progress=False,
                         fingerprints=fps)
    assert sorted(CALLS) == [0, 1, 2, 3] and FINGERPRINT not in first[keys[0][0]]
    paths = {x: tmp_path / "members" / f"{k}.npz" for x, (k, _) in keys.items()}
    assert str(load_member(paths[0])[FINGERPRINT]) == keys[0][1]
    mtimes = {x: p.stat().st_mtime_ns for x, p in paths.items()}
    data = paths[0].read_bytes()
    paths[0].write_bytes(data[:len(data) // 2])                       # truncated
    np.savez(paths[1], y=np.array([9.0, 9.0]), fingerprint=np.array("0" * 64))  # foreign
    paths[2].unlink()                                                  # missing
    CALLS.clear()
    again = run_ensemble(counted, members, tmp_path, scheduler="inline", progress=False,
                         fingerprints=fps)
    assert sorted(CALLS) == [0, 1, 2]                         # member 3 was not recomputed
    assert paths[3].stat().st_mtime_ns == mtimes[3]
    for x, (k, sha) in keys.items():
        assert np.array_equal(again[k]["y"], [x, 2.0 * x])
        assert str(load_member(paths[x])[FINGERPRINT]) == sha      # files replaced
    # without fingerprints (validation/shear_sweep.py), a damaged member is still recomputed
    plain = {"a": {"x": 5.0}}
    run_ensemble(counted, plain, tmp_path / "p", scheduler="inline", progress=False)
    (tmp_path / "p" / "members" / "a.npz").write_bytes(b"PK\x03\x04 not a zip")
    CALLS.clear()
    res = run_ensemble(counted, plain, tmp_path / "p", scheduler="inline", progress=False)
    assert CALLS == [5.0] and np.array_equal(res["a"]["y"], [5.0, 10.0])


def test_waves_resume_recomputes_a_truncated_member_only(tmp_path, monkeypatch, capsys):
    from fricstab.protocols import waves

    def interrupted(reals):
        raise ConvergenceError("interrupted for the test")

    out = tmp_path / "w"
    with monkeypatch.context() as m:
        m.setattr(waves, "fit_waves", interrupted)
        assert _waves(out) == 4                               # members stored, no record
    assert not (out / "waves.json").exists() and rundir.journal_path(out, "waves").exists()
    before = _members(out)
    assert len(before) == 2
    damaged, kept = sorted(before)
    path = out / "members" / damaged
    path.write_bytes(path.read_bytes()[:100])
    assert _waves(out) == 2                                   # interrupted: refused
    assert "--resume" in capsys.readouterr().err
    assert _waves(out, "--resume", duration="6") == 2         # other parameters: refused
    assert "duration_paper_units: 5.0 there, 6.0 now" in capsys.readouterr().err
    assert _waves(out, "--resume") == 0
    after = _members(out)
    assert set(after) == set(before)
    assert after[kept] == before[kept] and after[damaged] != before[damaged]
    assert int(load_member(path)["seed"]) in (0, 1)           # loads again
    assert rundir.verify(out, "waves")


def test_every_chain_record_is_fingerprinted_with_the_law_and_its_parameters(tmp_path):
    out = tmp_path / "c"
    law = ["--n", "4", "--law", "charan", "--param", "kt=500", "--no-progress", "--quiet",
           "--out", str(out)]
    runs = {"ramp": ["--fx-max", "0.01", "--step", "0.005"],
            "jacobian": ["--fx", "0.005"],
            "dynamics": ["--fx", "0.005", "--duration", "5", "--seed", "3"],
            "waves": ["--fx", "0.005", "--realizations", "2", "--duration", "5",
                      "--scheduler", "inline"]}
    options = {"ramp": {"fx_max": 0.01, "step": 0.005, "tol": 1e-6},
               "jacobian": {"fx": 0.005, "step": 1e-3},
               "dynamics": {"fx": 0.005, "duration_paper_units": 5.0, "seed": 3},
               "waves": {"fx": [0.005], "realizations": 2, "duration_paper_units": 5.0,
                         "slide_threshold_2R": 0.02}}
    for name, argv in runs.items():
        assert main(["chain", name, *argv, *law]) == 0, name
        fp = _record(out, name)["fingerprint"]
        params = fp["parameters"]
        assert params["law"] == "charan" and params["kt"] == 500.0 and params["mu"] == 10.0
        assert params["n"] == 4 and params["fy"] == 0.1
        assert options[name].items() <= params.items(), name
        assert not {"out", "force", "scheduler", "workers", "checkpoint_every"} & set(params)
        assert fp["sha256"] == rundir.fingerprint(params)["sha256"]
        listed = set(rundir.verify(out, name)["files"])          # every file in the manifest
        assert {f"{name}.npz" if name != "jacobian" else "jacobian.npy"} <= listed, name
    assert {"state.npz", "jacobian.npz", "dofs.json", "mass.npy"} <= \
        set(_record(out, "jacobian")["files"])


def test_dynamics_resume_with_another_parameter_is_refused_naming_it(tmp_path, monkeypatch,
                                                                      capsys):
    from fricstab.errors import NumericalError
    from fricstab.protocols import dynamics, growth, waves  # noqa: F401  (bind before the patch)

    def blow_up(*args, **kwargs):
        raise NumericalError("non-finite force F_x on disk 1 at Verlet step 3")

    out = tmp_path / "d"
    argv = ["chain", "dynamics", "--n", "4", "--fx", "0.005", "--duration", "5",
            "--no-progress", "--out", str(out)]
    with monkeypatch.context() as m:
        m.setattr(dynamics, "run_dynamics", blow_up)
        assert main(argv) == 4                                # interrupted: journal kept
    capsys.readouterr()
    assert main(argv + ["--resume", "--mu", "5"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "mu: 10.0 there, 5.0 now" in err
    assert main(argv + ["--resume", "--disk", "1"]) == 2      # the figure's disk: an output
    assert "disk: 4 there, 1 now" in capsys.readouterr().err
    assert main(argv + ["--resume"]) == 0
    assert not (out / "checkpoints").exists()


def test_ramp_without_equilibrium_exits_4_and_a_failed_force_leaves_no_stale_record(
        tmp_path, capsys):
    out = tmp_path / "r"
    base = ["chain", "ramp", "--n", "4", "--no-progress", "--out", str(out)]
    assert main(["chain", "jacobian", "--n", "4", "--fx", "0.005", "--no-progress",
                 "--quiet", "--out", str(out)]) == 0
    assert main(base + ["--fx-max", "0.01", "--step", "0.005", "--quiet"]) == 0
    assert json.loads((out / "result.json").read_text())["protocols"] == ["jacobian", "ramp"]
    capsys.readouterr()
    # a Coulomb cap of 4 mu F_y = 0.04 < F_x: no equilibrium past the first step
    rc = main(base + ["--mu", "0.1", "--fx-max", "0.1", "--step", "0.01", "--force"])
    err = capsys.readouterr().err
    assert rc == 4 and err.count("\n") == 1 and "no equilibrium at F_x = 0.01" in err
    assert not (out / "ramp.json").exists() and not (out / "ramp.npz").exists()
    index = json.loads((out / "result.json").read_text())
    assert index["protocols"] == ["jacobian"]                 # no record of removed files
    assert rundir.verify(out, "jacobian")
    assert main(base + ["--fx-max", "5", "--step", "1"]) == 2   # the failed run is in the way
    assert "--resume" not in capsys.readouterr().err           # ramp has no --resume
    assert main(base + ["--fx-max", "5", "--step", "1", "--force"]) == 4   # Newton fails
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "no equilibrium at F_x = 1" in err


def test_member_keys_hash_the_exact_fx():
    a, sha = member_key("fx0.083_seed0", {"fx": 0.0830001})
    b, _ = member_key("fx0.083_seed0", {"fx": 0.0830002})
    assert a != b and a == f"fx0.083_seed0_{sha[:12]}"
