"""Issue 39, hardening: extreme but finite numeric input gets a one-line answer.

* every numeric option of every command (found by walking the argparse parser
  of :func:`fricstab.cli._parser`) at 1e-320, 1e-300, 1e300 and the largest
  float (ints at +-1e30 and 2^63) exits 0, 2 or 4 with at most one line, never
  70; the sub-normal and the largest values are refused (exit 2) naming the option;
* scene-file values out of float64's reach are refused naming the key;
* a bad numba threads' environment is one line (exit 2), not a traceback;
* a closed stdout (``| head -1``) ends quietly;
* inputs accepted though wrong (``chain waves``: a duplicate F_x, a chain too
  short to fit, a duration too short for a fit) are refused or reported.
"""

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from fricstab.cli import _parser, main

ROOT = Path(__file__).resolve().parents[1]
TINY, HUGE = "1e-320", "1.7976931348623157e308"
FLOATS = (TINY, "1e-300", "1e300", HUGE)
INTS = (str(10 ** 30), str(2 ** 63), str(-10 ** 30))
MUST_REFUSE = {TINY, HUGE, *INTS}

#: The smallest command line of each command (--out added); --dry-run where it exists.
BASE = {
    "verify": ["--law", "hertz", "--cases", "1", "--no-progress"],
    "chain ramp": ["--n", "3", "--fx-max", "0.01"],
    "chain jacobian": ["--n", "3"],
    "chain dynamics": ["--n", "3", "--fx", "0.01", "--duration", "10"],
    "chain waves": ["--n", "3", "--fx", "0.01", "--realizations", "2", "--duration", "10",
                    "--scheduler", "inline"],
    "packing make": ["--n", "16"],
    "packing rigidity": ["--n", "16"],
    "packing dos": ["--n", "16"],
    "packing jacobian": ["--n", "16"],
    "packing aqs": ["--n", "16", "--strain", "0.01", "--dgamma", "1e-3"],
    "shear run": ["--n", "16", "--strain", "1e-4"],
    "shear jacobian": ["--n", "16"],
    "shear sweep": ["--n", "16", "--strain", "1e-4", "--mus", "0.3", "--scheduler", "inline"],
    "shear analyze": [],
    "shear export": [],
    "import": [str(ROOT / "docs" / "examples" / "import" / "csv" / "packing.csv"), "--law",
               "ishima", "--param", "kn=1", "--param", "kt=1", "--units",
               "length=0.4,force=100,mass=20"],
}


def _leaves(parser, path=()):
    subs = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    if not subs:
        yield " ".join(path), parser
        return
    for name, sub in subs[0].choices.items():
        yield from _leaves(sub, path + (name,))


def _kind(action):
    """'int', 'float' or None: the numeric type of an option, from what its type returns."""
    t = action.type
    if t is None or t in (str, Path) or not callable(t):
        return None
    for text in ("7", "16", "1000", "0.5", "0.05", "1e-6"):
        try:
            value = t(text)
        except (argparse.ArgumentTypeError, ValueError, TypeError):
            continue
        if isinstance(value, bool):
            return None
        return "int" if isinstance(value, int) else "float" if isinstance(value, float) else None
    return None


def _numeric_options():
    found = []
    parser = _parser()
    for a in parser._actions:   # top level: --threads
        if a.option_strings and _kind(a):
            found.append(("laws", a.option_strings[0], _kind(a), 1, False))
    for cmd, p in _leaves(parser):
        dry = any("--dry-run" in a.option_strings for a in p._actions)
        for a in p._actions:
            kind = _kind(a) if a.option_strings else None
            if kind:
                n = a.nargs if isinstance(a.nargs, int) else 1
                found.append((cmd, a.option_strings[0], kind, n, dry))
    return found


OPTIONS = _numeric_options()
COMMANDS = sorted({o[0] for o in OPTIONS})


def _argv(cmd, opt, values, out, dry):
    base = list(BASE.get(cmd, []))
    if opt in base:
        i = base.index(opt)
        del base[i:i + 2]
    if cmd == "laws":   # a top-level option
        return [opt, *values, "laws"]
    argv = [*cmd.split(), *base, opt, *values]
    if cmd != "verify":
        argv += ["--out", str(out)]
    return argv + (["--dry-run"] if dry else [])


def _run(argv, capsys):
    capsys.readouterr()
    rc = main(argv)
    err = capsys.readouterr().err
    return rc, [line for line in err.splitlines() if line.strip()]


def _answered(rc, lines, argv):
    assert rc in (0, 2, 4), (argv, rc, lines)
    assert not any("Traceback" in line or "internal error" in line for line in lines), argv
    if rc:
        assert len(lines) == 1 and lines[0].startswith("fricstab: error:"), (argv, lines)
    else:
        assert len(lines) <= 1, (argv, lines)


def test_every_numeric_option_is_found():
    """The walk sees the options of every command, nargs ones included."""
    names = {(c, o) for c, o, *_ in OPTIONS}
    for want in (("shear run", "--dgamma"), ("shear run", "--inertial-number"),
                 ("shear run", "--density"), ("chain ramp", "--mu"), ("chain waves", "--fx"),
                 ("verify", "--mu-range"), ("packing rigidity", "--kt"),
                 ("packing aqs", "--window"), ("shear analyze", "--gamma0"),
                 ("shear export", "--every"), ("laws", "--threads")):
        assert want in names
    assert len(OPTIONS) > 120
    assert set(BASE) | {"laws"} >= set(COMMANDS)


@pytest.mark.parametrize("cmd", COMMANDS)
def test_extreme_numeric_values_answered(cmd, tmp_path, capsys):
    """Each option at 1e-320, 1e-300, 1e300, max float (ints: +-1e30, 2^63): 0, 2 or 4 with
    one line; the sub-normal, the largest float and the huge ints refused naming the option.

    Commands with ``--dry-run`` are validated through it (the refusals come before any
    work); the others are run (their values are refused by the parser)."""
    for k, (c, opt, kind, n, dry) in enumerate(o for o in OPTIONS if o[0] == cmd):
        for value in (FLOATS if kind == "float" else INTS):
            out = tmp_path / f"o{k}_{len(value)}"
            argv = _argv(cmd, opt, [value] * n, out, dry)
            rc, lines = _run(argv, capsys)
            _answered(rc, lines, argv)
            if value in MUST_REFUSE and not (cmd == "laws" and value == INTS[0]):
                assert rc == 2, (argv, rc, lines)
                assert opt in lines[0] or opt.lstrip("-").replace("-", "_") in lines[0], \
                    (argv, lines)
            if rc:
                assert not out.exists(), argv


@pytest.mark.parametrize("argv, opt", [
    (["shear", "run", "--n", "16", "--strain", "1e-4", "--dgamma", "1e-320"], "--dgamma"),
    (["shear", "run", "--n", "16", "--strain", "1e-4", "--inertial-number", "1e-320"],
     "--inertial-number"),
    (["shear", "run", "--n", "16", "--strain", "1e-4", "--density", "1e-320"], "--density"),
    (["chain", "ramp", "--n", "3", "--fx-max", "0.01", "--mu", "1e-300"], "--mu"),
    (["chain", "waves", "--n", "3", "--fx", "0.01", "--duration", "1e30", "--realizations",
      "2", "--scheduler", "inline"], "--duration"),
])
def test_issue_examples_refused_before_work(argv, opt, tmp_path, capsys):
    """The issue's exit-70 (or endless) runs, without --dry-run: exit 2 naming the option."""
    out = tmp_path / "o"
    rc, lines = _run(argv + ["--out", str(out), "--no-progress"], capsys)
    assert rc == 2 and len(lines) == 1 and opt in lines[0], lines
    assert not out.exists()


@pytest.mark.parametrize("scene, text, key", [
    ("chain", "inertia = 1e-320", "inertia"),
    ("chain", "mass = 1e308", "mass"),
    ("chain", "kt = 1e-320", "kt"),
    ("chain", "fy = 1e-310", "fy"),
    ("packing", "kt = 1e-320", "kt"),
    ("shear", "density = 1e-320", "density"),
])
def test_scene_file_out_of_float64_named(scene, text, key, tmp_path, capsys):
    """A scene file value beyond float64's products: one line naming the key, exit 2."""
    path = tmp_path / "s.toml"
    path.write_text(text + "\n")
    out = tmp_path / "o"
    argv = {"chain": ["chain", "ramp", "--n", "3", "--fx-max", "0.01"],
            "packing": ["packing", "rigidity", "--n", "16", "--law", "ishima"],
            "shear": ["shear", "run", "--n", "16"]}[scene]
    rc, lines = _run(argv + ["--scene", str(path), "--out", str(out)], capsys)
    assert rc == 2 and len(lines) == 1, lines
    assert f"'{key}'" in lines[0] and "not allowed" in lines[0], lines
    assert not out.exists()


def _cli(args, env=None, **kw):
    full = {**os.environ, **(env or {})}
    full.pop("FRICSTAB_DEBUG", None)
    return subprocess.run([sys.executable, "-m", "fricstab", *args], cwd=ROOT, env=full,
                          capture_output=True, text=True, timeout=120, **kw)


@pytest.mark.parametrize("var, value", [
    ("NUMBA_NUM_THREADS", "0"), ("NUMBA_NUM_THREADS", "-1"), ("NUMBA_NUM_THREADS", "abc"),
    ("NUMBA_NUM_THREADS", str(10 ** 30)),
    ("NUMBA_THREADING_LAYER", "bogus"),
    ("NUMBA_THREADING_LAYER", "tbb"),
])
def test_bad_thread_environment_one_line(var, value):
    """Read when numba is imported: checked first, one line naming the variable, exit 2."""
    if value == "tbb":
        try:
            import numba.np.ufunc.tbbpool  # noqa: F401
            pytest.skip("TBB is installed here: the tbb layer works")
        except ImportError:
            pass
    res = _cli(["laws"], env={var: value})
    lines = res.stderr.strip().splitlines()
    assert res.returncode == 2, res.stderr
    assert len(lines) == 1 and lines[0].startswith("fricstab: error:") and var in lines[0]
    assert res.stdout == ""


def test_good_thread_environment_runs():
    res = _cli(["laws"], env={"NUMBA_NUM_THREADS": "1", "NUMBA_THREADING_LAYER": "workqueue"})
    assert res.returncode == 0 and res.stderr == "" and "hertz" in res.stdout


def test_closed_stdout_ends_quietly():
    """``fricstab scene show chain | head -1`` (head gone before the output): no "Broken
    pipe", exit 0."""
    env = {**os.environ, "NUMBA_NUM_THREADS": "1"}
    proc = subprocess.Popen([sys.executable, "-m", "fricstab", "scene", "show", "chain"],
                            cwd=ROOT, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    proc.stdout.close()   # the reader is gone before the first line, as `| head -0`, `| true`
    with proc.stderr:
        err = proc.stderr.read().decode()
    rc = proc.wait(timeout=120)
    assert rc == 0 and err == "", (rc, err)


def test_waves_duplicate_fx_refused(tmp_path, capsys):
    out = tmp_path / "o"
    rc, lines = _run(["chain", "waves", "--n", "3", "--fx", "0.083", "0.083", "--out",
                      str(out), "--dry-run"], capsys)
    assert rc == 2 and len(lines) == 1 and "--fx" in lines[0] and "0.083" in lines[0]
    assert not out.exists()


def test_waves_chain_too_short_to_fit_refused(tmp_path, capsys):
    rc, lines = _run(["chain", "waves", "--n", "2", "--fx", "0.083", "--out",
                      str(tmp_path / "o"), "--dry-run"], capsys)
    assert rc == 2 and len(lines) == 1 and "--n" in lines[0] and "3" in lines[0]


def test_waves_short_duration_says_not_defined(tmp_path, capsys):
    """Too short for any disk to breach: V1, V2 "not defined" (record and table), no nan."""
    out = tmp_path / "o"
    capsys.readouterr()
    rc = main(["chain", "waves", "--n", "4", "--fx", "0.083", "--realizations", "2",
               "--duration", "5", "--scheduler", "inline", "--no-progress", "--out", str(out)])
    text = capsys.readouterr().out
    assert rc == 0
    assert "nan" not in text and "V1 = not defined" in text, text
    (r,) = json.loads((out / "waves.json").read_text())["results"]
    assert r["v1"] is None and r["v1_note"].startswith("not defined")
    assert r["v2"] is None and r["v2_note"].startswith("not defined")
