"""Figures of ``fricstab chain ramp|dynamics|waves`` (matplotlib, Agg backend).

``ramp_figure``: real and imaginary parts of the eigenvalues of M^-1 J against
F_x, conjugate pairs in red, located events as vertical lines (Charan
Fig. 2).  ``dynamics_figure``: M(t) (Fig. 3), a disk's trajectory (Fig. 4)
and the centre of mass (Fig. 7).  ``wave_figure``: the realization-averaged
forward wave of Coulomb breaching and backward wave of sliding (Fig. 5).
Times and eigenvalues in Charan's units (length 2R, time sqrt(m 2R/kn)).
Each writes a PNG to ``path``.
"""

import numpy as np

__all__ = ["dynamics_figure", "ramp_figure", "wave_figure"]


def _pyplot():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def ramp_figure(res, events, unit2, path):
    """Charan Fig. 2 from a :class:`fricstab.protocols.ramp.RampResult`.

    ``events`` are the records of the ramp (dicts with ``fx`` and ``kind``),
    ``unit2`` the square of Charan's time unit (eigenvalues times it are in
    paper units).
    """
    plt = _pyplot()
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 6.5), sharex=True)
    w = res.eigenvalues * unit2
    top.plot(res.fx, w.real, color="0.75", lw=0.6)
    cplx = np.where(np.abs(w.imag) > 0, w.real, np.nan)
    top.plot(res.fx, cplx, color="C3", lw=1.4)
    bottom.plot(res.fx, np.where(w.imag > 0, w.imag, np.nan), color="C3", lw=1.4)
    for e in events:
        for ax in (top, bottom):
            ax.axvline(e["fx"], color="C0" if e["kind"] == "birth" else "C2", lw=0.6, ls="--")
    top.set_ylabel("Re eigenvalue of $M^{-1}J$ (paper units)")
    bottom.set_ylabel("Im eigenvalue (paper units)")
    bottom.set_xlabel("$F_x$")
    top.set_title("Chain ramp: complex pairs (red); births blue, deaths green")
    fig.tight_layout()
    fig.savefig(path, dpi=120, format="png")
    plt.close(fig)


def dynamics_figure(t, m, com, positions, disk, path):
    """Figs. 3, 4, 7: M(t), the trajectory of ``disk``, the centre of mass (t in paper units)."""
    plt = _pyplot()
    fig, axes = plt.subplots(1, 3, figsize=(14, 4))
    axes[0].semilogy(t[1:], m[1:])  # M(0) = 0
    axes[0].set_xlabel("t (paper units)")
    axes[0].set_ylabel("M(t) (2R)^2")
    axes[0].set_title("mean-square displacement (Fig. 3)")
    sc = axes[1].scatter(positions[:, disk, 0], positions[:, disk, 1], c=t, s=1, cmap="viridis")
    fig.colorbar(sc, ax=axes[1], label="t (paper units)")
    axes[1].set_xlabel("x (2R)")
    axes[1].set_ylabel("y (2R)")
    axes[1].set_title(f"trajectory of disk {disk} (Fig. 4)")
    axes[2].plot(t, com[:, 0] - com[0, 0], label="x")
    axes[2].plot(t, com[:, 1] - com[0, 1], label="y")
    axes[2].set_xlabel("t (paper units)")
    axes[2].set_ylabel("centre of mass - initial (2R)")
    axes[2].legend()
    axes[2].set_title("centre of mass (Fig. 7)")
    fig.tight_layout()
    fig.savefig(path, dpi=110, format="png")
    plt.close(fig)


def wave_figure(all_reals, path):
    """Charan Fig. 5: realization-averaged breach (upper) and sliding (lower) waves.

    ``all_reals`` maps F_x to a list of :class:`fricstab.protocols.waves.Realization`.
    """
    from fricstab.protocols.waves import nanmean
    plt = _pyplot()
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7, 8))
    for fx, reals in all_reals.items():
        dt = nanmean([r.tau - r.tau[0] for r in reals])
        dx = nanmean([r.x_tau - r.x_tau[0] for r in reals])
        top.plot(dt, dx, "o-", label=f"F_x = {fx}")
        dts = nanmean([r.tau_slide - r.tau_slide[-1] for r in reals])
        dxs = nanmean([r.x_slide - r.x_slide[-1] for r in reals])
        bottom.plot(dts, dxs, "o-", label=f"F_x = {fx}")
    top.set_xlabel("tau - tau_1 (paper units)")
    top.set_ylabel("x(tau) - x_1 (2R)")
    top.set_title("forward wave of Coulomb breaching (Fig. 5 upper)")
    bottom.set_xlabel("tau* - tau*_last (paper units)")
    bottom.set_ylabel("x* - x*_last (2R)")
    bottom.set_title("backward wave of sliding (Fig. 5 lower)")
    for ax in (top, bottom):
        ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110, format="png")
    plt.close(fig)
