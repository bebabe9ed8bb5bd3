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
``ishima``
    Hertz plus Ishima's tangential law (Eqs. 7-9, D1-D7),
    ``f_T = -k_T xi_N^{1/2} xi_T`` with the unprojected increment rule D4, in
    Ishima's generalized coordinates (x, y, l = d theta/2) with generalized
    force (F_x, F_y, F^l = 2T/d).  Ishima's Jacobian (Eq. 18) is ``-K``.
"""

from dataclasses import dataclass

import sympy as sp

from symbolic.geometry import PairGeometry, WallGeometry, chain_diff

__all__ = ["LAWS", "Law", "charan_pair", "charan_wall", "derive", "hertz_pair",
           "hertz_wall", "ishima_pair"]

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
        coulomb=False, geometry=g)


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
        coulomb=False, geometry=g)


def _tangential_pair_law(name, summary, tangential, arm_i, arm_j, coords,
                         outputs, params, coulomb):
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
        coulomb=coulomb, geometry=g)


def charan_pair():
    """Hertz + smoothed-Coulomb Mindlin, disk-disk (Charan Eqs. 1, 2, 5)."""
    def tangential(g):
        c = -_kt * g.sdelta * _smoothed_coulomb_factor(g.tn, g.delta)
        return c * g.tx, c * g.ty
    return _tangential_pair_law(
        "charan", "Hertz + smoothed-Coulomb Mindlin, disk-disk (Charan Eqs. 1, 2, 5); "
        "coords (x, y, theta)", tangential, _Ri, _Rj,
        ("x_i", "y_i", "theta_i", "x_j", "y_j", "theta_j"),
        ("Fx_i", "Fy_i", "T_i", "Fx_j", "Fy_j", "T_j"), ("kn", "kt", "mu"), True)


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
        ("Fx_i", "Fy_i", "Fl_i", "Fx_j", "Fy_j", "Fl_j"), ("kn", "kt"), False)


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
        coulomb=True, geometry=g)


LAWS = {
    "hertz": hertz_pair,
    "hertz_wall": hertz_wall,
    "charan": charan_pair,
    "charan_wall": charan_wall,
    "ishima": ishima_pair,
}


def derive(name):
    """Derive the law called ``name`` (one of :data:`LAWS`)."""
    try:
        return LAWS[name]()
    except KeyError:
        raise ValueError(f"unknown law {name!r}; known: {', '.join(LAWS)}") from None
