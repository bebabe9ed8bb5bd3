"""LAMMPS analogue of Lee & Hurley's plane-shear cell: export, deck, force check.

Ours (:mod:`fricstab.scenes.shear`, :mod:`fricstab.protocols.shear_run`): the
quick preset (``fricstab.cli.shear.resolve_params(None, "quick", {"n": n})``,
300 bulk disks; n = 1,000 is the paper's size), compressed by the servo
(:func:`~fricstab.protocols.shear_run.prepare`), then sheared for
:data:`SHEARED_FRAMES` output frames; reduced units (length: mean radius,
pressure: E*, mass: rho L0^2 per unit thickness).  The prepared cell is cached
in ``validation/.packings/`` (git-ignored; the quick cell takes ~2 minutes to
prepare on one core, the paper-size one ~8).  Law ``lee_hurley``: 2D Hertz
cylinders (Eq. A2), Lai's tangential stiffness (A8) with a Coulomb cap mu_s =
0.7, a type-C rolling spring (A15-A18, mu_r = 0.01), dashpots (A4, A12,
A20-A22: ratios 0.1, 0.1, 0.3); bottom row fixed, top row a rigid body driven
at V in x, its y velocity servoed on the contact force N (v_y = -g (N_t - N)).

LAMMPS (``units lj`` in our reduced units; the same disks, positions and
velocities, x folded into [0, lx), ``boundary p f p``): ``pair_style
granular`` with

* ``hertz k_n e`` + ``damping coeff_restitution``: F_n = k_n a delta, a =
  sqrt(R_eff delta), 3D Hertz (ours: the 2D cylinder, pi E* delta / (ln(4 R1/a)
  + ln(4 R2/a) - 1), no width).  k_n = k_N / sqrt(1/2) with k_N = f_n(delta_0) /
  delta_0^(3/2) of ``lee_hurley`` at the cell's typical overlap delta_0 (the
  scene's ``hertz``/``charan`` defaults): equal forces for two disks of the mean
  radius at delta_0, LAMMPS' stiffer by sqrt(R_eff / (1/2)) for larger pairs
  and deeper overlaps.  LAMMPS' damping is 2 beta sqrt(m_eff F_n / delta) with
  beta = sqrt(5) |ln e| / sqrt(pi^2 + ln^2 e); e = exp(-2 pi alpha_n /
  sqrt(5 - 4 alpha_n^2)) = 0.754 makes beta = alpha_n, our A4 with the secant
  stiffness F_n / delta (the engine's ``kn`` of a contact), exactly;
* ``tangential mindlin/force k_t x_t mu_s``: incremental dF_t = -k_t a d xi
  (A7's form), k_t = k_T / sqrt(1/2) with k_T sqrt(delta_0) = Lai's k_t at
  delta_0 (ours varies with a, Eq. A8); x_t = sqrt(k_T / k_N) (alpha_t /
  alpha_n) gives A12's gamma_t at delta_0; cap mu_s F_n as A10;
* ``rolling sds k_r g_r mu_r``: torque R_eff^2 k_r d theta = A14-A15 exactly
  with k_r = pi E*/4; the cap R_eff mu_r F_n = A18 exactly; g_r = C_r / R_eff^2
  with A20-A22's C_r for two disks of the mean radius (ours per pair);
* the bottom row frozen (no integrator; ``neigh_modify exclude`` of wall-wall
  pairs, as our neighbour list skips pairs of two non-free disks); the top row
  ``fix rigid single`` with the x force and all torques off (it keeps the x
  velocity V) under ``fix addforce`` of -N_target in total: a constant load on
  an inertial lid (the paper's lid mass, the sum of its disks), where ours
  servoes the lid's velocity on the contact force (``fix aveforce`` would give
  every lid disk the same force, and disks of unequal mass would then leave
  the row: ``fix rigid`` keeps it one body); the lid disks enter the
  dashpots with their own masses (ours: the lid's total mass); bulk ``fix
  nve/sphere disc`` (inertia m r^2 / 2, ours); dt, skin and neighbour check
  as ours.

Force check (step 0, where the laws coincide up to a known factor): every
velocity zero and no history, so dashpots, tangential and rolling forces are
zero in both; LAMMPS' per-disk force is then sum_c k_n sqrt(R_eff,c)
delta_c^(3/2) n_c (+ the load on the lid disks), ours the same sum with
delta_c^(3/2) n_c from the engine's contact list and overlaps (a ``hertz``
System with kn = 1 on the same cell): this checks the export (disks, masses,
periodic images, wall groups, exclusions) and both codes' contact detection,
with the round-off bound of :func:`_lammps.roundoff_tolerance`.
"""

import hashlib
import json
import math
import os
from pathlib import Path

import numpy as np

from _lammps import check_forces, lammps_forces, roundoff_tolerance, write_data

from fricstab.cli.shear import resolve_params
from fricstab.engine import Material, System
from fricstab.protocols.shear_run import SPF, V, ShearRun, prepare
from fricstab.scenes.shear import make_cell, material, units_of

__all__ = ["SHEARED_FRAMES", "commands", "force_check", "mapping", "prepared"]

CACHE = Path(os.environ.get("FRICSTAB_PACKING_CACHE",
                            Path(__file__).resolve().parents[1] / ".packings"))
SHEARED_FRAMES = 10   # output frames sheared after the preparation (90 steps each)
TYPES = (1, 2, 3)     # LAMMPS atom types of our families 0 (bulk), 1 (bottom), 2 (top)


def prepared(n, seed=0):
    """A :class:`ShearRun` of the quick preset, ``n`` bulk disks, prepared and sheared (cached)."""
    p = resolve_params(None, "quick", {"n": n, "seed": seed})
    key = hashlib.sha1(json.dumps(p, sort_keys=True).encode()).hexdigest()[:12]
    path = CACHE / f"shear_n{n}_s{seed}_f{SHEARED_FRAMES}_{key}.npz"
    sim = ShearRun(make_cell(p))
    if path.exists():
        with np.load(path) as d:
            sim.load_arrays(dict(d))
        return sim
    print(f"  preparing the shear cell n = {n} (cached in {path.parent}) ...", flush=True)
    prepare(sim)
    sim.start_shear()
    sim.advance(SHEARED_FRAMES * int(sim.scalars[SPF]))
    CACHE.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp.npz")
    np.savez(tmp, **sim.arrays())
    os.replace(tmp, path)
    return sim


def mapping(sim):
    """LAMMPS coefficients of the cell (module docstring): a dict of floats."""
    p = sim.cell.params
    hz = material(resolve_params(None, "quick", {**{k: p[k] for k in ("n", "seed")},
                                                 "law": "charan"}), units_of(p)).params
    lh = sim.system.material.params
    an, at, er = p["alpha_n"], p["alpha_t"], p["eta_r"]
    reff = 0.5                                   # two disks of the mean radius (1)
    m = math.pi                                  # their mass (rho = 1 per area)
    i_r = 1.0 / (2.0 / (0.5 * m + m))            # A22: 1/I_r = sum 1/(I + m R^2)
    k_r = math.pi * lh["E"] * reff ** 2 / 4.0    # A15
    return {"kn": hz["kn"] / math.sqrt(reff), "kt": hz["kt"] / math.sqrt(reff),
            "e": math.exp(-2 * math.pi * an / math.sqrt(5 - 4 * an * an)),
            "xt": math.sqrt(hz["kt"] / hz["kn"]) * at / an, "mus": lh["mus"],
            "kr": math.pi * lh["E"] / 4.0, "gr": er * 2 * math.sqrt(i_r * k_r) / reff ** 2,
            "mur": lh["mur"]}


def commands(sim, data, still=False):
    """The LAMMPS deck of the cell at ``sim``'s state; writes ``data`` (``still``: v = 0)."""
    c, st = sim.cell, sim.state
    pos = st.q[:, :2].copy()
    pos[:, 0] %= c.lx
    top = c.kind == 2
    vel = np.zeros((c.kind.size, 2)) if still else st.v[:, :2].copy()
    omega = np.zeros(c.kind.size) if still else st.v[:, 2].copy()
    if not still:
        vel[top] = sim.scalars[V], st.v[top, 1].mean()   # the lid: V and its servo v_y
        omega[c.kind != 0] = 0.0
    lo = (pos[:, 1] - c.radius).min()
    hi = (pos[:, 1] + c.radius).max()
    write_data(data, f"fricstab plane shear N={c.kind.size}", pos, c.radius,
               (0.0, c.lx, lo - 1.0, hi + 0.2 * (hi - lo)),
               types=np.array(TYPES)[c.kind], mass=c.mass, vel=vel, omega=omega)
    k = mapping(sim)
    return ["units lj", "dimension 2", "atom_style sphere", "boundary p f p", "newton off",
            "comm_modify vel yes", f"read_data {data}", "group bulk type 1",
            "group top type 3", "pair_style granular",
            f"pair_coeff * * hertz {k['kn']:.17g} {k['e']:.17g} "
            f"tangential mindlin/force {k['kt']:.17g} {k['xt']:.17g} {k['mus']:.17g} "
            f"rolling sds {k['kr']:.17g} {k['gr']:.17g} {k['mur']:.17g} "
            "damping coeff_restitution",
            f"neighbor {c.params['skin']:.17g} bin",
            "neigh_modify delay 0 every 1 check yes exclude type 2 2 exclude type 3 3 "
            "exclude type 2 3",
            "fix nve bulk nve/sphere disc",
            f"fix load top addforce 0.0 {-c.n_target / top.sum():.17g} 0.0",
            "fix lid top rigid single force * off on off torque * off off off",
            "fix 2d all enforce2d", f"timestep {sim.dt:.17g}", "thermo 0"]


def force_check(sim, data):
    """Step-0 forces of both codes on the cell at rest (module docstring): a row, pass."""
    c = sim.cell
    theirs = lammps_forces(commands(sim, data, still=True))
    hz = System(Material("hertz", {"kn": 1.0}), c.radius, c.mass, c.inertia, family=c.kind,
                lx=c.lx, skin=c.params["skin"])
    st = hz.state(sim.state.q[:, :2])
    ct = st.contacts
    per = hz.contact_forces(st)                  # delta^(3/2) n on i, then on j
    reff = c.radius[ct.i] * c.radius[ct.j] / (c.radius[ct.i] + c.radius[ct.j])
    w = mapping(sim)["kn"] * np.sqrt(reff)
    f = np.zeros((c.kind.size, 2))
    np.add.at(f, ct.i, w[:, None] * per[:, :2])
    np.add.at(f, ct.j, w[:, None] * per[:, 2:4])
    f[c.kind == 2, 1] -= c.n_target / (c.kind == 2).sum()
    mag = np.hypot(per[:, 0], per[:, 1])
    on = mag > 0
    size = c.radius[ct.i[on]] + c.radius[ct.j[on]] + 2 * np.abs(sim.state.q[:, :2]).max()
    tol = roundoff_tolerance(c.kind.size, ct.i[on], ct.j[on], w[on] * mag[on],
                             mag[on] ** (2.0 / 3.0), size)
    return check_forces("plane shear", c.kind.size, theirs,
                        {"f": f, "torque": np.zeros(c.kind.size)}, tol, c.radius, c.mass)
