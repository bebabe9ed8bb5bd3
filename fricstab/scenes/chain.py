"""A chain of disks on a flat substrate (Charan et al.): scene, forces, Jacobian.

Scene: N disks of radius R on the substrate y = 0, periodic in x with period
2NR (neighbours just touch), each pressed down by F_y, disk 0 pushed by F_x.
Contacts are only those the scene needs: ring neighbours (i, i+1 mod N) and
each disk with the wall.  Laws: ``charan`` (pairs) and ``charan_wall``
(Charan Eqs. 1, 2, 5), from the verified generated kernels.

Conventions (as the generated kernels, unscaled)
------------------------------------------------
* ``q`` is (N, 3): x, y, theta (radians, counter-clockwise), disk by disk.
* Pair contact c = (i, j = i+1 mod N): ``t_pair[c]`` is the tangential
  displacement of i relative to j in the lab frame (the tangential force on i
  opposes it); the separation is ``r_i - r_j`` with the image shift
  ``-period`` in x for the wrapping contact (N-1, 0), so N = 2 has two
  distinct contacts.  Wall contact of disk i: ``t_wall[i]`` along x.
* Generalized forces (N, 3): F_x, F_y, torque T.  The Jacobian is the dense
  3N x 3N ``dF/dq`` with rows (F_x, F_y, T) and columns (x, y, theta) per
  disk, disk by disk, the history advanced by the increment rule.  Charan's
  scaled coordinates (theta~ = R theta, T~ = T/R, mass diag(m, m, I/R^2))
  follow by :func:`scaled`.
"""

import math
from dataclasses import dataclass, field, replace

import numpy as np

from fricstab._numba import kernel_jit
from fricstab._numerics import overlap_correction
from fricstab.generated.charan import charan_force_jacobian, charan_increment
from fricstab.generated.charan_wall import charan_wall_force_jacobian
from fricstab.laws import ParameterError

__all__ = ["ChainScene", "ChainState", "contacts", "forces", "forces_and_jacobian",
           "initial_state", "advance_history", "scaled", "mass_vector"]


@dataclass(frozen=True)
class ChainScene:
    """Parameters of the chain (defaults: Charan et al.).

    ``kt`` defaults to 2 kn / 7 and the moment of inertia ``inertia`` to
    m R^2 / 2 (a uniform disk; the paper does not state it).
    """

    n: int = 10
    radius: float = 0.5
    mass: float = 1.0
    kn: float = 2000.0
    kt: float = None
    mu: float = 10.0
    fy: float = 0.1
    fx: float = 0.0
    inertia: float = None

    def __post_init__(self):
        if self.kt is None:
            object.__setattr__(self, "kt", 2.0 * self.kn / 7.0)
        if self.inertia is None:
            object.__setattr__(self, "inertia", self.mass * self.radius ** 2 / 2.0)
        if not isinstance(self.n, (int, np.integer)) or isinstance(self.n, bool) or self.n < 2:
            raise ParameterError(f"n must be an integer >= 2, got {self.n!r}")
        for key in ("radius", "mass", "kn", "kt", "mu", "fy", "inertia"):
            v = getattr(self, key)
            if not isinstance(v, (int, float)) or not math.isfinite(v) or v <= 0:
                raise ParameterError(f"{key} must be a finite number > 0, got {v!r}")
        if not isinstance(self.fx, (int, float)) or not math.isfinite(self.fx):
            raise ParameterError(f"fx must be a finite number, got {self.fx!r}")

    @property
    def period(self):
        return 2.0 * self.n * self.radius

    def with_fx(self, fx):
        return replace(self, fx=float(fx))


@dataclass
class ChainState:
    """Positions and the tangential history (state, see module docstring)."""

    q: np.ndarray
    t_pair: np.ndarray
    t_wall: np.ndarray
    meta: dict = field(default_factory=dict)

    def copy(self):
        return ChainState(self.q.copy(), self.t_pair.copy(), self.t_wall.copy(), dict(self.meta))


def contacts(scene):
    """(K, 2) int: ring pairs (i, i+1 mod N), then wall contacts (i, -1)."""
    n = scene.n
    ring = np.column_stack([np.arange(n), (np.arange(n) + 1) % n])
    wall = np.column_stack([np.arange(n), -np.ones(n, dtype=int)])
    return np.vstack([ring, wall])


def initial_state(scene, wall_overlap=None):
    """Disks at x_i = (2i + 1) R (neighbours just touching), no history.

    They start pressed into the wall by ``wall_overlap`` (default: half the
    Hertz equilibrium ``(F_y/kn)^(2/3)``), in contact but not in equilibrium:
    a disk just touching the wall has no stiffness to start a relaxation from.
    """
    n = scene.n
    if wall_overlap is None:
        wall_overlap = 0.5 * (scene.fy / scene.kn) ** (2.0 / 3.0)
    q = np.zeros((n, 3))
    q[:, 0] = (2 * np.arange(n) + 1) * scene.radius
    q[:, 1] = scene.radius - wall_overlap
    return ChainState(q, np.zeros((n, 2)), np.zeros(n))


def mass_vector(scene):
    """Diagonal of the mass matrix in (x, y, theta) order, disk by disk."""
    return np.tile([scene.mass, scene.mass, scene.inertia], scene.n)


def scaled(scene, jac):
    """Charan's scaled Jacobian (SM Eq. 36): rows T~ = T/R, columns theta~ = R theta."""
    s = np.tile([1.0, 1.0, scene.radius], scene.n)
    return jac / s[:, None] / s[None, :]


@kernel_jit
def _ring_separation(q, i, period):
    """Neighbour j = i+1 mod N and r_i - r_j, the image shifted for the wrap."""
    j = (i + 1) % q.shape[0]
    dx = q[i, 0] - q[j, 0]
    if j == 0:
        dx -= period
    return j, dx, q[i, 1] - q[j, 1]


@kernel_jit
def _assemble(q, t_pair, t_wall, R, kn, kt, mu, fy, fx, period, forces, jac, want_jac):
    n = q.shape[0]
    for i in range(n):
        forces[i, 0] = 0.0
        forces[i, 1] = -fy
        forces[i, 2] = 0.0
    forces[0, 0] += fx
    if want_jac:
        jac[:, :] = 0.0
    f = np.empty(6)
    b = np.empty((6, 6))
    fw = np.empty(3)
    bw = np.empty((3, 3))
    for i in range(n):
        j, dx, dy = _ring_separation(q, i, period)
        charan_force_jacobian(dx, dy, R, R, kn, kt, mu, t_pair[i, 0], t_pair[i, 1], f, b)
        for a in range(3):
            forces[i, a] += f[a]
            forces[j, a] += f[3 + a]
        if want_jac:
            for a in range(3):
                for c in range(3):
                    jac[3 * i + a, 3 * i + c] += b[a, c]
                    jac[3 * i + a, 3 * j + c] += b[a, 3 + c]
                    jac[3 * j + a, 3 * i + c] += b[3 + a, c]
                    jac[3 * j + a, 3 * j + c] += b[3 + a, 3 + c]
    for i in range(n):
        charan_wall_force_jacobian(q[i, 1], R, kn, kt, mu, t_wall[i], fw, bw)
        for a in range(3):
            forces[i, a] += fw[a]
        if want_jac:
            for a in range(3):
                for c in range(3):
                    jac[3 * i + a, 3 * i + c] += bw[a, c]


def _call(scene, state, want_jac):
    n = scene.n
    f = np.empty((n, 3))
    jac = np.empty((3 * n, 3 * n)) if want_jac else np.empty((1, 1))
    _assemble(state.q, state.t_pair, state.t_wall, scene.radius, scene.kn, scene.kt, scene.mu,
              scene.fy, scene.fx, scene.period, f, jac, want_jac)
    return f, jac


def forces(scene, state):
    """Total generalized forces (N, 3) including F_y and F_x."""
    return _call(scene, state, False)[0]


def forces_and_jacobian(scene, state):
    """Forces (N, 3) and the 3N x 3N Jacobian dF/dq (unscaled, with history)."""
    return _call(scene, state, True)


@kernel_jit
def _advance(q, dq, t_pair, t_wall, R, kn, kt, mu, period):
    """t += A(q) dq by the increment rule, then rescale onto the Coulomb circle.

    The increment matrix A is taken at the configuration before the step; the
    Coulomb limit and contact loss at the configuration after it (q + dq),
    so that |t| <= t* holds for the state the step produces.
    """
    n = q.shape[0]
    a = np.empty((2, 6))
    for i in range(n):
        j, dx, dy = _ring_separation(q, i, period)
        charan_increment(dx, dy, R, R, a)
        for r in range(2):
            s = 0.0
            for c in range(3):
                s += a[r, c] * dq[i, c] + a[r, 3 + c] * dq[j, c]
            t_pair[i, r] += s
        nx = dx + dq[i, 0] - dq[j, 0]
        ny = dy + dq[i, 1] - dq[j, 1]
        naive = 2.0 * R - math.sqrt(nx * nx + ny * ny)
        delta = naive + overlap_correction(nx, ny, R, R, naive)
        tn = math.sqrt(t_pair[i, 0] ** 2 + t_pair[i, 1] ** 2)
        if delta <= 0.0:
            t_pair[i, 0] = 0.0  # contact lost: history forgotten
            t_pair[i, 1] = 0.0
        elif tn > mu * kn / kt * delta:
            scale = mu * kn / kt * delta / tn
            t_pair[i, 0] *= scale
            t_pair[i, 1] *= scale
    for i in range(n):
        t_wall[i] += dq[i, 0] + R * dq[i, 2]
        delta = R - (q[i, 1] + dq[i, 1])
        tstar = mu * kn / kt * delta
        if delta <= 0.0:
            t_wall[i] = 0.0
        elif abs(t_wall[i]) > tstar:
            t_wall[i] = math.copysign(tstar, t_wall[i])


def advance_history(scene, state, dq):
    """Advance the history in place for the displacement dq (N, 3) from state.q.

    The increment rule is evaluated at the configuration before the step
    (first order in |dq|); a history beyond t* is rescaled onto the Coulomb
    circle, and a lost contact forgets its history.  ``state.q`` is not moved.
    """
    _advance(state.q, np.ascontiguousarray(dq), state.t_pair, state.t_wall, scene.radius,
             scene.kn, scene.kt, scene.mu, scene.period)
