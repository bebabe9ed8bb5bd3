"""Throughput of the engine on 1 and 2 threads, scene by scene.

For each scene the same system, law and step are run by the engine
(``fricstab.engine.run``) on 1 thread and on 2 (``fricstab --threads``),
interleaved ``--repeats`` times; the table gives particle-steps per second
(N x steps / seconds, compilation excluded by a warm-up), the median of each,
the ratio 2 threads / 1 thread and the run-to-run spread (max/min over the
repeats) that any difference must exceed to count.  The result is the same to
the bit on any thread count (tests/test_threads.py); below
``fricstab.engine.parallel.PARALLEL_MIN`` particles the engine stays on one
thread whatever the count.

* chain: Charan's scene (N = 10, charan + charan_wall, F_x = 0.03, undamped);
* packing: Ishima's scene (N = 1024, phi = 0.90, kT/kN = 1, kicked);
* plane shear: Lee & Hurley's quick preset prepared (bulk, fixed floor,
  servo-driven lid, dashpots), sheared.

The per-scene loops the engine replaced were timed against it in one run
before they were deleted (engine / old: chain 1.91, packing 1.10, plane shear
1.09; git history of engine.md).

``python validation/benchmarks/bench_engine.py [--repeats R] [--quick]`` -> engine.md
"""

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(1, str(Path(__file__).resolve().parents[1]))   # validation/_packings
import numpy as np  # noqa: E402
from _common import write_table  # noqa: E402

from fricstab.engine import Material, System, run  # noqa: E402
from fricstab.engine.parallel import available_threads, set_threads  # noqa: E402


# ---------------------------------------------------------------- chain

def chain_case(steps):
    from fricstab.protocols.dynamics import default_dt
    from fricstab.protocols.ramp import ramped_equilibrium
    from fricstab.scenes.chain import ChainScene, chain_system
    sc = ChainScene()
    n = sc.n
    eq = ramped_equilibrium(sc, 0.03)
    system = chain_system(sc.with_fx(0.03))
    dt = default_dt(sc, 0.02)

    def engine():
        s = eq.copy()
        run(system, s, dt, steps)
        return n * steps

    return n, engine


# ---------------------------------------------------------------- packing

def packing_case(steps, n=1024):
    from _packings import packing
    p = packing(n, 0.90, seed=0)
    rng = np.random.default_rng(1)
    v = 1e-3 * rng.standard_normal((n, 3))
    radius = p.radius
    system = System(Material("ishima", {"kn": 1.0, "kt": 1.0}), radius, p.mass, p.inertia,
                    lx=p.box, ly=p.box, skin=0.1)
    base = system.state(p.pos)
    base.v[:] = v  # (v_x, v_y, v_l): the same generalized velocities as the old loop

    def engine():
        s = base.copy()
        run(system, s, 0.02, steps)
        return n * steps
    return n, engine


# ---------------------------------------------------------------- plane shear

def shear_case(steps):
    from fricstab.cli.shear import resolve_params
    from fricstab.protocols.shear_run import ShearRun, prepare
    from fricstab.scenes.shear import make_cell
    p = resolve_params(None, "quick", {})
    sim = ShearRun(make_cell(p))
    prepare(sim)
    sim.start_shear()
    n = sim.system.n
    base = sim.state.copy()

    def engine():
        s = base.copy()
        run(sim.system, s, sim.dt, steps, sim.controls)
        return n * steps
    return n, engine


def measure(case, repeats, counts):
    """Rates (particle-steps/s) of the engine at each thread count, runs interleaved."""
    n, engine = case
    rates = {t: [] for t in counts}
    try:
        for t in counts:
            set_threads(t)
            engine()   # warm-up: compilation, caches
        for _ in range(repeats):
            for t in counts:
                set_threads(t)
                start = time.perf_counter()
                work = engine()
                rates[t].append(work / (time.perf_counter() - start))
    finally:
        set_threads(available_threads())
    return n, rates


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--quick", action="store_true", help="fewer steps (a smoke run)")
    ns = ap.parse_args()
    k = 10 if ns.quick else 1
    counts = (1, min(2, available_threads()))
    cases = [("chain (N = 10, charan)", lambda: chain_case(200_000 // k)),
             ("packing (N = 1,024, ishima)", lambda: packing_case(2_000 // k)),
             ("plane shear (quick preset, lee_hurley + dashpots + servo)",
              lambda: shear_case(4_000 // k))]
    rows = []
    for name, make in cases:
        set_threads(1)   # the preparation (packing FIRE, shear compression) on one thread
        case = make()
        n, rates = measure(case, ns.repeats, counts)
        m1, m2 = (statistics.median(rates[t]) for t in counts)
        spread = " / ".join(f"{max(rates[t]) / min(rates[t]):.2f}" for t in counts)
        rows.append([name, f"{n}", f"{m1:.3g}", f"{m2:.3g}", f"{m2 / m1:.2f}", spread])
        print(rows[-1], flush=True)
    write_table("engine", "Engine throughput on 1 and 2 threads (particle-steps per second)",
                __doc__.split("\n\n")[1:3], ["scene", "N", "1 thread", "2 threads",
                                             "2 threads / 1", "spread max/min (1 / 2)"], rows,
                notes=[f"Median of {ns.repeats} interleaved runs each. A ratio counts only "
                       "where it exceeds the spread; on a machine whose cores are busy with "
                       "other work the 2-thread figure drops (a thread waits for the slower). "
                       f"Load average at the end: {os.getloadavg()[0]:.1f} on {os.cpu_count()} "
                       "cores."])


if __name__ == "__main__":
    main()
