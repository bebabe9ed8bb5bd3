"""Quasistatic F_x ramp of the chain with detection of complex-pair events.

The ramp raises F_x in steps, relaxing each time from the previous
equilibrium so that the tangential history is carried along
(:func:`fricstab.quasistatic.relax_newton`), and records the spectrum of
M^-1 J.  A *birth* is a complex-conjugate pair present at a step and absent at
the previous one, a *death* the converse (pairs matched by their real parts).
Each event is then located by bisection in F_x on the sign of the pair
indicator D of :mod:`fricstab.spectrum`, each trial F_x relaxed from the
equilibrium of the step before the event, to the tolerance ``tol`` (default
1e-6): the event lies in ``[fx_lo, fx_hi]`` with ``fx_hi - fx_lo <= tol``.
"""

import time
from dataclasses import dataclass, field

import numpy as np

from fricstab.chain import forces_and_jacobian, initial_state, mass_vector
from fricstab.quasistatic import relax_newton
from fricstab.spectrum import complex_pairs, decompose, growth_rate, pair_indicator

__all__ = ["Event", "RampResult", "locate_event", "run_ramp"]


@dataclass(frozen=True)
class Event:
    """A birth or death of a complex-conjugate pair, located in F_x."""

    kind: str          # "birth" or "death"
    fx: float          # midpoint of the final bracket
    fx_lo: float
    fx_hi: float
    pair_center: float  # real part of the coalescing pair (sim units)
    bisections: int


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


def _equilibrium(scene, state, fx):
    res = relax_newton(scene.with_fx(fx), state)
    if not res.converged:
        raise RuntimeError(f"Newton did not converge at F_x = {fx:.9g} "
                           f"(residual {res.residual:.2e})")
    return res.state, res.residual


def _indicator(scene, state, fx, center, mass):
    s, _ = _equilibrium(scene, state, fx)
    _, jac = forces_and_jacobian(scene.with_fx(fx), s)
    return pair_indicator(decompose(jac, mass, vectors=False).eigenvalues, center)


def locate_event(scene, state_lo, fx_lo, fx_hi, center, tol=1e-6, max_iter=80):
    """Bisect the sign change of the pair indicator D in ``[fx_lo, fx_hi]``.

    ``state_lo`` is the equilibrium at ``fx_lo``; every trial is relaxed from
    it.  Returns ``(fx_lo, fx_hi, center, iterations)``.
    """
    mass = mass_vector(scene)
    d_lo, center = _indicator(scene, state_lo, fx_lo, center, mass)
    it = 0
    while fx_hi - fx_lo > tol and it < max_iter:
        mid = 0.5 * (fx_lo + fx_hi)
        d_mid, center = _indicator(scene, state_lo, mid, center, mass)
        if np.sign(d_mid) == np.sign(d_lo):
            fx_lo, d_lo = mid, d_mid
        else:
            fx_hi = mid
        it += 1
    return fx_lo, fx_hi, center, it


def _match(prev, cur, scale):
    """Pairs of ``cur`` with no partner in ``prev`` (by real part), and vice versa."""
    new, gone = [], list(prev)
    for w in cur:
        if gone:
            k = int(np.argmin([abs(w.real - g.real) for g in gone]))
            if abs(w.real - gone[k].real) < scale:
                gone.pop(k)
                continue
        new.append(w)
    return new, gone


def run_ramp(scene, fx_max, step, tol=1e-6, progress=None, keep_states=False):
    """Ramp F_x from 0 to ``fx_max`` in ``step`` increments; locate every event."""
    t0 = time.perf_counter()
    mass = mass_vector(scene)
    state, _ = _equilibrium(scene, initial_state(scene), 0.0)
    grid = np.round(np.arange(0.0, fx_max + 0.5 * step, step), 12)
    eig, cond, resid, growth, states, events = [], [], [], [], [], []
    prev_pairs, prev_state = np.array([]), state
    for k, fx in enumerate(grid):
        state, res = _equilibrium(scene, state, fx)
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
            for kind, group in (("birth", born), ("death", died)):
                for w in group:
                    lo, hi, center, n_it = locate_event(scene, prev_state, grid[k - 1], fx,
                                                        w.real, tol)
                    events.append(Event(kind, 0.5 * (lo + hi), lo, hi, center, n_it))
        prev_pairs, prev_state = pairs, state
        if progress is not None:
            progress.update(1)
    return RampResult(grid, np.array(eig), np.array(cond), np.array(resid), np.array(growth),
                      sorted(events, key=lambda e: e.fx), states, time.perf_counter() - t0)
