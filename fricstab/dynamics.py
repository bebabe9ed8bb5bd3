"""Velocity Verlet for the chain: the damped protocol and Newtonian dynamics.

``m r'' = F - m nu r'`` and ``I theta'' = T - I nu theta'`` (Charan SM: global
viscous drag proportional to the velocities, nu = 0.01; nu = 0 is Newtonian
dynamics).  Each step: half kick with the drag at the old velocity, drift,
history advanced by the increment rule for the drift (with the Coulomb
rescaling: Charan "history updated every step"), new forces, second half kick
with the drag treated implicitly.  Time is in simulation units
(``sqrt(m/kn)`` for m = kn = 1); Charan's unit is ``sqrt(m 2R/kn)``.
"""

import time
from dataclasses import dataclass

import numpy as np

from fricstab._numba import kernel_jit
from fricstab.chain import _advance, _assemble

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


@kernel_jit
def _verlet(q, v, t_pair, t_wall, R, kn, kt, mu, fy, fx, period, mass, inertia, nu, dt,
            max_steps, tol, check_every, record_every, rec_q, rec_tw):
    n = q.shape[0]
    f = np.empty((n, 3))
    jac = np.empty((1, 1))
    _assemble(q, t_pair, t_wall, R, kn, kt, mu, fy, fx, period, f, jac, False)
    inv = np.empty(3)
    inv[0] = 1.0 / mass
    inv[1] = 1.0 / mass
    inv[2] = 1.0 / inertia
    dq = np.empty((n, 3))
    residual = np.inf
    frame = 0
    for step in range(max_steps):
        if record_every > 0 and step % record_every == 0 and frame < rec_q.shape[0]:
            rec_q[frame] = q
            rec_tw[frame] = t_wall
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
        for i in range(n):
            for a in range(3):
                v[i, a] = (v[i, a] + 0.5 * dt * f[i, a] * inv[a]) / (1.0 + 0.5 * dt * nu)
        if tol > 0 and step % check_every == 0:
            residual = np.abs(f).max()
            if residual < tol:
                return step + 1, residual, frame
    residual = np.abs(f).max()
    return max_steps, residual, frame


def _run(scene, state, velocity, nu, dt, max_steps, tol, record_every, frames):
    s = state.copy()
    v = np.zeros_like(s.q) if velocity is None else np.array(velocity, dtype=float)
    rec_q = np.empty((max(frames, 1), scene.n, 3))
    rec_tw = np.empty((max(frames, 1), scene.n))
    t0 = time.perf_counter()
    steps, residual, frame = _verlet(
        s.q, v, s.t_pair, s.t_wall, scene.radius, scene.kn, scene.kt, scene.mu, scene.fy,
        scene.fx, scene.period, scene.mass, scene.inertia, nu, dt, max_steps, tol, 100,
        record_every, rec_q, rec_tw)
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


def run_dynamics(scene, state, velocity=None, dt=None, duration=100.0, frames=2000, nu=0.0):
    """Newtonian dynamics (``nu = 0``) for ``duration``, recording ``frames`` frames."""
    if dt is None:
        omega = np.sqrt(1.5 * scene.kn * (scene.fy / scene.kn) ** (1 / 3) / scene.mass)
        dt = 0.02 / omega
    n_steps = int(np.ceil(duration / dt))
    every = max(1, n_steps // frames)
    s, v, steps, residual, frame, rec_q, rec_tw, secs = _run(
        scene, state, velocity, nu, dt, n_steps, 0.0, every, n_steps // every + 1)
    times = np.arange(frame) * every * dt
    return VerletResult(s, v, float(residual), int(steps), True, secs, times, rec_q, rec_tw)
