"""The memory of a series, and the blocks of a trend test that respect it.

A trend test on block means (:func:`fricstab.analysis.stationarity.trend_test`) assumes the
means of neighbouring blocks independent: each block much longer than the series' memory.
The memory is measured on the values themselves, by the integrated autocorrelation time
``tau_int = 1 + 2 sum_k rho(k)`` (in values; :func:`integrated_time`: Geyer's initial positive
sequence).
:func:`memory_blocks` cuts the window into the most blocks, at most :data:`MAX_BLOCKS`, of
at least :data:`BLOCK_OVER_TAU` x ``tau_int`` values each, and never fewer than
:data:`MIN_BLOCKS` (with fewer the Mann-Kendall test loses the power to see a transient: on 6
blocks a rise of 3 std passes, p = 0.056); where the window is shorter than
``MIN_BLOCKS x BLOCK_OVER_TAU x tau_int`` the blocks are not independent, the test's p-value
is too small and its acceptance means nothing: the window is too short for the series'
memory (``independent`` False).  The steady start of a sheared run
(:func:`fricstab.analysis.stationarity.steady_window`) accepts a window only where this test
passes on independent blocks.
"""

import numpy as np

from fricstab.errors import ParameterError

__all__ = ["BLOCK_OVER_TAU", "MAX_BLOCKS", "MIN_BLOCKS", "RESOLVED_SLOPE", "integrated_time",
           "memory_blocks", "memory_growth"]

#: the most and the fewest blocks of :func:`memory_blocks` (module docstring)
MAX_BLOCKS, MIN_BLOCKS = 20, 10
#: a block holds at least this many integrated autocorrelation times for its mean to count as
#: independent of its neighbour's (block means of an AR(1) series then have a lag-1
#: correlation ~0.16: :mod:`tests.test_stationarity`)
BLOCK_OVER_TAU = 2.0
#: :func:`memory_growth` calls the memory resolved where log tau_int against log L has a slope
#: of at most this size (a finite memory: ~0, within the estimator's ~10 % scatter over a factor
#: 8 in L; a random walk: ~1; both in :mod:`tests.test_stationarity`)
RESOLVED_SLOPE = 0.25


def integrated_time(x):
    """The integrated autocorrelation time of ``x`` in values, ``1 + 2 sum_k rho(k)``, by
    Geyer's initial positive sequence (autocorrelations summed in pairs while a pair is
    positive) on ``x`` less its mean; 1 for a constant or uncorrelated series.  A drift reads
    as memory: the estimate errs towards calling a drifting window too short, never towards
    calling it steady.
    """
    x = np.asarray(x, float)
    if x.ndim != 1 or x.size < 3:
        raise ParameterError(f"the integrated time needs a one-dimensional series of at least "
                             f"3 values (got shape {x.shape})")
    if not np.all(np.isfinite(x)):
        raise ParameterError(f"the series has {int((~np.isfinite(x)).sum())} non-finite "
                             "values: its autocorrelation needs finite ones")
    d = x - x.mean()
    f = np.fft.rfft(d, 2 * x.size)
    acf = np.fft.irfft(f * np.conj(f))[: x.size]
    if not acf[0] > 1e-300:
        return 1.0
    pairs = (acf / acf[0])[: x.size - x.size % 2].reshape(-1, 2).sum(axis=1)
    stop = np.flatnonzero(pairs <= 0)
    return float(max(1.0, 2.0 * pairs[: stop[0] if stop.size else pairs.size].sum() - 1.0))


def memory_blocks(x):
    """The blocks of a trend test sized by the memory of ``x`` (module docstring):
    ``(n_blocks, tau_int, independent)``; pass ``n_blocks`` to
    :func:`fricstab.analysis.stationarity.trend_test`, and call its acceptance meaningful only
    where ``independent`` (every block holds at least ``BLOCK_OVER_TAU x tau_int`` values)."""
    x = np.asarray(x, float)
    g = integrated_time(x)
    n = int(np.clip(x.size // (BLOCK_OVER_TAU * g), MIN_BLOCKS, MAX_BLOCKS))
    return n, g, bool(x.size // n >= BLOCK_OVER_TAU * g)


def memory_growth(t, x, lengths, span=None):
    """Does the memory of ``x`` level off?  ``span = (lo, hi)`` of ``t`` (default: all of it)
    is cut into non-overlapping windows of each length L in ``lengths`` (units of ``t``, a
    strain say); per L, the median over its windows of :func:`integrated_time` (converted to
    units of ``t`` by the median spacing).  A series with a finite memory gives the same time
    at every L much longer than it; one whose time grows with L has memory on the scale of the
    longest window (slow excursions, a drift), and the time at the longest L is a lower bound.

    Returns a dict: ``rows`` (``length``, ``windows``, ``tau_int``), ``slope`` (least squares
    of log tau_int against log L), ``resolved`` (``|slope| <= RESOLVED_SLOPE``), ``needed``
    (the span of ``MIN_BLOCKS x BLOCK_OVER_TAU`` integrated times at the longest L, what a
    steady window asks for: :func:`fricstab.analysis.stationarity.steady_window`; a lower
    bound where not ``resolved``)."""
    t, x = np.asarray(t, float), np.asarray(x, float)
    if t.shape != x.shape or t.ndim != 1 or t.size < 3:
        raise ParameterError(f"t and x must be one-dimensional, of one length, at least 3 "
                             f"values (got {t.shape} and {x.shape})")
    if np.any(np.diff(t) <= 0):
        raise ParameterError("t must increase (a strain or time axis)")
    lo, hi = (float(t[0]), float(t[-1])) if span is None else map(float, span)
    spacing = float(np.median(np.diff(t)))
    rows = []
    for length in sorted(float(v) for v in lengths):
        if not length > 2 * spacing:
            raise ParameterError(f"window length {length!r}: longer than two samples "
                                 f"({2 * spacing:g}) needed")
        # a window [a, a + L) holds L / spacing samples: the span's samples fill
        # (hi - lo + spacing) / L of them
        starts = lo + length * np.arange(int((hi - lo + spacing) / length + 1e-9))
        times = [integrated_time(x[(t >= a) & (t < a + length)]) * spacing for a in starts]
        if times:
            rows.append({"length": length, "windows": len(times),
                         "tau_int": float(np.median(times))})
    if len(rows) < 2:
        raise ParameterError(f"windows of {len(rows)} length(s) fit in the span {lo:g}..{hi:g}: "
                             "at least 2 are needed to see whether the memory levels off")
    slope = float(np.polyfit(np.log([r["length"] for r in rows]),
                             np.log([r["tau_int"] for r in rows]), 1)[0])
    return {"rows": rows, "slope": slope, "resolved": bool(abs(slope) <= RESOLVED_SLOPE),
            "needed": float(MIN_BLOCKS * BLOCK_OVER_TAU * rows[-1]["tau_int"])}
