"""Issue 35: Ishima et al. at the paper's scale, by one command: the ensemble, Figs. 4-8, 10,
14, 16, the sign change of G_NA per phi, the band-mixing question, each with a computed verdict.

Paper: ``../shared/papers/ishima-rigidity-dos-frictional-grains.md``.  The paper's scale:
Figs. 4 and 6 at N = 1,024 (5 samples per phi, Sec. II), Figs. 5, 7-10, 14 and 16 at N = 4,096
(10 samples), phi = 0.83-0.90.  Two tiers:

``--tier paper``  that scale (``hours`` to days on one core; resumable: every piece is cached
                  per packing with the code that made it, ``validation/runs/ishima_paper/``, committed);
``--tier paper1024``  the paper tier's N = 1,024 part alone (5 samples per phi; ~3 core-h):
                  Figs. 4 and 6 at the paper's scale, and the figures the paper draws at
                  N = 4,096 (5, 7-10, 14, 16) at N = 1,024; the same store, so its pieces
                  count for ``paper`` too;
``--tier quick``  the same pipeline at N = 64, 3 samples, phi = 0.84, 0.87, 0.90 (a minute;
                  CI runs it, ``validation/test_ishima_paper.py``).

Per packing, in the order that fills the cheapest figures first (Figs. 4, 6 and the band
mixing at N = 1,024, then the phi = 0.90 spectra at the DOS size, then Figs. 5 and 16): the ensemble row (made, or read from ``validation/.packings``; judged
by the exclusion rule of :mod:`fricstab.analysis.stability`, :mod:`ishima_ensemble`); G_A,
G_NA by the sparse solve on a kT/kN grid and the root of G_NA (Brent in log kT); G by the mode
sum and by step strain at kT/kN = 1e-4, 1, 10 where the dense spectrum fits; the spectrum of
the backbone (symmetric route: J = J^T in the unstrained packing) and of the whole packing
with its rattlers.  A packing the rule excludes is listed with its reason and enters no mean.

``--max-hours H`` stops after the piece that crosses H hours and writes the report of what is
done (the scale reached is stated in it); ``--resume`` is implicit (the cache).  Several runs
share the work: start the command once per core (or on machines sharing the store), each with
its own ``--out``; a run holds the packing whose pieces it computes (:func:`_hold`) and leaves
a packing another live run holds to it.  Writes
``ishima_paper_<tier>.md``, ``.json`` and ``.png`` in ``--out``.
"""

import argparse
import json
import math
import platform
import sys
import time
from datetime import datetime, timezone
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
sys.path.insert(0, str(HERE))

import numpy as np  # noqa: E402
import scipy.optimize  # noqa: E402
import scipy.stats  # noqa: E402

import _packings  # noqa: E402
import _stamped  # noqa: E402
import ishima_ensemble  # noqa: E402
from fricstab.analysis.dos import participation, rotational_peak, spectrum  # noqa: E402
from fricstab.analysis.rigidity import linear_response, rigidity  # noqa: E402
from fricstab.errors import ParameterError  # noqa: E402
from fricstab.io.rundir import Lock  # noqa: E402
from fricstab.protocols.stepstrain import step_strain  # noqa: E402
from fricstab.scenes.packing_friction import Backbone, backbone  # noqa: E402

CACHE = HERE / ".ishima_paper"       # the quick tier's pieces (git-ignored)
#: the paper tier's pieces and packings: committed (``validation/runs/README.md``), so a run
#: spread over sittings on other machines goes on where it stopped, each piece beside the
#: packing it was computed on (seeded FIRE is chaotic: another CPU can reach another packing)
STORE = HERE / "runs" / "ishima_paper"
#: kT/kN of the rigidity sweep (0: the frictionless Hessian)
RIG_KTS = (0.0, 1e-8, 1e-6, 1e-4, 1e-2, 0.1, 0.5, 1.0, 2.0, 5.0, 10.0)
CHECK_KTS = (1e-4, 1.0, 10.0)        # Fig. 4: mode sum and step strain beside the solve
MIX_KTS = (1e-8, 1e-6, 1e-4, 1e-2)   # band mixing over phi (the paper's 1e-6..1e-2 and below)
DOS_KTS = (1e-8, 1e-6, 1e-4, 1e-2, 1.0, 10.0)   # the spectra at phi = 0.90 (Figs. 7-10, 14)
RATTLER_KTS = (1e-8, 1e-4)           # Figs. 13-14: the packing with its rattlers
MODES_MAX = 3300                     # dense mode sum up to this many dof (N = 1,024: ~3,000)
FIG_PHI = 0.90
ROOT_BRACKET = (-2.0, 1.5)           # log10 kT/kN where the root of G_NA is sought
MIXED = (0.1, 0.9)                   # a mode is mixed when 0.1 < psi^R < 0.9
PAPER_ROOT, PAPER_ROOT_ERR = 2.0, 0.05   # "k_T/k_N = 2.0": half a unit of its last digit
EDGES = np.geomspace(1e-7, 1e1, 81)  # ten bins per decade, fixed: histograms add over samples

TIERS = {
    "quick": {"fig4_n": 64, "dos_n": 64, "samples": {64: 3}, "phis": (0.84, 0.87, 0.90)},
    "paper": {"fig4_n": 1024, "dos_n": 4096, "samples": {1024: 5, 4096: 10},
              "phis": ishima_ensemble.PHIS},
    "paper1024": {"fig4_n": 1024, "dos_n": 1024, "samples": {1024: 5},
                  "phis": ishima_ensemble.PHIS},
}
#: tiers whose pieces live in the committed store (the quick tier's: the git-ignored CACHE)
STORED_TIERS = ("paper", "paper1024")


# ------------------------------------------------------------------ pieces, per packing

def use_store(tier):
    """Point the piece and packing caches at the tier's store (the paper tiers:
    :data:`STORE`)."""
    global CACHE
    if tier in STORED_TIERS:
        CACHE = STORE
        _packings.CACHE = STORE / "packings"


def _modes(**arrays):
    """Per-mode arrays as float32 (7 digits: far below any bin, threshold or statistic the
    analyses use; half the bytes the committed store holds)."""
    return {k: np.asarray(v, np.float32) for k, v in arrays.items()}


def _path(n, phi, seed, piece):
    return CACHE / f"{ishima_ensemble._key(n, phi, seed)}_{piece}.npz"


def _system(bb, kt):
    return _packings.ishima(bb, kt)


def ensemble_piece(n, phi, seed):
    """The ensemble row (:func:`ishima_ensemble.one`) as JSON text."""
    return {"row": np.str_(json.dumps(ishima_ensemble.one(n, phi, seed, log=lambda m: None)))}


def _root(bb):
    """kT/kN where G_NA changes sign (Brent in log10 kT over ROOT_BRACKET; nan if none)."""
    f = lambda lk: rigidity(*_system(bb, 10.0 ** lk)).g_na_solve  # noqa: E731
    lo, hi = ROOT_BRACKET
    if f(lo) * f(hi) > 0:
        return float("nan")
    return 10.0 ** scipy.optimize.brentq(f, lo, hi, xtol=1e-6)


def rigidity_piece(bb):
    """G_A and G_NA (solve) on RIG_KTS, the root of G_NA, and at CHECK_KTS G by the mode sum
    (where 3N' <= MODES_MAX) and by step strain (dgamma = 1e-6) with its error model.

    A packing at the jamming threshold can lose its rigidity under the finite strain (contacts
    open, the relaxation's Jacobian turns singular: N = 4,096, phi = 0.84, seed 1, z = 4.04):
    there the step-strain check is NaN and ``step_failed`` says why (the linear response, the
    solve, stands)."""
    # Imported here, not at the top: a change to this module's top level would change the
    # fingerprint of its module frame, which every stored piece traces, and stale them all.
    from fricstab.errors import ConvergenceError
    g_a, g_na = [], []
    for kt in RIG_KTS:
        r = rigidity(*_system(bb, kt))
        g_a.append(r.g_a)
        g_na.append(r.g_na_solve)
    modes = 3 * bb.n <= MODES_MAX
    g_modes, g_step, step_err, g_solve, failed = [], [], [], [], []
    for kt in CHECK_KTS:
        system, state = _system(bb, kt)
        r = rigidity(system, state, modes=modes, route="symmetric")
        g_solve.append(r.g)
        g_modes.append(r.g_modes if modes else float("nan"))
        try:
            s = step_strain(system, state, 1e-6)
        except ConvergenceError as exc:
            failed.append(f"kT/kN = {kt:g}: {exc}")
            g_step.append(float("nan"))
            step_err.append(float("nan"))
            continue
        g_step.append(float(s.g))
        step_err.append(float(s.error))
    return {"g_a": np.array(g_a), "g_na": np.array(g_na), "root": np.float64(_root(bb)),
            "g_check": np.array(g_solve), "g_modes": np.array(g_modes),
            "g_step": np.array(g_step), "step_err": np.array(step_err),
            "step_failed": np.str_("; ".join(failed))}


def spectrum_piece(bb, kt):
    """omega t0, psi^R and p of the backbone's modes, the two translations dropped."""
    jac = linear_response(*_system(bb, kt)).jacobian
    sp = spectrum(jac, route="symmetric")
    _, psi_r, p = participation(sp.right, 3 if kt > 0 else 2)
    keep = np.sort(np.argsort(np.abs(sp.eigenvalues.real))[2:])
    return {**_modes(omega=sp.omega[keep], psi_r=psi_r[keep], p=p[keep]),
            "seconds": np.float64(sp.seconds)}


def rattler_piece(pk, bb, kt):
    """The same for the whole packing, rattlers kept (the paper's Figs. 13-14), and each mode's
    weight on the rattlers; exact zero modes (free rattlers, translations) dropped."""
    whole = Backbone(pk.pos, pk.diameter / 2, pk.box, np.arange(pk.n), pk.n, 0.0)
    jac = linear_response(*_system(whole, kt)).jacobian
    sp = spectrum(jac, route="symmetric")
    _, psi_r, p = participation(sp.right, 3)
    w = sp.eigenvalues.real
    keep = np.abs(w) > 1e-12 * np.abs(w).max()
    rattler = np.ones(pk.n, bool)
    rattler[bb.keep] = False
    weight = (np.abs(sp.right) ** 2).reshape(pk.n, 3, -1).sum(axis=1)[rattler].sum(axis=0)
    return {**_modes(omega=sp.omega[keep], psi_r=psi_r[keep], p=p[keep],
                     w_rattler=weight[keep]), "seconds": np.float64(sp.seconds)}


def plan(tier):
    """The pieces of a tier, as (n, phi, seed, piece) in the order they are computed."""
    t = TIERS[tier]
    n4, nd, phis = t["fig4_n"], t["dos_n"], t["phis"]
    todo = []

    def add(n, phi, seed, pieces):
        for p in pieces:
            if (n, phi, seed, p) not in todo:
                todo.append((n, phi, seed, p))
    at_fig = [FIG_PHI] + [p for p in phis if p != FIG_PHI]
    # cheapest and most asked-for first: Figs. 4, 6 and the band mixing over phi (N = 1,024),
    # then the DOS size seed by seed, each seed over every phi (the phi = 0.90 spectra with
    # it): every phi gains a packing before any gains its next, so a store stopped part way
    # covers the sweep of Figs. 5 and 16 and not one phi alone
    for phi in at_fig:
        for seed in range(t["samples"][n4]):
            add(n4, phi, seed, ["ensemble", "rigidity"] + [f"dos{k:g}" for k in MIX_KTS]
                + [f"rattlers{k:g}" for k in MIX_KTS])
    for seed in range(t["samples"][nd]):
        for phi in at_fig:
            add(nd, phi, seed, ["ensemble", "rigidity", "dos1e-08"]
                + ([f"dos{k:g}" for k in DOS_KTS]
                   + [f"rattlers{k:g}" for k in RATTLER_KTS] if phi == FIG_PHI else []))
    return todo


def compute(n, phi, seed, piece, log=print):
    """One piece, from the cache while its code is unchanged."""
    def make():
        if piece == "ensemble":
            return ensemble_piece(n, phi, seed)
        pk = _packings.packing(n, phi, seed)
        bb = backbone(pk)
        if piece == "rigidity":
            return rigidity_piece(bb)
        if piece.startswith("rattlers"):
            return rattler_piece(pk, bb, float(piece[len("rattlers"):]))
        return spectrum_piece(bb, float(piece[len("dos"):]))
    return _stamped.cached(_path(n, phi, seed, piece), make, log=log)


def _hold(n, phi, seed, log=print):
    """Hold the packing ``(n, phi, seed)`` for this run while it computes the packing's pieces,
    so that several runs of this script (one per core, or machines sharing the store) share
    the work: a :class:`fricstab.io.rundir.Lock` in ``CACHE/.held/<key>/`` (git-ignored; a lock
    whose run is gone, on this host, is taken over).  Returns the lock, or None (logged) when
    another live run holds the packing: its pieces are left to that run."""
    folder = CACHE / ".held" / ishima_ensemble._key(n, phi, seed)
    folder.mkdir(parents=True, exist_ok=True)
    try:
        return Lock(folder, "ishima_paper", " ".join(sys.argv)).acquire()
    except ParameterError as exc:
        log(f"  N = {n} phi = {phi:g} seed {seed}: left to another run ({exc})")
        return None


def _let_go(lock):
    if lock is not None:
        lock.release()
        try:
            lock.path.parent.rmdir()
        except OSError:
            pass            # another run holds it again, or it holds something else


def run_pieces(tier, max_hours=None, log=print, compute_missing=True):
    """Compute (or read) every piece of ``tier`` (with ``compute_missing=False`` only read the
    fresh ones: the report of what is done); pieces of packings the rule excludes are
    skipped, and so are the pieces of a packing another run holds (:func:`_hold`).  Returns
    ``({(n, phi, seed, piece): arrays}, units, pending)``: ``pending`` the pieces owed and not
    done (stopped by ``max_hours``, or left to another run)."""
    todo = plan(tier)
    got, units, t0, excluded, pending = {}, {}, time.perf_counter(), set(), []
    held, lock, refused = None, None, set()  # the packing this run holds, its lock; others'
    try:
        for i, (n, phi, seed, piece) in enumerate(todo):
            if (n, phi, seed) in excluded:
                continue                # an excluded packing's pieces are not owed
            if max_hours is not None and time.perf_counter() - t0 > 3600 * max_hours:
                if compute_missing:
                    log(f"stopped after {max_hours:g} h: {len(got)} pieces done")
                compute_missing = False       # from here on: what the cache holds
            if held != (n, phi, seed):
                _let_go(lock)
                held, lock = (n, phi, seed), None
            a = time.perf_counter()
            out = _stamped.stored(_path(n, phi, seed, piece))
            if out is None and compute_missing and held not in refused:
                if lock is None:
                    lock = _hold(n, phi, seed, log)
                    if lock is None:    # another run's: not asked again in this pass
                        refused.add(held)
                if lock is not None:
                    out = compute(n, phi, seed, piece, log=log)
            if out is None:
                pending.append((n, phi, seed, piece))
                continue
            spent = time.perf_counter() - a
            if spent > 1.0:
                log(f"  N = {n} phi = {phi:g} seed {seed}: {piece} ({spent:.0f} s; "
                    f"{i + 1} of {len(todo)})")
            got[(n, phi, seed, piece)] = out
            units = _stamped.merge(units, _stamped.units_of(out))
            if piece == "ensemble" and not json.loads(out["row"])["use"]:
                excluded.add((n, phi, seed))
    finally:
        _let_go(lock)
    return got, units, pending


# ------------------------------------------------------------------ statistics

def _ms(xs):
    """(mean, sample sd, standard error, count) of the finite values in ``xs``."""
    x = np.asarray([v for v in xs if np.isfinite(v)], float)
    if x.size == 0:
        return {"mean": None, "sd": None, "se": None, "count": 0}
    sd = float(x.std(ddof=1)) if x.size > 1 else 0.0
    return {"mean": float(x.mean()), "sd": sd, "se": sd / math.sqrt(x.size), "count": int(x.size)}


def _used(got, n, phi):
    """Seeds of (n, phi) whose packing the rule keeps (its ensemble row at hand) and whose
    rigidity is done."""
    return sorted(s for (m, p, s, piece) in got if m == n and p == phi and piece == "rigidity"
                  and (m, p, s, "ensemble") in got
                  and json.loads(got[(m, p, s, "ensemble")]["row"])["use"])


def ensemble_table(got):
    rows = [dict(json.loads(v["row"])) for k, v in got.items() if k[3] == "ensemble"]
    return rows, ishima_ensemble.summary(rows)


def _worst(a):
    """The largest finite entry of ``a`` (a route check over the seeds that have it); None where
    no seed has it (no mode sum at this N, or every step strain failed)."""
    return float(np.nanmax(a)) if np.isfinite(a).any() else None


def rigidity_tables(got, n, phis):
    """Per phi: G, G_A, G_NA on RIG_KTS (mean, sd, se), the roots, the Fig. 4 route checks."""
    out = {}
    for phi in phis:
        seeds = _used(got, n, phi)
        if not seeds:
            continue
        r = [got[(n, phi, s, "rigidity")] for s in seeds]
        g = np.array([x["g_a"] + x["g_na"] for x in r])
        g_na = np.array([x["g_na"] for x in r])
        check = np.array([x["g_check"] for x in r])
        modes = np.array([x["g_modes"] for x in r])
        step = np.array([x["g_step"] for x in r])
        err = np.array([x["step_err"] for x in r])
        out[f"{phi:g}"] = {
            "seeds": seeds,
            "g": [_ms(g[:, k]) for k in range(len(RIG_KTS))],
            "g_na": [_ms(g_na[:, k]) for k in range(len(RIG_KTS))],
            "g_per_seed": g.tolist(), "g_na_per_seed": g_na.tolist(),
            "roots": [float(x["root"]) for x in r],
            "root": _ms([float(x["root"]) for x in r]),
            "modes_vs_solve": _worst(np.abs(modes / check - 1)),
            "step_vs_solve": _worst(np.abs(step / check - 1)),
            "step_over_model": _worst(np.abs(step - check) / np.maximum(err, 1e-300)),
            # the packings whose finite strain broke their contact network (rigidity_piece)
            "step_failed": {str(s): str(x["step_failed"]) for s, x in zip(seeds, r)
                            if str(x.get("step_failed", ""))},
        }
    return out


def sign_change(table):
    """Fig. 6 per phi: the mean root of G_NA against the paper's 2.0 in combined s.e."""
    rows = {}
    for phi, t in table.items():
        m = t["root"]
        if m["count"] < 2:
            rows[phi] = {**m, "distance": None, "label": "not comparable",
                         "why": f"{m['count']} root(s) in [1e-2, 10^1.5]"}
            continue
        d = math.fabs(m["mean"] - PAPER_ROOT) / math.hypot(m["se"], PAPER_ROOT_ERR)
        rows[phi] = {**m, "distance": d, "label": "agrees" if d <= 2 else "disagrees",
                     "why": f"{d:.1f} combined s.e. from 2.0; agree if <= 2"}
    return rows


#: "G_NA ~= 0" read off a figure: within this fraction of the figure's range of G_NA (the
#: per-phi means over every plotted kT/kN and phi): half a plotted marker (a 3 mm marker on an
#: 8 cm axis is ~4 % of it), so a point this close to zero sits on the zero line
FIG_ZERO = 0.02


def sign_figure(table):
    """Fig. 6 read as the figure shows it (G_NA against phi at fixed kT/kN, no root): per phi,
    the sign of the mean G_NA at each kT/kN > 0 of the grid against the paper's (negative
    below 2.0, positive above; 'as the paper' or 'opposite' beyond 2 s.e., else 'unresolved')
    and |mean G_NA(2.0)| over the figure's range.  Agrees at a phi when no sign is opposite
    and |G_NA(2.0)| <= FIG_ZERO of the range."""
    kts = [k for k in RIG_KTS if k > 0]
    means = [t["g_na"][RIG_KTS.index(k)]["mean"] for t in table.values() for k in kts]
    means = [m for m in means if m is not None]
    if not means:
        return {"range": None, "tol": FIG_ZERO, "rows": {}}
    span = max(means) - min(means)
    rows = {}
    for phi, t in table.items():
        signs, short = {}, []
        for k in kts:
            m = t["g_na"][RIG_KTS.index(k)]
            if k == PAPER_ROOT:
                continue
            if m["count"] < 2:
                short.append(k)
                continue
            want = 1.0 if k > PAPER_ROOT else -1.0
            signs[f"{k:g}"] = ("as the paper" if want * m["mean"] > 2 * m["se"] else
                               "opposite" if want * m["mean"] < -2 * m["se"] else "unresolved")
        at2 = t["g_na"][RIG_KTS.index(PAPER_ROOT)]
        if short or at2["count"] < 2:
            rows[phi] = {"signs": signs, "at_2": at2["mean"], "at_2_over_range": None,
                         "label": "not comparable", "why": "fewer than 2 packings"}
            continue
        frac = abs(at2["mean"]) / span if span > 0 else float("inf")
        bad = sorted((k for k, v in signs.items() if v == "opposite"), key=float)
        ok = not bad and frac <= FIG_ZERO
        rows[phi] = {"signs": signs, "at_2": at2["mean"], "at_2_se": at2["se"],
                     "at_2_over_range": frac, "label": "agrees" if ok else "disagrees",
                     "why": (f"|G_NA(2.0)| = {frac:.1%} of the figure's range (agree if <= "
                             f"{FIG_ZERO:.0%})" + (f"; opposite sign at kT/kN = "
                                                   f"{', '.join(bad)}" if bad else ""))}
    return {"range": span, "tol": FIG_ZERO, "rows": rows}


def proportional_test(table, kt):
    """'G is not proportional to phi - phi_c for a large kT/kN': a straight line through the
    per-phi means of G (weights 1/se^2), its chi^2 and p (small p: not a straight line)."""
    k = RIG_KTS.index(kt)
    phis = [float(p) for p in table if table[p]["g"][k]["count"] > 1]
    if len(phis) < 3:
        return {"kt": kt, "p": None, "label": "not comparable", "why": "fewer than 3 phi"}
    y = np.array([table[f"{p:g}"]["g"][k]["mean"] for p in phis])
    se = np.array([max(table[f"{p:g}"]["g"][k]["se"], 1e-15) for p in phis])
    coef = np.polyfit(phis, y, 1, w=1 / se)
    chi2 = float((((y - np.polyval(coef, phis)) / se) ** 2).sum())
    dof = len(phis) - 2
    p = float(scipy.stats.chi2.sf(chi2, dof))
    return {"kt": kt, "chi2": chi2, "dof": dof, "p": p, "phi_c": float(-coef[1] / coef[0]),
            "label": "linear" if p >= 0.05 else "not linear"}


def factorisation_test(table, kt, n):
    """Footnote 2: G(phi, kT) = G_0(phi) G(kT) would make G(phi, kT)/G_0(phi) the same at
    every phi.  Kruskal-Wallis test of the per-packing ratios across phi (small p: no
    factorisation): rank-based, because near jamming G_0 is close to zero and its ratios are
    heavy-tailed (phi = 0.84, N = 1,024: G_0 = 9e-5 +- 1e-4), which a one-way ANOVA's normal
    groups do not allow.  ``n``: the size of ``table``'s packings (the paper names none)."""
    k, k0 = RIG_KTS.index(kt), RIG_KTS.index(0.0)
    groups = [np.array(t["g_per_seed"])[:, k] / np.array(t["g_per_seed"])[:, k0]
              for t in table.values() if len(t["seeds"]) > 1]
    if len(groups) < 2:
        return {"kt": kt, "n": n, "p": None, "label": "not comparable"}
    h, p = scipy.stats.kruskal(*groups)
    return {"kt": kt, "n": n, "H": float(h), "p": float(p),
            "ratios": [float(np.median(g)) for g in groups],
            "label": "not factorised" if p < 0.05 else "consistent with a factorisation"}


def limit_table(table):
    """Fig. 5: |G(kT)/G(0) - 1| per phi for kT/kN <= 1e-4 (mean over packings)."""
    k0 = RIG_KTS.index(0.0)
    out = {}
    for phi, t in table.items():
        g = np.array(t["g_per_seed"])
        out[phi] = {f"{kt:g}": _ms(g[:, RIG_KTS.index(kt)] / g[:, k0] - 1)
                    for kt in (1e-8, 1e-6, 1e-4, 1e-2)}
    return out


#: Fig. 5's "G depends on k_T/k_N only little for k_T/k_N <= 1e-4", read strictly: a change
#: of G(1e-4)/G(0) - 1 within 1 %
LIMIT_STRICT = 0.01


def limit_readings(limit, table):
    """Fig. 5's statement judged per phi under two readings, with the sample error: strict
    (|G(1e-4)/G(0) - 1| within :data:`LIMIT_STRICT`) and as the figure shows it (G against
    kT/kN on logarithmic axes, the paper's only evidence, "see Fig. 5": within half a plotted
    marker, :data:`FIG_ZERO` of the G axis's range in decades, that range spanned by the
    per-phi mean G at kT/kN > 0 of ``table``).  At a phi a reading 'disagrees' when
    |mean| - 2 s.e. exceeds its bound, 'agrees' when |mean| + 2 s.e. is within it, else
    'unresolved' (always with one packing: no spread).  A reading agrees when every phi
    agrees, disagrees when one phi disagrees, else is undecided."""
    means = [m["mean"] for t in table.values()
             for k, m in zip(RIG_KTS, t["g"]) if k > 0 and m["mean"] and m["mean"] > 0]
    decades = float(np.log10(max(means) / min(means))) if len(means) > 1 else None
    bounds = {"strict": LIMIT_STRICT,
              "figure": None if decades is None else float(10.0 ** (FIG_ZERO * decades) - 1)}
    out = {"decades": decades, "readings": {}}
    for name, bound in bounds.items():
        rows = {}
        for phi, r in limit.items():
            m = r["0.0001"]
            if bound is None or m["mean"] is None or m["count"] < 2:
                rows[phi] = "unresolved"
                continue
            lo, hi = abs(m["mean"]) - 2 * m["se"], abs(m["mean"]) + 2 * m["se"]
            rows[phi] = ("disagrees" if lo > bound else "agrees" if hi <= bound
                         else "unresolved")
        said = list(rows.values())
        label = ("disagrees" if "disagrees" in said else
                 "agrees" if said and all(s == "agrees" for s in said) else "undecided")
        out["readings"][name] = {"bound": bound, "rows": rows, "label": label}
    return out


def band_measures(omega, psi_r, n_lowest):
    """How the rotational and translational bands sit: the fraction of mixed modes
    (0.1 < psi^R < 0.9), the ratio of the lowest translation-dominated frequency to the highest
    rotation-dominated one (> 1: a gap), the modes of one kind inside the other's range, and
    the rotation purity of the ``n_lowest`` lowest modes (the earlier rule: >= 0.99
    separated, <= 1/2 merged)."""
    rot, tr = omega[psi_r > 0.5], omega[psi_r <= 0.5]
    mixed = float(((psi_r > MIXED[0]) & (psi_r < MIXED[1])).mean())
    if rot.size == 0 or tr.size == 0:
        return {"mixed": mixed, "gap": None, "inside": 0, "purity": None, "band": "merged"}
    gap = float(tr.min() / rot.max())
    inside = int((tr < rot.max()).sum() + (rot > tr.min()).sum())
    purity = float(psi_r[np.argsort(omega)][:n_lowest].mean())
    band = ("separated" if gap > 1 else "merged" if purity <= 0.5 else "partial overlap")
    return {"mixed": mixed, "gap": gap, "inside": inside, "purity": purity, "band": band}


def coupled_near(omega, psi_r, target, factor=1.5):
    """Modes within a factor ``factor`` of ``target`` whose character is shared
    (0.25 < psi^R < 0.75): the paper's Fig. 7 b2 (kT/kN = 1e-4, omega t0 = 1.3e-2)."""
    near = (omega > target / factor) & (omega < target * factor)
    return {"near": int(near.sum()), "coupled": int((near & (psi_r > 0.25)
                                                     & (psi_r < 0.75)).sum())}


PAPER_BANDS = {1e-10: "separated", 1e-8: "separated", 1e-6: "partial overlap",
               1e-4: "partial overlap", 1e-2: "partial overlap", 1.0: "merged", 10.0: "merged"}


def band_table(got, n, phis, kts, with_rattlers):
    """Per phi and kT: each packing's band measures and the class most packings take."""
    out = {}
    piece = "rattlers" if with_rattlers else "dos"
    for phi in phis:
        for kt in kts:
            seeds = [s for s in _used(got, n, phi) if (n, phi, s, f"{piece}{kt:g}") in got]
            if not seeds:
                continue
            rows = []
            for s in seeds:
                x = got[(n, phi, s, f"{piece}{kt:g}")]
                n_low = int(json.loads(got[(n, phi, s, "ensemble")]["row"])["backbone"])
                rows.append(band_measures(x["omega"], x["psi_r"], n_low))
            classes = [r["band"] for r in rows]
            major = max(set(classes), key=classes.count)
            om = np.concatenate([got[(n, phi, s, f"{piece}{kt:g}")]["omega"] for s in seeds])
            pr = np.concatenate([got[(n, phi, s, f"{piece}{kt:g}")]["psi_r"] for s in seeds])
            gap = dos_gap(om, pr)
            dos_band = "merged" if major == "merged" else (
                "separated" if gap else "partial overlap")
            out[f"{phi:g}/{kt:g}"] = {
                "phi": phi, "kt": kt, "samples": len(rows), "band": major,
                "dos_band": dos_band, "dos_gap": gap,
                "classes": {c: classes.count(c) for c in sorted(set(classes))},
                "mixed": _ms([r["mixed"] for r in rows]),
                "gap": _ms([r["gap"] if r["gap"] is not None else np.nan for r in rows]),
                "inside": _ms([r["inside"] for r in rows]),
                "paper": PAPER_BANDS.get(kt)}
    return out


def dos_gap(omega, psi_r, edges=EDGES):
    """The DOS read as the paper's figures show it (pooled over the samples, ten log bins per
    decade): is there an empty bin between the rotational band's peak (the fullest bin of
    the rotation-dominated modes) and the median of the translation-dominated modes?  Unlike
    the strict rule of :func:`band_measures` (the extreme modes of each kind), a few modes far
    below or above their band, rattlers' say, do not close such a gap."""
    rot, tr = omega[psi_r > 0.5], omega[psi_r <= 0.5]
    if rot.size == 0 or tr.size == 0:
        return False
    c_rot, _ = np.histogram(rot, bins=edges)
    peak = int(np.argmax(c_rot))
    top = int(np.searchsorted(edges, np.median(tr))) - 1
    counts, _ = np.histogram(omega, bins=edges)
    return bool(top > peak + 1 and (counts[peak + 1:top] == 0).any())


def _pooled(got, n, phi, piece, key):
    seeds = [s for s in _used(got, n, phi) if (n, phi, s, piece) in got]
    return (np.concatenate([got[(n, phi, s, piece)][key] for s in seeds]) if seeds
            else np.zeros(0)), seeds


def rotational_table(got, n):
    """Fig. 10: per kT/kN <= 1e-2 at phi = 0.90, the peak and median of the rotation-dominated
    modes over sqrt(kT/kN) per packing (mean, sd), and the scaling collapse of
    omega_R D(omega / omega_R) on 0.1 < omega/omega_R < 10 against kT/kN = 1e-8, with the
    split-half distance of the 1e-8 samples as its noise."""
    rows, curves, noise = {}, {}, None
    x_edges = np.geomspace(0.1, 10.0, 21)
    for kt in [k for k in DOS_KTS if k <= 1e-2]:
        seeds = [s for s in _used(got, n, FIG_PHI) if (n, FIG_PHI, s, f"dos{kt:g}") in got]
        if not seeds:
            continue
        peaks, medians, hs = [], [], []
        for s in seeds:
            x = got[(n, FIG_PHI, s, f"dos{kt:g}")]
            pk, md = rotational_peak(x["omega"], x["psi_r"])
            peaks.append(pk / math.sqrt(kt))
            medians.append(md / math.sqrt(kt))
            n_total = int(json.loads(got[(n, FIG_PHI, s, "ensemble")]["row"])["n"])
            counts, _ = np.histogram(x["omega"] / math.sqrt(kt), bins=x_edges)
            hs.append(counts / (3 * n_total * np.diff(x_edges)))   # omega_R D(omega)
        rows[f"{kt:g}"] = {"peak": _ms(peaks), "median": _ms(medians), "samples": len(seeds)}
        curves[kt] = np.array(hs)
    if 1e-8 in curves:
        ref = curves[1e-8]
        dlx = np.diff(np.log(x_edges))

        def dist(a, b):
            return float(np.abs(a - b) @ dlx / (0.5 * (a + b) @ dlx))
        if len(ref) >= 2:
            half = len(ref) // 2
            noise = dist(ref[:half].mean(0), ref[half:].mean(0))
        for kt, h in curves.items():
            rows[f"{kt:g}"]["collapse"] = dist(h.mean(0), ref.mean(0))
    return {"rows": rows, "noise": noise}


def rattler_table(got, n):
    """Fig. 14: the modes carried by rattlers (weight on rattlers > 1/2), their p N and
    omega / sqrt(kT/kN), pooled over the phi = 0.90 samples."""
    out = {}
    for kt in RATTLER_KTS:
        om, seeds = _pooled(got, n, FIG_PHI, f"rattlers{kt:g}", "omega")
        if not seeds:
            continue
        w, _ = _pooled(got, n, FIG_PHI, f"rattlers{kt:g}", "w_rattler")
        p, _ = _pooled(got, n, FIG_PHI, f"rattlers{kt:g}", "p")
        r = w > 0.5
        # why a packing has no such mode: each free rattler (no contact) has three exact zero
        # modes, dropped with the two translations; the zero modes beyond the translations
        # against 3 x the rattlers says whether every rattler is free
        rattlers = sum(json.loads(got[(n, FIG_PHI, s, "ensemble")]["row"])["rattlers"]
                       for s in seeds)
        zeros = sum(3 * n - 2 - got[(n, FIG_PHI, s, f"rattlers{kt:g}")]["omega"].size
                    for s in seeds)
        out[f"{kt:g}"] = {"modes": int(r.sum()), "samples": len(seeds),
                          "rattlers": int(rattlers), "zero_modes": int(zeros),
                          "pN_median": float(np.median(p[r] * n)) if r.any() else None,
                          "omega_median": float(np.median(om[r]) / math.sqrt(kt))
                          if r.any() else None}
    return out


def phi_table(got, n, phis):
    """Fig. 16 at kT/kN = 1e-8: per packing the rotational peak over sqrt(kT/kN) and the low
    end of the translational band (5th percentile of the translation-dominated frequencies);
    Spearman's rho of each against phi (one-sided p: the paper's 'shifts to lower frequency
    as the density approaches jamming' is rho > 0)."""
    pts = []
    for phi in phis:
        for s in _used(got, n, phi):
            if (n, phi, s, "dos1e-08") in got:
                x = got[(n, phi, s, "dos1e-08")]
                pk, _ = rotational_peak(x["omega"], x["psi_r"])
                tr = x["omega"][x["psi_r"] <= 0.5]
                pts.append((phi, pk / 1e-4, float(np.percentile(tr, 5))))
    out = {"points": len(pts), "phis": sorted({p[0] for p in pts})}
    if len({p[0] for p in pts}) < 3:
        return {**out, "label": "not comparable", "why": "fewer than 3 phi"}
    arr = np.array(pts)
    for key, col in (("rot_peak", 1), ("trans_low", 2)):
        rho, p2 = scipy.stats.spearmanr(arr[:, 0], arr[:, col])
        out[key] = {"rho": float(rho), "p": float(p2 / 2 if rho > 0 else 1 - p2 / 2),
                    "by_phi": {f"{ph:g}": _ms(arr[arr[:, 0] == ph, col]) for ph in out["phis"]}}
    ok = all(out[k]["rho"] > 0 and out[k]["p"] < 0.05 for k in ("rot_peak", "trans_low"))
    out["label"] = "agrees" if ok else "disagrees"
    return out


def _kind(piece):
    return piece.rstrip("0123456789.e-") if piece[-1].isdigit() else piece


def cost_table(got, pending):
    """Per N and kind of piece (ensemble: make and judge a packing; rigidity; dos and rattlers:
    one spectrum each): the measured seconds (mean, count), and the projected seconds of the
    pieces still owed, each at the mean of its kind (None where no piece of that N and kind
    was measured yet).  An ensemble piece whose packing came from the cache (judged again,
    not made) prices nothing: the compression is most of what an owed one costs."""
    out = {}
    for (n, _, _, piece), x in got.items():
        if piece == "ensemble" and json.loads(x["row"]).get("from_cache"):
            continue
        if "stamp_seconds" in x:
            out.setdefault(f"{n}/{_kind(piece)}", []).append(float(x["stamp_seconds"]))
    rows = {k: {"mean": float(np.mean(v)), "count": len(v)} for k, v in out.items()}
    owed, unknown = 0.0, 0
    for n, _, _, piece in pending:
        r = rows.get(f"{n}/{_kind(piece)}")
        if r is None:
            unknown += 1
        else:
            owed += r["mean"]
    return {"rows": rows, "pending": len(pending), "projected_seconds": owed,
            "unpriced": unknown}


def analyse(got, tier):
    """Every table and verdict of the report from the computed pieces."""
    t = TIERS[tier]
    n4, nd, phis = t["fig4_n"], t["dos_n"], t["phis"]
    rows, summ = ensemble_table(got)
    fig4 = rigidity_tables(got, n4, phis)
    fig5 = rigidity_tables(got, nd, phis)
    big = max(RIG_KTS)
    bands = {"backbone": band_table(got, n4, phis, MIX_KTS, False),
             "rattlers": band_table(got, n4, phis, MIX_KTS, True),
             "backbone_fig": band_table(got, nd, [FIG_PHI], DOS_KTS, False),
             "rattlers_fig": band_table(got, nd, [FIG_PHI], RATTLER_KTS, True)}
    b2 = {}
    for s in _used(got, nd, FIG_PHI):
        if (nd, FIG_PHI, s, "dos0.0001") in got:
            x = got[(nd, FIG_PHI, s, "dos0.0001")]
            c = coupled_near(x["omega"], x["psi_r"], 1.3e-2)
            b2 = {k: b2.get(k, 0) + v for k, v in c.items()}
    limit = limit_table(fig5)
    return {
        "tier": tier, "sizes": {"fig4": n4, "dos": nd}, "phis": list(phis),
        "ensemble": {"rule": ishima_ensemble.RULE, "summary": summ,
                     "excluded": [r for r in rows if not r["use"]]},
        "rig_kts": list(RIG_KTS), "check_kts": list(CHECK_KTS),
        "fig4": fig4, "fig5": fig5,
        "sign_change": sign_change(fig4), "sign_figure": sign_figure(fig4),
        "linear": [proportional_test(fig4, k) for k in (0.0, 1.0, big)],
        "factorisation": [factorisation_test(tab, k, n) for n, tab in
                          ((n4, fig4),) + (((nd, fig5),) if nd != n4 else ())
                          for k in (1e-4, 1.0, big)],
        "limit": limit, "limit_readings": limit_readings(limit, fig5),
        "bands": bands, "fig7_b2": b2,
        "fig10": rotational_table(got, nd),
        "fig14": rattler_table(got, nd),
        "fig16": phi_table(got, nd, phis),
    }


# ------------------------------------------------------------------ report

def _f(m, fmt=".3g"):
    if m is None or m.get("mean") is None:
        return "-"
    return f"{format(m['mean'], fmt)} +- {m['sd']:.1g} ({m['count']})"


def report(doc, done, total, stamp):
    L = [f"<!-- generated by validation/ishima_paper.py ({stamp}) -->", "",
         "# Ishima et al. " + {"paper": "at the paper's scale",
                               "paper1024": "at N = 1,024 (the paper's N for Figs. 4 and 6)"}
         .get(doc["tier"], "by the paper's pipeline at a small N (quick tier)"),
         "", f"Figs. 4, 6 at N = {doc['sizes']['fig4']}; Figs. 5, 7-10, 14, 16 at N = "
         f"{doc['sizes']['dos']}; phi = {', '.join(f'{p:g}' for p in doc['phis'])}. "
         f"Pieces done: {done} of {total}"
         + (" (complete)." if done == total else " (the scale reached: see the counts)."),
         "", "Values: mean +- sample sd (packings).  " + doc["ensemble"]["rule"] + ".", "",
         "## Ensemble", "", "| N | phi | samples | used | excluded |", "|---|---|---|---|---|"]
    for c in doc["ensemble"]["summary"].values():
        ex = "; ".join(f"seed {e['seed']}: {e['reason']}" for e in c["excluded"]) or "-"
        ex = ex.replace("|", "\\|")          # a reason's |F| would split the table cell
        L.append(f"| {c['n']} | {c['phi']:g} | {c['samples']} | {c['used']} | {ex} |")
    kts = doc["rig_kts"]
    for fig, key in (("Fig. 4 (G) and Fig. 6 (G_NA)", "fig4"), ("Fig. 5 (G)", "fig5")):
        L += ["", f"## {fig}, N = {doc['sizes'][key[:4] if key == 'fig4' else 'dos']}", "",
              "| phi | " + " | ".join(f"G ({k:g})" for k in kts) + " |",
              "|---|" + "---|" * len(kts)]
        for phi, t in doc[key].items():
            L.append(f"| {phi} | " + " | ".join(_f(m) for m in t["g"]) + " |")
        if key == "fig4":
            L += ["", "| phi | " + " | ".join(f"G_NA ({k:g})" for k in kts)
                  + " | root of G_NA | mode sum / solve - 1 | step / solve - 1 | "
                  "step error / model |", "|---|" + "---|" * (len(kts) + 4)]
            failed = []
            for phi, t in doc[key].items():
                mv, sv, so = t["modes_vs_solve"], t["step_vs_solve"], t["step_over_model"]
                L.append(f"| {phi} | " + " | ".join(_f(m, "+.3g") for m in t["g_na"])
                         + f" | {_f(t['root'])} | {'-' if mv is None else f'{mv:.1e}'} | "
                         f"{'-' if sv is None else f'{sv:.1e}'} | "
                         f"{'-' if so is None else f'{so:.2f}'} |")
                failed += [f"phi = {phi} seed {seed}: {why}"
                           for seed, why in t.get("step_failed", {}).items()]
            if failed:
                L += ["", "Step strain not done (the finite strain broke the contact network; "
                      "the solve stands): " + "; ".join(failed) + "."]
    L += ["", "## The sign change of G_NA (Fig. 6): the paper's kT/kN = 2.0 per phi", "",
          "| phi | root, mean +- sd (packings) | s.e. | verdict |", "|---|---|---|---|"]
    for phi, r in doc["sign_change"].items():
        L.append(f"| {phi} | {_f(r)} | {'-' if r['se'] is None else format(r['se'], '.2g')} | "
                 f"**{r['label']}** ({r['why']}) |")
    sf = doc["sign_figure"]
    if sf["rows"]:
        signed = [f"{k:g}" for k in RIG_KTS if k > 0 and k != PAPER_ROOT]
        L += ["", "The same statement read as Fig. 6 shows it (G_NA against phi at fixed "
              "kT/kN, no root): the sign of the mean G_NA at each kT/kN of the grid (ok: the "
              "paper's, - below 2.0 and + above, beyond 2 s.e.; !: opposite; ?: unresolved) and |G_NA(2.0)| "
              f"against the figure's range of G_NA ({sf['range']:.3g}); ~= 0 if within "
              f"{sf['tol']:.0%} of it (half a plotted marker).", "",
              "| phi | signs at kT/kN = " + ", ".join(signed) + " | G_NA(2.0) | of the range "
              "| verdict |", "|---|---|---|---|---|"]
        mark = {"as the paper": "ok", "opposite": "!", "unresolved": "?"}
        for phi, r in sf["rows"].items():
            frac = r["at_2_over_range"]
            L.append(f"| {phi} | " + " ".join(mark[r["signs"][k]] if k in r["signs"] else "-"
                                               for k in signed)
                     + f" | {'-' if r['at_2'] is None else format(r['at_2'], '+.3g')} | "
                     f"{'-' if frac is None else format(frac, '.1%')} | **{r['label']}** "
                     f"({r['why'].replace('|', chr(92) + '|')}) |")   # |x| would split the cell
    # (column, the field it needs, its text): "-" where a test had too few groups to run
    for key, title, cols in (
            ("linear", "G against phi: a straight line (G proportional to phi - phi_c)?",
             [("chi^2 / dof", "chi2", lambda r: f"{r['chi2']:.2f} / {r['dof']}"),
              ("p", "p", lambda r: f"{r['p']:.2g}"),
              ("phi_c of the line", "phi_c", lambda r: f"{r['phi_c']:.4f}")]),
            ("factorisation", "Factorisation G(phi, kT) = G_0(phi) G(kT) (footnote 2)",
             [("N", "n", lambda r: f"{r['n']}"),
              ("G / G_0 per phi (median over packings)", "ratios",
               lambda r: ", ".join(f"{x:.3g}" for x in r["ratios"])),
              ("Kruskal-Wallis H", "H", lambda r: f"{r['H']:.3g}"),
              ("p", "p", lambda r: f"{r['p']:.2g}")])):
        L += ["", f"## {title}", "",
              "| kT/kN | " + " | ".join(c for c, _, _ in cols) + " | reading |",
              "|---" * (len(cols) + 2) + "|"]
        for r in doc[key]:
            L.append(f"| {r['kt']:g} | "
                     + " | ".join("-" if r.get(f) is None else text(r) for _, f, text in cols)
                     + f" | {r['label']} |")
    lr = doc["limit_readings"]["readings"]
    heads = [f"{name} (within {'-' if x['bound'] is None else format(x['bound'], '.1%')}, "
             "2 s.e.)" for name, x in lr.items()]
    L += ["", "## G(kT)/G(0) - 1 for small kT/kN (Fig. 5)", "",
          "| phi | 1e-8 | 1e-6 | 1e-4 | 1e-2 | " + " | ".join(heads) + " |",
          "|---" * (5 + len(heads)) + "|"]
    for phi, r in doc["limit"].items():
        L.append(f"| {phi} | " + " | ".join(_f(m, "+.2g") for m in r.values()) + " | "
                 + " | ".join(x["rows"][phi] for x in lr.values()) + " |")
    L += ["", "Fig. 5 by reading (G(1e-4)/G(0) - 1 per phi): "
          + "; ".join(f"{name}: {x['label']}" for name, x in lr.items())
          + ". The figure reading's bound is half a plotted marker on the G axis, "
          f"{doc['limit_readings']['decades'] or 0:.2f} decades wide (the per-phi means of G "
          "at kT/kN > 0)."]
    for name, key in (("backbone (rattlers removed)", "backbone"),
                      ("whole packing (rattlers kept)", "rattlers"),
                      (f"backbone at N = {doc['sizes']['dos']}, phi = 0.90", "backbone_fig"),
                      (f"with rattlers at N = {doc['sizes']['dos']}, phi = 0.90",
                       "rattlers_fig")):
        L += ["", f"## Bands (Figs. 7-9), {name}", "",
              "| phi | kT/kN | paper | DOS read as a figure | strict: class (counts) | "
              "mixed fraction | gap ratio | modes inside the other band |",
              "|---|---|---|---|---|---|---|---|"]
        for r in doc["bands"][key].values():
            L.append(f"| {r['phi']:g} | {r['kt']:g} | {r['paper']} | {r['dos_band']} | "
                     f"{r['band']} {r['classes']} | {_f(r['mixed'], '.2g')} | {_f(r['gap'])} | "
                     f"{_f(r['inside'], '.3g')} |")
        L += ["", "Strict: separated when the lowest translation-dominated frequency exceeds "
              "the highest rotation-dominated one (per packing; the class most take). DOS read "
              "as a figure: separated when an empty bin lies between the rotational peak and "
              "the translational median (pooled samples, 10 bins per decade); merged in both "
              "when the N' lowest modes have mean psi^R <= 1/2."]
    b2 = doc["fig7_b2"]
    L += ["", f"Fig. 7 b2 (kT/kN = 1e-4, omega t0 = 1.3e-2 +- a factor 1.5): "
          f"{b2.get('coupled', 0)} of {b2.get('near', 0)} modes there have 0.25 < psi^R < 0.75.",
          "", "## Rotational band (Fig. 10), phi = 0.90", "",
          "| kT/kN | peak / sqrt(kT/kN) | median / sqrt(kT/kN) | collapse distance to 1e-8 |",
          "|---|---|---|---|"]
    for kt, r in doc["fig10"]["rows"].items():
        c = r.get("collapse")
        L.append(f"| {kt} | {_f(r['peak'])} | {_f(r['median'])} | "
                 f"{'-' if c is None else f'{c:.3f}'} |")
    nz = doc["fig10"]["noise"]
    L += ["", f"Split-half distance of the 1e-8 samples (the noise): "
          f"{'-' if nz is None else f'{nz:.3f}'}.", "",
          "## Rattler modes (Fig. 14), phi = 0.90", "",
          "| kT/kN | rattlers (packings) | zero modes beyond the translations | modes on "
          "rattlers | median p N | median omega / sqrt(kT/kN) |",
          "|---|---|---|---|---|---|"]
    for kt, r in doc["fig14"].items():
        L.append(f"| {kt} | {r['rattlers']} ({r['samples']}) | {r['zero_modes']} | "
                 f"{r['modes']} | " + " | ".join(
            "-" if r[k] is None else f"{r[k]:.3g}" for k in ("pN_median", "omega_median"))
            + " |")
    f16 = doc["fig16"]
    c = doc["cost"]
    L += ["", "## Cost (one core, this machine)", "", "| N | piece | seconds (mean) | pieces |",
          "|---|---|---|---|"]
    for k, r in sorted(c["rows"].items(), key=lambda kv: (int(kv[0].split("/")[0]), kv[0])):
        n, kind = k.split("/")
        L.append(f"| {n} | {kind} | {r['mean']:.3g} | {r['count']} |")
    L += ["", f"Pieces still owed: {c['pending']}; projected {c['projected_seconds'] / 3600:.2g} h "
          f"at the measured means" + (f", {c['unpriced']} of a kind not measured yet"
                                      if c["unpriced"] else "") + "."]
    L += ["", "## DOS against phi (Fig. 16), kT/kN = 1e-8", ""]
    if "rot_peak" in f16:
        L += ["| phi | rotational peak / sqrt(kT/kN) | translational low end (5th pct) |",
              "|---|---|---|"]
        for ph in f16["rot_peak"]["by_phi"]:
            L.append(f"| {ph} | {_f(f16['rot_peak']['by_phi'][ph])} | "
                     f"{_f(f16['trans_low']['by_phi'][ph])} |")
        L += ["", f"Spearman against phi: rotational peak rho {f16['rot_peak']['rho']:+.2f} "
              f"(p {f16['rot_peak']['p']:.2g}), translational low end rho "
              f"{f16['trans_low']['rho']:+.2f} (p {f16['trans_low']['p']:.2g}): "
              f"**{f16['label']}**."]
    else:
        L.append(f"**{f16['label']}** ({f16['why']}).")
    return "\n".join(L) + "\n"


def figure(doc, got, path):
    """Figs. 4, 5, 6, 8, 10 and 16 in one sheet, with units."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(2, 3, figsize=(15, 8.5))
    kts = doc["rig_kts"]
    for k in (0.0, 1e-4, 1.0, 10.0):
        i = kts.index(k)
        phis = [float(p) for p in doc["fig4"]]
        for a, key in ((ax[0, 0], "g"), (ax[0, 2], "g_na")):
            m = [doc["fig4"][f"{p:g}"][key][i] for p in phis]
            a.errorbar(phis, [x["mean"] for x in m], [x["sd"] for x in m], marker="o",
                       capsize=2, label=f"kT/kN = {k:g}")
    for phi, t in doc["fig5"].items():
        x = [k for k in kts if k > 0]
        ax[0, 1].plot(x, [t["g"][kts.index(k)]["mean"] for k in x], "o-", label=f"phi {phi}")
    ax[0, 0].set(xlabel="phi", ylabel="G  [k_N d^(1/2)]", title="Fig. 4")
    ax[0, 1].set(xscale="log", xlabel="kT/kN", ylabel="G  [k_N d^(1/2)]", title="Fig. 5")
    ax[0, 2].set(xlabel="phi", ylabel="G_NA  [k_N d^(1/2)]", title="Fig. 6")
    ax[0, 2].axhline(0, color="k", lw=0.5)
    nd = doc["sizes"]["dos"]
    edges = EDGES
    centres = np.sqrt(edges[1:] * edges[:-1])
    for kt in DOS_KTS:
        om, seeds = _pooled(got, nd, FIG_PHI, f"dos{kt:g}", "omega")
        if not seeds:
            continue
        pr, _ = _pooled(got, nd, FIG_PHI, f"dos{kt:g}", "psi_r")
        idx = np.digitize(om, edges) - 1
        ok = (idx >= 0) & (idx < len(centres))
        cnt = np.bincount(idx[ok], minlength=len(centres))
        mean = np.bincount(idx[ok], weights=pr[ok], minlength=len(centres))
        sel = cnt > 0
        ax[1, 0].plot(centres[sel], mean[sel] / cnt[sel], ".-", label=f"{kt:g}")
        if kt <= 1e-2:
            x = np.geomspace(0.1, 10, 21)
            c, _ = np.histogram(om / math.sqrt(kt), bins=x)
            ax[1, 1].loglog(np.sqrt(x[1:] * x[:-1]), c / (3 * nd * len(seeds) * np.diff(x)),
                            ".-", label=f"{kt:g}")
    ax[1, 0].set(xscale="log", xlabel="omega t0  [1]", ylabel="psi^R (bin mean)  [1]",
                 title="Fig. 8 (psi^T = 1 - psi^R), phi = 0.90")
    ax[1, 1].set(xlabel="omega / omega_R  [1]", ylabel="omega_R D(omega)  [1]",
                 title="Fig. 10, phi = 0.90")
    for phi in doc["phis"]:
        om, seeds = _pooled(got, nd, phi, "dos1e-08", "omega")
        if seeds:
            c, _ = np.histogram(om, bins=edges)
            d = c / (3 * nd * len(seeds) * np.diff(edges))
            ax[1, 2].loglog(centres[c > 0], d[c > 0], ".-", label=f"phi {phi:g}")
    ax[1, 2].set(xlabel="omega t0  [1]", ylabel="D(omega) t0  [1]",
                 title="Fig. 16, kT/kN = 1e-8")
    for a in ax.flat:
        if a.lines:
            a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def run(tier="quick", out=HERE, max_hours=None, log=print, figures=True, compute_missing=True):
    """Compute (or read) the tier and write its report; returns the document."""
    use_store(tier)
    got, units, pending = run_pieces(tier, max_hours, log, compute_missing)
    doc = analyse(got, tier)
    done, total = len(got), len(got) + len(pending)
    stamp = f"{datetime.now(timezone.utc):%Y-%m-%d %H:%M} UTC, {platform.node()}"
    doc.update({"pieces_done": done, "pieces_total": total, "units": units,
                "cost": cost_table(got, pending)})
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    stem = out / f"ishima_paper_{tier}"
    stem.with_suffix(".json").write_text(json.dumps({**doc, "stamp": stamp}, indent=1,
                                                    default=float) + "\n")
    stem.with_suffix(".md").write_text(report(doc, done, total, stamp))
    if figures:
        figure(doc, got, stem.with_suffix(".png"))
    return doc


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tier", choices=sorted(TIERS), default="quick")
    ap.add_argument("--out", type=Path, default=HERE)
    ap.add_argument("--max-hours", type=float, default=None,
                    help="stop after the piece that crosses this many hours and report what "
                         "is done (the cache keeps it; run again to go on)")
    ap.add_argument("--plan", action="store_true", help="list the pieces and stop")
    ap.add_argument("--report-only", action="store_true",
                    help="compute nothing: the report of the pieces the cache holds (fresh)")
    a = ap.parse_args(argv)
    if a.max_hours is not None and not a.max_hours > 0:
        ap.error("--max-hours must be positive")
    if a.plan:
        use_store(a.tier)
        todo = plan(a.tier)
        have = sum(_path(*t).exists() for t in todo)
        print(f"{len(todo)} pieces, {have} cached (fresh or not) in {CACHE}")
        return 0
    run(a.tier, a.out, a.max_hours, log=lambda m: print(m, flush=True),
        compute_missing=not a.report_only)
    print(f"wrote {a.out / f'ishima_paper_{a.tier}.md'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
