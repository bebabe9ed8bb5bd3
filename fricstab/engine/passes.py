"""The passes over the contacts: forces, Jacobian blocks, history updates.

Every pass loops over the contacts in key order (:mod:`fricstab.engine.
contacts`) and calls the law through the generated dispatch
(:mod:`fricstab.generated.dispatch`, an integer switch on the law id), so one
compiled loop serves every law.  Everything here is compiled without numba's
reference counting (:data:`fricstab._numba.hot_jit`, a factor ~3 on the pass):
no function allocates; scratch space comes from the caller as ``work``
(8 + :data:`LANES`, 9) and ``jwork`` (6, 6) float64 arrays.

Generalized coordinates ``q`` (N, 3): ``x, y`` and the law's rotational
coordinate (``theta``, or Ishima's ``l = R theta``; unused by a frictionless
law, whose blocks are 4 x 4).  Forces (N, 3) are the generalized forces
conjugate to ``q``.  A wall contact's kernel works in the wall's frame: for a
ceiling (direction -1) x and y are reversed, the rotation is not.

Passes
------
:func:`eval_pass`
    Forces (and blocks ``K = dF/dq`` with the increment rule) from the stored
    histories; pure.
:func:`increment_pass`
    ``h += A(q) dq`` at the current configuration (Newton's history update).
:func:`project_pass`
    Histories onto their admissible sets at the current configuration
    (Coulomb circle, caps; zero for a lost contact).
:func:`advance_range`
    One dynamics step of a range of contacts at the new configuration,
    geometry computed once: ``h += A dq``, projection, forces, contact
    damping, each contact's forces into its own row of ``fcon``
    (:mod:`fricstab.engine.parallel` runs it on threads and gathers the rows).
:func:`contact_pass`
    Each contact's own forces (for stresses, force networks, exports).
"""

import numpy as np

from fricstab._numba import hot_inline_jit, hot_jit
from fricstab._numerics import pair_geometry_lanes, pair_overlap
from fricstab.engine.contacts import separation
from fricstab.generated.dispatch import (WIDTH, pair_advance, pair_eval, pair_project, pair_rate,
                                         wall_advance, wall_eval, wall_project, wall_rate)

__all__ = ["LANES", "advance_range", "contact_pass", "driven_contacts", "driven_force",
           "effective_masses", "eval_pass", "increment_pass", "project_pass"]


#: A listed pair with ``r^2 > (R_i + R_j)^2 (1 + APART)`` is apart by far more than
#: the round-off of r: the passes skip its kernel (a neighbour list with a skin
#: holds many such pairs).  Closer pairs go to the kernel, whose accurate overlap
#: decides.
APART = 1e-12

#: Contacts per block of :func:`advance_range`, whose pairs' geometry is
#: computed in lanes for a law with a contact width
#: (:func:`fricstab._numerics.pair_geometry_lanes`; measured in
#: docs/concepts/performance.md).  The scratch ``work`` has ``8 + LANES`` rows.
LANES = 16
#: A pair's block-position tag (``work[8 + b, 8]``) when it is apart (no lane).
APART_TAG = -1.0


@hot_inline_jit
def _apart(dx, dy, ri, rj):
    s = ri + rj
    return dx * dx + dy * dy > s * s * (1.0 + APART)


@hot_inline_jit
def _wall_y(q, i, radius, walls, w):
    """Height of particle i above wall w in the wall's frame, and the direction."""
    d = walls[w, 1]
    return (q[i, 1] - walls[w, 0]) * d, d


@hot_jit
def eval_pass(law, p, pw, walls, q, radius, lx, ly, shift, ci, cj, cm, ck, hist, ext, f,
              blocks, want_jac, dof, work, jwork):
    """Forces into ``f`` (external ``ext`` first, then contacts in order); blocks if asked.

    ``blocks`` (K, 2 dof, 2 dof): a pair's block with columns (i, j); a wall
    contact's (dof, dof) block in the top-left corner, in global axes.
    """
    n = q.shape[0]
    for a in range(n):
        for b in range(3):
            f[a, b] = ext[a, b]
    nd = 2 * dof
    fc = work[0, :nd]
    jc = jwork[:nd, :nd]
    for c in range(ci.shape[0]):
        i = ci[c]
        j = cj[c]
        if j >= 0:
            dx, dy = separation(q, i, j, cm[c], ck[c], lx, ly, shift)
            if _apart(dx, dy, radius[i], radius[j]):
                if want_jac:
                    for a in range(nd):
                        for b in range(nd):
                            blocks[c, a, b] = 0.0
                continue
            pair_eval(law, dx, dy, radius[i], radius[j], p, hist[c], fc, jc, want_jac)
            for b in range(dof):
                f[i, b] += fc[b]
                f[j, b] += fc[dof + b]
            if want_jac:
                for a in range(nd):
                    for b in range(nd):
                        blocks[c, a, b] = jc[a, b]
        else:
            y, d = _wall_y(q, i, radius, walls, -1 - j)
            wall_eval(law, y, radius[i], pw, hist[c], fc, jc, want_jac)
            for b in range(dof):
                f[i, b] += fc[b] * (d if b < 2 else 1.0)
            if want_jac:
                for a in range(nd):
                    for b in range(nd):
                        blocks[c, a, b] = 0.0
                for a in range(dof):
                    sa = d if a < 2 else 1.0
                    for b in range(dof):
                        sb = d if b < 2 else 1.0
                        blocks[c, a, b] = sa * jc[a, b] * sb


@hot_jit
def increment_pass(law, p, pw, walls, q, radius, lx, ly, shift, ci, cj, cm, ck, hist, dq, dof,
                   jwork):
    """``h += A(q) dq`` for every contact (A at the current configuration)."""
    nh = hist.shape[1]
    nd = 2 * dof
    a = jwork[:max(nh, 1), :nd]
    for c in range(ci.shape[0]):
        if nh == 0:
            break
        i = ci[c]
        j = cj[c]
        if j >= 0:
            dx, dy = separation(q, i, j, cm[c], ck[c], lx, ly, shift)
            pair_rate(law, dx, dy, radius[i], radius[j], p, a)
            for r in range(nh):
                s = 0.0
                for b in range(dof):
                    s += a[r, b] * dq[i, b] + a[r, dof + b] * dq[j, b]
                hist[c, r] += s
        else:
            y, d = _wall_y(q, i, radius, walls, -1 - j)
            a[:, :] = 0.0  # a wall form may have fewer history slots than the pair form
            wall_rate(law, y, radius[i], pw, a)
            for r in range(nh):
                s = 0.0
                for b in range(dof):
                    s += a[r, b] * dq[i, b] * (d if b < 2 else 1.0)
                hist[c, r] += s


@hot_jit
def project_pass(law, p, pw, walls, q, radius, lx, ly, shift, ci, cj, cm, ck, hist, flag):
    """Histories onto their admissible sets at the current configuration; flags set."""
    for c in range(ci.shape[0]):
        i = ci[c]
        j = cj[c]
        if j >= 0:
            dx, dy = separation(q, i, j, cm[c], ck[c], lx, ly, shift)
            flag[c] = pair_project(law, dx, dy, radius[i], radius[j], p, hist[c])
        else:
            y, d = _wall_y(q, i, radius, walls, -1 - j)
            flag[c] = wall_project(law, y, radius[i], pw, hist[c])


@hot_jit
def effective_masses(ci, cj, radius, mdamp, idamp, out):
    """The dashpots' ``m*`` and ``I_r`` of each contact into ``out[:, 0]``, ``out[:, 1]``.

    ``1/m* = 1/m_i + 1/m_j`` and ``1/I_r = 1/(I_i + m_i R_i^2) + 1/(I_j + m_j R_j^2)``
    (Lee & Hurley A4, A19) from the damping masses and inertias; a wall
    contact's partner has ``m_j = I_j = inf`` (and ``R_j = R_i``, which then
    does not matter).  Constants of a contact list: :func:`fricstab.engine.
    parallel.workspace` computes them once, :func:`advance_range` reads them.
    """
    for c in range(ci.shape[0]):
        i = ci[c]
        j = cj[c]
        mi = mdamp[i]
        ii = idamp[i]
        ri = radius[i]
        if j >= 0:
            mj = mdamp[j]
            ij = idamp[j]
            rj = radius[j]
        else:
            mj = np.inf
            ij = np.inf
            rj = ri
        out[c, 0] = 1.0 / (1.0 / mi + 1.0 / mj)
        out[c, 1] = 1.0 / (1.0 / (ii + mi * ri * ri) + 1.0 / (ij + mj * rj * rj))


@hot_inline_jit
def _damping(dx, dy, r, ri, rj, si, sj, vi, vj, kn, kt, kr, m_eff, i_eff, damp,
             rolling_slides, out):
    """Dashpot forces on i (x, y) and torques on i and j (Lee & Hurley A4, A12, A19-A22).

    ``gamma_n = 2 alpha_n sqrt(kn m*)``, ``gamma_t = 2 alpha_t sqrt(kt m*)``,
    ``C_r = 2 eta_r sqrt(I_r kr)`` with the contact's ``m*`` and ``I_r``
    (:func:`effective_masses`); ``kn, kt, kr`` the law's secant stiffnesses.
    ``vi, vj`` are generalized velocities; the physical angular velocity is
    ``v[2] / s``.  ``r = np.sqrt(dx * dx + dy * dy)``, as the caller has it.
    """
    nx = dx / r
    ny = dy / r
    tx = -ny
    ty = nx
    wi = vi[2] / si
    wj = vj[2] / sj
    vx = vi[0] - vj[0]
    vy = vi[1] - vj[1]
    vn = vx * nx + vy * ny
    vt = vx * tx + vy * ty - (ri * wi + rj * wj)
    gn = 2.0 * damp[0] * np.sqrt(kn * m_eff)
    gt = 2.0 * damp[1] * np.sqrt(kt * m_eff)
    cr = 2.0 * damp[2] * np.sqrt(i_eff * kr)
    md = 0.0 if rolling_slides else -cr * (wi - wj)
    out[0] = -gn * vn * nx + gt * vt * ny
    out[1] = -gn * vn * ny - gt * vt * nx
    out[2] = ri * gt * vt + md
    out[3] = rj * gt * vt - md


@hot_jit
def advance_range(lo, hi, law, p, pw, walls, q, dq, v, radius, rscale, box, damp, ci, cj, cm,
                  ck, hist, flag, cout, fcon, live, dof, work, want_out, f, scatter):
    """One dynamics step of contacts ``lo .. hi - 1`` at the new configuration ``q``.

    ``box = (lx, ly, shift, dshift, shift_rate)``: the periods, the
    Lees-Edwards offset, its growth over the step and its rate.  ``dq`` (N,
    3) is the displacement of the step (the image of a contact with
    ``k != 0`` moves by ``k dshift`` more in x); ``v`` the velocities of
    the drift (for the dashpots, ``damp = (alpha_n, alpha_t, eta_r)``, off
    when all are 0; their effective mass and inertia in ``fcon[c, 6:8]``,
    :func:`effective_masses`).  Each contact writes only its own rows: its generalized
    forces into ``fcon[c]`` (on i in ``0 .. dof - 1``, on j in ``dof .. 2 dof - 1``;
    a wall contact's on i in global axes), ``live[c] = 0`` for a pair apart by
    far (no force: :func:`fricstab.engine.parallel.gather_range` skips it)
    and 1 otherwise; ``cout[c]`` = force on i (x, y) and the elastic normal
    force, written only ``if want_out`` (a caller reads them after its last
    step).  So contacts may be
    advanced in any order or on several threads with the same result.

    With ``scatter`` (one thread, all contacts) each contact also adds its
    forces to ``f[i]`` and ``f[j]`` (which hold the applied forces), in
    contact order: the same sums, to the bit, as
    :func:`fricstab.engine.parallel.gather_range` forms, without a second
    pass.

    The loop is compiled once per law, with the law id and the dof as
    constants (the law's kernel alone in its loop, the dispatch folded away,
    the loops over the dof unrolled), and once with both as variables (the
    frictionless ``hertz``, whose dof is 2, and any law added without a
    branch here); one compiled signature serves them all.  What each choice
    of the loop is worth is measured in docs/concepts/performance.md.
    """
    # one branch per law with a rotation (dispatch.N_DOF[law] == 3); the last
    # branch is correct for every law
    if law == 1 and dof == 3:
        _advance_loop(lo, hi, 1, p, pw, walls, q, dq, v, radius, rscale, box, damp, ci, cj,
                      cm, ck, hist, flag, cout, fcon, live, 3, work, want_out, f, scatter)
    elif law == 2 and dof == 3:
        _advance_loop(lo, hi, 2, p, pw, walls, q, dq, v, radius, rscale, box, damp, ci, cj,
                      cm, ck, hist, flag, cout, fcon, live, 3, work, want_out, f, scatter)
    elif law == 3 and dof == 3:
        _advance_loop(lo, hi, 3, p, pw, walls, q, dq, v, radius, rscale, box, damp, ci, cj,
                      cm, ck, hist, flag, cout, fcon, live, 3, work, want_out, f, scatter)
    else:
        _advance_loop(lo, hi, law, p, pw, walls, q, dq, v, radius, rscale, box, damp, ci, cj,
                      cm, ck, hist, flag, cout, fcon, live, dof, work, want_out, f, scatter)


@hot_inline_jit
def _advance_loop(lo, hi, law, p, pw, walls, q, dq, v, radius, rscale, box, damp, ci, cj, cm,
                  ck, hist, flag, cout, fcon, live, dof, work, want_out, f, scatter):
    """The body of :func:`advance_range`, inlined into it once per law branch.

    For a law with a contact width (``WIDTH[law]``, Lee & Hurley) the
    contacts go in blocks of :data:`LANES`: first the geometry of the block's
    pairs that are not apart (separation, centre distance, accurate overlap
    and the width's solve), lane by lane
    (:func:`fricstab._numerics.pair_geometry_lanes`: the values are one
    contact's to the bit, the processor overlaps the lanes' square roots and
    logarithms); then each contact of the block in order.  For the other
    laws each contact computes its own (:func:`fricstab._numerics.pair_overlap`,
    the same values): their geometry is short, and the lanes' stores and
    loads cost more than they overlap (packing, Ishima: 87 us a step against
    109 in lanes; docs/concepts/performance.md).
    Particle indices are read as unsigned integers where they index arrays:
    numba then omits the wraparound of negative indices (a wall contact's
    ``j < 0`` is decoded before).  The kernels write ``aux`` only when a
    dashpot or ``cout`` reads it (``want_aux``).
    """
    lx, ly, shift, dshift, shift_rate = box[0], box[1], box[2], box[3], box[4]
    nd = 2 * dof
    du = work[1, :nd]
    aux = work[2, :4]
    dmp = work[3, :4]
    vj = work[4, :3]
    zero3 = work[5, :3]
    zero3[:] = 0.0
    # rows 8 ..: the lanes (columns LANE_COLUMNS) and, in column 8 of row 8 + b,
    # the lane of the pair at block position b, or APART_TAG (walls: no tag)
    lanes = work[8:8 + LANES, :8]
    tags = work[8:8 + LANES, 8]
    width = WIDTH[law]
    damped = damp[0] > 0.0 or damp[1] > 0.0 or damp[2] > 0.0
    want_aux = damped or want_out   # the kernels' aux: the dashpots' stiffnesses, cout[:, 2]
    # scatter: the force on the current i is summed in registers (contacts are
    # sorted by i) and stored when i changes; the same additions in the same order
    cur = -1
    a0 = a1 = a2 = 0.0
    for blo in range(lo, hi, LANES):
        bhi = min(blo + LANES, hi)
        if width:
            n = 0
            for c in range(blo, bhi):
                j = cj[c]
                if j < 0:
                    continue
                iu = np.uint64(ci[c])
                ju = np.uint64(j)
                dx, dy = separation(q, iu, ju, cm[c], ck[c], lx, ly, shift)
                ri = radius[iu]
                rj = radius[ju]
                if _apart(dx, dy, ri, rj):
                    tags[c - blo] = APART_TAG
                    continue
                tags[c - blo] = n
                lanes[n, 0] = dx
                lanes[n, 1] = dy
                lanes[n, 2] = ri
                lanes[n, 3] = rj
                n += 1
            pair_geometry_lanes(lanes, n, width)
        for c in range(blo, bhi):
            i = ci[c]
            j = cj[c]
            iu = np.uint64(i)
            fc = fcon[c, :nd]
            if scatter and i != cur:
                if cur >= 0:
                    f[cur, 0] = a0
                    f[cur, 1] = a1
                    f[cur, 2] = a2
                cur = i
                a0 = f[iu, 0]
                a1 = f[iu, 1]
                a2 = f[iu, 2]
            live[c] = 1
            if j >= 0:
                ju = np.uint64(j)
                if width:   # the lanes hold the geometry
                    k = int(tags[c - blo])
                    apart = k < 0   # APART_TAG
                    if not apart:
                        dx = lanes[k, 0]
                        dy = lanes[k, 1]
                        ri = lanes[k, 2]
                        rj = lanes[k, 3]
                        r = lanes[k, 4]
                        delta = lanes[k, 5]
                        lam = lanes[k, 6]
                else:   # the same values, contact by contact (no lanes: cheaper for these laws)
                    dx, dy = separation(q, iu, ju, cm[c], ck[c], lx, ly, shift)
                    ri = radius[iu]
                    rj = radius[ju]
                    apart = _apart(dx, dy, ri, rj)
                    if not apart:
                        r, delta = pair_overlap(dx, dy, ri, rj)
                        lam = 0.0
                if apart:
                    for b in range(hist.shape[1]):
                        hist[c, b] = 0.0  # a contact that opened forgets its history
                    flag[c] = 0
                    live[c] = 0
                    if want_out:
                        cout[c, 0] = 0.0
                        cout[c, 1] = 0.0
                        cout[c, 2] = 0.0
                    continue
                fl = pair_advance(law, dx, dy, ri, rj, r, delta, lam, p, hist[c], dq[iu], dq[ju],
                                  ck[c] * dshift, fc, aux, want_aux)
                if damped and aux[3] > 0.0:
                    for b in range(3):
                        vj[b] = v[ju, b]
                    vj[0] += ck[c] * shift_rate
                    _damping(dx, dy, r, ri, rj, rscale[iu], rscale[ju], v[iu], vj, aux[0],
                             aux[1], aux[2], fcon[c, 6], fcon[c, 7], damp, (fl & 2) != 0, dmp)
                    fc[0] += dmp[0]
                    fc[1] += dmp[1]
                    fc[dof] -= dmp[0]
                    fc[dof + 1] -= dmp[1]
                    if dof == 3:
                        fc[2] += dmp[2] / rscale[iu]
                        fc[5] += dmp[3] / rscale[ju]
            else:
                w = -1 - j
                d = walls[w, 1]
                y = (q[i, 1] - walls[w, 0]) * d
                for b in range(dof):
                    du[b] = dq[i, b] * (d if b < 2 else 1.0)
                fl = wall_advance(law, y, radius[i], pw, hist[c], du, fc, aux, want_aux)
                if damped and aux[3] > 0.0:
                    vj[0] = d * v[i, 0]
                    vj[1] = d * v[i, 1]
                    vj[2] = v[i, 2]
                    # the wall as a still partner below, in the wall's frame (infinite
                    # mass and inertia: the contact's m* and I_r, effective_masses)
                    rw = radius[i] + abs(y)
                    _damping(0.0, rw, np.sqrt(rw * rw), radius[i], radius[i], rscale[i],
                             1.0, vj, zero3, aux[0], aux[1], aux[2], fcon[c, 6], fcon[c, 7],
                             damp, (fl & 2) != 0, dmp)
                    fc[0] += dmp[0]
                    fc[1] += dmp[1]
                    if dof == 3:
                        fc[2] += dmp[2] / rscale[i]
                fc[0] = fc[0] * d
                fc[1] = fc[1] * d
            if scatter:
                a0 += fc[0]
                a1 += fc[1]
                if dof == 3:
                    a2 += fc[2]
                if j == i:   # i's own periodic image
                    a0 += fc[dof]
                    a1 += fc[dof + 1]
                    if dof == 3:
                        a2 += fc[5]
                elif j >= 0:   # ju: set in the pair branch above
                    for b in range(dof):
                        f[ju, b] += fc[dof + b]
            flag[c] = fl
            if want_out:
                cout[c, 0] = fc[0]
                cout[c, 1] = fc[1]
                cout[c, 2] = aux[3]
    if cur >= 0:
        f[cur, 0] = a0
        f[cur, 1] = a1
        f[cur, 2] = a2


@hot_jit
def driven_force(drv, ci, cj, live, fcon, family, meas):
    """``meas[0:2]``: the pair-contact force on the driven particles (family 2), in contact order.

    ``drv`` (:func:`driven_contacts`) lists the contacts that may touch them: the
    same sums as a loop over every contact, reading 1 row in 36 (quick shear cell)
    to 54 (the paper's) of ``fcon``, on the calling thread.
    """
    meas[0] = 0.0
    meas[1] = 0.0
    for c in drv:
        j = cj[c]
        if j < 0 or not live[c]:
            continue
        if family[ci[c]] == 2:
            meas[0] += fcon[c, 0]
            meas[1] += fcon[c, 1]
        if family[j] == 2:
            meas[0] -= fcon[c, 0]
            meas[1] -= fcon[c, 1]


def driven_contacts(ci, cj, family):
    """The contacts with a driven particle (family 2) on either side, in increasing order."""
    ci, cj = np.asarray(ci), np.asarray(cj)
    pair = cj >= 0
    touch = family[ci] == 2
    touch[pair] |= family[cj[pair]] == 2
    return np.flatnonzero(touch).astype(np.int64)


@hot_jit
def contact_pass(law, p, pw, walls, q, radius, lx, ly, shift, ci, cj, cm, ck, hist, out, dof,
                 work, jwork):
    """Per-contact generalized forces on particle i (and j) from the stored histories.

    ``out`` (K, 2 dof): a pair's forces on i then j; a wall contact's force
    on i in global axes in the first ``dof`` entries (the rest 0).
    """
    nd = 2 * dof
    fc = work[0, :nd]
    jc = jwork[:nd, :nd]
    for c in range(ci.shape[0]):
        i = ci[c]
        j = cj[c]
        for b in range(nd):
            out[c, b] = 0.0
        if j >= 0:
            dx, dy = separation(q, i, j, cm[c], ck[c], lx, ly, shift)
            pair_eval(law, dx, dy, radius[i], radius[j], p, hist[c], fc, jc, False)
            for b in range(nd):
                out[c, b] = fc[b]
        else:
            y, d = _wall_y(q, i, radius, walls, -1 - j)
            wall_eval(law, y, radius[i], pw, hist[c], fc, jc, False)
            for b in range(dof):
                out[c, b] = fc[b] * (d if b < 2 else 1.0)
