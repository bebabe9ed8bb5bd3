"""The chain's transverse band against wavenumber (Charan Fig. 6 and the V2 prediction).

``transverse_band_figure``: each mode of a :class:`fricstab.analysis.modes.TransverseBand`
at its assigned wavenumber k = 2 pi m / N, its omega in Charan's units, coloured by its
y fraction and sized by its purity; the band's frequency of each wavelength
(``omega_by_m``) as a line; the paper's omega = 0.235 at k = pi and the line
omega = V2 k with V2 = 0.075 dashed.  Units are Charan's (length 2R, time
t_0 = sqrt(m 2R / k_n)); the function returns the Figure and with ``path`` writes
the PNG and closes it (:mod:`fricstab.figures.common`).
"""

import numpy as np

from fricstab.figures.common import finish, note, pyplot

__all__ = ["PAPER_OMEGA", "PAPER_V2", "transverse_band_figure"]

#: Charan p. 4: the transverse mode's omega ~ 0.235, wavelength ~ 2, V2 ~ 0.075.
PAPER_OMEGA = 0.235
PAPER_V2 = 0.075


def transverse_band_figure(band, path=None, title=None, marks=None):
    """omega against k for the band's modes (paper units), with the paper's mode and V2 line.

    Parameters
    ----------
    band : TransverseBand
    path : path-like, optional
        Write the PNG there (and close the figure).
    title : str, optional
    marks : dict, optional
        Label -> omega of other conventions' wavelength-2 frequencies, drawn at k = pi.

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    k = band.wavenumber
    sc = ax.scatter(k, band.omega, c=band.y_fraction, cmap="viridis", vmin=0, vmax=1,
                    s=20 + 80 * band.purity, edgecolors="k", linewidths=0.4, zorder=3,
                    label="band modes (size: purity)")
    fig.colorbar(sc, ax=ax, label=r"y fraction $|v_y|^2/|v|^2$ [-]")
    km = 2 * np.pi * np.arange(len(band.omega_by_m)) / band.n
    ax.plot(km, band.omega_by_m, "-", color="C1", lw=1.2, zorder=2,
            label=r"$\omega(k)$: y-power weighted mean")
    kk = np.linspace(0, np.pi * 1.05, 50)
    ax.plot(kk, PAPER_V2 * kk, "--", color="0.4", lw=1,
            label=rf"$\omega = V_2 k$, $V_2 = {PAPER_V2}$")
    ax.plot([np.pi], [PAPER_OMEGA], "*", color="C3", ms=13, zorder=4,
            label=rf"paper: $\omega = {PAPER_OMEGA}$, $k = \pi$")
    for i, (label, omega) in enumerate((marks or {}).items()):
        ax.plot([np.pi], [omega], "_", color=f"C{4 + i}", ms=16, mew=2, zorder=4,
                label=rf"{label}: $\omega(\pi)$ = {omega:.3f}")
    lo = min(np.nanmin(band.omega), PAPER_OMEGA)
    hi = max(np.nanmax(band.omega), PAPER_OMEGA)
    pad = max(0.1 * (hi - lo), 0.01)
    ax.set_ylim(lo - pad, hi + pad)
    ax.set_xlim(-0.1, np.pi * 1.08)
    ax.set_xlabel(r"wavenumber $k = 2\pi m/N$ [$(2R)^{-1}$]")
    ax.set_ylabel(r"$\omega = \sqrt{-\lambda}$ [$t_0^{-1}$]")
    ax.set_title(title or f"transverse band ({band.convention or 'M^-1 J'})", fontsize=10)
    ax.legend(fontsize=7, loc="upper left", framealpha=0.9)
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    note(fig, r"units (Charan): length $2R$, time $t_0=\sqrt{m\,2R/k_n}$; "
              r"wavelength $N/m$ in $2R$")
    return finish(fig, path)
