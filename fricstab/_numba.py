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

The threads of those loops wait passively between parallel regions
(``OMP_WAIT_POLICY=PASSIVE`` unless the environment says otherwise, set here
before numba starts its OpenMP pool): by default OpenMP's idle threads spin,
and on a machine whose cores run other jobs a spinning thread takes the core
from the thread that has the work.  Measured on the project's 2-core machine
under load: an empty parallel region cost 1,950 us spinning, 7.5 us passive
(numba's workqueue layer: 30 us).

``hot_inline_jit`` adds numba's IR inlining, for the tiny functions called per
contact (the law-id dispatch, the separation of a pair): a call with ~40
scalar arguments costs ~15 ns per contact, as much as half a contact law.
"""

import os

os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")   # before numba loads its OpenMP pool

import numba  # noqa: E402

__all__ = ["hot_inline_jit", "hot_jit", "kernel_jit", "threads_jit"]

kernel_jit = numba.njit(cache=True, error_model="numpy")

try:  # ``_nrt`` is a compiler flag of numba's own (numba/core/options.py)
    hot_jit = numba.njit(cache=True, error_model="numpy", _nrt=False)
    hot_inline_jit = numba.njit(cache=True, error_model="numpy", _nrt=False, inline="always")
    threads_jit = numba.njit(cache=True, error_model="numpy", _nrt=False, parallel=True)
except (TypeError, KeyError):  # pragma: no cover - a numba without the flag
    hot_jit = kernel_jit
    hot_inline_jit = numba.njit(cache=True, error_model="numpy", inline="always")
    threads_jit = numba.njit(cache=True, error_model="numpy", parallel=True)
