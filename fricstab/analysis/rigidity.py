"""Shear rigidity G = G_A + G_NA of a frictional packing from its Jacobian.

Ishima et al. (2023), Sec. III B and App. G, in their convention (see
:mod:`fricstab.scenes.pack_system`): ``J = -dF/dq``, coordinates (x, y, l) per
particle.  An affine step strain ``dgamma`` moves every contact's ``dx`` by
``dgamma * y_ij`` at frozen history; the nonaffine rate ``u = dq/dgamma``
then solves

    J u = Xi,   Xi = dF/dgamma|_affine  (Eqs. 34-35, G14),

and, with the stress of Eq. 14,

    G_A  = -(1/L^2) sum_c y_c dF^x_c/dgamma|_affine       (Eqs. 40, 46),
    G_NA = -(1/L^2) Theta . u                              (Eqs. 41, 44),
    Theta_k = -sum_c y_c J_c[x_i, k] + F^x_i delta_{k, y_i} (Eq. 45),

where the sum runs over contacts c = (i, j) with ``y_c = y_i - y_j`` and
``J_c`` the contact's block (rows of particle i).

The last term of Theta vanishes in force balance (App. G, Eq. G23); it is kept
so that the formula is the exact strain derivative of Eq. 14.

**The modified Jacobian.**  The paper replaces J by J~ with sign flips
(Eqs. 36-37).  ``validation/errata.md`` shows from the paper's own Appendix G
that the exact relation is ``J u = Xi`` with the Eq.-18 Jacobian, i.e.
``J~ = J``; the flipped matrix of Eqs. 36-37 is available as
:func:`ishima_flipped` so that the difference can be measured, and the tests
show that only ``J~ = J`` matches step-strain simulation.

``J`` has the zero modes ``e_x``, ``e_y`` (App. C) on both sides
(``e_x^T J = 0``: the total force does not depend on q).  The direct route
solves the bordered system ``[J C; C^T 0] [u; mu] = [Xi; 0]`` with
``C = (e_x, e_y)``, i.e. on the complement of the zero modes; the mode sum
(Eq. 38, 44) excludes the same two modes.  Rattlers are removed before
(:func:`fricstab.scenes.pack_system.backbone`).

Conventions of the exported vectors: ``xi`` and ``theta`` here are Ishima's
``|Xi>`` and ``<Theta|`` with ``J~ = J``, so that ``G_NA = -Theta . J^+ Xi / L^2``.
"""

import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sps
import scipy.sparse.linalg as spla

from fricstab.analysis.dos import spectrum
from fricstab.scenes.pack_system import (affine_rates, assemble, contact_dofs, ndof, network,
                                  sparse_jacobian)

__all__ = ["Rigidity", "ishima_flipped", "linear_response", "mode_sum", "rigidity",
           "solve_nonaffine", "zero_modes"]


@dataclass(frozen=True)
class Rigidity:
    """Linear-response rigidity of one backbone at one ``kt/kn``."""

    kt: float
    box: float
    g_a: float
    g_na_solve: float
    g_na_modes: float = float("nan")
    jacobian: object = None          # scipy.sparse CSR, J~ = J
    xi: np.ndarray = None
    theta: np.ndarray = None
    u: np.ndarray = None             # nonaffine rate dq/dgamma (direct solve)
    checks: dict = field(default_factory=dict)
    seconds: dict = field(default_factory=dict)

    @property
    def g(self):
        """G = G_A + G_NA (direct solve)."""
        return self.g_a + self.g_na_solve

    @property
    def g_modes(self):
        """G = G_A + G_NA (mode sum)."""
        return self.g_a + self.g_na_modes


def zero_modes(n, k):
    """``e_x``, ``e_y`` (App. C, Eqs. C6, C8) as columns, normalized."""
    c = np.zeros((n * k, 2))
    c[0::k, 0] = 1.0
    c[1::k, 1] = 1.0
    return c / np.sqrt(n)


def linear_response(bb, kt, net=None):
    """``J``, ``Xi``, ``Theta``, ``G_A`` and force residual of backbone ``bb``."""
    k = ndof(kt)
    if net is None:
        net = network(bb.pos, bb.radius, bb.box)
    forces, blocks = assemble(net, bb.radius, kt)
    jac = sparse_jacobian(net.pairs, blocks, bb.n, kt)
    dofs = contact_dofs(net.pairs, k)
    y = net.sep[:, 1]
    rates = affine_rates(net, bb.radius, kt) * y[:, None]   # dF_c/dgamma, affine
    xi = np.zeros(bb.n * k)
    np.add.at(xi, dofs.ravel(), rates.ravel())
    g_a = -(y * rates[:, 0]).sum() / bb.box**2
    theta = np.zeros(bb.n * k)
    # Theta_k = sum_c y_c K_c[x_i, k] + F^x_i delta_{k, y_i}, K_c = dF_c/dq = -J_c
    np.add.at(theta, dofs.ravel(), (blocks[:, 0, :] * y[:, None]).ravel())
    theta[1::k] += forces[:, 0]
    return jac, xi, theta, g_a, forces


def solve_nonaffine(jac, xi, n, k):
    """``u`` with ``J u = Xi`` on the complement of the zero modes (bordered LU).

    Returns ``u`` and the two multipliers, which measure the part of ``Xi``
    along the left zero modes (zero up to round-off: the total force of an
    affine strain vanishes).
    """
    c = zero_modes(n, k)
    a = sps.bmat([[jac, sps.csr_matrix(c)], [sps.csr_matrix(c.T), None]], format="csc")
    sol = spla.spsolve(a, np.concatenate([xi, np.zeros(2)]))
    return sol[:-2], sol[-2:]


def ishima_flipped(jac, k=3):
    """J~ as printed in Ishima Eqs. 36-37 (sign flips), for comparison only."""
    coo = jac.tocoo()
    ri, ci = coo.row // k, coo.col // k
    ra, ca = coo.row % k, coo.col % k
    flip = ((ri == ci) & (ra == 2) & (ca < 2)) | ((ri != ci) & (ra < 2) & (ca == 2))
    data = np.where(flip, -coo.data, coo.data)
    return sps.csr_matrix((data, (coo.row, coo.col)), shape=jac.shape)


def mode_sum(jac, xi, theta, box, k, route="auto", n_zero=2):
    """``G_NA`` by the eigenmode sum (Eq. 44), excluding the ``n_zero`` zero modes.

    ``route``: ``"symmetric"`` (``eigh``; exact when J = J^T, which holds when
    the tangential histories vanish), ``"dense"`` (``eig`` with left and right
    vectors, biorthonormalized), or ``"auto"`` (symmetric when
    ``max|J - J^T| <= 1e-12 max|J|``).  Returns ``G_NA`` and checks.
    """
    sp = spectrum(jac, route)
    w, left, right = sp.eigenvalues, sp.left, sp.right
    order = np.argsort(np.abs(w))
    zero, rest = order[:n_zero], order[n_zero:]
    biortho = np.abs(left[:, rest].conj().T @ right[:, rest] - np.eye(len(rest))).max()
    # The excluded modes must be the translations: check their span.
    c = zero_modes(len(w) // k, k)
    q, _ = np.linalg.qr(right[:, zero])
    span_err = np.linalg.norm(c - q @ (q.conj().T @ c))
    coef = (left[:, rest].conj().T @ xi) / w[rest]
    g_na = -(theta @ (right[:, rest] @ coef)).real / box**2
    gap = np.abs(w[rest]).min() / max(np.abs(w[zero]).max(), np.finfo(float).tiny)
    return g_na, {"route": sp.route, "asymmetry": sp.asymmetry,
                  "biorthonormality": float(biortho), "zero_mode_span_error": float(span_err),
                  "zero_gap": float(gap), "max_imag": sp.max_imag, "seconds": sp.seconds,
                  "eigenvalues": np.sort(np.real(w))}


def rigidity(bb, kt, modes=False, route="auto"):
    """G_A and G_NA of backbone ``bb`` at ``kt/kn`` by direct solve (and mode sum)."""
    k = ndof(kt)
    t0 = time.perf_counter()
    jac, xi, theta, g_a, forces = linear_response(bb, kt)
    t1 = time.perf_counter()
    u, mult = solve_nonaffine(jac, xi, bb.n, k)
    t2 = time.perf_counter()
    g_na = -(theta @ u) / bb.box**2
    c = zero_modes(bb.n, k)
    scale = abs(jac).max()
    checks = {"zero_mode_residual": float(np.abs(jac @ c).max() * np.sqrt(bb.n) / scale),
              "left_zero_mode_residual": float(np.abs(jac.T @ c).max() * np.sqrt(bb.n) / scale),
              "max_force": float(np.abs(forces).max()),
              "solve_residual": float(np.abs(jac @ u - xi).max() / np.abs(xi).max()),
              "multipliers": float(np.abs(mult).max())}
    seconds = {"assemble": t1 - t0, "solve": t2 - t1}
    g_na_modes = float("nan")
    if modes:
        g_na_modes, info = mode_sum(jac, xi, theta, bb.box, k, route)
        checks.update({f"modes_{key}": v for key, v in info.items() if key != "eigenvalues"})
        seconds["modes"] = info["seconds"]
    return Rigidity(kt, bb.box, g_a, float(g_na), float(g_na_modes), jac, xi, theta, u,
                    checks, seconds)
