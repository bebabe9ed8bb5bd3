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

__all__ = ["BLOCK_OVER_TAU", "MAX_BLOCKS", "MIN_BLOCKS", "integrated_time", "memory_blocks"]

#: the most and the fewest blocks of :func:`memory_blocks` (module docstring)
MAX_BLOCKS, MIN_BLOCKS = 20, 10
#: a block holds at least this many integrated autocorrelation times for its mean to count as
#: independent of its neighbour's (block means of an AR(1) series then have a lag-1
#: correlation ~0.16: :mod:`tests.test_stationarity`)
BLOCK_OVER_TAU = 2.0


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
