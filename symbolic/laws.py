"""Contact laws of frictional disks as pure functions returning SymPy expressions.

Every law returns a :class:`Law`: the generalized forces on the particles of one
contact, the increment rule of the tangential history, and the full Jacobian
block ``K = dF/dq`` (positive derivative, Charan's sign) including the
derivative through the history by the increment rule and through the Coulomb
threshold ``t*``.

Conventions (shared by all laws)
--------------------------------
* Pair contact of particles i and j: ``dx = x_i - x_j``, ``dy = y_i - y_j``,
  ``r = |(dx, dy)|``, ``n = (dx, dy)/r`` (from j to i),
  ``delta = R_i + R_j - r`` (> 0 in contact).  Forces are listed on i then j;
  j receives the opposite force.  Torque on either particle from the force
  ``F`` on i: ``T = -R (n_x F_y - n_y F_x)`` with that particle's radius.
* Wall contact with the flat substrate at ``y = 0``: ``delta = R - y``, the
  normal is ``y-hat`` and the tangential history is a scalar ``t`` along
  ``x-hat``.
* The history ``t`` is state.  Its change under ``dq`` is the law's increment
  rule ``dt = A(q) dq`` and the Jacobian is ``dF/dq|_t + dF/dt A``.

Laws
----
``hertz``, ``hertz_wall``
    Frictionless Hertz (Charan Eq. 1, Ishima Eq. D1): ``F = k_n delta^{3/2} n``;
    coordinates (x, y) per particle: the Hessian limit has no rotations.
``charan``, ``charan_wall``
    Hertz plus the smoothed-Coulomb Mindlin force of Charan Eq. 5,
    ``F_t = -k_t delta^{1/2} (1 + s - s^2) t`` with ``s = |t|/t*`` and
    ``t* = mu (k_n/k_t) delta``; increment rule Charan Eq. 2.  Coordinates
    (x, y, theta), outputs (F_x, F_y, T).
``ishima``, ``ishima_wall``
    Hertz plus Ishima's tangential law (Eqs. 7-9, D1-D7),
    ``f_T = -k_T xi_N^{1/2} xi_T`` with the unprojected increment rule D4, in
    Ishima's generalized coordinates (x, y, l = d theta/2) with generalized
    force (F_x, F_y, F^l = 2T/d).  Ishima's Jacobian (Eq. 18) is ``-K``.  At
    the wall ``l = R theta``, ``dt = dx + dl`` and ``F^l = T/R = F_t``.
``lee_hurley``, ``lee_hurley_wall`` (in :data:`CAPPED_LAWS`, own template)
    Lee & Hurley App. A: Hertz for cylinders with the implicit contact width
    (A1-A3), Lai's incremental tangential stiffness (A7-A10, A23) and Ai's
    type C rolling spring (A13-A18), both capped; histories are the trial
    tangential force ``ft`` and rolling torque ``mr`` (scalars).  See
    :func:`lee_hurley_pair` and :func:`lee_hurley_wall`.
``linear``, ``linear_wall`` (in :data:`LAWS`; :mod:`symbolic.linear`)
    LAMMPS ``gran/hooke/history`` without damping: ``F_n = k_n delta``,
    ``F_t = -k_t t`` with Charan's history projected onto ``|t| <= t*``
    (a hard cap; its sliding Jacobian carries the flag ``slide``).
``ishima_fi``, ``charan_fi``, ``linear_fi`` and their walls (in :data:`LAWS`; :mod:`symbolic.frame`)
    The same laws with a frame-indifferent history: a scalar ``xi`` along the
    tangent ``t_hat = (n_y, -n_x)``, ``d xi = t_hat^T A dq``, force the vector
    law's at ``t = xi t_hat``; the walls are the ``_wall`` laws renamed.

Metadata (every law; written into each generated module)
--------------------------------------------------------
``params`` (PARAMS: material parameters in kernel order), ``param_units``
(PARAM_UNITS), ``param_docs`` (PARAM_DOCS, one line with the paper's
equation), ``rotation`` (ROTATION: ``"theta"`` with generalized force T,
``"l"`` = R theta with T/R, ``""`` without rotations), ``has_cap`` (CAPPED: the
history is projected onto a cap), ``partner`` (WALL of a pair law, PAIR of a
wall law) and ``contact``: the expressions of :data:`CONTACT` = (secant
normal stiffness F_n/delta, tangential stiffness at zero history, rolling
stiffness, elastic normal force F_n).
"""

from dataclasses import dataclass

import sympy as sp

from symbolic.geometry import (CylinderPairGeometry, CylinderWallGeometry, PairGeometry,
                               WallGeometry, chain_diff)

__all__ = ["ALL_LAWS", "CAPPED_LAWS", "CONTACT", "LAWS", "PAIR_LAWS", "CappedLaw", "Law",
           "charan_pair", "charan_wall", "derive", "hertz_pair", "hertz_wall", "ishima_pair",
           "ishima_wall", "lai_penalty", "lee_hurley_pair", "lee_hurley_wall", "linear_pair",
           "linear_wall"]

#: Names of the contact quantities of :attr:`Law.contact`, in order.
CONTACT = ("kn", "kt", "kr", "fn")

_kn = sp.Symbol("kn", positive=True)
_kt = sp.Symbol("kt", positive=True)
_mu = sp.Symbol("mu", positive=True)
_Ri = sp.Symbol("Ri", positive=True)
_Rj = sp.Symbol("Rj", positive=True)
_R = sp.Symbol("R", positive=True)
#: Factor on the history increment: 1 while sticking; ``t*/|t|`` when the
#: stored history lies beyond the Coulomb circle and is rescaled onto it
#: (the derivative of ``t -> t* t/|t|`` across the circle).
SLIP_SCALE = sp.Symbol("slip_scale", positive=True)


@dataclass(frozen=True)
class Law:
    """A contact law: inputs, forces, increment rule and Jacobian block.

    Attributes
    ----------
    name : str
    kind : str
        ``"pair"`` or ``"wall"``.
    summary : str
        One line for the README and the CLI.
    inputs : tuple of sympy.Symbol
        Kernel arguments in order: geometry, radii, stiffnesses, history.
    params : tuple of str
        Names of the material parameters among ``inputs``.
    history : tuple of sympy.Symbol
        Tangential history components (empty for frictionless laws).
    coords : tuple of str
        Names of the coordinates the Jacobian columns refer to.
    outputs : tuple of str
        Names of the generalized forces (Jacobian rows).
    force : sympy.Matrix
        Generalized forces, ``len(outputs) x 1``.
    increment : sympy.Matrix
        ``dt/dq``, ``len(history) x len(coords)``.
    jacobian : sympy.Matrix
        ``dF/dq`` with history, ``len(outputs) x len(coords)``.
    coulomb : bool
        True when the law has a Coulomb threshold ``t* = mu (kn/kt) delta``
        past which the stored history is rescaled onto ``|t| = t*``; the
        Jacobian then contains the symbol ``slip_scale`` (see SLIP_SCALE).
    geometry : object
        The :mod:`symbolic.geometry` instance whose intermediates appear.
    param_units : tuple of str
        Dimension of each parameter of ``params`` ("-" for a pure number).
    param_docs : tuple of str
        One line per parameter, with the paper's equation.
    rotation : str
        ``"theta"`` (generalized force T), ``"l"`` (l = R theta, force T/R) or
        ``""`` (no rotational degree of freedom).
    has_cap : bool
        True when the history is projected onto a cap (Charan's Coulomb
        circle, Lee & Hurley's caps).
    partner : str
        The wall form of a pair law, or the pair form of a wall law.
    contact : tuple of sympy.Expr
        The quantities of :data:`CONTACT`: secant normal stiffness
        ``F_n/delta``, tangential stiffness at zero history, rolling
        stiffness (0 without rolling resistance), elastic normal force.
    """

    name: str
    kind: str
    summary: str
    inputs: tuple
    params: tuple
    history: tuple
    coords: tuple
    outputs: tuple
    force: sp.Matrix
    increment: sp.Matrix
    jacobian: sp.Matrix
    coulomb: bool
    geometry: object
    param_units: tuple
    param_docs: tuple
    rotation: str
    has_cap: bool
    partner: str
    contact: tuple

    @property
    def n_dof(self):
        """Degrees of freedom per particle."""
        return len(self.coords) // (2 if self.kind == "pair" else 1)


_HERTZ_KN = "force/length^(3/2)"
_DOC_KN = "normal stiffness: F_n = kn delta^(3/2) (Charan Eq. 1, Ishima Eqs. 7, D1)"


def _hertz_contact(g, tangential):
    """CONTACT of the Hertz family: kn delta^(1/2), kt delta^(1/2) (or 0), 0, F_n."""
    kt = _kt * g.sdelta if tangential else sp.Integer(0)
    return (_kn * g.sdelta, kt, sp.Integer(0), _kn * g.delta * g.sdelta)


def _smoothed_coulomb_factor(tn, delta):
    """``1 + s - s^2`` of Charan Eq. 5 with ``s = |t| / t*``."""
    s = tn * _kt / (_mu * _kn * delta)
    return 1 + s - s**2


def _pair_columns(geom, increment, dof, slip=sp.Integer(1)):
    """Base-variable derivatives for each coordinate column of a pair block."""
    columns = []
    for k in range(2 * dof):
        particle, comp = divmod(k, dof)
        sign = 1 if particle == 0 else -1
        d = {geom.dx: sp.Integer(sign if comp == 0 else 0),
             geom.dy: sp.Integer(sign if comp == 1 else 0)}
        if increment.shape[0]:
            d[geom.tx] = slip * increment[0, k]
            d[geom.ty] = slip * increment[1, k]
        columns.append(d)
    return columns


def _tangent_increment(geom, arm_i, arm_j):
    """``dt = (I - n n^T) dr_ij + (arm_i dq3_i + arm_j dq3_j) (n_y, -n_x)``.

    Charan Eq. 2 with ``arm = R`` (coordinate theta); Ishima Eq. D4 with
    ``arm = 1`` (coordinate l = R theta).  ``I - n n^T`` is written with
    ``ny^2`` and ``nx^2`` on the diagonal, exact for a unit normal and free of
    cancellation when n lies along an axis.
    """
    nx, ny = geom.nx, geom.ny
    return sp.Matrix([
        [ny**2, -nx * ny, arm_i * ny, -ny**2, nx * ny, arm_j * ny],
        [-nx * ny, nx**2, -arm_i * nx, nx * ny, -nx**2, -arm_j * nx],
    ])


def _jacobian(force, geom, columns):
    rows = []
    for comp in force:
        rows.append([chain_diff(comp, geom, col) for col in columns])
    return sp.Matrix(rows)


def hertz_pair():
    """Frictionless Hertz between two disks (Charan Eq. 1, Ishima D1)."""
    g = PairGeometry()
    fn = _kn * g.delta * g.sdelta
    force = sp.Matrix([fn * g.nx, fn * g.ny, -fn * g.nx, -fn * g.ny])
    increment = sp.zeros(0, 4)
    cols = _pair_columns(g, increment, 2)
    return Law(
        name="hertz", kind="pair",
        summary="frictionless Hertz, disk-disk (Charan Eq. 1); coords (x, y)",
        inputs=(g.dx, g.dy, _Ri, _Rj, _kn), params=("kn",), history=(),
        coords=("x_i", "y_i", "x_j", "y_j"),
        outputs=("Fx_i", "Fy_i", "Fx_j", "Fy_j"),
        force=force, increment=increment, jacobian=_jacobian(force, g, cols),
        coulomb=False, geometry=g, param_units=(_HERTZ_KN,), param_docs=(_DOC_KN,),
        rotation="", has_cap=False, partner="hertz_wall", contact=_hertz_contact(g, False))


def hertz_wall():
    """Frictionless Hertz between a disk and the substrate y = 0."""
    g = WallGeometry()
    force = sp.Matrix([sp.Integer(0), _kn * g.delta * g.sdelta])
    increment = sp.zeros(0, 2)
    cols = [{}, {g.y: sp.Integer(1)}]
    return Law(
        name="hertz_wall", kind="wall",
        summary="frictionless Hertz, disk-substrate at y = 0; coords (x, y)",
        inputs=(g.y, _R, _kn), params=("kn",), history=(),
        coords=("x", "y"), outputs=("Fx", "Fy"),
        force=force, increment=increment, jacobian=_jacobian(force, g, cols),
        coulomb=False, geometry=g, param_units=(_HERTZ_KN,), param_docs=(_DOC_KN,),
        rotation="", has_cap=False, partner="hertz", contact=_hertz_contact(g, False))


def _tangential_pair_law(name, summary, tangential, arm_i, arm_j, coords,
                         outputs, params, coulomb, meta):
    g = PairGeometry()
    fn = _kn * g.delta * g.sdelta
    ftx, fty = tangential(g)
    fx, fy = fn * g.nx + ftx, fn * g.ny + fty
    # Torque about each centre; only the tangential force has an arm.
    cross = g.nx * fty - g.ny * ftx
    force = sp.Matrix([fx, fy, -arm_i * cross, -fx, -fy, -arm_j * cross])
    increment = _tangent_increment(g, arm_i, arm_j)
    cols = _pair_columns(g, increment, 3, SLIP_SCALE if coulomb else sp.Integer(1))
    inputs = (g.dx, g.dy, _Ri, _Rj, _kn, _kt) + ((_mu,) if coulomb else ()) + (g.tx, g.ty)
    return Law(
        name=name, kind="pair", summary=summary, inputs=inputs, params=params,
        history=(g.tx, g.ty), coords=coords, outputs=outputs, force=force,
        increment=increment, jacobian=_jacobian(force, g, cols),
        coulomb=coulomb, geometry=g, contact=_hertz_contact(g, True), **meta)


_DOC_KT_CHARAN = "tangential stiffness: F_t = -kt delta^(1/2) (1 + s - s^2) t (Charan Eq. 5)"
_DOC_MU = "friction coefficient: t* = mu (kn/kt) delta, |F_t| <= mu F_n (Charan Eqs. 4, 5)"
_DOC_KT_ISHIMA = "tangential stiffness k_T: f_T = -k_T xi_N^(1/2) xi_T (Ishima Eqs. 8, D1-D7)"
_CHARAN_META = dict(param_units=(_HERTZ_KN, _HERTZ_KN, "-"),
                    param_docs=(_DOC_KN, _DOC_KT_CHARAN, _DOC_MU),
                    rotation="theta", has_cap=True)
_ISHIMA_META = dict(param_units=(_HERTZ_KN, _HERTZ_KN), param_docs=(_DOC_KN, _DOC_KT_ISHIMA),
                    rotation="l", has_cap=False)


def charan_pair():
    """Hertz + smoothed-Coulomb Mindlin, disk-disk (Charan Eqs. 1, 2, 5)."""
    def tangential(g):
        c = -_kt * g.sdelta * _smoothed_coulomb_factor(g.tn, g.delta)
        return c * g.tx, c * g.ty
    return _tangential_pair_law(
        "charan", "Hertz + smoothed-Coulomb Mindlin, disk-disk (Charan Eqs. 1, 2, 5); "
        "coords (x, y, theta)", tangential, _Ri, _Rj,
        ("x_i", "y_i", "theta_i", "x_j", "y_j", "theta_j"),
        ("Fx_i", "Fy_i", "T_i", "Fx_j", "Fy_j", "T_j"), ("kn", "kt", "mu"), True,
        dict(_CHARAN_META, partner="charan_wall"))


def ishima_pair():
    """Hertz + Ishima's tangential law in generalized coordinates (Eqs. 7-9, D1-D7)."""
    def tangential(g):
        c = -_kt * g.sdelta
        return c * g.tx, c * g.ty
    one = sp.Integer(1)
    return _tangential_pair_law(
        "ishima", "Hertz + Ishima tangential law f_T = -kT xi_N^(1/2) xi_T (Ishima Eqs. "
        "7-9, D1-D7); coords (x, y, l = d theta/2), forces (Fx, Fy, 2T/d)",
        tangential, one, one,
        ("x_i", "y_i", "l_i", "x_j", "y_j", "l_j"),
        ("Fx_i", "Fy_i", "Fl_i", "Fx_j", "Fy_j", "Fl_j"), ("kn", "kt"), False,
        dict(_ISHIMA_META, partner="ishima_wall"))


def charan_wall():
    """Hertz + smoothed-Coulomb Mindlin, disk on the substrate (Charan Eqs. 1, 2, 5)."""
    g = WallGeometry()
    ft = -_kt * g.sdelta * _smoothed_coulomb_factor(g.tn, g.delta) * g.t
    # Contact point at r - R y-hat: torque (-R y-hat) x (F_t x-hat) = R F_t z-hat.
    force = sp.Matrix([ft, _kn * g.delta * g.sdelta, _R * ft])
    increment = sp.Matrix([[1, 0, _R]])  # dt = dx + R dtheta (Charan Eq. 2)
    cols = [{g.t: SLIP_SCALE * increment[0, 0]}, {g.y: sp.Integer(1)},
            {g.t: SLIP_SCALE * increment[0, 2]}]
    return Law(
        name="charan_wall", kind="wall",
        summary="Hertz + smoothed-Coulomb Mindlin, disk-substrate at y = 0 "
                "(Charan Eqs. 1, 2, 5); coords (x, y, theta)",
        inputs=(g.y, _R, _kn, _kt, _mu, g.t), params=("kn", "kt", "mu"),
        history=(g.t,), coords=("x", "y", "theta"), outputs=("Fx", "Fy", "T"),
        force=force, increment=increment, jacobian=_jacobian(force, g, cols),
        coulomb=True, geometry=g, contact=_hertz_contact(g, True),
        **dict(_CHARAN_META, partner="charan"))


def ishima_wall():
    """Hertz + Ishima's tangential law, disk on the substrate y = 0 (Eqs. 7-9, D1-D7).

    Ishima's coordinates (x, y, l = R theta) with generalized forces
    (F_x, F_y, F^l = T/R); scalar history ``t`` along x-hat with
    ``dt = dx + dl`` (``dl = R dtheta``: Charan's ``dt = dx + R dtheta``), so
    ``F_t = -k_T delta^{1/2} t`` and ``F^l = T/R = F_t``.  No Coulomb limit.
    """
    g = WallGeometry()
    ft = -_kt * g.sdelta * g.t
    force = sp.Matrix([ft, _kn * g.delta * g.sdelta, ft])
    increment = sp.Matrix([[1, 0, 1]])  # dt = dx + dl
    cols = [{g.t: increment[0, 0]}, {g.y: sp.Integer(1)}, {g.t: increment[0, 2]}]
    return Law(
        name="ishima_wall", kind="wall",
        summary="Hertz + Ishima tangential law, disk-substrate at y = 0 (Ishima Eqs. "
                "7-9, D1-D7); coords (x, y, l = R theta), forces (Fx, Fy, T/R)",
        inputs=(g.y, _R, _kn, _kt, g.t), params=("kn", "kt"),
        history=(g.t,), coords=("x", "y", "l"), outputs=("Fx", "Fy", "Fl"),
        force=force, increment=increment, jacobian=_jacobian(force, g, cols),
        coulomb=False, geometry=g, contact=_hertz_contact(g, True),
        **dict(_ISHIMA_META, partner="ishima"))


@dataclass(frozen=True)
class CappedLaw(Law):
    """A law whose scalar histories are capped (Lee & Hurley App. A).

    ``force`` and ``jacobian`` are written in the capped histories
    ``capped = (ft_c, mr_c)``; the generated prologue computes them from the
    trial histories and sets the branch flags ``slides = (slide_t, slide_r)``
    (0 stick, 1 slide) that select the Jacobian rows of the capped values.
    A history exactly on its cap takes the sliding branch (``|ft| >= cap``).

    Attributes (besides :class:`Law`'s)
    ------------------------------------
    capped : tuple of sympy.Symbol
    slides : tuple of sympy.Symbol
    caps : tuple of sympy.Expr
        The caps ``mu_s F_n^e`` and ``mu_r R_r F_n^e`` (A10, A18).
    domain : tuple of (sympy.Expr, str)
        Expressions that must be > 0 where the tangential stiffness is used,
        with the message of the ValueError raised otherwise.
    """

    capped: tuple
    slides: tuple
    caps: tuple
    domain: tuple


_E = sp.Symbol("E", positive=True)
_nu = sp.Symbol("nu", nonnegative=True)
_mus = sp.Symbol("mus", positive=True)
_mur = sp.Symbol("mur", nonnegative=True)
_Rw = sp.Symbol("Rw", positive=True)

_LH_UNITS = ("pressure", "-", "-", "-")
_LH_DOCS = (
    "contact modulus E* (Eq. A3): kn = pi E*/lam (A2), Lai's kt (A8), kr = pi E* R_r^2/4 (A15)",
    "Poisson ratio in Lai's kt (Eqs. A8, A9), in [0, 0.5)",
    "sliding friction: |F_t^e| <= mus F_n^e (Eqs. A10, A23)",
    "rolling friction: |M_r^k| <= mur R_r F_n^e (Eqs. A17, A18); 0: no rolling resistance",
)
_RW_DOC = ("wall radius of curvature: contact width and stiffnesses of cylinders R and Rw "
           "(Eqs. A2, A8, A16); the kinematics stays that of the flat wall")


def lai_penalty(x, nu):
    """Lai's penalty factor ``w(a/R)`` (Lee & Hurley Eq. A9), exact rationals.

    ``0.22 + 2.89 x + 0.18 nu - 10.31 x^2 + 1.75 x nu + 0.36 nu^2``, written
    in Horner form in ``x`` (the generated code evaluates it as written).
    """
    r = sp.Rational
    return (r(22, 100) + r(18, 100) * nu + r(36, 100) * nu**2
            + x * (r(289, 100) + r(175, 100) * nu - r(1031, 100) * x))


def _lee_hurley_springs(g, r1, r2):
    """k_n (A2), F_n^e, Lai's k_t (A8, A9) with its denominator, k_r (A15) and R_r (A16).

    Lai's logarithms come from lam, which is already
    ``ln(4 R_1/a) + ln(4 R_2/a) - 1``, and ``a = 4 sqrt(R_1 R_2) exp(-(lam + 1)/2)``:
    ``ln(4 R_1/a) = (lam + 1 + ln(R_1/R_2))/2``, ``ln(4 R_2/a) = (lam + 1 - ln(R_1/R_2))/2``
    and ``ln(2 R_1/a) + ln(2 R_2/a) = lam + 1 - 2 ln 2``: one logarithm, of the
    radii only, instead of four of the width.  Identities at the root, so
    every kernel (force, Jacobian, increment, advance, both forms) uses the
    same law; k_t has no derivative in the hypoelastic Jacobian.
    """
    lam, hw = g.lam, g.hw
    kn = sp.pi * _E / lam
    fn = kn * g.delta
    lai = _nu / (2 * (1 - _nu))
    log_ratio = sp.log(r1 / r2)
    log4_1 = (lam + 1 + log_ratio) / 2   # ln(4 R_1/a)
    log4_2 = (lam + 1 - log_ratio) / 2   # ln(4 R_2/a)
    denom = (lam + 2 - 2 * sp.log(2)
             + lai_penalty(hw / r1, _nu) * (log4_1 + lai)
             + lai_penalty(hw / r2, _nu) * (log4_2 + lai))
    kt = sp.pi * _E / denom
    rr = r1 * r2 / (r1 + r2)
    kr = sp.pi * _E * rr**2 / 4
    return kn, fn, kt, denom, kr, rr


def _capped_history_symbols():
    return (sp.Symbol("ft", real=True), sp.Symbol("mr", real=True),
            sp.Symbol("ftc", real=True), sp.Symbol("mrc", real=True),
            sp.Symbol("slide_t", nonnegative=True), sp.Symbol("slide_r", nonnegative=True))


def _capped_jacobian(force, g, cols, fn, increment, ftc, mrc, slide_t, slide_r):
    """dF/dq through the geometry and the capped histories, per branch flag."""
    rows = []
    for comp in force:
        row = []
        for k, col in enumerate(cols):
            dfn = chain_diff(fn, g, col)
            dftc = (1 - slide_t) * increment[0, k] + slide_t * ftc / fn * dfn
            dmrc = (1 - slide_r) * increment[1, k] + slide_r * mrc / fn * dfn
            row.append(chain_diff(comp, g, col) + sp.diff(comp, ftc) * dftc
                       + sp.diff(comp, mrc) * dmrc)
        rows.append(row)
    return sp.Matrix(rows)


def lee_hurley_pair():
    """Lee & Hurley's plane-shear contact law between two disks (App. A).

    Normal (A1-A3): ``F_n^e = k_n delta``, ``k_n = pi E* / lam`` with
    ``lam = ln(4R_i/a) + ln(4R_j/a) - 1`` and the implicit half-width ``a``
    (:class:`symbolic.geometry.CylinderPairGeometry`).  Tangential (A7-A9):
    ``k_t = pi E* / D`` with Lai's denominator
    ``D = ln(2R_i/a) + ln(2R_j/a) + 1 + sum_k w_k (ln(4R_k/a) + nu/(2(1 - nu)))``
    (the printed ``nu/2(1 - nu)`` read as ``nu/(2(1 - nu))``).  Rolling (A15,
    A16): ``k_r = pi E* R_r^2/4``, ``1/R_r = 1/R_i + 1/R_j``.

    Histories (trial values, after the DEM's increment): ``ft`` along
    ``t_hat = (-n_y, n_x)`` with ``d ft = k_t d delta_t``,
    ``d delta_t = t_hat . (dr_i - dr_j) - (R_i dtheta_i + R_j dtheta_j)``
    (the tangential displacement of i's contact point relative to j's), and
    ``mr`` with ``d mr = -k_r (dtheta_i - dtheta_j)`` (A14).  Caps with the
    elastic normal force (A10, A18, A23): ``ft_c = ft`` while
    ``|ft| < mu_s F_n^e``, else ``mu_s F_n^e sign(ft)`` (a history exactly on
    the cap slides); ``mr_c`` likewise with ``mu_r R_r F_n^e``.

    Forces: ``F_i = F_n^e n - ft_c t_hat = -F_j``; torques
    ``T_i = R_i ft_c + mr_c``, ``T_j = R_j ft_c - mr_c`` (the existing
    convention ``T = -R n x F_i`` for the tangential part).  The elastic work is
    ``-ft_c d delta_t + mr_c d theta_r``: both springs resist.

    Jacobian ``K = dF/dq`` with the histories advanced by the increment rule
    (hypoelastic: ``d ft = k_t d delta_t`` with no ``dk_t/dq`` term, as the DEM
    integrates it): ``dft_c/dq = k_t d delta_t/dq`` while sticking and
    ``(ft_c/F_n^e) dF_n^e/dq = mu_s sign(ft) dF_n^e/dq`` while sliding; the
    same for ``mr_c``.  The blocks of the two branches differ at the cap.
    """
    g = CylinderPairGeometry()
    nx, ny = g.nx, g.ny
    ft, mr, ftc, mrc, slide_t, slide_r = _capped_history_symbols()
    kn, fn, kt, denom, kr, rr = _lee_hurley_springs(g, _Ri, _Rj)
    fx, fy = fn * nx + ftc * ny, fn * ny - ftc * nx
    force = sp.Matrix([fx, fy, _Ri * ftc + mrc, -fx, -fy, _Rj * ftc - mrc])
    dt_row = [-ny, nx, -_Ri, ny, -nx, -_Rj]
    dr_row = [0, 0, -1, 0, 0, 1]
    increment = sp.Matrix([[kt * c for c in dt_row], [kr * c for c in dr_row]])
    cols = []
    for k in range(6):
        p, c = divmod(k, 3)
        sign = 1 if p == 0 else -1
        cols.append({g.dx: sp.Integer(sign if c == 0 else 0),
                     g.dy: sp.Integer(sign if c == 1 else 0)})
    jac = _capped_jacobian(force, g, cols, fn, increment, ftc, mrc, slide_t, slide_r)
    return CappedLaw(
        name="lee_hurley", kind="pair",
        summary="Lee & Hurley plane shear: Hertz cylinders (implicit width), Lai's "
                "incremental tangential and Ai's type C rolling springs, capped "
                "(App. A1-A23); coords (x, y, theta)",
        inputs=(g.dx, g.dy, _Ri, _Rj, _E, _nu, _mus, _mur, ft, mr),
        params=("E", "nu", "mus", "mur"), history=(ft, mr),
        coords=("x_i", "y_i", "theta_i", "x_j", "y_j", "theta_j"),
        outputs=("Fx_i", "Fy_i", "T_i", "Fx_j", "Fy_j", "T_j"),
        force=force, increment=increment, jacobian=jac, coulomb=True,
        geometry=g, param_units=_LH_UNITS, param_docs=_LH_DOCS, rotation="theta",
        has_cap=True, partner="lee_hurley_wall", contact=(kn, kt, kr, fn),
        capped=(ftc, mrc), slides=(slide_t, slide_r),
        caps=(_mus * fn, _mur * rr * fn),
        domain=((denom, "lee_hurley: Lai's k_t (Eqs. A8-A9) has a nonpositive "
                        "denominator: contact width a too large for the fit"),))


def lee_hurley_wall():
    """Lee & Hurley's law for a disk (radius R) on the flat wall y = 0.

    Normal ``n = (0, 1)`` into the disk, ``delta = R - y``; the contact width
    and the stiffnesses are those of two cylinders ``R`` and ``Rw``
    (:class:`symbolic.geometry.CylinderWallGeometry`; ``Rw`` is a parameter:
    a 2D Hertz contact on a half-space has no finite stiffness without a
    reference length), while the kinematics is that of a flat wall (the
    normal never rotates).  With ``t_hat = (-n_y, n_x) = (-1, 0)``:
    ``d ft = k_t (t_hat . dr - R dtheta) = k_t (-dx - R dtheta)``,
    ``d mr = -k_r dtheta``; ``k_n = pi E*/lam``, Lai's ``k_t`` with
    ``(R, Rw)``, ``k_r = pi E* R_r^2/4``, ``R_r = R Rw/(R + Rw)``.  Forces
    ``F = F_n n - ft_c t_hat = (ft_c, F_n)``, ``T = R ft_c + mr_c``; caps
    ``|ft_c| <= mu_s F_n``, ``|mr_c| <= mu_r R_r F_n`` (A10, A18, A23).  The
    pair law with ``R_j = Rw`` and particle j held fixed, except that j's
    curvature does not turn the normal.
    """
    g = CylinderWallGeometry()
    ft, mr, ftc, mrc, slide_t, slide_r = _capped_history_symbols()
    kn, fn, kt, denom, kr, rr = _lee_hurley_springs(g, _R, _Rw)
    force = sp.Matrix([ftc, fn, _R * ftc + mrc])
    increment = sp.Matrix([[-kt, 0, -kt * _R], [0, 0, -kr]])
    cols = [{}, {g.y: sp.Integer(1)}, {}]
    jac = _capped_jacobian(force, g, cols, fn, increment, ftc, mrc, slide_t, slide_r)
    return CappedLaw(
        name="lee_hurley_wall", kind="wall",
        summary="Lee & Hurley plane shear, disk on the flat wall y = 0: Hertz cylinders "
                "R and Rw (implicit width), Lai's incremental tangential and Ai's type C "
                "rolling springs, capped (App. A1-A23); coords (x, y, theta)",
        inputs=(g.y, _R, _E, _nu, _mus, _mur, _Rw, ft, mr),
        params=("E", "nu", "mus", "mur", "Rw"), history=(ft, mr),
        coords=("x", "y", "theta"), outputs=("Fx", "Fy", "T"),
        force=force, increment=increment, jacobian=jac, coulomb=True,
        geometry=g, param_units=_LH_UNITS + ("length",), param_docs=_LH_DOCS + (_RW_DOC,),
        rotation="theta", has_cap=True, partner="lee_hurley", contact=(kn, kt, kr, fn),
        capped=(ftc, mrc), slides=(slide_t, slide_r),
        caps=(_mus * fn, _mur * rr * fn),
        domain=((denom, "lee_hurley_wall: Lai's k_t (Eqs. A8-A9) has a nonpositive "
                        "denominator: contact width a too large for the fit"),))


#: Laws with capped scalar histories, generated by their own template
#: (kept apart from :data:`LAWS`, whose tests assume the (kn, kt, mu, t) family).
CAPPED_LAWS = {"lee_hurley": lee_hurley_pair, "lee_hurley_wall": lee_hurley_wall}


def linear_pair():
    """The linear spring-Coulomb law, disk-disk (:mod:`symbolic.linear`; imported late)."""
    from symbolic.linear import linear_pair as derive_pair
    return derive_pair()


def linear_wall():
    """The linear spring-Coulomb law on the substrate (:mod:`symbolic.linear`)."""
    from symbolic.linear import linear_wall as derive_wall
    return derive_wall()


def _fi(name, wall=False):
    """The frame-indifferent form (:mod:`symbolic.frame`) of the law ``name``, or its wall."""
    from symbolic import frame
    vector = LAWS[name]()
    return frame.fi_wall(vector) if wall else frame.fi_pair(vector)


#: The (kn, kt, [mu], history t) family of :mod:`fricstab.laws.verify`; the
#: ``_fi`` laws keep a scalar history along the tangent (:mod:`symbolic.frame`).
LAWS = {
    "hertz": hertz_pair,
    "hertz_wall": hertz_wall,
    "charan": charan_pair,
    "charan_wall": charan_wall,
    "ishima": ishima_pair,
    "ishima_wall": ishima_wall,
    "linear": linear_pair,
    "linear_wall": linear_wall,
    "ishima_fi": lambda: _fi("ishima"),
    "ishima_fi_wall": lambda: _fi("ishima_wall", wall=True),
    "charan_fi": lambda: _fi("charan"),
    "charan_fi_wall": lambda: _fi("charan_wall", wall=True),
    "linear_fi": lambda: _fi("linear"),
    "linear_fi_wall": lambda: _fi("linear_wall", wall=True),
}

#: Pair laws in dispatch order: the id of a law is its index here, and its
#: wall form (``Law.partner``) has the same id.
PAIR_LAWS = ("hertz", "charan", "ishima", "lee_hurley", "linear", "ishima_fi", "charan_fi",
             "linear_fi")

#: Every law: pair forms and their wall forms.
ALL_LAWS = tuple(LAWS) + tuple(CAPPED_LAWS)


def derive(name):
    """Derive the law called ``name`` (one of :data:`LAWS` or :data:`CAPPED_LAWS`)."""
    known = {**LAWS, **CAPPED_LAWS}
    try:
        return known[name]()
    except KeyError:
        raise ValueError(f"unknown law {name!r}; known: {', '.join(known)}") from None
