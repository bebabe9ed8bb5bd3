"""The SymPy derivations: chain rule against plain differentiation, exactly.

For every law, the Jacobian written by the explicit chain rule over the
geometric intermediates (symbolic/geometry.py) must equal ``sympy.diff`` of the
fully expanded force along each coordinate, with the history advanced by the
increment rule, at exact rational points: the difference is exactly zero.
"""

import random

import pytest
import sympy as sp

from symbolic.geometry import PairGeometry, expand_geometry
from symbolic.laws import LAWS, SLIP_SCALE, derive


def _point(law, exprs, rng):
    vals = {}
    for e in exprs:
        for s in e.free_symbols:
            vals.setdefault(s, sp.Rational(rng.randint(1, 90), 97))
    names = {str(s): s for s in vals}
    if isinstance(law.geometry, PairGeometry):
        vals[names["dx"]], vals[names["dy"]] = sp.Rational(3, 4), sp.Rational(-1, 2)
        vals[names["Ri"]], vals[names["Rj"]] = sp.Rational(1, 2), sp.Rational(2, 5)
    else:
        vals[names["y"]], vals[names["R"]] = sp.Rational(9, 20), sp.Rational(1, 2)
    if "slip_scale" in names:
        vals[SLIP_SCALE] = 1  # the sticking branch: the plain derivative
    return vals


@pytest.mark.parametrize("name", list(LAWS))
def test_chain_rule_equals_direct_differentiation(name):
    law = derive(name)
    g = law.geometry
    force = law.force.applyfunc(lambda e: expand_geometry(e, g))
    jac = law.jacobian.applyfunc(lambda e: expand_geometry(e, g))
    inc = law.increment.applyfunc(lambda e: expand_geometry(e, g))
    eps = sp.Symbol("eps", real=True)
    vals = _point(law, list(force) + list(jac) + list(inc), random.Random(7))
    nq = jac.shape[1]
    for k in range(nq):
        sub = {}
        if isinstance(g, PairGeometry):
            dof = nq // 2
            p, c = divmod(k, dof)
            sign = 1 if p == 0 else -1
            if c == 0:
                sub[g.dx] = g.dx + sign * eps
            if c == 1:
                sub[g.dy] = g.dy + sign * eps
        elif law.coords[k] == "y":
            sub[g.y] = g.y + eps
        for a, h in enumerate(law.history):
            sub[h] = h + eps * inc[a, k]
        for i in range(jac.shape[0]):
            direct = sp.diff(force[i].subs(sub, simultaneous=True), eps).subs(eps, 0)
            diff = sp.nsimplify(sp.N((direct - jac[i, k].subs(SLIP_SCALE, 1)).subs(vals), 60),
                                tolerance=1e-50)
            assert diff == 0, (name, i, k)


@pytest.mark.parametrize("name", [n for n in LAWS if derive(n).kind == "pair"])
def test_action_reaction_symbolically(name):
    law = derive(name)
    dof = len(law.coords) // 2
    for c in range(2):
        assert sp.simplify(law.force[dof + c] + law.force[c]) == 0


def test_unknown_law_is_named():
    with pytest.raises(ValueError, match="unknown law 'nope'"):
        derive("nope")
