"""CI quick tier of the plane shear (Lee & Hurley): stick-slip appears in a small cell.

A smaller version of the quick default (150 disks, strain 0.03, window from
strain 0.01; the quick preset's I = 1e-4 and kappa = 1e3) must show stick and
slip phases with stress drops, keep the normal force on target, and write its
figure.  The full quick default is ``python validation/shear_quick.py``.
"""

import json

import numpy as np

from fricstab.cli.shear import resolve_params, run_shear


def test_small_cell_shows_stick_slip(tmp_path):
    p = resolve_params(None, "quick", {"n": 150, "strain": 0.03, "gamma0": 0.01})
    rec = run_shear(p, tmp_path, log=lambda *a: None)
    ph = rec["phases"]
    # stick-slip: both kinds of phase, many of them (tau is not monotonic), and
    # at least one drop of tau larger than 1% of N (a slip event, not noise:
    # the servo's rms error of N is below 1% and tau fluctuates by less between
    # events, see validation/shear_quick.md)
    assert ph["n_stick"] >= 10 and ph["n_slip"] >= 10
    assert ph["largest_drop"] < -0.01
    assert abs(rec["servo"]["mean_rel_error"]) < 0.01
    with np.load(tmp_path / "shear.npz") as z:
        tau = z["tau"]
    assert np.all(np.isfinite(tau)) and len(tau) == 3001
    assert (tmp_path / "shear.png").stat().st_size > 1000
    assert json.loads((tmp_path / "shear.json").read_text())["parameters"]["n"] == 150
