"""Relaxation of a packing under a law's normal forces at zero history (App. A.1-A.2 for any law).

Friction is switched on at a force-balanced state with every tangential
history zero (Ishima App. A.2).  For a law whose normal force is not
Hertz's (``lee_hurley``), that state is the balance of the law's normal
forces alone, ``F(q, h = 0) = 0``: :func:`relax_normal` finds it by FIRE on
the law's :func:`frictionless_form` (the paper's relaxer, App. A.1) and
Newton over the positions with the bordered solver.  Relaxing with the
histories following the increment rule instead (plain
:func:`fricstab.engine.newton` on the frictional law) reaches a balance too,
but leaves some contacts on their Coulomb or rolling caps (measured: 15 of
676 at N = 256 with lee_hurley's defaults), where the linear response is
one-sided and step strain departs from the theory beyond its error model.

Units and coordinates of :mod:`fricstab.scenes.packing_friction`.
"""

import contextlib
import warnings
from dataclasses import replace

import numpy as np
import scipy.sparse as sps
import scipy.sparse.linalg as spla

from fricstab.engine import Material, System, fire
from fricstab.engine.newton import bordered_solve, translation_modes
from fricstab.errors import ConvergenceError
from fricstab.laws import get_law

__all__ = ["frictionless_form", "frozen_rates", "relax_normal", "separations", "singular_guard"]

STALLS = 3     # Newton iterations in a row that do not halve the residual before FIRE


@contextlib.contextmanager
def singular_guard(what):
    """A singular sparse LU (a warning, or SuperLU's RuntimeError) as a :class:`ConvergenceError`.

    A bordered solve is singular when the packing has a zero mode besides the
    translations (a disk that lost its contacts, a contact with zero
    stiffness on its cap): a numerical failure of the relaxation, exit 4.
    """
    with warnings.catch_warnings():
        warnings.simplefilter("error", spla.MatrixRankWarning)
        try:
            yield
        except (RuntimeError, spla.MatrixRankWarning) as exc:
            raise ConvergenceError(f"{what}: singular Jacobian (sparse LU: "
                                   f"{' '.join(str(exc).split())})") from None


def separations(system, state):
    """``r_i - r_j`` (K, 2) of every listed pair contact (images and Lees-Edwards offset)."""
    c, q = state.contacts, state.q
    j = np.maximum(c.j, 0)
    sep = np.empty((c.n, 2))
    sep[:, 0] = ((q[c.i, 0] - q[j, 0]) - c.k * state.shift) - c.m * system.lx
    sep[:, 1] = (q[c.i, 1] - q[j, 1]) - c.k * system.ly
    return sep


STEP = 1e-30   # complex step (any h << |dx| works: no subtraction)


def frozen_rates(system, state, axis=0):
    """``dF_c / d(sep_axis)`` at frozen history per contact, (K, 2 dof), the law's coordinates.

    ``sep = r_i - r_j`` (axis 0: x, 1: y).  Complex step through the law's
    verified scalar force kernel (``LawInfo.force``, arguments passed by name
    as ``LawInfo.inputs`` lists them, so any law): exact to round-off.
    Contacts that do not overlap get zeros.
    """
    law = get_law(system.material.law)
    c = state.contacts
    out = np.zeros((c.n, 2 * system.dof))
    params = dict(zip(law.params, system._p))
    sep = separations(system, state)
    r = system.radius
    f = np.zeros(len(law.outputs), dtype=complex)
    step = (complex(0.0, STEP), 0.0) if axis == 0 else (0.0, complex(0.0, STEP))
    for a in np.flatnonzero(c.j >= 0):
        i, j = c.i[a], c.j[a]
        s = r[i] + r[j]
        if sep[a, 0] ** 2 + sep[a, 1] ** 2 > s * s * (1 + 1e-12):
            continue
        values = {"dx": sep[a, 0] + step[0], "dy": sep[a, 1] + step[1], "Ri": r[i], "Rj": r[j],
                  **params, **{name: c.hist[a, b] for b, name in enumerate(law.history)}}
        law.force(*(complex(values[name]) for name in law.inputs), f)
        out[a] = f.imag / STEP
    return out


def _normal_jacobian(system, state):
    """``dF/d(x, y)`` at zero history, (2N, 2N) CSR, from :func:`frozen_rates`."""
    c, dof, n = state.contacts, system.dof, system.n
    pair = np.flatnonzero(c.j >= 0)
    rows, cols, vals = [], [], []
    for axis in (0, 1):
        rates = frozen_rates(system, state, axis)[pair]
        for side, who in ((0, c.i[pair]), (1, c.j[pair])):
            for a in (0, 1):             # force component on `who`
                for sign, col in ((1.0, c.i[pair]), (-1.0, c.j[pair])):
                    rows.append(2 * who + a)
                    cols.append(2 * col + axis)
                    vals.append(sign * rates[:, side * dof + a])
    return sps.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                          shape=(2 * n, 2 * n))


def _zero_history_forces(system, state):
    state.contacts.hist[:] = 0.0
    state.contacts.flag[:] = 0
    return system.forces(state)


def _line_search(system, state, dq, f, halvings=30):
    """Move ``state`` by ``alpha dq`` with the largest ``alpha = 2^-k`` that lowers ``|F|``.

    Backtracking on ``|F|_2`` (Armijo with c = 1e-4): the Newton direction
    of a symmetric Jacobian descends ``|F|^2``; far from the balance (the
    Hertz state is not close to the law's) a full step would overshoot and
    open contacts.  Returns the forces at the new positions.
    """
    q0 = state.q.copy()
    norm0 = np.linalg.norm(f[:, :2])
    alpha = 1.0
    for _ in range(halvings):
        state.q[:] = q0
        state.q[:, :2] += alpha * dq
        if system.needs_rebuild(state):
            system.rebuild(state)
        try:
            new = _zero_history_forces(system, state)
        except ValueError:     # a law refusing the trial overlaps: shorten the step
            new = None
        if new is not None and np.linalg.norm(new[:, :2]) <= (1 - 1e-4 * alpha) * norm0:
            return new
        alpha *= 0.5
    raise ConvergenceError(f"normal-force relaxation: no step of the Newton direction lowers "
                           f"|F| = {norm0:.3g} (line search)")


def frictionless_form(mat):
    """The law ``mat`` without friction: its normal force alone.

    ``hertz`` for the laws with Hertz's normal force (hertz, ishima, charan:
    ``k_N xi^(3/2)`` with their ``kn``); for ``lee_hurley`` the same law with
    its Coulomb caps at ``1e-300`` of the normal force and no rolling
    resistance (every contact slides: the tangential force and the torques
    vanish to round-off, the normal force is the law's); ``linear`` likewise
    with ``mu = 1e-300`` (its normal force ``kn xi`` is not Hertz's).
    """
    from fricstab.laws import vector_form
    if vector_form(mat.law) == "linear":
        return replace(mat, params={**mat.params, "mu": 1e-300})
    if "kn" in mat.params:
        return Material("hertz", {"kn": mat.params["kn"]})
    return replace(mat, params={**mat.params, "mus": 1e-300, "mur": 0.0})


def _newton_normal(system, state, f_tol, max_iter):
    """Newton over (x, y) on ``F(q, h = 0) = 0`` with a line search; ``(converged, it, res)``.

    Gives up after ``STALLS`` iterations in a row that do not halve the
    residual (a contact opening or closing: FIRE's turn).
    """
    n = system.n
    f = _zero_history_forces(system, state)
    res, stalls = np.inf, 0
    for it in range(max_iter + 1):
        last, res = res, float(np.abs(f[:, :system.dof]).max())
        if res < f_tol:
            return True, it, res
        stalls = stalls + 1 if res > 0.5 * last else 0
        if it == max_iter or stalls > STALLS:
            break
        try:
            with singular_guard("normal-force relaxation"):
                dq, _ = bordered_solve(_normal_jacobian(system, state), -f[:, :2].ravel(),
                                       translation_modes(n, 2))
        except ConvergenceError:
            break
        if not np.all(np.isfinite(dq)):
            break
        try:
            f = _line_search(system, state, dq.reshape(n, 2), f)
        except ConvergenceError:
            break
    return False, it, res


def relax_normal(system, state, f_tol=1e-14, max_iter=60, fire_tols=(1e-8, 1e-10, 1e-12),
                 fire_iter=5_000_000):
    """Relax ``state`` in place to ``F(q, h = 0) = 0``: the law's normal forces, frictionless.

    Newton over the positions (rotations do not enter: at zero history the
    torques vanish): each iterate solves ``K_xy dq = -F_xy`` with the
    bordered solver (the translations are the zero modes), ``K_xy`` the
    Jacobian of the normal forces (:func:`frozen_rates`), with a backtracking
    line search on ``|F|`` (:func:`_line_search`).  Far from the balance a
    contact that must open or close stalls Newton (its force has a kink at
    zero overlap), so :func:`fricstab.engine.fire` on the law's
    :func:`frictionless_form` (App. A.1, the paper's relaxer) first brings
    the residual to each of ``fire_tols`` in turn until Newton converges.
    Every history stays zero.  Returns ``(newton iterations, FIRE
    iterations, residual)``; raises :class:`ConvergenceError` when neither
    reaches ``f_tol``.
    """
    fire_total = 0
    res = np.inf
    flat = System(frictionless_form(system.material), system.radius, system.mass,
                  system.inertia, lx=system.lx, ly=system.ly, skin=system.skin)
    for tol in (None,) + tuple(t for t in fire_tols if t > f_tol) + (f_tol,):
        if tol is not None:
            relaxed = flat.state(state.q[:, :2], shift=state.shift)
            done, fres = fire(flat, relaxed, tol, fire_iter)
            fire_total += done
            if done > fire_iter:
                raise ConvergenceError(f"normal-force relaxation: FIRE did not reach max|F| "
                                       f"< {tol:g} in {fire_iter} iterations ({fres:.3g})")
            state.q[:, :2] = relaxed.q[:, :2]
            system.rebuild(state)
        trial = state.copy()
        ok, it, res = _newton_normal(system, trial, f_tol, max_iter)
        if ok:
            state.q[:] = trial.q
            system.rebuild(state)
            _zero_history_forces(system, state)
            return it, fire_total, res
    raise ConvergenceError(f"normal-force relaxation did not reach max|F| < {f_tol:g} "
                           f"(residual {res:.3g})")
