"""Every exit path named (issue "Results that cannot go stale", classes 4 and 5).

Each example of the issue, run as written: a value that is allowed runs (or
fails with a named reason), one that cannot work is refused before the run
with one line ``fricstab: error: ...`` naming it, exit 2, nothing written;
warnings go into the record, not onto stderr one by one.
"""

import json
import warnings

import pytest

from fricstab.cli import main


def _run(argv, capsys):
    rc = main(argv)
    cap = capsys.readouterr()
    return rc, cap.out, cap.err


def _refused(rc, err, *words):
    assert rc == 2, err
    assert err.startswith("fricstab: error: ") and err.count("\n") == 1, err
    for w in words:
        assert w in err, (w, err)


@pytest.mark.parametrize("argv, words", [
    (["chain", "ramp", "--out", ""], ["--out", "names no new directory"]),
    (["chain", "ramp", "--out", "."], ["--out", "names no new directory"]),
    (["chain", "ramp", "--scene", "/dev/zero", "--out", "o"], ["/dev/zero", "not a regular file"]),
    (["packing", "rigidity", "--n", "16", "--dgamma", "1e-320", "--out", "o"],
     ["--dgamma", "1e-10"]),
    (["verify", "--law", "hertz", "--cases", "100000000"], ["--cases", "1000000"]),
    (["verify", "--law", "charan", "--mu-range", "1e300", "1e301"], ["--mu-range"]),
    (["verify", "--law", "charan", "--kt-ratio-range", "1e-300", "1e300"], ["--kt-ratio-range"]),
    (["verify", "--law", "hertz", "--radius", "1e300"], ["--radius"]),
    (["shear", "run", "--param", "E=nan", "--out", "o"], ["E", "finite"]),
])
def test_impossible_values_are_refused_before_the_run(argv, words, tmp_path, monkeypatch,
                                                      capsys):
    monkeypatch.chdir(tmp_path)
    rc, _, err = _run(argv, capsys)
    _refused(rc, err, *words)
    assert not (tmp_path / "o").exists() and not list(tmp_path.glob("*.json"))


def test_a_key_given_twice_in_a_scene_file_is_refused(tmp_path, capsys):
    scene = tmp_path / "s.toml"
    scene.write_text("n = 5\n[chain]\nn = 6\n")
    rc, _, err = _run(["chain", "ramp", "--scene", str(scene), "--out", str(tmp_path / "o")],
                      capsys)
    _refused(rc, err, "'n'", "both at the top level and under [chain]")
    assert not (tmp_path / "o").exists()


def test_a_scene_file_larger_than_a_scene_is_refused_unread(tmp_path, capsys):
    big = tmp_path / "big.toml"
    big.write_bytes(b"#" * (2 << 20))
    rc, _, err = _run(["chain", "ramp", "--scene", str(big), "--out", str(tmp_path / "o")],
                      capsys)
    _refused(rc, err, "larger than")


def test_critical_damping_is_allowed_and_runs(tmp_path, capsys):
    """alpha_n = 1 (critically damped, restitution 0) was accepted and then crashed
    after the run (exit 70); it runs and records restitution 0."""
    out = tmp_path / "s"
    rc, _, err = _run(["shear", "run", "--alpha-n", "1", "--n", "20", "--strain", "0.001",
                       "--dgamma", "1e-4", "--out", str(out), "--quiet", "--no-progress"],
                      capsys)
    assert rc == 0, err
    rec = json.loads((out / "shear.json").read_text())
    assert rec["derived"]["restitution_implied_by_alpha_n"] == 0.0


def test_scene_show_and_help_give_the_defaults_a_run_uses(capsys):
    from fricstab.cli.shear import resolve_params
    rc, out, _ = _run(["scene", "show", "shear"], capsys)
    assert rc == 0
    run = resolve_params(None)
    for key in ("n", "kappa", "strain", "dgamma", "inertial_number"):
        block = out.split(f"\n{key}  (", 1)[1].split("\n", 1)[0]
        assert f"default {run[key]!r}," in block or f"default {run[key]}," in block, (key, block)


def test_warnings_go_into_the_record_and_one_line(tmp_path, capsys, monkeypatch):
    """A warning inside a protocol: no warning text on stderr, one note line, and the
    record lists it with its count."""
    from fricstab.protocols import ramp
    real = ramp.run_ramp

    def noisy(*args, **kwargs):
        for _ in range(3):
            warnings.warn("a test warning", RuntimeWarning)
        return real(*args, **kwargs)

    monkeypatch.setattr(ramp, "run_ramp", noisy)
    out = tmp_path / "o"
    rc, _, err = _run(["chain", "ramp", "--fx-max", "0.002", "--out", str(out), "--quiet",
                       "--no-progress"], capsys)
    assert rc == 0, err
    assert err.count("\n") == 1 and err.startswith("fricstab: note: RuntimeWarning: a test "
                                                   "warning"), err
    rec = json.loads((out / "ramp.json").read_text())
    assert [(w["category"], w["message"], w["count"]) for w in rec["warnings"]] == \
        [("RuntimeWarning", "a test warning", 3)]


@pytest.mark.parametrize("content, words", [
    ("npy", "not an NPZ archive"), ("other", "pos is not a file"), ("garbage", "not an NPZ")])
def test_a_foreign_packing_file_is_refused_naming_it(content, words, tmp_path, capsys):
    """A .npy named .npz, an NPZ of something else, garbage: exit 2, one line."""
    import numpy as np
    path = tmp_path / "p.npz"
    if content == "npy":
        with open(path, "wb") as fh:
            np.save(fh, np.zeros(3))
    elif content == "other":
        with open(path, "wb") as fh:
            np.savez(fh, a=np.zeros(3))
    else:
        path.write_bytes(b"garbage" * 10)
    rc, _, err = _run(["packing", "rigidity", "--packing", str(path), "--kt", "1",
                       "--out", str(tmp_path / "o")], capsys)
    _refused(rc, err, str(path), words)
