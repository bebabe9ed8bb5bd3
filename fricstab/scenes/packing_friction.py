"""Any verified contact law in a packing: defaults in Ishima's units, rattlers, friction switched on.

Units of :mod:`fricstab.scenes.packing`: large diameter ``d = 1``,
``k_N = 1``, mass of a large disk ``m = 1`` (so ``t0 = 1``).  A packing is
made frictionless (``hertz``, App. A.1); this module turns it into a System
with the chosen law (:data:`LAWS`, the packing's :class:`LawChoice`), with
every tangential history zero and ``theta_i = 0`` (App. A.2).

* ``hertz``, ``ishima`` and ``charan`` share the normal force
  ``k_N xi^(3/2)``: the frictionless force balance is a frictional one (at
  zero history there is no tangential force), so nothing moves.
* ``lee_hurley`` has the 2D Hertz-cylinder normal force ``pi E* xi / lam``
  (Lee & Hurley A2): the state is first relaxed under it, frictionless
  (:func:`fricstab.scenes.packing_relax.relax_normal`: FIRE and Newton with
  the bordered solver at zero history), then friction is switched on with
  zero histories, as App. A.2 does after the Hertz FIRE.

Rattlers (Z <= z_th, removed iteratively, App. E.1) are removed before, on the
frictionless packing (:func:`backbone`).
"""

from dataclasses import dataclass, replace

import numpy as np

from fricstab._numerics import cylinder_lambda
from fricstab.engine import Material, System, newton
from fricstab.errors import ParameterError, check_instance, check_int, check_real
from fricstab.io.scenes import LawChoice
from fricstab.laws import vector_form
from fricstab.scenes.packing_relax import relax_normal, singular_guard
from fricstab.scenes.packing import KN, Packing, find_contacts, frictionless_system, hertz_forces

__all__ = ["LAWS", "Backbone", "Frictional", "SKIN", "backbone", "frictional", "material",
           "packing_system", "rattler_mask", "with_kt"]

SKIN = 0.1                  # neighbour-list skin of a frictional packing, in d
TYPICAL_OVERLAP = 0.02      # median overlap at phi = 0.90 (N = 256, seed 0), in d


def _matched_modulus(delta, ri=0.5, rj=0.5):
    """E* with the stiffness of Hertz at ``delta``: ``pi E*/(lam - 1) = 1.5 k_N delta^(1/2)``.

    ``dF/d delta = pi E*/(lam - 1)`` for ``F = pi E* delta / lam`` (Lee &
    Hurley A2, ``d lam/d delta = -lam/((lam - 1) delta)``).
    """
    lam = float(cylinder_lambda(delta, ri, rj))
    return 1.5 * KN * np.sqrt(delta) * (lam - 1.0) / np.pi


E_MATCHED = round(float(_matched_modulus(TYPICAL_OVERLAP)), 4)
#: kn of ``linear`` (a force/length, k_N d^(1/2)): Hertz's stiffness
#: dF/d xi = 1.5 k_N xi^(1/2) at the median overlap, as E_MATCHED matches it.
LINEAR_KN = round(1.5 * KN * float(np.sqrt(TYPICAL_OVERLAP)), 6)
#: kt of ``linear``: ishima's tangential stiffness kT xi^(1/2) (kT/kN = 1) there.
LINEAR_KT = round(KN * float(np.sqrt(TYPICAL_OVERLAP)), 6)


def _refuse(law, values):
    if values.get("kt_scan") is not None and vector_form(law) not in ("ishima", "charan"):
        return ("has no kt: --kt (scene key kt_scan) scans kT/kN of ishima and charan; "
                "set this law's parameters with --param")
    return None


#: The laws of a packing and their defaults in Ishima's units (``fricstab scene show packing``).
LAWS = LawChoice(
    default="ishima",
    defaults={
        "hertz": {"kn": KN},
        "ishima": {"kn": KN, "kt": 1.0},
        "charan": {"kn": KN, "kt": 1.0, "mu": 0.5},
        "lee_hurley": {"E": E_MATCHED, "nu": 0.2, "mus": 0.7, "mur": 0.01, "Rw": 1.0},
        "linear": {"kn": LINEAR_KN, "kt": LINEAR_KT, "mu": 0.5},
    },
    docs={
        "hertz": "frictionless, 2 dof per disk: J is the Hessian of the Hertz energy (App. A.1)",
        "ishima": "the paper's law (Eqs. 7-9): kn = k_N = 1, kt = kT/kN = 1 (the middle of "
                  "the paper's scan 1e-8..10); no Coulomb threshold",
        "charan": "Hertz + smoothed Coulomb (Charan Eq. 5): kn = 1 and kt = 1 as ishima, so "
                  "at zero history J and G equal ishima's; mu = 0.5, a grain-grain friction "
                  "(glass), puts t* = mu (kn/kt) delta ~ 0.01 d at phi = 0.9, so strains of "
                  "1e-3 probe the smoothed cap",
        "lee_hurley": f"E* = {E_MATCHED:g} gives the Hertz stiffness 1.5 k_N delta^(1/2) of "
                      f"two large disks at delta = {TYPICAL_OVERLAP:g} d, the median overlap "
                      "at phi = 0.90 (pi E*/(lam - 1), Lee & Hurley A2); nu, mus, mur as "
                      "Lee & Hurley's shear cell (0.2, 0.7, 0.01); Rw unused (no walls)",
        "linear": f"kn = {LINEAR_KN:g} is Hertz's stiffness 1.5 k_N delta^(1/2) and kt = "
                  f"{LINEAR_KT:g} ishima's kT delta^(1/2) (kT/kN = 1) at delta = "
                  f"{TYPICAL_OVERLAP:g} d, the median overlap at phi = 0.90; mu = 0.5 as charan",
    },
    units={"kn": "k_N", "kt": "k_N", "mu": "-", "E": "k_N d^(1/2)", "nu": "-", "mus": "-",
           "mur": "-", "Rw": "d", "linear.kn": "k_N d^(1/2)", "linear.kt": "k_N d^(1/2)"},
    refuse=_refuse,
)


def material(law="ishima", **params):
    """The :class:`~fricstab.engine.Material` of a law with the packing's defaults.

    Defaults are in Ishima's units (k_N = 1, d = 1): ``ishima`` (the paper's
    law, Eqs. 7-9) kn = 1, kt = kT/kN = 1; ``charan`` the same with mu = 0.5;
    ``hertz`` kn = 1 (frictionless); ``lee_hurley`` with the Hertz stiffness of
    two large disks at the median overlap (:data:`LAWS` states each reason).

    Parameters
    ----------
    law : str
        A pair law (:data:`PAIR_LAW_NAMES`).
    **params : float
        Parameters overriding the defaults (names as ``fricstab laws`` prints
        them; ``kn``, ``kt`` in k_N units).

    Returns
    -------
    Material

    Raises
    ------
    ParameterError
        A parameter the law does not take, or a bad value.
    """
    if law not in LAWS.defaults:
        raise ParameterError(f"unknown law {law!r}; a packing takes {', '.join(LAWS.defaults)}")
    pair, wall = LAWS.params(law)
    unknown = [k for k in params if k not in pair + wall]
    if unknown:
        raise ParameterError(f"{unknown[0]} is not a parameter of law {law} "
                             f"(it takes {', '.join(pair + wall)})")
    for key, value in params.items():
        check_real(key, value)
    values = {**LAWS.defaults[law], **params}
    return Material(law, {k: float(values[k]) for k in pair},
                    {k: float(values[k]) for k in wall})


def with_kt(mat, kt):
    """``mat`` with ``kt = kT/kN`` replaced; ``kt = 0``: the frictionless limit ``hertz``.

    The limit keeps ``kn`` (the normal force of ishima and charan is
    ``hertz``'s).  A law without ``kt`` (hertz, lee_hurley) is refused.
    """
    if "kt" not in mat.params:
        raise ParameterError(f"law {mat.law} has no kt (it takes {', '.join(mat.params)})")
    if not (np.isfinite(kt) and kt >= 0):
        raise ParameterError(f"kt (= kT/kN) must be a finite number >= 0, got {kt!r}")
    if kt == 0:
        return Material("hertz", {"kn": mat.params["kn"]})
    return replace(mat, params={**mat.params, "kt": float(kt)})


def rattler_mask(pairs, n, z_th=2):
    """Rattlers by iterative removal (Ishima App. E.1): Z_i <= z_th, repeated."""
    rattler = np.zeros(n, dtype=bool)
    while True:
        live = ~(rattler[pairs[:, 0]] | rattler[pairs[:, 1]])
        z = np.bincount(pairs[live].ravel(), minlength=n)
        new = (z <= z_th) & ~rattler
        if not new.any():
            return rattler
        rattler |= new


@dataclass(frozen=True)
class Backbone:
    """The packing without rattlers: what the rigidity and the DOS are about."""

    pos: np.ndarray        # (n, 2) frictionless force balance, folded into the box
    radius: np.ndarray
    box: float
    keep: np.ndarray       # indices of the kept particles in the packing
    n_total: int           # particles of the packing, rattlers included
    rattler_force: float   # largest |f| of a removed contact (0 if rattlers are free)

    @property
    def n(self):
        return len(self.radius)

    @property
    def mass(self):
        """``m_i = d_i^2`` (Sec. II)."""
        return (2 * self.radius) ** 2

    @property
    def inertia(self):
        """``I_i = m_i d_i^2 / 8`` (Sec. II)."""
        return self.mass * (2 * self.radius) ** 2 / 8


#: A packing handed to :func:`backbone` must be force-balanced: max |F_i| at most this
#: times its mean contact force, or the ``f_tol`` it records (make_packing), whichever is
#: larger.  The same rule as :data:`fricstab.analysis.rigidity.FORCE_BALANCE_TOL`
#: (a residual force shifts G by about |F|/f_mean relative; make_packing's packings sit
#: near 1e-11).  A state far from balance would otherwise reach the backbone's Newton
#: relaxation and fail there as a singular sparse LU, or walk a disk out of the box.
BALANCE_TOL = 1e-6


def _check_balanced(packing, radius, pairs, sep):
    """ParameterError naming max |F| unless ``packing`` is force-balanced (BALANCE_TOL)."""
    xi = radius[pairs[:, 0]] + radius[pairs[:, 1]] - np.hypot(sep[:, 0], sep[:, 1])
    fc = KN * np.clip(xi, 0, None) ** 1.5
    mean = float(fc[fc > 0].mean()) if np.any(fc > 0) else 0.0
    recorded = packing.info.get("f_tol", 0.0) if isinstance(packing.info, dict) else 0.0
    tol = max(BALANCE_TOL * mean, float(recorded or 0.0))
    fmax = float(np.abs(hertz_forces(packing.pos, radius, packing.box)).max())
    if not fmax <= tol:
        raise ParameterError(f"the packing is not force-balanced: max |F| = {fmax:.3g} "
                             f"(tolerance {tol:.3g}: {BALANCE_TOL:g} x the mean contact force "
                             f"{mean:.3g}, or the f_tol it records); relax it first "
                             "(fricstab packing make, or fricstab.make_packing)")


def backbone(packing, z_th=2, f_tol=1e-14):
    """Remove rattlers (and their contacts) from a packing (Ishima App. E.1).

    Particles with at most ``z_th`` contacts are removed, iteratively, since a
    removal may create new rattlers.  A removed contact that carried force (a
    rattler held between two diametrically opposite neighbours) leaves the
    backbone out of balance; it is then relaxed frictionlessly (Newton, bordered
    solver) so that theory and simulation start from the same force-balanced
    state.

    Parameters
    ----------
    packing : Packing
        A force-balanced frictionless packing (:func:`make_packing`).
    z_th : int
        Rattler threshold: particles with ``Z <= z_th`` contacts are removed
        (paper: 2).
    f_tol : float
        Force threshold of the relaxation after the removal (k_N d^(3/2)).

    Returns
    -------
    Backbone
        ``pos``, ``radius``, ``box`` (units of d), ``keep`` (indices kept),
        ``n_total`` (particles of the packing, rattlers included: the N of
        the DOS normalization, Eq. 23) and ``rattler_force``.
    """
    check_instance("packing", packing, Packing, "a Packing (make_packing)")
    check_int("z_th", z_th, 0)
    check_real("f_tol", f_tol, 0.0, low_open=True)
    radius = packing.diameter / 2
    pairs, sep = find_contacts(packing.pos, radius, packing.box)
    _check_balanced(packing, radius, pairs, sep)
    rattler = rattler_mask(pairs, len(radius), z_th)
    removed = rattler[pairs[:, 0]] | rattler[pairs[:, 1]]
    d = np.hypot(sep[removed, 0], sep[removed, 1])
    xi = radius[pairs[removed, 0]] + radius[pairs[removed, 1]] - d
    rattler_force = float((KN * np.clip(xi, 0, None) ** 1.5).max()) if removed.any() else 0.0
    keep = np.flatnonzero(~rattler)
    if len(keep) < 2:
        raise ParameterError(f"the packing (N = {len(radius)}, phi = {packing.phi:g}) has no "
                             f"rigid backbone: every particle is a rattler (Z <= {z_th})")
    pos = packing.pos[keep].copy()
    if np.abs(hertz_forces(pos, radius[keep], packing.box)).max() >= f_tol:
        system = frictionless_system(radius[keep], packing.box, skin=SKIN)
        state = system.state(pos)
        with singular_guard("backbone relaxation"):
            newton(system, state, f_tol, solver="bordered")
        pos = state.q[:, :2].copy()
    return Backbone(pos, radius[keep].copy(), float(packing.box), keep, len(radius),
                    rattler_force)


def _check_bb_mat(bb, mat):
    check_instance("bb", bb, (Backbone, Packing), "a Backbone (backbone) or a Packing")
    check_instance("mat", mat, Material, "a Material (packing_material)")


def packing_system(bb, mat, skin=SKIN):
    """The periodic :class:`~fricstab.engine.System` of a backbone (or packing) under a law.

    Parameters
    ----------
    bb : Backbone or Packing
        Positions, radii and box (Ishima's units: d = 1).
    mat : Material
        The law and its parameters (:func:`material`).
    skin : float
        Neighbour-list skin (units of d).

    Returns
    -------
    System
        Periodic in x and y (side ``bb.box``), masses ``~ d^2`` (a large disk
        m = 1), inertias ``m d^2 / 8``, every particle free.
    """
    _check_bb_mat(bb, mat)
    check_real("skin", skin, 0.0)
    radius = np.asarray(bb.radius, float)
    mass = (2 * radius) ** 2
    return System(mat, radius, mass, mass * (2 * radius) ** 2 / 8, lx=bb.box, ly=bb.box,
                  skin=skin)


@dataclass
class Frictional:
    """A force-balanced packing under a law: ``system``, ``state`` and how it got there.

    ``switch_residual``: max |F| right after the switch (zero histories,
    theta = 0) at the frictionless Hertz balance; ``normal_iterations`` and
    ``fire_iterations``: those of :func:`relax_normal` (0 when none was needed).
    """

    system: System
    state: object
    switch_residual: float
    normal_iterations: int = 0
    fire_iterations: int = 0

    @property
    def residual(self):
        f = self.system.forces(self.state)[:, :self.system.dof]
        return float(np.abs(f).max()) if f.size else 0.0


def frictional(bb, mat, f_tol=1e-14, max_iter=60):
    """Switch friction on (Ishima App. A.2) on a backbone with a law, force-balanced.

    Every history starts at zero and ``theta_i = 0``.  If ``max |F|`` is then
    not below ``f_tol`` (a law whose normal force is not Hertz's, or ``kn``
    scaling the Hertz residual above the threshold), the positions are first
    relaxed under the law's normal forces at zero history
    (:func:`relax_normal`), so that friction is switched on at a force-balanced
    state, as in the paper.

    Parameters
    ----------
    bb : Backbone
        The rattler-free packing (:func:`backbone`).
    mat : Material
        The law and its parameters (:func:`material`).
    f_tol : float
        Force threshold (k_N d^(3/2); paper: 1e-14).
    max_iter : int
        Iteration cap of the relaxation.

    Returns
    -------
    Frictional
        ``system`` and ``state`` (force-balanced, zero histories) and how it got
        there (``switch_residual``, ``normal_iterations``, ``fire_iterations``).

    Raises
    ------
    fricstab.errors.ConvergenceError
        When the relaxation does not reach ``f_tol`` in ``max_iter`` iterations.
    """
    _check_bb_mat(bb, mat)
    check_real("f_tol", f_tol, 0.0, low_open=True)
    check_int("max_iter", max_iter, 1)
    system = packing_system(bb, mat)
    state = system.state(bb.pos)
    f = system.forces(state)[:, :system.dof]
    residual = float(np.abs(f).max())
    iterations = fire_iterations = 0
    if residual >= f_tol:
        iterations, fire_iterations, _ = relax_normal(system, state, f_tol, max_iter)
    return Frictional(system, state, residual, iterations, fire_iterations)
