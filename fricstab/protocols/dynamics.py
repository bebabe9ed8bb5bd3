"""Velocity Verlet for the chain: the damped protocol and Newtonian dynamics.

``m r'' = F - m nu r'`` and ``I theta'' = T - I nu theta'`` (Charan SM: global
viscous drag proportional to the velocities, nu = 0.01; nu = 0 is Newtonian
dynamics).  Each step: half kick with the drag at the old velocity, drift,
history advanced by the increment rule for the drift (with the Coulomb
rescaling: Charan "history updated every step"), new forces, second half kick
with the drag treated implicitly.  Time is in simulation units
(``sqrt(m/kn)`` for m = kn = 1); Charan's unit is ``sqrt(m 2R/kn)``.

Checkpoints: :func:`run_dynamics` runs the Verlet loop in chunks of whole
steps and may save the full state between chunks (q, v, histories, the
frames recorded so far, the step counter; :class:`fricstab.io.checkpoint.
Checkpointer`).  A chunk starts by recomputing the forces from the state,
which is the same deterministic function of the same numbers the
uninterrupted loop evaluated, so a resumed run is bit-identical to an
uninterrupted one on the same machine.  A non-finite force stops the loop at
that step and raises :class:`fricstab.errors.NumericalError` naming the step,
the disk and the component.
"""

import time
from dataclasses import dataclass

import numpy as np

from fricstab._numba import kernel_jit
from fricstab.scenes.chain import _advance, _assemble
from fricstab.errors import NumericalError

__all__ = ["VerletResult", "relax_damped", "run_dynamics"]


@dataclass(frozen=True)
class VerletResult:
    """Outcome of a Verlet run."""

    state: object
    velocity: np.ndarray
    residual: float
    steps: int
    converged: bool
    seconds: float
    times: np.ndarray = None       # recorded times (dynamics)
    positions: np.ndarray = None   # recorded q, (frames, N, 3)
    wall_t: np.ndarray = None      # recorded wall histories, (frames, N)
    velocities: np.ndarray = None  # recorded velocities (x', y', theta'), (frames, N, 3)


@kernel_jit
def _first_nonfinite(f):
    for i in range(f.shape[0]):
        for a in range(3):
            if not np.isfinite(f[i, a]):
                return 3 * i + a
    return -1


@kernel_jit
def _verlet(q, v, t_pair, t_wall, R, kn, kt, mu, fy, fx, period, mass, inertia, nu, dt,
            step0, max_steps, tol, check_every, record_every, frame0, rec_q, rec_tw, rec_v):
    """Steps ``step0 .. max_steps - 1``; returns (steps done, residual, frames, bad, step).

    ``bad`` is -1, or ``3 i + a`` for the first non-finite force component a
    of disk i, found after step ``step`` (then the loop stops there).
    """
    n = q.shape[0]
    f = np.empty((n, 3))
    jac = np.empty((1, 1))
    _assemble(q, t_pair, t_wall, R, kn, kt, mu, fy, fx, period, f, jac, False)
    bad = _first_nonfinite(f)
    if bad >= 0:
        return step0, np.inf, frame0, bad, step0
    inv = np.empty(3)
    inv[0] = 1.0 / mass
    inv[1] = 1.0 / mass
    inv[2] = 1.0 / inertia
    dq = np.empty((n, 3))
    residual = np.inf
    frame = frame0
    for step in range(step0, max_steps):
        if record_every > 0 and step % record_every == 0 and frame < rec_q.shape[0]:
            rec_q[frame] = q
            rec_tw[frame] = t_wall
            rec_v[frame] = v
            frame += 1
        for i in range(n):
            for a in range(3):
                v[i, a] += 0.5 * dt * (f[i, a] * inv[a] - nu * v[i, a])
                dq[i, a] = dt * v[i, a]
        _advance(q, dq, t_pair, t_wall, R, kn, kt, mu, period)
        for i in range(n):
            for a in range(3):
                q[i, a] += dq[i, a]
        _assemble(q, t_pair, t_wall, R, kn, kt, mu, fy, fx, period, f, jac, False)
        bad = _first_nonfinite(f)
        if bad >= 0:
            return step + 1, np.inf, frame, bad, step + 1
        for i in range(n):
            for a in range(3):
                v[i, a] = (v[i, a] + 0.5 * dt * f[i, a] * inv[a]) / (1.0 + 0.5 * dt * nu)
        if tol > 0 and step % check_every == 0:
            residual = np.abs(f).max()
            if residual < tol:
                return step + 1, residual, frame, -1, step + 1
    residual = np.abs(f).max()
    return max_steps, residual, frame, -1, max_steps


_COMPONENTS = ("F_x", "F_y", "torque T")


def _raise_nonfinite(bad, step, checkpoint_path=None):
    where = f"; last checkpoint {checkpoint_path}" if checkpoint_path else ""
    raise NumericalError(f"non-finite force {_COMPONENTS[bad % 3]} on disk {bad // 3} "
                         f"at Verlet step {step}{where}", step=step, item=bad // 3,
                         quantity=_COMPONENTS[bad % 3])


def _run(scene, state, velocity, nu, dt, max_steps, tol, record_every, frames):
    s = state.copy()
    v = np.zeros_like(s.q) if velocity is None else np.array(velocity, dtype=float)
    rec_q = np.empty((max(frames, 1), scene.n, 3))
    rec_tw = np.empty((max(frames, 1), scene.n))
    t0 = time.perf_counter()
    steps, residual, frame, bad, at = _verlet(
        s.q, v, s.t_pair, s.t_wall, scene.radius, scene.kn, scene.kt, scene.mu, scene.fy,
        scene.fx, scene.period, scene.mass, scene.inertia, nu, dt, 0, max_steps, tol, 100,
        record_every, 0, rec_q, rec_tw, np.empty_like(rec_q))
    if bad >= 0:
        _raise_nonfinite(bad, at)
    return s, v, steps, residual, frame, rec_q[:frame], rec_tw[:frame], time.perf_counter() - t0


def relax_damped(scene, state, nu=0.01, dt=None, tol=1e-12, max_steps=50_000_000):
    """The damped protocol: Verlet with drag ``nu`` until max |F|, |T| < ``tol``.

    ``dt`` defaults to 0.05 / omega_wall with ``omega_wall^2 = 1.5 kn
    (F_y/kn)^(1/3) / m``, the stiffest normal mode of the scene at rest.
    """
    if dt is None:
        omega = np.sqrt(1.5 * scene.kn * (scene.fy / scene.kn) ** (1 / 3) / scene.mass)
        dt = 0.05 / omega
    s, v, steps, residual, _, _, _, secs = _run(scene, state, None, nu, dt, max_steps, tol, 0, 0)
    return VerletResult(s, v, float(residual), int(steps), bool(residual < tol), secs)


def _default_dt(scene, fraction):
    omega = np.sqrt(1.5 * scene.kn * (scene.fy / scene.kn) ** (1 / 3) / scene.mass)
    return fraction / omega


def run_dynamics(scene, state, velocity=None, dt=None, duration=100.0, frames=2000, nu=0.0,
                 checkpointer=None, checkpoint_every=None, resume=None, progress=None):
    """Newtonian dynamics (``nu = 0``) for ``duration``, recording ``frames`` frames.

    Parameters
    ----------
    scene, state : ChainScene, ChainState
        The scene (with its F_x) and the starting state (not modified).
    velocity : ndarray (N, 3), optional
        Initial velocities (default zero).
    dt : float, optional
        Verlet step in simulation units (default ``0.02 / omega_wall``, see
        :func:`relax_damped`); smaller is more accurate and proportionally slower.
    duration : float
        Simulated time in simulation units.
    frames : int
        About this many frames are recorded, every ``max(1, steps // frames)`` steps.
    checkpointer : fricstab.io.checkpoint.Checkpointer, optional
        Where the state is saved every ``checkpoint_every`` steps.
    resume : dict, optional
        A checkpoint (:meth:`Checkpointer.latest`) to continue from.
    progress : tqdm, optional
        Advanced by the number of steps done after each chunk.

    Raises
    ------
    NumericalError
        A force became NaN or inf (the message names the step, disk and component).
    """
    if dt is None:
        dt = _default_dt(scene, 0.02)
    n_steps = int(np.ceil(duration / dt))
    every = max(1, n_steps // frames)
    n_frames = n_steps // every + 1
    s = state.copy()
    v = np.zeros_like(s.q) if velocity is None else np.array(velocity, dtype=float)
    rec_q = np.empty((n_frames, scene.n, 3))
    rec_tw = np.empty((n_frames, scene.n))
    rec_v = np.empty((n_frames, scene.n, 3))
    step = frame = 0
    if resume is not None:
        step, frame = int(resume["step"]), int(resume["frame"])
        s.q[...], v[...] = resume["q"], resume["v"]
        s.t_pair[...], s.t_wall[...] = resume["t_pair"], resume["t_wall"]
        rec_q[:frame], rec_tw[:frame] = resume["rec_q"], resume["rec_tw"]
        rec_v[:frame] = resume["rec_v"]
        if progress is not None:
            progress.update(step)
    chunk = checkpoint_every if checkpointer is not None and checkpoint_every else \
        max(1, n_steps // 100)
    last_path = None if resume is None else resume.get("path")
    t0 = time.perf_counter()
    residual = np.inf
    while step < n_steps:
        end = min(n_steps, (step // chunk + 1) * chunk)
        done, residual, frame, bad, at = _verlet(
            s.q, v, s.t_pair, s.t_wall, scene.radius, scene.kn, scene.kt, scene.mu, scene.fy,
            scene.fx, scene.period, scene.mass, scene.inertia, nu, dt, step, end, 0.0, 100,
            every, frame, rec_q, rec_tw, rec_v)
        if bad >= 0:
            _raise_nonfinite(bad, at, last_path)
        if progress is not None:
            progress.update(end - step)
        step = end
        if checkpointer is not None and checkpoint_every and step < n_steps:
            last_path = checkpointer.save(step, frame=np.int64(frame), q=s.q, v=v,
                                          t_pair=s.t_pair, t_wall=s.t_wall,
                                          rec_q=rec_q[:frame], rec_tw=rec_tw[:frame],
                                          rec_v=rec_v[:frame])
    times = np.arange(frame) * every * dt
    return VerletResult(s, v, float(residual), int(step), True, time.perf_counter() - t0,
                        times, rec_q[:frame], rec_tw[:frame], rec_v[:frame])
