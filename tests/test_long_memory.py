"""Long memory (fricstab.analysis.long_memory): fGn synthesis, the aggregated-variance Hurst
exponent, and the Mann-Kendall test under the scaling hypothesis (Hamed 2008)."""

import numpy as np
import pytest

from fricstab.analysis.long_memory import (aggregated_variance, ensemble_trend_test, fgn,
                                           fgn_correlation, hurst_mle, ltp_trend_test)
from fricstab.analysis.stationarity import trend_test
from fricstab.errors import ParameterError


@pytest.mark.parametrize("h", [0.5, 0.75, 0.9])
def test_fgn_has_the_fgn_correlation(h):
    x = fgn(512, h, size=400, rng=1)
    # error model: 400 x 511 products per lag, each of variance ~1 but correlated along a
    # series (long memory); the per-series estimates' spread over the 400 series is measured,
    # and the mean over series must lie within 4 of its standard errors
    for k in (1, 2, 8):
        per = (x[:, k:] * x[:, :-k]).mean(axis=1)
        se = per.std() / np.sqrt(per.size)
        assert abs(per.mean() - fgn_correlation(h, k)[k]) < 4 * se + 1e-3
    assert abs(x.var() - 1.0) < 0.05


@pytest.mark.parametrize("h, bias", [(0.5, 0.0), (0.7, 0.0), (0.9, -0.06)])
def test_aggregated_variance_recovers_the_hurst_exponent(h, bias):
    # error model: one 2^14-value fGn series, blocks of 16-512 values, gives H with a spread
    # of 0.03-0.04 (measured over 40 series) and, near H = 1, a bias of about -0.06 (few
    # blocks at the longest length: their mean is the series' own); the mean of 8 series lies
    # within 0.05 of H + bias (about 4 standard errors)
    got = []
    for seed in range(8):
        x = fgn(2 ** 14, h, rng=seed)[0]
        a = aggregated_variance(np.arange(x.size, dtype=float), x,
                                [16, 32, 64, 128, 256, 512])
        got.append(a["hurst"])
    assert abs(np.mean(got) - (h + bias)) < 0.05
    assert [r["blocks"] for r in a["rows"]] == [2 ** 14 // L for L in (16, 32, 64, 128, 256, 512)]


def test_aggregated_variance_of_a_finite_memory_is_one_half_whatever_its_time():
    # AR(1) with phi = 0.9: memory ~19 values; blocks of 64-2048 are far longer
    rng = np.random.default_rng(3)
    e = rng.standard_normal(2 ** 16)
    x = np.empty_like(e)
    x[0] = e[0]
    for i in range(1, x.size):
        x[i] = 0.9 * x[i - 1] + e[i]
    a = aggregated_variance(np.arange(x.size, dtype=float), x, [64, 128, 256, 512, 1024, 2048])
    assert abs(a["hurst"] - 0.5) < 0.08       # spread ~0.035 at these block counts (above)


def test_the_ltp_test_holds_its_size_where_the_short_memory_test_does_not():
    # fGn with H = 0.9, 64 values in 32 blocks; 150 series.  Error model: the rejection rate
    # of a test of level 0.05 on 150 series has a binomial s.e. of 0.018: Hamed's test must
    # reject at most 0.05 + 3 s.e. = 0.105 of them.  The Mann-Kendall test on the same block
    # means, which assumes them independent, rejects ~0.4 (measured over 200 series): it must
    # reject at least 0.25, so the comparison can fail if the LTP test were no different.
    x = fgn(64, 0.9, size=150, rng=11)
    ltp = np.mean([not ltp_trend_test(v, 32)["steady"] for v in x])
    mk = np.mean([not trend_test(v, 32)["steady"] for v in x])
    assert ltp <= 0.105
    assert mk >= 0.25


def test_the_ltp_test_sees_a_drift_in_independent_values():
    # white noise plus a rise of 3 std over the window: rejected in 0.88 of 100 series
    # (measured); binomial s.e. 0.033 at that rate, so at least 0.7
    rng = np.random.default_rng(5)
    x = rng.standard_normal((100, 32)) + 3.0 * np.linspace(0.0, 1.0, 32)
    res = [ltp_trend_test(v, 32) for v in x]
    assert np.mean([not r["steady"] for r in res]) >= 0.7
    assert np.median([r["drift_over_std"] for r in res]) > 0


def test_hurst_mle_tells_persistence_from_independence():
    # the ML estimate is biased low on short series (why Hamed corrects Var(S)); over 40
    # series of 32 values its mean is ~0.52 for independent values and ~0.75 for H = 0.9
    lo = np.mean([hurst_mle(v) for v in np.random.default_rng(2).standard_normal((40, 32))])
    hi = np.mean([hurst_mle(v) for v in fgn(32, 0.9, size=40, rng=2)])
    assert lo < 0.6 < 0.68 < hi


def test_the_memory_widens_the_variance_of_s():
    r = ltp_trend_test(fgn(64, 0.95, rng=4)[0], 32)
    assert r["var_s"] > r["var_s_independent"]
    assert r["n_blocks"] == 32 and r["n_values"] == 64


T = np.linspace(0.0, 1.0, 2000)


def test_the_ensemble_test_holds_its_size_under_long_memory():
    # 150 ensembles of 6 independent fGn members with H = 0.9: the t test on one slope per
    # member is exact for independent normal slopes; binomial s.e. of the rejection rate at
    # 0.05 over 150 ensembles is 0.018, so at most 0.105 (measured: 0.045-0.05 over 200)
    x = fgn(2000, 0.9, size=(150 * 6), rng=21).reshape(150, 6, 2000)
    rejected = [not ensemble_trend_test([(T, v) for v in e], (0.0, 1.0))["steady"] for e in x]
    assert np.mean(rejected) <= 0.105


def test_the_ensemble_test_sees_a_rise_one_member_cannot():
    # a rise of 1 std over the span on fGn with H = 0.9: 8 members see it in 0.97 of 100
    # ensembles (measured); binomial s.e. ~0.02 there, so at least 0.85.  One member's
    # scaling test (32 block means) sees it in ~0.12 of series at H = 0.9 (measured)
    x = fgn(2000, 0.9, size=800, rng=22).reshape(100, 8, 2000) + T
    res = [ensemble_trend_test([(T, v) for v in e], (0.0, 1.0)) for e in x]
    assert np.mean([not r["steady"] for r in res]) >= 0.85
    r = res[0]
    assert r["members"] == 8 and r["n_bins"] == 20 and r["rise_over_std"] > 0
    # the mean's error is the members' spread over sqrt(M), whatever their memory
    bins = np.minimum(np.floor(T * 20).astype(int), 19)
    means = np.array([[v[bins == b].mean() for b in range(20)] for v in x[0]]).mean(axis=1)
    assert r["mean_se"] == pytest.approx(means.std(ddof=1) / np.sqrt(8), rel=1e-9)


def test_a_member_stopped_at_the_span_end_to_round_off_covers_it():
    # a run asked for strain 0.01 stops at 0.009999999999999912 (measured): it covers the span
    # and gives the test's numbers as if it ended at 0.01 exactly (its last value in the last bin)
    x = fgn(2000, 0.7, size=3, rng=23)
    short = T * (1.0 - 1e-15)
    exact = ensemble_trend_test([(T, v) for v in x], (0.0, 1.0))
    got = ensemble_trend_test([(short, v) for v in x], (0.0, 1.0))
    assert got == exact
    with pytest.raises(ParameterError, match="run it further"):
        ensemble_trend_test([(T[:-2], v[:-2]) for v in x], (0.0, 1.0))


def test_a_member_sampled_up_to_one_spacing_short_of_the_span_end_covers_it():
    # frames every 7.2e-7 of strain end at 0.19999944 below a span's end of 0.2 (the paper
    # preset's seeds, measured): no frame of the grid is missing inside the span, so it covers
    # it; its last frame lies in the last bin as it would with one more frame at 0.2.  Two
    # spacings short, a frame is missing: refused (above)
    x = fgn(2000, 0.7, size=3, rng=23)
    grid = T[:-1] + 0.5 / 1999                  # samples half a spacing inside both ends
    got = ensemble_trend_test([(grid, v[:-1]) for v in x], (0.0, 1.0))
    assert got["members"] == 3 and np.isfinite(got["p"])
    with pytest.raises(ParameterError, match="run it further"):     # one whole spacing short
        ensemble_trend_test([(T[:-1], v[:-1]) for v in x], (0.0, 1.0))
    with pytest.raises(ParameterError, match="run it further"):
        ensemble_trend_test([(T[1:] + 1.0 / 1999, v[1:]) for v in x], (0.0, 1.0))


@pytest.mark.parametrize("call, match", [
    (lambda: ensemble_trend_test([(T, T), (T, T)], (0.0, 1.0)), "at least 3"),
    (lambda: ensemble_trend_test([(T, T)] * 3, (0.0, 2.0)), "run it further"),
    (lambda: ensemble_trend_test([(T, T), (T, 2 * T), (T, T)], (0.0, 1.0)),
     "members 0 and 2 have the same bin means"),
    (lambda: ensemble_trend_test([(T, T)] * 3, (1.0, 0.0)), "hi > lo"),
    (lambda: ensemble_trend_test([(np.r_[0.0, 0.01, 1.0], np.ones(3))] * 3, (0.0, 1.0), 40),
     "empty bin"),
    (lambda: ltp_trend_test(np.ones(10), 32), "at least 32 values"),
    (lambda: ltp_trend_test(np.r_[np.ones(40), np.nan], 32), "non-finite"),
    (lambda: ltp_trend_test(np.ones(64), 4), "n_blocks"),
    (lambda: ltp_trend_test(np.ones(64), 32, alpha=1.5), "alpha"),
    (lambda: fgn(16, 1.2), "hurst"),
    (lambda: aggregated_variance(np.arange(100.0), np.ones(100), [30, 40, 50]), "at least 4 are needed"),
    (lambda: aggregated_variance(np.arange(100.0)[::-1], np.ones(100), [5, 10, 20]),
     "increase"),
])
def test_bad_input_says_what_is_wrong(call, match):
    with pytest.raises(ParameterError, match=match):
        call()
