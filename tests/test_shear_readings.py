"""The two readings of Lee & Hurley's protocol (issue 34, item 1): restitution against damping
ratio (``damping_ratio``), kappa as E*/P against k_n/P (``kappa_from_kn``), and the study that
compares them (``validation/shear_protocol.py``) on a tiny cell."""

import json
import math
import shutil
import sys
from pathlib import Path

import numpy as np
import pytest

from fricstab.errors import ParameterError
from fricstab.scenes.shear import damping_ratio, kappa_from_kn, restitution, typical_overlap

VALIDATION = Path(__file__).resolve().parents[1] / "validation"


@pytest.mark.parametrize("e", [0.05, 0.5, 0.73, 0.9, 0.99])
def test_damping_ratio_inverts_restitution(e):
    """Round trip to rounding (a few ulps through log, sqrt and exp)."""
    assert restitution(damping_ratio(e)) == pytest.approx(e, rel=1e-14)


def test_damping_ratio_values():
    """The paper's e = 0.9 is a ratio of 0.0335 (Hu et al.'s linear damping), against the 0.1
    the paper lists as damping constants; e = 1 is no damping, e = 0 critical."""
    assert damping_ratio(0.9) == pytest.approx(0.0335, abs=5e-5)
    assert damping_ratio(1.0) == 0.0 and damping_ratio(0.0) == 1.0
    with pytest.raises(ParameterError, match="restitution"):
        damping_ratio(1.2)


@pytest.mark.parametrize("kappa_kn", [1e2, 1e3, 1e4, 1e6])
def test_kn_reading_puts_the_typical_overlap_at_d_over_kappa(kappa_kn):
    """k_n / P = kappa means delta_0 = f_0 / k_n = P d / k_n = d / kappa = 2 L0 / kappa: the
    E*/P it returns, through the scene's own typical_overlap (a root find to ~4 eps), gives
    that overlap to ~1e-12 relative (the root find's tolerance amplified by the force law's
    slope, ~1.5 on the log scale)."""
    ke = kappa_from_kn(kappa_kn)
    assert typical_overlap(ke) == pytest.approx(2.0 / kappa_kn, rel=1e-12)
    # the pressure it implies is lower than E*/kappa: k_n < E* for Hertz cylinders at these
    # overlaps (A2: pi E* / [2 log(4R/a) - 1])
    assert ke > kappa_kn


def test_kn_reading_rejects_soft_contacts():
    with pytest.raises(ParameterError, match="kappa_kn"):
        kappa_from_kn(5.0)


def test_protocol_study_on_a_tiny_cell(tmp_path):
    """Four readings, one seed, a 40-disk cell sheared 1 %: the runs carry the reading's
    parameters, and the table and JSON come out (the observables are checked for existence
    and range only: a 40-disk cell decides nothing)."""
    sys.path.insert(0, str(VALIDATION))
    import shear_protocol as sp
    sp.SCALES["tiny"] = {"n": 40, "strain": 0.01, "gamma0": 0.002}
    try:
        rows = {r: {"0": sp.one("tiny", r, 0, tmp_path / "cache", log=lambda m: None,
                                store=tmp_path / "store")}
                for r in sp.READINGS}
        summary = sp.summarise(rows)
        sp.write(rows, summary, "tiny", [0], tmp_path)
    finally:
        del sp.SCALES["tiny"]
    doc = json.loads((tmp_path / "shear_protocol_tiny.json").read_text())
    assert set(doc["runs"]) == set(sp.READINGS)
    a = damping_ratio(0.9)
    assert rows["restitution"]["0"]["alpha_n"] == pytest.approx(a)
    assert rows["damping"]["0"]["alpha_n"] == 0.1
    p_kn = rows["kn"]["0"]["pressure_over_estar"]
    assert 1.0 / p_kn == pytest.approx(kappa_from_kn(1e3))
    for r in rows.values():
        o = r["0"]
        assert 0.0 <= o["rate"] <= 1.0 and math.isfinite(o["tau_mean"])
        assert o["n_slips"] >= 0
    assert "not judged" in doc["verdict"]
    # a stored run is reused (no new run: the log stays silent), and from the store alone:
    # the run's own folder (frames: not committed) is not needed
    assert (tmp_path / "store" / "tiny" / "damping_s0.npz").exists()
    shutil.rmtree(tmp_path / "cache")
    logged = []
    sp.SCALES["tiny"] = {"n": 40, "strain": 0.01, "gamma0": 0.002}
    try:
        again = sp.one("tiny", "damping", 0, tmp_path / "cache", log=logged.append,
                       store=tmp_path / "store")
        # other parameters (a longer strain) are run again, not read from the store
        sp.SCALES["tiny"] = {"n": 40, "strain": 0.012, "gamma0": 0.002}
        assert sp.one("tiny", "damping", 0, tmp_path / "cache", run=False,
                      store=tmp_path / "store") is None
    finally:
        del sp.SCALES["tiny"]
    assert logged == [] and again == rows["damping"]["0"]
    assert np.isfinite(summary["damping"]["rate"]["mean"])


def test_a_run_that_fails_to_prepare_is_a_row_that_says_so(tmp_path):
    """A preparation that does not settle (here: 500 steps allowed, x 3.8 for kn) is stored as a failure
    with its message, is reused like a finished run, and the table names it instead of
    stopping the study with a traceback."""
    sys.path.insert(0, str(VALIDATION))
    import shear_protocol as sp
    sp.SCALES["tiny"] = {"n": 40, "strain": 0.01, "gamma0": 0.002, "prep_max_steps": 500}
    try:
        got = sp.one("tiny", "kn", 0, tmp_path / "cache", log=lambda m: None,
                     store=tmp_path / "store")
        again = sp.one("tiny", "kn", 0, tmp_path / "cache", run=False, store=tmp_path / "store")
        rows = {"kn": {"0": got}}
        summary = sp.summarise(rows)
        sp.write(rows, summary, "tiny", [0], tmp_path)
    finally:
        del sp.SCALES["tiny"]
    assert got["failure"].startswith("preparation: after ") and got["seconds"] > 0
    assert again == got
    assert summary["kn"]["failed"] == {"0": got["failure"]} and "rate" not in summary["kn"]
    table = (tmp_path / "shear_protocol_tiny.md").read_text()
    assert "failed (seed 0: preparation: after " in table


def _summary(**rates):
    """A summary of readings: name -> (seed mean, standard error) of the phase rate."""
    return {r: {"failed": {}, "rate": {"mean": m, "se": se, "n": 3}}
            for r, (m, se) in rates.items()}


def test_a_readings_effect_is_carried_to_the_papers_cell_with_its_error():
    """The prediction is the paper-preset run's rate times the decide-scale ratio, its relative
    errors added in quadrature (the three are independent runs); the damping reading is the
    paper-preset run itself, with that run's error alone."""
    sys.path.insert(0, str(VALIDATION))
    import shear_protocol as sp
    paper = {"rate": 0.30, "se": 0.01}
    t = sp.transfer(_summary(damping=(0.40, 0.02), restitution=(0.44, 0.03)), paper)
    assert t["damping"]["predicted"] == pytest.approx(0.30)
    assert t["damping"]["se"] == pytest.approx(0.01)
    rel = math.sqrt((0.01 / 0.30) ** 2 + (0.03 / 0.44) ** 2 + (0.02 / 0.40) ** 2)
    assert t["restitution"]["predicted"] == pytest.approx(0.33)
    assert t["restitution"]["se"] == pytest.approx(0.33 * rel)
    assert t["restitution"]["distance"] == pytest.approx((0.33 - 0.323) / (0.33 * rel))
    # without the damping reading, or a reading without an error, nothing is carried
    assert sp.transfer(_summary(restitution=(0.44, 0.03)), paper) == {}
    assert "kn" not in sp.transfer(_summary(damping=(0.4, 0.02), kn=(0.5, None)), paper)


@pytest.mark.parametrize("rates, paper, pick, supported", [
    # both near 0.323: not separated, the preset stays
    ({"damping": (0.40, 0.02), "restitution": (0.44, 0.02)}, (0.30, 0.02), "damping",
     ["damping", "restitution"]),
    # the preset far below, the other reading on 0.323: it is chosen
    ({"damping": (0.40, 0.004), "restitution": (0.646, 0.004)}, (0.20, 0.002), "restitution",
     ["restitution"]),
    # the preset excluded and two others on 0.323: undecided between them
    ({"damping": (0.40, 0.004), "restitution": (0.646, 0.004), "kn": (0.646, 0.004)},
     (0.20, 0.002), None, ["restitution", "kn"]),
    # nothing near 0.323: the preset stays, and the text says the rate supports none
    ({"damping": (0.40, 0.004), "restitution": (0.30, 0.004)}, (0.10, 0.002), "damping", []),
])
def test_the_reading_chosen_follows_the_stated_rule(rates, paper, pick, supported):
    sys.path.insert(0, str(VALIDATION))
    import shear_protocol as sp
    got, ok, why = sp.chosen(_summary(**rates), "decide", {"rate": paper[0], "se": paper[1]})
    assert got == pick and ok == supported
    assert ("supports none" in why) == (not supported)
    # below the decide scale nothing is judged
    assert sp.chosen(_summary(**rates), "quick")[0] is None


def test_the_paper_preset_rate_and_its_error_come_from_the_windows_along_the_run(tmp_path):
    sys.path.insert(0, str(VALIDATION))
    import shear_protocol as sp
    w = [0.30, 0.28, 0.26, 0.32]
    (tmp_path / "p.json").write_text(json.dumps(
        {"summary": {"phases_per_step": 0.29}, "along_the_run": [{"per_step": x} for x in w]}))
    got = sp.paper_preset_rate(tmp_path / "p.json")
    assert got["rate"] == 0.29
    assert got["se"] == pytest.approx(np.std(w, ddof=1) / 2.0)
