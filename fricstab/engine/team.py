"""How the engine's threads share a loop and meet: part counters and a barrier.

A loop over the contacts or the particles is cut into :data:`PARTS` parts per
thread.  Thread w does the parts of its own share in order and then takes
what is left of the others' shares, one part at a time, from each share's
counter (:func:`claim`): on a quiet machine every thread works on its own
particles, as with a fixed split, and a thread slowed by another job on its
core does fewer parts instead of holding the others.  Which thread does a
part changes no bit: every part writes only its own rows, and what the
threads report (first bad item, farthest drift, largest force) is a minimum
or a maximum.

Between loops the threads meet at :func:`barrier`, a counter and a
generation number in shared memory: ~0.1 us on the project's 2-core machine,
against ~1.4 us to start and end one parallel region of numba (measured with
both in one process: docs/concepts/performance.md).  So the dynamics loop runs
a whole call's steps in one parallel region (:mod:`fricstab.engine.verlet`).
A waiting thread spins; after :data:`SPINS` turns it yields its core at every
turn (``sched_yield``), so threads that outnumber the free cores still get
the work done.

Threads that wait for each other need all of them running at once.  The
first meeting of a region is therefore :func:`gate`, which gives up where a
thread of the team never comes (a threading layer that runs two members one
after the other on one thread, ``OMP_DYNAMIC``, a thread limit): after
:data:`GATE_YIELDS` yields of a waiting thread the gate is closed, every
member returns before it has changed anything, and the caller runs the same
steps with a parallel region per loop instead (the same bits).  A team that
passed the gate cannot hang at a later barrier: every member runs the same
steps and leaves at the same one.

``share`` (:func:`share_array`) is an int64 array ``(2 T + 2, 8)`` for T
threads: row w holds what thread w found in each loop (columns 0-2), row
``T + w`` the part counters of its share (columns 0-2: the contacts, the
gather and the drift) and :data:`PARTS` (column 7), the last two rows the
barrier's count (and the gate's, column 1) and generation.  Each row is one
64-byte cache line: a thread writes only its own.
"""

import sys

import numpy as np
from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic

from fricstab._numba import hot_jit

__all__ = ["CONTACTS", "DRIFT", "GATE_YIELDS", "GATHER", "PARTS", "SPINS", "barrier", "claim",
           "first", "gate", "gate_closed", "next_part", "open_gate", "parts_of", "reset",
           "share_array", "threads_of"]

#: Parts per thread of each loop (measured: docs/concepts/performance.md).
PARTS = 4
#: Turns a thread waiting at :func:`barrier` spins before it yields its core at each turn.
SPINS = 1 << 14
#: Yields of a thread waiting at :func:`gate` before it closes the gate: about a second
#: where the missing thread does not exist (each yield returns at once), far
#: longer where other jobs hold the cores (each yield may cede a time slice).
GATE_YIELDS = 1 << 20
_CLOSED = -(1 << 62)   # the gate's count once closed: stays negative after any arrivals
#: Columns of ``share`` (and counters) of the three loops.
CONTACTS, GATHER, DRIFT = 0, 1, 2


def share_array(n_threads, parts=None):
    """A zeroed ``share`` for ``n_threads`` threads, :data:`PARTS` (or ``parts``) per thread."""
    share = np.zeros((2 * n_threads + 2, 8), np.int64)
    share[n_threads:2 * n_threads, 7] = PARTS if parts is None else parts
    return share


def _element(context, builder, signature, args):
    aryty = signature.args[0]
    ary = context.make_array(aryty)(context, builder, args[0])
    index = context.cast(builder, args[1], signature.args[1], types.intp)
    return cgutils.get_item_pointer(context, builder, aryty, ary, [index])


def _int64_vector(a):
    return isinstance(a, types.Array) and a.ndim == 1 and a.dtype == types.int64


@intrinsic
def _fetch_add(typingctx, counters, index):
    """``counters[index] += 1`` as one atomic instruction; the value before."""
    if not _int64_vector(counters):
        return None

    def codegen(context, builder, signature, args):
        return builder.atomic_rmw("add", _element(context, builder, signature, args),
                                  context.get_constant(types.int64, 1), "seq_cst")

    return types.int64(counters, types.intp), codegen


@intrinsic
def _load(typingctx, counters, index):
    """``counters[index]`` read from memory (an atomic load: never a register's stale copy)."""
    if not _int64_vector(counters):
        return None

    def codegen(context, builder, signature, args):
        return builder.load_atomic(_element(context, builder, signature, args), "acquire", 8)

    return types.int64(counters, types.intp), codegen


@intrinsic
def _compare_exchange(typingctx, counters, index, expected, value):
    """``counters[index] = value`` if it equals ``expected``, as one atomic instruction:
    whether it did."""
    if not _int64_vector(counters):
        return None

    def codegen(context, builder, signature, args):
        pair = builder.cmpxchg(_element(context, builder, signature, args), args[2], args[3],
                               "seq_cst", "seq_cst")
        return builder.extract_value(pair, 1)

    return types.boolean(counters, types.intp, types.int64, types.int64), codegen


@intrinsic
def _yield(typingctx):
    """``sched_yield()`` (POSIX; nothing on Windows): give the core to another thread."""
    def codegen(context, builder, signature, args):
        if sys.platform != "win32":
            fn = cgutils.get_or_insert_function(builder.module, ir.FunctionType(ir.IntType(32), []),
                                                "sched_yield")
            builder.call(fn, [])
        return context.get_dummy_value()

    return types.void(), codegen


@hot_jit
def threads_of(share):
    """The thread count ``share`` was made for."""
    return (share.shape[0] - 2) // 2


@hot_jit
def claim(share, queue, loop):
    """The next part of thread ``queue``'s share of ``loop``: 0 .. parts - 1, or more when none
    is left (module docstring)."""
    return _fetch_add(share[threads_of(share) + queue], loop)


@hot_jit
def parts_of(share):
    """Parts of a loop in all: :data:`PARTS` (as ``share`` was made) per thread."""
    n_threads = threads_of(share)
    return share[n_threads, 7] * n_threads


@hot_jit
def next_part(share, w, loop, d):
    """Thread w's next part of ``loop``: ``(part, d)``, part -1 when none is left.

    Thread w takes the parts of its own share first (``d = 0``), then of the
    others' in turn (``d`` counts the shares it has emptied; pass back what it
    returned).  Part t of all :func:`parts_of` covers items ``t n // parts``
    to ``(t + 1) n // parts``.
    """
    n_threads = threads_of(share)
    per = share[n_threads, 7]
    while d < n_threads:
        u = (w + d) % n_threads
        t = claim(share, u, loop)
        if t < per:
            return u * per + t, d
        d += 1
    return -1, d


@hot_jit
def reset(share, loop):
    """Zero the part counters of ``loop`` (while no thread takes parts of it)."""
    n_threads = threads_of(share)
    for w in range(n_threads):
        share[n_threads + w, loop] = 0


@hot_jit
def barrier(share):
    """Wait until every thread of ``share`` has called this (their writes before it are seen
    by all after it)."""
    row = share.shape[0] - 2
    gen = _load(share[row + 1], 0)
    if _fetch_add(share[row], 0) == threads_of(share) - 1:
        share[row, 0] = 0   # the last to come: the next barrier's count starts here
        _fetch_add(share[row + 1], 0)
        return
    spins = 0
    while _load(share[row + 1], 0) == gen:
        spins += 1
        if spins > SPINS:
            _yield()


@hot_jit
def open_gate(share):
    """Ready ``share``'s :func:`gate` for a new region (while no thread is in one)."""
    share[share.shape[0] - 2, 1] = 0


@hot_jit
def gate(share):
    """The first meeting of a region: True on every thread once all have come, False on
    every thread if the gate was closed first (module docstring).

    A thread that has waited :data:`SPINS` turns and then :data:`GATE_YIELDS`
    yields closes the gate, atomically and only if no thread came in the
    meantime; a thread that comes to a closed gate finds it closed.
    """
    count = share[share.shape[0] - 2]
    n_threads = threads_of(share)
    if _fetch_add(count, 1) < 0:
        return False
    turns = 0
    while True:
        seen = _load(count, 1)
        if seen >= n_threads:
            return True
        if seen < 0:
            return False
        turns += 1
        if turns > SPINS:
            _yield()
            if turns > SPINS + GATE_YIELDS and _compare_exchange(count, 1, seen, _CLOSED):
                return False


@hot_jit
def gate_closed(share):
    """Whether the last region's :func:`gate` was closed."""
    return share[share.shape[0] - 2, 1] < 0


@hot_jit
def first(a, b):
    """The lower of two indices, where -1 means none."""
    if a < 0:
        return b
    if b < 0:
        return a
    return min(a, b)
