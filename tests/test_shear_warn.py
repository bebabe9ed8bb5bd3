"""``fricstab shear run`` says when to distrust it (issue 32): servo error, tau < 0, --help."""

import json
import re
import subprocess
import sys
from pathlib import Path

import numpy as np

from fricstab.cli.shear import (NEGATIVE_TAU_WARN, PRESETS, SERVO_RMS_WARN, quality)
from fricstab.scenes.shear import SCHEMA

ROOT = Path(__file__).resolve().parents[1]
#: `fricstab shear run` with the defaults (quick preset, seed 0): strain, tau,
#: normal_force and n_target of its shear.npz / shear.json, copied from the
#: run of `python validation/shear_knobs.py` (base, seed 0) whose servo rms
#: 0.22 % is the claim shear.quick_servo (validation/records/shear.knobs.json).
QUICK_SERIES = ROOT / "tests" / "data" / "shear_quick_seed0_series.npz"
#: The cell of docs/figures.md that issue 32 found untrustworthy (~10 s on one core).
SMALL = ["--n", "100", "--strain", "0.03", "--dgamma", "1e-5", "--gamma0", "0.01"]


def test_a_small_cell_warns_on_stderr_and_in_the_record(tmp_path):
    out = tmp_path / "run"
    proc = subprocess.run([sys.executable, "-m", "fricstab", "shear", "run", "--out", str(out),
                           "--quiet", "--no-progress", *SMALL], cwd=ROOT, capture_output=True,
                          text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    lines = [x for x in proc.stderr.splitlines() if x.startswith("fricstab: warning:")]
    rec = json.loads((out / "shear.json").read_text())
    q = rec["quality"]
    assert q["warnings"] and len(lines) == len(q["warnings"])
    assert [x.removeprefix("fricstab: warning: ") for x in lines] == q["warnings"]
    # the record's numbers are those of shear.npz over the window strain >= gamma0
    s = np.load(out / "shear.npz")
    win = s["strain"][1:] >= 0.01
    err = s["normal_force"][1:][win] / rec["derived"]["normal_force_N_per_m"] - 1.0
    # the same float64 operations in another order: relative round-off ~1e-15
    assert np.isclose(q["servo_rms_window"], np.sqrt(np.mean(err ** 2)), rtol=1e-12)
    assert q["negative_tau_fraction_window"] == np.mean(s["tau"][1:][win] < 0.0)
    # issue 32: tau < 0 for long stretches, N off by several percent (seed 0: 34 %, 8.4 %)
    assert q["negative_tau_fraction_window"] > NEGATIVE_TAU_WARN
    assert q["servo_rms_window"] > SERVO_RMS_WARN


def test_the_quick_preset_run_does_not_warn():
    s = np.load(QUICK_SERIES)
    q = quality(s["strain"], s["tau"], s["normal_force"], float(s["n_target"]),
                float(s["gamma0"]))
    assert q["warnings"] == []
    assert q["window_frames"] == 3801          # frames 2200..6000: strain 0.022..0.06
    assert q["servo_rms_window"] < SERVO_RMS_WARN / 3   # the margin the thresholds claim


def test_quality_warns_on_each_measure_alone():
    strain = np.linspace(0.0, 0.03, 301)
    tau, n = np.full(301, 0.2), np.ones(301)
    assert quality(strain, tau, n, 1.0, 0.01)["warnings"] == []
    n_bad = n.copy()
    n_bad[200:] = 1.1                          # 10 % off in half the window
    assert "servo" in " ".join(quality(strain, tau, n_bad, 1.0, 0.01)["warnings"])
    tau_bad = tau.copy()
    tau_bad[250:] = -0.1                       # 51 of 200 window frames
    (w,) = quality(strain, tau_bad, n, 1.0, 0.01)["warnings"]
    assert "tau = S/N < 0" in w


def _help_entries(text):
    """Option -> its help text (whitespace joined) of an argparse ``--help``."""
    entries, cur = {}, None
    for line in text.splitlines():
        m = re.match(r"  (--[a-z0-9-]+)", line)
        if m:
            cur = m.group(1)
            entries[cur] = line
        elif cur and line.startswith("   "):
            entries[cur] += " " + line
        else:
            cur = None
    return {k: " ".join(v.split()) for k, v in entries.items()}


def test_help_shows_the_real_preset_values():
    proc = subprocess.run([sys.executable, "-m", "fricstab", "shear", "run", "--help"],
                          cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    entries = _help_entries(proc.stdout)
    for f in SCHEMA.fields:
        if f.key in ("seed", "checkpoint_every"):
            continue
        text = entries[f.option]
        assert f"(default {f.default:g}" in text, text
        for name in ("paper", "large"):
            value = PRESETS[name].get(f.key, f.default)
            shown = f"--preset {name}: {value:g}" in text
            assert shown == (value != f.default), (f.option, name, text)
    assert "--preset paper: 1000;" in entries["--n"]   # the example, typed once
