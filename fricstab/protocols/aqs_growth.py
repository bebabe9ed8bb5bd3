"""Dynamic confirmation at an AQS state: Newtonian growth of the pair's mode against the Jacobian.

Linear theory as :mod:`fricstab.protocols.growth` (the chain's): ``q'' = A q``
with ``A = M^-1 K`` on the complement of the translations
(:func:`fricstab.protocols.aqs.reduced_matrix`); a mode with eigenvalue
lambda grows as ``exp(s t)``, ``s^2 = lambda``, at the rate ``Re sqrt(lambda)``
(= ``Im sqrt(-lambda)`` of :func:`fricstab.analysis.spectrum.growth_rate`).
The state is perturbed along the real part of the right eigenvector of the
fastest-growing eigenvalue, at rest, and integrated by the engine's velocity
Verlet (:func:`fricstab.engine.run`, no damping, histories by the increment
rule); the modal amplitude ``|l^H (q(t) - q_0)|`` with the biorthonormal
left eigenvector isolates the mode, and its log is fitted over the second
half of the run (the decaying root ``exp(-s t)`` is then below
``exp(-e_folds)`` of the growing one).
"""

import numpy as np

from fricstab.analysis.spectrum import decompose
from fricstab.engine import jacobian
from fricstab.engine import run as run_dynamics
from fricstab.errors import ParameterError
from fricstab.protocols.aqs import reduced_matrix
from fricstab.protocols.growth import GrowthCheck

__all__ = ["measure_growth"]


def measure_growth(system, state, amplitude=1e-10, e_folds=10.0, dt_factor=0.05, frames=2000):
    """Perturb the equilibrium ``state`` along its fastest-growing mode and fit the growth.

    Newtonian dynamics (velocity Verlet) from ``state`` displaced by
    ``amplitude`` along the real part of the right eigenvector of ``M^-1 K``
    with the largest growth rate; the amplitude of that mode (projection on
    the left eigenvector) is fitted to an exponential over the second half of
    the run.

    Parameters
    ----------
    system : fricstab.System
        The packing system (reduced units: d, k_N, t0).
    state : fricstab.State
        An equilibrium with a complex pair (a growing mode).
    amplitude : float, optional
        Initial displacement in d; ``amplitude e^e_folds`` bounds the final one
        (2e-6 d by default: linear, well below the overlaps ~1e-2 d and the
        smoothing scale of charan's Coulomb cap).
    e_folds : float, optional
        Length of the run in e-folds of the predicted growth.
    dt_factor : float, optional
        ``dt = dt_factor / sqrt(max |lambda|)``: Verlet's phase error on the
        fastest mode is ``O((omega dt)^2) ~ 2.5e-3`` and far less on the slow
        growing one.
    frames : int, optional
        Recorded frames for the fit.

    Returns
    -------
    GrowthCheck
        ``predicted`` and ``measured`` growth rates (``t0^-1``), the
        eigenvalue, the fit window (t0) and ``relative_difference``.

    Raises
    ------
    ParameterError
        The state has no growing mode.
    """
    _, k = jacobian(system, state)
    gm = system.gmass[system.free, :system.dof].ravel()
    n_free = int(system.free.sum())
    a, basis = reduced_matrix(k, gm, n_free, system.dof)
    spec = decompose(a, np.ones(a.shape[0]))
    rates = np.abs(np.sqrt(spec.eigenvalues.astype(complex)).real)
    j = int(np.argmax(rates))
    predicted = float(rates[j])
    if predicted <= 0:
        raise ParameterError("the state has no growing mode (no complex pair): nothing to confirm")
    right = basis @ spec.right[:, j]
    left = basis @ spec.left[:, j]
    shape = right.real / np.abs(right.real).max()
    start = state.copy()
    start.v[:] = 0.0
    q = start.q[system.free, :system.dof] + amplitude * shape.reshape(n_free, system.dof)
    start.q[system.free, :system.dof] = q
    dt = dt_factor / np.sqrt(np.abs(spec.eigenvalues).max())
    n_steps = int(np.ceil(e_folds / predicted / dt))
    every = max(1, n_steps // frames)
    res = run_dynamics(system, start, dt, n_steps, record_every=every)
    disp = (res.q[:, system.free, :system.dof] - state.q[None, system.free, :system.dof])
    c = np.abs(disp.reshape(len(res.times), -1) @ left.conj())
    half = len(res.times) // 2
    slope = float(np.polyfit(res.times[half:], np.log(c[half:]), 1)[0])
    return GrowthCheck(predicted, slope, complex(spec.eigenvalues[j]),
                       (float(res.times[half]), float(res.times[-1])))
