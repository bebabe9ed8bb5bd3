"""Newtonian dynamics of a periodic frictional disk packing (velocity Verlet, DEM).

The scene of Ishima et al. (2023): bidisperse disks in a periodic square box
(no Lees-Edwards offset), Hertz normal force and the Mindlin-type tangential
law ``f_T = -k_T xi_N^(1/2) xi_T`` (Ishima Eqs. 7-9) with its history, from the
verified generated kernels :mod:`fricstab.generated.ishima` (force and the
increment rule, Eq. D4).  The law has no Coulomb threshold, so a contact never
slides.  No damping: the run is Newtonian.

Contract
--------
* Units of :mod:`fricstab.scenes.packing`: large diameter ``d = 1``, ``k_N = 1``,
  ``m_i = d_i^2``, so ``t0 = 1``.
* Coordinates per disk ``q_i = (x_i, y_i, l_i)`` with ``l_i = d_i theta_i / 2``
  (Ishima's convention); generalized forces ``(F_x, F_y, F^l = 2 T / d)``.  The
  inertia of ``l`` is ``I_i (2 / d_i)^2 = m_i / 2`` (``I_i = m_i d_i^2 / 8``).
* ``q`` (N, 3) and ``v`` (N, 3) float64; positions are unwrapped during a run
  (wrapped into ``[0, L)`` at each neighbour-list rebuild).
* History: one tangential displacement ``t`` (2,) per listed pair ``i < j``
  (Verlet list with ``skin``, cell list of :mod:`fricstab.scenes.packing`), advanced
  in each step by ``dt_c = A_c dq_c`` (Eq. D4) at the new configuration with
  the drift ``dq = dt v(t + dt/2)`` (the update order of LAMMPS'
  ``gran/hertz/history``); zero while the pair does not overlap.  At a rebuild
  it is carried to the new list by pair.

Step (velocity Verlet): ``v += dt/2 M^-1 F``; ``q += dt v``; history
increment; new ``F``; ``v += dt/2 M^-1 F``.  The per-step cost is one pass over
the listed pairs.  The loop is serial (one core).
"""

from dataclasses import dataclass

import numpy as np

from fricstab._numba import kernel_jit
from fricstab.generated.ishima import ishima_force, ishima_increment
from fricstab.laws import ParameterError
from fricstab.scenes.pack_system import carry_history
from fricstab.scenes.packing import _pair_list, _wrap_all

__all__ = ["DemState", "DemRun", "init_state", "forces", "energy", "run"]

SKIN = 0.1  # Verlet-list skin, in d (also the LAMMPS benchmark's `neighbor`)


@dataclass
class DemState:
    """Mutable state of a DEM run.

    ``q`` (N, 3) and ``v`` (N, 3) in the coordinates above; ``pairs`` (P, 4)
    int64 rows ``(i, j, m, k)`` of the Verlet list (the image of j displaced by
    ``(m L, k L)``); ``hist`` (P, 2) the tangential displacements; ``ref``
    (N, 2) the positions at the last rebuild; ``skin`` the list's skin.
    """

    q: np.ndarray
    v: np.ndarray
    radius: np.ndarray
    mass: np.ndarray
    box: float
    kt: float
    pairs: np.ndarray
    hist: np.ndarray
    ref: np.ndarray
    force: np.ndarray
    skin: float = SKIN
    rebuilds: int = 0

    @property
    def n(self):
        return len(self.radius)


@dataclass(frozen=True)
class DemRun:
    """Outcome of :func:`run`: steps done, list rebuilds, energies if recorded."""

    steps: int
    rebuilds: int
    energies: np.ndarray


@kernel_jit
def _forces(q, dq, radius, box, pairs, hist, kn, kt, update, force):
    """Forces over the listed pairs into ``force``; advances ``hist`` by Eq. D4 if ``update``.

    Returns the number of overlapping pairs.
    """
    force[:] = 0.0
    f = np.empty(6)
    a = np.empty((2, 6))
    touching = 0
    for p in range(pairs.shape[0]):
        i, j, m, k = pairs[p, 0], pairs[p, 1], pairs[p, 2], pairs[p, 3]
        dy = (q[i, 1] - q[j, 1]) - k * box
        dx = (q[i, 0] - q[j, 0]) - m * box
        s = radius[i] + radius[j]
        if dx * dx + dy * dy >= s * s:
            hist[p, 0] = 0.0  # a contact that opens forgets its history
            hist[p, 1] = 0.0
            continue
        touching += 1
        if update:
            ishima_increment(dx, dy, radius[i], radius[j], a)
            for r in range(2):
                inc = 0.0
                for b in range(3):
                    inc += a[r, b] * dq[i, b] + a[r, 3 + b] * dq[j, b]
                hist[p, r] += inc
        ishima_force(dx, dy, radius[i], radius[j], kn, kt, hist[p, 0], hist[p, 1], f)
        for b in range(3):
            force[i, b] += f[b]
            force[j, b] += f[3 + b]
    return touching


@kernel_jit
def _energy(q, v, radius, mass, box, pairs, hist, kn, kt):
    """Kinetic + Hertz (2/5 k_N xi^(5/2)) + tangential spring (1/2 k_T xi^(1/2) |t|^2)."""
    e = 0.0
    for i in range(q.shape[0]):
        e += 0.5 * mass[i] * (v[i, 0] ** 2 + v[i, 1] ** 2 + 0.5 * v[i, 2] ** 2)
    for p in range(pairs.shape[0]):
        i, j, m, k = pairs[p, 0], pairs[p, 1], pairs[p, 2], pairs[p, 3]
        dy = (q[i, 1] - q[j, 1]) - k * box
        dx = (q[i, 0] - q[j, 0]) - m * box
        xi = radius[i] + radius[j] - np.sqrt(dx * dx + dy * dy)
        if xi > 0.0:
            e += 0.4 * kn * xi ** 2.5 + 0.5 * kt * np.sqrt(xi) * (hist[p, 0] ** 2 + hist[p, 1] ** 2)
    return e


@kernel_jit
def _steps(q, v, radius, mass, box, pairs, hist, ref, kn, kt, dt, n_steps, skin, force):
    """Velocity Verlet until ``n_steps`` or until the list must be rebuilt.

    Returns the steps done; fewer than ``n_steps`` means a disk moved more than
    ``skin / 2`` since the last rebuild (checked after the drift, before the
    forces, so the caller rebuilds and the step is completed there).
    """
    n = q.shape[0]
    dq = np.empty((n, 3))
    lim = 0.25 * skin * skin
    for s in range(n_steps):
        far = 0.0
        for i in range(n):
            inv = 1.0 / mass[i]
            v[i, 0] += 0.5 * dt * force[i, 0] * inv
            v[i, 1] += 0.5 * dt * force[i, 1] * inv
            v[i, 2] += dt * force[i, 2] * inv  # l-inertia m/2
            for b in range(3):
                dq[i, b] = dt * v[i, b]
                q[i, b] += dq[i, b]
            far = max(far, (q[i, 0] - ref[i, 0]) ** 2 + (q[i, 1] - ref[i, 1]) ** 2)
        if far > lim:
            # undo the drift and half kick: the caller rebuilds and redoes the step
            for i in range(n):
                inv = 1.0 / mass[i]
                for b in range(3):
                    q[i, b] -= dq[i, b]
                v[i, 0] -= 0.5 * dt * force[i, 0] * inv
                v[i, 1] -= 0.5 * dt * force[i, 1] * inv
                v[i, 2] -= dt * force[i, 2] * inv
            return s
        _forces(q, dq, radius, box, pairs, hist, kn, kt, True, force)
        for i in range(n):
            inv = 1.0 / mass[i]
            v[i, 0] += 0.5 * dt * force[i, 0] * inv
            v[i, 1] += 0.5 * dt * force[i, 1] * inv
            v[i, 2] += dt * force[i, 2] * inv
    return n_steps


def _rebuild(state):
    skin = state.skin
    pos = np.ascontiguousarray(state.q[:, :2])
    _wrap_all(pos, state.box)
    state.q[:, :2] = pos
    pairs = _pair_list(pos, state.radius, state.box, 0.0, skin)
    order = np.lexsort((pairs[:, 1], pairs[:, 0]))
    pairs = np.ascontiguousarray(pairs[order])
    state.hist = carry_history(state.pairs[:, :2], state.hist, pairs[:, :2], state.n)
    state.pairs = pairs
    state.ref = pos.copy()
    state.rebuilds += 1


def init_state(pos, radius, box, kt, velocity=None, skin=SKIN):
    """A DEM state at ``pos`` (N, 2) with zero histories.

    Parameters
    ----------
    pos : array_like, shape (N, 2)
    radius : array_like, shape (N,)
        Masses are ``m_i = (2 R_i)^2`` (d = 1 for the large disks).
    box : float
        Side of the periodic box, larger than twice the largest diameter.
    kt : float
        ``k_T / k_N`` > 0 (the law is frictional; use :mod:`fricstab.scenes.packing` for kt = 0).
    velocity : array_like, shape (N, 3), optional
        ``(v_x, v_y, v_l)``, ``v_l = d omega / 2``; zero if omitted.
    skin : float
        Verlet-list skin (> 0).
    """
    pos = np.array(pos, dtype=np.float64)
    radius = np.ascontiguousarray(radius, dtype=np.float64)
    n = len(radius)
    if pos.shape != (n, 2) or not np.all(np.isfinite(pos)):
        raise ParameterError(f"pos must be a finite array of shape ({n}, 2), got shape {pos.shape}")
    if not (np.all(np.isfinite(radius)) and np.all(radius > 0)):
        raise ParameterError("radius must be finite and > 0")
    if not (np.isfinite(box) and box > 4 * radius.max()):
        raise ParameterError(f"box must be a finite number > 2 max diameter = "
                             f"{4 * radius.max()}, got {box!r}")
    if not (np.isfinite(kt) and kt > 0):
        raise ParameterError(f"kt (= kT/kN) must be a finite number > 0, got {kt!r}")
    if not (np.isfinite(skin) and skin > 0):
        raise ParameterError(f"skin must be a finite number > 0, got {skin!r}")
    v = np.zeros((n, 3)) if velocity is None else np.array(velocity, dtype=np.float64)
    if v.shape != (n, 3) or not np.all(np.isfinite(v)):
        raise ParameterError(f"velocity must be a finite array of shape ({n}, 3), got {v.shape}")
    q = np.zeros((n, 3))
    q[:, :2] = pos
    state = DemState(q, v, radius, (2 * radius) ** 2, float(box), float(kt),
                     np.zeros((0, 4), np.int64), np.zeros((0, 2)), pos.copy(), np.zeros((n, 3)),
                     float(skin))
    _rebuild(state)
    state.rebuilds = 0
    _forces(state.q, np.zeros((n, 3)), radius, state.box, state.pairs, state.hist, 1.0,
            state.kt, False, state.force)
    return state


def forces(state):
    """Generalized forces (N, 3) at the state's positions and histories (no update)."""
    out = np.zeros((state.n, 3))
    hist = state.hist.copy()
    _forces(state.q, np.zeros((state.n, 3)), state.radius, state.box, state.pairs, hist, 1.0,
            state.kt, False, out)
    return out


def energy(state):
    """Kinetic + Hertz + tangential spring energy (``k_N d^(5/2)``).

    The tangential term ``k_T xi^(1/2) |t|^2 / 2`` is the energy of the law at
    fixed overlap; the law is not derived from a potential (its stiffness
    changes with ``xi``), so this total is conserved only up to
    ``(k_T / 4) xi^(-1/2) |t|^2 d xi`` summed over the run, besides the
    ``O(dt^2)`` error of the integrator.
    """
    return float(_energy(state.q, state.v, state.radius, state.mass, state.box, state.pairs,
                         state.hist, 1.0, state.kt))


def run(state, dt, n_steps, record_every=0):
    """Advance ``state`` in place by ``n_steps`` velocity-Verlet steps of ``dt`` (t0).

    ``record_every > 0`` records :func:`energy` every that many steps (and at
    the start).  Returns a :class:`DemRun`.
    """
    if not (np.isfinite(dt) and dt > 0):
        raise ParameterError(f"dt must be a finite number > 0, got {dt!r}")
    if not (isinstance(n_steps, (int, np.integer)) and n_steps >= 0):
        raise ParameterError(f"n_steps must be an integer >= 0, got {n_steps!r}")
    chunk = record_every if record_every > 0 else n_steps
    energies = [energy(state)] if record_every > 0 else []
    done, rebuilds = 0, state.rebuilds
    while done < n_steps:
        goal = min(chunk, n_steps - done)
        got = 0
        while got < goal:
            got += _steps(state.q, state.v, state.radius, state.mass, state.box, state.pairs,
                          state.hist, state.ref, 1.0, state.kt, float(dt), goal - got, state.skin,
                          state.force)
            if got < goal:
                _rebuild(state)
        done += goal
        if record_every > 0:
            energies.append(energy(state))
    return DemRun(done, state.rebuilds - rebuilds, np.array(energies))
