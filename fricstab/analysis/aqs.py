"""Stress drops of an AQS path and whether complex-pair births precede them (issue 17).

Drops.  Step ``k`` (from strain ``gamma_{k-1}`` to ``gamma_k``) is a *drop*
when ``sigma_k - sigma_{k-1} < -threshold``; consecutive drop steps are one
drop (an avalanche that the steps cut), its size their summed decrease and its
strain the onset ``gamma_{k-1}`` of the first, the last equilibrium of the
branch.  ``threshold`` is an
absolute stress (``k_N d^(-1/2)``; default :data:`DROP_THRESHOLD`), so a drop
does not depend on ``dgamma`` through it; on an elastic branch ``Delta sigma =
G dgamma > 0`` and the round-off of sigma (``4 eps sum |f^x y| / L^2``, about
1e-18 here) is far below.

Precursors.  A drop at ``g`` is *preceded* when a pair birth lies in the
window ``(g - window, g]``: strictly before the onset, so a birth inside the
drop's own step (where the branch is not continuous) does not count.  The
null is the same statistic at strains drawn uniformly from ``[window,
gamma_max]``: its probability ``p0`` is the measure of the union of the
windows ``[b, b + window)`` after the births ``b`` within that range divided
by its length (exact, no sampling).  Pooled over runs, the drops of a law are
compared with the drop-weighted mean ``p0`` by an exact binomial test
(:func:`scipy.stats.binomtest`, one-sided, greater) with Wilson intervals.
"""

from dataclasses import dataclass

import numpy as np

__all__ = ["DROP_THRESHOLD", "Drop", "compare", "detect_drops", "null_fraction", "preceded",
           "wilson"]

DROP_THRESHOLD = 1e-5   # k_N d^(-1/2): about G dgamma for G ~ 0.03 at dgamma = 3e-4


@dataclass(frozen=True)
class Drop:
    step: int          # the first step that drops: from step - 1 to step
    gamma: float       # onset strain gamma_{step - 1}
    size: float        # summed decrease over the consecutive drop steps
    steps: int = 1     # consecutive drop steps

    def record(self):
        return {"step": self.step, "gamma": self.gamma, "size": self.size,
                "steps": self.steps}


def detect_drops(strain, stress, threshold=DROP_THRESHOLD):
    """The stress drops of an AQS path (module doc: consecutive drop steps are one drop).

    Parameters
    ----------
    strain : array_like
        Strain of each relaxed state (dimensionless).
    stress : array_like
        Shear stress of each state (``k_N d^(-1/2)``).
    threshold : float, optional
        A step whose stress falls by more than this (``k_N d^(-1/2)``) drops.

    Returns
    -------
    list of Drop
        ``step`` (first dropping step), ``gamma`` (onset strain), ``size``
        (summed decrease) and ``steps``.
    """
    from fricstab.errors import ParameterError, check_finite_array, check_real
    check_finite_array("strain", strain, ndim=1)
    check_finite_array("stress", stress, ndim=1)
    check_real("threshold", threshold, 0.0)
    if len(strain) != len(stress):
        raise ParameterError(f"strain and stress must have the same length, got {len(strain)} "
                             f"and {len(stress)}")
    ds = np.diff(np.asarray(stress, float))
    out = []
    for k in np.flatnonzero(ds < -threshold) + 1:
        if out and out[-1].step + out[-1].steps == k:
            last = out.pop()
            out.append(Drop(last.step, last.gamma, last.size - float(ds[k - 1]),
                            last.steps + 1))
        else:
            out.append(Drop(int(k), float(strain[k - 1]), float(-ds[k - 1])))
    return out


def preceded(gammas, births, window):
    """For each strain, whether a birth lies in ``(g - window, g]``; and the lag to the latest."""
    births = np.sort(np.asarray(births, float))
    gammas = np.asarray(gammas, float)
    idx = np.searchsorted(births, gammas, side="right") - 1
    lag = np.where(idx >= 0, gammas - births[np.clip(idx, 0, None)], np.inf) \
        if births.size else np.full(gammas.shape, np.inf)
    return lag < window, lag


def null_fraction(births, window, gamma_max):
    """Probability that a uniform strain in ``[window, gamma_max]`` is preceded (module doc)."""
    lo, hi = window, gamma_max
    if hi <= lo:
        return float("nan")
    covered, end = 0.0, lo
    for b in np.sort(np.asarray(births, float)):
        a, c = max(b, end), min(b + window, hi)
        if c > a:
            covered += c - a
            end = c
    return covered / (hi - lo)


def wilson(k, n, confidence=0.95):
    """Wilson score interval of ``k`` successes in ``n`` (scipy.stats); (nan, nan) for n = 0."""
    if n == 0:
        return float("nan"), float("nan")
    from scipy.stats import binomtest
    ci = binomtest(int(k), int(n)).proportion_ci(confidence, method="wilson")
    return float(ci.low), float(ci.high)


def compare(runs, window):
    """Pooled precursor statistic of one law over ``runs`` (module doc).

    Parameters
    ----------
    runs : list of dict
        Each with ``drops`` (onset strains), ``births`` (strains) and
        ``gamma_max`` (the strain the path reached).
    window : float
        A drop is preceded when a birth lies in ``(g - window, g]`` (strain).

    Returns
    -------
    dict
        ``drops``, ``preceded``, ``fraction`` and its 95 % Wilson interval
        ``fraction_ci95``, the drop-weighted null ``null_fraction``, the
        one-sided exact binomial ``pvalue_greater``, and the median lags
        ``median_lag`` (drops) and ``median_lag_null`` (a uniform grid of
        strains) among the preceded; NaN where undefined (no drops).
    """
    from scipy.stats import binomtest
    k = n = 0
    p0_weighted, lags, null_lags = 0.0, [], []
    for r in runs:
        drops = np.asarray(r["drops"], float)
        drops = drops[drops >= window]
        hit, lag = preceded(drops, r["births"], window)
        k += int(hit.sum())
        n += len(drops)
        lags += list(lag[hit])
        p0 = null_fraction(r["births"], window, r["gamma_max"])
        if len(drops):
            p0_weighted += len(drops) * p0
        grid = np.linspace(window, r["gamma_max"], 2001)
        hit0, lag0 = preceded(grid, r["births"], window)
        null_lags += list(lag0[hit0])
    p0 = p0_weighted / n if n else float("nan")
    if n and 0 < p0 < 1:
        pvalue = float(binomtest(k, n, p0, alternative="greater").pvalue)
    elif n:
        pvalue = 1.0 if p0 >= 1 else (0.0 if k else 1.0)
    else:
        pvalue = float("nan")
    lo, hi = wilson(k, n)
    return {"window": window, "drops": n, "preceded": k,
            "fraction": k / n if n else float("nan"), "fraction_ci95": [lo, hi],
            "null_fraction": p0, "pvalue_greater": pvalue,
            "median_lag": float(np.median(lags)) if lags else float("nan"),
            "median_lag_null": float(np.median(null_lags)) if null_lags else float("nan")}
