"""Step-strain simulation of the rigidity (Ishima Eqs. 10-17), by Newton relaxation.

An affine step ``x_i -> x_i + dgamma y_i`` with the Lees-Edwards offset
``shift = dgamma L`` is applied at frozen tangential history (the step is
instantaneous), then the backbone is relaxed to force balance
``max |F~| < f_tol`` (paper: 1e-14 k_N d^(3/2)).  Relaxation is Newton on
``F(q, t(q)) = 0`` with the verified Jacobian: each iterate solves
``K dq = -F`` on the complement of the translations, advances every contact's
history by the increment rule (Eq. D4) at the current configuration, and
moves ``q``; contacts are recomputed at every iterate (new contacts start
with zero history; lost ones are dropped, and both are counted).  The
converged state is fixed by the forces, not by the Jacobian; the history
path differs from the paper's damped dynamics by O(dgamma^2), below the
step-strain truncation error O(dgamma).

Results: the nonaffine displacements (Eqs. 10-11), the stress (Eq. 14) and
``g = (sigma(dgamma) - sigma(0)) / dgamma`` (Eq. 16).

Error model of g (stated with each result): truncation ``|g(+dg) - g(-dg)|``,
twice the O(dgamma) term that one extra step of opposite sign measures
(``g(+-dg) = G +- c dg + O(dg^2)``; the factor 2 covers the O(dg^2) remainder
while it is below the first-order term), plus round-off ``2 eps_sigma / dgamma``
with ``eps_sigma = 4 eps sum_c |f^x_c y_c| / L^2 + f_tol sum_c |y_c| / L^2``
(summation error of Eq. 14 and the stress of the residual forces).
"""

import time
from dataclasses import dataclass

import numpy as np

from fricstab.laws import ParameterError
from fricstab.scenes.pack_system import (Network, assemble, history_increment, ndof, network,
                                  shear_stress, sparse_jacobian)
from fricstab.scenes.packing import ConvergenceError
from fricstab.analysis.rigidity import solve_nonaffine

__all__ = ["ConvergenceError", "Relaxed", "StepStrain", "relax", "step_strain"]


@dataclass(frozen=True)
class Relaxed:
    """A force-balanced state of the backbone."""

    pos: np.ndarray      # (n, 2), unwrapped
    ell: np.ndarray      # (n,) rotational coordinate l = d theta / 2
    net: Network
    shift: float
    residual: float
    iterations: int
    contacts_gained: int
    contacts_lost: int


def _wrap(pos, box, shift):
    """Positions folded into the primary Lees-Edwards cell."""
    k = np.floor(pos[:, 1] / box)
    out = np.empty_like(pos)
    out[:, 1] = pos[:, 1] - k * box
    out[:, 0] = np.mod(pos[:, 0] - k * shift, box)
    return out


def relax(pos, ell, radius, box, kt, shift=0.0, net=None, f_tol=1e-14, max_iter=50):
    """Newton relaxation to ``max |F~| < f_tol`` from ``(pos, ell)`` with histories of ``net``."""
    k = ndof(kt)
    n = len(radius)
    pos, ell = pos.copy(), ell.copy()
    gained = lost = 0
    prev = net
    for it in range(max_iter + 1):
        net = network(_wrap(pos, box, shift), radius, box, shift, prev)
        if prev is not None:
            key_old = prev.pairs[:, 0] * n + prev.pairs[:, 1]
            key_new = net.pairs[:, 0] * n + net.pairs[:, 1]
            gained += len(np.setdiff1d(key_new, key_old))
            lost += len(np.setdiff1d(key_old, key_new))
        forces, blocks = assemble(net, radius, kt)
        res = float(np.abs(forces).max()) if n else 0.0
        if res < f_tol:
            return Relaxed(pos, ell, net, shift, res, it, gained, lost)
        if it == max_iter:
            break
        # K dq = -F, i.e. J dq = F, on the complement of the translations
        dq, _ = solve_nonaffine(sparse_jacobian(net.pairs, blocks, n, kt), forces.ravel(), n, k)
        if not np.all(np.isfinite(dq)):
            raise ConvergenceError(f"Newton step is not finite at iteration {it} "
                                   f"(residual {res:.3g}): singular Jacobian")
        if kt > 0:
            hist = net.hist + history_increment(net, radius, dq, k)
            net = Network(net.pairs, net.sep, hist)
        dq = dq.reshape(n, k)
        pos += dq[:, :2]
        if k == 3:
            ell += dq[:, 2]
        prev = net
    raise ConvergenceError(f"Newton relaxation did not reach max|F| < {f_tol:g} in "
                           f"{max_iter} iterations (residual {res:.3g})")


@dataclass(frozen=True)
class StepStrain:
    """Outcome of :func:`step_strain` (Eqs. 10-16)."""

    dgamma: float
    g: float                 # Eq. 16, forward step
    g_backward: float        # the same with -dgamma (for the error model)
    error: float             # truncation + round-off estimate of |g - G|
    sigma0: float
    nonaffine: np.ndarray    # (n, ndof) (Eqs. 10-11) divided by dgamma
    iterations: int
    contacts_changed: int
    seconds: float


def _strained(bb, kt, dgamma, ref, f_tol):
    pos = ref.pos.copy()
    pos[:, 0] += dgamma * ref.pos[:, 1]
    shift = dgamma * bb.box
    out = relax(pos, ref.ell, bb.radius, bb.box, kt, shift, ref.net, f_tol)
    sigma, _ = shear_stress(out.net, bb.radius, kt, bb.box)
    return out, sigma


def step_strain(bb, kt, dgamma=1e-6, f_tol=1e-14):
    """Rigidity ``g`` of backbone ``bb`` by step strain ``dgamma`` (and ``-dgamma``)."""
    if not (np.isfinite(dgamma) and 0 < dgamma <= 0.1):
        raise ParameterError(f"dgamma must be in (0, 0.1], got {dgamma!r}")
    t0 = time.perf_counter()
    k = ndof(kt)
    ref = relax(bb.pos, np.zeros(bb.n), bb.radius, bb.box, kt, 0.0, None, f_tol)
    sigma0, abs0 = shear_stress(ref.net, bb.radius, kt, bb.box)
    fwd, s_f = _strained(bb, kt, dgamma, ref, f_tol)
    bwd, s_b = _strained(bb, kt, -dgamma, ref, f_tol)
    g_f = (s_f - sigma0) / dgamma
    g_b = (sigma0 - s_b) / dgamma
    eps_sigma = 4 * np.finfo(float).eps * abs0 + f_tol * np.abs(ref.net.sep[:, 1]).sum() / bb.box**2
    error = abs(g_f - g_b) + 2 * eps_sigma / dgamma
    nonaffine = np.zeros((bb.n, k))
    nonaffine[:, :2] = (fwd.pos - ref.pos) / dgamma
    nonaffine[:, 0] -= ref.pos[:, 1]
    if k == 3:
        nonaffine[:, 2] = (fwd.ell - ref.ell) / dgamma
    return StepStrain(dgamma, g_f, g_b, error, sigma0, nonaffine,
                      fwd.iterations + bwd.iterations,
                      fwd.contacts_gained + fwd.contacts_lost, time.perf_counter() - t0)
