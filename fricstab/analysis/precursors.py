"""The ranked precursor test of stress drops, its permutation null and its power (issue 36).

Rank.  For a per-state series ``x`` of an AQS path (pair count, growth rate,
largest real eigenvalue, the smallest ``|Im|`` of the pairs) and a drop whose
onset is state ``k`` (the last equilibrium before the drop), the rank of
``x[k]`` among its neighbourhood ``x[k - W .. k + W]`` (clipped at the ends
of the path, NaN entries left out) is the normalised mid-rank
``(#{x < x[k]} + (#{x = x[k]} - 1) / 2) / (m - 1)`` over the ``m`` finite
entries: 0 lowest, 1 highest, ties averaged (a flat window gives 0.5).

Test.  The statistic is the mean onset rank over all drops of all paths.
Under the null hypothesis the onsets are exchangeable with the other states
of their path, so the permutation null draws, per path, as many distinct
states as the path has (finite-ranked) onsets, uniformly among all its
states with a finite rank *including the onsets themselves*: the observed
configuration is then one of the permutations and the +1-corrected p-value
``(1 + #{null at least as extreme}) / (1 + n_perm)`` is exact in level
(leaving the onsets out would make the observed draw impossible under the
null and the test inexact).  ``alternative="greater"``: the candidate is a
precursor when it is *high* at the onset (more pairs, faster growth, the
largest real eigenvalue nearest zero from below); ``"less"``: when it is
*low* (the pair nearest the real axis, smallest ``|Im|``).

Power.  By simulation of the test: in each replicate every drop is, with
probability ``fraction`` (independently), *preceded* (its rank set to the
extreme of its window in the alternative's direction: 1 or 0), otherwise its
onset is a random admissible state (the null); the test is run at ``alpha``
and the power is the rejection rate.  The null sample is the permutation
distribution of the observed series (planting changes only the drops'
ranks), drawn once.  :func:`window_power` does the same for the birth-window
test of :mod:`fricstab.analysis.aqs` (a birth within ``window`` before the
onset against the exact null fraction ``p0``, binomial test): a preceded drop
has a birth in its window, another one with the path's probability ``p0``;
where births cover nearly every window (``p0`` near 1) that test cannot
reject at any ``fraction``.
"""

import numpy as np

from fricstab.errors import ParameterError

__all__ = ["ALTERNATIVES", "null_statistics", "permutation_test", "power", "window_power",
           "window_ranks"]

ALTERNATIVES = ("greater", "less")


def _check_alternative(alternative):
    if alternative not in ALTERNATIVES:
        raise ParameterError(f"alternative must be one of {ALTERNATIVES}, got {alternative!r}")


def window_ranks(series, onsets, half_width=25):
    """Normalised mid-rank of ``series[k]`` in ``series[k - W .. k + W]`` for each onset k.

    Parameters
    ----------
    series : array_like
        One value per state (NaN: undefined there, left out of every window).
    onsets : array_like of int
        State indices (``0 <= k < len(series)``).
    half_width : int, optional
        ``W``, states on each side (clipped at the ends of the path).

    Returns
    -------
    ndarray
        Ranks in [0, 1] (1 = highest in its neighbourhood); NaN where
        ``series[k]`` is NaN or the window holds fewer than two finite values.
    """
    x = np.asarray(series, float)
    idx = np.asarray(onsets, int).reshape(-1)
    if x.ndim != 1:
        raise ParameterError(f"series must be one-dimensional, got shape {x.shape}")
    if not (isinstance(half_width, (int, np.integer)) and half_width >= 1):
        raise ParameterError(f"half_width must be an integer >= 1, got {half_width!r}")
    if idx.size and (idx.min() < 0 or idx.max() >= x.size):
        raise ParameterError(f"onsets must lie in [0, {x.size - 1}], got {idx.min()} .. "
                             f"{idx.max()}")
    out = np.full(idx.size, np.nan)
    for i, k in enumerate(idx):
        v = x[max(0, k - half_width):k + half_width + 1]
        v = v[np.isfinite(v)]
        if np.isfinite(x[k]) and v.size >= 2:
            out[i] = (np.sum(v < x[k]) + 0.5 * (np.sum(v == x[k]) - 1)) / (v.size - 1)
    return out


def _prepared(paths, half_width):
    """Per path: the ranks of all states with a finite rank, and the finite onset ranks."""
    out = []
    for series, onsets in paths:
        every = window_ranks(series, np.arange(len(series)), half_width)
        at = window_ranks(series, onsets, half_width)
        out.append((every[np.isfinite(every)], at[np.isfinite(at)]))
    return out


def _draws(prepared, n, rng):
    """``(n, m)`` ranks at random admissible states, per path as many (distinct) as onsets."""
    cols = []
    for every, at in prepared:
        if at.size > every.size:
            raise ParameterError(f"{at.size} onsets but {every.size} admissible states in a "
                                 "path")
        if at.size:
            pick = np.argsort(rng.random((n, every.size)), axis=1)[:, :at.size]
            cols.append(every[pick])
    return np.concatenate(cols, axis=1) if cols else np.zeros((n, 0))


def null_statistics(prepared, n_perm, rng):
    """``n_perm`` draws of the mean rank at random admissible states (module doc)."""
    d = _draws(prepared, n_perm, rng)
    return d.mean(axis=1) if d.shape[1] else np.full(n_perm, np.nan)


def _pvalue(observed, null, alternative):
    """+1-corrected permutation p-value; ties within 1e-12 count as extreme."""
    if not np.isfinite(observed):
        return float("nan")
    hits = np.sum(null >= observed - 1e-12) if alternative == "greater" \
        else np.sum(null <= observed + 1e-12)
    return float((1 + hits) / (1 + null.size))


def permutation_test(paths, half_width=25, n_perm=999, rng=None, alternative="greater"):
    """The ranked test of one candidate over ``paths`` (module doc).

    Parameters
    ----------
    paths : list of (series, onsets)
        Per path the candidate's per-state series and the drop onset indices.
    half_width : int, optional
        Neighbourhood half-width ``W`` in states.
    n_perm : int, optional
        Permutation draws of the null.
    rng : numpy.random.Generator, optional
        Source of the draws (default: ``default_rng(0)``).
    alternative : {"greater", "less"}
        The direction in which a precursor is extreme at the onset.

    Returns
    -------
    dict
        ``statistic`` (mean onset rank), ``drops`` (onsets with a finite
        rank), ``null_mean``, ``null_sd``, ``pvalue``, ``n_perm``, ``ranks``
        (the onset ranks, for histograms); NaN statistic and p without drops.
    """
    _check_alternative(alternative)
    rng = np.random.default_rng(0) if rng is None else rng
    prep = _prepared(paths, half_width)
    ranks = np.concatenate([at for _, at in prep]) if prep else np.zeros(0)
    stat = float(ranks.mean()) if ranks.size else float("nan")
    null = null_statistics(prep, n_perm, rng)
    return {"statistic": stat, "drops": int(ranks.size),
            "null_mean": float(np.mean(null)), "null_sd": float(np.std(null)),
            "pvalue": _pvalue(stat, null, alternative), "n_perm": int(n_perm),
            "ranks": ranks.tolist()}


def power(paths, fraction, half_width=25, n_rep=400, n_perm=199, rng=None,
          alternative="greater", alpha=0.05):
    """Rejection rate of the ranked test when a ``fraction`` of the drops is preceded.

    Each replicate: per path, as many random admissible states as onsets
    (without replacement); each drop independently with probability
    ``fraction`` gets the extreme rank (1 for "greater", 0 for "less"); the
    p-value against one null sample of ``n_perm`` draws. Returns the power and
    its binomial standard error; NaN without drops.
    """
    _check_alternative(alternative)
    if not 0.0 <= fraction <= 1.0:
        raise ParameterError(f"fraction must lie in [0, 1], got {fraction!r}")
    rng = np.random.default_rng(1) if rng is None else rng
    prep = _prepared(paths, half_width)
    if not sum(at.size for _, at in prep):
        return {"power": float("nan"), "se": float("nan"), "n_rep": int(n_rep)}
    null = null_statistics(prep, n_perm, rng)
    ranks = _draws(prep, n_rep, rng)
    planted = rng.random(ranks.shape) < fraction
    stats = np.where(planted, 1.0 if alternative == "greater" else 0.0, ranks).mean(axis=1)
    p = np.array([_pvalue(s, null, alternative) for s in stats])
    rate = float(np.mean(p <= alpha))
    return {"power": rate, "se": float(np.sqrt(max(rate * (1 - rate), 1e-12) / n_rep)),
            "n_rep": int(n_rep)}


def window_power(runs, window, fraction, n_rep=400, rng=None, alpha=0.05):
    """Rejection rate of the birth-window test (:func:`fricstab.analysis.aqs.compare`).

    ``runs``: dicts with ``drops`` (onset strains), ``births``, ``gamma_max``.
    A preceded drop (probability ``fraction``) has a birth in its window; any
    other one with its path's exact null probability ``p0``; the exact
    one-sided binomial test against the drop-weighted ``p0`` at ``alpha``.
    Returns the power, its standard error and the drop-weighted ``p0``.
    """
    from scipy.stats import binom

    from fricstab.analysis.aqs import null_fraction
    rng = np.random.default_rng(2) if rng is None else rng
    p0 = np.concatenate([np.full(int(np.sum(np.asarray(r["drops"], float) >= window)),
                                 null_fraction(r["births"], window, r["gamma_max"]))
                         for r in runs]) if runs else np.zeros(0)
    if p0.size == 0:
        return {"power": float("nan"), "se": float("nan"), "p0": float("nan"),
                "n_rep": int(n_rep)}
    n, pbar = p0.size, float(p0.mean())
    hit = (rng.random((n_rep, n)) < fraction) | (rng.random((n_rep, n)) < p0)
    k = hit.sum(axis=1)
    pvalue = binom.sf(k - 1, n, pbar) if pbar < 1 else np.ones(n_rep)
    rate = float(np.mean(pvalue <= alpha))
    return {"power": rate, "se": float(np.sqrt(max(rate * (1 - rate), 1e-12) / n_rep)),
            "p0": pbar, "n_rep": int(n_rep)}
