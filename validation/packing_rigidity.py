"""Ishima et al. (2023) Figs. 3-6: G by mode sum, sparse solve and step strain.

Paper: "Theory of rigidity and numerical analysis of density of states of
two-dimensional amorphous solids with dispersed frictional grains in the
linear response regime" (``../shared/papers/ishima-rigidity-dos-frictional-grains.md``).

1. Agreement (acceptance): N = 256 and 1024, phi = 0.90, kT/kN in
   {1e-4, 1, 10}, every sample: G by direct sparse solve, by the eigenmode
   sum (Eq. 44; symmetric route, exact because J = J^T in the unstrained
   state) and by step strain (Eq. 16, dgamma = 1e-6, with its error model).
   The printed J~ of Eqs. 36-37 is evaluated alongside (errata).
2. dgamma independence: g at dgamma = 1e-6, 1e-5, 1e-4 (paper: independent).
3. Sign of G_NA (Fig. 6): the root of G_NA(kT/kN) by bisection in log kT.
4. G and G_NA against phi for kT/kN in {1e-8, 1e-4, 1e-2, 1, 2, 10} and the
   frictionless Hessian (Figs. 4-6), and G against kT/kN (Fig. 5).
5. N = 4096: G by sparse solve and its wall time (acceptance: < 1 min).

``python validation/packing_rigidity.py [--tier quick|medium|full]``
(quick: N = 256 only, minutes; medium (also "full"): + N = 1024 and 4096).
Writes ``packing_rigidity.md`` and ``.png`` (quick) or ``packing_rigidity_<tier>.md``
and ``.png``; :func:`run` returns the numbers (``validation/claims/packing.py``).
"""

import argparse
import platform
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
sys.path.insert(0, str(HERE))

import numpy as np  # noqa: E402
import scipy.optimize  # noqa: E402

from _packings import ishima, packing  # noqa: E402
from fricstab.analysis.rigidity import ishima_flipped, rigidity, solve_nonaffine  # noqa: E402
from fricstab.protocols.stepstrain import step_strain  # noqa: E402
from fricstab.scenes.packing_friction import backbone  # noqa: E402


def _g(bb, kt, **kw):
    return rigidity(*ishima(bb, kt), **kw)

KTS = (1e-4, 1.0, 10.0)
DGAMMAS = (1e-6, 1e-5, 1e-4)
SWEEP_KTS = (0.0, 1e-8, 1e-4, 1e-2, 1.0, 2.0, 10.0)
PHIS = (0.85, 0.86, 0.88, 0.90)


def agreement(n, seeds, lines, modes=True):
    lines += [f"### N = {n}, phi = 0.90, seeds {list(seeds)}", "",
              "| seed | kT/kN | G_A | G_NA (solve) | G (solve) | G (modes) / G (solve) - 1 | "
              "G (step) / G (solve) - 1 | step-strain error model / G | G (Eqs. 36-37) / G - 1 | "
              "mode-sum s | solve s | step s |",
              "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    worst, rows = 0.0, []
    for seed in seeds:
        bb = backbone(packing(n, 0.90, seed))
        for kt in KTS:
            system, state = ishima(bb, kt)
            r = rigidity(system, state, modes=modes, route="symmetric")
            s = step_strain(system, state, 1e-6)
            u, _ = solve_nonaffine(ishima_flipped(r.jacobian), r.xi, bb.n, 3)
            g_fl = r.g_a - r.theta @ u / bb.box**2
            d_modes = r.g_modes / r.g - 1 if modes else float("nan")
            d_step = s.g / r.g - 1
            worst = max(worst, abs(d_step), abs(d_modes) if modes else 0.0)
            rows.append({"seed": seed, "kt": kt, "g_a": r.g_a, "g_na": r.g_na_solve, "g": r.g,
                         "g_modes": r.g_modes if modes else float("nan"),
                         "cond": _cond(r.jacobian) if modes else float("nan"),
                         "g_step": float(s.g), "step_error": float(s.error),
                         "g_flipped": float(g_fl)})
            lines.append(f"| {seed} | {kt:g} | {r.g_a:.6g} | {r.g_na_solve:.6g} | {r.g:.8g} | "
                         f"{d_modes:.1e} | {d_step:.1e} | {s.error / abs(r.g):.1e} | "
                         f"{g_fl / r.g - 1:+.3f} | {r.seconds.get('modes', float('nan')):.2f} | "
                         f"{r.seconds['solve']:.3f} | {s.seconds:.2f} |")
    lines += ["", f"Largest |relative disagreement| of the three routes: {worst:.1e} "
              "(acceptance: 1e-2 on every sample).", ""]
    return worst, rows


def _cond(jac):
    """max |lambda| / min |lambda| over the nonzero eigenvalues of J (two zero modes)."""
    from fricstab.analysis.dos import spectrum
    w = np.sort(np.abs(spectrum(jac, vectors=False).eigenvalues))
    return float(w[-1] / w[2])


def dgamma_independence(n, seed, lines):
    bb = backbone(packing(n, 0.90, seed))
    lines += ["### dgamma independence (N = %d, seed %d)" % (n, seed), "",
              "| kT/kN | G (solve) | g(1e-6)/G - 1 | g(1e-5)/G - 1 | g(1e-4)/G - 1 | "
              "contacts changed at 1e-4 |", "|---|---|---|---|---|---|"]
    out = []
    for kt in KTS:
        g = _g(bb, kt).g
        row = [f"{kt:g}", f"{g:.8g}"]
        rel, err = [], []
        for dg in DGAMMAS:
            s = step_strain(*ishima(bb, kt), dg)
            row.append(f"{s.g / g - 1:+.1e}")
            rel.append(float(s.g / g - 1))
            err.append(float(s.error / abs(g)))
        row.append(str(s.contacts_changed))
        lines.append("| " + " | ".join(row) + " |")
        out.append({"kt": kt, "g": g, "rel": rel, "error": err, "changed": s.contacts_changed})
    lines += ["", "The O(dgamma) truncation term grows linearly with dgamma, as the error "
              "model says; at 1e-4 it stays below 1e-2 unless contacts open or close.", ""]
    return out


def gna_root(bb):
    """kT/kN where G_NA changes sign (bisection in log10 kT between 1e-2 and 10)."""
    f = lambda lk: _g(bb, 10.0 ** lk).g_na_solve  # noqa: E731
    lo, hi = -2.0, 1.0
    if f(lo) * f(hi) > 0:
        return float("nan")
    return 10.0 ** scipy.optimize.brentq(f, lo, hi, xtol=1e-6)


def sweeps(n, seeds, phis, lines):
    lines += [f"### G and G_NA against phi (N = {n}, mean over seeds {list(seeds)})", "",
              "| phi | " + " | ".join(f"G (kT/kN={k:g})" for k in SWEEP_KTS) + " | "
              + " | ".join(f"G_NA ({k:g})" for k in SWEEP_KTS) + " | root of G_NA |",
              "|---|" + "---|" * (2 * len(SWEEP_KTS) + 1)]
    table, per = {}, {}
    roots = []
    for phi in phis:
        gs = np.zeros((len(seeds), len(SWEEP_KTS)))
        gna = np.zeros_like(gs)
        rts = []
        for a, seed in enumerate(seeds):
            bb = backbone(packing(n, phi, seed))
            for b, kt in enumerate(SWEEP_KTS):
                r = _g(bb, kt)
                gs[a, b], gna[a, b] = r.g, r.g_na_solve
            rts.append(gna_root(bb))
        table[phi] = (gs.mean(0), gna.mean(0), gs.std(0) / np.sqrt(len(seeds)))
        per[phi] = {"g": gs.tolist(), "g_na": gna.tolist(), "roots": rts}
        roots += rts
        lines.append(f"| {phi:.2f} | " + " | ".join(f"{v:.4g}" for v in gs.mean(0)) + " | "
                     + " | ".join(f"{v:+.3g}" for v in gna.mean(0)) + " | "
                     + ", ".join(f"{v:.3g}" for v in rts) + " |")
    roots = np.array(roots)
    lines += ["", f"G_NA changes sign at kT/kN = {np.nanmin(roots):.3g} to {np.nanmax(roots):.3g} "
              f"(median {np.nanmedian(roots):.3g}) over {len(roots)} packings "
              "(paper: negative below 2, about zero at 2, positive above).", ""]
    return table, roots, per


def kt_curve(n, seed, phi=0.90):
    bb = backbone(packing(n, phi, seed))
    kts = np.logspace(-10, 1, 23)
    g0 = _g(bb, 0.0).g
    return kts, np.array([_g(bb, k).g for k in kts]), g0


def figure(table, curve, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 3, figsize=(14, 4.2))
    phis = sorted(table)
    for b, kt in enumerate(SWEEP_KTS):
        lab = "frictionless" if kt == 0 else f"kT/kN = {kt:g}"
        ax[0].errorbar(phis, [table[p][0][b] for p in phis], [table[p][2][b] for p in phis],
                       marker="o", label=lab)
        ax[2].plot(phis, [table[p][1][b] for p in phis], marker="o", label=lab)
    ax[0].set(xlabel="phi [-]", ylabel="G [k_N d^1/2]", title="G vs phi (Fig. 4)")
    ax[2].axhline(0, color="k", lw=0.5)
    ax[2].set(xlabel="phi [-]", ylabel="G_NA [k_N d^1/2]", title="G_NA vs phi (Fig. 6)")
    ax[0].legend(fontsize=7)
    kts, gs, g0 = curve
    ax[1].semilogx(kts, gs, "o-", label="frictional")
    ax[1].axhline(g0, color="k", ls="--", label="frictionless (kT = 0)")
    ax[1].set(xlabel="kT/kN [-]", ylabel="G [k_N d^1/2]", title="G vs kT/kN, phi = 0.90 (Fig. 5)")
    ax[1].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def report_name(tier):
    """The report of a tier: ``packing_rigidity.md`` (quick) or ``packing_rigidity_<tier>.md``."""
    return "packing_rigidity" if tier == "quick" else f"packing_rigidity_{tier}"


def run(tier="quick", out=HERE):
    """Compute a tier, write its report and figure into ``out``; returns (values, paths).

    ``values``: ``agreement`` (N -> one row per seed and kT/kN: G_A, G_NA, G by solve,
    modes and step strain with its error model, cond J, G with the printed J~),
    ``dgamma`` (g(dgamma)/G - 1 per kT/kN), ``sweeps`` (phi -> per-packing G and G_NA
    for ``SWEEP_KTS`` and the root of G_NA), ``curve`` (G against kT/kN, seed 0) and,
    past quick, ``n4096`` (G and wall seconds per kT/kN).
    """
    out = Path(out)
    t_start = time.perf_counter()
    name = report_name(tier)
    lines = ["# Packings: G by mode sum, sparse solve and step strain (Ishima Figs. 3-6)", "",
             f"`python validation/packing_rigidity.py --tier {tier}` ({platform.machine()}, "
             f"Python {platform.python_version()}, {time.strftime('%Y-%m-%d')}).  Units: d = 1, "
             "k_N = 1, m = 1.  Packings: `make_packing` defaults (dphi = 1e-3, f_tol = 1e-14); "
             "rattlers (Z <= 2) removed.", "", "## Agreement of the three routes", ""]
    values = {"tier": tier, "agreement": {}}
    worst, values["agreement"]["256"] = agreement(256, (0, 1, 2), lines)
    if tier != "quick":
        w, values["agreement"]["1024"] = agreement(1024, (0, 1), lines)
        worst = max(worst, w)
    values["worst"] = worst
    values["dgamma"] = dgamma_independence(256, 0, lines)
    lines += ["## Sweeps (Figs. 4-6)", ""]
    seeds = (0, 1, 2) if tier == "quick" else (0, 1, 2, 3)
    table, roots, per = sweeps(256, seeds, PHIS, lines)
    values["sweeps"] = {"seeds": list(seeds), "kts": list(SWEEP_KTS),
                        "phi": {f"{phi:.2f}": v for phi, v in per.items()}}
    curve = kt_curve(256, 0)
    kts, gs, g0 = curve
    values["curve"] = {"kts": kts.tolist(), "g": gs.tolist(), "g0": g0}
    lines += ["### G against kT/kN (Fig. 5; N = 256, seed 0, phi = 0.90)", "",
              "| kT/kN | G | G/G(kT = 0) - 1 |", "|---|---|---|"]
    lines += [f"| {k:.3g} | {g:.8g} | {g / g0 - 1:+.2e} |" for k, g in zip(kts, gs)]
    lines += ["", f"Frictionless Hessian: G = {g0:.8g}.  G(kT) - G(0) is linear in kT as "
              "kT -> 0: the frictionless limit is reached smoothly (paper: Fig. 5).", ""]
    if tier != "quick":
        p4 = packing(4096, 0.90, 0)
        t0 = time.perf_counter()
        bb = backbone(p4)
        rows, big = [], {"backbone": bb.n, "kts": list(KTS), "g": [], "seconds": []}
        for kt in KTS:
            t1 = time.perf_counter()
            r = _g(bb, kt)
            big["g"].append(r.g)
            big["seconds"].append(time.perf_counter() - t1)
            rows.append(f"| {kt:g} | {r.g:.8g} | {time.perf_counter() - t1:.2f} |")
        values["n4096"] = big
        lines += ["## N = 4096 by sparse solve", "",
                  f"Backbone {bb.n} of 4096 particles ({time.perf_counter() - t0:.1f} s in all).",
                  "", "| kT/kN | G | wall s (assembly + solve) |", "|---|---|---|"] + rows + [""]
    png, md = out / f"{name}.png", out / f"{name}.md"
    figure(table, curve, png)
    lines += [f"![G vs phi, G vs kT, G_NA vs phi]({name}.png)", "",
              f"Total wall time: {time.perf_counter() - t_start:.0f} s."]
    md.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    return values, (md, png)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--tier", choices=("quick", "medium", "full"), default="quick")
    ns = p.parse_args(argv)
    values, _ = run(ns.tier)
    return 0 if values["worst"] < 1e-2 else 1


if __name__ == "__main__":
    sys.exit(main())
