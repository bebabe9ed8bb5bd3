"""The ``lee_hurley`` law: contact-width solver, generated blocks, caps, damping.

Error models behind the tolerances
----------------------------------
* Contact width (cylinder_lambda): Newton to |step| <= 2 eps lam, then one
  correction; the backward error |delta(a) - delta|/delta is a few eps times
  the terms of ``a^2 lam/(4 R*)`` (lam <= 40): bound 64 eps.  The forward
  error of lam against Lambert W is the backward error times the condition
  number ``1/(lam - 1)`` (lam -> 1 at the turning point).
* Complex step / 50-digit differences: the float64 block differs from an
  exact reference by its own rounding, 64 eps of the terms each row sums
  (fricstab.laws.verify_lee_hurley.exact_bound).
* float64 central differences at the best step, where the column length is
  >= 1e7 ulp(r): rounding ~eps r/h and truncation (h/L)^2 both < 1e-7: 1e-6.
* Taylor test in 50 digits: slope >= 1.9 (a first-order error in K gives 1).
"""

import math

import mpmath
import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from fricstab._numerics import contact_halfwidth, cylinder_lambda, turning_overlap
from fricstab.generated import lee_hurley as gen
from fricstab.laws import ParameterError, evaluate
from fricstab.protocols.shear_law import damping_coefficients
from fricstab.laws.verify_lee_hurley import (
    CENTRAL_BOUND, EXTREMES, ShearCase, case_inputs, central_jacobian, central_resolvable,
    complex_step_jacobian, exact_bound, generated_jacobian, lai_kt, mp_central_jacobian,
    reference_increment, sample_cases, taylor_slope, verify_cases)
from fricstab.laws.verify import row_relative_error
from tests.strategies import corrupt_jacobian

EPS = np.finfo(float).eps


def _ranged(key, log=True):
    lo, hi = EXTREMES[key]
    inner = st.floats(math.log(lo), math.log(hi)).map(math.exp) if log and lo > 0 else st.floats(lo, hi)
    return st.one_of(st.sampled_from([lo, hi]), inner.map(lambda v: min(max(v, lo), hi)))


def _ratio(slides):
    mag = (st.one_of(st.just(1 + 1e-6), st.just(1e3), st.floats(1 + 1e-6, 1e3)) if slides
           else st.one_of(st.just(0.0), st.just(1 - 1e-6), st.floats(0.0, 1 - 1e-6)))
    return st.tuples(mag, st.sampled_from([1.0, -1.0])).map(lambda p: p[0] * p[1])


@st.composite
def shear_cases(draw):
    """A ShearCase in any regime, reaching the ends of every range."""
    return ShearCase(
        delta_over_R=draw(_ranged("delta_over_R")), radius_ratio=draw(_ranged("radius_ratio")),
        phi=draw(st.floats(0.0, 2 * math.pi)), nu=draw(_ranged("nu", log=False)),
        mus=draw(_ranged("mus")), mur=draw(_ranged("mur")),
        t_ratio=draw(_ratio(draw(st.booleans()))), r_ratio=draw(_ratio(draw(st.booleans()))))


# --- the contact-width solver -------------------------------------------------

@given(log_rel=st.floats(-14.0, math.log10(0.999)), ratio=st.floats(0.2, 5.0))
def test_cylinder_width_solves_eq_a2(log_rel, ratio):
    ri, rj = 1.0, ratio
    delta = 10.0 ** log_rel * turning_overlap(ri, rj) if log_rel > -2 else 10.0 ** log_rel * min(ri, rj)
    lam = cylinder_lambda(delta, ri, rj)
    a = contact_halfwidth(delta, ri, rj)
    assert lam > 1.0 and a > 0.0
    with mpmath.workdps(40):
        am = mpmath.mpf(a)
        rs = mpmath.mpf(ri) * rj / (ri + rj)
        back = am ** 2 / (4 * rs) * (mpmath.log(4 * ri / am) + mpmath.log(4 * rj / am) - 1)
        assert abs(back - delta) / delta <= 64 * EPS
        ref = -mpmath.lambertw(-mpmath.e * mpmath.mpf(delta) / (4 * (ri + rj)), -1).real
        assert abs(lam - ref) / ref <= 64 * EPS / float(ref - 1)


@given(ratio=st.floats(0.2, 5.0))
def test_cylinder_width_is_monotonic_with_complex_step_derivative(ratio):
    ri, rj = 1.0, ratio
    deltas = np.concatenate([np.logspace(-14, -1, 40) * min(ri, rj),
                             turning_overlap(ri, rj) * (1 - np.logspace(-1, -9, 9))])
    deltas.sort()
    widths = [contact_halfwidth(d, ri, rj) for d in deltas]
    assert np.all(np.diff(widths) > 0)
    for d in deltas:
        lam = cylinder_lambda(d, ri, rj)
        h = 1e-20 * d
        cs = cylinder_lambda(complex(d, h), complex(ri), complex(rj)).imag / h
        exact = -lam / ((lam - 1) * d)  # implicit differentiation
        # the complex correction step is exact to O(h^2); rounding of its terms
        # grows with the conditioning 1/(lam - 1)
        assert abs(cs - exact) <= 64 * EPS * abs(exact) / min(1.0, lam - 1)


def test_beyond_the_turning_point_raises():
    ri, rj = 0.5, 0.7
    with pytest.raises(ValueError, match="turning point"):
        cylinder_lambda(turning_overlap(ri, rj) * (1 + 1e-12), ri, rj)
    with pytest.raises(ValueError, match="nonpositive denominator"):
        # a ~ R: Lai's fit (A9) no longer gives a positive k_t
        r = ri + rj - 0.5 * ri
        gen.lee_hurley_force_jacobian(r, 0.0, ri, rj, 1.0, 0.2, 0.5, 0.01, 0.0, 0.0,
                                      np.empty(6), np.empty((6, 6)))


# --- generated blocks against the references ----------------------------------

@given(case=shear_cases())
def test_complex_step_agrees(case):
    args = case_inputs(case)
    f, jac = generated_jacobian(args)
    assert np.all(np.isfinite(f)) and np.all(np.isfinite(jac))
    jcs = complex_step_jacobian(args, reference_increment(args))
    assert row_relative_error(jac, jcs) <= exact_bound(args, jcs)


@given(case=shear_cases())
@settings(max_examples=25)
def test_central_differences_agree(case):
    args = case_inputs(case)
    if not central_resolvable(args):
        return  # the column lengths lie below float64 resolution (see module doc)
    f, jac = generated_jacobian(args)
    jfd = central_jacobian(args, reference_increment(args), jac)
    assert row_relative_error(jac, jfd) <= CENTRAL_BOUND


@given(case=shear_cases())
@settings(max_examples=20)
def test_mp50_differences_agree(case):
    args = case_inputs(case)
    f, jac = generated_jacobian(args)
    jmp = mp_central_jacobian(args)
    assert row_relative_error(jac, jmp) <= exact_bound(args, jmp)


@given(case=shear_cases(), direction=st.lists(st.floats(-1, 1), min_size=6, max_size=6).filter(
    lambda v: max(abs(x) for x in v) > 0.1))
@settings(max_examples=20)
def test_taylor_remainder_is_second_order(case, direction):
    slope, errs = taylor_slope(case_inputs(case), direction)
    assert slope is None or slope >= 1.9, (slope, errs)


def test_taylor_check_catches_a_wrong_jacobian(monkeypatch):
    import fricstab.laws.verify_lee_hurley as sv
    monkeypatch.setattr(sv, "_mp_function", corrupt_jacobian(sv._mp_function))
    case = ShearCase(1e-3, 1.3, 0.7, 0.2, 0.5, 0.01, 3.0, 0.3)
    slope, _ = sv.taylor_slope(case_inputs(case), np.linspace(-1, 1, 6) + 0.1)
    assert slope < 1.5


# --- the caps --------------------------------------------------------------------

@given(case=shear_cases())
def test_caps_hold_for_any_trial_history(case):
    args = case_inputs(case)
    out = np.empty(9)
    gen.lee_hurley_contact(*args, out)
    delta, a, kn, kt, kr, fn, ftc, mrc, flag = out
    ri, rj = args[2], args[3]
    rr = ri * rj / (ri + rj)
    # k_n delta and Johnson's pi E* a^2/(4 R*) agree to the solver's backward error
    assert math.isclose(fn, math.pi * a * a / (4 * rr), rel_tol=64 * EPS)
    assert math.isclose(kt, lai_kt(a, ri, rj, 1.0, case.nu), rel_tol=64 * EPS)
    assert math.isclose(kr, math.pi * rr * rr / 4, rel_tol=4 * EPS)
    assert abs(ftc) <= case.mus * fn * (1 + 4 * EPS)
    assert abs(mrc) <= case.mur * rr * fn * (1 + 4 * EPS)
    assert flag == (abs(case.t_ratio) > 1) + 2 * (abs(case.r_ratio) > 1)


@given(case=shear_cases())
def test_block_jump_at_the_caps_is_the_documented_one(case):
    """At |ft| = cap: force continuous; the block jumps by dF/dft_c (D_slip - D_stick).

    D_stick = k_t d delta_t/dq (increment rule), D_slip = mu_s sign dF_n/dq;
    likewise for the rolling spring.  Ratios 1 -/+ 1e-9: the remaining
    difference is O(1e-9) relative to the terms of a row (bound 1e-7).
    """
    lo = case_inputs(ShearCase(**{**case.__dict__, "t_ratio": 1 - 1e-9, "r_ratio": -(1 - 1e-9)}))
    hi = case_inputs(ShearCase(**{**case.__dict__, "t_ratio": 1 + 1e-9, "r_ratio": -(1 + 1e-9)}))
    f0, j0 = generated_jacobian(lo)
    f1, j1 = generated_jacobian(hi)
    ri, rj = lo[2], lo[3]
    scale = np.abs(j0).max() + np.abs(j1).max()
    assert np.all(np.abs(f1 - f0) <= 1e-7 * np.abs(f0).max())
    inc = reference_increment(lo)
    nx, ny = lo[0] / math.hypot(lo[0], lo[1]), lo[1] / math.hypot(lo[0], lo[1])
    out = np.empty(9)
    gen.lee_hurley_contact(*hi, out)
    fn, rr = out[5], ri * rj / (ri + rj)
    lam = math.pi / out[2]  # E* = 1: kn = pi/lam
    # dF_n/dq = pi E*/(lam - 1) d delta/dq (implicit differentiation of A2)
    dfn = math.pi / (lam - 1) * np.array([-nx, -ny, 0.0, nx, ny, 0.0])
    d_t = case.mus * dfn - inc[0]
    d_r = -case.mur * rr * dfn - inc[1]
    dF_dft = np.array([ny, -nx, ri, -ny, nx, rj])
    dF_dmr = np.array([0, 0, 1.0, 0, 0, -1.0])
    expect = np.outer(dF_dft, d_t) + np.outer(dF_dmr, d_r)
    assert np.all(np.abs(j1 - j0 - expect) <= 1e-7 * scale)
    assert fn > 0


# --- conventions, array layer, registry, damping ---------------------------------

def test_closed_forms_at_zero_history():
    """n = x-hat, no history: hand-derived stiffnesses pin the signs."""
    ri, rj, delta = 0.5, 0.7, 1e-3
    args = (ri + rj - delta, 0.0, ri, rj, 1.0, 0.2, 0.5, 0.01, 0.0, 0.0)
    f, jac = generated_jacobian(args)
    out = np.empty(9)
    gen.lee_hurley_contact(*args, out)
    lam = math.pi / out[2]
    assert math.isclose(f[0], out[5], rel_tol=1e-15)
    # tangent normal stiffness d F_n/d delta = pi E*/(lam - 1)
    assert math.isclose(jac[0, 0], -math.pi / (lam - 1), rel_tol=1e-12)
    kt, kr = out[3], out[4]
    assert math.isclose(jac[2, 2], -kt * ri * ri - kr, rel_tol=1e-12)
    assert math.isclose(jac[5, 2], -kt * ri * rj + kr, rel_tol=1e-12)
    # transverse: -k_t plus the destabilizing geometric term +F_n/r (rotation of n)
    assert math.isclose(jac[1, 1], -kt + out[5] / (ri + rj - delta), rel_tol=1e-12)
    assert np.allclose(jac, jac.T, rtol=0, atol=1e-14 * np.abs(jac).max())


@given(case=shear_cases())
def test_action_reaction_and_translation_modes(case):
    args = case_inputs(case)
    f, jac = generated_jacobian(args)
    scale = np.abs(f).max()
    assert np.allclose(f[3:5], -f[:2], rtol=0, atol=4 * EPS * scale)
    rowscale = np.maximum(np.abs(jac).max(axis=1), 1e-300)
    for c in range(2):
        assert np.all(np.abs(jac[:, c] + jac[:, 3 + c]) <= 64 * EPS * rowscale)


def test_array_layer_matches_the_scalar_kernel():
    rng = np.random.default_rng(3)
    n = 4
    radius = rng.uniform(0.4, 0.6, n)
    pos = np.column_stack([np.cumsum(radius) * 2 - radius, np.zeros(n)])
    pos[:, 0] -= rng.uniform(1e-4, 1e-2, n).cumsum()
    contacts = np.array([[i + 1, i] for i in range(n - 1)])
    sep = pos[contacts[:, 0]] - pos[contacts[:, 1]]
    hist = rng.uniform(-1e-4, 1e-4, (n - 1, 2))
    forces, blocks = np.zeros((n, 3)), np.empty((n - 1, 6, 6))
    gen.lee_hurley_assemble(sep, radius, contacts, 1.0, 0.2, 0.5, 0.01, hist, forces, blocks)
    expect = np.zeros_like(forces)
    for c, (i, j) in enumerate(contacts):
        f, jac = generated_jacobian((sep[c, 0], sep[c, 1], radius[i], radius[j], 1.0, 0.2, 0.5,
                                     0.01, hist[c, 0], hist[c, 1]))
        expect[i] += f[:3]
        expect[j] += f[3:]
        assert np.array_equal(blocks[c], jac)
    assert np.allclose(forces, expect, rtol=1e-15, atol=0) and np.any(forces)


def test_parameters_are_checked():
    good = dict(dx=1.19, dy=0.0, Ri=0.5, Rj=0.7, E=1.0, nu=0.2, mus=0.5, mur=0.01, ft=0.0, mr=0.0)
    evaluate("lee_hurley", **good)
    for key, bad in (("nu", 0.5), ("nu", -0.1), ("E", 0.0), ("mus", -1.0), ("mur", -0.1)):
        with pytest.raises(ParameterError, match=key):
            evaluate("lee_hurley", **{**good, key: bad})


def test_damping_coefficients_follow_a4_a12_a20_a22():
    g_n, g_t, c_r = damping_coefficients(2.0, 1.0, 0.5, 1.0, 3.0, 0.5, 1.5, 1.0, 1.0,
                                         0.1, 0.2, 0.3)
    m = 0.75  # 1/(1/1 + 1/3)
    i_r = 1.0 / (1.0 / 1.5 + 1.0 / 4.5)
    assert math.isclose(g_n, 0.2 * math.sqrt(2.0 * m), rel_tol=4 * EPS)
    assert math.isclose(g_t, 0.4 * math.sqrt(1.0 * m), rel_tol=4 * EPS)
    assert math.isclose(c_r, 0.6 * math.sqrt(i_r * 0.5), rel_tol=4 * EPS)
    wall = damping_coefficients(2.0, 1.0, 0.5, 1.0, np.inf, 0.5, np.inf, 1.0, 1.0, 0.1, 0.2, 0.3)
    assert math.isclose(wall[0], 0.2 * math.sqrt(2.0), rel_tol=4 * EPS)


def test_symbolic_chain_rule_matches_direct_differentiation():
    """Stick and slide branches of the SymPy block against sympy.diff, 40 digits."""
    from symbolic.geometry import expand_geometry
    from symbolic.laws import derive

    law = derive("lee_hurley")
    g = law.geometry
    ftc, mrc = law.capped
    st_, sr_ = law.slides
    ft, mr = law.history
    eps = sp.Symbol("eps", real=True)
    vals = {sp.Symbol("Ri", positive=True): sp.Rational(1, 2),
            sp.Symbol("Rj", positive=True): sp.Rational(7, 10),
            sp.Symbol("E", positive=True): 1, sp.Symbol("nu", nonnegative=True): sp.Rational(1, 5),
            sp.Symbol("mus", positive=True): sp.Rational(1, 2),
            sp.Symbol("mur", nonnegative=True): sp.Rational(1, 50),
            g.dx: sp.Rational(119, 100) * sp.Rational(3, 5), g.dy: sp.Rational(119, 100) * sp.Rational(4, 5),
            ft: sp.Rational(1, 10000), mr: sp.Rational(-1, 10**6)}
    fn = expand_geometry(law.contact[3][1], g)
    cap_t, cap_r = (expand_geometry(c, g) for c in law.caps)
    inc = law.increment.applyfunc(lambda e: expand_geometry(e, g)).subs(vals)
    for slide_t in (0, 1):
        for slide_r in (0, 1):
            tc = cap_t if slide_t else None
            rc = cap_r if slide_r else None
            for k in range(6):
                p, c = divmod(k, 3)
                sign = 1 if p == 0 else -1
                sub = {g.dx: g.dx + (sign * eps if c == 0 else 0), g.dy: g.dy + (sign * eps if c == 1 else 0)}
                ftc_e = tc.subs(sub, simultaneous=True) if tc is not None else ft + eps * inc[0, k]
                mrc_e = rc.subs(sub, simultaneous=True) if rc is not None else mr + eps * inc[1, k]
                for i in (0, 2, 5):
                    force = expand_geometry(law.force[i], g).subs(sub, simultaneous=True)
                    direct = sp.diff(force.subs({ftc: ftc_e, mrc: mrc_e}), eps).subs(eps, 0)
                    block = expand_geometry(
                        law.jacobian[i, k].subs({st_: slide_t, sr_: slide_r}), g)
                    block = block.subs({ftc: tc if tc is not None else ft,
                                        mrc: rc if rc is not None else mr})
                    diff = sp.N((direct - block).subs(vals), 40)
                    scale = abs(sp.N(direct.subs(vals), 40)) + abs(sp.N(fn.subs(vals), 40))
                    assert abs(diff) <= 1e-30 * scale, (slide_t, slide_r, i, k)


def test_sampled_cases_cover_every_regime():
    report = verify_cases(sample_cases(8, 0), 0)
    assert set(report["regimes"]) == {"stick", "slide_t", "slide_r", "slide_both"}


@pytest.mark.slow
def test_thousands_of_cases_pass():
    report = verify_cases(sample_cases(2000, 0), 0)
    for s in report["regimes"].values():
        assert s["nonfinite"] == 0
        assert s["complex_step_above_bound"] == 0 and s["central_mp50_above_bound"] == 0
        assert s["central_above_1e-6"] == 0 and s["taylor_slope_min"] >= 1.9
