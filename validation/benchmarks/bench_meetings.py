"""What a meeting of the engine's threads costs: a parallel region against a barrier.

The engine's velocity Verlet loop meets its threads three times a step
(:mod:`fricstab.engine.verlet`).  Opened and closed as a numba parallel
region each time, a meeting costs the fork and join of the threads; inside
one region per call, it is :func:`fricstab.engine.team.barrier`.  Both are
timed here with no work between meetings (two threads, one process, the two
kinds alternated in ``--rounds`` rounds of ``--meetings`` meetings each):
what is left of a step's cost once its work is taken away.

``python validation/benchmarks/bench_meetings.py [--rounds R] [--meetings M] [--quick]`` -> meetings.md
"""

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import numba  # noqa: E402
import numpy as np  # noqa: E402
from _common import write_table  # noqa: E402
from numba import njit, prange  # noqa: E402

from fricstab.engine import team  # noqa: E402

THREADS = 2


@njit(parallel=True, nogil=True)
def _regions(meetings, x):
    for _ in range(meetings):
        for w in prange(THREADS):
            x[8 * w] += 1.0   # one cache line a thread


@njit(nogil=True)
def _member(w, meetings, share, x):
    team.gate(share)
    for _ in range(meetings):
        x[8 * w] += 1.0
        team.barrier(share)


@njit(parallel=True, nogil=True)
def _barriers(meetings, x, share):
    team.open_gate(share)
    for w in prange(THREADS):
        _member(w, meetings, share, x)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--meetings", type=int, default=20_000)
    ap.add_argument("--quick", action="store_true", help="2,000 meetings a round (a smoke run)")
    ns = ap.parse_args()
    if ns.quick:
        ns.meetings = min(ns.meetings, 2_000)
    if numba.config.NUMBA_NUM_THREADS < THREADS:
        sys.exit(f"bench_meetings: needs {THREADS} numba threads (NUMBA_NUM_THREADS)")
    numba.set_num_threads(THREADS)
    x = np.zeros(8 * THREADS)
    share = team.share_array(THREADS)
    _regions(10, x)   # compile, start the threads
    _barriers(10, x, share)
    costs = {"region": [], "barrier": []}
    for _ in range(ns.rounds):
        for name, call in (("region", lambda: _regions(ns.meetings, x)),
                           ("barrier", lambda: _barriers(ns.meetings, x, share))):
            start = time.perf_counter()
            call()
            costs[name].append((time.perf_counter() - start) / ns.meetings * 1e6)
    rows = [[name, f"{statistics.median(c):.3f}", f"{min(c):.3f}", f"{max(c):.3f}"]
            for name, c in (("an empty parallel region (fork and join)", costs["region"]),
                            ("a barrier inside one region (fricstab.engine.team)",
                             costs["barrier"]))]
    write_table("meetings", "A meeting of two threads: parallel region against barrier (us)",
                __doc__.split("\n\n")[1:2], ["meeting", "median (us)", "lowest", "highest"],
                rows, notes=[f"{ns.rounds} rounds of {ns.meetings:,} meetings of each kind, "
                             f"alternated; threading layer {numba.threading_layer()}, "
                             f"GOMP_SPINCOUNT {os.environ.get('GOMP_SPINCOUNT', 'unset')}. "
                             f"Load average at the end: {os.getloadavg()[0]:.1f} on "
                             f"{os.cpu_count()} cores."])


if __name__ == "__main__":
    main()
