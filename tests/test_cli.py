"""The fricstab command: reports, and one-line errors for bad input."""

import json

import pytest

from fricstab.cli import main

REQUIRED = {"law", "cases", "max_rel_err_complex_step", "max_rel_err_central"}


def test_laws_lists_every_law(capsys):
    assert main(["laws"]) == 0
    out = capsys.readouterr().out
    for name in ("hertz", "hertz_wall", "charan", "charan_wall", "ishima"):
        assert name in out


def test_verify_writes_one_object_per_law(tmp_path, capsys):
    path = tmp_path / "v.json"
    rc = main(["verify", "--law", "hertz,charan_wall", "--cases", "4", "--seed", "3",
               "--json", str(path), "--no-progress"])
    assert rc == 0
    data = json.loads(path.read_text())
    assert [d["law"] for d in data] == ["hertz", "charan_wall"]
    for d in data:
        assert REQUIRED <= d.keys()
        assert d["cases"] == 4 and d["nonfinite"] == 0
        assert d["meta"]["numba"]


@pytest.mark.parametrize("argv, name", [
    (["verify", "--law", "coulomb"], "--law"),
    (["verify", "--cases", "0"], "--cases"),
    (["verify", "--cases", "many"], "--cases"),
    (["verify", "--seed", "-1"], "--seed"),
    (["verify", "--radius", "-0.5"], "--radius"),
    (["verify", "--kn", "0"], "--kn"),
    (["verify", "--kn", "nan"], "--kn"),
    (["verify", "--mu-range", "0", "1"], "--mu-range"),
    (["verify", "--mu-range", "5", "1"], "--mu-range"),
    (["verify", "--kt-ratio-range", "-1", "1"], "--kt-ratio-range"),
    (["verify", "--delta-range", "1e-3", "3"], "--delta-range"),
    (["verify", "--radius-ratio-range", "0.5", "1"], "--radius-ratio-range"),
    (["verify", "--json", "/nonexistent-dir/x.json"], "--json"),
    (["frobnicate"], "frobnicate"),
])
def test_bad_input_is_one_line_naming_the_parameter(argv, name, capsys):
    assert main(argv + ["--no-progress"] if argv[0] == "verify" else argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert err.startswith("fricstab: error:") and name in err


def test_python_api_names_bad_parameters():
    from fricstab.laws import ParameterError, evaluate
    good = dict(dx=0.999, dy=0.0, Ri=0.5, Rj=0.5, kn=1.0, kt=0.3, mu=0.5, tx=0.0, ty=0.0)
    f, jac = evaluate("charan", **good)
    assert f.shape == (6,) and jac.shape == (6, 6) and f[0] > 0
    for key, bad in (("Ri", -0.5), ("kt", 0.0), ("mu", -1.0), ("kn", float("inf")), ("tx", "x")):
        with pytest.raises(ParameterError, match=key):
            evaluate("charan", **{**good, key: bad})
    with pytest.raises(ParameterError, match="missing argument 'mu'"):
        evaluate("charan", **{k: v for k, v in good.items() if k != "mu"})
    with pytest.raises(ParameterError, match="unknown argument 'mu'"):
        evaluate("ishima", **good)
    with pytest.raises(ParameterError, match="unknown law"):
        evaluate("coulomb", **good)
