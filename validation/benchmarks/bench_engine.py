"""Throughput of the one engine against the three per-scene loops it replaced.

For each scene the same system, law and step are run by the old loop and by
the engine (``fricstab.engine.run``), interleaved ``--repeats`` times; the
table gives particle-steps per second (N x steps / seconds, compilation
excluded by a warm-up), the median of each, the ratio engine / old and the
run-to-run spread (max/min over the repeats of each code) that any
difference must exceed to count.

* chain: Charan's scene (N = 10, charan + charan_wall, F_x = 0.03, undamped);
  old: ``fricstab.protocols.dynamics._verlet``;
* packing: Ishima's scene (N = 1024, phi = 0.90, kT/kN = 1, kicked);
  old: ``fricstab.protocols.pack_dynamics``;
* plane shear: Lee & Hurley's quick preset prepared (bulk, fixed floor,
  servo-driven lid, dashpots); old: ``fricstab.protocols.shear_dem``.

The old loops are deleted once the scenes run on the engine: this table was
measured in one run before that (its header names the revision), and the
script then times the engine alone.

``python validation/benchmarks/bench_engine.py [--repeats R] [--quick]`` -> engine.md
"""

import argparse
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import numpy as np  # noqa: E402
from _common import write_table  # noqa: E402

from fricstab.engine import Material, System, run  # noqa: E402


def _old(module):
    try:
        return __import__(module, fromlist=["x"])
    except ImportError:
        return None


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

    return n, engine, None   # the chain's own loop (dynamics._verlet) is deleted


# ---------------------------------------------------------------- packing

def packing_case(steps, n=1024):
    from fricstab.scenes.packing import make_packing
    p = make_packing(n, 0.90, seed=0)
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

    pdyn = _old("fricstab.protocols.pack_dynamics")

    def old():
        st = pdyn.init_state(p.pos, radius, p.box, 1.0, velocity=v)
        pdyn.run(st, 0.02, steps)
        return n * steps
    return n, engine, (old if pdyn is not None else None)


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
    return n, engine, None   # the old loop (fricstab.protocols.shear_dem) is deleted


def measure(case, repeats):
    n, engine, old = case
    engine()
    if old is not None:
        old()
    te, to = [], []
    for _ in range(repeats):
        t = time.perf_counter()
        work = engine()
        te.append(work / (time.perf_counter() - t))
        if old is not None:
            t = time.perf_counter()
            work = old()
            to.append(work / (time.perf_counter() - t))
    return n, te, to


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--quick", action="store_true", help="fewer steps (a smoke run)")
    ns = ap.parse_args()
    k = 10 if ns.quick else 1
    cases = [("chain (N = 10, charan)", lambda: chain_case(200_000 // k)),
             ("packing (N = 1,024, ishima)", lambda: packing_case(2_000 // k)),
             ("plane shear (quick preset, lee_hurley + dashpots + servo)",
              lambda: shear_case(4_000 // k))]
    rows = []
    for name, make in cases:
        n, te, to = measure(make(), ns.repeats)
        me = statistics.median(te)
        spread_e = max(te) / min(te)
        if to:
            mo = statistics.median(to)
            spread_o = max(to) / min(to)
            rows.append([name, f"{n}", f"{mo:.3g}", f"{me:.3g}", f"{me / mo:.2f}",
                         f"{spread_o:.2f} / {spread_e:.2f}"])
        else:
            rows.append([name, f"{n}", "(deleted)", f"{me:.3g}", "-", f"- / {spread_e:.2f}"])
        print(rows[-1], flush=True)
    write_table("engine", "Engine throughput against the per-scene loops it replaced",
                __doc__.split("\n\n")[1:3], ["scene", "N", "old loop (particle-steps/s)",
                                             "engine", "engine / old",
                                             "spread max/min (old / engine)"], rows,
                notes=[f"Median of {ns.repeats} interleaved runs each; one core (both loops "
                       "are serial).  A ratio counts only where it exceeds the spread."])


if __name__ == "__main__":
    main()
