"""Drops and the precursor statistic of an AQS path (fricstab.analysis.aqs)."""

import numpy as np

from fricstab.analysis.aqs import compare, detect_drops, null_fraction, preceded


def test_drops_merge_consecutive_steps():
    stress = np.array([0.0, 1.0, 0.5, 0.2, 0.3, 0.1])
    drops = detect_drops(np.arange(6.0), stress, threshold=0.01)
    assert [(d.step, d.gamma, d.steps) for d in drops] == [(2, 1.0, 2), (5, 4.0, 1)]
    assert np.isclose(drops[0].size, 0.8)


def test_null_fraction_exact_against_sampling():
    rng = np.random.default_rng(1)
    births = np.sort(rng.uniform(0, 1, 40))
    window = 0.013
    p0 = null_fraction(births, window, 1.0)
    u = rng.uniform(window, 1.0, 400_000)
    hit, _ = preceded(u, births, window)
    # binomial sampling error sqrt(p (1 - p) / n) <= 8e-4; 4 sigma
    assert abs(hit.mean() - p0) < 4 * 8e-4


def test_compare_counts_and_lags():
    run = {"drops": [0.5, 0.8], "births": [0.45, 0.1], "gamma_max": 1.0}
    s = compare([run], 0.1)
    assert (s["preceded"], s["drops"]) == (1, 2)
    assert np.isclose(s["median_lag"], 0.05)
    assert np.isclose(s["null_fraction"], 0.2 / 0.9)
