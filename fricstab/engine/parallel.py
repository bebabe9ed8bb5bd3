"""The dynamics pass on threads, the same to the bit at every thread count.

One step of the contacts is two loops, each shared among the threads
(:func:`contacts_share`, :func:`gather_share`):

1. over the contacts (:func:`fricstab.engine.passes.advance_range`): each
   contact advances its own history and writes its forces on i and j into its
   own row of ``fcon``; no two contacts write the same memory;
2. over the particles (:func:`gather_range`): each
   particle sums the applied force and then its contacts' rows in increasing
   contact order, from a list built once per contact list (:func:`workspace`).

That order is the order in which one serial loop over the contacts scattering
into i and j adds them (what the pass does on one thread, in one loop), so
every thread count gives the serial result to the bit, and a run resumed from
a checkpoint (``--resume``) stays bit-identical whatever ``--threads`` either
part ran with.  The integrator's half kicks and drift are per particle and
share the particles the same way.  Each loop is cut into parts that the
threads take from each other's shares when they run out of their own
(:mod:`fricstab.engine.team`): which thread does a part changes no bit.

:func:`fricstab.engine.verlet.run` runs all the steps of a call in one
parallel region whose threads meet at a barrier after each loop, three a
step (:func:`team_ready`); FIRE, and the velocity Verlet loop where the
threads cannot all run at once, open a region per pass (:func:`advance_pass`).

The thread count is numba's (``NUMBA_NUM_THREADS``, all cores by default;
:func:`set_threads` sets it at run time, ``fricstab --threads N``).  A system
below :data:`PARALLEL_MIN` particles runs on one thread: there the cost of
meeting the threads three times a step exceeds the work (the chain has 10
disks and ~20 contacts, ~1 us a step).  Left at its default (no
:func:`set_threads`), a run also stays on one thread when the machine is busy
(:func:`busy`): a core taken by another job delays every meeting (measured on
the project's 2-core machine with other jobs running: packing N = 1,024, two
threads 0.6e6-7e6 particle-steps/s against one thread's 8e6-9e6).  An
explicit count is always used.  The threads spin briefly between regions
(:mod:`fricstab._numba`) and at the team's barriers (:mod:`fricstab.engine.team`).
"""

import os
import time
import warnings

import numba
import numpy as np
from numba import prange
from numba.np.ufunc.parallel import _launch_threads

from fricstab._numba import hot_inline_jit, hot_jit, threads_jit
from fricstab.engine import passes, team
from fricstab.engine.integrate import kick_range
from fricstab.errors import ParameterError

__all__ = ["PARALLEL_MIN", "advance_pass", "available_threads", "busy", "chunks", "contacts_share",
           "gather_range", "gather_share", "layout", "own_load", "set_threads", "team_failed",
           "team_ready", "workspace"]

#: Particles below which the dynamics pass stays on one thread (measured:
#: docs/concepts/performance.md).
PARALLEL_MIN = 256

_explicit = False   # set_threads was called: use that count whatever the load
_team_failed = False   # a team's threads did not all run at once (team_failed)


def available_threads():
    """The most threads numba may use (``NUMBA_NUM_THREADS``, default the core count)."""
    return int(numba.config.NUMBA_NUM_THREADS)


def set_threads(n):
    """Use ``n`` threads from now on (1 <= n <= :func:`available_threads`)."""
    top = available_threads()
    try:
        n = int(n)
    except (TypeError, ValueError):
        raise ParameterError(f"threads must be an integer, got {n!r}") from None
    if not 1 <= n <= top:
        raise ParameterError(f"threads must be between 1 and {top} (NUMBA_NUM_THREADS), got {n}")
    global _explicit
    numba.set_num_threads(n)
    _explicit = True


_own = [time.perf_counter(), time.process_time(), 0.0]   # wall, CPU, this process's load


def own_load():
    """This process's recent CPU use in cores (busy threads), averaged over about a minute.

    Updated at each call from the CPU time used since the last update (at
    least a second earlier), with the 1-minute memory of the load average.
    """
    wall, cpu = time.perf_counter(), time.process_time()
    span = wall - _own[0]
    if span >= 1.0:
        weight = 1.0 - np.exp(-span / 60.0)
        _own[2] += weight * ((cpu - _own[1]) / span - _own[2])
        _own[0], _own[1] = wall, cpu
    return _own[2]


def busy(threads=None):
    """Whether other jobs hold the cores that ``threads`` threads need.

    Other jobs' load = the 1-minute load average minus this process's own
    recent use (:func:`own_load`); busy when it exceeds the cores left free
    by ``threads`` (default numba's count) plus 1/2.
    """
    threads = numba.get_num_threads() if threads is None else threads
    try:
        others = os.getloadavg()[0] - own_load()
    except (OSError, AttributeError):   # no load average on this platform
        return False
    return others > (os.cpu_count() or 1) - threads + 0.5


def chunks(n_particles):
    """How many chunks a system of ``n_particles`` splits each loop into (1: serial).

    The thread count; 1 below :data:`PARALLEL_MIN` particles, and 1 on a busy
    machine unless :func:`set_threads` chose the count (module docstring).
    The chunks change no bit of the result.
    """
    threads = numba.get_num_threads()
    if n_particles < PARALLEL_MIN or threads == 1 or (not _explicit and busy(threads)):
        return 1
    return threads


def team_ready(n_threads):
    """Whether ``n_threads`` (> 1) threads will run one parallel region together.

    :func:`fricstab.engine.verlet.run` then runs all its steps in one
    region whose threads wait for each other at barriers
    (:mod:`fricstab.engine.team`); that needs each of them on its own
    thread at once: numba's count equal to ``n_threads``, and the OpenMP or
    workqueue layer (TBB may run two of them one after the other on one
    thread; there the loop meets the threads in a parallel region per loop
    instead, with the same result).  False for the rest of the process once
    a team's threads did not all come (:func:`team_failed`).
    """
    if _team_failed or n_threads < 2 or numba.get_num_threads() != n_threads:
        return False
    _launch_threads()   # numba picks its threading layer here, once
    return numba.threading_layer() in ("omp", "workqueue")


def team_failed():
    """A team's threads did not all run at once (:func:`fricstab.engine.team.gate`): warn
    once, and meet the threads in a region per loop from now on."""
    global _team_failed
    if not _team_failed:
        warnings.warn(f"fricstab: {numba.get_num_threads()} numba threads did not run at once "
                      f"(threading layer {numba.threading_layer()!r}; OMP_DYNAMIC or a thread "
                      "limit?); the engine now meets its threads in a parallel region per "
                      "loop: the same results, a few microseconds more a step",
                      RuntimeWarning, stacklevel=3)
    _team_failed = True


def workspace(contacts, system, n_chunks):
    """Scratch of :func:`advance_pass` for a contact list of ``system``: ``(fcon, live, pstart,
    pidx, drv, work, share)``.

    ``fcon`` (K, 8): columns 0-5 each contact's forces of a pass, 6-7 its
    dashpots' effective mass and inertia, constants of the list
    (:func:`~fricstab.engine.passes.effective_masses`); ``drv`` lists the
    contacts that touch a driven particle (``family`` 2), in contact order
    (:func:`~fricstab.engine.passes.driven_force` reads only their rows).
    ``work`` (``n_chunks`` = the threads, 8 + LANES, 9): each thread's
    scratch; ``share`` the threads' part counters, findings and barrier
    (:func:`fricstab.engine.team.share_array`).
    """
    k = contacts.n
    pstart, pidx = layout(contacts.i, contacts.j, system.n)
    fcon = np.zeros((k, 8))
    passes.effective_masses(contacts.i, contacts.j, system.radius, system.damping_mass,
                            system.damping_inertia, fcon[:, 6:])
    return (fcon, np.zeros(k, np.int8), pstart, pidx,
            passes.driven_contacts(contacts.i, contacts.j, system.family),
            np.zeros((n_chunks, 8 + passes.LANES, 9)), team.share_array(n_chunks))


@hot_jit
def gather_range(lo, hi, ext, fcon, live, pstart, pidx, dof, f):
    """Forces on particles ``lo .. hi - 1``: ``ext``, then their contacts in contact order.

    ``pidx[pstart[a]:pstart[a + 1]]`` lists particle a's contacts as ``2 c + side``
    (side 0: a is i, 1: a is j) in increasing ``c``: exactly the order in which
    one loop over the contacts scattering into i and j would add them, so the
    sums are the same to the bit however the particles are shared out.
    Compiled with the dof as the constant 3 (the laws with a rotation) and
    as a variable.
    """
    if dof == 3:
        _gather_body(lo, hi, ext, fcon, live, pstart, pidx, 3, f)
    else:
        _gather_body(lo, hi, ext, fcon, live, pstart, pidx, dof, f)


@hot_inline_jit
def _gather_body(lo, hi, ext, fcon, live, pstart, pidx, dof, f):
    # each particle's sums in registers (fcon may alias f for all the compiler
    # knows, so a sum in f[a] would go through memory at every addition)
    for a in range(lo, hi):
        a0 = ext[a, 0]
        a1 = ext[a, 1]
        a2 = ext[a, 2]
        for e in range(pstart[a], pstart[a + 1]):
            code = pidx[e]
            c = np.uint64(code >> 1)
            if live[c]:
                off = np.uint64((code & 1) * dof)
                a0 += fcon[c, off]
                a1 += fcon[c, off + 1]
                if dof == 3:
                    a2 += fcon[c, off + 2]
        f[a, 0] = a0
        f[a, 1] = a1
        f[a, 2] = a2


def layout(ci, cj, n):
    """``(pstart, pidx)`` of :func:`gather_range`: each particle's contacts in contact order."""
    c = np.arange(len(ci), dtype=np.int64)
    pair = cj >= 0
    code = np.concatenate([2 * c, 2 * c[pair] + 1])
    owner = np.concatenate([ci, cj[pair]])
    order = np.argsort(owner * (2 * len(ci) + 2) + code, kind="stable")
    pstart = np.zeros(n + 1, np.int64)
    np.cumsum(np.bincount(owner, minlength=n), out=pstart[1:])
    return pstart, np.ascontiguousarray(code[order])


@hot_jit
def _guarded(lo, hi, law, p, pw, walls, q, dq, v, radius, rscale, box, damp, ci, cj, cm, ck,
             hist, flag, cout, fcon, live, dof, work, want_out):
    """:func:`~fricstab.engine.passes.advance_range`: -1, or ``lo`` if a kernel raised.

    An exception cannot leave a thread of a parallel region (numba reports a
    SystemError after it); the caller raises it again outside the threads.
    """
    try:   # no scatter: hi < lo is False, and not a literal constant (which would
        #        compile another specialization of the pass)
        passes.advance_range(lo, hi, law, p, pw, walls, q, dq, v, radius, rscale, box, damp, ci,
                             cj, cm, ck, hist, flag, cout, fcon, live, dof, work, want_out, fcon,
                             hi < lo)
    except Exception:  # noqa: BLE001 - numba catches every exception or none
        return lo
    return -1


@hot_jit
def contacts_share(w, law, p, pw, walls, q, dq, v, radius, rscale, box, damp, ci, cj, cm, ck,
                   hist, flag, cout, fcon, live, dof, work, want_out, share):
    """Thread w's parts of the contacts' loop (:func:`~fricstab.engine.team.claim`): the first
    contact of the first part where a kernel raised, or -1."""
    parts = team.parts_of(share)
    k = ci.shape[0]
    bad = -1
    t, d = team.next_part(share, w, team.CONTACTS, 0)
    while t >= 0:
        bad = team.first(bad, _guarded(t * k // parts, (t + 1) * k // parts, law, p, pw, walls,
                                       q, dq, v, radius, rscale, box, damp, ci, cj, cm, ck, hist,
                                       flag, cout, fcon, live, dof, work[w], want_out))
        t, d = team.next_part(share, w, team.CONTACTS, d)
    return bad


@hot_jit
def gather_share(w, ext, fcon, live, pstart, pidx, dof, f, v, ginv, family, half, implicit,
                 kick, check, share):
    """Thread w's parts of the particles' loop: forces (:func:`gather_range`), then the second
    half kick if ``kick``: ``(bad, largest)``.

    ``bad``: the first particle of a part whose force is not finite (only
    with ``kick``), or -1; ``largest``: the largest ``|F|`` on a free dof of
    its particles if ``check``, else 0.
    """
    parts = team.parts_of(share)
    n = f.shape[0]
    bad = -1
    largest = 0.0
    t, d = team.next_part(share, w, team.GATHER, 0)
    while t >= 0:
        lo = t * n // parts
        hi = (t + 1) * n // parts
        gather_range(lo, hi, ext, fcon, live, pstart, pidx, dof, f)
        if check:
            for i in range(lo, hi):
                if family[i] == 0:
                    for b in range(dof):
                        largest = max(largest, abs(f[i, b]))
        if kick:
            bad = team.first(bad, kick_range(lo, hi, f, v, ginv, family, dof, half, implicit))
        t, d = team.next_part(share, w, team.GATHER, d)
    return bad, largest


@threads_jit
def _threads(law, p, pw, walls, q, dq, v, radius, rscale, box, damp, ci, cj, cm, ck, hist, flag,
             cout, ext, f, dof, work, want_out, fcon, live, pstart, pidx, share, ginv, family,
             half, implicit, kick):
    n_threads = team.threads_of(share)
    team.reset(share, team.CONTACTS)
    team.reset(share, team.GATHER)
    for w in prange(n_threads):
        share[w, 0] = contacts_share(w, law, p, pw, walls, q, dq, v, radius, rscale, box, damp,
                                     ci, cj, cm, ck, hist, flag, cout, fcon, live, dof, work,
                                     want_out, share)
    check = kick and not kick   # False, and not a literal (another specialization)
    for w in prange(n_threads):
        share[w, 1] = gather_share(w, ext, fcon, live, pstart, pidx, dof, f, v, ginv, family,
                                   half, implicit, kick, check, share)[0]


@hot_jit
def advance_pass(law, p, pw, walls, q, dq, v, radius, rscale, box, damp, ci, cj, cm, ck, hist,
                 flag, cout, ext, family, f, dof, meas, want_out, track_driven, fcon, live,
                 pstart, pidx, drv, work, share, ginv, half, implicit, kick):
    """One dynamics step of every contact at ``q``; forces into ``f`` (``ext`` first).

    ``box`` as in :func:`~fricstab.engine.passes.advance_range`; the scratch
    ``fcon .. share`` is :func:`workspace`'s.  With one thread the contacts
    scatter their forces as they go (the same sums as the gather, one pass),
    on the calling thread, and a kernel's exception propagates; with
    several, returns the first contact of the first part where a kernel
    raised, or -1 (the caller raises the law's error again:
    :func:`fricstab.engine.verlet.law_error`).  ``meas[0:2]``: the summed
    contact force on driven particles (family 2) if ``track_driven``.

    With ``kick`` each particle's forces are followed at once by its second
    half kick (:func:`~fricstab.engine.integrate.kick_range` with ``ginv``,
    ``half``, ``implicit``), in the same loop over the particles.  Returns
    ``(contact, particle)``: the contact whose kernel raised on a thread (or
    -1), and the first free particle whose force is not finite (or -1; only
    with ``kick``, otherwise finiteness is the caller's check).
    """
    bad = -1
    bad_f = -1
    n_threads = team.threads_of(share)
    if n_threads > 1:
        _threads(law, p, pw, walls, q, dq, v, radius, rscale, box, damp, ci, cj, cm, ck, hist,
                 flag, cout, ext, f, dof, work, want_out, fcon, live, pstart, pidx, share, ginv,
                 family, half, implicit, kick)
        for w in range(n_threads):
            bad = team.first(bad, share[w, 0])
            if kick:
                bad_f = team.first(bad_f, share[w, 1])
    else:
        for a in range(q.shape[0]):
            for b in range(3):
                f[a, b] = ext[a, b]
        # lo = 0 and scatter = True as variables, not literal constants: numba would
        # compile another specialization of the pass for them
        k = ci.shape[0]
        passes.advance_range(k - k, k, law, p, pw, walls, q, dq, v, radius, rscale, box, damp,
                             ci, cj, cm, ck, hist, flag, cout, fcon, live, dof, work[0],
                             want_out, f, k >= 0)
        if kick:
            bad_f = kick_range(k - k, q.shape[0], f, v, ginv, family, dof, half, implicit)
    if track_driven:
        passes.driven_force(drv, ci, cj, live, fcon, family, meas)
    else:
        meas[0] = 0.0
        meas[1] = 0.0
    return bad, bad_f
