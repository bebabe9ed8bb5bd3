"""Figures of ``fricstab chain ramp|dynamics|waves`` (matplotlib, Agg backend).

``ramp_figure``: real and imaginary parts of the eigenvalues of M^-1 J against
F_x, conjugate pairs in red, located events as vertical lines (Charan
Fig. 2).  ``dynamics_figure``: M(t) (Fig. 3), a disk's trajectory (Fig. 4)
and the centre of mass (Fig. 7).  ``wave_figure``: the realization-averaged
forward wave of Coulomb breaching and backward wave of sliding (Fig. 5) with
the fitted lines whose slopes are V1 and V2.

Units are Charan's: length 2R, time t_0 = sqrt(m 2R / k_n), force
k_n (2R)^(3/2) / 2000 (the simulation's units: m = 2R = 1, k_n = 2000, F_y = 0.1).  Disks are numbered from 1 as in the
paper (disk 1 is the pushed disk, index 0 of the arrays).  Each function
returns the Figure; with ``path`` it writes the PNG and closes it
(:mod:`fricstab.figures.common`).
"""

import numpy as np

from fricstab.figures.common import finish, note, pyplot

__all__ = ["LABELS", "dynamics_figure", "ramp_figure", "units_note", "wave_figure"]

#: The axis labels of the chain's quantities, in Charan's units (length 2R, time
#: t_0 = sqrt(m 2R / k_n), force k_n (2R)^{3/2} / 2000): the CLI's figures and the
#: tutorials take theirs from here, so one quantity has one label and one unit
#: (eigenvalues of M^-1 J in simulation units times ``time_unit(scene)**2``).
LABELS = {
    "fx": r"$F_x$ [$k_n (2R)^{3/2} / 2000$]",
    "re_lambda": r"Re $\lambda(M^{-1}J)$ [$t_0^{-2}$]",
    "im_lambda": r"Im $\lambda(M^{-1}J)$ [$t_0^{-2}$]",
    "growth": r"growth rate Im $\sqrt{-\lambda}$ [$t_0^{-1}$]",
}

UNITS = (r"units (Charan): length $2R$, time $t_0=\sqrt{m\,2R/k_n}$, force "
         r"$k_n (2R)^{3/2}/2000$ (the simulation's $k_n = 2000$, $F_y = 0.1$)")


def units_note(scene=None):
    """The figure's units line; with ``scene``, its own k_n and F_y (or how k_n is set).

    A law without a Hertz k_n (``lee_hurley``, and ``linear`` whose k_n is in
    force/length) takes the Hertz k_n with the same rest overlap as its unit of
    stiffness (:func:`fricstab.scenes.chain.reference_stiffness`).
    """
    head = (r"units (Charan): length $2R$, time $t_0=\sqrt{m\,2R/k_n}$, force "
            r"$k_n (2R)^{3/2}/2000$")
    if scene is None:
        return UNITS
    from fricstab.scenes.chain import reference_stiffness
    kn = reference_stiffness(scene)
    own = scene.params.get("kn")
    if own == kn:
        return head + rf" (this scene: $k_n = {kn:.6g}$, $F_y = {scene.fy:g}$)"
    what = ("has no Hertz $k_n$" if own is None else
            rf"has a linear $k_n = {own:.6g}$ (force/length)")
    return head + (rf" ({scene.law} {what}: $k_n = {kn:.6g}$ is the Hertz $k_n$ with its "
                   rf"rest overlap; $F_y = {scene.fy:g}$)")


def _events_to_curves(ax, fx, w, events):
    """Start each pair's Im curve at its located birth and end it at its located death
    (Im = 0 there), not at the grid steps around them."""
    fx = np.asarray(fx)
    for e in events:
        k = int(np.searchsorted(fx, e["fx"], side="right"))
        if not 0 < k < len(fx):
            continue
        before, after = w[k - 1].imag > 0, w[k].imag > 0
        if e["kind"] == "birth":
            for col in np.flatnonzero(after & ~before):
                ax.plot([e["fx"], fx[k]], [0.0, w[k, col].imag], color="C3", lw=1.4)
        else:
            for col in np.flatnonzero(before & ~after):
                ax.plot([fx[k - 1], e["fx"]], [w[k - 1, col].imag, 0.0], color="C3", lw=1.4)
        ax.plot([e["fx"]], [0.0], "o", color="C0" if e["kind"] == "birth" else "C2", ms=3)


#: How each spectrum convention (fricstab.scenes.chain.CONVENTIONS) names its matrix.
_MATRIX = {"physical": "M^{-1}J", "lammps": r"M^{-1}J,\ I = 2mR^2/5",
           "sm": r"M^{-1}J,\ I = mR^2", "bare": r"J/m"}


def ramp_figure(res, events, unit2, path=None, scene=None, convention="physical"):
    """Charan Fig. 2 from a ramp result (``res.fx`` (S,), ``res.eigenvalues`` (S, n)).

    ``events`` are the records of the ramp (dicts with ``fx`` and ``kind``),
    ``unit2`` the square of Charan's time unit (eigenvalues times it are in
    units of t_0^-2); ``scene`` (optional) names its k_n and F_y in the units line;
    ``convention`` the matrix whose spectrum it is (``bare``: J itself, per unit mass).
    Each pair's Im curve runs from its located birth to its located death; a
    ramp with no complex pair says so in the lower panel.
    """
    plt = pyplot()
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 6.5), sharex=True)
    w = np.asarray(res.eigenvalues) * unit2
    top.plot(res.fx, w.real, color="0.75", lw=0.6)
    cplx = np.where(np.abs(w.imag) > 0, w.real, np.nan)
    top.plot(res.fx, cplx, color="C3", lw=1.4)
    bottom.plot(res.fx, np.where(w.imag > 0, w.imag, np.nan), color="C3", lw=1.4)
    _events_to_curves(bottom, res.fx, w, events)
    if not np.any(w.imag > 0):
        bottom.text(0.5, 0.5, rf"no complex pair for $F_x \leq {np.max(res.fx):.4g}$: "
                    "every eigenvalue is real", transform=bottom.transAxes, ha="center",
                    va="center", fontsize=9)
    for e in events:
        for ax in (top, bottom):
            ax.axvline(e["fx"], color="C0" if e["kind"] == "birth" else "C2", lw=0.6, ls="--")
    from matplotlib.lines import Line2D
    handles = [Line2D([], [], color="0.75", lw=0.6, label="real eigenvalue"),
               Line2D([], [], color="C3", lw=1.4, label="complex pair"),
               Line2D([], [], color="C0", lw=0.6, ls="--", label="birth of a pair"),
               Line2D([], [], color="C2", lw=0.6, ls="--", label="death of a pair")]
    top.legend(handles=handles, fontsize=8, loc="lower left")
    matrix = _MATRIX.get(convention, "M^{-1}J")
    top.set_ylabel(LABELS["re_lambda"].replace("M^{-1}J", matrix))
    bottom.set_ylabel(LABELS["im_lambda"].replace("M^{-1}J", matrix))
    bottom.set_xlabel(LABELS["fx"])
    top.set_title("Chain ramp: eigenvalues against the pushing force (cf. Charan Fig. 2)")
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    note(fig, units_note(scene))
    return finish(fig, path, dpi=120)


def dynamics_figure(t, m, com, positions, disk, path=None):
    """Figs. 3, 4, 7: M(t), the trajectory of ``disk`` (0-based index), the centre of mass.

    ``t`` (T,) in t_0, ``m`` (T,) in (2R)^2, ``com`` (T, 2) and ``positions``
    (T, N, >=2) in 2R.  The disk is labelled ``disk + 1``: the paper's number.
    """
    plt = pyplot()
    fig, axes = plt.subplots(2, 2, figsize=(11, 7.5))
    (a, b), (c, d) = axes
    a.semilogy(t[1:], m[1:], color="C0", lw=0.7, rasterized=True)  # M(0) = 0
    a.set_xlabel(r"$t$ [$t_0$]")
    a.set_ylabel(r"$M(t)$ [$(2R)^2$]")
    a.set_title("(a) mean-square displacement (cf. Fig. 3)")
    sc = b.scatter(positions[:, disk, 0], positions[:, disk, 1], c=t, s=2, cmap="viridis",
                   rasterized=True)
    fig.colorbar(sc, ax=b, label=r"$t$ [$t_0$]")
    b.set_xlabel(r"$x$ [$2R$]")
    b.set_ylabel(r"$y$ [$2R$]")
    b.set_title(f"(b) trajectory of disk {disk + 1} of {positions.shape[1]} (cf. Fig. 4)")
    b.ticklabel_format(useOffset=False)
    c.plot(t, com[:, 0] - com[0, 0], color="C1")
    c.set_xlabel(r"$t$ [$t_0$]")
    c.set_ylabel(r"$x_{cm}(t) - x_{cm}(0)$ [$2R$]")
    c.set_title("(c) centre of mass, x (cf. Fig. 7)")
    d.plot(t, com[:, 1] - com[0, 1], color="C2", lw=0.5, rasterized=True)
    d.set_xlabel(r"$t$ [$t_0$]")
    d.set_ylabel(r"$y_{cm}(t) - y_{cm}(0)$ [$2R$]")
    d.set_title("(d) centre of mass, y")
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    note(fig, UNITS + "; disks numbered from 1 (the pushed disk) as in the paper")
    return finish(fig, path, dpi=110)


def _line(ax, dt, dx, style, label):
    """Averaged points and their least-squares line (slope = the reported speed).

    Returns the legend entry: (points, line) drawn on top of each other.
    """
    ok = np.isfinite(dt) & np.isfinite(dx)
    marker, colour = style
    (points,) = ax.plot(dt, dx, marker, color=colour, ls="none", ms=5)
    if ok.sum() >= 3 and np.ptp(dt[ok]) > 0:
        slope, icpt = np.polyfit(dt[ok], dx[ok], 1)
        span = np.array([dt[ok].min(), dt[ok].max()])
        (line,) = ax.plot(span, icpt + slope * span, color=colour, lw=1.2, label=label)
        return (points, line), label
    points.set_label(label + " (no fit: < 3 disks)")
    return (points,), points.get_label()


def _speed(name, fit, key):
    if fit is None:
        return name
    v, e = getattr(fit, key), getattr(fit, key + "_err")
    return f"{name} = {v:.3g} ± {e:.2g}"


def wave_figure(all_reals, path=None, fits=None):
    """Charan Fig. 5: realization-averaged breach (upper) and sliding (lower) waves.

    ``all_reals`` maps F_x to a list of :class:`fricstab.protocols.waves.Realization`;
    ``fits`` (optional) maps F_x to its :class:`~fricstab.protocols.waves.WaveFit`,
    whose V1, V2 and errors label the lines.  The lines are the least-squares fits
    of the plotted points: slope V1 (upper) and -V2 (lower) by construction.
    """
    from fricstab.protocols.waves import nanmean
    plt = pyplot()
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7.5, 8.5))
    styles = ("o", "s", "^", "D", "v", "P", "X", "*")
    entries = {top: [], bottom: []}
    for n, (fx, reals) in enumerate(all_reals.items()):
        style = (styles[n % len(styles)], f"C{n % 10}")
        fit = (fits or {}).get(fx)
        dt = nanmean([r.tau - r.tau[0] for r in reals])
        dx = nanmean([r.x_tau - r.x_tau[0] for r in reals])
        entries[top].append(_line(top, dt, dx, style,
                                  f"$F_x$ = {fx:g}: " + _speed("$V_1$", fit, "v1")))
        dts = nanmean([r.tau_slide - r.tau_slide[-1] for r in reals])
        dxs = nanmean([r.x_slide - r.x_slide[-1] for r in reals])
        entries[bottom].append(_line(bottom, dts, dxs, style,
                                     f"$F_x$ = {fx:g}: " + _speed("$V_2$", fit, "v2")))
    count = len(next(iter(all_reals.values()), []))
    top.set_xlabel(r"$\tau_i - \tau_1$ [$t_0$]")
    top.set_ylabel(r"$x_i(\tau_i) - x_1(\tau_1)$ [$2R$]")
    top.set_title(f"(a) forward wave of Coulomb breaching (cf. Fig. 5 upper), {count} "
                  "realizations", fontsize=10)
    last = len(next(iter(all_reals.values()))[0].tau) if all_reals else "N"
    bottom.set_xlabel(rf"$\tau^*_i - \tau^*_{{{last}}}$ [$t_0$]")
    bottom.set_ylabel(rf"$x^*_i - x^*_{{{last}}}$ [$2R$]")
    bottom.set_title("(b) backward wave of sliding (cf. Fig. 5 lower)", fontsize=10)
    from matplotlib.legend_handler import HandlerTuple
    for ax, rows in entries.items():
        ax.legend([h for h, _ in rows], [t for _, t in rows],
                  handler_map={tuple: HandlerTuple(ndivide=1)}, fontsize=8, title=r"points: mean over realizations; lines: fits, "
                  r"speeds in $2R/t_0$", title_fontsize=7)
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    note(fig, UNITS + "; disk i counted from 1 (the pushed disk)")
    return finish(fig, path, dpi=110)
