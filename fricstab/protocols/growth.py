"""Growth of the unstable mode in Newtonian dynamics against the Jacobian.

Linear theory: ``q'' = A q`` with ``A = M^-1 J``; a mode with eigenvalue
lambda evolves as ``exp(s t)``, ``s^2 = lambda``, so its e-folding rate is
``Re sqrt(lambda)`` (positive for one root of a complex lambda).  The modal
amplitude ``c(t) = l^H (q(t) - q_0)`` with the left eigenvector ``l`` isolates
the mode; its log grows with slope ``Re sqrt(lambda)`` once the decaying
partner root has died out.
"""

from dataclasses import dataclass

import numpy as np

from fricstab.analysis.spectrum import decompose
from fricstab.errors import ParameterError, check_real
from fricstab.protocols.dynamics import run_dynamics
from fricstab.scenes.chain import (chain_system, check_chain, forces_and_jacobian, mass_vector,
                                   rest_overlap)

__all__ = ["GrowthCheck", "measure_growth"]


@dataclass(frozen=True)
class GrowthCheck:
    """Predicted and measured growth rate of the most unstable mode (sim units)."""

    predicted: float
    measured: float
    eigenvalue: complex
    fit_window: tuple

    @property
    def relative_difference(self):
        return abs(self.measured - self.predicted) / self.predicted


def measure_growth(scene, state, amplitude=1e-9, e_folds=12.0, dt=None):
    """Growth rate of the most unstable mode in Newtonian dynamics, against the Jacobian's.

    ``state`` (an equilibrium) is perturbed along the real part of the right
    eigenvector of the mode with the largest ``Re sqrt(lambda)`` of ``M^-1 J``;
    the run lasts ``e_folds`` predicted e-foldings, so the amplitude stays below
    ``amplitude * e^e_folds`` (linear regime for the default 1e-9 * 1.6e5); the
    modal amplitude (projection on the left eigenvector) is fitted over the
    second half.

    Parameters
    ----------
    scene : ChainScene
        The scene (with its F_x).
    state : State
        An equilibrium with an unstable mode.
    amplitude : float
        Perturbation, in units of the rest wall overlap.
    e_folds : float
        Duration in predicted e-foldings.
    dt : float, optional
        Verlet step (simulation units; default :func:`run_dynamics`'s).

    Returns
    -------
    GrowthCheck
        ``predicted`` and ``measured`` rates (1/time, simulation units),
        the ``eigenvalue`` and the ``fit_window`` (times).

    Raises
    ------
    ParameterError
        If the state has no unstable mode (a subclass of ValueError), or an
        argument is of the wrong type or out of range (module
        :mod:`fricstab.errors`, "input checks").
    """
    check_chain(scene, state)
    check_real("amplitude", amplitude, 0.0, low_open=True)
    check_real("e_folds", e_folds, 0.0, low_open=True)
    check_real("dt", dt, 0.0, low_open=True, allow_none=True)
    _, jac = forces_and_jacobian(scene, state)
    spec = decompose(jac, mass_vector(scene))
    rates = np.sqrt(spec.eigenvalues.astype(complex)).real
    rates = np.abs(rates)
    k = int(np.argmax(rates))
    predicted = float(rates[k])
    if predicted <= 0:
        raise ParameterError("the state has no unstable mode")
    n, dof = scene.n, scene.dof
    right = spec.right[:, k].real
    right /= np.abs(right).max()
    start = state.copy()
    start.q[:, :dof] += (amplitude * rest_overlap(scene) * right).reshape(n, dof)
    duration = e_folds / predicted
    res = run_dynamics(scene, start, dt=dt, duration=duration, frames=4000)
    # the recorded positions are physical (theta); the modes live in generalized q
    gen = res.positions.copy()
    gen[:, :, 2] *= chain_system(scene).rscale
    disp = (gen[:, :, :dof] - state.q[None, :, :dof]).reshape(len(res.times), -1)
    c = np.abs(disp @ spec.left[:, k].conj())
    half = len(res.times) // 2
    # Fit the envelope: the modal amplitude oscillates at Im sqrt(lambda); take
    # local maxima of |c| over windows of one period to fit their growth.
    t, logc = res.times[half:], np.log(c[half:])
    slope = float(np.polyfit(t, logc, 1)[0])
    return GrowthCheck(predicted, slope, complex(spec.eigenvalues[k]),
                       (float(t[0]), float(t[-1])))
