"""LAMMPS anchor of Charan's chain: the deck, the common state and the force check.

Scene (:mod:`fricstab.scenes.chain`): N disks of radius R = 1/2, mass 1, on
the substrate y = 0, periodic in x with period 2NR, F_y = 0.1 down on every
disk, F_x = 0.03 on disk 0, law ``charan`` (Charan Eqs. 1, 2, 5: Hertz
``kn delta^(3/2)``, tangential ``-kt delta^(1/2) (1 + s - s^2) t``, s = |t|/t*,
t* = mu kn/kt delta; kn = 2000, kt = 2 kn/7, mu = 10) with its wall form at
the substrate; contacts: each disk with its two neighbours (static pairs) and
the substrate.  Start: the disks at x_i = (2i + 1) R pressed into the
substrate by half the rest overlap, every coordinate moved by 0.3 rest
overlaps times N(0, 1) (:func:`fricstab.protocols.dynamics.perturbed`, seed 0),
at rest, zero history; undamped velocity Verlet, dt = 0.02 / omega_wall.

LAMMPS deck: ``pair_style granular`` with ``hertz`` normal (``F = k a delta``,
a = sqrt(R_eff delta)) and ``tangential mindlin`` (``F_t = -k_t a xi``, the
displacement history xi, Coulomb cap mu F_n), damping 0; the substrate is
``fix wall/gran granular`` with the same sub-models on the plane y = 0 (R_eff
= R); ``fix addforce`` for F_y and F_x; ``fix nve/sphere disc`` (inertia
m R^2 / 2, as ours), ``fix enforce2d``.  Mapping: ``k = kn / sqrt(R_eff)``,
``k_t = kt / sqrt(R_eff)`` (R_eff = R/2 for a pair, R at the wall), the same
mu.  The laws coincide in the normal force, and in the tangential force at
zero history; they differ in the tangential force away from it: Charan's
smoothed Coulomb factor (1 + s - s^2) (ours) against LAMMPS' linear Mindlin
spring cut at mu F_n, and LAMMPS rotates its history into the tangent plane
every step (Charan's increment rule does not).  LAMMPS finds the pairs with
a neighbour list (skin 0.1 d, no pair farther than the next disk), ours lists
them statically: the same contacts per disk.

Force check: step 0 (zero history), where both codes evaluate the same
Hertz force on the same doubles: per-particle forces and torques with the
round-off bound of :func:`_lammps.roundoff_tolerance`.
"""

import numpy as np

from _lammps import check_forces, lammps_forces, roundoff_tolerance, write_data

from fricstab.protocols.dynamics import default_dt, perturbed
from fricstab.scenes.chain import ChainScene, chain_system, initial_state

__all__ = ["FX", "case", "commands", "force_check"]

FX = 0.03          # F_x on disk 0 (the scale of Charan's onset, F_y = 0.1)
DT_FRACTION = 0.02  # dt = DT_FRACTION / omega_wall (bench_engine's chain)
AMPLITUDE = 0.3    # start: rest overlaps of random displacement
SKIN = 0.1         # LAMMPS neighbour skin (the diameter is 1)


def case(n, seed=0):
    """``(scene, system, state, dt)`` of a chain of ``n`` disks (module docstring)."""
    sc = ChainScene(n=n, fx=FX)
    system = chain_system(sc)
    state = perturbed(sc, initial_state(sc), AMPLITUDE, np.random.default_rng(seed))
    return sc, system, state, default_dt(sc, DT_FRACTION)


def commands(sc, state, dt, data):
    """The LAMMPS deck (a list of commands) of chain ``sc`` at ``state``; writes ``data``."""
    r, p = sc.radius, sc.params
    pos = state.q[:, :2].copy()
    pos[:, 0] %= sc.period
    write_data(data, f"fricstab chain N={sc.n}", pos, np.full(sc.n, r),
               (0.0, sc.period, -2 * r, 4 * r), mass=np.full(sc.n, sc.mass),
               vel=state.v[:, :2], omega=state.v[:, 2])

    def model(reff):
        s = 1.0 / np.sqrt(reff)
        return (f"hertz {p['kn'] * s:.17g} 0.0 tangential mindlin {p['kt'] * s:.17g} 0.0 "
                f"{p['mu']:.17g}")
    return ["units lj", "dimension 2", "atom_style sphere", "boundary p f p", "newton off",
            "comm_modify vel yes", f"read_data {data}", "group first id 1",
            "pair_style granular", f"pair_coeff * * {model(r / 2)}",
            f"neighbor {SKIN} bin", "neigh_modify delay 0 every 1 check yes",
            f"fix wall all wall/gran granular {model(r)} yplane 0.0 NULL",
            f"fix load all addforce 0.0 {-sc.fy:.17g} 0.0",
            f"fix push first addforce {sc.fx:.17g} 0.0 0.0",
            "fix nve all nve/sphere disc", "fix 2d all enforce2d", f"timestep {dt:.17g}",
            "thermo 0"]


def force_check(n, data):
    """Forces of both codes at the chain's start (step 0): a row and whether it passes."""
    sc, system, state, dt = case(n)
    theirs = lammps_forces(commands(sc, state, dt, data))
    f = system.forces(state)
    c = state.contacts
    per = system.contact_forces(state)
    fmag = np.hypot(per[:, 0], per[:, 1])
    on = fmag > 0
    delta = (fmag[on] / sc.params["kn"]) ** (2.0 / 3.0)
    size = 2 * sc.radius + 2 * np.abs(state.q[:, :2]).max()
    tol = roundoff_tolerance(sc.n, c.i[on], c.j[on], fmag[on], delta, size)
    return check_forces("chain", sc.n, theirs, {"f": f[:, :2], "torque": f[:, 2]}, tol,
                        sc.radius, np.full(sc.n, sc.mass))
