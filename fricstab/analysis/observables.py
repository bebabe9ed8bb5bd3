"""Observables of a chain dynamics run (Charan Figs. 3, 4, 7 and the breach times).

From recorded frames of :func:`fricstab.protocols.dynamics.run_dynamics`:

* ``msd``: ``M(t) = sum_i |r_i(t) - r_i(0)|^2`` (Charan, Fig. 3);
* ``centre_of_mass``: ``(1/N) sum_i (x_i, y_i)`` (Fig. 7);
* ``first_breach``: per disk, the first recorded time at which its wall
  contact is at the Coulomb limit, ``|t_w| = t*`` (to 1e-12 relative), and the
  disk's x there (Fig. 5 upper panel, tau_i and x(tau_i)); NaN if never.
  The history is rescaled onto the circle within the step that reaches it,
  so ``|t_w| = t*`` marks slip at the substrate.

Times are returned in simulation units and in Charan's unit sqrt(m 2R/kn).
"""

import numpy as np

__all__ = ["centre_of_mass", "first_breach", "msd", "paper_time"]


def paper_time(scene, t):
    """Simulation time -> Charan's unit sqrt(m 2R / kn)."""
    return np.asarray(t) / np.sqrt(scene.mass * 2 * scene.radius / scene.kn)


def msd(positions):
    """M(t) over frames (frames, N, 3): translations only."""
    d = positions[:, :, :2] - positions[:1, :, :2]
    return (d ** 2).sum(axis=(1, 2))


def centre_of_mass(positions):
    """(frames, 2): mean x and y."""
    return positions[:, :, :2].mean(axis=1)


def first_breach(scene, times, positions, wall_t, rtol=1e-12):
    """Per disk: (time, x) of the first frame at the Coulomb limit of the wall."""
    tstar = scene.mu * scene.kn / scene.kt * (scene.radius - positions[:, :, 1])
    at_limit = np.abs(wall_t) >= tstar * (1 - rtol)
    tau = np.full(scene.n, np.nan)
    x = np.full(scene.n, np.nan)
    for i in range(scene.n):
        hit = np.flatnonzero(at_limit[:, i])
        if hit.size:
            tau[i] = times[hit[0]]
            x[i] = positions[hit[0], i, 0]
    return tau, x
