"""Claims of section packing: Ishima et al., rigidity and density of states of frictional disks.

Three kinds of job.  ``seconds``: the stored N = 256 packing
(``validation/regression/packing256.npz``, made by ``make_packing(256, 0.90,
seed=0)``), deterministic on any CPU up to round-off, recomputed by CI.
``minutes`` and ``hours``: the validation scripts (``packing_rigidity.py``,
``packing_dos.py``, ``packing_knobs.py``) on packings made afresh by seeded FIRE
(the script cache ``validation/.packings/`` is bypassed: each job makes its
packings with the code it is fingerprinted with).  Seeded FIRE is bit-identical
on one machine; another CPU may reach other packings (a chaotic compression),
so the checks of those jobs allow the sample-to-sample spread.
"""

import math
import sys
from pathlib import Path

from .core import Claim, Result, Verdict, bound_verdict, floor_verdict, sigma_verdict
from . import _packing_paper

HEADING = 'Frictional packings (Ishima et al.)'
INTRO = ('Paper: Ishima, Saitoh, Otsuki, Hayakawa (2023). Units d = 1, k_N = 1, m = 1 '
         '(G in k_N d^(1/2), omega in 1/t0). Packings from `make_packing` defaults '
         '(dphi = 1e-3, f_tol_compress = 1e-6, f_tol = 1e-14), phi = 0.90 unless stated, '
         'rattlers (Z <= 2) removed; step strain dgamma = 1e-6. The seconds tier works on the '
         'stored packing `validation/regression/packing256.npz` (N = 256, phi = 0.90, seed 0); '
         'the scripts make their packings afresh (seeded FIRE). Tables with every sample: '
         '`validation/packing_rigidity.md` (quick tier), `validation/packing_rigidity_medium.md`, '
         '`validation/packing_dos_{quick,medium,full}.md`, `validation/packing_knobs.md`.')

#: RESULTS.md's tables of this section (claims.render): the paper's figures at its scale
#: first, then the same figures at the paper's smaller N, then the checks on small packings
PARTS = [
    ("At the paper's scale",
     "The paper's statements judged on its ensemble: N = 1,024 x 5 packings (Figs. 4, 6) and "
     "N = 4,096 x 10 (Figs. 5, 7-10, 14, 16) per phi = 0.83-0.90, by `python "
     "validation/ishima_paper.py --tier paper` (one command, resumable from the committed "
     "store; `docs/reference/packing.md`). A packing that is unjammed, not force-balanced, "
     "not converged or unstable (a negative G or eigenvalue beyond the zero modes) enters no "
     "mean; each row counts the packings used.",
     lambda c: c.name.startswith("packing.paper_") and not c.name.endswith("_n1024")),
    ("The N = 4,096 figures at the paper's smaller N",
     "Figs. 7-10 and 16 again on the N = 1,024 ensemble (5 packings per phi): how they move "
     "with size. The reproduction is the table above.",
     lambda c: c.name.startswith("packing.paper_")),
    ("Checks of our routes and knobs on small packings (not reproductions)",
     "These rows check the machinery on one to eight packings of N = 256-4,096, most at "
     "phi = 0.90: G by mode sum, solve and step strain, the printed J~, the DOS routes, the "
     "effective Hessian, the knobs dphi and the force thresholds. Where a row quotes the "
     "paper, it applies the paper's statement to those few small packings as a fast check "
     "of the code, not as its reproduction, and it may part from the paper-scale row: the "
     "reproduction of each figure is the row above that judges it (Fig. 4: "
     "`packing.paper_g_phi`; Fig. 5: `packing.paper_g_little`, `packing.paper_g_little_figure`; "
     "Fig. 6: `packing.paper_sign_change`, `packing.paper_sign_figure`; Figs. 7-9: "
     "`packing.paper_bands`; Fig. 10: `packing.paper_rot_prefactor`; Fig. 14: "
     "`packing.paper_rattlers`; Fig. 16: `packing.paper_dos_phi`).",
     lambda c: True),
]

ROOT = Path(__file__).resolve().parents[2]
STORED = "validation/regression/packing256.npz"
EPS = 2.0 ** -52
KTS = (1e-4, 1.0, 10.0)              # the acceptance values of kT/kN
LIMIT_KTS = (1e-10, 1e-8, 1e-6, 1e-4)
DOS_KTS = (1e-10, 1e-8, 1e-6, 1e-4, 1e-2, 1.0, 10.0)
PEAK_BIN = 10 ** 0.1                 # rotational_peak's bin: 0.1 decade


# ------------------------------------------------------------------ helpers

def _stored_backbone():
    from fricstab.scenes.packing import Packing
    from fricstab.scenes.packing_friction import backbone
    return backbone(Packing.load(ROOT / STORED))


def _ishima(bb, kt):
    from fricstab.scenes.packing_friction import frictional, material, with_kt
    fr = frictional(bb, with_kt(material("ishima"), kt))
    return fr.system, fr.state


def _script(name):
    """Import a validation script with a fresh packing cache (packings made by this code)."""
    import importlib
    import tempfile
    sys.path.insert(0, str(ROOT / "validation"))
    import _packings
    _packings.CACHE = Path(tempfile.mkdtemp(prefix="fricstab-packings-"))
    return importlib.import_module(name)


def _rel(paths):
    return tuple(str(Path(p).resolve().relative_to(ROOT)) for p in paths)


def _pct(x):
    return f"{100 * x:+.2g} %"


def _range(lo, hi, fmt=".2f"):
    a, b = format(lo, fmt), format(hi, fmt)
    return a if a == b else f"{a}-{b}"


def _spread(rows, key):
    """kT/kN -> sample standard deviation of ``key`` over the seeds (0 with one seed)."""
    by = {}
    for r in rows:
        by.setdefault(r["kt"], []).append(r[key])
    out = {}
    for kt, v in by.items():
        m = sum(v) / len(v)
        out[kt] = math.sqrt(sum((x - m) ** 2 for x in v) / (len(v) - 1)) if len(v) > 1 else 0.0
    return out


# ------------------------------------------------------------------ seconds: stored packing

def stored_g():
    """G three ways on the stored packing at kT/kN = 1e-4, 1, 10, and G towards kT -> 0."""
    import numpy as np
    from fricstab.analysis.dos import spectrum
    from fricstab.analysis.rigidity import rigidity
    from fricstab.protocols.stepstrain import step_strain
    bb = _stored_backbone()
    rows = {}
    for kt in KTS:
        system, state = _ishima(bb, kt)
        r = rigidity(system, state, modes=True)
        s = step_strain(system, state, dgamma=1e-6)
        w = np.sort(np.abs(spectrum(r.jacobian, vectors=False).eigenvalues))
        rows[f"{kt:g}"] = {"g_a": r.g_a, "g_na": r.g_na_solve, "g": r.g, "g_modes": r.g_modes,
                           "cond": float(w[-1] / w[2]), "g_step": float(s.g),
                           "step_error": float(s.error)}
    g0 = rigidity(*_ishima(bb, 0.0)).g
    limit = [rigidity(*_ishima(bb, kt)).g for kt in LIMIT_KTS]
    return Result({"backbone": bb.n, "rows": rows, "g0": g0, "limit_kts": list(LIMIT_KTS),
                   "limit_g": limit})


def zero_modes():
    """max |J e_x|, |J e_y|, |e_x^T J|, |e_y^T J| over max |J|, stored packing."""
    import numpy as np
    from fricstab.engine.jacobian import jacobian
    bb = _stored_backbone()
    right, left = {}, {}
    for kt in KTS:
        system, state = _ishima(bb, kt)
        _, k = jacobian(system, state, free_only=False)
        k = k.toarray()
        scale = np.abs(k).max()
        r = l_ = 0.0
        for axis in (0, 1):
            e = np.zeros(k.shape[0])
            e[axis::system.dof] = 1.0
            r = max(r, float(np.abs(k @ e).max() / scale))
            l_ = max(l_, float(np.abs(e @ k).max() / scale))
        right[f"{kt:g}"], left[f"{kt:g}"] = r, l_
    return Result({"right": right, "left": left})


def biorthonormal():
    """Dense eig with left and right vectors: max |L^H R - I| and G_NA by that mode sum."""
    from fricstab.analysis.rigidity import rigidity
    bb = _stored_backbone()
    out = {}
    for kt in KTS:
        r = rigidity(*_ishima(bb, kt), modes=True, route="dense")
        out[f"{kt:g}"] = {"biortho": r.checks["modes_biorthonormality"],
                          "modes_vs_solve": abs(r.g_modes / r.g - 1)}
    return Result({"rows": out})


def _band_class(om, psi_r, n_rot):
    """Mean psi^R over the ``n_rot`` lowest modes (1: the rotations form a band of their
    own below the translations; 1/3 when rotation is spread evenly over the 3N' dof) and
    its class: separated (>= 0.99), merged (<= 1/2), partial."""
    import numpy as np
    purity = float(psi_r[np.argsort(om)][:n_rot].mean())
    return ("separated" if purity >= 0.99 else "merged" if purity <= 0.5 else "partial"), purity


def stored_dos():
    """Rotational band of the stored packing: peak and median frequency of the
    rotation-dominated modes, their number and the band classes, kT/kN = 1e-10..10."""
    import numpy as np
    from fricstab.analysis.dos import participation, rotational_peak, spectrum
    from fricstab.analysis.rigidity import linear_response
    bb = _stored_backbone()
    rows = []
    for kt in DOS_KTS:
        sp = spectrum(linear_response(*_ishima(bb, kt)).jacobian)
        _, psi_r, _ = participation(sp.right, 3)
        keep = np.argsort(np.abs(sp.eigenvalues.real))[2:]       # drop the two translations
        om, pr = sp.omega[keep], psi_r[keep]
        peak, median = rotational_peak(om, pr)
        cls, purity = _band_class(om, pr, bb.n)
        rows.append({"kt": kt, "peak": peak, "median": median,
                     "rotation_dominated": int((pr > 0.5).sum()), "band": cls,
                     "purity": purity})
    fit = [r for r in rows if r["kt"] <= 1e-2]
    lk = np.log10([r["kt"] for r in fit])
    a_peak = float(np.polyfit(lk, np.log10([r["peak"] for r in fit]), 1)[0])
    a_median = float(np.polyfit(lk, np.log10([r["median"] for r in fit]), 1)[0])
    return Result({"backbone": bb.n, "rows": rows, "exponent_peak": a_peak,
                   "exponent_median": a_median, "decades": float(lk[-1] - lk[0])})


# checks and verdicts of the stored-packing claims

def _solve_bound(row):
    return 64 * EPS * row["cond"]


def _check_solve(old, new):
    """G (solve) and G (modes) within 64 eps cond(J) of the record; modes vs solve within it."""
    for kt, a in old["rows"].items():
        b = new["rows"][kt]
        tol = _solve_bound(a) * abs(a["g"])
        for key in ("g", "g_modes", "g_a"):
            if abs(b[key] - a[key]) > tol:
                return False, f"kT/kN = {kt}: {key} {a[key]:.10g} -> {b[key]:.10g} (> {tol:.1e})"
        if abs(b["g_modes"] / b["g"] - 1) > _solve_bound(b):
            return False, f"kT/kN = {kt}: mode sum vs solve beyond 64 eps cond(J)"
    return True, "G within 64 eps cond(J) at every kT/kN"


def _check_step(old, new):
    """g (step strain) within its error model of the record, and of G."""
    for kt, a in old["rows"].items():
        b = new["rows"][kt]
        if abs(b["g_step"] - a["g_step"]) > a["step_error"] + b["step_error"]:
            return False, f"kT/kN = {kt}: g {a['g_step']:.10g} -> {b['g_step']:.10g}"
        if abs(b["g_step"] - b["g"]) > b["step_error"]:
            return False, f"kT/kN = {kt}: |g - G| beyond the error model"
    return True, "g within the error models at every kT/kN"


def _limit_terms(v):
    import numpy as np
    d = np.array(v["limit_g"]) - v["g0"]
    slope = float(np.polyfit(np.log10(v["limit_kts"]), np.log10(np.abs(d)), 1)[0])
    return d / v["g0"], slope


def _check_limit(old, new):
    (da, sa), (db, sb) = _limit_terms(old), _limit_terms(new)
    worst = max(abs(y / x - 1) for x, y in zip(da, db))
    ok = worst <= 1e-3 and abs(sb - sa) <= 1e-3
    return ok, f"G/G(0) - 1 moved by {worst:.1e} of itself; slope {sa:.5f} -> {sb:.5f}"


def _limit_verdict(v):
    d, slope = _limit_terms(v)
    ok = abs(slope - 1) <= 0.05 and all(x > 0 for x in d)
    return Verdict("agrees" if ok else "disagrees",
                   f"slope of log(G - G(0)) against log kT/kN {slope:.3f}; agree if 1 +- 0.05 "
                   "(G - G(0) linear in kT: continuous and smooth)")


def _little_verdict(v):
    d = v["limit_g"][v["limit_kts"].index(1e-4)] / v["g0"] - 1
    return Verdict("agrees" if abs(d) <= 0.01 else "disagrees",
                   f"|G(1e-4)/G(0) - 1| = {abs(d):.2g}; agree if <= 1 %")


def _check_dos(old, new):
    for a, b in zip(old["rows"], new["rows"]):
        if not (a["peak"] / PEAK_BIN * 0.999 <= b["peak"] <= a["peak"] * PEAK_BIN * 1.001):
            return False, f"kT/kN = {a['kt']:g}: peak {a['peak']:.4g} -> {b['peak']:.4g}"
        if abs(b["median"] / a["median"] - 1) > 0.02:
            return False, f"kT/kN = {a['kt']:g}: median {a['median']:.6g} -> {b['median']:.6g}"
    for key in ("exponent_peak", "exponent_median"):
        if abs(new[key] - old[key]) > 0.02:
            return False, f"{key} {old[key]:.4f} -> {new[key]:.4f}"
    return True, (f"exponents {old['exponent_peak']:.4f} -> {new['exponent_peak']:.4f} (peak), "
                  f"{old['exponent_median']:.4f} -> {new['exponent_median']:.4f} (median)")


def _prefactors(v):
    fit = [r for r in v["rows"] if r["kt"] <= 1e-2]
    cp = [r["peak"] / math.sqrt(r["kt"]) for r in fit]
    cm = [r["median"] / math.sqrt(r["kt"]) for r in fit]
    return min(cp), max(cp), min(cm), max(cm)


def _exponent_verdict(v):
    dp, dm = abs(v["exponent_peak"] - 0.5), abs(v["exponent_median"] - 0.5)
    return Verdict("agrees" if max(dp, dm) <= 0.02 else "disagrees",
                   f"|a - 1/2| = {dp:.1e} (peak), {dm:.1e} (median); agree if <= 0.02 "
                   "(the peak's 0.1-decade bin over the fitted decades)")


def _prefactor_verdict(v):
    lo, hi, mlo, mhi = _prefactors(v)
    far = max(abs(math.log10(x)) for x in (lo, hi))
    return Verdict("agrees" if far <= math.log10(2) else "disagrees",
                   f"peak / sqrt(kT/kN) {lo:.3g}-{hi:.3g}, a factor {10 ** far:.2g} from 1; "
                   "agree if within a factor 2 (the paper's 'around')")


BAND_PAPER = {1e-10: "separated", 1e-8: "separated", 1.0: "merged", 10.0: "merged"}


def _band_verdict(v):
    ours = {r["kt"]: r["band"] for r in v["rows"]}
    bad = [f"{k:g}" for k in BAND_PAPER if ours.get(k) != BAND_PAPER[k]]
    first = next((f"{r['kt']:g}" for r in v["rows"] if r["band"] != "separated"), "none")
    return Verdict("disagrees" if bad else "agrees",
                   ("separated at kT/kN = 1e-10, 1e-8 and merged at 1, 10, as the paper states"
                    if not bad else f"differs from the paper at kT/kN = {', '.join(bad)}")
                   + "; rule: mean psi^R of the N' lowest modes >= 0.99 separated, <= 1/2 "
                   f"merged. Not judged: the paper's partial overlap from 1e-6 (N = 4096); here "
                   f"the first kT/kN not separated is {first}")


def _check_bands(old, new):
    for a, b in zip(old["rows"], new["rows"]):
        if a["band"] != b["band"] or abs(a["rotation_dominated"] - b["rotation_dominated"]) > 2 \
                or abs(a["purity"] - b["purity"]) > 1e-3:
            return False, f"kT/kN = {a['kt']:g}: {a['band']} {a['rotation_dominated']} -> " \
                          f"{b['band']} {b['rotation_dominated']}"
    return True, "band classes equal, counts within 2 modes"


def _check_tiny(bound_of):
    """Check for round-off-sized values: the new ones stay below the stated bound."""
    def check(old, new):
        worst, bound = bound_of(new)
        return worst <= bound, f"{worst:.1e} <= {bound:.0e}" if worst <= bound else \
            f"{worst:.1e} > {bound:.0e}"
    return check


def _zero_worst(v):
    return max(max(v["right"].values()), max(v["left"].values())), 32 * EPS


def _biortho_worst(v):
    return max(r["biortho"] for r in v["rows"].values()), 1e-10


# ------------------------------------------------------------------ minutes: scripts

def rigidity_quick():
    """``packing_rigidity.py --tier quick``: N = 256, 3 seeds at phi = 0.90 (three routes,
    printed J~, dgamma) and 3 seeds at phi = 0.85-0.90 (sweeps, roots of G_NA)."""
    mod = _script("packing_rigidity")
    values, paths = mod.run("quick")
    return Result(values, seeds=tuple(values["sweeps"]["seeds"]), outputs=_rel(paths))


def rigidity_medium():
    """``packing_rigidity.py --tier medium``: adds N = 1024 (2 seeds), a fourth seed to the
    sweeps, and G at N = 4096 by sparse solve."""
    mod = _script("packing_rigidity")
    values, paths = mod.run("medium")
    return Result(values, seeds=tuple(values["sweeps"]["seeds"]), outputs=_rel(paths))


def dos_quick():
    """``packing_dos.py --tier quick``: N = 256, seeds 0-2."""
    mod = _script("packing_dos")
    values, paths = mod.run("quick")
    return Result(values, seeds=tuple(values["seeds"]), outputs=_rel(paths))


def dos_medium():
    """``packing_dos.py --tier medium``: N = 1024, seeds 0-1."""
    mod = _script("packing_dos")
    values, paths = mod.run("medium")
    return Result(values, seeds=tuple(values["seeds"]), outputs=_rel(paths))


def dos_full():
    """``packing_dos.py --tier full``: N = 4096, seed 0; with the stored N = 256 packing's
    rotational band for the size dependence."""
    mod = _script("packing_dos")
    values, paths = mod.run("full")
    values["stored_256"] = stored_dos().values
    return Result(values, seeds=tuple(values["seeds"]), outputs=_rel(paths))


def knobs():
    """``packing_knobs.py``: dphi (8 seeds each) and the force thresholds (seed 0)."""
    mod = _script("packing_knobs")
    values, paths = mod.run(False)
    return Result(values, seeds=tuple(values["seeds"]), outputs=_rel(paths))


# checks and verdicts of the script claims

def _rows(v, n="256"):
    return v["agreement"][n]


def _route_ratios(v, ns=("256",)):
    """Worst |G_modes/G - 1| / (64 eps cond J) and |g - G| / error model over samples."""
    m = s = 0.0
    for n in ns:
        for r in _rows(v, n):
            m = max(m, abs(r["g_modes"] / r["g"] - 1) / (64 * EPS * r["cond"]))
            s = max(s, abs(r["g_step"] - r["g"]) / r["step_error"])
    return m, s


def _routes_show(v, ns=("256",)):
    rows = [r for n in ns for r in _rows(v, n)]
    dm = max(abs(r["g_modes"] / r["g"] - 1) for r in rows)
    ds = max(abs(r["g_step"] / r["g"] - 1) for r in rows)
    m, s = _route_ratios(v, ns)
    return (f"mode sum vs solve <= {dm:.1e} ({m:.1e} of 64 eps cond J); step strain vs solve "
            f"<= {ds:.1e} ({s:.2f} of its error model), {len(rows)} (seed, kT/kN) cases")


def _routes_verdict(ns):
    def verdict(v):
        m, s = _route_ratios(v, ns)
        return bound_verdict(max(m, s), 1.0, "worst disagreement / its error model")
    return verdict


def _check_samples(key_sets, ns=("256",)):
    """Per sample, G within 3 sample standard deviations (a packing from another CPU's FIRE
    may differ), and the routes still within their error models."""
    def check(old, new):
        for n in ns:
            sd = _spread(_rows(old, n), "g")
            for a, b in zip(_rows(old, n), _rows(new, n)):
                for key in key_sets:
                    if abs(b[key] - a[key]) > 3 * sd[a["kt"]] + 64 * EPS * a["cond"] * abs(a[key]):
                        return False, (f"N = {n}, seed {a['seed']}, kT/kN = {a['kt']:g}: {key} "
                                       f"{a[key]:.6g} -> {b[key]:.6g} (> 3 sample sd)")
        m, s = _route_ratios(new, ns)
        if max(m, s) > 1:
            return False, f"routes beyond their error models ({m:.2g}, {s:.2g})"
        return True, "every sample within 3 sample sd; routes within their error models"
    return check


def _jtilde(v):
    rows = _rows(v)
    rel = [r["g_flipped"] / r["g"] - 1 for r in rows]
    models = [abs(r["g_flipped"] - r["g_step"]) / r["step_error"] for r in rows]
    return rel, models


def _jtilde_verdict(v):
    rel, models = _jtilde(v)
    worst = max(models)
    return Verdict("disagrees" if worst > 100 else "agrees",
                   f"|G(J~) - g_step| up to {worst:.2g} step-strain error models (at least "
                   f"{min(models):.2g}); disagree if > 100 in one case, which supports the "
                   "erratum J~ = J (validation/errata.md)")


def _check_jtilde(old, new):
    sd = _spread(_rows(old), "g")
    for a, b in zip(_rows(old), _rows(new)):
        if abs(b["g_flipped"] - a["g_flipped"]) > 3 * sd[a["kt"]] + 1e-12:
            return False, f"seed {a['seed']}, kT/kN = {a['kt']:g}: G(J~) moved"
    return _jtilde_verdict(new).label == "disagrees", "G(J~) within 3 sample sd"


def _dgamma_verdict(v):
    worst = max(abs(x) for r in v["dgamma"] for x in r["rel"])
    changed = sum(r["changed"] for r in v["dgamma"])
    return Verdict("agrees" if worst <= 1e-2 and changed == 0 else "disagrees",
                   f"max |g/G - 1| = {worst:.1e} over dgamma = 1e-6..1e-4, {changed} contacts "
                   "changed; agree if <= 1 % (issue) with no contact change")


def _check_dgamma(old, new):
    for a, b in zip(old["dgamma"], new["dgamma"]):
        for dg, x, y, ea, eb in zip((1e-6, 1e-5, 1e-4), a["rel"], b["rel"], a["error"], b["error"]):
            if abs(y - x) > ea + eb:
                return False, f"kT/kN = {a['kt']:g}, dgamma {dg:g}: {x:+.2e} -> {y:+.2e}"
    return True, "each g/G - 1 within the two error models"


def _roots(v):
    return {phi: [x for x in d["roots"] if x == x] for phi, d in v["sweeps"]["phi"].items()}


def _signs(v):
    """Packings with G_NA < 0 at every kT/kN <= 1 and > 0 at 10, and the total."""
    kts = v["sweeps"]["kts"]
    ok = n = 0
    for d in v["sweeps"]["phi"].values():
        for gna in d["g_na"]:
            n += 1
            ok += all(g < 0 for k, g in zip(kts, gna) if k <= 1) and gna[kts.index(10.0)] > 0
    return ok, n


def _gna_show(v):
    r = _roots(v)
    allr = sorted(x for xs in r.values() for x in xs)
    med = allr[len(allr) // 2] if len(allr) % 2 else (allr[len(allr) // 2 - 1]
                                                      + allr[len(allr) // 2]) / 2
    ok, n = _signs(v)
    return (f"G_NA < 0 at kT/kN <= 1 and > 0 at 10 in {ok} of {n} packings; root at "
            f"kT/kN = {allr[0]:.3g}-{allr[-1]:.3g}, median {med:.3g}; per phi: "
            + "; ".join(f"{phi}: {min(xs):.3g}-{max(xs):.3g}" for phi, xs in r.items()))


def _gna_verdict(v):
    r = _roots(v)
    allr = [x for xs in r.values() for x in xs]
    ok, n = _signs(v)
    inside = min(allr) <= 2.0 <= max(allr)
    outside = [phi for phi, xs in r.items() if not min(xs) <= 2.0 <= max(xs)]
    return Verdict("agrees" if inside and ok == n else "disagrees",
                   f"2 {'inside' if inside else 'outside'} the roots' range over all packings, "
                   f"signs as stated in {ok} of {n}; agree if both (the paper states one "
                   "threshold for phi = 0.83-0.90)"
                   + (f"; per phi, 2 lies outside the range at phi = {', '.join(outside)}"
                      if outside else ""))


def _check_roots(old, new):
    a = [x for xs in _roots(old).values() for x in xs]
    b = [x for xs in _roots(new).values() for x in xs]
    ma, mb = sum(a) / len(a), sum(b) / len(b)
    se = math.sqrt(sum((x - ma) ** 2 for x in a) / (len(a) - 1) / len(a))
    return abs(mb - ma) <= 3 * se, f"mean root {ma:.4g} -> {mb:.4g} (3 s.e. = {3 * se:.2g})"


def _phi_stats(v, kt):
    """phi -> (mean, standard error) of G at ``kt`` over the seeds."""
    k = v["sweeps"]["kts"].index(kt)
    out = {}
    for phi, d in v["sweeps"]["phi"].items():
        g = [row[k] for row in d["g"]]
        m = sum(g) / len(g)
        out[phi] = (m, math.sqrt(sum((x - m) ** 2 for x in g) / (len(g) - 1) / len(g)))
    return out


def _phi_show(v):
    parts = []
    for phi in v["sweeps"]["phi"]:
        parts.append(f"phi = {phi}: " + " / ".join(
            f"{_phi_stats(v, kt)[phi][0]:.3g} +- {_phi_stats(v, kt)[phi][1]:.1g}"
            for kt in (0.0, 1.0, 10.0)))
    k0 = v["sweeps"]["kts"].index(0.0)
    neg = [f"phi = {phi}, seed {seed} ({row[k0]:.2g})" for phi, d in v["sweeps"]["phi"].items()
           for seed, row in zip(v["sweeps"]["seeds"], d["g"]) if row[k0] < 0]
    return ("; ".join(parts) + f" (frictionless / kT/kN = 1 / 10, mean +- s.e. over "
            f"{len(v['sweeps']['seeds'])} seeds); frictionless G < 0 (force-balanced but "
            "unstable to shear) in " + (", ".join(neg) if neg else "no packing"))


def _check_phi(old, new):
    for kt in (0.0, 1.0, 10.0):
        a, b = _phi_stats(old, kt), _phi_stats(new, kt)
        for phi in a:
            s = math.hypot(a[phi][1], b[phi][1])
            if abs(a[phi][0] - b[phi][0]) > 3 * s + 1e-12:
                return False, f"phi {phi}, kT/kN {kt:g}: {a[phi][0]:.4g} -> {b[phi][0]:.4g}"
    return True, "every mean within 3 combined s.e."


def _routes_dos(v):
    return {r["kt"]: r for r in v["routes"]}


def _route_exact_verdict(v):
    worst = max(r["l1"] for r in v["routes"])
    return bound_verdict(worst, 0.0, "L1 distance of the two DOS histograms")


def _speedup_verdict(v):
    return floor_verdict(min(r["speedup"] for r in v["routes"]), 3.0, "eig / eigh wall time")


def _check_speedup(old, new):
    lo = min(r["speedup"] for r in new["routes"])
    return lo >= 3.0, f"speed-up {min(r['speedup'] for r in old['routes']):.1f}x -> {lo:.1f}x"


def _heff_verdict(v):
    worst = max(r["rel"] for r in v["effective_hessian"])
    return Verdict("agrees" if worst <= 1e-2 else "disagrees",
                   f"largest relative eigenvalue difference {worst:.1e}; agree if <= 1e-2 "
                   "(a DOS on the paper's 0.12-decade bins cannot tell such spectra apart)")


def _check_heff(old, new):
    for a, b in zip(old["effective_hessian"], new["effective_hessian"]):
        if not (a["rel"] / 10 <= b["rel"] <= a["rel"] * 10):
            return False, f"kT/kN = {a['kt']:g}: {a['rel']:.1e} -> {b['rel']:.1e}"
    return True, "within a factor 10 (the histories, ~dgamma, set the size)"


def _rot_table(v):
    return {r["kt"]: r for r in v["rotational"]}


def _script_exponent_verdict(v):
    d = abs(v["exponent_peak"] - 0.5)
    dm = abs(v["exponent_median"] - 0.5)
    return Verdict("agrees" if max(d, dm) <= 0.02 else "disagrees",
                   f"|a - 1/2| = {d:.1e} (peak), {dm:.1e} (median); agree if <= 0.02")


def _script_rot_show(v):
    fit = [r for r in v["rotational"] if r["kt"] <= 1e-2]
    cp = [r["peak"] / math.sqrt(r["kt"]) for r in fit]
    cm = [r["median"] / math.sqrt(r["kt"]) for r in fit]
    t = _rot_table(v)
    return (f"exponent {v['exponent_peak']:.4f} (peak), {v['exponent_median']:.4f} (median) "
            f"over {v['decades']:.0f} decades; peak at {_range(min(cp), max(cp), '.3f')} and "
            f"median at {_range(min(cm), max(cm), '.3f')} sqrt(kT/kN)/t0; rotation-dominated modes "
            f"{t[1e-8]['rotation_dominated']} of {sum(v['backbone'])} rotational dof at "
            f"kT/kN = 1e-8, {t[1.0]['rotation_dominated']} at 1")


def _check_script_rot(old, new):
    for key in ("exponent_peak", "exponent_median"):
        if abs(new[key] - old[key]) > 0.02:
            return False, f"{key} {old[key]:.4f} -> {new[key]:.4f}"
    return True, f"exponent {old['exponent_peak']:.4f} -> {new['exponent_peak']:.4f}"


def _size_verdict(v):
    big = [r["peak"] / math.sqrt(r["kt"]) for r in v["rotational"] if r["kt"] <= 1e-2]
    small = [r["peak"] / math.sqrt(r["kt"]) for r in v["stored_256"]["rows"] if r["kt"] <= 1e-2]
    d = abs(sum(big) / len(big) / (sum(small) / len(small)) - 1)
    return Verdict("agrees" if d <= 0.03 else "disagrees",
                   f"peak / sqrt(kT/kN) at N = 4096 vs N = 256 differs by {d:.1%}; agree if "
                   "<= 3 % (little size dependence)")


def _n4096_verdict(v):
    return bound_verdict(max(v["n4096"]["seconds"]), 60.0, "seconds per kT/kN (issue: < 60 s)")


def _dphi_pair(v, kt="1"):
    d = v["dphi"]
    return (d["0.001"][f"mean_{kt}"], d["0.001"][f"se_{kt}"],
            d["0.0001"][f"mean_{kt}"], d["0.0001"][f"se_{kt}"])


def _dphi_show(v):
    return "; ".join(f"dphi = {k}: G(1) {d['mean_1']:.4f} +- {d['se_1']:.4f}, G(1e-4) "
                     f"{d['mean_1e-4']:.4f} +- {d['se_1e-4']:.4f}" for k, d in v["dphi"].items()) \
        + f" (mean +- s.e., {len(v['seeds'])} seeds)"


def _check_dphi(old, new):
    for k, a in old["dphi"].items():
        b = new["dphi"][k]
        for kt in ("1", "1e-4"):
            s = math.hypot(a[f"se_{kt}"], b[f"se_{kt}"])
            if abs(a[f"mean_{kt}"] - b[f"mean_{kt}"]) > 3 * s:
                return False, f"dphi {k}, kT/kN {kt}: mean moved beyond 3 combined s.e."
    return True, "every mean within 3 combined s.e."


def _threshold_groups(v):
    """The (f_tol, f_tol_compress) pairs grouped by the packing they end in (G at both
    kT/kN equal to 1e-6), largest group first."""
    groups = []
    for r in v["thresholds"]:
        for grp in groups:
            g = grp[0]
            if abs(r["rel_1e-4"] - g["rel_1e-4"]) < 1e-6 and abs(r["rel_1"] - g["rel_1"]) < 1e-6:
                grp.append(r)
                break
        else:
            groups.append([r])
    return sorted(groups, key=len, reverse=True)


def _thresholds_show(v):
    groups = _threshold_groups(v)
    main = groups[0][0]
    pair = lambda r: f"({r['f_tol']:g}, {r['f_tol_compress']:g})"  # noqa: E731
    rel = lambda r, k: (1 + r[k]) / (1 + main[k]) - 1  # noqa: E731
    return (f"{len(groups[0])} of {len(v['thresholds'])} (f_tol, f_tol_compress) pairs end in "
            "one packing (G equal to 1e-6): " + ", ".join(pair(r) for r in groups[0])
            + "; the others, each another packing, against it: " + "; ".join(
                ", ".join(pair(r) for r in grp) + f": G(1e-4) {_pct(rel(grp[0], 'rel_1e-4'))}, "
                f"G(1) {_pct(rel(grp[0], 'rel_1'))}" for grp in groups[1:]))


def _check_thresholds(old, new):
    key = lambda v: sorted(sorted((r["f_tol"], r["f_tol_compress"]) for r in g)  # noqa: E731
                           for g in _threshold_groups(v))
    same = key(old) == key(new)
    return same, "the same pairs share a packing" if same else \
        "another grouping of the pairs (a chaotic compression path)"


# ------------------------------------------------------------------ the claims

_CMD = "python validation/reproduce.py --claim "
_STORED_T = "stored N = 256 packing (phi = 0.90, seed 0)"
_FIG4 = '"quantitative agreement" between theory (Eq. 39) and simulation (Eq. 16) (Fig. 4)'
_SAMPLES = ("bit-identical on one machine (seeded FIRE); another CPU's FIRE may reach other "
            "packings, so each sample's G may move by 3 sample standard deviations; the "
            "routes must still agree within their error models")

def _sign_and_phi(suffix, sign_title, sign_tolerance, phi_title, tier, script_tier, compute):
    """The two claims one run of packing_rigidity.py gives at a tier: the sign change of
    G_NA (Fig. 6) and G against phi (Fig. 4)."""
    command = f"python validation/packing_rigidity.py --tier {script_tier}"
    job = f"packing.rigidity_{script_tier}"
    return (
        Claim(f"packing.gna_sign{suffix}", "packing", sign_title, tier, command, compute,
              show=_gna_show, tolerance=sign_tolerance, check=_check_roots,
              paper='"G_NA is positive for k_T/k_N > 2.0, G_NA ~= 0 at k_T/k_N = 2.0, and G_NA '
                    'is negative for k_T/k_N < 2.0"',
              verdict=_gna_verdict, job=job),
        Claim(f"packing.g_vs_phi{suffix}", "packing", phi_title, tier, command, compute,
              show=_phi_show, tolerance="each mean within 3 combined standard errors",
              check=_check_phi, paper="Fig. 4 (values not tabulated; N = 1024)", job=job))


CLAIMS = [
    # ---- seconds: the stored packing
    Claim("packing.g_modes_vs_solve", "packing",
          f"G_NA by the mode sum (Eq. 44) vs the sparse solve, {_STORED_T}, kT/kN = 1e-4, 1, 10",
          "seconds", _CMD + "packing.g_modes_vs_solve", stored_g,
          show=lambda v: " / ".join(f"{abs(r['g_modes'] / r['g'] - 1):.1e}"
                                    for r in v["rows"].values())
          + " (|G_modes/G - 1|; 64 eps cond J = " + " / ".join(
              f"{_solve_bound(r):.0e}" for r in v["rows"].values()) + "); G = " + " / ".join(
              f"{r['g']:.6g}" for r in v["rows"].values()),
          tolerance="G within 64 eps cond(J) of the record (the LU solve and the "
                    "eigendecomposition are backward stable: another CPU's round-off moves G "
                    "by eps cond(J); 64 covers the constants and |G_NA|/G <= 4)",
          check=_check_solve, paper=_FIG4,
          verdict=lambda v: bound_verdict(max(abs(r["g_modes"] / r["g"] - 1) / _solve_bound(r)
                                              for r in v["rows"].values()), 1.0,
                                          "|G_modes/G - 1| / (64 eps cond J)"),
          inputs=(STORED,), job="packing.stored_g",
          texts={"g": lambda v: " / ".join(f"{r['g']:.4f}" for r in v["rows"].values())}),
    Claim("packing.g_step_vs_solve", "packing",
          f"G by step strain (Eq. 16, dgamma = 1e-6) vs the sparse solve, {_STORED_T}, "
          "kT/kN = 1e-4, 1, 10",
          "seconds", _CMD + "packing.g_step_vs_solve", stored_g,
          show=lambda v: " / ".join(f"{r['g_step'] / r['g'] - 1:+.1e}" for r in v["rows"].values())
          + " (g/G - 1; error model " + " / ".join(f"{r['step_error'] / abs(r['g']):.1e}"
                                                   for r in v["rows"].values()) + ")",
          tolerance="g within the sum of the two error models of the record (its round-off "
                    "term 2 eps_sigma/dgamma bounds what another CPU changes; the truncation "
                    "term |g(+dgamma) - g(-dgamma)| is measured each time)",
          check=_check_step, paper=_FIG4,
          verdict=lambda v: bound_verdict(max(abs(r["g_step"] - r["g"]) / r["step_error"]
                                              for r in v["rows"].values()), 1.0,
                                          "|g - G| / error model"),
          inputs=(STORED,), job="packing.stored_g"),
    Claim("packing.frictionless_limit", "packing",
          f"G(kT/kN) -> G(0) (frictionless Hessian) as kT -> 0 (Fig. 5), {_STORED_T}",
          "seconds", _CMD + "packing.frictionless_limit", stored_g,
          show=lambda v: ", ".join(f"{d:+.2e} at {k:g}" for k, d in zip(
              v["limit_kts"], _limit_terms(v)[0])) + f" (G/G(0) - 1, G(0) = {v['g0']:.6g}); "
          f"slope {_limit_terms(v)[1]:.4f} per decade",
          tolerance="each G/G(0) - 1 within 1e-3 of itself and the slope within 1e-3: the "
                    "differences are 6e-9 to 6e-3 of G, far above the solve's round-off",
          check=_check_limit,
          paper='"G smoothly approaches the frictionless value in the limit k_T -> 0"',
          verdict=_limit_verdict, inputs=(STORED,), job="packing.stored_g"),
    Claim("packing.g_little_below_1e-4", "packing",
          f"G depends little on kT/kN for kT/kN <= 1e-4 (Fig. 5), {_STORED_T}",
          "seconds", _CMD + "packing.g_little_below_1e-4", stored_g,
          show=lambda v: f"G(1e-4)/G(0) - 1 = {_pct(_limit_terms(v)[0][-1])}",
          tolerance="as packing.frictionless_limit (the same job)", check=_check_limit,
          paper='"G depends on k_T/k_N only little for k_T/k_N <= 1.0 x 10^-4"',
          verdict=_little_verdict, inputs=(STORED,), job="packing.stored_g"),
    Claim("packing.zero_modes", "packing",
          f"translations are zero modes of J, right and left: max |J e|, |e^T J| over max |J|, "
          f"e = e_x, e_y, {_STORED_T}, kT/kN = 1e-4, 1, 10",
          "seconds", _CMD + "packing.zero_modes", zero_modes,
          show=lambda v: f"right {min(v['right'].values()):.1e}-{max(v['right'].values()):.1e}, "
          f"left {min(v['left'].values()):.1e}-{max(v['left'].values()):.1e}",
          tolerance="any value up to 32 eps (round-off: each entry sums O(Z) terms of size "
                    "max |J|, in an order another CPU may change)",
          check=_check_tiny(_zero_worst),
          paper="sum_n J_nm = 0 over the x rows and over the y rows (Eqs. C4-C5)",
          verdict=lambda v: bound_verdict(_zero_worst(v)[0] / EPS, 32, "residual / eps"),
          inputs=(STORED,)),
    Claim("packing.biorthonormal", "packing",
          f"left/right eigenvectors of the dense eig route biorthonormal, max |L^H R - I| over "
          f"the nonzero modes, {_STORED_T}, kT/kN = 1e-4, 1, 10",
          "seconds", _CMD + "packing.biorthonormal", biorthonormal,
          show=lambda v: " / ".join(f"{r['biortho']:.1e}" for r in v["rows"].values())
          + "; G_NA by that mode sum vs solve " + " / ".join(
              f"{r['modes_vs_solve']:.0e}" for r in v["rows"].values()),
          tolerance="any value up to 1e-10 (round-off of LAPACK's eig, ~1e-14 here; the issue's "
                    "bound is 1e-8)",
          check=_check_tiny(_biortho_worst),
          verdict=lambda v: bound_verdict(_biortho_worst(v)[0], 1e-8,
                                          "max |L^H R - I| (issue bound)"),
          inputs=(STORED,)),
    Claim("packing.rot_exponent", "packing",
          f"rotational DOS peak ~ (kT/kN)^a over kT/kN = 1e-10..1e-2, {_STORED_T}",
          "seconds", _CMD + "packing.rot_exponent", stored_dos,
          show=lambda v: f"a = {v['exponent_peak']:.4f} (peak), {v['exponent_median']:.4f} "
          f"(median) over {v['decades']:.0f} decades",
          tolerance="exponents within 0.02, each peak within one 0.1-decade bin, medians within "
                    "2 %: round-off can move a mode across a bin edge or across psi^R = 1/2",
          check=_check_dos, paper="omega t0 ~ (k_T/k_N)^(1/2) (Figs. 9-10)",
          verdict=_exponent_verdict, inputs=(STORED,), job="packing.stored_dos"),
    Claim("packing.rot_prefactor", "packing",
          f"rotational DOS peak position omega t0 / sqrt(kT/kN), kT/kN = 1e-10..1e-2, {_STORED_T}",
          "seconds", _CMD + "packing.rot_prefactor", stored_dos,
          show=lambda v: "peak {}, median {} (over the five kT/kN)".format(
              _range(*_prefactors(v)[:2], ".3f"), _range(*_prefactors(v)[2:], ".3f")),
          tolerance="as packing.rot_exponent (the same job)", check=_check_dos,
          paper='"a peak of D(omega) around omega t0 ~= (k_T/k_N)^(1/2)" (Sec. IV B)',
          verdict=_prefactor_verdict, inputs=(STORED,), job="packing.stored_dos",
          texts={"peak": lambda v: _range(*_prefactors(v)[:2])}),
    Claim("packing.bands", "packing",
          "rotational and translational bands: separated at small kT/kN, merged at kT/kN >= 1 "
          f"(Figs. 8-9), {_STORED_T}",
          "seconds", _CMD + "packing.bands", stored_dos,
          show=lambda v: "; ".join(f"{r['kt']:g}: {r['band']} (mean psi^R {r['purity']:.2f}, "
                                   f"{r['rotation_dominated']} modes with psi^R > 1/2)"
                                   for r in v["rows"]) + f"; N' = {v['backbone']}",
          tolerance="band classes equal, mean psi^R within 1e-3 and counts within 2 modes "
                    "(round-off can move a mode across psi^R = 1/2)",
          check=_check_bands,
          paper="gap between the bands for 1e-10 <= k_T/k_N <= 1e-8; partial overlap for "
                "1e-6..1e-2 (N = 4096); 'completely merged for k_T/k_N >= 1.0'",
          verdict=_band_verdict, inputs=(STORED,), job="packing.stored_dos"),
    # ---- minutes: packing_rigidity.py --tier quick
    Claim("packing.g_three_routes", "packing",
          "G by mode sum, sparse solve and step strain on every sample, N = 256, seeds 0-2, "
          "phi = 0.90, kT/kN = 1e-4, 1, 10",
          "minutes", "python validation/packing_rigidity.py --tier quick", rigidity_quick,
          show=_routes_show, tolerance=_SAMPLES, check=_check_samples(("g", "g_step")),
          paper=_FIG4, verdict=_routes_verdict(("256",)), job="packing.rigidity_quick",
          texts={"step": lambda v: f"{max(abs(r['g_step'] / r['g'] - 1) for r in _rows(v)):.1e}"}),
    Claim("packing.printed_jtilde", "packing",
          "G with the printed J~ (Eqs. 36-37) vs step strain, N = 256, seeds 0-2, kT/kN = 1e-4, "
          "1, 10",
          "minutes", "python validation/packing_rigidity.py --tier quick", rigidity_quick,
          show=lambda v: f"G(J~)/G - 1 from {min(_jtilde(v)[0]):+.1%} to {max(_jtilde(v)[0]):+.1%}"
          f" (|G(J~)/G - 1| >= {min(abs(x) for x in _jtilde(v)[0]):.1%}); |G(J~) - g_step| = "
          f"{min(_jtilde(v)[1]):.0f} to {max(_jtilde(v)[1]):.0f} step-strain error models",
          tolerance="G(J~) within 3 sample standard deviations; still beyond 100 error models "
                    "somewhere (" + _SAMPLES + ")",
          check=_check_jtilde,
          paper="J~ of Eqs. 36-37: the l-x, l-y entries of J_ii and x-l, y-l of J_ij sign-flipped",
          verdict=_jtilde_verdict, job="packing.rigidity_quick",
          texts={"range": lambda v: f"{min(abs(x) for x in _jtilde(v)[0]):.1%}-"
                                    f"{max(abs(x) for x in _jtilde(v)[0]):.0%}"}),
    Claim("packing.dgamma", "packing",
          "G independent of dgamma in [1e-6, 1e-4], N = 256, seed 0, phi = 0.90",
          "minutes", "python validation/packing_rigidity.py --tier quick", rigidity_quick,
          show=lambda v: "; ".join(f"kT/kN = {r['kt']:g}: "
                                   + " / ".join(f"{x:+.1e}" for x in r["rel"])
                                   for r in v["dgamma"])
          + " (g/G - 1 at dgamma = 1e-6 / 1e-5 / 1e-4); contacts changed: "
          + str(sum(r["changed"] for r in v["dgamma"])),
          tolerance="each g/G - 1 within the sum of the two error models (old and new) at its "
                    "dgamma: the drift is the truncation term the error model measures",
          check=_check_dgamma,
          paper='"results are independent of the choice of dgamma for 1.0 x 10^-6 <= dgamma <= '
                '1.0 x 10^-4"',
          verdict=_dgamma_verdict, job="packing.rigidity_quick"),
    *_sign_and_phi("", "sign of G_NA (Fig. 6): root of G_NA(kT/kN) per packing (Brent in log "
                       "kT, 1e-6), N = 256, phi = 0.85, 0.86, 0.88, 0.90, seeds 0-2",
                   "mean root within 3 standard errors of the record (sample-to-sample spread; "
                   "bit-identical on one machine)", "G against phi, N = 256, seeds 0-2 (Fig. 4)",
                   "minutes", "quick", rigidity_quick),
    # ---- minutes: packing_dos.py --tier quick
    Claim("packing.dos_route_exact", "packing",
          "DOS by eigh of the symmetric J vs dense eig with left/right vectors, N = 256, "
          "seed 0, kT/kN = 1e-8, 1: L1 distance of the DOS histograms",
          "minutes", "python validation/packing_dos.py --tier quick", dos_quick,
          show=lambda v: "; ".join(f"kT/kN = {r['kt']:g}: L1 {r['l1']:.1e}, max relative "
                                   f"eigenvalue error {r['rel_error']:.1e}" for r in v["routes"]),
          tolerance="L1 stays 0; the eigenvalue error is eig's backward error eps max|lambda| "
                    "on the smallest eigenvalues",
          check=lambda a, b: (max(r["l1"] for r in b["routes"]) == 0.0,
                              "L1 " + " / ".join(f"{r['l1']:.1e}" for r in b["routes"])),
          verdict=_route_exact_verdict, job="packing.dos_quick"),
    Claim("packing.dos_heff", "packing",
          "J vs the effective Hessian (App. H, Fig. 12) after a 1e-4 step strain (histories "
          "~1e-4 d), N = 256, seed 0",
          "minutes", "python validation/packing_dos.py --tier quick", dos_quick,
          show=lambda v: "; ".join(f"kT/kN = {r['kt']:g}: max relative eigenvalue difference "
                                   f"{r['rel']:.1e}" for r in v["effective_hessian"])
          + " (unstrained: identical, all histories zero)",
          tolerance="within a factor 10 (set by the histories, ~dgamma; another packing from "
                    "another CPU's FIRE changes it by O(1))",
          check=_check_heff, paper='D(omega) and D_H(omega) "almost identical" (Fig. 12)',
          verdict=_heff_verdict, job="packing.dos_quick"),
    Claim("packing.dos_rot_n256", "packing",
          "rotational band over three samples, N = 256, seeds 0-2, kT/kN = 1e-10..1e-2",
          "minutes", "python validation/packing_dos.py --tier quick", dos_quick,
          show=_script_rot_show, tolerance="exponents within 0.02 (peak bin; another CPU may "
                                           "give other packings)",
          check=_check_script_rot, paper="omega t0 ~ (k_T/k_N)^(1/2) (Figs. 9-10)",
          verdict=_script_exponent_verdict, job="packing.dos_quick"),
    # ---- minutes: packing_dos.py --tier medium
    Claim("packing.dos_speedup", "packing",
          "DOS route: eigh vs dense eig with left/right vectors, N = 1024, seed 0, kT/kN = "
          "1e-8, 1, one run side by side",
          "minutes", "python validation/packing_dos.py --tier medium", dos_medium,
          show=lambda v: "; ".join(f"kT/kN = {r['kt']:g}: {r['speedup']:.1f}x, max relative "
                                   f"eigenvalue error {r['rel_error']:.1e}, L1 {r['l1']:.1e}"
                                   for r in v["routes"]),
          tolerance="a ratio of two wall times in one run on a shared 2-core machine, which "
                    "moves with the load by tens of percent between runs: the check is the "
                    "floor itself, 3x (issue)",
          check=_check_speedup, verdict=_speedup_verdict, job="packing.dos_medium"),
    Claim("packing.dos_rot_n1024", "packing",
          "rotational band over two samples, N = 1024, seeds 0-1, kT/kN = 1e-10..1e-2",
          "minutes", "python validation/packing_dos.py --tier medium", dos_medium,
          show=_script_rot_show, tolerance="exponents within 0.02 (peak bin)",
          check=_check_script_rot, paper="omega t0 ~ (k_T/k_N)^(1/2) (Figs. 9-10)",
          verdict=_script_exponent_verdict, job="packing.dos_medium"),
    Claim("packing.dos_heff_n1024", "packing",
          "J vs the effective Hessian after a 1e-4 step strain, N = 1024, seed 0",
          "minutes", "python validation/packing_dos.py --tier medium", dos_medium,
          show=lambda v: "; ".join(f"kT/kN = {r['kt']:g}: {r['rel']:.1e}"
                                   for r in v["effective_hessian"]),
          tolerance="within a factor 10", check=_check_heff,
          paper='D(omega) and D_H(omega) "almost identical" (Fig. 12)',
          verdict=_heff_verdict, job="packing.dos_medium"),
    # ---- hours
    Claim("packing.g_three_routes_n1024", "packing",
          "G by mode sum, sparse solve and step strain on every sample, N = 256 (seeds 0-2) and "
          "N = 1024 (seeds 0-1), phi = 0.90, kT/kN = 1e-4, 1, 10",
          "hours", "python validation/packing_rigidity.py --tier medium", rigidity_medium,
          show=lambda v: _routes_show(v, ("256", "1024")), tolerance=_SAMPLES,
          check=_check_samples(("g", "g_step"), ("256", "1024")), paper=_FIG4,
          verdict=_routes_verdict(("256", "1024")), job="packing.rigidity_medium"),
    Claim("packing.g_n4096", "packing",
          "G at N = 4096 (seed 0) by sparse solve, kT/kN = 1e-4, 1, 10, with its wall time",
          "hours", "python validation/packing_rigidity.py --tier medium", rigidity_medium,
          show=lambda v: "G = " + " / ".join(f"{g:.5f}" for g in v["n4096"]["g"])
          + f"; {min(v['n4096']['seconds']):.2f}-{max(v['n4096']['seconds']):.2f} s per kT/kN",
          tolerance="G within 3 % (another packing from another CPU's FIRE: the "
                    "sample-to-sample spread at N = 4096); the time a measurement, only its "
                    "bound checked",
          check=lambda a, b: (all(abs(y / x - 1) <= 0.03 for x, y in zip(a["n4096"]["g"],
                                                                      b["n4096"]["g"]))
                              and max(b["n4096"]["seconds"]) < 60, "G within 3 %, time < 60 s"),
          verdict=_n4096_verdict, job="packing.rigidity_medium"),
    *_sign_and_phi("_4seeds", "sign of G_NA (Fig. 6): root per packing, N = 256, phi = "
                   "0.85-0.90, seeds 0-3", "mean root within 3 standard errors of the record",
                   "G against phi, N = 256, seeds 0-3 (Fig. 4)", "hours", "medium",
                   rigidity_medium),
    Claim("packing.dos_size", "packing",
          "rotational band at N = 4096 (seed 0, kT/kN = 1e-8..1e-2) against the stored N = 256 "
          "packing (App. I)",
          "hours", "python validation/packing_dos.py --tier full", dos_full,
          show=_script_rot_show, tolerance="exponents within 0.02 (peak bin)",
          check=_check_script_rot,
          paper='"both the rotational and translational bands show little dependence on system '
                'size" (Fig. 15)',
          verdict=_size_verdict, inputs=(STORED,), job="packing.dos_full"),
    Claim("packing.dphi", "packing",
          "compression increment dphi against G, N = 256, phi = 0.90, seeds 0-7 each",
          "hours", "python validation/packing_knobs.py", knobs,
          show=_dphi_show,
          tolerance="each mean within 3 combined standard errors (different dphi, different "
                    "packings: the sample spread)",
          check=_check_dphi, paper="dphi = 1e-4 (App. A.1; our default 1e-3)",
          verdict=lambda v: sigma_verdict([_dphi_pair(v, "1"), _dphi_pair(v, "1e-4")]),
          job="packing.knobs"),
    Claim("packing.force_thresholds", "packing",
          "force thresholds f_tol (1e-8..1e-14) and f_tol_compress (1e-12..1e-4) against G, "
          "N = 256, phi = 0.90, seed 0",
          "hours", "python validation/packing_knobs.py", knobs,
          show=_thresholds_show,
          tolerance="the same grouping of the pairs into packings (bit-identical on one "
                    "machine); which thresholds keep the compression in one basin depends on the "
                    "FIRE trajectory (chaotic), so another CPU may group them otherwise",
          check=_check_thresholds, paper="F_Th = 1.0 x 10^-14 k_N d^(3/2)", job="packing.knobs"),
]

# issue 35: the figures at the paper's scale (validation/ishima_paper.py --tier paper)
CLAIMS += _packing_paper.claims()
