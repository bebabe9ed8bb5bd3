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
from symbolic.linear import SLIDE


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
            # the sticking branch (linear's hard cap: slide = 0; its sliding block is
            # checked by complex step in tests/test_linear_law.py and fricstab verify)
            stick = jac[i, k].subs({SLIP_SCALE: 1, SLIDE: 0})
            diff = sp.nsimplify(sp.N((direct - stick).subs(vals), 60),
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


def test_wall_cylinder_geometry_partials_are_the_derivatives_of_its_definitions():
    """d lam/dy and d hw/dy of CylinderWallGeometry against sympy.diff of the Lambert W form."""
    from symbolic.geometry import CylinderWallGeometry, chain_diff

    g = CylinderWallGeometry()
    vals = {sp.Symbol("R", positive=True): sp.Rational(1, 2),
            sp.Symbol("Rw", positive=True): sp.Rational(7, 3), g.y: sp.Rational(97, 200)}
    for sym in (g.delta, g.lam, g.hw):
        direct = sp.diff(expand_geometry(sym, g), g.y)
        chain = expand_geometry(chain_diff(sym, g, {g.y: sp.Integer(1)}), g)
        diff = sp.N((direct - chain).subs(vals), 50)
        assert abs(diff) <= 1e-40 * abs(sp.N(direct.subs(vals), 50)), sym


@pytest.mark.parametrize("name", ["hertz", "hertz_wall", "charan", "charan_wall", "ishima",
                                  "ishima_wall"])
def test_contact_quantities_of_a_hand_computed_hertz_contact(name):
    """(dx, dy) = (24/25, 7/25), r = 1, R = 13/25: delta = 1/25, sqrt(delta) = 1/5
    (wall: y = 12/25); kn = 3, kt = 2: CONTACT = (3/5, 2/5 or 0, 0, 3/125), exactly."""
    law = derive(name)
    g = law.geometry
    vals = {sp.Symbol("kn", positive=True): 3, sp.Symbol("kt", positive=True): 2,
            sp.Symbol("mu", positive=True): 1}
    if isinstance(g, PairGeometry):
        vals.update({g.dx: sp.Rational(24, 25), g.dy: sp.Rational(7, 25),
                     sp.Symbol("Ri", positive=True): sp.Rational(13, 25),
                     sp.Symbol("Rj", positive=True): sp.Rational(13, 25)})
    else:
        vals.update({g.y: sp.Rational(12, 25), sp.Symbol("R", positive=True): sp.Rational(13, 25)})
    got = [sp.nsimplify(sp.simplify(expand_geometry(e, g).subs(vals))) for e in law.contact]
    kt = sp.Rational(2, 5) if law.history else 0
    assert got == [sp.Rational(3, 5), kt, 0, sp.Rational(3, 125)]
    # the normal force is F_n: the force's normal component at zero history
    fn = law.contact[3]
    if law.kind == "wall":
        zero = {h: 0 for h in law.history}
        assert sp.simplify(law.force[1].subs(zero) - fn) == 0


@pytest.mark.parametrize("name", list(LAWS) + ["lee_hurley", "lee_hurley_wall"])
def test_metadata_of_every_law(name):
    from symbolic.laws import CONTACT, derive as d

    law = d(name)
    assert len(law.params) == len(law.param_units) == len(law.param_docs)
    assert set(law.params) <= {str(s) for s in law.inputs}
    assert len(law.contact) == len(CONTACT) == 4
    assert law.n_dof == (3 if law.rotation else 2)
    partner = d(law.partner)
    assert partner.partner == name and partner.kind != law.kind
    assert partner.has_cap == law.has_cap and partner.rotation == law.rotation
