"""Stick and slip phases and the Spearman tables of Lee & Hurley (Secs. 3.2-3.3, Figs. 9-10).

Pure functions over per-step series (see :mod:`fricstab.analysis.shear` for
the conventions: a step k goes from frame k - 1 to frame k; entry 0 of a
per-step array is unused).

* Phases (Sec. 3.2): maximal runs of steps with Delta tau > 0 (stick) or
  Delta tau < 0 (slip) among the steps of the analysed window; a step with
  Delta tau == 0 ends a run and belongs to none.  A phase over steps a..b
  has Delta tau_p = tau[b] - tau[a-1] and t_p = b - a + 1 (in output strain
  steps); long when t_p > 3.  Eqs. 1-4 per phase: :func:`phase_metrics`.
* Spearman tables: rho, p and n per bin of Delta tau (or Delta tau_p), the
  paper's eight bins :data:`PAPER_BINS`; ``n/a`` for fewer than 3 samples or
  constant input; p > 0.05 is marked (the paper omits those cells).
"""

import math
import warnings

import numpy as np
from scipy.stats import spearmanr

from fricstab.errors import ParameterError

__all__ = ["PAPER_BINS", "binned_spearman", "find_phases", "phase_metrics", "phase_summary",
           "spearman_cell", "step_metrics", "tables_markdown"]

#: Bins of Delta tau (and Delta tau_p) of Figs. 9, 10 and 13.
PAPER_BINS = ((-1e-1, -1e-2), (-1e-2, -1e-3), (-1e-3, -1e-4), (-1e-4, 0.0),
              (0.0, 1e-4), (1e-4, 1e-3), (1e-3, 1e-2), (1e-2, 1e-1))


#: Below this many pairs the p-value is exact (all n! pairings, scipy's permutation_test):
#: the t approximation spearmanr uses gives p = 0 for a perfect rank order at any n
#: (n = 3 was "significant"), while the exact two-sided p of n = 3 is at least 1/3.
EXACT_BELOW = 9


def _exact_p(x, y):
    """Two-sided exact p of Spearman's rho under the permutation null (n < EXACT_BELOW)."""
    from scipy.stats import permutation_test, rankdata
    rx, ry = rankdata(x), rankdata(y)
    ry = (ry - ry.mean()) / np.sqrt(np.sum((ry - ry.mean()) ** 2))

    def rho(r, axis=-1):
        r = r - r.mean(axis=axis, keepdims=True)
        return np.sum(r * ry, axis=axis) / np.sqrt(np.sum(r * r, axis=axis))

    res = permutation_test((rx,), rho, permutation_type="pairings", vectorized=True,
                           n_resamples=np.inf, alternative="two-sided")
    return float(res.pvalue)


def spearman_cell(x, y, min_n=3, alpha=0.05):
    """Spearman rho of finite pairs; ``rho`` None ("n/a") for n < min_n or constant input.

    The p-value is exact for n < :data:`EXACT_BELOW` and scipy's t approximation above.
    """
    x, y = np.asarray(x, float), np.asarray(y, float)
    ok = np.isfinite(x) & np.isfinite(y)
    x, y = x[ok], y[ok]
    cell = {"n": len(x), "rho": None, "p": None, "significant": False, "status": "ok"}
    if len(x) < min_n:
        cell["status"] = f"n/a (n<{min_n})"
    elif np.ptp(x) == 0 or np.ptp(y) == 0:
        cell["status"] = "n/a (constant input)"
    else:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            res = spearmanr(x, y)
        p = _exact_p(x, y) if len(x) < EXACT_BELOW else float(res.pvalue)
        cell.update(rho=float(res.statistic), p=p, significant=bool(p <= alpha))
    return cell


def binned_spearman(key, values, bins=PAPER_BINS, **kw):
    """Spearman of ``key`` against each series of ``values`` within each bin of ``key``.

    A value belongs to bin (lo, hi) when lo <= x < hi, x != 0.

    Returns
    -------
    dict
        ``{name: [cell per bin]}``, each cell as :func:`spearman_cell` plus
        ``lo`` and ``hi``.
    """
    key = np.asarray(key, float)
    out = {}
    for name, v in values.items():
        v = np.asarray(v, float)
        cells = []
        for lo, hi in bins:
            m = (key >= lo) & (key < hi) & (key != 0)
            cells.append({"lo": lo, "hi": hi, **spearman_cell(key[m], v[m], **kw)})
        out[name] = cells
    return out


def tables_markdown(tables, title="Spearman correlations"):
    """Markdown of :func:`binned_spearman` tables: one row per series, one column per bin.

    A cell reads ``rho (p)``; cells with p > 0.05 are struck through, as the
    paper omits them; ``n/a`` where fewer than 3 samples or constant input.
    ``tables`` maps a section name to ``{series: [cell per bin]}``.
    """
    lines = [f"## {title}", ""]
    for section, series in tables.items():
        if not series:
            continue
        cells0 = next(iter(series.values()))
        head = [f"[{c['lo']:g}, {c['hi']:g})" for c in cells0]
        lines += [f"### {section}", "", "| series | " + " | ".join(head) + " |",
                  "|---" * (len(head) + 1) + "|"]
        for name, cells in series.items():
            row = []
            for c in cells:
                if c["rho"] is None:
                    row.append(f"n/a (n={c['n']})")
                else:
                    txt = f"{c['rho']:+.2f} (p={c['p']:.1e}, n={c['n']})"
                    row.append(txt if c["significant"] else f"~~{txt}~~")
            lines.append(f"| {name} | " + " | ".join(row) + " |")
        lines.append("")
    return "\n".join(lines)


def find_phases(tau, step_ok):
    """Stick and slip phases (Sec. 3.2) of a tau series.

    Parameters
    ----------
    tau : ndarray (T,)
    step_ok : ndarray (T,) bool
        Steps k (frame k-1 -> k) inside the analysed window; entry 0 ignored.

    Returns
    -------
    ndarray (P, 2) int64
        First and last step (a, b) of each phase; sign from tau[b] - tau[a-1].
    """
    tau = np.asarray(tau, float)
    sign = np.zeros(len(tau), np.int8)
    sign[1:] = np.sign(np.diff(tau))
    sign[~np.asarray(step_ok, bool)] = 0
    sign[0] = 0
    phases, a = [], None
    for k in range(1, len(tau) + 1):
        cur = sign[k] if k < len(tau) else 0
        if a is not None and cur != sign[a]:
            phases.append((a, k - 1))
            a = None
        if a is None and cur != 0:
            a = k
    return np.array(phases, dtype=np.int64).reshape(-1, 2)


def phase_metrics(phases, tau, g, g10, n_clusters, ts_rule="min_gr"):
    """Delta tau_p, t_p and Eqs. 1-4 per phase.

    Returns
    -------
    dict of ndarray (P,)
        ``dtau_p, t_p, mg, mg10, sg, sg10, ts`` (t_s step index).
    """
    if ts_rule not in ("min_gr", "start"):
        raise ParameterError(f"ts_rule = {ts_rule!r}; allowed: 'min_gr', 'start'")
    P = len(phases)
    out = {name: np.full(P, np.nan) for name in ("dtau_p", "mg", "mg10", "sg", "sg10")}
    out["t_p"] = np.zeros(P, np.int64)
    out["ts"] = np.zeros(P, np.int64)
    for p, (a, b) in enumerate(phases):
        s = slice(a, b + 1)
        out["dtau_p"][p] = tau[b] - tau[a - 1]
        out["t_p"][p] = b - a + 1
        ts = a + int(np.argmin(n_clusters[s])) if ts_rule == "min_gr" else a
        out["ts"][p] = ts
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN phases stay NaN
            out["mg"][p] = np.nanmax(g[s]) if np.any(np.isfinite(g[s])) else np.nan
            out["mg10"][p] = np.nanmax(g10[s]) if np.any(np.isfinite(g10[s])) else np.nan
        out["sg"][p] = np.sum(g[ts:b + 1])
        out["sg10"][p] = np.sum(g10[ts:b + 1])
    return out


def phase_summary(phases, metrics, n_steps, strain_span):
    """Counts for comparison with the paper (about 0.32 phases per output step)."""
    dt, tp = metrics["dtau_p"], metrics["t_p"]
    slips = dt < 0
    P = len(phases)
    largest = int(np.argmin(dt)) if P else None
    return {
        "n_steps": int(n_steps), "n_phases": int(P),
        "phases_per_step": P / n_steps if n_steps else None,
        "phases_per_unit_strain": P / strain_span if strain_span > 0 else None,
        "n_stick": int((dt > 0).sum()), "n_slip": int(slips.sum()),
        "fraction_long": float((tp > 3).mean()) if P else None,
        "fraction_short": float((tp <= 3).mean()) if P else None,
        "slip_abs_dtau_mean": float(np.abs(dt[slips]).mean()) if slips.any() else None,
        "slip_abs_dtau_median": float(np.median(np.abs(dt[slips]))) if slips.any() else None,
        "largest_drop": float(dt[largest]) if P else None,
        "largest_drop_steps": [int(x) for x in phases[largest]] if P else None,
    }


def step_metrics(d2, bulk):
    """gD2min (max) and g_t10%D2min (mean of the top 10 %) over finite bulk D2min."""
    v = d2[bulk & np.isfinite(d2)]
    if len(v) == 0:
        return np.nan, np.nan
    top = np.sort(v)[-max(1, math.ceil(0.1 * len(v))):]
    return float(v.max()), float(top.mean())
