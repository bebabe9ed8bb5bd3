"""Runtime helpers of the Lee & Hurley plane-shear contact law (App. A).

The elastic part of the law is the generated ``fricstab.generated.lee_hurley``
(see its docstring and ``symbolic/laws.py::lee_hurley_pair`` for the sign
conventions).  The linear damping (A4, A11, A12, A19-A22) depends on masses
and inertias, which the kernels do not see; the DEM adds it with the
coefficients of :func:`damping_coefficients`.  Scalars, any consistent units
(2D: per unit thickness).
"""

import numpy as np

from fricstab._numba import kernel_jit

__all__ = ["damping_coefficients"]


@kernel_jit
def damping_coefficients(kn, kt, kr, mi, mj, Ii, Ij, Ri, Rj, alpha_n, alpha_t, eta_r):
    """Damping constants ``(gamma_n, gamma_t, C_r)`` of one contact.

    ``gamma_n = 2 alpha_n sqrt(k_n m*)`` (A4), ``gamma_t = 2 alpha_t sqrt(k_t m*)``
    (A12) with ``1/m* = 1/m_i + 1/m_j`` (A5); ``C_r = eta_r 2 sqrt(I_r k_r)``
    (A20, A21) with ``1/I_r = 1/(I_i + m_i R_i^2) + 1/(I_j + m_j R_j^2)`` (A22).
    A clamped (wall) particle may be passed with ``mj = Ij = inf``.

    Parameters
    ----------
    kn, kt, kr : float
        Secant normal, tangential and rolling stiffness (``lee_hurley_contact``
        out[2:5]).
    mi, mj, Ii, Ij, Ri, Rj : float
        Masses, moments of inertia about the centroids and radii.
    alpha_n, alpha_t, eta_r : float
        Damping ratios.

    Returns
    -------
    (gamma_n, gamma_t, C_r) : tuple of float
    """
    m_eff = 1.0 / (1.0 / mi + 1.0 / mj)
    i_eff = 1.0 / (1.0 / (Ii + mi * Ri * Ri) + 1.0 / (Ij + mj * Rj * Rj))
    return (2.0 * alpha_n * np.sqrt(kn * m_eff), 2.0 * alpha_t * np.sqrt(kt * m_eff),
            eta_r * 2.0 * np.sqrt(i_eff * kr))
