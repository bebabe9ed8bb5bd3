"""Two of Lee & Hurley's statements on long phases, from the arrays of :func:`fricstab.analysis.
shear.analyze` (``analysis.npz``): Fig. 11, and sg against mg in long slips (Sec. 4).

**Fig. 11.**  For long phases (``t_p > 3`` output steps), the Spearman correlation of
``Delta tau_p`` with the mean and the median of the GR contacts' ``|theta|`` at the phase's
``t_s`` (the step of fewest GR clusters), within ranges of ``mg_t10%D2min`` (a) and
``sg_t10%D2min`` (b).  The paper's ranges are drawn in its figure only; here they are the
quartiles of the long phases' values (:func:`angle_correlations`).  The paper: weak or not
significant (p > 0.05) everywhere.

**sg against mg in long slips.**  "The correlations between Delta tau_p and sg_t10%D2min are
almost equal to or stronger than those between Delta tau_p and mg_t10%D2min in long phases"
during slips (Sec. 4, Fig. 13 c and g).  The two correlations share their phases, so their
difference is tested paired: per bin of ``Delta tau_p`` (the paper's), the phases are
resampled together (bootstrap, ``n_boot``) and the difference ``|rho_sg| - |rho_mg|`` gets a
two-sided 95 % interval (:func:`sg_versus_mg`).  Per bin: *stronger* when the interval lies
above 0, *weaker* when below, *almost equal* when it contains 0.  The statement holds in a bin
unless it is *weaker*.
"""

import numpy as np
from scipy import stats

from fricstab.analysis.shear_phases import PAPER_BINS, spearman_cell
from fricstab.errors import ParameterError

__all__ = ["angle_correlations", "sg_versus_mg"]

LONG = 3          # t_p > 3 output steps: a long phase (Sec. 3.3)
NEEDED = ("phase_dtau_p", "phase_t_p", "phase_ts", "phase_mg10", "phase_sg10", "angle_mean",
          "angle_median")


def _arrays(a):
    missing = [k for k in NEEDED if k not in a]
    if missing:
        raise ParameterError(f"the analysis arrays lack {', '.join(missing)}: give the arrays "
                             "of fricstab.analysis.shear.analyze (RUN/analysis.npz)")
    return {k: np.asarray(a[k]) for k in NEEDED}


def angle_correlations(arrays, n_bins=4, min_n=3):
    """Fig. 11: per range of mg10 (``"mg10"``) and of sg10 (``"sg10"``), the Spearman cells
    (:func:`spearman_cell`) of ``Delta tau_p`` with ``angle_mean`` and ``angle_median`` at
    ``t_s``, over long phases; ranges are the ``n_bins`` quantile bins of the long phases'
    values.  Returns ``{"mg10": [cell, ...], "sg10": [...]}``, each cell with ``lo``, ``hi``
    and ``mean`` / ``median`` sub-cells."""
    a = _arrays(arrays)
    if int(n_bins) != n_bins or n_bins < 1:
        raise ParameterError(f"n_bins = {n_bins!r}: a positive integer")
    long_ = a["phase_t_p"] > LONG
    ts = a["phase_ts"][long_].astype(np.int64)
    dt = a["phase_dtau_p"][long_]
    ang = {"mean": a["angle_mean"][ts], "median": a["angle_median"][ts]}
    out = {}
    for key in ("mg10", "sg10"):
        x = a[f"phase_{key}"][long_]
        ok = np.isfinite(x)
        edges = np.quantile(x[ok], np.linspace(0, 1, int(n_bins) + 1)) if ok.any() else []
        cells = []
        for i in range(len(edges) - 1):
            lo, hi = edges[i], edges[i + 1]
            m = ok & (x >= lo) & ((x < hi) if i < len(edges) - 2 else (x <= hi))
            cell = {"lo": float(lo), "hi": float(hi), "n_phases": int(m.sum())}
            for name, v in ang.items():
                sel = m & np.isfinite(v)
                cell[name] = spearman_cell(dt[sel], v[sel], min_n=min_n)
            cells.append(cell)
        out[key] = cells
    return out


def _abs_rho(x, y):
    if x.size < 3 or np.all(x == x[0]) or np.all(y == y[0]):
        return np.nan
    return abs(float(stats.spearmanr(x, y).statistic))


def sg_versus_mg(arrays, bins=None, n_boot=2000, seed=0):
    """The paired test of sg10 against mg10 in long slips (module docstring), per bin of
    ``Delta tau_p < 0`` (default: the paper's slip bins).  Returns a list of cells: ``lo``,
    ``hi``, ``n``, ``rho_mg10``, ``rho_sg10`` (absolute values), ``diff`` and its 95 %
    ``interval``, ``reading`` (stronger / almost equal / weaker / too few) and ``holds``."""
    a = _arrays(arrays)
    bins = [b for b in PAPER_BINS if b[1] <= 0] if bins is None else bins
    long_ = a["phase_t_p"] > LONG
    dt = a["phase_dtau_p"][long_]
    mg, sg = a["phase_mg10"][long_], a["phase_sg10"][long_]
    rng = np.random.default_rng(seed)
    out = []
    for lo, hi in bins:
        m = (dt >= lo) & (dt < hi) & (dt != 0) & np.isfinite(mg) & np.isfinite(sg)
        x, u, v = dt[m], mg[m], sg[m]
        cell = {"lo": lo, "hi": hi, "n": int(m.sum())}
        if x.size < 10:
            cell.update(reading="too few", holds=None)
            out.append(cell)
            continue
        r_mg, r_sg = _abs_rho(x, u), _abs_rho(x, v)
        idx = rng.integers(0, x.size, size=(n_boot, x.size))
        diffs = np.array([_abs_rho(x[i], v[i]) - _abs_rho(x[i], u[i]) for i in idx])
        diffs = diffs[np.isfinite(diffs)]
        lo_ci, hi_ci = np.quantile(diffs, [0.025, 0.975])
        reading = ("stronger" if lo_ci > 0 else "weaker" if hi_ci < 0 else "almost equal")
        cell.update(rho_mg10=r_mg, rho_sg10=r_sg, diff=r_sg - r_mg,
                    interval=[float(lo_ci), float(hi_ci)], reading=reading,
                    holds=reading != "weaker")
        out.append(cell)
    return out
