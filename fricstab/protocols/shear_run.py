"""Preparation and shearing of the plane-shear cell with the engine's velocity Verlet.

:class:`ShearRun` holds the cell (:mod:`fricstab.scenes.shear`), its engine
:class:`~fricstab.engine.System` and :class:`~fricstab.engine.State`, the
forces of the last step (dashpots included) and the controller measurements
(``meas``: the contact force on the top row and its x displacement), so that
:meth:`ShearRun.arrays` / :meth:`ShearRun.from_arrays` continue a run
bit-identically (the checkpoint).  Reduced units (the scene's docstring).

Protocol
--------
:func:`prepare`
    Servo compression (``Controls(servo, affine_y, drag)``): the top row moves
    at v_y = -prep_speed (N_target - N) / N_target (clipped to prep_speed), the
    bulk y coordinates follow it affinely about the bottom row, and a global
    drag at the rate 0.05 / t_c drains the kinetic energy (it replaces the
    velocity scaling v *= 1 - 0.05 dt / t_c of the loop before the engine: the
    same rate, split over the two half kicks).  Ends when |N / N_target - 1| <
    prep_tol and the mean kinetic energy per bulk disk < prep_ke P d^2 at a
    check (every :data:`PREP_STAGE_STEPS` steps).  The contacts' histories
    advance with the dynamic displacement ``dt v`` only, not with the affine
    move (as the loop before the engine): the quick cell ends at area fraction
    0.7295 (seed 0; 0.7354, 0.7184 for seeds 1, 2) and compacts by 1.4 % over
    the shear run.
:meth:`ShearRun.start_shear`
    V = gamma_dot h0 from I and kappa, the servo v_y = -g (N_target - N) with
    g = servo_gain h0 / (E* lx t_c), |v_y| <= prep_speed, dt fitted to an
    integer number of steps per output frame.
:meth:`ShearRun.advance`
    ``engine.run`` with ``Controls(drive=(V, 0), servo=...)``, the histories
    advanced at the new configuration of each step (the engine's order).

Frames (:meth:`ShearRun.frame`, SI) are taken from the state: positions,
velocities, and per touching contact (elastic normal force > 0) the force on
i (elastic + dashpots) and the elastic normal force (``state.contacts.out``,
written on the last step of a run call), the law's histories and the cap
flags (``state.contacts.flag``).
"""

import math
import time

import numpy as np

from fricstab.engine import Controls, State, run
from fricstab.errors import (MAX_STEPS, ConvergenceError, NumericalError, check_instance,
                             check_int)
from fricstab.scenes.shear import HISTORY_UNITS, Cell
from fricstab.signals import Interrupted

__all__ = ["PREP_STAGE_STEPS", "ShearRun", "prepare"]

PREP_STAGE_STEPS = 500  # preparation: criteria checked every this many steps

# run scalars: step, frame, dt, steps per frame, h0, gamma_dot, V, servo gain
STEP, FRAME, DT, SPF, H0, GDOT, V, GAIN = range(8)


class ShearRun:
    """A run of Lee & Hurley's plane-shear cell: system, state, last forces, controllers, counters.

    ``ShearRun(cell)`` starts from the placed cell;
    :func:`fricstab.protocols.shear_run.prepare` compresses it under the servo,
    :meth:`start_shear` sets V (from I and kappa), the servo on N and the frame
    interval, :meth:`advance` runs steps and :meth:`frame` returns the current
    frame in SI per unit thickness.  The loop runs in reduced units (length:
    the mean radius; pressure: E*).  :meth:`arrays` and :meth:`load_arrays`
    checkpoint and continue a run bit-identically.

    Parameters
    ----------
    cell : Cell
        The placed cell (:func:`make_cell`).
    """

    def __init__(self, cell):
        check_instance("cell", cell, Cell, "a Cell (make_cell)")
        self.cell = cell
        self.system = cell.system()
        self.state = self.system.state(cell.pos)
        self.forces = None
        self.meas = np.zeros(8)
        self.controls = Controls()
        self.scalars = np.zeros(8)
        self.scalars[DT] = cell.params["dt_frac"] * cell.t_c
        self.y_floor = float(cell.pos[cell.kind == 1, 1].mean())

    @property
    def dt(self):
        return float(self.scalars[DT])

    # ---------------------------------------------------------------- checkpoints
    def arrays(self):
        """Every array needed to continue bit-identically."""
        d = {k: np.array(v, copy=True) for k, v in self.state.arrays().items()}
        d.update(forces=np.array(self.forces, copy=True), meas=self.meas.copy(),
                 run_scalars=self.scalars.copy())
        return d

    def load_arrays(self, d):
        """Continue from :meth:`arrays` (a checkpoint)."""
        self.state = State.from_arrays(d)
        self.forces = np.array(d["forces"], float)
        self.meas = np.array(d["meas"], float)
        self.scalars = np.array(d["run_scalars"], float)
        self.controls = self._shear_controls()

    # ---------------------------------------------------------------- stepping
    def advance(self, nsteps):
        """Run ``nsteps`` steps; NumericalError naming the step and item on a blow-up.

        ``nsteps`` is an integer >= 0 (ParameterError otherwise).
        """
        check_int("nsteps", nsteps, 0, MAX_STEPS)
        step0 = int(self.scalars[STEP])
        try:
            out = run(self.system, self.state, self.dt, nsteps, self.controls,
                      forces=self.forces, meas=self.meas)
        except Interrupted as exc:   # the same: name the step of the shear, not of the call
            raise Interrupted(exc.signum, f" at step {step0 + (exc.step or 0)}") from None
        except NumericalError as exc:   # the engine counts the steps of this call
            step = step0 + (exc.step or 0)
            text = str(exc).replace(f"at step {exc.step}", f"at step {step}")
            raise NumericalError(f"{text}; reduce dt_frac", step=step, item=exc.item,
                                 quantity=exc.quantity) from None
        except ValueError as exc:   # a kernel refused an overlap beyond its law's domain
            raise NumericalError(f"{exc} within steps {step0 + 1}..{step0 + nsteps}; reduce "
                                 "dt_frac", step=step0, quantity="overlap") from None
        self.forces = out.forces
        self.meas = out.driven_force
        self.scalars[STEP] += nsteps

    def kinetic_energy(self):
        """Mean kinetic energy per bulk disk (reduced units)."""
        free = self.system.free
        v = self.state.v[free, :self.system.dof]
        return 0.5 * np.sum(self.system.gmass[free, :self.system.dof] * v * v) / free.sum()

    @property
    def height(self):
        """Distance between the wall-row centre lines (reduced)."""
        return float(self.state.q[self.cell.kind == 2, 1].mean()) - self.y_floor

    def _shear_controls(self):
        s, c = self.scalars, self.cell
        return Controls(drive=(float(s[V]), 0.0),
                        servo=(float(s[GAIN]), c.n_target, c.params["prep_speed"]))

    def start_shear(self):
        """Set V, gamma_dot, dt and the steps per frame from I, kappa, dgamma (module doc)."""
        c, p = self.cell, self.cell.params
        h0 = self.height
        pressure = c.n_target / c.lx
        gamma_dot = p["inertial_number"] * math.sqrt(pressure) / 2.0  # d = 2, rho = 1
        spf = max(1, math.ceil(p["dgamma"] / (gamma_dot * p["dt_frac"] * c.t_c)))
        gain = p["servo_gain"] * h0 / (c.lx * c.t_c)  # rate g K_eff, K_eff ~ E* lx / h0
        self.scalars[:] = [0, 0, p["dgamma"] / (gamma_dot * spf), spf, h0, gamma_dot,
                           gamma_dot * h0, gain]
        self.meas[2] = 0.0
        self.controls = self._shear_controls()
        self.system.rebuild(self.state)
        self.forces = None

    # ---------------------------------------------------------------- frames
    def frame(self):
        """The current frame in SI, as keyword arguments of ``FrameWriter.append``."""
        u, st = self.cell.units, self.state
        ct = st.contacts
        on = ct.out[:, 2] > 0.0
        ij = np.column_stack([ct.i[on], ct.j[on]]).astype(np.int32)
        n, s = self.meas[1], -self.meas[0]
        pos, angle = self.system.positions(st)
        hs = np.array([getattr(u, name) for name in HISTORY_UNITS[self.system.material.law]])
        return dict(time=self.scalars[STEP] * self.dt * u.time,
                    strain=self.meas[2] / self.scalars[H0], normal_force=n * u.force,
                    shear_force=s * u.force, height=self.height * u.length,
                    pos=pos * u.length, angle=angle, vel=st.v[:, :2] * u.velocity,
                    omega=st.v[:, 2] / self.system.rscale / u.time, contact_ij=ij,
                    contact_force=ct.out[on, :2] * u.force,
                    contact_fn=ct.out[on, 2] * u.force,
                    contact_hist=ct.hist[on][:, :len(hs)] * hs,
                    contact_flag=ct.flag[on], tau=s / n if n > 0 else 0.0)


def prepare(sim, progress=None):
    """Compress the placed cell under the servo until N and the kinetic energy settle.

    Module docstring; ConvergenceError after ``prep_max_steps``.  Returns a
    dict of statistics.
    """
    c, p = sim.cell, sim.cell.params
    nt = c.n_target
    sim.controls = Controls(drag=0.05 / c.t_c, servo=(p["prep_speed"] / nt, nt, p["prep_speed"]),
                            affine_y=sim.y_floor)
    ke_tol = p["prep_ke"] * (nt / c.lx) * 4.0
    t0 = time.perf_counter()
    steps = 0
    while True:
        sim.advance(PREP_STAGE_STEPS)
        steps += PREP_STAGE_STEPS
        err = abs(sim.meas[1] / nt - 1.0)
        ke = sim.kinetic_energy()
        if progress is not None:
            progress(steps, err, ke / ke_tol)
        if err < p["prep_tol"] and ke < ke_tol:
            break
        if steps >= p["prep_max_steps"]:
            raise ConvergenceError(f"preparation: after {steps} steps |N/N_target - 1| = "
                                   f"{err:.3g} (tol {p['prep_tol']:g}), kinetic energy "
                                   f"{ke / ke_tol:.3g} x tolerance; raise prep_max_steps")
    sim.controls = Controls()
    sim.state.v[sim.system.free] = 0.0
    sim.forces = None
    return {"steps": steps, "seconds": time.perf_counter() - t0,
            "normal_force_error": err, "kinetic_energy": ke,
            "height_m": sim.height * c.units.length,
            "area_fraction": float(np.sum(np.pi * c.radius[c.kind == 0] ** 2)
                                   / (c.lx * sim.height)),
            "rebuilds": int(sim.state.rebuilds)}
