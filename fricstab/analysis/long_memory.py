"""Long memory: how fast does the mean of a series settle, and a trend test that allows for it.

A stress series of a sheared cell can wander on the scale of the whole run: its integrated
autocorrelation time grows with the window it is measured on
(:func:`fricstab.analysis.autocorrelation.memory_growth`), and a trend test on blocks sized by
that time (:func:`fricstab.analysis.stationarity.steady_window`) then asks for ever more
strain.  This module measures that memory on the scaling hypothesis and tests for a trend
under it.

:func:`aggregated_variance`: the variance of the means of non-overlapping blocks of length L
against L.  A series with a finite memory gives Var ~ L^-1 once L is longer than the memory;
fractional Gaussian noise (fGn) with Hurst exponent H gives Var ~ L^(2H - 2) at every L.
The slope beta of log Var against log L gives ``H = 1 + beta / 2``: 0.5 for a finite memory,
towards 1 for a series whose block means hardly settle (a slow drift reads the same way: one
series cannot tell them apart).  The standard error of a mean over a window W then falls as
W^(H - 1): halving it takes 2^(1 / (1 - H)) times the window, against 4 times the independent
replicas.

:func:`ltp_trend_test`: the Mann-Kendall test under the scaling hypothesis (Hamed 2008,
J. Hydrol. 349, 350-363), on the means of ``n_blocks`` blocks: H estimated by maximum
likelihood on the normal scores of the block means less their Theil-Sen trend, the variance
of Kendall's S for fGn with that H (Hamed's arcsine sum over pairs of pairs), times
Hamed's correction for the bias of the estimated H (his polynomial in n and H).  Its size holds
on fGn of any H (:mod:`tests.test_long_memory`); the price is power: with H near 1 a long
rise of the mean is what the model expects, and the test accepts it.

:func:`ensemble_trend_test`: the test that long memory cannot fool, across independent
members (seeds): one slope per member, Student's t on the slopes.

:func:`fgn`: fGn by circulant embedding (Davies & Harte 1987), for tests and power studies.
"""

import numpy as np
from scipy import linalg, optimize, stats

from fricstab.errors import ParameterError

__all__ = ["aggregated_variance", "ensemble_trend_test", "error_of_mean", "fgn", "fgn_correlation", "hurst_mle",
           "ltp_trend_test"]

#: the search interval of :func:`hurst_mle` (the scaling hypothesis: persistence, H >= 0.5;
#: H = 1 is a series that never settles, where the fGn correlation matrix is singular)
H_BOUNDS = (0.5, 1.0 - 1e-6)


def _series(x, least, what="series"):
    x = np.asarray(x, float)
    if x.ndim != 1 or x.size < least:
        raise ParameterError(f"the {what} must be one-dimensional with at least {least} values "
                             f"(got shape {x.shape})")
    if not np.all(np.isfinite(x)):
        raise ParameterError(f"the {what} has {int((~np.isfinite(x)).sum())} non-finite "
                             "values")
    return x


def fgn_correlation(hurst, n):
    """The autocorrelation of fGn with exponent ``hurst`` at lags 0..n:
    ``(|k+1|^2H - 2|k|^2H + |k-1|^2H) / 2``."""
    if not 0.0 < hurst < 1.0:
        raise ParameterError(f"hurst = {hurst!r}: an exponent in (0, 1)")
    k = np.arange(int(n) + 1, dtype=float)
    h2 = 2.0 * hurst
    return 0.5 * (np.abs(k + 1.0) ** h2 - 2.0 * k ** h2 + np.abs(k - 1.0) ** h2)


def fgn(n, hurst, size=1, rng=None):
    """``size`` independent fGn series of ``n`` values, unit variance, exponent ``hurst``
    (circulant embedding, exact for 0 < H < 1); shape ``(size, n)``."""
    if int(n) != n or n < 2:
        raise ParameterError(f"n = {n!r}: at least 2 values (an integer)")
    n = int(n)
    c = fgn_correlation(hurst, n)
    row = np.concatenate([c[:n], c[n:n + 1], c[n - 1:0:-1]])
    lam = np.fft.fft(row).real
    if lam.min() < -1e-9 * lam.max():
        raise ParameterError(f"the circulant embedding of fGn with H = {hurst} is not "
                             "non-negative")
    rng = np.random.default_rng(rng)
    m = row.size
    w = rng.standard_normal((int(size), m)) + 1j * rng.standard_normal((int(size), m))
    return np.fft.fft(np.sqrt(np.clip(lam, 0.0, None) / m) * w, axis=1).real[:, :n]


def aggregated_variance(t, x, lengths, span=None):
    """The variance of block means against the block length (module docstring).

    ``span = (lo, hi)`` of ``t`` (default: all of it) is cut into non-overlapping blocks of each
    length L in ``lengths`` (units of ``t``, a strain say), at least 4 blocks per L.  Returns a
    dict: ``rows`` (``length``, ``blocks``, ``var`` of the block means, ddof 1), ``slope``
    (least squares of log var against log L), ``hurst`` (``1 + slope / 2``) and its
    ``hurst_se`` (from the fit's residuals; the block means of one series are correlated across
    L, so it is a rough guide, not a confidence interval), ``std`` (of ``x`` over the span).
    """
    t, x = _series(t, 8, "axis"), _series(x, 8)
    if t.shape != x.shape:
        raise ParameterError(f"t and x must be of one length (got {t.size} and {x.size})")
    if np.any(np.diff(t) <= 0):
        raise ParameterError("t must increase (a strain or time axis)")
    lo, hi = (float(t[0]), float(t[-1])) if span is None else map(float, span)
    sel = (t >= lo) & (t <= hi)
    t, x = t[sel], x[sel]
    spacing = float(np.median(np.diff(t)))
    rows = []
    for length in sorted(float(v) for v in lengths):
        idx = np.floor((t - lo) / length).astype(int)
        # a block [a, a + L) holds L / spacing samples: the span's fill (hi - lo + spacing) / L
        full = int((hi - lo + spacing) / length + 1e-9)
        if full < 4:
            raise ParameterError(f"block length {length:g}: {full} blocks fit in the span "
                                 f"{lo:g}..{hi:g}, at least 4 are needed")
        keep = idx < full
        counts = np.bincount(idx[keep], minlength=full)
        if counts.min() < 2:
            raise ParameterError(f"block length {length:g}: a block holds {counts.min()} "
                                 "values, at least 2 are needed")
        means = np.bincount(idx[keep], weights=x[keep], minlength=full) / counts
        rows.append({"length": length, "blocks": full, "var": float(means.var(ddof=1))})
    if len(rows) < 3:
        raise ParameterError(f"{len(rows)} block lengths: at least 3 are needed for a slope")
    lx = np.log([r["length"] for r in rows])
    ly = np.log([max(r["var"], 1e-300) for r in rows])
    (slope, icpt), cov = np.polyfit(lx, ly, 1, cov=True)
    return {"rows": rows, "slope": float(slope), "hurst": float(1.0 + slope / 2.0),
            "hurst_se": float(np.sqrt(cov[0, 0]) / 2.0), "std": float(x.std()),
            "span": [lo, hi]}


def error_of_mean(agg, width):
    """The standard error of a mean over a window of ``width`` (units of t) on the scaling of
    :func:`aggregated_variance`'s result ``agg``: the longest blocks' spread carried to the
    window as (W / L)^(H - 1); where H >= 1 the block means do not settle, and that spread is
    the error."""
    last = agg["rows"][-1]
    return float(np.sqrt(last["var"]) * (width / last["length"]) ** min(agg["hurst"] - 1.0, 0.0))


def _theil_sen(m):
    return float(stats.theilslopes(m).slope)


def hurst_mle(m):
    """Hurst exponent of the (short) series ``m`` by maximum likelihood on its normal scores
    less its Theil-Sen trend, as in Hamed (2008): H in :data:`H_BOUNDS`."""
    m = _series(m, 4)
    n = m.size
    y = m - _theil_sen(m) * np.arange(n)
    z = stats.norm.ppf(stats.rankdata(y) / (n + 1.0))
    g0 = float(np.var(stats.norm.ppf(np.arange(1, n + 1) / (n + 1.0)), ddof=1))
    lag = np.abs(np.subtract.outer(np.arange(n), np.arange(n)))

    def minus_log_likelihood(h):
        cf = linalg.cho_factor(fgn_correlation(h, n)[lag])
        return float(np.log(np.diag(cf[0])).sum() + z @ linalg.cho_solve(cf, z) / (2.0 * g0))

    res = optimize.minimize_scalar(minus_log_likelihood, bounds=H_BOUNDS, method="bounded",
                                   options={"xatol": 1e-6})
    return float(res.x)


def _var_s(hurst, n, chunk=512):
    """Var(S) of the Mann-Kendall statistic of n fGn values (Hamed 2008: the arcsine sum)."""
    c = fgn_correlation(hurst, n)
    i, j = np.triu_indices(n, 1)
    d = 2.0 - 2.0 * c[j - i]
    total = 0.0
    for s in range(0, i.size, chunk):
        a, b = i[s:s + chunk, None], j[s:s + chunk, None]
        num = c[np.abs(b - j)] - c[np.abs(a - j)] - c[np.abs(b - i)] + c[np.abs(a - i)]
        total += float(np.arcsin(np.clip(num / np.sqrt(d[s:s + chunk, None] * d),
                                         -1.0, 1.0)).sum())
    return 2.0 / np.pi * total


def _bias_factor(hurst, n):
    """Hamed's (2008) correction of Var(S) for the bias of the estimated H (his polynomial in n and H)."""
    a = ((1.0024 * n - 2.5681) / (n + 18.6693), (-2.2510 * n + 157.2075) / (n + 9.2245),
         (15.3402 * n - 188.6140) / (n + 5.8917), (-31.4258 * n + 549.8599) / (n - 1.1040),
         (20.7988 * n - 419.0402) / (n - 1.9248))
    return float(sum(ak * hurst ** k for k, ak in enumerate(a)))


def ltp_trend_test(x, n_blocks=32, alpha=0.05):
    """The Mann-Kendall test under the scaling hypothesis (Hamed 2008; module docstring) on
    the means of ``n_blocks`` equal blocks of ``x`` (all of ``x`` where it holds exactly
    ``n_blocks`` values).

    Returns a dict: ``s`` (Kendall's S), ``hurst`` (of the block means), ``var_s`` (for fGn
    with that H, times ``bias_factor``), ``z`` (continuity-corrected), ``p`` (two-sided),
    ``steady`` (p >= alpha), ``var_s_independent`` (Var(S) of independent values, to show how
    much the memory widens it), ``drift_over_std`` (Theil-Sen slope of the block means x the
    window, over the std of ``x``), ``n_blocks``, ``n_values``.
    """
    if not 0.0 < alpha < 1.0:
        raise ParameterError(f"alpha = {alpha!r}: a test level in (0, 1)")
    if int(n_blocks) != n_blocks or not 8 <= n_blocks <= 200:
        raise ParameterError(f"n_blocks = {n_blocks!r}: an integer in 8..200 (fewer give Hamed's "
                             "H estimate no footing; more cost n^4)")
    n = int(n_blocks)
    x = _series(x, n)
    per = x.size // n
    m = x[: per * n].reshape(n, per).mean(axis=1)
    i, j = np.triu_indices(n, 1)
    s = int(np.sign(m[j] - m[i]).sum())
    h = hurst_mle(m)
    factor = _bias_factor(h, n)
    var = _var_s(h, n) * factor
    z = (s - np.sign(s)) / np.sqrt(var) if var > 0 else 0.0
    p = float(2.0 * stats.norm.sf(abs(z)))
    sd = float(x.std())
    return {"s": s, "hurst": h, "var_s": float(var), "bias_factor": factor, "z": float(z),
            "p": p, "steady": bool(p >= alpha), "alpha": alpha,
            "var_s_independent": n * (n - 1) * (2 * n + 5) / 18.0,
            "drift_over_std": _theil_sen(m) * n / sd if sd > 0 else 0.0,
            "n_blocks": n, "n_values": int(x.size)}


def ensemble_trend_test(members, span, n_bins=20, alpha=0.05):
    """A trend test that no memory can fool: independent members (seeds) of one protocol.

    ``members``: a list of ``(t, x)`` pairs, one per independent run (a strain axis and tau);
    ``span = (lo, hi)`` of ``t``, common to all, is cut into ``n_bins`` equal bins; a member
    covers the span where its first and last samples lie within one of its sample spacings of
    the span's ends (no sample of its grid missing inside it; else ``ParameterError``).  Per member,
    the least-squares slope of its bin means against the bin centres: one number per member,
    and members are independent whatever each one's memory.  The test is Student's t on those
    slopes (:func:`scipy.stats.ttest_1samp`, ``M - 1`` degrees of freedom): steady where the
    mean slope is not distinguishable from zero at level ``alpha``.

    Returns a dict: ``slope`` (mean over members, units of x per unit t) and ``slope_se``,
    ``p``, ``steady``, ``rise_over_std`` (mean slope x the span over the pooled std of the bin
    means), ``resolvable_rise`` (the rise, in the same units, that the test sees half the time:
    ``t_{1-alpha/2, M-1}`` standard errors of the slope x the span over that std), ``mean``
    (of x over the span and members) with its ``mean_se`` (the spread of the members' means
    over sqrt(M)), ``members``, ``n_bins``.  Two members with the same bin means (one run
    passed twice) raise :class:`~fricstab.errors.ParameterError`: they are not independent.
    """
    if not 0.0 < alpha < 1.0:
        raise ParameterError(f"alpha = {alpha!r}: a test level in (0, 1)")
    if int(n_bins) != n_bins or n_bins < 3:
        raise ParameterError(f"n_bins = {n_bins!r}: at least 3 bins (an integer)")
    members = list(members)
    if len(members) < 3:
        raise ParameterError(f"{len(members)} member(s): a test across independent members "
                             "needs at least 3 (one member cannot tell a long memory from a "
                             "drift: fricstab.analysis.long_memory)")
    lo, hi = map(float, span)
    if not hi > lo:
        raise ParameterError(f"span {span!r}: (lo, hi) with hi > lo")
    n = int(n_bins)
    slack = 1e-9 * (hi - lo)          # round-off at the span's ends
    edges = np.linspace(lo, hi, n + 1)
    centres = 0.5 * (edges[1:] + edges[:-1])
    means = []
    for k, (t, x) in enumerate(members):
        t, x = _series(t, 2, "axis"), _series(x, 2)
        if t.shape != x.shape:
            raise ParameterError(f"member {k}: t and x of lengths {t.size} and {x.size}")
        # a sampled member covers the span where no sample of its grid is missing inside it:
        # its first and last samples lie within one sample spacing of the ends (a run cut at
        # the last frame at or below hi, or stopped at hi to round-off)
        if (t[0] - lo > slack and t[0] - lo >= t[1] - t[0]) or \
                (hi - t[-1] > slack and hi - t[-1] >= t[-1] - t[-2]):
            raise ParameterError(f"member {k} covers {t[0]:g}..{t[-1]:g}, not the span "
                                 f"{lo:g}..{hi:g} to within its sample spacing: run it further")
        idx = np.searchsorted(edges, t, side="right") - 1
        idx[t == hi] = n - 1                          # the span's end belongs to the last bin
        keep = (idx >= 0) & (idx < n)
        counts = np.bincount(idx[keep], minlength=n)
        if counts.min() < 1:
            raise ParameterError(f"member {k}: an empty bin ({n} bins over {lo:g}..{hi:g})")
        means.append(np.bincount(idx[keep], weights=x[keep], minlength=n) / counts)
    means = np.asarray(means)
    for k in range(1, len(means)):
        same = [j for j in range(k) if np.array_equal(means[j], means[k])]
        if same:
            raise ParameterError(f"members {same[0]} and {k} have the same bin means: one run "
                                 "passed twice, not independent members (seeds)")
    slopes = np.polyfit(centres, means.T, 1)[0]
    m = slopes.size
    se = float(slopes.std(ddof=1) / np.sqrt(m))
    if se > 0:
        p = float(stats.ttest_1samp(slopes, 0.0).pvalue)
    else:                     # equal slopes of distinct members: a zero-spread t is 0 or infinite
        p = 1.0 if slopes[0] == 0.0 else 0.0
    sd = float(np.sqrt(np.mean(means.var(axis=1, ddof=1))))
    width = hi - lo
    member_means = means.mean(axis=1)
    return {"slope": float(slopes.mean()), "slope_se": se, "p": p, "steady": bool(p >= alpha),
            "alpha": alpha,
            "rise_over_std": float(slopes.mean() * width / sd) if sd > 0 else 0.0,
            "resolvable_rise": float(stats.t.ppf(1 - alpha / 2, m - 1) * se * width / sd)
            if sd > 0 else 0.0,
            "mean": float(member_means.mean()),
            "mean_se": float(member_means.std(ddof=1) / np.sqrt(m)),
            "members": m, "n_bins": n}
