"""The integrator's per-particle steps, on a range of particles (velocity Verlet).

Each function touches only the particles of its range, so the particles may
be shared among threads (:mod:`fricstab.engine.parallel`,
:mod:`fricstab.engine.verlet`) with the serial result to the bit.  Both are
compiled with the dof as the constant 3 (the laws with a rotation) and as a
variable (the frictionless law, 2).
"""

import numpy as np

from fricstab._numba import hot_inline_jit, hot_jit

__all__ = ["drift_range", "kick_range"]


@hot_inline_jit
def _drift_body(lo, hi, q, v, f, dq, dqh, ginv, family, ref, dof, half, nu, dt, vx_drive, vy,
                affine, y_ref, scale):
    far = 0.0
    for i in range(lo, hi):
        fam = family[i]
        if fam == 0:
            for b in range(dof):
                v[i, b] += half * (f[i, b] * ginv[i, b] - nu * v[i, b])
                dq[i, b] = dt * v[i, b]
            if affine:
                for b in range(3):
                    dqh[i, b] = dq[i, b]
                y_new = y_ref + (q[i, 1] + dq[i, 1] - y_ref) * scale
                dq[i, 1] = y_new - q[i, 1]
        elif fam == 2:
            v[i, 0] = vx_drive
            v[i, 1] = vy
            v[i, 2] = 0.0
            dq[i, 0] = dt * vx_drive
            dq[i, 1] = dt * vy
            dq[i, 2] = 0.0
        else:
            for b in range(3):
                dq[i, b] = 0.0
        if affine and fam != 0:
            for b in range(3):
                dqh[i, b] = dq[i, b]
        for b in range(3):
            q[i, b] += dq[i, b]
        ex = q[i, 0] - ref[i, 0]
        ey = q[i, 1] - ref[i, 1]
        d2 = ex * ex + ey * ey
        if not d2 < np.inf:
            return far, i
        far = max(far, d2)
    return far, -1


@hot_jit
def drift_range(lo, hi, q, v, f, dq, dqh, ginv, family, ref, dof, half, nu, dt, vx_drive, vy,
                affine, y_ref, scale):
    """First half kick and drift of particles ``lo .. hi - 1``: ``(far, bad)``.

    ``far``: the largest squared distance from the reference positions of the
    contact list; ``bad``: the first particle whose position is not finite,
    or -1 (the particles after it are left undone).  Per particle, so the
    particles may be shared among threads with the same result.  Compiled
    with the dof as a constant for the common 3.
    """
    if dof == 3:
        return _drift_body(lo, hi, q, v, f, dq, dqh, ginv, family, ref, 3, half, nu, dt,
                           vx_drive, vy, affine, y_ref, scale)
    return _drift_body(lo, hi, q, v, f, dq, dqh, ginv, family, ref, dof, half, nu, dt, vx_drive,
                       vy, affine, y_ref, scale)


@hot_inline_jit
def _kick_body(lo, hi, f, v, ginv, family, dof, half, implicit):
    for i in range(lo, hi):
        if family[i] == 0:
            for b in range(dof):
                if not abs(f[i, b]) < np.inf:
                    return i
                v[i, b] = (v[i, b] + half * f[i, b] * ginv[i, b]) * implicit
    return -1


@hot_jit
def kick_range(lo, hi, f, v, ginv, family, dof, half, implicit):
    """Second half kick of particles ``lo .. hi - 1``: the first with a non-finite force, or -1."""
    if dof == 3:
        return _kick_body(lo, hi, f, v, ginv, family, 3, half, implicit)
    return _kick_body(lo, hi, f, v, ginv, family, dof, half, implicit)
