"""Quasistatic F_x ramp of the chain with detection of complex-pair events.

Equilibria: :func:`relax_newton`, Newton-Raphson of the engine
(:func:`fricstab.engine.newton`, dense least squares so that a free-rolling
disk, a zero mode without stiffness, is not moved) with the history carried
by the increment rule along the iterates (``h += A(q) dq`` at the current
configuration, projected at the new one), each iteration's largest
coordinate change capped at ``0.1 delta_w + 1e-3 |F_x| / kn`` so that an
iterate cannot jump past contacts.  Starting from the previous equilibrium of
a ramp, the steps are small and the history path differs from a damped
relaxation by O(|dq|^2) per step (the difference is measured in the protocol
comparison, ``validation/chain_protocols.md``).

The ramp raises F_x in steps, relaxing each time from the previous
equilibrium so that the tangential history is carried along, and records
the spectrum of M^-1 J.  A *birth* is a complex-conjugate pair present at a step and absent at
the previous one, a *death* the converse (pairs matched by their real parts).
Each event is then located by bisection in F_x on the sign of the pair
indicator D of :mod:`fricstab.analysis.spectrum`, each trial F_x relaxed from the
equilibrium of the step before the event, to the tolerance ``tol`` (default
1e-6): the event lies in ``[fx_lo, fx_hi]`` with ``fx_hi - fx_lo <= tol``.
"""

import time
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import linear_sum_assignment

from fricstab.analysis.spectrum import (complex_pairs, decompose, growth_rate, pair_indicator,
                                        tracking_radius)
from fricstab.engine import newton
from fricstab.errors import (ConvergenceError, check_bool, check_instance, check_int, check_real,
                             check_steps)
from fricstab.scenes.chain import (chain_system, check_chain, forces_and_jacobian, initial_state,
                                   mass_vector, reference_stiffness, rest_overlap)

__all__ = ["Event", "NewtonResult", "RampResult", "locate_event", "ramped_equilibrium",
           "relax_newton", "run_ramp"]


@dataclass(frozen=True)
class NewtonResult:
    """Outcome of :func:`relax_newton`: the relaxed state (a copy) and the engine's report."""

    state: object
    residual: float
    iterations: int
    converged: bool
    seconds: float


def relax_newton(scene, state, tol=1e-12, max_iter=60, max_step=None):
    """Relax a copy of a chain state to equilibrium by Newton's method (history carried).

    :func:`fricstab.newton` with dense least squares (a free-rolling disk, a zero
    mode without stiffness, is not moved) and each iteration's largest
    coordinate change capped, so that an iterate cannot jump past contacts.

    Parameters
    ----------
    scene : ChainScene
    state : State
        Starting state (not modified).
    tol : float
        Threshold on ``max |F|, |T|`` over the free dof (Charan's force units).
    max_iter : int
        Iteration cap.
    max_step : float, optional
        Cap on one iteration's largest coordinate change (length); default
        ``0.1 delta_w + 1e-3 |F_x| / kn``, ``delta_w`` the rest overlap of the
        wall, ``kn`` the reference stiffness.

    Returns
    -------
    NewtonResult
        ``state`` (the relaxed copy), ``residual``, ``iterations``,
        ``converged``, ``seconds``.
    """
    check_chain(scene, state)
    check_real("tol", tol, 0.0, low_open=True)
    check_int("max_iter", max_iter, 0)
    check_real("max_step", max_step, 0.0, low_open=True, allow_none=True)
    if max_step is None:
        max_step = 0.1 * rest_overlap(scene) + 1e-3 * abs(scene.fx) / reference_stiffness(scene)
    s = state.copy()
    res = newton(chain_system(scene), s, tol, max_iter=max_iter, solver="lstsq",
                 max_step=max_step, raise_on_failure=False)
    return NewtonResult(s, res.residual, res.iterations, res.converged, res.seconds)


def ramped_equilibrium(scene, fx, step=1e-3):
    """The chain's equilibrium at ``fx`` reached by a Newton ramp from F_x = 0 (history carried).

    Parameters
    ----------
    scene : ChainScene
    fx : float
        Target F_x (force, Charan's units).
    step : float
        Largest ramp step (force); the ramp takes ``ceil(|fx| / step)`` equal steps.

    Returns
    -------
    State
        The equilibrium at ``fx``.

    Raises
    ------
    ConvergenceError
        Naming the F_x of a step without equilibrium.
    ParameterError
        A wrong type, a NaN or inf, ``step <= 0`` or too many steps.
    """
    check_chain(scene)
    check_real("fx", fx)
    check_real("step", step, 0.0, low_open=True)
    check_steps("ramped_equilibrium", abs(fx) / step)
    state = _equilibrium(scene, initial_state(scene.with_fx(0.0)), 0.0)[0]
    n_steps = max(1, int(np.ceil(abs(fx) / step)))
    for f in np.linspace(0.0, fx, n_steps + 1)[1:]:
        state = _equilibrium(scene, state, f)[0]
    return state


@dataclass(frozen=True)
class Event:
    """A birth or death of a complex-conjugate pair, located in F_x."""

    kind: str          # "birth" or "death"
    fx: float          # midpoint of the final bracket
    fx_lo: float
    fx_hi: float
    pair_center: float  # real part of the coalescing pair (sim units)
    radius: float       # tracking radius of the pair (see pair_indicator)
    bisections: int
    located: bool = True  # False: no sign change of D across the step (see run_ramp)


@dataclass
class RampResult:
    """Spectra along the ramp and the located events."""

    fx: np.ndarray
    eigenvalues: np.ndarray   # (steps, 3N) complex, sorted by real part
    condition: np.ndarray     # (steps, 3N)
    residual: np.ndarray
    growth: np.ndarray        # largest Im sqrt(-lambda) per step
    events: list
    states: list = field(repr=False, default_factory=list)
    seconds: float = 0.0


#: The most F_x steps of one :func:`run_ramp` (each a Newton relaxation and a spectrum).
RAMP_MAX_STEPS = 10**7


def _newton(scene, state):
    return relax_newton(scene, state)


def _equilibrium(scene, state, fx, relax=_newton):
    res = relax(scene.with_fx(fx), state)
    if not res.converged:
        raise ConvergenceError(f"no equilibrium at F_x = {fx:.9g} (residual "
                               f"{res.residual:.2e})")
    return res.state, res.residual


def _indicator(scene, state, fx, center, radius, mass, relax):
    s, _ = _equilibrium(scene, state, fx, relax)
    _, jac = forces_and_jacobian(scene.with_fx(fx), s)
    return pair_indicator(decompose(jac, mass, vectors=False).eigenvalues, center, radius)


def locate_event(scene, state_lo, fx_lo, fx_hi, center, radius, tol=1e-6, max_iter=80,
                 relax=_newton, convention="physical"):
    """Bisect the sign change of the pair indicator D in ``[fx_lo, fx_hi]``.

    ``state_lo`` is the equilibrium at ``fx_lo``; every trial is relaxed from
    it.  ``center`` and ``radius`` identify the conjugate pair (see
    :func:`fricstab.analysis.spectrum.pair_indicator`).  Returns ``(fx_lo, fx_hi,
    center, iterations, located)``; ``located`` is False when D has the same
    sign at both ends (two events within one step, or a pair that moved too
    far to be tracked): refine the ramp step.  ``convention``: the spectrum's mass
    matrix (:data:`fricstab.scenes.chain.CONVENTIONS`).
    """
    mass = mass_vector(scene, convention)
    d_lo, c_lo = _indicator(scene, state_lo, fx_lo, center, radius, mass, relax)
    d_hi, c_hi = _indicator(scene, state_lo, fx_hi, center, radius, mass, relax)
    if np.sign(d_lo) == np.sign(d_hi):
        return fx_lo, fx_hi, center, 0, False
    it = 0
    while fx_hi - fx_lo > tol and it < max_iter:
        mid = 0.5 * (fx_lo + fx_hi)
        d_mid, c_mid = _indicator(scene, state_lo, mid, center, radius, mass, relax)
        if d_mid < 0:
            center = c_mid  # follow the conjugate pair's real part
        if np.sign(d_mid) == np.sign(d_lo):
            fx_lo, d_lo = mid, d_mid
        else:
            fx_hi = mid
        it += 1
    return fx_lo, fx_hi, center, it, True


def _match(prev, cur, scale):
    """Pairs of ``cur`` with no partner in ``prev``, and vice versa.

    Optimal assignment (scipy's linear_sum_assignment) on the distance of the
    upper eigenvalues in the complex plane; a matched distance above ``scale``
    counts as a death and a birth.
    """
    if len(prev) == 0 or len(cur) == 0:
        return list(cur), list(prev)
    cost = np.abs(np.subtract.outer(np.asarray(prev), np.asarray(cur)))
    rows, cols = linear_sum_assignment(cost)
    ok = cost[rows, cols] <= scale
    matched_prev, matched_cur = set(rows[ok]), set(cols[ok])
    born = [w for j, w in enumerate(cur) if j not in matched_cur]
    died = [w for i, w in enumerate(prev) if i not in matched_prev]
    return born, died


def run_ramp(scene, fx_max, step, tol=1e-6, progress=None, keep_states=False, relax=_newton,
             locate=True, convention="physical"):
    """Quasistatic F_x ramp of the chain; every birth and death of a complex pair located.

    F_x rises from 0 to ``fx_max`` in steps of ``step``; each step is relaxed from
    the previous equilibrium, the history carried (Charan Eq. 2), and the
    spectrum of ``M^-1 J`` recorded with condition numbers (Charan Fig. 2).  A
    birth (death) is a conjugate pair present (absent) at a step and absent
    (present) at the one before, pairs matched by optimal assignment; each is
    bisected in F_x to ``tol`` on the sign of :func:`pair_indicator`.  Units:
    the chain's (forces in the unit of F_y, eigenvalues in simulation
    time^-2; :class:`ChainScene`).

    Parameters
    ----------
    scene : ChainScene
    fx_max : float
        End of the ramp (force).
    step : float
        Ramp step in F_x (force); an event pair closer than a step is not
        located (two sign changes cancel), so smaller is safer and slower.
    tol : float
        Width of the final bracket of each event in F_x (force).
    progress : callable or tqdm, optional
        Progress reporting over the steps.
    keep_states : bool
        Keep the equilibrium of every step in ``states``.
    relax : callable
        ``relax(scene, state)`` returning an object with ``state``,
        ``residual`` and ``converged``: :func:`relax_newton` (default) or
        :func:`relax_damped` (the paper's damped protocol).
    locate : bool
        False: events at the step resolution only (``fx_lo``, ``fx_hi`` the
        step ends, ``located`` False).
    convention : str
        The matrix whose spectrum is taken (:data:`fricstab.scenes.chain.CONVENTIONS`):
        ``physical`` (M^-1 J with the scene's inertia, default), ``lammps``
        (I = 2/5 m R^2), ``sm`` (I = m R^2, Charan's supplementary material) or
        ``bare`` (J itself, force/length).  The equilibria do not depend on it.

    Returns
    -------
    RampResult
        ``fx`` (steps,), ``eigenvalues`` (steps, 3N) complex sorted by real
        part, ``condition`` (steps, 3N), ``residual``, ``growth`` (largest
        ``Im sqrt(-lambda)`` per step), ``events`` (list of :class:`Event`:
        ``kind``, ``fx``, ``fx_lo``, ``fx_hi``, ``pair_center``, ``radius``,
        ``bisections``, ``located``), ``states``, ``seconds``.

    Raises
    ------
    ConvergenceError
        A step without equilibrium, naming its F_x.
    ParameterError
        A scene that is not a :class:`ChainScene`, ``fx_max < 0``, ``step <= 0``,
        ``tol <= 0``, a NaN or inf, or more than :data:`RAMP_MAX_STEPS` steps
        (:mod:`fricstab.errors`, input checks).
    """
    check_chain(scene)
    check_real("fx_max", fx_max, 0.0)
    check_real("step", step, 0.0, low_open=True)
    check_real("tol", tol, 0.0, low_open=True)
    check_bool("keep_states", keep_states)
    check_bool("locate", locate)
    if not callable(relax):
        check_instance("relax", relax, type(_newton), "a callable (relax_newton, relax_damped)")
    check_steps("run_ramp", fx_max / step, RAMP_MAX_STEPS)
    t0 = time.perf_counter()
    mass = mass_vector(scene, convention)
    state, _ = _equilibrium(scene, initial_state(scene.with_fx(0.0)), 0.0, relax)
    grid = np.round(np.arange(0.0, fx_max + 0.5 * step, step), 12)
    eig, cond, resid, growth, states, events = [], [], [], [], [], []
    prev_pairs, prev_state = np.array([]), state
    for k, fx in enumerate(grid):
        state, res = _equilibrium(scene, state, fx, relax)
        _, jac = forces_and_jacobian(scene.with_fx(fx), state)
        spec = decompose(jac, mass)
        eig.append(spec.eigenvalues)
        cond.append(spec.condition)
        resid.append(res)
        growth.append(growth_rate(spec.eigenvalues))
        if keep_states:
            states.append(state.copy())
        pairs = complex_pairs(spec.eigenvalues)
        if k > 0:
            # Two pairs are the same when their real parts moved by less than a
            # tenth of the spectral width per step.
            scale = 0.1 * (np.abs(spec.eigenvalues.real).max() + 1e-300)
            born, died = _match(prev_pairs, pairs, scale)
            for kind, group, where in (("birth", born, spec.eigenvalues),
                                       ("death", died, eig[-2])):
                for w in group:
                    radius = tracking_radius(where, w.real)
                    if locate:
                        lo, hi, center, n_it, ok = locate_event(
                            scene, prev_state, grid[k - 1], fx, w.real, radius, tol,
                            relax=relax, convention=convention)
                    else:
                        lo, hi, center, n_it, ok = grid[k - 1], fx, w.real, 0, False
                    events.append(Event(kind, 0.5 * (lo + hi), lo, hi, center, radius, n_it, ok))
        prev_pairs, prev_state = pairs, state
        if progress is not None:
            progress.update(1)
    return RampResult(grid, np.array(eig), np.array(cond), np.array(resid), np.array(growth),
                      sorted(events, key=lambda e: e.fx), states, time.perf_counter() - t0)
