"""Shear rigidity G = G_A + G_NA of a packing from its Jacobian, for any contact law.

Ishima et al. (2023), Sec. III B and App. G, in their convention whatever the
law: coordinates ``(x, y, l = R theta)`` per particle (``(x, y)`` for the
frictionless ``hertz``), generalized forces ``(F_x, F_y, F^l = T/R)`` and
``J = -dF/dq`` (Eq. 18).  The engine works in the law's own rotation
coordinate ``r = s theta`` (:mod:`fricstab.engine.system`; ``s = R`` for
``ishima``, 1 for ``charan`` and ``lee_hurley``); with ``c_i = R_i / s_i`` and
``C = diag(1, 1, c_i)`` per particle, ``l = C r`` and

    J = -C^-1 K C^-1,   Xi = C^-1 Xi_r,   Theta = C^-1 Theta_r,   u = C u_r,

a congruence that leaves G unchanged (``Theta . u`` is invariant) and makes
the spectra of different laws comparable (ishima and charan with the same
``kt`` have the same J at zero history).

An affine step strain ``dgamma`` moves every contact's ``dx`` by
``dgamma * y_c`` at frozen history; the nonaffine rate ``u = dq/dgamma`` then
solves

    J u = Xi,   Xi = dF/dgamma|_affine  (Eqs. 34-35, G14),

and, with the stress of Eq. 14,

    G_A  = -(1/L^2) sum_c y_c dF^x_c/dgamma|_affine       (Eqs. 40, 46),
    G_NA = -(1/L^2) Theta . u                              (Eqs. 41, 44),
    Theta_k = sum_c y_c K_c[x_i, k] + F^x_i delta_{k, y_i}  (Eq. 45),

where the sum runs over contacts c = (i, j) with ``y_c`` the y component of
``r_i - r_j`` (images included) and ``K_c`` the contact's block ``dF/dq``
(engine, with the increment rule).  ``dF_c/dgamma|_affine`` is a complex step
through the law's verified scalar force kernel (``LawInfo.force``, called by
argument name, so it is generic over laws): exact to round-off, and through
a Coulomb cap it follows the cap as the engine's blocks do.  The last term of
Theta vanishes in force balance (App. G, Eq. G23); it is kept so that the
formula is the exact strain derivative of Eq. 14.

**The modified Jacobian.**  The paper replaces J by J~ with sign flips
(Eqs. 36-37).  ``validation/errata.md`` shows from the paper's own Appendix G
that the exact relation is ``J u = Xi`` with the Eq.-18 Jacobian, i.e.
``J~ = J``; the flipped matrix is :func:`ishima_flipped`, so that the
difference can be measured.

``J`` has the zero modes ``e_x``, ``e_y`` (App. C) on both sides.  G_NA is
computed by :func:`fricstab.engine.newton.bordered_solve` with those
translations, i.e. on their complement; the mode sum (Eq. 38, 44) excludes
the same two modes.  Rattlers are removed before
(:func:`fricstab.scenes.packing_friction.backbone`).
"""

import time
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
import scipy.sparse as sps

from fricstab.analysis.dos import spectrum
from fricstab.engine.jacobian import jacobian
from fricstab.engine.newton import bordered_solve, translation_modes
from fricstab.engine.system import check_system_state
from fricstab.errors import ParameterError, check_bool
from fricstab.scenes.packing_relax import frozen_rates, separations

__all__ = ["FORCE_BALANCE_TOL", "LinearResponse", "Rigidity", "affine_rates",
           "check_force_balance", "ishima_flipped", "ishima_scale", "linear_response",
           "mode_sum", "rigidity", "solve_nonaffine", "zero_modes"]

#: Force balance required before ``J`` is factorized: max |F| (per particle, Ishima's
#: coordinates, F^l = T/R) <= this x the mean |contact force|.  Error model: the
#: linearization about a state with a residual force F moves G by O(|F| / f_mean)
#: relative, so 1e-6 keeps it far below the 1 % acceptance of theory against step
#: strain; the packings are relaxed to max |F| < f_tol = 1e-14 k_N d^(3/2) (Newton),
#: ~1e-12 of their mean contact force (~1e-2 k_N d^(3/2) at phi = 0.86-0.9), six
#: decades below it, and a state that is not relaxed is off by far more.
FORCE_BALANCE_TOL = 1e-6

def check_force_balance(system, state, rel_tol=FORCE_BALANCE_TOL):
    """ParameterError unless ``state`` is force-balanced; returns ``(max |F|, tolerance)``.

    ``max |F|`` over the free particles' generalized forces in Ishima's
    coordinates (F_x, F_y, F^l = T/R), against ``rel_tol`` times the mean
    magnitude of the contact forces (on i) of the contacts that carry force
    (:data:`FORCE_BALANCE_TOL`, its error model).  A state outside the law's
    domain (an overlap the law refuses) is refused the same way.
    """
    try:
        f = system.forces(state)[system.free, :system.dof]
        fc = system.contact_forces(state)[:, :2]
    except ValueError as exc:   # a kernel refused an overlap: far from any relaxed state
        if isinstance(exc, ParameterError):
            raise
        raise ParameterError(f"the state is not force-balanced: an overlap outside the law's "
                             f"domain ({' '.join(str(exc).split())}); relax it first "
                             "(fricstab packing make, or fricstab.newton)") from None
    if system.dof == 3:   # the engine's T/s as Ishima's F^l = T/R (c = R/s)
        f[:, 2] /= ishima_scale(system)[system.free]
    mag = np.hypot(fc[:, 0], fc[:, 1])
    mag = mag[mag > 0]
    scale = float(mag.mean()) if mag.size else 0.0
    tol = rel_tol * scale
    fmax = float(np.abs(f).max()) if f.size else 0.0
    if not fmax <= tol:
        raise ParameterError(f"the state is not force-balanced: max |F| = {fmax:.3g} "
                             f"(tolerance {tol:.3g} = {rel_tol:g} x the mean contact force "
                             f"{scale:.3g}); relax it first (fricstab packing make, or "
                             "fricstab.newton / fricstab.frictional)")
    return fmax, tol


def ishima_scale(system):
    """``c_i = R_i / s_i``: Ishima's ``l = c r`` for the law's rotation coordinate ``r``."""
    return system.radius / system.rscale


def _dof_scale(system):
    """``1 / c`` per Jacobian dof (1 on x and y), flat, particle by particle."""
    d = np.ones((system.n, system.dof))
    if system.dof == 3:
        d[:, 2] = 1.0 / ishima_scale(system)
    return d[system.free].ravel()


def zero_modes(n, k):
    """``e_x``, ``e_y`` (App. C, Eqs. C6, C8) as unit columns (:func:`translation_modes`)."""
    return translation_modes(n, k)


def affine_rates(system, state):
    """``dF_c / d(dx)`` at frozen history per contact, (K, 2 dof), the engine's coordinates.

    An affine step strain moves ``dx`` of a contact by ``dgamma * y_c`` and
    leaves its history unchanged (the step is instantaneous: Ishima Sec. III B);
    so the affine force rate of contact c is this row times ``y_c``.  Complex
    step through the law's verified scalar force kernel
    (:func:`fricstab.scenes.packing_relax.frozen_rates`): exact to round-off.
    """
    return frozen_rates(system, state, axis=0)


class LinearResponse(NamedTuple):
    """``J`` (CSR, Ishima's convention), ``Xi``, ``Theta`` (flat), ``G_A``, forces (n, dof)."""

    jacobian: object
    xi: np.ndarray
    theta: np.ndarray
    g_a: float
    forces: np.ndarray


def linear_response(system, state):
    """The linear response of a periodic state: ``J``, ``Xi``, ``Theta``, ``G_A`` and forces.

    In Ishima's coordinates ``(x, y, l = d theta / 2)`` whatever the law:
    ``J = -dF/dq`` (Eq. 18) with the history advanced by the increment rule
    (Eq. D4), ``Xi`` the affine force rate at frozen history (Eq. 35; complex
    step through the kernel), ``Theta`` the stress rate (Eq. 45), ``G_A``
    (Eq. 40).

    Parameters
    ----------
    system : System
        Every particle free (a rattler-free backbone); square box
        (``system.lx = system.ly = L``).
    state : State

    Returns
    -------
    jac : scipy.sparse.csr_matrix
        ``J`` (k_N d^(1/2)).
    xi : ndarray
        ``Xi`` per dof (k_N d^(3/2) per unit strain).
    theta : ndarray
        ``Theta`` per dof.
    g_a : float
        ``G_A`` (k_N d^(1/2)).
    forces : ndarray
        Generalized forces per dof (k_N d^(3/2)).

    Raises
    ------
    ParameterError
        If a particle is not free.
    """
    check_system_state(system, state)
    if not np.all(system.free):
        raise ParameterError("linear_response: every particle must be free (a backbone)")
    dof, box = system.dof, system.lx
    f, blocks = system.forces(state, want_blocks=True)
    k = jacobian(system, state)[1]
    c = state.contacts
    pair = c.j >= 0
    y = np.where(pair, separations(system, state)[:, 1], 0.0)
    rates = affine_rates(system, state) * y[:, None]      # dF_c/dgamma, affine
    local = np.arange(dof)
    dofs = np.concatenate([c.i[:, None] * dof + local, np.maximum(c.j, 0)[:, None] * dof + local],
                          axis=1)
    xi = np.zeros(system.n * dof)
    np.add.at(xi, dofs[pair].ravel(), rates[pair].ravel())
    g_a = -(y * rates[:, 0]).sum() / box**2
    theta = np.zeros(system.n * dof)
    # Theta_k = sum_c y_c K_c[x_i, k] + F^x_i delta_{k, y_i}
    np.add.at(theta, dofs[pair].ravel(), (blocks[pair, 0, :] * y[pair, None]).ravel())
    theta[1::dof] += f[:, 0]
    d = _dof_scale(system)
    jac = -(sps.diags(d) @ k @ sps.diags(d)).tocsr()
    forces = f[:, :dof] * d.reshape(-1, dof)
    return LinearResponse(jac, xi * d, theta * d, float(g_a), forces)


def solve_nonaffine(jac, xi, n, k):
    """``u`` with ``J u = Xi`` on the complement of the zero modes (bordered LU).

    Returns ``u`` and the two multipliers, which measure the part of ``Xi``
    along the left zero modes (zero up to round-off: the total force of an
    affine strain vanishes).
    """
    return bordered_solve(jac, xi, translation_modes(n, k))


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


@dataclass(frozen=True)
class Rigidity:
    """Linear-response rigidity of one state under one law (``law``, ``params``)."""

    law: str
    params: dict
    box: float
    g_a: float
    g_na_solve: float
    g_na_modes: float = float("nan")
    jacobian: object = None          # scipy.sparse CSR, J~ = J, Ishima's coordinates
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


def rigidity(system, state, modes=False, route="auto"):
    """Shear rigidity ``G = G_A + G_NA`` of a force-balanced periodic state (Ishima Sec. III).

    ``G_A`` (Eq. 40) from the affine stress rate; ``G_NA = -Theta . u / L^2``
    with ``u`` the solution of ``J u = Xi`` (a bordered sparse LU on the
    complement of the zero modes ``e_x``, ``e_y``), and optionally by the mode
    sum over biorthonormal left and right eigenvectors (Eq. 44).  ``J~ = J``:
    the sign flips of Eqs. 36-37 are not supported by the paper's Appendix G
    (``validation/errata.md``).

    Parameters
    ----------
    system : System
        A rattler-free backbone under any law (:func:`frictional`), square
        periodic box.
    state : State
        Force-balanced: ``max |F| <=`` :data:`FORCE_BALANCE_TOL` x the mean
        contact force (:func:`check_force_balance`), checked before the LU.
    modes : bool
        Also compute ``G_NA`` by the mode sum (Eq. 44; a dense
        eigendecomposition).
    route : {"auto", "dense", "symmetric"}
        Spectrum route of the mode sum (:func:`dos_spectrum`).

    Returns
    -------
    Rigidity
        ``g_a``, ``g_na_solve``, ``g_na_modes`` (NaN without ``modes``), in
        ``k_N d^(1/2)`` (Ishima's units), the ``jacobian`` (CSR, Ishima's
        convention ``-dF/dq`` in ``(x, y, l)``), ``xi``, ``theta``, ``u``,
        ``checks`` (zero-mode and solve residuals) and ``seconds``.

    Raises
    ------
    ParameterError
        A state that is not force-balanced (naming ``max |F|`` and the
        tolerance), or a bad argument.
    """
    check_system_state(system, state)
    check_bool("modes", modes)
    if route not in ("auto", "symmetric", "dense"):
        raise ParameterError(f"route must be 'auto', 'symmetric' or 'dense', got {route!r}")
    k, n, box = system.dof, system.n, system.lx
    t0 = time.perf_counter()
    check_force_balance(system, state)   # before the LU: a clear refusal, not SuperLU's
    jac, xi, theta, g_a, forces = linear_response(system, state)
    t1 = time.perf_counter()
    u, mult = solve_nonaffine(jac, xi, n, k)
    t2 = time.perf_counter()
    g_na = -(theta @ u) / box**2
    c = zero_modes(n, k)
    scale = abs(jac).max()
    checks = {"zero_mode_residual": float(np.abs(jac @ c).max() * np.sqrt(n) / scale),
              "left_zero_mode_residual": float(np.abs(jac.T @ c).max() * np.sqrt(n) / scale),
              "max_force": float(np.abs(forces).max()),
              "solve_residual": float(np.abs(jac @ u - xi).max() / np.abs(xi).max()),
              "multipliers": float(np.abs(mult).max())}
    seconds = {"assemble": t1 - t0, "solve": t2 - t1}
    g_na_modes = float("nan")
    if modes:
        g_na_modes, info = mode_sum(jac, xi, theta, box, k, route)
        checks.update({f"modes_{key}": v for key, v in info.items() if key != "eigenvalues"})
        seconds["modes"] = info["seconds"]
    mat = system.material
    return Rigidity(mat.law, dict(mat.params), box, float(g_a), float(g_na), float(g_na_modes),
                    jac, xi, theta, u, checks, seconds)
