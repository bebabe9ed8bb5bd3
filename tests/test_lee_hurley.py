"""The ``lee_hurley`` law: contact-width solver, generated blocks, caps, damping.

Error models behind the tolerances
----------------------------------
* Contact width (cylinder_lambda): a fitted start and one Newton step (the
  start's error is checked below); the backward error |delta(a) - delta|/delta is a few eps times
  the terms of ``a^2 lam/(4 R*)`` (lam <= 40): bound 64 eps.  The forward
  error of lam against Lambert W is the backward error times the condition
  number ``1/(lam - 1)`` (lam -> 1 at the turning point).
* Complex step / 50-digit differences: the float64 block differs from an
  exact reference by its own rounding, 64 eps of the terms each row sums
  (fricstab.laws.verify_lee_hurley.exact_bound).
* float64 central differences at the best step, where the column length is
  >= 1e7 ulp(r): rounding ~eps r/h and truncation (h/L)^2 both < 1e-7: 1e-6.
* Taylor test in 50 digits: slope >= 1.9 (a first-order error in K gives 1).

Both forms, the pair ``lee_hurley`` and the wall ``lee_hurley_wall``; the
2,000-case acceptance run of both is in validation/test_verification_tiers.py
(``pytest -m slow``).
"""

import math

import mpmath
import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from fricstab._numerics import (LANE_COLUMNS, contact_halfwidth, cylinder_lambda, overlap_correction,
                                pair_geometry, pair_geometry_lanes, turning_overlap)
from fricstab.generated import lee_hurley as gen
from fricstab.generated import lee_hurley_wall as gen_wall
from fricstab.laws import ParameterError, evaluate
from fricstab.laws.verify_lee_hurley import (
    CENTRAL_BOUND, LAWS, ShearCase, case_inputs, central_jacobian, central_resolvable,
    complex_step_jacobian, exact_bound, generated_jacobian, lai_kt, mp_central_jacobian,
    reference_increment, row_terms, sample_cases, taylor_slope, verify_cases)
from fricstab.laws.verify import row_relative_error
from tests.strategies import corrupt_jacobian, shear_cases

EPS = np.finfo(float).eps


def _contact(args):
    out = np.empty(9)
    (gen.lee_hurley_contact if len(args) == 10 else gen_wall.lee_hurley_wall_contact)(*args, out)
    return out


def _radii(args):
    """(R_1, R_2) of a pair (Ri, Rj) or a wall contact (R, Rw)."""
    return (args[2], args[3]) if len(args) == 10 else (args[1], args[6])


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


def test_width_start_leaves_one_newton_step():
    """The fitted start of cylinder_lambda against Lambert W, and what one Newton step leaves.

    Error model: the fit's own error (1.83e-10 (lam - 1) at most on its 3,200
    points; 2e-10 allows for the points between) plus the rounding of
    ``1 + p P/Q`` (4 eps absolute, what dominates as lam -> 1).  Newton's error
    after one step is ``e^2/(2 lam (lam - 1))``: below 1e-19 lam here, far
    under the rounding of the step itself.  Beyond the fit (B > 50, overlaps
    below 1e-20 R) the start is within 1e-6 (lam - 1) and two steps are made.
    """
    from fricstab._numerics import _START_FIT_B, _lambda_start

    bs = np.concatenate([1.0 + np.logspace(-15, 0, 150), np.linspace(2.0, _START_FIT_B, 400)])
    with mpmath.workdps(30):
        for b in bs:
            lam = -mpmath.lambertw(-mpmath.exp(-mpmath.mpf(b)), -1).real
            e0 = float(abs(_lambda_start(b) - lam))
            assert e0 <= 2e-10 * float(lam - 1) + 4 * EPS, b
            assert e0 ** 2 / (2 * float(lam * (lam - 1))) <= 1e-19 * float(lam), b
        for b in np.linspace(_START_FIT_B, 745.0, 60):
            lam = -mpmath.lambertw(-mpmath.exp(-mpmath.mpf(b)), -1).real
            assert abs(_lambda_start(b) - lam) <= 1e-6 * (lam - 1), b
    # two steps beyond the fit: at lam >> 1 the rounding of B (eps B) and of the
    # step (eps lam) bound the error: 4 eps relative
    ri, rj = 0.5, 0.7
    for delta in (1e-25, 1e-100, 1e-300):
        ref = -mpmath.lambertw(-mpmath.e * mpmath.mpf(delta) / (4 * (ri + rj)), -1).real
        assert abs(cylinder_lambda(delta, ri, rj) - ref) / ref <= 4 * EPS


_LANE = st.tuples(st.floats(-3.0, 3.0), st.floats(-3.0, 3.0), st.floats(0.2, 1.5),
                  st.floats(0.2, 1.5), st.floats(-14.0, -0.2))


@given(lanes=st.lists(_LANE, min_size=1, max_size=16), width=st.booleans())
def test_geometry_in_lanes_is_one_contacts_to_the_bit(lanes, width):
    """pair_geometry_lanes (the engine's, several contacts at once) against the scalar
    functions the force kernels call: r, the accurate overlap and lam equal to the bit,
    in lanes that touch (overlap 10^-14 .. 0.6 of the turning point) and lanes apart."""
    g = np.full((len(lanes), len(LANE_COLUMNS)), np.nan)
    for k, (x, y, ri, rj, log_rel) in enumerate(lanes):
        if x > 0.0:   # touching: an overlap of a given fraction of the turning point
            r = ri + rj - 0.6 * 10.0 ** log_rel * turning_overlap(ri, rj)
            x, y = r * math.cos(y), r * math.sin(y)
        else:         # at or beyond contact: the centres at least Ri + Rj apart in x
            x -= ri + rj
        g[k, :4] = x, y, ri, rj
    pair_geometry_lanes(g, len(lanes), width)
    for k, (x, y, ri, rj) in enumerate(g[:, :4]):
        r = np.sqrt(x * x + y * y)
        naive = ri + rj - r
        delta = naive + overlap_correction(x, y, ri, rj, naive)
        assert g[k, 4] == r and g[k, 5] == delta
        if width and delta > 0.0:
            assert g[k, 6] == cylinder_lambda(delta, ri, rj)
            assert pair_geometry(x, y, ri, rj, True) == (r, delta, g[k, 6])
        else:
            assert np.isnan(g[k, 6])


def test_geometry_in_lanes_raises_as_the_width_does():
    """A lane beyond the turning point, or with a NaN overlap, raises cylinder_lambda's error."""
    ri, rj = 0.5, 0.7
    g = np.zeros((2, len(LANE_COLUMNS)))
    g[:, 2:4] = ri, rj
    g[0, 0] = ri + rj - 0.5 * turning_overlap(ri, rj)
    g[1, 0] = ri + rj - turning_overlap(ri, rj) * (1 + 1e-9)
    with pytest.raises(ValueError, match="turning point"):
        pair_geometry_lanes(g, 2, True)
    pair_geometry_lanes(g, 2, False)   # no width: nothing to refuse
    g[1, 0] = np.nan
    with pytest.raises(ValueError, match="must be > 0"):
        pair_geometry_lanes(g, 2, True)


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

@pytest.mark.parametrize("law", LAWS)
@given(data=st.data())
def test_complex_step_agrees(law, data):
    args = case_inputs(data.draw(shear_cases(law)), law=law)
    f, jac = generated_jacobian(args)
    assert np.all(np.isfinite(f)) and np.all(np.isfinite(jac))
    jcs = complex_step_jacobian(args, reference_increment(args))
    assert row_relative_error(jac, jcs) <= exact_bound(args, jcs)


@pytest.mark.parametrize("law", LAWS)
@given(data=st.data())
@settings(max_examples=25)
def test_central_differences_agree(law, data):
    args = case_inputs(data.draw(shear_cases(law)), law=law)
    if not central_resolvable(args):
        return  # the column lengths lie below float64 resolution (see module doc)
    f, jac = generated_jacobian(args)
    jfd = central_jacobian(args, reference_increment(args), jac)
    assert row_relative_error(jac, jfd) <= CENTRAL_BOUND


@pytest.mark.parametrize("law", LAWS)
@given(data=st.data())
@settings(max_examples=20)
def test_mp50_differences_agree(law, data):
    args = case_inputs(data.draw(shear_cases(law)), law=law)
    f, jac = generated_jacobian(args)
    jmp = mp_central_jacobian(args)
    assert row_relative_error(jac, jmp) <= exact_bound(args, jmp)


@pytest.mark.parametrize("law", LAWS)
@given(data=st.data())
@settings(max_examples=20)
def test_taylor_remainder_is_second_order(law, data):
    args = case_inputs(data.draw(shear_cases(law)), law=law)
    n = 6 if law == "lee_hurley" else 3
    direction = data.draw(st.lists(st.floats(-1, 1), min_size=n, max_size=n).filter(
        lambda v: max(abs(x) for x in v) > 0.1))
    slope, errs = taylor_slope(args, direction)
    assert slope is None or slope >= 1.9, (slope, errs)


@pytest.mark.parametrize("law", LAWS)
def test_taylor_check_catches_a_wrong_jacobian(law, monkeypatch):
    import fricstab.laws.verify_lee_hurley as sv
    monkeypatch.setattr(sv, "_mp_function", corrupt_jacobian(sv._mp_function))
    case = ShearCase(1e-3, 1.3, 0.7, 0.2, 0.5, 0.01, 3.0, 0.3)
    n = 6 if law == "lee_hurley" else 3
    slope, _ = sv.taylor_slope(case_inputs(case, law=law), np.linspace(-1, 1, n) + 0.1)
    assert slope < 1.5


# --- the caps --------------------------------------------------------------------

@pytest.mark.parametrize("law", LAWS)
@given(data=st.data())
def test_caps_hold_for_any_trial_history(law, data):
    case = data.draw(shear_cases(law))
    args = case_inputs(case, law=law)
    delta, a, kn, kt, kr, fn, ftc, mrc, flag = _contact(args)
    ri, rj = _radii(args)
    rr = ri * rj / (ri + rj)
    # k_n delta and Johnson's pi E* a^2/(4 R*) agree to the solver's backward error
    assert math.isclose(fn, math.pi * a * a / (4 * rr), rel_tol=64 * EPS)
    assert math.isclose(kt, lai_kt(a, ri, rj, 1.0, case.nu), rel_tol=64 * EPS)
    assert math.isclose(kr, math.pi * rr * rr / 4, rel_tol=4 * EPS)
    assert abs(ftc) <= case.mus * fn * (1 + 4 * EPS)
    assert abs(mrc) <= case.mur * rr * fn * (1 + 4 * EPS)
    assert flag == (abs(case.t_ratio) > 1) + 2 * (abs(case.r_ratio) > 1)


def _documented_jump(args, case):
    """dF/dft_c (D_slip - D_stick) + dF/dmr_c (D_slip - D_stick) at the caps.

    D_stick = the increment rule, D_slip = mu sign(h) dF_n/dq with
    dF_n/dq = pi E*/(lam - 1) d delta/dq (implicit differentiation of A2);
    the tangential history positive, the rolling one negative (as the callers
    put them).
    """
    ri, rj = _radii(args)
    rr = ri * rj / (ri + rj)
    inc = reference_increment(args)
    lam = math.pi / _contact(args)[2]  # E* = 1: kn = pi/lam
    if len(args) == 10:
        r = math.hypot(args[0], args[1])
        nx, ny = args[0] / r, args[1] / r
        ddelta = np.array([-nx, -ny, 0.0, nx, ny, 0.0])
        dF_dft = np.array([ny, -nx, ri, -ny, nx, rj])
        dF_dmr = np.array([0, 0, 1.0, 0, 0, -1.0])
    else:
        ddelta = np.array([0.0, -1.0, 0.0])
        dF_dft = np.array([1.0, 0.0, ri])  # F = (ft_c, F_n), T = R ft_c + mr_c
        dF_dmr = np.array([0.0, 0.0, 1.0])
    dfn = math.pi / (lam - 1) * ddelta
    d_t = case.mus * dfn - inc[0]
    d_r = -case.mur * rr * dfn - inc[1]
    return np.outer(dF_dft, d_t) + np.outer(dF_dmr, d_r)


@pytest.mark.parametrize("law", LAWS)
@given(data=st.data())
def test_block_jump_at_the_caps_is_the_documented_one(law, data):
    """At |ft| = cap: force continuous; the block jumps by dF/dft_c (D_slip - D_stick).

    Likewise for the rolling spring.  Ratios 1 -/+ 1e-9: the remaining
    difference is O(1e-9) relative to the terms of a row (bound 1e-7).
    """
    case = data.draw(shear_cases(law))
    lo = case_inputs(ShearCase(**{**case.__dict__, "t_ratio": 1 - 1e-9, "r_ratio": -(1 - 1e-9)}),
                     law=law)
    hi = case_inputs(ShearCase(**{**case.__dict__, "t_ratio": 1 + 1e-9, "r_ratio": -(1 + 1e-9)}),
                     law=law)
    f0, j0 = generated_jacobian(lo)
    f1, j1 = generated_jacobian(hi)
    scale = np.abs(j0).max() + np.abs(j1).max()
    assert np.all(np.abs(f1 - f0) <= 1e-7 * np.abs(f0).max())
    assert np.all(np.abs(j1 - j0 - _documented_jump(lo, case)) <= 1e-7 * scale)
    assert _contact(hi)[5] > 0


def _on_caps(args):
    """args with both histories put on their caps by the generated project kernel."""
    if len(args) == 10:
        law, mod, geo, p, ih = "lee_hurley", gen, args[:4], args[4:8], 8
    else:
        law, mod, geo, p, ih = "lee_hurley_wall", gen_wall, args[:2], args[2:7], 7
    h = np.array(args[ih:ih + 2])
    flags = getattr(mod, f"{law}_project")(*geo, np.array(p), h)
    return tuple(args[:ih]) + (float(h[0]), float(h[1])), flags


@pytest.mark.parametrize("law", LAWS)
@given(data=st.data())
def test_a_history_exactly_on_its_cap_takes_the_sliding_branch(law, data):
    """Ratio exactly 1 (the output of a projection): the one-sided, loading derivative.

    Complex step keeps the real part exactly on the cap, so it differentiates
    the branch the real part selects: it must agree with the block to the
    exact-reference bound, and so must the sliding block from just beyond the
    cap (ratio 1 + 1e-9: an O(1e-9) difference, bound 1e-7 of the terms);
    from just inside, the block differs by the documented jump.
    """
    case = data.draw(shear_cases(law))
    beyond = ShearCase(**{**case.__dict__, "t_ratio": 2.0, "r_ratio": -2.0})
    at, flags = _on_caps(case_inputs(beyond, law=law))
    assert flags == 3
    f, jac = generated_jacobian(at)
    out = _contact(at)
    assert out[8] == 3  # both branch flags set by the kernel's own >=
    jcs = complex_step_jacobian(at, reference_increment(at), shorten=False)
    assert row_relative_error(jac, jcs) <= exact_bound(at, jcs)
    near = case_inputs(ShearCase(**{**case.__dict__, "t_ratio": 1 + 1e-9, "r_ratio": -(1 + 1e-9)}),
                       law=law)
    inside = case_inputs(ShearCase(**{**case.__dict__, "t_ratio": 1 - 1e-9,
                                      "r_ratio": -(1 - 1e-9)}), law=law)
    scale = row_terms(at)[:, None]
    assert np.all(np.abs(jac - generated_jacobian(near)[1]) <= 1e-7 * scale)
    jump = jac - generated_jacobian(inside)[1]
    assert np.all(np.abs(jump - _documented_jump(at, case)) <= 1e-7 * scale)


@pytest.mark.parametrize("law", LAWS)
@given(data=st.data())
def test_no_rolling_resistance_at_mur_zero(law, data):
    """mur = 0: cap 0, every rolling history on it: zero torque and zero block terms.

    The capped torque is +-0, so T = R ft_c exactly; the block equals that of
    a rolling spring sticking at mr = 0 (mur > 0) minus the spring's own
    term dF/dmr (x) (d mr/dq): equal up to the rounding of that one
    subtraction, 4 eps of k_r.
    """
    case = data.draw(shear_cases(law))
    mr = data.draw(st.sampled_from([0.0, 1e-9, -3.0]))
    args = list(case_inputs(ShearCase(**{**case.__dict__, "mur": 1e-3, "r_ratio": 0.0}), law=law))
    imur, imr = (7, 9) if law == "lee_hurley" else (5, 8)
    stick = tuple(args)
    args[imur], args[imr] = 0.0, mr
    f, jac = generated_jacobian(tuple(args))
    out = _contact(tuple(args))
    ftc, kr = out[6], out[4]
    ri, rj = _radii(args)
    assert out[7] == 0.0 and int(out[8]) & 2
    assert f[2] == ri * ftc
    if law == "lee_hurley":
        assert f[5] == rj * ftc
        dF_dmr = np.array([0, 0, 1.0, 0, 0, -1.0])
    else:
        dF_dmr = np.array([0.0, 0.0, 1.0])
    expect = generated_jacobian(stick)[1] - np.outer(dF_dmr, reference_increment(stick)[1])
    # the kernel's k_r and the hand-written one differ by a few eps of k_r
    assert np.all(np.abs(jac - expect) <= 8 * EPS * (np.abs(expect) + kr))


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


def test_wall_closed_forms_at_zero_history():
    """Wall, no history: F = (0, F_n), the flat wall's stiffnesses, those of cylinders R, Rw.

    kn, kt, kr are the pair law's with R_j = Rw at the same overlap (same
    expressions, an overlap 2^-10 exact in both: a few eps apart at most).  The block: dF_y/dy = -pi E*/(lam - 1) (no geometric
    term: the normal does not rotate), dF_x/dx = -k_t, dF_x/dtheta = dT/dx =
    -k_t R, dT/dtheta = -k_t R^2 - k_r, and dF_y/dx = 0: symmetric.
    """
    r, rw, delta = 0.5, 3.0, 2.0 ** -10
    args = (r - delta, r, 1.0, 0.2, 0.5, 0.01, rw, 0.0, 0.0)
    f, jac = generated_jacobian(args)
    out = _contact(args)
    pair = _contact((r + rw - delta, 0.0, r, rw, 1.0, 0.2, 0.5, 0.01, 0.0, 0.0))
    assert np.allclose(out[2:6], pair[2:6], rtol=16 * EPS, atol=0)
    lam = math.pi / out[2]
    kt, kr, fn = out[3], out[4], out[5]
    assert f[0] == 0.0 and f[2] == 0.0 and math.isclose(f[1], fn, rel_tol=4 * EPS)
    assert math.isclose(jac[1, 1], -math.pi / (lam - 1), rel_tol=1e-12)
    assert math.isclose(jac[0, 0], -kt, rel_tol=1e-14)
    assert math.isclose(jac[0, 2], -kt * r, rel_tol=1e-14)
    assert math.isclose(jac[2, 2], -kt * r * r - kr, rel_tol=1e-14)
    assert jac[1, 0] == 0.0 and jac[1, 2] == 0.0 and jac[0, 1] == 0.0
    assert np.array_equal(jac, jac.T)


@given(case=shear_cases())
def test_action_reaction_and_translation_modes(case):
    """Forces on j opposite to i; a rigid translation of the pair changes nothing.

    The translation columns cancel term by term; the remainder is the
    rounding of the terms each row sums (row_terms): 64 eps of those, not of
    the row's largest entry (a sliding row's entries can nearly cancel).
    """
    args = case_inputs(case)
    f, jac = generated_jacobian(args)
    scale = np.abs(f).max()
    assert np.allclose(f[3:5], -f[:2], rtol=0, atol=4 * EPS * scale)
    for c in range(2):
        assert np.all(np.abs(jac[:, c] + jac[:, 3 + c]) <= 64 * EPS * row_terms(args))


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
    wall = dict(y=0.49, R=0.5, E=1.0, nu=0.2, mus=0.5, mur=0.01, Rw=2.0, ft=0.0, mr=0.0)
    f, jac = evaluate("lee_hurley_wall", **wall)
    assert f.shape == (3,) and jac.shape == (3, 3) and f[1] > 0
    for key, bad in (("Rw", 0.0), ("Rw", -1.0), ("Rw", float("inf")), ("nu", 0.5)):
        with pytest.raises(ParameterError, match=key):
            evaluate("lee_hurley_wall", **{**wall, key: bad})


def _dashpot(vi, vj, mi, mj, ii, ij, damp=(0.1, 0.2, 0.3), kn=2.0, kt=1.0, kr=0.5):
    """The engine's dashpot of a contact along x (n = (1, 0), t = (0, 1)), radii 1, with the
    contact's m* and I_r as the engine computes them once per contact list."""
    from fricstab.engine.passes import _damping, effective_masses
    masses = np.zeros((1, 8))[:, 6:]   # as the engine stores them (fcon[:, 6:8])
    effective_masses(np.array([0]), np.array([1]), np.ones(2), np.array([mi, mj]),
                     np.array([ii, ij]), masses)
    out = np.zeros(4)
    _damping(1.0, 0.0, 1.0, 1.0, 1.0, 1.0, 1.0, np.array(vi, float), np.array(vj, float), kn, kt,
             kr, masses[0, 0], masses[0, 1], np.array(damp), False, out)
    return out


def test_effective_masses_of_a_wall_contact_are_those_of_an_infinite_partner():
    """A wall contact (j < 0) gets the m* and I_r of a partner with m_j = I_j = inf, to the bit."""
    from fricstab.engine.passes import effective_masses
    wall, pair = np.zeros((1, 8))[:, 6:], np.zeros((1, 8))[:, 6:]   # as in fcon[:, 6:8]
    effective_masses(np.array([0]), np.array([-1]), np.array([0.7]), np.array([1.3]),
                     np.array([0.4]), wall)
    effective_masses(np.array([0]), np.array([1]), np.array([0.7, 0.7]), np.array([1.3, np.inf]),
                     np.array([0.4, np.inf]), pair)
    assert np.array_equal(wall, pair) and wall[0, 0] == 1.0 / (1.0 / 1.3)


def test_damping_coefficients_follow_a4_a12_a20_a22():
    """The engine's dashpots (fricstab.engine.passes._damping, effective_masses) of Lee & Hurley.

    gamma_n = 2 alpha_n sqrt(kn m*) (A4), gamma_t = 2 alpha_t sqrt(kt m*) (A12),
    C_r = 2 eta_r sqrt(I_r kr) (A20, A21) with 1/m* = 1/m_i + 1/m_j (A5) and
    1/I_r = 1/(I_i + m_i R_i^2) + 1/(I_j + m_j R_j^2) (A22); a wall partner has
    m_j = I_j = inf.  Unit velocities read the coefficients off to 4 eps.
    """
    m = 0.75  # 1/(1/1 + 1/3)
    i_r = 1.0 / (1.0 / 1.5 + 1.0 / 4.5)
    g_n = -_dashpot((1, 0, 0), (0, 0, 0), 1.0, 3.0, 0.5, 1.5)[0]      # F_x = -g_n v_n
    g_t = -_dashpot((0, 1, 0), (0, 0, 0), 1.0, 3.0, 0.5, 1.5)[1]      # F_y = -g_t v_t
    rot = _dashpot((0, 0, 1), (0, 0, 0), 1.0, 3.0, 0.5, 1.5)          # v_t = -R w_i
    c_r = -(rot[2] - 1.0 * g_t * -1.0)                                 # T_i = R g_t v_t + M_d
    assert math.isclose(g_n, 0.2 * math.sqrt(2.0 * m), rel_tol=4 * EPS)
    assert math.isclose(g_t, 0.4 * math.sqrt(1.0 * m), rel_tol=4 * EPS)
    assert math.isclose(c_r, 0.6 * math.sqrt(i_r * 0.5), rel_tol=4 * EPS)
    wall = -_dashpot((1, 0, 0), (0, 0, 0), 1.0, np.inf, 0.5, np.inf)[0]
    assert math.isclose(wall, 0.2 * math.sqrt(2.0), rel_tol=4 * EPS)


@pytest.mark.parametrize("law", LAWS)
def test_symbolic_chain_rule_matches_direct_differentiation(law):
    """Stick and slide branches of the SymPy block against sympy.diff, 40 digits."""
    from symbolic.geometry import expand_geometry
    from symbolic.laws import derive

    sym = derive(law)
    g = sym.geometry
    ftc, mrc = sym.capped
    st_, sr_ = sym.slides
    ft, mr = sym.history
    eps = sp.Symbol("eps", real=True)
    vals = {sp.Symbol("E", positive=True): 1, sp.Symbol("nu", nonnegative=True): sp.Rational(1, 5),
            sp.Symbol("mus", positive=True): sp.Rational(1, 2),
            sp.Symbol("mur", nonnegative=True): sp.Rational(1, 50),
            ft: sp.Rational(1, 10000), mr: sp.Rational(-1, 10**6)}
    if law == "lee_hurley":
        vals.update({sp.Symbol("Ri", positive=True): sp.Rational(1, 2),
                     sp.Symbol("Rj", positive=True): sp.Rational(7, 10),
                     g.dx: sp.Rational(119, 100) * sp.Rational(3, 5),
                     g.dy: sp.Rational(119, 100) * sp.Rational(4, 5)})
    else:
        vals.update({sp.Symbol("R", positive=True): sp.Rational(1, 2),
                     sp.Symbol("Rw", positive=True): sp.Rational(3, 1),
                     g.y: sp.Rational(99, 200)})
    fn = expand_geometry(sym.contact[3], g)
    cap_t, cap_r = (expand_geometry(c, g) for c in sym.caps)
    inc = sym.increment.applyfunc(lambda e: expand_geometry(e, g)).subs(vals)
    nq = len(sym.coords)
    for slide_t in (0, 1):
        for slide_r in (0, 1):
            tc = cap_t if slide_t else None
            rc = cap_r if slide_r else None
            for k in range(nq):
                if law == "lee_hurley":
                    p, c = divmod(k, 3)
                    sign = 1 if p == 0 else -1
                    sub = {g.dx: g.dx + (sign * eps if c == 0 else 0),
                           g.dy: g.dy + (sign * eps if c == 1 else 0)}
                else:  # only y moves the wall geometry
                    sub = {g.y: g.y + eps} if k == 1 else {}
                ftc_e = tc.subs(sub, simultaneous=True) if tc is not None else ft + eps * inc[0, k]
                mrc_e = rc.subs(sub, simultaneous=True) if rc is not None else mr + eps * inc[1, k]
                for i in ((0, 2, 5) if law == "lee_hurley" else (0, 1, 2)):
                    force = expand_geometry(sym.force[i], g).subs(sub, simultaneous=True)
                    direct = sp.diff(force.subs({ftc: ftc_e, mrc: mrc_e}), eps).subs(eps, 0)
                    block = expand_geometry(
                        sym.jacobian[i, k].subs({st_: slide_t, sr_: slide_r}), g)
                    block = block.subs({ftc: tc if tc is not None else ft,
                                        mrc: rc if rc is not None else mr})
                    diff = sp.N((direct - block).subs(vals), 40)
                    scale = abs(sp.N(direct.subs(vals), 40)) + abs(sp.N(fn.subs(vals), 40))
                    assert abs(diff) <= 1e-30 * scale, (slide_t, slide_r, i, k)


@pytest.mark.parametrize("law", LAWS)
def test_sampled_cases_cover_every_regime(law):
    report = verify_cases(sample_cases(8, 0, law=law), 0, law=law)
    assert report["law"] == law
    assert set(report["regimes"]) == {"stick", "slide_t", "slide_r", "slide_both"}


def test_pair_sampler_draws_are_unchanged_by_the_wall_form():
    """The pair's cases (seeded) are those of the single-form sampler: same ranges, same draws."""
    a = sample_cases(20, 7)
    assert a == sample_cases(20, 7, law="lee_hurley")
    assert all(0.2 <= c.radius_ratio <= 5.0 for c in a)
