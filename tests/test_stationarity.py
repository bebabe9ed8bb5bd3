"""The steady-state test of :mod:`fricstab.analysis.stationarity`: its size, its power, the
steady start, and its errors on bad input."""

import numpy as np
import pytest

from fricstab.analysis.stationarity import steady_start, steady_window, trend_test
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


def test_steady_window_starts_at_the_steady_start_or_at_gamma0():
    """The rise of test_steady_start_after_a_transient: the window starts where steady_start
    (run on the frames from gamma0) accepts, never before gamma0; a drift to the end gives
    gamma0 and says so; too few frames after gamma0 give gamma0 with the test's reason."""
    rng = np.random.default_rng(2)
    n = 4000
    t = np.linspace(0.0, 0.1, n)
    x = _ar1(rng, n)[0] + 3.0 * np.clip(t / 0.04, 0, 1)
    start, info = steady_window(t, x, 0.01)
    want, _ = steady_start(t[t >= 0.01], x[t >= 0.01])
    assert info["steady"] and start == want == info["start"] and start >= 0.01
    # gamma0 past the transient: the first candidate passes, the window starts at gamma0
    start, info = steady_window(t, x, 0.06)
    assert info["steady"] and start == pytest.approx(0.06, abs=1e-4)
    drift = 5 * t / 0.1 + 0.01 * rng.normal(size=n)
    start, info = steady_window(t, drift, 0.02)
    assert start == 0.02 and not info["steady"] and "extend the run" in info["reason"]
    start, info = steady_window(t, x, 0.0999)
    assert start == 0.0999 and not info["steady"] and "values" in info["reason"]
    with pytest.raises(ParameterError, match="one length"):
        steady_window(t, x[:-1], 0.0)
