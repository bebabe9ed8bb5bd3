"""Quasistatic equilibrium of the chain with the verified Jacobian (Newton).

Newton-Raphson on F(q, t(q)) = 0, where the history is carried by the
increment rule along the iterates: each step solves ``J dq = -F`` (least
squares, so free-rolling disks, whose zero mode has no stiffness, do not
move along it), advances the history by ``t += A(q) dq`` with the Coulomb
rescaling, then moves ``q``.  Starting from the previous equilibrium of a
quasistatic ramp, the steps are small and the history path differs from a
damped relaxation by O(|dq|^2) per step (the difference is measured in the
protocol comparison).
"""

import time
from dataclasses import dataclass

import numpy as np

from fricstab.scenes.chain import advance_history, forces, forces_and_jacobian

__all__ = ["NewtonResult", "relax_newton"]


@dataclass(frozen=True)
class NewtonResult:
    """Outcome of :func:`relax_newton`."""

    state: object
    residual: float
    iterations: int
    converged: bool
    seconds: float


def relax_newton(scene, state, tol=1e-12, max_iter=60, max_step=None):
    """Relax ``state`` (not modified) to max |F|, |T| < ``tol``.

    ``max_step`` caps the largest coordinate change of one iteration
    (default: a tenth of the wall overlap scale ``(F_y/kn)^(2/3)``), so that an
    iterate cannot jump past contacts.
    """
    t0 = time.perf_counter()
    s = state.copy()
    if max_step is None:
        max_step = 0.1 * (scene.fy / scene.kn) ** (2.0 / 3.0) + 1e-3 * abs(scene.fx) / scene.kn
    residual = np.inf
    for it in range(max_iter + 1):
        f, jac = forces_and_jacobian(scene, s)
        residual = float(np.abs(f).max())
        if residual < tol:
            return NewtonResult(s, residual, it, True, time.perf_counter() - t0)
        if it == max_iter:
            break
        dq = np.linalg.lstsq(jac, -f.ravel(), rcond=None)[0].reshape(-1, 3)
        biggest = np.abs(dq).max()
        if biggest > max_step:
            dq *= max_step / biggest
        advance_history(scene, s, dq)
        s.q += dq
    return NewtonResult(s, residual, max_iter, False, time.perf_counter() - t0)


def residual(scene, state):
    """max |F|, |T| of a state."""
    return float(np.abs(forces(scene, state)).max())
