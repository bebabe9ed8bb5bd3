"""Rigidity of frictional packings: theory (solve, mode sum) against step strain.

Preconditions first (force balance, zero modes, symmetry of the unstrained
Jacobian), then values.  Tolerances come from the error models stated in
:mod:`fricstab.protocols.stepstrain` (step strain) and from ``eps * cond(J)`` (linear
algebra).
"""

import numpy as np
import pytest

from fricstab.analysis.dos import dos, log_bins, participation, rotational_peak, spectrum
from fricstab.laws import ParameterError
from fricstab.scenes.pack_system import backbone, rattler_mask
from fricstab.scenes.packing import make_packing
from fricstab.analysis.rigidity import (ishima_flipped, linear_response, mode_sum, rigidity,
                               solve_nonaffine, zero_modes)
from fricstab.protocols.stepstrain import relax, step_strain

EPS = np.finfo(float).eps


@pytest.fixture(scope="module")
def bb():
    return backbone(make_packing(64, 0.88, seed=0))


def _cond(jac):
    w = np.sort(np.abs(np.linalg.eigvalsh(jac.toarray())))[2:]
    return w[-1] / w[0]


def test_backbone_is_force_balanced_and_rigid(bb):
    for kt in (0.0, 1e-4, 1.0):
        r = rigidity(bb, kt)
        assert r.checks["max_force"] < 1e-14
        assert r.g_a > 0 and r.g > 0


@pytest.mark.parametrize("kt", [0.0, 1e-8, 1.0, 10.0])
def test_translations_are_zero_modes(bb, kt):
    # App. C: J e_x = J e_y = 0 and e^T J = 0 (total force), to round-off:
    # each entry sums O(z) terms of size max|J|, so a few eps relative.
    jac, *_ = linear_response(bb, kt)
    c = zero_modes(bb.n, 3 if kt > 0 else 2) * np.sqrt(bb.n)
    scale = abs(jac).max()
    assert np.abs(jac @ c).max() <= 32 * EPS * scale
    assert np.abs(jac.T @ c).max() <= 32 * EPS * scale


@pytest.mark.parametrize("kt", [1e-8, 1e-4, 1.0, 10.0])
def test_solve_and_mode_sums_agree(bb, kt):
    r = rigidity(bb, kt, modes=True, route="symmetric")
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
    r = rigidity(bb, kt)
    s = step_strain(bb, kt, dgamma=1e-6)
    assert s.contacts_changed == 0
    # The error model of step_strain bounds |g - G|; and it is below 1 %.
    assert abs(s.g - r.g) <= s.error
    assert s.error < 1e-2 * abs(r.g)
    # Nonaffine rates (Eqs. 10-13) against J u = Xi (Eq. 38), same model per dof.
    scale = np.abs(r.u).max()
    assert np.abs(s.nonaffine.ravel() - r.u).max() < 1e-3 * scale


def test_printed_modified_jacobian_disagrees_with_simulation(bb):
    # Eqs. 36-37 flip signs; J~ = J (errata.md) is what step strain confirms.
    r = rigidity(bb, 1.0)
    s = step_strain(bb, 1.0, dgamma=1e-6)
    u, _ = solve_nonaffine(ishima_flipped(r.jacobian), r.xi, bb.n, 3)
    g_flipped = r.g_a - r.theta @ u / bb.box**2
    assert abs(g_flipped - s.g) > 100 * s.error


def test_frictionless_limit_is_smooth(bb):
    g0 = rigidity(bb, 0.0).g
    d = [rigidity(bb, kt).g - g0 for kt in (1e-10, 1e-8, 1e-6)]
    # G(kt) = G(0) + G'(0) kt + O(kt^2): differences scale linearly in kt.
    assert abs(d[2]) < 1e-2 * g0
    assert d[1] / d[2] == pytest.approx(1e-2, rel=0.05)
    assert d[0] / d[2] == pytest.approx(1e-4, rel=0.05)


def test_strained_state_has_history_and_nonsymmetric_jacobian(bb):
    pos = bb.pos.copy()
    pos[:, 0] += 1e-4 * pos[:, 1]
    out = relax(pos, np.zeros(bb.n), bb.radius, bb.box, 1.0, shift=1e-4 * bb.box,
                net=relax(bb.pos, np.zeros(bb.n), bb.radius, bb.box, 1.0).net)
    assert np.abs(out.net.hist).max() > 0
    from fricstab.scenes.pack_system import assemble, sparse_jacobian
    _, blocks = assemble(out.net, bb.radius, 1.0)
    jac = sparse_jacobian(out.net.pairs, blocks, bb.n, 1.0)
    sp = spectrum(jac)
    assert sp.route == "dense" and sp.asymmetry > 1e-12


def test_dos_and_participation(bb):
    r = rigidity(bb, 1e-6)
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


def test_bad_kt_is_rejected(bb):
    for bad in (-1.0, float("nan")):
        with pytest.raises(ParameterError, match="kt"):
            rigidity(bb, bad)
    with pytest.raises(ParameterError, match="dgamma"):
        step_strain(bb, 1.0, dgamma=0.0)


def test_a_non_finite_jacobian_is_named_before_lapack():
    from fricstab.errors import NumericalError
    jac = np.eye(4)
    jac[2, 1] = np.inf
    with pytest.raises(NumericalError, match="Jacobian entry.*row 2"):
        spectrum(jac)
