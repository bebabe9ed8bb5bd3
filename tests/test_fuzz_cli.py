"""Fuzzing the command line: generated scene files and argv, valid, invalid and absurd.

Properties, for every case: no traceback reaches the user; exit status in
{0 ok, 2 bad input, 3 disagreement, 4 numerical failure} (70, an internal
error, is a bug and fails the test); a bad input exits 2 with one line
``fricstab: error: ...``; a successful ``--dry-run`` prints strict JSON
(no NaN).  Valid inputs run ``--dry-run`` (everything resolved and checked,
nothing computed), except a family of tiny real runs.

CI runs ``FRICSTAB_FUZZ_EXAMPLES`` (default 100) examples per test; the
acceptance run is ``FRICSTAB_FUZZ_EXAMPLES=10000 python -m pytest tests/test_fuzz_cli.py``.
"""

import contextlib
import io
import json
import os
import tempfile
from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from fricstab.cli import main
from fricstab.io.scenes import get

EXAMPLES = int(os.environ.get("FRICSTAB_FUZZ_EXAMPLES", "100"))
FUZZ = settings(max_examples=EXAMPLES, deadline=None, database=None,
                suppress_health_check=list(HealthCheck))
OK_CODES = {0, 2, 3, 4}

COMMANDS = [["chain", "ramp"], ["chain", "jacobian"], ["chain", "dynamics"], ["chain", "waves"],
            ["packing", "make"], ["packing", "rigidity"], ["packing", "dos"],
            ["packing", "jacobian"],
            ["shear", "run"], ["shear", "analyze"], ["shear", "export"], ["shear", "jacobian"],
            ["shear"],
            ["scene", "show"], ["scene", "list"], ["laws"], ["verify"], ["chain"], [],
            ["frobnicate"], ["packing", "melt"]]
OPTIONS = ["--n", "--fy", "--mu", "--inertia", "--step", "--fx", "--fx-max", "--tol",
           "--duration", "--seed", "--amplitude", "--disk", "--export", "--checkpoint-every",
           "--realizations", "--slide-threshold", "--scheduler", "--workers", "--phi",
           "--dphi", "--f-tol", "--kt", "--dgamma", "--z-th", "--route", "--bins", "--modes",
           "--packing", "--force", "--resume", "--quiet", "--cases", "--law", "--frobnicate",
           "--param",
           "--help", "-h", "--version", "--debug", "--",
           "--param", "--strain", "--inertial-number", "--kappa", "--gamma0",
           "--dt-frac", "--preset", "--format", "--every", "--no-spectra", "--modulus"]

texts = st.one_of(
    st.sampled_from(["0", "1", "-1", "2", "3", "4", "16", "0.5", "1e-3", "1e308", "-1e308",
                     "1e-320", "nan", "inf", "-inf", "NaN", "9" * 40, "-" + "9" * 40, "",
                     "x", "0x10", "1,2", "1e", "xyz", "dump", "local", "inline",
                     "tcp://127.0.0.1:1", "auto", "dense", "charan", "all", "chain",
                     "hertz", "ishima", "lee_hurley", "kt=0.5", "kn=-1", "mu=nan", "E=1",
                     "kt", "=1", "nu=0.5", "mus=0.3", "kn=1e12", "E=-1", "mur=nan", "Rw=1",
                     "kt=", "packing", "shear", "\u00e9\u00e8", "\x00", "--out"]),
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.integers(min_value=-10 ** 30, max_value=10 ** 30).map(str),
    st.text(max_size=12))

toml_values = st.one_of(
    st.integers(min_value=-10 ** 20, max_value=10 ** 20).map(str),
    st.sampled_from(["0", "1", "2", "4", "8", "0.5", "1e-3", "1e308", "-1e308", "nan", "inf",
                     "-inf", "true", "false", '"high"', '"auto"', "[]", "[1, -2]", "[0.1, 1]",
                     "[[1]]", "{a = 1}", '"\u00e9\u00e8"', "1979-05-27", "9" * 30, "0.0",
                     "1_000", "0b11", '""', "[1, 'x']", "-0.0"]),
    st.floats(allow_nan=False, allow_infinity=False).map(repr))


@st.composite
def scene_texts(draw):
    kind = draw(st.sampled_from(["keys", "keys", "keys", "garbage", "binary", "empty"]))
    if kind == "empty":
        return b""
    if kind == "binary":
        return draw(st.binary(max_size=40))
    if kind == "garbage":
        return draw(st.text(max_size=60)).encode("utf-8", "surrogatepass")
    scene = draw(st.sampled_from(["chain", "packing", "shear"]))
    keys = list(get(scene).keys) + ["friction", "n_disks", "[x]", "chain", "packing", "\u00fc"]
    lines = []
    if draw(st.booleans()):
        lines.append(f"[{draw(st.sampled_from(['chain', 'packing', 'shear', 'other']))}]")
    for key in draw(st.lists(st.sampled_from(keys), max_size=4, unique=True)):
        lines.append(f"{key} = {draw(toml_values)}")
    return ("\n".join(lines) + "\n").encode("utf-8", "surrogatepass")


@st.composite
def command_lines(draw):
    argv = list(draw(st.sampled_from(COMMANDS)))
    if argv == ["scene", "show"] and draw(st.booleans()):
        argv.append(draw(st.sampled_from(["chain", "packing", "shear", "foam", ""])))
    for _ in range(draw(st.integers(0, 5))):
        argv.append(draw(st.sampled_from(OPTIONS)))
        if draw(st.integers(0, 4)):
            argv.append(draw(texts))
    return argv


def _run(argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        rc = main(argv)
    return rc, out.getvalue(), err.getvalue()


def _check(rc, out, err, argv):
    assert "Traceback" not in out + err, (argv, err)
    assert rc in OK_CODES or (rc == 0 and ("--help" in argv or "-h" in argv)), (argv, rc, err)
    if rc == 2:
        assert err.startswith("fricstab: error:") and err.count("\n") == 1, (argv, err)
    protocol = argv[:1] in (["chain"], ["packing"], ["shear"])
    silent = {"--help", "-h", "--version", "--quiet"} & set(argv)
    if rc == 0 and protocol and "--dry-run" in argv and not silent:
        json.loads(out, parse_constant=lambda c: (_ for _ in ()).throw(ValueError(c)))


@FUZZ
@given(argv=command_lines(), scene=scene_texts(), with_scene=st.booleans(),
       dry=st.integers(0, 9))
def test_fuzzed_command_lines_never_show_a_traceback(argv, scene, with_scene, dry):
    with tempfile.TemporaryDirectory() as tmp:
        full = list(argv)
        if with_scene:
            path = Path(tmp) / "scene.toml"
            path.write_bytes(scene)
            full += ["--scene", str(path)]
        if dry:                        # valid input stays cheap: resolve, validate, stop
            full.append("--dry-run")
        if "--out" not in full and dry % 3:
            full += ["--out", str(Path(tmp) / "out")]
        full = [a for a in full if a not in ("--resume",)] if not dry else full
        if not dry and full[:2] not in (["scene", "show"], ["scene", "list"], ["laws"]):
            full.append("--help")      # a real run of an arbitrary command could be long
        _check(*_run(full), full)


@FUZZ
@given(cmd=st.sampled_from(["jacobian", "dynamics"]), n=st.integers(2, 6),
       fx=st.floats(-0.02, 0.02), fy=st.sampled_from(["1e-3", "0.1", "1", "1e3", "1e-12"]),
       mu=st.sampled_from(["1e-3", "1", "10", "1e6"]), duration=st.sampled_from(["1", "20"]),
       amplitude=st.sampled_from(["1e-9", "1e-3", "1e3", "1e300"]))
def test_tiny_real_runs_succeed_or_fail_numerically(cmd, n, fx, fy, mu, duration, amplitude):
    with tempfile.TemporaryDirectory() as tmp:
        argv = ["chain", cmd, "--n", str(n), "--fx", repr(fx), "--fy", fy, "--mu", mu,
                "--step", "0.01", "--out", str(Path(tmp) / "o"), "--no-progress"]
        if cmd == "dynamics":
            argv += ["--duration", duration, "--amplitude", amplitude, "--disk", "1",
                     "--checkpoint-every", "50"]
        rc, out, err = _run(argv)
        _check(rc, out, err, argv)
        if rc == 0:
            doc = json.loads((Path(tmp) / "o" / f"{cmd}.json").read_text())
            assert doc["versions"]["numpy"] and doc["parameters"]["n"] == n


@FUZZ
@given(scene_key=st.sampled_from(
           [("chain", k) for k in ("n", "fy", "mu", "kn", "radius", "mass", "inertia", "kt")]
           + [("shear", k) for k in ("n", "modulus", "kappa", "inertial_number", "dgamma")]),
       value=st.sampled_from(["-1", "0", "nan", "inf", '"x"', "[1]", "true", "1e999"]))
def test_a_bad_scene_value_is_named(scene_key, value):
    scene, key = scene_key
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "s.toml"
        path.write_text(f"[{scene}]\n{key} = {value}\n")
        argv = [scene, "ramp" if scene == "chain" else "run", "--scene", str(path),
                "--out", str(Path(tmp) / "o"), "--dry-run"]
        rc, out, err = _run(argv)
        # a contact-law parameter of the chain (kn, kt, mu) that is a finite
        # number but out of the law's range is named with the law's rule
        rule = "allowed:" in err or (scene == "chain" and f"{key} must be" in err)
        assert rc == 2 and f"'{key}'" in err and rule and "\n" not in err[:-1]


@FUZZ
@given(law_key=st.sampled_from([("lee_hurley", k) for k in ("E", "nu", "mus", "mur")]
                               + [("hertz", "kn"), ("charan", "kn"), ("charan", "kt"),
                                  ("charan", "mu"), ("ishima", "kt")]),
       value=st.sampled_from(["-1", "0", "nan", "inf", '"x"', "[1]", "true", "1e999", "0.7"]),
       where=st.sampled_from(["file", "option"]))
def test_a_bad_shear_law_parameter_is_named(law_key, value, where):
    """The law's parameters of the shear scene (scene file or --param): one line naming
    the key, exit 2; allowed values (nu = 0.7 is not) resolve."""
    law, key = law_key
    allowed = (value == "0.7" and key != "nu") or (value == "0" and key in ("nu", "mur"))
    with tempfile.TemporaryDirectory() as tmp:
        argv = ["shear", "run", "--law", law, "--out", str(Path(tmp) / "o"), "--dry-run"]
        if where == "file":
            path = Path(tmp) / "s.toml"
            path.write_text(f"[shear]\n{key} = {value}\n")
            argv += ["--scene", str(path)]
        else:
            argv += ["--param", f"{key}={value}"]
        rc, out, err = _run(argv)
        _check(rc, out, err, argv)
        if allowed:
            assert rc == 0 and json.loads(out)["law_params"][key] == float(value)
        else:
            assert rc == 2 and key in err and "\n" not in err[:-1], (argv, err)
