"""The one place that sets numba options for fricstab kernels.

``kernel_jit`` compiles lazily with ``cache=True`` (compiled machine code is
kept in ``__pycache__`` between runs) and NumPy's error model (no Python
exception checks on division in the hot loops; the kernels guard their own
divisions).  Scalar contact kernels are compiled for at most two signatures:
float64 and, for complex-step verification, complex128.

``hot_jit`` is the same without numba's reference-counting runtime (NRT), for
every function on the engine's hot path: the generated contact kernels and
their dispatch, the passes over contacts and the integrator loops.  With NRT,
each call of a jitted function with array arguments (and each array view such
as ``hist[c]``) costs atomic reference-count updates: measured, one
``charan_wall_advance`` (about 25 flops) took 51 ns with NRT and 8.7 ns
without, and the engine's contact pass of the chain 1,723 ns against 597 ns.
A ``hot_jit`` function must not allocate (no ``np.empty``, no lists): its
callers pass every array, scratch space included.

``threads_jit`` is ``hot_jit`` with ``parallel=True``, for the few functions
whose ``prange`` loops share the engine's work among threads
(:mod:`fricstab.engine.parallel`); each chunk of a ``prange`` calls one
``hot_jit`` function over a range, so the reference counting of the
parallel region costs once per chunk, not per contact.

The threads of those loops spin for a short while after a parallel region
and then sleep (``GOMP_SPINCOUNT=1000`` unless the environment sets it or
``OMP_WAIT_POLICY``, set here before numba starts its OpenMP pool).  The
engine meets its threads three times a step, microseconds apart: a sleeping
thread takes ~7.7 us to wake, a spinning one ~1 us.  Measured on the
project's 2-core machine, idle, two threads: packing N = 1,024 1.77e7
particle-steps/s spinning (1,000, 10,000 or 100,000 spins alike) against
1.31e7 never spinning (``OMP_WAIT_POLICY=PASSIVE``).  On a machine whose
cores run other jobs a spinning thread takes the core from the thread that
has the work (plane shear, two threads, load ~2: 0.85e6 particle-steps/s
with 1,000 spins, 0.11e6 with 10,000, 3.2e6 passive, 4.3e6 on one thread),
so a default run goes to one thread there
(:func:`fricstab.engine.parallel.busy`); set ``OMP_WAIT_POLICY=PASSIVE`` to
run explicit thread counts on a shared machine.

numba's on-disk cache keys a function on its own source file only: a change
in a function it calls from another file (an inlined kernel, the overlap
correction) leaves the caller's cached machine code stale.
:func:`purge_stale_cache` guards against that: at import it hashes the files
compiled code can depend on (:func:`jit_sources`: every module of the package
that imports numba, and the package modules those import from) and, when the
hash differs from the one stored with the cache, deletes the package's cached
numba code (it is recompiled on first use).  Editing any other module (the
command line, the protocols' Python drivers, the analyses) keeps the cache.

``hot_inline_jit`` adds numba's IR inlining, for the tiny functions called per
contact (the law-id dispatch, the separation of a pair): a call with ~40
scalar arguments costs ~15 ns per contact, as much as half a contact law.
"""

import hashlib
import os
import re
from pathlib import Path

if "OMP_WAIT_POLICY" not in os.environ:   # before numba loads its OpenMP pool
    os.environ.setdefault("GOMP_SPINCOUNT", "1000")

import numba  # noqa: E402

__all__ = ["hot_inline_jit", "hot_jit", "kernel_jit", "purge_stale_cache", "threads_jit"]

PACKAGE = Path(__file__).resolve().parent
_STAMP = "fricstab-sources.sha256"


_USES_NUMBA = re.compile(rb"^(?:import numba|from numba|from \S*_numba import)", re.M)
_FROM = re.compile(rb"^from (\.*[\w.]*) import", re.M)


def jit_sources(root=PACKAGE):
    """The ``.py`` files of the package that compiled code can depend on, sorted: the
    modules that import numba at top level (``import numba``, ``from numba``,
    ``from fricstab._numba``; jitted functions are defined in such modules) and every
    package module they import from at top level (its globals are frozen into the
    machine code).  A module that jitted code reaches only through another numba
    module is in the first set already."""
    root = Path(root)
    texts = {p: p.read_bytes() for p in root.rglob("*.py")}
    jit = {p for p, t in texts.items() if _USES_NUMBA.search(t)}
    out = set(jit)
    for p in jit:
        for mod in _FROM.findall(texts[p]):
            mod = mod.decode()
            if mod.startswith("."):                       # relative to the file's package
                dots = len(mod) - len(mod.lstrip("."))
                base = p.parent
                for _ in range(dots - 1):
                    base = base.parent
                parts = [x for x in mod.lstrip(".").split(".") if x]
            elif mod.split(".")[0] == root.name:
                base, parts = root, mod.split(".")[1:]
            else:
                continue
            target = base.joinpath(*parts)
            for cand in (target.with_suffix(".py"), target / "__init__.py"):
                if cand in texts:
                    out.add(cand)
    return sorted(out)


def purge_stale_cache(root=PACKAGE):
    """Delete the cached numba code under ``root`` if any source file changed since it was cached.

    Returns the number of cache files deleted.  A read-only install is left
    alone (numba then caches elsewhere, keyed by the installed files, which
    do not change).
    """
    sources = jit_sources(root)
    digest = hashlib.sha256()
    for path in sources:
        digest.update(str(path.relative_to(root)).encode())
        digest.update(path.read_bytes())
    stamp = root / "__pycache__" / _STAMP
    try:
        if stamp.read_text() == digest.hexdigest():
            return 0
    except OSError:
        pass
    removed = 0
    try:
        for path in root.rglob("__pycache__/*"):
            if path.suffix in (".nbi", ".nbc"):
                path.unlink()
                removed += 1
        stamp.parent.mkdir(exist_ok=True)
        stamp.write_text(digest.hexdigest())
    except OSError:   # not writable: nothing of ours is cached here
        pass
    return removed


purge_stale_cache()

kernel_jit = numba.njit(cache=True, error_model="numpy")

try:  # ``_nrt`` is a compiler flag of numba's own (numba/core/options.py)
    hot_jit = numba.njit(cache=True, error_model="numpy", _nrt=False)
    hot_inline_jit = numba.njit(cache=True, error_model="numpy", _nrt=False, inline="always")
    threads_jit = numba.njit(cache=True, error_model="numpy", _nrt=False, parallel=True)
except (TypeError, KeyError):  # pragma: no cover - a numba without the flag
    hot_jit = kernel_jit
    hot_inline_jit = numba.njit(cache=True, error_model="numpy", inline="always")
    threads_jit = numba.njit(cache=True, error_model="numpy", parallel=True)
