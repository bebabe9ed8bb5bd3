"""Velocity Verlet for every scene, with drag and the controllers at fixed points.

One step (free particles; :mod:`fricstab.engine.system` for the families)::

    v += dt/2 (M^-1 F - nu v)             half kick, drag at the old velocity
    driven body: v = (V_x, V_y or servo)  controller
    q += dt v  (+ affine y, + LE offset)   drift; dq the displacement
    [contacts rebuilt if a particle moved half the skin]
    F = advance_pass(q, dq, v)            histories advanced by the increment rule
                                          at the new configuration, projected,
                                          forces (+ dashpots, + applied forces)
    v = (v + dt/2 M^-1 F) / (1 + dt/2 nu) second half kick, drag implicit

``nu = 0`` is Newtonian dynamics.  The servo (LIGGGHTS-style) sets the driven
body's ``v_y = -g (N_target - N)`` clipped to ``|v_y| <= v_max``, with ``N``
the summed y contact force on the driven particles of the previous step.
``affine_y`` moves the free particles' y with the driven body (a compression
that need not wait for the disks to travel); the affine part of that move is a
preparation device, not a relative motion of contacts: the histories advance
with the dynamic displacement ``dt v`` only, as in the preparation of the
plane-shear cell before the engine.  The Lees-Edwards offset grows
by ``rate dt`` per step.

Contacts and particles are visited in a fixed order, and the dynamics pass
sums every force in that order whatever the thread count
(:mod:`fricstab.engine.parallel`), so a run restarted from a saved state
(:meth:`State.arrays`) at a step boundary is bit-identical to an uninterrupted
one on the same machine, with any ``--threads``.

The compiled loop returns to Python at least every :data:`CHUNK` particle-steps
(about a second), where a pending SIGINT or SIGTERM stops the run
(:func:`fricstab.signals.check`); the chunks do not change a bit of the result.
"""

from dataclasses import dataclass

import numpy as np
from numba import prange

from fricstab import signals
from fricstab._numba import hot_jit, threads_jit
from fricstab.engine import parallel, passes, team
from fricstab.engine.integrate import drift_range
from fricstab.errors import NumericalError

__all__ = ["Controls", "Run", "run"]

OK, REBUILD, BAD_FORCE, BAD_STATE, CONVERGED, BAD_LAW, NO_TEAM = 0, 1, 2, 3, 4, 5, 6
#: Particle-steps between returns to Python (signal checks): ~0.2-1 s of work.
CHUNK = 1 << 21


@dataclass(frozen=True)
class Controls:
    """Controllers of a run (all off by default).

    Parameters
    ----------
    drag : float
        Global viscous drag rate ``nu`` on free particles (1/time): the force
        ``-m nu v`` of Charan's damped protocol.
    drive : (float, float)
        Velocity ``(V_x, V_y)`` of the driven particles (family 2; length/time).
    servo : (gain, target, vmax) or None
        Replaces ``V_y`` by ``-gain (target - N)`` clipped to ``vmax``: a
        velocity servo on the normal force N on the driven body (Lee & Hurley
        Sec. 2; gain in length/(time force), target in force, vmax in
        length/time).
    affine_y : float or None
        With a driven body: the free particles' y follow its vertical motion
        affinely about this reference height (length).
    shear_rate : float
        Growth rate of the Lees-Edwards offset (length/time).
    """

    drag: float = 0.0
    drive: tuple = (0.0, 0.0)
    servo: tuple = None
    affine_y: float = None
    shear_rate: float = 0.0

    def array(self):
        gain, target, vmax = self.servo if self.servo is not None else (0.0, 0.0, 0.0)
        return np.array([self.drag, self.drive[0], self.drive[1], gain, target, vmax,
                         0.0 if self.affine_y is None else 1.0,
                         0.0 if self.affine_y is None else self.affine_y, self.shear_rate,
                         0.0])


@dataclass
class Run:
    """Outcome of :func:`run`: steps done, whether ``tol`` was reached, the residual,
    recorded frames (``times``, ``q``, ``v``, ``hist`` if asked), the measured
    contact force on the driven body (x, y) of the last step, and the forces of
    the last step (dashpots included: what a continued run passes as ``forces``)."""

    steps: int
    converged: bool
    residual: float
    times: np.ndarray
    q: np.ndarray
    v: np.ndarray
    hist: np.ndarray
    driven_force: np.ndarray
    forces: np.ndarray = None


@hot_jit
def _driven_height(q, family):
    """``(mean y of the driven particles, their count)``; (0, 0) without any."""
    y_top = 0.0
    n_drv = 0
    for i in range(q.shape[0]):
        if family[i] == 2:
            y_top += q[i, 1]
            n_drv += 1
    if n_drv:
        y_top /= n_drv
    return y_top, n_drv


@hot_jit
def _box(box, lx, ly, rate, dt):
    """Fill ``box`` (a row of the workspace) with the passes' ``(lx, ly, shift, dshift,
    shift rate)`` but the shift, which the loop sets each step."""
    box[0] = lx
    box[1] = ly
    box[3] = rate * dt
    box[4] = rate


@hot_jit
def _record(frame, q, v, hist, rec_q, rec_v, rec_h):
    """Frame ``frame`` of the records: ``q``, ``v`` and, if ``rec_h`` has frames, ``hist``."""
    for i in range(q.shape[0]):
        for b in range(3):
            rec_q[frame, i, b] = q[i, b]
            rec_v[frame, i, b] = v[i, b]
    if rec_h.shape[0]:
        for c in range(hist.shape[0]):
            for b in range(hist.shape[1]):
                rec_h[frame, c, b] = hist[c, b]


@hot_jit
def _loop(law, p, pw, walls, q, v, f, dq, ginv, radius, rscale, family, ext, lx, ly, shiftv, ci,
          cj, cm, ck, hist, flag, cout, ref, skin, dof, damp, ctrl, meas, dt, step0, n_steps, mid,
          record_every, frame0, rec_q, rec_v, rec_h, tol, check_every, dqh, fcon, live, pstart,
          pidx, drv, work, share):
    """Steps ``step0 .. n_steps - 1``; returns (step, status, item, frame, residual).

    ``shiftv = [shift, ref_shift, time]`` is updated in place.  ``mid``: the
    drift of step ``step0`` is done (a rebuild interrupted it).  ``dqh`` holds the
    displacement the histories see (``dq`` without the affine move).
    """
    n = q.shape[0]
    nu, vx_drive, vy_drive = ctrl[0], ctrl[1], ctrl[2]
    gain, target, vmax = ctrl[3], ctrl[4], ctrl[5]
    affine, y_ref, rate = ctrl[6] > 0.0, ctrl[7], ctrl[8]
    half = 0.5 * dt
    implicit = 1.0 / (1.0 + half * nu)  # the second half kick's drag, implicit
    frame = frame0
    residual = np.inf
    y_top, n_drv = _driven_height(q, family)
    lim = skin * skin
    box = work[0, 7, :5]   # (lx, ly, shift, dshift, shift rate) of the passes
    _box(box, lx, ly, rate, dt)
    for step in range(step0, n_steps):
        if not (mid and step == step0):
            if record_every > 0 and step % record_every == 0 and frame < rec_q.shape[0]:
                _record(frame, q, v, hist, rec_q, rec_v, rec_h)
                frame += 1
            vy = vy_drive
            if gain > 0.0:
                vy = -gain * (target - meas[1])
                vy = min(max(vy, -vmax), vmax)
            meas[3] = vy
            scale = 1.0
            if affine and n_drv and y_top - y_ref != 0.0:
                scale = 1.0 + vy * dt / (y_top - y_ref)
            # lo = n - n: 0, and not a literal constant (which would compile another drift_range)
            far, bad = drift_range(n - n, n, q, v, f, dq, dqh, ginv, family, ref, dof, half, nu,
                                   dt, vx_drive, vy, affine, y_ref, scale)
            if bad >= 0:
                return step, BAD_STATE, bad, frame, residual
            y_top += vy * dt
            meas[2] += vx_drive * dt
            shiftv[0] += rate * dt
            shiftv[2] += dt
            gap = 2.0 * np.sqrt(far) + abs(shiftv[0] - shiftv[1])
            if skin > 0.0 and gap * gap > lim:
                return step, REBUILD, -1, frame, residual
        hq = dqh if affine else dq
        box[2] = shiftv[0]
        # forces, then each particle's second half kick (kick = n_drv >= 0: True, and not a
        # literal constant, which would compile another advance_pass beside FIRE's)
        bad, bad_f = parallel.advance_pass(law, p, pw, walls, q, hq, v, radius, rscale, box,
                                           damp, ci, cj, cm, ck, hist, flag, cout, ext, family,
                                           f, dof, meas, step == n_steps - 1, n_drv > 0, fcon,
                                           live, pstart, pidx, drv, work, share, ginv, half,
                                           implicit, n_drv >= 0)
        if bad >= 0:
            return step + 1, BAD_LAW, bad, frame, residual
        if bad_f >= 0:
            return step + 1, BAD_FORCE, bad_f, frame, residual
        if tol > 0.0 and step % check_every == 0:
            residual = 0.0
            for i in range(n):
                if family[i] == 0:
                    for b in range(dof):
                        residual = max(residual, abs(f[i, b]))
            if residual < tol:
                return step + 1, CONVERGED, -1, frame, residual
    return n_steps, OK, -1, frame, residual


@hot_jit
def _drift_share(w, q, v, f, dq, dqh, ginv, family, ref, dof, half, nu, dt, vx_drive, vy, affine,
                 y_ref, scale, share):
    """Thread w's parts of :func:`drift_range` (:func:`fricstab.engine.team.claim`):
    ``(far, bad)`` over its parts."""
    parts = team.parts_of(share)
    n = q.shape[0]
    far = 0.0
    bad = -1
    t, d = team.next_part(share, w, team.DRIFT, 0)
    while t >= 0:
        far_t, bad_t = drift_range(t * n // parts, (t + 1) * n // parts, q, v, f, dq, dqh, ginv,
                                   family, ref, dof, half, nu, dt, vx_drive, vy, affine, y_ref,
                                   scale)
        far = max(far, far_t)
        bad = team.first(bad, bad_t)
        t, d = team.next_part(share, w, team.DRIFT, d)
    return far, bad


@hot_jit
def _member(w, law, p, pw, walls, q, v, f, dq, ginv, radius, rscale, family, ext, lx, ly, shiftv,
            ci, cj, cm, ck, hist, flag, cout, ref, skin, dof, damp, ctrl, meas, dt, step0,
            n_steps, mid, record_every, frame0, rec_q, rec_v, rec_h, tol, check_every, dqh,
            fcon, live, pstart, pidx, drv, work, share):
    """Thread w's part of :func:`_loop`'s steps, run by every thread of the team at once.

    The same step as :func:`_loop`: each loop over the contacts or the
    particles shared out in parts (:mod:`fricstab.engine.team`), the
    threads meeting at a barrier after each; every decision (rebuild, error,
    convergence) is taken by every thread from what all of them wrote before
    the barrier, so all leave at the same step.  Thread 0 alone writes the
    shared scalars (``meas``, ``shiftv``, the records) and the result:
    ``share[0, 3:7]`` = (step, status, item, frame), ``work[0, 6, 5]`` the
    residual.
    """
    n_threads = team.threads_of(share)
    lead = w == 0
    n = q.shape[0]
    nu, vx_drive, vy_drive = ctrl[0], ctrl[1], ctrl[2]
    gain, target, vmax = ctrl[3], ctrl[4], ctrl[5]
    affine, y_ref, rate = ctrl[6] > 0.0, ctrl[7], ctrl[8]
    half = 0.5 * dt
    implicit = 1.0 / (1.0 + half * nu)
    frame = frame0
    residual = np.inf
    y_top, n_drv = _driven_height(q, family)
    shift, ref_shift, clock = shiftv[0], shiftv[1], shiftv[2]
    lim = skin * skin
    box = work[w, 7, :5]   # this thread's
    _box(box, lx, ly, rate, dt)
    hq = dqh if affine else dq
    stop, status, item = n_steps, OK, -1
    if not team.gate(share):   # everyone has read q before anyone moves it
        return   # a thread never came: nothing changed (_team says NO_TEAM)
    for step in range(step0, n_steps):
        if not (mid and step == step0):
            if record_every > 0 and step % record_every == 0 and frame < rec_q.shape[0]:
                if lead:
                    _record(frame, q, v, hist, rec_q, rec_v, rec_h)
                frame += 1
                team.barrier(share)   # recorded before anyone moves on
            vy = vy_drive
            if gain > 0.0:
                vy = -gain * (target - meas[1])
                vy = min(max(vy, -vmax), vmax)
            scale = 1.0
            if affine and n_drv and y_top - y_ref != 0.0:
                scale = 1.0 + vy * dt / (y_top - y_ref)
            far, bad = _drift_share(w, q, v, f, dq, dqh, ginv, family, ref, dof, half, nu, dt,
                                    vx_drive, vy, affine, y_ref, scale, share)
            work[w, 6, 0] = far
            share[w, 2] = bad
            team.barrier(share)
            for u in range(n_threads):
                far = max(far, work[u, 6, 0])
                bad = team.first(bad, share[u, 2])
            if lead:
                team.reset(share, team.DRIFT)
                meas[3] = vy
            if bad >= 0:
                stop, status, item = step, BAD_STATE, bad
                break
            y_top += vy * dt
            if lead:
                meas[2] += vx_drive * dt
            shift += rate * dt
            clock += dt
            gap = 2.0 * np.sqrt(far) + abs(shift - ref_shift)
            if skin > 0.0 and gap * gap > lim:
                stop, status = step, REBUILD
                break
        box[2] = shift
        bad = parallel.contacts_share(w, law, p, pw, walls, q, hq, v, radius, rscale, box, damp,
                                      ci, cj, cm, ck, hist, flag, cout, fcon, live, dof, work,
                                      step == n_steps - 1, share)
        share[w, 0] = bad
        team.barrier(share)
        for u in range(n_threads):
            bad = team.first(bad, share[u, 0])
        if bad >= 0:
            stop, status, item = step + 1, BAD_LAW, bad
            break
        if lead:
            team.reset(share, team.CONTACTS)
            if n_drv > 0:
                passes.driven_force(drv, ci, cj, live, fcon, family, meas)
            else:
                meas[0] = 0.0
                meas[1] = 0.0
        check = tol > 0.0 and step % check_every == 0
        bad_f, largest = parallel.gather_share(w, ext, fcon, live, pstart, pidx, dof, f, v, ginv,
                                               family, half, implicit, n_drv >= 0, check, share)
        share[w, 1] = bad_f
        work[w, 6, 2] = largest
        team.barrier(share)
        for u in range(n_threads):
            bad_f = team.first(bad_f, share[u, 1])
            largest = max(largest, work[u, 6, 2])
        if lead:
            team.reset(share, team.GATHER)
        if bad_f >= 0:
            stop, status, item = step + 1, BAD_FORCE, bad_f
            break
        if check:
            residual = largest
            if residual < tol:
                stop, status = step + 1, CONVERGED
                break
    if lead:
        shiftv[0], shiftv[2] = shift, clock
        share[0, 3], share[0, 4], share[0, 5], share[0, 6] = stop, status, item, frame
        work[0, 6, 5] = residual


@threads_jit
def _team(law, p, pw, walls, q, v, f, dq, ginv, radius, rscale, family, ext, lx, ly, shiftv, ci,
          cj, cm, ck, hist, flag, cout, ref, skin, dof, damp, ctrl, meas, dt, step0, n_steps, mid,
          record_every, frame0, rec_q, rec_v, rec_h, tol, check_every, dqh, fcon, live, pstart,
          pidx, drv, work, share):
    """:func:`_loop` on the workspace's threads, in one parallel region (:func:`_member`).

    Every thread of the workspace must run at once (they wait for each other:
    :func:`fricstab.engine.parallel.team_ready`).
    """
    for loop in (team.CONTACTS, team.GATHER, team.DRIFT):
        team.reset(share, loop)
    team.open_gate(share)
    for w in prange(team.threads_of(share)):
        _member(w, law, p, pw, walls, q, v, f, dq, ginv, radius, rscale, family, ext, lx, ly,
                shiftv, ci, cj, cm, ck, hist, flag, cout, ref, skin, dof, damp, ctrl, meas, dt,
                step0, n_steps, mid, record_every, frame0, rec_q, rec_v, rec_h, tol, check_every,
                dqh, fcon, live, pstart, pidx, drv, work, share)
    if team.gate_closed(share):
        return step0, NO_TEAM, -1, frame0, np.inf
    return share[0, 3], share[0, 4], share[0, 5], share[0, 6], work[0, 6, 5]


def _culprit(system, state, particle):
    """``" from pair (i, j)"`` naming a contact of ``particle`` whose force is not finite."""
    c = state.contacts
    try:
        fc = system.contact_forces(state)
    except (ValueError, ArithmeticError) as exc:  # the law refused the configuration
        return f" ({exc})"
    bad = np.flatnonzero(~np.all(np.isfinite(fc), axis=1) & ((c.i == particle) | (c.j == particle)))
    if not len(bad):
        return ""
    k = bad[0]
    return (f" from pair ({c.i[k]}, {c.j[k]})" if c.j[k] >= 0 else
            f" from its contact with wall {-1 - c.j[k]}")


def law_error(system, state, contact):
    """The ValueError a contact kernel raised on a thread (where it cannot propagate)."""
    system.contact_forces(state)   # the same law at the same overlaps: raises it here
    c = state.contacts
    raise ValueError(f"the contact law refused contact ({c.i[contact]}, {c.j[contact]}) or one "
                     "listed after it")


def run(system, state, dt, n_steps, controls=Controls(), *, record_every=0, record_hist=False,
        tol=0.0, check_every=100, forces=None, step0=0, meas=None):
    """Advance ``state`` in place by velocity Verlet steps ``step0`` to ``n_steps - 1`` of ``dt``.

    Each step: half kick, drift, the histories advanced by the law's increment
    rule at the new configuration and projected onto their admissible set
    (Coulomb circle, caps), forces with the dashpots, half kick; the controllers
    of ``controls`` act on the driven particles.

    Parameters
    ----------
    system : System
    state : State
        Modified in place.
    dt : float
        Time step (time units of the scene).
    n_steps : int
        Index of the step to stop before (with ``step0``, a resumed run).
    controls : Controls
        Drag, drive, servo, affine motion, shear rate.
    record_every : int
        Record ``q``, ``v`` (and the histories if ``record_hist``; only for a
        contact list that never changes, e.g. the chain's) before every that
        many steps; 0: no record.
    record_hist : bool
        Also record the histories.
    tol : float
        Stop early when ``max |F|`` over the free dof falls below it (force;
        checked every ``check_every`` steps); 0: never.
    check_every : int
        Steps between checks of ``tol`` (and of interrupts).
    forces : ndarray, shape (N, 3), optional
        The forces of ``state`` (computed from its projected histories if
        omitted; a resumed run passes the forces it saved, which include the
        dashpots of the last step).
    step0 : int
        Index of the first step (a resumed run).
    meas : ndarray, shape (8,), optional
        Controller measurements carried between calls (driven-body force,
        driven displacement); created if omitted and returned in the Run.

    Returns
    -------
    Run
        ``steps`` done, ``converged`` (``tol`` reached), ``residual``, the
        recorded ``times``, ``q``, ``v``, ``hist``, the measured force on the
        driven body and the forces of the last step.

    Raises
    ------
    NumericalError
        A non-finite contact force or position (names the step and the
        contact or particle).
    """
    if forces is None:
        system.project(state)
        f = system.forces(state)
    else:
        f = np.array(forces, float)
    meas = np.zeros(8) if meas is None else meas
    ctrl = controls.array()
    every = max(record_every, 1)
    first = -(-step0 // every) * every   # the first recorded step: a multiple of every
    n_frames = 0 if record_every <= 0 else max(0, -(-n_steps // every) - first // every)
    c = state.contacts
    rec_q = np.empty((n_frames, system.n, 3))
    rec_v = np.empty((n_frames, system.n, 3))
    rec_h = np.empty((n_frames if record_hist else 0, c.n, c.hist.shape[1]))
    dq = np.zeros((system.n, 3))
    dqh = np.zeros((system.n, 3))
    n_chunks = parallel.chunks(system.n)
    shiftv = np.array([state.shift, state.ref_shift, state.time])
    step, mid, frame = step0, False, 0
    residual, converged = np.inf, False
    chunk = max(1, CHUNK // max(system.n, 1))
    end = step0
    space = None
    while step < n_steps:
        if step >= end:   # a call or a chunk begins: the state is at a step boundary
            signals.check(f" at step {step}", step)
            end = min(n_steps, step + chunk)
        if state.contacts is not c or space is None:
            c = state.contacts
            space = parallel.workspace(c, system, n_chunks)
        if record_hist and c.n != rec_h.shape[1]:
            raise ValueError("record_hist needs a contact list that never changes")
        loop = _team if parallel.team_ready(n_chunks) else _loop
        step, status, item, frame, residual = loop(
            system.law_id, system._p, system._pw, system.walls, state.q, state.v, f, dq,
            system.ginv, system.radius, system.rscale, system.family, system.external,
            float(system.lx), float(system.ly), shiftv, c.i, c.j, c.m, c.k, c.hist, c.flag,
            c.out, state.ref, float(system.skin), system.dof, system.damping, ctrl, meas,
            float(dt), step, end, mid, record_every, frame, rec_q, rec_v, rec_h, float(tol),
            check_every, dqh, *space)
        if status == NO_TEAM:   # nothing changed: the same steps, a region per loop
            parallel.team_failed()
            continue
        state.shift, state.ref_shift, state.time = shiftv
        mid = False
        if status == REBUILD:
            system.rebuild(state)
            shiftv[1] = state.ref_shift
            mid = True
        elif status == BAD_STATE:
            raise NumericalError(f"non-finite position of particle {item} at step {step + 1}",
                                 step=step + 1, item=int(item), quantity="position")
        elif status == BAD_FORCE:
            raise NumericalError(f"non-finite force on particle {item} at step {step}"
                                 f"{_culprit(system, state, item)}", step=int(step),
                                 item=int(item), quantity="force")
        elif status == BAD_LAW:
            law_error(system, state, item)
        elif status == CONVERGED:
            converged = True
            break
    times = (first + np.arange(frame) * every) * dt
    return Run(step, converged, float(residual), times, rec_q[:frame], rec_v[:frame],
               rec_h[:frame], meas, f)
