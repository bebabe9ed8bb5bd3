"""FIRE relaxation (Bitzek et al. 2006) on the engine's forces.

The variant of Ishima et al. App. A.1 (Eqs. A5-A12): position update
``q += dt v + dt^2/2 M^-1 F`` (A5), velocity ``v += dt/2 M^-1 (F_old + F_new)``
(A6), then the FIRE mixing ``v -> (1 - chi) v + chi |v| F/|F|`` with norms over
all free dof (Ishima's Eq. A7 is garbled; this is Bitzek's), and the adaptive
step (A8-A12).  Each relaxation starts from ``v = 0``, ``dt = dt_ini``,
``chi = chi_start``.  Histories, if the law has any, follow the increment
rule (the relaxation is then one damped path among many).

Parameters of the paper (in t0): ``dt_ini = 1e-2``, ``dt_max = 10 dt_ini``,
``f_inc = 1.1``, ``f_dec = 0.5``, ``f_chi = 0.99``, ``chi_start = 0.1``,
``N_min = 5``.
"""

from dataclasses import dataclass

import numpy as np

from fricstab import signals
from fricstab._numba import hot_jit
from fricstab.engine import parallel
from fricstab.engine.verlet import CHUNK, law_error
from fricstab.errors import NumericalError

__all__ = ["FireParameters", "fire"]

OK, REBUILD, BAD_FORCE, CONVERGED, BAD_LAW = 0, 1, 2, 4, 5


@dataclass(frozen=True)
class FireParameters:
    """FIRE constants (Ishima App. A.1, Bitzek et al. 2006), times in t0."""

    dt_ini: float = 1e-2
    dt_max: float = 1e-1
    f_inc: float = 1.1
    f_dec: float = 0.5
    f_alpha: float = 0.99
    alpha_start: float = 0.1
    n_min: int = 5

    def array(self):
        return np.array([self.dt_ini, self.dt_max, self.f_inc, self.f_dec, self.f_alpha,
                         self.alpha_start, float(self.n_min)])


@hot_jit
def _fire(law, p, pw, walls, q, v, f, new, dq, gmass, radius, rscale, family,
          ext, lx, ly, shift, ci, cj, cm, ck, hist, flag, cout, ref, skin, dof, damp, meas,
          par, sv, it0, stop, max_iter, tol, fcon, live, pstart, pidx, drv, work, share):
    """FIRE iterations ``it0 .. stop`` (of ``max_iter``); ``sv = [dt, chi, n_pos]``
    carried between calls, so iterations split over calls are those of one call.

    Returns ``(iteration, status, residual)``; REBUILD after a position update
    that may have moved a particle half the skin (the caller rebuilds and
    calls again: the forces at the new positions are computed first).
    """
    n = q.shape[0]
    dt, chi, n_pos = sv[0], sv[1], int(sv[2])
    f_inc, f_dec, f_alpha, a_start, n_min, dt_max = par[2], par[3], par[4], par[5], par[6], par[1]
    lim = skin * skin
    res = np.inf
    box = work[0, 7, :5]   # (lx, ly, shift, dshift, shift rate) of the passes
    box[0] = lx
    box[1] = ly
    box[2] = shift
    box[3] = 0.0
    box[4] = 0.0
    no = n < 0   # False, but not a literal constant: one compiled advance_pass for both callers
    for it in range(it0, stop + 1):
        bad, _ = parallel.advance_pass(law, p, pw, walls, q, dq, v, radius, rscale, box, damp,
                                       ci, cj, cm, ck, hist, flag, cout, ext, family, new, dof,
                                       meas, no, no, fcon, live, pstart, pidx, drv, work, share,
                                       gmass, 0.0, 1.0, no)   # no kick: FIRE's own (A6)
        if bad >= 0:
            sv[0], sv[1], sv[2] = dt, chi, n_pos
            return it, BAD_LAW, float(bad)
        res = 0.0
        for i in range(n):
            if family[i] == 0:
                for b in range(dof):
                    if not abs(new[i, b]) < np.inf:
                        sv[0], sv[1], sv[2] = dt, chi, n_pos
                        return it, BAD_FORCE, res
                    res = max(res, abs(new[i, b]))
        if it > 0:
            for i in range(n):
                if family[i] == 0:
                    for b in range(dof):  # Eq. A6
                        v[i, b] += 0.5 * dt * (f[i, b] + new[i, b]) / gmass[i, b]
        for i in range(n):
            for b in range(3):
                f[i, b] = new[i, b]
        if res < tol:
            sv[0], sv[1], sv[2] = dt, chi, n_pos
            return it, CONVERGED, res
        if it == max_iter:
            break
        if it > 0:
            power = 0.0
            vv = 0.0
            ff = 0.0
            for i in range(n):
                if family[i] == 0:
                    for b in range(dof):
                        power += f[i, b] * v[i, b]
                        vv += v[i, b] * v[i, b]
                        ff += f[i, b] * f[i, b]
            scale = chi * np.sqrt(vv / ff) if ff > 0.0 else 0.0
            for i in range(n):
                if family[i] == 0:
                    for b in range(dof):
                        v[i, b] = (1.0 - chi) * v[i, b] + scale * f[i, b]
            if power > 0.0:  # Eqs. A8-A9
                n_pos += 1
                if n_pos > n_min:
                    dt = min(dt * f_inc, dt_max)
                    chi *= f_alpha
            else:  # Eqs. A10-A12
                for i in range(n):
                    for b in range(3):
                        v[i, b] = 0.0
                chi = a_start
                dt *= f_dec
                n_pos = 0
        far = 0.0
        for i in range(n):  # Eq. A5
            if family[i] == 0:
                for b in range(dof):
                    dq[i, b] = dt * v[i, b] + 0.5 * dt * dt * f[i, b] / gmass[i, b]
                    q[i, b] += dq[i, b]
                ex = q[i, 0] - ref[i, 0]
                ey = q[i, 1] - ref[i, 1]
                far = max(far, ex * ex + ey * ey)
        if skin > 0.0 and 4.0 * far > lim:
            sv[0], sv[1], sv[2] = dt, chi, n_pos
            return it + 1, REBUILD, res
    sv[0], sv[1], sv[2] = dt, chi, n_pos
    return min(stop, max_iter) + 1, OK, res


def fire(system, state, tol, max_iter, params=FireParameters()):
    """Relax ``state`` in place with FIRE until ``max |F|`` over the free dof < ``tol``.

    The FIRE minimizer (Bitzek et al. 2006) as Ishima App. A.1 uses it, with the
    histories projected at every iterate.

    Parameters
    ----------
    system : System
    state : State
        Relaxed in place; velocities are reset to zero first.
    tol : float
        Force threshold (force units of the scene; Ishima's ``F_Th = 1e-14
        k_N d^(3/2)``).
    max_iter : int
        Iteration cap.
    params : FireParameters
        Time-step and mixing parameters (``dt_ini``, ``dt_max``, ``f_inc``,
        ``f_dec``, ``f_alpha``, ``alpha_start``, ``n_min``).

    Returns
    -------
    iterations : int
        Iterations done; ``iterations > max_iter`` means not converged (the
        caller decides whether that is an error).
    residual : float
        ``max |F|`` over the free dof at the end (force).
    """
    n = system.n
    system.project(state)
    f = np.zeros((n, 3))
    new = np.zeros((n, 3))
    dq = np.zeros((n, 3))
    n_chunks = parallel.chunks(n)
    c, space = None, None
    state.v[:] = 0.0
    meas = np.zeros(8)
    par = params.array()
    sv = np.array([par[0], par[5], 0.0])
    it = 0
    chunk = max(1, CHUNK // max(n, 1))
    end = -1
    while True:
        if it > end and end < max_iter:   # the start, or a chunk of iterations done
            signals.check(f" in FIRE iteration {it}")
            end = min(max_iter, it + chunk - 1)
        if state.contacts is not c:
            c = state.contacts
            space = parallel.workspace(c, system, n_chunks)
        it, status, res = _fire(system.law_id, system._p, system._pw, system.walls, state.q,
                                state.v, f, new, dq, system.gmass, system.radius, system.rscale,
                                system.family, system.external, float(system.lx), float(system.ly),
                                float(state.shift), c.i, c.j, c.m, c.k, c.hist, c.flag, c.out,
                                state.ref, float(system.skin), system.dof, system.damping, meas,
                                par, sv, it, end, max_iter, float(tol), *space)
        if status == REBUILD:
            system.rebuild(state)  # the histories are carried; dq is applied next
            continue
        if status == BAD_LAW:
            law_error(system, state, int(res))
        if status == BAD_FORCE:
            raise NumericalError(f"non-finite contact force in FIRE iteration {it}",
                                 step=int(it), quantity="contact force")
        if status == OK and it <= max_iter:
            continue   # the end of a chunk, not of max_iter
        return it, res
