"""The plane-shear cell of Lee & Hurley (Sec. 2): scene, preparation, shear, frames, checkpoints.

A 2D cell periodic in x (box length ``lx``) between two rows of disks: the
bottom row is fixed, the top row moves as one rigid body at the constant
horizontal velocity V while a velocity servo holds the normal force N on it
(LIGGGHTS-style: v_y = -g (N_target - N)).  Bulk disks: radius uniform in
[r_min, r_max], no gravity.  Contact law: :mod:`fricstab.generated.lee_hurley`
with the damping of :mod:`fricstab.protocols.shear_law` (Appendix A); the loop is
:mod:`fricstab.protocols.shear_dem`.

Units
-----
Scene values and every output (frames, series, JSON) are SI, per unit
thickness (forces N/m, torques N m/m, masses kg/m).  Inside, reduced units:
length L0 = mean radius (r_min + r_max)/2, pressure E* = E / (2 (1 - nu^2))
(Eq. A3), mass per thickness rho L0^2, time T0 = L0 sqrt(rho / E*).

Control numbers (da Cruz et al. 2005, 2D, per unit thickness)
--------------------------------------------------------------
P = N / lx, kappa = E* / P, I = gamma_dot d sqrt(rho / P) with d the mean
diameter and gamma_dot = V / h0 (h0 the distance between the wall-disk centre
lines when shearing starts).  So N = E* lx / kappa and V = I h0 sqrt(P/rho)/d.
Shear strain gamma = (x displacement of the top wall) / h0.

Time step: dt <= dt_frac t_c with t_c = r_min sqrt(rho / (2 E*)) =
sqrt(m*_min / (pi E*)), a lower bound of the contact time sqrt(m*/k_n)
(k_n <= pi E* for a/R <= 1, Eq. A2); dt is then shortened so that an output
interval dgamma is an integer number of steps.

Damping: alpha_n = gamma_n = 0.1 and alpha_t = gamma_t = 0.1 are the damping
ratios of Eqs. A4 and A12, eta_r = 0.3 of Eq. A20.  The paper's restitution
0.9 is not used: for a linear spring-dashpot the ratio 0.1 means
e = exp(-pi 0.1 / sqrt(1 - 0.01)) = 0.73, and e = 0.9 would need a ratio of
0.034; we follow the damping constants the paper states (the contact law it
details) and record the implied e in the result.
"""

import math
import time
from dataclasses import dataclass

import numpy as np

from fricstab.errors import NumericalError
from fricstab.laws import ParameterError
from fricstab.io.scenes import Field, Schema, register, validate

__all__ = ["SCHEMA", "Units", "Cell", "make_cell", "prepare", "Shear", "restitution",
           "PREP_STAGE_STEPS"]

SCHEMA = register(Schema("shear", "Plane shear cell with constant normal force (Lee & Hurley)", (
    Field("n", "int", 1000, "-", "bulk disks", low=4),
    Field("r_min", "float", 0.5e-6, "m", "smallest bulk radius", low=0.0, low_open=True),
    Field("r_max", "float", 1.0e-6, "m", "largest bulk radius (>= r_min)", low=0.0,
          low_open=True),
    Field("aspect", "float", 1.0, "-", "lx / height of the dense cell", low=0.1, high=10.0),
    Field("E", "float", 1e9, "Pa", "Young's modulus", low=0.0, low_open=True),
    Field("nu", "float", 0.2, "-", "Poisson ratio", low=0.0, high=0.49),
    Field("density", "float", 2500.0, "kg/m^3", "density", low=0.0, low_open=True),
    Field("mu_s", "float", 0.7, "-", "sliding friction coefficient", low=0.0, low_open=True),
    Field("mu_r", "float", 0.01, "-", "rolling friction coefficient", low=0.0),
    Field("alpha_n", "float", 0.1, "-", "normal damping ratio (A4)", low=0.0, high=1.0),
    Field("alpha_t", "float", 0.1, "-", "tangential damping ratio (A12)", low=0.0, high=1.0),
    Field("eta_r", "float", 0.3, "-", "rolling viscous damping ratio (A20)", low=0.0, high=1.0),
    Field("inertial_number", "float", 4e-6, "-", "I = gamma_dot d sqrt(rho/P)", low=0.0,
          low_open=True, high=0.1),
    Field("kappa", "float", 1e4, "-", "stiffness number E*/P, P = N/lx", low=10.0),
    Field("dgamma", "float", 7.2e-7, "-", "shear strain between output frames", low=0.0,
          low_open=True, high=0.01),
    Field("strain", "float", 0.0936, "-", "total shear strain (paper: 130,000 x 7.2e-7)",
          low=0.0, low_open=True, high=10.0),
    Field("gamma0", "float", 0.022, "-", "start of the stick-slip regime for the analysis",
          low=0.0),
    Field("seed", "int", 0, "-", "seed of the random radii and placement", low=0),
    Field("dt_frac", "float", 0.15, "-", "time step bound / t_c, t_c = r_min sqrt(rho/2E*)",
          low=0.0, low_open=True, high=1.0),
    Field("skin", "float", 0.2, "mean radius", "neighbour-list skin", low=0.0, low_open=True,
          high=2.0),
    Field("servo_gain", "float", 0.1, "-",
          "shear servo: v_y = -g (N_target - N), g = servo_gain h0 / (E* lx t_c)",
          low=0.0, low_open=True, high=1.0),
    Field("prep_phi", "float", 0.45, "-", "area fraction of the random placement", low=0.1,
          high=0.5),
    Field("prep_speed", "float", 1e-3, "sqrt(E*/rho)", "largest wall speed while preparing",
          low=0.0, low_open=True, high=0.1),
    Field("prep_tol", "float", 0.01, "-", "preparation ends at |N/N_target - 1| below this",
          low=0.0, low_open=True, high=0.5),
    Field("prep_ke", "float", 1e-7, "P d^2", "... and mean kinetic energy below this",
          low=0.0, low_open=True),
    Field("prep_max_steps", "int", 3_000_000, "-", "preparation step limit", low=1),
    Field("checkpoint_every", "int", 200, "frames", "checkpoint (and frame chunk) interval",
          low=1),
)))

PREP_STAGE_STEPS = 500  # preparation: criteria checked every this many steps


def restitution(alpha):
    """Restitution of a linear spring-dashpot with damping ratio ``alpha`` (< 1)."""
    return math.exp(-math.pi * alpha / math.sqrt(1.0 - alpha * alpha))


@dataclass(frozen=True)
class Units:
    """Reduced units: ``length`` [m], ``pressure`` (E*) [Pa], ``mass`` [kg/m], ``time`` [s]."""

    length: float
    pressure: float
    density: float

    @property
    def mass(self):
        return self.density * self.length ** 2

    @property
    def time(self):
        return self.length * math.sqrt(self.density / self.pressure)

    @property
    def force(self):
        return self.pressure * self.length

    @property
    def velocity(self):
        return self.length / self.time

    def to_json(self):
        return {"length_m": self.length, "pressure_Pa": self.pressure,
                "mass_kg_per_m": self.mass, "time_s": self.time,
                "force_N_per_m": self.force, "velocity_m_per_s": self.velocity}


@dataclass
class Cell:
    """Particles of the cell in reduced units (mutable state arrays, see shear_dem)."""

    params: dict
    units: Units
    lx: float
    radius: np.ndarray
    mass: np.ndarray
    inertia: np.ndarray
    kind: np.ndarray
    pos: np.ndarray
    vel: np.ndarray
    angle: np.ndarray
    omega: np.ndarray
    n_target: float
    t_c: float

    @property
    def mdamp(self):
        wall = self.mass[self.kind == 2].sum()
        return np.where(self.kind == 0, self.mass, np.where(self.kind == 2, wall, np.inf))

    @property
    def idamp(self):
        return np.where(self.kind == 0, self.inertia, np.inf)

    def law(self):
        p = self.params
        return np.array([1.0, p["nu"], p["mu_s"], p["mu_r"], p["alpha_n"], p["alpha_t"],
                         p["eta_r"]])


def _wall_row(rng, lx, rmin, rmax):
    """Radii and x of touching disks filling the period lx exactly (radii rescaled)."""
    radii = []
    while 2.0 * sum(radii) < lx:
        radii.append(rng.uniform(rmin, rmax))
    r = np.array(radii) * lx / (2.0 * sum(radii))
    x = np.concatenate([[0.0], np.cumsum(r[:-1] + r[1:])]) + r[0]
    return r, x


def make_cell(params):
    """Random non-overlapping placement (seeded) of the validated ``params``; a :class:`Cell`.

    The bulk disks are placed one by one (random sequential addition, largest
    first) at area fraction ``prep_phi`` between the walls; ``lx`` is chosen
    so that the cell at area fraction 0.82 has lx / h = ``aspect``.
    """
    p = validate("shear", params)
    if p["r_max"] < p["r_min"]:
        raise ParameterError(f"r_max = {p['r_max']:g} must be >= r_min = {p['r_min']:g}")
    estar = p["E"] / (2.0 * (1.0 - p["nu"] ** 2))
    units = Units((p["r_min"] + p["r_max"]) / 2.0, estar, p["density"])
    rng = np.random.default_rng(p["seed"])
    rmin, rmax = p["r_min"] / units.length, p["r_max"] / units.length
    rb = np.sort(rng.uniform(rmin, rmax, p["n"]))[::-1]
    area = math.pi * np.sum(rb ** 2)
    lx = math.sqrt(p["aspect"] * area / 0.82)
    if lx < 6.0 * rmax:
        raise ParameterError(f"n = {p['n']}: the box (lx = {lx:.3g} mean radii) is narrower "
                             "than 6 r_max; use more disks or a larger aspect")
    r_bot, x_bot = _wall_row(rng, lx, rmin, rmax)
    r_top, x_top = _wall_row(rng, lx, rmin, rmax)
    h_loose = area / (p["prep_phi"] * lx)
    y0 = r_bot.max()
    placed = np.empty((p["n"], 2))
    for k, r in enumerate(rb):
        for attempt in range(100000):
            if attempt and attempt % 2000 == 0:
                h_loose *= 1.05
            x, y = rng.uniform(0.0, lx), rng.uniform(y0 + r, y0 + h_loose - r)
            if k:
                dx = placed[:k, 0] - x
                dx -= lx * np.round(dx / lx)
                if np.any(dx * dx + (placed[:k, 1] - y) ** 2 < (rb[:k] + r) ** 2):
                    continue
            dxb = x_bot - x
            dxb -= lx * np.round(dxb / lx)
            if np.any(dxb * dxb + y * y < (r_bot + r) ** 2):
                continue
            placed[k] = x, y
            break
        else:  # pragma: no cover - prep_phi <= 0.5 leaves room
            raise ParameterError(f"prep_phi = {p['prep_phi']:g}: cannot place disk {k}")
    y_top = y0 + h_loose + r_top.max()
    radius = np.concatenate([rb, r_bot, r_top])
    kind = np.concatenate([np.zeros(p["n"]), np.ones(len(r_bot)),
                           2 * np.ones(len(r_top))]).astype(np.int8)
    pos = np.concatenate([placed, np.column_stack([x_bot, np.zeros_like(x_bot)]),
                          np.column_stack([x_top, np.full_like(x_top, y_top)])])
    mass = math.pi * radius ** 2
    n_all = len(radius)
    return Cell(params=p, units=units, lx=lx, radius=radius, mass=mass,
                inertia=0.5 * mass * radius ** 2, kind=kind, pos=pos,
                vel=np.zeros((n_all, 2)), angle=np.zeros(n_all), omega=np.zeros(n_all),
                n_target=lx / p["kappa"], t_c=rmin / math.sqrt(2.0))


class Shear:
    """State of a run: the cell, the neighbour list with histories, forces, wall, counters.

    ``Shear(cell)`` starts from a placed cell; :func:`prepare` compresses it,
    :meth:`start_shear` sets V and the frame interval, :meth:`advance` runs
    steps.  :meth:`state` / :meth:`from_state` give every array needed to
    continue bit-identically (the checkpoint).
    """

    STATE = ("pos", "vel", "angle", "omega", "force", "torque", "pi", "pj", "hist", "cf",
             "cfn", "csl", "ref", "wall", "ctrl", "scalars")

    def __init__(self, cell):
        from fricstab.protocols import shear_dem as dem
        self.cell = cell
        self.dem = dem
        n = len(cell.radius)
        self.force = np.zeros((n, 2))
        self.torque = np.zeros(n)
        self.pi, self.pj = dem.build_pairs(cell.pos, cell.radius, cell.kind, cell.lx,
                                           cell.params["skin"])
        m = len(self.pi)
        self.hist = np.zeros((m, 4))
        self.cf = np.zeros((m, 2))
        self.cfn = np.zeros(m)
        self.csl = np.zeros(m, np.int8)
        self.ref = cell.pos.copy()
        self.wall = np.zeros(8)
        self.wall[4] = cell.pos[cell.kind == 1, 1].mean()
        self.ctrl = np.zeros(8)
        # step, frame, dt, steps per frame, h0, gamma_dot, V, rebuilds
        self.scalars = np.zeros(8)
        self.dt = cell.params["dt_frac"] * cell.t_c

    # ---------------------------------------------------------------- state
    def state(self):
        c = self.cell
        d = {"pos": c.pos, "vel": c.vel, "angle": c.angle, "omega": c.omega}
        d.update({k: getattr(self, k) for k in self.STATE if k not in d})
        return {k: np.array(v, copy=True) for k, v in d.items()}

    def load_state(self, st):
        c = self.cell
        for k in ("pos", "vel", "angle", "omega"):
            setattr(c, k, np.array(st[k], dtype=float))
        for k in self.STATE:
            if k not in ("pos", "vel", "angle", "omega"):
                setattr(self, k, np.array(st[k]))
        self.pi = self.pi.astype(np.int64)
        self.pj = self.pj.astype(np.int64)
        self.csl = self.csl.astype(np.int8)
        self.dt = float(self.scalars[2]) if self.scalars[2] > 0 else self.dt

    # ---------------------------------------------------------------- stepping
    def rebuild(self):
        """Rebuild the neighbour list now (histories carried by pair key)."""
        c = self.cell
        ni, nj = self.dem.build_pairs(c.pos, c.radius, c.kind, c.lx, c.params["skin"])
        self.hist = self.dem.carry_histories(len(c.radius), self.pi, self.pj, self.hist, ni, nj)
        keep = self.dem.carry_histories(len(c.radius), self.pi, self.pj,
                                        np.column_stack([self.cf, self.cfn, self.csl]), ni, nj)
        self.cf, self.cfn = keep[:, :2].copy(), keep[:, 2].copy()
        self.csl = keep[:, 3].astype(np.int8)
        self.pi, self.pj = ni, nj
        self.ref = c.pos.copy()

    def advance(self, nsteps):
        """Run ``nsteps`` steps; NumericalError naming the step and item on a blow-up."""
        c = self.cell
        out = self.dem.run_steps(nsteps, c.pos, c.vel, c.angle, c.omega, self.force,
                                 self.torque, c.radius, c.mass, c.inertia, c.mdamp, c.idamp,
                                 c.kind, c.lx, self.pi, self.pj, self.hist, self.ref, self.cf,
                                 self.cfn, self.csl, c.law(), self.dt, c.params["skin"],
                                 self.wall, self.ctrl)
        status, done, item, self.pi, self.pj, self.hist, self.cf, self.cfn, self.csl, nreb = out
        step = int(self.scalars[0]) + done + 1   # 1-based number of the failing step
        self.scalars[0] += done
        self.scalars[7] += nreb
        if status != self.dem.OK:
            what = {self.dem.BAD_OVERLAP: ("overlap beyond the domain of the contact law "
                                           "(delta >= 4 (Ri + Rj) / e^2)", "pair"),
                    self.dem.BAD_STATE: ("non-finite position or velocity", "particle"),
                    self.dem.BAD_FORCE: ("non-finite contact force", "pair")}[status]
            label = (f"pair ({self.pi[item]}, {self.pj[item]})" if what[1] == "pair"
                     else f"particle {item}")
            raise NumericalError(f"{what[0]} of {label} at step {step}; reduce dt_frac",
                                 step=step, item=item, quantity=what[0])

    def kinetic_energy(self):
        c = self.cell
        b = c.kind == 0
        return 0.5 * (np.sum(c.mass[b] * np.sum(c.vel[b] ** 2, axis=1))
                      + np.sum(c.inertia[b] * c.omega[b] ** 2)) / b.sum()

    @property
    def height(self):
        c = self.cell
        return c.pos[c.kind == 2, 1].mean() - self.wall[4]

    def start_shear(self):
        """Set V, gamma_dot, dt and the steps per frame from I, kappa, dgamma (module doc)."""
        c, p = self.cell, self.cell.params
        h0 = self.height
        pressure = c.n_target / c.lx
        gamma_dot = p["inertial_number"] * math.sqrt(pressure) / 2.0  # d = 2, rho = 1
        spf = max(1, math.ceil(p["dgamma"] / (gamma_dot * p["dt_frac"] * c.t_c)))
        self.dt = p["dgamma"] / (gamma_dot * spf)
        # relaxation rate g K_eff with K_eff ~ E* lx / h0 the cell stiffness
        gain = p["servo_gain"] * h0 / (c.lx * c.t_c)
        self.ctrl[:] = [gamma_dot * h0, c.n_target, gain, p["prep_speed"], 0.0, 0.0, 0.0, 0.0]
        self.wall[0] = 0.0
        self.scalars[1:7] = [0, self.dt, spf, h0, gamma_dot, gamma_dot * h0]
        self.scalars[0] = 0
        self.rebuild()

    # ---------------------------------------------------------------- frames
    def frame(self):
        """The current frame in SI, as keyword arguments of ``FrameWriter.append``."""
        c, u = self.cell, self.cell.units
        h0 = self.scalars[4]
        on = self.cfn > 0.0
        ij = np.column_stack([self.pi[on], self.pj[on]]).astype(np.int32)
        n, s = self.wall[1], self.wall[2]
        return dict(time=self.scalars[0] * self.dt * u.time, strain=self.wall[0] / h0,
                    normal_force=n * u.force, shear_force=s * u.force,
                    height=self.height * u.length, pos=c.pos * u.length, angle=c.angle,
                    vel=c.vel * u.velocity, omega=c.omega / u.time, contact_ij=ij,
                    contact_force=self.cf[on] * u.force, contact_fn=self.cfn[on] * u.force,
                    contact_ft=self.hist[on, 0] * u.force,
                    contact_mr=self.hist[on, 1] * u.force * u.length,
                    contact_sliding=(self.csl[on] & 1).astype(np.int8),
                    tau=s / n if n > 0 else 0.0)


def prepare(sim, progress=None):
    """Compress the placed cell under the servo until N and the kinetic energy settle.

    The top wall moves at v_y = -prep_speed (N_target - N) / N_target (clipped
    to prep_speed); the bulk y coordinates follow the wall affinely and the
    bulk velocities are damped at the rate 0.05 / t_c, so the disks need not
    travel to the wall.  Ends when |N / N_target - 1| < prep_tol and the mean
    kinetic energy per bulk disk < prep_ke P d^2 at a check (every
    PREP_STAGE_STEPS steps); ConvergenceError after prep_max_steps.
    Returns a dict of statistics.
    """
    from fricstab.scenes.packing import ConvergenceError
    c, p = sim.cell, sim.cell.params
    nt = c.n_target
    sim.ctrl[:] = [0.0, nt, p["prep_speed"] / nt, p["prep_speed"], 0.05 / c.t_c, 1.0, 0, 0]
    ke_tol = p["prep_ke"] * (nt / c.lx) * 4.0
    t0 = time.perf_counter()
    steps = 0
    while True:
        sim.advance(PREP_STAGE_STEPS)
        steps += PREP_STAGE_STEPS
        err = abs(sim.wall[1] / nt - 1.0)
        ke = sim.kinetic_energy()
        if progress is not None:
            progress(steps, err, ke / ke_tol)
        if err < p["prep_tol"] and ke < ke_tol:
            break
        if steps >= p["prep_max_steps"]:
            raise ConvergenceError(f"preparation: after {steps} steps |N/N_target - 1| = "
                                   f"{err:.3g} (tol {p['prep_tol']:g}), kinetic energy "
                                   f"{ke / ke_tol:.3g} x tolerance; raise prep_max_steps")
    sim.ctrl[4:6] = 0.0
    c.vel[c.kind == 0] = 0.0
    c.omega[c.kind == 0] = 0.0
    return {"steps": steps, "seconds": time.perf_counter() - t0,
            "normal_force_error": err, "kinetic_energy": ke,
            "height_m": sim.height * c.units.length,
            "area_fraction": float(np.sum(np.pi * c.radius[c.kind == 0] ** 2)
                                   / (c.lx * sim.height)),
            "rebuilds": int(sim.scalars[7])}
