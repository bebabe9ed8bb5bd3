"""The linear spring-Coulomb law (LAMMPS ``gran/hooke/history`` without damping).

``linear`` (disk-disk) and ``linear_wall`` (disk on the substrate y = 0), in the
``(kn, kt, mu, t)`` family of :mod:`symbolic.laws` (conventions there):

* normal: ``F_n = k_n delta`` along ``n``;
* tangential: ``F_t = -k_t t`` with the lab-frame history ``t`` of Charan's
  increment rule (Eq. 2: the relative tangential velocity of the contact
  points, coordinates ``theta``, arms ``R_i``, ``R_j``);
* Coulomb: ``|F_t| <= mu F_n``, i.e. ``|t| <= t* = mu (k_n/k_t) delta``, by
  projecting the history: past the circle ``t <- t t*/|t|`` (LAMMPS rescales
  its shear history by ``F_n mu/|F_t|``, the same map).

LAMMPS ``pair_style gran/hooke/history kn kt 0 0 xmu 0`` (``gamman = gammat =
0``, no damping): ``F_n = kn delta``, ``F_t = -kt xi`` with ``|F_t| <= xmu F_n``;
LAMMPS's kn, kt, xmu are this law's kn, kt, mu.  (LAMMPS also rotates the
stored shear into the current tangent plane each step; here the history is
advanced by Charan's rule, whose increments are tangent, and stored as is.)

Why the family's machinery is exact for this hard cap.  ``t* = mu (kn/kt)
delta`` is the family's threshold: ``|k_t t| <= mu k_n delta`` is
``|t| <= mu (k_n/k_t) delta``, so the force kernels' rescaling onto the circle,
``project`` and ``advance`` are the projection the law asks for, unchanged.
What differs from Charan's smoothed law is the Jacobian on the circle: Charan's
force has zero radial stiffness at ``|t| = t*`` (so ``slip_scale A`` suffices),
this one has ``k_t``.  The block therefore carries the derivative of the
projected history ``t_c = t* t/|t|`` (flag ``slide`` = 1, ``slip_scale =
t*/|t|`` of the stored history)::

    dt_c/dq = slip_scale (I - t_hat t_hat^T) A + t_hat dt*/dq,
    dt*/dq  = mu (k_n/k_t) d delta/dq,          t_hat = t/|t|,

and ``A`` while sticking (``slide`` = 0).  With ``F_t = -k_t t_c`` the sliding
block is ``dF_t/dq = -mu k_n (t_hat d delta/dq + delta (I - t_hat t_hat^T) A
dq/|t|)``: the force follows the cap ``mu F_n`` and turns with the history.  A
history on the circle to rounding (``|t| >= t* (1 - 8 eps)``, the flag of
``project``) takes the sliding branch, so a projected history keeps it.
"""

import sympy as sp

from symbolic.geometry import PairGeometry, WallGeometry, chain_diff
from symbolic.laws import SLIP_SCALE, Law, _kn, _kt, _mu, _R, _Ri, _Rj, _tangent_increment

__all__ = ["SLIDE", "linear_pair", "linear_wall"]

#: Branch flag of the hard cap: 1 when the history is on the Coulomb circle
#: (to rounding), 0 while sticking.  Its presence in a Jacobian makes the
#: generated prologue use the threshold ``|t| >= t* (1 - 8 eps)``.
SLIDE = sp.Symbol("slide", nonnegative=True)

_UNITS = ("force/length", "force/length", "-")
_DOCS = ("normal stiffness: F_n = kn delta (LAMMPS gran/hooke/history kn)",
         "tangential stiffness: F_t = -kt t (LAMMPS kt; its default 2 kn/7)",
         "friction coefficient: |F_t| <= mu F_n by projecting t onto |t| = mu (kn/kt) delta "
         "(LAMMPS xmu)")


def _contact(g):
    """CONTACT: secant kn, tangential kt, no rolling, F_n = kn delta."""
    return (_kn, _kt, sp.Integer(0), _kn * g.delta)


def _capped_columns(g, geo_cols, increment, hist):
    """Per column, base derivatives with the history through its projection."""
    that = [h * g.inv_tn for h in hist]  # inv_tn = 1/|t|, 0 at t = 0 (never sliding)
    tstar = _mu * _kn / _kt * g.delta
    cols = []
    for k, geo in enumerate(geo_cols):
        radial = sum(that[b] * increment[b, k] for b in range(len(hist)))
        dtstar = chain_diff(tstar, g, geo)
        col = dict(geo)
        for a, h in enumerate(hist):
            # A scalar history has no direction to turn: (I - t_hat t_hat^T) = 0.
            along = (1 - SLIDE) * increment[a, k] if len(hist) == 1 else \
                increment[a, k] - SLIDE * that[a] * radial
            col[h] = SLIP_SCALE * along + SLIDE * that[a] * dtstar
        cols.append(col)
    return cols


def _jacobian(force, g, cols):
    return sp.Matrix([[chain_diff(c, g, col) for col in cols] for c in force])


def linear_pair():
    """Linear normal and tangential springs with a hard Coulomb cap, disk-disk."""
    g = PairGeometry()
    fn = _kn * g.delta
    ftx, fty = -_kt * g.tx, -_kt * g.ty
    fx, fy = fn * g.nx + ftx, fn * g.ny + fty
    cross = g.nx * fty - g.ny * ftx
    force = sp.Matrix([fx, fy, -_Ri * cross, -fx, -fy, -_Rj * cross])
    increment = _tangent_increment(g, _Ri, _Rj)
    geo = []
    for k in range(6):
        p, c = divmod(k, 3)
        sign = 1 if p == 0 else -1
        geo.append({g.dx: sp.Integer(sign if c == 0 else 0),
                    g.dy: sp.Integer(sign if c == 1 else 0)})
    cols = _capped_columns(g, geo, increment, (g.tx, g.ty))
    return Law(
        name="linear", kind="pair",
        summary="linear spring-Coulomb (LAMMPS gran/hooke/history, no damping): "
                "F_n = kn delta, F_t = -kt t capped at mu F_n, disk-disk; coords (x, y, theta)",
        inputs=(g.dx, g.dy, _Ri, _Rj, _kn, _kt, _mu, g.tx, g.ty),
        params=("kn", "kt", "mu"), history=(g.tx, g.ty),
        coords=("x_i", "y_i", "theta_i", "x_j", "y_j", "theta_j"),
        outputs=("Fx_i", "Fy_i", "T_i", "Fx_j", "Fy_j", "T_j"),
        force=force, increment=increment, jacobian=_jacobian(force, g, cols),
        coulomb=True, geometry=g, param_units=_UNITS, param_docs=_DOCS,
        rotation="theta", has_cap=True, partner="linear_wall", contact=_contact(g))


def linear_wall():
    """Linear springs with a hard Coulomb cap, disk on the substrate y = 0.

    ``F = (-k_t t, k_n delta)``, ``T = R F_t`` (contact point at ``-R y-hat``),
    ``dt = dx + R dtheta`` (Charan Eq. 2), ``|t| <= mu (k_n/k_t) delta``.
    """
    g = WallGeometry()
    ft = -_kt * g.t
    force = sp.Matrix([ft, _kn * g.delta, _R * ft])
    increment = sp.Matrix([[1, 0, _R]])
    geo = [{}, {g.y: sp.Integer(1)}, {}]
    cols = _capped_columns(g, geo, increment, (g.t,))
    return Law(
        name="linear_wall", kind="wall",
        summary="linear spring-Coulomb (LAMMPS gran/hooke/history, no damping), "
                "disk-substrate at y = 0; coords (x, y, theta)",
        inputs=(g.y, _R, _kn, _kt, _mu, g.t), params=("kn", "kt", "mu"),
        history=(g.t,), coords=("x", "y", "theta"), outputs=("Fx", "Fy", "T"),
        force=force, increment=increment, jacobian=_jacobian(force, g, cols),
        coulomb=True, geometry=g, param_units=_UNITS, param_docs=_DOCS,
        rotation="theta", has_cap=True, partner="linear", contact=_contact(g))
