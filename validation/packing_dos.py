"""Ishima et al. (2023) Figs. 8-13: DOS, mode character, rotational band.

1. Spectrum routes (acceptance): dense ``eig`` with left and right vectors
   (the baseline) against ``eigh`` of the symmetric Jacobian, side by side on
   the same backbone: wall time, largest relative eigenvalue error, and the
   L1 distance between the two DOS histograms.
2. Rotational band (Figs. 9-10): the peak (and median) frequency of the
   rotation-dominated modes (psi^R > 1/2) against kT/kN over eight decades,
   with the fitted exponent (paper: omega t0 ~ sqrt(kT/kN)) and the collapse
   omega_R D(omega / omega_R), omega_R = sqrt(kT/kN) / t0.
3. Participation fractions psi^T, psi^R (Fig. 8), participation ratio (Fig. 14).
4. Frictionless Hessian DOS (Fig. 11), effective-Hessian DOS (Fig. 12, App. H),
   DOS with and without rattlers (Fig. 13).

``python validation/packing_dos.py [--tier quick|medium|full]``
quick: N = 256 (3 samples); medium: N = 1024 (2 samples) and the route
comparison at N = 1024; full: N = 4096 (1 sample, symmetric route only, kT/kN = 1e-8 .. 1; the
effective-Hessian and rattler comparisons are left to the smaller tiers).
Writes ``packing_dos_<tier>.md`` and ``.png``; :func:`run` returns the numbers
(``validation/claims/packing.py``).
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

from _packings import ishima, packing  # noqa: E402
from fricstab.analysis.dos import (binned_mean, dos, log_bins, participation,  # noqa: E402
                                   rotational_peak, spectrum)
from fricstab.analysis.rigidity import linear_response  # noqa: E402
from fricstab.figures.packing import RUN_STYLES  # noqa: E402
from fricstab.scenes.packing_friction import Backbone, backbone  # noqa: E402

KTS = (1e-10, 1e-8, 1e-6, 1e-4, 1e-2, 1.0, 10.0)


def modes(bb, kt, route="symmetric"):
    """omega (translations dropped), psi^T, psi^R, p, and the spectrum."""
    jac = linear_response(*ishima(bb, kt)).jacobian
    sp = spectrum(jac, route=route)
    k = 3 if kt > 0 else 2
    psi_t, psi_r, p = participation(sp.right, k)
    order = np.argsort(np.abs(sp.eigenvalues.real))[2:]
    keep = np.sort(order)
    return sp.omega[keep], psi_t[keep], psi_r[keep], p[keep], sp


def route_comparison(bb, lines, n_total):
    lines += [f"## Spectrum routes (N = {n_total}, backbone {bb.n}, 3N' = {3 * bb.n}), "
              "one run, side by side", "",
              "| kT/kN | dense eig (L+R) s | eigh s | speed-up | max rel. eigenvalue error | "
              "L1 distance of DOS | max |Im lambda| (dense) | asymmetry |",
              "|---|---|---|---|---|---|---|---|"]
    out = []
    for kt in (1e-8, 1.0):
        jac = linear_response(*ishima(bb, kt)).jacobian
        d = spectrum(jac, route="dense")
        s = spectrum(jac, route="symmetric")
        wd = np.sort(d.eigenvalues.real)
        ws = np.sort(s.eigenvalues.real)
        nz = np.argsort(np.abs(ws))[2:]
        rel = np.max(np.abs(wd[nz] - ws[nz]) / np.abs(ws[nz]))
        od, os_ = np.sqrt(np.clip(wd[nz], 0, None)), np.sqrt(np.clip(ws[nz], 0, None))
        edges = log_bins(os_.min() / 2, os_.max() * 2)
        l1 = np.abs(dos(od, n_total, edges) - dos(os_, n_total, edges)) @ np.diff(edges)
        lines.append(f"| {kt:g} | {d.seconds:.2f} | {s.seconds:.2f} | {d.seconds / s.seconds:.1f}x"
                     f" | {rel:.1e} | {l1:.1e} | {d.max_imag:.1e} | {d.asymmetry:.1e} |")
        out.append((kt, d.seconds / s.seconds, rel, l1))
    lines += ["", "Why eigh is exact here: friction is switched on at the frictionless "
              "force-balanced state, every tangential history is zero, and J is then symmetric "
              "(the Hessian of the effective potential, App. H).  `spectrum(route=\"auto\")` "
              "checks max|J - J^T| <= 1e-12 max|J| before taking this route and falls back to the "
              "dense non-symmetric route otherwise.", ""]
    return out


def rotational(samples, n_total, lines, kts=KTS):
    lines += ["## Rotational band against kT/kN (Figs. 9-10)", "",
              "| kT/kN | peak omega t0 | median omega t0 | peak / sqrt(kT/kN) | "
              "median / sqrt(kT/kN) | rotation-dominated modes |", "|---|---|---|---|---|---|"]
    peaks, medians, used, table = [], [], [], []
    for kt in kts:
        om = np.concatenate([s[kt][0] for s in samples])
        pr = np.concatenate([s[kt][2] for s in samples])
        pk, md = rotational_peak(om, pr)
        nrot = int((pr > 0.5).sum())
        table.append({"kt": kt, "peak": pk, "median": md, "rotation_dominated": nrot})
        lines.append(f"| {kt:g} | {pk:.3g} | {md:.3g} | {pk / np.sqrt(kt):.3g} | "
                     f"{md / np.sqrt(kt):.3g} | {nrot} |")
        if kt <= 1e-2:
            peaks.append(pk)
            medians.append(md)
            used.append(kt)
    lk = np.log10(used)
    sp = np.polyfit(lk, np.log10(peaks), 1)[0]
    sm = np.polyfit(lk, np.log10(medians), 1)[0]
    lines += ["", f"Fitted exponent over kT/kN = {used[0]:g} .. {used[-1]:g} "
              f"({lk[-1] - lk[0]:.0f} decades): peak {sp:.4f}, median {sm:.4f} "
              "(paper: 1/2).  Above kT/kN ~ 1 the bands merge and there is no separate "
              "rotational band (paper: Figs. 8c-d, 9c-d).", ""]
    return sp, sm, (lk[-1] - lk[0]), table


def figure(samples, hess, eff, ratt, n_total, path, kts=KTS):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    allom = np.concatenate([s[kt][0] for s in samples for kt in kts])
    allom = allom[allom > 0]
    edges = log_bins(allom.min() / 1.5, allom.max() * 1.5, 60)
    mid = np.sqrt(edges[1:] * edges[:-1])
    fig, ax = plt.subplots(2, 4, figsize=(20, 8.5))
    for kt, mk in ((1e-8, "o"), (1e-4, "s")):
        if kt not in kts:
            continue
        om = np.concatenate([s[kt][0] for s in samples])
        pp = np.concatenate([s[kt][3] for s in samples])
        pm = binned_mean(om, pp, edges)
        ax[0, 3].loglog(mid, np.where(pm > 0, pm, np.nan), mk + "-", ms=3, label=f"{kt:g}")
    ax[0, 3].axhline(1 / n_total, color="k", ls="--", lw=0.8, label="1/N")
    ax[0, 3].set(xlabel="omega [t0^-1]", ylabel="participation ratio p(omega) [-]", title="participation ratio (Fig. 14)")
    ax[0, 3].legend(title="kT/kN", fontsize=7)
    ax[1, 3].axis("off")
    for i, kt in enumerate(kts):
        om = np.concatenate([s[kt][0] for s in samples])
        d = dos(om, n_total * len(samples), edges)
        # Equal bands (the translational band of 1e-8 and 1e-4) stay visible:
        # a larger open marker under a smaller one, another dash.
        mk, size, ls = RUN_STYLES[i % len(RUN_STYLES)]
        ax[0, 0].loglog(mid, np.where(d > 0, d, np.nan), marker=mk, ms=size, ls=ls, mfc="none",
                        label=f"{kt:g}")
        if kt <= 1e-2:
            wr = np.sqrt(kt)
            e2 = log_bins(0.01, 100.0, 60)
            d2 = dos(om / wr, n_total * len(samples), e2)
            m2 = np.sqrt(e2[1:] * e2[:-1])
            ax[0, 1].loglog(m2, np.where(d2 > 0, d2, np.nan), ".-", label=f"{kt:g}")
    ax[0, 0].set(xlabel="omega [t0^-1]", ylabel="D(omega) [t0]", title="DOS (Fig. 9)")
    ax[0, 0].legend(title="kT/kN", fontsize=7)
    ax[0, 1].set(xlabel="omega / omega_R [-]", ylabel="omega_R D [-]", xlim=(0.05, 20),
                 title="rotational band collapse (Fig. 10)")
    ax[0, 1].legend(title="kT/kN", fontsize=7)
    for kt, mk in ((1e-8, "o"), (1e-4, "s"), (1.0, "^")):
        om = np.concatenate([s[kt][0] for s in samples])
        pr = np.concatenate([s[kt][2] for s in samples])
        pt = np.concatenate([s[kt][1] for s in samples])
        ax[0, 2].semilogx(mid, binned_mean(om, pr, edges), mk + "-", ms=3,
                          label=f"psi^R, {kt:g}")
        ax[0, 2].semilogx(mid, binned_mean(om, pt, edges), mk + "--", ms=3, mfc="none",
                          label=f"psi^T, {kt:g}")
    ax[0, 2].set(xlabel="omega [t0^-1]", ylabel="participation fraction [-]", title="Fig. 8")
    ax[0, 2].legend(fontsize=6)
    om8 = np.concatenate([s[1e-8][0] for s in samples])
    d8 = dos(om8, n_total * len(samples), edges)
    dh = dos(hess, n_total * len(samples), edges)
    ax[1, 0].loglog(mid[d8 > 0], d8[d8 > 0], "o", ms=3, label="Jacobian, kT/kN = 1e-8")
    ax[1, 0].loglog(mid[dh > 0], dh[dh > 0], "^", ms=3, label="frictionless Hessian")
    ax[1, 0].set(xlabel="omega [t0^-1]", ylabel="D(omega) [t0]", title="Fig. 11")
    ax[1, 0].legend(fontsize=7)
    for kt, (oj, oh) in eff.items():
        dj, dh2 = dos(oj, n_total, edges), dos(oh, n_total, edges)
        ax[1, 1].loglog(mid[dj > 0], dj[dj > 0], "o", ms=3, label=f"J, {kt:g}")
        ax[1, 1].loglog(mid[dh2 > 0], dh2[dh2 > 0], "x", ms=4, label=f"H_eff, {kt:g}")
    ax[1, 1].set(xlabel="omega [t0^-1]", ylabel="D(omega) [t0]",
                 title="Jacobian vs effective Hessian after a 1e-4 step (Fig. 12)")
    if eff:
        ax[1, 1].legend(fontsize=6)
    else:  # full tier: compared at the smaller sizes
        ax[1, 1].axis("off")
    for kt, (ow, oo) in ratt.items():
        dw, do = dos(ow, n_total, edges), dos(oo, n_total, edges)
        ax[1, 2].loglog(mid[dw > 0], dw[dw > 0], "o", ms=3, label=f"with rattlers, {kt:g}")
        ax[1, 2].loglog(mid[do > 0], do[do > 0], "^", ms=3, label=f"without, {kt:g}")
    ax[1, 2].set(xlabel="omega [t0^-1]", ylabel="D(omega) [t0]", title="rattlers (Fig. 13)")
    if ratt:
        ax[1, 2].legend(fontsize=6)
    else:
        ax[1, 2].axis("off")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def with_rattlers(pk, kt):
    """Spectrum of the whole packing (rattlers kept) with the zero modes dropped."""
    bb = Backbone(pk.pos, pk.diameter / 2, pk.box, np.arange(pk.n), pk.n, 0.0)
    jac = linear_response(*ishima(bb, kt)).jacobian
    w = spectrum(jac, route="symmetric", vectors=False).eigenvalues
    w = w[np.abs(w) > 1e-12 * np.abs(w).max()]
    return np.sqrt(np.clip(w, 0, None))


def effective_hessian(bb, kt):
    """J of a state with history (after a 1e-4 step strain) and H_eff (history set to 0)."""
    from fricstab.protocols.stepstrain import strain
    system, state = ishima(bb, kt)
    out, _ = strain(system, state, 1e-4)
    jac = linear_response(system, out).jacobian
    zero = out.copy()
    zero.contacts.hist[:] = 0.0
    h = linear_response(system, zero).jacobian
    wj = spectrum(jac, route="dense", vectors=False).eigenvalues
    wh = spectrum(h, route="symmetric", vectors=False).eigenvalues
    wj, wh = np.sort(wj.real), np.sort(wh.real)
    nzj = np.sort(np.argsort(np.abs(wj))[2:])
    nzh = np.sort(np.argsort(np.abs(wh))[2:])
    rel = np.max(np.abs(wj[nzj] - wh[nzh]) / np.abs(wh[nzh]))
    return (np.sqrt(np.clip(wj[nzj], 0, None)), np.sqrt(np.clip(wh[nzh], 0, None)), rel,
            float(np.abs(out.contacts.hist).max()))


def report_name(tier):
    """The report of a tier: ``packing_dos_<tier>.md``."""
    return f"packing_dos_{tier}"


def run(tier="quick", out=HERE):
    """Compute a tier, write its report and figure into ``out``; returns (values, paths).

    ``values``: ``routes`` (quick, medium: per kT/kN the dense/eigh wall-time ratio,
    the largest relative eigenvalue error and the L1 distance of the DOS), ``rotational``
    (per kT/kN: peak and median frequency of the rotation-dominated modes, their
    number), the fitted exponents over kT/kN <= 1e-2, ``effective_hessian`` (quick,
    medium: largest relative eigenvalue difference J vs H_eff after a 1e-4 step),
    ``backbone`` sizes.
    """
    out = Path(out)
    t_start = time.perf_counter()
    n, seeds = {"quick": (256, (0, 1, 2)), "medium": (1024, (0, 1)),
                "full": (4096, (0,))}[tier]
    name = report_name(tier)
    lines = ["# Packings: density of states and mode character (Ishima Figs. 8-14)", "",
             f"`python validation/packing_dos.py --tier {tier}` ({platform.machine()}, Python "
             f"{platform.python_version()}, {time.strftime('%Y-%m-%d')}).  N = {n}, phi = 0.90, "
             f"seeds {list(seeds)}; rattlers (Z <= 2) removed; D normalized by 3N (all "
             "particles), translations dropped.", ""]
    pks = [packing(n, 0.90, s) for s in seeds]
    bbs = [backbone(pk) for pk in pks]
    values = {"tier": tier, "n": n, "seeds": list(seeds), "backbone": [bb.n for bb in bbs]}
    ok = True
    if tier in ("quick", "medium"):
        res = route_comparison(bbs[0], lines, n)
        values["routes"] = [{"kt": kt, "speedup": sp, "rel_error": rel, "l1": l1}
                            for kt, sp, rel, l1 in res]
        ok &= all(r[2] < 1e-6 for r in res)
        if tier == "medium":
            ok &= all(r[1] >= 3 for r in res)
    kts = KTS if tier != "full" else (1e-8, 1e-6, 1e-4, 1e-2, 1.0)
    samples = []
    for bb in bbs:
        t0 = time.perf_counter()
        samples.append({kt: modes(bb, kt)[:4] for kt in kts})
        lines.append(f"Spectra with vectors (eigh), {len(kts)} values of kT/kN: "
                     f"{time.perf_counter() - t0:.0f} s for a backbone of {bb.n}.")
    lines.append("")
    sp, sm, decades, table = rotational(samples, n, lines, kts)
    values.update({"rotational": table, "exponent_peak": sp, "exponent_median": sm,
                   "decades": decades})
    ok &= abs(sp - 0.5) < 0.05 and decades >= 4
    hess = np.concatenate([modes(bb, 0.0)[0] for bb in bbs])
    eff, ratt = {}, {}
    png, md = out / f"{name}.png", out / f"{name}.md"
    if tier == "full":
        figure(samples, hess, eff, ratt, n, png, kts)
        lines += [f"![DOS figures]({name}.png)", "",
                  f"Total wall time: {time.perf_counter() - t_start:.0f} s."]
        md.write_text("\n".join(lines) + "\n")
        print("\n".join(lines))
        values["ok"] = bool(ok)
        return values, (md, png)
    lines += ["## Effective Hessian (App. H, Fig. 12) and rattlers (Fig. 13)", "",
              "In the unstrained state the histories vanish and J equals the effective Hessian "
              "exactly, so the paper's Fig. 12 agreement is an identity there.  To test the "
              "comparison where it can fail, J and H_eff (the same contacts with the history "
              "set to zero) are compared after a step strain of 1e-4 (histories ~1e-4 d):", "",
              "| kT/kN | max |xi_T| | max rel. eigenvalue difference J vs H_eff |", "|---|---|---|"]
    values["effective_hessian"] = []
    for kt in (1e-4, 1.0):
        oj, oh, rel, hmax = effective_hessian(bbs[0], kt)
        eff[kt] = (oj, oh)
        values["effective_hessian"].append({"kt": kt, "max_hist": hmax, "rel": float(rel)})
        lines.append(f"| {kt:g} | {hmax:.2e} | {rel:.2e} |")
    for kt in (1e-8, 1e-4):
        ratt[kt] = (with_rattlers(pks[0], kt), modes(bbs[0], kt)[0])
    nr = [pk.n - bb.n for pk, bb in zip(pks, bbs)]
    lines += ["", f"Rattlers (iterative Z <= 2): {nr} of {n} per sample.  With rattlers kept, "
              "their rotations and translations add near-zero and intermediate modes "
              "(figure, bottom right), as the paper's Fig. 13.", ""]
    figure(samples, hess, eff, ratt, n, png, kts)
    lines += [f"![DOS figures]({name}.png)", "",
              f"Total wall time: {time.perf_counter() - t_start:.0f} s."]
    md.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    values["ok"] = bool(ok)
    return values, (md, png)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--tier", choices=("quick", "medium", "full"), default="quick")
    ns = p.parse_args(argv)
    values, _ = run(ns.tier)
    return 0 if values["ok"] else 1


if __name__ == "__main__":
    sys.exit(main())
