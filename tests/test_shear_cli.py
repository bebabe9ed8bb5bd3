"""``fricstab shear run|jacobian``: bad input, any law, servo, SIGKILL + --resume bit-identical."""

import json
import os
import random
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from fricstab.cli import main

ROOT = Path(__file__).resolve().parents[1]
SMALL = ["--n", "40", "--strain", "0.02", "--dgamma", "1e-4", "--checkpoint-every", "10"]


def _cmd(out, *extra):
    return [sys.executable, "-m", "fricstab", "shear", "run", "--out", str(out), "--quiet",
            "--no-progress", *SMALL, *extra]


@pytest.mark.parametrize("command", ["run", "jacobian"])
@pytest.mark.parametrize("args, key", [
    (["--param", "mus=-0.1"], "--param mus"), (["--kappa", "-1e4"], "--kappa"),
    (["--n", "1"], "--n"), (["--strain", "1e-6"], "strain"),
    (["--inertial-number", "0"], "--inertial-number"), (["--law", "bogus"], "--law"),
    (["--law", "hertz", "--param", "mus=0.5"], "mus is not a parameter of law hertz"),
    (["--param", "kn=1"], "kn is not a parameter of law lee_hurley"),
    (["--param", "E"], "KEY=VALUE"), (["--param", "nu=nan"], "nu"),
    (["--law", "charan", "--param", "kt=0"], "kt must be > 0")])
def test_bad_input_is_one_line_and_exit_2_writing_nothing(tmp_path, capsys, command, args,
                                                           key):
    out = tmp_path / "o"
    assert main(["shear", command, "--out", str(out), *args]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("fricstab: error:")
    assert err.count("\n") == 0 and key in err and "Traceback" not in err
    assert not out.exists()


@pytest.mark.parametrize("law", ["lee_hurley", "hertz", "charan", "ishima"])
def test_jacobian_of_a_relaxed_clamped_cell_for_every_law(tmp_path, law):
    """``shear jacobian --law NAME`` with the law's defaults: exit 0 and the four files.

    The written state is relaxed: max |F| over the bulk dof below the relaxation
    tolerance (1e-10 f_0, f_0 = 2 E* L0 / kappa); the Jacobian recomputed from
    state.npz alone equals the written one to round-off (same kernels, same
    order: exactly).
    """
    import scipy.sparse as sps

    from fricstab.engine import Material, System, jacobian
    from fricstab.io.jacobian_export import read_state
    out = tmp_path / law
    assert main(["shear", "jacobian", "--out", str(out), "--law", law, "--n", "30",
                 "--quiet"]) == 0
    rec = json.loads((out / "jacobian.json").read_text())
    assert rec["law"] == law and rec["max_abs_force_f0"] < 1e-10
    s = read_state(out / "state.npz")
    dofs = json.loads((out / "dofs.json").read_text())
    k = sps.load_npz(out / "jacobian.npz")
    mass = np.load(out / "mass.npy")
    assert k.shape == (dofs["n_dof"],) * 2 == (len(mass),) * 2
    assert dofs["law"] == law and "L0" in dofs["units"]["length"]
    system = System(Material(law, dict(zip(s["param_names"], s["param_values"]))), s["radius"],
                    s["mass"], s["inertia"], family=s["family"], lx=float(s["box"][0]),
                    skin=0.1)
    state = system.state(s["pos"], s["theta"])
    rows = {(int(i), int(j)): h for (i, j), h in zip(s["contacts"], s["history"])}
    for c in range(state.contacts.n):
        key = (int(state.contacts.i[c]), int(state.contacts.j[c]))
        state.contacts.hist[c] = rows.get(key, 0.0)
    _, k2 = jacobian(system, state)
    assert abs(k2 - k).max() <= 1e-12 * abs(k).max()


def test_unknown_scene_key_exit_2(tmp_path, capsys):
    scene = tmp_path / "s.toml"
    scene.write_text("n = 40\nnormal_force = -3.0\n")
    assert main(["shear", "run", "--out", str(tmp_path / "o"), "--scene", str(scene)]) == 2
    err = capsys.readouterr().err
    assert "normal_force" in err and err.strip().count("\n") == 0


def _arrays(out):
    got = {}
    for f in sorted((out / "frames").glob("chunk_*.npz")) + [out / "shear.npz"]:
        with np.load(f, allow_pickle=False) as z:
            for k in z.files:
                got[f"{f.name}:{k}"] = z[k]
    return got


@pytest.fixture(scope="module")
def uninterrupted(tmp_path_factory):
    a = tmp_path_factory.mktemp("shear") / "a"
    subprocess.run(_cmd(a), cwd=ROOT, check=True, timeout=600)
    return a


def test_servo_holds_n(uninterrupted):
    rec = json.loads((uninterrupted / "shear.json").read_text())
    # The velocity servo holds N: the mean relative error over the frames
    # within 1% and its rms within 5% (40 disks: single rearrangements move N
    # by several percent; the 1,000-disk figures are in validation/).
    assert abs(rec["servo"]["mean_rel_error"]) < 0.01
    assert rec["servo"]["rms_rel_error"] < 0.05
    assert not (uninterrupted / "checkpoints").exists()   # removed once complete


@pytest.mark.parametrize("signum, code", [(signal.SIGKILL, -signal.SIGKILL),
                                          (signal.SIGTERM, 143), (signal.SIGINT, 130)])
def test_signal_then_resume_is_bit_identical(tmp_path, uninterrupted, signum, code):
    """A kill at a random moment of the shear stage, then --resume: the frames and
    series equal the uninterrupted run's.  SIGTERM and SIGINT stop at the next
    chunk of the compiled loop with one line naming the signal, exit 143 or 130,
    the checkpoints kept and the lock released."""
    b = tmp_path / "b"
    proc = subprocess.Popen(_cmd(b), cwd=ROOT, stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 600
    while not list((b / "checkpoints").glob("ckpt_*.npz")) and time.time() < deadline:
        if proc.poll() is not None:
            break
        time.sleep(0.05)
    time.sleep(random.Random().uniform(0.0, 0.8))   # a random moment of the shear stage
    assert proc.poll() is None, "run B ended before the kill; lengthen SMALL"
    os.kill(proc.pid, signum)
    err = proc.communicate(timeout=60)[1]
    assert proc.returncode == code
    if signum != signal.SIGKILL:
        name = signal.Signals(signum).name
        assert err.count("\n") == 1 and f"interrupted by {name}" in err and "--resume" in err
        # the step of the shear stage (after its first checkpoint), not of the engine call
        step = re.search(r"at step (\d+)", err)
        assert step and int(step.group(1)) > 0, err
        assert not (b / ".fricstab.lock").exists()
    assert not (b / "shear.json").exists() and list((b / "checkpoints").glob("ckpt_*.npz"))
    subprocess.run(_cmd(b, "--resume"), cwd=ROOT, check=True, timeout=600)
    ra, rb = _arrays(uninterrupted), _arrays(b)
    assert ra.keys() == rb.keys()
    for k in ra:
        assert np.array_equal(ra[k], rb[k]), k


def test_resume_with_a_larger_strain_extends_the_run(tmp_path, uninterrupted, capsys):
    """The total strain only stops a run: --resume with a larger one continues the same
    trajectory (the first frames and series equal the shorter uninterrupted run's to
    the bit); one that the run has already passed is refused with exit 2."""
    b = tmp_path / "b"
    proc = subprocess.Popen(_cmd(b), cwd=ROOT, stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 600
    while not list((b / "checkpoints").glob("ckpt_*.npz")) and time.time() < deadline:
        time.sleep(0.05)
    assert proc.poll() is None, "run B ended before the kill; lengthen SMALL"
    os.kill(proc.pid, signal.SIGTERM)
    assert proc.communicate(timeout=60) and proc.returncode == 143
    assert main(["shear", "run", "--out", str(b), "--quiet", "--no-progress", *SMALL,
                 "--resume", "--strain", "1e-4"]) == 2
    assert "past strain = 0.0001" in capsys.readouterr().err
    subprocess.run(_cmd(b, "--resume", "--strain", "0.03"), cwd=ROOT, check=True, timeout=600)
    ra, rb = _arrays(uninterrupted), _arrays(b)
    chunks = [k for k in ra if k.startswith("chunk_") and not k.endswith(":header")]
    assert len(chunks) > 10 and all(np.array_equal(ra[k], rb[k]) for k in chunks)
    n = len(ra["shear.npz:tau"])
    assert len(rb["shear.npz:tau"]) == 301 and n == 201
    for k in (k for k in ra if k.startswith("shear.npz:")):
        assert np.array_equal(ra[k], rb[k][:n]), k
    assert json.loads((b / "shear.json").read_text())["parameters"]["strain"] == 0.03
