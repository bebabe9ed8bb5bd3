"""The report functions of the plane-shear validation scripts on synthetic inputs (no runs).

``shear_sweep.report`` and ``shear_knobs.write`` are what the claims of
``validation/claims/shear.py`` call after their runs; here they get members and
tables made up for the test, so that a change of their format fails in seconds.
"""

import json
import sys
from pathlib import Path


HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import shear_knobs  # noqa: E402
import shear_sweep  # noqa: E402

BINS = ((-1e-1, -1e-2), (-1e-2, -1e-3), (-1e-3, -1e-4), (-1e-4, 0.0),
        (0.0, 1e-4), (1e-4, 1e-3), (1e-3, 1e-2), (1e-2, 1e-1))


def _cells(rho):
    return [{"lo": lo, "hi": hi, "n": 20, "rho": rho, "p": 0.01, "significant": True,
             "status": "ok"} for lo, hi in BINS]


#: the tables and series of an analysis (fricstab.analysis.shear.analyze)
SERIES = {"step_dtau": ("g", "g10"), "phase_all": ("mg", "mg10", "sg", "sg10"),
          "phase_long": ("mg", "mg10", "sg", "sg10"), "phase_short": ("mg", "mg10", "sg", "sg10"),
          "phase_tp": ("long", "short")}


def _member(rate, steps, rho):
    tables = {t: {s: _cells(rho) for s in series} for t, series in SERIES.items()}
    rec = {"phases": {"phases_per_step": rate, "n_phases": round(rate * steps),
                      "window_steps": steps}}
    return shear_sweep.as_member(rec, {"summary": {}, "tables": tables})


def test_sweep_report_writes_the_page_and_returns_its_numbers(tmp_path):
    res = {f"mu{m:g}": _member(0.1 * (k + 1), 1000, 0.5) for k, m in enumerate(shear_sweep.PAPER)}
    md = tmp_path / "sweep.md"
    out = shear_sweep.report(res, md)
    assert set(out) == {f"{m:g}" for m in shear_sweep.PAPER}
    assert out["0.7"]["rate"] == 0.4 and out["0.7"]["steps"] == 1000
    assert out["0.1"]["tables"]["phase_long"]["mg10"][0]["rho"] == 0.5
    text = md.read_text()
    assert "| 0.7 | 400 | 1000 | 0.400 | 0.323 |" in text
    # every cell moderate (0.5, n = 20): 4.4 (long phases mostly moderate) agrees at every
    # mu_s, 4.3 (strong below -1e-2) disagrees at every one
    assert "| 4.4 | 13c, g |" in text and "| 4.3 | 13c, g |" in text
    row = next(ln for ln in text.splitlines() if ln.startswith("| 4.3 |"))
    assert row.endswith("| disagrees | disagrees | disagrees | disagrees | **disagrees** |")
    assert "(j) Delta tau_p - t_p, long phases" in text
    assert (tmp_path / "shear_sweep_fig13c.png").stat().st_size > 1000
    json.dumps(out)


def test_sweep_report_reads_members_stored_without_their_step_count(tmp_path):
    res = {f"mu{m:g}": _member(0.25, 800, 0.3) for m in shear_sweep.PAPER}
    for r in res.values():
        del r["window_steps"]
    out = shear_sweep.report(res, tmp_path / "sweep.md")
    assert all(x["steps"] == 800 for x in out.values())


def test_knobs_write_tabulates_every_seed(tmp_path):
    table = {"base": {"0": {"rate": 0.128}, "1": {"rate": 0.148}, "2": {"rate": 0.203}},
             "kappa": {"0": {"rate": 0.362}}}
    md = tmp_path / "knobs.md"
    shear_knobs.write(table, (0, 1, 2), ("base", "kappa"), md)
    text = md.read_text()
    assert "| the quick preset | 0.128, 0.148, 0.203 | 0.160 | 0.128-0.203 |" in text
    assert "| kappa = 1e4 (quick 1e3) | 0.362 | 0.362 | 0.362-0.362 |" in text


def test_long_phases_report_on_synthetic_arrays(tmp_path):
    """``shear_long_phases.report`` reads RUN/analysis.npz and writes the two verdicts: angles
    independent of Delta tau_p agree with Fig. 11; sg10 as strongly tied to |Delta tau_p| as
    mg10 holds the Sec. 4 statement in every bin (not significantly weaker)."""
    import numpy as np
    import shear_long_phases
    rng = np.random.default_rng(0)
    n, steps = 2000, 10000
    dt = -10.0 ** rng.uniform(-4.5, -1, n)
    mag = np.abs(dt)
    ang = rng.uniform(0, np.pi / 2, steps)
    np.savez(tmp_path / "analysis.npz", phase_dtau_p=dt, phase_t_p=rng.integers(4, 9, n),
             phase_ts=rng.integers(0, steps, n), phase_mg10=mag * (1 + rng.random(n)),
             phase_sg10=mag * (1 + rng.random(n)), angle_mean=ang, angle_median=ang)
    doc = shear_long_phases.report(tmp_path, n_boot=200)
    assert doc["fig11_verdict"].startswith("agrees")
    assert doc["sg_verdict"].startswith("agrees") and "4 of 4" in doc["sg_verdict"]
    text = (tmp_path / "long_phases.md").read_text()
    assert "## Fig. 11" in text and "almost equal" in text
    assert json.loads((tmp_path / "long_phases.json").read_text())["n_boot"] == 200
