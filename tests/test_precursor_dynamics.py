"""The analysis of ``validation/precursor_dynamics.py`` on synthetic records with known answers
(the dynamics itself: ``tests/test_pack_dynamics.py``)."""

import importlib.util
from pathlib import Path

import numpy as np
import pytest

SCRIPT = Path(__file__).resolve().parents[1] / "validation" / "precursor_dynamics.py"


@pytest.fixture(scope="module")
def pd():
    spec = importlib.util.spec_from_file_location("precursor_dynamics", SCRIPT)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _record(pd, g, rate=1e-5, intervals=40, grow=range(10, 20)):
    """E_na growing at exactly 2 g in the intervals ``grow``, constant elsewhere; a stress
    that drops by 1e-3 after interval 19."""
    n = intervals * pd.QS_EVERY + 1
    t = np.arange(n) * pd.REC_STRAIN / rate
    rate_of = np.zeros(n - 1)
    for i in grow:
        rate_of[pd.QS_EVERY * i:pd.QS_EVERY * (i + 1)] = 2 * g
    log_e = np.concatenate([[0.0], np.cumsum(rate_of * np.diff(t))]) - 30.0
    stress = 1e-3 + 1e-6 * np.arange(n)
    stress[pd.QS_EVERY * 20 + 1:] -= 1e-3
    return {"time": t, "strain": rate * t, "stress": stress, "e_na": np.exp(log_e),
            "qs_strain": rate * t[::pd.QS_EVERY][:intervals],
            "qs_growth": np.full(intervals, g), "qs_n_pairs": np.ones(intervals),
            "rate": rate, "seconds": 0.0}


def test_interval_rates_recover_twice_the_growth(pd):
    """ln E_na is exactly linear in each growing interval: the fit returns 2 g to rounding
    (relative 1e-9: polyfit on times ~1e4 with log values ~30)."""
    g = 3e-3
    r = _record(pd, g)
    rr = pd.interval_rates(r)
    assert np.allclose(rr[10:20], 2 * g, rtol=1e-9)
    assert np.allclose(rr[:10], 0.0, atol=1e-12) and np.allclose(rr[21:40], 0.0, atol=1e-12)
    assert pd.episodes(rr, pd.QS_EVERY * pd.REC_STRAIN / 1e-5) == [(10, 20)]


def test_growth_before_the_drop_measured_and_predicted(pd):
    """The drop after interval 19 is located at its onset; the 5 intervals before it grow by
    exactly 2 g dt each, as predicted."""
    g = 3e-3
    r = _record(pd, g)
    rr = pd.interval_rates(r)
    drops = pd.detect_drops(r["qs_strain"], pd.interval_stress(r))
    assert [d.step - 1 for d in drops] == [19]
    m, p = pd.pre_drop_growth(r, rr)
    dt = pd.QS_EVERY * pd.REC_STRAIN / r["rate"]
    assert m[19] == pytest.approx(pd.LEAD * 2 * g * dt, rel=1e-9)
    assert p[19] == pytest.approx(pd.LEAD * 2 * g * dt, rel=1e-12)


def test_analyse_reports_the_episode_and_its_ratio(pd):
    rows = pd.analyse({("law", 1e-5): [_record(pd, 3e-3)]}, half_width=5, n_perm=99, n_rep=10)
    (row,) = rows
    e_folds, ratio, start = row["largest"][0]
    assert ratio == pytest.approx(1.0, rel=1e-9)
    assert e_folds == pytest.approx(10 * 2 * 3e-3 * pd.QS_EVERY * pd.REC_STRAIN / 1e-5, rel=1e-9)
    assert row["drops"] == 1
