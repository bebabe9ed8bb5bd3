"""Geometric intermediates and the chain rule over them.

The contact laws are written in terms of a few intermediate quantities
(centre distance ``r``, contact normal ``n``, overlap ``delta``, its square
root ``sdelta`` and the tangential magnitude ``tn``) instead of the raw
coordinates.  Differentiating with an explicit chain rule over these symbols
keeps the derivatives in the compact, well-conditioned form a careful hand
derivation would have, and lets the code generator evaluate each intermediate
once.  ``expand_geometry`` substitutes the intermediates back, so tests can
check the chain-rule derivative against plain ``sympy.diff`` of the fully
expanded expression.

Two intermediates are chosen for numerical safety at the extremes:

* ``inv_tn`` stands for ``1/|t|`` wherever differentiation of ``|t|`` produces
  it.  In every Jacobian entry it multiplies a product ``t_a t_b`` (or ``t^2``),
  so the generated code defines ``inv_tn = 0`` at ``t = 0``, which is the
  exact limit.
* ``ny**2/r`` rather than ``(1 - nx**2)/r`` for the derivative of ``nx``, so
  there is no cancellation when ``n`` is along an axis.
"""

import sympy as sp

__all__ = [
    "CylinderPairGeometry",
    "CylinderWallGeometry",
    "PairGeometry",
    "ScalarPairGeometry",
    "WallGeometry",
    "chain_diff",
    "expand_geometry",
    "half_width",
]


class PairGeometry:
    """Intermediates of a disk-disk contact; base variables dx, dy, tx, ty.

    ``dx = x_i - x_j`` and ``dy = y_i - y_j``; ``n = (dx, dy)/r`` points from
    particle j to particle i; ``delta = R_i + R_j - r``.
    """

    def __init__(self):
        s = sp.Symbol
        self.dx, self.dy = s("dx", real=True), s("dy", real=True)
        self.tx, self.ty = s("tx", real=True), s("ty", real=True)
        self.r = s("r", positive=True)
        self.nx, self.ny = s("nx", real=True), s("ny", real=True)
        self.delta = s("delta", positive=True)
        self.sdelta = s("sdelta", positive=True)
        self.tn = s("tn", nonnegative=True)
        self.inv_tn = s("inv_tn", nonnegative=True)
        self.base = (self.dx, self.dy, self.tx, self.ty)

    def intermediates(self):
        """Ordered (symbol, definition) pairs, each in terms of earlier ones."""
        return [
            (self.r, sp.sqrt(self.dx**2 + self.dy**2)),
            (self.nx, self.dx / self.r),
            (self.ny, self.dy / self.r),
            (self.delta, sp.Symbol("Ri", positive=True) + sp.Symbol("Rj", positive=True) - self.r),
            (self.sdelta, sp.sqrt(self.delta)),
            (self.tn, sp.sqrt(self.tx**2 + self.ty**2)),
            (self.inv_tn, 1 / self.tn),
        ]

    def partials(self):
        """d(intermediate)/d(base variable), as expressions in intermediates."""
        nx, ny, r, sd = self.nx, self.ny, self.r, self.sdelta
        return {
            self.r: {self.dx: nx, self.dy: ny},
            self.nx: {self.dx: ny**2 / r, self.dy: -nx * ny / r},
            self.ny: {self.dx: -nx * ny / r, self.dy: nx**2 / r},
            self.delta: {self.dx: -nx, self.dy: -ny},
            self.sdelta: {self.dx: -nx / (2 * sd), self.dy: -ny / (2 * sd)},
            self.tn: {self.tx: self.tx * self.inv_tn, self.ty: self.ty * self.inv_tn},
            self.inv_tn: {
                self.tx: -self.tx * self.inv_tn**3,
                self.ty: -self.ty * self.inv_tn**3,
            },
        }


class ScalarPairGeometry(PairGeometry):
    """A disk-disk contact whose history is a scalar ``t`` along the tangent; base dx, dy, t.

    The frame-indifferent laws (:mod:`symbolic.frame`) keep their history on the
    current tangent line, ``t_vec = t t_hat(n)`` with ``t_hat = (n_y, -n_x)``, so
    ``|t_vec| = |t|``: ``tn = sqrt(t^2)`` as for a wall.  The geometric
    intermediates (``r``, ``n``, ``delta``, ``sdelta``) are :class:`PairGeometry`'s,
    the same symbols; ``tx``, ``ty`` are kept only so that a vector law's
    expressions can be rewritten at ``t_vec = t t_hat`` (they are no base variables).
    """

    def __init__(self):
        super().__init__()
        self.t = sp.Symbol("t", real=True)
        self.base = (self.dx, self.dy, self.t)

    def intermediates(self):
        out = [(s, d) for s, d in super().intermediates() if s not in (self.tn, self.inv_tn)]
        return out + [(self.tn, sp.sqrt(self.t**2)), (self.inv_tn, 1 / self.tn)]

    def partials(self):
        table = super().partials()
        table[self.tn] = {self.t: self.t * self.inv_tn}
        table[self.inv_tn] = {self.t: -self.t * self.inv_tn**3}
        return table


class WallGeometry:
    """Intermediates of a disk on the flat substrate y = 0; base variables y, t.

    The normal is the unit vector y-hat, ``delta = R - y`` and the tangential
    displacement is a scalar ``t`` along x-hat.
    """

    def __init__(self):
        s = sp.Symbol
        self.y = s("y", real=True)
        self.t = s("t", real=True)
        self.delta = s("delta", positive=True)
        self.sdelta = s("sdelta", positive=True)
        self.tn = s("tn", nonnegative=True)
        self.inv_tn = s("inv_tn", nonnegative=True)
        self.base = (self.y, self.t)

    def intermediates(self):
        return [
            (self.delta, sp.Symbol("R", positive=True) - self.y),
            (self.sdelta, sp.sqrt(self.delta)),
            (self.tn, sp.sqrt(self.t**2)),
            (self.inv_tn, 1 / self.tn),
        ]

    def partials(self):
        return {
            self.delta: {self.y: sp.Integer(-1)},
            self.sdelta: {self.y: -1 / (2 * self.sdelta)},
            self.tn: {self.t: self.t * self.inv_tn},
            self.inv_tn: {self.t: -self.t * self.inv_tn**3},
        }


class CylinderPairGeometry:
    """Disk-disk contact with the Hertz cylinder width; base variables dx, dy.

    Same ``dx, dy, r, n, delta`` as :class:`PairGeometry`, plus two implicit
    intermediates of the Hertz law for cylinders (Johnson 1985, Lee & Hurley
    Eq. A2):

    * ``lam = ln(4 R_i/a) + ln(4 R_j/a) - 1`` solving
      ``lam - ln lam = ln(4 (R_i + R_j)/delta) - 1`` (the generated code calls
      ``fricstab._numerics.cylinder_lambda``); implicit differentiation gives
      ``d lam/d delta = -lam / ((lam - 1) delta)``;
    * ``hw = a``, the contact half-width, ``4 sqrt(R_i R_j) exp(-(lam + 1)/2)``
      by the definition of lam, computed as ``sqrt(4 R* delta/lam)`` (Eq. A2
      solved for a, ``R* = R_i R_j/(R_i + R_j)``): the same number at the
      root, one square root and no exponential, and better conditioned (a
      relative error e of lam moves it by e/2, not by e lam/2).

    :meth:`intermediates` defines ``lam`` in closed form through the lower
    branch of Lambert W, ``lam = -W_{-1}(-e delta/(4 (R_i + R_j)))``, so that
    :func:`expand_geometry` yields an expression ``sympy.diff`` can check the
    implicit derivative against.  The tangential and rolling histories are not
    base variables here: the laws differentiate through their capped values
    explicitly (see ``symbolic.laws.lee_hurley_pair``).
    """

    def __init__(self):
        s = sp.Symbol
        self.dx, self.dy = s("dx", real=True), s("dy", real=True)
        self.r = s("r", positive=True)
        self.nx, self.ny = s("nx", real=True), s("ny", real=True)
        self.delta = s("delta", positive=True)
        self.lam = s("lam", positive=True)
        self.hw = s("hw", positive=True)
        self.base = (self.dx, self.dy)

    def intermediates(self):
        ri, rj = sp.Symbol("Ri", positive=True), sp.Symbol("Rj", positive=True)
        return [
            (self.r, sp.sqrt(self.dx**2 + self.dy**2)),
            (self.nx, self.dx / self.r),
            (self.ny, self.dy / self.r),
            (self.delta, ri + rj - self.r),
            (self.lam, -sp.LambertW(-sp.E * self.delta / (4 * (ri + rj)), -1)),
            (self.hw, half_width(ri, rj, self.delta, self.lam)),
        ]

    def partials(self):
        nx, ny, r = self.nx, self.ny, self.r
        # d lam/d delta = -lam/((lam - 1) delta) and d delta/d(dx, dy) = -n
        dlam = self.lam / ((self.lam - 1) * self.delta)
        return {
            self.r: {self.dx: nx, self.dy: ny},
            self.nx: {self.dx: ny**2 / r, self.dy: -nx * ny / r},
            self.ny: {self.dx: -nx * ny / r, self.dy: nx**2 / r},
            self.delta: {self.dx: -nx, self.dy: -ny},
            self.lam: {self.dx: dlam * nx, self.dy: dlam * ny},
            self.hw: {self.dx: -self.hw * dlam * nx / 2, self.dy: -self.hw * dlam * ny / 2},
        }


class CylinderWallGeometry:
    """Disk on the flat wall y = 0 with the Hertz cylinder width; base variable y.

    The kinematics is that of a flat wall (``delta = R - y``, normal y-hat,
    never rotating), while the contact width is that of two cylinders of radii
    ``R`` and ``Rw`` (the wall's radius of curvature, a law parameter): a 2D
    Hertz contact on a half-space has no finite stiffness without a reference
    length.  Same implicit intermediates as :class:`CylinderPairGeometry` with
    ``(R_i, R_j) = (R, Rw)``:

    * ``lam = ln(4 R/a) + ln(4 Rw/a) - 1`` solving
      ``lam - ln lam = ln(4 (R + Rw)/delta) - 1``
      (``fricstab._numerics.cylinder_lambda(delta, R, Rw)``), with
      ``d lam/d delta = -lam / ((lam - 1) delta)`` and ``d delta/dy = -1``;
    * ``hw = a = 4 sqrt(R Rw) exp(-(lam + 1)/2) = sqrt(4 R* delta/lam)``
      (computed in the second form, as :class:`CylinderPairGeometry`).
    """

    def __init__(self):
        s = sp.Symbol
        self.y = s("y", real=True)
        self.delta = s("delta", positive=True)
        self.lam = s("lam", positive=True)
        self.hw = s("hw", positive=True)
        self.base = (self.y,)

    def intermediates(self):
        r, rw = sp.Symbol("R", positive=True), sp.Symbol("Rw", positive=True)
        return [
            (self.delta, r - self.y),
            (self.lam, -sp.LambertW(-sp.E * self.delta / (4 * (r + rw)), -1)),
            (self.hw, half_width(r, rw, self.delta, self.lam)),
        ]

    def partials(self):
        # d lam/dy = d lam/d delta * d delta/dy = lam/((lam - 1) delta)
        dlam = self.lam / ((self.lam - 1) * self.delta)
        return {
            self.delta: {self.y: sp.Integer(-1)},
            self.lam: {self.y: dlam},
            self.hw: {self.y: -self.hw * dlam / 2},
        }


def half_width(r1, r2, delta, lam):
    """Hertz-cylinder half-width ``a = sqrt(4 R* delta/lam)``, ``R* = R_1 R_2/(R_1 + R_2)``.

    Eq. A2, ``delta = a^2 lam/(4 R*)``, solved for ``a``: equal to
    ``4 sqrt(R_1 R_2) exp(-(lam + 1)/2)`` where lam solves it.  Kept as one
    square root (SymPy would split the root of a product of positive symbols
    into five).
    """
    return sp.Pow(4 * r1 * r2 * delta / ((r1 + r2) * lam), sp.Rational(1, 2), evaluate=False)


def chain_diff(expr, geometry, dbase):
    """Total derivative of ``expr`` along a direction given on the base variables.

    Parameters
    ----------
    expr : sympy.Expr
        Expression in base variables, intermediates and parameters.
    geometry : PairGeometry or WallGeometry
    dbase : dict
        ``{base_symbol: d(base)/d(coordinate)}``; missing entries are zero.

    Returns
    -------
    sympy.Expr
        ``sum_b (d expr/d b) dbase[b] + sum_g (d expr/d g) sum_b (d g/d b) dbase[b]``
        where the partial derivatives treat every symbol as independent.
    """
    partials = geometry.partials()
    total = sp.Integer(0)
    free = expr.free_symbols
    for b in geometry.base:
        if b in free and b in dbase:
            total += sp.diff(expr, b) * dbase[b]
    for g, table in partials.items():
        if g not in free:
            continue
        dg = sum((table[b] * dbase[b] for b in table if b in dbase), sp.Integer(0))
        if dg != 0:
            total += sp.diff(expr, g) * dg
    return total


def expand_geometry(expr, geometry):
    """Substitute every intermediate by its definition (for symbolic tests)."""
    for sym, definition in reversed(geometry.intermediates()):
        expr = expr.subs(sym, definition)
    return expr
