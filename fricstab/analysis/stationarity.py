"""Is a sheared series in a steady state?  A trend test on block means, and the steady start.

A stress series of a sheared cell is correlated over many frames, so a test on the frames
themselves would call any slow fluctuation a trend.  The window is cut into ``n_blocks``
blocks of equal length; the block means are nearly independent when a block is much longer
than the series' correlation length, and the Mann-Kendall test (Kendall's tau of the block
means against their order, :func:`scipy.stats.kendalltau`) asks whether they trend.  The
window is *steady* when that test does not reject at level ``alpha``.  Beside the p-value,
the size of the drift: the Theil-Sen slope of the block means (:func:`scipy.stats.theilslopes`)
times the window's length, in units of the series' standard deviation over the window.

The error model of the test: independent block means.  Their lag-1 autocorrelation is
returned (``block_lag1``); above ~0.5 the blocks are too short for the series' memory and the
p-value is too small (the test rejects too often), so fewer, longer blocks are needed.

:func:`steady_start` scans candidate starts and returns the earliest from which the rest of
the series passes the test (None when no start leaving ``min_fraction`` of the series does).
"""

import numpy as np
from scipy import stats

from fricstab.errors import ParameterError

__all__ = ["steady_start", "trend_test"]


def _blocks(x, n_blocks):
    x = np.asarray(x, float)
    if x.ndim != 1:
        raise ParameterError(f"the series must be one-dimensional (got shape {x.shape})")
    if not np.all(np.isfinite(x)):
        raise ParameterError(f"the series has {int((~np.isfinite(x)).sum())} non-finite "
                             "values: a trend test needs finite ones")
    if int(n_blocks) != n_blocks or n_blocks < 4:
        raise ParameterError(f"n_blocks = {n_blocks!r}: at least 4 blocks (an integer) are "
                             "needed for a trend test")
    n_blocks = int(n_blocks)
    if x.size < 2 * n_blocks:
        raise ParameterError(f"{x.size} values for {n_blocks} blocks: at least 2 values per "
                             "block are needed")
    per = x.size // n_blocks
    return x[: per * n_blocks].reshape(n_blocks, per).mean(axis=1)


def trend_test(x, n_blocks=20, alpha=0.05):
    """The Mann-Kendall test of the block means of ``x`` (module docstring).

    Returns a dict: ``kendall_tau`` and ``p`` (two-sided), ``steady`` (p >= alpha),
    ``drift_over_std`` (Theil-Sen slope of the block means x the window, over the std of
    ``x``), ``mean``, ``std``, ``block_lag1`` (lag-1 autocorrelation of the block means), the
    counts.
    """
    if not 0.0 < alpha < 1.0:
        raise ParameterError(f"alpha = {alpha!r}: a test level in (0, 1)")
    m = _blocks(x, n_blocks)
    x = np.asarray(x, float)
    order = np.arange(m.size)
    res = stats.kendalltau(order, m)
    tau_k = float(res.statistic) if np.isfinite(res.statistic) else 0.0
    p = float(res.pvalue) if np.isfinite(res.pvalue) else 1.0   # constant means: no trend
    slope = float(stats.theilslopes(m, order).slope)
    sd = float(x.std())
    dm = m - m.mean()
    lag1 = float(np.dot(dm[1:], dm[:-1]) / np.dot(dm, dm)) if np.dot(dm, dm) > 0 else 0.0
    return {"kendall_tau": tau_k, "p": p, "steady": bool(p >= alpha), "alpha": alpha,
            "drift_over_std": slope * m.size / sd if sd > 0 else 0.0,
            "mean": float(x.mean()), "std": sd, "block_lag1": lag1,
            "n_blocks": int(m.size), "n_values": int(x.size)}


def steady_start(t, x, starts=None, n_blocks=20, alpha=0.05, min_fraction=0.3):
    """The earliest start (a value of ``t``) from which ``x`` is steady, and its test.

    ``starts``: candidate starts (default: 20 evenly spaced in the first
    ``1 - min_fraction`` of ``t``); a start is accepted when the series from it passes
    :func:`trend_test` and holds at least ``min_fraction`` of the values.  Returns
    ``(start, test)``, or ``(None, test of the last candidate)`` when none passes.

    Scanning starts makes the accepted start a choice after the fact: the first start that
    passes is more likely than ``alpha`` to hide a weak trend.  The test at the accepted start
    is reported as it is; use a start fixed in advance where a p-value must keep its meaning.
    """
    t, x = np.asarray(t, float), np.asarray(x, float)
    if t.shape != x.shape or t.ndim != 1:
        raise ParameterError(f"t and x must be one-dimensional and of one length (got "
                             f"{t.shape} and {x.shape})")
    if not 0.0 < min_fraction < 1.0:
        raise ParameterError(f"min_fraction = {min_fraction!r}: a fraction in (0, 1)")
    if t.size and np.any(np.diff(t) < 0):
        raise ParameterError("t must not decrease (a strain or time axis)")
    if starts is None:
        hi = t[int((1.0 - min_fraction) * (t.size - 1))] if t.size else 0.0
        starts = np.linspace(t[0], hi, 20) if t.size else []
    test = None
    for s in starts:
        sel = t >= s
        if sel.sum() < max(min_fraction * t.size, 2 * n_blocks):
            break
        test = trend_test(x[sel], n_blocks, alpha)
        if test["steady"]:
            return float(s), test
    if test is None:
        raise ParameterError(f"no candidate start leaves {min_fraction:.0%} of the "
                             f"{t.size} values and {2 * n_blocks} values for the blocks")
    return None, test


def steady_window(strain, tau, gamma0, alpha=0.05, min_fraction=0.3):
    """Where the steady-state statistics of a sheared run start: the earliest strain at or
    after ``gamma0`` from which ``tau`` is steady, else ``gamma0`` itself.

    The candidate starts are :func:`steady_start`'s (20, evenly spaced over the frames from
    ``gamma0``, each leaving at least ``min_fraction`` of them), but each window is tested by
    the Mann-Kendall test on blocks sized by tau's integrated autocorrelation time
    (:func:`fricstab.analysis.autocorrelation.memory_blocks`), and a window accepted only where its blocks are
    independent and the test does not reject.  A window shorter than 20 integrated times of
    tau is never called steady: the run needs more strain.

    Returns ``(start, info)``: ``info["steady"]`` is False where no candidate start passes
    or the window is too short for the test (``info["reason"]`` says which); otherwise
    ``info`` holds the accepted start; both hold the (last) test's ``p``,
    ``drift_over_std``, ``block_lag1``, ``n_blocks``, ``tau_int`` (frames) and ``n_values``.
    The caveat of :func:`steady_start` applies: the accepted start is a choice after the fact.
    """
    from fricstab.analysis.autocorrelation import BLOCK_OVER_TAU, MIN_BLOCKS
    strain, tau = np.asarray(strain, float), np.asarray(tau, float)
    if strain.shape != tau.shape or strain.ndim != 1:
        raise ParameterError(f"strain and tau must be one-dimensional and of one length (got "
                             f"{strain.shape} and {tau.shape})")
    if strain.size and np.any(np.diff(strain) < 0):
        raise ParameterError("the strain must not decrease")
    gamma0 = float(gamma0)
    t, x = strain[strain >= gamma0], tau[strain >= gamma0]
    test = None
    if t.size:
        for s in np.linspace(t[0], t[int((1.0 - min_fraction) * (t.size - 1))], 20):
            sel = t >= s
            if sel.sum() < max(min_fraction * t.size, 2 * MIN_BLOCKS):
                break
            test = memory_trend_test(x[sel], alpha)
            if test["steady"] and test["independent"]:
                break
    if test is None:
        return gamma0, {"steady": False, "start": None,
                        "reason": f"no candidate start leaves {min_fraction:.0%} of the "
                                  f"{t.size} frames from strain {gamma0:g} and "
                                  f"{2 * MIN_BLOCKS} frames for the blocks"}
    keep = {k: test[k] for k in ("p", "drift_over_std", "block_lag1", "n_blocks", "tau_int",
                                 "n_values")}
    if not (test["steady"] and test["independent"]):
        why = ("" if test["independent"] else
               f"; the last window holds {test['n_values'] / test['tau_int']:.1f} integrated "
               f"autocorrelation times of tau, {MIN_BLOCKS * BLOCK_OVER_TAU:g} needed")
        return gamma0, {"steady": False, "start": None, **keep,
                        "reason": f"no start from strain {gamma0:g} on passes the trend test "
                                  f"on independent blocks (last candidate p = "
                                  f"{test['p']:.2g}{why}): extend the run"}
    return max(gamma0, float(s)), {"steady": True, "start": float(s), **keep}


def memory_trend_test(x, alpha=0.05):
    """:func:`trend_test` of ``x`` on blocks sized by its memory
    (:func:`fricstab.analysis.autocorrelation.memory_blocks`): the test's dict and
    ``tau_int`` (values) and ``independent`` (every block holds at least
    ``BLOCK_OVER_TAU`` integrated times; where False, an acceptance means nothing)."""
    from fricstab.analysis.autocorrelation import memory_blocks
    n, g, independent = memory_blocks(x)
    return {**trend_test(x, n, alpha), "tau_int": g, "independent": independent}
