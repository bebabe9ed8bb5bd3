"""Rigidity of frictional packings on the engine: theory (solve, mode sum) against step strain.

Preconditions first (force balance, zero modes, symmetry of the unstrained
Jacobian), then values.  Tolerances come from the error models stated in
:mod:`fricstab.protocols.stepstrain` (step strain) and from ``eps * cond(J)``
(linear algebra).
"""

import numpy as np
import pytest

from fricstab.analysis.dos import dos, log_bins, participation, rotational_peak, spectrum
from fricstab.analysis.rigidity import (ishima_flipped, linear_response, mode_sum, rigidity,
                                        solve_nonaffine, zero_modes)
from fricstab.engine import jacobian
from fricstab.laws import ParameterError
from fricstab.protocols.stepstrain import step_strain, strain
from fricstab.scenes.packing import make_packing
from fricstab.scenes.packing_friction import (backbone, frictional, material, rattler_mask,
                                              with_kt)

EPS = np.finfo(float).eps
LAWS = ("hertz", "ishima", "charan", "lee_hurley")


@pytest.fixture(scope="module")
def bb():
    return backbone(make_packing(64, 0.88, seed=0))


def _ishima(bb, kt):
    fr = frictional(bb, with_kt(material("ishima"), kt))
    return fr.system, fr.state


def _cond(jac):
    w = np.sort(np.abs(np.linalg.eigvalsh(jac.toarray())))[2:]
    return w[-1] / w[0]


def test_backbone_is_force_balanced_and_rigid(bb):
    for kt in (0.0, 1e-4, 1.0):
        r = rigidity(*_ishima(bb, kt))
        assert r.checks["max_force"] < 1e-14
        assert r.g_a > 0 and r.g > 0


@pytest.mark.parametrize("kt", [0.0, 1e-8, 1.0, 10.0])
def test_translations_are_zero_modes(bb, kt):
    # App. C: J e_x = J e_y = 0 and e^T J = 0 (total force), to round-off:
    # each entry sums O(z) terms of size max|J|, so a few eps relative.
    jac = linear_response(*_ishima(bb, kt)).jacobian
    c = zero_modes(bb.n, 3 if kt > 0 else 2) * np.sqrt(bb.n)
    scale = abs(jac).max()
    assert np.abs(jac @ c).max() <= 32 * EPS * scale
    assert np.abs(jac.T @ c).max() <= 32 * EPS * scale


@pytest.mark.parametrize("kt", [1e-8, 1e-4, 1.0, 10.0])
def test_solve_and_mode_sums_agree(bb, kt):
    r = rigidity(*_ishima(bb, kt), modes=True, route="symmetric")
    assert r.checks["modes_asymmetry"] < 1e-14  # history zero: J symmetric
    g_dense, info = mode_sum(r.jacobian, r.xi, r.theta, bb.box, 3, route="dense")
    assert info["biorthonormality"] < 1e-8
    assert info["zero_mode_span_error"] < 1e-6
    # Backward-stable LU and eigensolvers: relative error <= c eps cond(J).
    tol = 1e3 * EPS * _cond(r.jacobian)
    scale = abs(r.g_a)
    assert abs(r.g_na_modes - r.g_na_solve) <= tol * scale
    assert abs(g_dense - r.g_na_solve) <= tol * scale


@pytest.mark.parametrize("kt", [0.0, 1e-4, 1.0, 10.0])
def test_step_strain_matches_theory(bb, kt):
    system, state = _ishima(bb, kt)
    r = rigidity(system, state)
    s = step_strain(system, state, dgamma=1e-6)
    assert s.contacts_changed == 0
    # The error model of step_strain bounds |g - G|; and it is below 1 %.
    assert abs(s.g - r.g) <= s.error
    assert s.error < 1e-2 * abs(r.g)
    # Nonaffine rates (Eqs. 10-13) against J u = Xi (Eq. 38), same model per dof.
    scale = np.abs(r.u).max()
    assert np.abs(s.nonaffine.ravel() - r.u).max() < 1e-3 * scale


@pytest.mark.parametrize("law", LAWS)
def test_every_law_theory_matches_step_strain(bb, law):
    """Any law in the packing, with its defaults: friction switched on at a force-balanced
    state with zero histories (lee_hurley relaxed under its normal force first), then the
    three routes.  Same error model as above; the mode sum to eps cond(J)."""
    fr = frictional(bb, material(law))
    assert fr.residual < 1e-14 and not fr.state.contacts.hist.any()
    assert (fr.normal_iterations > 0) == (law == "lee_hurley")
    r = rigidity(fr.system, fr.state, modes=True)
    s = step_strain(fr.system, fr.state, dgamma=1e-6)
    assert r.checks["zero_mode_residual"] < 1e-14 and r.g > 0
    assert abs(s.g - r.g) <= s.error < 1e-2 * abs(r.g)
    assert abs(r.g_na_modes - r.g_na_solve) <= 1e3 * EPS * _cond(r.jacobian) * abs(r.g_a)


def test_charan_and_ishima_agree_at_zero_history(bb):
    """Same kt, zero histories: the tangential stiffness of both is kt delta^(1/2) and the
    smoothed-Coulomb term of charan has zero slope at t = 0, so in Ishima's coordinates
    (l = R theta) the Jacobians are equal up to the round-off of two generated
    expressions (a few eps of max|J| per entry) and G to eps cond(J)."""
    a = linear_response(*_ishima(bb, 1.0))
    fr = frictional(bb, material("charan", kt=1.0))
    b = linear_response(fr.system, fr.state)
    scale = abs(a.jacobian).max()
    assert abs(a.jacobian - b.jacobian).max() <= 64 * EPS * scale
    assert np.abs(a.xi - b.xi).max() <= 64 * EPS * np.abs(a.xi).max()
    ga = rigidity(*_ishima(bb, 1.0)).g
    gb = rigidity(fr.system, fr.state).g
    assert abs(ga - gb) <= 1e3 * EPS * _cond(a.jacobian) * abs(ga)


def test_lee_hurley_switch_is_balanced_with_symmetric_jacobian(bb):
    """The normal-force relaxation lands on F(q, h = 0) = 0: friction switched on with zero
    histories is balanced, no contact sits on a cap, and J is symmetric (App. H)."""
    fr = frictional(bb, material("lee_hurley"))
    assert fr.switch_residual > 1e-6          # Hertz's balance is not the law's
    assert fr.residual < 1e-14 and not fr.state.contacts.flag.any()
    jac = linear_response(fr.system, fr.state).jacobian
    assert spectrum(jac, vectors=False).asymmetry < 1e-14


def test_printed_modified_jacobian_disagrees_with_simulation(bb):
    # Eqs. 36-37 flip signs; J~ = J (errata.md) is what step strain confirms.
    system, state = _ishima(bb, 1.0)
    r = rigidity(system, state)
    s = step_strain(system, state, dgamma=1e-6)
    u, _ = solve_nonaffine(ishima_flipped(r.jacobian), r.xi, bb.n, 3)
    g_flipped = r.g_a - r.theta @ u / bb.box**2
    assert abs(g_flipped - s.g) > 100 * s.error


def test_frictionless_limit_is_smooth(bb):
    g0 = rigidity(*_ishima(bb, 0.0)).g
    d = [rigidity(*_ishima(bb, kt)).g - g0 for kt in (1e-10, 1e-8, 1e-6)]
    # G(kt) = G(0) + G'(0) kt + O(kt^2): differences scale linearly in kt.
    assert abs(d[2]) < 1e-2 * g0
    assert d[1] / d[2] == pytest.approx(1e-2, rel=0.05)
    assert d[0] / d[2] == pytest.approx(1e-4, rel=0.05)


def test_strained_state_has_history_and_nonsymmetric_jacobian(bb):
    system, state = _ishima(bb, 1.0)
    out, res = strain(system, state, 1e-4)
    assert res.converged and np.abs(out.contacts.hist).max() > 0
    assert out.shift == pytest.approx(1e-4 * bb.box)
    sp = spectrum(jacobian(system, out)[1])
    assert sp.route == "dense" and sp.asymmetry > 1e-12


def test_dos_and_participation(bb):
    r = rigidity(*_ishima(bb, 1e-6))
    sp = spectrum(r.jacobian)
    assert sp.route == "symmetric"
    psi_t, psi_r, p = participation(sp.right, 3)
    np.testing.assert_allclose(psi_t + psi_r, 1.0, atol=1e-12)
    assert np.all((p > 0) & (p <= 1 + 1e-12))
    om = sp.omega[2:]  # the two translations first (eigenvalues ~ 0)
    edges = log_bins(om.min() / 2, om.max() * 2)
    d = dos(om, bb.n_total, edges)
    assert (d * np.diff(edges)).sum() == pytest.approx(len(om) / (3 * bb.n_total))
    # A rotation-dominated band sits near sqrt(kt) (in units of 1/t0).
    peak, median = rotational_peak(om, psi_r[2:])
    assert 0.05 < median / np.sqrt(1e-6) < 5


def test_rattlers_removed_iteratively():
    # 0-1-2 chain hanging on a triangle 3-4-5-6 (each with 3 contacts).
    pairs = np.array([[0, 1], [1, 2], [2, 3], [3, 4], [3, 5], [4, 5], [4, 6], [5, 6], [3, 6]])
    mask = rattler_mask(pairs, 7, z_th=2)
    assert mask.tolist() == [True, True, True, False, False, False, False]


def test_bad_input_is_rejected(bb):
    for bad in (-1.0, float("nan")):
        with pytest.raises(ParameterError, match="kt"):
            with_kt(material("ishima"), bad)
    with pytest.raises(ParameterError, match="has no kt"):
        with_kt(material("lee_hurley"), 1.0)
    with pytest.raises(ParameterError, match="mu is not a parameter of law ishima"):
        material("ishima", mu=0.5)
    with pytest.raises(ParameterError, match="dgamma"):
        step_strain(*_ishima(bb, 1.0), dgamma=0.0)
    assert with_kt(material("charan", kn=2.0), 0.0).law == "hertz"


def test_a_non_finite_jacobian_is_named_before_lapack():
    from fricstab.errors import NumericalError
    jac = np.eye(4)
    jac[2, 1] = np.inf
    with pytest.raises(NumericalError, match="Jacobian entry.*row 2"):
        spectrum(jac)
