"""Frame-indifferent forms of the laws with a vector history: ``ishima_fi``, ``charan_fi``, ``linear_fi``.

The pair laws ``charan``, ``ishima`` and ``linear`` store a lab-frame vector
history ``t = (tx, ty)`` advanced by ``dt = A dq`` (``A`` of
:func:`symbolic.laws._tangent_increment`: rows ``(I - n n^T) dr`` and
``arm t_hat dq3``).  The history is never turned with the contact, so under a
large rotation of the pair it leaves the tangent line and the "tangential"
force acquires a normal part (issue 36).

In 2D a history kept on the tangent line is a scalar along
``t_hat = (n_y, -n_x)``: ``t = xi t_hat(n)``.  The frame-indifferent variant
stores ``xi`` (the symbol ``t`` of :class:`symbolic.geometry.ScalarPairGeometry`)
and advances it by the tangent component of the same increment::

    d xi = t_hat^T A dq = [t_hat_x, t_hat_y, arm_i, -t_hat_x, -t_hat_y, arm_j] . dq

(``t_hat^T (I - n n^T) = t_hat^T``, ``t_hat . t_hat = 1``; :func:`tangent_row`
derives it from ``A`` and reduces by ``n_x^2 + n_y^2 = 1``).  Its force is the
vector law's force at ``t = xi t_hat(n)`` (:func:`fi_pair` substitutes it into
the vector law's own expressions, so no formula is written twice), with
``|t| = |xi|`` in the Coulomb factor and the cap.  Under a rigid rotation of
the pair xi is carried with the contact and the tangential force is exactly
along ``t_hat``: its normal part is zero up to rounding.

Wall forms (:func:`fi_wall`): the wall normal is fixed, so the scalar wall
history is already frame-indifferent; the dispatch gives a pair law and its
wall form the same id, so each ``<law>_fi`` has a partner ``<law>_fi_wall``
with the physics of ``<law>_wall`` (the same expressions, a new name).
"""

from dataclasses import replace

import sympy as sp

from symbolic.geometry import ScalarPairGeometry, chain_diff
from symbolic.laws import SLIP_SCALE

__all__ = ["FI_SUMMARY", "fi_pair", "fi_wall", "tangent_row"]

#: Appended to the summary of every frame-indifferent law.
FI_SUMMARY = "frame-indifferent history (scalar along the tangent)"


def tangent_row(increment, nx, ny):
    """``t_hat^T A`` with ``t_hat = (n_y, -n_x)``, reduced by ``n_x^2 + n_y^2 = 1``."""
    unit = nx**2 + ny**2 - 1
    row = ny * increment[0, :] - nx * increment[1, :]
    return row.applyfunc(lambda e: sp.rem(sp.expand(e), unit, nx))


def _geometry_columns(g, dof=3):
    cols = []
    for k in range(2 * dof):
        p, c = divmod(k, dof)
        sign = 1 if p == 0 else -1
        cols.append({g.dx: sp.Integer(sign if c == 0 else 0),
                     g.dy: sp.Integer(sign if c == 1 else 0)})
    return cols


def _history_columns(vector, g, geo, increment):
    """Columns with the history's derivative: the same slip rule as the vector law."""
    free = {str(s) for s in vector.jacobian.free_symbols}
    if "slide" in free:  # a hard cap (symbolic.linear): through the projection
        from symbolic.linear import _capped_columns
        return _capped_columns(g, geo, increment, (g.t,))
    slip = SLIP_SCALE if "slip_scale" in free else sp.Integer(1)
    return [{**col, g.t: slip * increment[0, k]} for k, col in enumerate(geo)]


def fi_pair(vector):
    """The frame-indifferent form of the vector-history pair law ``vector`` (a :class:`Law`)."""
    g = ScalarPairGeometry()
    on_tangent = {g.tx: g.t * g.ny, g.ty: -g.t * g.nx}
    force = vector.force.subs(on_tangent, simultaneous=True)  # tn -> |xi| by g's definition
    increment = tangent_row(vector.increment, g.nx, g.ny)
    cols = _history_columns(vector, g, _geometry_columns(g), increment)
    jacobian = sp.Matrix([[chain_diff(c, g, col) for col in cols] for c in force])
    inputs = tuple(s for s in vector.inputs if s not in (g.tx, g.ty)) + (g.t,)
    return replace(
        vector, name=f"{vector.name}_fi", summary=f"{vector.summary}; {FI_SUMMARY}",
        inputs=inputs, history=(g.t,), force=force, increment=increment,
        jacobian=jacobian, geometry=g, partner=f"{vector.name}_fi_wall")


def fi_wall(wall):
    """The wall partner of a ``_fi`` pair law: ``wall``'s physics under a new name."""
    pair = f"{wall.partner}_fi"
    return replace(wall, name=f"{pair}_wall", partner=pair,
                   summary=f"{wall.summary}; the same law as {wall.name} (a wall history is "
                           f"a scalar along the fixed tangent: already {FI_SUMMARY})")
