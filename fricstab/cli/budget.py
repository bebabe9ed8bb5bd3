"""What a command will cost, said before it allocates: memory refused, time announced.

Every command whose cost grows faster than its input (a dense
eigendecomposition is ``O(d^2)`` in memory and ``O(d^3)`` in time for a
``d x d`` matrix) asks :func:`require` first.  It compares the estimate with
the memory this process may use (``MemAvailable`` of ``/proc/meminfo``, and a
cgroup limit where one is set) and

* refuses (:class:`~fricstab.errors.ParameterError`, exit 2) when the
  estimate exceeds :data:`MEMORY_FRACTION` of it, naming the estimate, what
  is available and what to change;
* prints one line with the estimated time when it exceeds
  :data:`ANNOUNCE_SECONDS` (so that a long computation is never silent);
* returns the estimate, which ``--dry-run`` shows under ``"estimate"``.

The models (LAPACK's dense drivers; :func:`dense_eig`) count the arrays
that are alive at the same time and the textbook flop counts; the time
divides the flops by a rate measured once per process (a 256 x 256
eigendecomposition, a few milliseconds).  They are estimates, good to a
factor of about 2-3 (see ``tests/test_budget.py`` for the memory model
against a measurement).
"""

import math
import os
import sys
import time

from fricstab.errors import ParameterError

__all__ = ["available_memory", "dense_eig", "flop_rate", "require", "gib", "shear",
           "shear_steps"]

#: refuse when the estimate exceeds this fraction of the available memory
MEMORY_FRACTION = 0.8
#: announce the estimated time when it exceeds this many seconds
ANNOUNCE_SECONDS = 30.0

_RATE = None


def gib(nbytes):
    """Bytes as a short GiB string."""
    return f"{nbytes / 2**30:.3g} GiB"


def _cgroup_limit():
    for path in ("/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"):
        try:
            with open(path) as f:
                text = f.read().strip()
        except OSError:
            continue
        if text.isdigit() and int(text) < 2**60:
            return int(text)
    return None


def available_memory():
    """Bytes this process may allocate: ``MemAvailable`` (else physical memory), capped
    by a cgroup limit; ``FRICSTAB_MEMORY`` (bytes) overrides both (tests, batch systems)."""
    env = os.environ.get("FRICSTAB_MEMORY")
    if env:
        try:
            value = float(env)
        except ValueError:
            raise ParameterError(f"FRICSTAB_MEMORY must be a number of bytes, got {env!r}") \
                from None
        if not (math.isfinite(value) and value > 0):
            raise ParameterError(f"FRICSTAB_MEMORY must be a positive number of bytes, "
                                 f"got {env!r}")
        return int(value)
    avail = None
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    avail = int(line.split()[1]) * 1024
                    break
    except OSError:
        pass
    if avail is None:
        try:
            avail = os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
        except (ValueError, OSError, AttributeError):
            avail = 2**40       # unknown: do not refuse on a guess
    limit = _cgroup_limit()
    return min(avail, limit) if limit else avail


def dense_eig(d, *, vectors=True, left=False, symmetric=False):
    """(bytes, flops) of the dense eigendecomposition of a real ``d x d`` matrix.

    Arrays alive together (8 bytes a real entry, 16 a complex one): the dense
    matrix and LAPACK's copy of it; with ``symmetric``, the symmetrised copy and
    the eigenvectors (``eigh``); otherwise the real vectors LAPACK returns and
    their complex form (``eig``), for the right and, with ``left``, the left
    ones; and 64 d words for LAPACK's workspace (``(2 + nb) d`` with a block
    size ``nb`` <= 62) and the eigenvalues.  Flops: ``eigh`` 4/3 d^3 (values) or 9 d^3 (vectors); ``eig`` 10 d^3
    (values) or 25 d^3 (vectors), the usual counts for the QR algorithms.
    """
    d = int(d)
    words = 2.0
    if symmetric:
        words += 1 + (1 if vectors else 0)
        flops = (9.0 if vectors else 4.0 / 3.0) * d**3
    else:
        if vectors:
            words += 3 * (2 if left else 1)
        flops = (25.0 if vectors else 10.0) * d**3
    return int(8 * (words * d * d + 64 * d)), flops


def flop_rate():
    """Floating-point operations per second of a dense eigendecomposition here
    (measured once per process on a 256 x 256 matrix, at least 1e8)."""
    global _RATE
    if _RATE is None:
        import numpy as np
        import scipy.linalg
        a = np.random.default_rng(0).standard_normal((256, 256))
        scipy.linalg.eigvals(a)                       # load LAPACK
        t0 = time.perf_counter()
        scipy.linalg.eigvals(a)
        dt = max(time.perf_counter() - t0, 1e-4)
        _RATE = max(10.0 * 256**3 / dt, 1e8)
    return _RATE


def _duration(seconds):
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


def require(what, nbytes, flops=0.0, *, advice="use a smaller system", count=1,
            dry_run=False, seconds=None):
    """Refuse (``ParameterError``) if ``what`` needs more memory than is available; print
    one line when it will take longer than :data:`ANNOUNCE_SECONDS`; return the estimate
    as a dict (``--dry-run`` prints it; nothing is announced then).

    ``nbytes`` is the peak of one unit of work, ``flops`` its operations, ``count``
    how many such units the command runs one after another; ``seconds`` (of all of them)
    replaces the flop model where the time has another model.
    """
    avail = available_memory()
    if seconds is None:
        seconds = count * flops / flop_rate() if flops else 0.0
    estimate = {"what": what, "peak_memory_bytes": int(nbytes),
                "available_memory_bytes": int(avail), "estimated_seconds": round(seconds, 1)}
    if nbytes > MEMORY_FRACTION * avail:
        raise ParameterError(f"{what} needs about {gib(nbytes)} of memory, "
                             f"{gib(avail)} available: {advice}")
    if seconds > ANNOUNCE_SECONDS and not dry_run:
        print(f"fricstab: note: {what}: estimated {_duration(seconds)} on this machine "
              f"(peak memory {gib(nbytes)})", file=sys.stderr, flush=True)
    return estimate


def lstsq(d):
    """(bytes, flops) of a dense least-squares solve with a ``d x d`` matrix (LAPACK's
    ``gelsd``, the chain's Newton step): the sparse matrix made dense, LAPACK's copy and
    its SVD workspace (about one more d x d), 64 d words; about 12 d^3 flops."""
    d = int(d)
    return int(8 * (3 * d * d + 64 * d)), 12.0 * d**3


def chain(what, n_disks, spectra, solves, *, dry_run=False):
    """The estimate of a chain command: ``spectra`` eigendecompositions of M^-1 J with
    left and right vectors and ``solves`` Newton least-squares steps, each of size 3 N."""
    d = 3 * int(n_disks)
    eb, ef = dense_eig(d, vectors=True, left=True)
    lb, lf = lstsq(d)
    return require(f"{what} ({spectra} spectra and ~{solves} Newton steps of size {d})",
                   max(eb, lb) if spectra else lb, spectra * ef + solves * lf,
                   advice="use a smaller --n", dry_run=dry_run)


def packing(what, opened, params, count, *, route="dense", vectors=True, dry_run=False):
    """The estimate of ``count`` dense spectra of a packing's Jacobian (3 coordinates a
    disk; the packing's size bounds its backbone's): ``route`` 'symmetric' is ``eigh``,
    any other the general ``eig`` with left vectors (the worst case of 'auto')."""
    source = getattr(opened, "source", None)
    n = source.packing.n if source is not None else int(params["n"])
    d = 3 * n
    nbytes, flops = dense_eig(d, vectors=vectors, left=vectors and route != "symmetric",
                              symmetric=route == "symmetric")
    return require(f"{what} ({count} dense spectra of size {d})", nbytes, count * flops,
                   advice="use a smaller packing", dry_run=dry_run)


#: bytes a bulk disk of the shear cell costs, bounded above: its coordinates, velocities,
#: forces and their scratch (about 25 float64 arrays of 3), up to 6 contacts with their
#: histories, indices and flags (about 120 bytes each), the cell lists and the thread
#: partitions: about 1.5 kB, taken as 2 kB (measured: the peak RSS of n = 500 and 2,000
#: cells differs by less than 1 MB, within numba's and LLVM's 250 MB)
SHEAR_BYTES_PER_DISK = 2048


#: particle-steps per second of the shear cell's integrator on one thread: the paper-preset
#: run (1,067 disks, 8.2e7 steps in 5.7 h, validation/shear_paper.md) sheared at about 4e6
SHEAR_PARTICLE_STEPS = 4e6


def shear_steps(params):
    """Integration steps of the shear stage of validated shear-scene ``params``: frames
    ``strain / dgamma`` times the steps per frame ``ceil(dgamma / (gamma_dot dt_frac t_c))``
    (the rule of :meth:`fricstab.protocols.shear_run.ShearSim.start_shear`, in reduced
    units: pressure 1/kappa, gamma_dot = I sqrt(P) / 2, t_c = r_min / sqrt(2) in mean radii)."""
    r_mean = (params["r_min"] + params["r_max"]) / 2.0
    t_c = params["r_min"] / r_mean / math.sqrt(2.0)
    gamma_dot = params["inertial_number"] * math.sqrt(1.0 / params["kappa"]) / 2.0
    per_frame = max(1, math.ceil(params["dgamma"] / (gamma_dot * params["dt_frac"] * t_c)))
    return math.ceil(params["strain"] / params["dgamma"]) * per_frame


def shear(params, *, count=1, dry_run=False):
    """The estimate of ``count`` shear runs of validated scene ``params``: memory by
    :data:`SHEAR_BYTES_PER_DISK`, time of the shear stage on one thread by
    :data:`SHEAR_PARTICLE_STEPS` (good to a factor of ~2; the preparation comes on top,
    at most ``prep_max_steps`` steps; the run's own progress bar has the measured rate)."""
    n = int(params["n"])
    steps = shear_steps(params)
    seconds = count * steps * n / SHEAR_PARTICLE_STEPS
    runs = "shear run" if count == 1 else f"{count} shear runs"
    estimate = require(f"{runs} ({n} bulk disks, {steps:.3g} steps of shear)",
                       SHEAR_BYTES_PER_DISK * n, advice="use a smaller --n", dry_run=dry_run,
                       seconds=seconds)
    return {**estimate, "shear_steps": steps, "prep_max_steps": int(params["prep_max_steps"]),
            "time_model": f"{SHEAR_PARTICLE_STEPS:.0e} particle-steps/s on one thread, shear "
                          "only (the preparation comes on top)"}
