"""Figures of ``fricstab packing aqs`` and the AQS study (issue 17)."""

import numpy as np

__all__ = ["aqs_figure"]


def aqs_figure(res, drops, path):
    """Stress-strain curve with drops, pair count and growth rate, births marked."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(3, 1, figsize=(7, 7), sharex=True)
    ax[0].plot(res.strain, res.stress, "k-", lw=0.8)
    if drops:
        g = np.array([d.gamma for d in drops])
        ax[0].plot(g, np.interp(g, res.strain, res.stress), "rv", ms=4, label="drop onset")
        ax[0].legend(loc="best", fontsize=8)
    ax[0].set_ylabel(r"$\sigma_{xy}$ [$k_N d^{-1/2}$]")
    ax[1].step(res.strain, res.n_pairs, "b-", where="post", lw=0.8)
    ax[1].set_ylabel("complex pairs")
    births = [e.gamma for e in res.events if e.kind == "birth"]
    for b in births:
        ax[1].axvline(b, color="g", lw=0.4, alpha=0.5)
    ax[2].semilogy(res.strain, np.where(res.growth > 0, res.growth, np.nan), "m.", ms=2)
    ax[2].set_ylabel(r"growth rate [$t_0^{-1}$]")
    ax[2].set_xlabel(r"strain $\gamma$")
    fig.tight_layout()
    fig.savefig(path, format="png", dpi=110)
    plt.close(fig)
