"""A system: particles, space, contact sources and one contact law; and its state.

:class:`System` holds what does not change during a run (radii, masses,
families, the box, walls, the law and its parameters, applied forces,
dashpots); :class:`State` holds what does (coordinates, velocities, the
Lees-Edwards offset, the contacts with their histories).  Scenes build a
System; protocols move a State with the engine's passes, integrators and
relaxers.

Coordinates
-----------
``q`` (N, 3) are generalized coordinates ``(x, y, r)`` with ``r = s theta``:
``s = 1`` for a law in ``theta`` (charan, lee_hurley: generalized force the
torque T), ``s = R`` for Ishima's ``l = R theta`` (generalized force T/R).
The generalized masses are ``(m, m, I/s^2)``.  A frictionless law has 2 dof
per particle (x, y); its ``r`` column is carried but never moves.

Families: 0 free (moves under forces, carries dof in the Jacobian), 1 fixed
(never moves), 2 driven (moved as one body by a controller, clamped in the
Jacobian).

Space: ``lx > 0`` periodic in x with that period, ``ly > 0`` periodic in y
with the Lees-Edwards offset ``state.shift`` of the image above; 0 is open.
"""

import copy
from dataclasses import dataclass, field

import numpy as np

from fricstab.engine import contacts as cts
from fricstab.engine import passes
from fricstab.errors import NumericalError, ParameterError
from fricstab.generated.dispatch import N_HIST, N_HIST_WALL, N_PARAMS_WALL, PAIR_LAWS
from fricstab.laws import check_parameters, get_law

__all__ = ["FREE", "FIXED", "DRIVEN", "Material", "State", "System", "check_system_state"]

FREE, FIXED, DRIVEN = 0, 1, 2


@dataclass(frozen=True)
class Material:
    """A pair law with its parameter values (and those of its wall form).

    Checked on construction: an unknown law, a missing or a bad parameter is a
    :class:`ParameterError` naming it.

    Parameters
    ----------
    law : str
        A pair law (:data:`PAIR_LAW_NAMES`); its wall form serves the walls.
    params : dict
        The law's parameters by name (``fricstab laws`` lists them with their
        units: ``kn``, ``kt`` in force/length^(3/2) and ``mu`` for ``charan``,
        Charan Eqs. 1, 5; ``kn``, ``kt`` for ``ishima``, Ishima Eqs. 7-9;
        ``E`` (pressure), ``nu``, ``mus``, ``mur`` for ``lee_hurley``, Lee &
        Hurley App. A), in the scene's units.
    wall_params : dict, optional
        The wall form's extra parameters (``Rw`` of ``lee_hurley_wall``, length).
    """

    law: str
    params: dict
    wall_params: dict = field(default_factory=dict)

    def __post_init__(self):
        for key in ("params", "wall_params"):
            if not isinstance(getattr(self, key), dict):
                raise ParameterError(f"{key} must be a dict of law parameters, got "
                                     f"{type(getattr(self, key)).__name__}")
        if self.law not in PAIR_LAWS:
            raise ParameterError(f"unknown law {self.law!r}; known laws: {', '.join(PAIR_LAWS)}")
        info = get_law(self.law)
        names = tuple(info.params)
        wall_names = tuple(info.wall_form().params[len(names):])
        unknown_w = [k for k in self.wall_params if k not in wall_names]
        if unknown_w:
            raise ParameterError(f"law {self.law}: unknown wall parameter {unknown_w[0]!r} "
                                 f"(the wall form takes {', '.join(wall_names) or 'none'})")
        missing = [k for k in names if k not in self.params]
        unknown = [k for k in self.params if k not in names]
        if missing:
            raise ParameterError(f"law {self.law}: missing parameter {missing[0]!r} "
                                 f"(needs {', '.join(names)})")
        if unknown:
            raise ParameterError(f"law {self.law}: unknown parameter {unknown[0]!r} "
                                 f"(takes {', '.join(names)})")
        check_parameters(**self.params, **self.wall_params)

    @property
    def id(self):
        return PAIR_LAWS.index(self.law)

    @property
    def info(self):
        return get_law(self.law)

    @property
    def dof(self):
        return self.info.n_dof

    @property
    def rotation(self):
        """The law's rotational coordinate: 'theta', 'l' (= R theta) or '' (none)."""
        return self.info.rotation

    @property
    def n_hist(self):
        return max(N_HIST[self.id], N_HIST_WALL[self.id])

    def vector(self):
        return np.array([float(self.params[k]) for k in self.info.params])

    def wall_vector(self):
        """Parameters of the wall form, in its order (the pair law's, then its own)."""
        info = self.info
        extra = info.wall_form().params[len(info.params):]
        missing = [k for k in extra if k not in self.wall_params]
        if missing:
            raise ParameterError(f"law {self.law}: the wall form needs {missing[0]!r} "
                                 f"({info.wall_form().param_docs[len(info.params)]})")
        return np.concatenate([self.vector(), [float(self.wall_params[k]) for k in extra]])


@dataclass
class State:
    """Coordinates, velocities, Lees-Edwards offset and contacts of a system.

    Build one with :meth:`System.state`; protocols copy it (:meth:`copy`)
    rather than modify a caller's state unless they say so.

    Parameters
    ----------
    q : ndarray, shape (N, 3)
        Generalized coordinates: x, y (length; never folded into the box, so a
        contact keeps its key across rebuilds) and the law's rotation
        coordinate (theta in radians, or Ishima's ``l = R theta``, length).
    v : ndarray, shape (N, 3)
        Generalized velocities (length/time, and rad/time or length/time).
    shift : float
        Lees-Edwards offset of the periodic images in x (length).
    contacts : Contacts
        The contacts ``(i, j, m, k)`` with their histories (the tangential
        displacement ``t``, Charan Eq. 2; Ishima's ``xi_T``; Lee & Hurley's
        ``ft``, ``mr``) and cap flags; a wall contact has ``j = -1 - w``.
    keys : ndarray of int64
        Sorted contact keys: forces are summed in an order that depends on the
        contact set only.
    ref : ndarray, shape (N, 2)
        Positions at the last neighbour-list build.
    ref_shift : float
        Lees-Edwards offset at the last build.
    time : float
        Simulated time (time units of the scene).
    rebuilds : int
        Neighbour-list rebuilds so far.
    """

    q: np.ndarray
    v: np.ndarray
    shift: float
    contacts: cts.Contacts
    keys: np.ndarray
    ref: np.ndarray          # q[:, :2] at the last contact build
    ref_shift: float         # shift at the last contact build
    time: float = 0.0
    rebuilds: int = 0

    def copy(self):
        return State(self.q.copy(), self.v.copy(), float(self.shift), self.contacts.copy(),
                     self.keys.copy(), self.ref.copy(), float(self.ref_shift), self.time,
                     self.rebuilds)

    def arrays(self):
        """Every array needed to continue bit-identically (for checkpoints)."""
        d = {"q": self.q, "v": self.v, "keys": self.keys, "ref": self.ref,
             "scalars": np.array([self.shift, self.ref_shift, self.time, self.rebuilds])}
        d.update(self.contacts.arrays())
        return d

    @classmethod
    def from_arrays(cls, d):
        s = np.asarray(d["scalars"], float)
        return cls(np.array(d["q"], float), np.array(d["v"], float), float(s[0]),
                   cts.Contacts.from_arrays(d), np.array(d["keys"], np.int64),
                   np.array(d["ref"], float), float(s[1]), float(s[2]), int(s[3]))


def scratch():
    """Scratch arrays ``(work (8, 6), jwork (6, 6))`` for the passes (which allocate nothing)."""
    return np.zeros((8, 6)), np.zeros((6, 6))


def _array(name, value, shape, dtype=float):
    a = np.ascontiguousarray(np.broadcast_to(np.asarray(value, dtype=dtype), shape),
                             dtype=dtype).copy()
    return a


@dataclass
class System:
    """What stays fixed during a run: particles, box, walls, law, applied forces, dashpots.

    Units are the scene's (any consistent set).  Generalized coordinates are
    ``q`` (N, 3): x, y and the law's rotation coordinate, theta (generalized
    force the torque T) or Ishima's ``l = R theta`` (force T/R, Ishima Eq. 7);
    a frictionless law has 2 dof per particle.  :meth:`state` builds a
    :class:`State` from positions; :meth:`forces` evaluates the generalized
    forces (and the per-contact blocks ``K = dF/dq``).

    Parameters
    ----------
    material : Material
        The pair law and its parameters (its wall form at the walls).
    radius, mass, inertia : array_like, shape (N,)
        Radii (length), masses (mass) and moments of inertia (mass length^2).
    family : array_like of int, shape (N,), optional
        0 free (default), 1 fixed, 2 driven.
    lx, ly : float
        Periods in x and y (length; 0: an open direction).
    walls : sequence of (y0, direction)
        Analytic walls ``y = y0``; direction +1 a floor, -1 a ceiling.
    static : array_like, shape (S, 4), optional
        Pairs ``(i, j, m, k)`` always listed (``i < j``; ``m``, ``k`` the
        periodic image of j: ``r_j + m (lx, 0) + k (shift, ly)``).
    neighbours : bool
        Whether a neighbour list finds pairs (False: only static pairs and walls).
    skin : float
        Neighbour-list skin (length).
    external : array_like, shape (N, 3), optional
        Applied generalized forces (force; the chain's F_x and F_y).
    damping : (alpha_n, alpha_t, eta_r)
        Contact dashpot ratios (Lee & Hurley Eqs. A4, A12, A20; dimensionless);
        0 is none.
    damping_mass, damping_inertia : array_like, shape (N,), optional
        Masses and inertias in the dashpots (default: own; a fixed particle inf).
    """

    material: Material
    radius: np.ndarray
    mass: np.ndarray
    inertia: np.ndarray
    family: np.ndarray = None
    lx: float = 0.0
    ly: float = 0.0
    walls: tuple = ()
    static: np.ndarray = None
    neighbours: bool = True
    skin: float = 0.0
    external: np.ndarray = None
    damping: tuple = (0.0, 0.0, 0.0)
    damping_mass: np.ndarray = None
    damping_inertia: np.ndarray = None

    def __post_init__(self):
        n = len(np.atleast_1d(self.radius))
        self.radius = _array("radius", self.radius, (n,))
        self.mass = _array("mass", self.mass, (n,))
        self.inertia = _array("inertia", self.inertia, (n,))
        self.family = _array("family", FREE if self.family is None else self.family, (n,),
                             np.int8)
        for name in ("radius", "mass", "inertia"):
            a = getattr(self, name)
            if not (np.all(np.isfinite(a)) and np.all(a > 0)):
                raise ParameterError(f"{name} must be finite and > 0 for every particle")
        if not (np.isfinite(self.skin) and self.skin >= 0):
            raise ParameterError(f"skin must be a finite number >= 0, got {self.skin!r}")
        for name in ("lx", "ly"):
            v = getattr(self, name)
            if not (np.isfinite(v) and v >= 0):
                raise ParameterError(f"{name} must be a finite number >= 0 (0: open), got {v!r}")
        self.walls = np.asarray(self.walls, float).reshape(-1, 2)
        if np.any(np.abs(self.walls[:, 1]) != 1.0):
            raise ParameterError("a wall's direction must be +1 (floor) or -1 (ceiling)")
        if self.static is not None:
            self.static = np.asarray(self.static, np.int64).reshape(-1, 4)
        self.external = _array("external", 0.0 if self.external is None else self.external,
                               (n, 3))
        fixed = self.family == FIXED
        self.damping = np.asarray(self.damping, float).reshape(3)
        self.damping_mass = np.where(fixed, np.inf, self.mass if self.damping_mass is None
                                     else _array("damping_mass", self.damping_mass, (n,)))
        self.damping_inertia = np.where(
            fixed, np.inf, self.inertia if self.damping_inertia is None
            else _array("damping_inertia", self.damping_inertia, (n,)))
        self.rscale = self.radius.copy() if self.material.rotation == "l" else np.ones(n)
        self.gmass = np.column_stack([self.mass, self.mass, self.inertia / self.rscale ** 2])
        self.ginv = 1.0 / self.gmass
        self._p = self.material.vector()
        self._pw = (self.material.wall_vector() if len(self.walls) else
                    np.zeros(N_PARAMS_WALL[self.material.id]))

    # ---------------------------------------------------------------- basics
    @property
    def n(self):
        return len(self.radius)

    @property
    def dof(self):
        return self.material.dof

    @property
    def law_id(self):
        return self.material.id

    @property
    def free(self):
        return self.family == FREE

    def with_external(self, external):
        """The same system with other applied generalized forces (N, 3)."""
        new = copy.copy(self)
        new.external = _array("external", external, (self.n, 3))
        return new

    # ---------------------------------------------------------------- states
    def state(self, pos, theta=None, vel=None, omega=None, shift=0.0):
        """A state at physical positions (N, 2), angles and velocities (zero if omitted)."""
        n = self.n
        pos = np.asarray(pos, float)
        if pos.shape != (n, 2) or not np.all(np.isfinite(pos)):
            raise ParameterError(f"pos must be a finite array of shape ({n}, 2)")
        q = np.zeros((n, 3))
        q[:, :2] = pos
        v = np.zeros((n, 3))
        if theta is not None:
            q[:, 2] = self.rscale * np.asarray(theta, float)
        if vel is not None:
            v[:, :2] = vel
        if omega is not None:
            v[:, 2] = self.rscale * np.asarray(omega, float)
        st = State(q, v, float(shift), cts.Contacts.empty(self.material.n_hist),
                   np.zeros(0, np.int64), pos.copy(), float(shift))
        self.rebuild(st)
        st.rebuilds = 0
        return st

    def positions(self, state):
        """Physical positions (N, 2) and angles (N,) of a state."""
        return state.q[:, :2].copy(), state.q[:, 2] / self.rscale

    def rebuild(self, state):
        """Rebuild the contact list now; histories carried by contact key."""
        rows, keys = cts.build(state.q, self.radius, self.free, self.lx, self.ly, state.shift,
                               self.skin, self.walls, self.static, self.neighbours)
        state.contacts = cts.carry(state.contacts, state.keys, rows, keys, self.material.n_hist)
        state.keys = keys
        state.ref = state.q[:, :2].copy()
        state.ref_shift = state.shift
        state.rebuilds += 1

    def needs_rebuild(self, state):
        """Whether a particle may have moved into reach since the last build."""
        if not self.neighbours and not len(self.walls):
            return False
        d = state.q[:, :2] - state.ref
        far = np.sqrt(np.max(np.sum(d * d, axis=1))) if self.n else 0.0
        return 2.0 * far + abs(state.shift - state.ref_shift) > self.skin

    # ---------------------------------------------------------------- forces
    def _args(self, state):
        c = state.contacts
        return (self.law_id, self._p, self._pw, self.walls, state.q, self.radius,
                float(self.lx), float(self.ly), float(state.shift), c.i, c.j, c.m, c.k)

    def forces(self, state, want_blocks=False):
        """Generalized forces (N, 3) (applied forces included); and blocks if asked."""
        c = state.contacts
        f = np.empty((self.n, 3))
        nd = 2 * self.dof
        blocks = np.zeros((c.n if want_blocks else 0, nd, nd))
        passes.eval_pass(*self._args(state), c.hist, self.external, f, blocks, want_blocks,
                         self.dof, *scratch())
        return (f, blocks) if want_blocks else f

    def contact_forces(self, state):
        """Per-contact generalized forces (K, 2 dof): on i, then on j (a wall: on i only)."""
        c = state.contacts
        out = np.zeros((c.n, 2 * self.dof))
        passes.contact_pass(*self._args(state), c.hist, out, self.dof, *scratch())
        return out

    def project(self, state):
        """Histories onto their admissible sets at the current configuration."""
        c = state.contacts
        passes.project_pass(*self._args(state), c.hist, c.flag)

    def advance_history(self, state, dq):
        """A quasistatic step: ``h += A(q) dq``, ``q += dq``, projection at the new ``q``.

        ``dq`` (N, dof) or (N, 3), generalized; rebuilds the contacts if needed.
        """
        dq3 = np.zeros((self.n, 3))
        dq = np.asarray(dq, float).reshape(self.n, -1)
        dq3[:, :dq.shape[1]] = dq
        c = state.contacts
        passes.increment_pass(*self._args(state), c.hist, dq3, self.dof, scratch()[1])
        state.q += dq3
        if self.needs_rebuild(state):
            self.rebuild(state)
        self.project(state)

    def check_forces(self, f, what="force", step=None):
        """NumericalError naming the particle and component of a non-finite force."""
        bad = ~np.isfinite(f[:, :self.dof])
        if bad.any():
            i, a = np.argwhere(bad)[0]
            comp = ("F_x", "F_y", "generalized torque")[a]
            at = f" at step {step}" if step is not None else ""
            raise NumericalError(f"non-finite {what} {comp} on particle {i}{at}", step=step,
                                 item=int(i), quantity=comp)


def check_system_state(system, state):
    """Check an engine System and a finite State of its particles (ParameterError)."""
    from fricstab.errors import check_instance, check_state
    check_instance("system", system, System, "a System")
    return check_state("state", state, State, system.n)
