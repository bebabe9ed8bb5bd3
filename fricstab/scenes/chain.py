"""A chain of disks on a flat substrate (Charan et al.), built on the engine.

Scene: N disks of radius R on the substrate y = 0 (an analytic floor wall of
:class:`fricstab.engine.System`), periodic in x with period 2NR (neighbours
just touch), each pressed down by F_y, disk 0 pushed by F_x: both are the
System's applied generalized forces.  Contacts are only those the scene
needs: the ring pairs, listed as static pairs, and each disk with the wall.

Any pair law of the engine runs here with its wall form (``hertz``,
``charan``, ``ishima``, ``lee_hurley``; :data:`LAW_DEFAULTS`, in Charan's
units 2R = 1, m = 1).  The paper's law is ``charan`` (Eqs. 1, 2, 5).

Conventions
-----------
* ``state`` is an engine :class:`~fricstab.engine.State`; ``state.q`` (N, 3)
  holds the generalized coordinates x, y and the law's rotation coordinate:
  theta (radians, counter-clockwise; charan, lee_hurley, generalized force the
  torque T) or Ishima's l = R theta (generalized force T/R).  A frictionless
  law (hertz) has 2 dof per disk; its third column never moves.
* Ring pair c = (i, i+1) for i < N-1 is the static pair ``(i, i+1, 0, 0)``;
  the wrapping pair (N-1, 0) is canonicalized to ``(0, N-1, -1, 0)``: its
  separation is ``r_0 - r_{N-1} + 2NR`` (the image of disk N-1 one period to
  the left), so N = 2 has two distinct contacts.  Its history is the
  displacement of disk 0 relative to N-1, the opposite of the pre-engine
  convention (N-1 relative to 0), which :func:`pair_history` restores.
* Contacts are sorted by key (engine): (0, 1), (0, N-1), (0, wall), (1, 2),
  (1, wall), ...; :func:`legacy_order` maps them to the pre-engine order
  (ring pairs i = 0..N-1, then the wall contacts of disks 0..N-1).
* Generalized forces (N, 3).  The Jacobian is the dense ``dF/dq`` over the N
  dof-per-disk coordinates, disk by disk, with the history advanced by the
  increment rule (:func:`forces_and_jacobian`); Charan's scaled coordinates
  (theta~ = R theta, T~ = T/R, mass diag(m, m, I/R^2)) follow by
  :func:`scaled` (Ishima's l already is one).
"""

import functools
import math
from dataclasses import dataclass, replace

import numpy as np

from fricstab.engine import Material, System
from fricstab.engine.jacobian import jacobian
from fricstab.errors import check_instance, check_int, check_real, check_state
from fricstab.laws import PAIR_LAW_NAMES, ParameterError, get_law, vector_form

__all__ = ["CONVENTIONS", "CONVENTION_INERTIA", "ChainScene", "LAW_DEFAULTS", "LAW_DOCS",
           "LAW_UNITS", "LEE_HURLEY_E",
           "chain_system", "check_chain", "check_convention", "convention_scene",
           "eigenvalue_unit", "forces", "forces_and_jacobian", "initial_state", "law_defaults",
           "legacy_order", "mass_vector", "pair_history", "reference_stiffness", "refusal",
           "rest_overlap", "scaled", "time_unit", "wall_history", "wall_slots",
           "wall_stiffness"]

#: E* of ``lee_hurley`` in Charan's units (force/length; 2R = 1, F_y = 0.1): the
#: Hertz-cylinder wall force pi E* delta / lam(delta; R, Rw = R) (Lee & Hurley
#: Eqs. A2, A3) equals F_y = 0.1 at Hertz's overlap (F_y/kn)^(2/3) = 1.3572e-3
#: for kn = 2000, so that the chain rests at the paper's height under any law.
LEE_HURLEY_E = 215.975945884343

_KT = ("2 kn / 7", lambda v: 2.0 * v["kn"] / 7.0)

#: kn of ``linear`` (force/length): F_y/kn = (F_y/2000)^(2/3), Hertz's rest
#: overlap 1.3572e-3 at F_y = 0.1, so the chain rests at the paper's height.
LINEAR_KN = 0.1 / (0.1 / 2000.0) ** (2.0 / 3.0)

#: Default law parameters in Charan's units (a pair ``(doc, fn)`` is derived
#: from the other values: ``fn(values)``).
LAW_DEFAULTS = {
    "hertz": {"kn": 2000.0},
    "charan": {"kn": 2000.0, "kt": _KT, "mu": 10.0},
    "ishima": {"kn": 2000.0, "kt": _KT},
    "lee_hurley": {"E": LEE_HURLEY_E, "nu": 0.2, "mus": 10.0, "mur": 0.0,
                   "Rw": ("R (the disk radius)", lambda v: v["radius"])},
    "linear": {"kn": LINEAR_KN, "kt": _KT, "mu": 10.0},
}

LAW_DOCS = {
    "hertz": "frictionless Hertz (Charan Eq. 1), kn = 2000: F_x > 0 is refused (no equilibrium)",
    "charan": "the paper: Hertz + smoothed Coulomb Mindlin (Eqs. 1, 2, 5), kn = 2000, "
              "kt = 2 kn / 7, mu = 10",
    "ishima": "Hertz + Ishima's tangential spring (Ishima Eqs. 7-9), kn = 2000, kt = 2 kn / 7; "
              "no Coulomb cap",
    "lee_hurley": "Hertz cylinders with Lai's tangential and a type-C rolling spring, capped "
                  "(Lee & Hurley App. A): E* = 215.976 gives the wall overlap of kn = 2000 "
                  "under F_y = 0.1, mus = Charan's mu = 10, nu = 0.2 (Lee & Hurley's), "
                  "mur = 0 (no rolling resistance, as Charan's contacts; with mur > 0 the "
                  "ring pairs' rolling moments sit on caps that vanish with their normal "
                  "force and Newton alternates between the two signs of the cap), Rw = R",
    "linear": "linear spring-Coulomb (LAMMPS gran/hooke/history, no damping): kn = 73.68 "
              "gives the wall overlap of Hertz kn = 2000 under F_y = 0.1, kt = 2 kn / 7 "
              "(LAMMPS's default), mu = 10",
}

LAW_UNITS = {"kn": "force/length^(3/2)", "kt": "force/length^(3/2)", "mu": "-",
             "E": "force/length", "nu": "-", "mus": "-", "mur": "-", "Rw": "length",
             "linear.kn": "force/length", "linear.kt": "force/length"}

#: Wall skin: every disk less than a period above the floor keeps its wall
#: contact listed, so the contact list of a chain never changes in a run.
SKIN_PERIODS = 1.0


def law_defaults(law, values):
    """The law's parameters (pair, wall) with defaults for those ``values`` lacks."""
    if law not in PAIR_LAW_NAMES:
        raise ParameterError(f"unknown law {law!r}; known laws: {', '.join(PAIR_LAW_NAMES)}")
    info = get_law(law)
    pair = tuple(info.params)
    wall = tuple(info.wall_form().params[len(pair):])
    vals = dict(values)
    out = {}
    for key in pair + wall:
        if vals.get(key) is None:
            d = LAW_DEFAULTS[vector_form(law)][key]
            vals[key] = float(d[1](vals) if isinstance(d, tuple) else d)
        out[key] = vals[key]
    return {k: out[k] for k in pair}, {k: out[k] for k in wall}


def refusal(law, values):
    """Why ``law`` with ``values`` (scene keys and law parameters) cannot make sense, or None.

    A frictionless law under F_x != 0 has no equilibrium (nothing resists
    sliding); ``lee_hurley`` cannot carry F_y beyond its largest wall force
    pi E* 4 (R + Rw)/e^2 (the turning point of the Hertz-cylinder width).
    """
    fx = values.get("fx") or 0.0
    if get_law(law).n_hist == 0 and fx != 0.0:
        return (f"frictionless: F_x = {fx:g} on disk 0 has no equilibrium (nothing resists "
                "sliding); use a law with friction (charan, ishima, lee_hurley)")
    if law == "lee_hurley":
        r, rw, e = values["radius"], values["Rw"], values["E"]
        fmax = math.pi * e * 4.0 * (r + rw) / math.e ** 2
        if not values["fy"] < 0.99 * fmax:
            return (f"F_y = {values['fy']:g} exceeds the Hertz-cylinder wall's largest force "
                    f"(0.99 pi E* 4 (R + Rw)/e^2 = {0.99 * fmax:.4g})")
    return None


@dataclass(frozen=True)
class ChainScene:
    """Charan's chain of disks on a flat substrate: the scene's parameters.

    N disks of radius R on the substrate ``y = 0``, periodic in x with period
    2NR, each pressed down by F_y, disk 0 (the paper's disk 1) pushed by F_x.
    Units are Charan's numbers: 2R = 1, m = 1, k_n = 2000, F_y = 0.1, forces
    in the unit of F_y; the simulation time unit is that of these numbers,
    Charan's is ``sqrt(m 2R / k_n)`` (:func:`time_unit`).  Frozen; use
    :meth:`with_fx` for another F_x.

    Parameters
    ----------
    n : int
        Number of disks (>= 2; paper: 10).
    radius : float
        Disk radius R (length; 0.5, so 2R = 1).
    mass : float
        Disk mass m (1).
    fy : float
        Normal load on every disk (force; paper: 0.1).
    fx : float
        Tangential force on disk 0 (force).
    inertia : float, optional
        Moment of inertia (mass length^2); default ``m R^2 / 2``, a uniform disk.
        The paper's supplementary material states ``I = m R^2`` for its Jacobian
        (:data:`CONVENTIONS`); its LAMMPS dynamics default to ``2/5 m R^2``.
    law : str
        Pair law (:data:`PAIR_LAW_NAMES`; the paper's ``charan``, Eqs. 1, 2, 5),
        with its wall form at the substrate.
    params : dict, optional
        The pair law's parameters (``fricstab laws``); missing ones take
        :data:`LAW_DEFAULTS` (``charan``: kn = 2000, kt = 2 kn/7, mu = 10).
    wall_params : dict, optional
        The wall form's extra parameters (``Rw`` of ``lee_hurley``).

    Raises
    ------
    ParameterError
        A value out of range, a parameter the law does not take, or a
        combination without equilibrium (a frictionless chain under F_x > 0).
    """

    n: int = 10
    radius: float = 0.5
    mass: float = 1.0
    fy: float = 0.1
    fx: float = 0.0
    inertia: float = None
    law: str = "charan"
    params: dict = None
    wall_params: dict = None

    def __post_init__(self):
        check_int("n", self.n, 2)
        for key in ("radius", "mass", "fy", "fx", "inertia"):   # numpy scalars are numbers
            v = getattr(self, key)
            if isinstance(v, (np.integer, np.floating)):
                object.__setattr__(self, key, float(v))
        for key in ("radius", "mass"):
            check_real(key, getattr(self, key), 0.0, low_open=True)
        if self.inertia is None:
            try:
                object.__setattr__(self, "inertia", self.mass * self.radius ** 2 / 2.0)
            except OverflowError:
                raise ParameterError(f"inertia m R^2 / 2 overflows for mass = {self.mass!r}, "
                                     f"radius = {self.radius!r}; give inertia") from None
        for key in ("fy", "inertia"):
            check_real(key, getattr(self, key), 0.0, low_open=True)
        check_real("fx", self.fx)
        check_instance("law", self.law, str, "a law name (str)")
        for key in ("params", "wall_params"):
            if getattr(self, key) is not None:
                check_instance(key, getattr(self, key), dict, "a dict of law parameters or None")
        given = {**(self.params or {}), **(self.wall_params or {})}
        info = get_law(self.law) if self.law in PAIR_LAW_NAMES else None
        if info is None:
            raise ParameterError(f"unknown law {self.law!r}; known laws: "
                                 f"{', '.join(PAIR_LAW_NAMES)}")
        known = tuple(info.wall_form().params)
        unknown = [k for k in given if k not in known]
        if unknown:
            raise ParameterError(f"law {self.law}: unknown parameter {unknown[0]!r} "
                                 f"(takes {', '.join(known)})")
        pair, wall = law_defaults(self.law, {"radius": self.radius, **given})
        object.__setattr__(self, "params", pair)
        object.__setattr__(self, "wall_params", wall)
        Material(self.law, pair, wall)  # checks every value, naming a bad one
        why = refusal(self.law, {"fx": self.fx, "fy": self.fy, "radius": self.radius,
                                 **pair, **wall})
        if why:
            raise ParameterError(f"law {self.law}: {why}")

    @property
    def period(self):
        return 2.0 * self.n * self.radius

    @property
    def dof(self):
        """Degrees of freedom per disk (2 for a frictionless law, else 3)."""
        return get_law(self.law).n_dof

    @property
    def kn(self):
        """Reference normal stiffness: the law's kn, or (lee_hurley) :func:`reference_stiffness`."""
        return reference_stiffness(self)

    def with_fx(self, fx):
        return replace(self, fx=float(fx))

    def key(self):
        """The parameters that fix the System apart from F_x (hashable)."""
        return (int(self.n), float(self.radius), float(self.mass), float(self.fy),
                float(self.inertia), self.law, tuple(sorted(self.params.items())),
                tuple(sorted(self.wall_params.items())))


def check_chain(scene, state=..., name="state"):
    """The front door's checks of a chain protocol: a ChainScene and a finite (N, 3) State.

    Raises :class:`ParameterError` naming the argument; returns nothing.
    """
    from fricstab.engine import State
    check_instance("scene", scene, ChainScene, "a ChainScene")
    if state is not ...:
        check_state(name, state, State, scene.n)


@functools.lru_cache(maxsize=64)
def _base_system(key):
    n, radius, mass, fy, inertia, law, params, wall = key
    static = [(i, i + 1, 0, 0) for i in range(n - 1)] + [(0, n - 1, -1, 0)]
    ext = np.zeros((n, 3))
    ext[:, 1] = -fy
    period = 2.0 * n * radius
    return System(Material(law, dict(params), dict(wall)), np.full(n, radius),
                  np.full(n, mass), np.full(n, inertia), lx=period, walls=[(0.0, 1.0)],
                  static=np.array(static), neighbours=False, skin=SKIN_PERIODS * period,
                  external=ext)


def chain_system(scene):
    """The engine :class:`System` of ``scene`` (F_y on every disk, F_x on disk 0)."""
    base = _base_system(scene.key())
    if scene.fx == 0.0:
        return base
    ext = base.external.copy()
    ext[0, 0] += scene.fx
    return base.with_external(ext)


@functools.lru_cache(maxsize=64)
def _rest_overlap(key):
    n, radius, mass, fy, inertia, law, params, wall = key
    p = dict(params)
    if vector_form(law) == "linear":
        return fy / p["kn"]
    if law != "lee_hurley":
        return (fy / p["kn"]) ** (2.0 / 3.0)
    from scipy.optimize import brentq

    from fricstab._numerics import cylinder_lambda
    rw = dict(wall)["Rw"]
    turn = 4.0 * (radius + rw) / math.e ** 2
    force = lambda d: math.pi * p["E"] * d / cylinder_lambda(d, radius, rw) - fy  # noqa: E731
    return brentq(force, 1e-300, turn * (1 - 1e-12), xtol=1e-300, rtol=4 * np.finfo(float).eps)


def rest_overlap(scene):
    """Wall overlap delta_w of a disk under F_y alone (length).

    Hertz normal force (hertz, charan, ishima): ``(F_y/kn)^(2/3)``; ``linear``:
    ``F_y/kn``; ``lee_hurley``: the root of ``pi E* delta / lam(delta) = F_y`` (Eq. A2).
    """
    return _rest_overlap(scene.key())


def reference_stiffness(scene):
    """kn of the law, or for ``lee_hurley``, ``linear`` the Hertz kn with the same rest overlap.

    Sets Charan's time unit sqrt(m 2R / kn) and the scales of the protocols
    (``linear``'s kn is a force/length, not a Hertz stiffness).
    """
    if "kn" in scene.params and vector_form(scene.law) != "linear":
        return scene.params["kn"]
    return scene.fy / rest_overlap(scene) ** 1.5


def wall_stiffness(scene):
    """dF_n/d delta of the wall contact at the rest overlap (force/length).

    Hertz: ``1.5 kn (F_y/kn)^(1/3)``; Hertz cylinders: ``pi E* / (lam - 1)``;
    linear: ``kn``.
    """
    if vector_form(scene.law) == "linear":
        return scene.params["kn"]
    if scene.law != "lee_hurley":
        kn = scene.params["kn"]
        return 1.5 * kn * (scene.fy / kn) ** (1 / 3)
    from fricstab._numerics import cylinder_lambda
    lam = cylinder_lambda(rest_overlap(scene), scene.radius, scene.wall_params["Rw"])
    return math.pi * scene.params["E"] / (lam - 1.0)


def time_unit(scene):
    """Charan's time unit ``sqrt(m 2R / kn)`` in simulation units (kn: reference)."""
    return math.sqrt(scene.mass * 2 * scene.radius / reference_stiffness(scene))


def initial_state(scene, wall_overlap=None):
    """Disks at x_i = (2i + 1) R (neighbours just touching), no history.

    They start pressed into the wall by ``wall_overlap`` (default: half the
    rest overlap :func:`rest_overlap`), in contact but not in equilibrium: a
    disk just touching the wall has no stiffness to start a relaxation from.
    """
    n = scene.n
    if wall_overlap is None:
        wall_overlap = 0.5 * rest_overlap(scene)
    pos = np.zeros((n, 2))
    pos[:, 0] = (2 * np.arange(n) + 1) * scene.radius
    pos[:, 1] = scene.radius - wall_overlap
    return chain_system(scene).state(pos)


#: The mass matrices under which the chain's spectrum can be taken.  Charan et al. print
#: eigenvalues "of J" without saying which matrix; each reading is an option of
#: ``fricstab chain ramp|jacobian`` (``--convention``) and of the analyses
#: (:func:`mass_vector`).  The statics (equilibria, histories) never depend on it.
CONVENTIONS = {
    "physical": "M^-1 J with the scene's moment of inertia (default I = m R^2 / 2, a "
                "uniform disk); eigenvalues in 1/time^2",
    "lammps": "M^-1 J with I = 2/5 m R^2, the default of LAMMPS' fix nve/sphere (a "
              "sphere's inertia; the paper ran LAMMPS); eigenvalues in 1/time^2",
    "sm": "M^-1 J with I = m R^2: the supplementary material's I_i = I_0 m_i R^2 with "
          "m_i = I_0 = 1 (around its Eqs. 36-37); the same spectrum as its scaled J~ "
          "for m = 1; eigenvalues in 1/time^2",
    "bare": "J itself, no mass matrix (eigenvalues in force/length); for m = 1 the same "
            "spectrum as M^-1 J with I = 1 = m (2R)^2 in Charan's units",
}

#: I / (m R^2) of each convention that fixes the inertia (``physical``: the scene's own).
CONVENTION_INERTIA = {"lammps": 0.4, "sm": 1.0}


def check_convention(convention):
    """The convention's name, or ParameterError naming the known ones."""
    if not isinstance(convention, str) or convention not in CONVENTIONS:
        raise ParameterError(f"unknown spectrum convention {convention!r}; known: "
                             f"{', '.join(CONVENTIONS)}")
    return convention


def convention_scene(scene, convention):
    """The scene whose physical M^-1 J is ``convention``'s matrix (``bare``: I = m (2R)^2 at m = 1).

    For dynamics under the same reading (``fricstab chain dynamics --inertia``):
    ``physical`` the scene itself, ``lammps`` I = 2/5 m R^2, ``sm`` I = m R^2; for
    ``bare`` the scene with I = m (2R)^2, whose M^-1 J is J itself where m = 1 and
    2R = 1 (Charan's units); elsewhere the two spectra differ by those factors.
    """
    check_convention(convention)
    if convention == "physical":
        return scene
    if convention == "bare":
        return replace(scene, inertia=scene.mass * (2 * scene.radius) ** 2)
    return replace(scene, inertia=CONVENTION_INERTIA[convention] * scene.mass * scene.radius ** 2)


def mass_vector(scene, convention="physical"):
    """Generalized masses of the Jacobian's dof under a spectrum convention.

    ``physical`` (default): (m, m, I/s^2) per disk with the scene's inertia
    (s = 1 for theta, R for Ishima's l = R theta); ``lammps`` and ``sm`` the
    same with I = 2/5 m R^2 and m R^2; ``bare``: ones (the eigenvalues of J
    itself).  :data:`CONVENTIONS` says what each reading is.
    """
    check_convention(convention)
    system = chain_system(scene if convention in ("physical", "bare")
                          else convention_scene(scene, convention))
    mass = system.gmass[:, :system.dof].ravel().copy()
    return np.ones_like(mass) if convention == "bare" else mass


def eigenvalue_unit(scene, convention="physical"):
    """The factor that puts an eigenvalue of ``convention`` in Charan's units.

    ``t0^2`` (t0 = :func:`time_unit`) for the M^-1 J readings; ``t0^2 / m``
    for ``bare`` (force/length over mass: the same number as M^-1 J at m = 1).
    """
    check_convention(convention)
    unit = time_unit(scene) ** 2
    return unit / scene.mass if convention == "bare" else unit


def scaled(scene, jac):
    """Charan's scaled Jacobian (SM Eq. 36): rows T~ = T/R, columns theta~ = R theta.

    For a law in theta; Ishima's ``l = R theta`` already is the scaled
    coordinate and a frictionless law has none: ``jac`` is returned as is.
    """
    if get_law(scene.law).rotation != "theta":
        return jac
    s = np.tile([1.0, 1.0, scene.radius], scene.n)
    return jac / s[:, None] / s[None, :]


def forces(scene, state):
    """Total generalized forces (N, 3) including F_y and F_x."""
    return chain_system(scene).forces(state)


def forces_and_jacobian(scene, state):
    """Forces (N, 3) and the dense Jacobian dF/dq (N dof square, with history)."""
    system = chain_system(scene)
    _, k = jacobian(system, state)
    return system.forces(state), k.toarray()


def legacy_order(state):
    """Rows of ``state.contacts`` in the pre-engine order, and the sign of each history.

    Returns ``(rows, sign)`` of length 2N: ring pairs (i, i+1 mod N) for
    i = 0..N-1, then the wall contacts of disks 0..N-1; ``sign`` is -1 for
    the wrapping pair, stored as (0, N-1) with the opposite orientation.
    """
    c = state.contacts
    n = len(state.q)
    pair = c.j >= 0
    slot = np.where(pair, np.where(c.m == -1, n - 1, c.i), n + c.i)
    rows = np.empty(2 * n, np.int64)
    rows[slot] = np.arange(c.n)
    sign = np.ones(2 * n)
    sign[n - 1] = -1.0
    return rows, sign


def pair_history(scene, state):
    """(N, H) history of ring pair (i, i+1 mod N), i relative to i+1 (pre-engine orientation).

    The sign flip of the wrapping pair applies to lab-frame displacement
    histories (charan, ishima, linear); ``lee_hurley``'s (ft, mr) are returned as stored.
    """
    rows, sign = legacy_order(state)
    h = state.contacts.hist[rows[:scene.n]]
    if scene.law in ("charan", "ishima", "linear"):
        h = h * sign[:scene.n, None]
    return h


def wall_slots(scene):
    """Number of history slots of the law's wall form (the engine stores the pair form's)."""
    return get_law(scene.law).wall_form().n_hist


def wall_history(scene, state):
    """(N, H) wall-contact history of disks 0..N-1 (charan: t along x; lee_hurley: ft, mr)."""
    rows, _ = legacy_order(state)
    return state.contacts.hist[rows[scene.n:], :wall_slots(scene)]
