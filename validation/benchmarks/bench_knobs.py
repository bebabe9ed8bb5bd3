"""The knobs no other study measures: DEM time step against energy error, system size against cost.

1. Time step of the packing DEM (:func:`fricstab.engine.run` on the packing's
   System, ``ishima`` law, velocity Verlet) against the energy error and the cost: N = 256, phi = 0.9,
   velocities of amplitude 1e-3, t = 40 t0.  Two numbers per dt: the spread
   ``(max E - min E) / E_kin(0)`` of the recorded energy (integrator error plus
   the non-conservative part of the tangential law, which does not vanish as
   dt -> 0), and ``|E(t) - E_ref(t)| / E_kin(0)`` against the run with the
   smallest dt (the integrator's own error, O(dt^2)).  k_T/k_N = 1 and 1e-4.
   The chain's time step against the growth rate of its unstable mode is in
   ``chain_tradeoffs.md`` (copied here by ``run_all.py``).
2. System size against cost, with the fitted exponent ``cost ~ N^a``
   (``np.polyfit`` of log cost on log N): one DEM step, the sparse Jacobian
   assembly, ARPACK's 50 lowest eigenvalues, and dense ``eig`` (left + right).

``python validation/benchmarks/bench_knobs.py [--quick]`` -> knobs_dt.md,
knobs_size.md, knobs.png.
"""

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import numpy as np  # noqa: E402
import scipy.sparse.linalg as spla  # noqa: E402
from _common import median_time, save_figure, write_table  # noqa: E402

from fricstab.analysis.dos import spectrum  # noqa: E402
from fricstab.analysis.packing_energy import energy  # noqa: E402
from fricstab.engine import jacobian, run  # noqa: E402
from fricstab.scenes.packing_friction import material, packing_system  # noqa: E402

SKIN = 0.1  # neighbour-list skin of the DEM, in d (as the LAMMPS comparison)


def _dem(p, kt, v0):
    """The engine System and State of packing ``p`` (ishima at ``kt``), velocities ``v0``."""
    system = packing_system(p, material("ishima", kt=kt), skin=SKIN)
    state = system.state(p.pos)
    state.v[:] = v0
    return system, state


def _run_energies(system, state, dt, steps, every):
    """``run`` in chunks of ``every`` steps; the energy at the start and after each chunk."""
    out = [energy(system, state)]
    done = 0
    while done < steps:
        k = min(every, steps - done)
        run(system, state, dt, k)
        done += k
        out.append(energy(system, state))
    return np.array(out)


def _jacobian_with_history(p, scale):
    """``-K`` of packing ``p`` (ishima, kT/kN = 1) with random histories of size ``scale``."""
    system, state = _dem(p, 1.0, 0.0)
    c = state.contacts
    c.hist[:] = np.random.default_rng(0).normal(size=c.hist.shape) * scale
    return -jacobian(system, state)[1]


def _packing(n):
    from _packings import packing
    return packing(n, 0.9, 0)


def dt_study(quick):
    p = _packing(256)
    v0 = np.random.default_rng(1).normal(size=(p.n, 3)) * 1e-3
    e_kin = 0.5 * np.sum(p.mass * (v0[:, 0] ** 2 + v0[:, 1] ** 2 + 0.5 * v0[:, 2] ** 2))
    t_end = 20.0 if quick else 40.0
    dts = (0.4, 0.2, 0.1, 0.05, 0.025) if quick else (0.4, 0.2, 0.1, 0.05, 0.025, 0.0125)
    rows, curves = [], {}
    for kt in (1.0, 1e-4):
        runs = {}
        for dt in dts:
            system, s = _dem(p, kt, v0)
            run(system, s, dt, 5)  # compile outside the timing
            system, s = _dem(p, kt, v0)
            steps = int(round(t_end / dt))
            t0 = time.perf_counter()
            e = _run_energies(system, s, dt, steps, max(1, int(round(1.0 / dt))))
            runs[dt] = (e, time.perf_counter() - t0, steps)
        ref = runs[dts[-1]][0][-1]
        for dt in dts:
            e, sec, steps = runs[dt]
            spread = (e.max() - e.min()) / e_kin
            vs_ref = abs(e[-1] - ref) / e_kin
            curves.setdefault(kt, []).append((dt, spread, vs_ref))
            rows.append((f"{kt:g}", dt, steps, f"{spread:.2e}",
                         f"{vs_ref:.2e}" if dt != dts[-1] else "(reference)", f"{sec:.2f}",
                         f"{1e9 * sec / (steps * p.n):.0f}"))
    write_table(
        "knobs_dt", "Knob: DEM time step against energy error and cost",
        [f"`python validation/benchmarks/bench_knobs.py{' --quick' if quick else ''}`; packing "
         f"N = 256, phi = 0.9 (seed 0), velocities N(0, 1e-3^2), t = {t_end:g} t0, skin "
         f"{SKIN}; E_kin(0) = {e_kin:.3e}. Default dt in the LAMMPS comparison: 0.01. "
         "Timings include the energy evaluations (every t0)."],
        ["kT/kN", "dt / t0", "steps", "(max E - min E) / E_kin(0)",
         "abs(E(t) - E_ref(t)) / E_kin(0)", "s", "ns per particle-step"], rows,
        ["Reading: the energy difference to the finest run falls as dt^2 (velocity Verlet) "
         "until the reference's own error; the spread levels off at the part no dt removes: "
         "the tangential law f_T = -k_T xi^(1/2) t is not derived from a potential (its "
         "stiffness follows the overlap), so with k_T/k_N = 1 the total drifts at any dt, and "
         "with 1e-4 nearly not. The cost is linear in 1/dt."])
    return curves


def _fit(ns, secs):
    return float(np.polyfit(np.log(ns), np.log(secs), 1)[0])


def size_study(quick):
    ns_ = (64, 256, 1024) if quick else (64, 256, 1024, 4096)
    dense_ns = (64, 128, 256) if quick else (64, 128, 256, 512)
    repeats = 3 if quick else 5
    cost = {"DEM step (per step)": [], "sparse J assembly": [], "eigs k=50 (shift-invert)": [],
            "dense eig, left + right": []}
    for n in ns_:
        p = _packing(n)
        v0 = np.random.default_rng(1).normal(size=(p.n, 3)) * 1e-3
        system, s = _dem(p, 1.0, v0)
        steps = max(50, int(2e5 / n))
        run(system, s, 0.01, 5)
        t, _ = median_time(lambda: run(system, s, 0.01, steps), repeats)
        cost["DEM step (per step)"].append((n, t / steps))

        def build(p=p):
            return _jacobian_with_history(p, 1e-4)

        jac = build()
        t, _ = median_time(build, repeats)
        cost["sparse J assembly"].append((n, t))
        # Rattlers make zero modes: shift below 0 so the factorization is regular.
        sigma = -1e-6 * abs(jac).max()
        t, _ = median_time(lambda: spla.eigs(jac.tocsc(), k=50, sigma=sigma, which="LM"), 1)
        cost["eigs k=50 (shift-invert)"].append((n, t))
    for n in dense_ns:
        p = _packing(n)
        dense = _jacobian_with_history(p, 1e-4).toarray()
        secs = sorted(spectrum(dense, route="dense").seconds for _ in range(3 if n <= 256 else 1))
        cost["dense eig, left + right"].append((n, secs[len(secs) // 2]))
    rows = []
    for what, pts in cost.items():
        pts = np.array(pts)
        a = _fit(pts[:, 0], pts[:, 1])
        rows.append((what, ", ".join(f"{int(n)}: {t:.2e}" for n, t in pts), f"{a:.2f}"))
    write_table(
        "knobs_size", "Knob: system size against cost (fitted exponent)",
        [f"`python validation/benchmarks/bench_knobs.py{' --quick' if quick else ''}`; packings "
         f"at phi = 0.9 (seed 0), k_T/k_N = 1, random histories 1e-4; median of {repeats} runs "
         "(eigs: one run; dense eig: median of 3 up to N = 256, then one)."],
        ["what", "N: seconds", "exponent a (cost ~ N^a)"], rows,
        ["Expected: 1 for the DEM step and the assembly (cell/Verlet lists, O(N)); the sparse "
         "shift-invert factorization of a 2D contact network grows like N^1.5 at large N; "
         "dense eig like N^3 (LAPACK at small N is below its asymptote)."])
    return cost


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ns = ap.parse_args(argv)
    t_all = time.perf_counter()
    curves = dt_study(ns.quick)
    cost = size_study(ns.quick)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(9, 3.5))
    for kt, pts in curves.items():
        pts = np.array(pts)
        a1.loglog(pts[:-1, 0], pts[:-1, 2], "o-", label=f"|E - E_ref|, kT/kN = {kt:g}")
        a1.loglog(pts[:, 0], pts[:, 1], "s--", label=f"spread, kT/kN = {kt:g}")
    a1.minorticks_off()
    a1.set_xlabel("dt / t0")
    a1.set_ylabel("energy error / E_kin(0)")
    a1.legend(fontsize=7)
    for what, pts in cost.items():
        pts = np.array(pts)
        a2.loglog(pts[:, 0], pts[:, 1], "o-", label=what)
    a2.set_xlabel("N")
    a2.set_ylabel("seconds")
    a2.legend(fontsize=7)
    save_figure(fig, "knobs")
    print(f"Total {time.perf_counter() - t_all:.0f} s.")
    return 0


if __name__ == "__main__":
    sys.exit(main())
