"""Step-strain simulation of the rigidity (Ishima Eqs. 10-17), by Newton relaxation on the engine.

An affine step ``x_i -> x_i + dgamma y_i`` with the Lees-Edwards offset
``shift -> shift + dgamma L`` is applied at frozen tangential history (the
step is instantaneous), then the state is relaxed to force balance
``max |F| < f_tol`` (paper: 1e-14 k_N d^(3/2)) by
:func:`fricstab.engine.newton` with the bordered solver: each iterate solves
``K dq = -F`` on the complement of the translations with the verified
Jacobian, advances every contact's history by the increment rule at the
current configuration, moves ``q`` and projects the histories (a Coulomb cap,
for a law that has one).  The contact list follows the iterates (new contacts
start with zero history; contacts gained and lost are counted against the
reference).  The converged state is fixed by the forces, not by the Jacobian;
the history path differs from the paper's damped dynamics by O(dgamma^2),
below the step-strain truncation error O(dgamma).

Any law of :mod:`fricstab.scenes.packing_friction`; the nonaffine
displacements are reported in Ishima's coordinates ``(x, y, l = R theta)``
(:mod:`fricstab.analysis.rigidity`).

Results: the nonaffine displacements (Eqs. 10-11), the stress (Eq. 14) and
``g = (sigma(dgamma) - sigma(0)) / dgamma`` (Eq. 16).

Error model of g (stated with each result): ``g(h) = G + a h + b |h| + O(h^2)``
with ``g(-h) = (sigma(0) - sigma(-h)) / h``.  The analytic first-order term
``a h`` is measured by one extra step of opposite sign, ``|g(+dg) - g(-dg)| =
2 |a| dg``; the term ``b |h|``, even in the sign of the step, comes from a
law that is C1 but not C2 at zero history (Charan's smoothed Coulomb law has
``|t| t``, Eq. 5) and is measured by the mean of two more steps of twice the
size, ``gbar(2 dg) - gbar(dg) = b dg`` with ``gbar(h) = (g(h) + g(-h)) / 2``.
Truncation: ``|g(+dg) - g(-dg)| + 2 |gbar(2 dg) - gbar(dg)|`` (twice each
first-order term: the factor 2 covers the O(dg^2) remainder while it is below
them), plus round-off ``2 eps_sigma / dgamma`` with ``eps_sigma = 4 eps sum_c
|f^x_c y_c| / L^2 + f_tol sum_c |y_c| / L^2`` (summation error of Eq. 14 and
the stress of the residual forces; sums over the touching contacts).
"""

import time
from dataclasses import dataclass

import numpy as np

from fricstab.analysis.rigidity import ishima_scale
from fricstab.scenes.packing_relax import separations, singular_guard
from fricstab.engine import newton
from fricstab.engine.newton import touching
from fricstab.engine.system import check_system_state
from fricstab.errors import ConvergenceError, ParameterError, check_int, check_real

__all__ = ["ConvergenceError", "StepStrain", "affine_step", "relax", "shear_stress", "step_strain", "strain"]


def shear_stress(system, state):
    """``sigma_xy = -(1/L^2) sum_c f^x_c y_c`` (Ishima Eq. 14) and ``sum_c |f^x_c y_c| / L^2``."""
    fc = system.contact_forces(state)
    y = separations(system, state)[:, 1]
    terms = np.where(state.contacts.j >= 0, fc[:, 0] * y, 0.0)
    area = system.lx * system.ly
    return -terms.sum() / area, np.abs(terms).sum() / area


def relax(system, state, f_tol=1e-14, max_iter=50):
    """Newton (bordered solver) in place to ``max |F| < f_tol``; the NewtonResult.

    Raises :class:`ConvergenceError` also when the sparse LU finds the
    Jacobian singular (:func:`fricstab.scenes.packing_relax.singular_guard`).
    """
    with singular_guard("Newton relaxation"):
        return newton(system, state, f_tol, max_iter=max_iter, solver="bordered")


def strain(system, state, dgamma, f_tol=1e-14, max_iter=50):
    """A copy of a periodic state after an affine step strain at frozen history, relaxed.

    The affine step ``x += dgamma y`` with the Lees-Edwards offset grown by
    ``dgamma L_y`` (Ishima Eqs. 10-11), then Newton relaxation with the
    verified Jacobian, the history carried and contacts recomputed at every
    iterate.

    Parameters
    ----------
    system : System
        A periodic system (square box).
    state : State
        The reference state (not modified).
    dgamma : float
        Shear strain step (dimensionless).
    f_tol : float
        Force threshold of the relaxation (the scene's force units).
    max_iter : int
        Newton iteration cap.

    Returns
    -------
    strained : State
        The relaxed strained state.
    result : NewtonResult
        The relaxation's residual, iterations and convergence.

    Raises
    ------
    ParameterError
        A wrong type, a non-finite state, ``|dgamma| > 1``, ``f_tol <= 0`` or
        ``max_iter < 1`` (:mod:`fricstab.errors`, input checks).
    """
    check_system_state(system, state)
    check_real("dgamma", dgamma, -1.0, 1.0)
    check_real("f_tol", f_tol, 0.0, low_open=True)
    check_int("max_iter", max_iter, 1)
    s = affine_step(system, state, dgamma)
    return s, relax(system, s, f_tol, max_iter)


def affine_step(system, state, dgamma):
    """A copy of ``state`` after the affine step ``x += dgamma y`` at frozen history.

    The Lees-Edwards offset grows by ``dgamma L_y`` (Ishima Eqs. 10-11).
    """
    s = state.copy()
    s.q[:, 0] += dgamma * s.q[:, 1]
    s.shift = state.shift + dgamma * system.ly
    return s


@dataclass(frozen=True)
class StepStrain:
    """Outcome of :func:`step_strain` (Eqs. 10-16)."""

    dgamma: float
    g: float                 # Eq. 16, forward step
    g_backward: float        # the same with -dgamma (for the error model)
    g_double: float          # gbar(2 dgamma), the mean of +-2 dgamma (for the error model)
    error: float             # truncation + round-off estimate of |g - G|
    sigma0: float
    nonaffine: np.ndarray    # (n, dof) (Eqs. 10-11) divided by dgamma, Ishima's coordinates
    iterations: int
    contacts_changed: int
    seconds: float


def step_strain(system, state, dgamma=1e-6, f_tol=1e-14):
    """Shear rigidity ``g`` of a periodic state by step strain (Ishima Eqs. 10-16).

    Affine steps ``+-dgamma`` and ``+-2 dgamma`` with the Lees-Edwards offset at
    frozen history, each relaxed by Newton with the history carried
    (:func:`strain`); ``g = (sigma(dgamma) - sigma(0)) / dgamma`` (Eq. 16).
    The error model: truncation ``|g(+dgamma) - g(-dgamma)|`` plus round-off
    ``2 eps_sigma / dgamma``.

    Parameters
    ----------
    system : System
        A periodic backbone under a law (:func:`frictional`).
    state : State
        The reference state; relaxed first (on a copy) if its residual is not
        below ``f_tol``.
    dgamma : float
        Strain step, in (0, 0.1].
    f_tol : float
        Force threshold of the relaxations (k_N d^(3/2)).

    Returns
    -------
    StepStrain
        ``g`` (k_N d^(1/2), Ishima's units), ``g_backward``, ``g_double``,
        ``error`` (estimate of ``|g - G|``), ``sigma0``, ``nonaffine`` (N, dof)
        displacement per unit strain, ``iterations``, ``contacts_changed``,
        ``seconds``.

    Raises
    ------
    ParameterError
        ``dgamma`` out of range.
    """
    check_system_state(system, state)
    check_real("dgamma", dgamma, 0.0, 0.1, low_open=True)
    check_real("f_tol", f_tol, 0.0, low_open=True)
    t0 = time.perf_counter()
    ref = state.copy()
    relax(system, ref, f_tol)
    before = touching(system, ref)
    sigma0, abs0 = shear_stress(system, ref)
    states, g, iterations = {}, {}, 0
    for h in (dgamma, -dgamma, 2 * dgamma, -2 * dgamma):
        states[h], res = strain(system, ref, h, f_tol)
        g[h] = (shear_stress(system, states[h])[0] - sigma0) / h
        iterations += res.iterations
    fwd = states[dgamma]
    g_f, g_b = g[dgamma], g[-dgamma]
    g_double = (g[2 * dgamma] + g[-2 * dgamma]) / 2
    keys = np.searchsorted(ref.keys, before)
    y = separations(system, ref)[keys, 1]
    area = system.lx * system.ly
    eps_sigma = 4 * np.finfo(float).eps * abs0 + f_tol * np.abs(y).sum() / area
    error = abs(g_f - g_b) + 2 * abs(g_double - (g_f + g_b) / 2) + 2 * eps_sigma / dgamma
    k = system.dof
    nonaffine = (fwd.q[:, :k] - ref.q[:, :k]) / dgamma
    nonaffine[:, 0] -= ref.q[:, 1]
    if k == 3:
        nonaffine[:, 2] *= ishima_scale(system)
    after = touching(system, fwd)
    changed = len(np.setdiff1d(after, before)) + len(np.setdiff1d(before, after))
    return StepStrain(dgamma, g_f, g_b, g_double, error, sigma0, nonaffine, iterations, changed,
                      time.perf_counter() - t0)
