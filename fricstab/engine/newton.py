"""Quasistatic relaxation: Newton's method with the verified system Jacobian.

Newton-Raphson on ``F(q, h(q)) = 0`` over the free dof, where the histories
are carried by the increment rule along the iterates: each iteration solves
``K dq = -F`` (``K = dF/dq`` with the increment rule,
:mod:`fricstab.engine.jacobian`), advances every history by ``A(q) dq`` at
the current configuration, moves ``q`` and projects the histories at the new
one (:meth:`System.advance_history`).  Contacts are rebuilt when a particle
moved half the skin; a new contact starts with zero history.

Linear solvers (``solver``):

``"lstsq"``
    dense least squares (minimum-norm ``dq``: a zero mode, e.g. a free-rolling
    disk of the chain, is not moved);
``"bordered"``
    sparse LU of ``[K C; C^T 0]`` with ``C`` the uniform translations in x and
    y (the zero modes of a periodic packing, Ishima App. C): ``dq`` on their
    complement;
``"lsmr"``
    sparse least squares (scipy's LSMR) for large systems with zero modes
    other than translations;
``"regularized"``
    sparse LU of ``K + s I``, ``s = 1e-12 max|diag K|`` (:func:`regularized_solve`):
    a singular ``K`` (a disk without contacts, one with a single contact) at the cost
    of a sparse factorisation; a mode softer than ``s`` is under-solved, which the
    Newton iteration corrects (its residual decides convergence);
``"auto"``
    lstsq up to 1,500 dof, else bordered when the box is periodic in x and y,
    else lsmr.
"""

import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sps
import scipy.sparse.linalg as spla

from fricstab import signals
from fricstab.engine.jacobian import jacobian
from fricstab.errors import ConvergenceError, ParameterError, check_instance, check_int, check_real

__all__ = ["NewtonResult", "bordered_solve", "expand", "newton", "translation_modes",
           "touching"]


@dataclass(frozen=True)
class NewtonResult:
    """Outcome of :func:`newton` (the state is relaxed in place)."""

    residual: float
    iterations: int
    converged: bool
    seconds: float
    contacts_gained: int = 0
    contacts_lost: int = 0


def translation_modes(n_free, dof):
    """Uniform translations in x and y over the free dof, normalized (columns)."""
    c = np.zeros((n_free * dof, 2))
    c[0::dof, 0] = 1.0
    c[1::dof, 1] = 1.0
    return c / np.sqrt(max(n_free, 1))


def bordered_solve(k, rhs, c):
    """``x`` with ``k x = rhs`` on the complement of the columns of ``c`` (bordered LU).

    Returns ``x`` and the multipliers (the part of ``rhs`` along the left
    null space spanned by ``c``; zero up to round-off for a consistent system).
    """
    m = c.shape[1]
    a = sps.bmat([[k, sps.csr_matrix(c)], [sps.csr_matrix(c.T), None]], format="csc")
    sol = spla.spsolve(a, np.concatenate([rhs, np.zeros(m)]))
    return sol[:-m], sol[-m:]


def expand(system, x):
    """Free-dof vector (flat) as generalized displacements (N, 3)."""
    out = np.zeros((system.n, 3))
    out[system.free, :system.dof] = np.asarray(x).reshape(-1, system.dof)
    return out


def touching(system, state):
    """Keys of the contacts that touch (overlap > 0) in ``state``."""
    c = state.contacts
    q, r = state.q, system.radius
    pair = c.j >= 0
    jj = np.where(pair, c.j, 0)
    dx = ((q[c.i, 0] - q[jj, 0]) - c.k * state.shift) - c.m * system.lx
    dy = (q[c.i, 1] - q[jj, 1]) - c.k * system.ly
    gap_pair = np.hypot(dx, dy) - r[c.i] - r[jj]
    w = np.where(pair, 0, -1 - c.j)
    gap_wall = ((q[c.i, 1] - system.walls[w, 0]) * system.walls[w, 1] - r[c.i]
                if len(system.walls) else np.zeros(c.n))
    gap = np.where(pair, gap_pair, gap_wall)
    return state.keys[gap < 0]


def regularized_solve(k, rhs, shift=1e-12):
    """``x`` with ``(K + s I) x = rhs``, ``s = shift * max|diag K|``, by sparse LU and one
    step of iterative refinement on the same matrix.

    For a singular ``K`` with ``rhs`` in its range this is the minimum-norm solution up to
    ``O(s)``: a null mode's component of ``x`` is ``rhs``'s (zero up to round-off) over
    ``s``.  Measured on the AQS polish after FIRE (N = 512 charan, strain steps 340-352,
    1,533 dof): 0.02 s a solve against 2.0 s for dense least squares and 5.7 s for LSMR,
    the same Newton iterations (171) and the same stresses.
    """
    n = k.shape[0]
    d = float(np.abs(k.diagonal()).max()) if n else 0.0
    a = (sps.csc_matrix(k) + (shift * (d if d > 0 else 1.0)) * sps.identity(n, format="csc"))
    lu = spla.splu(a.tocsc())
    x = lu.solve(rhs)
    return x + lu.solve(rhs - a @ x)


def _solve(system, k, f, solver):
    n = k.shape[0]
    if solver == "auto":
        if n <= 1500:
            solver = "lstsq"
        elif system.lx > 0 and system.ly > 0:
            solver = "bordered"
        else:
            solver = "lsmr"
    if solver == "lstsq":
        return np.linalg.lstsq(k.toarray(), -f, rcond=None)[0]
    if solver == "bordered":
        dq, _ = bordered_solve(k, -f, translation_modes(int(system.free.sum()), system.dof))
        return dq
    if solver == "lsmr":
        return spla.lsmr(k, -f, atol=1e-14, btol=1e-14, maxiter=20 * n)[0]
    if solver == "regularized":
        return regularized_solve(k, -f)
    raise ValueError(f"unknown solver {solver!r} (lstsq, bordered, lsmr, regularized, auto)")


def newton(system, state, tol, max_iter=60, solver="auto", max_step=None, raise_on_failure=True):
    """Relax ``state`` in place to ``max |F|`` over the free dof below ``tol``, by Newton's method.

    Each iteration solves ``K dq = -F`` with the engine's Jacobian
    ``K = dF/dq`` (:func:`jacobian`), advances every history by the increment
    rule ``h += A(q) dq`` at the current configuration and projects it at the
    new one (Charan Eq. 2, Ishima Eq. D4), so the history is carried along
    the iterates.

    Parameters
    ----------
    system : System
    state : State
        Relaxed in place.
    tol : float
        Force threshold (force units of the scene).
    max_iter : int
        Iteration cap.
    solver : {"auto", "lstsq", "bordered", "lsmr", "regularized"}
        Linear solver: ``"lstsq"`` dense least squares (a zero mode, e.g. a
        free-rolling disk, is not moved); ``"bordered"`` sparse LU with the
        uniform translations removed (a periodic packing, Ishima App. C);
        ``"lsmr"`` sparse least squares; ``"regularized"`` sparse LU of ``K + s I``
        (module doc); ``"auto"``: lstsq up to 1,500 dof, else
        bordered when periodic in x and y, else lsmr.
    max_step : float, optional
        Cap on the largest coordinate change of one iteration (length), so that
        an iterate cannot jump past contacts; None: no cap.
    raise_on_failure : bool
        Raise :class:`ConvergenceError` (True) or return ``converged=False``.

    Returns
    -------
    NewtonResult
        ``residual`` (force), ``iterations``, ``converged``, ``seconds`` and the
        contacts gained and lost.

    Raises
    ------
    ConvergenceError
        When ``max_iter`` iterations do not suffice or a step is not finite
        (with ``raise_on_failure``).
    ParameterError
        A wrong type, ``tol < 0``, ``max_iter < 0``, an unknown solver
        (:mod:`fricstab.errors`, input checks; a state that turns non-finite
        fails as above).
    """
    from fricstab.engine.system import State, System
    check_instance("system", system, System, "a System")
    check_instance("state", state, State, "a State")
    check_real("tol", tol, 0.0)
    check_int("max_iter", max_iter, 0)
    check_real("max_step", max_step, 0.0, low_open=True, allow_none=True)
    if solver not in ("auto", "lstsq", "bordered", "lsmr", "regularized"):
        raise ParameterError(f"solver must be auto, lstsq, bordered, lsmr or regularized, got "
                             f"{solver!r}")
    t0 = time.perf_counter()
    system.project(state)
    before = touching(system, state)
    residual = np.inf
    it = 0
    for it in range(max_iter + 1):
        f, k = jacobian(system, state)
        residual = float(np.abs(f).max()) if f.size else 0.0
        if residual < tol:
            after = touching(system, state)
            return NewtonResult(residual, it, True, time.perf_counter() - t0,
                                len(np.setdiff1d(after, before)),
                                len(np.setdiff1d(before, after)))
        if it == max_iter:
            break
        signals.check(f" in Newton iteration {it}")
        dq = _solve(system, k, f, solver)
        if not np.all(np.isfinite(dq)):
            if not raise_on_failure:
                break
            raise ConvergenceError(f"Newton step not finite at iteration {it} (residual "
                                   f"{residual:.3g}): singular Jacobian")
        biggest = np.abs(dq).max() if dq.size else 0.0
        if max_step is not None and biggest > max_step:
            dq *= max_step / biggest
        system.advance_history(state, expand(system, dq))
    if raise_on_failure:
        raise ConvergenceError(f"Newton relaxation did not reach max|F| < {tol:g} in "
                               f"{max_iter} iterations (residual {residual:.3g})")
    return NewtonResult(residual, it, False, time.perf_counter() - t0)
