"""Checkpoints: atomic, fingerprinted, and a SIGKILLed run resumes bit for bit."""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from fricstab.io.checkpoint import Checkpointer
from fricstab.cli import main
from fricstab.errors import NumericalError, check_finite
from fricstab.laws import ParameterError

ROOT = Path(__file__).resolve().parent.parent


def test_latest_prunes_and_checks_the_fingerprint(tmp_path):
    ck = Checkpointer(tmp_path / "c", {"n": 3, "dt": 0.1}, keep=2)
    assert ck.latest() is None
    for step in (10, 20, 30):
        ck.save(step, q=np.full(3, float(step)))
    assert sorted(p.name for p in (tmp_path / "c").iterdir()) == \
        ["ckpt_000000000020.npz", "ckpt_000000000030.npz"]
    last = ck.latest()
    assert int(last["step"]) == 30 and np.array_equal(last["q"], np.full(3, 30.0))
    with pytest.raises(ParameterError, match="dt: 0.1 there, 0.2 now"):
        Checkpointer(tmp_path / "c", {"n": 3, "dt": 0.2}).latest()
    ck.clear()
    assert not (tmp_path / "c").exists()


def test_a_hand_edited_checkpoint_is_refused(tmp_path):
    """A checkpoint carries a SHA-256 of its arrays: one changed value (written back
    as a valid NPZ) is refused by --resume, naming the file."""
    ck = Checkpointer(tmp_path / "c", {"n": 3})
    path = ck.save(10, q=np.arange(3.0), v=np.zeros(3))
    with np.load(path) as z:
        data = {k: z[k] for k in z.files}
    data["q"][1] = 1.5
    with open(path, "wb") as fh:
        np.savez(fh, **data)
    with pytest.raises(ParameterError, match="ckpt_000000000010.npz does not match its checksum"):
        ck.latest()


def test_check_finite_names_item_component_and_step():
    f = np.zeros((4, 3))
    check_finite("force", f, step=5)
    f[2, 1] = np.nan
    f[3, 0] = np.inf
    with pytest.raises(NumericalError) as err:
        check_finite("force", f, step=5, item="particle", components=("F_x", "F_y", "T"))
    assert str(err.value) == "non-finite force F_y = nan of particle 2 at step 5 " \
                             "(2 non-finite entries)"
    assert err.value.step == 5 and err.value.item == 2


def test_dynamics_stops_at_the_first_nonfinite_force(monkeypatch):
    from fricstab.errors import ParameterError
    from fricstab.protocols import dynamics
    from fricstab.scenes.chain import ChainScene, initial_state
    scene = ChainScene(n=3)
    v = np.zeros((3, 3))
    v[1, 0] = np.nan             # disk 1 moves to NaN in the first drift (its neighbours' forces too)
    # the front door refuses a NaN velocity before the engine runs ...
    with pytest.raises(ParameterError, match="velocity must be finite"):
        dynamics.run_dynamics(scene, initial_state(scene), velocity=v, duration=1.0)
    # ... and behind it the engine stops at the first non-finite position it meets
    monkeypatch.setattr(dynamics, "check_finite_array", lambda *a, **k: a[1])
    with pytest.raises(NumericalError, match=r"^non-finite position of disk 1 at Verlet step 1$"):
        dynamics.run_dynamics(scene, initial_state(scene), velocity=v, duration=1.0)


def test_numerical_failure_exits_4(tmp_path, capsys, monkeypatch):
    # waves and growth bind run_dynamics when first imported: import them before
    # the patch, or a first import under it would keep the patched function
    from fricstab.protocols import dynamics, growth, waves  # noqa: F401  (bound before the patch)

    def blow_up(*args, **kwargs):
        raise NumericalError("non-finite force F_x on disk 3 at Verlet step 17")

    monkeypatch.setattr(dynamics, "run_dynamics", blow_up)
    rc = main(["chain", "dynamics", "--fx", "0.01", "--duration", "10", "--n", "4",
               "--out", str(tmp_path / "o"), "--no-progress"])
    err = capsys.readouterr().err
    assert rc == 4 and err.count("\n") == 1 and "disk 3 at Verlet step 17" in err
    assert "--resume" in err and not (tmp_path / "o" / "dynamics.json").exists()


def _load(out):
    doc = json.loads((out / "dynamics.json").read_text())
    with np.load(out / "dynamics.npz") as z:
        arrays = {k: z[k] for k in z.files}
    numbers = {k: doc[k] for k in ("first_breach_paper_time", "first_slide_paper_time",
                                   "first_breach_x", "final_msd")}
    return arrays, numbers


def test_sigkill_then_resume_is_bit_identical(tmp_path):
    argv = ["chain", "dynamics", "--fx", "0.085", "--duration", "24000", "--seed", "3",
            "--checkpoint-every", "20000", "--no-progress", "--quiet"]
    assert main(argv + ["--out", str(tmp_path / "a")]) == 0
    out = tmp_path / "b"
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    proc = subprocess.Popen([sys.executable, "-m", "fricstab", *argv, "--out", str(out)],
                            cwd=ROOT, env=env, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 120
    while not list((out / "checkpoints").glob("ckpt_*.npz")) and proc.poll() is None:
        assert time.monotonic() < deadline
        time.sleep(0.01)
    # a random moment after the first checkpoint (seeded: the test is reproducible)
    time.sleep(np.random.default_rng(int(time.time()) % 1000).uniform(0.0, 0.3))
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    assert proc.returncode == -signal.SIGKILL
    assert not (out / "dynamics.json").exists()       # killed mid-run: no record yet
    assert main(argv + ["--out", str(out), "--resume"]) == 0
    a_arrays, a_numbers = _load(tmp_path / "a")
    b_arrays, b_numbers = _load(out)
    assert json.loads((out / "dynamics.json").read_text())["resumed_from_step"] > 0
    assert set(a_arrays) == set(b_arrays)
    for key in a_arrays:
        assert np.array_equal(a_arrays[key], b_arrays[key], equal_nan=True), key
    assert a_numbers == b_numbers
    assert not (out / "checkpoints").exists()         # removed once the result is complete
