"""The steady-state test of :mod:`fricstab.analysis.stationarity`: its size, its power, the
steady start, and its errors on bad input."""

import numpy as np
import pytest

from fricstab.analysis.autocorrelation import integrated_time, memory_blocks, memory_growth
from fricstab.analysis.stationarity import (memory_trend_test, steady_start, steady_window,
                                            trend_test)
from fricstab.errors import ParameterError


def _ar1(rng, n, phi=0.9, size=1):
    """Correlated noise (correlation length ~ 1/(1 - phi) = 10 values), unit variance."""
    e = rng.normal(size=(size, n)) * np.sqrt(1 - phi ** 2)
    x = np.empty((size, n))
    x[:, 0] = rng.normal(size=size)
    for i in range(1, n):
        x[:, i] = phi * x[:, i - 1] + e[:, i]
    return x


def test_size_on_stationary_correlated_noise():
    """Blocks of 100 values, 10x the correlation length: the test rejects a stationary
    series at about its level.  Error model: 600 independent series, the rejection count is
    binomial(600, r); with r = 0.05 its standard error is 0.0089, and block means of an AR(1)
    with 10x-longer blocks keep a lag-1 correlation ~0.1, which inflates the size a little.
    The bound 0.05 + 4 x 0.0089 = 0.086 fails for a test that ignores the correlation (a
    frame-wise Kendall test on this noise rejects ~70 % of the series)."""
    rng = np.random.default_rng(0)
    x = _ar1(rng, 2000, size=600)
    rej = np.mean([not trend_test(s, n_blocks=20)["steady"] for s in x])
    assert rej < 0.05 + 4 * np.sqrt(0.05 * 0.95 / 600)


def test_power_against_a_drift():
    """A drift of 2 std over the window is found.  Block means of this noise have a std of
    ~0.44 (variance (1 + phi)/(1 - phi)/100 per block of 100), so a drift of 2 spans ~4.5 of
    their std; measured power ~0.99 (1.0 at a drift of 3, 0.78 at 1).  Error model: 200
    series, the count of rejections is binomial; the bound 0.9 is 6 standard errors below
    0.99 (se 0.007) and fails for a test without power (the size, ~0.05)."""
    rng = np.random.default_rng(1)
    x = _ar1(rng, 2000, size=200) + np.linspace(0, 2, 2000)
    tests = [trend_test(s) for s in x]
    assert np.mean([not t["steady"] for t in tests]) > 0.9
    drift = np.median([t["drift_over_std"] for t in tests])
    # the std of x includes the drift (sqrt(1 + 4/12) = 1.15): the drift reads ~1.7
    assert 1.4 < drift < 2.0


def test_steady_start_after_a_transient():
    """A rise over the first 40 % (3 std) then a stationary series: the accepted start lies
    at or after the end of the rise minus one candidate spacing (the rise's last part is
    within the noise), and before the end of the scan."""
    rng = np.random.default_rng(2)
    n = 4000
    t = np.linspace(0.0, 0.1, n)
    x = _ar1(rng, n)[0] + 3.0 * np.clip(t / 0.04, 0, 1)
    start, test = steady_start(t, x)
    spacing = 0.07 / 19
    assert start is not None and 0.04 - 2 * spacing <= start <= 0.07
    assert test["steady"] and test["n_values"] >= 0.3 * n


def test_steady_start_none_for_a_drifting_series():
    t = np.linspace(0.0, 0.1, 3000)
    x = 5 * t / 0.1 + 0.01 * np.random.default_rng(3).normal(size=t.size)
    start, test = steady_start(t, x)
    assert start is None and not test["steady"]


@pytest.mark.parametrize("x, kw, match", [
    (np.ones(10), {"n_blocks": 20}, "at least 2 values per block"),
    (np.r_[np.ones(100), np.nan], {}, "non-finite"),
    (np.ones((10, 10)), {}, "one-dimensional"),
    (np.ones(100), {"n_blocks": 3}, "at least 4 blocks"),
    (np.ones(100), {"alpha": 1.5}, "test level"),
])
def test_bad_input(x, kw, match):
    with pytest.raises(ParameterError, match=match):
        trend_test(x, **kw)


def test_constant_series_is_steady():
    r = trend_test(np.full(100, 0.3))
    assert r["steady"] and r["drift_over_std"] == 0.0 and r["std"] == 0.0


def test_steady_start_rejects_a_decreasing_axis():
    with pytest.raises(ParameterError, match="must not decrease"):
        steady_start(np.linspace(1, 0, 100), np.ones(100))


def test_steady_window_starts_after_the_transient_or_at_gamma0():
    """The rise of test_steady_start_after_a_transient: the window starts at or after the end
    of the rise less three candidate spacings (0.063 / 19 from gamma0 = 0.01: the last 0.75
    std of the rise, which the block means' noise of ~0.44 std hides at the test's level),
    never before gamma0, on independent blocks; gamma0 past the transient: the first candidate passes; a
    drift to the end gives gamma0 and says so; too few frames after gamma0 give gamma0 with
    the reason."""
    rng = np.random.default_rng(2)
    n = 4000
    t = np.linspace(0.0, 0.1, n)
    x = _ar1(rng, n)[0] + 3.0 * np.clip(t / 0.04, 0, 1)
    start, info = steady_window(t, x, 0.01)
    assert info["steady"] and start == info["start"]
    assert 0.04 - 3 * 0.063 / 19 <= start <= 0.07
    assert info["n_blocks"] == 20 and info["n_values"] / info["n_blocks"] >= 2 * info["tau_int"]
    start, info = steady_window(t, x, 0.06)
    assert info["steady"] and start == pytest.approx(0.06, abs=1e-4)
    drift = 5 * t / 0.1 + 0.01 * rng.normal(size=n)
    start, info = steady_window(t, drift, 0.02)
    assert start == 0.02 and not info["steady"] and "extend the run" in info["reason"]
    start, info = steady_window(t, x, 0.0999)
    assert start == 0.0999 and not info["steady"] and "frames for the blocks" in info["reason"]
    with pytest.raises(ParameterError, match="one length"):
        steady_window(t, x[:-1], 0.0)
    with pytest.raises(ParameterError, match="must not decrease"):
        steady_window(t[::-1], x, 0.0)


def test_integrated_time_of_correlated_noise():
    """AR(1) with phi = 0.9: tau_int = (1 + phi) / (1 - phi) = 19 values.  Error model: the
    estimate of one series of 20,000 values has a relative standard error ~sqrt(2 (2M + 1) /
    N) ~ 0.1 (Sokal; window M ~ 5 tau_exp ~ 50), so the mean of 40 has ~0.016; the bound
    4 x 0.016 fails for an estimator off by a factor (the lag-1 correlation alone reads 0.9,
    the exponential time 9.5).  A drift of 5 std added to each series reads as memory (the
    estimate grows more than 10x): the error is towards calling a drifting window too short
    for the test, never towards calling it steady."""
    rng = np.random.default_rng(4)
    xs = _ar1(rng, 20_000, size=40)
    g = np.array([integrated_time(v) for v in xs])
    assert abs(g.mean() / 19 - 1) < 4 * 0.016
    drifted = np.array([integrated_time(v + np.linspace(0, 5, v.size)) for v in xs])
    assert np.min(drifted / g) > 10
    assert integrated_time(np.full(50, 2.0)) == 1.0
    assert integrated_time(rng.normal(size=5000)) < 1.2


def test_memory_blocks_size_the_test_by_the_memory():
    """Size: on AR(1) noise (tau_int 19, 2,000 values) the blocks are 100 values, 20 of them,
    independent (>= 2 x tau_int) for all but the series whose estimate exceeds 50 (its
    estimates on 2,000 values spread 13-37 from the 1st to the 99th percentile: at most 5 %
    allowed), and the rejection rate is at the test's level (the bound of
    test_size_on_stationary_correlated_noise).  A memory of tau_int ~ 199 (phi = 0.99) in the
    same 2,000 values leaves 10 blocks of 200 < 2 x 199: not independent, and no start of
    such a stationary series is called steady, however the test comes out."""
    rng = np.random.default_rng(5)
    tests = [memory_trend_test(v) for v in _ar1(rng, 2000, size=400)]
    assert np.mean([t["n_blocks"] == 20 and t["independent"] for t in tests]) > 0.95
    assert all(t["n_blocks"] >= 10 and (t["n_blocks"] == 20) == (t["tau_int"] <= 50)
               for t in tests)
    assert np.mean([not t["steady"] for t in tests]) < 0.05 + 4 * np.sqrt(0.05 * 0.95 / 400)
    long = _ar1(rng, 2000, phi=0.99)[0]
    n, g, ok = memory_blocks(long)
    assert n == 10 and not ok and g > 100
    start, info = steady_window(np.linspace(0, 0.1, 2000), long, 0.0)
    assert start == 0.0 and not info["steady"]
    assert "integrated autocorrelation times of tau, 20 needed" in info["reason"]
    with pytest.raises(ParameterError, match="non-finite"):
        integrated_time(np.r_[np.ones(10), np.inf])
    with pytest.raises(ParameterError, match="one-dimensional"):
        integrated_time(np.ones((3, 3)))


def test_memory_growth_tells_a_finite_memory_from_an_unresolved_one():
    """AR(1) with phi = 0.9 (tau_int 19 values) against a random walk, on 100,000 values
    spaced 1e-4.  Error model: Geyer's estimate from windows of >= 5,000 values scatters by
    ~10 % (test_integrated_time_of_correlated_noise), so over a factor 8 in L the slope stays
    within ~0.1 of 0, inside RESOLVED_SLOPE = 0.25; a random walk's estimated time grows with
    the window (slope ~1; 0.6-1.4 allowed)."""
    rng = np.random.default_rng(3)
    t = 1e-4 * np.arange(100_000)
    lengths = (4.0, 0.5, 1.0, 2.0)               # any order: the rows come sorted
    finite = memory_growth(t, _ar1(rng, t.size)[0], lengths)
    assert finite["resolved"] and abs(finite["slope"]) <= 0.25
    assert [r["windows"] for r in finite["rows"]] == [20, 10, 5, 2]
    assert finite["rows"][-1]["tau_int"] == pytest.approx(19e-4, rel=0.3)
    assert finite["needed"] == pytest.approx(20 * finite["rows"][-1]["tau_int"], rel=1e-12)
    walk = memory_growth(t, np.cumsum(rng.normal(size=t.size)), lengths)
    assert not walk["resolved"] and 0.6 <= walk["slope"] <= 1.4
    part = memory_growth(t, np.cumsum(rng.normal(size=t.size)), (0.5, 1.0), span=(2.0, 4.0))
    assert [r["windows"] for r in part["rows"]] == [4, 2]


@pytest.mark.parametrize("t, x, lengths, match", [
    (np.arange(10.0), np.ones(9), (2, 4), "one length"),
    (np.arange(10.0)[::-1], np.ones(10), (2, 4), "must increase"),
    (np.arange(10.0), np.ones(10), (1, 4), "longer than two samples"),
    (np.arange(10.0), np.ones(10), (4, 20), "at least 2 are needed"),
])
def test_memory_growth_bad_input(t, x, lengths, match):
    with pytest.raises(ParameterError, match=match):
        memory_growth(t, x, lengths)
