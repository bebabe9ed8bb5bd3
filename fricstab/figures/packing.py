"""Figures of ``fricstab packing make|rigidity|dos`` (matplotlib, Agg backend).

``packing_figure``: disks to scale in the periodic box, rattlers in grey,
contact forces as lines of width ~ force.  ``rigidity_figure``: G_A, G_NA and
G (solve, modes, step strain) against kT/kN, and the nonaffine rates of theory
against step strain (Ishima Fig. 3c).  ``dos_figure``: D(omega) (Fig. 9) and
psi^R = 1 - psi^T against omega (Fig. 8), one marker and line style per run so
that runs with equal spectra (kT/kN = 1e-8 and 1e-4 share their
translational band) stay visible on top of each other.

Units are Ishima's: length d (large diameter), time t_0 = sqrt(m/k_N) d^(1/4),
rigidity k_N d^(1/2).  Each function returns the Figure; with ``path`` it
writes the PNG and closes it (:mod:`fricstab.figures.common`).
"""

import numpy as np

from fricstab.figures.common import finish, note, pyplot

__all__ = ["dos_figure", "packing_figure", "rigidity_figure"]

UNITS = (r"units (Ishima): length $d$ (large diameter), time $t_0=\sqrt{m/k_N}\,d^{1/4}$, "
         r"rigidity $k_N d^{1/2}$")
#: Marker, size, line style per run: later runs smaller, drawn on top of earlier ones.
RUN_STYLES = (("o", 9, "-"), ("s", 6, "--"), ("^", 4, ":"), ("D", 3, "-."), ("v", 3, "-"),
              ("x", 5, "--"))


def packing_figure(packing, pairs, sep, force, rattler, path=None):
    """Disks to scale, rattlers grey, contacts ``pairs`` (M, 2) with ``sep = r_i - r_j`` (M, 2).

    ``packing`` needs ``box``, ``diameter``, ``pos``, ``n``, ``phi``, ``seed``.
    """
    plt = pyplot()
    from matplotlib.collections import LineCollection, PatchCollection
    from matplotlib.patches import Circle

    box = packing.box
    radius = packing.diameter / 2
    fig, ax = plt.subplots(figsize=(7, 7.6))
    patches, colours = [], []
    for i, (x, y) in enumerate(packing.pos):
        r = radius[i]
        for sx in (-box, 0.0, box):
            for sy in (-box, 0.0, box):
                cx, cy = x + sx, y + sy
                if -r < cx < box + r and -r < cy < box + r:
                    patches.append(Circle((cx, cy), r))
                    colours.append("0.75" if rattler[i] else
                                   ("#8fb8de" if packing.diameter[i] == 1 else "#f4b183"))
    ax.add_collection(PatchCollection(patches, facecolors=colours, edgecolors="0.3",
                                      linewidths=0.4))
    m = len(pairs)
    if m:
        i, j = pairs[:, 0], pairs[:, 1]
        a = packing.pos[i]
        b = a - sep                           # the image of j touching i
        segs = [np.stack([a, b], axis=1)]
        # The same contact seen from j's side, where it crosses the boundary.
        c = packing.pos[j]
        crossing = np.any(np.abs(b - c) > 1e-9 * box, axis=1)
        segs.append(np.stack([c[crossing], (c + sep)[crossing]], axis=1))
        width = 0.3 + 3.0 * force / force.max() if force.max() > 0 else np.full(m, 0.5)
        lines = LineCollection(np.concatenate(segs),
                               linewidths=np.concatenate([width, width[crossing]]),
                               colors="k")
        ax.add_collection(lines)
    ax.add_patch(plt.Rectangle((0, 0), box, box, fill=False, lw=1.0, ec="k"))
    ax.set_xlim(0, box)
    ax.set_ylim(0, box)
    ax.set_aspect("equal")
    ax.set_xlabel("$x$ [$d$]")
    ax.set_ylabel("$y$ [$d$]")
    ax.set_title(f"N = {packing.n}, phi = {packing.phi:g}, seed = {packing.seed}: "
                 f"{m} contacts, {int(rattler.sum())} rattlers")
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch
    fmax = float(force.max()) if m else 0.0
    handles = [Patch(fc="#8fb8de", ec="0.3", label="large disk ($d$ = 1)"),
               Patch(fc="#f4b183", ec="0.3", label="small disk"),
               Patch(fc="0.75", ec="0.3", label="rattler"),
               Line2D([], [], color="k", lw=3.3,
                      label=f"contact force, width $\\propto |f|$: max {fmax:.3g} $k_N d^{{3/2}}$")]
    fig.legend(handles=handles, loc="lower center", ncol=2, fontsize=8, frameon=False)
    fig.tight_layout(rect=(0, 0.07, 1, 1))
    return finish(fig, path, dpi=120)


def rigidity_figure(results, first, path=None):
    """G_A, G_NA, G against kT/kN (a) and the nonaffine rates of one run (b).

    ``results``: dicts with ``kt``, ``law``, ``g_a``, ``g_na_solve``, ``g``,
    ``g_modes``, ``g_step``, ``g_step_error`` (None where absent); ``first``:
    ``(label, u, step)`` with u and step (n, k) nonaffine rates of theory and
    of the step strain.
    """
    plt = pyplot()

    fig, (a, b) = plt.subplots(1, 2, figsize=(13, 5))
    pos = [e for e in results if e["kt"] is not None and e["kt"] > 0]
    zero = [e for e in results if e["kt"] is None or e["kt"] == 0]
    # The three estimates of G agree: an open diamond, a smaller x and a larger +
    # keep each visible on top of the others.
    series = (("g_a", "$G_A$", "C0", "o", "-", 7), ("g_na_solve", "$G_{NA}$", "C1", "s", "-", 7),
              ("g", "$G$ (solve)", "C2", "D", "-", 10), ("g_modes", "$G$ (modes)", "C3", "x",
                                                          "none", 6),
              ("g_step", "$G$ (step strain)", "k", "+", "none", 13))
    for key, label, colour, marker, ls, size in series:
        pts = [(e["kt"], e[key]) for e in pos if e[key] is not None]
        if pts:
            x, y = zip(*pts)
            a.plot(x, y, color=colour, marker=marker, ls=ls, label=label, ms=size,
                   mfc="none" if marker == "D" else colour, mew=1.3)
        for e in zero:
            if e[key] is not None:
                a.axhline(e[key], color=colour, ls=":", lw=0.8,
                          label=None if pos or e is not zero[0] else label)
    if pos:
        a.errorbar([e["kt"] for e in pos], [e["g_step"] for e in pos],
                   yerr=[e["g_step_error"] for e in pos], fmt="none", ecolor="k", capsize=3)
        a.set_xscale("log")
    a.axhline(0, color="0.6", lw=0.5)
    a.set_xlabel("$k_T / k_N$ [-]")
    a.set_ylabel("rigidity [$k_N d^{1/2}$]")
    a.set_title("(a) rigidity" + (" (dotted: " + ", ".join(
        "$k_T = 0$" if e["kt"] == 0 else e["law"] for e in zero) + ")" if zero else ""))
    a.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    label, u, step = first
    k = u.shape[1]
    names = ("x", "y", "l")
    for c in range(k):
        b.plot(u[:, c], step[:, c], ".", ms=4, label=f"{names[c]} components")
    lim = max(np.abs(u).max(), np.abs(step).max(), 1e-300) * 1.05
    b.plot([-lim, lim], [-lim, lim], color="0.5", lw=0.8)
    b.set_xlim(-lim, lim)
    b.set_ylim(-lim, lim)
    b.set_aspect("equal")
    b.set_xlabel("nonaffine rate $du/d\\gamma$, theory ($u = J^{-1} \\Xi$) [$d$]")
    b.set_ylabel("nonaffine rate $du/d\\gamma$, step strain [$d$]")
    b.set_title(f"(b) {label} (cf. Ishima Fig. 3c)")
    b.legend(fontsize=8)
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    note(fig, UNITS + "; $l = R\\theta$ for the rotational components")
    return finish(fig, path, dpi=110)


def dos_figure(spectra, edges, path=None):
    """D(omega) (a) and the binned rotational participation psi^R = 1 - psi^T (b).

    ``spectra``: dicts with ``label``, ``k`` (dof per particle), ``omega``
    (modes), ``dos``, ``psi_t_mean``, ``psi_r_mean`` (per bin of ``edges``).
    """
    plt = pyplot()
    centres = np.sqrt(edges[:-1] * edges[1:])
    fig, (a, b) = plt.subplots(1, 2, figsize=(12, 5.2))
    for i, s in enumerate(spectra):
        colour = f"C{i % 10}"
        marker, size, ls = RUN_STYLES[i % len(RUN_STYLES)]
        kw = dict(color=colour, marker=marker, ms=size, ls=ls, lw=1.0, mfc="none", mew=1.1)
        d = np.where(s["dos"] > 0, s["dos"], np.nan)
        a.plot(centres, d, label=s["label"], **kw)
        empty = np.histogram(s["omega"], bins=edges)[0] == 0
        if s["k"] == 3:     # unit eigenvectors: psi^T = 1 - psi^R, one curve says both
            b.plot(centres, np.where(empty, np.nan, s["psi_r_mean"]), label=s["label"], **kw)
        else:
            b.plot([], [], label=f"{s['label']}: no rotations ($\\psi^R = 0$)", **kw)
    a.set_xscale("log")
    a.set_yscale("log")
    a.set_xlabel("$\\omega$ [$t_0^{-1}$]")
    a.set_ylabel("$D(\\omega)$ [$t_0$]")
    a.set_title("(a) density of states (cf. Ishima Fig. 9)")
    a.legend(fontsize=8, title="one marker per run; equal bands overlap",
             title_fontsize=7)
    b.set_xscale("log")
    b.set_ylim(-0.04, 1.04)
    b.set_xlabel("$\\omega$ [$t_0^{-1}$]")
    b.set_ylabel("rotational participation $\\psi^R = 1 - \\psi^T$ per bin [-]")
    b.set_title("(b) mode character (cf. Ishima Fig. 8)")
    b.legend(fontsize=8)
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    note(fig, UNITS + "; $D(\\omega)$ = modes per bin / (3N bin width), translations dropped")
    return finish(fig, path, dpi=110)
