"""The ranked precursor test (fricstab.analysis.precursors): ranks, null, power (issue 36)."""

import numpy as np
import pytest
from scipy.stats import kstest

from fricstab.analysis.precursors import permutation_test, power, window_power, window_ranks
from fricstab.errors import ParameterError


def _noise_path(rng, n=401, drops=6):
    return rng.normal(size=n), np.sort(rng.choice(n, drops, replace=False))


def test_ranks_mid_rank_with_ties_and_nan_and_clipping():
    x = np.array([1.0, 2.0, 2.0, 2.0, 5.0, np.nan, 0.0])
    # k = 2, W = 2: window [1, 2, 2, 2, 5]: 1 below, 3 equal -> (1 + 1) / 4
    assert window_ranks(x, [2], 2)[0] == pytest.approx(0.5)
    # k = 4, W = 2: window [2, 2, 5, nan, 0] -> 4 finite, 3 below: 3 / 3
    assert window_ranks(x, [4], 2)[0] == 1.0
    # k = 0 clipped: window [1, 2, 2]: lowest
    assert window_ranks(x, [0], 2)[0] == 0.0
    # a NaN onset has no rank; a flat window ranks 0.5
    assert np.isnan(window_ranks(x, [5], 2)[0])
    assert window_ranks(np.zeros(9), [4], 3)[0] == 0.5


def test_ranks_refuse_bad_input():
    with pytest.raises(ParameterError, match="onsets"):
        window_ranks(np.zeros(5), [5], 2)
    with pytest.raises(ParameterError, match="half_width"):
        window_ranks(np.zeros(5), [1], 0)
    with pytest.raises(ParameterError, match="alternative"):
        permutation_test([(np.zeros(5), [1])], 2, 9, alternative="two-sided")


def test_planted_precursor_is_found_in_both_directions():
    rng = np.random.default_rng(5)
    paths = []
    for _ in range(6):
        x, on = _noise_path(rng)
        x[on] += 3.0                       # each onset well above its neighbourhood
        paths.append((x, on))
    t = permutation_test(paths, 25, 1999, np.random.default_rng(0), "greater")
    # 36 onsets near rank 1 against a null of mean 0.5, sd ~0.05: no null draw reaches it,
    # so p is the smallest possible, 1 / 2000
    assert t["pvalue"] < 1e-3 and t["statistic"] > 0.9
    low = permutation_test([(-x, on) for x, on in paths], 25, 1999,
                           np.random.default_rng(0), "less")
    assert low["pvalue"] < 1e-3
    # the wrong direction finds nothing
    assert permutation_test(paths, 25, 999, np.random.default_rng(0), "less")["pvalue"] > 0.5


def test_noise_gives_uniform_pvalues():
    ps = []
    for seed in range(200):
        rng = np.random.default_rng(1000 + seed)
        paths = [_noise_path(rng, n=201, drops=4) for _ in range(3)]
        ps.append(permutation_test(paths, 25, 199, rng, "greater")["pvalue"])
    # exact-level permutation test: p uniform on the grid k / 200; KS against U(0, 1) over
    # 200 seeds with the grid step 1/200 adds at most 0.005 to D; reject only at 1e-3
    # (D > 0.14), a bound a valid test fails in 1 of 1000 seeds
    assert kstest(ps, "uniform").pvalue > 1e-3
    assert np.mean(np.array(ps) <= 0.05) < 0.05 + 3 * np.sqrt(0.05 * 0.95 / 200)


def test_integer_series_with_ties_keeps_the_level():
    """Pair counts: many ties; mid-ranks keep the null mean at 0.5 and p not small."""
    rng = np.random.default_rng(7)
    paths = [(rng.integers(0, 3, 401).astype(float), np.sort(rng.choice(401, 6, False)))
             for _ in range(4)]
    t = permutation_test(paths, 25, 999, rng, "greater")
    # null mean of a random state's mid-rank is 0.5 up to the clipped ends: sd/sqrt(999)
    assert abs(t["null_mean"] - 0.5) < 5 * t["null_sd"] / np.sqrt(999) + 0.01
    assert 0.01 < t["pvalue"]


def test_power_zero_at_alpha_and_monotone():
    rng = np.random.default_rng(11)
    paths = [_noise_path(rng, drops=5) for _ in range(4)]
    pw = [power(paths, f, 25, 400, 199, np.random.default_rng(3), "greater")["power"]
          for f in (0.0, 0.2, 0.5, 0.8)]
    # f = 0: the level 0.05; binomial sd over 400 replicates 0.011, plus the null sample's
    # own error on the 5 % quantile (199 draws): allow 0.05 +- 0.04
    assert abs(pw[0] - 0.05) < 0.04
    assert pw[0] < pw[1] < pw[2] <= pw[3] and pw[3] > 0.95


def test_window_power_has_none_when_births_cover_the_windows():
    """The old birth-window test: with a birth at nearly every step (p0 ~ 1) no fraction
    of preceded drops can be told from the null; with sparse births it can."""
    dense = [{"drops": np.linspace(0.01, 0.19, 8), "births": np.arange(0, 0.2, 5e-4)[::1],
              "gamma_max": 0.2}]
    sparse = [{"drops": np.linspace(0.01, 0.19, 8), "births": np.arange(0, 0.2, 2e-2),
               "gamma_max": 0.2}]
    d = window_power(dense, 5e-4, 0.8, 400, np.random.default_rng(0))
    s = window_power(sparse, 5e-4, 0.8, 400, np.random.default_rng(0))
    assert d["p0"] > 0.99 and d["power"] == 0.0
    assert s["p0"] < 0.05 and s["power"] > 0.9


def test_aqs_records_the_pair_nearest_the_real_axis_and_resumes_it():
    """AQSResult.pair_min_imag: min Im of the counted pairs at each state (NaN without one),
    the same from a checkpoint's state, and carried bit-identically through a resume.
    N = 32, phi = 0.90, seed 0, ishima kT/kN = 1: pairs at steps 3, 4, 5, 7 of 2e-3 (measured)."""
    from fricstab.engine import State
    from fricstab.protocols import aqs
    from fricstab.scenes.packing import make_packing
    from fricstab.scenes.packing_friction import backbone, frictional, material
    fr = frictional(backbone(make_packing(32, 0.9, 0)), material("ishima", kt=1.0))
    saved = {}
    full = aqs.run_aqs(fr.system, fr.state, 1.6e-2, 2e-3, locate_events=False,
                       checkpoint=saved.__setitem__, checkpoint_every=4)
    assert np.array_equal(np.isnan(full.pair_min_imag), full.n_pairs == 0)
    assert full.n_pairs[4] > 0 and np.isfinite(full.pair_min_imag).sum() >= 2
    s4 = State.from_arrays({k[6:]: v for k, v in saved[4].items() if k.startswith("state_")})
    assert full.pair_min_imag[4] == aqs.pairs(aqs.spectrum(fr.system, s4)[0]).imag.min()
    cont = aqs.run_aqs(fr.system, fr.state, 1.6e-2, 2e-3, locate_events=False,
                       resume=dict(saved[4], step=np.int64(4)))
    assert np.array_equal(cont.pair_min_imag, full.pair_min_imag, equal_nan=True)
