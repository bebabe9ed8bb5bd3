"""Property tests of the generated contact kernels (hypothesis, all laws).

Error models behind the tolerances
----------------------------------
* Complex step (h = 1e-20 L): truncation O(h^2) ~ 1e-40, no subtractive
  cancellation.  Both it and the generated block are float64 evaluations of
  expressions of ~100 operations: they differ by ~64 eps of the terms a row
  sums, i.e. 64 eps kappa of the row (kappa = cancellation_factor: normal
  against tangential stiffness, or torque terms that cancel exactly for a
  history along the normal).  Bound: max(1e-12, 64 eps kappa).
* 50-digit central differences (h = 1e-20 L): truncation < 1e-30 and
  round-off ~1e-30; what remains is the float64 rounding of the generated
  block, as above.
* float64 central differences at the best step: the floor predicted by
  :func:`fricstab.laws.verify.central_error_model` (truncation, round-off, first
  order at the C1 points t = 0 and |t| = t*, the last bit of the centre
  distance, cancellation within a row); a case may exceed the 1e-6 bound only
  within 10x of that floor.
* Taylor test over h = 1e-3 .. 1e-8 L with F and K both evaluated in 50
  digits (the generated sources): the remainder is c2 h^2 + c3 h^3 + 1e-50;
  the cubic term moves the fitted slope by ~c3/c2 1e-3 L, so the slope is at
  least 1.9 (higher where c2 vanishes along dq; a first-order error in K
  would give 1).  Where the steps cross a kink (t = 0, |t| = t*) the
  coefficient of h^2 changes but e/h^2 must stay bounded (within 10x); where
  c2 vanishes (F linear along dq) or the float64 base point lies within
  rounding of the slip kink, the remainder must stay below the block's own
  rounding, 64 eps kappa h (taylor_consistent).
"""

import itertools
import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from fricstab._numerics import overlap_correction
from fricstab.laws import LAW_NAMES, get_law
from fricstab.laws.verify_common import HARD_CAP, on_cap
from fricstab.laws.verify import (
    CENTRAL_BOUND, EXTREMES, Case, cancellation_factor, case_inputs, exact_reference_bound, central_error_model, central_jacobian,
    complex_step_jacobian, generated_jacobian, mp_central_jacobian, reference_increment,
    row_relative_error, taylor_consistent, taylor_slope, uncancelled_scale,
)
from tests.strategies import cases, corrupt_jacobian, directions

EPS = np.finfo(float).eps


def _setup(name, case):
    law = get_law(name)
    args = case_inputs(law, case)
    f, jac = generated_jacobian(law, args)
    return law, args, f, jac, reference_increment(law, args)


@pytest.mark.parametrize("name", LAW_NAMES)
@given(case=cases())
def test_complex_step_agrees(name, case):
    law, args, f, jac, inc = _setup(name, case)
    assert np.all(np.isfinite(f)) and np.all(np.isfinite(jac))
    jcs = complex_step_jacobian(law, args, inc)
    err = row_relative_error(jac, jcs)
    assert err <= exact_reference_bound(cancellation_factor(law, args, jcs))


@pytest.mark.parametrize("name", LAW_NAMES)
@given(case=cases())
def test_central_differences_agree_within_their_floor(name, case):
    law, args, f, jac, inc = _setup(name, case)
    # a hard cap's block jumps on its circle: a difference step there crosses the jump;
    # complex step (test_complex_step_agrees) checks those cases, as `fricstab verify` does
    assume(not on_cap(law, dict(zip(law.inputs, args))))
    jfd, _ = central_jacobian(law, args, inc, jac)
    err = row_relative_error(jac, jfd)
    assert err <= max(CENTRAL_BOUND, 10.0 * central_error_model(law, args, jfd))


@pytest.mark.parametrize("name", LAW_NAMES)
@given(case=cases())
@settings(max_examples=25)
def test_mp50_central_differences_agree(name, case):
    law, args, f, jac, inc = _setup(name, case)
    jmp = mp_central_jacobian(law, args, inc)
    err = row_relative_error(jac, jmp)
    assert err <= exact_reference_bound(cancellation_factor(law, args, jmp))


@pytest.mark.parametrize("name", LAW_NAMES)
@given(case=cases(), data=st.data())
@settings(max_examples=25)
def test_taylor_remainder_is_second_order(name, case, data):
    law, args, f, jac, inc = _setup(name, case)
    assume(not on_cap(law, dict(zip(law.inputs, args))))   # the jump: first order there
    direction = data.draw(directions(len(law.coords)))
    slope, errs = taylor_slope(law, args, inc, direction)
    kappa = cancellation_factor(law, args, jac)
    assert taylor_consistent(slope, errs, kappa), (slope, errs)


@pytest.mark.parametrize("name", [n for n in LAW_NAMES if get_law(n).history])
@given(case=cases())
def test_generated_increment_is_the_papers_rule(name, case):
    law = get_law(name)
    args = case_inputs(law, case)
    a = np.empty((len(law.history), len(law.coords)))
    geo = [args[law.inputs.index(k)] for k in law.inputs if k in ("dx", "dy", "Ri", "Rj", "y", "R")]
    law.increment(*geo, a)
    ref = reference_increment(law, args)
    # I - n n^T written as ny^2 versus 1 - nx^2: a few eps of the unit scale.
    assert np.max(np.abs(a - ref)) <= 8 * EPS * max(1.0, np.max(np.abs(ref)))


@pytest.mark.parametrize("name", LAW_NAMES)
def test_no_contact_gives_zero_force_and_block(name):
    law = get_law(name)
    for gap in (0.0, 1e-9, 0.3):
        v = {"kn": 1.0, "kt": 0.3, "mu": 0.5, "tx": 1e-3, "ty": -2e-3, "t": 1e-3,
             "Ri": 0.5, "Rj": 0.6, "R": 0.5, "dx": 1.1 + gap, "dy": 0.0, "y": 0.5 + gap}
        args = tuple(v[k] for k in law.inputs)
        f, jac = generated_jacobian(law, args)
        assert not f.any() and not jac.any()


PAIR_LAWS = [n for n in LAW_NAMES if get_law(n).kind == "pair"]


@pytest.mark.parametrize("name", PAIR_LAWS)
@given(case=cases())
def test_action_reaction_and_translation_zero_modes(name, case):
    law, args, f, jac, inc = _setup(name, case)
    dof = law.n_dof
    scale = np.abs(f).max()
    # Newton's third law: the forces on j are the opposite of those on i.
    assert np.allclose(f[dof:dof + 2], -f[:2], rtol=0, atol=4 * EPS * scale)
    if dof == 3:
        # Same generalized torque sign on both (T_i/R_i = T_j/R_j, or F^l equal).
        a = dict(zip(law.inputs, args))
        ri, rj = (a["Ri"], a["Rj"]) if law.coords[2].startswith("theta") else (1.0, 1.0)
        assert math.isclose(f[2] / ri, f[5] / rj, rel_tol=8 * EPS, abs_tol=8 * EPS * scale)
    # Rigid translation of the pair changes nothing (history included).
    rowscale = np.abs(jac).max(axis=1)
    for c in range(2):
        moved = jac[:, c] + jac[:, dof + c]
        assert np.all(np.abs(moved) <= 64 * EPS * np.maximum(rowscale, 1e-300))


COULOMB_LAWS = [n for n in LAW_NAMES if get_law(n).coulomb]


@pytest.mark.parametrize("name", COULOMB_LAWS)
@given(case=cases(), overshoot=st.floats(1.0, 1e6))
def test_coulomb_condition_holds_for_any_history(name, case, overshoot):
    """|F_t| <= mu F_n (Charan Eq. 4), also for a stored |t| beyond t*.

    At the circle both sides are the same product computed in different
    orders: a few eps apart; 1e-12 leaves room for thousands.
    """
    law = get_law(name)
    big = Case(**{**case.__dict__, "t_ratio": case.t_ratio * overshoot})
    args = case_inputs(law, big)
    f, _ = generated_jacobian(law, args)
    a = dict(zip(law.inputs, args))
    if law.kind == "pair":
        r = math.hypot(a["dx"], a["dy"])
        n = np.array([a["dx"], a["dy"]]) / r
        naive = a["Ri"] + a["Rj"] - r
        delta = naive + overlap_correction(a["dx"], a["dy"], a["Ri"], a["Rj"], naive)
        # the normal force of the law: Hertz kn delta^(3/2), or linear kn delta
        fn = a["kn"] * delta ** (1.0 if name in HARD_CAP else 1.5)
        ft = np.linalg.norm(f[:2] - fn * n)
    else:
        fn, ft = f[1], abs(f[0])
    assert ft <= a["mu"] * fn * (1 + 1e-12)


@pytest.mark.parametrize("name", [n for n in COULOMB_LAWS if n not in HARD_CAP])
@given(case=cases())
def test_block_is_continuous_across_the_coulomb_circle(name, case):
    """At |t| = t* the smoothed law has zero radial stiffness: stick and slip agree.

    Not for a hard cap (``linear``): its radial stiffness kt drops to 0 at the circle,
    a jump that tests/test_linear_law.py asserts."""
    law = get_law(name)
    args_in = case_inputs(law, Case(**{**case.__dict__, "t_ratio": 1 - 1e-9}))
    inside = generated_jacobian(law, args_in)
    outside = generated_jacobian(law, case_inputs(law, Case(**{**case.__dict__, "t_ratio": 1 + 1e-9})))
    # Stick (s = 1 - ds) and slip (stored s = 1 + ds, rescaled onto the
    # circle) must differ by O(ds), ds = 1e-9, not O(1) as a wrong slip branch
    # would.  The O(ds) coefficient is a ratio of the law's stiffness scales
    # within a row, e.g. 4 kt/(mu kn) for the radial stiffness
    # kt delta^{1/2} (1 + 2s - 3s^2) ~ 4 kt delta^{1/2} (1 - s) against the
    # slip stiffness ~mu kn delta^{1/2}; over the ranges it stays below ~1e2,
    # so the bound is 500 ds (1 + kt/(mu kn)), plus rounding.
    # Measured against the terms each row sums (uncancelled_scale): at mu = 1
    # with t along n the Fx row itself is O(1 - s).
    scale = uncancelled_scale(law, args_in)
    jump = np.abs(outside[1] - inside[1]).max(axis=1) / scale
    assert np.all(jump <= 5e-7 * (1 + case.kt_over_kn / case.mu) + 64 * EPS)
    a = dict(zip(law.inputs, args_in))
    delta = case.delta_over_R * (a["Ri"] if law.kind == "pair" else a["R"])
    terms = a["kn"] * delta ** 1.5 * (1 + case.mu)  # |F_n| + |F_t| at the circle
    assert np.all(np.abs(outside[0] - inside[0]) <= 5e-7 * terms + 64 * EPS * terms)


CORNERS = list(itertools.product(EXTREMES["delta_over_R"], EXTREMES["t_ratio"],
                                 EXTREMES["kt_over_kn"], EXTREMES["mu"],
                                 EXTREMES["radius_ratio"]))


@pytest.mark.parametrize("name", LAW_NAMES)
def test_every_corner_of_the_parameter_box(name):
    """All 32 combinations of the end points, several orientations: finite and exact."""
    law = get_law(name)
    for corner in CORNERS:
        for phi in (0.0, math.pi / 2, 1.0, 4.0):
            case = Case(corner[0], corner[1], phi, phi + math.pi / 2, corner[2], corner[3],
                        corner[4])
            args = case_inputs(law, case)
            f, jac = generated_jacobian(law, args)
            assert np.all(np.isfinite(f)) and np.all(np.isfinite(jac)), case
            inc = reference_increment(law, args)
            jcs = complex_step_jacobian(law, args, inc)
            err = row_relative_error(jac, jcs)
            assert err <= exact_reference_bound(cancellation_factor(law, args, jcs)), case


def test_closed_forms_at_zero_history():
    """Hand-derived values pin the sign conventions (see validation/errata.md).

    n = x-hat, t = 0: dFx_i/dx_i = -(3/2) kn delta^{1/2} (Hertz), and the
    rotational stiffness dT_i/dtheta_i = -kt delta^{1/2} R_i^2, i.e.
    dT~/dtheta~ = -kt delta^{1/2} in Charan's scaled coordinates (the remark
    after Charan SM Eq. 27 prints it with a + sign); for the wall
    dT/dtheta = -kt delta^{1/2} R^2 too, and Ishima's dF^l_i/dl_i = -kT xi^{1/2}.
    """
    kn, kt, ri, rj, delta = 2.0, 0.7, 0.5, 0.6, 1e-3
    sd = math.sqrt(delta)
    pair = {"dx": ri + rj - delta, "dy": 0.0, "Ri": ri, "Rj": rj, "kn": kn, "kt": kt,
            "mu": 10.0, "tx": 0.0, "ty": 0.0}
    for name in ("hertz", "charan", "ishima"):
        law = get_law(name)
        f, jac = generated_jacobian(law, tuple(pair[k] for k in law.inputs))
        assert math.isclose(jac[0, 0], -1.5 * kn * sd, rel_tol=1e-12)
        if name == "charan":
            assert math.isclose(jac[2, 2], -kt * sd * ri * ri, rel_tol=1e-12)
            assert math.isclose(jac[5, 5], -kt * sd * rj * rj, rel_tol=1e-12)
        if name == "ishima":
            assert math.isclose(jac[2, 2], -kt * sd, rel_tol=1e-12)
    law = get_law("charan_wall")
    f, jac = generated_jacobian(law, (ri - delta, ri, kn, kt, 10.0, 0.0))
    assert math.isclose(f[1], kn * delta * sd, rel_tol=1e-12)
    assert math.isclose(jac[1, 1], -1.5 * kn * sd, rel_tol=1e-12)
    assert math.isclose(jac[2, 2], -kt * sd * ri * ri, rel_tol=1e-12)
    assert math.isclose(jac[0, 0], -kt * sd, rel_tol=1e-12)
    # Ishima at the wall, l = R theta: dF_x/dx = dF_x/dl = dF^l/dl = -kT xi^{1/2}
    law = get_law("ishima_wall")
    f, jac = generated_jacobian(law, (ri - delta, ri, kn, kt, 0.0))
    assert math.isclose(f[1], kn * delta * sd, rel_tol=1e-12) and f[0] == f[2] == 0.0
    assert math.isclose(jac[1, 1], -1.5 * kn * sd, rel_tol=1e-12)
    for a, b in ((0, 0), (0, 2), (2, 0), (2, 2)):
        assert math.isclose(jac[a, b], -kt * sd, rel_tol=1e-12)


def test_ishima_wall_is_charan_wall_in_l_without_the_limit():
    """With |t| << t* and F^l = T/R, l = R theta: Ishima's wall block is Charan's rescaled.

    Charan's smoothed factor 1 + s - s^2 with s = |t|/t* ~ 1e-12 (mu = 1e9)
    differs from 1 by ~1e-12; columns theta -> l divide by R, rows T -> T/R
    too: the blocks agree to 1e-9 of each entry's scale.
    """
    kn, kt, r, delta, t = 2.0, 0.7, 0.5, 1e-3, 3e-5
    f_i, j_i = generated_jacobian(get_law("ishima_wall"), (r - delta, r, kn, kt, t))
    f_c, j_c = generated_jacobian(get_law("charan_wall"), (r - delta, r, kn, kt, 1e9, t))
    scale = np.diag([1.0, 1.0, 1.0 / r])
    assert np.allclose(scale @ f_c, f_i, rtol=1e-9, atol=0)
    assert np.allclose(scale @ j_c @ scale, j_i, rtol=1e-9, atol=1e-12 * np.abs(j_i).max())


@pytest.mark.parametrize("name", [n for n in LAW_NAMES if get_law(n).assemble is not None])
def test_array_layer_matches_the_scalar_kernel(name):
    """The generated loop over contacts accumulates what the scalar kernel gives.

    Only the laws whose loops modules outside the laws still import keep one
    (symbolic.codegen.LEGACY_ASSEMBLE); the engine assembles the others.
    """
    law = get_law(name)
    rng = np.random.default_rng(5)
    n = 4
    pos = np.column_stack([np.arange(n) * 0.99, 0.5 - rng.uniform(1e-4, 1e-2, n)])
    radius = np.full(n, 0.5)
    params = {"kn": 2.0, "kt": 0.5, "mu": 3.0}
    pvals = [params[p] for p in law.params]
    nh = len(law.history)
    forces = np.zeros((n, law.n_dof))
    if law.kind == "pair":
        contacts = np.array([[i, i + 1] for i in range(n - 1)])
        sep = pos[contacts[:, 0]] - pos[contacts[:, 1]]
        hist = rng.uniform(-1e-4, 1e-4, (len(contacts), nh))
        blocks = np.empty((len(contacts), 2 * law.n_dof, 2 * law.n_dof))
        law.assemble(sep, radius, contacts, *pvals, *([hist] if nh else []), forces, blocks)
        expect = np.zeros_like(forces)
        for c, (i, j) in enumerate(contacts):
            args = (sep[c, 0], sep[c, 1], 0.5, 0.5, *pvals, *hist[c])
            f, jac = generated_jacobian(law, args)
            expect[i] += f[:law.n_dof]
            expect[j] += f[law.n_dof:]
            assert np.array_equal(blocks[c], jac)
    else:
        contacts = np.arange(n)
        hist = rng.uniform(-1e-4, 1e-4, (n, nh))
        blocks = np.empty((n, law.n_dof, law.n_dof))
        law.assemble(pos, radius, contacts, *pvals, *([hist] if nh else []), forces, blocks)
        expect = np.zeros_like(forces)
        for c in contacts:
            f, jac = generated_jacobian(law, (pos[c, 1], 0.5, *pvals, *hist[c]))
            expect[c] += f
            assert np.array_equal(blocks[c], jac)
    assert np.allclose(forces, expect, rtol=1e-15, atol=0)
    assert np.any(forces)


@pytest.mark.parametrize("name", LAW_NAMES)
def test_taylor_check_catches_a_wrong_jacobian(name, monkeypatch):
    """Mutation test: K off by 1e-3 (relative) must fail taylor_consistent."""
    import fricstab.laws.verify as verify

    monkeypatch.setattr(verify, "_mp_function", corrupt_jacobian(verify._mp_function))
    law = get_law(name)
    case = Case(1e-3, 0.5, 0.7, 0.7 + math.pi / 2, 0.3, 2.0, 1.2)
    args = case_inputs(law, case)
    f, jac = generated_jacobian(law, args)
    direction = np.linspace(-1.0, 1.0, len(law.coords)) + 0.1
    slope, errs = taylor_slope(law, args, reference_increment(law, args), direction)
    assert not taylor_consistent(slope, errs, cancellation_factor(law, args, jac))
