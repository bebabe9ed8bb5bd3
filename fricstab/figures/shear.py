"""Figures of the plane-shear analyses (Lee & Hurley Figs. 2-10, 13), matplotlib Agg.

Each function takes a :class:`fricstab.io.frames.Frames` and/or a
:class:`fricstab.analysis.shear.ShearAnalysis` and writes one PNG to ``path``.
Maps draw the cell with x wrapped into [0, lx); bonds crossing the periodic
boundary are drawn from particle i along the minimum-image vector.
"""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.collections import LineCollection, PatchCollection
from matplotlib.patches import Circle

from fricstab.analysis import shear as sa
from fricstab.laws import ParameterError

__all__ = ["fig_d2min_map", "fig_differential_network", "fig_force_network",
           "fig_gr_clusters", "fig_nonaffine", "fig_spearman_bins", "fig_step_panels",
           "fig_stress_strain"]


def _save(fig, path):
    fig.savefig(path, format="png", dpi=120)  # atomic writers pass a .tmp name
    plt.close(fig)


def _check_step(frames, k):
    if not 1 <= k < frames.n_frames:
        raise ParameterError(f"step k={k} must lie in [1, {frames.n_frames})")


def _disks(ax, frames, k, values=None, cmap="viridis", label=None):
    pos = frames.pos[k].copy()
    pos[:, 0] = np.mod(pos[:, 0], frames.lx)
    circles = [Circle(p, r) for p, r in zip(pos, frames.radius)]
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
    ax.set_xlim(-frames.radius.max(), frames.lx + frames.radius.max())
    ax.set_ylim(pos[:, 1].min() - 2 * frames.radius.max(), pos[:, 1].max() + 2 * frames.radius.max())
    ax.set_aspect("equal")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    return pos


def _bonds(frames, k, ij):
    pos = frames.pos[k].copy()
    pos[:, 0] = np.mod(pos[:, 0], frames.lx)
    d = pos[ij[:, 1]] - pos[ij[:, 0]]
    d[:, 0] -= frames.lx * np.round(d[:, 0] / frames.lx)
    return np.stack([pos[ij[:, 0]], pos[ij[:, 0]] + d], axis=1)


def fig_stress_strain(frames, path, result=None, half_width=20):
    """tau against strain (Fig. 2a), with the largest slip of ``result`` zoomed (Fig. 2b)."""
    ncols = 2 if result is not None and result.summary.get("largest_drop_steps") else 1
    fig, axes = plt.subplots(1, ncols, figsize=(5 * ncols, 3.6), squeeze=False)
    axes[0, 0].plot(frames.strain * 100, frames.tau, lw=0.6)
    axes[0, 0].set(xlabel="shear strain (%)", ylabel="tau = S/N")
    if ncols == 2:
        a, b = result.summary["largest_drop_steps"]
        lo, hi = max(a - 1 - half_width, 0), min(b + 1 + half_width, frames.n_frames)
        ax = axes[0, 1]
        ax.plot(frames.strain[lo:hi] * 100, frames.tau[lo:hi], "o-", ms=2, lw=0.8)
        ax.axvspan(frames.strain[a - 1] * 100, frames.strain[b] * 100, color="C3", alpha=0.2)
        ax.set(xlabel="shear strain (%)", ylabel="tau", title="largest slip")
        axes[0, 0].axvline(frames.strain[b] * 100, color="C3", lw=0.5)
    fig.tight_layout()
    _save(fig, path)


def fig_d2min_map(frames, k, path, d2=None, radius_factor=5.0):
    """D2min of step ``k`` per disk (Figs. 3-5, right column); rattlers colourless."""
    _check_step(frames, k)
    if d2 is None:
        rcut = radius_factor * frames.radius[frames.kind == 0].mean()
        d2 = sa.d2min(frames.pos[k - 1], frames.pos[k], frames.lx, rcut,
                      ~sa.rattler_mask(frames, k - 1))
    fig, ax = plt.subplots(figsize=(6, 4))
    _disks(ax, frames, k, np.asarray(d2, float), cmap="inferno", label="D2min")
    ax.set_title(f"D2min, step {k}")
    fig.tight_layout()
    _save(fig, path)


def fig_force_network(frames, k, path):
    """Force network of frame ``k`` (Fig. 6): bonds coloured by |f|."""
    ij, force, *_ = frames.contacts(k)
    fig, ax = plt.subplots(figsize=(6, 4))
    _disks(ax, frames, k)
    lc = LineCollection(_bonds(frames, k, ij), cmap="plasma")
    mag = np.hypot(force[:, 0], force[:, 1])
    lc.set_array(mag)
    lc.set_linewidth(0.5 + 2.5 * mag / max(mag.max(), 1e-300))
    ax.add_collection(lc)
    fig.colorbar(lc, ax=ax, label="|f|", shrink=0.7)
    ax.set_title(f"force network, frame {k}")
    fig.tight_layout()
    _save(fig, path)


def fig_differential_network(frames, k, path):
    """Differential force network of step ``k`` (Figs. 3-5): |f_k| - |f_k-1| per bond."""
    _check_step(frames, k)
    ij, *_ = frames.contacts(k)
    df = sa.differential_forces(frames, k)
    fig, ax = plt.subplots(figsize=(6, 4))
    _disks(ax, frames, k)
    lim = max(np.abs(df).max(), 1e-300)
    lc = LineCollection(_bonds(frames, k, ij), cmap="coolwarm", linewidth=1.2)
    lc.set_array(df)
    lc.set_clim(-lim, lim)
    ax.add_collection(lc)
    fig.colorbar(lc, ax=ax, label="|f_t| - |f_t-1|", shrink=0.7)
    ax.set_title(f"differential forces, step {k}")
    fig.tight_layout()
    _save(fig, path)


def fig_gr_clusters(frames, k, path, radius_factor=5.0, fraction=0.01):
    """GR particles of step ``k`` coloured by DBSCAN cluster (Figs. 3-5, left column)."""
    _check_step(frames, k)
    eps = radius_factor * frames.radius[frames.kind == 0].mean()
    gr = sa.gr_regions(frames, k, eps, fraction)
    fig, ax = plt.subplots(figsize=(6, 4))
    pos = _disks(ax, frames, k)
    for lab in np.unique(gr["labels"]):
        p = pos[gr["particles"][gr["labels"] == lab]]
        ax.scatter(p[:, 0], p[:, 1], s=25, color="k" if lab < 0 else f"C{lab % 10}",
                   label="noise" if lab < 0 else f"cluster {lab}", zorder=3)
    if len(gr["particles"]):
        ax.legend(fontsize=6, loc="upper right")
    ax.set_title(f"GR regions, step {k}: {gr['n_clusters']} cluster(s)")
    fig.tight_layout()
    _save(fig, path)


def fig_nonaffine(frames, k, path):
    """Non-affine displacement arrows of step ``k`` (Fig. 7), scaled per figure."""
    _check_step(frames, k)
    keep = ~sa.rattler_mask(frames, k - 1)
    na = sa.nonaffine_displacement(frames.pos[k - 1], frames.pos[k], keep)
    fig, ax = plt.subplots(figsize=(6, 4))
    pos = _disks(ax, frames, k)
    ok = np.isfinite(na[:, 0])
    ax.quiver(pos[ok, 0], pos[ok, 1], na[ok, 0], na[ok, 1], angles="xy", color="C3")
    ax.set_title(f"non-affine displacement, step {k}")
    fig.tight_layout()
    _save(fig, path)


def fig_step_panels(result, path, window=None):
    """Fig. 8: Spearman(|dsigma_p|, D2min), gD2min and g_t10%, GR clusters, |theta|."""
    a = result.arrays
    T = len(a["tau"])
    lo, hi = window or (1, T)
    s = slice(lo, hi)
    steps = np.arange(lo, hi)
    fig, axes = plt.subplots(4, 1, figsize=(6, 8), sharex=True)
    axes[0].plot(steps, a["rho_sigma_d2"][s], "o-", ms=3)
    axes[0].set_ylabel("rho(|dsigma_p|, D2min)")
    axes[1].semilogy(steps, a["g"][s], "o-", ms=3, label="gD2min")
    axes[1].semilogy(steps, a["g10"][s], "s-", ms=3, label="g_t10% D2min")
    axes[1].legend(fontsize=7)
    axes[2].plot(steps, a["n_clusters"][s], "o-", ms=3)
    axes[2].set_ylabel("GR clusters")
    axes[3].plot(steps, a["angle_mean"][s], "o-", ms=3, label="mean |theta|")
    axes[3].plot(steps, a["angle_median"][s], "s-", ms=3, label="median |theta|")
    axes[3].set(ylabel="rad", xlabel="step")
    axes[3].legend(fontsize=7)
    fig.tight_layout()
    _save(fig, path)


def fig_spearman_bins(table, path, title=""):
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
    ax.set(ylim=(0, 1.05), ylabel="|rho| (p <= 0.05)", xlabel="Delta tau bin", title=title)
    ax.legend(fontsize=7)
    fig.tight_layout()
    _save(fig, path)
