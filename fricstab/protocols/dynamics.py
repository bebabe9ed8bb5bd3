"""Velocity Verlet for the chain on the engine: the damped protocol and Newtonian dynamics.

``m r'' = F - m nu r'`` and ``I theta'' = T - I nu theta'`` (Charan SM: global
viscous drag proportional to the velocities, nu = 0.01; nu = 0 is Newtonian
dynamics), run by :func:`fricstab.engine.run` with ``Controls(drag=nu)``:
half kick with the drag at the old velocity, drift, the history advanced by
the increment rule at the new configuration (``A(q_new) du``, LAMMPS' order;
the pre-engine loop took ``A(q_old)``, an O(dt) difference per step in the
discrete dynamics) and projected onto the Coulomb circle (Charan: "history
updated every step"), new forces, second half kick with the drag implicit.
Time is in simulation units (``sqrt(m/kn)`` for m = kn = 1); Charan's unit
is ``sqrt(m 2R/kn)`` (:func:`fricstab.scenes.chain.time_unit`).

Checkpoints: :func:`run_dynamics` runs the loop in chunks of whole steps
and may save the full state between chunks (the engine state's arrays, the
frames recorded so far, the step counter; :class:`fricstab.io.checkpoint.
Checkpointer`).  Each chunk starts from the forces recomputed from the state
(:meth:`System.forces`, no projection), the same deterministic function of
the same numbers in an uninterrupted and in a resumed run, so a resumed run
is bit-identical to an uninterrupted one on the same machine.  A non-finite
force or position stops the loop and raises :class:`fricstab.errors.
NumericalError` naming the step and the disk.
"""

import time
from dataclasses import dataclass

import numpy as np

from fricstab.engine import Controls, State, run
from fricstab.errors import (MAX_STEPS, NumericalError, check_finite_array, check_int,
                             check_real, check_steps)
from fricstab.scenes.chain import (chain_system, check_chain, legacy_order, rest_overlap,
                                   wall_slots, wall_stiffness)

__all__ = ["VerletResult", "default_dt", "perturbed", "relax_damped", "run_dynamics"]


@dataclass(frozen=True)
class VerletResult:
    """Outcome of a Verlet run.

    ``positions`` and ``velocities`` are physical: (x, y, theta) and
    (x', y', omega) per disk, whatever the law's rotation coordinate;
    ``wall_hist`` (frames, N, H) the wall contacts' histories of disks 0..N-1.
    """

    state: object
    velocity: np.ndarray
    residual: float
    steps: int
    converged: bool
    seconds: float
    times: np.ndarray = None       # recorded times (dynamics), simulation units
    positions: np.ndarray = None   # recorded (x, y, theta), (frames, N, 3)
    wall_hist: np.ndarray = None   # recorded wall histories, (frames, N, H)
    velocities: np.ndarray = None  # recorded velocities (x', y', theta'), (frames, N, 3)

    @property
    def wall_t(self):
        """The first wall history (charan: t along x), (frames, N)."""
        return self.wall_hist[:, :, 0]


def default_dt(scene, fraction):
    """``fraction / omega_wall``, ``omega_wall^2 = k_wall / m`` the wall's normal frequency at rest."""
    return fraction / np.sqrt(wall_stiffness(scene) / scene.mass)


def perturbed(scene, state, amplitude, rng):
    """A copy of ``state`` moved by ``amplitude`` times the rest wall overlap times N(0, 1).

    One standard normal draw per entry of ``q`` (N, 3), so that a seed gives
    the same perturbation under every law; a frictionless law's rotation
    column is left at rest.
    """
    start = state.copy()
    noise = rng.standard_normal(start.q.shape)
    noise[:, scene.dof:] = 0.0
    start.q += amplitude * rest_overlap(scene) * noise
    return start


def _rename(exc, step0, checkpoint_path=None):
    """The engine's NumericalError in the chain's words (disk, Verlet step)."""
    where = f"; last checkpoint {checkpoint_path}" if checkpoint_path else ""
    step = exc.step if exc.step is not None else step0
    what = exc.quantity or "force"
    return NumericalError(f"non-finite {what} of disk {exc.item} at Verlet step {step}{where}",
                          step=step, item=exc.item, quantity=what)


def relax_damped(scene, state, nu=0.01, dt=None, tol=1e-12, max_steps=50_000_000):
    """Charan's damped protocol: Verlet with drag ``nu`` from rest until ``max |F|, |T| < tol``.

    ``m r'' = F - m nu r'`` and ``I theta'' = T - I nu theta'`` (Charan SM), the
    history updated every step.  It settles only on equilibria whose growth rate
    is below ``nu/2``, so the pairs a damped ramp sees depend on ``nu``
    (``validation/chain_protocols.md``).

    Parameters
    ----------
    scene : ChainScene
    state : State
        Starting state (not modified; velocities start at zero).
    nu : float
        Drag rate (1/time, simulation units; Charan: 0.01 per paper time unit).
    dt : float, optional
        Verlet step (simulation units); default ``0.05 / omega_wall``
        (:func:`default_dt`), omega_wall the stiffest normal mode at rest.
    tol : float
        Force threshold (Charan's force units).
    max_steps : int
        Step cap.

    Returns
    -------
    VerletResult
        ``state`` (relaxed copy), ``velocity``, ``residual``, ``steps``,
        ``converged``, ``seconds``.
    """
    check_chain(scene, state)
    check_real("nu", nu, 0.0)
    check_real("dt", dt, 0.0, low_open=True, allow_none=True)
    check_real("tol", tol, 0.0, low_open=True)
    check_int("max_steps", max_steps, 1, MAX_STEPS)
    if dt is None:
        dt = default_dt(scene, 0.05)
    system = chain_system(scene)
    s = state.copy()
    s.v[:] = 0.0
    t0 = time.perf_counter()
    try:
        out = run(system, s, dt, max_steps, Controls(drag=nu), tol=tol, check_every=100)
    except NumericalError as exc:
        raise _rename(exc, 0) from None
    return VerletResult(s, s.v.copy(), float(out.residual), int(out.steps), bool(out.converged),
                        time.perf_counter() - t0)


def _physical(system, frames):
    """Generalized frames (F, N, 3) -> physical (x, y, theta): the rotation over s."""
    out = np.array(frames, dtype=float)
    out[..., 2] /= system.rscale
    return out


def run_dynamics(scene, state, velocity=None, dt=None, duration=100.0, frames=2000, nu=0.0,
                 checkpointer=None, checkpoint_every=None, resume=None, progress=None):
    """Newtonian dynamics of the chain (``nu = 0``) for ``duration``, recording about ``frames`` frames.

    Velocity Verlet with the history advanced every step (module docstring;
    Charan Sec. III, Figs. 3-7).  Time is in simulation units, ``sqrt(m/k)``
    with m = 1 and the stiffness unit of the scene; Charan's unit is
    ``sqrt(m 2R/k_n)`` (:func:`fricstab.scenes.chain.time_unit`).

    Parameters
    ----------
    scene : ChainScene
        The scene (with its F_x).
    state : State
        The starting state (not modified); its histories are projected at
        its configuration before the first step.
    velocity : ndarray, shape (N, 3), optional
        Initial generalized velocities (default zero).
    dt : float, optional
        Verlet step in simulation units (default ``0.02 / omega_wall``,
        :func:`default_dt`); smaller is more accurate and proportionally slower.
    duration : float
        Simulated time in simulation units.
    frames : int
        Frames are recorded every ``max(1, steps // frames)`` steps.
    nu : float
        Drag rate (1/time; Charan's damped protocol uses 0.01); 0 is Newtonian.
    checkpointer : fricstab.io.checkpoint.Checkpointer, optional
        Where the state is saved every ``checkpoint_every`` steps.
    checkpoint_every : int, optional
        Steps between checkpoints.
    resume : dict, optional
        A checkpoint (:meth:`Checkpointer.latest`) to continue from.
    progress : tqdm, optional
        Advanced by the number of steps done after each chunk.

    Returns
    -------
    VerletResult
        The final ``state`` and ``velocity``, ``residual``, ``steps``,
        ``seconds``, and the recorded ``times`` (simulation units),
        ``positions`` (frames, N, 3: x, y, theta), ``wall_hist`` and
        ``velocities``.

    Raises
    ------
    NumericalError
        A force or position became NaN or inf (the message names the step and disk).
    """
    check_chain(scene, state)
    if velocity is not None:
        check_finite_array("velocity", velocity, shape=state.v.shape)
    check_real("dt", dt, 0.0, low_open=True, allow_none=True)
    check_real("duration", duration, 0.0, low_open=True)
    check_int("frames", frames, 1, MAX_STEPS)
    check_real("nu", nu, 0.0)
    if dt is None:
        dt = default_dt(scene, 0.02)
    check_steps("run_dynamics", duration / dt)
    system = chain_system(scene)
    n_steps = int(np.ceil(duration / dt))
    every = max(1, n_steps // frames)
    s = state.copy()
    s.v[:] = 0.0 if velocity is None else np.asarray(velocity, dtype=float)
    walls = legacy_order(s)[0][scene.n:]
    rec_q, rec_v, rec_h = [], [], []
    meas = np.zeros(8)
    step = 0
    if resume is not None:
        step = int(resume["step"])
        s = State.from_arrays({k[6:]: v for k, v in resume.items() if k.startswith("state_")})
        meas = np.array(resume["meas"], float)
        rec_q, rec_v, rec_h = [resume["rec_q"]], [resume["rec_v"]], [resume["rec_h"]]
        if progress is not None:
            progress.update(step)
    else:
        system.project(s)
    chunk = checkpoint_every if checkpointer is not None and checkpoint_every else \
        max(1, n_steps // 100)
    last_path = None if resume is None else resume.get("path")
    t0 = time.perf_counter()
    residual = np.inf
    while step < n_steps:
        end = min(n_steps, (step // chunk + 1) * chunk)
        try:
            out = run(system, s, dt, end, Controls(drag=nu), record_every=every,
                      record_hist=True, forces=system.forces(s), step0=step, meas=meas)
        except NumericalError as exc:
            raise _rename(exc, step, last_path) from None
        except ValueError as exc:   # the law refused a configuration (e.g. no contact width)
            raise NumericalError(f"the contact law failed at Verlet step {step}..{end}: "
                                 f"{exc}", step=step) from None
        residual = out.residual
        meas = out.driven_force
        rec_q.append(out.q)
        rec_v.append(out.v)
        rec_h.append(out.hist[:, walls, :wall_slots(scene)])
        if progress is not None:
            progress.update(end - step)
        step = end
        if checkpointer is not None and checkpoint_every and step < n_steps:
            arrays = {"state_" + k: v for k, v in s.arrays().items()}
            last_path = checkpointer.save(step, meas=meas, rec_q=np.concatenate(rec_q),
                                          rec_v=np.concatenate(rec_v),
                                          rec_h=np.concatenate(rec_h), **arrays)
    q = np.concatenate(rec_q) if rec_q else np.zeros((0, scene.n, 3))
    v = np.concatenate(rec_v) if rec_v else np.zeros((0, scene.n, 3))
    h = np.concatenate(rec_h) if rec_h else np.zeros((0, scene.n, wall_slots(scene)))
    times = np.arange(len(q)) * every * dt
    return VerletResult(s, s.v.copy(), float(residual), int(step), True,
                        time.perf_counter() - t0, times, _physical(system, q), h,
                        _physical(system, v))
