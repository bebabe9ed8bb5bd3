"""Energy of a packing under the ``hertz`` or ``ishima`` law (Ishima Eqs. 7-9), for dynamics checks.

Kinetic energy ``sum 1/2 gmass v^2`` over the law's dof (generalized masses
``(m, m, I/s^2)``; Ishima's ``l = R theta`` has mass ``I/R^2 = m/2``), plus per
touching contact the Hertz energy ``2/5 k_N xi^(5/2)`` and, for ``ishima``,
the tangential spring ``1/2 k_T xi^(1/2) |t|^2``.  Units of
:mod:`fricstab.scenes.packing`: ``k_N d^(5/2)``.

The tangential term is the energy of the law at fixed overlap; the law is not
derived from a potential (its stiffness follows ``xi``), so the total is
conserved only up to ``(k_T / 4) xi^(-1/2) |t|^2 d xi`` summed over a run,
besides the ``O(dt^2)`` error of velocity Verlet.  The other laws have no
such energy (a Coulomb cap dissipates) and are refused.
"""

import numpy as np

from fricstab.scenes.packing_relax import separations
from fricstab.errors import ParameterError

__all__ = ["energy"]


def energy(system, state):
    """Kinetic + elastic energy of ``state`` (module docstring)."""
    law = system.material.law
    if law not in ("hertz", "ishima"):
        raise ParameterError(f"energy: law {law} has no energy function (hertz and ishima do)")
    dof = system.dof
    e = 0.5 * np.sum(system.gmass[:, :dof] * state.v[:, :dof] ** 2)
    c = state.contacts
    pair = c.j >= 0
    sep = separations(system, state)[pair]
    r = system.radius
    xi = r[c.i[pair]] + r[c.j[pair]] - np.hypot(sep[:, 0], sep[:, 1])
    on = xi > 0
    kn = system.material.params["kn"]
    e += np.sum(0.4 * kn * xi[on] ** 2.5)
    if law == "ishima":
        t2 = np.sum(c.hist[pair][on] ** 2, axis=1)
        e += np.sum(0.5 * system.material.params["kt"] * np.sqrt(xi[on]) * t2)
    return float(e)
