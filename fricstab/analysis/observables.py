"""Observables of a chain dynamics run (Charan Figs. 3, 4, 7 and the breach times).

From recorded frames of :func:`fricstab.protocols.dynamics.run_dynamics`:

* ``msd``: ``M(t) = sum_i |r_i(t) - r_i(0)|^2`` (Charan, Fig. 3);
* ``centre_of_mass``: ``(1/N) sum_i (x_i, y_i)`` (Fig. 7);
* ``first_breach``: per disk, the first recorded time at which its wall
  contact is at the Coulomb limit of the law (charan: ``|t_w| = t* = mu
  (kn/kt) delta``, Eq. 5; lee_hurley: ``|F_t| = mus F_n``, Eq. A10) or has
  lost contact (``delta <= 0``: no normal force, so ``t* <= 0``; the
  pre-engine test ``|t_w| >= t*`` counted a disk leaving the wall as
  breached, and so does this one), and the disk's x there (Fig. 5 upper
  panel, tau_i and x(tau_i)); NaN if never, and always for a law without a
  cap (hertz, ishima).  The history is put on the cap within the step that
  reaches it, so the law's own projection
  (:func:`fricstab.generated.dispatch.wall_project`, the kernel the engine
  applied) flags it there.

Times are returned in simulation units and in Charan's unit sqrt(m 2R/kn).
"""

import numpy as np

from fricstab._numba import kernel_jit
from fricstab.generated.dispatch import wall_project
from fricstab.scenes.chain import chain_system, time_unit

__all__ = ["at_coulomb_limit", "centre_of_mass", "first_breach", "msd", "paper_time"]


def paper_time(scene, t):
    """Simulation time -> Charan's unit sqrt(m 2R / kn) (kn: the reference stiffness)."""
    return np.asarray(t) / time_unit(scene)


def msd(positions):
    """M(t) over frames (frames, N, 3): translations only."""
    d = positions[:, :, :2] - positions[:1, :, :2]
    return (d ** 2).sum(axis=(1, 2))


def centre_of_mass(positions):
    """(frames, 2): mean x and y."""
    return positions[:, :, :2].mean(axis=1)


@kernel_jit
def _cap_flags(law, pw, y, radius, hist, scale, out):
    h = np.empty(max(hist.shape[2], 1))
    for f in range(y.shape[0]):
        for i in range(y.shape[1]):
            if y[f, i] >= radius[i]:   # off the wall: t* <= 0, breached
                out[f, i] = 1
                continue
            for k in range(hist.shape[2]):
                h[k] = hist[f, i, k] * scale
            out[f, i] = wall_project(law, y[f, i], radius[i], pw, h[:hist.shape[2]]) & 1


def at_coulomb_limit(scene, heights, wall_hist, rtol=1e-12):
    """(frames, N) bool: the wall history is at its tangential cap (to ``rtol``) or off the wall.

    ``heights`` (frames, N) the disks' y, ``wall_hist`` (frames, N, H) their
    wall histories.  The law's projection of the history scaled by
    ``1 + rtol`` reports whether it lies on the cap; a law without a cap
    never breaches.
    """
    system = chain_system(scene)
    hist = np.ascontiguousarray(wall_hist, dtype=float)
    if hist.ndim == 2:
        hist = hist[:, :, None]
    out = np.zeros(hist.shape[:2], np.int64)
    if hist.shape[2] == 0 or not len(hist) or not system.material.info.capped:
        return out.astype(bool)
    _cap_flags(system.law_id, system._pw, np.ascontiguousarray(heights, dtype=float),
               system.radius, hist, 1.0 + rtol, out)
    return out.astype(bool)


def first_breach(scene, times, positions, wall_hist, rtol=1e-12):
    """Per disk: (time, x) of the first frame at the Coulomb limit of the wall (module doc)."""
    at_limit = at_coulomb_limit(scene, positions[:, :, 1], wall_hist, rtol)
    tau = np.full(scene.n, np.nan)
    x = np.full(scene.n, np.nan)
    for i in range(scene.n):
        hit = np.flatnonzero(at_limit[:, i])
        if hit.size:
            tau[i] = times[hit[0]]
            x[i] = positions[hit[0], i, 0]
    return tau, x
