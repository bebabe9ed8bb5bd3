"""Figures of the plane-shear analyses (Lee & Hurley Figs. 2-10, 13), matplotlib Agg.

Each function takes a :class:`fricstab.io.frames.Frames` and/or a
:class:`fricstab.analysis.shear.ShearAnalysis` (or plain arrays) and returns
the Figure; with ``path`` it writes the PNG and closes it
(:mod:`fricstab.figures.common`).  Maps draw the cell with x wrapped into
[0, lx); bonds crossing the periodic boundary are drawn from particle i
along the minimum-image vector.

Units: the cell is SI per unit thickness (frames: m, N/m, s); lengths,
forces and D2min are drawn in the SI prefix that fits the data (µm, mN/m,
nm^2...), named on the axis; strain in %, tau = S/N and rho are pure
numbers [-].
"""

import numpy as np
from matplotlib.collections import LineCollection, PatchCollection
from matplotlib.patches import Circle
from matplotlib.ticker import MaxNLocator

from fricstab.analysis import shear as sa
from fricstab.figures.common import finish, note, pyplot, si_scale
from fricstab.laws import ParameterError

__all__ = ["fig_d2min_map", "fig_differential_network", "fig_force_network",
           "fig_gr_clusters", "fig_nonaffine", "fig_shear_run", "fig_slip_spectra",
           "fig_spearman_bins", "fig_step_panels", "fig_stress_strain"]

plt = pyplot()
#: Above this many points a series is drawn as a thin rasterized line without markers.
MARKER_LIMIT = 200
TAU = r"$\tau = S/N$ [-]"
STRAIN = r"shear strain $\gamma$ [%]"


def _save(fig, path):
    return finish(fig, path, dpi=120)


def _series(ax, x, y, marker, n, smooth=False, ls="-", width=1.0, size=3, **kw):
    """A per-step series: markers while they can be told apart, else a thin line.

    With ``smooth`` (a series that flips between few values) and more than
    :data:`MARKER_LIMIT` steps, the thin line is faint and a running mean over
    n/50 steps is drawn on top of it.
    """
    if n <= MARKER_LIMIT:
        return ax.plot(x, y, marker + ls, ms=size, lw=0.8, **kw)
    if not smooth:
        return ax.plot(x, y, ls, lw=0.5, rasterized=True, **kw)
    label = kw.pop("label", None)
    ax.plot(x, y, "-", lw=0.4, alpha=0.35, rasterized=True, **kw)
    w = max(n // 50, 2)
    y = np.asarray(y, float)
    ok = np.isfinite(y)
    box = np.ones(w)
    mean = np.convolve(np.where(ok, y, 0.0), box, "same") / np.convolve(ok, box, "same")
    return ax.plot(x, mean, ls, lw=width, rasterized=True, label=label, **kw)


def _check_step(frames, k):
    if not 1 <= k < frames.n_frames:
        raise ParameterError(f"step k={k} must lie in [1, {frames.n_frames})")


def _length(frames):
    """Factor and prefixed unit of the map's lengths (frames in m)."""
    return si_scale([frames.lx], "m")


def _map_figure(frames, k):
    """A figure shaped like the cell (tall cells get tall figures), room for a colour bar."""
    y = frames.pos[k][:, 1]
    ratio = (np.ptp(y) + 4 * frames.radius.max()) / (frames.lx + 2 * frames.radius.max())
    return plt.subplots(figsize=(5.6, float(np.clip(4.2 * ratio + 0.9, 3.0, 9.0))))


def _disks(ax, frames, k, values=None, cmap="viridis", label=None):
    """Disks of frame ``k`` (x wrapped), coloured by ``values``; positions returned scaled."""
    scale, unit = _length(frames)
    pos = frames.pos[k].copy()
    pos[:, 0] = np.mod(pos[:, 0], frames.lx)
    pos *= scale
    radius = frames.radius * scale
    circles = [Circle(p, r) for p, r in zip(pos, radius)]
    if values is None:
        pc = PatchCollection(circles, facecolor="none", edgecolor="0.6", linewidth=0.4)
        ax.add_collection(pc)
    else:
        ok = np.isfinite(values)
        ax.add_collection(PatchCollection([c for c, o in zip(circles, ok) if not o],
                                          facecolor="none", edgecolor="0.7", linewidth=0.4))
        pc = PatchCollection([c for c, o in zip(circles, ok) if o], cmap=cmap,
                             edgecolor="none")
        pc.set_array(values[ok])
        ax.add_collection(pc)
        ax.figure.colorbar(pc, ax=ax, label=label, shrink=0.7)
    rmax = radius.max()
    ax.set_xlim(-rmax, frames.lx * scale + rmax)
    ax.set_ylim(pos[:, 1].min() - 2 * rmax, pos[:, 1].max() + 2 * rmax)
    ax.set_aspect("equal")
    ax.set_xlabel(f"$x$ [{unit}]")
    ax.set_ylabel(f"$y$ [{unit}]")
    return pos


def _bonds(frames, k, ij):
    pos = frames.pos[k].copy()
    pos[:, 0] = np.mod(pos[:, 0], frames.lx)
    d = pos[ij[:, 1]] - pos[ij[:, 0]]
    d[:, 0] -= frames.lx * np.round(d[:, 0] / frames.lx)
    return _length(frames)[0] * np.stack([pos[ij[:, 0]], pos[ij[:, 0]] + d], axis=1)


def fig_stress_strain(frames, path=None, result=None, half_width=20):
    """tau against strain (Fig. 2a), with the largest slip of ``result`` zoomed (Fig. 2b)."""
    ncols = 2 if result is not None and result.summary.get("largest_drop_steps") else 1
    fig, axes = plt.subplots(1, ncols, figsize=(5 * ncols, 3.6), squeeze=False)
    axes[0, 0].plot(frames.strain * 100, frames.tau, lw=0.6, color="k")
    axes[0, 0].set(xlabel=STRAIN, ylabel=TAU, title="stress ratio (cf. Lee & Hurley Fig. 2a)")
    if ncols == 2:
        a, b = result.summary["largest_drop_steps"]
        lo, hi = max(a - 1 - half_width, 0), min(b + 1 + half_width, frames.n_frames)
        ax = axes[0, 1]
        ax.plot(frames.strain[lo:hi] * 100, frames.tau[lo:hi], "o-", ms=2, lw=0.8, color="k")
        ax.axvspan(frames.strain[a - 1] * 100, frames.strain[b] * 100, color="C3", alpha=0.2)
        ax.set(xlabel=STRAIN, ylabel=TAU, title="largest slip (shaded; cf. Fig. 2b)")
        axes[0, 0].axvline(frames.strain[b] * 100, color="C3", lw=0.5)
    for ax in axes[0]:
        ax.ticklabel_format(axis="x", useOffset=False)
    fig.tight_layout()
    return _save(fig, path)


def fig_d2min_map(frames, k, path=None, d2=None, radius_factor=5.0):
    """D2min of step ``k`` per disk (Figs. 3-5, right column); rattlers colourless."""
    _check_step(frames, k)
    if d2 is None:
        rcut = radius_factor * frames.radius[frames.kind == 0].mean()
        d2 = sa.d2min(frames.pos[k - 1], frames.pos[k], frames.lx, rcut,
                      ~sa.rattler_mask(frames, k - 1))
    d2 = np.asarray(d2, float)
    scale, unit = si_scale(d2, "m", 2)
    fig, ax = _map_figure(frames, k)
    _disks(ax, frames, k, d2 * scale, cmap="inferno", label=f"$D^2_{{min}}$ [{unit}]")
    ax.set_title(f"$D^2_{{min}}$ of step {k} (cf. Lee & Hurley Figs. 3-5); "
                 "outlined: wall disks, rattlers", fontsize=9)
    fig.tight_layout()
    return _save(fig, path)


def fig_force_network(frames, k, path=None):
    """Force network of frame ``k`` (Fig. 6): bonds coloured by |f|."""
    ij, force, *_ = frames.contacts(k)
    fig, ax = _map_figure(frames, k)
    _disks(ax, frames, k)
    lc = LineCollection(_bonds(frames, k, ij), cmap="plasma")
    mag = np.hypot(force[:, 0], force[:, 1])
    scale, unit = si_scale(mag, "N/m")
    lc.set_array(mag * scale)
    lc.set_linewidth(0.5 + 2.5 * mag / max(mag.max(), 1e-300))
    ax.add_collection(lc)
    fig.colorbar(lc, ax=ax, label=f"$|f|$ [{unit}]", shrink=0.7)
    ax.set_title(f"force network, frame {k} (cf. Lee & Hurley Fig. 6); width ~ $|f|$",
                 fontsize=9)
    fig.tight_layout()
    return _save(fig, path)


def _differential(ax, frames, k, ij, **style):
    """The differential force network of step ``k`` on ``ax`` with its colour bar.

    Returns the differences |f_k| - |f_k-1| per bond (N/m) and the bonds' segments.
    """
    df = sa.differential_forces(frames, k)
    scale, unit = si_scale(df, "N/m")
    lim = max(np.abs(df).max() * scale, 1e-300)
    bonds = _bonds(frames, k, ij)
    lc = LineCollection(bonds, cmap="coolwarm", **style)
    lc.set_array(df * scale)
    lc.set_clim(-lim, lim)
    ax.add_collection(lc)
    ax.figure.colorbar(lc, ax=ax, label=f"$|f_k| - |f_{{k-1}}|$ [{unit}]", shrink=0.7)
    return df, bonds


def fig_differential_network(frames, k, path=None):
    """Differential force network of step ``k`` (Figs. 3-5): |f_k| - |f_k-1| per bond."""
    _check_step(frames, k)
    ij, *_ = frames.contacts(k)
    fig, ax = _map_figure(frames, k)
    _disks(ax, frames, k)
    _differential(ax, frames, k, ij, linewidth=1.2)
    ax.set_title(f"differential forces, step {k} (cf. Lee & Hurley Figs. 3-5)", fontsize=9)
    fig.tight_layout()
    return _save(fig, path)


def fig_gr_clusters(frames, k, path=None, radius_factor=5.0, fraction=0.01):
    """GR regions of step ``k`` (Figs. 3-5, left column) on its differential force network.

    The network (|f_k| - |f_k-1| per bond, faint) gives the context; the GR
    contacts (the ``fraction`` of contacts with the greatest force reduction) are
    drawn thick, and their disks filled at their true size in their DBSCAN
    cluster's colour (black: noise), so a handful of GR disks is still a map.
    """
    _check_step(frames, k)
    eps = radius_factor * frames.radius[frames.kind == 0].mean()
    gr = sa.gr_regions(frames, k, eps, fraction)
    ij, *_ = frames.contacts(k)
    fig, ax = _map_figure(frames, k)
    pos = _disks(ax, frames, k)
    df, bonds = _differential(ax, frames, k, ij, linewidth=0.8, alpha=0.45)
    ax.add_collection(LineCollection([bonds[c] for c in gr["contacts"]], colors="k",
                                     linewidth=2.4, zorder=4))
    radius = frames.radius * _length(frames)[0]
    for lab in np.unique(gr["labels"]):
        members = gr["particles"][gr["labels"] == lab]
        colour = "k" if lab < 0 else f"C{lab % 10}"
        ax.add_collection(PatchCollection([Circle(pos[i], radius[i]) for i in members],
                                          facecolor=colour, edgecolor="k", alpha=0.8,
                                          linewidth=0.6, zorder=3))
        ax.plot([], [], "o", color=colour, label="noise" if lab < 0 else f"cluster {lab + 1}")
    if len(gr["particles"]):
        ax.legend(fontsize=6, loc="upper right")
    ax.set_title(f"GR regions, step {k}: {gr['n_clusters']} cluster(s) of "
                 f"{len(gr['particles'])} disks (cf. Lee & Hurley Figs. 3-5)", fontsize=9)
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    note(fig, f"GR: the {100 * fraction:g} % of contacts with the greatest force reduction "
              f"({len(gr['contacts'])} of {len(df)}, thick); DBSCAN eps = "
              f"{radius_factor:g} mean radii")
    return _save(fig, path)


def fig_nonaffine(frames, k, path=None):
    """Non-affine displacement arrows of step ``k`` (Fig. 7), scaled per figure (key arrow)."""
    _check_step(frames, k)
    keep = ~sa.rattler_mask(frames, k - 1)
    na = sa.nonaffine_displacement(frames.pos[k - 1], frames.pos[k], keep)
    fig, ax = _map_figure(frames, k)
    pos = _disks(ax, frames, k)
    ok = np.isfinite(na[:, 0])
    scale, unit = si_scale(np.hypot(na[ok, 0], na[ok, 1]), "m")
    q = ax.quiver(pos[ok, 0], pos[ok, 1], scale * na[ok, 0], scale * na[ok, 1], color="C3")
    longest = float(np.hypot(na[ok, 0], na[ok, 1]).max() * scale) if ok.any() else 1.0
    ax.quiverkey(q, 0.84, 1.03, longest, f"{longest:.3g} {unit}", labelpos="E",
                 fontproperties={"size": 8})
    ax.set_title(f"non-affine displacement, step {k} (cf. Fig. 7)", loc="left", fontsize=8)
    fig.tight_layout()
    return _save(fig, path)


def fig_step_panels(result, path=None, window=None):
    """Fig. 8: Spearman(|dsigma_p|, D2min), gD2min and g_t10%, GR clusters, |theta|.

    ``result.arrays`` holds per output step ``tau``, ``rho_sigma_d2``, ``g``,
    ``g10`` (m^2), ``n_clusters``, ``angle_mean``, ``angle_median`` (rad).
    More than :data:`MARKER_LIMIT` steps are drawn as thin rasterized lines.
    """
    a = result.arrays
    T = len(a["tau"])
    lo, hi = window or (1, T)
    s = slice(lo, hi)
    steps = np.arange(lo, hi)
    n = len(steps)
    scale, unit = si_scale(np.concatenate([a["g"][s], a["g10"][s]]), "m", 2)
    fig, axes = plt.subplots(4, 1, figsize=(7, 8.5), sharex=True)
    _series(axes[0], steps, a["rho_sigma_d2"][s], "o", n, color="C0")
    axes[0].set_ylabel(r"$\rho(|\Delta\sigma_p|, D^2_{min})$ [-]")
    axes[0].set_title(f"per output step, steps {lo}-{hi - 1} (cf. Lee & Hurley Fig. 8)",
                      fontsize=9)
    _series(axes[1], steps, a["g"][s] * scale, "o", n, color="C0", label=r"$gD^2_{min}$")
    _series(axes[1], steps, a["g10"][s] * scale, "s", n, color="C1",
            label=r"$g_{t10\%}D^2_{min}$")
    axes[1].set_yscale("log")
    axes[1].set_ylabel(f"$D^2_{{min}}$ [{unit}]")
    axes[1].legend(fontsize=7)
    _series(axes[2], steps, a["n_clusters"][s], "o", n, smooth=True, color="C2")
    axes[2].set_ylabel("GR clusters [-]")
    axes[2].yaxis.set_major_locator(MaxNLocator(integer=True))
    _series(axes[3], steps, a["angle_mean"][s], "o", n, smooth=True, color="C3", width=2.2,
            size=7, mfc="none", label=r"mean $|\theta|$")
    _series(axes[3], steps, a["angle_median"][s], "s", n, smooth=True, ls="--", color="C4",
            label=r"median $|\theta|$")
    axes[3].set(ylabel=r"GR contact angle $|\theta|$ [rad]", xlabel="output step $k$ [-]")
    axes[3].legend(fontsize=7)
    if n > MARKER_LIMIT:
        fig.tight_layout(rect=(0, 0.025, 1, 1))
        note(fig, f"GR clusters and angles: faint, per step; bold, running mean over "
                  f"{max(n // 50, 2)} steps")
    else:
        fig.tight_layout()
    return _save(fig, path)


def fig_spearman_bins(table, path=None, title=""):
    """|rho| per Delta tau bin (Figs. 9, 10, 13); only cells with p <= 0.05 are drawn.

    ``table`` is ``{series name: [cells]}`` as from
    :func:`fricstab.analysis.shear.binned_spearman`.
    """
    fig, ax = plt.subplots(figsize=(6, 3.6))
    labels = None
    for n, (name, cells) in enumerate(table.items()):
        labels = [f"({c['lo']:.0e},{c['hi']:.0e})" for c in cells]
        y = [abs(c["rho"]) if c["rho"] is not None and c["significant"] else np.nan
             for c in cells]
        ax.plot(np.arange(len(cells)), y, "o-", color=f"C{n}", label=name)
    ax.set_xticks(np.arange(len(labels or [])), labels or [], rotation=45, fontsize=7)
    ax.set(ylim=(0, 1.05), ylabel=r"Spearman $|\rho|$ (p $\leq$ 0.05) [-]",
           xlabel=r"$\Delta\tau$ bin [-]", title=title)
    ax.legend(fontsize=7)
    fig.tight_layout()
    return _save(fig, path)


def fig_shear_run(strain, tau, phases_from, path=None):
    """``shear.png``: tau = S/N against strain, the analysed window's start marked."""
    fig, ax = plt.subplots(figsize=(7, 3.5), constrained_layout=True)
    ax.plot(100 * np.asarray(strain), tau, lw=0.6, color="k")
    ax.axvline(100 * phases_from, color="C1", lw=0.8, ls="--",
               label=r"start of the stick-slip window $\gamma_0$")
    ax.set_xlabel(STRAIN)
    ax.set_ylabel(TAU)
    ax.legend(loc="lower right", frameon=False)
    return finish(fig, path, dpi=130)


def fig_slip_spectra(a, path=None, sp=None):
    """``analysis_slip_spectra.png``: complex pairs and growth rate of J before each slip.

    ``a``: arrays ``slip_dtau_p`` (< 0), ``slip_n_complex_pairs``,
    ``slip_max_growth_rate`` (1/s), one entry per slip; ``sp``: the spectra
    record (``route``, ``k``), named in the title.
    """
    d = np.asarray(a.get("slip_dtau_p", []))
    fig, ax = plt.subplots(1, 2, figsize=(8, 3.4), constrained_layout=True)
    where = ("" if sp is None else ": whole spectrum (dense)" if sp.get("route") == "dense"
             else f": the {sp.get('k')} softest modes (shift-invert ARPACK)")
    fig.suptitle("Jacobian before each slip" + where, fontsize=10)
    scale, unit = si_scale(a.get("slip_max_growth_rate", []), "s", -1)
    for axis, key, label, f in ((ax[0], "slip_n_complex_pairs", "complex pairs [-]", 1.0),
                                (ax[1], "slip_max_growth_rate",
                                 f"largest growth rate [{unit}]", scale)):
        if key in a and d.size:
            axis.scatter(-d, f * np.asarray(a[key], float), s=8)
        axis.set_xscale("log")
        axis.set_xlabel(r"$-\Delta\tau_p$ of the following slip [-]")
        axis.set_ylabel(label)
    return finish(fig, path, dpi=120)
