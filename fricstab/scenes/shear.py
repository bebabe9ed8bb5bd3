"""The plane-shear cell of Lee & Hurley (Sec. 2) on the engine: scene, units, placement, system.

A 2D cell periodic in x (box length ``lx``) between two rows of disks: the
bottom row is fixed (engine family 1), the top row moves as one rigid body
(family 2) at the constant horizontal velocity V while a velocity servo holds
the normal force N on it (LIGGGHTS-style: v_y = -g (N_target - N)).  Bulk
disks (family 0): radius uniform in [r_min, r_max], no gravity.  Any verified
contact law (:data:`LAWS`, default ``lee_hurley``) with the contact dashpots
of Lee & Hurley App. A (A4, A12, A20-A22) in the engine; the run itself is
:mod:`fricstab.protocols.shear_run`.

Units
-----
Scene values and every output (frames, series, JSON) are SI, per unit
thickness (forces N/m, torques N m/m, masses kg/m).  Inside, reduced units:
length L0 = mean radius (r_min + r_max)/2, pressure E* = ``modulus`` (the
contact modulus of Eq. A3, E* = E / (2 (1 - nu^2)) for Young's modulus E and
Poisson ratio nu), mass per thickness rho L0^2, time T0 = L0 sqrt(rho / E*).

Scene keys and law parameters
-----------------------------
``modulus`` (E*, Pa) is the cell's reference stiffness, whatever the law: it
sets the pressure unit, the normal force (kappa) and the time step.  The law
and its parameters are the keys of :class:`fricstab.io.scenes.LawChoice`, in
SI, named as ``fricstab laws`` names them; for ``lee_hurley`` these are the
contact modulus ``E`` (Pa; default: ``modulus``), ``nu`` (Lai's k_t),
``mus`` and ``mur`` (they replace the scene keys ``E`` = Young's modulus,
``nu``, ``mu_s`` and ``mu_r`` of the loop before the engine; the paper's
E = 1 GPa, nu = 0.2 give E* = 0.5208 GPa).  The other laws' defaults (:data:`LAWS`)
have the normal force of ``lee_hurley`` at the cell's typical overlap
delta_0, the overlap at which ``lee_hurley`` carries the typical contact force
f_0 = P d (2D: the mean normal force of a packing of coordination ~4 under
pressure P = N/lx is ~ 1.9 P d); the tangential stiffness is Lai's k_t at
delta_0 and the friction coefficient mu_s.  So ``--law NAME`` alone shears a
packing of the same pressure, overlaps and time scales.  ``ishima`` has no
Coulomb cap: with the matched k_t its tangential springs store so much that
rearrangements throw the top row off the packing (quick cell, 150 disks:
N < N_target / 2 in 6 % of the frames, rms servo error 23 %, tau from -0.3
to 0.4); its default is a tenth of it (:data:`ISHIMA_KT_FACTOR`; rms error
2.5 %, slips up to 3 % in tau; a hundredth leaves drops below 0.2 %).

Control numbers (da Cruz et al. 2005, 2D, per unit thickness)
--------------------------------------------------------------
P = N / lx, kappa = E* / P, I = gamma_dot d sqrt(rho / P) with d the mean
diameter and gamma_dot = V / h0 (h0 the distance between the wall-disk centre
lines when shearing starts).  So N = E* lx / kappa and V = I h0 sqrt(P/rho)/d.
Shear strain gamma = (x displacement of the top wall) / h0.

Time step: dt <= dt_frac t_c with t_c = r_min sqrt(rho / (2 E*)) =
sqrt(m*_min / (pi E*)), a lower bound of the contact time sqrt(m*/k_n)
(``lee_hurley``: k_n <= pi E* for a/R <= 1, Eq. A2; the other laws' defaults
have k_n below that at the overlaps of the cell); dt is then shortened so that
an output interval dgamma is an integer number of steps.

Damping: alpha_n = gamma_n = 0.1 and alpha_t = gamma_t = 0.1 are the damping
ratios of Eqs. A4 and A12, eta_r = 0.3 of Eq. A20 (the engine's dashpots,
``System.damping``; a wall disk enters with the wall's total mass and an
infinite inertia, ``System.damping_mass``).  The paper's restitution 0.9 is
not used: for a linear spring-dashpot the ratio 0.1 means
e = exp(-pi 0.1 / sqrt(1 - 0.01)) = 0.73, and e = 0.9 would need a ratio of
0.034; we follow the damping constants the paper states and record the
implied e in the result.
"""

import math
from dataclasses import dataclass

import numpy as np

from fricstab.engine import Material, System
from fricstab.errors import ParameterError
from fricstab.io.scenes import (SCALE_HIGH, SCALE_LOW, Derived, Field, LawChoice, Schema,
                                in_scale_window, register, validate)
from fricstab.laws import vector_form

__all__ = ["SCHEMA", "LAWS", "HISTORY_UNITS", "ISHIMA_KT_FACTOR", "Units", "Cell", "make_cell", "material",
           "restitution", "typical_overlap", "units_of"]

#: Young's modulus 1 GPa and Poisson ratio 0.2 of the paper: E* = E / (2 (1 - nu^2)).
PAPER_ESTAR = 1e9 / (2.0 * (1.0 - 0.2 ** 2))
PAPER_NU, PAPER_MUS, PAPER_MUR = 0.2, 0.7, 0.01


def _lee_hurley_contact(delta, nu=PAPER_NU):
    """(f_n, k_t) of ``lee_hurley`` for two unit disks at overlap ``delta`` (E* = 1)."""
    from fricstab.generated.lee_hurley import lee_hurley_contact
    out = np.empty(9)
    lee_hurley_contact(2.0 - delta, 0.0, 1.0, 1.0, 1.0, nu, PAPER_MUS, PAPER_MUR, 0.0, 0.0,
                       out)
    return out[5], out[3]


def typical_overlap(kappa):
    """delta_0 / L0 at which ``lee_hurley`` (E* = 1, R = L0) carries f_0 = P d = 2 E* L0 / kappa.

    kappa >= 10 (the schema's bound) gives delta_0 <= 0.25 L0, inside the
    domain of Lai's k_t (a/R < ~1).
    """
    from scipy.optimize import brentq
    f0 = 2.0 / kappa
    return brentq(lambda d: _lee_hurley_contact(d)[0] - f0, 1e-14, 0.4, xtol=1e-300,
                  rtol=4 * np.finfo(float).eps)


def _kn(v):
    """Hertz normal stiffness [Pa m^(-1/2)] with the force of ``lee_hurley`` at delta_0."""
    d0 = typical_overlap(v["kappa"])
    l0 = (v["r_min"] + v["r_max"]) / 2.0
    return _lee_hurley_contact(d0)[0] / d0 ** 1.5 * v["modulus"] / math.sqrt(l0)


def _kt(v):
    """Tangential stiffness [Pa m^(-1/2)]: kt sqrt(delta_0) = Lai's k_t of ``lee_hurley``."""
    d0 = typical_overlap(v["kappa"])
    l0 = (v["r_min"] + v["r_max"]) / 2.0
    return _lee_hurley_contact(d0)[1] / math.sqrt(d0) * v["modulus"] / math.sqrt(l0)


_KN = Derived(_kn, "f_n of lee_hurley at the typical overlap delta_0 (kappa) / delta_0^(3/2)")
_KT = Derived(_kt, "Lai's k_t of lee_hurley (nu = 0.2) at delta_0 / delta_0^(1/2)")
#: Ishima's tangential springs have no cap: a tenth of the matched k_t (module docstring).
ISHIMA_KT_FACTOR = 0.1
_KT_ISHIMA = Derived(lambda v: ISHIMA_KT_FACTOR * _kt(v),
                     "0.1 x Lai's k_t of lee_hurley at delta_0 / delta_0^(1/2)")
_KN_LINEAR = Derived(lambda v: _lee_hurley_contact(typical_overlap(v["kappa"]))[0]
                     / typical_overlap(v["kappa"]) * v["modulus"],
                     "f_n of lee_hurley at the typical overlap delta_0 (kappa) / delta_0")
_KT_LINEAR = Derived(lambda v: _lee_hurley_contact(typical_overlap(v["kappa"]))[1]
                     * v["modulus"], "Lai's k_t of lee_hurley (nu = 0.2) at delta_0")
#: Unit of each law parameter in the scene, and its reduced unit (as a function of Units);
#: a key "law.parameter" is that law's (linear's springs are N/m per m: Pa).
PARAM_UNITS = {"E": "Pa", "nu": "-", "mus": "-", "mur": "-", "mu": "-", "Rw": "m",
               "kn": "Pa m^(-1/2) (N/m per m^(3/2))", "kt": "Pa m^(-1/2) (N/m per m^(3/2))",
               "linear.kn": "Pa (N/m per m)", "linear.kt": "Pa (N/m per m)"}
_REDUCE = {"E": lambda u: u.pressure, "Rw": lambda u: u.length,
           "kn": lambda u: u.pressure / math.sqrt(u.length),
           "kt": lambda u: u.pressure / math.sqrt(u.length),
           "linear.kn": lambda u: u.pressure, "linear.kt": lambda u: u.pressure}

LAWS = LawChoice(
    default="lee_hurley",
    defaults={
        "lee_hurley": {"E": Derived(lambda v: v["modulus"], "modulus"), "nu": PAPER_NU,
                       "mus": PAPER_MUS, "mur": PAPER_MUR,
                       "Rw": Derived(lambda v: v["r_max"], "r_max (not used)")},
        "hertz": {"kn": _KN},
        "charan": {"kn": _KN, "kt": _KT, "mu": PAPER_MUS},
        "ishima": {"kn": _KN, "kt": _KT_ISHIMA},
        "linear": {"kn": _KN_LINEAR, "kt": _KT_LINEAR, "mu": PAPER_MUS},
    },
    docs={
        "lee_hurley": "the paper's law (App. A): E* = modulus, nu, mu_s, mu_r of Sec. 2; "
                      "Rw (its wall form) is not used: the walls are rows of disks",
        "hertz": "frictionless; kn gives lee_hurley's normal force at the typical overlap "
                 "delta_0 of the preset's kappa (slips are rearrangements)",
        "charan": "smoothed Coulomb (mu = mu_s); kn as hertz, kt sqrt(delta_0) = Lai's k_t "
                  "of lee_hurley at delta_0; no rolling resistance",
        "ishima": "no Coulomb cap (tangential springs never slide): kn as hertz, kt a tenth "
                  "of charan's (with charan's, rearrangements lift the top row off); slips "
                  "are rearrangements and rolling",
        "linear": "linear spring-Coulomb (LAMMPS gran/hooke/history, mu = mu_s): kn delta_0 "
                  "= lee_hurley's normal force, kt = Lai's k_t of lee_hurley at delta_0; no "
                  "rolling resistance",
    },
    units=PARAM_UNITS,
)

_SCALE_WHY = "beyond which the products of the cell's scales leave float64"
_STEPS_WHY = "below it the steps per strain grow past any run"
_TINY = "0 or >= 1e-30 (a sub-normal value leaves float64 in its products)"

SCHEMA = register(Schema("shear", "Plane shear cell with constant normal force (Lee & Hurley)", (
    Field("n", "int", 300, "-", "bulk disks (paper: ~1,000; --preset paper)", low=4,
          high=10 ** 9, check_doc="beyond 1e9 no machine holds the cell"),
    Field("r_min", "float", 0.5e-6, "m", "smallest bulk radius", low=SCALE_LOW, high=SCALE_HIGH, check_doc=_SCALE_WHY),
    Field("r_max", "float", 1.0e-6, "m", "largest bulk radius (>= r_min)", low=SCALE_LOW, high=SCALE_HIGH, check_doc=_SCALE_WHY),
    Field("aspect", "float", 1.0, "-", "lx / height of the dense cell", low=0.1, high=10.0),
    Field("modulus", "float", PAPER_ESTAR, "Pa",
          "contact modulus E* = E/(2(1-nu^2)) of the cell (paper: E = 1 GPa, nu = 0.2): "
          "pressure unit, N = E* lx/kappa, time step; lee_hurley's E defaults to it",
          low=SCALE_LOW, high=SCALE_HIGH, check_doc=_SCALE_WHY),
    Field("density", "float", 2500.0, "kg/m^3", "density", low=SCALE_LOW, high=SCALE_HIGH, check_doc=_SCALE_WHY),
    Field("alpha_n", "float", 0.1, "-", "normal damping ratio (A4)", low=0.0, high=1.0,
          check=in_scale_window, check_doc=_TINY),
    Field("alpha_t", "float", 0.1, "-", "tangential damping ratio (A12)", low=0.0, high=1.0,
          check=in_scale_window, check_doc=_TINY),
    Field("eta_r", "float", 0.3, "-", "rolling viscous damping ratio (A20)", low=0.0, high=1.0,
          check=in_scale_window, check_doc=_TINY),
    Field("inertial_number", "float", 1e-4, "-", "I = gamma_dot d sqrt(rho/P) (paper: 4e-6)",
          low=1e-9, high=0.1, check_doc=_STEPS_WHY + " (~ 1/I)"),
    Field("kappa", "float", 1e3, "-", "stiffness number E*/P, P = N/lx (paper: 1e4)",
          low=10.0, high=1e8, check_doc="above it the steps per strain (~ sqrt(kappa)) grow "
          "past any run"),
    Field("dgamma", "float", 1e-5, "-", "shear strain between output frames (paper: 7.2e-7)",
          low=0.0,
          low_open=True, high=0.01),
    Field("strain", "float", 0.06, "-", "total shear strain (paper: 0.1156 = 0.022 + 130,000 x 7.2e-7); --resume with a larger one extends a run",
          low=0.0, low_open=True, high=10.0),
    Field("gamma0", "float", 0.022, "-", "start of the stick-slip regime for the analysis",
          low=0.0, high=10.0, check=in_scale_window, check_doc=_TINY),
    Field("seed", "int", 0, "-", "seed of the random radii and placement", low=0,
          high=2 ** 63 - 1),
    Field("dt_frac", "float", 0.15, "-", "time step bound / t_c, t_c = r_min sqrt(rho/2E*)",
          low=1e-6, high=1.0, check_doc=_STEPS_WHY + " (~ 1/dt_frac)"),
    Field("skin", "float", 0.2, "mean radius", "neighbour-list skin", low=1e-6, high=2.0,
          check_doc="below it the list is rebuilt at every step"),
    Field("servo_gain", "float", 0.1, "-",
          "shear servo: v_y = -g (N_target - N), g = servo_gain h0 / (E* lx t_c)",
          low=1e-6, high=1.0, check_doc="below it the servo does not hold N"),
    Field("prep_phi", "float", 0.45, "-", "area fraction of the random placement", low=0.1,
          high=0.5),
    Field("prep_speed", "float", 1e-3, "sqrt(E*/rho)", "largest wall speed while preparing",
          low=1e-9, high=0.1, check_doc="below it the walls do not move within any run"),
    Field("prep_tol", "float", 0.01, "-", "preparation ends at |N/N_target - 1| below this",
          low=1e-12, high=0.5, check_doc="below it round-off never meets it"),
    Field("prep_ke", "float", 1e-7, "P d^2", "... and mean kinetic energy below this",
          low=SCALE_LOW, high=SCALE_HIGH, check_doc=_SCALE_WHY),
    Field("prep_max_steps", "int", 3_000_000, "-", "preparation step limit", low=1,
          high=10 ** 12),
    Field("checkpoint_every", "int", 500, "frames", "checkpoint (and frame chunk) interval",
          low=1),
), laws=LAWS))

#: Unit (a Units attribute) of each history slot of each law, for SI frames.
HISTORY_UNITS = {"lee_hurley": ("force", "moment"), "charan": ("length", "length"),
                 "ishima": ("length", "length"), "hertz": (), "linear": ("length", "length"),
                 "charan_fi": ("length",), "ishima_fi": ("length",), "linear_fi": ("length",)}


def restitution(alpha):
    """Restitution of a linear spring-dashpot with damping ratio ``alpha``.

    ``exp(-pi alpha / sqrt(1 - alpha^2))`` below critical damping; 0 at and
    above it (``alpha >= 1``: the contact does not rebound).
    """
    if alpha >= 1.0:
        return 0.0
    return math.exp(-math.pi * alpha / math.sqrt(1.0 - alpha * alpha))


def damping_ratio(e):
    """The damping ratio of a linear spring-dashpot with restitution ``e`` (inverse of
    :func:`restitution`): ``-ln e / sqrt(pi^2 + ln^2 e)``; 1 (critical) at ``e = 0``."""
    if not 0.0 <= e <= 1.0:
        raise ParameterError(f"restitution e = {e!r}: a coefficient in [0, 1]")
    if e == 0.0:
        return 1.0
    ln = math.log(e)
    return -ln / math.sqrt(math.pi ** 2 + ln * ln)


def kappa_from_kn(kappa_kn):
    """E*/P (the scene's ``kappa``) for the stiffness number read as k_n/P (da Cruz et al.
    2005, 2D), k_n the secant stiffness of Eq. A1 at the typical contact: the typical force
    f_0 = P d = 2 P L0 at overlap delta_0 = f_0 / k_n gives delta_0 = 2 L0 / kappa_kn, and
    E*/P = 2 / f_n(delta_0) with f_n ``lee_hurley``'s normal force (E* = 1, R = L0)."""
    if not kappa_kn >= 10.0:
        raise ParameterError(f"kappa_kn = {kappa_kn!r}: at least 10 (overlaps below 0.2 L0)")
    return 2.0 / _lee_hurley_contact(2.0 / kappa_kn)[0]


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
    def moment(self):
        return self.force * self.length

    @property
    def velocity(self):
        return self.length / self.time

    def to_json(self):
        return {"length_m": self.length, "pressure_Pa": self.pressure,
                "mass_kg_per_m": self.mass, "time_s": self.time,
                "force_N_per_m": self.force, "velocity_m_per_s": self.velocity}


def units_of(params):
    """The reduced :class:`Units` of validated scene ``params``."""
    return Units((params["r_min"] + params["r_max"]) / 2.0, params["modulus"],
                 params["density"])


def material(params, units=None):
    """The engine :class:`Material` of ``params`` (SI; in the reduced ``units`` if given)."""
    law = dict(params["law_params"])
    if units is not None:
        physics = vector_form(params["law"])     # a _fi law has its vector law's units
        red = {k: _REDUCE.get(f"{physics}.{k}", _REDUCE.get(k)) for k in law}
        law = {k: v / red[k](units) if red[k] is not None else v for k, v in law.items()}
    return Material(params["law"], law)


@dataclass(frozen=True)
class Cell:
    """The placed cell in reduced units: particles, box, target force and time scale.

    ``kind`` (N,) int8: 0 bulk, 1 bottom wall (fixed), 2 top wall (driven), the
    engine's families.  ``pos`` is the random placement before compression.
    """

    params: dict
    units: Units
    lx: float
    radius: np.ndarray
    mass: np.ndarray
    inertia: np.ndarray
    kind: np.ndarray
    pos: np.ndarray
    n_target: float
    t_c: float

    @property
    def damping_mass(self):
        """Masses in the dashpots: own (bulk), the wall's total (top row), inf (bottom row)."""
        wall = self.mass[self.kind == 2].sum()
        return np.where(self.kind == 0, self.mass, np.where(self.kind == 2, wall, np.inf))

    @property
    def damping_inertia(self):
        """Inertias in the dashpots: own (bulk); inf for wall disks (they never rotate)."""
        return np.where(self.kind == 0, self.inertia, np.inf)

    def system(self):
        """The engine :class:`System` of the cell (reduced units, the scene's law)."""
        p = self.params
        return System(material(p, self.units), self.radius, self.mass, self.inertia,
                      family=self.kind, lx=self.lx, skin=p["skin"],
                      damping=(p["alpha_n"], p["alpha_t"], p["eta_r"]),
                      damping_mass=self.damping_mass, damping_inertia=self.damping_inertia)


def _wall_row(rng, lx, rmin, rmax):
    """Radii and x of touching disks filling the period lx exactly (radii rescaled)."""
    radii = []
    while 2.0 * sum(radii) < lx:
        radii.append(rng.uniform(rmin, rmax))
    r = np.array(radii) * lx / (2.0 * sum(radii))
    x = np.concatenate([[0.0], np.cumsum(r[:-1] + r[1:])]) + r[0]
    return r, x


def _place(rng, rb, lx, x_bot, r_bot, y0, h_loose, prep_phi):
    """Random sequential addition of the bulk disks ``rb`` (largest first) above the floor."""
    placed = np.empty((len(rb), 2))
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
            raise ParameterError(f"prep_phi = {prep_phi:g}: cannot place disk {k}")
    return placed, h_loose


def make_cell(params):
    """Lee & Hurley's plane-shear cell, placed at random (seeded): a :class:`Cell`.

    A fixed bottom row of disks, a rigid driven top row and polydisperse bulk
    disks between them, periodic in x (Lee & Hurley Sec. 2).  The bulk disks
    are placed one by one (random sequential addition, largest first) at area
    fraction ``prep_phi`` between the walls; ``lx`` is chosen so that the cell
    at area fraction 0.82 has ``lx / h = aspect``.

    Parameters
    ----------
    params : dict
        Scene keys (``fricstab scene show shear`` lists each with its unit,
        default and range; SI per unit thickness): e.g. ``n`` (bulk disks),
        ``r_min``, ``r_max`` (m), ``modulus`` (E*, Pa), ``inertial_number``,
        ``kappa`` (E*/P, which sets the normal force), ``strain``, ``dgamma``,
        ``seed``, ``law`` and the law's
        parameters (``lee_hurley``: ``E`` in Pa, ``nu``, ``mus``, ``mur``,
        Lee & Hurley App. A).  Validated and completed with the defaults (the
        quick preset) here.

    Returns
    -------
    Cell
        The placed cell in reduced units (length: the mean radius; pressure:
        E*), with ``units`` converting to SI, ``kind`` (0 bulk, 1 bottom row,
        2 top row), radii, masses, inertias, ``lx`` and the target normal force.

    Raises
    ------
    ParameterError
        An unknown key or a value out of range, naming it.
    """
    if not isinstance(params, dict):
        raise ParameterError(f"params must be a dict of the shear scene's keys, got "
                             f"{type(params).__name__}")
    p = params if "law_params" in params else validate("shear", params)
    if p["r_max"] < p["r_min"]:
        raise ParameterError(f"r_max = {p['r_max']:g} must be >= r_min = {p['r_min']:g}")
    units = units_of(p)
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
    y0 = r_bot.max()
    placed, h_loose = _place(rng, rb, lx, x_bot, r_bot, y0, area / (p["prep_phi"] * lx),
                             p["prep_phi"])
    y_top = y0 + h_loose + r_top.max()
    radius = np.concatenate([rb, r_bot, r_top])
    kind = np.concatenate([np.zeros(p["n"]), np.ones(len(r_bot)),
                           2 * np.ones(len(r_top))]).astype(np.int8)
    pos = np.concatenate([placed, np.column_stack([x_bot, np.zeros_like(x_bot)]),
                          np.column_stack([x_top, np.full_like(x_top, y_top)])])
    mass = math.pi * radius ** 2
    return Cell(params=p, units=units, lx=lx, radius=radius, mass=mass,
                inertia=0.5 * mass * radius ** 2, kind=kind, pos=pos,
                n_target=lx / p["kappa"], t_c=rmin / math.sqrt(2.0))
